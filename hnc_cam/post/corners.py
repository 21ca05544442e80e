"""Chamfers and rounds of a contour written as corner words (SINUMERIK ``CHF=`` / ``RND=``).

A contour block that is a chamfer (a line) or a round (an arc tangent to both neighbours)
between two lines can be written as the corner of those two lines with a corner word: the
incoming line runs to the corner point and carries ``CHF=`` (the chamfer's own length) or
``RND=`` (the round's radius); the chamfer or round block is left out. The post does this only
where the control rebuilds the planned points: the corner is recomputed from the numbers as
they are written (3 decimals, X as a diameter) with the one corner construction
(:func:`hnc_cam.geometry.corner.corner`), and the block is replaced only when both tangent
points land within :data:`TOLERANCE` of the plan's.

A chamfer or round next to an arc is written the same way (the control builds it with
:func:`hnc_cam.geometry.corner.element_corner`): the arc before the corner runs on its
circle to the corner point (CR= or I K of its start, as planned), the arc after it starts
there (its I K then taken from the corner point); the block is replaced only where the arcs
rebuilt from the written numbers keep their centres and the tangent points land within
:data:`TOLERANCE`.

A block's spindle change (:attr:`Block.spindle`) is not kept on a block left out: the
SINUMERIK post holds the spindle limit with ``LIMS=`` and writes no speed changes inside a
contour. The result is data for the templates, never text: ``(block, word, value)`` per written block,
``word`` ``""`` (the block as planned), ``"CHF"`` or ``"RND"`` (the block's end is the corner
point and ``value`` the chamfer length or the radius).
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, Optional

from ..geometry.corner import CornerError, corner, element_corner
from ..geometry.intersect import carrier_intersections
from ..geometry.primitives import Arc, Line, dist

#: the largest distance (mm) between a planned tangent point and the one the control builds
#: from the written corner
TOLERANCE = 0.001


def _written(p: tuple[float, float]) -> tuple[float, float]:
    """A point as the program writes it: X a diameter with 3 decimals, Z with 3 decimals."""
    return (round(2.0 * p[0], 3) / 2.0, round(p[1], 3))


def _meet(a, b, c, d) -> Optional[tuple[float, float]]:
    """The intersection of the line through a, b with the line through c, d (None when
    parallel)."""
    r = (b[0] - a[0], b[1] - a[1])
    s = (d[0] - c[0], d[1] - c[1])
    den = r[0] * s[1] - r[1] * s[0]
    if abs(den) < 1e-12:
        return None
    t = ((c[0] - a[0]) * s[1] - (c[1] - a[1]) * s[0]) / den
    return (a[0] + t * r[0], a[1] + t * r[1])


def _near(p, q) -> bool:
    return math.hypot(p[0] - q[0], p[1] - q[1]) <= TOLERANCE


def _chamfer(a, t1, t2, b) -> Optional[tuple[tuple[float, float], float]]:
    """(corner point, CHF length) when t1 -> t2 is a chamfer between a -> t1 and t2 -> b that
    the control rebuilds from the written numbers."""
    g = _meet(a, t1, t2, b)
    if g is None:
        return None
    d1, d2 = math.dist(g, t1), math.dist(g, t2)
    if d1 < 1e-6 or abs(d1 - d2) > 1e-6:
        return None
    if math.dist(a, g) <= d1 or math.dist(g, b) <= d2:  # the corner must lie beyond t1/t2
        return None
    gw = _written(g)
    chf = round(math.dist(t1, t2), 3)
    ux, uz = (gw[0] - a[0]), (gw[1] - a[1])
    l1 = math.hypot(ux, uz)
    vx, vz = (b[0] - gw[0]), (b[1] - gw[1])
    l2 = math.hypot(vx, vz)
    turn = math.atan2(abs(ux * vz - uz * vx), ux * vx + uz * vz)
    half = math.cos(turn / 2.0)
    if half <= 1e-9 or l1 < 1e-9 or l2 < 1e-9:
        return None
    trim = chf / (2.0 * half)
    s = (gw[0] - ux / l1 * trim, gw[1] - uz / l1 * trim)
    e = (gw[0] + vx / l2 * trim, gw[1] + vz / l2 * trim)
    if not (_near(s, t1) and _near(e, t2)) or trim >= l1 or trim >= l2:
        return None
    return g, chf


def _round(a, t1, arc, b) -> Optional[tuple[tuple[float, float], float]]:
    """(corner point, RND radius) when ``arc`` (t1 -> its end) is a round tangent to a -> t1
    and its end -> b that the control rebuilds from the written numbers."""
    t2 = (arc.x, arc.z)
    if arc.r is None:
        return None
    g = _meet(a, t1, t2, b)
    if g is None:
        return None
    gw = _written(g)
    r = round(abs(arc.r), 3)
    try:
        cn = corner(a, gw, b, "R", r)
    except CornerError:
        return None
    if not cn.fits or cn.cw != (arc.kind == "cw"):
        return None
    if not (_near(cn.start, t1) and _near(cn.end, t2)):
        return None
    return g, r


def _element(bl, a, e, g=None):
    """The planned element of block ``bl`` from ``a`` to ``e`` (a Line or Arc); None when
    an arc's centre is not known."""
    if not bl.arc:
        return Line(a, e)
    cw = bl.kind == "cw"
    if bl.i is not None:
        return Arc(a, e, (a[0] + bl.i, a[1] + (bl.k or 0.0)), cw)
    if bl.r is None:
        return None
    try:
        return Arc.from_radius(a, e, bl.r, cw)
    except ValueError:
        return None


