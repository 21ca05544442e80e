"""SINUMERIK 802S/802C cycles LCYC82/83/840/85/93/95/97 (hnc_cam.dialect.siemens802.cycles).

The handlers run on the shared fake cycle context extended with the 802 members (R
parameters, ``_CNAME``, the contour subprogram, the plane); positions are (x radius, z).
The document's examples (LCYC82, LCYC83, LCYC840) are transcribed with their positions."""
from __future__ import annotations

import math

import pytest

from hnc_cam.errors import NCError
from hnc_cam.geometry.primitives import Arc, Line
from hnc_cam.dialect.siemens802 import cycles as sc

from cyclefake import FakeCycleContext


class Ctx802(FakeCycleContext):
    """The fake with the 802 members: ``r``/``set_r``, ``text``, ``contour``, ``plane``."""

    def __init__(self, name, r, pos, *, plane=18, contours=None, texts=None, **kw):
        code = int(name[4:])
        super().__init__(code, {}, pos, **kw)
        self.name = name
        self.R = dict(r)
        self.plane = plane
        self.contours = contours or {}
        self.texts = texts or {}
        self.feeds = []

    def r(self, n):
        return float(self.R.get(n, 0.0))

    def set_r(self, n, v):
        self.R[n] = float(v)

    def text(self, name):
        return self.texts.get(name)

    def contour(self, name):
        if name not in self.contours:
            raise NCError(f"subprogram {name} not found", line=self.line, col=0)
        return self.contours[name]

    def tool_nose(self):
        return (0.0, 0)

    def feed(self, x, z, feed=None):
        self.feeds.append(feed)
        super().feed(x, z, feed)

    def arc(self, x, z, center, cw, feed=None):
        self.feeds.append(feed)
        super().arc(x, z, center, cw, feed)


def run(name, r, pos, **kw) -> Ctx802:
    ctx = Ctx802(name, r, pos, **kw)
    sc.CYCLES[name](ctx)
    return ctx


def legs(ctx, kinds=("rapid", "feed", "thread", "arc")):
    return [(m[0], (round(m[1][0], 6), round(m[1][1], 6))) for m in ctx.moves if m[0] in kinds]


def alarm_of(name, r, pos=(0.0, 100.0), **kw) -> str:
    with pytest.raises(NCError) as exc:
        run(name, r, pos, **kw)
    return str(exc.value)


# --------------------------------------------------------------------------- drilling


def test_lcyc82_document_example():
    # N20 Z110 X0; R101=110 R102=4 R103=102 R104=75 R105=2; G17 LCYC82
    ctx = run("LCYC82", {101: 110, 102: 4, 103: 102, 104: 75, 105: 2}, (0.0, 110.0), plane=17)
    assert legs(ctx) == [("rapid", (0.0, 106.0)), ("feed", (0.0, 75.0)), ("rapid", (0.0, 110.0))]
    assert ("dwell", 2.0) in ctx.moves
    # the tool ends on the retraction plane above the hole it drilled: X0 Z110 (the
    # document's "X24 Z110" does not follow from its program, which drills at X0)
    assert ctx.pos == (0.0, 110.0)


def test_lcyc83_document_example_chip_removal():
    r = {101: 155, 102: 1, 103: 150, 104: 5, 105: 0, 109: 0, 110: 100, 111: 20, 107: 500,
         127: 1, 108: 400}
    ctx = run("LCYC83", r, (0.0, 155.0), plane=17)
    feeds = [(p[1], f) for (k, p), f in zip([m for m in ctx.moves if m[0] == "feed"], ctx.feeds)]
    # strokes 50, 30, 20, 20 then the 25 left split in two: Z100 70 50 30 17.5 5
    assert [round(z, 6) for z, _ in feeds] == [100.0, 70.0, 50.0, 30.0, 17.5, 5.0]
    assert [f for _, f in feeds] == [400, 500, 500, 500, 500, 500]
    # chip removal: back to the safety plane Z151 in rapid, re-entry 145/50 = 2.9 mm before
    rapids = [p[1] for k, p in legs(ctx) if k == "rapid"]
    assert rapids == [151.0, 151.0, 102.9, 151.0, 72.9, 151.0, 52.9, 151.0, 32.9, 151.0, 20.4,
                      155.0]
    assert ctx.pos == (0.0, 155.0)


def test_lcyc83_chip_breaking_backs_off_one_mm():
    r = {101: 10, 102: 2, 103: 0, 104: -30, 110: -10, 111: 0, 107: 0.1, 127: 0, 105: 0.5}
    ctx = run("LCYC83", r, (0.0, 10.0), plane=17)
    zs = [(k, p[1]) for k, p in legs(ctx)]
    assert zs == [("rapid", 2.0), ("feed", -10.0), ("feed", -9.0), ("feed", -20.0),
                  ("feed", -19.0), ("feed", -30.0), ("rapid", 10.0)]
    assert sum(1 for m in ctx.moves if m[0] == "dwell") == 3


def test_drill_strokes_degression():
    assert sc.drill_strokes(50, 145, 20) == [50, 80, 100, 120, 132.5, 145]
    assert sc.drill_strokes(10, 30, 0) == [10, 20, 30]
    assert sc.drill_strokes(10, 15, 0) == [10, 15]
    assert sc.drill_strokes(10, 25, 0) == [10, 17.5, 25]
    assert sc.drill_strokes(30, 30, 5) == [30]
    assert sc.anticipation(20) == 0.6 and sc.anticipation(400) == 7.0


