"""Every bundled part in every dialect and compensation mode: generate, read the program back
with the same dialect's reader, verify against the model; the FANUC/Haas text follows the
control's rules (a decimal point on every coordinate, G50 S before each G96, the two-block or
one-block cycles); the same plan cuts the same part in every dialect."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from hnc_cam.plan.api import generate

REPO = Path(__file__).resolve().parents[1]
PARTS = REPO / "parts"

pytestmark = pytest.mark.cad

DIALECTS = ("hnc21t", "fanuc0it", "haas", "siemens802")
BUNDLED = sorted(p.name for p in PARTS.glob("*.py"))

#: a part written the way a user writes one: a sleeve with a chamfered bore, a taper and a
#: convex arc on the outside, cut from a tube
SLEEVE = '''\
from build123d import (Axis, BuildLine, BuildPart, BuildSketch, Line, Plane, ThreePointArc,
                       make_face, revolve)

STOCK = "50/16x46+1"


def part(outer: float = 46.0, bore: float = 22.0, length: float = 42.0):
    ro, rb = outer / 2, bore / 2
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Line((rb + 1.0, 0), (ro - 6.0, 0))
                Line((ro - 6.0, 0), (ro - 6.0, -8))
                Line((ro - 6.0, -8), (ro - 2.0, -16))
                ThreePointArc((ro - 2.0, -16), (ro - 1.5, -19), (ro - 2.0, -22))
                Line((ro - 2.0, -22), (ro - 2.0, -26))
                Line((ro - 2.0, -26), (ro, -26))
                Line((ro, -26), (ro, -length))
                Line((ro, -length), (rb, -length))
                Line((rb, -length), (rb, -1.0))
                Line((rb, -1.0), (rb + 1.0, 0))
            make_face()
        revolve(axis=Axis.Z)
    return p.part
'''

_HNC: dict = {}


def _hnc_report(part: Path, comp: str):
    """The HNC-21T program's verification of the same part and mode (the reference)."""
    key = (str(part), comp)
    if key not in _HNC:
        _HNC[key] = generate(part, comp=comp, dialect="hnc21t").report
    return _HNC[key]


_WORD = re.compile(r"([A-Z])([-+]?[0-9.]+)")


def _blocks(text: str) -> list[str]:
    """The program's blocks without their N numbers (comments, % and the O line left out)."""
    out = []
    for ln in text.splitlines():
        if not ln or ln.startswith(("(", "%", "O")):
            continue
        out.append(re.sub(r"^N\d+ ", "", ln))
    return out


def _check_fanuc_text(text: str, dialect: str, plan) -> None:
    lines = text.splitlines()
    assert lines[0] == "%" and lines[-1] == "%"
    assert re.fullmatch(r"O\d{4} \(.*\)", lines[1])
    blocks = _blocks(text)
    assert blocks[0] == "G21 G40 G99 G97"
    for i, b in enumerate(blocks):
        words = _WORD.findall(b)
        letters = [w[0] for w in words]
        for letter, value in words:
            integer = letter in "GMNSTPQ" or (letter == "R" and b.startswith("G73 U")) \
                or (letter == "D" and b.startswith("G73 P")) \
                or (letter == "A" and b.startswith("G76 X"))
            if integer:
                assert "." not in value, (b, letter)
            else:  # a coordinate, a length or a feed: always with its decimal point
                assert "." in value, (b, letter)
        if "G96" in letters and b.startswith("G96"):
            assert blocks[i - 1].startswith("G50 S"), (blocks[i - 1], b)
    roles = {op.role for op in plan.operations}
    rough = [op for op in plan.operations if op.kind == "rough"]
    for op in rough:
        code = {"turn": "G71", "face": "G72", "pattern": "G73"}[op.rough.strategy]
        if dialect == "fanuc0it":
            first = [i for i, b in enumerate(blocks) if b.startswith(code + " ")
                     and " P" not in b]
            assert first, (code, blocks)
            second = [blocks[i + 1] for i in first]
            assert all(s.startswith(f"{code} P") and " Q" in s and " U" in s for s in second)
        else:
            assert any(b.startswith(f"{code} P") and (" D" in b) for b in blocks), code
    if rough:
        assert any(b.startswith("G70 P") for b in blocks)
    if "thread" in roles:
        g76 = [b for b in blocks if b.startswith("G76 ")]
        if dialect == "fanuc0it":
            assert len(g76) % 2 == 0 and g76[0].startswith("G76 P") and " X" in g76[1]
        else:
            assert g76 and all(" K" in b and " D" in b for b in g76)
    if plan.comp == "control":
        assert any(" G41" in b or " G42" in b for b in blocks)


