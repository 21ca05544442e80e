"""The deepest point of leftover and gouges, measured with bounds on the distance: the same
maximum as every boundary point measured, on slivers along lines and arcs, with an unreachable
region that counts as model, and with the reach of several tools computed one after another."""
from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

from hnc_cam.geometry import Arc, Line
from hnc_cam.sim.measure import SegmentTable, distances
from hnc_cam.sim.region import polygons
from hnc_cam.sim.verify import PRUNE_EPS, _boundary_points, _deepest, _depths, _edges, reachable
from hnc_cam.sim.tool import tool_shape
from hnc_cam.tooling import Insert, Register


def model_segments():
    """A dome (R16), a shoulder with a fillet, a taper and a face, as (x, z) kernel segments."""
    return [Arc((0.0, 0.0), (10.0, -3.510004003), (0.0, -16.0), False),
            Line((10.0, -3.510004003), (10.0, -23.5)),
            Arc((10.0, -23.5), (11.5, -25.0), (11.5, -23.5), True),
            Line((11.5, -25.0), (14.0, -25.0)),
            Line((14.0, -25.0), (14.0, -50.0)),
            Line((14.0, -50.0), (19.9, -64.7)),
            Line((19.9, -64.7), (19.9, -80.0)),
            Line((19.9, -80.0), (0.0, -80.0))]


def brute(polys, segs, also=None):
    """Every boundary point of each polygon against every segment (and ``also``'s edges)."""
    out = []
    for p in polys:
        pts = _boundary_points(p)
        d, _ = distances(pts, segs)
        if also is not None:
            a, b = _edges(also)
            lines = shapely.linestrings(np.stack([a, b], axis=1))
            d = np.minimum(d, shapely.distance(shapely.points(pts)[:, None], lines[None, :]).min(axis=1))
        out.append(float(d.max()))
    return out


def along(chain, off0, off1, n=400):
    """A sliver between a chain of (z, x) points and the same chain pushed out along its
    normals by a thickness growing from off0 to off1 (a pass that drifts off the contour)."""
    c = np.asarray(chain, dtype=float)
    t = np.diff(c, axis=0)
    t = np.vstack([t, t[-1:]])
    nrm = np.column_stack([-t[:, 1], t[:, 0]]) / np.hypot(t[:, 0], t[:, 1])[:, None]
    off = np.linspace(off0, off1, len(c))[:, None]
    ring = np.vstack([c, (c + off * nrm)[::-1]])
    return shapely.make_valid(Polygon(ring))


