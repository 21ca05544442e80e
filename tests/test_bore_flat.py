"""Flat-bottomed blind bores from solid bar: the largest drill whose point stays above the
bottom, then the boring bar roughs and finishes the bore and faces the bottom toward the
centre as far as its head (``min_bore``) leaves it; what the drill's point leaves nearer the
axis is named in a note; bottoms the bar cannot face at all are refused."""
from __future__ import annotations

import pytest

from hnc_cam.cli import main
from hnc_cam.plan.api import generate

from test_drill import COT59, FRESH, _part  # a user's part file, written as there


def _feeds(prog, tool: int):
    return [m for m in prog.toolpath.moves if m.tool == tool and m.kind != "rapid"]


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_flat_bottom_is_drilled_and_faced_to_the_centre_and_verifies(comp):
    prog = generate(FRESH / "flat_bore.py", comp=comp)
    assert prog.report.passed, prog.report.summary()
    ops = prog.plan.operations
    names = [op.name for op in ops]
    assert names[names.index("spot"):names.index("bore_finish") + 1] == [
        "spot", "drill", "bore_rough", "bore_finish"]
    # the 20 mm drill, the largest that fits the 36 mm bore, its tip 0.001 above the bottom
    drill = next(op for op in ops if op.name == "drill")
    assert drill.tool.number == 14 and drill.drill.z_end == pytest.approx(-24.999)
    assert min(m.end[1] for m in prog.toolpath.moves if m.tool == 14) == pytest.approx(-24.999)
    # the bar (its head, min_bore 16, fits across the 36 mm bore) roughs from the axis
    rough = next(op for op in ops if op.name == "bore_rough")
    assert rough.start[0] == pytest.approx(0.0)
    # the finishing pass reaches the bottom's Z and faces along it from the wall to the axis
    fin = _feeds(prog, 3)
    face = [m for m in fin if abs(m.start[1] + 25.0) < 1e-6 and abs(m.end[1] + 25.0) < 1e-6
            and m.end[0] < m.start[0] - 1.0]
    assert face, "no face pass along Z-25"
    assert max(m.start[0] for m in face) >= 18.0 - 0.5 - 1e-6
    # the tip P of code 2 lies a nose radius (0.4) off the nose's lowest point: that is on
    # the axis
    assert min(m.end[0] for m in face) <= 0.4 + 1e-6
    assert min(m.end[1] for m in _feeds(prog, 3)) == pytest.approx(-25.0, abs=1e-3)
    # nothing left on the bottom: what no tool reaches is the nose's fillet in the bore's
    # corner and the left end's edge, none near the axis
    assert prog.report.max_undercut_mm <= 0.01
    assert all(2 * u.x > 35.0 for u in prog.report.unreachable)


def test_flat_bottom_the_bars_head_does_not_reach_the_centre_is_named(tmp_path):
    # a 24 mm bore: the bar's head (min_bore 16) against the wall across the axis keeps its
    # tip 16 - 12 = 4 mm off the axis; it faces to 4 + 1 mm
    f = _part(tmp_path, "cup24", [(13, 0), (19, 0), (20, -1), (20, -40), (0, -40), (0, -25),
                                  (12, -25), (12, -1)], "42x50+1")
    prog = generate(f, verify=False)
    ops = prog.plan.operations
    drill = next(op for op in ops if op.name == "drill")
    assert drill.tool.number == 14 and drill.drill.z_end == pytest.approx(-24.999)
    assert any("inside diameter 10 is beyond the boring bar T03's reach" in n
               for n in drill.notes)
    rough = next(op for op in ops if op.name == "bore_rough")
    assert rough.start[0] == pytest.approx(5.0)
    # the bar's tip never goes nearer the axis than 4 mm below the drilled hole's mouth...
    deep = [m for m in prog.toolpath.moves if m.tool == 3 and min(m.start[1], m.end[1]) < -20]
    assert deep and min(min(m.start[0], m.end[0]) for m in deep) >= 4.0 - 1e-6
    # ... and leaves along +Z from the bottom (not across what it leaves near the axis)
    fin = [m for m in prog.toolpath.moves if m.tool == 3]
    k = max(i for i, m in enumerate(fin) if abs(m.end[1] + 25.0) < 1e-3 and m.kind != "rapid")
    nxt = fin[k + 1]
    assert nxt.end[0] == pytest.approx(fin[k].end[0]) and nxt.end[1] > 0
    # the face pass along the bottom from the wall in to 5 mm (the tip path's nose in cam)
    face = [m for m in fin if abs(m.start[1] + 25.0) < 1e-6 and abs(m.end[1] + 25.0) < 1e-6
            and m.kind != "rapid" and m.end[0] < m.start[0] - 1.0]
    assert face and min(m.end[0] for m in face) <= 5.0 + 0.4 + 1e-6


