"""Fuzzer of the interpreter: every input must give a toolpath or the project's own alarm.

Two generators, alternating case by case:

* **grammar**: whole programs built from the dialect's grammar: headers, every word letter
  with plausible and extreme values, G00-G03 moves with chamfer C / round R words, G41/G42/G40
  with T words, the cycles G80/G81/G82/G32/G76/G71/G72/G73 with random parameters and random
  N ns…nf profiles (lines, arcs, chamfers), macro assignments with ``#`` variables and
  functions, IF/ELSE/ENDIF and WHILE/ENDW (closed or not, sometimes endless), subprograms
  with M98 P L / G65 and M99, comments, odd line ends;
* **mutation**: byte-level mutations (flip, insert, delete, duplicate, splice, special bytes
  such as CR, NUL, ESC, non-ASCII digits, 400-digit numbers) of the manual's example programs
  (``../shared/examples/manual`` when present) or else of the project's own generated
  programs (``tests/data/golden``).

A case passes when :func:`hnc_cam.nc.run` returns a toolpath whose moves are finite, or raises
an :class:`~hnc_cam.errors.HncError` whose one-line form is one printable line (no CR/LF,
no control bytes) of bounded length. Anything else is a failure, grouped by exception type
and the innermost project frame (file:line). Cases over 5 s are reported as well.

The runs use small limits (``--steps``, moves and calls scaled from it) so that endless
programs end in milliseconds; ``--default-limits`` runs with the machine's defaults instead.

Run: ``python benchmarks/fuzz.py --cases N --seed S [--save DIR] [--default-limits]
[--case-timeout S] [--seconds S] [--compare]`` (``--compare``: each case also with the
compiled core off; a difference from the Python code is a failure).
Prints the count, the rate (cases/s), every distinct failure with a reproducer, the cases
over 5 s, the longest case and the peak memory (max RSS) of the process.
"""
from __future__ import annotations

import argparse
import math
import os
import random
import resource
import sys
import time
import traceback
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from hnc_cam.errors import HncError  # noqa: E402
from hnc_cam.nc import run  # noqa: E402
from hnc_cam.tooling import load_machine  # noqa: E402

SLOW_S = 5.0
MAX_LINE = 1200  # characters of an alarm's one-line form


# ------------------------------------------------------------------------------- seeds

def seed_programs() -> list[str]:
    """The manual's examples when the shared folder is there, else the project's golden
    programs, else one built-in program."""
    for d in (ROOT.parent / "shared" / "examples" / "manual", ROOT / "tests" / "data" / "golden"):
        if d.is_dir():
            progs = [p.read_text("utf-8", errors="replace") for p in sorted(d.rglob("*"))
                     if p.is_file() and p.suffix.lower() in (".nc", ".txt", ".cnc", "")
                     and p.name != "INDEX.md"]
            progs = [t for t in progs if t.strip()]
            if progs:
                return progs
    return ["%1\nT0101\nM03 S600\nG00 X42 Z2\nG71 U1 R1 P10 Q20 X0.4 Z0.1 F120\n"
            "N10 G00 X20\nG01 Z-10 C1\nX30 Z-20 R2\nN20 G01 X40\nG00 X60 Z50\nM30\n"]


# ------------------------------------------------------------------------------- grammar

def num(r: random.Random, lo: float = -100, hi: float = 100) -> str:
    k = r.random()
    if k < 0.012:
        return r.choice(["0", "-0", "0.", ".5", "99999.999", "-99999.999", "1E3", "100000",
                         "1" + "0" * r.choice([20, 300, 400]), "0.0001", "4294967295",
                         "4294967296", "-1", "1.5.2", "+3", "--2", "²"])
    if k < 0.5:
        return str(r.randint(int(lo), int(hi)))
    return f"{r.uniform(lo, hi):.{r.choice([1, 2, 3])}f}"


def pos(r: random.Random) -> str:
    return f"{r.uniform(0, 120):.3f}"