def test_lcyc840_document_example():
    # N20 X35 Z60; R101=60 R102=2 R103=56 R104=15 R106=0.5 R126=3
    ctx = run("LCYC840", {101: 60, 102: 2, 103: 56, 104: 15, 105: 1, 106: 0.5, 126: 3},
              (17.5, 60.0), plane=17)
    assert legs(ctx) == [("rapid", (17.5, 58.0)), ("thread", (17.5, 15.0)),
                         ("thread", (17.5, 58.0)), ("rapid", (17.5, 60.0))]
    assert all(m[2] == 0.5 for m in ctx.moves if m[0] == "thread")


def test_lcyc85_feeds_in_and_out():
    ctx = run("LCYC85", {101: 5, 102: 1, 103: 0, 104: -20, 105: 1, 107: 0.2, 108: 0.5},
              (10.0, 5.0), plane=17)
    assert legs(ctx) == [("rapid", (10.0, 1.0)), ("feed", (10.0, -20.0)), ("feed", (10.0, 1.0)),
                         ("rapid", (10.0, 5.0))]
    assert ctx.feeds == [0.2, 0.5]
    assert ("dwell", 1.0) in ctx.moves


@pytest.mark.parametrize("name", ["LCYC82", "LCYC83", "LCYC840", "LCYC85"])
def test_drilling_alarms(name):
    base = {101: 10, 102: 1, 103: 0, 104: -20, 106: 1, 126: 3, 110: -5, 127: 0}
    assert alarm_of(name, base, plane=18).startswith("17040 ")
    assert alarm_of(name, {**base, 104: 0}, plane=17).startswith("61101 ")
    assert alarm_of(name, {**base, 103: 20}, plane=17).startswith("61101 ")


def test_lcyc83_and_840_own_alarms():
    base = {101: 10, 102: 1, 103: 0, 104: -20, 127: 0}
    assert alarm_of("LCYC83", {**base, 110: -25}, plane=17).startswith("61107 ")
    assert alarm_of("LCYC83", {**base, 110: 0}, plane=17).startswith("61107 ")
    assert "R127" in alarm_of("LCYC83", {**base, 110: -5, 127: 2}, plane=17)
    assert alarm_of("LCYC840", {**base, 126: 3}, plane=17).startswith("61001 ")
    assert alarm_of("LCYC840", {**base, 106: 1, 126: 5}, plane=17).startswith("61102 ")


# --------------------------------------------------------------------------- LCYC95


def chain(*pts_dia):
    """Lines through the points (X diameter, Z)."""
    pts = [(x / 2.0, z) for x, z in pts_dia]
    return [Line(a, b) for a, b in zip(pts, pts[1:])]


def items(segs, approach_from=None):
    out = []
    if approach_from is not None:
        out.append((Line(approach_from, segs[0].start), 9, "rapid"))
    out += [(s, 10 + i, "feed") for i, s in enumerate(segs)]
    return out


def mirror_x(segs):
    return [Line((-s.start[0], s.start[1]), (-s.end[0], s.end[1])) for s in segs]


# a stepped shaft: X20 Z0 -> Z-20 -> X30 -> X40 Z-30 -> Z-50 -> X60
SHAFT = chain((20, 0), (20, -20), (30, -20), (40, -30), (40, -50), (60, -50))


def run95(r105, segs, pos, allowance=0.5, infeed=2.0, retract=1.0, **kw):
    r = {105: r105, 106: allowance, 108: infeed, 109: 0, 110: retract, 111: 0.3, 112: 0.1}
    return run("LCYC95", r, pos, texts={"_CNAME": "KONTUR1"},
               contours={"KONTUR1": items(segs, pos)}, **kw)


def level_cuts(ctx, axis):
    """Feed legs that run along the cut axis (``axis``: 1 = Z, 0 = X): (level, start, end)."""
    out, at = [], None
    for m in ctx.moves:
        if m[0] == "feed" and at is not None and abs(m[1][1 - axis] - at[1 - axis]) < 1e-9 \
                and abs(m[1][axis] - at[axis]) > 1e-6:
            out.append((m[1][1 - axis], at[axis], m[1][axis]))
        if m[0] in ("rapid", "feed", "arc"):
            at = m[1]
    return out


def profile_level(segs, v, axis, sign=1.0):
    """The contour's coordinate along the level axis (signed by ``sign``: the stock lies
    toward +sign) where the cut coordinate (``axis``) is ``v``: the highest hit."""
    best = -math.inf
    for s in segs:
        a, b = s.start, s.end
        lo, hi = sorted((a[axis], b[axis]))
        if lo - 1e-9 <= v <= hi + 1e-9:
            if abs(b[axis] - a[axis]) < 1e-12:
                best = max(best, sign * a[1 - axis], sign * b[1 - axis])
            else:
                t = (v - a[axis]) / (b[axis] - a[axis])
                best = max(best, sign * (a[1 - axis] + t * (b[1 - axis] - a[1 - axis])))
    return best


def assert_no_gouge(ctx, segs, cut_axis, cut_sign, lvl_sign, allowance):
    """No feed ends inside the contour + allowance (the allowance is a translation by R106
    toward the stock along the level axis and against the cut)."""
    checked = 0
    for m in ctx.moves:
        if m[0] not in ("feed", "arc"):
            continue
        p = m[1]
        v = p[cut_axis] + cut_sign * allowance - cut_sign * 1e-4  # a point on an offset wall
        floor = profile_level(segs, v, cut_axis, lvl_sign)      # belongs to the face ahead
        if floor > -math.inf:
            assert lvl_sign * p[1 - cut_axis] >= floor + allowance - 1e-6, p
            checked += 1
    assert checked > 5


