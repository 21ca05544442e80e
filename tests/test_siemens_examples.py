"""The SINUMERIK 802 document's example programs (tests/data/siemens802, see its INDEX.md)
run through the 802 reader and executor, with their positions asserted. X of a position is a
radius (the toolpath's convention); the document writes diameters."""
from __future__ import annotations

import math
import pathlib

import pytest

from hnc_cam import nc
from hnc_cam.dialect import get

DATA = pathlib.Path(__file__).parent / "data" / "siemens802"


def run(name, start=(100.0, 150.0), **kw):
    p = DATA / name
    return nc.run(p.read_text(), dialect="siemens802", file=str(p), start=start, **kw)


def ends(tp, kind=None):
    return [(round(m.end[0], 3), round(m.end[1], 3)) for m in tp.moves if kind is None or m.kind == kind]


def near(p, q, tol=1e-3):
    return abs(p[0] - q[0]) <= tol and abs(p[1] - q[1]) <= tol


def has_cycle(name):
    try:
        return name in get("siemens802").cycle_table()
    except ImportError:
        return False


@pytest.mark.parametrize("name", ["g0_abs.mpf", "g0_inc.mpf"])
def test_g0_absolute_and_incremental_reach_x48_z_26(name):
    tp = run(name, start=(34.5, 5.0))  # P0: X69 Z5
    assert ends(tp)[-1] == (24.0, -26.0)
    assert all(m.kind == "rapid" for m in tp.moves)


@pytest.mark.parametrize("name", ["g1_abs.mpf", "g1_inc.mpf"])
def test_g1_absolute_and_incremental_reach_x48_z_37(name):
    tp = run(name)
    last = tp.moves[-1]
    assert last.kind == "line" and near(last.start, (19.5, 0.0)) and near(last.end, (24.0, -37.0))


@pytest.mark.parametrize("name,centre", [
    ("g2_centre.mpf", (51.92, -5.98)),        # I31.92 K-5.98 from X40 Z0
    ("g2_radius.mpf", None),                   # CR=34
    ("g2_angle_end.mpf", None),                # X Z AR=60
    ("g3_centre.mpf", (-0.95, -23.64)),        # I-20.95 K-23.64
    ("g3_radius.mpf", None),
    ("g3_angle_end.mpf", None),
])
def test_arc_forms_with_an_end_point_end_at_x60_z_29_94(name, centre):
    tp = run(name)
    arc = tp.moves[-1]
    assert arc.kind == "arc" and arc.cw == name.startswith("g2")
    assert near(arc.start, (20.0, 0.0)) and near(arc.end, (30.0, -29.94))
    r0 = math.dist(arc.start, arc.center)
    r1 = math.dist(arc.end, arc.center)
    assert abs(r0 - r1) < 0.01
    if centre is not None:
        assert near(arc.center, centre)
    if "radius" in name:
        assert r0 == pytest.approx(34.0)
    if "angle_end" in name:  # AR=60: the radius is the chord over 2 sin 30 deg
        chord = math.dist(arc.start, arc.end)
        assert r0 == pytest.approx(chord)


def test_g3_centre_and_angle_reaches_the_printed_end_point():
    arc = run("g3_angle_centre.mpf").moves[-1]
    assert arc.kind == "arc" and not arc.cw and near(arc.center, (-0.95, -23.64))
    assert near(arc.end, (30.0, -29.94), 0.03)  # the printed AR=60 is rounded (59.96 deg)


def test_g2_centre_and_angle_turns_sixty_degrees_from_the_start():
    arc = run("g2_angle_centre.mpf").moves[-1]
    assert arc.kind == "arc" and arc.cw and near(arc.center, (51.92, -5.98))
    a0 = math.atan2(arc.start[0] - 51.92, arc.start[1] + 5.98)
    a1 = math.atan2(arc.end[0] - 51.92, arc.end[1] + 5.98)
    assert math.degrees((a0 - a1) % (2 * math.pi)) == pytest.approx(60.0)
    # the document's printed AR=60 does not quite reach X60 Z-29.94 for G2 (see INDEX.md)
    assert near(arc.end, (30.781, -30.634))


def test_g5_through_the_intermediate_point():
    tp = run("g5.mpf")
    arc = tp.moves[-1]
    assert arc.kind == "arc" and near(arc.start, (10.0, 17.0)) and near(arc.end, (10.0, 57.0))
    assert near(arc.center, (-5.0, 37.0))  # the circle through X20 Z17, X40 Z37, X20 Z57
    assert arc.cw  # the intermediate point lies above the chord: clockwise in the ZX view


