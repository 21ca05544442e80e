"""Verdicts that agree with what a tool can reach: parts written here (plain build123d or a
profile built in the test), each a case the verifier, the plot or the fitter got wrong."""
from __future__ import annotations

import json

import numpy as np
import pytest
import shapely
from shapely.geometry import box

from hnc_cam.errors import StockError
from hnc_cam.geometry import Line, TurnedProfile
from hnc_cam.nc.interp import run
from hnc_cam.sim import simulate, verify
from hnc_cam.sim.region import profile_polygon
from hnc_cam.sim.tool import tool_shape
from hnc_cam.sim.verify import _with_tails, holder_direction, reachable, tool_body
from hnc_cam.tooling import Machine, Register, Stock, load_machine, load_tools

DEFAULT = load_machine(None, load_tools(None))  # the bundled tool library in its registers
OD_ROUGH, BORING_BAR, GROOVE = DEFAULT.register(1), DEFAULT.register(3), DEFAULT.register(7)
NOSE08 = Machine(registers={1: Register(number=1, radius=0.8, tip=3)})


def chain(*pts):
    return [Line(a, b) for a, b in zip(pts[:-1], pts[1:])]


def tube(outer=25.0, inner=14.0, length=36.0) -> TurnedProfile:
    """Half-section of a plain tube (radii), right face at Z0."""
    return TurnedProfile(outside=chain((inner, 0.0), (outer, 0.0), (outer, -length),
                                       (inner, -length)),
                         bore=chain((inner, 0.0), (inner, -length)), name="tube")


# --- 1. an outside tool reaches only from outside, a boring bar only along the bore ---------

def test_holder_runs_out_of_the_work_by_tip_code():
    assert holder_direction(3) == holder_direction(4) == holder_direction(8) == (0.0, 1.0)
    assert holder_direction(2) == holder_direction(1) == holder_direction(6) == (1.0, 0.0)
    body = tool_body(tool_shape(GROOVE), 100.0)
    ins = tool_shape(GROOVE).outline
    # the blade's body: as wide as the blade, reaching 100 mm beyond it radially
    assert body[:, 0].min() == pytest.approx(ins[:, 0].min())
    assert body[:, 0].max() == pytest.approx(ins[:, 0].max())
    assert body[:, 1].max() == pytest.approx(ins[:, 1].max() + 100.0)
    bar = tool_body(tool_shape(BORING_BAR), 100.0)
    assert bar[:, 0].max() == pytest.approx(tool_shape(BORING_BAR).outline[:, 0].max() + 100.0)
    assert bar[:, 1].max() == pytest.approx(tool_shape(BORING_BAR).outline[:, 1].max())


def test_outside_grooving_blade_does_not_reach_into_the_bore():
    model = profile_polygon(tube())
    chuck = box(-51.0, 12.5, -36.0, 25.0)  # the stock beyond the left face (tube bore 25)
    # a 0.3 mm fillet left where the bore meets the chucked stock, and the same fillet in the
    # corner of an outside shoulder (the chuck face beyond the OD)
    bore_corner = shapely.Polygon([(-36.0, 13.7), (-36.0, 14.0), (-35.7, 14.0)])
    assert reachable(model, [tool_shape(GROOVE)], bore_corner, chuck).area < 1e-9
    # the boring bar (nose 0.4) reaches into the fillet from the bore's open end, down to its
    # own nose fillet
    got = reachable(model, [tool_shape(BORING_BAR)], bore_corner, chuck).area
    assert 0 < got < bore_corner.area
    # the same blade reaches the same corner from outside (nose 0.2 < 0.3)
    od_model = profile_polygon(TurnedProfile(outside=chain((0.0, 0.0), (20.0, 0.0),
                                                           (20.0, -36.0), (25.0, -36.0),
                                                           (25.0, -50.0), (0.0, -50.0))))
    od_corner = shapely.Polygon([(-36.0, 20.0), (-36.0, 20.3), (-35.7, 20.0)])
    assert reachable(od_model, [tool_shape(GROOVE)], od_corner).area > 0.5 * od_corner.area


