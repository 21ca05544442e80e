"""FANUC 0i-T canned cycles (G71–G76, G90/G92/G94) and the Haas one-block forms
(hnc_cam.dialect.fanuc0it.cycles).

The unit tests drive the handlers through a fake of the interpreter's cycle context that
records every leg, with the positions docs/FANUC.md §15 computes; the end-to-end tests at the
bottom run whole programs through ``hnc_cam.nc.run(..., dialect="fanuc0it")`` when the FANUC
dialect is available.
"""
from __future__ import annotations

import math

import pytest

from hnc_cam.errors import NCError
from hnc_cam.geometry.primitives import Arc, Line
from hnc_cam.dialect.fanuc0it import cycles as fc
from hnc_cam.nc import cycles_rough, cycles_simple

from cyclefake import FakeCycleContext as FakeCtx, run_cycle

TAN30 = math.tan(math.radians(30.0))


def run(code, words, pos, table=fc.CYCLES, **kw) -> FakeCtx:
    return run_cycle(table, code, words, pos, **kw)


def near(p, q, tol=1e-4):
    return abs(p[0] - q[0]) <= tol and abs(p[1] - q[1]) <= tol


def dia(x_dia, z):
    """A point written as in the program (X diameter) -> (radius, z)."""
    return (x_dia / 2.0, z)


def path(start_dia, *blocks):
    """Profile items from blocks ('rapid'|'feed'|'cw'|'ccw', X dia, Z[, R], letters)."""
    at = dia(*start_dia)
    items = []
    for n, b in enumerate(blocks):
        kind, xd, z = b[0], b[1], b[2]
        end = dia(xd, z)
        if kind in ("cw", "ccw"):
            seg = Arc.from_radius(at, end, b[3], kind == "cw")
            letters = b[4] if len(b) > 4 else "XZ"
            items.append((seg, 100 + n, "feed", letters))
        else:
            letters = b[3] if len(b) > 3 else "XZ"
            items.append((Line(at, end), 100 + n, kind, letters))
        at = end
    return items


# --------------------------------------------------------------------------- §15.1 G71


def o9007_profile(letters_ns="X"):
    return path((46, 3), ("rapid", 0, 3, letters_ns), ("feed", 10, -2), ("feed", 10, -20, "Z"),
                ("cw", 20, -25, 5), ("feed", 20, -35, "W"), ("ccw", 34, -42, 7),
                ("feed", 34, -52, "Z"), ("feed", 44, -62, "UW"), ("feed", 44, -82, "W"))


def cuts(ctx, axis=1):
    """(start, end) of the level passes: feed legs along Z (``axis`` 1; along X: 0) that
    start on the start point's face."""
    out, at = [], None
    a = ctx.moves[-1][1]  # every roughing cycle ends on A
    for m in ctx.moves:
        if (m[0] == "feed" and at is not None and abs(m[1][1 - axis] - at[1 - axis]) < 1e-9
                and abs(at[axis] - a[axis]) < 1e-9):
            out.append((at, m[1]))
        at = m[1]
    return out


def level_cut(ctx, x):
    """True when a feed runs along Z at radius ``x``."""
    at = None
    for m in ctx.moves:
        if m[0] == "feed" and at is not None and abs(at[0] - x) < 1e-9 and abs(m[1][0] - x) < 1e-9:
            return True
        at = m[1]
    return False


def test_g71_type_i_o9007_positions():
    store = {}
    run(71, {"U": 1.5, "R": 1.0}, dia(46, 3), store=store)
    assert store[71] == {"depth": 1.5, "retract": 1.0}
    ctx = run(71, {"P": 50, "Q": 130, "U": 0.4, "W": 0.1, "F": 0.3}, dia(46, 3), store=store,
              profile={(50, 130): o9007_profile()})
    assert ctx.resumed == 130
    mv = ctx.moves
    # first level: rapid infeed (N50 is G00) to X43, feed to the allowance taper, 45° retract
    assert mv[0] == ("rapid", dia(43, 3))
    assert mv[1][0] == "feed" and near(mv[1][1], dia(43, -60.5))
    assert mv[2][0] == "rapid" and near(mv[2][1], dia(45, -59.5))
    assert mv[3][0] == "rapid" and near(mv[3][1], dia(45, 3))
    levels = cuts(ctx)
    xs = sorted({round(s[0] * 2, 6) for s, _ in levels}, reverse=True)
    assert xs == [43 - 3 * k for k in range(15)]  # X43 … X1
    last = [c for c in levels if abs(c[0][0] - 0.5) < 1e-9]
    assert len(last) == 1 and near(last[0][1], dia(1.0, 2.8))
    # the pass along the allowance profile from (X0.4, Z3.1) to (X44.4, Z-81.9), back to A
    i = next(j for j, m in enumerate(mv) if near(m[1], dia(0.4, 3.1)))
    assert mv[i][0] == "rapid"  # N50 is G00
    assert near(mv[i + 1][1], dia(10.4, -1.9))
    fin = [m for m in mv[i:] if m[0] in ("feed", "arc")]
    assert near(fin[-1][1], dia(44.4, -81.9))
    assert mv[-1] == ("rapid", dia(46, 3))
    assert not ctx.warnings


def test_g71_type_i_pass_ends_equal_hnc_for_the_same_profile():
    """The FANUC two-block G71 and HNC's one-block G71 give the same moves for the same
    profile, depth, retract and allowance."""
    prof = o9007_profile()
    f = run(71, {"P": 50, "Q": 130, "U": 0.4, "W": 0.1}, dia(46, 3),
            store={71: {"depth": 1.5, "retract": 1.0}}, profile={(50, 130): prof})

    class Hnc(FakeCtx):
        def profile(self, ns, nf):
            return [it[:3] for it in prof]

    h = Hnc(71, {"U": 1.5, "R": 1.0, "P": 50, "Q": 130, "X": 0.4, "Z": 0.1}, dia(46, 3))
    cycles_rough.execute(71, h)
    assert len(f.moves) == len(h.moves)
    for a, b in zip(f.moves, h.moves):
        assert a[0] == b[0] and near(a[1], b[1], 1e-9)


def test_g71_feed_infeed_when_ns_is_g01():
    prof = path((46, 3), ("feed", 0, 3, "X"), ("feed", 10, -2), ("feed", 44, -62))
    ctx = run(71, {"P": 1, "Q": 3}, dia(46, 3), store={71: {"depth": 2.0, "retract": 0.5}},
              profile={(1, 3): prof})
    at, infeeds = dia(46, 3), []
    for m in ctx.moves:
        if abs(at[1] - 3) < 1e-9 and abs(m[1][1] - 3) < 1e-9 and m[1][0] < at[0] - 1e-9:
            infeeds.append(m)
        at = m[1]
    assert len(infeeds) >= 11 and all(m[0] == "feed" for m in infeeds)
    assert infeeds[0] == ("feed", dia(42, 3))


