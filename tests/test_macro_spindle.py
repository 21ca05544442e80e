"""The HNC-21T macro's spindle: its G96 has no clamp word, so where G96 would need more than
the tool's limit (the machine's, the chuck's or the tool's) the per-variant program switches
to G97 before the blocks that come inside the critical diameter, and back. The macro writes
those switches at the control where the per-variant program has them, for every set of the
domain: the commanded spindle of each move (mode and S, compared on a machine without the
G96 clamp, where both show) equals the per-variant program's, and never exceeds the limit."""
from __future__ import annotations

import dataclasses
import re
from pathlib import Path
from types import SimpleNamespace

import pytest

from hnc_cam.errors import PlanError

ROOT = Path(__file__).resolve().parent.parent
FAMS = ROOT / "tests" / "data" / "families"
SPACER = FAMS / "spacer.py"
MACHINE = ROOT / "hnc_cam" / "data" / "machine.toml"


def _machine(tmp, rpm):
    """The bundled machine with a chuck rated ``rpm`` (below the machine's 3000)."""
    text = MACHINE.read_text(encoding="utf-8")
    assert "[chuck]" in text
    path = Path(tmp) / f"chuck{rpm}.toml"
    path.write_text(text.replace("[chuck]", f"[chuck]\nmax_rpm = {rpm}.0", 1), encoding="utf-8")
    return path


def _derive(path, base=None, machine=None):
    """(context, family, pieces, machine, tools) of the HNC-21T derivation, as the command
    does it."""
    from hnc_cam.plan import macro_command as mc
    from hnc_cam.plan.api import _load_machine, _load_tools
    from hnc_cam.plan.macro import load_family
    from hnc_cam.plan.macro_program import Ctx, derive_pieces, family_stock, sample
    fam = load_family(str(path), base or {}, [], spread=mc.SPREAD)
    stock = family_stock(fam, fam.lo, fam.hi, sample(fam, fam.trace, fam.lo, fam.hi, 20, "stock"))
    opts = dict(comp="control", verify=False, dialect="hnc21t",
                machine=str(machine) if machine else None)
    ctx = Ctx(str(path), opts, stock, "hnc21t")
    lib = _load_tools(None)
    mach = _load_machine(opts["machine"], lib)
    return ctx, fam, derive_pieces(ctx, fam), mach, lib


def _spindles(text, machine):
    """(tool, rpm) of each move that moves, run on ``machine`` without its G96 clamp: a G96
    move turns at the rpm of its own surface speed, a G97 move at its S."""
    from hnc_cam.nc import run
    free = dataclasses.replace(machine, max_rpm=1.0e9)
    return [(m.tool, m.spindle, m.start, m.end) for m in run(text, machine=free).moves
            if m.kind != "dwell" and (abs(m.end[0] - m.start[0]) > 1e-3
                                      or abs(m.end[1] - m.start[1]) > 1e-3)]


def _same_spindle(macro, ref):
    assert len(macro) == len(ref)
    for a, b in zip(macro, ref):
        assert a[0] == b[0]
        assert a[1] == pytest.approx(b[1], rel=1e-4, abs=0.5), (a, b)


def _at(pieces, fam, **kw):
    """The piece holding the nominal set changed by ``kw``, and that set."""
    from hnc_cam.plan.macro_program import piece_of
    p = dict(fam.params, **kw)
    pc = piece_of(pieces, p)
    assert pc is not None, p
    return pc, p


def _finish_rpm(moves, radius):
    """The rpm of the finishing tool's (T02) feed moves along Z at ``radius`` (the part's
    diameter, whatever the nose's offset from it)."""
    got = {round(m[1], 3) for m in moves
           if m[0] == 2 and abs(m[2][0] - m[3][0]) < 1e-6 and abs(m[2][0] - radius) < 0.5
           and abs(m[2][1] - m[3][1]) > 5}
    assert len(got) == 1, got
    return got.pop()


@pytest.fixture(scope="module")
def spacer_26():
    """The spacer around d2 = 26: the finishing contour's G97 S3000 (inside diameter 25.465,
    G96 S240 at 3000 rpm) falls before the collar's chamfer, its cylinder, or neither."""
    return _derive(SPACER, {"d2": "26"})


