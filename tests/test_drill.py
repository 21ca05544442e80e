"""Holes from solid bar: drills in the library and the simulator, the drilling plan (spot,
pilot, opener, pecks), the boring bar on what the drills leave, and the refusals."""
from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.errors import PlanError, ToolError
from hnc_cam.plan.api import generate
from hnc_cam.tooling import Insert, load_tools

ROOT = Path(__file__).resolve().parents[1]
FRESH = ROOT / "tests" / "data" / "turning_parts"
LIB = (ROOT / "hnc_cam" / "data" / "tools.toml").read_text()
COT59 = 1.0 / math.tan(math.radians(59.0))

#: a part as a user writes it: a closed polyline revolved about Z
PART = '''
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "{stock}"


def part():
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*{pts!r}, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
'''


def _part(tmp_path: Path, name: str, pts, stock: str) -> Path:
    f = tmp_path / f"{name}.py"
    f.write_text(PART.format(pts=[tuple(p) for p in pts], stock=stock))
    return f


def _moves(prog, tool: int):
    return [m for m in prog.toolpath.moves if m.tool == tool]


# ---------------------------------------------------------------- library and simulator

def test_drills_in_the_default_library():
    lib = load_tools()
    drills = {t.number: t for t in lib.tools if t.kind == "drill"}
    assert sorted(t.diameter for t in drills.values()) == [8.0, 10.0, 12.0, 16.0, 20.0]
    assert all(t.point_angle == 118.0 and t.nose_radius == 0.0 for t in drills.values())
    assert drills[12].flute_length == 80.0 and drills[12].insert.code == "DRILL12-118L80"
    spot = [t for t in lib.tools if t.kind == "center_drill"]
    assert len(spot) == 1 and spot[0].point_angle == 90.0 and spot[0].diameter == 10.0
    # every tool number once; the registers reach the simulator with the drill's insert
    assert len({t.number for t in lib.tools}) == len(lib.tools)
    assert lib.registers()[14].insert.kind == "drill" and lib.registers()[14].kind == "drill"


def test_drill_codes_and_keys():
    ins = Insert.parse("drill6.8-135L40")
    assert (ins.kind, ins.width, ins.angle, ins.edge_length) == ("drill", 6.8, 135.0, 40.0)
    assert Insert.parse("DRILL10").angle == 118.0 and Insert.parse("DRILL10").edge_length == 50.0


@pytest.mark.parametrize("entry,needle", [
    ('number = 20\nkind = "drill"\n', r"tools.toml:\d+: tool\[\d+\]: a drill needs diameter"),
    ('number = 20\nkind = "drill"\ndiameter = 0\n', r"tools.toml:\d+: .*diameter"),
    ('number = 20\ninsert = "CNMG120408"\ndiameter = 8.0\n',
     r"tools.toml:\d+: tool T20: diameter is a drill's key"),
    ('number = 20\nkind = "drill"\ninsert = "DRILL8"\ndiameter = 9.0\n',
     r"tools.toml:\d+: tool T20: diameter 9 disagrees with insert DRILL8 \(8\)"),
    ('number = 20\ninsert = "DRILL8"\n', r"tools.toml:\d+: tool T20: insert DRILL8 is a drill"),
    ('number = 20\nkind = "drill"\ninsert = "DRILL0-118L50"\n',
     r"tools.toml:\d+: tool\[\d+\]: insert 'DRILL0-118L50': a drill needs a diameter above 0"),
    ('number = 20\ninsert = "XXXX"\n', r"tools.toml:\d+: tool\[\d+\]: insert 'XXXX': not an ISO"),
])
def test_drill_entries_that_are_wrong_name_file_and_line(tmp_path, entry, needle):
    f = tmp_path / "tools.toml"
    f.write_text(LIB + "\n[[tool]]\n" + entry)
    with pytest.raises(ToolError, match=needle):
        load_tools(f)


def test_the_simulator_draws_a_drill_as_its_point_and_body_on_the_axis():
    from hnc_cam.sim.tool import tool_shape
    from hnc_cam.tooling import load_machine
    s = tool_shape(load_machine().register(12))
    pts = {(round(float(z), 6), round(float(x), 6)) for z, x in s.outline}
    h = round(6.0 * COT59, 6)
    # tip at the controlled point, the 118 deg cone to diameter 12, the 80 mm body
    assert pts == {(0.0, 0.0), (h, 6.0), (h, -6.0), (80.0, 6.0), (80.0, -6.0)}
    assert len(s.non_cutting) == 3  # the back and the two margins


