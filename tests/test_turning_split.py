"""A G71 run in two at the spindle-limit diameter (HNC-21T, no G96 clamp word) under the
control's G41/G42: the split's blocks of no length stand where the control's compensation
follows them, and the planner checks the contour as the control will run it. Fresh parts
written as a user writes them (``tests/data/turning_parts/spacer_collar.py``: a journal d1
15 mm long, a collar d2, chamfers, ``sketch`` + ``revolve``)."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from hnc_cam.geometry import TurnedProfile
from hnc_cam.plan import contour as ct
from hnc_cam.plan.api import generate
from hnc_cam.plan.model import Block
from hnc_cam.tooling import load_machine, load_tools

from test_plan_shapes import chain

FRESH = Path(__file__).parent / "data" / "turning_parts"
SPACER = str(FRESH / "spacer_collar.py")
LIB = load_tools(None)
MACH = load_machine(None, tools=LIB)
DIALECTS = ["hnc21t", "fanuc0it", "haas", "siemens802"]


def _split_parts(prog):
    rough = next(op for op in prog.plan.operations if op.kind == "rough" and op.split)
    owner = prog.plan.contour_owner(rough)
    blk = next(b for b in owner.blocks if b.before)
    return rough, owner, blk


def test_a_split_on_the_face_beside_the_journal_moves_out_past_the_nose():
    """d1 18: the critical diameter (G96 S180 at 3000 rpm, less the X allowance) is 18.7, on
    the collar's face 0.35 mm (radius) from the 18 mm journal, inside the trim of the nose
    (radius 0.4) in that concave corner: the split moves out along the face to just past the
    point where the nose's path along it begins (journal radius + nose radius)."""
    prog = generate(SPACER, comp="control")
    assert prog.report.passed, prog.report.summary()
    rough, owner, blk = _split_parts(prog)
    r = owner.tool.nose_radius
    first, to_x, to_z = blk.before
    assert first.kind == "line" and first.z == pytest.approx(-15.0)
    assert 9.0 + r < first.x <= 9.0 + r + 0.011        # past the nose's trim, by 0.01 at most
    assert to_x.kind == "rapid" and to_x.x == first.x and to_z.z == first.z
    # the outer cycle still keeps G96 under the limit: its lowest radius (the split plus the
    # X allowance) at or outside the critical radius
    r_c = rough.speed * 1000 / (2 * math.pi * rough.max_rpm)
    assert rough.split.x + rough.rough.allowance_x >= r_c - 1e-9
    # the control's compensation of the contour as written follows it
    assert ct.control_alarm(owner.blocks, owner.start, r, owner.tool.tip, "right") is None
    # and every move of the program keeps within the limit on a machine that does not clamp
    assert max(m.spindle for m in prog.toolpath.moves) <= MACH.max_rpm + 1e-6


def test_the_planners_check_sees_the_split_blocks_as_the_control_runs_them():
    """The split where it was put before (on the face at the critical diameter, 0.35 mm from
    the journal): the contour alone passes the check, the contour with the split's blocks
    alarms as the control does (the face's first part lies inside the corner's trim)."""
    prog = generate(SPACER, comp="control", verify=False)
    _rough, owner, blk = _split_parts(prog)
    r, tip = owner.tool.nose_radius, owner.tool.tip
    saved = blk.before
    try:
        blk.before = []
        assert ct.control_alarm(owner.blocks, owner.start, r, tip, "right") is None
        blk.before = [Block("line", x=9.35, z=-15.0), Block("rapid", x=9.35),
                      Block("line", z=-15.0)]
        msg = ct.control_alarm(owner.blocks, owner.start, r, tip, "right")
        assert msg is not None and "too narrow for the nose radius 0.4" in msg
        blk.before = [Block("line", x=9.41, z=-15.0), Block("rapid", x=9.41),
                      Block("line", z=-15.0)]
        assert ct.control_alarm(owner.blocks, owner.start, r, tip, "right") is None
    finally:
        blk.before = saved


def test_block_path_reads_the_blocks_as_written():
    blocks = [Block("rapid", x=5.0), Block("line", z=-10.0, feed=0.1),
              Block("cw", x=8.0, z=-13.0, r=3.0)]
    blocks[2].before = [Block("line", x=6.0000004, z=-10.0)]
    path = ct.block_path(blocks, (20.0, 2.0))
    assert [k for _, k in path] == ["rapid", "feed", "feed", "feed"]
    assert [(round(s.end[0], 6), round(s.end[1], 6)) for s, _ in path] == \
        [(5.0, 2.0), (5.0, -10.0), (6.0, -10.0), (8.0, -13.0)]
    arc = path[3][0]
    assert arc.cw and arc.radius == pytest.approx(3.0)