def test_g71_defaults_from_the_machine_settings():
    prof = path((46, 3), ("rapid", 0, 3, "X"), ("feed", 10, -2), ("feed", 44, -62))
    ctx = run(71, {"P": 1, "Q": 3}, dia(46, 3), profile={(1, 3): prof},
              settings={"g71_depth": 4.0, "g71_retract": 0.5})
    assert ctx.moves[0] == ("rapid", dia(38, 3))  # 46 − 2·4
    assert near(ctx.moves[2][1], (ctx.moves[1][1][0] + 0.5, ctx.moves[1][1][1] + 0.5))
    ctx = run(71, {"P": 1, "Q": 3}, dia(46, 3), profile={(1, 3): prof})
    assert ctx.moves[0] == ("rapid", dia(42, 3))  # default Δd 2.0


def test_g71_id_bore_quadrant():
    """An ID G71 (bore from Ø20 to Ø40 / Ø30): levels go outward, the allowance U is
    negative (toward the axis), passes end on the allowance profile."""
    prof = path((18, 2), ("rapid", 40, 2, "X"), ("feed", 40, -10), ("feed", 30, -15),
                ("feed", 30, -30), ("feed", 18, -30))
    ctx = run(71, {"P": 1, "Q": 5, "U": -0.4, "W": 0.1, "F": 0.2}, dia(18, 2),
              store={71: {"depth": 1.0, "retract": 0.5}}, profile={(1, 5): prof})
    assert not ctx.warnings
    lv = cuts(ctx)
    assert near(lv[0][0], dia(20, 2)) and near(lv[0][1], dia(20, -29.9))
    # X28 reaches the Ø29.6 floor at Z-29.9; X34 ends on the allowance taper at Z-12.1
    ends = {round(s[0] * 2, 6): e for s, e in lv}
    assert near(ends[28.0], dia(28, -29.9))
    assert near(ends[34.0], dia(34, -12.7))
    # every pass end lies on the allowance profile (profile moved by (−0.2, +0.1))
    off = [it[0].translated(-0.2, 0.1) for it in prof[1:]]
    for _, e in lv:
        assert min(s.distance_to(e) for s in off) < 1e-7
    # retract is toward the axis (away from the wall) and toward +Z
    j = ctx.moves.index(("feed", lv[0][1]))
    assert near(ctx.moves[j + 1][1], (lv[0][1][0] - 0.5, lv[0][1][1] + 0.5))
    assert ctx.moves[-1] == ("rapid", dia(18, 2))


def test_g71_type_ii_by_ns_words_and_machine_without_it():
    prof = path((42, 2), ("rapid", 30, 2, "XW"), ("feed", 30, -10), ("feed", 20, -15),
                ("feed", 30, -20), ("feed", 30, -30), ("feed", 42, -30))
    ok = run(71, {"P": 1, "Q": 6, "U": 0.2}, dia(42, 2), store={71: {"depth": 1, "retract": .5}},
             profile={(1, 6): prof})
    assert level_cut(ok, 11.0), "the pocket to Ø20 is roughed at the level X22"
    with pytest.raises(NCError, match=r"type II.*g71_type2 = false"):
        run(71, {"P": 1, "Q": 6}, dia(42, 2), profile={(1, 6): prof},
            settings={"g71_type2": False})
    # the same profile with X only in block ns is a type I profile that turns back: PS0064
    prof1 = [(prof[0][0], prof[0][1], prof[0][2], "X")] + prof[1:]
    with pytest.raises(NCError, match=r"type I profile is not monotonic in X.*PS0064"):
        run(71, {"P": 1, "Q": 6}, dia(42, 2), profile={(1, 6): prof1})
    # type II with a Z allowance: planned, with a warning
    w = run(71, {"P": 1, "Q": 6, "U": 0.2, "W": 0.1}, dia(42, 2), profile={(1, 6): prof})
    assert any("type II" in m for m in w.warnings)


def test_g71_type_fallback_without_ns_letters():
    """Profile items without the letters of block ns: type II when the profile turns back."""
    prof = [it[:3] for it in path((42, 2), ("rapid", 30, 2), ("feed", 30, -10),
                                  ("feed", 20, -15), ("feed", 30, -20), ("feed", 42, -30))]
    ctx = run(71, {"P": 1, "Q": 5}, dia(42, 2), profile={(1, 5): prof})
    assert level_cut(ctx, 11.0)
    mono = [it[:3] for it in o9007_profile()]
    f = run(71, {"P": 50, "Q": 130}, dia(46, 3), profile={(50, 130): mono})
    assert f.resumed == 130


# --------------------------------------------------------------------------- §15.2 G72


def g72_profile(letters_ns="Z"):
    return path((82, 2), ("rapid", 82, -10, letters_ns), ("feed", 50, -10, "X"),
                ("feed", 30, -5), ("feed", 30, 2, "Z"))


def test_g72_type_i_positions():
    store = {}
    run(72, {"W": 2.0, "R": 1.0}, dia(82, 2), store=store)
    ctx = run(72, {"P": 10, "Q": 20, "U": 0.4, "W": 0.2, "F": 0.2}, dia(82, 2), store=store,
              profile={(10, 20): g72_profile()})
    mv = ctx.moves
    assert mv[0] == ("rapid", dia(82, 0))
    assert mv[1][0] == "feed" and near(mv[1][1], dia(30.4, 0))
    assert mv[2][0] == "rapid" and near(mv[2][1], dia(32.4, 1))
    feeds_x = {round(e[1], 6): e for _, e in cuts(ctx, axis=0)}
    assert sorted(feeds_x) == [-8, -6, -4, -2, 0]
    assert near(feeds_x[-6], dia(35.2, -6)) and near(feeds_x[-8], dia(43.2, -8))
    assert ctx.resumed == 20 and mv[-1] == ("rapid", dia(82, 2))


def test_g72_type_ii():
    """G72 type II (block ns with Z and X): a face profile with a recess, X monotonic."""
    prof = path((82, 2), ("rapid", 82, -10, "ZU"), ("feed", 60, -10), ("feed", 50, -4),
                ("feed", 40, -8), ("feed", 30, -8), ("feed", 30, 2))
    ctx = run(72, {"P": 1, "Q": 6}, dia(82, 2), store={71: {"depth": 1.0, "retract": 0.5}},
              profile={(1, 6): prof})
    # the recess between Ø50 and Ø30 is roughed below the Ø50 lip (Z-4)
    assert any(m[1][1] < -4.5 and 15 < m[1][0] < 25 and m[0] == "feed" for m in ctx.moves)
    with pytest.raises(NCError, match="PS0064"):
        run(72, {"P": 1, "Q": 6}, dia(82, 2),
            profile={(1, 6): [(prof[0][0], 100, "rapid", "Z")] + prof[1:]})


# --------------------------------------------------------------------------- §15.3 G73


def g73_profile():
    return path((70, 2), ("feed", 50, 0), ("ccw", 40, -15, 22), ("cw", 40, -45, 25),
                ("feed", 40, -50, "Z"))