def test_g33_two_start_thread():
    tp = run("g33_two_start.mpf")
    threads = [m for m in tp.moves if m.kind == "thread"]
    assert len(threads) == 2
    for m, angle in zip(threads, (0.0, 180.0)):
        assert near(m.start, (25.0, 0.0)) and near(m.end, (25.0, -100.0))
        assert m.lead == 4.0 and m.angle == angle and m.spindle == 500.0
    assert ends(tp)[-1] == (27.0, -100.0)


def test_g4_dwells_seconds_and_revolutions():
    tp = run("g4.mpf")
    dwells = [m for m in tp.moves if m.kind == "dwell"]
    assert [round(m.duration, 6) for m in dwells] == [2.5, 6.0]  # 30 rev at 300 rev/min
    lines = [m for m in tp.moves if m.kind == "line"]
    assert all(m.feed == 200.0 and m.spindle == 300.0 for m in lines)  # F and S stay


def test_g74_reference_point_and_g75_fixed_point():
    tp = run("g74.mpf", start=(20.0, 30.0))
    assert ends(tp)[-1] == (100.0, 150.0)  # the machine's reference point (work = machine, G500)
    assert all(m.kind == "rapid" and m.op == "G74" for m in tp.moves)
    tp = run("g75.mpf", start=(20.0, 30.0))
    assert ends(tp)[-1] == (100.0, 150.0) and tp.moves[-1].op == "G75"


def test_g158_shifts_the_subprogram():
    tp = run("g158.mpf")
    lines = [m for m in tp.moves if m.kind == "line"]
    # L10 writes X20 Z0 then X30: shifted by X3 (radius) and Z5
    assert [(round(m.end[0], 3), round(m.end[1], 3)) for m in lines] == [(13.0, 5.0), (18.0, 5.0)]
    assert ends(tp)[-1] == (10.0, 10.0)  # after G158 alone: unshifted


def test_g25_g26_limit_the_spindle():
    tp = run("g25_g26.mpf")
    assert {m.spindle for m in tp.moves} == {700.0}  # S1000 above the G26 limit


def test_g70_inch_and_g71_metric():
    tp = run("g70_g71.mpf")
    e = ends(tp)
    assert (127.0, 762.0) in e and (508.0, 1270.0) in e  # X10 Z30, X40 Z50 inch
    assert e[-1] == (9.5, 17.3)


def test_g96_constant_cutting_speed_with_lims():
    tp = run("g96.mpf")
    cut = [m for m in tp.moves if m.kind == "line"]
    n40 = cut[0]
    assert near(n40.end, (16.0, -10.0)) and n40.feed > 0
    # N32 X40: the speed for the contour, 120 m/min at D40 (under LIMS=2500)
    assert tp.moves[-3].spindle == pytest.approx(1000 * 120 / (math.pi * 40))
    # N180 G97: the spindle keeps the speed it turned at when G96 ended (D32)
    assert cut[-1].spindle == pytest.approx(1000 * 120 / (math.pi * 32))


def test_g22_radius_g23_diameter():
    e = [p for p in ends(run("g22_g23.mpf")) if p not in ((40.0, 30.0), (24.0, 26.0), (22.0, 14.0))]
    # G23 X44 Z30, X48 Z25, Z10 and then G22 X22 Z30, X24 Z25, Z10: the same points (radius)
    assert e == [(22.0, 30.0), (24.0, 25.0), (24.0, 10.0)] * 2


@pytest.mark.skipif(not has_cycle("LCYC82"), reason="LCYC82 is not yet in the 802 cycle table")
def test_lcyc82_drills_to_75_and_returns_to_110():
    tp = run("lcyc82.mpf")
    cyc = [m for m in tp.moves if m.op == "LCYC82"]
    assert cyc and min(m.end[1] for m in cyc) == pytest.approx(75.0)
    assert any(m.kind == "dwell" and m.duration == pytest.approx(2.0) for m in cyc)
    assert near(cyc[-1].end, (0.0, 110.0))


@pytest.mark.skipif(not has_cycle("LCYC83"), reason="LCYC83 is not yet in the 802 cycle table")
def test_lcyc83_deep_hole_reaches_5():
    tp = run("lcyc83.mpf")
    cyc = [m for m in tp.moves if m.op == "LCYC83"]
    assert cyc and min(m.end[1] for m in cyc) == pytest.approx(5.0)
    assert near(cyc[-1].end, (0.0, 155.0))


@pytest.mark.skipif(not has_cycle("LCYC840"), reason="LCYC840 is not yet in the 802 cycle table")
def test_lcyc840_taps_to_15_with_lead_0_5():
    tp = run("lcyc840.mpf")
    thr = [m for m in tp.moves if m.kind == "thread"]
    assert thr and all(m.lead == 0.5 for m in thr)
    assert min(m.end[1] for m in thr) == pytest.approx(15.0)
    assert near(tp.moves[-1].end, (17.5, 60.0))