# ---------------------------------------------------------------- blind bore, drill point

@pytest.mark.parametrize("comp", ["cam", "control"])
def test_blind_bore_is_drilled_to_its_point_and_bored_and_verifies(comp):
    prog = generate(FRESH / "blind_bore.py", comp=comp)
    assert prog.report.passed, prog.report.summary()
    names = [op.name for op in prog.plan.operations]
    assert names[names.index("spot"):names.index("bore_finish") + 1] == [
        "spot", "drill", "bore_rough", "bore_finish"]
    drill = _moves(prog, 14)
    # every drill move on the axis; the point's tip at the model's apex (rounded toward the
    # face): Z-30 - 10 cot 59 = -36.0086 -> -36.008
    assert all(abs(m.start[0]) < 1e-9 and abs(m.end[0]) < 1e-9 for m in drill
               if m.end[1] < 2.0 - 1e-9)
    assert min(m.end[1] for m in drill) == pytest.approx(-36.008)
    # the spot drill's 90 deg cone to diameter 10: 5 mm deep
    assert min(m.end[1] for m in _moves(prog, 9)) == pytest.approx(-5.0)
    # the boring bar starts its G71 from the drilled hole and finishes the mouth's chamfer,
    # running on 1 mm along the drilled wall; it never goes deeper
    bar = [m for m in _moves(prog, 3) if m.kind != "rapid"]
    assert min(m.end[1] for m in bar) > -3.0


def test_the_simulated_hole_has_the_drill_point_for_a_bottom():
    from hnc_cam.sim import simulate
    from shapely.geometry import Point
    prog = generate(FRESH / "blind_bore.py", verify=False)
    m = simulate(prog.toolpath, prog.plan.stock, prog.plan.machine)
    apex = -36.008
    for r in (0.5, 5.0, 9.5):
        z = apex + r * COT59  # on the cone
        assert m.material.contains(Point(z - 0.01, r)), r
        assert not m.material.contains(Point(z + 0.01, r)), r
    assert not m.material.contains(Point(-20.0, 9.9)) and m.material.contains(Point(-20.0, 10.1))


# ---------------------------------------------------------------- stepped bore, pecks

PECKS = [-10.902, -21.804, -32.706]


def _drill_sequence(prog, tool):
    """(kind, end z) of the drill's moves on the axis from the R plane on."""
    out = []
    for m in _moves(prog, tool):
        if abs(m.end[0]) < 1e-9 and abs(m.start[0]) < 1e-9 and m.end[1] <= 1.0 + 1e-9:
            out.append((m.kind, round(m.end[1], 6)))
    return out


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_stepped_blind_bore_pilot_opener_and_bar(comp):
    prog = generate(FRESH / "stepped_blind_bore.py", comp=comp)
    assert prog.report.passed, prog.report.summary()
    ops = prog.plan.operations
    drills = [(op.tool.number, op.drill.z_end) for op in ops if op.kind == "drill"]
    # spot, the 12 mm pilot to size (its point on the model's apex), the 20 mm opener as
    # deep as its point stays 0.3 mm off the 30 mm counterbore's floor at Z-15
    assert drills[0] == (9, -5.0)
    assert drills[1] == (12, pytest.approx(math.ceil((-40 - 6 * COT59) * 1000) / 1000))
    t, z_open = drills[2]
    assert t == 14
    # the opener's cone at the pilot's wall plus 0.3 mm is 0.3 mm above the floor
    assert z_open + 5.7 * COT59 == pytest.approx(-15.0 + 0.3, abs=0.011)
    rough = next(op for op in ops if op.name == "bore_rough")
    assert rough.start[0] == pytest.approx(6.0)  # G71 from the pilot's hole
    # the bar works on the counterbore only: never below its floor
    bar = [m for m in _moves(prog, 3) if m.kind != "rapid"]
    assert min(m.end[1] for m in bar) >= -15.0 - 1.0 - 0.05 - 1e-6


