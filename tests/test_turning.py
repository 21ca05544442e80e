"""Outside turning as a lathe programmer writes it: which tool removes what, allowances,
approach and retract, threads, large and small stock; asserted on the toolpath and the
simulated material, not on the program text."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from hnc_cam.errors import PlanError
from hnc_cam.geometry import Line, TurnedProfile
from hnc_cam.plan import Options, make_plan
from hnc_cam.plan.api import generate
from hnc_cam.tooling import Stock, load_machine, load_tools

from test_plan_shapes import chain

LIB = load_tools(None)
MACH = load_machine(None, tools=LIB)
PARTS = "parts/"


def _plan(profile, stock, comp="cam"):
    return make_plan(profile, Stock.parse(stock), LIB, MACH, Options(comp=comp), name=profile.name)


# ---------------------------------------------------------------- turn-back tolerance

def test_sub_micron_rise_toward_the_face_is_not_a_back_facing_undercut():
    # the face rises 0.00001 mm over its width (noise of a fitted curve)
    prof = TurnedProfile(chain((0, 0), (8, 0.00001), (10, -2), (10, -30), (0, -30)), name="noisy")
    p = _plan(prof, "24x35+1")
    assert [op.name for op in p.operations][:3] == ["face", "rough", "finish"]


def test_a_real_rise_toward_the_face_is_still_refused():
    prof = TurnedProfile(chain((0, 0), (8, 0), (9, 0.2), (10, -2), (10, -30), (0, -30)),
                         name="backface")
    with pytest.raises(PlanError, match="turns back toward the right face at X18.000"):
        _plan(prof, "24x35+1")


# ---------------------------------------------------------------- threads too short

@pytest.mark.parametrize("length", [2.2, 3.0, 3.9])
def test_thread_too_short_for_full_depth_is_refused_naming_the_minimum(length):
    with pytest.raises(PlanError) as e:
        generate(PARTS + "threaded_stud.py", params={"thread_length": str(length)}, verify=False)
    msg = str(e.value)
    assert "too short to reach full depth" in msg
    assert "at least 4 mm" in msg and f"thread_length={length:g}" in msg


def test_thread_just_long_enough_reaches_the_standard_minor_diameter():
    prog = generate(PARTS + "threaded_stud.py", params={"thread_length": "4"})
    assert prog.report.passed
    th = prog.report.threads[0]
    assert abs(th.achieved_diameter - 18.16) <= 0.05


# ---------------------------------------------------------------- solids given directly

def test_generate_accepts_build123d_and_cadquery_solids():
    bd = pytest.importorskip("build123d")
    cq = pytest.importorskip("cadquery")
    solid = bd.Pos(0, 0, -20) * bd.Cylinder(10, 40)
    a = generate(solid, stock="22x45+1")
    w = cq.Workplane("XY").circle(10).extrude(-40)
    b = generate(w, stock="22x45+1")
    for prog in (a, b):
        assert prog.report.passed
        xs = [2 * abs(m.end[0]) for m in prog.toolpath.moves if m.kind in ("line", "arc")]
        assert max(xs) >= 20.0
    with pytest.raises(PlanError, match="parameters given"):
        generate(solid, stock="22x45+1", params={"length": "3"})


# ---------------------------------------------------------------- threads run out

@pytest.mark.parametrize("cycle", ["g76", "g82"])
def test_thread_runs_into_the_relief_and_starts_three_leads_before(cycle):
    prog = generate(PARTS + "threaded_stud.py", thread_cycle=cycle)
    assert prog.report.passed
    th = [m for m in prog.toolpath.moves if m.kind == "thread"]
    z_lo, pitch = -22.0, 1.5  # the stud's M20x1.5 ends at Z-22, its relief begins there
    assert min(min(m.start[1], m.end[1]) for m in th) <= z_lo - pitch + 1e-6
    # the relief's far wall (the collar) is at Z-28.578: the insert's flank stays clear
    assert min(min(m.start[1], m.end[1]) for m in th) >= -28.578 + 0.5 * pitch + 0.2
    assert max(max(m.start[1], m.end[1]) for m in th) >= 0.0 + 3 * pitch - 1e-6
    # the spindle runs G97 within the machine's limit and the 1200/lead - 80 threading rule
    assert all(0 < m.spindle <= min(3000, 1200 / pitch - 80) + 1e-6 for m in th)


# ---------------------------------------------------------------- material, allowance, explain

def test_material_limits_the_cutting_data_and_unknown_names_the_known(tmp_path, capsys):
    from hnc_cam.cli import main
    alu = generate(PARTS + "stepped_shaft.py", material="6061")
    rough = [op for op in alu.plan.operations if op.name == "rough"][0]
    assert 300.0 <= rough.speed <= 800.0  # the library's 180 m/min raised into 6061's range
    steel = generate(PARTS + "stepped_shaft.py", material="1045")  # an alias of C45
    assert [op.speed for op in steel.plan.operations if op.name == "rough"] == [180.0]
    assert alu.cycle_time_s < steel.cycle_time_s
    out = tmp_path / "o.nc"
    rc = main(["generate", PARTS + "stepped_shaft.py", "--material", "unobtainium", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1
    assert err[0].startswith("error: unknown material") and "6061" in err[0] and "GG25" in err[0]


@pytest.mark.parametrize("value,msg", [("-0.4,0.1", "cannot be negative"),
                                       ("0.4", "give it as X,Z"),
                                       ("0.4,500", "larger than the stock"),
                                       ("50,0.1", "larger than the stock")])
def test_contradictory_allowance_is_one_line_exit_2(tmp_path, capsys, value, msg):
    from hnc_cam.cli import main
    out = tmp_path / "o.nc"
    rc = main(["generate", PARTS + "threaded_stud.py", f"--allowance={value}", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1 and msg in err[0]


def test_allowance_option_is_what_the_roughing_leaves():
    """The radial stock left after the roughing tools, measured on the simulated material
    over the plain diameter 30 of the stud's collar (Z-32..-45), is the allowance asked."""
    from hnc_cam.sim import simulate
    from hnc_cam.sim.region import polygons
    import shapely
    for x_all in (0.4, 1.0):
        prog = generate(PARTS + "threaded_stud.py", allowance=f"{x_all},0.1", verify=False)
        # the moves before the finishing operation's comment line: the roughing tools only
        lines = prog.text.splitlines()
        at = next(i for i, ln in enumerate(lines, 1) if "FINISH OD" in ln)
        moves = prog.toolpath.moves
        first = next(i for i, m in enumerate(moves) if m.line > at)
        from dataclasses import replace
        tp = replace(prog.toolpath, moves=moves[:first])
        mach = simulate(tp, prog.plan.stock, model=prog.plan.profile)
        for z in (-33.0, -38.0, -44.0):
            cut = mach.material.intersection(shapely.LineString([(z, 0.0), (z, 100.0)]))
            top = cut.bounds[3]
            assert 2 * top - 30.0 == pytest.approx(x_all, abs=0.01)


