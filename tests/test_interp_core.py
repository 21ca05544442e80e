"""The interpreter's compiled core (``hnc_cam/nc/_core.c``) against the Python code.

The core runs plain blocks, splits the file into lines and computes the summary's figures;
everything else, and every alarm and warning, stays with the Python code. These tests run
each program through both paths and require the same outcome bit for bit: every field of
every move, the warnings, the block count, the alarm with its line, column and block, the
summary. Programs: the repo's test data and goldens, the manual's examples where present,
and random plain-block programs written as a user would (G90/G91, U/W, R and I/K arcs,
full circles, G95/G96, G20, G36/G37, T changes with offsets, F changes, N numbers,
comments, lower case, odd blanks), some with mistakes that alarm."""
from __future__ import annotations

import contextlib
import dataclasses
import os
import random
from pathlib import Path

import pytest

from hnc_cam.errors import NCError
from hnc_cam.nc import interp, parser, toolpath
from hnc_cam.nc.interp import run
from hnc_cam.tooling import Register, load_machine

from conftest import MANUAL, REPO

CORE = toolpath.core
needs_core = pytest.mark.skipif(CORE is None, reason="the compiled core is not built here "
                                "(or HNC_CAM_PURE is set): nothing to compare")


def test_core_is_built():
    """Every install builds the core from its C source; only HNC_CAM_PURE turns it off."""
    if os.environ.get("HNC_CAM_PURE"):
        assert toolpath.core is None and interp._core is None
        return
    from hnc_cam.nc import _core  # noqa: F401  (ImportError here: the install did not build it)
    assert toolpath.core is _core and interp._core is _core


@contextlib.contextmanager
def pure():
    saved = toolpath.core, interp._core
    toolpath.core = interp._core = None
    try:
        yield
    finally:
        toolpath.core, interp._core = saved


def _val(v):
    if isinstance(v, float):
        return v.hex()  # -0.0 and 0.0 differ
    if isinstance(v, tuple):
        return tuple(_val(x) for x in v)
    return v


def outcome(text: str, **kw):
    try:
        tp = run(text, **kw)
    except NCError as e:
        return ("alarm", e.message, e.line, e.col, e.block, e.file)
    moves = [tuple(_val(getattr(m, f)) for f in toolpath.MOVE_FIELDS) for m in tp.moves]
    return ("ok", moves, [(w.line, w.message) for w in tp.warnings], tp.blocks_executed,
            tp.source_lines, tp.summary(), _val(tp._figures()[1:]))


def same(text: str, **kw):
    a = outcome(text, **kw)
    with pure():
        b = outcome(text, **kw)
    assert a[0] == b[0], (a[:3], b[:3])
    if a[0] == "ok":
        for i, (ma, mb) in enumerate(zip(a[1], b[1])):
            assert ma == mb, f"move {i}: {ma} != {mb}"
    assert a == b
    return a


def _programs():
    out = []
    for base in (REPO / "tests" / "data", MANUAL):
        if base.is_dir():
            for p in sorted(base.rglob("*")):
                if p.suffix.lower() in (".nc", ".mpf", ".ngc", ".txt") and p.is_file():
                    out.append(p)
    return out


PROGRAMS = _programs()


@needs_core
@pytest.mark.parametrize("path", PROGRAMS, ids=[str(p.relative_to(p.parents[1])) for p in PROGRAMS])
def test_files_same_both_ways(path: Path):
    text = path.read_bytes().decode("utf-8", errors="replace")
    dialect = ("siemens802" if path.suffix.lower() == ".mpf"
               else "fanuc0it" if "fanuc" in str(path) else None)
    if path.parent.name == "fuzz_corpus":  # runaway programs: alarmed by small limits
        same(text, machine=dataclasses.replace(load_machine(None), step_limit=20_000,
                                               move_limit=20_000))
        return
    same(text, dialect=dialect)
    if dialect is None:
        same(text, start=(0.0, 0.0))


# -- random plain-block programs -------------------------------------------------------------

