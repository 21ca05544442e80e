"""Tool outlines of the simulator: insert corner geometry, orientation by tip code."""
from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from hnc_cam.sim.tool import CHORD, tool_shape
from hnc_cam.tooling import Insert, Register, load_machine


def _edge_angles(s):
    """Polar angles (deg, in the z-right x-up view) of the outline's sides longer than 3 mm."""
    o = np.vstack([s.outline, s.outline[:1]])
    out = []
    for a, b in zip(o[:-1], o[1:]):
        d = b - a
        if math.hypot(*d) > 3:
            out.append(math.degrees(math.atan2(d[1], d[0])) % 360)
    return out


def test_default_insert_tip3_corner_at_controlled_point():
    s = tool_shape(Register(number=1, radius=0.8, tip=3))
    z0, x0 = s.outline.min(axis=0)
    # imaginary tip P at the origin: lowest point X = 0 (nose bottom), leftmost Z = 0
    assert abs(x0) < 1e-9 and abs(z0) < 1e-9
    assert s.centre == pytest.approx((0.8, 0.8))
    # nose points lie on the circle of radius 0.8 about the centre (within the chord error)
    c = np.array(s.centre)
    r = np.hypot(*(s.outline - c).T)
    assert (np.abs(r - 0.8) < 1e-9).sum() >= 10
    assert shapely.Polygon(s.outline).is_valid
    assert shapely.Polygon(s.outline).convex_hull.area == pytest.approx(shapely.Polygon(s.outline).area)


def test_main_edge_at_approach_angle():
    # kappa_r 95: the main edge leaves the nose toward +X leaning 5 deg toward +Z
    s = tool_shape(Register(number=1, radius=0.0, tip=3, approach=95.0))
    pts = s.outline
    # sharp corner at the origin; the two edges at 85 and 5 deg (80 deg insert)
    assert np.allclose(pts.min(axis=0), 0.0, atol=1e-12)
    v = [p for p in pts if np.hypot(*p) > 1e-9]
    angs = sorted(round(math.degrees(math.atan2(p[1], p[0])), 6) for p in v
                  if abs(np.hypot(*p) - 12.0) < 1e-6)
    assert angs == pytest.approx([5.0, 85.0])


def test_tip_codes_mirror():
    r3 = tool_shape(Register(number=1, radius=0.4, tip=3)).outline
    r2 = tool_shape(Register(number=1, radius=0.4, tip=2)).outline
    r4 = tool_shape(Register(number=1, radius=0.4, tip=4)).outline
    # code 2 (boring bar) is code 3 mirrored in X, code 4 mirrored in Z
    assert r2[:, 1].max() == pytest.approx(0.0, abs=1e-9) and r2[:, 0].min() == pytest.approx(0.0, abs=1e-9)
    assert r4[:, 0].max() == pytest.approx(0.0, abs=1e-9) and r4[:, 1].min() == pytest.approx(0.0, abs=1e-9)
    assert shapely.Polygon(r2).area == pytest.approx(shapely.Polygon(r3).area)


def test_tip_0_is_centre_oriented_as_3():
    s = tool_shape(Register(number=1, radius=0.5, tip=0))
    assert s.centre == (0.0, 0.0)
    assert s.outline[:, 1].min() == pytest.approx(-0.5)
    assert s.outline[:, 0].min() == pytest.approx(-0.5)


def test_library_inserts():
    m = load_machine()
    d = tool_shape(m.register(2))  # DNMG150404 on PDJNR: 55 deg, kappa_r 93
    assert d.nose_radius == pytest.approx(0.4)
    ang = _edge_angles(d)
    assert any(abs(a - 87.0) < 0.01 or abs(a - 267.0) < 0.01 for a in ang)
    th = tool_shape(m.register(4))  # 60 deg threading, tip 8
    o = th.outline
    assert o[:, 1].min() == pytest.approx(0.0, abs=1e-9)
    # symmetric V: width at 3 mm above the tip ~ 2 * 3 * tan 30 (+ nose rounding)
    g = shapely.Polygon(o).intersection(shapely.LineString([(-10, 3), (10, 3)]))
    assert g.bounds[2] - g.bounds[0] == pytest.approx(2 * (3 * math.tan(math.radians(30)))
                                                      + 2 * 0.1875 * (1 / math.cos(math.radians(30)) - math.tan(math.radians(30))), abs=1e-3)
    gr = tool_shape(m.register(7))  # 3 mm grooving blade, reference corner at -Z
    assert gr.width == pytest.approx(3.0)
    assert gr.outline[:, 0].min() == pytest.approx(0.0, abs=1e-9)


def test_thread_shape_for_thread_moves():
    s = tool_shape(Register(number=1, radius=0.0, tip=8), thread_angle=55.0)
    g = shapely.Polygon(s.outline).intersection(shapely.LineString([(-10, 2), (10, 2)]))
    assert g.bounds[2] - g.bounds[0] == pytest.approx(2 * 2 * math.tan(math.radians(27.5)), abs=1e-3)


def test_nose_sampling_within_chord_error():
    s = tool_shape(Register(number=1, radius=2.0, tip=3))
    c = np.array(s.centre)
    o = s.outline
    # chord midpoints of the nose lie within CHORD of the circle
    for a, b in zip(o[:-1], o[1:]):
        if abs(np.hypot(*(a - c)) - 2) < 1e-9 and abs(np.hypot(*(b - c)) - 2) < 1e-9:
            mid = (a + b) / 2
            assert 2 - np.hypot(*(mid - c)) <= CHORD + 1e-12


def test_non_cutting_sides_only_for_known_inserts():
    assert tool_shape(Register(number=1, radius=0.8, tip=3)).non_cutting == ()
    known = tool_shape(Register(number=1, radius=0.8, tip=3, insert=Insert.parse("CNMG120408")))
    assert len(known.non_cutting) == 2


def test_sweep_hulls_equal_the_convex_hull_of_both_placements():
    import numpy as np
    import shapely

    from hnc_cam.sim.tool import sweep_hulls
    from hnc_cam.tooling import Register
    rng = np.random.default_rng(7)
    for reg, ta in ((Register(number=1, radius=0.8, tip=3), None),
                    (Register(number=2, radius=0.4, tip=2), None),
                    (Register(number=3, radius=0.2, tip=8), 60.0)):
        K = tool_shape(reg, ta).outline
        a = rng.normal(size=(300, 2)) * 5
        b = a + rng.normal(size=(300, 2)) * rng.choice([0.0, 1e-9, 0.05, 1.0, 20.0], size=(300, 1))
        b[:60, 1] = a[:60, 1]  # along Z
        b[60:120, 0] = a[60:120, 0]  # along X
        for outline in (K, -K, K[::-1]):  # any orientation
            got = sweep_hulls(outline, a, b)
            ref = shapely.convex_hull(shapely.linestrings(
                np.concatenate([outline[None] + a[:, None], outline[None] + b[:, None]], axis=1)))
            assert shapely.is_valid(got).all()
            assert shapely.area(shapely.symmetric_difference(got, ref)).max() < 1e-9