def test_boring_bar_reaches_the_bore_from_its_mouth_not_a_recess_behind_it():
    # bore 20 at the mouth (Z0..-10), a recess of 24 (Z-10..-20), bore 20 again to Z-30
    outside = chain((10.0, 0.0), (20.0, 0.0), (20.0, -30.0), (10.0, -30.0))
    bore = chain((10.0, 0.0), (10.0, -10.0), (12.0, -10.0), (12.0, -20.0), (10.0, -20.0),
                 (10.0, -30.0))
    model = profile_polygon(TurnedProfile(outside=outside, bore=bore))
    bar = [tool_shape(BORING_BAR)]
    mouth = box(-8.0, 9.9, -2.0, 10.0)  # a 0.1 band left on the mouth's wall
    assert reachable(model, bar, mouth).area == pytest.approx(mouth.area, rel=1e-6)
    recess = box(-18.0, 11.9, -12.0, 12.0)  # the same band on the recess's wall
    assert reachable(model, bar, recess).area < 1e-9


@pytest.mark.cad
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_grooved_tube_verifies_with_the_bore_exit_corner_unreachable(comp):
    """50/28 x 36 tube with a 4 mm square OD groove: the program uses the OD grooving tool, and
    the fillet the boring bar leaves at the bore exit is not in its reach."""
    from build123d import BuildPart, Cylinder, Align, Mode, Pos
    from hnc_cam.cad import profile
    from hnc_cam.testing import assert_roundtrip
    top = (Align.CENTER, Align.CENTER, Align.MAX)
    with BuildPart() as bp:
        Cylinder(25, 36, align=top)
        Cylinder(14, 36, align=top, mode=Mode.SUBTRACT)
    part = bp.part - Pos(0, 0, -18) * (Cylinder(25, 4) - Cylinder(21, 4))
    prof = profile(part)
    prog, rep = assert_roundtrip(prof, stock="50/25x53+2", tol=0.01, comp=comp)
    assert "Grooving" in prog.text
    assert rep.passed and rep.max_undercut_mm <= 0.01
    exit_corner = [u for u in rep.unreachable if abs(u.z + 36.0) < 0.01 and abs(u.x - 14) < 0.5]
    assert exit_corner and exit_corner[0].size_mm == pytest.approx(0.2068, abs=0.002)


# --- 2. a feature left for another operation is unreachable with its tail -----------------

def test_tail_of_unreachable_leftover_is_unreachable():
    region = shapely.union_all([box(0, 0, 1, 1), box(5, 0, 6, 1)])
    unreach = box(0, 0, 0.5, 1)
    reach = shapely.union_all([box(0.5, 0, 1, 1), box(5, 0, 6, 1)])
    r, u = _with_tails(region, reach, unreach, 0.01)
    # the strip 0.01 wide beside the unreachable piece moves over; the separate piece stays
    assert u.area == pytest.approx(0.51, abs=1e-6)
    assert r.area == pytest.approx(0.49 + 1.0, abs=1e-6)
    assert r.intersects(box(5, 0, 6, 1)) and not u.intersects(box(5, 0, 6, 1))


def bushing_with_back_chamfer(R=25.0, rb=15.0, L=40.0, c=1.0, cb=1.5) -> TurnedProfile:
    outside = chain((rb + c, 0.0), (R - c, 0.0), (R, -c), (R, -L + c), (R - c, -L),
                    (rb + cb, -L))
    bore = chain((rb + c, 0.0), (rb, -c), (rb, -L + cb), (rb + cb, -L))
    return TurnedProfile(outside=outside, bore=bore, name="back-chamfered bushing")


@pytest.mark.cad
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_back_chamfer_is_made_in_a_second_setup_and_verifies(comp):
    """One setup refuses the bore's chamfer facing the chuck (no NOTE bridging it); two setups
    make it from the part turned around, and the whole part verifies with nothing left at
    the chamfer (now the new face's bore mouth, Z0 to Z-1.5)."""
    from hnc_cam.errors import PlanError
    from hnc_cam.plan.api import generate
    from hnc_cam.plan.setups import generate_setups
    prof = bushing_with_back_chamfer()
    with pytest.raises(PlanError, match=r"bore's chamfer from Z-38.5 to Z-40 .*--setups 2"):
        generate(prof, "55/27x57+2", comp=comp)
    s = generate_setups(prof, "55/27x57+2", grip=8, grip2=15, comp=comp)
    rep = s.report
    assert rep.passed and rep.max_undercut_mm <= 0.01
    assert not [u for u in rep.unreachable if u.z > -1.6 and u.x < 34.0]


