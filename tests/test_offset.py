"""The exact offset of a chain (hnc_cam.geometry.offset): closed-form corners, arcs, tapers,
vanishing features and their departure reports, and a randomised property check."""
from __future__ import annotations

import math

import pytest
from hypothesis import given, settings, strategies as st

from hnc_cam.geometry import Arc, Line, chain_is_connected, dist
from hnc_cam.geometry.offset import offset_chain, offset_segment, side_sign


def chain_of(*pts):
    return [Line(a, b) for a, b in zip(pts, pts[1:])]


def dense_points(segs, n=200):
    for g in segs:
        for k in range(n + 1):
            yield g.point_at(k / n)


def dist_to_chain(p, chain):
    return min(g.distance_to(p) for g in chain)


def assert_at_exactly_r(res, chain, r, tol=1e-9):
    assert res.segments, "empty offset"
    assert chain_is_connected(res.segments, 1e-9)
    for p in dense_points(res.segments):
        assert dist_to_chain(p, chain) == pytest.approx(r, abs=tol), p


def assert_seg(seg, kind, start, end, center=None, radius=None, tol=1e-9):
    assert seg.kind == kind
    assert dist(seg.start, start) < tol, (seg.start, start)
    assert dist(seg.end, end) < tol, (seg.end, end)
    if center is not None:
        assert dist(seg.center, center) < tol
    if radius is not None:
        assert seg.radius == pytest.approx(radius, abs=tol)


def test_side_names():
    assert side_sign("left") == side_sign(41) == 1
    assert side_sign("right") == side_sign(42) == side_sign(-1) == -1
    with pytest.raises(ValueError):
        side_sign("up")


@pytest.mark.parametrize("r", [0.4, 0.8])
def test_concave_corner_trimmed_to_the_intersection(r):
    # turning toward -Z at x=10, then a shoulder up: tool above (G42) -> concave corner
    ch = chain_of((10, 0), (10, -10), (15, -10))
    res = offset_chain(ch, r, "right")
    assert len(res.segments) == 2
    assert_seg(res.segments[0], "line", (10 + r, 0), (10 + r, -10 + r))
    assert_seg(res.segments[1], "line", (10 + r, -10 + r), (15, -10 + r))
    assert [o.before for o in res.origins] == [0, 1]
    (d,) = res.departures
    assert d.kind == "corner" and not d.unreachable
    assert d.departure == pytest.approx(r * (math.sqrt(2) - 1), abs=1e-7)
    assert dist(d.at, (10, -10)) < 1e-5
    assert not res.unreachable
    assert_at_exactly_r(res, ch, r)


@pytest.mark.parametrize("r", [0.4, 0.8])
def test_convex_corner_arc_centred_on_the_corner(r):
    ch = chain_of((10, 0), (10, -10), (5, -10))
    res = offset_chain(ch, r, 42)
    assert len(res.segments) == 3
    assert_seg(res.segments[0], "line", (10 + r, 0), (10 + r, -10))
    arc = res.segments[1]
    assert_seg(arc, "arc", (10 + r, -10), (10, -10 - r), center=(10, -10), radius=r)
    assert arc.cw is False and arc.sweep == pytest.approx(math.pi / 2)
    assert res.origins[1].kind == "corner" and (res.origins[1].before, res.origins[1].after) == (0, 1)
    assert_seg(res.segments[2], "line", (10, -10 - r), (5, -10 - r))
    assert res.departures == []
    assert_at_exactly_r(res, ch, r)


@pytest.mark.parametrize("r", [0.4, 0.8])
@pytest.mark.parametrize("deg", [45.0, 30.0])
def test_taper_between_cylinders(r, deg):
    # dia 20 -> taper rising toward -Z at `deg` to the Z axis -> dia 30, tool above
    th = math.radians(deg)
    x0, x1 = 10.0, 15.0
    z0 = -5.0
    z1 = z0 - (x1 - x0) / math.tan(th)
    ch = chain_of((x0, 0), (x0, z0), (x1, z1), (x1, z1 - 10))
    res = offset_chain(ch, r, "right")
    kinds = [g.kind for g in res.segments]
    # concave at the taper foot (trim), convex at its top (arc)
    assert kinds == ["line", "line", "arc", "line"]
    n = (math.cos(th), math.sin(th))  # taper's outward normal (x, z)
    taper_off = res.segments[1]
    # trimmed foot: on x = x0 + r and on the taper shifted by r n
    assert taper_off.start[0] == pytest.approx(x0 + r, abs=1e-9)
    foot_z = z0 + r * math.tan(th / 2)  # closed form of the concave trim
    assert taper_off.start[1] == pytest.approx(foot_z, abs=1e-9)
    assert_seg(taper_off, "line", taper_off.start, (x1 + r * n[0], z1 + r * n[1]))
    assert_seg(res.segments[2], "arc", (x1 + r * n[0], z1 + r * n[1]), (x1 + r, z1),
               center=(x1, z1), radius=r)
    assert res.segments[2].sweep == pytest.approx(th)
    (d,) = res.departures
    assert d.kind == "corner"
    # the fillet left in a concave corner of angle 180-deg: r/sin(half) - r
    half = (math.pi - th) / 2
    assert d.departure == pytest.approx(r / math.sin(half) - r, abs=1e-7)
    assert_at_exactly_r(res, ch, r)