def test_lcyc95_longitudinal_external_roughing_levels_and_allowance():
    ctx = run95(1, SHAFT, (40.0, 5.0))
    cuts = level_cuts(ctx, 1)
    # the start level: the contour's top X60 (r 30) + R106 0.5 + R110 1 = r 31.5; equal
    # depths not over R108 2 down to the deepest contour level r 10 + 0.5: 21 / 11 = 1.909
    levels = sorted({round(c[0], 6) for c in cuts}, reverse=True)
    step = 21.0 / 11
    assert levels[:3] == [round(31.5 - step * k, 6) for k in (1, 2, 3)]
    assert all(c[2] < c[1] for c in cuts)  # every cut toward -Z
    assert_no_gouge(ctx, SHAFT, 1, -1.0, 1.0, 0.5)
    assert ctx.pos == (31.5, 1.5)  # back on the start point
    assert set(f for f in ctx.feeds) == {0.3}


def test_lcyc95_finishing_follows_the_contour_at_the_finishing_feed():
    ctx = run95(5, SHAFT, (40.0, 5.0))
    ends = [m[1] for m in ctx.moves if m[0] == "feed"]
    assert [(round(x, 6), round(z, 6)) for x, z in ends] == \
        [(10.0, 0.0), (10.0, -20.0), (15.0, -20.0), (20.0, -30.0), (20.0, -50.0), (30.0, -50.0)]
    assert set(ctx.feeds) == {0.1}
    assert ctx.pos == (31.5, 1.5)


def test_lcyc95_complete_roughs_then_finishes():
    ctx = run95(9, SHAFT, (40.0, 5.0))
    assert set(ctx.feeds) == {0.3, 0.1}
    assert ctx.feeds.index(0.1) > max(i for i, f in enumerate(ctx.feeds) if f == 0.3)


def test_lcyc95_contour_written_backwards_is_the_same_job():
    fwd = run95(1, SHAFT, (40.0, 5.0))
    back = run95(1, [s.reversed() for s in reversed(SHAFT)], (40.0, 5.0))
    assert level_cuts(fwd, 1) == level_cuts(back, 1)


def test_lcyc95_internal_longitudinal():
    # a bore from X20: X60 at the front, stepping in to X20 at Z-50
    hole = chain((60, 0), (60, -20), (50, -20), (40, -30), (40, -50), (20, -50))
    ctx = run95(3, hole, (5.0, 5.0))
    cuts = level_cuts(ctx, 1)
    assert cuts and all(c[2] < c[1] for c in cuts)
    assert_no_gouge(ctx, hole, 1, -1.0, -1.0, 0.5)
    levels = sorted({round(c[0], 6) for c in cuts})
    # start level r 10 - 0.5 - 1 = 8.5; the last level at the deepest r 30 - 0.5
    assert levels[-1] == pytest.approx(29.5) and levels[0] > 8.5


def test_lcyc95_face_external_cuts_along_x():
    # the front of a flange, X60 down to the centre: Z-10 at the rim, Z0 at the centre
    face = chain((60, -10), (40, -10), (40, -5), (20, -5), (20, 0), (0, 0))
    ctx = run95(2, face, (40.0, 10.0))
    cuts = level_cuts(ctx, 0)
    assert cuts and all(c[2] < c[1] for c in cuts)  # toward the centre
    assert_no_gouge(ctx, face, 0, -1.0, 1.0, 0.5)
    # levels step down in Z from the start level Z0 + 0.5 + 1 toward the rim's Z-10 + 0.5
    levels = sorted({round(c[0], 6) for c in cuts})
    assert levels[0] == pytest.approx(-9.5) and levels[-1] < 1.5


def test_lcyc95_face_internal_cuts_outward():
    # an inner face at the bottom of a counterbore: X20 at Z-10 out to X60 at Z0
    face = chain((20, -10), (40, -10), (40, -5), (60, -5), (60, 0), (80, 0))
    ctx = run95(4, face, (5.0, 10.0))
    cuts = level_cuts(ctx, 0)
    assert cuts and all(c[2] > c[1] for c in cuts)  # outward
    assert_no_gouge(ctx, face, 0, 1.0, 1.0, 0.5)


@pytest.mark.parametrize("r105", [1, 2, 3, 4])
def test_lcyc95_roughing_ends_with_the_offset_contour(r105):
    shapes = {1: SHAFT, 3: chain((60, 0), (60, -20), (50, -20), (40, -30), (40, -50), (20, -50)),
              2: chain((60, -10), (40, -10), (40, -5), (20, -5), (20, 0), (0, 0)),
              4: chain((20, -10), (40, -10), (40, -5), (60, -5), (60, 0), (80, 0))}
    segs = shapes[r105]
    ctx = run95(r105, segs, (45.0, 10.0) if r105 != 3 else (5.0, 10.0))
    ends = {(round(m[1][0], 6), round(m[1][1], 6)) for m in ctx.moves if m[0] == "feed"}
    face = r105 in (2, 4)
    lvl = [0.0, 0.0]
    lvl[1 if face else 0] = -0.5 if r105 == 3 else 0.5
    cut = [0.0, 0.0]
    d = segs[-1].end[0 if face else 1] - segs[0].start[0 if face else 1]
    cut[0 if face else 1] = 0.5 if d > 0 else -0.5
    off = (lvl[0] - cut[0], lvl[1] - cut[1])
    # every corner of the contour + allowance is reached by the last roughing pass
    for s in segs:
        p = (round(s.end[0] + off[0], 6), round(s.end[1] + off[1], 6))
        assert p in ends, p


def test_lcyc95_alarms():
    assert alarm_of("LCYC95", {105: 13, 108: 1}, texts={"_CNAME": "K"}).startswith("61002 ")
    assert alarm_of("LCYC95", {105: 1, 108: 0}, texts={"_CNAME": "K"}).startswith("61610 ")
    assert alarm_of("LCYC95", {105: 1, 108: 1}).startswith("61606 ")
    under = chain((20, 0), (20, -20), (30, -10), (40, -30))  # turns back toward +Z
    msg = alarm_of("LCYC95", {105: 1, 108: 1}, pos=(40.0, 5.0), texts={"_CNAME": "K"},
                   contours={"K": items(under, (40.0, 5.0))})
    assert msg.startswith("61605 ") and "line 11" in msg
    assert alarm_of("LCYC95", {105: 1, 108: 1}, texts={"_CNAME": "K"},
                    diameter_mode=False).startswith("17040 ")