@pytest.mark.parametrize("r", [4.0, 0.004])  # R4. / R4 read at DPI = 0
def test_g73_positions(r):
    store = {}
    run(73, {"U": 5.0, "W": 0.0, "R": r}, dia(70, 2), store=store)
    assert store[73]["passes"] == 4
    ctx = run(73, {"P": 10, "Q": 11, "U": 0.2, "W": 0.1, "F": 0.1}, dia(70, 2), store=store,
              profile={(10, 11): g73_profile()})
    starts = [dia(60.2, 0.1), dia(56.8667, 0.1), dia(53.5333, 0.1), dia(50.2, 0.1)]
    ends = [dia(50.2, -49.9), dia(46.8667, -49.9), dia(43.5333, -49.9), dia(40.2, -49.9)]
    pts = [m[1] for m in ctx.moves]
    for p in starts + ends:
        assert any(near(p, q, 2e-4) for q in pts), p
    i_end = [next(i for i, q in enumerate(pts) if near(q, e, 2e-4)) for e in ends]
    assert i_end == sorted(i_end)
    assert ctx.moves[-1] == ("rapid", dia(70, 2)) and ctx.resumed == 11


def test_g73_one_pass_and_settings():
    ctx = run(73, {"P": 10, "Q": 11}, dia(70, 2), profile={(10, 11): g73_profile()},
              settings={"g73_relief_x": 3.0, "g73_passes": 1})
    assert any("one pass" in w for w in ctx.warnings)
    assert any(near(m[1], dia(40, -50)) for m in ctx.moves)
    with pytest.raises(NCError, match="PS0062"):
        run(73, {"U": 5.0, "R": 0}, dia(70, 2))


# --------------------------------------------------------------------------- §15.4 G76


def test_g76_m68x6_passes():
    store = {}
    run(76, {"P": 11060.0, "Q": 100.0, "R": 0.2}, dia(80, 130), store=store)
    assert store[76] == {"m": 1, "r": 10, "a": 60, "min_depth": 0.1, "allowance": 0.2}
    ctx = run(76, {"X": 60.64, "Z": 25.0, "P": 3680.0, "Q": 1800.0, "F": 6.0}, dia(80, 130),
              store=store)
    threads = [m for m in ctx.moves if m[0] == "thread"]
    assert len(threads) == 10  # 5 passes × (straight + chamfer)
    depths = [1.8, 1.8 * math.sqrt(2), 1.8 * math.sqrt(3), 3.48, 3.68]
    for n, t in enumerate(depths):
        x = 30.32 + (3.68 - t)
        straight, chamfer = threads[2 * n], threads[2 * n + 1]
        assert near(straight[1], (x, 31.0), 1e-9)  # 6 mm chamfer inside Z25
        assert near(chamfer[1], (x + 6.0, 25.0), 1e-9)
        assert straight[2] == 6.0 and straight[4] == 60
    xs = [round(threads[2 * n][1][0] * 2, 3) for n in range(5)]
    assert xs == [64.4, 62.909, 61.765, 61.04, 60.64]
    # pass starts: shifted by depth·tan30 toward the chuck; back to A by X then Z
    starts = [m[1] for m in ctx.moves if m[0] == "rapid" and m[1][0] < 34]
    assert near(starts[0], (32.2, 130 - 1.8 * TAN30), 1e-9)
    assert near(starts[-1], (30.32, 130 - 3.68 * TAN30), 1e-9)
    i = ctx.moves.index(threads[1])
    assert ctx.moves[i + 1] == ("rapid", (40.0, 25.0)) and ctx.moves[i + 2] == ("rapid", (40.0, 130.0))


def test_g76_settings_and_alarms():
    ctx = run(76, {"X": 16.0, "Z": -20.0, "P": 1000.0, "Q": 400.0, "F": 1.5}, dia(22, 5),
              settings={"g76_finish_passes": 2})
    th = [m for m in ctx.moves if m[0] == "thread"]
    assert [round(m[1][0] * 2, 4) for m in th][-2:] == [16.0, 16.0]
    assert all(m[1][1] == -20.0 for m in th)
    with pytest.raises(NCError, match="tool angle"):
        run(76, {"P": 11045.0}, dia(80, 130))
    with pytest.raises(NCError, match="µm without a decimal point"):
        run(76, {"X": 16.0, "Z": -20.0, "P": 1.5, "Q": 400.0, "F": 1.5}, dia(22, 5))
    with pytest.raises(NCError, match="thread height"):
        run(76, {"X": 16.0, "Z": -20.0, "Q": 400.0, "F": 1.5}, dia(22, 5))
    with pytest.raises(NCError, match="lead"):
        run(76, {"X": 16.0, "Z": -20.0, "P": 1000.0, "Q": 400.0}, dia(22, 5))


# --------------------------------------------------------------------------- §15.5 G75 / G74


def test_g75_groove_positions():
    store = {}
    run(75, {"R": 0.5}, dia(62, -20), store=store)
    ctx = run(75, {"X": 40.0, "Z": -30.0, "P": 2000.0, "Q": 2500.0, "F": 0.1}, dia(62, -20),
              store=store)
    mv = ctx.moves
    cols = []
    for m in mv:
        if m[0] == "feed" and (not cols or cols[-1][0] != m[1][1]):
            cols.append((m[1][1], []))
        if m[0] == "feed":
            cols[-1][1].append(round(m[1][0] * 2, 6))
    assert [c for c, _ in cols] == [-20, -22.5, -25, -27.5, -30]
    for _, xs in cols:
        assert xs == [58, 54, 50, 46, 42, 40]
    # the retract after a peck is 0.5 (Ø +1), then the feed goes on Δi + e
    assert mv[0] == ("feed", dia(58, -20)) and mv[1] == ("rapid", dia(59, -20))
    assert mv[2] == ("feed", dia(54, -20))
    assert ("rapid", dia(62, -20)) in mv[:12] and mv[-1] == ("rapid", dia(62, -20))
    assert ("rapid", dia(62, -22.5)) in mv


def test_g75_groove_wider_than_the_insert_with_relief():
    """A fresh 10.2 mm wide groove with a 3 mm insert from Z-12: four columns, the last
    one landing exactly on Z-19.2; each bottom relieved 0.2 back toward the start side."""
    ctx = run(75, {"U": -10.0, "W": -7.2, "P": 1500.0, "Q": 2500.0, "R": 0.2, "F": 0.08},
              dia(52, -12), store={74: {"return": 0.3}})
    bottoms = [m[1] for m in ctx.moves if m[0] == "feed" and abs(m[1][0] - 21.0) < 1e-9]
    assert [round(b[1], 6) for b in bottoms] == [-12, -11.8, -14.5, -14.3, -17, -16.8,
                                                 -19.2, -19.0]
    pecks = [m[1][0] for m in ctx.moves if m[0] == "feed" and m[1][1] == -12.0]
    assert pecks == [24.5, 23.0, 21.5, 21.0]


def test_g74_peck_drill_positions():
    store = {}
    run(74, {"R": 1.0}, dia(0, 2), store=store)
    ctx = run(74, {"Z": -20.0, "Q": 5000.0, "F": 0.1}, dia(0, 2), store=store)
    feeds = [m[1][1] for m in ctx.moves if m[0] == "feed"]
    assert feeds == [-3, -8, -13, -18, -20]
    rapids = [m[1][1] for m in ctx.moves if m[0] == "rapid"]
    assert rapids == [-2, -7, -12, -17, 2]