@pytest.mark.parametrize("r", [0.4, 0.8])
def test_convex_and_concave_arcs(r):
    # R15 dome (convex, G03) then an R5 hollow (concave, G02) then a cylinder: fig. 3.3.45
    a1 = Arc((0, 0), (12, -24), (0, -15), False)
    a2 = Arc.from_radius((12, -24), (13, -31), 5, True)
    ch = [a1, a2, Line((13, -31), (13, -40))]
    res = offset_chain(ch, r, "right")
    g = res.segments
    assert [x.kind for x in g] == ["arc", "arc", "arc", "line"]
    assert_seg(g[0], "arc", (0, r), (12 * (15 + r) / 15, -15 - 9 * (15 + r) / 15),
               center=(0, -15), radius=15 + r)
    assert g[1].radius == pytest.approx(5 - r, abs=1e-12) and dist(g[1].center, a2.center) < 1e-12
    # the R5 ends at (13,-31) where the cylinder starts: a convex kink -> corner arc about it
    assert dist(g[2].center, (13, -31)) < 1e-12 and g[2].radius == pytest.approx(r)
    assert_seg(g[3], "line", (13 + r, -31), (13 + r, -40))
    assert res.departures == []
    assert_at_exactly_r(res, ch, r)


def test_offset_segment_arc_sides():
    a = Arc((10, 0), (0, -10), (0, 0), True)  # cw quarter, centre below-left
    assert offset_segment(a, 1, "left").radius == pytest.approx(11)
    assert offset_segment(a, 1, "right").radius == pytest.approx(9)
    assert offset_segment(a, 10, "right") is None


@pytest.mark.parametrize("r", [0.4, 0.8])
def test_inside_radius_smaller_than_nose(r):
    # 90 deg inside fillet R0.3 between the cylinder and a shoulder
    rf = 0.3
    ch = [Line((10, 0), (10, -9.7)), Arc((10, -9.7), (10.3, -10), (10.3, -9.7), True),
          Line((10.3, -10), (15, -10))]
    res = offset_chain(ch, r, "right")
    assert [g.kind for g in res.segments] == ["line", "line"]
    corner = (10 + r, -10 + r)
    assert dist(res.segments[0].end, corner) < 1e-9
    (d,) = res.departures
    assert d.kind == "radius" and d.unreachable and 1 in d.segments
    # nose centre `corner`, fillet centre c: the far side of the fillet is left oversize
    c = (10 + rf, -10 + rf)
    assert d.departure == pytest.approx(dist(corner, c) + rf - r, abs=1e-6)
    assert "smaller than the nose radius" in d.message
    assert_at_exactly_r(res, ch, r)


@pytest.mark.parametrize("r", [0.4, 0.8])
def test_inside_radius_equal_nose_is_exact(r):
    ch = [Line((10, 0), (10, -10 + r)), Arc((10, -10 + r), (10 + r, -10), (10 + r, -10 + r), True),
          Line((10 + r, -10), (15, -10))]
    res = offset_chain(ch, r, "right")
    assert res.departures == []


@pytest.mark.parametrize("r", [0.4, 0.8])
def test_groove_narrower_than_2r(r):
    w = 1.3 * r  # groove width < 2r
    ch = chain_of((10, 0), (10, -10), (8, -10), (8, -10 - w), (10, -10 - w), (10, -20))
    res = offset_chain(ch, r, "right")
    g = res.segments
    assert [x.kind for x in g] == ["line", "arc", "arc", "line"]
    h = math.sqrt(r * r - (w / 2) ** 2)
    cusp = (10 + h, -10 - w / 2)
    assert dist(g[1].end, cusp) < 1e-9 and dist(g[2].start, cusp) < 1e-9
    (d,) = res.departures
    assert d.kind == "groove" and d.segments == (1, 2, 3)
    # farthest: the groove's bottom corners, seen from the cusp
    assert d.departure == pytest.approx(math.hypot(cusp[0] - 8, w / 2) - r, abs=1e-6)
    assert dist(d.start, (10, -10)) < 1e-6 and dist(d.end, (10, -10 - w)) < 1e-6
    assert_at_exactly_r(res, ch, r)


