"""G80, G81, G82, G32 and G76 (hnc_cam.nc.cycles_simple).

The unit tests drive ``execute`` through a small fake of the interpreter's CycleContext and
check every leg (type, end point, lead, spindle angle) against the figures of the manual
(figs. 3.3.15–3.3.23, 3.3.36–3.3.38). The end-to-end tests at the bottom run the manual's
example programs through the interpreter when it is available.
"""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hnc_cam.errors import NCError
from hnc_cam.nc import cycles_simple
from hnc_cam.nc.cycles_simple import execute, g76_depths, start_angles

from cyclefake import FakeCycleContext as FakeCtx


def run(code, words, pos, **kw) -> FakeCtx:
    ctx = FakeCtx(code, words, pos, **kw)
    execute(code, ctx)
    return ctx


def approx_path(moves, expected):
    """Compare recorded legs with [(kind, (x, z)[, lead, angle, thread_angle])]."""
    assert len(moves) == len(expected), moves
    for got, exp in zip(moves, expected):
        assert got[0] == exp[0], (got, exp)
        assert got[1] == pytest.approx(exp[1], abs=1e-9), (got, exp)
        if len(exp) > 2:
            assert got[2:] == pytest.approx(exp[2:], abs=1e-9), (got, exp)


def alarm(code, words, pos=(20.0, 5.0), match="", **kw):
    with pytest.raises(NCError, match=match):
        run(code, words, pos, **kw)


# ----------------------------------------------------------------------------- G80


def test_g80_straight_absolute_fig_3_3_15():
    ctx = run(80, {"X": 30, "Z": -20, "F": 100}, (20.0, 2.0))  # A = X40 Z2
    approx_path(ctx.moves, [("rapid", (15, 2)), ("feed", (15, -20)),
                            ("feed", (20, -20)), ("rapid", (20, 2))])
    assert ctx.pos == (20, 2)


def test_g80_taper_incremental_3317_first_pass():
    # A = X40 Z3; G91 G80 X-10 Z-33 I-5.5: C = X30 Z-30, B = radius 15 - 5.5 at Z3
    ctx = run(80, {"X": -10, "Z": -33, "I": -5.5, "F": 100}, (20.0, 3.0), incremental=True)
    approx_path(ctx.moves, [("rapid", (9.5, 3)), ("feed", (15, -30)),
                            ("feed", (20, -30)), ("rapid", (20, 3))])


def test_g80_radius_mode_and_inside():
    # G37: X words are radii; a bore (C above the axis, A inside): same leg order
    ctx = run(80, {"X": 12, "Z": -15, "I": 1}, (8.0, 2.0), diameter_mode=False)
    approx_path(ctx.moves, [("rapid", (13, 2)), ("feed", (12, -15)),
                            ("feed", (8, -15)), ("rapid", (8, 2))])


def test_g80_alarms():
    alarm(80, {"Z": -20}, match="missing word X")
    alarm(80, {"X": 30}, match="missing word Z")
    alarm(80, {"X": 30, "W": -20}, match="incremental W")
    alarm(80, {"U": -2, "Z": -20, "X": 30}, match="incremental U")


# ----------------------------------------------------------------------------- G81


def test_g81_face_fig_3_3_18():
    ctx = run(81, {"X": 0, "Z": 1.5, "F": 100}, (30.0, 5.0))  # 3346 N5, A = X60 Z5
    approx_path(ctx.moves, [("rapid", (30, 1.5)), ("feed", (0, 1.5)),
                            ("feed", (0, 5)), ("rapid", (30, 5))])


def test_g81_taper_3320_last_pass_matches_the_figure():
    # A = X60 Z45; X25 Z25.5 K-3.5: B = (radius 30, Z22), C = (12.5, 25.5)
    ctx = run(81, {"X": 25, "Z": 25.5, "K": -3.5, "F": 100}, (30.0, 45.0))
    approx_path(ctx.moves, [("rapid", (30, 22)), ("feed", (12.5, 25.5)),
                            ("feed", (12.5, 45)), ("rapid", (30, 45))])
    # the cone passes dia 55 at Z22.5 (fig. 3.3.20: "3 mm lower" than Z25.5)
    (_, b), (_, c) = ctx.moves[0], ctx.moves[1]
    z_at_55 = b[1] + (c[1] - b[1]) * (b[0] - 27.5) / (b[0] - c[0])
    assert z_at_55 == pytest.approx(22.5)


