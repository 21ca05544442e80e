"""The chamfer or round between two lines: the one construction the interpreter (``G01 ... C``
/ ``R``, FANUC ``,C`` / ``,R``) and the part sketches (``line_to(chamfer=, fillet=)``) use.

A corner at ``g`` between the line ``a -> g`` and the line ``g -> e``: a chamfer ``C`` cuts
``size`` mm from the corner along both lines; a round ``R`` of radius ``size`` is tangent to
both, its tangent points ``size * tan(turn / 2)`` from the corner. Whether it fits and what
to say when it does not stay with the callers (their messages differ).

:func:`element_corner` is the same corner between any two contour elements, lines or arcs
(the SINUMERIK ``CHF=`` / ``RND=``): the round is the circle of that radius tangent to both
on the inside of the corner (its centre where the two carriers moved inward by the radius
meet), the chamfer the line whose ends lie on the elements at equal chord distances from the
corner point and whose own length is the size. Both stay exact: an arc keeps its centre and
sense, only the end the corner cuts moves.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

from .intersect import circle_circle_carriers, line_circle_carriers, line_line_carriers
from .primitives import (Arc, Line, Point, Segment, cross, dist, left_normal, point_at_angle,
                         polar_angle)


class CornerError(ValueError):
    """No corner to cut: ``reason`` is ``"straight"`` (the lines continue each other) or
    ``"reverse"`` (the second line turns back on the first) or ``"degenerate"`` (a line
    of no length)."""

    def __init__(self, reason: str):
        super().__init__(reason)
        self.reason = reason


@dataclass(frozen=True)
class Corner:
    kind: str  # "C" chamfer, "R" round
    size: float
    trim: float  # distance from the corner to each tangent point
    len_in: float  # length of the incoming line a -> g
    len_out: float  # length of the outgoing line g -> e
    start: Point  # tangent point on the incoming line
    end: Point  # tangent point on the outgoing line
    center: Optional[Point]  # of the round (None for a chamfer)
    cw: bool  # the round's sense (G02 when True)

    @property
    def fits(self) -> bool:
        return self.trim <= self.len_in and self.trim <= self.len_out

    def segment(self):
        """The chamfer line or the round's arc from :attr:`start` to :attr:`end`."""
        if self.center is None:
            return Line(self.start, self.end)
        return Arc(self.start, self.end, self.center, self.cw)


def corner(a: Point, g: Point, e: Point, kind: str, size: float) -> Corner:
    """The chamfer (``kind == "C"``) or round (``"R"``) of ``size`` at ``g`` between the lines
    ``a -> g`` and ``g -> e``; raises :class:`CornerError` when there is no corner."""
    l1 = math.hypot(g[0] - a[0], g[1] - a[1])
    l2 = math.hypot(e[0] - g[0], e[1] - g[1])
    if l1 < 1e-12 or l2 < 1e-12:
        raise CornerError("degenerate")
    u1 = ((g[0] - a[0]) / l1, (g[1] - a[1]) / l1)
    u2 = ((e[0] - g[0]) / l2, (e[1] - g[1]) / l2)
    cr = cross(u1, u2)
    dot = u1[0] * u2[0] + u1[1] * u2[1]
    if abs(cr) < 1e-12:
        raise CornerError("straight" if dot > 0 else "reverse")
    if kind == "C":
        t = size
    else:
        theta = math.atan2(abs(cr), dot)  # the turning angle
        t = size * math.tan(theta / 2.0)
    b = (g[0] - u1[0] * t, g[1] - u1[1] * t)
    c = (g[0] + u2[0] * t, g[1] + u2[1] * t)
    center = None
    cw = cr < 0
    if kind != "C":
        # from B along the normal toward the inside of the turn (left when turning left)
        nx, nz = (u1[1], -u1[0]) if cr > 0 else (-u1[1], u1[0])
        center = (b[0] + nx * size, b[1] + nz * size)
    return Corner(kind, size, t, l1, l2, b, c, center, cw)


# -- corners next to arcs (SINUMERIK CHF= / RND= between any two contour elements) -------------

@dataclass(frozen=True)
class ElementCorner:
    """The chamfer or round between two elements that meet at a corner point: ``first`` and
    ``second`` as the corner leaves them (``None`` when the corner takes all of an element;
    an arc keeps its centre and sense, only its end or start moves) and ``segment`` the
    chamfer's line or the round's arc from the end of ``first`` to the start of ``second``."""

    kind: str
    size: float
    first: Optional[Segment]
    segment: Segment
    second: Optional[Segment]

    @property
    def start(self) -> Point:
        return self.segment.start

    @property
    def end(self) -> Point:
        return self.segment.end