def _check_siemens_text(text: str, plan) -> None:
    """The 802 program's framing and cycles: %_N_NAME_MPF with its ;$PATH line, then one
    %_N_NAME_Cn_SPF per roughed contour ending in RET; every roughing operation an LCYC95
    call naming a subprogram of the file (a pattern repeat: the subprogram under G158), a
    groove LCYC93, a thread LCYC97 (G33 passes), G96 always with LIMS=."""
    from hnc_cam.plan.export import split_programs
    progs = split_programs(text)
    names = [n for n, _ in progs]
    assert names[0].endswith(".MPF") and all(n.endswith(".SPF") for n in names[1:])
    main = progs[0][1].splitlines()
    assert main[0] == f"%_N_{names[0][:-4]}_MPF" and main[1] == ";$PATH=/_N_MPF_DIR"
    body = [re.sub(r"^N\d+ ", "", ln) for ln in main if not ln.startswith((";", "%"))]
    assert body[0] == "G18 G23 G71 G90 G95 G40" and body[-1] == "M2"
    for _, sub in progs[1:]:
        lines = sub.splitlines()
        assert lines[1] == ";$PATH=/_N_SPF_DIR" and re.fullmatch(r"N\d+ RET", lines[-1])
    for b in body:
        assert not re.search(r"\b[UWQPH]-?\d", b), b  # no FANUC/HNC words
        if b.startswith("G96"):
            assert " LIMS=" in b, b
    cnames = [b.split('"')[1] for b in body if b.startswith("_CNAME=")]
    assert all(f"{c}.SPF" in names for c in cnames)
    rough = [op for op in plan.operations if op.kind == "rough"]
    pattern = [op for op in rough if op.rough.strategy == "pattern"]
    assert body.count("LCYC95") >= len(rough) - len(pattern)
    if pattern:
        assert any(b.startswith("G158 X") for b in body)
    roles = [op.role for op in plan.operations]
    assert body.count("LCYC93") == roles.count("groove")
    assert body.count("LCYC97") == roles.count("thread")
    if "thread_passes" in roles:
        assert any(b.startswith("G33 Z") and " K" in b and " SF=" in b for b in body)
    if plan.comp == "control":
        assert any(" G41" in b or " G42" in b or re.search(r"R105=[5-8]\b", b) for b in body)


