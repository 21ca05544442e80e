"""Arc fitting and merging (pure geometry, no CAD kernel)."""
from __future__ import annotations

import math

import pytest

from hnc_cam.cad.fit import arc_from_tangent, biarc, fit_curve, merge_segments
from hnc_cam.geometry import Arc, Line, chain_is_connected


def _ellipse(a: float, b: float, zc: float):
    """Quarter ellipse in (r, z): r = b sin t, z = zc + a cos t, t in [0, pi/2]."""
    def fn(t):
        return (b * math.sin(t), zc + a * math.cos(t)), (b * math.cos(t), -a * math.sin(t))
    return fn


@pytest.mark.parametrize("tol", [0.01, 0.001, 0.0001])
def test_ellipse_fitted_within_tolerance_measured_densely(tol):
    fn = _ellipse(20.0, 8.0, -20.0)
    segs = fit_curve(fn, 0.0, math.pi / 2, tol)
    assert all(isinstance(s, (Line, Arc)) for s in segs)
    assert chain_is_connected(segs, 1e-9)
    assert segs[0].start == pytest.approx((0.0, 0.0), abs=1e-12)
    assert segs[-1].end == pytest.approx((8.0, -20.0), abs=1e-12)
    worst = max(min(s.distance_to(fn(math.pi / 2 * i / 5000)[0]) for s in segs)
                for i in range(5001))
    assert worst <= tol
    # and the other way: every point of the arcs is near the ellipse
    for s in segs:
        for k in range(1, 10):
            r, z = s.point_at(k / 10)
            # algebraic distance of the ellipse (r/b)^2 + ((z - zc)/a)^2 = 1, scaled to mm
            t = math.atan2(r / 8.0, (z + 20.0) / 20.0)
            lo, hi = t - 0.05, t + 0.05
            for _ in range(100):  # ternary search of the nearest ellipse point
                m1, m2 = lo + (hi - lo) / 3, hi - (hi - lo) / 3
                if math.dist((r, z), fn(m1)[0]) < math.dist((r, z), fn(m2)[0]):
                    hi = m2
                else:
                    lo = m1
            assert math.dist((r, z), fn(lo)[0]) <= tol


def test_tighter_tolerance_more_segments_and_g1():
    fn = _ellipse(30.0, 10.0, 0.0)
    coarse = fit_curve(fn, 0.0, math.pi / 2, 0.01)
    fine = fit_curve(fn, 0.0, math.pi / 2, 0.0001)
    assert len(fine) > len(coarse)
    for a, b in zip(fine, fine[1:]):  # tangent continuity at the biarc joints
        ta, tb = a.tangent_at_end(), b.tangent_at_start()
        assert ta[0] * tb[0] + ta[1] * tb[1] == pytest.approx(1.0, abs=1e-6)


def test_straight_and_circular_curves_give_one_segment():
    line = fit_curve(lambda t: ((5 + t, -2 * t), (1.0, -2.0)), 0.0, 3.0, 1e-4)
    assert len(line) == 1 and isinstance(line[0], Line)
    assert line[0].end == pytest.approx((8.0, -6.0))
    circ = fit_curve(lambda t: ((10 * math.sin(t), 10 * math.cos(t)),
                                (10 * math.cos(t), -10 * math.sin(t))), 0.2, 1.4, 1e-6)
    assert len(circ) == 1 and isinstance(circ[0], Arc)
    assert circ[0].center == pytest.approx((0.0, 0.0), abs=1e-9)
    assert circ[0].radius == pytest.approx(10.0)


def test_biarc_tangents_and_ends():
    p0, t0, p1, t1 = (0.0, 0.0), (0.0, -1.0), (5.0, -10.0), (1.0, 0.0)
    segs = biarc(p0, t0, p1, t1)
    assert len(segs) == 2 and chain_is_connected(segs, 1e-9)
    assert segs[0].tangent_at_start() == pytest.approx(t0, abs=1e-9)
    assert segs[-1].tangent_at_end() == pytest.approx(t1, abs=1e-9)
    j0, j1 = segs[0].tangent_at_end(), segs[1].tangent_at_start()
    assert j0 == pytest.approx(j1, abs=1e-9)


def test_arc_from_tangent_direction():
    a = arc_from_tangent((0.0, 0.0), (0.0, -1.0), (2.0, -2.0))
    # moving toward -Z (left in the view), ending up (+X): a right turn = G02
    assert isinstance(a, Arc) and a.cw
    assert a.center == pytest.approx((2.0, 0.0))


