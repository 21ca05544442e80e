"""Motion, modal state, feeds, spindle, tools and output of the interpreter (issue 2)."""
from __future__ import annotations

import json
import math

import pytest

from hnc_cam.nc import run
from hnc_cam.tooling import Machine, Register


def prog(*blocks: str) -> str:
    return "%1\n" + "\n".join(blocks) + "\nM30\n"


def pts(tp, kinds=None):
    """(kind, start dia, end dia) of the moves, X as diameter, rounded."""
    out = []
    for m in tp.moves:
        if kinds and m.kind not in kinds:
            continue
        out.append((m.kind, (round(2 * m.start[0], 6), round(m.start[1], 6)),
                    (round(2 * m.end[0], 6), round(m.end[1], 6))))
    return out


def end(tp):
    m = tp.moves[-1]
    return (round(2 * m.end[0], 6), round(m.end[1], 6))


# --- G00 / G01 ----------------------------------------------------------------------------

def test_g00_is_a_dog_leg_at_the_axis_rates():
    mach = Machine(rapid_x=4000.0, rapid_z=8000.0)
    tp = run(prog("G92 X0 Z0", "G00 X40 Z-100"), mach)
    # x radius 20 at 4000 mm/min -> 0.3 s; z 100 at 8000 mm/min -> 0.75 s: both move 0.3 s
    assert pts(tp) == [("rapid", (0, 0), (40, -40)), ("rapid", (40, -40), (40, -100))]
    assert tp.moves[0].duration == pytest.approx(0.3)
    assert tp.moves[1].duration == pytest.approx(0.45)
    assert tp.cycle_time_s == pytest.approx(0.75)
    assert all(m.feed is None for m in tp.moves)


def test_g00_single_axis_is_one_move():
    tp = run(prog("G92 X10 Z0", "G00 Z50"))
    assert pts(tp) == [("rapid", (10, 0), (10, 50))]


def test_g01_feed_and_time():
    tp = run(prog("G92 X0 Z0", "G01 X60 Z-40 F100"))
    (m,) = tp.moves
    assert m.kind == "line" and m.feed == 100
    assert m.duration == pytest.approx(50 / 100 * 60)  # radius 30, z 40 -> 50 mm
    assert tp.warnings == []


def test_feed_before_any_f_uses_default_and_warns():
    mach = Machine(default_feed=250.0)
    tp = run(prog("G92 X0 Z0", "G01 Z-10", "Z-20"), mach)
    assert [m.feed for m in tp.moves] == [250.0, 250.0]
    assert len(tp.warnings) == 1 and tp.warnings[0].line == 3
    assert "default feed" in tp.warnings[0].message


def test_u_w_and_x_z_mixed():
    tp = run(prog("G92 X0 Z0", "G01 X15 Z20 F100", "U30 Z40", "X25 W20"))
    assert [p[2] for p in pts(tp)] == [(15, 20), (45, 40), (25, 60)]


def test_g91_x_is_a_diameter_increment():
    tp = run(prog("G91 G01 X15 Z20 F100", "X30 Z20", "X-20 Z20", "X-25 Z-60"), start=(0, 0))
    assert [p[2] for p in pts(tp)] == [(15, 20), (45, 40), (25, 60), (0, 0)]


def test_g37_radius_programming():
    tp = run(prog("G92 X90 Z254", "G37 G01 X10 W-44 F100", "U15 Z204"))
    assert [p[2] for p in pts(tp)] == [(20, 210), (50, 204)]


def test_g20_inch_input():
    tp = run(prog("G92 X0 Z0", "G20 G01 X2 Z-1 F10"))
    assert end(tp) == (50.8, -25.4)
    assert tp.moves[0].feed == pytest.approx(254.0)


# --- arcs -----------------------------------------------------------------------------------

def test_g02_g03_with_r_match_the_manual_3310():
    tp = run(prog("G92 X0 Z0", "G01 F60 X0 Z0", "G03 U24 W-24 R15", "G02 X26 Z-31 R5"))
    a, b = tp.moves
    assert a.kind == "arc" and not a.cw and (2 * a.center[0], a.center[1]) == pytest.approx((0, -15))
    assert b.cw and (2 * b.center[0], b.center[1]) == pytest.approx((32, -27))
    assert a.duration == pytest.approx(a.segment().length / 60 * 60)