def _refused(tmp_path, capsys, part) -> str:
    out = tmp_path / "out.nc"
    rc = main(["generate", str(part), "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists()
    assert len(err.strip().splitlines()) == 1, err
    return err


def test_flat_bottom_the_bar_cannot_face_is_refused(tmp_path, capsys):
    # a 16 mm bore: the 16 mm drill fits, but the bar's head fills the hole
    f = _part(tmp_path, "cup16", [(8, 0), (15, 0), (15, -30), (0, -30), (0, -20), (8, -20)],
              "32x40+1")
    err = _refused(tmp_path, capsys, f)
    assert "flat bottom at Z-20 (diameter 16) that the boring bar T03 (min_bore 16) cannot " \
           "face" in err


def test_flat_bottom_drill_under_the_bars_min_bore_is_refused(tmp_path, capsys):
    # a 14 mm bore: the 12 mm drill is the largest that fits; the bar needs 16
    f = _part(tmp_path, "cup14", [(7, 0), (15, 0), (15, -30), (0, -30), (0, -20), (7, -20)],
              "32x40+1")
    err = _refused(tmp_path, capsys, f)
    assert "T12 (12 mm), makes a hole under the boring bar T03's min_bore 16" in err


# ---------------------------------------------------------------- the bar's head in the bore

def test_a_step_narrower_than_the_bars_min_bore_deeper_than_the_opener_is_refused(tmp_path,
                                                                                   capsys):
    # 22 mm to Z-10 (the 20 mm opener lets the bar in), then 14 mm to Z-30 over an 8 mm hole
    # ending in its point: the bar (min_bore 16) would have to bore the 14 mm step
    tip = 4 * COT59
    f = _part(tmp_path, "step14", [(11, 0), (18, 0), (18, -50), (0, -50), (0, -40 - tip),
                                   (4, -40), (4, -30), (7, -30), (7, -10), (11, -10)], "38x60+1")
    err = _refused(tmp_path, capsys, f)
    assert "is diameter 14 from Z-10" in err
    assert "the boring bar T03's head does not fit a bore of that diameter (min_bore 16): it " \
           "needs a boring bar with min_bore <= 14 or a drill of diameter 14" in err


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_flat_bottom_out_of_the_bars_reach_verifies_with_its_centre_unreachable(tmp_path, comp):
    """The 24 mm cup: what the drill's point leaves inside the bar's reach (its head of
    min_bore 16 plus its running clearance across the bore keeps its tip off the axis) is
    listed as unreachable, and the program verifies."""
    f = _part(tmp_path, "cup24", [(13, 0), (19, 0), (20, -1), (20, -40), (0, -40), (0, -25),
                                  (12, -25), (12, -1)], "42x50+1")
    rep = generate(f, comp=comp).report
    assert rep.passed and rep.max_undercut_mm <= 0.01
    centre = [u for u in rep.unreachable if u.x < 2.0 and abs(u.z + 25.0) < 1.0]
    # the 118 deg point of the 20 mm drill stands 0.3 mm proud near the axis
    assert len(centre) == 1 and 0.25 < centre[0].size_mm < 0.35
