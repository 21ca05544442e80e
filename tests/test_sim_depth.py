"""The depth of leftover measured against an ``also`` region of few edges in numpy gives the
same doubles as GEOS's nearest query, and so the same deepest points."""
from __future__ import annotations

import importlib

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from hnc_cam.geometry import Arc, Line
from hnc_cam.sim.measure import SegmentTable

V = importlib.import_module("hnc_cam.sim.verify")


@pytest.mark.parametrize("seed", range(3))
def test_nearest_edges_are_geos_distances(seed):
    rng = np.random.default_rng(seed)
    for trial in range(60):
        k = int(rng.integers(1, V.ALSO_FEW + 1))
        a = rng.normal(size=(k, 2)) * rng.choice([1e-3, 1.0, 30.0])
        b = a + rng.normal(size=(k, 2)) * rng.choice([1e-7, 1e-3, 1.0, 10.0])
        b[0] = a[0] if trial % 4 == 0 else b[0]  # a zero-length edge
        q = rng.normal(size=(int(rng.integers(1, 2000)), 2)) * rng.choice([1e-3, 1.0, 30.0])
        j = min(k, len(q))
        q[:j] = a[:j] + 0.5 * (b[:j] - a[:j])  # points on the edges
        w, d = V._nearest_edges(q, a, b, step=int(rng.integers(1, 3000)))
        tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
        (i, _), da = tree.query_nearest(shapely.points(q), return_distance=True,
                                        all_matches=False)
        assert np.array_equal(i, np.arange(len(q)))
        assert np.array_equal(d, da)
        # the edge named is one at that distance, the first of them
        at = shapely.distance(shapely.points(q), shapely.linestrings(np.stack([a[w], b[w]], axis=1)))
        assert np.array_equal(at, d)


def test_depths_against_few_edges_equal_the_trees(monkeypatch):
    """Slivers along a taper and a fillet's corner, the corner counting as model: the deepest
    points and depths are the same measured in numpy and through the STRtree."""
    segs = SegmentTable([Line((14.0, -25.0), (14.0, -50.0)), Line((14.0, -50.0), (19.9, -64.7)),
                         Arc((19.9, -64.7), (20.9, -65.7), (19.9, -65.7), True),
                         Line((20.9, -65.7), (20.9, -80.0))])
    sliver = Polygon([(-50.0, 14.0), (-64.7, 19.9), (-64.7, 19.9 + 3e-3), (-50.0, 14.0 + 1e-3)])
    corner = Polygon([(-64.6, 19.9), (-65.8, 19.9), (-65.8, 21.0), (-65.4, 21.0), (-64.6, 20.3)])
    nick = Polygon([(-70.0, 20.9), (-72.0, 20.9), (-71.0, 20.95)])
    polys = [sliver, corner, nick]
    got = V._depths(polys, segs, also=corner, mode=["max", "beyond", "max"],
                    also_for=[True, False, True])
    monkeypatch.setattr(V, "ALSO_FEW", 0)
    want = V._depths(polys, segs, also=corner, mode=["max", "beyond", "max"],
                     also_for=[True, False, True])
    assert [(d.z, d.x, d.size_mm) for d in got] == [(d.z, d.x, d.size_mm) for d in want]
    assert got[2].size_mm == pytest.approx(0.05, abs=1e-9)