def test_g81_incremental():
    ctx = run(81, {"X": -50, "Z": -4, "K": -1}, (30.0, 5.0), incremental=True)
    approx_path(ctx.moves, [("rapid", (30, 0)), ("feed", (5, 1)),
                            ("feed", (5, 5)), ("rapid", (30, 5))])


def test_g81_refuses_u():
    alarm(81, {"X": 0, "Z": 0, "U": 1}, match="incremental U")


# ----------------------------------------------------------------------------- G82


def test_g82_straight_single_start():
    ctx = run(82, {"X": 29.2, "Z": 18.5, "F": 3, "P": 45}, (17.5, 104.0))
    approx_path(ctx.moves, [("rapid", (14.6, 104)), ("thread", (14.6, 18.5), 3, 45, 60),
                            ("rapid", (17.5, 18.5)), ("rapid", (17.5, 104))])


def test_g82_multi_start_3323():
    # N3 G82 X29.2 Z18.5 C2 P180 F3 from A = X35 Z104: the loop twice, angles 0 and 180
    ctx = run(82, {"X": 29.2, "Z": 18.5, "C": 2, "P": 180, "F": 3}, (17.5, 104.0))
    one = [("rapid", (14.6, 104)), None, ("rapid", (17.5, 18.5)), ("rapid", (17.5, 104))]
    exp = []
    for ang in (0, 180):
        exp += [one[0], ("thread", (14.6, 18.5), 3, ang, 60), one[2], one[3]]
    approx_path(ctx.moves, exp)


def test_g82_runout_and_taper_3346():
    # N38 G82 X19.3 Z-20 R-3 E1 C2 P120 F3 from A = X30 Z5
    ctx = run(82, {"X": 19.3, "Z": -20, "R": -3, "E": 1, "C": 2, "P": 120, "F": 3}, (15.0, 5.0))
    exp = []
    for ang in (0, 120):
        exp += [("rapid", (9.65, 5)), ("thread", (9.65, -20), 3, ang, 60),
                ("thread", (10.65, -23), 3, ang, 60), ("rapid", (15, -23)), ("rapid", (15, 5))]
    approx_path(ctx.moves, exp)
    assert not ctx.warnings
    # taper, G91: C = A + (-5, -30) radius, B = C.x + I
    ctx = run(82, {"X": -10, "Z": -30, "I": -1, "F": 2}, (15.0, 5.0), incremental=True)
    approx_path(ctx.moves, [("rapid", (9, 5)), ("thread", (10, -25), 2, 0, 60),
                            ("rapid", (15, -25)), ("rapid", (15, 5))])


def test_g82_inward_runout_warns():
    ctx = run(82, {"X": 19.3, "Z": -20, "E": -1, "F": 1}, (15.0, 5.0))
    assert ctx.warnings and "into the work" in ctx.warnings[0]


def test_g82_multi_start_without_p_warns_and_follows_the_macro():
    ctx = run(82, {"X": 19.3, "Z": -20, "C": 3, "F": 3}, (15.0, 5.0))
    assert [m[3] for m in ctx.moves if m[0] == "thread"] == [0, 0, 0]
    assert "P120" in ctx.warnings[0]


def test_start_angles():
    assert start_angles(0, 30) == [30]
    assert start_angles(1, 400) == [40]
    assert start_angles(4, 90) == [0, 90, 180, 270]
    assert start_angles(3, 180) == [0, 180, 0]


def test_g82_alarms():
    alarm(82, {"X": 19, "Z": -20}, match="missing word F")
    alarm(82, {"X": 19, "Z": -20, "F": 0}, match="lead 0")
    alarm(82, {"X": 19, "Z": -20, "F": -1}, match="negative")
    alarm(82, {"X": 19, "F": 1}, match="missing word Z")
    alarm(82, {"X": 19, "Z": -20, "F": 1, "C": 1.5}, match="whole number")
    alarm(82, {"X": 19, "Z": -20, "F": 1, "C": 100}, match="whole number")
    alarm(82, {"X": 19, "Z": -20, "F": 1, "W": 2}, match="incremental W")
    alarm(82, {"X": 19, "Z": 5, "F": 1}, pos=(15.0, 5.0), match="no length")