def test_negative_r_is_the_larger_arc():
    small = run(prog("G92 X0 Z0", "G02 X20 Z-10 R10 F100")).moves[0]
    large = run(prog("G92 X0 Z0", "G02 X20 Z-10 R-10 F100")).moves[0]
    assert abs(small.segment().sweep) < math.pi < abs(large.segment().sweep)


def test_ik_centre_is_incremental_radius_values_in_both_modes():
    for mode in ("G90", "G91"):
        target = "X20 Z-10" if mode == "G90" else "X20 Z-10"
        tp = run(prog("G92 X0 Z0", f"{mode} G03 {target} I0 K-10 F100"))
        m = tp.moves[0]
        assert m.center == pytest.approx((0.0, -10.0))
        assert m.end == pytest.approx((10.0, -10.0))


def test_r_wins_over_ik():
    tp = run(prog("G92 X0 Z0", "G02 X20 Z-10 R10 I99 K99 F100"))
    assert tp.moves[0].segment().radius == pytest.approx(10.0)


def test_full_circle_with_ik_is_two_half_arcs():
    tp = run(prog("G92 X20 Z0", "G02 X20 Z0 I0 K-5 F100"))
    assert [m.kind for m in tp.moves] == ["arc", "arc"]
    assert sum(m.segment().length for m in tp.moves) == pytest.approx(2 * math.pi * 5)


def test_radius_rounded_to_three_decimals_is_accepted_as_half_circle():
    tp = run(prog("G92 X0 Z0", "G02 X0 Z-10.001 R5 F100"))
    assert tp.moves[0].segment().radius == pytest.approx(5.0005, abs=1e-6)


# --- chamfer and round ------------------------------------------------------------------------

def test_chamfer_and_round_3307_geometry():
    tp = run(prog("G92 X0 Z0", "G01 X26 C3 F100", "W-22 R3", "U39 W-14 C3", "W-34"))
    k = pts(tp)
    assert k[0] == ("line", (0, 0), (20, 0))          # A -> B, 3 mm (radius) before the corner
    assert k[1] == ("line", (20, 0), (26, -3))        # 3x45 chamfer
    # the R3 round between the dia 26 line and the taper
    arc = tp.moves[3]
    assert arc.kind == "arc" and arc.cw
    assert arc.segment().radius == pytest.approx(3.0)
    assert tp.moves[2].end == pytest.approx(arc.start)
    # tangency: the centre is 3 mm from both lines
    assert abs(arc.center[0] - 13.0) == pytest.approx(3.0)
    assert end(tp) == (65, -70)


def test_round_tangent_points():
    # 90 deg corner: the tangent points are R from the corner on both lines
    tp = run(prog("G92 X0 Z0", "G01 Z-20 R5 F100", "X40"))
    k = pts(tp)
    assert k[0][2] == (0, -15)
    assert k[1][2] == (10, -20)
    assert k[2] == ("line", (10, -20), (40, -20))


def test_round_before_a_collinear_line_keeps_the_corner_blocks_line():
    # nothing to round between two collinear lines: both run whole, in their own blocks' feeds
    tp = run(prog("G92 X40 Z10", "G01 X20 Z0 F100", "Z-10 R2 F50", "Z-20 F80", "X30"))
    assert pts(tp) == [("line", (40, 10), (20, 0)), ("line", (20, 0), (20, -10)),
                       ("line", (20, -10), (20, -20)), ("line", (20, -20), (30, -20))]
    assert [m.feed for m in tp.moves] == [100, 50, 80, 80]
    assert [m.line for m in tp.moves] == [3, 4, 5, 6]


# --- dwell, coordinates ---------------------------------------------------------------------------

def test_g04_dwell_counts_time():
    tp = run(prog("G92 X10 Z0", "G04 P2.5"))
    (m,) = tp.moves
    assert m.kind == "dwell" and m.duration == 2.5 and tp.cycle_time_s == 2.5


def test_g28_g29_via_the_intermediate_point():
    mach = Machine(reference=(100.0, 150.0))
    tp = run(prog("G92 X50 Z100", "G28 X80 Z200", "G29 X40 Z250"), mach, start=(0, 0))
    ends = [p[2] for p in pts(tp)]
    # G92 X50 Z100 at machine 0,0: work = machine + (25, 100); reference (100, 150) -> dia 250, Z250
    assert (80, 200) in ends and (250, 250) in ends
    assert ends[-1] == (40, 250)
    i_ref = ends.index((250, 250))
    assert (80, 200) in ends[i_ref:]