def test_groove_wide_enough_is_cut():
    r = 0.8
    ch = chain_of((10, 0), (10, -10), (8, -10), (8, -12), (10, -12), (10, -20))
    res = offset_chain(ch, r, "right")
    bottom = [g for g, o in zip(res.segments, res.origins) if o.kind == "seg" and o.before == 2]
    assert len(bottom) == 1
    assert_seg(bottom[0], "line", (8 + r, -10 - r), (8 + r, -12 + r))
    assert [d.kind for d in res.departures] == ["corner", "corner"]
    assert not res.unreachable


def test_step_smaller_than_radius_between_corners():
    # short step (0.3) between a convex and a concave corner: the nose cannot touch it
    r = 0.8
    ch = chain_of((10, 0), (10, -10), (9.7, -10), (9.7, -20))
    res = offset_chain(ch, r, "right")
    assert [g.kind for g in res.segments] == ["line", "arc", "line"]
    hit = (9.7 + r, -10 - math.sqrt(r * r - (r - 0.3) ** 2))
    assert dist(res.segments[1].end, hit) < 1e-9
    (d,) = res.departures
    assert d.kind == "groove" and d.segments == (1, 2)
    assert d.departure == pytest.approx(dist((9.7, -10), hit) - r, abs=1e-6)
    assert_at_exactly_r(res, ch, r)


def test_short_face_at_the_end_is_reported_as_end():
    r = 0.8
    ch = chain_of((10, 0), (10, -10), (10.5, -10))
    res = offset_chain(ch, r, "right")
    assert len(res.segments) == 1
    # the nose stops where it would touch the face's outer end (10.5, -10)
    e = (10 + r, -10 + math.sqrt(r * r - (r - 0.5) ** 2))
    assert_seg(res.segments[0], "line", (10 + r, 0), e)
    (d,) = res.departures
    assert d.kind == "end" and d.segments == (0, 1)
    assert d.departure == pytest.approx(dist((10, -10), e) - r, abs=1e-6)


def test_reversal_gets_a_half_circle():
    r = 0.5
    ch = chain_of((10, 0), (12, 0), (10, 0))  # out and back along the same line
    res = offset_chain(ch, r, "right")
    arc = res.segments[1]
    assert arc.kind == "arc" and dist(arc.center, (12, 0)) < 1e-12
    assert abs(arc.sweep) == pytest.approx(math.pi)
    assert dist(arc.point_at(0.5), (12 + r, 0)) < 1e-9  # around the far end


def test_left_side_bore():
    # a bore cut toward -Z with the tool on the left (G41): the offset lies toward the axis
    r = 0.4
    ch = chain_of((12, 0), (10, -2), (10, -20), (6, -20))
    res = offset_chain(ch, r, "left")
    # chamfer->bore edge is convex (arc about it), bore->bottom face concave (trimmed)
    assert [g.kind for g in res.segments] == ["line", "arc", "line", "line"]
    assert dist(res.segments[1].center, (10, -2)) < 1e-12
    assert_seg(res.segments[2], "line", (10 - r, -2), (10 - r, -20 + r))
    assert_at_exactly_r(res, ch, r)


def test_zero_length_and_degenerate():
    ch = [Line((10, 0), (10, -5)), Line((10, -5), (10, -5)), Line((10, -5), (10, -9))]
    res = offset_chain(ch, 0.8, "right")
    # the zero-length segment is skipped; its neighbours join tangentially (no corner arc)
    assert [o.before for o in res.origins] == [0, 2]
    assert_seg(res.segments[0], "line", (10.8, 0), (10.8, -5))
    assert_seg(res.segments[1], "line", (10.8, -5), (10.8, -9))
    assert res.departures == []
    assert offset_chain([], 0.8, "right").segments == []
    zero = offset_chain(ch, 0.0, "right")
    assert [g for g in zero.segments] == [ch[0], ch[2]]
    with pytest.raises(ValueError):
        offset_chain(ch, -1, "right")
    with pytest.raises(ValueError):
        offset_chain([Line((0, 0), (1, 0)), Line((2, 0), (3, 0))], 0.5, "right")