# ----------------------------------------------------------------------------- G32


def test_g32_straight_3312_n4():
    # N3 G00 X29.2 Z101.5; N4 G32 Z19 F1.5
    ctx = run(32, {"Z": 19, "F": 1.5}, (14.6, 101.5))
    approx_path(ctx.moves, [("thread", (14.6, 19), 1.5, 0, 60)])


def test_g32_incremental_u_w_3312_n16():
    # N15 U-11.96 from X40 -> X28.04; N16 G32 W-82.5 F1.5
    ctx = run(32, {"W": -82.5, "F": 1.5}, (14.02, 101.5))
    approx_path(ctx.moves, [("thread", (14.02, 19), 1.5, 0, 60)])
    ctx = run(32, {"U": -1, "W": -10, "F": 2, "P": 90}, (15.0, 0.0))
    approx_path(ctx.moves, [("thread", (14.5, -10), 2, 90, 60)])


def test_g32_taper_face_runout_and_g91():
    ctx = run(32, {"X": 20, "Z": -30, "R": -2, "E": 1.5, "F": 2, "P": 370}, (9.0, 2.0))
    approx_path(ctx.moves, [("thread", (10, -30), 2, 10, 60), ("thread", (11.5, -32), 2, 10, 60)])
    ctx = run(32, {"X": 10, "F": 1}, (25.0, 0.0))  # face thread
    approx_path(ctx.moves, [("thread", (5, 0), 1, 0, 60)])
    ctx = run(32, {"X": -2, "Z": -20, "F": 1}, (10.0, 0.0), incremental=True)
    approx_path(ctx.moves, [("thread", (9, -20), 1, 0, 60)])
    ctx = run(32, {"X": 10, "Z": -20, "F": 1}, (10.0, 0.0), diameter_mode=False)
    approx_path(ctx.moves, [("thread", (10, -20), 1, 0, 60)])


def test_g32_alarms():
    alarm(32, {"F": 1}, match="missing end point")
    alarm(32, {"Z": -20}, match="missing word F")
    alarm(32, {"Z": -20, "F": 0}, match="lead 0")
    alarm(32, {"X": 20, "U": 1, "Z": -20, "F": 1}, match="both X and U")
    alarm(32, {"Z": 5, "F": 1}, pos=(10.0, 5.0), match="no length")
    alarm(32, {"Z": -20, "C": 1, "F": 1}, match="chamfer C")


# ----------------------------------------------------------------------------- G76

G3338 = {"C": 2, "R": -3, "E": 1.3, "A": 60, "X": 58.15, "Z": -24, "I": -0.94, "K": 1.299,
         "U": 0.1, "V": 0.1, "Q": 0.9, "F": 2}


def test_g76_depth_rule():
    # sqrt rule: Q1, K10, no allowance: 1, 1.414, 1.732, 2, ... until K, then K finishing
    dep = g76_depths(10, 0, 1, 0, 1)
    rough = [t for t, f in dep if not f]
    assert rough == pytest.approx([math.sqrt(n) for n in range(1, 100)])
    assert dep[-1] == (10, True) and sum(f for _, f in dep) == 1
    # Δdmin floor: increments never below V once the sqrt increments shrink
    dep = g76_depths(3, 0.1, 0.5, 0.2, 2)
    rough = [t for t, f in dep if not f]
    # 0.5·√3 - 0.5·√2 = 0.159 < V: the third pass is floored to 0.5·√2 + 0.2
    assert rough[:3] == pytest.approx([0.5, 0.5 * math.sqrt(2), 0.5 * math.sqrt(2) + 0.2])
    steps = [b - a for a, b in zip(rough, rough[1:])]
    assert all(s >= 0.2 - 1e-12 for s in steps[:-1])
    assert rough[-1] == pytest.approx(2.9)  # the last roughing pass lies on K - d
    assert [t for t, f in dep if f] == [3, 3]
    # C0 is read as one finishing pass
    assert [t for t, f in g76_depths(1, 0, 0.3, 0, 0) if f] == [1]