def test_deep_hole_pecks_their_depths_and_retracts():
    prog = generate(FRESH / "stepped_blind_bore.py")
    seq = _drill_sequence(prog, 12)
    end = -43.605
    assert seq == [
        ("rapid", 1.0),
        ("line", PECKS[0]), ("rapid", PECKS[0] + 0.5),          # chip breaking
        ("line", PECKS[1]), ("rapid", PECKS[1] + 0.5),
        ("line", PECKS[2]), ("rapid", 1.0), ("rapid", PECKS[2] + 0.5),  # every third: out
        ("line", end), ("dwell", end), ("rapid", 1.0)]
    # equal pecks of at most one diameter
    steps = [0.0] + PECKS + [end]
    assert all(0 < a - b <= 12.0 + 1e-9 for a, b in zip(steps, steps[1:]))
    dwell = next(m for m in _moves(prog, 12) if m.kind == "dwell")
    # two revolutions at 663 rpm
    assert dwell.duration == pytest.approx(0.18)


def test_the_macro_style_runs_the_same_toolpath_as_the_blocks():
    blocks = generate(FRESH / "stepped_blind_bore.py", verify=False)
    macro = generate(FRESH / "stepped_blind_bore.py", drill_style="macro")
    assert macro.report.passed
    assert re.search(r"^N\d+ G65 P9001 B0 Q10.902 Z-43.605 R1 K3 C0.5 F0.18 E0.18$",
                     macro.text, re.M)
    assert "WHILE" in macro.text and "WHILE" not in blocks.text
    a = [(m.kind, m.tool, m.start, m.end, m.feed) for m in blocks.toolpath.moves]
    b = [(m.kind, m.tool, m.start, m.end, m.feed) for m in macro.toolpath.moves]
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x[:2] == y[:2] and x[4] == pytest.approx(y[4])
        assert x[2] == pytest.approx(y[2], abs=1e-9) and x[3] == pytest.approx(y[3], abs=1e-9)
    assert macro.cycle_time_s == pytest.approx(blocks.cycle_time_s)


def test_macro_subprogram_number_avoids_the_main_programs(tmp_path):
    prog = generate(FRESH / "stepped_blind_bore.py", drill_style="macro", program_number=9001,
                    verify=False)
    assert "G65 P9002 " in prog.text and "\n%9002\n" in prog.text


@pytest.mark.parametrize("dialect", ["fanuc0it", "haas"])
def test_fanuc_pecks_with_g74(dialect):
    prog = generate(FRESH / "stepped_blind_bore.py", dialect=dialect)
    assert prog.report.passed
    assert re.search(r"^N\d+ G74 R0\.5\nN\d+ G74 Z-43\.605 Q10902 F0\.18$", prog.text, re.M)
    # the pecks from the R plane Z1, 0.5 mm back after each, to the point's depth
    feeds = [round(m.end[1], 3) for m in _moves(prog, 12) if m.kind == "line"
             and abs(m.end[0]) < 1e-9]
    assert feeds == [round(1.0 - 10.902 * k, 3) for k in range(1, 5)] + [-43.605]


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_siemens802_drills_in_plain_blocks(comp):
    prog = generate(FRESH / "stepped_blind_bore.py", dialect="siemens802", comp=comp)
    assert prog.report.passed, prog.report.summary()
    assert re.search(r"^N\d+ G1 Z-43\.605\nN\d+ G4 F0\.18\nN\d+ G0 Z1$", prog.text, re.M)
    feeds = [round(m.end[1], 3) for m in _moves(prog, 12) if m.kind == "line"]
    assert feeds == PECKS + [-43.605]


def test_generate_cli_drill_style_macro(tmp_path, capsys):
    out = tmp_path / "o.nc"
    rc = main(["generate", str(FRESH / "stepped_blind_bore.py"), "--drill-style", "macro",
               "-o", str(out)])
    assert rc == 0 and "G65 P9001" in out.read_text()
    rc = main(["run", str(out)])
    assert rc == 0


# ---------------------------------------------------------------- through bore, part-off

def test_through_bore_of_a_drill_size_is_drilled_through_and_the_part_parted_off(tmp_path):
    # a 36 mm ring, 20 mm bore, 20 mm long, parted off a 40 mm bar held 15 mm deep
    f = _part(tmp_path, "ring", [(10, 0), (17, 0), (18, -1), (18, -19), (17, -20), (10, -20)],
              "40x60+1")
    for comp in ("cam", "control"):
        prog = generate(f, grip=15, comp=comp)
        assert prog.report.passed, prog.report.summary()
        names = [op.name for op in prog.plan.operations]
        assert "bore_rough" not in names and names[-1] == "partoff"
        # the drill's full diameter runs 0.5 mm past the part's left end
        tip = min(m.end[1] for m in _moves(prog, 14))
        assert tip == pytest.approx(math.floor((-20.5 - 10 * COT59) * 1000) / 1000)


# ---------------------------------------------------------------- refusals

