"""Planner: operation choice per kind of part, allowances, refusals (synthetic profiles, no
CAD kernel); programs run through the interpreter without alarm in both compensation modes."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from hnc_cam.errors import PlanError
from hnc_cam.plan import Options, make_plan
from hnc_cam.plan.api import generate
from hnc_cam.tooling import Stock, ToolLibrary, load_machine, load_tools

from test_plan_shapes import bushing, flange, grooved, shaft, stud, undercut, wavy

LIB = load_tools(None)
MACH = load_machine(None, tools=LIB)


def plan(profile, stock, comp="control", lib=LIB, **kw):
    return make_plan(profile, Stock.parse(stock), lib, MACH, Options(comp=comp, **kw),
                     name=profile.name)


def cycles(p):
    return [(op.name, op.cycle) for op in p.operations]


def test_monotonic_shaft_is_g71_type_1_with_facing():
    p = plan(shaft(), "50x90+2")
    # G96 S180 would need more than the machine's 3000 rpm inside diameter 19.1: G01 passes
    # that switch to G97 S3000 there
    assert cycles(p)[:3] == [("face", "G01"), ("rough", "G71"), ("finish", "contour")]
    face = p.operations[0]
    assert face.face.cap_rpm == 3000.0
    assert 2 * face.face.cap_x == pytest.approx(180000 / (math.pi * 3000))
    prog = generate(shaft(), stock="50x90+2", verify=False)
    cen = [m for m in prog.toolpath.moves if m.kind == "line" and m.tool == 1
           and abs(m.end[0]) < 9.0 and m.end[1] >= -1e-9]
    assert cen and all(m.spindle <= 3000.0 + 1e-6 for m in cen)
    assert face.passes[-1] == 0.0 and len(face.passes) == 2  # 2 mm in passes of <= 1.5
    assert face.face.x_end == pytest.approx(-0.8)  # past the centre by the nose radius
    rough = p.operations[1]
    assert rough.tool.number == 1 and p.operations[2].tool.number == 2
    assert rough.rough.allowance_x >= 0.2 and rough.rough.allowance_z >= 0.1
    assert "monotonic" in rough.reason


def test_undercut_is_g71_type_2_with_a_tool_that_reaches_it():
    p = plan(undercut(), "40x70")
    rough = [op for op in p.operations if op.name == "rough"][0]
    zone = [op for op in p.operations if op.name == "rough_zone"][0]
    # the 80 deg rougher takes the envelope (type I); the 45 deg wall is beyond the DNMG
    # (30 deg): the VNMG (50 deg) rest-roughs the zone (type II) and finishes
    assert rough.cycle == "G71" and rough.tool.number == 1
    assert zone.cycle == "G71E" and zone.tool.insert.code.startswith("VNMG")
    fin = [op for op in p.operations if op.name == "finish"][0]
    assert fin.tool.number == zone.tool.number and not fin.new_tool
    assert "45 deg" in zone.reason


def test_flange_is_g72_by_the_stated_rule():
    p = plan(flange(), "104x30+2")
    rough = [op for op in p.operations if op.name == "rough"][0]
    assert rough.cycle == "G72"
    assert "radial extent" in rough.reason and "> length" in rough.reason
    fin = [op for op in p.operations if op.name == "finish"][0]
    assert fin.nose_comp == "left" and fin.comp == 41  # contour run toward +Z
    assert fin.blocks[0].x is None and fin.blocks[0].z is not None  # ns moves along Z only


def test_offset_stock_is_g73():
    p = plan(wavy(), "offset:2")
    rough = [op for op in p.operations if op.name == "rough"][0]
    assert rough.cycle == "G73"
    # the blank's face allowance is faced first, then the passes step in X only
    assert rough.rough.relief_x == 2 and rough.rough.relief_z == 0 and rough.rough.count >= 2
    face = [op for op in p.operations if op.name == "face"][0]
    assert face.passes[-1] == 0.0 and face.start[1] == pytest.approx(4.0)


def test_tube_gets_bore_roughing_with_negative_allowance():
    p = plan(bushing(), "42/16x45+2")
    names = cycles(p)
    assert ("bore_rough", "G71") in names and ("bore_finish", "contour") in names
    b = [op for op in p.operations if op.name == "bore_rough"][0]
    assert b.tool.kind == "bore" and b.rough.side == "id" and b.rough.x_sign == -1
    assert b.rough.allowance_x > 0
    bf = [op for op in p.operations if op.name == "bore_finish"][0]
    assert bf.nose_comp == "left"


def test_square_groove_is_plunged_with_the_grooving_tool():
    p = plan(grooved(width=4.0), "30x70")
    g = [op for op in p.operations if op.name == "groove"][0]
    assert g.tool.kind == "groove"
    # plunges leave 0.1 mm on the walls and the bottom; the finishing pass takes it
    assert g.passes[0] == pytest.approx(-20 - 3.0 - 0.1)
    assert g.passes[-1] == pytest.approx(-24.0 + 0.1)
    assert g.groove.x_bottom == pytest.approx(8.1)
    f = g.groove.finish
    assert (f.z_right, f.z_left, f.x_bottom) == pytest.approx((-23.0, -24.0, 8.0))
    prog = generate(grooved(width=4.0), stock="30x70", verify=False)
    moves = [m for m in prog.toolpath.moves if m.tool == 7]
    # the groove tool's feed moves: down to the bottom, a dwell there, and never a rapid
    # below 0.5 mm above the groove's top (diameter 20)
    assert any(m.kind == "dwell" for m in moves)
    assert min(2 * m.end[0] for m in moves if m.kind == "rapid") >= 21.0 - 1e-6
    bottom = [m for m in moves if m.kind == "line" and abs(m.start[0] - 8.0) < 1e-6
              and abs(m.end[0] - 8.0) < 1e-6]
    assert bottom and min(m.end[1] for m in bottom) == pytest.approx(-24.0)
    rough = [op for op in p.operations if op.name == "rough"][0]
    assert rough.cycle == "G71" and "bridged" in rough.reason


def test_thread_g76_depth_from_the_standard_and_g82_option():
    p = plan(stud(), "30x60+1")
    th = [op for op in p.operations if op.name == "thread"][0]
    assert th.cycle == "G76"
    assert th.thread.height == pytest.approx(0.6134 * 1.5)
    assert 2 * th.thread.x_root == pytest.approx(20 - 2 * 0.6134 * 1.5)
    assert th.speed_mode == "G97" and th.spindle == "rpm"
    p2 = plan(stud(), "30x60+1", thread_cycle="g82")
    th2 = [op for op in p2.operations if op.name == "thread"][0]
    assert th2.cycle == "G82" and th2.passes[-1] == pytest.approx(10 - 0.6134 * 1.5)
    assert th2.passes == sorted(th2.passes, reverse=True)


# ---------------------------------------------------------------- refusals

def test_stock_too_small():
    with pytest.raises(PlanError, match="smaller than the part's largest diameter 44"):
        plan(shaft(), "40x90")


def test_stock_too_short():
    with pytest.raises(PlanError, match="too short"):
        plan(shaft(), "50x60+2")


def test_unreachable_groove_names_the_tool_needed():
    with pytest.raises(PlanError, match=r"unreachable.*grooving insert at most 2 mm wide.*T07 3 mm"):
        plan(grooved(width=2.0), "30x70")


def test_thread_longer_than_relief():
    with pytest.raises(PlanError, match="longer than the relief allows"):
        plan(stud(thread_len=28.8), "30x60+1")


def test_missing_thread_tool():
    lib = ToolLibrary(tuple(t for t in LIB.tools if t.kind != "thread"))
    with pytest.raises(PlanError, match="no external threading tool"):
        plan(stud(), "30x60+1", lib=lib)


def _stud_pitch(pitch: float):
    from hnc_cam.geometry import Thread
    s = stud()
    s.threads = [Thread(0.0, -22.0, 20.0, pitch)]
    return s


def _with_insert(code: str) -> ToolLibrary:
    """The default library with its external threading insert replaced by ``code``."""
    from dataclasses import replace
    from hnc_cam.tooling import Insert
    return ToolLibrary(tuple(replace(t, insert=Insert.parse(code)) if t.number == 4 else t
                             for t in LIB.tools))


def test_thread_pitch_from_the_part_not_from_the_insert():
    """The program's lead is the Thread's pitch; the insert's pitch (range) only chooses."""
    from hnc_cam.plan.tools import thread_pitch_range
    lib = _with_insert("16ERA60")
    assert thread_pitch_range(lib.by_number(4)) == (0.5, 1.5)
    for pitch in (1.0, 1.25, 1.5):
        th = [op for op in plan(_stud_pitch(pitch), "30x60+1", lib=lib).operations
              if op.name == "thread"][0]
        assert th.feed == pytest.approx(pitch) and th.thread.lead == pytest.approx(pitch)
        assert th.thread.height == pytest.approx(0.6134 * pitch)
        assert th.tool.insert.code == "16ERA60"
    from hnc_cam.post import render
    text = render(plan(_stud_pitch(1.0), "30x60+1", lib=lib))
    g76 = [ln for ln in text.splitlines() if " G76 " in ln]
    assert len(g76) == 1 and g76[0].endswith(" F1") and " K0.613 " in g76[0]