@settings(max_examples=200, deadline=None)
@given(k=st.floats(0.2, 5), dfrac=st.floats(0, 0.5), qfrac=st.floats(0.04, 1.5),
       ddmin=st.floats(0, 0.5), c=st.integers(0, 5))
def test_g76_depth_properties(k, dfrac, qfrac, ddmin, c):
    d, dd = k * dfrac, k * qfrac
    dep = g76_depths(k, d, dd, ddmin, c)
    depths = [t for t, _ in dep]
    assert all(b >= a - 1e-12 for a, b in zip(depths, depths[1:]))  # never shallower
    rough = [t for t, f in dep if not f]
    assert all(t <= k - d + 1e-9 for t in rough)
    assert rough and rough[0] == pytest.approx(min(dd, k - d)) or not rough
    if d > 1e-9:
        assert rough[-1] == pytest.approx(k - d)
    for n, t in enumerate(rough[:-1], start=1):
        assert t >= dd * math.sqrt(n) - 1e-9  # at least the sqrt depth (the floor only adds)
    assert [t for t, f in dep if f] == [k] * max(c, 1)


def test_g76_3338_passes():
    # N9 G00 X90 Z4; N10 G76 C2 R-3 E1.3 A60 X58.15 Z-24 I-0.94 K1.299 U0.1 V0.1 Q0.9 F2
    a = (45.0, 4.0)
    ctx = run(76, G3338, a)
    threads = [m for m in ctx.moves if m[0] == "thread"]
    # main legs (odd ones are the run-outs)
    mains, runs = threads[0::2], threads[1::2]
    depths = [0.9, 1.199, 1.299, 1.299]  # Δd·√1; √2·0.9 = 1.27 > K-d -> K-d; then C2 at K
    assert len(mains) == len(runs) == 4
    tan30 = math.tan(math.radians(30))
    root = 58.15 / 2
    for m, r, t in zip(mains, runs, depths):
        h = -t * tan30  # cutting toward -Z: the infeed shifts toward -Z
        assert m[1] == pytest.approx((root + 1.299 - t, -24 + h))
        assert m[2:] == pytest.approx((2, 0, 60))
        assert r[1] == pytest.approx((root + 1.299 - t + 1.3, -24 + h - 3))
    # the pass sequence of the macro: A -> (A.x - t, A.z + h) -> B -> C -> run-out -> A
    t, h = 0.9, -0.9 * tan30
    approx_path(ctx.moves[:5], [("rapid", (45 - t, 4 + h)), ("rapid", (root + 1.299 - t - 0.94, 4 + h)),
                                ("thread", (root + 1.299 - t, -24 + h), 2, 0, 60),
                                ("thread", (root + 1.299 - t + 1.3, -24 + h - 3), 2, 0, 60),
                                ("rapid", a)])
    assert ctx.moves[-1] == ("rapid", a)
    assert not ctx.warnings


def test_g76_single_flank_infeed():
    # successive thread starts lie on a line at A/2 from the radial direction
    ctx = run(76, {**G3338, "Q": 0.2, "V": 0.05, "A": 55}, (45.0, 4.0))
    mains = [m[1] for m in ctx.moves if m[0] == "thread"][0::2]
    for p, q in zip(mains, mains[1:]):
        dx, dz = q[0] - p[0], q[1] - p[1]
        if abs(dx) > 1e-12:
            assert abs(dz / dx) == pytest.approx(math.tan(math.radians(27.5)))
    ctx = run(76, {**G3338, "A": 0}, (45.0, 4.0))  # radial infeed
    assert {round(m[1][1], 9) for m in ctx.moves if m[0] == "thread"} <= {-24.0, -27.0}