def _refused(tmp_path, capsys, part: Path, *extra: str) -> str:
    out = tmp_path / "o.nc"
    rc = main(["generate", str(part), "-o", str(out), *extra])
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists(), err
    assert len(err.strip().splitlines()) == 1 and err.startswith("error: ")
    return err


def test_bore_under_the_bars_min_bore_without_an_opener_is_refused(tmp_path, capsys):
    lib = tmp_path / "tools.toml"
    blocks = LIB.split("[[tool]]")
    lib.write_text("[[tool]]".join(b for b in blocks if "Drill 16" not in b
                                   and "Drill 20" not in b))
    err = _refused(tmp_path, capsys, FRESH / "stepped_blind_bore.py", "--tools", str(lib))
    assert "blind bore diameter 12 to Z-40" in err
    assert ("is diameter 30 near the face, wider than the drill T12 (12 mm) makes it; the "
            "boring bar T03 enters a hole of min_bore 16") in err
    assert "a boring bar with min_bore <= 12 or a drill of diameter 16 to 29.4 mm" in err


def test_bore_no_drill_fits_is_refused_naming_the_drill_needed(tmp_path, capsys):
    tip = 3 * COT59
    f = _part(tmp_path, "pin6", [(3, 0), (12, 0), (12, -30), (0, -30), (0, -15 - tip), (3, -15)],
              "26x45+1")
    err = _refused(tmp_path, capsys, f)
    assert ("no drill in the library fits the blind bore diameter 6 to Z-15: the smallest, T10 "
            "(8 mm), is wider than the bore; it needs a drill of at most 6 mm with a 118 deg "
            "point") in err


def test_flat_bottom_is_faced_by_the_bar_as_far_as_its_head_leaves_it(tmp_path):
    # a 20 mm bore flat at Z-20: the 20 mm drill's point stops on the bottom; the bar's head
    # (min_bore 16) in the 20 mm bore keeps its tip 6 mm off the axis: it faces to 7 mm
    f = _part(tmp_path, "cup", [(10, 0), (18, 0), (18, -30), (0, -30), (0, -20), (10, -20)],
              "38x45+1")
    prog = generate(f, verify=False)
    drill = next(op for op in prog.plan.operations if op.name == "drill")
    assert drill.tool.number == 14 and drill.drill.z_end == pytest.approx(-19.999)
    assert any("inside diameter 14 is beyond the boring bar T03's reach" in n for n in drill.notes)
    bar = [m for m in _moves(prog, 3) if m.kind != "rapid"]
    assert min(m.end[1] for m in bar) == pytest.approx(-20.0, abs=1e-3)
    assert min(min(m.start[0], m.end[0]) for m in bar if m.end[1] < -15.0) >= 6.0 - 1e-6


def test_hole_deeper_than_the_flutes_is_refused(tmp_path, capsys):
    tip = 6 * COT59
    f = _part(tmp_path, "deep", [(6, 0), (15, 0), (15, -100), (0, -100), (0, -85 - tip),
                                 (6, -85)], "32x120+1")
    err = _refused(tmp_path, capsys, f)
    assert "T12 Drill 12 mm to drill 88.605 mm deep" in err
    assert "flutes reach 80 mm: it needs a 12 mm drill with flute_length >= 88.605" in err


def test_no_drill_in_the_library_is_refused(tmp_path, capsys):
    lib = tmp_path / "tools.toml"
    blocks = LIB.split("[[tool]]")
    lib.write_text("[[tool]]".join(b for b in blocks if 'kind = "drill"' not in b))
    err = _refused(tmp_path, capsys, FRESH / "blind_bore.py", "--tools", str(lib))
    assert "blind bore diameter 20 to Z-30 from solid bar needs a drill" in err


def test_material_table_limits_drill_speed():
    prog = generate(FRESH / "blind_bore.py", material="304", verify=False)
    drill = next(op for op in prog.plan.operations if op.name == "drill")
    # 304: at most 18 m/min: 286 rpm at 20 mm
    assert drill.speed == math.floor(18.0 * 1000 / (math.pi * 20.0))
    assert drill.feed == 0.2


# ---------------------------------------------------------------- inside thread and relief