# --------------------------------------------------------------------------- LCYC97


def test_thread_depths_constant_area_sum_to_depth():
    d = sc.thread_depths(1.3, 0.1, 6)
    assert len(d) == 7 and d[-1] == pytest.approx(1.3) and d[-2] == pytest.approx(1.2)
    # constant chip area: the n-th depth squared grows linearly
    sq = [x * x for x in d[:6]]
    assert all(b - a == pytest.approx(sq[0]) for a, b in zip([0.0] + sq, sq))


def test_lcyc97_external_thread_passes():
    r = {100: 42, 101: 0, 102: 42, 103: -35, 104: 2, 105: 1, 106: 0.1, 109: 4, 110: 2,
         111: 1.23, 112: 0, 113: 4, 114: 1}
    ctx = run("LCYC97", r, (30.0, 10.0))
    threads = [m for m in ctx.moves if m[0] == "thread"]
    assert len(threads) == 5
    ends = [m[1] for m in threads]
    assert all(z == pytest.approx(-37.0) for _, z in ends)  # R103 + run-out R110
    depths = [21.0 - x for x, _ in ends]
    assert depths[-1] == pytest.approx(1.23) and depths[-2] == pytest.approx(1.13)
    # every pass starts at the run-in point Z4 on its own depth
    starts = [ctx.moves[i - 1][1] for i, m in enumerate(ctx.moves) if m[0] == "thread"]
    assert all(z == pytest.approx(4.0) for _, z in starts)
    assert [21.0 - x for x, _ in starts] == pytest.approx(depths)
    assert all(m[2] == 2 for m in threads)
    assert ctx.pos == pytest.approx((22.0, 4.0))


def test_lcyc97_taper_multi_start_internal():
    r = {100: 30, 101: 0, 102: 34, 103: -20, 104: 3, 105: 2, 106: 0, 109: 0, 110: 0,
         111: 1, 112: 30, 113: 2, 114: 2}
    ctx = run("LCYC97", r, (10.0, 5.0))
    threads = [m for m in ctx.moves if m[0] == "thread"]
    assert len(threads) == 4
    assert [m[3] for m in threads] == [30.0, 210.0, 30.0, 210.0]
    starts = [ctx.moves[i - 1][1] for i, m in enumerate(ctx.moves) if m[0] == "thread"]
    # internal: the crest is the bore R100/R102; the passes go outward to crest + R111
    assert starts[-1] == pytest.approx((16.0, 0.0))
    assert threads[-1][1] == pytest.approx((18.0, -20.0))


def test_lcyc97_alarms():
    r = {100: 42, 101: 0, 102: 42, 103: -35, 104: 2, 105: 1, 111: 1.2, 113: 3, 114: 1}
    assert alarm_of("LCYC97", {**r, 105: 3}).startswith("61002 ")
    assert alarm_of("LCYC97", {**r, 104: 0}).startswith("61001 ")
    assert "R111" in alarm_of("LCYC97", {**r, 111: 0})
    assert "R113" in alarm_of("LCYC97", {**r, 113: 0})
    assert alarm_of("LCYC97", r, diameter_mode=False).startswith("17040 ")


# --------------------------------------------------------------------------- LCYC93


def groove_ctx(r105=1, over=None):
    r = {100: 40, 101: -20, 105: r105, 106: 0.2, 107: 3, 108: 2, 114: 10, 115: 4, 116: 0,
         117: 0, 118: 0, 119: 0.5}
    r.update(over or {})
    return run("LCYC93", r, (25.0, 0.0))


def test_lcyc93_external_groove_covers_width_and_depth():
    ctx = groove_ctx()
    feeds = [m[1] for m in ctx.moves if m[0] == "feed"]
    xs = [x for x, _ in feeds]
    zs = [z for _, z in feeds]
    # the finished groove: X40 -> 4 deep (r 16), Z-20 .. Z-10 with a 3 mm tool: the tool's
    # reference corner spans Z-20 .. Z-13 and reaches r 16 exactly, never deeper
    assert min(xs) == pytest.approx(16.0)
    assert min(zs) == pytest.approx(-20.0) and max(zs) == pytest.approx(-13.0)
    # roughing plunges: 2 mm infeeds to 4 - 0.2 deep with a 1 mm back-off between
    rough = [x for x in xs if x > 16.0 + 1e-9]
    assert pytest.approx(16.2) in rough and pytest.approx(19.0) in rough
    cols = sorted({round(z, 6) for (x, z) in feeds if abs(x - 16.2) < 1e-9})
    assert cols[0] == pytest.approx(-19.8) and cols[-1] == pytest.approx(-13.2)
    assert all(b - a <= 3.0 + 1e-9 for a, b in zip(cols, cols[1:]))
    assert any(m[0] == "dwell" and m[1] == 0.5 for m in ctx.moves)
    assert ctx.pos == pytest.approx((21.0, -20.0))


def test_lcyc93_right_start_and_internal_mirror():
    right = groove_ctx(5)
    zs = [m[1][1] for m in right.moves if m[0] == "feed"]
    # the groove Z-30 .. Z-20; the programmed point is the tool's -Z corner (a tip 3 tool,
    # or no tool): from Z-30 to Z-23
    assert max(zs) == pytest.approx(-23.0) and min(zs) == pytest.approx(-30.0)
    internal = run("LCYC93", {100: 40, 101: -20, 105: 3, 107: 3, 108: 2, 114: 10, 115: 4},
                   (15.0, 0.0))
    xs = [m[1][0] for m in internal.moves if m[0] == "feed"]
    assert max(xs) == pytest.approx(24.0)


