"""Arc fitting of free-form curves (B-spline, ellipse, offset, ...) in the (radius, Z) plane,
and merging of split pieces.

Choices made here:

* A free-form curve is replaced by **biarcs** (two tangent-continuous arcs per piece), the
  classic "equal tangent length" construction. Each piece keeps the curve's end points and
  end tangents, so the fitted chain is G1 wherever the curve was. The deviation is measured
  at ``SAMPLES`` points of the curve per piece (plus the piece ends); a piece whose deviation
  exceeds the tolerance is split at its parameter mid-point and fitted again. Pieces that are
  straight (chord deviation within the tolerance) become one ``Line``; pieces that one arc
  fits within the tolerance become one ``Arc``.
* **The curve's ends keep what the curve has there.** The piece at each end of the curve is
  tangent to the curve at that end whatever its kind: a Line only when it runs along the
  curve's end tangent, a single Arc only as the arc leaving the end along its tangent (and, at
  a piece that is the whole curve, arriving along the other end's tangent too), else a biarc.
  So an end perpendicular to the axis stays perpendicular, and an arc that leaves the axis
  perpendicular to it has its centre exactly on the axis (a nose never rises above the face
  it meets). End tangents within 1e-9 of the axis directions are taken as exactly along them.
  Interior pieces may also be one arc through their ends and middle (tangent within the
  fitting tolerance, not exactly).
* Nothing here samples to a polyline for output: the result is always Line/Arc.
* Merging joins consecutive collinear lines and consecutive co-circular arcs of the same
  direction (pieces split by seams, face splits or STEP exporters): that is
  :func:`hnc_cam.geometry.chain.merge_segments`, re-exported here, shared with the planner.
"""
from __future__ import annotations

import math
from typing import Callable, Sequence

from ..geometry.chain import merge_segments  # noqa: F401  (re-exported: one merge for the package)
from ..geometry.primitives import EPS, Arc, Line, Point, Segment, cross, dist, left_normal

#: curve evaluations per piece used to measure a fit's deviation
SAMPLES = 24
#: deepest bisection of a free-form curve (2**MAX_DEPTH pieces at most)
MAX_DEPTH = 14

CurveFn = Callable[[float], tuple[Point, Point]]  # t -> (point, derivative)


def _unit(v: Point) -> Point:
    n = math.hypot(v[0], v[1])
    if n < EPS:
        raise ValueError("zero tangent")
    u = (v[0] / n, v[1] / n)
    # a tangent along an axis direction up to evaluation noise is exactly along it
    if abs(u[0]) < 1e-9:
        return (0.0, math.copysign(1.0, u[1]))
    if abs(u[1]) < 1e-9:
        return (math.copysign(1.0, u[0]), 0.0)
    return u


def _along(d: Point, t: Point) -> bool:
    """Whether the chord ``d`` runs along the unit tangent ``t`` (angle within 1e-9 rad)."""
    n = math.hypot(d[0], d[1])
    return n > 0 and abs(cross(d, t)) <= 1e-9 * n and d[0] * t[0] + d[1] * t[1] > 0


def arc_from_tangent(p: Point, t: Point, q: Point) -> Segment:
    """The arc leaving ``p`` with unit tangent ``t`` and ending at ``q`` (a Line when ``q``
    lies on the tangent line)."""
    n = left_normal(t)
    v = (q[0] - p[0], q[1] - p[1])
    vn = v[0] * n[0] + v[1] * n[1]
    vv = v[0] * v[0] + v[1] * v[1]
    if abs(vn) < 1e-12 * max(1.0, math.sqrt(vv)):
        return Line(p, q)
    rho = vv / (2 * vn)  # signed: > 0 centre on the left (ccw in the z-right/x-up view)
    c = (p[0] + n[0] * rho, p[1] + n[1] * rho)
    return Arc(p, q, c, cw=rho < 0)


def biarc(p0: Point, t0: Point, p1: Point, t1: Point) -> list[Segment]:
    """Two tangent arcs from ``p0`` (unit tangent ``t0``) to ``p1`` (unit tangent ``t1``) with
    equal tangent lengths. Returns one Line when the data are collinear."""
    v = (p1[0] - p0[0], p1[1] - p0[1])
    vv = v[0] * v[0] + v[1] * v[1]
    if vv < EPS * EPS:
        return []
    tt = (t0[0] + t1[0], t0[1] + t1[1])
    vt = v[0] * tt[0] + v[1] * tt[1]
    a = tt[0] * tt[0] + tt[1] * tt[1] - 4.0
    if abs(a) < 1e-12:  # parallel end tangents
        if abs(vt) < 1e-15:
            # S-curve with tangents perpendicular to the chord: half-circles (rare)
            d = math.sqrt(vv) / 2
        else:
            d = vv / (2 * vt)
    else:
        disc = vt * vt - a * vv
        disc = max(disc, 0.0)
        r1 = (vt + math.sqrt(disc)) / a
        r2 = (vt - math.sqrt(disc)) / a
        cands = [r for r in (r1, r2) if r > 0]
        d = min(cands) if cands else abs(r1)
    q0 = (p0[0] + d * t0[0], p0[1] + d * t0[1])
    q1 = (p1[0] - d * t1[0], p1[1] - d * t1[1])
    j = ((q0[0] + q1[0]) / 2, (q0[1] + q1[1]) / 2)
    out: list[Segment] = []
    if dist(p0, j) > EPS:
        out.append(arc_from_tangent(p0, t0, j))
    if dist(j, p1) > EPS:
        s2 = arc_from_tangent(p1, (-t1[0], -t1[1]), j).reversed()
        out.append(s2)
    return out


