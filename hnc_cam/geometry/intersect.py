"""Exact intersections of lines, arcs, and their carrier lines/circles.

All functions return points as ``(x, z)`` tuples. ``*_carriers`` functions work on the
infinite line / full circle; ``intersect`` restricts to the segments themselves (ends
included, within ``TOL``).
"""
from __future__ import annotations

import math
from typing import Sequence

from .primitives import EPS, TOL, Arc, Line, Point, Segment, dist, polar_angle


def line_line_carriers(p0: Point, p1: Point, q0: Point, q1: Point) -> Point | None:
    """Intersection of the infinite lines p0p1 and q0q1 (None when parallel)."""
    d1 = (p1[0] - p0[0], p1[1] - p0[1])
    d2 = (q1[0] - q0[0], q1[1] - q0[1])
    den = d1[0] * d2[1] - d1[1] * d2[0]
    if abs(den) < EPS * max(1.0, math.hypot(*d1) * math.hypot(*d2)):
        return None
    t = ((q0[0] - p0[0]) * d2[1] - (q0[1] - p0[1]) * d2[0]) / den
    return (p0[0] + t * d1[0], p0[1] + t * d1[1])


def line_circle_carriers(p0: Point, p1: Point, c: Point, r: float) -> list[Point]:
    """Intersections of the infinite line p0p1 with the circle (c, r), ordered along p0->p1."""
    dx, dz = p1[0] - p0[0], p1[1] - p0[1]
    a = dx * dx + dz * dz
    if a < EPS * EPS:
        return []
    fx, fz = p0[0] - c[0], p0[1] - c[1]
    b = 2 * (fx * dx + fz * dz)
    cc = fx * fx + fz * fz - r * r
    disc = b * b - 4 * a * cc
    scale = max(1.0, r * r) * a
    if disc < -1e-12 * scale:
        return []
    if disc <= 1e-12 * scale:
        t = -b / (2 * a)
        return [(p0[0] + t * dx, p0[1] + t * dz)]
    s = math.sqrt(disc)
    t1, t2 = (-b - s) / (2 * a), (-b + s) / (2 * a)
    return [(p0[0] + t1 * dx, p0[1] + t1 * dz), (p0[0] + t2 * dx, p0[1] + t2 * dz)]


def circle_circle_carriers(c1: Point, r1: float, c2: Point, r2: float) -> list[Point]:
    d = dist(c1, c2)
    if d < EPS:
        return []
    if d > r1 + r2 + 1e-9 or d < abs(r1 - r2) - 1e-9:
        return []
    a = (r1 * r1 - r2 * r2 + d * d) / (2 * d)
    h2 = r1 * r1 - a * a
    h = math.sqrt(max(0.0, h2))
    ux, uz = (c2[0] - c1[0]) / d, (c2[1] - c1[1]) / d
    mx, mz = c1[0] + a * ux, c1[1] + a * uz
    if h < 1e-9:
        return [(mx, mz)]
    return [(mx - h * uz, mz + h * ux), (mx + h * uz, mz - h * ux)]


def _on_line(seg: Line, p: Point, tol: float) -> bool:
    return seg.distance_to(p) <= tol


def _on_arc(seg: Arc, p: Point, tol: float) -> bool:
    if abs(dist(p, seg.center) - seg.radius) > tol:
        return False
    if dist(p, seg.start) <= tol or dist(p, seg.end) <= tol:
        return True
    return seg.contains_angle(polar_angle(seg.center, p))


def on_segment(seg: Segment, p: Point, tol: float = TOL) -> bool:
    return _on_arc(seg, p, tol) if isinstance(seg, Arc) else _on_line(seg, p, tol)


def carrier_intersections(a: Segment, b: Segment) -> list[Point]:
    """Intersections of the carriers (infinite line / full circle) of two segments."""
    if isinstance(a, Line) and isinstance(b, Line):
        p = line_line_carriers(a.start, a.end, b.start, b.end)
        return [] if p is None else [p]
    if isinstance(a, Line):
        assert isinstance(b, Arc)
        return line_circle_carriers(a.start, a.end, b.center, b.radius)
    if isinstance(b, Line):
        return line_circle_carriers(b.start, b.end, a.center, a.radius)
    return circle_circle_carriers(a.center, a.radius, b.center, b.radius)


def intersect(a: Segment, b: Segment, tol: float = TOL) -> list[Point]:
    """Points where segments ``a`` and ``b`` meet (ends included). Overlapping collinear
    lines or co-circular arcs report their overlap's end points."""
    pts = carrier_intersections(a, b)
    if not pts:
        # overlapping carriers: report shared end points
        out = []
        for p in (a.start, a.end, b.start, b.end):
            if on_segment(a, p, tol) and on_segment(b, p, tol) and \
                    all(dist(p, q) > tol for q in out):
                out.append(p)
        return out
    return [p for p in pts if on_segment(a, p, tol) and on_segment(b, p, tol)]


def intersect_chain(seg: Segment, chain: Sequence[Segment], tol: float = TOL) -> list[tuple[int, Point]]:
    """All (index, point) where ``seg`` meets the chain's segments."""
    out: list[tuple[int, Point]] = []
    for i, s in enumerate(chain):
        for p in intersect(seg, s, tol):
            out.append((i, p))
    return out


def horizontal_hits(chain: Sequence[Segment], x: float) -> list[tuple[int, float]]:
    """Z values where the chain crosses the horizontal line X = x (radius), with the segment
    index; sorted by Z. Segments lying on the line report both of their ends."""
    out: list[tuple[int, float]] = []
    for i, s in enumerate(chain):
        if isinstance(s, Line):
            x0, x1 = s.start[0], s.end[0]
            if abs(x1 - x0) < EPS:
                if abs(x0 - x) <= TOL:
                    out.append((i, s.start[1]))
                    out.append((i, s.end[1]))
                continue
            t = (x - x0) / (x1 - x0)
            if -1e-12 <= t <= 1 + 1e-12:
                out.append((i, s.start[1] + t * (s.end[1] - s.start[1])))
        else:
            c, r = s.center, s.radius
            dxc = x - c[0]
            if abs(dxc) > r + 1e-12:
                continue
            h = math.sqrt(max(0.0, r * r - dxc * dxc))
            for z in {c[1] - h, c[1] + h}:
                if _on_arc(s, (x, z), 1e-9):
                    out.append((i, z))
    out.sort(key=lambda t: t[1])
    return out


def vertical_hits(chain: Sequence[Segment], z: float) -> list[tuple[int, float]]:
    """X values where the chain crosses the vertical line Z = z, sorted by X."""
    out: list[tuple[int, float]] = []
    for i, s in enumerate(chain):
        if isinstance(s, Line):
            z0, z1 = s.start[1], s.end[1]
            if abs(z1 - z0) < EPS:
                if abs(z0 - z) <= TOL:
                    out.append((i, s.start[0]))
                    out.append((i, s.end[0]))
                continue
            t = (z - z0) / (z1 - z0)
            if -1e-12 <= t <= 1 + 1e-12:
                out.append((i, s.start[0] + t * (s.end[0] - s.start[0])))
        else:
            c, r = s.center, s.radius
            dzc = z - c[1]
            if abs(dzc) > r + 1e-12:
                continue
            h = math.sqrt(max(0.0, r * r - dzc * dzc))
            for x in {c[0] - h, c[0] + h}:
                if _on_arc(s, (x, z), 1e-9):
                    out.append((i, x))
    out.sort(key=lambda t: t[1])
    return out