def test_g29_without_g28_alarms():
    from hnc_cam.errors import NCError
    with pytest.raises(NCError, match="G29 without"):
        run(prog("G29 X40 Z250"))


def test_g54_g59_origins_and_g53():
    mach = Machine(work_offsets={"G54": (0.0, 0.0), "G55": (10.0, -100.0), "G56": (0.0, 0.0),
                                 "G57": (0.0, 0.0), "G58": (0.0, 0.0), "G59": (0.0, 0.0)})
    tp = run(prog("G54 G00 X40 Z30", "G55", "G00 X40 Z30", "G53 G00 X0 Z0"), mach)
    # in G55 the same program point is 10 mm (radius) up and 100 left in machine terms;
    # reported positions stay work coordinates of the active system
    e = [p[2] for p in pts(tp)]
    assert (40, 30) in e
    assert tp.moves[-1].end == pytest.approx((0 - 10.0, 0 + 100.0))  # machine 0,0 in G55 work coords


def test_g52_local_shift():
    tp = run(prog("G92 X0 Z0", "G52 Z-10", "G00 Z0"))
    # positions are reported in the active work system: the tool was at local Z+10
    assert tp.moves[-1].start == pytest.approx((0.0, 10.0))
    assert tp.moves[-1].end == pytest.approx((0.0, 0.0))


# --- spindle, feed per rev, G96 ---------------------------------------------------------------------

def test_g95_feed_per_rev_converted_with_rpm():
    tp = run(prog("G92 X0 Z0", "M03 S500", "G95 G01 Z-10 F0.2"))
    assert tp.moves[0].feed == pytest.approx(100.0)
    assert tp.moves[0].spindle == 500


def test_g96_resolved_per_move_and_clamped():
    mach = Machine(max_rpm=2000.0)
    tp = run(prog("G92 X100 Z0", "M03 S400", "G96 S100", "G95 G01 Z-10 F0.1", "G00 X0",
                  "G97 S300", "G01 Z-20 F50"), mach)
    a = tp.moves[0]  # at dia 100: 1000*100/(pi*100) = 318.3 rpm
    assert a.spindle == pytest.approx(1000 * 100 / (math.pi * 100))
    assert a.feed == pytest.approx(0.1 * a.spindle)
    rapid_to_axis = tp.moves[1]
    assert rapid_to_axis.spindle == 2000.0  # clamped at the axis
    assert tp.moves[-1].spindle == 300


def test_m_codes_before_and_after_motion():
    tp = run(prog("G92 X0 Z0", "G00 Z-5 M03 S600", "G00 Z-10 M05", "G00 Z-15 M07", "G00 Z-20 M09"))
    sp = [(m.spindle_dir, m.coolant) for m in tp.moves]
    assert sp == [(3, False), (3, False), (5, True), (5, True)]


def test_s_above_max_rpm_clamped_with_warning():
    tp = run(prog("G92 X0 Z0", "M03 S9000", "G00 Z-1"), Machine(max_rpm=3000.0))
    assert tp.moves[0].spindle == 3000.0
    assert any("spindle limit" in w.message for w in tp.warnings)


# --- tools ---------------------------------------------------------------------------------------------

def _mach_with_offsets():
    return Machine(registers={2: Register(number=2, x=4.0, z=-3.0, x_wear=0.2, z_wear=0.1,
                                          radius=0.4, tip=3)})


def test_t_word_with_matching_register_is_the_programmed_point():
    tp = run(prog("T0202", "G01 X50 Z100 F100"), _mach_with_offsets())
    assert tp.moves[0].end == pytest.approx((25.0, 100.0))
    assert (tp.moves[0].tool, tp.moves[0].register) == (2, 2)


def test_t_offset_cancel_shifts_the_controlled_point():
    tp = run(prog("T0202", "G01 X50 Z100 F100", "Z200", "X100 Z250 T0200"), _mach_with_offsets())
    last = tp.moves[-1]
    # register 02: x 4.2 (dia) -> 2.1 radius, z -2.9 are the tool's own displacement
    assert last.end == pytest.approx((50.0 + 2.1, 250.0 - 2.9))
    assert last.register == 0 and last.tool == 2