class CornerFitError(CornerError):
    """The chamfer or round does not fit: ``element`` is ``"first"`` or ``"second"`` (the
    element too short or, for a round inside an arc, too tight) or ``"both"``, ``detail`` says why."""

    def __init__(self, element: str, detail: str):
        super().__init__("fit")
        self.element = element
        self.detail = detail


def _travelled(seg: Segment, p: Point) -> float:
    """How far along ``seg`` the point ``p`` (on its carrier) lies: a fraction of a line's
    length, an angle (rad) from an arc's start in its sense."""
    if isinstance(seg, Line):
        d = seg.direction
        L = seg.length
        return ((p[0] - seg.start[0]) * d[0] + (p[1] - seg.start[1]) * d[1]) / L
    a = polar_angle(seg.center, p) - seg.start_angle
    if seg.cw:
        a = -a
    a %= 2.0 * math.pi
    if a > 2.0 * math.pi - 1e-9:
        a = 0.0
    return a


def _span(seg: Segment) -> float:
    return 1.0 if isinstance(seg, Line) else abs(seg.sweep)


def _within(seg: Segment, p: Point) -> bool:
    t = _travelled(seg, p)
    tol = 1e-9 if isinstance(seg, Line) else 1e-9 / max(seg.radius, 1e-9)
    return -tol <= t <= _span(seg) + tol


def _cut_end(seg: Segment, p: Point) -> Optional[Segment]:
    """``seg`` up to ``p`` (None when nothing is left of it)."""
    if dist(seg.start, p) <= 1e-9:
        return None
    if isinstance(seg, Line):
        return Line(seg.start, p)
    return Arc(seg.start, p, seg.center, seg.cw)


def _cut_start(seg: Segment, p: Point) -> Optional[Segment]:
    """``seg`` from ``p`` on (None when nothing is left of it)."""
    if dist(p, seg.end) <= 1e-9:
        return None
    if isinstance(seg, Line):
        return Line(p, seg.end)
    return Arc(p, seg.end, seg.center, seg.cw)


def _describe(seg: Segment) -> str:
    if isinstance(seg, Line):
        return f"the line ({seg.length:.3f} mm)"
    return (f"the arc (radius {seg.radius:.3f} mm, "
            f"{math.degrees(abs(seg.sweep)):.3f} deg)")


def _leg_point(seg: Segment, g: Point, d: float, back: bool) -> Optional[Point]:
    """The point of ``seg`` at the chord distance ``d`` from its end ``g`` (``back``) or its
    start ``g``; None when the element has no such point."""
    if isinstance(seg, Line):
        if d > seg.length + 1e-12:
            return None
        u = seg.direction
        s = -d if back else d
        return (g[0] + u[0] * s, g[1] + u[1] * s)
    r = seg.radius
    if d > 2.0 * r:
        return None
    phi = 2.0 * math.asin(min(1.0, d / (2.0 * r)))
    if phi > abs(seg.sweep) + 1e-12:
        return None
    forward = -1.0 if seg.cw else 1.0  # the polar angle's change along the arc
    a = polar_angle(seg.center, g) + (-phi if back else phi) * forward
    return point_at_angle(seg.center, r, a)


def _max_leg(seg: Segment) -> float:
    if isinstance(seg, Line):
        return seg.length
    return 2.0 * seg.radius * math.sin(min(abs(seg.sweep), math.pi) / 2.0)


def _offset_carrier(seg: Segment, r: float, s: float):
    """The carrier of ``seg`` moved ``r`` to its left (``s`` = 1) or right (-1): a line as
    two points, an arc as (centre, radius); None when an arc's circle shrinks to nothing."""
    if isinstance(seg, Line):
        n = left_normal(seg.direction)
        dx, dz = n[0] * r * s, n[1] * r * s
        return ("line", (seg.start[0] + dx, seg.start[1] + dz), (seg.end[0] + dx, seg.end[1] + dz))
    # the centre lies on the left of a counter-clockwise (G3) arc
    toward = s if not seg.cw else -s
    R = seg.radius - toward * r
    if R <= 1e-9:
        return None
    return ("circle", seg.center, R)


def _meet(c1, c2) -> list[Point]:
    if c1[0] == "line" and c2[0] == "line":
        p = line_line_carriers(c1[1], c1[2], c2[1], c2[2])
        return [] if p is None else [p]
    if c1[0] == "line":
        return line_circle_carriers(c1[1], c1[2], c2[1], c2[2])
    if c2[0] == "line":
        return line_circle_carriers(c2[1], c2[2], c1[1], c1[2])
    return circle_circle_carriers(c1[1], c1[2], c2[1], c2[2])