def test_lcyc93_angled_flanks_and_chamfers_stay_in_the_form():
    ctx = groove_ctx(1, {116: 15, 117: 0.5, 118: 0.5})
    t = math.tan(math.radians(15))
    for m in ctx.moves:
        if m[0] != "feed":
            continue
        x, z = m[1]
        d = 20.0 - x
        if d <= 1e-9:
            continue
        w = z + 20.0  # the reference corner; the tool spans w .. w + 3
        assert w >= d * t - 1e-6 - 0.5 and w + 3 <= 10 - d * t + 1e-6 + 0.5


def test_lcyc93_alarms():
    assert alarm_of("LCYC93", {105: 9, 107: 3, 114: 10, 115: 4}).startswith("61002 ")
    assert alarm_of("LCYC93", {105: 1, 107: 12, 114: 10, 115: 4}).startswith("61602 ")
    assert alarm_of("LCYC93", {105: 1, 107: 3, 114: 10, 115: 4, 116: 60}).startswith("61603 ")
    assert alarm_of("LCYC93", {105: 1, 107: 3, 114: 0, 115: 4}).startswith("61603 ")
    assert alarm_of("LCYC93", {105: 1, 107: 3, 114: 10, 115: 4},
                    diameter_mode=False).startswith("17040 ")


# --------------------------------------------------------------------------- LCYC94


def test_lcyc94_form_e_external_shoulder_on_the_left():
    # a shaft X40 meeting a shoulder face at Z-30 that lies toward -Z: tip position 3
    ctx = run("LCYC94", {100: 40, 101: -30, 105: 55, 107: 3}, (30.0, 0.0))
    pts = [m[1] for m in ctx.moves if m[0] in ("feed", "arc")]
    # DIN 509 for 18 < d <= 80: r 0.6, t 0.3, f 2.5; the run-out at 15 degrees
    assert pts[0] == pytest.approx((20.0, -27.5))
    run_out = 0.3 / math.tan(math.radians(15))
    assert pts[1] == pytest.approx((19.7, -27.5 - run_out))
    assert pts[2] == pytest.approx((19.7, -29.4))
    assert pts[3] == pytest.approx((20.3, -30.0))  # the radius ends on the shoulder face
    assert [m[0] for m in ctx.moves if m[0] in ("feed", "arc")][3] == "arc"
    assert min(p[0] for p in pts) == pytest.approx(19.7)  # never deeper than t
    assert max(p[1] for p in pts) <= -27.5 + 1e-9 and min(p[1] for p in pts) >= -30.0 - 1e-9
    assert ctx.pos == pytest.approx((21.0, -26.5))


@pytest.mark.parametrize("d,r,t,f", [(3.0, 0.2, 0.1, 1.0), (8.0, 0.2, 0.2, 2.0),
                                     (12.0, 0.6, 0.2, 2.0), (100.0, 1.0, 0.4, 4.0)])
def test_lcyc94_sizes_follow_the_din_509_table(d, r, t, f):
    # the DIN 509 E sizes by diameter (up to 3, 3-10, 10-18, above 80 mm): length f from
    # the face, depth t, radius r ending on the face
    ctx = run("LCYC94", {100: d, 101: -30, 105: 55, 107: 3}, (d, 0.0))
    pts = [m[1] for m in ctx.moves if m[0] in ("feed", "arc")]
    assert pts[0] == pytest.approx((d / 2, -30.0 + f))
    assert min(p[0] for p in pts) == pytest.approx(d / 2 - t)
    assert pts[2] == pytest.approx((d / 2 - t, -30.0 + r))
    assert pts[3] == pytest.approx((d / 2 - t + r, -30.0))


def test_lcyc94_form_f_cuts_into_the_face_internal_mirror():
    # a bore X60 against a face at Z-20 toward -Z, boring bar: tip position 2 (+X, -Z)
    ctx = run("LCYC94", {100: 60, 101: -20, 105: 56, 107: 2}, (20.0, 5.0))
    pts = [m[1] for m in ctx.moves if m[0] in ("feed", "arc")]
    assert max(p[0] for p in pts) == pytest.approx(30.3)  # into the bore wall by t
    assert min(p[1] for p in pts) == pytest.approx(-20.2)  # into the face by t2
    face = [p for p in pts if abs(p[1] + 20.0) < 1e-9]
    assert face  # the 8 degree flank comes back to the face plane


def test_lcyc94_alarms():
    assert alarm_of("LCYC94", {100: 40, 105: 57, 107: 3}).startswith("61609 ")
    assert alarm_of("LCYC94", {100: 40, 105: 55, 107: 5}).startswith("61608 ")
    assert alarm_of("LCYC94", {100: 2, 105: 55, 107: 3}).startswith("61601 ")
    assert alarm_of("LCYC94", {100: 40, 105: 55, 107: 3},
                    diameter_mode=False).startswith("17040 ")