def _check(prog, part: Path, comp: str, dialect: str) -> None:
    assert prog.dialect == dialect
    assert prog.toolpath is not None and prog.toolpath.moves  # read back without an alarm
    lines = prog.text.splitlines()
    # no warning at all: G73's pass count R, written without a point, is a count to the reader
    warned = [(lines[w.line - 1], w.message) for w in prog.toolpath.warnings]
    assert not warned, warned
    rep = prog.report
    assert rep is not None and rep.passed, rep.summary()
    assert rep.max_overcut_mm <= 0.01
    if dialect == "siemens802":
        _check_siemens_text(prog.text, prog.plan)
    if dialect != "hnc21t":
        if dialect != "siemens802":
            _check_fanuc_text(prog.text, dialect, prog.plan)
        ref = _hnc_report(part, comp)
        # the same plan cuts the same part: gouge and leftover as the HNC program's
        assert rep.max_overcut_mm == pytest.approx(ref.max_overcut_mm, abs=0.002)
        assert rep.max_undercut_mm == pytest.approx(ref.max_undercut_mm, abs=0.002)
    else:
        assert prog.text.startswith("%0001\n")
    if comp == "cam":
        assert " G41" not in prog.text and " G42" not in prog.text


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("part", BUNDLED)
def test_bundled_part_in_every_dialect(part, dialect, comp):
    prog = generate(PARTS / part, comp=comp, dialect=dialect)
    _check(prog, PARTS / part, comp, dialect)


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("dialect", DIALECTS)
def test_fresh_sleeve_in_every_dialect(tmp_path, dialect, comp):
    part = tmp_path / "sleeve.py"
    part.write_text(SLEEVE)
    prog = generate(part, comp=comp, dialect=dialect)
    _check(prog, part, comp, dialect)
    assert {op.name for op in prog.plan.operations} >= {"bore_rough", "bore_finish", "finish"}


def test_cli_generate_and_verify_in_fanuc(tmp_path, capsys):
    """generate --dialect fanuc0it writes a FANUC program; verify reads it back with the same
    --dialect (parameters and stock from its header) and passes; read as HNC it is refused
    naming the FANUC framing."""
    from hnc_cam.cli import main
    out = tmp_path / "o.nc"
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--dialect", "fanuc0it",
               "--set", "length=95", "--program-number", "12", "-o", str(out)])
    assert rc == 0, capsys.readouterr().err
    text = out.read_text()
    assert text.startswith("%\nO0012 (stepped_shaft)\n(PARAMETERS ") and "length=95" in text
    capsys.readouterr()
    rc = main(["verify", str(out), "--model", str(PARTS / "stepped_shaft.py"),
               "--dialect", "fanuc0it"])
    cap = capsys.readouterr()
    assert rc == 0 and "PASS" in cap.out, cap.err
    rc = main(["verify", str(out), "--model", str(PARTS / "stepped_shaft.py")])
    err = capsys.readouterr().err
    assert rc == 2 and "alarm" in err and "FANUC" in err


def test_family_in_haas_and_the_machine_files_controller(tmp_path, capsys):
    """family --dialect haas writes Haas programs; a machine file with controller = "haas"
    makes it the default of generate, and --dialect overrides it."""
    from hnc_cam.cli import main
    table = tmp_path / "t.csv"
    table.write_text("length,program_number\n100,7\n95,8\n")
    out = tmp_path / "out"
    rc = main(["family", str(PARTS / "stepped_shaft.py"), "--table", str(table), "--out",
               str(out), "--jobs", "1", "--dialect", "haas"])
    assert rc == 0, capsys.readouterr().err
    for n in (7, 8):
        text = (out / f"O{n:04d}.nc").read_text()
        assert text.startswith(f"%\nO{n:04d} ") and re.search(r"\nN\d+ G71 P\d+ Q\d+ U", text)
    machine = tmp_path / "m.toml"
    machine.write_text('controller = "haas"\n'
                       + (REPO / "hnc_cam" / "data" / "machine.toml").read_text())
    prog = generate(PARTS / "stepped_shaft.py", machine=str(machine), verify=False)
    assert prog.dialect == "haas" and " D1.5 " in prog.text
    prog = generate(PARTS / "stepped_shaft.py", machine=str(machine), verify=False,
                    dialect="hnc21t")
    assert prog.dialect == "hnc21t" and prog.text.startswith("%0001\n")