# --- 3. an elliptical nose keeps its tangent at the axis ------------------------------------

@pytest.mark.cad
def test_elliptical_nose_solid_generates_and_verifies():
    from build123d import (BuildLine, BuildPart, BuildSketch, EllipticalCenterArc, Line as BLine,
                           Plane, make_face, revolve, Axis)
    from hnc_cam.cad import profile
    from hnc_cam.testing import assert_roundtrip
    with BuildPart() as bp:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                EllipticalCenterArc((0, -6), 10, 6, 0.0, arc_size=90)  # (10,-6) .. (0,0)
                BLine((0, 0), (0, -36))
                BLine((0, -36), (10, -36))
                BLine((10, -36), (10, -6))
            make_face()
        revolve(axis=Axis.Z)
    prof = profile(bp.part)
    first = prof.outside[0]
    assert first.start == (0.0, 0.0)
    assert first.center[0] == 0.0  # a centre on the axis: the nose leaves it perpendicular
    assert max(s.bbox()[3] for s in prof.outside) <= 0.0  # nothing above the right face
    for comp in ("cam", "control"):
        prog, rep = assert_roundtrip(prof, stock="25x50+1", tol=0.01, comp=comp)
        assert rep.passed


@pytest.mark.cad
def test_spline_nose_meeting_the_axis_square_generates_and_verifies():
    from build123d import (BuildLine, BuildPart, BuildSketch, Line as BLine, Plane, Spline,
                           make_face, revolve, Axis)
    from hnc_cam.cad import profile
    from hnc_cam.testing import assert_roundtrip
    with BuildPart() as bp:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                # a B-spline from the 24 mm cylinder to the axis, square to it there
                Spline((12, -8), (7, -2.5), (0, 0), tangents=[(0, 1), (-1, 0)])
                BLine((0, 0), (0, -40))
                BLine((0, -40), (12, -40))
                BLine((12, -40), (12, -8))
            make_face()
        revolve(axis=Axis.Z)
    prof = profile(bp.part)
    assert prof.outside[0].start == (0.0, 0.0) and prof.outside[0].center[0] == 0.0
    assert max(s.bbox()[3] for s in prof.outside) <= 0.0
    for comp in ("cam", "control"):
        prog, rep = assert_roundtrip(prof, stock="30x50+1", tol=0.01, comp=comp)
        assert rep.passed and rep.max_overcut_mm <= 0.01


# --- 4. the collision marker is where the tool met the stock -------------------------------

CRASH = "%1\nT0101\nM03 S800 G95\nG00 X60 Z-20\nG00 X30\nG00 X80\nG00 Z50\nM30\n"


def test_collision_located_at_first_contact_in_json_and_plot():
    from hnc_cam.sim.plot import figure
    m = simulate(run(CRASH, NOSE08), Stock.parse("45x60+1"), NOSE08)
    [iss] = m.issues
    assert iss.line == 5 and iss.message.startswith("collision:")
    # tip at Z-20 moving -X, nose 0.8 (code 3): its lowest point (Z-19.2) meets the bar's top
    x, z = iss.at
    assert 2 * x == pytest.approx(45.0, abs=0.01) and z == pytest.approx(-19.2, abs=0.01)
    js = m.to_json()["collisions"][0]
    assert js["at"] == [pytest.approx(45.0, abs=0.01), pytest.approx(-19.2, abs=0.01)]
    assert set(js) == {"line", "block", "message", "at"}
    fig = figure(m)
    try:
        marks = [ln for ln in fig.axes[0].lines if ln.get_marker() == "x"]
        assert len(marks) == 1
        assert marks[0].get_xdata()[0] == pytest.approx(-19.2, abs=0.01)
        assert marks[0].get_ydata()[0] == pytest.approx(22.5, abs=0.01)  # not the move's end X30
    finally:
        import matplotlib.pyplot as plt
        plt.close(fig)