def arc_chain(cz, cx, r, a0, a1, n):
    a = np.linspace(a0, a1, n)
    return np.column_stack([cz + r * np.cos(a), cx + r * np.sin(a)])


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_depths_equal_every_boundary_point(seed):
    rng = np.random.default_rng(seed)
    segs = model_segments()
    polys = []
    # long slivers on the lines: along the shoulder (outside, x > 14), the taper, the face
    for z0, z1 in ((-26.0, -49.0), (-30.0, -45.0)):
        th = rng.uniform(0.0005, 0.01, 2)
        polys.append(box(z0, 14.0, z1, 14.0).union(Polygon([(z0, 14.0), (z1, 14.0),
                                                             (z1, 14.0 + th[1]), (z0, 14.0 + th[0])])))
    taper = np.array([(-50.0, 14.0), (-64.7, 19.9)])
    polys.append(along(np.linspace(taper[0], taper[1], 2), *rng.uniform(-0.004, -0.0002, 2)))
    # slivers on the arcs (the dome R16 about (z -16, x 0), the fillet R1.5): the arc sampled
    # coarsely, so the sliver's edges are chords, some of them long
    dome = arc_chain(-16.0, 0.0, 16.0, math.radians(36), math.radians(3), 40)
    polys.append(along(dome, 0.0, rng.uniform(0.001, 0.02)))
    polys.append(along(arc_chain(-16.0, 0.0, 16.0, math.radians(30), math.radians(10), 3),
                       0.0, 0.003))
    fillet = arc_chain(-23.5, 11.5, 1.5, math.radians(180), math.radians(270), 25)
    polys.append(along(fillet, 0.0, -rng.uniform(0.001, 0.05)))
    # a piece away from the model, and random boxes
    polys.append(box(-40.0, 15.1, -38.0, 16.0))
    for _ in range(6):
        z, x = rng.uniform(-78, -2), rng.uniform(0.5, 25)
        polys.append(box(z, x, z + rng.uniform(0.01, 8), x + rng.uniform(0.001, 3)))
    polys = [p for g in polys for p in polygons(g)]
    got = _depths(polys, segs)
    want = brute(polys, segs)
    for g, w in zip(got, want):
        assert g.size_mm == pytest.approx(w, abs=2 * PRUNE_EPS)
    # the place given is a point of the polygon's boundary with that depth
    for p, g in zip(polys, got):
        assert shapely.distance(p.boundary, shapely.Point(g.z, g.x)) < 1e-9
        d, _ = distances(np.array([[g.z, g.x]]), segs)
        assert d[0] == pytest.approx(g.size_mm, abs=1e-12)
    # one table for many queries, the same answers; and _deepest is the deepest of them
    tab = SegmentTable(segs)
    assert [d.size_mm for d in _depths(polys, tab)] == [d.size_mm for d in got]
    assert _deepest(shapely.MultiPolygon(polys[:3]), segs, interior=False).size_mm == max(
        d.size_mm for d in got[:3])


def test_depths_with_unreachable_region_counted_as_model():
    # a 0.006 mm band over the shoulder running into an unreachable corner block: measured
    # from the model and the block together; the band's end at the block is no deeper
    segs = model_segments()
    corner = Polygon([(-50.0, 14.0), (-49.0, 14.0), (-49.0, 14.3), (-50.0, 14.3)])
    band = Polygon([(-49.0, 14.0), (-30.0, 14.0), (-30.0, 14.006), (-49.0, 14.006)])
    drift = Polygon([(-49.0, 14.0), (-40.0, 14.0), (-40.0, 14.0005), (-49.0, 14.0002)])
    for p in (band, drift):
        got = _depths([p], segs, also=corner)[0]
        assert got.size_mm == pytest.approx(brute([p], segs, also=corner)[0], abs=2 * PRUNE_EPS)
    assert _depths([band], segs, also=corner)[0].size_mm == pytest.approx(0.006, abs=1e-9)


def test_interior_grid_finds_a_part_cut_through():
    # the whole part removed: its boundary lies on the model's, the deepest point is inside
    segs = [Line((2.0, -30.0), (12.0, -30.0)), Line((12.0, -30.0), (12.0, -45.0)),
            Line((12.0, -45.0), (2.0, -45.0)), Line((2.0, -45.0), (2.0, -30.0))]
    hole = box(-45.0, 2.0, -30.0, 12.0)
    assert _depths([hole], segs)[0].size_mm < 1e-12
    got = _depths([hole], segs, interior=True)[0]
    assert got.size_mm == pytest.approx(5.0, abs=0.2) and 6.0 < got.x < 8.0


def _turning(code, shape, nose_angle, edge, r):
    ins = Insert(code=code, kind="turn", shape=shape, nose_angle=nose_angle, edge_length=edge,
                 nose_radius=r)
    return tool_shape(Register(number=1, insert=ins, tip=3, radius=r, approach=93.0))