def test_the_spacer_is_one_macro_family_on_the_default_machine(tmp_path, capsys):
    """The spacer on the default machine: its G71 is split where G96 S180 meets 3000 rpm and
    its inner part runs G97 at the rpm of its top (S2981 at d1 18), which moves with d1; the
    macro holds it and passes its check on 20 sets."""
    from hnc_cam.cli import main
    out = tmp_path / "m.nc"
    assert main(["family", str(SPACER), "--macro", "--check", "20", "-o", str(out)]) == 0
    assert out.exists()
    ctx, fam, pieces, mach, _lib = _derive(SPACER)
    for d1 in (17.96, 18.2, 18.59):
        pc, p = _at(pieces, fam, d1=d1)
        from hnc_cam.plan.macro_program import render_program
        text = render_program(pc, "hnc21t", values=p).text
        _same_spindle(_spindles(text, mach), _spindles(ctx.program(p), mach))


@pytest.mark.parametrize("d2, chamfer, where", [
    (25.0, 0.8, "both"),  # the chamfer and the cylinder inside 25.465: G97
    (25.9, 0.8, "chamfer"),  # the chamfer starts inside (24.3), the cylinder is outside
    (27.0, 0.76, "neither"),  # the chamfer starts at 25.48: G96 from there
])
def test_the_finishing_switch_moves_with_the_collar(spacer_26, d2, chamfer, where):
    from hnc_cam.plan.macro_program import render_program
    ctx, fam, pieces, mach, _lib = spacer_26
    pc, p = _at(pieces, fam, d2=d2, chamfer=chamfer)
    text = render_program(pc, "hnc21t", values=p).text
    got, ref = _spindles(text, mach), _spindles(ctx.program(p), mach)
    _same_spindle(got, ref)
    cyl = _finish_rpm(got, d2 / 2)
    if where == "both":
        assert cyl == pytest.approx(3000)
    else:  # G96 S240 at the cylinder: below 3000
        assert cyl == pytest.approx(240000 / (3.141592653589793 * d2), rel=0.02)
        assert cyl < 3000


def test_the_macro_check_reports_a_set_whose_spindle_differs(spacer_26):
    """--check compares the commanded spindle: the macro with its conditional switches taken
    out fails at a set where the per-variant program switches back to G96 before the
    collar's cylinder (the macro stays at G97 S3000, a slower spindle: no limit passed, but
    not the per-variant program's), and the failure names the set."""
    from hnc_cam.plan.macro_program import Rendered, check_program, render_program
    ctx, fam, pieces, mach, lib = spacer_26
    pc, p = _at(pieces, fam, d2=25.9, chamfer=0.8)
    good = render_program(pc, "hnc21t", values=p)
    bad = Rendered(re.sub(r"(?m)^G\[#\d+\] S\[#\d+\]\n", "", good.text), good.var, good.dialect)
    assert bad.text != good.text
    res = check_program(ctx, pc, [("good", p, good), ("bad", p, bad)], mach, lib, 0.01)
    assert res[0]["ok"], res[0]["message"]
    assert not res[1]["ok"] and "d2=25.9" in res[1]["params"]
    assert res[1]["message"].startswith("spindle")


@pytest.fixture(scope="module")
def spacer_chuck(tmp_path_factory):
    """The spacer on a machine whose chuck is rated 2500 rpm: G96 S240 needs more inside
    diameter 30.558, inside the collar's range (28.5-31.5), so the finishing switch before
    the collar's cylinder moves with d2, inside the profile that the G71 roughs."""
    return _derive(SPACER, machine=_machine(tmp_path_factory.mktemp("m"), 2500))


def _profile(text, program="%1001"):
    """The lines of each G71's profile (P..Q) in the macro subprogram."""
    lines = text.split(program, 1)[1].splitlines()
    out = []
    for ln in lines:
        m = re.search(r"G71 .*P(\d+) Q(\d+)", ln)
        if m:
            i = next(k for k, x in enumerate(lines) if x.startswith(f"N{m.group(1)} "))
            j = next(k for k, x in enumerate(lines) if x.startswith(f"N{m.group(2)} "))
            out.append(lines[i:j + 1])
    return out