def test_collision_on_a_diagonal_rapid_and_in_the_cli_json(tmp_path):
    from hnc_cam.cli import main
    # sharp point (default outline, nose 0, its lowest point the tip): the tip from X50 Z5 to
    # X20 Z-25 (radius 25 -> 10 over 30 mm) passes the face Z0 at X45, then meets the top of a
    # 40x60+0 bar at radius 20, Z-5
    (tmp_path / "c.nc").write_text("%1\nT0101\nM03 S800\nG00 X50 Z5\nG00 X20 Z-25\nM30\n")
    (tmp_path / "sharp.toml").write_text("use_tool_library = false\n[machine]\nname = \"s\"\n")
    out = tmp_path / "c.json"
    rc = main(["simulate", str(tmp_path / "c.nc"), "--stock", "40x60+0", "--machine",
               str(tmp_path / "sharp.toml"), "--json", str(out)])
    assert rc == 1
    [c] = json.loads(out.read_text())["collisions"]
    assert c["at"][0] == pytest.approx(40.0, abs=0.02) and c["at"][1] == pytest.approx(-5.0, abs=0.02)


# --- 5. a stock that does not hold the model is bad input -----------------------------------

def test_stock_smaller_than_model_is_refused():
    model = tube()
    m = simulate(run("%1\nM30\n", DEFAULT), Stock.parse("45/25x53+2"), DEFAULT)
    with pytest.raises(StockError, match=r"diameter 45\.000.*diameter 50\.000"):
        verify(m, model)
    short = simulate(run("%1\nM30\n", DEFAULT), Stock.parse("55/25x30+2"), DEFAULT)
    with pytest.raises(StockError, match=r"30\.000 long.*36\.000 long"):
        verify(short, model)
    # a stock exactly the size of the model is fine
    exact = simulate(run("%1\nM30\n", DEFAULT), Stock.parse("50/28x36"), DEFAULT)
    assert verify(exact, model).passed


def test_cli_verify_with_small_stock_exits_2_and_writes_nothing(tmp_path, capsys):
    from hnc_cam.cli import main
    (tmp_path / "p.nc").write_text("%1\nM30\n")
    (tmp_path / "part.py").write_text(
        "from hnc_cam.cad.sketch import Outline, revolve\n"
        "def sketch(d: float = 30.0):\n"
        "    s = Outline((0.0, 0.0))\n"
        "    s.line_to(d / 2, 0.0)\n"
        "    s.line_to(d / 2, -20.0)\n"
        "    s.line_to(0.0, -20.0)\n"
        "    return s.segments()\n"
        "def part(d: float = 30.0):\n"
        "    return revolve(sketch(d))\n")
    out = tmp_path / "v.json"
    rc = main(["verify", str(tmp_path / "p.nc"), "--model", str(tmp_path / "part.py"),
               "--stock", "25x40", "--json", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists()
    assert len(err) == 1 and err[0].startswith("error:")
    assert "25.000" in err[0] and "30.000" in err[0]


# --- 6. a stopped spindle is one finding per move -------------------------------------------

def test_stopped_spindle_under_g95_is_one_finding_per_move():
    text = "%1\nT0101\nG95 M05\nG00 X50 Z2\nG01 X38 F0.2\nG01 Z-10\nG01 X44 Z-20\nG00 X80 Z50\nM30\n"
    m = simulate(run(text, NOSE08), Stock.parse("45x60+1"), NOSE08)
    assert [(i.line, i.kind) for i in m.issues] == [(6, "spindle"), (7, "spindle")]
    assert all(i.at is not None for i in m.issues)
    # a toolpath with feed 0: stopped spindle, one finding; spindle turning, the feed finding
    from hnc_cam.nc.toolpath import Move, Toolpath
    for rpm, kinds in ((0.0, ["spindle"]), (500.0, ["feed"])):
        mv = Move("line", (19.0, 2.0), (19.0, -8.0), 1, feed=0.0, spindle=rpm, register=1)
        m = simulate(Toolpath(moves=[mv], source_lines=["G01 Z-8"]), Stock.parse("40x60"), NOSE08)
        assert [i.kind for i in m.issues] == kinds


def test_thread_move_with_stopped_spindle_is_one_finding():
    text = "%1\nT0101\nG95 M05\nG00 X50 Z2\nG00 X39\nG32 Z-10 F1.5\nG00 X50\nG00 X80 Z50\nM30\n"
    m = simulate(run(text, NOSE08), Stock.parse("40x60+1"), NOSE08)
    assert [(i.line, i.kind) for i in m.issues] == [(6, "thread-spindle")]