def test_g76_inside_thread_toward_plus_z_incremental_with_start_angle():
    # a bore thread cut away from the chuck, G91: C = A + (X+4 dia, Z+20)
    words = {"A": 60, "X": 4, "Z": 20, "K": 0.6, "U": 0.05, "V": 0.05, "Q": 0.3, "F": 1,
             "P": 240, "R": 1}
    a = (8.0, -25.0)
    ctx = run(76, words, a, incremental=True)
    c = (10.0, -5.0)
    mains = [m for m in ctx.moves if m[0] == "thread"][0::2]
    runs = [m for m in ctx.moves if m[0] == "thread"][1::2]
    last = mains[-1]
    assert last[1] == pytest.approx((c[0], c[1] + 0.6 * math.tan(math.radians(30))))
    assert runs[-1][1] == pytest.approx((c[0] - 0.6, last[1][1] + 1))  # default E = K outward (-X)
    assert {m[3] for m in mains} == {240}
    first = mains[0]
    assert first[1][0] == pytest.approx(c[0] - 0.6 + 0.3)  # crest (C.x - K) + Δd
    assert not ctx.warnings


def test_g76_alarms():
    alarm(76, {**G3338, "A": 45}, match="angle A45")
    for letter in "AXZKUVQF":
        w = dict(G3338)
        del w[letter]
        alarm(76, w, pos=(45.0, 4.0), match=f"missing word {letter}")
    alarm(76, {**G3338, "Q": 0}, pos=(45.0, 4.0), match="Q0")
    alarm(76, {**G3338, "Q": -0.2}, pos=(45.0, 4.0), match="must be > 0")
    alarm(76, {**G3338, "F": 0}, pos=(45.0, 4.0), match="lead 0")
    alarm(76, {**G3338, "W": -3}, pos=(45.0, 4.0), match="incremental W")
    alarm(76, {**G3338, "U": 1.3}, pos=(45.0, 4.0), match="allowance")
    alarm(76, {**G3338, "K": 0}, pos=(45.0, 4.0), match="height")
    alarm(76, {**G3338, "C": 120}, pos=(45.0, 4.0), match="whole number")
    alarm(76, {**G3338, "Q": 0.001, "V": 0}, pos=(45.0, 4.0), match="more than 1000 passes")
    alarm(76, G3338, pos=(45.0, -24.0), match="no length")


def test_g76_start_inside_crest_warns():
    ctx = run(76, G3338, (29.2, 4.0))  # crest at B: 29.075 - 0.94 + 1.299
    assert any("inside the thread crest" in w for w in ctx.warnings)


def test_dispatch_through_cycles_module():
    from hnc_cam.nc import cycles
    ctx = FakeCtx(80, {"X": 30, "Z": -20}, (20.0, 2.0))
    cycles.execute(80, ctx)
    assert len(ctx.moves) == 4
    assert cycles_simple.THREAD_ANGLES == (80, 60, 55, 30, 29, 0)


# ----------------------------------------------------------------------------- end to end
# The manual's examples through the interpreter (hnc_cam.nc.run); positions in the
# assertions are diameters, as the programs and their comments give them.

def _interp():
    return pytest.importorskip("hnc_cam.nc.interp", reason="the interpreter core is not there yet")


def _moves(path, op=None, **kw):
    interp = _interp()
    tp = interp.run(path.read_text(), file=str(path), **kw)
    return tp, [m for m in tp.moves if op is None or m.op == op]


def _dia(p):
    return (round(2 * p[0], 6), round(p[1], 6))


def _threads(moves):
    return [m for m in moves if m.kind == "thread"]


def test_3317_g80_legs_reach_the_commented_diameters(manual):
    # the tool is assumed at A = X40 Z3 (header); each cycle cuts 3 mm more on diameter
    tp, ms = _moves(manual("3317.nc"), "G80", start=(20.0, 3.0))
    cuts = [m for m in ms if m.kind == "line"]
    b_to_c, c_to_d = cuts[0::2], cuts[1::2]
    assert [_dia(m.start) for m in b_to_c] == [(19.0, 3.0), (16.0, 3.0), (13.0, 3.0)]
    assert [_dia(m.end) for m in b_to_c] == [(30.0, -30.0), (27.0, -30.0), (24.0, -30.0)]
    assert all(_dia(m.end) == (40.0, -30.0) for m in c_to_d)
    ends = [m.end[0] * 2 for m in b_to_c]
    assert [a - b for a, b in zip(ends, ends[1:])] == pytest.approx([3, 3])
    # last pass: the finished taper from dia 14 at Z0 to dia 24 at Z-30 lies on B->C
    last = b_to_c[-1]
    x_at_0 = last.start[0] + (last.end[0] - last.start[0]) * (0 - last.start[1]) / (last.end[1] - last.start[1])
    assert 2 * x_at_0 == pytest.approx(14.0)
    assert all(m.kind == "rapid" for m in ms if m not in cuts)
    assert all(m.feed == pytest.approx(100) for m in cuts)  # F100 kept by the modal cycle
    assert _dia(tp.moves[-1].end) == (40.0, 3.0)