def _roughed(prog):
    """The simulated material after the roughing tools (the moves before the finishing
    contour's comment line)."""
    from dataclasses import replace
    from hnc_cam.sim import simulate
    lines = prog.text.splitlines()
    at = next(i for i, ln in enumerate(lines, 1) if "FINISH OD" in ln)
    moves = prog.toolpath.moves
    first = next(i for i, m in enumerate(moves) if m.line > at)
    return simulate(replace(prog.toolpath, moves=moves[:first]), prog.plan.stock,
                    model=prog.plan.profile).material


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("allowance", [None, "0.8,0.2"])
@pytest.mark.parametrize("part,shoulder,diameters", [
    # the collar's shoulder behind the thread relief (Z-24, radius 6.9..12); the thread's
    # diameter, the relief's floor, the collar
    ("stud_relief", (-24.0, (9.0, 10.0, 11.0, 11.5)), ((-10.0, 16.0), (-23.0, 13.8),
                                                       (-30.0, 24.0), (-38.0, 24.0))),
    # the shoulder the DIN 509 undercut runs into (Z-30, radius 15.3..19, its fillet from
    # 14.7 to 15.3); the journal, the undercut's floor, the collar
    ("din509_shaft", (-30.0, (15.5, 16.0, 17.0, 18.0, 18.5)),
     ((-10.0, 30.0), (-28.5, 29.4), (-40.0, 40.0), (-55.0, 40.0))),
])
def test_the_finisher_sees_the_allowance_on_parts_with_undercuts(part, shoulder, diameters,
                                                                 allowance, comp):
    """After the roughing tools (the envelope's cycle and semi-finishing pass, the rest
    roughing of the undercut) the material left, measured on the simulation, is the X
    allowance on every diameter (in and out of the undercut) and the Z allowance on the
    shoulder behind it: not the X allowance there, and nothing cut into the shoulder."""
    import shapely
    prog = generate(FRESH + part + ".py", comp=comp, allowance=allowance, verify=False)
    assert [op.name for op in prog.plan.operations].count("rough_zone") == 1
    ax, az = (0.4, 0.1) if allowance is None else (0.8, 0.2)
    mat = _roughed(prog)
    z_sh, radii = shoulder
    for x in radii:
        cut = mat.intersection(shapely.LineString([(-200.0, x), (10.0, x)]))
        assert cut.bounds[2] - z_sh == pytest.approx(az, abs=0.002), x
    for z, d in diameters:
        cut = mat.intersection(shapely.LineString([(z, 0.0), (z, 100.0)]))
        assert 2 * cut.bounds[3] - d == pytest.approx(ax, abs=0.002), z


def test_operator_comments_are_short_and_explain_has_the_reasons(capsys):
    from hnc_cam.cli import main
    rc = main(["generate", PARTS + "threaded_stud.py", "--explain", "--no-verify"])
    cap = capsys.readouterr()
    assert rc == 0
    body = cap.out.split("G21 G90 G36 G95 G40 G97", 1)[1]
    comments = [ln for ln in body.splitlines() if "(" in ln]
    assert comments and all(len(ln[ln.index("("):]) < 60 for ln in comments)
    assert "rest-rough undercut from Z-22 to Z-28.578" in cap.err


# ---------------------------------------------------------------- parts written fresh

FRESH = "tests/data/turning_parts/"


def _model_distance(prof, p):
    segs = list(prof.outside) + list(prof.bore or [])
    return min(s.distance_to(p) for s in segs)


def _removed_by_tool(prog):
    """mm^2 of the half-section each tool removed (the simulator's per-move removed area)."""
    from hnc_cam.sim import simulate
    mach = simulate(prog.toolpath, prog.plan.stock, model=prog.plan.profile)
    out: dict[int, float] = {}
    for m, a in zip(prog.toolpath.moves, mach.removed_area):
        out[m.tool] = out.get(m.tool, 0.0) + float(a)
    return out, mach


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("name", ["stud_relief", "din509_shaft", "disc_hub", "wall30",
                                  "tube_grooves", "long_shaft"])
def test_fresh_part_generates_verifies_and_never_rapids_onto_the_part(name, comp):
    prog = generate(FRESH + name + ".py", comp=comp)
    assert prog.report.passed, prog.report.summary()
    prof = prog.plan.profile
    # program G00 ends (not the cycles' own retracts) stay 0.5 mm or more from the model
    for m in prog.toolpath.moves:
        if m.kind == "rapid" and m.op == "G00":
            assert _model_distance(prof, m.end) >= 0.5 - 1e-6, (m.line, m.end)