def test_g74_face_groove_columns_in_x():
    """G74 from (X20, Z1) to X40 Z-6 with P2500 (2.5 radius shift) Q2000: columns at X20,
    X25, X30, X35, X40 (the last exactly on X); pecks to Z-1, -3, -5, -6 in each."""
    ctx = run(74, {"X": 40.0, "Z": -6.0, "P": 2500.0, "Q": 2000.0, "F": 0.05}, dia(20, 1),
              store={74: {"return": 0.5}})
    cols: dict = {}
    for m in ctx.moves:
        if m[0] == "feed":
            cols.setdefault(round(m[1][0] * 2, 6), []).append(m[1][1])
    assert list(cols) == [20, 25, 30, 35, 40]
    assert all(v == [-1, -3, -5, -6] for v in cols.values())
    assert ("rapid", dia(20, -0.5)) in ctx.moves  # the return e after the first peck
    assert ctx.moves[-1] == ("rapid", dia(20, 1))


def test_g75_one_column_relief_keeps_its_sign():
    ctx = run(75, {"X": 30.0, "P": 3000.0, "R": -0.1, "F": 0.05}, dia(40, -15),
              store={74: {"return": 0.0}})
    assert ctx.moves == [("feed", dia(34, -15)), ("feed", dia(30, -15)),
                         ("feed", dia(30, -15.1)), ("rapid", dia(40, -15.1)),
                         ("rapid", dia(40, -15))]


def test_haas_rough_allowance_into_the_part_alarms():
    prof = path((46, 3), ("rapid", 0, 3, "X"), ("feed", 10, -2), ("feed", 44, -62))
    with pytest.raises(NCError, match="allowance of the last pass"):
        run(71, {"P": 1, "Q": 3, "U": 0.4, "D": 2.0, "I": -0.3}, dia(46, 3),
            table=fc.HAAS_CYCLES, profile={(1, 3): prof})


def test_peck_alarms():
    with pytest.raises(NCError, match="peck depth"):
        run(74, {"Z": -20.0, "F": 0.1}, dia(0, 2))
    with pytest.raises(NCError, match="shift P"):
        run(74, {"X": 20.0, "Z": -5.0, "Q": 1000.0}, dia(0, 2))
    with pytest.raises(NCError, match="µm"):
        run(75, {"X": 40.0, "P": 2.5}, dia(62, -20))
    with pytest.raises(NCError, match="cycle_passes"):
        run(75, {"X": 0.0, "Z": -1000.0, "P": 1.0, "Q": 1.0}, dia(62, 0), max_passes=1000)


# --------------------------------------------------------------------------- §5 G90 G92 G94


def test_g90_taper_and_increments():
    ctx = run(90, {"X": 40.0, "Z": -30.0, "R": -2.5, "F": 0.2}, dia(52, 2))
    assert ctx.moves == [("rapid", dia(35, 2)), ("feed", dia(40, -30)), ("feed", dia(52, -30)),
                         ("rapid", dia(52, 2))]
    inc = run(90, {"U": -12.0, "W": -32.0}, dia(52, 2))
    assert inc.moves == [("rapid", dia(40, 2)), ("feed", dia(40, -30)), ("feed", dia(52, -30)),
                         ("rapid", dia(52, 2))]
    with pytest.raises(NCError, match="both X and U"):
        run(90, {"X": 40.0, "U": -2.0, "Z": -30.0}, dia(52, 2))
    with pytest.raises(NCError, match=r"missing Z\(W\)"):
        run(90, {"X": 40.0}, dia(52, 2))


def test_g94_facing():
    ctx = run(94, {"X": 20.0, "Z": -2.0, "R": -1.0}, dia(62, 2))
    assert ctx.moves == [("rapid", dia(62, -3)), ("feed", dia(20, -2)), ("feed", dia(20, 2)),
                         ("rapid", dia(62, 2))]


def test_g92_multi_pass_thread():
    """G92 X29.2 Z-20 F1.5, then X28.6, X28.2, X28.05 (the modal repeats): each pass rapid
    in X, thread to Z-20, out in X, back in Z."""
    out = []
    for x in (29.2, 28.6, 28.2, 28.05):
        ctx = run(92, {"X": x, "Z": -20.0, "F": 1.5}, dia(32, 4))
        out.append(ctx.moves)
        assert ctx.moves == [("rapid", dia(x, 4)),
                             ("thread", dia(x, -20), 1.5, 0.0, 60.0),
                             ("rapid", dia(32, -20)), ("rapid", dia(32, 4))]
    # taper R, start angle Q (0.001°) and the chamfer from the machine (r = 10: one lead)
    ctx = run(92, {"X": 29.2, "Z": -20.0, "R": -0.5, "F": 1.5, "Q": 180000.0}, dia(32, 4),
              settings={"thread_chamfer": 10})
    assert ctx.moves[0] == ("rapid", dia(28.2, 4))
    th = [m for m in ctx.moves if m[0] == "thread"]
    assert th[0][3] == 180.0
    assert near(th[0][1], (14.6 - 0.5 * 1.5 / 24, -18.5), 1e-9)
    assert near(th[1][1], (14.6 + 1.5, -20.0), 1e-9)
    with pytest.raises(NCError, match="lead"):
        run(92, {"X": 29.2, "Z": -20.0}, dia(32, 4))


# --------------------------------------------------------------------------- Haas


def test_haas_one_block_g71_equals_fanuc_two_block():
    prof = o9007_profile()
    h = run(71, {"P": 50, "Q": 130, "U": 0.4, "W": 0.1, "D": 1.5, "F": 0.3}, dia(46, 3),
            table=fc.HAAS_CYCLES, settings={"g71_retract": 1.0}, profile={(50, 130): prof})
    f = run(71, {"P": 50, "Q": 130, "U": 0.4, "W": 0.1}, dia(46, 3),
            store={71: {"depth": 1.5, "retract": 1.0}}, profile={(50, 130): prof})
    assert h.moves == f.moves and h.resumed == 130
    # two-block form read under Haas too
    store = {}
    run(71, {"U": 1.5, "R": 1.0}, dia(46, 3), table=fc.HAAS_CYCLES, store=store)
    t = run(71, {"P": 50, "Q": 130, "U": 0.4, "W": 0.1}, dia(46, 3), table=fc.HAAS_CYCLES,
            store=store, profile={(50, 130): prof})
    assert t.moves == f.moves


def test_haas_g71_rough_allowance_i_k():
    prof = path((46, 3), ("rapid", 0, 3, "X"), ("feed", 10, -2), ("feed", 44, -62))
    h = run(71, {"P": 1, "Q": 3, "U": 0.4, "W": 0.1, "D": 2.0, "I": 0.3, "K": 0.2}, dia(46, 3),
            table=fc.HAAS_CYCLES, profile={(1, 3): prof})
    lv = cuts(h)
    # the level passes stop at profile + (0.2 + 0.3, 0.1 + 0.2)
    off = [it[0].translated(0.5, 0.3) for it in prof[1:]]
    for _, e in lv:
        assert min(s.distance_to(e) for s in off) < 1e-7
    # the last pass runs on profile + (0.2, 0.1) and ends at (X44.4, Z-61.9)
    assert any(near(m[1], dia(44.4, -61.9)) for m in h.moves)
    assert not any(near(m[1], dia(45.0, -61.7)) for m in h.moves if m[0] == "feed")