def expr(r: random.Random, depth: int = 0) -> str:
    k = r.random()
    if depth > 3 or k < 0.3:
        return num(r, -50, 50)
    if k < 0.5:
        if r.random() < 0.85:
            return f"#{r.choice(VARS)}"
        return f"#{r.choice([10, 199, 250, 600, 701, 1000, 1020, 1022, 1152, 2000, 5000])}"
    if k < 0.7:
        return f"[{expr(r, depth + 1)}{r.choice('+-*/')}{expr(r, depth + 1)}]"
    if k < 0.85:
        f = r.choice(["SIN", "COS", "TAN", "ATAN", "ABS", "INT", "SIGN", "SQRT", "EXP"])
        return f"{f}[{expr(r, depth + 1)}]"
    if k < 0.9:
        return f"ATAN2[{expr(r, depth + 1)},{expr(r, depth + 1)}]"
    if k < 0.95:
        return f"[{expr(r, depth + 1)} {r.choice(['EQ', 'NE', 'GT', 'GE', 'LT', 'LE', 'AND', 'OR'])} " \
               f"{expr(r, depth + 1)}]"
    return r.choice(["PI", "TRUE", "FALSE", "AR[#1]", "NOT 1", "-#1", "#[#1]", "#[1+1]"])


#: variables every grammar program assigns first (reading a vacant one is an alarm)
VARS = [1, 2, 3, 4, 50, 51, 100]


def word(r: random.Random, letter: str) -> str:
    if r.random() < 0.08:
        return f"{letter}[{expr(r)}]"
    if r.random() < 0.04:
        return f"{letter}#{r.choice(VARS)}"
    if letter == "X":
        return "X" + (pos(r) if r.random() < 0.8 else num(r))
    return letter + num(r)


def move(r: random.Random) -> str:
    g = r.choice(["G00", "G01", "G01", "G02", "G03", ""])
    ws = [g] if g else []
    axes = [r.choice("XU")] if r.random() < 0.8 else []
    if not axes or r.random() < 0.7:
        axes.append(r.choice("ZW"))
    if r.random() < 0.02:
        axes.append(r.choice("XZUW"))
    for L in axes:
        ws.append(word(r, L))
    if g in ("G02", "G03") or (not g and r.random() < 0.2):
        if r.random() < 0.6:
            ws.append("R" + num(r, 1, 30))
        else:
            ws += ["I" + num(r, -20, 20), "K" + num(r, -20, 20)]
    elif g in ("G01", "") and r.random() < 0.25:
        ws.append(r.choice("CR") + num(r, 0, 5))
    if r.random() < 0.3:
        ws.append("F" + num(r, 0, 300))
    return " ".join(ws)


def profile(r: random.Random, ns: int, nf: int, face: bool = False) -> list[str]:
    out = []
    n = r.randint(1, 6)
    x = r.uniform(5, 40)
    z = 0.0
    out.append(f"N{ns} G0{r.choice('01')} " + (f"Z{z:.3f}" if face else f"X{2 * x:.3f}")
               + (f" Z{r.uniform(-2, 2):.3f}" if r.random() < 0.2 else ""))
    for i in range(n):
        z -= r.uniform(0.5, 15)
        x += r.uniform(-3, 8) if r.random() < 0.8 else r.uniform(-20, 20)
        k = r.random()
        if k < 0.6:
            w = f"G01 X{2 * x:.3f} Z{z:.3f}"
            if r.random() < 0.2:
                w += f" {r.choice('CR')}{r.uniform(0, 2):.2f}"
        elif k < 0.9:
            w = f"G0{r.choice('23')} X{2 * x:.3f} Z{z:.3f} R{r.uniform(1, 30):.3f}"
        else:
            w = move(r)
        out.append(w)
    out.append(f"N{nf} G01 X{2 * (x + r.uniform(0, 10)):.3f}")
    return out