@pytest.mark.parametrize("name,zone", [("stud_relief", (-24.0, -20.0)),
                                       ("din509_shaft", (-30.0, -26.5)),
                                       ("wall30", (-40.0, -25.0))])
def test_the_rougher_takes_the_bulk_and_the_zone_tool_only_its_undercut(name, zone):
    prog = generate(FRESH + name + ".py", verify=False)
    ops = prog.plan.operations
    rough = next(op for op in ops if op.name == "rough")
    zop = next(op for op in ops if op.name == "rough_zone")
    assert rough.tool.insert.code.startswith("CNMG") and rough.cycle == "G71"
    # the strongest insert that reaches the undercut: the 55 deg DNMG for walls up to 30 deg
    assert zop.tool.insert.code.startswith("DNMG")
    by_tool, mach = _removed_by_tool(prog)
    total = sum(by_tool.values())
    assert by_tool[rough.tool.number] > 0.75 * total
    # every move of the zone operation's tool before the finishing pass cuts inside the zone
    lines = prog.text.splitlines()
    z_ops = [i for i, ln in enumerate(lines, 1) if "REST ROUGH" in ln]
    fin = next(i for i, ln in enumerate(lines, 1) if "FINISH OD" in ln)
    for m, a in zip(prog.toolpath.moves, mach.removed_area):
        if z_ops[0] < m.line < fin and a > 1e-6:
            assert zone[0] - 1.0 <= min(m.start[1], m.end[1]) and \
                max(m.start[1], m.end[1]) <= zone[1] + 1.5, (m.line, m.start, m.end)


def test_face_dominated_disc_is_g72_from_its_face_with_little_air():
    prog = generate(FRESH + "disc_hub.py")
    rough = next(op for op in prog.plan.operations if op.name == "rough")
    assert rough.cycle == "G72" and rough.start[1] == pytest.approx(0.0)
    assert prog.report.air_cut_fraction <= 0.08


def test_bar_twice_the_diameter_works_and_the_chamfer_pass_meets_no_bar_wall():
    for d in (60, 70):
        prog = generate(FRESH + "long_shaft.py", stock=f"{d}x92+1")
        assert prog.report.passed and not prog.report.collisions


@pytest.mark.parametrize("name", ["bushing", "cast_blank", "cq_pin", "flange", "grooved_shaft",
                                  "stepped_shaft", "threaded_stud"])
def test_bundled_part_air_cut_is_small(name):
    prog = generate(PARTS + name + ".py")
    assert prog.report.air_cut_fraction <= 0.08


# ---------------------------------------------------------------- large parts

def test_large_part_approaches_behind_the_face_x_first_and_verifies():
    prog = generate(PARTS + "bushing.py", params={"outer_diameter": "240"})
    assert prog.report.passed and not prog.report.collisions
    r_stock = prog.plan.stock.diameter / 2
    # every G00 that ends behind the stock's face (Z < 0) starts outside the stock or moves
    # along one axis only: no dog-leg through the stock from the tool-change point
    for m in prog.toolpath.moves:
        if m.kind == "rapid" and m.op == "G00" and m.end[1] < -1e-6:
            one_axis = abs(m.start[0] - m.end[0]) < 1e-9 or abs(m.start[1] - m.end[1]) < 1e-9
            assert one_axis or m.start[0] >= r_stock, (m.line, m.start, m.end)


def test_flange_720_plans_its_approaches_from_the_stock_there():
    from hnc_cam.cad import load_part
    lp = load_part(PARTS + "flange.py", {"diameter": "720"})
    p = make_plan(lp.profile, Stock.parse(lp.stock), LIB, MACH, Options(), name="flange")
    r_stock = 360.0
    for op in p.operations:
        if op.start[1] < 0 and op.start[0] >= r_stock:
            assert op.approach_moves[0] == (op.start[0], None)  # X first, outside the stock


def test_disc_with_a_small_od_step_is_roughed_by_g71_in_fewer_passes_than_g72():
    """A 150 mm disc, 20 mm thick, from a 155 mm bar: G72 would need 14 passes (20 mm / 1.5),
    G71 two (2.5 mm radial / 1.5)."""
    prof = TurnedProfile(chain((0, 0), (74, 0), (75, -1), (75, -20), (0, -20)), name="disc")
    prog = generate(prof, stock="155x23+1")
    assert prog.report.passed
    rough = next(op for op in prog.plan.operations if op.name == "rough")
    assert rough.cycle == "G71" and rough.tool.number == 1
    g71 = [m for m in prog.toolpath.moves if m.op == "G71" and m.kind == "line"
           and abs(m.end[1] - m.start[1]) > 10.0]
    assert len({round(m.start[0], 3) for m in g71}) <= 3  # two levels and the last pass


