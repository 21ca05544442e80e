"""Clean-up of segment chains: merging pieces that continue each other, absorbing pieces
shorter than a resolution.

One implementation for the whole package: the CAD front end merges the pieces a seam, a face
split or a STEP exporter leaves (``tol`` 1e-6 mm), the planner merges the fragments of a
compensated tip path before writing it and absorbs moves shorter than the program's number
resolution (:func:`absorb_short`).

Exactness (the bounds are stated per function and hold for the whole merged piece, not per
joint, so merging many small pieces cannot drift):

* :func:`merge_segments`: lines are merged while every joint they absorb lies within ``tol``
  of the merged line and all of them point the same way; arcs are merged while they have the
  same direction, their centres and radii agree within ``tol`` and every absorbed joint lies
  within ``tol`` of the merged circle (the centre and radius kept from the first piece). A
  merged line stays within ``tol`` of the pieces it replaces (the pieces are straight between
  joints within ``tol`` of it); a merged arc within ``2 tol`` (a point of a piece is off the
  merged circle by at most ``|dc| + |dr|``).
* :func:`absorb_short`: a piece shorter than ``min_len`` is removed, its line neighbours
  taking the gap (arcs keep their end points on their circles); the path moves by less than
  ``min_len / 2`` (proof in the function's docstring).
"""
from __future__ import annotations

import math
from typing import Sequence

from .primitives import Arc, Line, Point, Segment, dist


def _line_ok(start: Point, end: Point, joints: Sequence[Point], dirs: Sequence[Point],
             tol: float) -> bool:
    L = dist(start, end)
    if L < 1e-12:
        return False
    d = ((end[0] - start[0]) / L, (end[1] - start[1]) / L)
    if any(u[0] * d[0] + u[1] * d[1] <= 0 for u in dirs if u != (0.0, 0.0)):
        return False  # a piece that runs backwards is not a continuation
    carrier = Line(start, end)
    return all(carrier.distance_to(p) <= tol for p in joints)


def merge_segments(segs: Sequence[Segment], tol: float = 1e-6) -> list[Segment]:
    """Join consecutive collinear lines and co-circular arcs (same centre, radius and
    direction) into one segment each; the result stays within ``tol`` of ``segs`` (see the
    module docstring)."""
    out: list[Segment] = []
    joints: list[Point] = []  # joints absorbed into out[-1]
    dirs: list[Point] = []  # directions of the lines merged into out[-1]
    for s in segs:
        if out:
            p = out[-1]
            if isinstance(p, Line) and isinstance(s, Line):
                if not dirs:
                    dirs = [p.direction]
                j = joints + [p.end]
                dd = dirs + [s.direction]
                if _line_ok(p.start, s.end, j, dd, tol):
                    out[-1] = Line(p.start, s.end)
                    joints, dirs = j, dd
                    continue
            if (isinstance(p, Arc) and isinstance(s, Arc) and p.cw == s.cw
                    and dist(p.center, s.center) <= tol and abs(p.radius - s.radius) <= tol
                    and abs(p.sweep) + abs(s.sweep) < 2 * math.pi - 1e-6):
                r = p.radius
                j = joints + [p.end]
                if all(abs(dist(p.center, q) - r) <= tol for q in j + [s.end]):
                    out[-1] = Arc(p.start, s.end, p.center, p.cw)
                    joints = j
                    continue
        out.append(s)
        joints, dirs = [], []
    return out


def absorb_short(segs: Sequence[Segment], min_len: float) -> list[Segment]:
    """Remove pieces shorter than ``min_len`` (mm) from a connected chain, keeping it
    connected and its first and last points fixed.

    * between two lines the neighbours meet at the short piece's mid-point ``m``: every point
      ``p`` of the piece is within ``(|p-a| + |p-b|) / 2 <= L / 2`` of ``m`` (median bound),
      and each line moves by at most ``|a-m| <= L / 2``;
    * next to one line (the other neighbour an arc, or the chain's end) a piece shorter than
      ``min_len / 2`` is taken over by that line, whose end moves by ``L < min_len / 2``;
    * anything else (a short piece between two arcs) is kept.

    So the path moves by less than ``min_len / 2``.
    """
    out = list(segs)
    i = 0
    while i < len(out):
        s = out[i]
        if s.length >= min_len or len(out) < 2:
            i += 1
            continue
        prev = out[i - 1] if i > 0 else None
        nxt = out[i + 1] if i + 1 < len(out) else None
        if isinstance(prev, Line) and isinstance(nxt, Line):
            m = ((s.start[0] + s.end[0]) / 2, (s.start[1] + s.end[1]) / 2)
            out[i - 1] = Line(prev.start, m)
            out[i + 1] = Line(m, nxt.end)
            del out[i]
            continue
        if s.length < min_len / 2:
            if isinstance(prev, Line) and prev.length > s.length:
                out[i - 1] = Line(prev.start, s.end)
                del out[i]
                continue
            if isinstance(nxt, Line) and nxt.length > s.length:
                out[i + 1] = Line(s.start, nxt.end)
                del out[i]
                continue
        i += 1
    return out
