"""The placements a tool's body cannot take, as the region under one envelope across the
holder's direction: the same region as the union of the swept edges, the envelope's crossings
exact, and the reach built from it the same as from the union, for outside tools, a boring bar
and a grooving blade on a part with arcs, a bore and a chucking allowance."""
from __future__ import annotations

import importlib

import numpy as np
import pytest
import shapely
import shapely.affinity
from shapely.geometry import Polygon, box

from hnc_cam.geometry import Arc, Line, TurnedProfile
from hnc_cam.sim.region import profile_polygon
from hnc_cam.sim.tool import tool_shape
from hnc_cam.tooling import load_machine, load_tools

V = importlib.import_module("hnc_cam.sim.verify")  # the module (hnc_cam.sim.verify is the function)


def part() -> TurnedProfile:
    """A knob: a dome, a fillet into a shoulder, a groove, a taper, a bore with a step."""
    outside = [Arc((0.0, 0.0), (8.0, -4.0), (0.0, -10.0), False),
               Line((8.0, -4.0), (8.0, -12.0)),
               Arc((8.0, -12.0), (10.0, -14.0), (10.0, -12.0), True),
               Line((10.0, -14.0), (18.0, -14.0)),
               Line((18.0, -14.0), (18.0, -22.0)),
               Line((18.0, -22.0), (14.0, -22.0)),
               Line((14.0, -22.0), (14.0, -25.0)),
               Line((14.0, -25.0), (18.0, -25.0)),
               Line((18.0, -25.0), (22.0, -40.0)),
               Line((22.0, -40.0), (22.0, -50.0))]
    return TurnedProfile(outside=outside)


def bored() -> TurnedProfile:
    pts = [(9.0, 0.0), (16.0, 0.0), (16.0, -12.0), (24.0, -18.0), (24.0, -45.0)]
    outside = [Line(a, b) for a, b in zip(pts[:-1], pts[1:])]
    bore = [Line((9.0, 0.0), (9.0, -20.0)),
            Arc((9.0, -20.0), (7.0, -22.0), (7.0, -20.0), False),
            Line((7.0, -22.0), (5.0, -22.0)), Line((5.0, -22.0), (5.0, -45.0))]
    return TurnedProfile(outside=outside, bore=bore)


def solids(mp: Polygon, keep: Polygon | None = None) -> list[Polygon]:
    out = [mp, shapely.affinity.scale(mp, 1.0, -1.0, origin=(0, 0))]
    if keep is not None:
        out += [keep, shapely.affinity.scale(keep, 1.0, -1.0, origin=(0, 0))]
    return out


def reference_reachable(mp, shapes, where, keep=None):
    """The reach from the union of the swept edges of the obstacles facing the holder (the
    whole body swept, a finite holder past the part), per tool as :func:`reachable` goes."""
    solid = shapely.union_all(solids(mp, keep))
    sb = solid.bounds
    left = where
    for s in shapes:
        if left.is_empty:
            break
        ext = float(np.ptp(s.outline, axis=0).max()) + 1.0
        body = V._body(s, 2 * max(sb[2] - sb[0], sb[3] - sb[1]) + 2 * ext)
        bounds = shapely.bounds(np.array(V._polys(left), dtype=object))
        k0, k1 = s.outline.min(axis=0), s.outline.max(axis=0)
        lo, hi = bounds[:, :2] - k1 - 1.0, bounds[:, 2:] - k0 + 1.0
        window = shapely.union_all(shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1]))
        blocked = V._blocked(solid, body, V.holder_direction(s.tip), window)
        place = shapely.difference(window, shapely.union_all(blocked)) if len(blocked) else window
        if place.is_empty:
            continue
        covered = V._minkowski_parts(place, s.outline, near=left)
        if covered:
            left = shapely.difference(left, shapely.union_all(covered))
    return shapely.difference(where, left)


LIB = load_machine(None, load_tools(None))