def cycle(r: random.Random, n: int) -> list[str]:
    c = r.choice([80, 81, 82, 32, 76, 71, 71, 72, 73])
    start = f"G00 X{r.uniform(20, 120):.3f} Z{r.uniform(-5, 10):.3f}"
    if c in (71, 72, 73):
        ns, nf = n, n + 10
        if c == 71:
            w = f"G71 U{num(r, 0, 3)} R{num(r, 0, 2)} P{ns} Q{nf} X{num(r, -1, 1)} Z{num(r, -1, 1)} F100"
            if r.random() < 0.2:
                w = f"G71 U{num(r, 0, 3)} R1 P{ns} Q{nf} E{num(r, -1, 1)} F100"
        elif c == 72:
            w = f"G72 W{num(r, 0, 3)} R{num(r, 0, 2)} P{ns} Q{nf} X0.4 Z0.1 F100"
        else:
            w = (f"G73 U{num(r, 0, 5)} W{num(r, 0, 5)} R{num(r, 0, 20) if r.random() < 0.9 else '99999'} "
                 f"P{ns} Q{nf} X0.4 Z0.1 F100")
        return [start, w] + profile(r, ns, nf, face=c == 72)
    if c == 76:
        return [start, f"G76 C{r.randint(0, 3)} R{num(r, -2, 2)} E{num(r, -2, 2)} A{r.choice(['60', '55', '0', '45'])} "
                       f"X{pos(r)} Z{num(r, -60, 0)} I{num(r, -2, 2)} K{num(r, 0, 3)} U{num(r, 0, 0.5)} "
                       f"V{num(r, 0, 0.5)} Q{r.choice(['0.3', '0.01', '0.001', num(r, 0, 2)])} F{num(r, 0, 3)}"]
    if c == 32:
        return [start, f"G32 X{pos(r)} Z{num(r, -50, 0)} F{num(r, 0, 3)}" +
                (f" P{num(r, 0, 360)}" if r.random() < 0.3 else "")]
    ws = [f"G{c}", f"X{pos(r)}", f"Z{num(r, -50, 0)}"]
    for L in r.sample("IRFECP", r.randint(0, 4)):
        ws.append(L + num(r, -5, 5))
    lines = [start, " ".join(ws)]
    for _ in range(r.randint(0, 3)):
        lines.append(f"X{pos(r)}" + (f" Z{num(r, -50, 0)}" if r.random() < 0.5 else ""))
    return lines


def statement(r: random.Random, n: int, depth: int, subs: list[int]) -> list[str]:
    k = r.random()
    if k < 0.30:
        return [move(r)]
    if k < 0.40:
        return cycle(r, n)
    if k < 0.50:
        return [f"#{r.choice([1, 2, 3, 50, 100, 200, 600, 701, 1040, 2000, 1000])}={expr(r)}"]
    if k < 0.56 and depth < 3:
        body = [x for _ in range(r.randint(0, 4)) for x in statement(r, n + 20, depth + 1, subs)]
        tail = [] if r.random() < 0.05 else (["ELSE"] + [move(r)] if r.random() < 0.3 else []) + ["ENDIF"]
        return [f"IF {expr(r)}"] + body + tail
    if k < 0.62 and depth < 3:
        body = [x for _ in range(r.randint(0, 3)) for x in statement(r, n + 30, depth + 1, subs)]
        v = r.choice([1, 2, 3])
        cond = r.choice([f"#{v} LT {r.randint(0, 50)}", "1", expr(r)])
        tail = [] if r.random() < 0.05 else ["ENDW"]
        return [f"#{v}=0", f"WHILE {cond}"] + body + [f"#{v}=#{v}+{r.choice(['1', '0.5', '0', '-1'])}"] + tail
    if k < 0.68:
        p = r.choice(subs) if subs and r.random() < 0.9 else r.randint(0, 9999)
        if r.random() < 0.5:
            return [f"M98 P{p}" + (f" L{r.choice(['2', '0', '100', '4294967295', num(r, 0, 5)])}" if r.random() < 0.5 else "")]
        return [f"G65 P{p} " + " ".join(word(r, L) for L in r.sample("ABCIJKXZ", 3))]
    if k < 0.76:
        return [r.choice(["G41", "G42", "G40"]) + " " + r.choice(["G00", "G01"]) + " " + word(r, "X") + " "
                + word(r, "Z") + (f" T0{r.randint(1, 4)}0{r.randint(0, 4)}" if r.random() < 0.5 else "")]
    if k < 0.85:
        return [r.choice(["T0101", "T0202", "T0303", "T0100", "T4", "T0200", "M03 S600", "M04 S300", "M05",
                          "M07", "M08", "M09", "M06", "M00", "M01", "M10", "G96 S120", "G97 S800",
                          "G95", "G94", "G90", "G91", "G36", "G37", "G20", "G21", "G54", "G55",
                          "G92 X100 Z50", "G28 X100 Z50", "G29 X40 Z5", "G52 X1 Z1", "G53 X10 Z10",
                          "G04 P0.5", "G04", "F0", "F100", "S0"])]
    if k < 0.86:
        letters = r.sample("ABCDEFGHIJKLMNOPQRSTUVWXYZ", r.randint(1, 4))
        return [" ".join(word(r, L) for L in letters)]
    if k < 0.88:
        return [r.choice(["(a comment)", "; note", "(unclosed", "", "   ", "N10 G01 X1 (c) Z2",
                          "%", "O12", "ENDW", "ENDIF", "ELSE", "M99", "M02", "M30"])]
    if k < 0.89:
        return [move(r) + " " + word(r, r.choice("NGMFSTD"))]
    return [move(r)]