def test_reach_of_several_tools_is_the_union_of_each_tools_reach():
    # the tools are tried one after another, each on what the ones before left: the same
    # region as each tool on the whole leftover
    from hnc_cam.geometry import TurnedProfile
    from hnc_cam.sim.region import profile_polygon
    model = TurnedProfile(outside=[Line((10.0, 0.0), (10.0, -20.0)), Line((10.0, -20.0), (16.0, -20.0)),
                                   Line((16.0, -20.0), (16.0, -30.0)), Line((16.0, -30.0), (12.0, -34.0)),
                                   Line((12.0, -34.0), (12.0, -40.0)), Line((12.0, -40.0), (20.0, -40.0)),
                                   Line((20.0, -40.0), (20.0, -60.0))])
    mp = profile_polygon(model)
    # leftover along the face, in the inside corners and in the groove's corners
    where = shapely.union_all([box(-19.9, 10.0, -0.5, 10.3), box(-20.0, 10.0, -19.2, 10.9),
                               box(-34.0, 12.0, -32.5, 12.25), box(-40.0, 12.0, -39.6, 14.0),
                               Polygon([(-30.0, 16.0), (-33.9, 12.1), (-33.6, 12.1), (-29.8, 15.9)])])
    where = shapely.difference(where, mp)
    tools = [_turning("CNMG120408", "C", 80.0, 12.0, 0.8), _turning("VNMG160404", "V", 35.0, 16.0, 0.4)]
    both = reachable(mp, tools, where)
    each = shapely.union_all([reachable(mp, [t], where) for t in tools])
    assert both.area > 0.3 * where.area
    assert shapely.symmetric_difference(both, each).area < 1e-9
    assert reachable(mp, tools[::-1], where).symmetric_difference(both).area < 1e-9


@pytest.mark.parametrize("which", ["od", "bar", "groove"])
def test_blocked_placements_from_the_edges_facing_the_holder_equal_the_whole_sum(which):
    # the placements a tool's body cannot take, from the edges of the obstacle that face the
    # holder only: the same as the whole Minkowski sum (every edge and the inside) wherever it
    # meets the window, for an outside tool over a tall flange and a groove, a boring bar in a
    # stepped bore, a grooving blade
    from hnc_cam.geometry import TurnedProfile
    from hnc_cam.sim.region import profile_polygon
    from hnc_cam.sim.verify import _blocked, _body, _minkowski_parts, holder_direction
    from hnc_cam.tooling import load_machine, load_tools
    lib = load_machine(None, load_tools(None))
    reg = {"od": lib.register(1), "bar": lib.register(3), "groove": lib.register(7)}[which]
    s = tool_shape(reg)
    pts = [(6.0, 0.0), (12.0, 0.0), (12.0, -10.0), (30.0, -10.0), (30.0, -14.0), (16.0, -14.0),
           (16.0, -20.0), (30.0, -20.0), (30.0, -40.0), (20.0, -42.0), (20.0, -60.0),
           (6.0, -60.0)]
    model = TurnedProfile(outside=[Line(a, b) for a, b in zip(pts[:-1], pts[1:])],
                          bore=[Line((6.0, 0.0), (6.0, -25.0)), Line((6.0, -25.0), (4.0, -25.0)),
                                Line((4.0, -25.0), (4.0, -60.0)), Line((4.0, -60.0), (6.0, -60.0))])
    mp = profile_polygon(model)
    solid = shapely.union_all([mp, shapely.affinity.scale(mp, 1.0, -1.0, origin=(0, 0))])
    sb = solid.bounds
    body = _body(s, 2 * max(sb[2] - sb[0], sb[3] - sb[1]) + 2 * (float(np.ptp(s.outline, axis=0).max()) + 1))
    rng = np.random.default_rng(7)
    for _ in range(6):
        z, x = rng.uniform(-62, 2), rng.uniform(-2, 34)
        window = box(z, x, z + rng.uniform(2, 25), x + rng.uniform(2, 25))
        got = _blocked(solid, body, holder_direction(s.tip), window)
        want = _minkowski_parts(solid, -body, near=window)
        a = shapely.difference(window, shapely.union_all(got)) if len(got) else window
        b = shapely.difference(window, shapely.union_all(want)) if want else window
        assert shapely.symmetric_difference(a, b).area < 1e-9
        assert len(got) < len(want)