def test_haas_g73_and_g76():
    h = run(73, {"P": 10, "Q": 11, "D": 4.0, "I": 5.0, "K": 0.0, "U": 0.2, "W": 0.1},
            dia(70, 2), table=fc.HAAS_CYCLES, profile={(10, 11): g73_profile()})
    pts = [m[1] for m in h.moves]
    assert any(near(p, dia(60.2, 0.1), 2e-4) for p in pts)
    assert any(near(p, dia(40.2, -49.9), 2e-4) for p in pts)
    # G76 X16.93 Z-25. K1.534 D.485 F2.5 (crest Ø19.998)
    t = run(76, {"X": 16.93, "Z": -25.0, "K": 1.534, "D": 0.485, "F": 2.5}, dia(22, 3),
            table=fc.HAAS_CYCLES)
    th = [m for m in t.moves if m[0] == "thread"]
    d = [round(16.93 / 2 + 1.534 - m[1][0], 6) for m in th]
    assert d[0] == 0.485 and d[1] == round(0.485 * math.sqrt(2), 6) and d[-1] == 1.534
    assert all(m[1][1] == -25.0 for m in th)
    # P3: constant depth 0.5 → 0.5, 1.0, 1.5, 1.534; P4 alternates the flank
    t3 = run(76, {"X": 16.93, "Z": -25.0, "K": 1.534, "D": 0.5, "F": 2.5, "P": 3.0},
             dia(22, 3), table=fc.HAAS_CYCLES)
    d3 = [round(16.93 / 2 + 1.534 - m[1][0], 6) for m in t3.moves if m[0] == "thread"]
    assert d3 == [0.5, 1.0, 1.5, 1.534]
    t4 = run(76, {"X": 16.93, "Z": -25.0, "K": 1.534, "D": 0.5, "F": 2.5, "P": 4.0},
             dia(22, 3), table=fc.HAAS_CYCLES)
    zs = [m[1][1] for m in t4.moves if m[0] == "rapid" and m[1][0] < 10.5]
    assert zs[0] == pytest.approx(3 - 0.5 * TAN30) and zs[1] == pytest.approx(3 - (3.068 - 1.0) * TAN30)
    with pytest.raises(NCError, match="not read under haas"):
        run(76, {"P": 11060.0, "Q": 100.0, "R": 0.2}, dia(22, 3), table=fc.HAAS_CYCLES)


# --------------------------------------------------------------------------- alarms


@pytest.mark.parametrize("code,words,msg", [
    (71, {"P": 1}, r"missing Q.*PS0061"),
    (71, {"U": -1.0}, "PS0062"),
    (71, {"U": 1.0, "W": 1.0}, "W is not a word of the first G71"),
    (72, {"U": 1.0}, "U is not a word of the first G72"),
    (71, {"P": 1.5, "Q": 3}, "sequence number"),
    (71, {"P": 1, "Q": 3, "D": 1.5}, "µm without a decimal point"),
    (73, {"R": 0.0045}, "whole number"),
    (71, {"U": 1.5, "R": 1.0, "P": 1, "Q": 3, "X": 0.4, "Z": 0.1},
     r"R is a word of the first G71 block"),
    (73, {"P": 1, "Q": 3, "R": 3.0}, r"R is a word of the first G73 block"),
    (74, {"P": 100.0}, "P is not a word of the first G74"),
    (76, {"P": 11060.0, "Q": -1.0}, "without a sign"),
])
def test_alarms_on_words(code, words, msg):
    prof = path((46, 3), ("rapid", 0, 3, "X"), ("feed", 10, -2), ("feed", 44, -62))
    with pytest.raises(NCError, match=msg):
        run(code, words, dia(46, 3), profile={(1, 3): prof})


def test_runaway_levels_are_bounded():
    prof = path((46, 3), ("rapid", 0, 3, "X"), ("feed", 44, -62))
    with pytest.raises(NCError, match=r"depth of cut 0\.001: about 23000 pass levels"):
        run(71, {"P": 1, "Q": 2}, dia(46, 3), store={71: {"depth": 0.001}},
            profile={(1, 2): prof})
    with pytest.raises(NCError, match=r"G71 D0\.001: about"):
        run(71, {"P": 1, "Q": 2, "D": 0.001}, dia(46, 3), table=fc.HAAS_CYCLES,
            profile={(1, 2): prof})
    with pytest.raises(NCError, match="cycle_passes"):
        run(73, {"P": 1, "Q": 2, "D": 20000.0}, dia(46, 3), table=fc.HAAS_CYCLES,
            profile={(1, 2): prof})
    with pytest.raises(NCError, match="passes"):
        run(76, {"X": 16.0, "Z": -20.0, "P": 1000.0, "Q": 1.0, "F": 1.5}, dia(22, 5))


def test_bad_machine_setting_alarms():
    with pytest.raises(NCError, match="g71_depth"):
        run(71, {"P": 1, "Q": 3}, dia(46, 3), settings={"g71_depth": "deep"},
            profile={(1, 3): path((46, 3), ("rapid", 0, 3, "X"), ("feed", 44, -62))})


def test_tables():
    assert set(fc.CYCLES) == {71, 72, 73, 74, 75, 76, 90, 92, 94}
    assert set(fc.HAAS_CYCLES) == {71, 72, 73, 76}
    assert fc.MODAL_CYCLES == frozenset({90, 92, 94})
    assert cycles_simple.thread_passes and cycles_rough.emit


# --------------------------------------------------------------------------- any words

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_values = st.one_of(st.sampled_from([0.0, 1.0, -1.0, 0.5, 2.0, 3.0, 1000.0, 0.004, 11060.0,
                                     60.0, 99.0, 1e9, -1e9]),
                    st.floats(-1e4, 1e4, allow_nan=False))
_words = st.dictionaries(st.sampled_from(list("XZUWPQRDIKFA")), _values, max_size=3)


_GOOD = {71: {"P": 1, "Q": 3, "U": 0.4, "W": 0.1}, 72: {"P": 1, "Q": 3, "U": 0.4},
         73: {"P": 1, "Q": 3, "U": 0.4}, 74: {"X": 20.0, "Z": -10.0, "P": 1000.0, "Q": 2000.0},
         75: {"X": 20.0, "Z": -10.0, "P": 1000.0, "Q": 2000.0},
         76: {"X": 16.0, "Z": -20.0, "P": 1000.0, "Q": 400.0, "F": 1.5},
         90: {"X": 20.0, "Z": -20.0, "F": 1.0}, 92: {"X": 20.0, "Z": -20.0, "F": 1.0},
         94: {"X": 20.0, "Z": -20.0, "F": 1.0}, 1071: {"P": 1, "Q": 3, "D": 1.0},
         1072: {"P": 1, "Q": 3, "D": 1.0}, 1073: {"P": 1, "Q": 3, "D": 3.0, "I": 2.0},
         1076: {"X": 16.0, "Z": -20.0, "K": 1.0, "D": 0.3, "F": 1.5}}


@settings(max_examples=400, deadline=None)
@given(code=st.sampled_from(sorted(fc.CYCLES) + [1071, 1072, 1073, 1076]), words=_words,
       first=_words, pos=st.tuples(st.floats(0.5, 50), st.floats(-50, 50)))