def shapes(which):
    return tool_shape(LIB.register({"od": 1, "bar": 3, "groove": 7}[which]))


@pytest.mark.parametrize("which", ["od", "bar", "groove"])
@pytest.mark.parametrize("model", [part, bored])
@pytest.mark.parametrize("path", ["envelope", "union"])
def test_blocked_region_equals_the_union_of_the_swept_edges(which, model, path, monkeypatch):
    # the region under the envelope (and the union of the swept upper chains, taken for very
    # few or very many chains) equals the union of the swept edges of the obstacles facing
    # the holder (the whole body swept) in windows of one to three boxes anywhere around
    monkeypatch.setattr(V, "ENVELOPE_MIN", 0)
    if path == "union":
        monkeypatch.setattr(V, "ENVELOPE_CELLS", 0)
    s = shapes(which)
    mp = profile_polygon(model())
    keep = box(-60.0, 0.0, -50.0 if model is part else -45.0, 26.0)
    pieces = solids(mp, keep)
    solid = shapely.union_all(pieces)
    sb = solid.bounds
    body = V._body(s, 2 * max(sb[2] - sb[0], sb[3] - sb[1])
                   + 2 * (float(np.ptp(s.outline, axis=0).max()) + 1))
    u = V.holder_direction(s.tip)
    edges = V._facing(pieces, u)
    rng = np.random.default_rng(11)
    blocked_some = 0
    for _ in range(8):
        n = int(rng.integers(1, 4))
        lo = np.column_stack([rng.uniform(-62, 2, n), rng.uniform(-26, 28, n)])
        hi = lo + rng.uniform(1, 20, (n, 2))
        window = shapely.union_all(shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1]))
        got = V._blocked_region(edges, s, lo, hi)
        want = V._blocked(solid, body, u, window)
        a = shapely.intersection(window, got) if got is not None else Polygon()
        b = shapely.intersection(window, shapely.union_all(want)) if len(want) else Polygon()
        assert shapely.symmetric_difference(a, b).area < 1e-9
        if not b.is_empty:
            blocked_some += 1
            assert shapely.hausdorff_distance(a.boundary, b.boundary) < 1e-7
    assert blocked_some >= 3


def brute_max(ch, h):
    """The maximum of the chains' functions at the points h (-inf where none is defined)."""
    out = np.full(len(h), -np.inf)
    for c in ch:
        inside = (h >= c[0, 0]) & (h <= c[-1, 0])
        out[inside] = np.maximum(out[inside], np.interp(h[inside], c[:, 0], c[:, 1]))
    return out


@pytest.mark.parametrize("seed", range(6))
def test_envelope_is_the_maximum_with_its_crossings(seed):
    # random convex-from-below chains (tops of segments summed with a random convex set) and
    # plain segments: the envelope's polyline is the pointwise maximum everywhere, between its
    # breakpoints too (a crossing left out would put a chord above or below it)
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(9, 2)) * [2.0, 1.0]
    chain = V._upper_chain(pts)
    assert (np.diff(chain[:, 0]) > 0).all()
    assert (np.diff(np.diff(chain[:, 1]) / np.diff(chain[:, 0])) < 0).all()
    n = int(rng.integers(2, 30))
    a = rng.uniform(-10, 10, (n, 2))
    b = a + rng.normal(size=(n, 2)) * 3
    b[:2, 0] = a[:2, 0]  # vertical segments too
    segs = np.where((a[:, 0] <= b[:, 0])[:, None, None], np.stack([a, b], 1), np.stack([b, a], 1))
    for ch in (V._tops(a, b, chain), segs[segs[:, 1, 0] > segs[:, 0, 0]]):
        top = V._envelope(ch, -1e3)
        h = np.sort(rng.uniform(ch[:, 0, 0].min(), ch[:, -1, 0].max(), 4000))
        h = h[~np.isin(h, top[:, 0])]
        want = brute_max(ch, h)
        got = np.interp(h, top[:, 0], top[:, 1])
        ok = np.isfinite(want)
        assert np.abs(got[ok] - want[ok]).max() < 1e-9
        assert (got[~ok] == -1e3).all()
        assert (np.diff(top[:, 0]) >= 0).all()