@pytest.mark.parametrize("d2", [30.2, 31.0])
def test_a_slower_chuck_switches_inside_a_g71_profile(spacer_chuck, d2):
    from hnc_cam.plan.macro_program import render_program
    ctx, fam, pieces, mach, _lib = spacer_chuck
    assert len(pieces) == 1
    pc, p = _at(pieces, fam, d2=d2)
    text = render_program(pc, "hnc21t", values=p).text
    # the conditional switch stands inside a G71's profile: a block, no IF there
    assert any(any(ln.startswith("G[#") for ln in prof) for prof in _profile(text))
    assert not any(ln.startswith(("IF", "#")) for prof in _profile(text) for ln in prof)
    got, ref = _spindles(text, mach), _spindles(ctx.program(p), mach)
    _same_spindle(got, ref)
    cyl = _finish_rpm(got, d2 / 2)
    assert cyl == (pytest.approx(2500) if d2 < 30.558 else pytest.approx(
        240000 / (3.141592653589793 * d2), rel=0.02))


def test_a_slower_chuck_is_never_passed_over_the_domain(spacer_chuck):
    """20 sets over the domain on the real machine (3000 rpm, chuck 2500): every move of the
    macro at or below 2500 rpm, its toolpath the per-variant program's, verified; with G96
    S240 in place of the switch (the limit left to the control's clamp at 3000), d2 30.2
    turns the chuck at 2529 rpm and the check says so."""
    from hnc_cam.plan.macro_program import Rendered, check_program, render_program, sample
    from hnc_cam.nc import run
    ctx, fam, pieces, mach, lib = spacer_chuck
    pc = pieces[0]
    sets = sample(fam, pc.tr, pc.lo, pc.hi, 20, "chuck", extra=pc.extra)
    runs = [(str(i), p, render_program(pc, "hnc21t", values=p)) for i, p in enumerate(sets)]
    for res in check_program(ctx, pc, runs, mach, lib, 0.01):
        assert res["ok"], res
    for _label, _p, rend in runs[:5]:
        assert max(m.spindle for m in run(rend.text, machine=mach).moves) <= 2500 + 1e-6
    p = dict(fam.params, d2=30.2)
    good = render_program(pc, "hnc21t", values=p)
    bad = Rendered(re.sub(r"(?m)^G\[#\d+\] S\[#\d+\]$", "G96 S240", good.text), good.var,
                   good.dialect)
    assert bad.text != good.text
    res = check_program(ctx, pc, [("bad", p, bad)], mach, lib, 0.01)[0]
    assert not res["ok"] and "above T02's limit of 2500" in res["message"]


@pytest.mark.parametrize("check", ["2", "0"])
def test_a_chuck_slower_than_the_machine_gets_its_macro(tmp_path, capsys, check):
    """The pin on a chuck rated 1500 rpm (once refused): the per-variant program runs G97 at
    1500 wherever G96 would need more, and so does the macro; on that machine no move of it
    turns faster than 1500 rpm."""
    from hnc_cam.cli import main
    from hnc_cam.nc import run
    from hnc_cam.plan.api import _load_machine, _load_tools
    mach_path = _machine(tmp_path, 1500)
    out = tmp_path / "m.nc"
    assert main(["family", str(FAMS / "pin.py"), "--macro", "--check", check, "--machine",
                 str(mach_path), "-o", str(out)]) == 0
    mach = _load_machine(str(mach_path), _load_tools(None))
    moves = run(out.read_text(), machine=mach).moves
    assert moves and max(m.spindle for m in moves) <= 1500 + 1e-6


def test_spacer_split_on_the_chamfer_matches_on_every_row(tmp_path, capsys):
    """The spacer with d1 from 17.95 up to 19.5: from about 18.7 the G71's split falls on
    the 45 deg chamfer at a half of the last digit (d1 with an odd third decimal); the macro
    rounds it as the planner does."""
    rc, err, _out = _spacer_macro(tmp_path, capsys, "(17.95, 19.5)",
                                  "d1,chamfer\n18.801,0.8\n18.903,0.78\n19.005,0.8\n"
                                  "19.207,0.82\n19.409,0.8\n18.8,0.8\n19.3,0.8\n", "2")
    assert rc == 0, err
    assert "checked 9 parameter set(s): pass" in err