def test_any_words_give_moves_or_an_alarm(code, words, first, pos):
    """Whatever the words (and an earlier first block), a cycle either moves or alarms with
    an NCError; it never raises anything else and never exceeds its bounds."""
    table = fc.HAAS_CYCLES if code > 1000 else fc.CYCLES
    base = _GOOD.get(code, _GOOD.get(code % 1000, {}))
    words = {**base, **words}
    code %= 1000
    if code == 72:
        prof = path((2 * pos[0], pos[1]), ("rapid", 2 * pos[0], pos[1] - 10, "Z"),
                    ("feed", 10, pos[1] - 10), ("feed", 8, pos[1] - 2), ("feed", 8, pos[1] + 1))
    else:
        prof = path((2 * pos[0], pos[1]), ("rapid", 0, pos[1], "X"),
                    ("feed", pos[0], pos[1] - 5), ("feed", 1.8 * pos[0], pos[1] - 65))
    store: dict = {}
    try:
        run(code, first, pos, table=table, store=store, max_passes=500, moves_left=20_000)
    except NCError:
        pass
    try:
        ctx = run(code, words, pos, table=table, store=store, max_passes=500, moves_left=20_000,
                  profile={(1, 3): prof, (1, 2): prof[:2]})
    except NCError:
        return
    assert len(ctx.moves) <= 20_000 * 3
    for m in ctx.moves:
        assert all(math.isfinite(v) for v in m[1])


# --------------------------------------------------------------------------- end to end


def fanuc(text: str, dialect: str = "fanuc0it", machine=None):
    """Run ``text`` through the interpreter under ``dialect`` (skips while the interpreter
    does not take a dialect)."""
    import inspect

    from hnc_cam import nc
    if "dialect" not in inspect.signature(nc.run).parameters:
        pytest.skip("the interpreter does not take a dialect yet")
    return nc.run(text, machine, dialect=dialect)


def op_moves(tp, op):
    return [m for m in tp.moves if m.op == op]


def has_end(moves, p, kind=None, tol=1e-6):
    return any(near(m.end, p, tol) and (kind is None or m.kind == kind) for m in moves)


O9007 = """%
O9007
N10 G54 G00 X80. Z80.
N20 M03 S400
N30 G01 X46. Z3. F0.2
N35 G71 U1.5 R1.
N40 G71 P50 Q130 U0.4 W0.1 F0.3
N50 G00 X0.
N60 G01 X10. Z-2.
N70 Z-20.
N80 G02 U10. W-5. R5.
N90 G01 W-10.
N100 G03 U14. W-7. R7.
N110 G01 Z-52.
N120 U10. W-10.
N130 W-20.
N135 G70 P50 Q130
N140 X50.
N150 G00 X80. Z80.
N160 M05
N170 M30
%
"""


def test_e2e_o9007_g71_then_g70():
    tp = fanuc(O9007)
    g71 = op_moves(tp, "G71")
    assert near(g71[0].start, dia(46, 3)) and near(g71[-1].end, dia(46, 3))
    assert has_end(g71, dia(43, -60.5), "line") and has_end(g71, dia(45, -59.5), "rapid")
    assert has_end(g71, dia(1.0, 2.8), "line") and has_end(g71, dia(44.4, -81.9))
    assert all(m.feed == pytest.approx(0.3 * m.spindle) for m in g71 if m.kind != "rapid")
    # the profile blocks N50..N130 (lines 8..16) run only inside the cycles: after the G71
    # the program goes on with G70 (line 17), which runs them and returns to A
    g70 = [m for m in tp.moves if m.op != "G71" and 8 <= m.line <= 17]
    assert g70 and min(tp.moves.index(m) for m in g70) > tp.moves.index(g71[-1])
    assert has_end(g70, dia(44, -82))
    assert len([m for m in g70 if near(m.end, dia(10, -2))]) == 1  # once, not also after G71
    after = [m for m in tp.moves if m.line == 18]  # N140 X50.
    assert after and after[-1].end[0] == pytest.approx(25.0)


def test_e2e_g71_pass_ends_equal_hnc(manual):
    """The HNC program 3327 is O9007's profile in HNC's one-block G71: the roughing moves
    are the same."""
    from hnc_cam.nc import run_file
    hnc = [m for m in run_file(str(manual("3327.nc"))).moves if m.op == "G71"]
    fan = op_moves(fanuc(O9007), "G71")
    assert len(hnc) == len(fan)
    for a, b in zip(hnc, fan):
        assert a.kind == b.kind and near(a.start, b.start, 1e-9) and near(a.end, b.end, 1e-9)


def test_e2e_g72_type_i():
    tp = fanuc("""%
O0002
T0101
G99 G97 S600 M03
G00 X82.0 Z2.0
G72 W2.0 R1.0
G72 P10 Q20 U0.4 W0.2 F0.2
N10 G00 Z-10.0
G01 X50.0
X30.0 Z-5.0
N20 Z2.0
G70 P10 Q20
G00 X100.0 Z100.0
M30
%
""")
    g72 = op_moves(tp, "G72")
    assert has_end(g72, dia(30.4, 0), "line") and has_end(g72, dia(32.4, 1), "rapid")
    assert has_end(g72, dia(35.2, -6), "line") and has_end(g72, dia(43.2, -8), "line")
    assert near(g72[-1].end, dia(82, 2))


def test_e2e_g73():
    tp = fanuc("""%
O0003
M03 S1000
T0101
G0 X70. Z2.
G73 U5. W0 R4
G73 P10 Q11 U0.2 W0.1 F0.1
N10 G01 X50. Z0
G3 X40. Z-15. R22.
G2 Z-45. R25.
N11 G1 Z-50.
G70 P10 Q11
G0 X100. Z200.
T0100
M30
%
""")
    g73 = op_moves(tp, "G73")
    for p in (dia(60.2, 0.1), dia(50.2, 0.1), dia(50.2, -49.9), dia(40.2, -49.9)):
        assert has_end(g73, p, tol=2e-4), p
    assert near(g73[-1].end, dia(70, 2))


def test_e2e_g76_m68x6():
    tp = fanuc("""%
O0004
G97 S200 M03
G00 X80.0 Z130.0
G76 P011060 Q100 R200
G76 X60640 Z25000 P3680 Q1800 F6.0
G00 X100.0
M30
%
""")
    th = [m for m in op_moves(tp, "G76") if m.kind == "thread"]
    assert len(th) == 10 and all(m.lead == 6.0 for m in th)
    xs = [round(m.end[0] * 2, 3) for m in th[::2]]
    assert xs == [64.4, 62.909, 61.765, 61.04, 60.64]
    assert all(m.end[1] == pytest.approx(31.0) for m in th[::2])
    assert all(m.end[1] == pytest.approx(25.0) for m in th[1::2])