def test_unknown_register_is_a_sharp_point():
    tp = run(prog("T0909", "G01 X50 Z100 F100"), Machine())
    assert tp.moves[0].end == pytest.approx((25.0, 100.0))


def test_compensation_with_zero_radius_passes_through():
    tp = run(prog("T0505", "G00 X40 Z5", "G42 G01 X20 Z0 F100", "Z-20", "G40 G00 X40 Z5"),
             Machine(registers={5: Register(number=5, radius=0.0, tip=3)}))
    assert end(tp) == (40, 5)
    assert (20, -20) in [p[2] for p in pts(tp)]


# --- output ------------------------------------------------------------------------------------

def test_json_contract():
    tp = run(prog("G92 X40 Z5", "M03 S400", "G00 X0", "G01 Z0", "G03 U24 W-24 R15 F60"))
    d = json.loads(tp.dumps())
    assert set(d) == {"moves", "cycle_time_s", "warnings"}
    arc = d["moves"][-1]
    assert arc["type"] == "arc" and arc["cw"] is False
    assert arc["start"] == [0.0, 0.0] and arc["end"] == [24.0, -24.0]
    assert arc["center"] == [0.0, -15.0]
    assert arc["line"] == 6 and arc["tool"] == 0 and arc["feed"] == 60.0
    # fields added to the contract: register, spindle (rpm; G96 resolved), spindle_dir, op
    assert arc["register"] == 0 and arc["spindle"] == 400.0 and arc["spindle_dir"] == 3
    assert arc["op"] == "G03"
    r = d["moves"][0]
    assert r["type"] == "rapid" and r["feed"] is None and "center" not in r
    assert d["warnings"] == [{"line": 5, "message": tp.warnings[0].message}]


def test_summary_line():
    tp = run(prog("G92 X40 Z5", "G01 X0 F100"), file="p.nc")
    s = tp.summary()
    assert s.startswith("p.nc: 3 blocks executed, 1 moves")
    assert "X 0.000..40.000 (dia)" in s and "cycle time" in s


def test_lines_are_one_based_file_lines():
    text = "(comment)\n\n%5\nG92 X0 Z0\n\nG01 Z-1 F10\nM30\n"
    tp = run(text)
    assert tp.moves[0].line == 6


# --- second-wave audit: work systems, tools, inch, cycle time, move fields -----------------------

def _mach_wcs():
    off = {f"G{n}": (0.0, 0.0) for n in range(54, 60)}
    off.update({"G54": (20.0, -300.0), "G55": (5.0, -250.0)})  # (x radius, z) machine coords
    return Machine(reference=(100.0, 150.0), work_offsets=off)


def test_nonzero_g54_from_the_reference_is_continuous_in_work_coordinates():
    tp = run(prog("G00 X40 Z10", "G01 Z-20 F100", "G00 X80 Z50"), _mach_wcs(), start="reference")
    # the reference (machine 100, 150) seen from G54 (20, -300): work X dia 160, Z 450
    assert pts(tp)[0][1] == (160.0, 450.0)
    assert ((40.0, 10.0) in [p[2] for p in pts(tp)]) and end(tp) == (80.0, 50.0)
    for a, b in zip(tp.moves, tp.moves[1:]):
        assert math.dist(a.end, b.start) < 1e-9


def test_switching_work_system_keeps_the_machine_position():
    tp = run(prog("G00 X40 Z10", "G55", "G00 X40 Z10", "G53 G00 X0 Z0", "G54 G00 X0 Z0"),
             _mach_wcs(), start="reference")
    after = [m for m in tp.moves if m.line == 4]
    # the tool did not move at G55: machine (40, -290) is work (35, -40) in G55 (radius, z)
    assert after[0].start == pytest.approx((20.0 + 20.0 - 5.0, 10.0 - 300.0 + 250.0))
    assert after[-1].end == pytest.approx((20.0, 10.0))
    g53 = [m for m in tp.moves if m.line == 5]
    assert g53[-1].end == pytest.approx((-5.0, 250.0))  # machine 0,0 in G55 work coordinates
    g54 = [m for m in tp.moves if m.line == 6]
    assert g54[0].start == pytest.approx((-20.0, 300.0)) and g54[-1].end == pytest.approx((0.0, 0.0))