#: diameters of the journal around the critical diameter 18.7 (and up to where no split is
#: needed), the spacer's collar 30
SWEEP = [17.0, 17.5, 18.0, 18.1, 18.3, 18.5, 18.7, 18.9, 19.1, 19.5, 20.0, 21.0, 22.0,
         23.0, 24.0, 25.0, 26.0]


@pytest.mark.parametrize("d1", [17.0, 18.0, 18.3, 18.7, 19.1, 22.0])
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_spacer_journals_near_the_critical_diameter_verify_on_the_hnc(d1, comp):
    prog = generate(SPACER, params={"d1": str(d1)}, comp=comp)
    assert prog.report.passed, prog.report.summary()
    assert max(m.spindle for m in prog.toolpath.moves) <= MACH.max_rpm + 1e-6


@pytest.mark.slow
@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("d1", SWEEP)
def test_spacer_sweep_every_dialect(d1, comp, dialect):
    prog = generate(SPACER, params={"d1": str(d1)}, comp=comp, dialect=dialect)
    assert prog.report.passed, prog.report.summary()


#: other fresh shapes with a shoulder just outside the critical diameter: a journal whose
#: root is a fillet, a taper into the shoulder, a shoulder with a chamfer at its root, a pin
#: with a fillet at the left, under both modes and every dialect
SHOULDERS = {
    "fillet_root": chain((0, 0), (8.6, 0), (9.0, -0.4), (9.0, -12.0), (14.0, -12.0),
                         (15.0, -13.0), (15.0, -40.0), (0, -40.0)),
    "short_face": chain((0, 0), (8.9, 0), (9.3, -0.4), (9.3, -10.0), (9.9, -10.0),
                        (9.9, -20.0), (14.0, -20.0), (14.0, -35.0), (0, -35.0)),
    "taper_in": chain((0, 0), (8.5, 0), (9.0, -0.5), (9.0, -12.0), (9.8, -14.0),
                      (12.0, -14.0), (12.0, -30.0), (0, -30.0)),
    "root_chamfer": chain((0, 0), (8.2, 0), (9.0, -0.8), (9.0, -14.6), (9.4, -15.0),
                          (14.2, -15.0), (15.0, -15.8), (15.0, -40.0), (0, -40.0)),
}


@pytest.mark.parametrize("dialect", DIALECTS)
@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("name", sorted(SHOULDERS))
def test_shoulders_near_the_critical_diameter(name, comp, dialect):
    prof = TurnedProfile(SHOULDERS[name], name=name)
    prog = generate(prof, stock="32x45+1", comp=comp, dialect=dialect)
    assert prog.report.passed, prog.report.summary()


BALL = str(FRESH / "ball_end_pin.py")


@pytest.mark.parametrize("stock", ["24x45", "24x45+1"])
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_a_split_on_an_arc_from_past_the_centre_lies_on_that_arc(stock, comp):
    """A ball end: the tip path (cam) starts its arc at a negative X (the lead-in past the
    centre); the split of that arc at the critical diameter lies on the circle the control
    draws from that start with the arc's R, and on the path the tool must follow."""
    prog = generate(BALL, stock=stock, comp=comp)
    assert prog.report.passed, prog.report.summary()
    rough, owner, blk = _split_parts(prog)
    first = blk.before[0]
    assert first.kind == "ccw" and first.r is not None
    # the point on the contour the finisher follows (tip path or part), within the words'
    # rounding (Z to 0.001 mm, X to 0.001 mm on the diameter)
    d = min(s.distance_to((first.x, first.z)) for s in owner.contour)
    assert d <= 0.0006, d
    path = ct.block_path(owner.blocks, owner.start)
    arcs = [s for s, _ in path if getattr(s, "radius", None) is not None]
    # both pieces of the split arc keep the arc's circle (the same centre, within rounding)
    pieces = [a for a in arcs if abs(a.radius - first.r) < 1e-6]
    assert len(pieces) == 2
    assert math.dist(pieces[0].center, pieces[1].center) <= 0.002


def test_stepped_shaft_split_within_rounding_of_an_arc_end():
    """d1 18.7003: the critical diameter falls within rounding of the end of the journal's
    corner arc: no arc of no length (a full circle to the control) is written."""
    for comp in ("cam", "control"):
        prog = generate("parts/stepped_shaft.py", params={"d1": "18.7003"}, comp=comp)
        assert prog.report.passed, prog.report.summary()
        owner = next(op for op in prog.plan.operations if op.name == "finish")
        for s, _ in ct.block_path(owner.blocks, owner.start):
            if getattr(s, "radius", None) is not None:
                assert math.dist(s.start, s.end) >= 0.002