def test_a_crossing_inside_an_interval_is_a_vertex():
    # two lines over the same span crossing in its middle, a third just under the crossing:
    # the envelope has the crossing (5, 5) as a vertex and nothing of the third
    ch = np.array([[(0.0, 0.0), (10.0, 10.0)], [(0.0, 10.0), (10.0, 0.0)],
                   [(0.0, 4.0), (10.0, 4.9)]])
    top = V._envelope(ch, -1.0)
    assert top[0].tolist() == [0.0, 10.0] and top[-1].tolist() == [10.0, 10.0]
    mid = top[(top[:, 0] > 0) & (top[:, 0] < 10)]
    assert len(mid) == 1 and np.allclose(mid[0], (5.0, 5.0), atol=1e-12)
    # the third raised above the crossing: two crossings, with it between them
    ch[2] = [(0.0, 5.5), (10.0, 5.5)]
    top = V._envelope(ch, -1.0)
    mid = top[(top[:, 0] > 0) & (top[:, 0] < 10)]
    assert np.allclose(mid, [(4.5, 5.5), (5.5, 5.5)], atol=1e-12)


@pytest.mark.parametrize("model", [part, bored])
@pytest.mark.parametrize("least", [0, 8])
def test_reach_equals_the_reach_from_the_union(model, least, monkeypatch):
    # leftover all round the part (corners, the groove, the dome, the bore's step and arc):
    # the reach of an outside tool, a finishing tool, a boring bar and a blade, one after the
    # other, equals the reach computed from the union of the swept edges (every blocked
    # region from the envelope, or the few-chain ones united)
    monkeypatch.setattr(V, "ENVELOPE_MIN", least)
    mp = profile_polygon(model())
    keep = box(-60.0, 0.0, mp.bounds[0], 26.0)
    grown = shapely.difference(mp.buffer(0.6, quad_segs=16), mp)
    where = shapely.intersection(grown, box(mp.bounds[0] + 0.01, 0.0, 5.0, 30.0))
    tools = [tool_shape(LIB.register(r)) for r in (1, 2, 3, 7)]
    got = V.reachable(mp, tools, where, keep)
    want = reference_reachable(mp, tools, where, keep)
    assert got.area > 0.2 * where.area
    assert shapely.difference(where, got).area > 1e-4  # some of it no tool reaches
    assert shapely.symmetric_difference(got, want).area < 1e-9


@pytest.mark.parametrize("seed", range(4))
def test_over_and_under_from_one_overlay_equal_the_two_differences(seed):
    # a bar cut by random passes (some into the part, some short of it, some beyond its left
    # end into the chucking allowance): gouges and leftover split from the symmetric
    # difference equal model - material and material from the left end on - model
    rng = np.random.default_rng(seed)
    mp = profile_polygon(part())
    material = box(-60.0, 0.0, 2.0, 24.0)
    for _ in range(12):
        z = rng.uniform(-62, 0)
        x = rng.uniform(2, 24)
        cut = box(z, x, z + rng.uniform(2, 20), 30.0)
        material = shapely.difference(material, shapely.affinity.rotate(cut, rng.uniform(-20, 20)))
    over, under = V._over_under(mp, material, -50.0)
    want_over = shapely.difference(mp, material)
    want_under = shapely.difference(shapely.intersection(material, box(-50.0, -1.0, 1e4, 1e4)), mp)
    assert not want_over.is_empty and not want_under.is_empty
    assert shapely.symmetric_difference(over, want_over).area < 1e-9
    assert shapely.symmetric_difference(under, want_under).area < 1e-9
    assert len(V._polys(over)) == len(V._polys(want_over))
    assert len(V._polys(under)) == len(V._polys(want_under))
    assert under.bounds[0] >= -50.0 - 1e-12