def test_g52_local_shift_on_top_of_a_nonzero_g54():
    tp = run(prog("G52 X10 Z-5", "G00 X20 Z0", "G52 X0 Z0", "G00 X20 Z0"), _mach_wcs(), start="reference")
    l3 = [m for m in tp.moves if m.line == 3]
    assert l3[-1].end == pytest.approx((10.0, 0.0))
    # cancelling the shift: the same machine point is now (10 + 5, 0 - 5) in G54
    l5 = [m for m in tp.moves if m.line == 5]
    assert l5[0].start == pytest.approx((15.0, -5.0)) and l5[-1].end == pytest.approx((10.0, 0.0))


def _two_tools():
    return Machine(registers={
        1: Register(number=1, x=0.0, z=0.0, radius=0.4, tip=3),
        2: Register(number=2, x=-12.0, z=25.0, x_wear=0.2, z_wear=-0.1, radius=0.8, tip=2)})


def test_t_change_mid_program_and_a_foreign_register():
    tp = run(prog("T0101", "G00 X50 Z5", "G01 Z-10 F100", "T0202", "G00 X30 Z5", "G01 Z-5",
                  "T0201", "G01 Z-8"), _two_tools())
    by = {m.line: m for m in tp.moves}
    assert by[4].end == pytest.approx((25.0, -10.0)) and (by[4].tool, by[4].register) == (1, 1)
    # each tool with its own register: the controlled point is the programmed point
    assert by[7].end == pytest.approx((15.0, -5.0)) and (by[7].tool, by[7].register) == (2, 2)
    # tool 2 with register 01: displaced by register 02 minus register 01
    # (x (-12 + 0.2) / 2 = -5.9 radius, z 25 - 0.1 = 24.9)
    assert by[9].start == pytest.approx((15.0 - 5.9, -5.0 + 24.9))
    assert by[9].end == pytest.approx((15.0 - 5.9, -8.0 + 24.9)) and by[9].register == 1
    j = tp.to_json()["moves"]
    assert [m["tool"] for m in j] == [m.tool for m in tp.moves]


def test_g20_converts_every_length_and_feed_to_mm():
    tp = run(prog("G92 X0 Z0", "G20", "G01 X1 Z-1 F10", "G02 X2 Z-1.5 R0.5", "G03 X3 Z-2 I0 K-0.5",
                  "G01 X4 Z-3 C0.1", "X5", "M03 S100 G95 G01 Z-4 F0.01", "G04 P1", "G21 G94 G01 Z-150"))
    arcs = [m for m in tp.moves if m.kind == "arc"]
    # G02 from (r 12.7, Z-25.4) to (r 25.4, Z-38.1) with R0.5 in: clockwise about (25.4, -25.4)
    assert arcs[0].center == pytest.approx((25.4, -25.4)) and arcs[0].end == pytest.approx((25.4, -38.1))
    assert arcs[1].center == pytest.approx((25.4, -50.8)) and arcs[1].end == pytest.approx((38.1, -50.8))
    assert all(m.feed == pytest.approx(254.0) for m in tp.moves[:3])
    chamfer = [m for m in tp.moves if m.line == 7]
    corner = (4 * 25.4 / 2, -3 * 25.4)  # C0.1 in: 2.54 mm from the corner along both lines
    assert math.dist(chamfer[-1].start, corner) == pytest.approx(2.54)
    assert math.dist(chamfer[-1].end, corner) == pytest.approx(2.54)
    per_rev = [m for m in tp.moves if m.line == 9][0]
    assert per_rev.feed == pytest.approx(0.01 * 25.4 * 100) and per_rev.end[1] == pytest.approx(-101.6)
    assert tp.moves[-1].end == pytest.approx((63.5, -150.0))  # back in mm


def test_cycle_time_is_feeds_at_f_rapids_per_axis_and_dwells():
    mach = Machine(rapid_x=3000.0, rapid_z=6000.0)
    tp = run(prog("G92 X100 Z50", "G00 X40 Z2", "G01 Z-30 F150", "G02 X60 Z-40 R10 F75", "G04 P2.5",
                  "G00 X100 Z50"), mach)
    # rapids: (50, 50) -> (20, 2) and (30, -40) -> (50, 50), radius X; the slower axis decides
    rapid = max(30 / 3000, 48 / 6000) * 60 + max(20 / 3000, 90 / 6000) * 60
    arc = math.pi / 2 * 10  # quarter circle
    expect = rapid + 32 / 150 * 60 + arc / 75 * 60 + 2.5
    assert tp.cycle_time_s == pytest.approx(expect)
    assert json.loads(tp.dumps())["cycle_time_s"] == pytest.approx(expect, abs=1e-6)