def test_e2e_g75_g74():
    tp = fanuc("""%
O0005
G97 S500 M03
G00 X62.0 Z-20.0
G75 R0.5
G75 X40.0 Z-30.0 P2000 Q2500 F0.1
G00 X100.0
G00 X0 Z2.0
G74 R1.0
G74 Z-20.0 Q5000 F0.1
M30
%
""")
    g75 = op_moves(tp, "G75")
    bottoms = sorted({round(m.end[1], 6) for m in g75 if m.kind == "line"
                      and abs(m.end[0] - 20.0) < 1e-9})
    assert bottoms == [-30, -27.5, -25, -22.5, -20]
    assert near(g75[-1].end, dia(62, -20))
    g74 = op_moves(tp, "G74")
    assert [round(m.end[1], 6) for m in g74 if m.kind == "line"] == [-3, -8, -13, -18, -20]


def test_e2e_fresh_id_g71_and_g90_g92():
    """A bore roughed by G71 (U negative), an OD taper by G90 and a thread by G92 passes."""
    tp = fanuc("""%
O0101 (BORE, TAPER, THREAD)
G99 G97 S800 M03
G00 X18. Z2.
G71 U1. R0.5
G71 P1 Q5 U-0.4 W0.1 F0.2
N1 G00 X40.
N2 G01 Z-10.
N3 X30. Z-15.
N4 Z-30.
N5 X18.
G00 X52. Z2.
G90 X48. Z-30. R-1.5 F0.25
X46.
X44.
G00 X32. Z4.
G92 X29.2 Z-20. F1.5
X28.6
X28.2
X28.05
G00 X100. Z100.
M30
%
""")
    g71 = op_moves(tp, "G71")
    assert has_end(g71, dia(20, -29.9), "line") and has_end(g71, dia(34, -12.7), "line")
    g90 = op_moves(tp, "G90")
    taper_ends = [m for m in g90 if m.kind == "line" and m.end[1] == pytest.approx(-30.0)
                  and m.start[1] == pytest.approx(2.0)]
    assert [round(m.end[0] * 2, 6) for m in taper_ends] == [48, 46, 44]
    assert [round(m.start[0] * 2, 6) for m in taper_ends] == [45, 43, 41]
    th = [m for m in op_moves(tp, "G92") if m.kind == "thread"]
    assert [round(m.end[0] * 2, 6) for m in th] == [29.2, 28.6, 28.2, 28.05]
    assert all(m.end[1] == pytest.approx(-20.0) and m.lead == 1.5 for m in th)


def test_e2e_fresh_g72_type_ii_and_wide_groove():
    tp = fanuc("""%
O0102
G99 G97 S600 M03
G00 X82. Z2.
G72 W1. R0.5
G72 P1 Q6 U0.2 W0.1 F0.2
N1 G00 Z-10. U0
N2 G01 X60.
N3 X50. Z-4.
N4 X40. Z-8.
N5 X30.
N6 Z2.
G00 X52. Z-12.
G75 R0.3
G75 U-10. W-7.2 P1500 Q2500 R0.2 F0.08
G00 X100. Z100.
M30
%
""")
    g72 = op_moves(tp, "G72")
    assert any(m.kind == "line" and m.end[1] < -4.5 and 15 < m.end[0] < 25 for m in g72)
    g75 = op_moves(tp, "G75")
    bottoms = [round(m.end[1], 6) for m in g75 if m.kind == "line" and abs(m.end[0] - 21) < 1e-9]
    assert bottoms == [-12, -11.8, -14.5, -14.3, -17, -16.8, -19.2, -19.0]


def test_e2e_haas_one_block_g71():
    text = O9007.replace("N35 G71 U1.5 R1.\nN40 G71 P50 Q130 U0.4 W0.1 F0.3",
                         "N35 (ONE BLOCK)\nN40 G71 P50 Q130 U0.4 W0.1 D1.5 F0.3")
    try:
        haas = op_moves(fanuc(text, dialect="haas"), "G71")
    except NCError as e:  # pragma: no cover - depends on the machine's retract setting
        raise AssertionError(e)
    fan = op_moves(fanuc(O9007), "G71")
    assert has_end(haas, dia(43, -60.5), "line")
    # the default retract (1.0) equals O9007's R1.: the same moves
    assert [(m.kind, m.end) for m in haas] == [(m.kind, m.end) for m in fan]


def test_e2e_alarm_has_the_place():
    with pytest.raises(NCError) as e:
        fanuc("%\nO0103\nG00 X46. Z3.\nG71 U1.5 R1.\nG71 P50 U0.4 W0.1 F0.3\nM30\n%\n")
    assert e.value.line == 5 and "PS0061" in str(e.value)


def test_e2e_machine_parameters_and_type_ii_refused():
    from dataclasses import replace

    from hnc_cam.tooling import load_machine
    prog = ("%\nO0104\nG97 S500 M03\nG00 X42. Z2.\nG71 P1 Q4 U0.2 F0.2\nN1 G00 X30. Z2.\n"
            "N2 G01 Z-10.\nN3 X20. Z-15.\nN4 X42. Z-30.\nM30\n%\n")
    m = replace(load_machine(), parameters={"g71_depth": 3.0, "g71_retract": 0.25})
    g71 = op_moves(fanuc(prog, machine=m), "G71")
    assert g71[0].end == pytest.approx(dia(36, 2))  # A.x − 2·3.0, no first block
    first_cut = next(i for i, mv in enumerate(g71) if mv.kind == "line")
    cx, cz = g71[first_cut].end
    assert has_end(g71, (cx + 0.25, cz + 0.25), "rapid")  # the 45° retract e = 0.25
    assert any(mv.kind == "line" and mv.end[0] < 12.5 for mv in g71)  # type II pocket
    m2 = replace(load_machine(), parameters={"g71_type2": False})
    with pytest.raises(NCError, match=r"line 6.*g71_type2 = false") as e:
        fanuc(prog, machine=m2)
    assert e.value.line == 5
    with pytest.raises(NCError, match="g71_depth"):
        fanuc(prog, machine=replace(load_machine(), parameters={"g71_depth": True}))


def test_e2e_simple_cycles_and_g76_agree_with_hnc():
    """G90/G94/G92 move as HNC's G80/G81/G82 with I/K for R; FANUC's G76 cuts at the depths
    of HNC's G76 for the same thread (one law)."""
    from hnc_cam import nc
    fan = fanuc("%\nO0105\nG97 S500 M03\nG00 X52. Z2.\nG90 X40. Z-30. R-2.5 F0.2\n"
                "G00 X62. Z2.\nG94 X20. Z-2. R-1. F0.2\nG00 X32. Z4.\nG92 X29.2 Z-20. F1.5\n"
                "G00 X80. Z130.\nG76 P011060 Q100 R200\nG76 X60640 Z25000 P3680 Q1800 F6.0\n"
                "M30\n%\n")
    hnc = nc.run("%0105\nM03 S500\nG00 X52 Z2\nG80 X40 Z-30 I-2.5 F100\nG00 X62 Z2\n"
                 "G81 X20 Z-2 K-1 F100\nG00 X32 Z4\nG82 X29.2 Z-20 F1.5\nG00 X80 Z130\n"
                 "G76 C1 A60 X60.64 Z25 K3.68 U0.2 V0.1 Q1.8 F6\nM30\n")
    for f_op, h_op in (("G90", "G80"), ("G94", "G81"), ("G92", "G82")):
        f = [(m.kind, m.end) for m in op_moves(fan, f_op)]
        h = [(m.kind, m.end) for m in op_moves(hnc, h_op)]
        assert f == h, f_op
    f76 = [m.start for m in op_moves(fan, "G76") if m.kind == "thread"][::2]
    h76 = [m.start for m in op_moves(hnc, "G76") if m.kind == "thread"][::2]  # + run-out
    assert len(f76) == len(h76) == 5
    for a, b in zip(f76, h76):
        assert a == pytest.approx(b)


