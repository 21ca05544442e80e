"""Exact 2-D primitives of the turning half-plane.

Conventions (one place for them, the whole package follows):

* A point is a tuple ``(x, z)``: ``x`` is the **radius** (physical distance from the
  spindle axis, mm), ``z`` the position along the axis (mm). Diameters appear only at the
  edges (program text, JSON, display).
* Orientation is judged in the view with **Z to the right and X up** (the HNC-21T view of
  fig. 3.3.8/3.3.43). In that view ``G02`` is clockwise, so ``Arc.cw`` is True for G02.
  The polar angle of a point about a centre is ``atan2(x - xc, z - zc)``; clockwise means
  that angle decreases along the arc.
* "Left" of a direction of travel is the side obtained by turning the direction
  counter-clockwise in that view, so G41 puts the tool on the left, G42 on the right.

Segments are immutable. Sampling to polylines exists only for the simulator and plots, and
always takes a chord error bound.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterator, Sequence, Union

EPS = 1e-9
#: positions closer than this are the same point (mm)
TOL = 1e-6

Point = tuple[float, float]


def dist(a: Point, b: Point) -> float:
    return math.hypot(a[0] - b[0], a[1] - b[1])


def same_point(a: Point, b: Point, tol: float = TOL) -> bool:
    return abs(a[0] - b[0]) <= tol and abs(a[1] - b[1]) <= tol


def cross(u: Point, v: Point) -> float:
    """Cross product in the (z right, x up) view: >0 when v turns counter-clockwise from u."""
    # with horizontal axis z and vertical axis x: u = (uz, ux)
    return u[1] * v[0] - u[0] * v[1]


def left_normal(d: Point) -> Point:
    """Unit vector pointing to the left of direction ``d`` (in the z right, x up view)."""
    n = math.hypot(d[0], d[1])
    if n < EPS:
        raise ValueError("zero-length direction has no normal")
    # rotate (dz, dx) by +90 deg: (dz, dx) -> (-dx, dz); back in (x, z) order
    return (d[1] / n, -d[0] / n)


def polar_angle(center: Point, p: Point) -> float:
    return math.atan2(p[0] - center[0], p[1] - center[1])


def point_at_angle(center: Point, radius: float, ang: float) -> Point:
    return (center[0] + radius * math.sin(ang), center[1] + radius * math.cos(ang))


@dataclass(frozen=True, slots=True)
class Line:
    start: Point
    end: Point

    kind = "line"

    @property
    def length(self) -> float:
        return dist(self.start, self.end)

    @property
    def direction(self) -> Point:
        """Unit direction (dx, dz)."""
        L = self.length
        if L < EPS:
            return (0.0, 0.0)
        return ((self.end[0] - self.start[0]) / L, (self.end[1] - self.start[1]) / L)

    def tangent_at_start(self) -> Point:
        return self.direction

    def tangent_at_end(self) -> Point:
        return self.direction

    def point_at(self, t: float) -> Point:
        """Point at parameter ``t`` in [0, 1]."""
        return (self.start[0] + (self.end[0] - self.start[0]) * t,
                self.start[1] + (self.end[1] - self.start[1]) * t)

    def reversed(self) -> "Line":
        return Line(self.end, self.start)

    def translated(self, dx: float, dz: float) -> "Line":
        return Line((self.start[0] + dx, self.start[1] + dz), (self.end[0] + dx, self.end[1] + dz))

    def sample(self, chord_error: float = 0.0005) -> list[Point]:
        return [self.start, self.end]

    def bbox(self) -> tuple[float, float, float, float]:
        """(xmin, zmin, xmax, zmax)."""
        return (min(self.start[0], self.end[0]), min(self.start[1], self.end[1]),
                max(self.start[0], self.end[0]), max(self.start[1], self.end[1]))

    def closest_point(self, p: Point) -> Point:
        dx, dz = self.end[0] - self.start[0], self.end[1] - self.start[1]
        L2 = dx * dx + dz * dz
        if L2 < EPS * EPS:
            return self.start
        t = ((p[0] - self.start[0]) * dx + (p[1] - self.start[1]) * dz) / L2
        t = min(1.0, max(0.0, t))
        return (self.start[0] + t * dx, self.start[1] + t * dz)

    def distance_to(self, p: Point) -> float:
        return dist(p, self.closest_point(p))


@dataclass(frozen=True, slots=True)
class Arc:
    """Circular arc from ``start`` to ``end`` about ``center``; ``cw`` as G02 (see module doc).

    A full circle (start == end) is not a valid ``Arc``; split it in two.
    """
    start: Point
    end: Point
    center: Point
    cw: bool

    kind = "arc"

    # the angles, radius and sweep are worked out inline (the formulas of polar_angle, dist and
    # point_at_angle), each once per call: the planner and the verifier ask for them often

    @property
    def radius(self) -> float:
        c, p = self.center, self.start
        return math.hypot(c[0] - p[0], c[1] - p[1])

    @property
    def start_angle(self) -> float:
        c, p = self.center, self.start
        return math.atan2(p[0] - c[0], p[1] - c[1])

    @property
    def end_angle(self) -> float:
        c, p = self.center, self.end
        return math.atan2(p[0] - c[0], p[1] - c[1])

    def _angles(self) -> tuple[float, float]:
        """(start angle, sweep)."""
        c, p, q = self.center, self.start, self.end
        a0 = math.atan2(p[0] - c[0], p[1] - c[1])
        return a0, _sweep(a0, math.atan2(q[0] - c[0], q[1] - c[1]), self.cw)

    @property
    def sweep(self) -> float:
        """Signed sweep angle in radians: negative for cw, positive for ccw; |sweep| in (0, 2pi)."""
        return self._angles()[1]

    @property
    def length(self) -> float:
        return abs(self.sweep) * self.radius

    def point_at(self, t: float) -> Point:
        a0, s = self._angles()
        c, p = self.center, self.start
        r = math.hypot(c[0] - p[0], c[1] - p[1])
        ang = a0 + s * t
        return (c[0] + r * math.sin(ang), c[1] + r * math.cos(ang))

    def _tangent(self, p: Point) -> Point:
        # radial vector in (x, z); tangent = rotate radial by +-90 deg in the (z, x) view
        rx, rz = p[0] - self.center[0], p[1] - self.center[1]
        r = math.hypot(rx, rz) or 1.0
        # ccw tangent: d/dtheta of (sin t, cos t) = (cos t, -sin t) in (x, z)
        tx, tz = rz / r, -rx / r
        if self.cw:
            tx, tz = -tx, -tz
        return (tx, tz)

    def tangent_at_start(self) -> Point:
        return self._tangent(self.start)

    def tangent_at_end(self) -> Point:
        return self._tangent(self.end)

    def reversed(self) -> "Arc":
        return Arc(self.end, self.start, self.center, not self.cw)

    def translated(self, dx: float, dz: float) -> "Arc":
        return Arc((self.start[0] + dx, self.start[1] + dz), (self.end[0] + dx, self.end[1] + dz),
                   (self.center[0] + dx, self.center[1] + dz), self.cw)

    def contains_angle(self, ang: float) -> bool:
        """True when the polar angle ``ang`` lies on the arc (ends included)."""
        a0, s = self._angles()
        d = ang - a0
        if s > 0:
            d = d % (2 * math.pi)
            return d <= s + 1e-12
        d = (-d) % (2 * math.pi)
        return d <= -s + 1e-12

    def segments_for(self, chord_error: float) -> int:
        """Number of chords so that the sagitta does not exceed ``chord_error``."""
        r = self.radius
        if r <= chord_error:
            return max(1, int(math.ceil(abs(self.sweep) / (math.pi / 2))))
        half = math.acos(max(-1.0, 1.0 - chord_error / r))
        return max(1, int(math.ceil(abs(self.sweep) / (2 * half))))

    def sample(self, chord_error: float = 0.0005) -> list[Point]:
        """Polyline through the arc whose chords deviate at most ``chord_error`` from it."""
        return [(x, z) for x, z in self.sample_array(chord_error).tolist()]

    def sample_array(self, chord_error: float = 0.0005):
        """:meth:`sample` as a numpy array (n, 2) of (x, z) rows: the ends exact, the points
        between at the angles a0 + sweep * i / n (:func:`point_at_angle`'s formula, computed
        for all of them at once)."""
        import numpy as np  # not at import time: the interpreter runs without numpy
        n = self.segments_for(chord_error)
        a0, s, r = self.start_angle, self.sweep, self.radius
        ang = a0 + s * np.arange(1, n, dtype=float) / n
        out = np.empty((n + 1, 2))
        out[0], out[n] = self.start, self.end
        out[1:n, 0] = self.center[0] + r * np.sin(ang)
        out[1:n, 1] = self.center[1] + r * np.cos(ang)
        return out

    @staticmethod
    def sample_arrays(arcs: Sequence["Arc"], chord_error: float = 0.0005):
        """:meth:`sample_array` of each arc, the same points, computed together: their rows one
        after another ((sum of n_i + 1, 2) of (x, z)) and each arc's number of rows."""
        import numpy as np  # not at import time: the interpreter runs without numpy
        m = len(arcs)
        n = np.empty(m, dtype=np.int64)
        a0 = np.empty(m)
        s = np.empty(m)
        r = np.empty(m)
        ends = np.empty((m, 2, 2))
        cen = np.empty((m, 2))
        for i, a in enumerate(arcs):
            n[i] = a.segments_for(chord_error)
            a0[i], s[i], r[i] = a.start_angle, a.sweep, a.radius
            ends[i, 0], ends[i, 1], cen[i] = a.start, a.end, a.center
        rows = n + 1
        first = np.cumsum(rows) - rows
        out = np.empty((int(rows.sum()), 2))
        inner = n - 1
        own = np.repeat(np.arange(m), inner)
        k = np.arange(len(own)) - np.repeat(np.cumsum(inner) - inner, inner) + 1
        ang = a0[own] + s[own] * k / n[own]
        at = first[own] + k
        out[at, 0] = cen[own, 0] + r[own] * np.sin(ang)
        out[at, 1] = cen[own, 1] + r[own] * np.cos(ang)
        out[first] = ends[:, 0]
        out[first + n] = ends[:, 1]
        return out, rows

    def bbox(self) -> tuple[float, float, float, float]:
        xs = [self.start[0], self.end[0]]
        zs = [self.start[1], self.end[1]]
        r = self.radius
        cx, cz = self.center
        a0, s = self._angles()
        for ang, p in ((0.0, (cx, cz + r)), (math.pi / 2, (cx + r, cz)),
                       (math.pi, (cx, cz - r)), (-math.pi / 2, (cx - r, cz))):
            # contains_angle(ang)
            if ((ang - a0) % (2 * math.pi) <= s + 1e-12 if s > 0
                    else (-(ang - a0)) % (2 * math.pi) <= -s + 1e-12):
                xs.append(p[0])
                zs.append(p[1])
        return (min(xs), min(zs), max(xs), max(zs))

    def closest_point(self, p: Point) -> Point:
        ang = polar_angle(self.center, p)
        if dist(p, self.center) > EPS and self.contains_angle(ang):
            return point_at_angle(self.center, self.radius, ang)
        return self.start if dist(p, self.start) <= dist(p, self.end) else self.end

    def distance_to(self, p: Point) -> float:
        return dist(p, self.closest_point(p))

    @staticmethod
    def from_radius(start: Point, end: Point, radius: float, cw: bool) -> "Arc":
        """Arc through two points with signed radius: R > 0 the arc of at most 180 deg,
        R < 0 the larger arc (FANUC usage; the manual does not define it).

        Raises ``ValueError`` when |R| is smaller than half the chord.
        """
        r = abs(radius)
        dx, dz = end[0] - start[0], end[1] - start[1]
        c = math.hypot(dx, dz)
        if c < EPS:
            raise ValueError("arc start and end coincide")
        if r < c / 2 - 1e-7:
            raise ValueError(f"arc radius {r:g} is smaller than half the chord {c / 2:g}")
        h = math.sqrt(max(0.0, r * r - (c / 2) ** 2))
        mx, mz = (start[0] + end[0]) / 2, (start[1] + end[1]) / 2
        ln = left_normal((dx, dz))
        # For a cw arc of at most 180 deg the centre lies to the right of the chord.
        small_side = -1.0 if cw else 1.0
        side = small_side if radius > 0 else -small_side
        center = (mx + side * h * ln[0], mz + side * h * ln[1])
        return Arc(start, end, center, cw)