def test_3320_g81_legs_reach_the_commented_depths(manual):
    tp, ms = _moves(manual("3320.nc"), "G81")
    cuts = [m for m in ms if m.kind == "line"]
    b_to_c = cuts[0::2]
    assert [_dia(m.end) for m in b_to_c] == [(25.0, 31.5), (25.0, 29.5), (25.0, 27.5), (25.0, 25.5)]
    assert [_dia(m.start) for m in b_to_c] == [(60.0, 28.0), (60.0, 26.0), (60.0, 24.0), (60.0, 22.0)]
    assert all(_dia(m.end) == (25.0, 45.0) for m in cuts[1::2])  # C->D feed back to Z of A
    assert _dia(ms[-1].end) == (60.0, 45.0)
    # fig. 3.3.20: the last cone passes dia 55 at Z22.5 (3 below the Z25.5 shoulder)
    b, c = b_to_c[-1].start, b_to_c[-1].end
    z55 = b[1] + (c[1] - b[1]) * (b[0] - 27.5) / (b[0] - c[0])
    assert z55 == pytest.approx(22.5)


def test_3312_vs_3323_same_depths_two_starts(manual):
    _, g32 = _moves(manual("3312.nc"), "G32")
    _, g82 = _moves(manual("3323.nc"), "G82")
    t32, t82 = _threads(g32), _threads(g82)
    # 3312: four G32 passes Z101.5 -> Z19 at dia 29.2, 28.6, 28.2, 28.04 (0.8/0.6/0.4/0.16)
    assert [_dia(m.start) for m in t32] == [(29.2, 101.5), (28.6, 101.5), (28.2, 101.5), (28.04, 101.5)]
    assert all(_dia(m.end)[1] == 19.0 and m.end[0] == m.start[0] for m in t32)
    d32 = [2 * m.end[0] for m in t32]
    assert [a - b for a, b in zip([30.0] + d32, d32)] == pytest.approx([0.8, 0.6, 0.4, 0.16])
    assert all(m.lead == 1.5 and m.angle == 0 and m.thread_angle == 60 for m in t32)
    # 3323: the same four depths, each cut for two starts at spindle angles 0 and 180, lead 3
    assert [2 * m.end[0] for m in t82] == pytest.approx([d for d in d32 for _ in (0, 1)])
    assert [m.angle for m in t82] == [0, 180] * 4
    assert all(m.lead == 3 and _dia(m.start)[1] == 104.0 and _dia(m.end)[1] == 18.5 for m in t82)
    # each start is a complete A->B->C->D->A loop: back on A = X35 Z104 between the starts
    loops = [i for i, m in enumerate(g82) if m.kind == "thread"]
    for i in loops:
        assert _dia(g82[i - 1].end) == _dia(g82[i].start)  # rapid A->B ends on the thread start
        assert (g82[i + 1].kind, _dia(g82[i + 1].end)) == ("rapid", (35.0, 18.5))  # C->D
        assert (g82[i + 2].kind, _dia(g82[i + 2].end)) == ("rapid", (35.0, 104.0))  # D->A