def test_lookahead_window():
    # two passes joined by a retract/return: globally the second pass is within r of the
    # first, inside a 1-segment window it is not considered
    r = 0.8
    ch = chain_of((10, 0), (10, -20), (12, -20), (12, 0), (9.5, 0), (9.5, -20))
    full = offset_chain(ch, r, "right")
    local = offset_chain(ch, r, "right", lookahead=1)
    last_local = local.segments[-1]
    assert_seg(last_local, "line", last_local.start, (9.5 - r * 0 + r, -20))
    assert any(d.unreachable for d in full.departures)
    assert all(d.kind == "corner" for d in local.departures)


profiles = st.lists(
    st.tuples(st.floats(0.3, 6.0), st.floats(-4.0, 4.0), st.sampled_from(["line", "arc+", "arc-"])),
    min_size=1, max_size=7)


@settings(max_examples=60, deadline=None)
@given(profiles, st.sampled_from([0.4, 0.8]))
def test_random_monotone_profiles_are_at_exactly_r(steps, r):
    """Random turned-like chains (monotone toward -Z, lines and bulged arcs): the offset is
    connected, everywhere at exactly r from the contour (never closer)."""
    pts = [(10.0, 0.0)]
    ch = []
    for dz, dx, kind in steps:
        a = pts[-1]
        b = (max(1.0, a[0] + dx), a[1] - dz)
        if dist(a, b) < 0.05:
            continue
        if kind == "line":
            ch.append(Line(a, b))
        else:
            c = dist(a, b)
            ch.append(Arc.from_radius(a, b, c * 0.75, kind == "arc+"))
        pts.append(b)
    if not ch:
        return
    res = offset_chain(ch, r, "right")
    if not res.segments:  # e.g. a lone inside arc smaller than r: nothing to follow, reported
        assert res.unreachable
        return
    assert chain_is_connected(res.segments, 1e-6)
    for p in dense_points(res.segments, 60):
        assert dist_to_chain(p, ch) == pytest.approx(r, abs=1e-7)
    for d in res.departures:
        assert d.departure > 0


# ---------------------------------------------------------------------------------------------
# a path that runs over itself: the distance index and the shared measuring budget

def _brute_distance(segs, p):
    return min(g.distance_to(p) for g in segs)


def test_segment_grid_distance_is_the_exact_minimum():
    import random

    from hnc_cam.geometry.offset import _SegmentGrid

    rng = random.Random(5)
    segs = []
    for _ in range(60):  # lines and arcs crossing back and forth over one area, some repeated
        a = (rng.uniform(0, 30), rng.uniform(-40, 0))
        b = (rng.uniform(0, 30), rng.uniform(-40, 0))
        if rng.random() < 0.3:
            m = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
            h = dist(a, b) * rng.uniform(0.1, 0.6)
            d = (b[0] - a[0], b[1] - a[1])
            c = (m[0] - d[1] / dist(a, b) * h, m[1] + d[0] / dist(a, b) * h)
            segs.append(Arc(a, b, c, rng.random() < 0.5))
        else:
            segs.append(Line(a, b))
    segs += segs[:20] + [Line(g.end, g.start) for g in segs[:10] if isinstance(g, Line)]
    segs.append(Line((200.0, 5.0), (201.0, 5.0)))  # far from the rest
    grid = _SegmentGrid(segs)
    pts = [(rng.uniform(-20, 60), rng.uniform(-60, 20)) for _ in range(400)]
    pts += [g.point_at(0.37) for g in segs] + [(1e4, -1e4), (-50.0, 3.0), (200.5, 5.0)]
    for p in pts:
        assert grid.distance(p) == _brute_distance(segs, p), p


def _loops(n):
    # a rectangle X 10..15 (radius), Z 0..-20 run n times over itself
    one = chain_of((10.0, 0.0), (10.0, -20.0), (15.0, -20.0), (15.0, 0.0), (10.0, 0.0))
    return one * n


class _ScanAll:
    """Reference for the index: a scan of every path segment (no index, no sharing)."""

    def __init__(self, segs):
        self.segs = list(segs)

    def distance(self, p):
        return _brute_distance(self.segs, p)


@pytest.mark.parametrize("side", ["left", "right"])
def test_repeated_loop_same_result_with_and_without_the_index(side, monkeypatch):
    from hnc_cam.geometry import offset as off

    chain = _loops(5) + chain_of((10.0, 0.0), (12.0, -7.0), (10.0, -20.0), (15.0, -3.0))
    fast = offset_chain(chain, 0.8, side)
    monkeypatch.setattr(off, "_SegmentGrid", _ScanAll)
    slow = offset_chain(chain, 0.8, side)
    assert fast.segments == slow.segments
    assert [(d.kind, d.segments, d.departure, d.at) for d in fast.departures] == \
        [(d.kind, d.segments, d.departure, d.at) for d in slow.departures]
    assert fast.departures