def test_move_fields_spindle_tool_source_line():
    tp = run("; set-up comment\n%1\nT0101\nG92 X100 Z50\nM03 S500\nG00 X40 Z2\nG01 Z-30 F100 M05\n"
             "M04 S200\nG96 S100 G95 G01 X50 Z-35 F0.2\nM30\n", _two_tools())
    a, b, c, d = tp.moves
    assert [m.line for m in tp.moves] == [6, 6, 7, 9]
    assert (a.kind, a.spindle, a.spindle_dir, a.feed) == ("rapid", 500, 3, None)
    assert (c.kind, c.spindle, c.spindle_dir, c.feed) == ("line", 500, 3, 100)  # M05 acts after
    rpm = 1000 * 100 / (2 * math.pi * 22.5)  # G96 at the move's mid radius
    assert d.spindle == pytest.approx(rpm) and d.spindle_dir == 4 and d.feed == pytest.approx(0.2 * rpm)
    assert {m.tool for m in tp.moves} == {1} and {m.register for m in tp.moves} == {1}


def test_m00_stops_after_the_move_and_m06_is_accepted():
    tp = run(prog("G92 X0 Z0", "M03 S300", "G01 Z-5 F100 M00", "M06 T0101", "G00 X20 M05", "G00 Z5"))
    assert [m.line for m in tp.moves] == [4, 6, 7]
    assert [w for w in tp.warnings if "M00" in w.message][0].line == 4
    assert [m.spindle_dir for m in tp.moves] == [3, 3, 5]  # M05 acts after its block's move
    assert tp.moves[1].tool == 1
    from hnc_cam.errors import NCError
    with pytest.raises(NCError, match="M00 and M30 in one block"):
        run(prog("G92 X0 Z0", "M00 M30"))


def test_g97_without_s_returns_to_the_speed_before_g96():
    """Manual 3.3.6: G97 without S keeps the spindle speed in force before G96."""
    tp = run(prog("G92 X60 Z0", "M03 S450", "G96 S120 G01 Z-5 F100", "G97 G01 Z-10", "G96 G01 Z-15"))
    a, b, c = tp.moves
    assert a.spindle == pytest.approx(1000 * 120 / (math.pi * 60))
    assert b.spindle == 450
    assert c.spindle == pytest.approx(a.spindle)  # G96 without S: the last surface speed


def test_g96_g95_facing_time_integrates_the_changing_speed():
    """Facing X100 -> X0 at 100 m/min, 0.2 mm/rev, clamp 2000 rpm: the feed rises as the
    radius falls until the clamp radius rc; time = pi (R^2 - rc^2) / (1000 vc f) + rc / (nmax f)."""
    vc, f, nmax = 100.0, 0.2, 2000.0
    tp = run(prog("G92 X100 Z0", "M03 S500", "G96 S100 G95 G01 X0 F0.2"), Machine(max_rpm=nmax))
    rc = 1000 * vc / (2 * math.pi * nmax)
    minutes = math.pi * (50.0 ** 2 - rc ** 2) / (1000 * vc * f) + rc / (nmax * f)
    assert tp.cycle_time_s == pytest.approx(minutes * 60, rel=2e-3)
    # a G96 + G95 arc: quarter circle R20 from X40 Z0 up to X80 Z-20 about (X80, Z0) (radius
    # 20 -> 40), no clamp: time = integral of 2 pi x ds / (1000 vc f)
    tp = run(prog("G92 X40 Z0", "M03 S500", "G96 S100 G95 G02 X80 Z-20 R20 F0.2"))
    # x(a) = 40 - 20 cos(a), ds = 20 da, a in 0..pi/2: integral = 20 (40 pi/2 - 20)
    minutes = 2 * math.pi * 20 * (40 * math.pi / 2 - 20) / (1000 * vc * f)
    assert tp.cycle_time_s == pytest.approx(minutes * 60, rel=1e-4)
