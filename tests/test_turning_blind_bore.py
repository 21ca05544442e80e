"""Blind bores finished under the control's G41: where a dialect cancels the compensation in
the contour's last block (FANUC, Haas: G40 in block nf), that block runs on along the
bottom toward the axis instead of being the bottom's own cut, so the cancel does not put the
nose a radius deep into the bottom (the concave corner of wall and bottom). Fresh part files
(``tests/data/turning_parts/``), every dialect, both modes."""
from __future__ import annotations

from pathlib import Path

import pytest

from hnc_cam.plan.api import generate

FRESH = Path(__file__).parent / "data" / "turning_parts"


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas", "siemens802"])
@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("name", ["blind_bore_collar", "blind_bore", "stepped_blind_bore",
                                  "flat_bottom_centre"])
def test_blind_bores_verify(name, comp, dialect):
    prog = generate(str(FRESH / f"{name}.py"), comp=comp, dialect=dialect)
    assert prog.report.passed, prog.report.summary()
    assert prog.report.max_overcut_mm <= 0.01


@pytest.mark.parametrize("dialect", ["fanuc0it", "haas"])
def test_the_cancel_runs_on_past_the_bottom(dialect):
    prog = generate(str(FRESH / "blind_bore_collar.py"), comp="control", dialect=dialect)
    assert prog.report.passed, prog.report.summary()
    lines = prog.text.splitlines()
    g41 = next(i for i, ln in enumerate(lines) if " G41 " in ln)
    g40 = next(i for i in range(g41, len(lines)) if " G40 " in lines[i])
    # wall, bottom to the drilled hole, then the run-on that cancels: 0.5 mm (radius) on
    assert lines[g40 - 1].endswith("G01 X13.2 Z-25.5") or "X13.2 Z-25.5" in lines[g40 - 1]
    assert lines[g40].split()[1:] == ["G01", "G40", "X12.2"]
    # the cycles refer to the run-on as their nf
    n = lines[g40].split()[0][1:]
    assert sum(f"Q{n}" in ln for ln in lines) == 2  # G71 and G70
    # no move of the boring bar goes deeper than the bottom
    bar = [m for m in prog.toolpath.moves if m.tool == 3]
    assert bar and min(min(m.start[1], m.end[1]) for m in bar) >= -25.5 - 1e-3


@pytest.mark.parametrize("dialect", ["fanuc0it", "haas"])
def test_a_bottom_faced_to_the_centre_runs_on_past_it(dialect):
    """The bar faces the bottom to the centre (X0): the cancelling block runs on across the
    axis along the bottom's plane (the bar's nose is past it already)."""
    prog = generate(str(FRESH / "flat_bottom_centre.py"), comp="control", dialect=dialect)
    assert prog.report.passed, prog.report.summary()
    lines = prog.text.splitlines()
    g41 = next(i for i, ln in enumerate(lines) if " G41 " in ln)
    g40 = next(i for i in range(g41, len(lines)) if " G40 " in lines[i])
    assert "X0. Z-59.3" in lines[g40 - 1] and lines[g40].split()[1:] == ["G01", "G40", "X-1."]
    bar = [m for m in prog.toolpath.moves if m.tool == 3]
    assert min(min(m.start[1], m.end[1]) for m in bar) >= -59.3 - 1e-3


def test_the_hnc_program_keeps_its_bore_contour():
    """The HNC-21T cancels on the retract (G00 G40 after the contour): no run-on there."""
    prog = generate(str(FRESH / "blind_bore_collar.py"), comp="control")
    assert "X12.2" not in prog.text
    assert prog.report.passed


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas", "siemens802"])
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_a_mouth_rounded_into_the_face_is_entered_along_the_face(comp, dialect):
    """The round R2 from the face into the bore: the bar comes down onto the face outside
    the round and rolls along the face into it; straight down onto the round's start its
    nose met the round only past the face and left a sliver (0.014 mm) where the round
    leaves the face."""
    prog = generate(str(FRESH / "rounded_mouth.py"), comp=comp, dialect=dialect)
    assert prog.report.passed, prog.report.summary()
    assert prog.report.max_undercut_mm <= 0.01
    fin = next(op for op in prog.plan.operations if op.name == "bore_finish")
    # the contour's first feed runs along the face (Z0) from outside the round (radius 14.1)
    from hnc_cam.plan import contour as ct
    path = ct.block_path(fin.blocks, fin.start)
    feeds = [s for s, k in path if k == "feed"]
    face = next(s for s in feeds if abs(s.start[1] - s.end[1]) < 1e-9)
    r = fin.tool.nose_radius
    if comp == "control":
        assert face.start[1] == pytest.approx(0.0) and face.start[0] > 14.1 + r
        assert face.end == pytest.approx((14.1, 0.0))
    else:  # the tip path: the nose's centre a radius above the face
        assert face.start[0] > 14.1 + r - 1e-6 and face.end[0] <= 14.1 + r + 1e-6