def _variants():
    """Operations the bundled parts do not all reach: G94/G81 facing without a spindle cap,
    G01 facing, G92/G82 thread passes, a two-start thread, a thread run into a shoulder
    without a relief (the run-out), G72, G73, an undercut zone (type II), a groove."""
    import sys
    sys.path.insert(0, str(Path(__file__).parent))
    from test_plan_shapes import bushing, chain, flange, grooved, shaft, stud, undercut, wavy
    from hnc_cam.geometry import Thread, TurnedProfile

    def two_start():
        p = stud()
        p.threads = [Thread(0.0, -22.0, 20.0, 1.5, 2)]
        return p

    def shoulder():  # no relief: the thread runs out along G76's end chamfer
        return TurnedProfile(chain((0, 0), (9, 0), (10, -1), (10, -26), (13, -26), (13, -45),
                                   (0, -45)),
                             threads=[Thread(0.0, -26.0, 20.0, 1.5)], name="shoulder")
    return {
        "face_cycle": (bushing, "42/16x45+2", {"face_cycle": "g81"}, "m.toml"),
        "face_passes": (shaft, "50x90+2", {"face_cycle": "g01"}, None),
        "thread_passes": (stud, "30x46+1", {"thread_cycle": "g82"}, None),
        "two_start": (two_start, "30x46+1", {}, None),
        "two_start_passes": (two_start, "30x46+1", {"thread_cycle": "g82"}, None),
        "shoulder": (shoulder, "30x46+1", {}, None),
        "g72": (flange, "104x30+2", {}, None),
        "g73": (wavy, "offset:2", {}, None),
        "zones": (undercut, "40x70", {}, None),
    }


