"""Depths measured together: pieces for which a region counts as model beside pieces for which
only the model does, in one measurement, come out as each measured on its own; and a thread
zone's verdict does not depend on who built the model's polygon."""
from __future__ import annotations

import pytest
from shapely.geometry import Polygon, box

from hnc_cam.geometry import Line, Thread, TurnedProfile
from hnc_cam.sim.region import profile_polygon
from hnc_cam.sim.verify import PRUNE_EPS, _depths, _zones


def shoulder():
    """A 28 mm shaft with a 40 mm shoulder at Z -30, as (x, z) kernel segments."""
    return [Line((0.0, 0.0), (14.0, 0.0)), Line((14.0, 0.0), (14.0, -30.0)),
            Line((14.0, -30.0), (20.0, -30.0)), Line((20.0, -30.0), (20.0, -50.0)),
            Line((20.0, -50.0), (0.0, -50.0))]


@pytest.mark.parametrize("mode", ["max", "each"])
def test_pieces_with_and_without_the_region_measured_together(mode):
    segs = shoulder()
    # an unreachable block in the inside corner, a band running into it, a drifting band
    # beside it, and pieces of unreachable leftover elsewhere
    corner = Polygon([(-30.0, 14.0), (-29.0, 14.0), (-29.0, 14.4), (-30.0, 14.4)])
    band = Polygon([(-29.0, 14.0), (-10.0, 14.0), (-10.0, 14.007), (-29.0, 14.007)])
    drift = Polygon([(-29.0, 14.0), (-20.0, 14.0), (-20.0, 14.0004), (-29.0, 14.0001)])
    lone = [corner, box(-50.0, 20.0, -40.0, 20.003), box(-6.0, 14.0, -2.0, 14.02)]
    with_also = [band, drift]
    got = _depths(with_also + lone, segs, also=corner,
                  mode=[mode] * 2 + ["beyond"] * 3, also_for=[True] * 2 + [False] * 3)
    alone_a = _depths(with_also, segs, also=corner, mode=mode)
    alone_b = _depths(lone, segs, mode="beyond")
    if mode == "max":  # only the deepest of the group is exact
        assert max(d.size_mm for d in got[:2]) == pytest.approx(
            max(d.size_mm for d in alone_a), abs=2 * PRUNE_EPS)
    else:
        for g, w in zip(got[:2], alone_a):
            assert (g.z, g.x) == (w.z, w.x) and g.size_mm == pytest.approx(w.size_mm, abs=1e-12)
    # the band measured from the corner block too: 0.007 mm, not the block's 0.4
    assert max(d.size_mm for d in got[:2]) == pytest.approx(0.007, abs=1e-9)
    # the unreachable pieces measured from the model only (the corner block: its full height)
    for g, w in zip(got[2:], alone_b):
        assert g.size_mm == pytest.approx(w.size_mm, abs=2 * PRUNE_EPS)
    assert got[2].size_mm == pytest.approx(0.4, abs=1e-9)
    assert got[3].size_mm == pytest.approx(0.003, abs=1e-9)
    assert got[4].size_mm == pytest.approx(0.02, abs=1e-9)


def test_thread_zones_from_a_given_model_polygon_equal_those_built_here():
    segs = [Line((0.0, 0.0), (9.0, 0.0)), Line((9.0, 0.0), (10.0, -1.0)),
            Line((10.0, -1.0), (10.0, -20.0)), Line((10.0, -20.0), (15.0, -20.0)),
            Line((15.0, -20.0), (15.0, -40.0)), Line((15.0, -40.0), (0.0, -40.0))]
    model = TurnedProfile(outside=segs, threads=[Thread(z_start=-1.0, z_end=-20.0, diameter=20.0,
                                                        pitch=1.5, internal=False)])

    class Bare:
        thread_spans: list = []
    m = Bare()
    a = _zones(model, m, None)  # type: ignore[arg-type]
    b = _zones(model, m, None, profile_polygon(model))  # type: ignore[arg-type]
    assert [(z.z0, z.z1, z.target, z.e0, z.e1) for z in a] == [(z.z0, z.z1, z.target, z.e0, z.e1) for z in b]
    # the shoulder beyond the thread's end is a wall: three pitches of run-out there
    assert a[0].e0 == pytest.approx(3 * 1.5)