def _foot(seg: Segment, p: Point) -> Point:
    """The foot of ``p`` on the carrier of ``seg``."""
    if isinstance(seg, Line):
        u = seg.direction
        t = (p[0] - seg.start[0]) * u[0] + (p[1] - seg.start[1]) * u[1]
        return (seg.start[0] + u[0] * t, seg.start[1] + u[1] * t)
    c = seg.center
    d = dist(c, p)
    r = seg.radius
    return (c[0] + (p[0] - c[0]) * r / d, c[1] + (p[1] - c[1]) * r / d)


def element_corner(first: Segment, second: Segment, kind: str, size: float) -> ElementCorner:
    """The chamfer (``kind == "C"``, ``size`` the chamfer's own length, its ends at equal
    chord distances from the corner point) or round (``"R"``, ``size`` the radius, tangent to
    both elements on the inside of the corner) between ``first`` (a line or arc ending at the
    corner point) and ``second`` (starting there).

    Raises :class:`CornerError` ``"straight"`` when the elements meet tangentially (no
    corner), ``"reverse"`` when the second turns back along the first, ``"degenerate"`` for
    an element of no length, and :class:`CornerFitError` when the corner does not fit."""
    g = first.end
    if dist(first.start, g) < 1e-12 and isinstance(first, Line) or \
            dist(g, second.end) < 1e-12 and isinstance(second, Line):
        raise CornerError("degenerate")
    t1 = first.tangent_at_end()
    t2 = second.tangent_at_start()
    cr = cross(t1, t2)
    dot = t1[0] * t2[0] + t1[1] * t2[1]
    if abs(cr) < 1e-9:
        raise CornerError("straight" if dot > 0 else "reverse")
    if kind == "C":
        return _chamfer(first, second, g, size)
    s = 1.0 if cr > 0 else -1.0  # the round lies on the left when the path turns left
    o1 = _offset_carrier(first, size, s)
    o2 = _offset_carrier(second, size, s)
    if o1 is None:
        raise CornerFitError("first", f"the radius is not smaller than {_describe(first)} "
                                      f"on the inside of the corner")
    if o2 is None:
        raise CornerFitError("second", f"the radius is not smaller than {_describe(second)} "
                                       f"on the inside of the corner")
    best = None
    for c in _meet(o1, o2):
        b, e = _foot(first, c), _foot(second, c)
        ok1, ok2 = _within(first, b), _within(second, e)
        rank = (not (ok1 and ok2), dist(b, g) + dist(e, g))
        if best is None or rank < best[0]:
            best = (rank, c, b, e, ok1, ok2)
    if best is None:
        raise CornerFitError("both", f"no circle of this radius touches {_describe(first)} and "
                                      f"{_describe(second)} on the inside of the corner")
    _, c, b, e, ok1, ok2 = best
    if not ok1:
        raise CornerFitError("first", f"its tangent point lies beyond {_describe(first)}")
    if not ok2:
        raise CornerFitError("second", f"its tangent point lies beyond {_describe(second)}")
    seg = Arc(b, e, c, cr < 0)
    return ElementCorner(kind, size, _cut_end(first, b), seg, _cut_start(second, e))


def _chamfer(first: Segment, second: Segment, g: Point, length: float) -> ElementCorner:
    """The chamfer of ``length`` whose ends lie at equal chord distances ``d`` from ``g``: ``d``
    solves |B(d) C(d)| = length (by bisection to the float precision; on two lines
    d = length / (2 cos(turn / 2)))."""
    hi = min(_max_leg(first), _max_leg(second))

    def ends(d: float):
        return _leg_point(first, g, d, True), _leg_point(second, g, d, False)

    b, e = ends(hi)
    while (b is None or e is None) and hi > 0.0:  # rounding at the element's far end
        hi *= 1.0 - 1e-12
        b, e = ends(hi)
    if b is None or e is None or dist(b, e) < length - 1e-12:
        short = "first" if _max_leg(first) <= _max_leg(second) else "second"
        el = first if short == "first" else second
        raise CornerFitError(short, f"a chamfer of {length:g} mm needs more than "
                                    f"{_describe(el)}")
    lo = 0.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        b, e = ends(mid)
        if dist(b, e) < length:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15 * max(1.0, hi):
            break
    b, e = ends(hi)
    return ElementCorner("C", length, _cut_end(first, b), Line(b, e), _cut_start(second, e))