def test_a_split_on_the_chamfer_at_a_half_digit_is_rounded_alike(tmp_path, capsys):
    """The pin on a chuck rated 2500 rpm (HNC-21T: the G71 split where G96 would need more,
    FANUC and the 802 clamp instead): the G71's split falls on the 45 deg chamfer, at a
    Z that is an exact half of the last digit wherever the split's diameter and the chamfer's
    end are (d with an odd third decimal); the planner and the macro round that half the
    same way (up), so the macro's Z is the per-variant program's on every row."""
    from hnc_cam.cli import main
    table = tmp_path / "rows.csv"
    table.write_text("d,chamfer\n24.113,0.957\n23.001,1\n24.503,1.01\n23.999,0.99\n"
                     "24.5,1\n")
    out = tmp_path / "m"
    rc = main(["family", str(FAMS / "pin.py"), "--macro", "--table",
               str(table), "--check", "2", "--machine", str(_machine(tmp_path, 2500)),
               "-o", str(out) + "/"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert "checked 7 parameter set(s): pass" in err


@pytest.mark.parametrize("dialect, clamp", [("fanuc0it", "G50 S2500"),
                                            ("siemens802", "LIMS=2500")])
def test_fanuc_and_the_802_clamp_in_the_program(tmp_path, dialect, clamp):
    """FANUC (G50 S) and the 802 (LIMS=) clamp G96 in the program: their macros keep the
    clamp and have no switches at the control."""
    from hnc_cam.cli import main
    out = tmp_path / "m.nc"
    assert main(["family", str(FAMS / "pin.py"), "--macro", "--dialect", dialect, "--check",
                 "2", "--machine", str(_machine(tmp_path, 2500)), "-o", str(out)]) == 0
    text = out.read_text()
    assert clamp in text and "G[#" not in text


def _toy(text, p):
    from hnc_cam.plan import macro_merge as mm
    v = mm.prog(p, text, "hnc21t")
    return v, v.secs


_TOY = """%0001
(T01 TURN)
N1 T0101
N2 G96 S180 M03
N3 G00 X40 Z2
{a}N4 G01 X20 Z-5 F0.2
{b}N5 G01 X40 Z-5
N6 M30
"""


def test_a_switch_no_diameter_explains_is_refused():
    """Two variants whose blocks are the same numbers but whose switch differs: no condition
    on the diameters tells them apart, so the macro is refused, naming the block."""
    from hnc_cam.plan.macro_program import spindle_gaps
    a = _toy(_TOY.format(a="", b=""), {"d": 1.0})
    b = _toy(_TOY.format(a="N30 G97 S3000\n", b="N31 G96 S180\n"), {"d": 2.0})
    ab = [blk for sec in a[1] for blk in sec.blocks]
    fam = SimpleNamespace(path="toy.py", free=["d"])
    tr = SimpleNamespace(segments=[])
    with pytest.raises(PlanError, match=r"toy.py: the spindle switch before line \d+ "
                                        r"\[N4 G01 X20 Z-5 F0.2\]"):
        spindle_gaps(fam, tr, [a, b], ab, [], None, lambda t: 3000.0, [])
    # where the block's diameter is a law of d, the switch is the planner's condition on it:
    # inside 1000*180/(pi*3000) = 19.099 G97 S3000, else G96 S180; back to G96 after
    from hnc_cam.plan.macro_program import Slot, _holds_all
    c = _toy(_TOY.format(a="N30 G97 S3000\n", b="N31 G96 S180\n").replace("X20", "X18"),
             {"d": 0.9})
    n4 = next(i for i, blk in enumerate(ab) if blk.raw.startswith("N4 "))
    x = next(i for i, w in enumerate(ab[n4].words) if w.letter == "X")
    law = Slot(n4, x, "fit", ("*", ("c", 20.0), ("p", "d")))
    gaps = spindle_gaps(fam, tr, [a, c], ab, [law], None, lambda t: 3000.0, [])
    assert sorted(gaps) == [n4, n4 + 1]
    g = gaps[n4]
    assert (g.yes, g.no) == ((97.0, 3000.0), (96.0, 180.0))
    assert list(_holds_all(g.cond, [{"d": 0.95}, {"d": 0.96}])) == [True, False]
    assert gaps[n4 + 1].cond is None and gaps[n4 + 1].yes == (96.0, 180.0)


def test_a_switch_no_variant_showed_is_written_from_the_domain():
    """The sampled variants all run the block at G96 (its diameter 20 d outside 19.099 at
    d 1 and 1.05), but the domain reaches d 0.9: the planner's condition, evaluated over the
    domain's sets, gives the block its conditional switch, and the next one (which starts
    where the block ends) its own."""
    from hnc_cam.plan.macro_program import Slot, _holds_all, spindle_gaps
    a = _toy(_TOY.format(a="", b=""), {"d": 1.0})
    b = _toy(_TOY.format(a="", b="").replace("X20", "X21"), {"d": 1.05})
    ab = [blk for sec in a[1] for blk in sec.blocks]
    fam = SimpleNamespace(path="toy.py", free=["d"])
    tr = SimpleNamespace(segments=[])
    n4 = next(i for i, blk in enumerate(ab) if blk.raw.startswith("N4 "))
    x = next(i for i, w in enumerate(ab[n4].words) if w.letter == "X")
    law = Slot(n4, x, "fit", ("*", ("c", 20.0), ("p", "d")))
    assert spindle_gaps(fam, tr, [a, b], ab, [law], None, lambda t: 3000.0, []) == {}
    dom = [{"d": 0.9 + 0.01 * k} for k in range(20)]
    gaps = spindle_gaps(fam, tr, [a, b], ab, [law], None, lambda t: 3000.0, dom)
    assert sorted(gaps) == [n4, n4 + 1]
    for g in gaps.values():
        assert (g.yes, g.no) == ((97.0, 3000.0), (96.0, 180.0))
        assert list(_holds_all(g.cond, [{"d": 0.95}, {"d": 0.96}])) == [True, False]


def _spacer_macro(tmp_path, capsys, d1: str, rows: str, check: str):
    """The spacer family with ``DOMAIN = {"d1": d1}`` made with ``--macro`` for the table
    ``rows`` into a folder: (exit code, stderr, the folder)."""
    from hnc_cam.cli import main
    fam = tmp_path / "spacer.py"
    fam.write_text(SPACER.read_text().replace('DOMAIN = {"d1": (17.95, 18.6)}',
                                              f'DOMAIN = {{"d1": {d1}}}'))
    table = tmp_path / "rows.csv"
    table.write_text(rows)
    out = tmp_path / "m"
    rc = main(["family", str(fam), "--macro", "--table", str(table), "--check", check,
               "-o", str(out) + "/"])
    return rc, capsys.readouterr().err, out


def test_a_switch_beside_the_kink_is_decided_at_the_control(tmp_path, capsys):
    """The spacer over d1 17.1-18.6: the G71's split X is X19.1 below d1 17.9 and d1 + 1.22
    above it, but the laws cross at 17.88, not where the planner switches; the larger of the
    two was 0.0025 mm off at d1 17.885. The variants beside the kink show it, and the word
    becomes a decision at the planner's own switch: one program, proven on table rows on
    both sides of the switch and of the kink (other dimensions moved too)."""
    import re

    rc, err, out = _spacer_macro(
        tmp_path, capsys, "(17.1, 18.6)",
        "d1,chamfer,l1\n17.5,0.8,15\n17.879,0.8,15\n17.885,0.8,15\n"
        "17.895,0.78,15.5\n17.899,0.8,15\n17.9,0.82,14.5\n18.3,0.8,15\n", "3")
    assert rc == 0, err
    progs = sorted(out.glob("O*.nc"))
    assert len(progs) == 1
    text = progs[0].read_text()
    # the decision: on d1, at the planner's switch (17.899 takes X19.1, 17.9 takes d1 + 1.22)
    m = re.search(r"\(D1 < ([0-9.]+)\?\)", text)
    assert m and 17.899 < float(m.group(1)) <= 17.9, text
    # one branch holds the clamp's X19.1, the other the journal's law
    assert "X19.1\n" in text and re.search(r"X\[#\d+\+1\.22\]", text)