VARIANTS = ["face_cycle", "face_passes", "thread_passes", "two_start", "two_start_passes",
            "shoulder", "g72", "g73", "zones"]


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("dialect", ["fanuc0it", "haas"])
@pytest.mark.parametrize("key", VARIANTS)
def test_operation_variants_in_fanuc_and_haas(tmp_path, key, dialect, comp):
    shape, stock, kw, machine = _variants()[key]
    if machine:  # a spindle limit high enough that facing needs no G97 cap: the G94 cycle
        m = tmp_path / machine
        m.write_text((REPO / "hnc_cam" / "data" / "machine.toml").read_text()
                     .replace("max_rpm = 3000.0", "max_rpm = 9000.0"))
        kw = dict(kw, machine=str(m))
    ref = generate(shape(), stock, comp=comp, dialect="hnc21t", **kw)
    prog = generate(shape(), stock, comp=comp, dialect=dialect, **kw)
    assert ref.report.passed and prog.report.passed, prog.report.summary()
    assert prog.report.max_overcut_mm == pytest.approx(ref.report.max_overcut_mm, abs=0.002)
    assert prog.report.max_undercut_mm == pytest.approx(ref.report.max_undercut_mm, abs=0.002)
    _check_fanuc_text(prog.text, dialect, prog.plan)
    blocks = _blocks(prog.text)
    if key == "face_cycle":
        assert sum(b.startswith("G94 X") for b in blocks) == 2
    threads = [op for op in prog.plan.operations if op.kind == "thread"]
    if key in ("thread_passes", "two_start_passes"):
        g92 = [b for b in blocks if b.startswith("G92 ")]
        assert len(g92) == len(threads[0].passes) * threads[0].thread.starts
        assert g92[-1] == g92[-2]  # the spring pass
    if key.startswith("two_start"):
        assert threads[0].thread.starts == 2
        # the second start begins one lead / starts (1.5 mm) further out in Z
        z = [float(b.split("Z")[1]) for b in blocks if re.fullmatch(r"G00 Z[-0-9.]+", b)]
        assert any(abs(v - threads[0].start[1] - 1.5) < 1e-3 for v in z)
    if key == "shoulder":
        assert threads[0].thread.runout_z < 0
        if dialect == "fanuc0it":  # the run-out as the end chamfer r = 10 (one lead)
            assert any(b.startswith("G76 P0110") for b in blocks)

    def depths(p):  # the thread passes' depths (diameters), start and run-out legs aside
        return sorted({round(2 * m.start[0], 3) for m in p.toolpath.moves if m.kind == "thread"})
    if dialect == "fanuc0it" and threads:
        # the same passes as the HNC program's (G76: its depth law; G92: the G82 diameters)
        assert depths(prog) == depths(ref)


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("key", VARIANTS)
def test_operation_variants_in_siemens802(tmp_path, key, comp):
    """The same variants in the 802's forms: facing in G1 passes, G33 passes with SF= per
    start, LCYC97 with R114 starts, LCYC95 face roughing (R105=2), the pattern repeat as
    the contour subprogram under G158 offsets, undercut zones by LCYC95 on their own
    contours; each cuts the part as the HNC program does."""
    shape, stock, kw, machine = _variants()[key]
    if machine:
        m = tmp_path / machine
        m.write_text((REPO / "hnc_cam" / "data" / "machine.toml").read_text()
                     .replace("max_rpm = 3000.0", "max_rpm = 9000.0"))
        kw = dict(kw, machine=str(m))
    ref = generate(shape(), stock, comp=comp, dialect="hnc21t", **kw)
    prog = generate(shape(), stock, comp=comp, dialect="siemens802", **kw)
    assert prog.report.passed, prog.report.summary()
    assert not prog.toolpath.warnings
    assert prog.report.max_overcut_mm == pytest.approx(ref.report.max_overcut_mm, abs=0.002)
    assert prog.report.max_undercut_mm == pytest.approx(ref.report.max_undercut_mm, abs=0.002)
    _check_siemens_text(prog.text, prog.plan)
    blocks = _blocks(prog.text)
    ops = prog.plan.operations
    threads = [op for op in ops if op.kind == "thread"]
    if key.startswith("face"):
        face = ops[0]
        assert sum(b.startswith("G1 X") and " F" in b for b in blocks) >= len(face.passes)
    if key in ("thread_passes", "two_start_passes"):
        g33 = [b for b in blocks if b.startswith("G33 ")]
        t = threads[0]
        assert len(g33) == len(t.passes) * t.thread.starts
        assert {b.split("SF=")[1] for b in g33} == {f"{a:g}" for a in t.thread.start_angles}
    if key == "two_start":
        assert any(re.search(r"\bR114=2\b", b) for b in blocks)
    if key == "g72":
        assert any(re.search(r"\bR105=2\b", b) for b in blocks)
    if key == "g73":
        r = [op for op in ops if op.kind == "rough"][0].rough
        assert sum(b.startswith("G158 X") for b in blocks) == r.count
    if key == "zones":
        zones = [op for op in ops if op.name == "rough_zone"]
        assert blocks.count("LCYC95") >= 1 + len(zones)


def test_operations_are_named_by_the_dialects_cycles():
    """The summary (and the family table) names each operation by the cycle the program
    writes: G92 passes and G70 in FANUC, HNC-21T's own codes in HNC."""
    from test_plan_shapes import stud, undercut
    fanuc = generate(stud(), "30x46+1", dialect="fanuc0it", thread_cycle="g82", verify=False)
    assert fanuc.operations[-1] == "thread G92" and "finish G70" in fanuc.operations
    assert fanuc.operations[0] == "face G01"
    hnc = generate(stud(), "30x46+1", thread_cycle="g82", verify=False)
    assert hnc.operations[-1] == "thread G82" and "finish contour" in hnc.operations
    # --explain: the same names
    assert "FACE G01 " in fanuc.plan.explain(fanuc.labels)
    assert "G92" not in hnc.plan.explain(hnc.labels) and "G82" not in fanuc.plan.explain(fanuc.labels)
    zones = generate(undercut(), "40x70", dialect="haas", verify=False)
    assert "rough_zone G71-II" in zones.operations and "finish contour" in zones.operations
    assert "(T05 REST ROUGH Z-17.4..-37.4 G71-II D1 F0.2)" in zones.text
