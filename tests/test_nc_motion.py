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
    tp = run(prog("G91 G01 X15 Z20 F100", "X30 Z20", "X-20 Z20", "X-25 Z-60"))
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


# --- dwell, coordinates ---------------------------------------------------------------------------

def test_g04_dwell_counts_time():
    tp = run(prog("G92 X10 Z0", "G04 P2.5"))
    (m,) = tp.moves
    assert m.kind == "dwell" and m.duration == 2.5 and tp.cycle_time_s == 2.5


def test_g28_g29_via_the_intermediate_point():
    mach = Machine(reference=(100.0, 150.0))
    tp = run(prog("G92 X50 Z100", "G28 X80 Z200", "G29 X40 Z250"), mach)
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