def test_lcyc95_finishing_compensates_the_nose_radius():
    # a taper X30 Z-20 -> X40 Z-30 finished with a 0.8 mm nose, tip 3: the imaginary tip
    # runs parallel to the taper, shifted so that the nose touches it (G42 for an OD cut)
    class Nose(Ctx802):
        def tool_nose(self):
            return (0.8, 3)

    segs = chain((20, 0), (20, -20), (30, -20), (40, -30), (40, -50), (60, -50))
    ctx = Nose("LCYC95", {105: 5, 110: 1, 112: 0.1}, (40.0, 5.0), texts={"_CNAME": "K"},
               contours={"K": items(segs, (40.0, 5.0))})
    sc.CYCLES["LCYC95"](ctx)
    feeds = [m[1] for m in ctx.moves if m[0] in ("feed", "arc")]
    # on the cylinders and faces the tip P lies on the contour (tip 3 touches both axes)
    assert any(abs(x - 10.0) < 1e-9 for x, z in feeds)
    assert any(abs(x - 20.0) < 1e-9 for x, z in feeds)
    # on the taper X30 Z-20 -> X40 Z-30 the nose centre (P + (r, r) for tip 3) runs r off the
    # line, on the stock side
    kinds = [m[0] for m in ctx.moves if m[0] in ("feed", "arc")]
    i = next(k for k, (x, z) in enumerate(feeds) if kinds[k] == "feed" and 19.0 < x < 21.0
             and -31.0 < z < -29.0)
    ux, uz = 5 / math.sqrt(125), -10 / math.sqrt(125)
    for x, z in (feeds[i - 1], feeds[i]):
        cx, cz = x + 0.8 - 15.0, z + 0.8 + 20.0
        assert cx * uz - cz * ux == pytest.approx(-0.8)
    assert ctx.pos == (31.0, 1.0)


# --------------------------------------------------------------------------- end to end


def run802(text: str):
    """Run a program through the 802 reader (skips while the dialect is not registered)."""
    from hnc_cam import dialect, nc
    if "siemens802" not in dialect.names():
        pytest.skip("the siemens802 dialect is not registered yet")
    return nc.run(text, dialect="siemens802")


def cyc(tp, name):
    return [m for m in tp.moves if m.op == name]


def ends(moves):
    return [(m.kind, (round(m.end[0], 6), round(m.end[1], 6))) for m in moves]


LCYC82_DOC = """%_N_LCYC82_MPF
N10 G0 G18 G90 F500 T2 D1 S500 M4 ;
N20 Z110 X0
N25 G17
N30 R101=110 R102=4 R103=102 R104=75
N35 R105=2
N40 LCYC82
N50 M2
"""

LCYC83_DOC = """%_N_LCYC83_MPF
N100 G0 G18 G90 T4 S500 M3
N110 Z155
N120 X0
N125 G17
N130 R101=155 R102=1 R103=150 R104=5 R105=0 R109=0 R110=100
N135 R111=20 R107=500 R127=1 R108=400
N140 LCYC83
N199 M2
"""

LCYC840_DOC = """%_N_LCYC840_MPF
N10 G0 G17 G90 S300 M3 D1 T1
N20 X35 Z60
N30 R101=60 R102=2 R103=56 R104=15 R105=1
N40 R106=0.5 R126=3
N45 LCYC840
N50 M2
"""


def test_document_lcyc82_runs():
    tp = run802(LCYC82_DOC)
    moves = cyc(tp, "LCYC82")
    assert ends(moves) == [("rapid", (0.0, 106.0)), ("line", (0.0, 75.0)), ("dwell", (0.0, 75.0)),
                           ("rapid", (0.0, 110.0))]
    assert moves[2].duration == pytest.approx(2.0)


def test_document_lcyc83_runs():
    tp = run802(LCYC83_DOC)
    lines = [m.end[1] for m in cyc(tp, "LCYC83") if m.kind == "line"]
    assert lines == pytest.approx([100.0, 70.0, 50.0, 30.0, 17.5, 5.0])
    assert cyc(tp, "LCYC83")[-1].end == pytest.approx((0.0, 155.0))


def test_document_lcyc840_runs():
    tp = run802(LCYC840_DOC)
    moves = cyc(tp, "LCYC840")
    assert [m.kind for m in moves] == ["rapid", "thread", "thread", "rapid"]
    assert moves[1].end == pytest.approx((17.5, 15.0)) and moves[2].end == pytest.approx((17.5, 58.0))
    # in with M3 as programmed, out with the spindle reversed, stopped after the cycle
    assert [m.spindle_dir for m in moves] == [3, 3, 4, 4]
    after = [m for m in tp.moves if m.line > moves[-1].line]
    assert all(m.spindle_dir == 5 for m in after)


STEPPED = """%_N_SHAFT_MPF
;$PATH=/_N_MPF_DIR
N10 G18 G23 G90 G95 T1 D1 S800 M3
N20 G0 X50 Z5
N30 _CNAME="KONTUR1"
N40 R105=9 R106=0.3 R108=1.5 R109=0 R110=1 R111=0.25 R112=0.1
N50 LCYC95
N60 G0 X80 Z50
N70 M2
%_N_KONTUR1_SPF
;$PATH=/_N_SPF_DIR
N100 G1 X16 Z0
N110 X20 Z-2
N120 Z-20
N130 G3 X30 Z-25 CR=5
N140 G1 X36 Z-40
N150 Z-60
N160 X46
N170 RET
"""


def test_lcyc95_program_verifies_against_its_part():
    from hnc_cam.geometry import TurnedProfile
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Stock
    tp = run802(STEPPED)
    assert cyc(tp, "LCYC95") and not tp.warnings
    prof = TurnedProfile(outside=[
        Line((0, 0), (8, 0)), Line((8, 0), (10, -2)), Line((10, -2), (10, -20)),
        Arc((10, -20), (15, -25), (10, -25), False), Line((15, -25), (18, -40)),
        Line((18, -40), (18, -60)), Line((18, -60), (0, -60))], name="stepped")
    m = simulate(tp, Stock.parse("45x62+0"), None, model=prof)
    rep = verify(m, prof, tol=0.01)
    assert rep.passed, rep.summary()
    assert rep.max_overcut_mm <= 0.01 and rep.max_undercut_mm <= 0.01