def _num(rng: random.Random, v: float) -> str:
    s = f"{v:.{rng.choice((0, 1, 2, 3, 3, 3, 4))}f}"
    if rng.random() < 0.1 and "." in s:
        s = s.rstrip("0")  # "12." and ".5" forms
        if s.startswith("0."):
            s = s[1:]
        elif s.startswith("-0."):
            s = "-" + s[2:]
    if rng.random() < 0.03 and not s.startswith("-"):
        s = "+" + s
    return s


def random_program(seed: int, mistakes: bool = True) -> str:
    rng = random.Random(seed)
    sep = rng.choice((" ", "", "  ", "\t"))
    lines = ["%" + str(rng.randint(1, 9999))]
    if rng.random() < 0.2:
        lines.insert(0, "(header comment)")
    st = {"x": 60.0, "z": 5.0, "abs": True, "dm": 2.0, "g": 0}  # x as programmed (diameter)
    x0, z0 = 60.0, 5.0
    pre = [f"G92 X{x0:g} Z{z0:g}"] if rng.random() < 0.8 else []
    if rng.random() < 0.7:
        pre.append(rng.choice(("M03 S800", "M04 S1200", "M03 S0", "S500 M03")))
    if rng.random() < 0.3:
        pre.append(rng.choice(("G95 F0.15", "G95")))
    if rng.random() < 0.3:
        pre.append(rng.choice(("G96 S120", "G96 S80 M03")))
    if rng.random() < 0.2:
        pre += ["#601=1.25", "#702=0.4"]
    if rng.random() < 0.3:
        pre.append(rng.choice(("T0101", "T0102", "T0200", "T0202", "T0100")))
    if rng.random() < 0.1:
        pre.append("G37")
    if rng.random() < 0.05:
        pre.append("G20")
    if rng.random() < 0.8:
        pre.append(f"G01 F{rng.choice((80, 120, 0.2, 250))}")
    body = []
    nno = 10

    def track(line: str) -> None:
        import re
        u = line.upper()
        if u.startswith("G92"):
            return
        for g in re.findall(r"G\s*0*(\d+)(?![\d.])", u):
            g = int(g)
            if g == 90:
                st["abs"] = True
            elif g == 91:
                st["abs"] = False
            elif g == 37:
                st["dm"] = 1.0
            elif g == 36:
                st["dm"] = 2.0
            elif g <= 3:
                st["g"] = g
        for L, v in re.findall(r"([XZUW])\s*([-+]?(?:\d+\.?\d*|\.\d+))", u):
            v = float(v)
            key = "x" if L in "XU" else "z"
            if L in "UW" or not st["abs"]:
                st[key] += v
            else:
                st[key] = v

    for line in pre:
        track(line)
    for _ in range(rng.randint(5, 80)):
        r = rng.random()
        w = []
        if rng.random() < 0.15:
            w.append(f"N{nno}")
            nno += rng.choice((1, 5, 10))
        x, z, dm = st["x"], st["z"], st["dm"]
        if r < 0.05 and mistakes:
            w.append(rng.choice(("G01 X10 R2", "G02 X10 Z-3 R0.1", "G03 X20 Z1 I0 K0", "G01 X1 U2",
                                 "G01 X200000", "G05 X1", "G01 X1 Y2", "G02 X4 Z4", "I1",
                                 "G01 F0", "G00 X1 Z1 R1", "G01 F-3", "N1.5 G01 X1", "G01 X1 X2",
                                 "N12345678901 X1", "G1.5 X1", "G02 X40 Z0 I0 K5")))
        elif r < 0.08:
            w.append(rng.choice(("G91", "G90")))
        elif r < 0.11:
            w.append(rng.choice(("M05", "M03", "M08", "M09", "T0101", "T0202", "G97 S600",
                                 "G96 S150", "G94 F150", "G95 F0.1", "F90", "M03 S1000",
                                 "#1=5", "G04 P0.5", "S2500")))
        elif r < 0.13:
            w.append(rng.choice(("(a comment)", "; a comment", "G01 X30 (comment) Z-2",
                                 "g01 x32.5 z-3", "G01\x1cX33Z-4")))
        elif r < 0.16:
            w.append(f"G00 U{_num(rng, rng.uniform(-5, 5))} W{_num(rng, rng.uniform(-5, 5))}")
        elif r < 0.75 and r >= 0.45:
            # arcs: an end on a circle about a centre at offset I/K from here
            g = rng.choice(("G02", "G03", "G2", "G3"))
            if rng.random() < 0.5:
                ex, ez = rng.uniform(10, 90) / dm, z - rng.uniform(0.1, 8)
                chord = ((ex - x / dm) ** 2 + (ez - z) ** 2) ** 0.5
                R = rng.choice((chord / 2 + rng.uniform(0, 5), chord / 2 - 0.0004, chord / 2 + 2))
                if rng.random() < 0.1:
                    R = -R
                tail = f"R{R:.3f}"
            else:
                import math
                rad = rng.uniform(0.5, 10)
                a0 = rng.uniform(0, 2 * math.pi)
                a1 = a0 + rng.choice((-1, 1)) * rng.uniform(0.1, 3)
                xr = x / dm
                cx, cz = xr - rad * math.sin(a0), z - rad * math.cos(a0)
                ex, ez = cx + rad * math.sin(a1), cz + rad * math.cos(a1)
                if rng.random() < 0.08:
                    ex, ez = xr, z  # a full circle
                tail = f"I{cx - xr:.3f} K{cz - z:.3f}"
            if st["abs"]:
                w.append(f"{g} X{ex * dm:.3f} Z{ez:.3f} {tail}")
            else:
                w.append(f"{g} U{ex * dm - x:.3f} W{ez - z:.3f} {tail}")
        else:
            nx = round(rng.uniform(10, 90), 3)
            nz = round(z - rng.uniform(-3, 8), 3)
            g = rng.choice(("G01", "G1", "G00", "G0", "", "G01"))
            if g == "" and st["g"] >= 2:
                g = "G01"
            w.append(g)
            if st["abs"]:
                parts = [f"X{_num(rng, nx)}", f"Z{_num(rng, nz)}"]
                if rng.random() < 0.2:
                    parts = parts[rng.randrange(2):][:1]
            else:
                parts = [f"U{_num(rng, nx - x)}", f"W{_num(rng, nz - z)}"]
            if rng.random() < 0.15:
                parts.append(f"F{rng.choice((100, 60.5, 0.12, 300))}")
            w += parts
        line = sep.join(w)
        if rng.random() < 0.05:
            line = line.lower()
        if rng.random() < 0.05:
            line = "  " + line + "  "
        body.append(line)
        track(line)
    lines += pre + body
    lines.append(rng.choice(("M30", "M02", "M05 M30")))
    eol = rng.choice(("\n", "\r\n", "\r", "\n"))
    return eol.join(lines) + (eol if rng.random() < 0.9 else "")