Segment = Union[Line, Arc]


def _sweep(a0: float, a1: float, cw: bool) -> float:
    """:attr:`Arc.sweep` of an arc from the polar angle a0 to a1."""
    if cw:
        s = a1 - a0
        while s >= -EPS:
            s -= 2 * math.pi
        while s < -2 * math.pi:
            s += 2 * math.pi
        return s
    s = a1 - a0
    while s <= EPS:
        s += 2 * math.pi
    while s > 2 * math.pi:
        s -= 2 * math.pi
    return s


def reverse_chain(segs: Sequence[Segment]) -> list[Segment]:
    return [s.reversed() for s in reversed(segs)]


def chain_is_connected(segs: Sequence[Segment], tol: float = TOL) -> bool:
    return all(same_point(a.end, b.start, tol) for a, b in zip(segs, segs[1:]))


def sample_chain(segs: Sequence[Segment], chord_error: float = 0.0005) -> list[Point]:
    """Polyline of a connected chain with the stated chord error bound."""
    pts: list[Point] = []
    for s in segs:
        sp = s.sample(chord_error)
        if pts and same_point(pts[-1], sp[0]):
            sp = sp[1:]
        pts.extend(sp)
    return pts


def iter_points(segs: Sequence[Segment]) -> Iterator[Point]:
    if segs:
        yield segs[0].start
    for s in segs:
        yield s.end