@pytest.mark.parametrize("pitch,needs", [(1.0, r"16ER1ISO or a partial profile 16ERA60"),
                                         (2.0, r"16ER2ISO or a partial profile 16ERAG60")])
def test_thread_pitch_no_insert_fits_names_thread_and_insert(pitch, needs):
    """The default library's full-profile 16ER1.5ISO cuts pitch 1.5 only."""
    with pytest.raises(PlanError, match=rf"external thread M20x{pitch:g} from Z0 to Z-22: no "
                                        rf"threading insert in the library cuts pitch {pitch:g} mm.*"
                                        rf"T04 16ER1.5ISO \(pitch 1.5, 60 deg\).*{needs}"):
        plan(_stud_pitch(pitch), "30x60+1")


def test_partial_profile_range_refuses_a_pitch_outside_it():
    with pytest.raises(PlanError, match=r"T04 16ERA60 \(pitch 0.5-1.5, 60 deg\).*16ERAG60"):
        plan(_stud_pitch(2.0), "30x60+1", lib=_with_insert("16ERA60"))


def test_thread_insert_pitch_ranges_from_iso_codes():
    from hnc_cam.plan.tools import cuts_pitch, thread_pitch, thread_pitch_range
    from hnc_cam.tooling import Insert, Tool

    def tool(code):
        return Tool(number=1, register=1, name="t", insert=Insert.parse(code), kind="thread")
    assert thread_pitch_range(tool("16ER1.5ISO")) == (1.5, 1.5)
    assert thread_pitch(tool("16ER2ISO")) == 2.0 and thread_pitch(tool("16ERA60")) is None
    assert thread_pitch_range(tool("16ER16UN")) == pytest.approx((25.4 / 16, 25.4 / 16))
    assert thread_pitch_range(tool("11IR11W")) == pytest.approx((25.4 / 11, 25.4 / 11))
    assert cuts_pitch(tool("16ERA60"), 0.5) and cuts_pitch(tool("16ERA60"), 1.5)
    assert not cuts_pitch(tool("16ERA60"), 1.75) and not cuts_pitch(tool("16ER1.5ISO"), 1.0)