def test_3346_threads_three_starts_at_the_stated_depths(manual):
    tp, ms = _moves(manual("3346.nc"))
    g82 = _threads([m for m in ms if m.op == "G82"])
    g76 = _threads([m for m in ms if m.op == "G76"])
    main82, run82 = g82[0::2], g82[1::2]
    # N38..N41: X19.3 / 18.9 / 18.7 / 18.7, depth 0.7, 0.4, 0.2 (diameter) from the dia 20 crest
    d = [2 * m.end[0] for m in main82[0::2]]
    assert d == pytest.approx([19.3, 18.9, 18.7, 18.7])
    assert [a - b for a, b in zip([20.0] + d, d)][:3] == pytest.approx([0.7, 0.4, 0.2])
    assert [m.angle for m in main82] == [0, 120] * 4
    # run-out R-3 E1: from the thread end Z-20 to Z-23, 1 mm out on radius
    assert all(_dia(r.end) == (round(2 * m.end[0] + 2, 6), -23.0) for m, r in zip(main82, run82))
    # N42 G76 K0.65 U0.1 Q0.6 P240: Q > K-U, so the first pass lies on K-U = 0.55, then C2 at K
    main76 = g76[0::2]
    crest = 18.7 / 2 + 0.65
    assert [crest - m.end[0] for m in main76] == pytest.approx([0.55, 0.65, 0.65])
    assert {m.angle for m in g76} == {240}
    # together the three starts of M20x1 three-start: 0, 120, 240
    assert {m.angle for m in g82} | {m.angle for m in g76} == {0, 120, 240}
    assert all(m.thread_angle == 60 and m.lead == 3 for m in g82 + g76)
    assert _dia(next(m for m in reversed(ms) if m.op == "G76").end) == (30.0, 5.0)


def test_3338_g76_depths_follow_dd_sqrt_n(manual):
    tp, ms = _moves(manual("3338.nc"), "G76")
    th = _threads(ms)
    main, runs = th[0::2], th[1::2]
    k, d, q = 1.299, 0.1, 0.9
    crest_c = 58.15 / 2 + k
    depths = [crest_c - m.end[0] for m in main]
    assert depths[0] == pytest.approx(q * math.sqrt(1))  # pass 1: Δd
    assert q * math.sqrt(2) > k - d and depths[1] == pytest.approx(k - d)  # pass 2 capped at K-d
    assert depths[2:] == pytest.approx([k, k])  # C2 finishing passes at K: the root X58.15
    assert _dia(main[-1].end)[0] == 58.15
    tan30 = math.tan(math.radians(30))
    for m, t in zip(main, depths):
        assert m.end[1] == pytest.approx(-24 - t * tan30)  # single-flank shift toward -Z
        assert m.start[0] == pytest.approx(m.end[0] - 0.94)  # taper I-0.94 (radius)
        assert m.lead == 2 and m.thread_angle == 60
    for m, r in zip(main, runs):  # run-out R-3 E1.3
        assert (r.end[0] - m.end[0], r.end[1] - m.end[1]) == pytest.approx((1.3, -3))
    assert _dia(ms[-1].end) == (90.0, 4.0)
    assert all(m.kind in ("rapid", "thread") for m in ms)


def test_alarm_through_the_interpreter_names_the_block():
    interp = _interp()
    prog = "%1\nG00 X30 Z5\nG76 C1 A45 X18 Z-20 K1 U0.1 V0.1 Q0.3 F2\nM30\n"
    with pytest.raises(NCError) as e:
        interp.run(prog)
    assert e.value.line == 3 and "A45" in e.value.message
    with pytest.raises(NCError, match="incremental U"):
        interp.run("%1\nG00 X30 Z5\nG80 U-2 Z-20 F100\nM30\n")
    with pytest.raises(NCError, match="lead 0"):
        interp.run("%1\nG00 X30 Z5\nG32 Z-20 F0\nM30\n")


# ----------------------------------------------------------------------------- audit additions
# every form of the list: absolute and G91, straight and taper


def test_g80_taper_absolute_and_straight_incremental():
    # absolute taper: A = X40 Z3, C = X30 Z-30, I-5.5 -> B at radius 15 - 5.5 on Z3
    ctx = run(80, {"X": 30, "Z": -30, "I": -5.5, "F": 100}, (20.0, 3.0))
    approx_path(ctx.moves, [("rapid", (9.5, 3)), ("feed", (15, -30)),
                            ("feed", (20, -30)), ("rapid", (20, 3))])
    # G91 straight: C = A + (X-10 dia, Z-22)
    ctx = run(80, {"X": -10, "Z": -22, "F": 100}, (20.0, 2.0), incremental=True)
    approx_path(ctx.moves, [("rapid", (15, 2)), ("feed", (15, -20)),
                            ("feed", (20, -20)), ("rapid", (20, 2))])