def test_library_without_a_tool_for_a_zone_is_refused_naming_the_zone(tmp_path, capsys):
    """Without the 35 deg VNMG, nothing reaches the 45 deg wall of a zone: refused with its
    place and size and the tool it needs, nothing written."""
    from hnc_cam.cli import main
    text = Path("hnc_cam/data/tools.toml").read_text()
    blocks = text.split("[[tool]]")
    kept = [b for b in blocks[1:] if "VNMG" not in b]
    lib = tmp_path / "tools.toml"
    lib.write_text(blocks[0] + "".join("[[tool]]" + b for b in kept))
    part = tmp_path / "p.py"
    part.write_text(Path(FRESH + "wall30.py").read_text()
                    .replace("(14, -25), (11, -30.197)", "(14, -25), (11, -28)"))
    out = tmp_path / "o.nc"
    rc = main(["generate", str(part), "--tools", str(lib), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1
    assert "undercut from Z-25 to Z-40 down to diameter 22" in err[0]
    assert "trailing edge clears" in err[0]


@pytest.mark.parametrize("foot,wall", [((6, -12), 90), ((6, -15.276), 70)])
def test_a_wall_facing_the_chuck_no_trailing_edge_clears_asks_for_a_second_setup(
        tmp_path, capsys, foot, wall):
    """A shank behind a flange: its wall facing the chuck at 90 deg is steeper than any
    turning tool cutting toward the chuck clears (its trailing edge is under 90 deg): the
    refusal names the place and asks for a second setup or a tool cutting toward +Z, not
    for a tool that cannot exist; a 70 deg wall still names the clearance needed."""
    from hnc_cam.cli import main
    part = tmp_path / "flange.py"
    part.write_text(Path(FRESH + "stud_relief.py").read_text()
                    .replace("THREADS = [Thread(z_start=0.0, z_end=-20.0, diameter=16.0, "
                             "pitch=1.5)]", "THREADS = []")
                    .replace("(8, -1), (8, -20), (6.9, -21.906), (6.9, -24), (12, -24),\n"
                             "           (12, -40), (0, -40)",
                             f"(8, -1), (8, -10), (15, -10), (15, -12), {foot}, (6, -40), "
                             f"(0, -40)")
                    .replace('"26x50+1"', '"32x45+1"'))
    out = tmp_path / "o.nc"
    rc = main(["generate", str(part), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1
    assert "undercut from Z-12 to Z-40 down to diameter 12" in err[0]
    assert f"descending at up to {wall} deg" in err[0]
    if wall >= 88:
        assert "second setup" in err[0] and "toward +Z" in err[0]
        assert "clears 92 deg" not in err[0]
    else:
        assert f"trailing edge clears {wall + 2} deg" in err[0]
        assert "second setup" not in err[0]


# ---------------------------------------------------------------- spindle limit, groove dwell

def _lib(per_tool):
    """The bundled library with some tools changed: ``{2: {"max_rpm": 2000}}``."""
    import dataclasses
    from hnc_cam.tooling import ToolLibrary
    return ToolLibrary(tuple(dataclasses.replace(t, **per_tool.get(t.number, {}))
                             for t in LIB.tools))


def _pin(groove=False):
    # a 6 mm pin with a chamfer on a 9 mm head (and a square 3 mm groove to diameter 4): its
    # face finished to the centre, every finishing and grooving move below 14 mm diameter
    body = [(3, -8), (2, -8), (2, -11), (3, -11)] if groove else []
    return TurnedProfile(chain((0, 0), (2.5, 0), (3, -0.5), *body, (3, -20), (4.5, -21.5),
                               (4.5, -30), (0, -30)), name="pin6")


def _moves_by_tool(prog):
    out: dict[int, list] = {}
    for m in prog.toolpath.moves:
        out.setdefault(m.tool, []).append(m)
    return out


def test_tool_rpm_limit_caps_finishing_grooving_and_the_face_to_the_centre():
    lib = _lib({2: {"max_rpm": 2000.0}, 7: {"max_rpm": 1500.0}})
    prog = generate(_pin(), stock="14x36", tools=lib)  # no face stock: the finisher faces
    assert prog.report.passed
    grooved = generate(_pin(groove=True), stock="14x36+1", tools=lib)
    assert grooved.report.passed and grooved.report.max_undercut_mm <= 0.01
    by = _moves_by_tool(prog)
    by[7] = _moves_by_tool(grooved)[7]
    limit = {2: 2000.0, 7: 1500.0}
    for tool, moves in by.items():
        assert max(m.spindle for m in moves) <= limit.get(tool, MACH.max_rpm) + 1e-6, tool
    # the caps are reached (the pin needs more at G96), and the finisher runs to the centre
    assert max(m.spindle for m in by[2]) == pytest.approx(2000.0)
    assert max(m.spindle for m in by[7]) == pytest.approx(1500.0)
    assert any(min(m.start[0], m.end[0]) <= 1e-6 for m in by[2] if m.kind == "line")


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("shape,stock", [("pin", "14x36+1"), ("pin", "14x36"),
                                         ("grooved", "30x70"), ("stud", "30x60+1")])
def test_small_grooved_parts_leave_nothing_a_tool_reaches(shape, stock, comp):
    """The 6 mm pin with a square groove, the 4 mm groove shape and the stud: what is left
    is only where no tool reaches (the grooving insert's corner radius in the groove's
    bottom corners, a nose radius in an inside corner), nothing reachable above 0.01 mm."""
    from test_plan_shapes import grooved, stud
    prof = {"pin": lambda: _pin(groove=True), "grooved": grooved, "stud": stud}[shape]()
    prog = generate(prof, stock=stock, comp=comp)
    rep = prog.report
    assert rep.passed and rep.max_undercut_mm <= 0.01
    # unreachable: the groove's bottom corners (the grooving insert's 0.2 mm corner radius,
    # 0.06 mm) and the left end's corner against the bar left in the chuck (0.21 mm)
    assert all(d.size_mm <= 0.21 for d in rep.unreachable)


def test_machine_rpm_limit_holds_without_the_interpreter_clamp():
    """Run the program on a machine that does not clamp G96: the finishing contour switches
    to G97 at the machine's max rpm inside the critical diameter and back outside it."""
    import dataclasses
    from hnc_cam.plan.api import _interpret
    prof = TurnedProfile(chain((0, 0), (4, 0), (4, -10), (15, -10), (15, -30), (0, -30)),
                         name="step8_30")
    prog = generate(prof, stock="34x40")
    free = dataclasses.replace(MACH, max_rpm=100000.0)
    tp = _interpret(prog.text, free, "<free>")
    fin = [m for m in tp.moves if m.tool == 2 and m.kind in ("line", "arc")]
    assert max(m.spindle for m in fin) <= MACH.max_rpm + 1e-6
    # outside the critical diameter the surface speed is the finisher's own again
    vc = LIB.by_number(2).vc_finish
    r_c = vc * 1000 / (2 * math.pi * MACH.max_rpm)
    outer = [m for m in fin if min(abs(m.start[0]), abs(m.end[0])) > r_c + 0.01
             and m.kind == "line" and abs(m.start[0] - m.end[0]) < 1e-9]
    assert outer and all(m.spindle == pytest.approx(vc * 1000 / (2 * math.pi * abs(m.end[0])))
                         for m in outer)
    groove = [m for m in tp.moves if m.tool == 7]
    assert all(m.spindle <= MACH.max_rpm + 1e-6 for m in groove)


@pytest.mark.parametrize("revs", [2.0, 5.0])
def test_groove_dwell_is_the_tools_revolutions_at_the_bottom(revs):
    lib = _lib({7: {"dwell_rev": revs, "max_rpm": 1500.0}})
    prog = generate(_pin(groove=True), stock="14x36+1", tools=lib, verify=False)
    dwells = [m for m in prog.toolpath.moves if m.kind == "dwell" and m.tool == 7]
    assert dwells
    for m in dwells:
        assert abs(m.end[0] - 2.0) < 0.11  # at the bottom (0.1 left for the finishing pass)
        assert m.duration == pytest.approx(revs / m.spindle * 60.0, abs=0.006)


def test_dwell_rev_and_max_rpm_are_checked_in_the_tool_file(tmp_path):
    from hnc_cam.errors import ToolError
    src = tmp_path / "tools.toml"
    src.write_text('[[tool]]\nnumber = 7\ninsert = "GROOVE3.0"\nkind = "groove"\n'
                   'uses = ["groove"]\ndwell_rev = 50\n')
    with pytest.raises(ToolError, match=r"tools.toml:6.*dwell_rev"):
        load_tools(src)
    src.write_text('[[tool]]\nnumber = 7\ninsert = "GROOVE3.0"\nkind = "groove"\n'
                   'uses = ["groove"]\ndwell_rev = 3.5\nmax_rpm = 1800\n')
    t = load_tools(src).by_number(7)
    assert (t.dwell_rev, t.max_rpm) == (3.5, 1800.0)


# ---------------------------------------------------------------- thread to a shoulder

def _stud_to_shoulder(thread_len=25.0):
    # M20x1.5 running right up to a 26 mm collar, no relief groove
    from hnc_cam.geometry import Thread
    return TurnedProfile(chain((0, 0), (9, 0), (10, -1), (10, -25), (13, -25), (13, -45),
                               (0, -45)), threads=[Thread(0.0, -thread_len, 20.0, 1.5)],
                         name="stud_no_relief")


def test_thread_without_relief_runs_out_before_the_shoulder():
    prog = generate(_stud_to_shoulder(), stock="30x50+1")
    assert prog.report.passed  # the insert never touches the collar, the thread is whole
    th = [m for m in prog.toolpath.moves if m.kind == "thread"]
    root = min(m.end[0] for m in th)
    assert root == pytest.approx(10.0 - 0.6134 * 1.5, abs=0.002)
    full = [m for m in th if abs(m.start[0] - root) < 1e-6 and abs(m.end[0] - root) < 1e-6]
    assert full
    # the last full-depth point is at least one lead before the shoulder at Z-25
    assert min(m.end[1] for m in full) >= -25.0 + 1.5 - 1e-6
    # each pass leaves along the run-out: out to the crest while still moving toward the collar
    outs = [m for m in th if m.end[0] > m.start[0] + 1e-6]
    assert outs and all(m.end[1] < m.start[1] - 1e-6 for m in outs)
    assert min(m.end[1] for m in th) > -25.0  # never at the shoulder's face
    assert max(m.end[0] for m in outs) >= 10.0 - 1e-6
    assert prog.report.threads[0].achieved_diameter == pytest.approx(18.16, abs=0.05)


def _sleeve(thread_len=16.0):
    # M30x1.5 inside from the right face, then the bore steps in to 24 mm: no relief
    from hnc_cam.geometry import Thread
    return TurnedProfile(chain((14.2, 0), (20, 0), (20, -40), (12, -40)),
                         bore=chain((14.2, 0), (14.2, -thread_len), (12, -thread_len), (12, -40)),
                         threads=[Thread(0.0, -thread_len, 30.0, 1.5, internal=True)],
                         name="sleeve")


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it"])
@pytest.mark.parametrize("part,stock,wall,internal", [
    (_sleeve(), "42/22x45+1", -16.0, True),
    (_stud_to_shoulder(), "30x50+1", -25.0, False),
])
@pytest.mark.parametrize("cycle", ["g76", "g82"])
def test_threads_at_a_wall_without_relief_run_out_before_it(dialect, part, stock, wall,
                                                            internal, cycle):
    """Inside and outside, G76 and G82 (FANUC: G76's chamfer, G32 passes): full depth ends
    one lead and the flank's clearance before the shoulder, each pass leaves along the
    run-out away from the work while still moving toward the shoulder, and no pass reaches
    it; the thread verifies at the standard's diameter."""
    prog = generate(part, stock=stock, thread_cycle=cycle, dialect=dialect)
    assert prog.report.passed, prog.report.summary()
    th = [m for m in prog.toolpath.moves if m.kind == "thread"]
    s = -1.0 if internal else 1.0
    root = min(s * m.end[0] for m in th) * s
    full = [m for m in th if abs(m.start[0] - root) < 1e-6 and abs(m.end[0] - root) < 1e-6]
    assert full and min(m.end[1] for m in full) >= wall + 1.5 - 1e-6
    outs = [m for m in th if s * (m.end[0] - m.start[0]) > 1e-6]
    assert outs and all(m.end[1] < m.start[1] - 1e-6 for m in outs)
    assert min(m.end[1] for m in th) > wall
    t = prog.report.threads[0]
    assert abs(t.achieved_diameter - t.target_diameter) <= 0.05


def test_internal_thread_at_a_wall_with_no_room_for_the_run_out_names_the_minimum():
    with pytest.raises(PlanError, match=r"internal thread M30x1.5 from Z0 to Z-5 runs into the "
                                        r"shoulder.* needs at least 6.5 mm"):
        generate(_sleeve(5.0), stock="42/22x45+1", verify=False)


def test_thread_without_relief_and_no_room_for_the_run_out_is_refused():
    # two full leads and the run-out do not fit in 5 mm
    prof = TurnedProfile(chain((0, 0), (9, 0), (10, -1), (10, -5), (13, -5), (13, -30),
                               (0, -30)), name="short_stud",
                         threads=[__import__("hnc_cam.geometry", fromlist=["Thread"])
                                  .Thread(0.0, -5.0, 20.0, 1.5)])
    with pytest.raises(PlanError, match=r"external thread M20x1.5 from Z0 to Z-5 runs into the "
                                        r"shoulder at Z-5.* run-out does not fit"):
        _plan(prof, "30x35+1")


KNOB = '''"""A knob turned from a bar that ends at the part's left face, plain build123d."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "45x72+2"


def part():
    pts = [(0, 0), (11.5, 0), (12.5, -1), (12.5, -20), (20, -20), (20, -70), (0, -70)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
'''


@pytest.mark.cad
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_bar_ending_at_the_left_face_gets_a_square_left_corner(tmp_path, comp):
    """The stock ends exactly at the part's left end (72 mm of bar, 2 mm face stock, a 70 mm
    part): the passes run on past the corner by more than the largest nose radius, so the
    Ø40 corner at Z-70 is left square, not rounded by the nose."""
    from hnc_cam.testing import assert_roundtrip
    f = tmp_path / "knob.py"
    f.write_text(KNOB)
    program, report = assert_roundtrip(str(f), comp=comp)
    assert report.passed and report.max_undercut_mm <= 0.01


# ---------------------------------------------------------------- roughing cycles and the limit

def _free_run(prog, dialect="hnc21t"):
    """The program run on a machine that does not clamp G96 (the HNC-21T's G96 has no clamp
    word: only the program keeps the spindle within the limit)."""
    import dataclasses
    from hnc_cam.plan.api import _interpret
    return _interpret(prog.text, dataclasses.replace(MACH, max_rpm=100000.0), "<free>",
                      dialect=dialect)


def _flange():
    # a 120 mm flange 12 mm long with a 20 mm hub in front: face-dominated, G72 to the hub
    return TurnedProfile(chain((0, 0), (10, 0), (10, -3), (60, -3), (60, -12), (0, -12)),
                         name="flange120")


@pytest.mark.parametrize("part,stock,cycle", [
    (_pin(), "14x36+1", "G71"),          # a 6 mm pin: G96 would need ~4800 rpm at the pin
    (_flange(), "124x14+1", "G72"),      # a large face roughed down to the 20 mm hub
])
def test_roughing_cycles_keep_within_the_spindle_limit_without_a_clamp(part, stock, cycle):
    prog = generate(part, stock=stock)
    assert prog.report.passed
    rough = [op for op in prog.plan.operations if op.kind == "rough"]
    assert [op.cycle for op in rough] == [cycle]
    tp = _free_run(prog)
    moves = [m for m in tp.moves if m.op == cycle]
    assert moves
    assert max(m.spindle for m in moves) <= MACH.max_rpm + 1e-6
    # one G97 speed for the cycle: the roughing speed at the largest diameter it reaches
    t = rough[0].tool
    r_hi = max(max(abs(m.start[0]), abs(m.end[0])) for m in moves if m.kind != "rapid")
    assert {m.spindle for m in moves} == {rough[0].unclamped.value}
    assert rough[0].unclamped.value <= t.vc_rough * 1000 / (2 * math.pi * r_hi) + 1e-6
    # every operation of every tool keeps within the limit on a machine that does not clamp
    assert max(m.spindle for m in tp.moves) <= MACH.max_rpm + 1e-6


D60 = chain((0, 0), (28, 0), (30, -2), (30, -40), (0, -40))
#: the same with a 16 mm journal in front, 15 mm long
D60_JOURNAL = chain((0, 0), (7, 0), (8, -1), (8, -15), (28, -15), (30, -17), (30, -40), (0, -40))


@pytest.mark.parametrize("shape,stock,capped", [(D60, "80x45+1", False), (D60, "80x45", False),
                                                (D60_JOURNAL, "80x45+1", True)])
def test_roughing_keeps_g96_unless_the_cycle_reaches_the_critical_diameter(shape, stock, capped):
    # an 80 mm bar turned to 60: faced or not, the cycle's contour starts at the face's edge
    # (faced: near it; not faced: the finisher takes the face) and G96 stays under the limit;
    # with a 16 mm journal the cycle reaches inside the critical diameter: the cycle in two,
    # G96 outside it, G97 at the limit inside it
    prof = TurnedProfile(shape, name="d60")
    prog = generate(prof, stock=stock)
    assert prog.report.passed
    rough = [op for op in prog.plan.operations if op.kind == "rough"]
    assert [op.split is not None for op in rough] == [capped]
    assert [op.unclamped for op in rough] == [None]
    tp = _free_run(prog)
    g71 = [m for m in tp.moves if m.op == "G71"]
    assert (min(min(abs(m.start[0]), abs(m.end[0])) for m in g71) < 10.0) == capped
    assert max(m.spindle for m in tp.moves) <= MACH.max_rpm + 1e-6
    vc = rough[0].speed
    r_c = vc * 1000 / (2 * math.pi * MACH.max_rpm)
    # the passes along Z: G96 wherever it keeps under the limit, the limit inside
    cuts = [m for m in g71 if m.kind == "line" and abs(m.start[0] - m.end[0]) < 1e-9]
    for m in cuts:
        r = abs(m.end[0])
        if r >= r_c + 0.5:
            assert m.spindle == pytest.approx(vc * 1000 / (2 * math.pi * r), rel=1e-3) or \
                m.spindle == pytest.approx(MACH.max_rpm)
        if r < r_c - 0.5:
            assert m.spindle == pytest.approx(MACH.max_rpm)
    assert sum(m.spindle == pytest.approx(MACH.max_rpm) for m in cuts) >= (3 if capped else 0)


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas", "siemens802"])
@pytest.mark.parametrize("shape", [D60, D60_JOURNAL], ids=["d60", "journal"])
def test_a_face_in_the_finished_contour_is_finished_toward_the_centre(shape, comp, dialect):
    """A bar not faced first (no face stock): the finisher takes the right face, from its
    edge toward the centre until its nose is past the axis (the tip path in both modes),
    the finishing contour runs at most 1 mm of the face outward (control: the control rolls
    the nose around the edge), and the roughing cycle makes no passes in front of the face
    (its contour starts at the face's edge)."""
    prog = generate(TurnedProfile(shape, name="d60"), stock="80x45", comp=comp,
                    dialect=dialect)
    assert prog.report.passed
    fin = prog.plan.operations[-1].tool
    assert fin.number == 2
    x_e = shape[0].end[0]
    moves = [m for m in prog.toolpath.moves if m.kind != "rapid"]
    along = [m for m in moves if m.tool == 2 and abs(m.start[1]) < 1e-6
             and abs(m.end[1]) < 1e-6 and abs(m.end[0] - m.start[0]) > 1e-6]
    inward = [m for m in along if m.end[0] < m.start[0]]
    assert len(inward) == 1
    # from the edge (the tip where the nose's centre is over it) to past the axis
    assert inward[0].start[0] == pytest.approx(x_e - fin.nose_radius, abs=1e-3)
    assert inward[0].end[0] <= -fin.nose_radius + 1e-6
    assert all(m.end[0] - m.start[0] <= 1.0 + 1e-6 for m in along if m not in inward)
    # the face is cut after the roughing and before the finisher runs the contour
    i_face = moves.index(inward[0])
    assert all(m.tool == 1 for m in moves[:i_face] if m.tool != 2)
    assert all(m.tool == 2 for m in moves[i_face:] if m.tool in (1, 2)) and \
        any(m.tool == 2 and m.end[1] < -30 for m in moves[i_face:])
    # no pass in front of the face inside its edge: the roughing moves there stay out at
    # the edge's diameter (less the last millimetre the control-mode contour comes down on)
    assert all(min(m.start[0], m.end[0]) >= x_e - 1.0 - 1e-6 for m in moves
               if m.tool == 1 and max(m.start[1], m.end[1]) > 0.1 + 1e-6)


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas"])
@pytest.mark.parametrize("stock", ["42x45+1", "42x45"])
def test_a_g71_split_at_an_arcs_end_numbers_only_the_blocks_cycles_refer_to(stock, dialect):
    """An 18.7 mm journal: the G71's split falls on the end of the corner arc (the tip path
    reaches the critical radius there), so that arc is the inner cycle's nf on the HNC-21T.
    FANUC and Haas keep one cycle under G50: in ``--block-numbers pq`` no block carries a
    number that no P or Q refers to."""
    import re
    prof = TurnedProfile(chain((0, 0), (9.35, 0), (9.35, -10), (20, -10), (20, -40), (0, -40)),
                         name="journal")
    prog = generate(prof, stock=stock, dialect=dialect, block_numbers="pq")
    assert prog.report.passed
    (rough,) = [op for op in prog.plan.operations if op.split is not None]
    owner = prog.plan.contour_owner(rough)
    # the split is at a block's end: that block carries the inner cycle's nf
    assert any(b.label == rough.split.nf and b.kind in ("cw", "ccw") for b in owner.blocks)
    numbered = {int(n) for n in re.findall(r"^N(\d+)", prog.text, re.M)}
    refs = {int(n) for n in re.findall(r"\b[PQ](\d+)\b", prog.text)}
    assert numbered == refs and len(refs) == (4 if dialect == "hnc21t" else 2)


@pytest.mark.parametrize("part,cycles", [("stepped_shaft", 2), ("cq_pin", 2),
                                        ("grooved_shaft", 1), ("threaded_stud", 1)])
def test_bundled_parts_rough_at_g96_outside_the_critical_diameter(part, cycles):
    """The G71 whose G96 would exceed the limit near the axis: two cycles (G96 outside the
    critical diameter, G97 at the limit inside), or one G96 cycle where only the face's edge
    is inside and the semi-finishing pass takes it; on a machine that does not clamp, no
    move exceeds the limit and the passes outside run at the roughing surface speed."""
    prog = generate(PARTS + f"{part}.py")
    assert prog.report.passed
    rough = next(op for op in prog.plan.operations if op.name == "rough")
    assert rough.split is not None and rough.unclamped is None
    assert bool(rough.split.nf) == (cycles == 2)
    tp = _free_run(prog)
    assert max(m.spindle for m in tp.moves) <= MACH.max_rpm + 1e-6
    t1 = [m for m in tp.moves if m.op == "G71" and m.tool == rough.tool.number]
    vc = rough.speed
    r_c = vc * 1000 / (2 * math.pi * MACH.max_rpm)
    outside = [m for m in t1 if m.kind == "line" and abs(m.start[0] - m.end[0]) < 1e-9
               and abs(m.end[0]) > r_c + 0.01]
    assert outside and all(m.spindle == pytest.approx(vc * 1000 / (2 * math.pi * abs(m.end[0])),
                                                      rel=1e-3) for m in outside)
    lines = {m.line for m in t1}
    assert len(lines) == cycles


def test_a_tool_limit_lowers_the_roughing_speed():
    lib = _lib({1: {"max_rpm": 900.0}})
    prog = generate(_flange(), stock="124x14+1", tools=lib)
    tp = _free_run(prog)
    rough = [m for m in tp.moves if m.op == "G72"]
    assert rough and max(m.spindle for m in rough) <= 900.0 + 1e-6


# ---------------------------------------------------------------- the chuck's speed limit

def _chuck_machine(tmp_path, body):
    src = tmp_path / "lathe.toml"
    src.write_text('[machine]\nmax_rpm = 4000.0\n\n' + body)
    return src


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas"])
@pytest.mark.parametrize("part,stock", [(_pin(), "14x36+1"), (_flange(), "124x14+1"),
                                        (_stud_to_shoulder(), "30x50+1")])
def test_chuck_rated_speed_caps_every_move_in_every_dialect(tmp_path, dialect, part, stock):
    mach = _chuck_machine(tmp_path, "[chuck]\nmax_rpm = 1500\n")
    assert load_machine(mach).chuck_max_rpm == 1500.0
    prog = generate(part, stock=stock, machine=mach, dialect=dialect)
    assert prog.report.passed
    # the interpreter clamps G96 at the machine's 4000 rpm only: the program keeps 1500
    assert max(m.spindle for m in prog.toolpath.moves) <= 1500.0 + 1e-6
    if dialect != "hnc21t":
        import re
        assert set(re.findall(r"G50 S(\d+)", prog.text)) == {"1500"}
    # without the chuck table the same part runs faster somewhere
    free = generate(part, stock=stock, machine=_chuck_machine(tmp_path, ""), dialect=dialect,
                    verify=False)
    assert max(m.spindle for m in free.toolpath.moves) > 1500.0 + 1e-6


@pytest.mark.parametrize("body,limit,chuck", [("[chuck]\nmax_rpm = 1500\n", 1500, True),
                                              ("[chuck]\nmax_rpm = 5000\n", 4000, False),
                                              ("", 4000, False)])
def test_hnc_header_states_the_limit_the_program_keeps(tmp_path, body, limit, chuck):
    import re
    prog = generate(_pin(), stock="14x36+1", machine=_chuck_machine(tmp_path, body))
    head = [ln for ln in prog.text.splitlines() if "SPINDLE LIMIT" in ln]
    assert len(head) == 1
    assert int(re.search(r"SPINDLE LIMIT (\d+) RPM", head[0]).group(1)) == limit
    assert ("CHUCK" in head[0]) == chuck
    # the limit stated is the one every move keeps, and reached by the pin's small diameters
    assert max(m.spindle for m in prog.toolpath.moves) == pytest.approx(limit)


@pytest.mark.parametrize("body,line,what", [
    ("[chuck]\nmax_rmp = 1500\n", 5, "did you mean 'max_rpm'"),
    ("[chuck]\nmax_rpm = -1\n", 5, "max_rpm"),
    ("[chuck]\nmax_rpm = \"fast\"\n", 5, "max_rpm"),
    ("[chuk]\nmax_rpm = 1500\n", 4, "did you mean 'chuck'"),
])
def test_bad_chuck_table_is_one_line_naming_file_and_line(tmp_path, capsys, body, line, what):
    from hnc_cam.cli import main
    mach = _chuck_machine(tmp_path, body)
    out = tmp_path / "o.nc"
    rc = main(["generate", PARTS + "stepped_shaft.py", "--machine", str(mach), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1
    assert f"lathe.toml:{line}" in err[0] and what in err[0]


@pytest.mark.parametrize("d1", [18.7003, 18.7008, 18.701])
def test_g71_split_next_to_an_arcs_end_writes_no_arc_of_no_length(d1):
    """stepped_shaft's domed face ends at diameter d1; where the split radius (X18.7) falls
    within a few micrometres of the arc's end, the piece beyond it would round to an arc of
    no length (a full circle to the control): the cycle is cut at the arc's end instead."""
    for comp in ("cam", "control"):
        prog = generate(str(Path(__file__).resolve().parents[1] / "parts" / "stepped_shaft.py"),
                        params={"d1": str(d1)}, comp=comp)
        # it generated (the arc of no length was an interpreter alarm) and verifies
        assert prog.report.passed and prog.report.max_overcut_mm <= 0.01


@pytest.mark.parametrize("dialect, cycle", [("hnc21t", "g76"), ("hnc21t", "g82"),
                                            ("fanuc0it", "g76")])
def test_thread_ending_just_before_a_shoulder_runs_out_clear_of_it(dialect, cycle):
    """M20x1.5 to Z-14, a 2 mm plain length, then a 30 mm collar: no run-on past the end
    clears the insert's flanks, so the collar is the wall the run-out ends in front of (the
    flank cut 1.3 mm into the collar when the thread ran to its end at full depth)."""
    from hnc_cam.geometry import Thread
    prof = TurnedProfile(chain((0, 0), (9.2, 0), (10, -0.8), (10, -16), (15, -16), (15, -40),
                               (0, -40)), threads=[Thread(0.0, -14.0, 20.0, 1.5)],
                         name="stud_collar2")
    prog = generate(prof, stock="34x45+1", dialect=dialect, thread_cycle=cycle)
    assert prog.report.passed and prog.report.max_overcut_mm <= 0.01
    th = [m for m in prog.toolpath.moves if m.kind == "thread"]
    full = [m for m in th if abs(2 * m.end[0] - 18.16) < 1e-3 and abs(2 * m.start[0] - 18.16) < 1e-3]
    end = min(min(m.start[1], m.end[1]) for m in full)
    assert -14.0 < end < -14.0 + 3 * 1.5  # full form ends before the thread's end, within the run-out
    assert min(min(m.start[1], m.end[1]) for m in th) > -16.0  # never reaches the collar