@pytest.mark.parametrize("comp", ["cam", "control"])
def test_nut_from_solid_with_an_inside_thread_into_an_inside_relief(comp):
    prog = generate(FRESH / "nut_m24.py", comp=comp)
    assert prog.report.passed, prog.report.summary()
    ops = prog.plan.operations
    names = [op.name for op in ops]
    assert names.index("drill") < names.index("bore_rough") < names.index("bore_finish") \
        < names.index("groove") < names.index("thread")
    groove = ops[names.index("groove")]
    assert groove.tool.kind == "groove_id" and groove.tool.number == 15
    # the 3 mm relief Z-13..-16 out to diameter 25.5, one plunge of the 3 mm insert with its
    # -Z corner at Z-16, in and out of the bore along Z inside the minor diameter less 2 mm
    moves = [m for m in _moves(prog, 15) if m.kind in ("rapid", "line")]
    x_in = round((24 - 1.0825 * 1.5) / 2 - 1.0, 3)  # as the program writes it
    ends = [(round(m.end[0], 4), round(m.end[1], 4)) for m in moves]
    inside = ends[ends.index((round(x_in, 4), 2.0)):]
    assert inside[:5] == [(round(x_in, 4), 2.0), (round(x_in, 4), -16.0),
                          (round(22.376 / 2 - 0.6, 4), -16.0), (12.75, -16.0),
                          (round(22.376 / 2 - 0.6, 4), -16.0)]
    assert max(m.end[0] for m in moves if m.kind == "line") == pytest.approx(12.75)
    # the inside G76 to the major diameter, ending at the relief, depth 0.5413 x 1.5
    thread = ops[names.index("thread")]
    assert thread.tool.number == 6 and thread.thread.z_end == pytest.approx(-13.0)
    assert re.search(r"^N\d+ G76 C1 R0 E0 A60 X24 Z-13 K0\.812 ", prog.text, re.M)


@pytest.mark.parametrize("dialect", ["fanuc0it", "haas", "siemens802"])
def test_nut_parted_off_the_bar_in_every_dialect(dialect):
    prog = generate(FRESH / "nut_m24.py", grip=15, dialect=dialect)
    assert prog.report.passed and prog.plan.operations[-1].kind == "part"
    # the relief plunged outward from inside the bore to diameter 25.5
    plunge = [m for m in _moves(prog, 15) if m.kind == "line"]
    assert [(round(m.start[0], 3), round(m.end[0], 3), m.end[1]) for m in plunge] == [
        (10.588, 12.75, -16.0)]


def test_inside_groove_narrower_than_the_insert_is_refused(tmp_path, capsys):
    r = 11.0
    f = _part(tmp_path, "ring2", [(r + 1, 0), (17, 0), (17, -20), (r, -20), (r, -12),
                                  (12.5, -12), (12.5, -10), (r, -10), (r, -1)], "36x45+1")
    err = _refused(tmp_path, capsys, f)
    assert ("inside groove from Z-10 to Z-12 (2 mm wide, out to diameter 25) in the bore of "
            "diameter 22: no boring bar reaches it and no inside grooving tool in the library "
            "cuts it; it needs a kind = \"groove_id\" tool at most 2 mm wide") in err


def test_bore_deeper_than_the_boring_bars_reach_is_refused(tmp_path, capsys):
    # a 25 mm through bore 80 mm long; the bundled bar T03 reaches 64 mm (max_depth)
    f = _part(tmp_path, "sleeve80", [(12.5, 0), (20, 0), (20, -80), (12.5, -80)], "42/20x85+1")
    err = _refused(tmp_path, capsys, f)
    assert ("the bore runs 80 mm deep (to Z-80); the boring bar T03 reaches 64 mm (max_depth): "
            "it needs a boring bar reaching 80 mm") in err
    # the same sleeve 60 mm long is bored
    g = _part(tmp_path, "sleeve60", [(12.5, 0), (20, 0), (20, -60), (12.5, -60)], "42/20x65+1")
    assert generate(g, verify=False).plan.operations


def test_bore_under_the_bars_min_bore_and_no_drill_of_its_size_is_refused(tmp_path, capsys):
    f = _part(tmp_path, "through9", [(4.5, 0), (12, 0), (12, -30), (4.5, -30)], "26x45+1")
    err = _refused(tmp_path, capsys, f)
    assert ("the through bore diameter 9 needs the boring bar where it is diameter 9, under the "
            "smallest hole the boring bar T03 enters (min_bore 16); the drill T10 makes 8 mm: it "
            "needs a boring bar with min_bore <= 8 or a drill of diameter 9") in err