def grammar_program(r: random.Random) -> str:
    subs = [r.randint(1, 9999) for _ in range(r.randint(0, 2))]
    head = r.choice(["%1", "O1", "%0001", "%1", "O1", "%2000"] * 4 + ["", "%", "O1234"])
    lines = [head] if head else []
    if r.random() < 0.7:
        lines.append(f"G92 X{r.uniform(50, 150):.1f} Z{r.uniform(20, 100):.1f}")
    if r.random() < 0.95:
        lines += [f"#{v}={num(r, -5, 20)}" for v in VARS]
    if r.random() < 0.7:
        lines.append(r.choice(["M03 S600", "T0101 M03 S800", "G96 S150 M04", "T0202", "M08 S500 M03"]))
        lines.append(r.choice(["F100", "G95 F0.2", "F80"]))
    n = 100
    for _ in range(r.randint(1, 10)):
        lines += statement(r, n, 0, subs)
        n += 100
    if r.random() < 0.9:
        lines.append(r.choice(["M30", "M02", "M30", "M99"]))
    for p in subs:
        lines.append(r.choice([f"%{p}", f"O{p}"]))
        for _ in range(r.randint(0, 5)):
            lines += statement(r, n, 1, subs)
            n += 100
        if r.random() < 0.9:
            lines.append("M99")
    text = []
    for i, ln in enumerate(lines):
        if r.random() < 0.2 and not ln.startswith(("%", "O")):
            ln = f"N{(i + 1) * 10} {ln}"
        if r.random() < 0.05:
            ln = ln.lower()
        text.append(ln)
    eol = r.choice(["\n"] * 8 + ["\r\n", "\r"])
    return eol.join(text) + (eol if r.random() < 0.9 else "")


# ------------------------------------------------------------------------------- mutation

SPECIAL = ["\r", "\n", "\0", "\x1b", "\x0b", "\x0c", "\t", "\u2028", "\u00b3", "\u0661", "\ufffd",
           "%", "O", "(", ")", ";", "[", "]", "#", "=", "*", "/", "-", ".", "E", "IF", "WHILE",
           "ENDW", "ENDIF", "ELSE", "M99", "M98P1", "G65P1", "N", "L4294967295", "R99999",
           "1" + "0" * 400, "9" * 5000, "C3", "R3", "G41", "G40", "G71", "G76", "Q0.01"]