def test_g81_face_incremental_without_k():
    ctx = run(81, {"X": -60, "Z": -3.5}, (30.0, 5.0), incremental=True)
    approx_path(ctx.moves, [("rapid", (30, 1.5)), ("feed", (0, 1.5)),
                            ("feed", (0, 5)), ("rapid", (30, 5))])


def test_g81_refuses_w():
    alarm(81, {"X": 0, "Z": 0, "W": 1}, match="incremental W")


def test_g82_taper_absolute_and_straight_incremental():
    # absolute taper thread: C = X20 Z-25, I-1 -> B at radius 9 on the Z of A
    ctx = run(82, {"X": 20, "Z": -25, "I": -1, "F": 2}, (15.0, 5.0))
    approx_path(ctx.moves, [("rapid", (9, 5)), ("thread", (10, -25), 2, 0, 60),
                            ("rapid", (15, -25)), ("rapid", (15, 5))])
    # G91 straight thread with a run-out, start angle P90
    ctx = run(82, {"X": -10, "Z": -30, "R": -2, "E": 1, "P": 90, "F": 1.5}, (15.0, 5.0),
              incremental=True)
    approx_path(ctx.moves, [("rapid", (10, 5)), ("thread", (10, -25), 1.5, 90, 60),
                            ("thread", (11, -27), 1.5, 90, 60), ("rapid", (15, -27)),
                            ("rapid", (15, 5))])


def test_g82_refuses_u():
    alarm(82, {"X": 19, "Z": -20, "F": 1, "U": -1}, match="incremental U")


@pytest.mark.parametrize("a", [80, 60, 55, 30, 29, 0])
def test_g76_every_listed_angle_is_accepted(a):
    ctx = run(76, {**G3338, "A": a}, (45.0, 4.0))
    threads = [m for m in ctx.moves if m[0] == "thread"]
    assert threads and {m[4] for m in threads} == {a}
    # single-flank infeed along the A/2 flank: each pass shifted by t·tan(A/2) toward -Z
    crest = 58.15 / 2 + 1.299
    for m in threads[0::2]:
        t = crest - m[1][0]
        assert m[1][1] == pytest.approx(-24 - t * math.tan(math.radians(a / 2)))


@pytest.mark.parametrize("a", [45, 61, 90, -60])
def test_g76_other_angles_alarm(a):
    alarm(76, {**G3338, "A": a}, pos=(45.0, 4.0), match=f"angle A{a:g}")


def test_g32_start_angle_and_run_out_through_the_interpreter():
    interp = _interp()
    tp = interp.run("%1\nG00 X20 Z5\nG32 X20 Z-30 R-2 E1 P45 F1.5\nG00 X30\nM30\n")
    th = [m for m in tp.moves if m.kind == "thread"]
    assert len(th) == 2 and all(m.angle == 45 and m.lead == 1.5 for m in th)
    assert _dia(th[0].end) == (20.0, -30.0) and _dia(th[1].end) == (22.0, -32.0)


@pytest.mark.parametrize("text,kinds", [
    ("G80 X30 Z-20 F100", ["rapid", "line", "line", "rapid"]),
    ("G81 X10 Z-2 F100", ["rapid", "line", "line", "rapid"]),
    ("G82 X30 Z-20 F2", ["rapid", "thread", "rapid", "rapid"]),
])
def test_leg_types_through_the_interpreter(text, kinds):
    """A->B->C->D->A with rapid and feed legs typed as the figures, through the interpreter
    (every rapid leg of these cycles moves along one axis, so none is split in two)."""
    interp = _interp()
    tp = interp.run(f"%1\nG00 X40 Z5\n{text}\nM30\n")
    ms = [m for m in tp.moves if m.line == 3]
    assert [m.kind for m in ms] == kinds
    for a, b in zip(ms, ms[1:]):
        assert a.end == b.start
    assert _dia(ms[0].start) == (40.0, 5.0) and _dia(ms[-1].end) == (40.0, 5.0)