MACHINE = load_machine(None).with_registers({
    1: Register(number=1, x=2.5, z=-1.25, radius=0.4, tip=3),
    2: Register(number=2, x=-1.0, z=3.3, radius=0.8, tip=2)})


@needs_core
@pytest.mark.parametrize("seed", range(400))
def test_random_plain_programs_same_both_ways(seed: int):
    text = random_program(seed)
    same(text, machine=MACHINE)
    if seed % 4 == 0:
        same(text, machine=MACHINE, start=(0.0, 0.0), diameter=False)
    if seed % 7 == 0:  # the step and move limits inside runs of plain blocks
        for k in (3, 7, 20):
            same(text, machine=MACHINE, step_limit=k)
            same(text, machine=dataclasses.replace(MACHINE, move_limit=k))


@needs_core
def test_random_programs_mostly_run():
    """The generator writes programs that mostly run: the comparison is of moves, not only
    of alarms."""
    ok = sum(outcome(random_program(s, mistakes=False), machine=MACHINE)[0] == "ok"
             for s in range(60))
    assert ok >= 30


@needs_core
def test_core_takes_the_plain_runs():
    """On the benchmark's shape of program the core runs the blocks (the Python compiler sees
    only the blocks that are not plain) and gives what the Python code gives."""
    import sys
    sys.path.insert(0, str(REPO / "benchmarks"))
    try:
        import interp as bench  # benchmarks/interp.py
    finally:
        sys.path.pop(0)
    text = bench.plain_program(3000)
    src = parser.load(text)
    it = interp.Interp(src, load_machine(None))
    tp = it.run()
    compiled = sum(c is not None for c in it.compiled)
    assert compiled <= 3  # G92, M03 S800, M30
    assert len(tp.moves) == 3000
    same(text)


