"""The chamfer or round between two lines: the one construction the interpreter (``G01 ... C``
/ ``R``, FANUC ``,C`` / ``,R``) and the part sketches (``line_to(chamfer=, fillet=)``) use.

A corner at ``g`` between the line ``a -> g`` and the line ``g -> e``: a chamfer ``C`` cuts
``size`` mm from the corner along both lines; a round ``R`` of radius ``size`` is tangent to
both, its tangent points ``size * tan(turn / 2)`` from the corner. Whether it fits and what
to say when it does not stay with the callers (their messages differ).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Optional

from .primitives import Arc, Line, Point, cross


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