def test_bar_for_a_part_with_a_bore_is_drilled_before_the_boring_bar():
    p = plan(bushing(), "42x45+2")
    names = [op.name for op in p.operations]
    assert names.index("drill") < names.index("bore_rough")
    drill = p.operations[names.index("drill")]
    assert drill.tool.kind == "drill" and drill.start[0] == 0.0


# ---------------------------------------------------------------- interpreter

@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("shape,stock", [(shaft, "50x90+2"), (undercut, "40x70"),
                                         (grooved, "30x70"), (flange, "104x30+2"),
                                         (stud, "30x60+1"), (bushing, "42/16x45+2")])
def test_programs_run_in_the_interpreter(shape, stock, comp):
    prog = generate(shape(), stock, comp=comp, verify=False)
    assert prog.toolpath is not None and prog.toolpath.moves
    assert prog.text.startswith("%0001\n") and prog.text.rstrip().endswith("M30")
    assert "G41" not in prog.text and "G42" not in prog.text if comp == "cam" else True
    # the program ends at the tool-change point
    end = prog.toolpath.moves[-1].end
    assert end == pytest.approx(MACH.tool_change, abs=1e-6)


def test_tool_tables_parsed_once_per_file_version(tmp_path):
    """generate() parses a tool library once per process and file version (family workers
    share it across rows); an edited file is read again."""
    import os
    from hnc_cam.plan.api import _load_machine, _load_tools
    assert _load_tools(None) is _load_tools(None)
    assert _load_machine(None, _load_tools(None)) is _load_machine(None, _load_tools(None))
    src = (tmp_path / "tools.toml")
    from importlib import resources
    text = resources.files("hnc_cam").joinpath("data", "tools.toml").read_text("utf-8")
    src.write_text(text)
    a = _load_tools(src)
    assert _load_tools(str(src)) is a
    src.write_text(text.replace("depth = 1.5", "depth = 1.25"))
    os.utime(src, ns=(1, 1))
    b = _load_tools(src)
    assert b is not a and b.by_number(1).depth == 1.25 and a.by_number(1).depth == 1.5


def test_a_rest_roughing_zone_ends_where_it_starts_whatever_the_last_digit():
    """grooved_shaft at d2 37.5945 (the 0.4 mm above the arc groove's level is 37.9945 on the
    diameter, a tie the last bit decides): the rest-roughing zone's G71 type II profile
    starts and ends on that level written alike (one digit lower at its end would be a
    profile G71 refuses, and the program an interpreter alarm), and the part verifies."""
    import re
    from hnc_cam.plan.api import generate
    params = dict(d2="37.5945", length="81.14", d1="25.678", l1="29.708",
                  relief_width="4.036", relief_depth="0.809", relief_angle="28.898",
                  relief_radius="0.579", arc_z="54.624", arc_radius="5.086", arc_depth="1.149",
                  chamfer="1.016")
    prog = generate(Path(__file__).parent.parent / "parts" / "grooved_shaft.py", comp="control",
                    stock="40x101+2", params=params)
    assert prog.report is not None and prog.report.passed
    lines = prog.text.splitlines()
    zones = [i for i, ln in enumerate(lines) if re.search(r"\bG71\b.*\bE", ln)]
    assert zones
    for i in zones:
        p, q = (int(v) for v in re.search(r"P(\d+) Q(\d+)", lines[i]).groups())
        body = [ln for ln in lines if re.match(rf"N(\d+) ", ln)
                and p <= int(re.match(r"N(\d+)", ln).group(1)) <= q]
        xs = [float(m.group(1)) for ln in body for m in [re.search(r"X(-?[\d.]+)", ln)] if m]
        assert xs[-1] >= xs[0] - 1e-9