def test_lcyc95_roughing_only_leaves_the_allowance():
    from hnc_cam.geometry import TurnedProfile
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Stock
    tp = run802(STEPPED.replace("R105=9", "R105=1"))
    prof = TurnedProfile(outside=[
        Line((0, 0), (8, 0)), Line((8, 0), (10, -2)), Line((10, -2), (10, -20)),
        Arc((10, -20), (15, -25), (10, -25), False), Line((15, -25), (18, -40)),
        Line((18, -40), (18, -60)), Line((18, -60), (0, -60))], name="stepped")
    m = simulate(tp, Stock.parse("45x62+0"), None, model=prof)
    rep = verify(m, prof, tol=0.01)
    # the allowance is left (the part is not finished) and nothing is cut into it
    assert not rep.passed and rep.max_overcut_mm <= 0.01


def test_lcyc95_contour_alarm_names_the_line():
    bad = STEPPED.replace("N140 G1 X36 Z-40", "N140 G1 X36 Z-10")  # runs back toward +Z
    from hnc_cam.errors import NCError
    with pytest.raises(NCError) as exc:
        run802(bad)
    assert "61605" in str(exc.value) and "line 16" in str(exc.value)  # N140


def test_lcyc97_and_lcyc93_in_a_program():
    tp = run802("""%_N_T_MPF
N10 G18 G23 G90 G95 T1 D1 S500 M3
N20 G0 X50 Z10
N30 R100=42 R101=0 R102=42 R103=-30 R104=2 R105=1 R106=0.05 R109=4 R110=2
N40 R111=1.23 R112=0 R113=5 R114=1
N50 LCYC97
N60 G0 X50 Z-30
N70 R100=42 R101=-40 R105=1 R106=0.1 R107=3 R108=1 R114=8 R115=3 R116=0 R117=0 R118=0 R119=0
N80 LCYC93
N90 M2
""")
    th = [m for m in cyc(tp, "LCYC97") if m.kind == "thread"]
    assert len(th) == 6 and th[-1].end == pytest.approx((21.0 - 1.23, -32.0))
    gr = [m for m in cyc(tp, "LCYC93") if m.kind == "line"]
    assert min(m.end[0] for m in gr) == pytest.approx(18.0)
    assert min(m.end[1] for m in gr) == pytest.approx(-40.0)
    assert max(m.end[1] for m in gr) == pytest.approx(-35.0)


def test_lcyc840_reverses_and_stops_the_spindle_where_the_context_can():
    class Spin(Ctx802):
        def spindle(self, m):
            self.moves.append(("spindle", m))

    ctx = Spin("LCYC840", {101: 60, 102: 2, 103: 56, 104: 15, 106: 0.5, 126: 4}, (0.0, 60.0),
               plane=17)
    sc.CYCLES["LCYC840"](ctx)
    kinds = [m[0] if m[0] != "spindle" else m for m in ctx.moves]
    assert kinds == ["rapid", ("spindle", 4), "thread", ("spindle", 3), "thread", "rapid",
                     ("spindle", 5)]


def test_lcyc93_approaches_axis_by_axis():
    ctx = groove_ctx()
    # from X50 Z0: along Z at X50 to the first plunge column, then down to 1 mm above X40
    assert ctx.moves[0] == ("rapid", (25.0, -19.8))
    assert ctx.moves[1] == ("rapid", (21.0, -19.8))


def test_pass_counts_are_bounded_before_planning():
    assert "cycle_passes" in alarm_of("LCYC93", {100: 40, 101: -20, 105: 1, 107: 1e-9, 108: 1,
                                                 114: 10, 115: 4})
    assert "cycle_passes" in alarm_of("LCYC93", {100: 40, 101: -20, 105: 1, 107: 3, 108: 1e-9,
                                                 114: 10, 115: 4})
    assert "cycle_passes" in alarm_of("LCYC95", {105: 1, 108: 1e-9}, pos=(40.0, 5.0),
                                      texts={"_CNAME": "K"}, contours={"K": items(SHAFT, (40.0, 5.0))})
    assert "cycle_passes" in alarm_of("LCYC83", {101: 10, 103: 0, 104: -30, 110: -1e-7},
                                      plane=17)
    assert "cycle_passes" in alarm_of("LCYC97", {100: 42, 102: 42, 103: -35, 104: 2, 105: 1,
                                                 111: 1, 113: 9000, 114: 9})
    assert "finite" in alarm_of("LCYC82", {101: math.inf, 103: 0, 104: -5}, plane=17)


@pytest.mark.parametrize("name", sorted(sc.CYCLES))
def test_random_parameters_give_moves_or_an_alarm(name):
    """Random transfer parameters (seeded): every run ends in legs or a cycle alarm, never
    another exception, and within the pass limit."""
    import random
    rnd = random.Random(int(name[4:]))
    values = [0, 1, -1, 0.5, 2, 3, 4, 5, 9, 12, 55, 56, 89.999, 90, 100, -50, 1e-6, 1e6, 0.001]
    bore = chain((60, 0), (60, -20), (40, -30), (20, -30))
    for _ in range(150):
        r = {n: rnd.choice(values) if rnd.random() < 0.7 else rnd.uniform(-100, 100)
             for n in list(range(100, 120)) + [126, 127]}
        contour = rnd.choice([SHAFT, bore, SHAFT[:1], [s.reversed() for s in reversed(SHAFT)]])
        ctx = Ctx802(name, r, (rnd.uniform(-5, 40), rnd.uniform(-60, 20)),
                     plane=17 if name in ("LCYC82", "LCYC83", "LCYC840", "LCYC85") else 18,
                     texts={"_CNAME": "K"}, max_passes=2000,
                     contours={"K": items(contour, None)})
        try:
            sc.CYCLES[name](ctx)
        except NCError:
            continue
        assert len(ctx.moves) < 200_000


def _verify(tp, pts, stock):
    from hnc_cam.geometry import TurnedProfile
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Stock
    prof = TurnedProfile(outside=[Line(a, b) for a, b in zip(pts, pts[1:])], name="part")
    return verify(simulate(tp, Stock.parse(stock), None, model=prof), prof, tol=0.01)