def test_merge_collinear_and_cocircular():
    segs = [Line((0, 0), (5, 0)), Line((5, 0), (10, 0)), Line((10, 0), (10, -5)),
            Arc((10, -5), (10 * math.cos(0.3), -5 - 10 * math.sin(0.3) + 0), (0, -5), True)]
    m = merge_segments(segs)
    assert len(m) == 3 and m[0] == Line((0, 0), (10, 0))
    c = (0.0, 0.0)
    a1 = Arc((0.0, 10.0), (10 * math.sin(1.0), 10 * math.cos(1.0)), c, False)
    a2 = Arc(a1.end, (10.0, 0.0), c, False)
    m = merge_segments([a1, a2])
    assert len(m) == 1 and m[0].start == (0.0, 10.0) and m[0].end == (10.0, 0.0)
    assert m[0].sweep == pytest.approx(math.pi / 2)
    # opposite directions or different centres stay apart
    assert len(merge_segments([Line((0, 0), (5, 0)), Line((5, 0), (4, 0))])) == 2
    assert len(merge_segments([a1, Arc(a1.end, (10.0, 0.0), c, True)])) == 2


def test_cad_package_import_is_lazy():
    """Importing hnc_cam.cad (e.g. for parse_set) must not pull in OpenCascade."""
    import subprocess
    import sys
    code = ("import sys, hnc_cam.cad as c; c.parse_set(['a=1']); "
            "print(any(m == 'OCP' or m.startswith(('OCP.', 'build123d', 'cadquery')) for m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.parametrize("tol", [0.001, 0.000995, 0.0001])
def test_fit_keeps_the_curve_end_tangents_and_the_axis_centre(tol):
    """A nose ellipse (semi-axes 6 along Z, 10 radial) from the cylinder (10, -6) to the axis
    at (0, 0): it leaves the cylinder along Z and meets the axis perpendicular to it. The fit
    keeps both: the last arc's centre lies on the axis (at the curve end's own radius, 6e-16
    here), so it never rises above the face Z0, and the first piece leaves along +Z."""
    def fn(t):  # t from 0 at (10, -6) to pi/2 at (0, 0)
        return (10 * math.cos(t), -6 + 6 * math.sin(t)), (-10 * math.sin(t), 6 * math.cos(t))
    segs = fit_curve(fn, 0.0, math.pi / 2, tol)
    first, last = segs[0], segs[-1]
    assert first.start == pytest.approx((10.0, -6.0), abs=1e-12)
    assert first.tangent_at_start() == (0.0, 1.0)  # along +Z exactly, as the curve
    assert isinstance(last, Arc) and last.center[0] == pytest.approx(0.0, abs=1e-12)
    assert last.tangent_at_end() == pytest.approx((-1.0, 0.0), abs=1e-12)
    assert max(s.bbox()[3] for s in segs) <= 1e-12  # nothing above Z0
    for a, b in zip(segs, segs[1:]):  # G1 everywhere the curve is
        assert a.tangent_at_end() == pytest.approx(b.tangent_at_start(), abs=2e-3)


def test_fit_end_piece_is_a_line_only_along_the_end_tangent():
    # a parabola r = t, z = -0.001 t^2 from the axis: within 0.01 of its chord, but it leaves
    # the axis perpendicular; the first piece must too
    segs = fit_curve(lambda t: ((t, -0.001 * t * t), (1.0, -0.002 * t)), 0.0, 2.0, 0.01)
    assert segs[0].tangent_at_start() == (1.0, 0.0)
    assert segs[0].start == (0.0, 0.0)
    assert all(s.bbox()[3] <= 1e-12 for s in segs)
    if isinstance(segs[0], Arc):
        assert segs[0].center[0] == 0.0


def test_recognised_arc_about_the_axis_has_its_centre_on_it():
    """A free-form edge that is a circle about a point 3e-7 mm off the axis (a sphere exported
    as a B-spline) becomes one Arc whose centre is exactly on the axis."""
    from types import SimpleNamespace

    from hnc_cam.cad.extract import _recognise
    c = (3e-7, -5.0)

    def rz(t):
        return (c[0] + 5.0 * math.cos(t), c[1] + 5.0 * math.sin(t))
    e = SimpleNamespace(first=0.2, last=1.4, rz=rz)
    (arc,) = _recognise(e, rz(0.2), rz(1.4))
    assert isinstance(arc, Arc) and arc.center[0] == 0.0
    assert arc.center[1] == pytest.approx(-5.0, abs=1e-12)
    assert arc.radius == pytest.approx(5.0, abs=1e-6)
    # a centre farther off the axis is kept where it is
    c = (0.01, -5.0)
    (arc,) = _recognise(e, rz(0.2), rz(1.4))
    assert arc.center[0] == pytest.approx(0.01, abs=1e-9)