def test_through_hole_of_a_drill_size_needs_no_boring_bar(tmp_path):
    f = _part(tmp_path, "through8", [(4, 0), (12, 0), (12, -30), (4, -30)], "26x45+1")
    prog = generate(f)
    assert prog.report.passed
    assert [op.name for op in prog.plan.operations if op.tool.kind in ("drill", "bore")] == [
        "drill"]


@pytest.mark.parametrize("bottom,what", [
    ("Polyline((0, -40), (0, -25 - 10 / 3 ** 0.5), (10, -25))", "a 120 deg cone"),
    ("ThreePointArc((0, -35), (7.0711, -32.0711), (10, -25))", "a curved bottom")])
def test_a_bottom_no_drill_point_makes_is_refused(tmp_path, capsys, bottom, what):
    src = PART.replace("Polyline(*{pts!r}, close=True)",
                       "Line((10, 0), (18, 0)); Line((18, 0), (18, -40)); Line((18, -40), "
                       "(0, -40)); " + bottom + "; Line((10, -25), (10, 0))")
    src = src.replace("Polyline, ", "Polyline, Line, ThreePointArc, ")
    if "Arc" in bottom:
        src = src.replace("Line((18, -40), (0, -40)); ", "Line((18, -40), (0, -40)); "
                          "Line((0, -40), (0, -35)); ")
    f = tmp_path / "cup.py"
    f.write_text(src.format(stock="38x50+1"))
    err = _refused(tmp_path, capsys, f)
    assert f"blind bore diameter 20 to Z-25 ends in {what}" in err


def test_a_relief_in_a_drilled_hole_is_grooved_without_the_boring_bar(tmp_path):
    # a 20 mm blind hole (the 20 mm drill's size and point) with a relief Z-12..-15 to 23 mm
    tip = 10 * COT59
    f = _part(tmp_path, "relief20", [(10, 0), (18, 0), (18, -40), (0, -40), (0, -30 - tip),
                                     (10, -30), (10, -15), (11.5, -15), (11.5, -12), (10, -12)],
              "38x50+1")
    for comp in ("cam", "control"):
        prog = generate(f, comp=comp)
        assert prog.report.passed, prog.report.summary()
        kinds = [(op.name, op.tool.number) for op in prog.plan.operations
                 if op.tool.kind in ("drill", "bore", "groove_id")]
        assert kinds == [("drill", 14), ("groove", 15)]
        plunge = [m for m in _moves(prog, 15) if m.kind == "line"]
        assert [round(m.end[0], 3) for m in plunge] == [11.5]


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it"])
def test_nut_inside_thread_in_single_passes(dialect):
    prog = generate(FRESH / "nut_m24.py", dialect=dialect, thread_cycle="g82")
    assert prog.report.passed
    # the passes go outward from the minor diameter to the major (24), the last repeated
    radii = [round(m.end[0], 3) for m in prog.toolpath.moves
             if m.tool == 6 and m.kind == "thread"]
    assert radii and max(radii) == pytest.approx(12.0)
    firsts = sorted(set(radii))
    assert firsts[0] > (24 - 1.0825 * 1.5) / 2 - 1e-6


@pytest.mark.parametrize("dialect, labels", [
    ("fanuc0it", ["G01", "G74"]), ("haas", ["G01", "G74"]), ("siemens802", ["G1", "G1"]),
    ("hnc21t", ["G01", "G01"])])
def test_summary_and_json_name_the_drilling_cycles(dialect, labels):
    """The spot drill feeds once; the 12 mm pilot pecks (G74 where the dialect has it)."""
    from hnc_cam.plan.export import plan_json
    prog = generate(FRESH / "stepped_blind_bore.py", dialect=dialect, verify=False)
    drills = [o.split(" ", 1)[1] for o in prog.operations if o.split(" ", 1)[0] in ("spot", "drill")]
    assert drills[:2] == labels
    assert [o["cycle"] for o in plan_json(prog)["operations"]] == [
        o.split(" ", 1)[1] for o in prog.operations]


@pytest.mark.parametrize("dialect, how", [("siemens802", "plain blocks"), ("fanuc0it", "G74")])
def test_macro_drill_style_elsewhere_says_how_the_program_pecks(dialect, how):
    prog = generate(FRESH / "stepped_blind_bore.py", dialect=dialect, drill_style="macro",
                    verify=False)
    assert any(f"pecks with {how}" in w for w in prog.warnings)
    assert "WHILE" not in prog.text
    hnc = generate(FRESH / "stepped_blind_bore.py", drill_style="macro", verify=False)
    assert not any("drill-style" in w for w in hnc.warnings) and "WHILE" in hnc.text