def _extended(bl, seg, a, e, at_end: bool):
    """Block ``bl`` (an arc, planned as ``seg``) rewritten to run from ``a`` to ``e`` on the
    same circle, as the program writes it (CR= up to 170 degrees as the plan does, else I K
    from the start), and the arc the control builds from the written numbers; None when it
    cannot be written."""
    arc = Arc(a, e, seg.center, seg.cw)
    sweep = abs(math.degrees(arc.sweep))
    if bl.r is not None and sweep <= 170.0:
        r = round(seg.radius, 3)
        new = replace(bl, r=r, i=None, k=None)
        ws, we = _written(a), _written(e)
        try:
            built = Arc.from_radius(ws, we, r, seg.cw)
        except ValueError:
            return None
    else:
        i, k = round(seg.center[0] - a[0], 3), round(seg.center[1] - a[1], 3)
        new = replace(bl, r=None, i=i, k=k)
        ws, we = _written(a), _written(e)
        built = Arc(ws, we, (ws[0] + i, ws[1] + k), seg.cw)
    if at_end:
        new = replace(new, x=e[0], z=e[1])
    if not _near(built.center, seg.center):
        return None
    return new, built


def _arc_corner(blocks, i, pts):
    """(first block, second block, word, value, corner point) when blocks[i + 1] is a
    chamfer or round between blocks[i] and blocks[i + 2], one of them an arc, that the
    control rebuilds from the written numbers (see the module docstring)."""
    bl, mid, nx = blocks[i], blocks[i + 1], blocks[i + 2]
    a, t1, t2, b = pts[i:i + 4]
    e1, e2 = _element(bl, a, t1), _element(nx, t2, b)
    if e1 is None or e2 is None or dist(a, t1) < 1e-6 or dist(t2, b) < 1e-6:
        return None
    if mid.kind == "line":
        word, value = "CHF", round(dist(t1, t2), 3)
    elif mid.arc and mid.r is not None and mid.r > 0:
        word, value = "RND", round(mid.r, 3)
    else:
        return None
    if value <= 0:
        return None
    cands = carrier_intersections(e1, e2)
    if not cands:
        return None
    mid_pt = ((t1[0] + t2[0]) / 2.0, (t1[1] + t2[1]) / 2.0)
    g = min(cands, key=lambda p: dist(p, mid_pt))
    gw = _written(g)
    if isinstance(e1, Line):
        first, w1 = replace(bl, x=g[0], z=g[1]), Line(a, gw)
    else:
        got = _extended(bl, e1, a, g, True)
        if got is None:
            return None
        first, w1 = got
    if isinstance(e2, Line):
        second, w2 = nx, Line(gw, b)
    else:
        got = _extended(nx, e2, g, b, False)
        if got is None:
            return None
        second, w2 = got
    try:
        k = element_corner(w1, w2, "C" if word == "CHF" else "R", value)
    except CornerError:
        return None
    if not (_near(k.start, t1) and _near(k.end, t2)):
        return None
    if word == "RND" and k.segment.cw != (mid.kind == "cw"):
        return None
    return first, second, word, value, g


def corner_blocks(blocks: list, start: Any = None) -> list[tuple[Any, str, float]]:
    """The contour ``blocks`` (:class:`hnc_cam.plan.model.Block`) as written with corner
    words: ``(block, word, value)`` per written block (see the module docstring). ``start``:
    the point the first block starts from (x radius, z), where known."""
    x, z = (start if start is not None else (None, None))
    begin = None if x is None or z is None else (float(x), float(z))
    ends: list[Optional[tuple[float, float]]] = []  # end point of each block
    for bl in blocks:
        x = bl.x if bl.x is not None else x
        z = bl.z if bl.z is not None else z
        ends.append(None if x is None or z is None else (float(x), float(z)))
    pts = [begin] + ends  # pts[i] starts block i, pts[i + 1] ends it
    out: list[tuple[Any, str, float]] = []
    blocks = list(blocks)
    i = 0
    n = len(blocks)
    while i < n:
        bl = blocks[i]
        done = False
        if (i + 2 < n and (bl.arc or blocks[i + 2].arc) and bl.kind != "rapid"
                and blocks[i + 2].kind != "rapid" and not blocks[i + 1].label
                and blocks[i + 1].feed is None and blocks[i + 1].kind != "rapid"
                and None not in pts[i:i + 4]):
            found = _arc_corner(blocks, i, pts)
            if found is not None:
                first, second, word, value, g = found
                out.append((first, word, value))
                blocks[i + 2] = second
                pts[i + 2] = g
                i += 2
                continue
        if (i + 2 < n and bl.kind == "line" and not blocks[i + 1].label
                and blocks[i + 1].feed is None and blocks[i + 2].kind == "line"
                and None not in pts[i:i + 4]):
            a, t1, t2, b = pts[i:i + 4]
            mid = blocks[i + 1]
            found = None
            if mid.kind == "line":
                found = _chamfer(a, t1, t2, b)
                word = "CHF"
            elif mid.arc:
                found = _round(a, t1, mid, b)
                word = "RND"
            if found is not None:
                g, value = found
                out.append((replace(bl, x=g[0], z=g[1]), word, value))
                # the next line starts at the corner: its direction is unchanged
                pts[i + 2] = g
                i += 2
                done = True
        if not done:
            out.append((bl, "", 0.0))
            i += 1
    return out