def _deviation(segs: Sequence[Segment], pts: Sequence[Point]) -> float:
    return max(min(s.distance_to(p) for s in segs) for p in pts)


def circle3(a: Point, b: Point, c: Point) -> tuple[Point, float] | None:
    """Circle through three points (centre, radius) or None when collinear."""
    ax, az = a
    bx, bz = b
    cx, cz = c
    d = 2 * (ax * (bz - cz) + bx * (cz - az) + cx * (az - bz))
    if abs(d) < 1e-14:
        return None
    a2, b2, c2 = ax * ax + az * az, bx * bx + bz * bz, cx * cx + cz * cz
    ux = (a2 * (bz - cz) + b2 * (cz - az) + c2 * (az - bz)) / d
    uz = (a2 * (cx - bx) + b2 * (ax - cx) + c2 * (bx - ax)) / d
    return (ux, uz), math.hypot(ax - ux, az - uz)


def fit_curve(fn: CurveFn, t0: float, t1: float, tol: float) -> list[Segment]:
    """Lines/arcs within ``tol`` (mm) of the curve ``fn`` on [t0, t1].

    ``fn(t)`` returns ``(point, derivative)`` in (radius, Z). Raises ``ValueError`` when the
    curve cannot be fitted within ``MAX_DEPTH`` bisections (a cusp or a degenerate curve).
    """
    out: list[Segment] = []

    def piece(a: float, b: float, depth: int) -> None:
        pa, da = fn(a)
        pb, db = fn(b)
        ts = [a + (b - a) * (i + 0.5) / SAMPLES for i in range(SAMPLES)]
        pts = [fn(t)[0] for t in ts]
        if dist(pa, pb) < EPS:
            return
        first, last = a == t0, b == t1  # pieces at the curve's ends keep its end tangents
        try:
            ua, ub = _unit(da), _unit(db)
        except ValueError:
            ua = ub = None
        chord = (pb[0] - pa[0], pb[1] - pa[1])
        # straight?
        line = Line(pa, pb)
        if _deviation([line], pts) <= tol and (
                not (first or last) or (ua is not None and (not first or _along(chord, ua))
                                        and (not last or _along(chord, ub)))):
            out.append(line)
            return
        # one arc: through the ends and the middle, or at an end of the curve leaving it
        # along the curve's tangent
        arc: Segment | None = None
        if not (first or last):
            mid = fn((a + b) / 2)[0]
            circ = circle3(pa, mid, pb)
            if circ is not None:
                c, _r = circ
                ccw = cross((mid[0] - pa[0], mid[1] - pa[1]), (pb[0] - mid[0], pb[1] - mid[1])) > 0
                arc = Arc(pa, pb, c, cw=not ccw)
        elif ua is not None:
            arc = arc_from_tangent(pa, ua, pb) if first else \
                arc_from_tangent(pb, (-ub[0], -ub[1]), pa).reversed()
            if first and last and not _along(arc.tangent_at_end(), ub):
                arc = None
        if arc is not None and _deviation([arc], pts) <= tol and _covers([arc], pts, pa, pb):
            out.append(arc)
            return
        try:
            segs = biarc(pa, ua, pb, ub) if ua is not None else []
        except ValueError:
            segs = []
        if segs and _deviation(segs, pts) <= tol and _covers(segs, pts, pa, pb):
            out.extend(segs)
            return
        if depth >= MAX_DEPTH:
            raise ValueError(f"curve cannot be fitted with arcs within {tol:g} mm near "
                             f"(r={pa[0]:.4f}, z={pa[1]:.4f})")
        m = (a + b) / 2
        piece(a, m, depth + 1)
        piece(m, b, depth + 1)

    piece(t0, t1, 0)
    return out


def _covers(segs: Sequence[Segment], pts: Sequence[Point], pa: Point, pb: Point) -> bool:
    """Reject a biarc that loops (its length far exceeds the polyline through the samples)."""
    poly = [pa, *pts, pb]
    plen = sum(dist(u, v) for u, v in zip(poly, poly[1:]))
    return sum(s.length for s in segs) <= 1.5 * plen + 1e-9