@pytest.mark.parametrize("r105,z", [(1, -28), (5, -20)])
def test_lcyc93_groove_verifies_with_the_grooving_tool(r105, z):
    # the library's 3 mm grooving tool (T7, tip 3): an 8 x 3 groove in a 40 mm bar, from
    # its left edge (R105=1 at Z-28) or its right edge (R105=5 at Z-20)
    tp = run802(f"""%_N_GROOVE_MPF
N10 G18 G23 G90 G95 T7 D1 S600 M3 F0.05
N20 G0 X50 Z5
N30 R100=40 R101={z} R105={r105} R106=0.1 R107=3 R108=1.5 R114=8 R115=3 R116=0 R117=0
N35 R118=0 R119=0.2
N40 LCYC93
N50 G0 X60 Z20
N60 M2
""")
    rep = _verify(tp, [(0, 0), (20, 0), (20, -20), (17, -20), (17, -28), (20, -28), (20, -50),
                       (0, -50)], "40x50+0")
    assert rep.passed, rep.summary()


def test_lcyc95_face_complete_verifies():
    tp = run802("""%_N_FACE_MPF
N10 G18 G23 G90 G95 T1 D1 S800 M3
N20 G0 X90 Z5
N30 _CNAME="KF"
N40 R105=10 R106=0.3 R108=1.5 R109=0 R110=1 R111=0.25 R112=0.1
N50 LCYC95
N60 G0 X90 Z50
N70 M2
%_N_KF_SPF
N100 G1 X80 Z-10
N110 X50
N120 Z-6
N130 X30 Z-4
N140 X20
N150 Z0
N160 X0
N170 RET
""")
    rep = _verify(tp, [(0, 0), (10, 0), (10, -4), (15, -4), (25, -6), (25, -10), (40, -10),
                       (40, -30), (0, -30)], "80x30+0")
    assert rep.passed, rep.summary()


#: a shaft with a relief: a 30 degree flank (to Z) down from the 30 mm diameter into a 16 mm
#: relief and a flank back up to 36 mm; roughed with the 35 degree copying insert (T5)
RELIEF = """%_N_RELIEF_MPF
N10 G18 G23 G90 G95 T5 D1 S800 M3
N20 G0 X50 Z5
N30 _CNAME="KR"
N40 R105={r105} R106=1 R108=1.5 R109={r109} R110=1 R111=0.25 R112=0.1
N50 LCYC95
N60 G0 X80 Z50
N70 M2
%_N_KR_SPF
N100 G1 X20 Z0
N110 X30 Z-5
N120 Z-12
N130 X16 Z-24
N140 Z-30
N150 X36 Z-34
N160 Z-40
N170 X46
N180 RET
"""
RELIEF_PART = [(0, 0), (10, 0), (15, -5), (15, -12), (8, -24), (8, -30), (18, -34), (18, -40),
               (0, -40)]


def _relief_entries(tp):
    """(start, end, angle to Z in degrees) of each move that enters a relief pass: a feed
    move down to where a cut along -Z starts, inside the relief (below the flank's top at
    X30 Z-12 + the allowance, above its bottom + the allowance)."""
    ms = [m for m in tp.moves if m.op == "LCYC95"]
    out = []
    for a, b in zip(ms, ms[1:]):
        cut = (b.kind == "line" and abs(b.start[0] - b.end[0]) < 1e-9 and b.end[1] < b.start[1])
        if (a.kind == "line" and cut and a.end[0] < a.start[0] - 1e-9 and a.end[1] < -11.0
                and a.end[0] > 9.0 + 1e-6):
            ang = math.degrees(math.atan2(a.start[0] - a.end[0], abs(a.end[1] - a.start[1])))
            out.append((a.start, a.end, ang))
    return out


@pytest.mark.parametrize("r109", [45.0, 80.0])
def test_lcyc95_enters_a_relief_at_the_insertion_angle(r109):
    tp = run802(RELIEF.format(r105=9, r109=r109))
    entries = _relief_entries(tp)
    # the relief's levels below the flank's top (radius 16 = 15 + R106): 4 passes 16/11 mm
    # apart, each entered along a line at R109 to Z ending on the allowance-offset flank
    assert len(entries) == 4
    for start, end, ang in entries:
        assert ang == pytest.approx(r109, abs=1e-6)
        # the end on the offset flank (15, -12) -> (8, -24) moved by (1, 1)
        assert end[1] == pytest.approx(-11.0 - (16.0 - end[0]) * 12.0 / 7.0, abs=1e-6)
        # from the level above (the roughing depth), which the pass above has cleared
        assert start[0] - end[0] == pytest.approx(entries[0][0][0] - entries[0][1][0], abs=1e-6)
    rep = _verify(tp, RELIEF_PART, "45x42+0")
    assert rep.passed, rep.summary()


def test_lcyc95_relief_insertion_zero_plunges_straight_and_steep_flanks_stay_straight():
    straight = _relief_entries(run802(RELIEF.format(r105=9, r109=0)))
    assert len(straight) == 4 and all(a == pytest.approx(90.0) for _, _, a in straight)
    # an entry at 20 degrees would run into the 30 degree flank: the tool plunges straight
    # in front of it (the entry is never shallower than the flank it ends on)
    shallow = run802(RELIEF.format(r105=9, r109=20))
    got = _relief_entries(shallow)
    assert len(got) == len(straight)
    for (s1, e1, _), (s0, e0, _) in zip(got, straight):
        assert s1 == pytest.approx(s0, abs=1e-9) and e1 == pytest.approx(e0, abs=1e-9)
    rep = _verify(shallow, RELIEF_PART, "45x42+0")
    assert rep.passed, rep.summary()