O9007_AS_PRINTED = """O9007
N10 G54 G00 X80 Z80
N20 M03 S400
N30 G01 X46 Z3 F0.2
N35 G71 U1.5 R1
N40 G71 P50 Q130 U0.4 W0.1 F0.3
N50 G00 X0
N60 G01 X10 Z-2
N70 Z-20
N80 G02 U10 W-5 R5
N90 G01 W-10
N100 G03 U14 W-7 R7
N110 G01 Z-52
N120 U10 W-10
N130 W-20
N135 G70 P50 Q130
N140 X50
N150 G00 X80 Z80
N160 M05
N170 M30
"""


def test_e2e_o9007_as_printed_needs_calculator_input():
    """§15.1 as the source prints it (no decimal points, for a DPI = 1 machine): with
    decimal_point = "calculator" the passes are those of the program with points; read as
    least increments the profile shrinks 1000× and the cycle has nothing to rough."""
    from dataclasses import replace

    from hnc_cam.tooling import load_machine
    calc = replace(load_machine(), decimal_point="calculator")
    got = op_moves(fanuc(O9007_AS_PRINTED, machine=calc), "G71")
    ref = op_moves(fanuc(O9007), "G71")
    assert [(m.kind, m.end) for m in got] == [(m.kind, m.end) for m in ref]
    with pytest.raises(NCError) as e:
        fanuc(O9007_AS_PRINTED)
    assert e.value.line == 6


def test_e2e_g73_as_printed_with_calculator_input():
    from dataclasses import replace

    from hnc_cam.tooling import load_machine
    calc = replace(load_machine(), decimal_point="calculator")
    tp = fanuc("M03 S1000\nT0101\nG0 X70 Z2\nG73 U5 W0 R4\nG73 P10 Q11 U0.2 W0.1 F0.1\n"
               "N10 G01 X50 Z0\nG3 X40 Z-15 R22\nG2 Z-45 R25\nN11 G1 Z-50\nG70 P10 Q11\n"
               "G0 X100 Z200\nT0100\nM30\n", machine=calc)
    g73 = op_moves(tp, "G73")
    for p in (dia(60.2, 0.1), dia(56.8667, 0.1), dia(53.5333, 0.1), dia(50.2, 0.1),
              dia(50.2, -49.9), dia(46.8667, -49.9), dia(43.5333, -49.9), dia(40.2, -49.9)):
        assert has_end(g73, p, tol=2e-4), p


def test_e2e_type_by_the_letters_of_block_ns():
    """Block ns with X only is type I even when the profile turns back in X (PS0064 at the
    G71 block); with ``W0`` beside X the same profile is type II and cuts the pocket."""
    body = "N20 G01 Z-10.\nN30 X30. Z-15.\nN40 X24. Z-20.\nN50 X40. Z-30.\nM30\n%\n"
    head = "%\nO0110\nG97 S500 M03\nG00 X42. Z2.\nG71 U1. R0.5\nG71 P10 Q50 U0.2 W0 F0.2\n"
    with pytest.raises(NCError, match=r"type I profile is not monotonic in X.*PS0064") as e:
        fanuc(head + "N10 G00 X20.\n" + body)
    assert e.value.line == 6
    g71 = op_moves(fanuc(head + "N10 G00 X20. W0\n" + body), "G71")
    pocket = [mv.end for mv in g71 if mv.kind == "line" and -20.0 <= mv.end[1] < -15.0]
    assert pocket and min(x for x, _ in pocket) < 13.0  # passes below the X30 crest
    assert min(x for x, _ in pocket) >= 12.1 - 1e-6  # the pocket bottom X24 + U0.2 is left


def test_e2e_modal_g90_repeat_block_switches_x_and_u():
    """A repeat block of a modal G90/G94/G92 that writes one of a pair (X/U, Z/W) replaces the
    kept word of the other form: ``U-6.`` after ``X48.`` cuts at A.x − 6, ``X44.`` after it
    at X44, ``W-20.`` after ``Z-30.`` at A.z − 20."""
    tp = fanuc("%\nO0111\nG97 S500 M03\nG00 X52. Z2.\nG90 X48. Z-30. F0.2\nU-6.\nX44.\n"
               "W-20.\nG00 X60.\nM30\n%\n")
    g90 = op_moves(tp, "G90")
    by_line = {}
    for mv in g90:
        by_line.setdefault(mv.line, []).append(mv)
    assert sorted(by_line) == [5, 6, 7, 8]
    # each pass: rapid to X, feed to Z, feed up to A.x, rapid back to A
    assert by_line[5][0].end == pytest.approx(dia(48, 2))
    assert by_line[6][0].end == pytest.approx(dia(46, 2))
    assert by_line[6][1].end == pytest.approx(dia(46, -30))
    assert by_line[7][0].end == pytest.approx(dia(44, 2))
    assert by_line[8][1].end == pytest.approx(dia(44, -18))
    assert by_line[8][-1].end == pytest.approx(dia(52, 2))


def test_e2e_g70_returns_to_a_in_rapid():
    """After the finishing pass the tool goes back in rapid to A, where it stood before the
    G70 block (here not the G71's start point)."""
    prog = O9007.replace("N135 G70 P50 Q130", "G00 X48. Z4.\nN135 G70 P50 Q130")
    tp = fanuc(prog)
    line = next(i + 1 for i, t in enumerate(prog.splitlines()) if "G70" in t)
    at_g70 = [m for m in tp.moves if m.line == line]
    assert at_g70 and at_g70[-1].kind == "rapid" and at_g70[-1].end == pytest.approx(dia(48, 4))
    before = tp.moves.index(at_g70[0]) - 1
    assert tp.moves[before].end == pytest.approx(dia(44, -82))  # the profile's end nf
    after = [m for m in tp.moves if m.line == line + 1]  # N140 X50. starts from A
    assert after and after[0].start[1] == pytest.approx(4.0)


def test_e2e_g92_start_angle_up_to_360000():
    """Q of G92 is the spindle start angle in 0.001° up to 360000: Q180000 is 180°; more than
    360000 is an alarm at the word."""
    text = "%\nO0112\nG97 S500 M03\nG00 X32. Z4.\nG92 X29.2 Z-20. F1.5 Q180000\nM30\n%\n"
    th = [m for m in op_moves(fanuc(text), "G92") if m.kind == "thread"]
    assert th and all(m.angle == pytest.approx(180.0) for m in th)
    assert th[0].end == pytest.approx(dia(29.2, -20.0))
    with pytest.raises(NCError) as e:
        fanuc(text.replace("Q180000", "Q360001"))
    assert e.value.line == 5 and e.value.col == text.splitlines()[4].index("Q") + 1