def mutate(r: random.Random, text: str, seeds: list[str]) -> str:
    s = text
    for _ in range(r.randint(1, 6)):
        k = r.random()
        p = r.randint(0, len(s)) if s else 0
        if k < 0.2 and s:  # flip one character
            i = min(p, len(s) - 1)
            s = s[:i] + chr(r.choice([r.randint(0, 127), r.randint(0, 127), r.randint(128, 0x2FFF)])) + s[i + 1:]
        elif k < 0.4:  # insert a special token
            s = s[:p] + r.choice(SPECIAL) + s[p:]
        elif k < 0.55 and s:  # delete a run
            s = s[:p] + s[p + r.randint(1, 20):]
        elif k < 0.7 and s:  # duplicate a run
            q = min(len(s), p + r.randint(1, 80))
            s = s[:q] + s[p:q] * r.randint(1, 4) + s[q:]
        elif k < 0.8:  # splice lines of another program
            o = r.choice(seeds).splitlines()
            if o:
                a = r.randint(0, len(o) - 1)
                s = s[:p] + "\n".join(o[a:a + r.randint(1, 5)]) + "\n" + s[p:]
        elif k < 0.9:  # swap two lines
            ls = s.split("\n")
            if len(ls) > 2:
                i, j = r.randrange(len(ls)), r.randrange(len(ls))
                ls[i], ls[j] = ls[j], ls[i]
                s = "\n".join(ls)
        else:  # a random number replaced by an extreme one
            digits = [i for i, c in enumerate(s) if c.isdigit()]
            if digits:
                i = r.choice(digits)
                s = s[:i] + r.choice(["0", "99999.999", "0.0001", "-1", "4294967296", "1E9"]) + s[i + 1:]
    return s


def make_case(r: random.Random, seeds: list[str]) -> tuple[str, str]:
    if r.random() < 0.5:
        return "grammar", grammar_program(r)
    base = r.choice(seeds)
    if r.random() < 0.3:
        base = grammar_program(r)
    return "mutation", mutate(r, base, seeds)


# ------------------------------------------------------------------------------- checking