def test_repeated_loop_hand_values():
    # on the right the nose runs inside the rectangle: lines at X 10.5 / 14.5 and Z -0.5 /
    # -19.5; the path cuts the repeated passes to one; each corner of the rectangle keeps
    # r (sqrt 2 - 1) of the nose radius
    r = 0.5
    chain = _loops(4)
    res = offset_chain(chain, r, "right")
    assert_at_exactly_r(res, chain, r)
    assert [(g.kind, g.start, g.end) for g in res.segments] == [
        ("line", (14.5, -0.5), (10.5, -0.5)), ("line", (10.5, -0.5), (10.5, -19.5)),
        ("line", (10.5, -19.5), (14.5, -19.5)), ("line", (14.5, -19.5), (14.5, -0.5)),
        ("line", (14.5, -0.5), (10.5, -0.5))]
    corners = {(10.0, 0.0), (10.0, -20.0), (15.0, -20.0), (15.0, 0.0)}
    assert res.departures
    for d in res.departures:
        assert d.departure == pytest.approx(r * (math.sqrt(2) - 1), abs=1e-6)
        assert min(dist(d.at, c) for c in corners) < 1e-6


def _grooves(n, w=1.0, depth=2.0, pitch=4.0):
    # a face at X 20 (radius) with n grooves of width w < 2r, cut along -Z
    pts = [(20.0, 0.0)]
    for k in range(n):
        z = -pitch * (k + 1)
        pts += [(20.0, z), (20.0 - depth, z), (20.0 - depth, z - w), (20.0, z - w)]
    pts.append((20.0, pts[-1][1] - pitch))
    return chain_of(*pts)


def test_many_departures_share_one_budget_and_keep_the_figures():
    # 25 grooves measured under the shared budget report what one groove alone reports
    r = 0.8
    one = offset_chain(_grooves(1), r, "right")
    many = offset_chain(_grooves(25), r, "right")
    (g1,) = [d for d in one.departures if d.kind == "groove"]
    # by hand: the nose bridges the groove touching both rims, its centre sqrt(r^2 - 0.5^2)
    # above the face; the bottom corner is hypot(2 + that, 0.5) from the centre
    assert g1.departure == pytest.approx(math.hypot(2 + math.sqrt(r * r - 0.25), 0.5) - r,
                                         abs=2e-5)
    gs = [d for d in many.departures if d.kind == "groove"]
    assert len(gs) == 25
    for k, d in enumerate(gs):
        assert d.departure == pytest.approx(g1.departure, abs=2e-5)
        assert dist(d.at, (g1.at[0], g1.at[1] - 4.0 * k)) < 1e-3
        assert many.distance_to(d.at) - r == pytest.approx(d.departure, abs=1e-9)


def test_grid_distances_and_stretch_points_are_the_segments_own_bit_for_bit():
    """The nearest-distance grid and the departure measurement take each segment's distance
    and points from functions with its radius, angles and direction worked out once: the
    same values as ``distance_to`` and ``point_at``, to the last bit."""
    import random

    from hnc_cam.geometry.offset import _distance_fn, _point, _point_fn
    rnd = random.Random(3)
    segs = [Line((10.0, 0.0), (10.0, -8.0)), Line((10.0, -8.0), (14.5, -12.25)),
            Line((3.0, -3.0), (3.0, -3.0)),
            Arc((14.0, -12.0), (16.0, -14.0), (14.0, -14.0), True),
            Arc((16.0, -14.0), (18.0, -16.0), (18.0, -14.0), False),
            Arc((5.0, 0.0), (5.0, -10.0), (5.0, -5.0), True),
            Arc((0.0, 4.0), (4.0, 0.0), (0.0, 0.0), False)]  # three quarters of a turn
    for g in segs:
        d = _distance_fn(g)
        pts = [g.start, g.end, getattr(g, "center", g.start)]
        pts += [(rnd.uniform(-5, 25), rnd.uniform(-20, 8)) for _ in range(400)]
        for p in pts:
            assert d(p) == g.distance_to(p)
        at = _point_fn(g)
        for t in [0.0, 1.0, -0.5, 1.5] + [rnd.random() for _ in range(100)]:
            assert at(t) == _point(g, t)