@needs_core
@pytest.mark.parametrize("text", [
    "", "\n", "\r\n\r\n", "%1\nG01 X1 Z1 F100\nM30", "%1\r\nG01 X1 Z1 F100\r\nM30\r\n",
    "%1\rg01 x1 z1 f100\rm30\r", "%1\nG01 X1 Z1 F100   \t\nM30\n", "O12\n G01 X1\x1fZ1 F1\nM30\n",
    " %5\n%\nIF 1\nENDIF\nWHILE #1 LT 2\n#1=#1+1\nENDW\nM30\n", "N5 IF [1 EQ 1]\nN6ENDW\n",
    "%1\nG01 X1 Z1 F100\x00\nM30\n", "%1\n(cmt) G01 X1\nM30 ; end\n", "%1\nX1\xa0Z2\nM30\n",
    "%1\nG01 X\u0661 Z1 F1\nM30\n", "%1\n" + "X1 " * 50 + "\nM30\n",
])
def test_split_same_both_ways(text: str):
    """The core's line split gives the Python loader's lists (or hands the text to it)."""
    def load(t):
        try:
            s = parser.load(t, "f.nc", 100)
        except NCError as e:
            return ("alarm", e.message, e.line, e.col)
        return (s.lines, s.lineno, s.text, s.kind, s.number, s.spans, s.jump, s.bad, s.main,
                s.programs)
    a = load(text)
    with pure():
        b = load(text)
    assert a == b
    same(text)


@needs_core
@pytest.mark.parametrize("block", [
    "G01 X1.5 Z-2", "G1X1.5Z-2", "G01 X+1.5 Z-.5", "G01 X1. Z-2.", "G01 X 1.5 Z - 2",
    "G01 X1.5 Z-2 F", "G01 X1.5 Z-2 F24000.0001", "G01 X99999.999 Z-99999.999",
    "G01 X99999.9991", "G01 X0.1234567890123456789 Z1", "G01 X12345678901234567890",
    "N0 G01 X1", "N4294967295 X1", "N4294967296 X1", "N+5 X1", "N-5 X1", "N1.0 X1", "N01234567890 X1",
    "G00.0 X1", "G-0 X1 Z1", "G3.0 X1 Z1 R5", "G+1 X2", "G01 G01 X1", "X1 N1 N2",
    "G01 X1 Z2 F100 F100", "G02 X10 Z-5 R2.5 I1", "G03 X10 Z-5 K-2.5", "G02 U10 W-5 R-9",
    "G01 X1 W2", "G01 U1 Z2", "G00 X1 R1", "G01 K1", "R1", "F0", "F-0", "G01 X-0 Z-0",
    "X1E5", "X1..2", "X.", "X-", "X1 Z2;", "X1 Z2 (c)", "X1 #1", "X1 Z2 M03",
])
def test_blocks_same_both_ways(block: str):
    same(f"%1\nG92 X50 Z10\nM03 S700\nG01 F120\n{block}\nG01 X40 Z0\nM30\n", machine=MACHINE)
    same(f"%1\nG92 X50 Z10\nG95 G96 S90 M04 F0.2\nT0101\n{block}\n{block}\nM30\n", machine=MACHINE)
    same(f"%1\nG91 G20 G37\nM03 S700\nF5\n{block}\nM30\n", machine=MACHINE)