def fuzz_machine(steps: int | None):
    m = load_machine(None)
    if steps is None:
        return m
    small = {"step_limit": steps, "move_limit": max(1000, steps * 2), "call_limit": max(100, steps // 4)}
    return replace(m, **{k: v for k, v in small.items() if hasattr(m, k)})


def check(text: str, machine) -> str | None:
    """None when the case passes, else a failure key ``Type at file:line: message``."""
    try:
        tp = run(text, machine, file="fuzz.nc")
    except HncError as e:
        line = e.one_line()
        if "\n" in line or "\r" in line or not line.isprintable():
            return f"AlarmNotOneLine: {line[:80]!r}"
        if len(line) > MAX_LINE:
            return f"AlarmTooLong: {len(line)} characters"
        return None
    except BaseException as e:  # noqa: BLE001 - everything else is what we look for
        if isinstance(e, (KeyboardInterrupt, CaseTimeout)):
            raise
        return f"{type(e).__name__} at {_where(e)}: {str(e)[:100]}"
    for m in tp.moves:
        if not all(map(math.isfinite, (*m.start, *m.end, m.duration))) or m.duration < 0:
            return f"NonFiniteMove at line {m.line}"
    tp.summary()
    return None


def _outcome(text: str, machine) -> tuple:
    """Everything a run gives: the moves' fields (floats by their bits), the warnings, the
    block count, or the alarm's one-line form, or the exception's type."""
    from hnc_cam.nc import toolpath
    try:
        tp = run(text, machine, file="fuzz.nc")
    except HncError as e:
        return ("alarm", e.one_line())
    except BaseException as e:  # noqa: BLE001
        if isinstance(e, (KeyboardInterrupt, CaseTimeout)):
            raise
        return ("error", type(e).__name__)
    val = (lambda v: v.hex() if isinstance(v, float) else
           tuple(x.hex() if isinstance(x, float) else x for x in v) if isinstance(v, tuple) else v)
    return ("ok", [tuple(val(getattr(m, f)) for f in toolpath.MOVE_FIELDS) for m in tp.moves],
            [(w.line, w.message) for w in tp.warnings], tp.blocks_executed, tp.summary())


def compare_core(text: str, machine) -> str | None:
    """None when the compiled core and the Python code give the same outcome (or there is
    no core), else a failure key."""
    from hnc_cam.nc import interp, toolpath
    if toolpath.core is None:
        return None
    a = _outcome(text, machine)
    saved = toolpath.core, interp._core
    toolpath.core = interp._core = None
    try:
        b = _outcome(text, machine)
    finally:
        toolpath.core, interp._core = saved
    if a == b:
        return None
    if a[0] != b[0] or a[0] != "ok":
        return f"CoreDiffers: core {str(a)[:120]} / Python {str(b)[:120]}"
    for i, (ma, mb) in enumerate(zip(a[1], b[1])):
        if ma != mb:
            return f"CoreDiffers: move {i}: core {ma} / Python {mb}"
    return f"CoreDiffers: core {str(a[2:])[:120]} / Python {str(b[2:])[:120]}"


class CaseTimeout(BaseException):
    """Raised by the per-case timer (``--case-timeout``): the case is recorded as slow."""


def _on_timer(signum, frame):
    raise CaseTimeout()


def _where(e: BaseException) -> str:
    tb = traceback.extract_tb(e.__traceback__)
    frames = [f for f in tb if "hnc_cam" in f.filename] or tb
    if not frames:
        return "?"
    f = frames[-1]
    i = f.filename.find("hnc_cam")
    return f"{f.filename[i:] if i >= 0 else f.filename}:{f.lineno}"


def _key(failure: str) -> str:
    return failure.split(": ")[0]


def minimise(text: str, key: str, machine, budget: float = 10.0) -> str:
    """A smaller program with the same failure class (lines, then characters)."""
    t_end = time.perf_counter() + budget

    def same(t: str) -> bool:
        f = check(t, machine)
        return f is not None and _key(f) == key

    lines = text.split("\n")
    i = 0
    while i < len(lines) and time.perf_counter() < t_end:
        cand = lines[:i] + lines[i + 1:]
        if same("\n".join(cand)):
            lines = cand
        else:
            i += 1
    s = "\n".join(lines)
    i = 0
    while i < len(s) and time.perf_counter() < t_end and len(s) < 2000:
        cand = s[:i] + s[i + 1:]
        if same(cand):
            s = cand
        else:
            i += 1
    return s


def fuzz(cases: int, seed: int, steps: int | None = 2000, save: str | None = None,
         progress: bool = False, minimise_budget: float = 10.0, case_timeout: float = 0.0,
         seconds: float = 0.0, compare: bool = False) -> dict:
    """Run ``cases`` cases from ``seed``; returns the figures (also used by the tests).
    ``case_timeout`` > 0 stops a case after that many seconds (it counts as slow, with that
    time as a lower bound); ``seconds`` > 0 stops the run early (the count says how many ran)."""
    import signal
    if case_timeout > 0:
        signal.signal(signal.SIGALRM, _on_timer)
    r = random.Random(seed)
    seeds = seed_programs()
    machine = fuzz_machine(steps)
    failures: dict[str, tuple[int, str, str]] = {}  # key -> (count, first failure, program)
    slow: list[tuple[float, int, str]] = []
    longest = (0.0, -1)
    kinds = {"grammar": 0, "mutation": 0}
    alarms = 0
    t0 = time.perf_counter()
    done = 0
    for i in range(cases):
        if seconds > 0 and time.perf_counter() - t0 > seconds:
            break
        done += 1
        kind, text = make_case(r, seeds)
        kinds[kind] += 1
        t = time.perf_counter()
        if case_timeout > 0:
            signal.setitimer(signal.ITIMER_REAL, case_timeout)
        try:
            f = check(text, machine)
            if f is None and compare:
                f = compare_core(text, machine)
        except CaseTimeout:
            f = None
        finally:
            if case_timeout > 0:
                signal.setitimer(signal.ITIMER_REAL, 0)
        dt = time.perf_counter() - t
        if dt > longest[0]:
            longest = (dt, i)
        if dt > SLOW_S:
            slow.append((dt, i, text))
            if progress:
                print(f"  slow case {i}: {dt:.1f} s {text[:300]!r}", flush=True)
            if save:
                Path(save).mkdir(parents=True, exist_ok=True)
                (Path(save) / f"slow_{seed}_{i}.nc").write_text(text, "utf-8", newline="")
        if f is not None:
            k = _key(f)
            c, first, prog = failures.get(k, (0, f, text))
            failures[k] = (c + 1, first, prog)
        if progress and (i + 1) % 10000 == 0:
            el = time.perf_counter() - t0
            print(f"  {i + 1} cases, {el:.0f} s, {(i + 1) / el:.0f}/s, {len(failures)} failure classes, "
                  f"longest {longest[0]:.2f} s", flush=True)
        del text
    elapsed = time.perf_counter() - t0
    out = {"cases": done, "seed": seed, "elapsed_s": elapsed, "rate": done / elapsed if elapsed else 0.0,
           "kinds": kinds, "failures": failures, "slow": slow, "longest_s": longest[0],
           "longest_case": longest[1], "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
           "alarms": alarms}
    if save and failures:
        d = Path(save)
        d.mkdir(parents=True, exist_ok=True)
        for j, (k, (c, first, prog)) in enumerate(sorted(failures.items())):
            small = minimise(prog, k, machine, minimise_budget)
            (d / f"failure_{seed}_{j}.nc").write_text(small, "utf-8", newline="")
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--steps", type=int, default=2000, help="step limit per case (moves and calls "
                    "scaled from it); ignored with --default-limits")
    ap.add_argument("--default-limits", action="store_true", help="the default machine's limits")
    ap.add_argument("--save", help="write a minimised reproducer of each failure class here")
    ap.add_argument("--case-timeout", type=float, default=30.0, help="stop a case after this many "
                    "seconds (counted as slow); 0 = no timer")
    ap.add_argument("--seconds", type=float, default=0.0, help="stop the run after this many seconds")
    ap.add_argument("--memory-mb", type=int, default=3072, help="address-space cap of this process "
                    "(a case that needs more fails with MemoryError)")
    ap.add_argument("--compare", action="store_true", help="run each case also with the compiled "
                    "core off and report any difference from the Python code as a failure")
    a = ap.parse_args(argv)
    if a.memory_mb:
        lim = a.memory_mb * 1024 * 1024
        resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
    os.environ.setdefault("PYTHONHASHSEED", "0")
    res = fuzz(a.cases, a.seed, None if a.default_limits else a.steps, a.save, progress=True,
               case_timeout=a.case_timeout, seconds=a.seconds, compare=a.compare)
    from hnc_cam.nc import toolpath
    print("compiled core: " + ("on" + (", compared with the Python code case by case" if a.compare else "")
                               if toolpath.core is not None else "off (not built or HNC_CAM_PURE set)"))
    print(f"cases: {res['cases']} (grammar {res['kinds']['grammar']}, mutation {res['kinds']['mutation']}), "
          f"seed {res['seed']}")
    print(f"time: {res['elapsed_s']:.1f} s, rate {res['rate']:.0f} cases/s")
    print(f"failures (exceptions other than alarms, alarms not one printable line): "
          f"{sum(c for c, _, _ in res['failures'].values())} in {len(res['failures'])} classes")
    for k, (c, first, prog) in sorted(res["failures"].items()):
        print(f"  {c:6d}  {first}")
        print(f"          e.g. {prog[:200]!r}")
    print(f"cases over {SLOW_S:g} s: {len(res['slow'])}")
    for dt, i, text in res["slow"][:20]:
        print(f"  case {i}: {dt:.1f} s  {text[:200]!r}")
    print(f"longest case: {res['longest_s']:.3f} s (case {res['longest_case']})")
    print(f"peak memory (max RSS): {res['peak_rss_mb']:.0f} MB")
    return 1 if res["failures"] or res["slow"] else 0


if __name__ == "__main__":
    sys.exit(main())
