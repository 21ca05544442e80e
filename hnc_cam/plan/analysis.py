"""Shape analysis of a profile chain for planning: direction checks, monotony, pockets
(undercuts) and the steepest descending wall in each, normals for allowance checks.

Every function works on an **OD-normalised** chain: travelling from the right face toward
the chuck (Z decreasing), material below (smaller X). A bore chain is brought to that form by
mirroring X (:func:`mirror_x`), as the house rule "ID is OD mirrored in X" says.

Angles: the *descent* of a direction is the angle by which it dips below the -Z direction
(0 deg along -Z, 90 deg straight down toward the axis); walls with a descent > 0 are the
undercut walls a turning insert must reach with its trailing edge.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

from ..errors import PlanError
from ..geometry import Arc, Line, Point, Segment, point_at_angle
from ..geometry.intersect import horizontal_hits, vertical_hits

TOL = 1e-6
#: tangent samples per arc for angle extremes (the exact extremes at the ends and at the
#: arc's X-extreme points are added separately)
ARC_SAMPLES = 32


def mirror_x(seg: Segment) -> Segment:
    if isinstance(seg, Line):
        return Line((-seg.start[0], seg.start[1]), (-seg.end[0], seg.end[1]))
    return Arc((-seg.start[0], seg.start[1]), (-seg.end[0], seg.end[1]),
               (-seg.center[0], seg.center[1]), not seg.cw)


def mirror_chain(chain: Sequence[Segment]) -> list[Segment]:
    return [mirror_x(s) for s in chain]


def translate_chain(chain: Sequence[Segment], dz: float) -> list[Segment]:
    return [s.translated(0.0, dz) for s in chain]


def tangents(seg: Segment) -> list[Point]:
    """Unit tangents (dx, dz) along a segment: the ends, samples, and for arcs the tangents at
    its extreme points (where the extremes of the angle functions lie)."""
    if isinstance(seg, Line):
        return [seg.direction]
    out = [seg.tangent_at_start(), seg.tangent_at_end()]
    for i in range(1, ARC_SAMPLES):
        p = seg.point_at(i / ARC_SAMPLES)
        out.append(seg._tangent(p))
    for ang in (0.0, math.pi / 2, math.pi, -math.pi / 2, math.pi / 4, -math.pi / 4,
                3 * math.pi / 4, -3 * math.pi / 4):
        if seg.contains_angle(ang):
            out.append(seg._tangent(point_at_angle(seg.center, seg.radius, ang)))
    return out


def normals(seg: Segment) -> list[Point]:
    """Outward unit normals (material below) along a segment: n = (-dz, dx)."""
    return [(-t[1], t[0]) for t in tangents(seg)]


def descent_deg(d: Point) -> float:
    """Descent of a direction below -Z in degrees (negative when climbing)."""
    dx, dz = d
    return math.degrees(math.atan2(-dx, -dz)) if dz <= TOL else (180.0 if dx < 0 else -180.0)


def split_x_extremes(chain: Sequence[Segment]) -> list[Segment]:
    """Split arcs at their X-extreme points so that every piece is monotonic in X."""
    out: list[Segment] = []
    for s in chain:
        if isinstance(s, Arc):
            cuts = []
            for ang in (math.pi / 2, -math.pi / 2):  # polar angle measured from +Z toward +X
                if s.contains_angle(ang):
                    p = point_at_angle(s.center, s.radius, ang)
                    if math.dist(p, s.start) > 1e-7 and math.dist(p, s.end) > 1e-7:
                        a0, sw = s.start_angle, s.sweep
                        d = (ang - a0) % (2 * math.pi) if sw > 0 else (a0 - ang) % (2 * math.pi)
                        cuts.append((d, p))
            cuts.sort()
            cur = s.start
            for _d, p in cuts:
                out.append(Arc(cur, p, s.center, s.cw))
                cur = p
            out.append(Arc(cur, s.end, s.center, s.cw))
        else:
            out.append(s)
    return out


#: how far (mm, in Z) a chain may rise back toward the right face before it counts as a
#: back-facing undercut: the program's resolution; fitted curves carry sub-micron noise
TURN_BACK_TOL = 0.001


def check_turnable(chain: Sequence[Segment], what: str) -> None:
    """Refuse a chain that turns back toward the right face (a back-facing undercut) by more
    than :data:`TURN_BACK_TOL`: the chain is followed (arcs sampled at 0.0005 mm chord
    error, which can miss a rise by at most that much) and no point may lie more than the
    tolerance to the right of the leftmost point before it."""
    z_low = math.inf
    for s in chain:
        if s.length < 1e-9:
            continue
        pts = s.sample(0.0005)
        for p in pts:
            if p[1] > z_low + TURN_BACK_TOL:
                raise PlanError(f"{what}: the profile turns back toward the right face at "
                                f"X{2 * abs(p[0]):.3f} Z{p[1]:.3f} (a back-facing undercut that no "
                                f"tool can reach from the right; it needs a back-turning tool)")
            z_low = min(z_low, p[1])


@dataclass(frozen=True)
class FaceGroove:
    """An axial ring groove in the right face: open toward +Z between radii ``r_in`` and
    ``r_out`` (square walls along Z), its floor at ``z_floor``, its top at ``z_top``."""
    r_in: float
    r_out: float
    z_floor: float
    z_top: float

    @property
    def width(self) -> float:
        return self.r_out - self.r_in

    @property
    def depth(self) -> float:
        return self.z_top - self.z_floor


def face_grooves(chain: Sequence[Segment], z_face: float = 0.0
                 ) -> tuple[list[Segment], list[FaceGroove]]:
    """The (OD-normalised) chain with each square ring groove in the face plane ``z_face``
    bridged by a line along the face, and those grooves: a wall straight down along -Z at
    one radius, a floor along +X, a wall straight back up to the face at a larger radius."""
    segs = [s for s in chain if s.length > 1e-9]
    out: list[Segment] = []
    found: list[FaceGroove] = []

    def along_z(s: Segment) -> bool:
        return isinstance(s, Line) and abs(s.end[0] - s.start[0]) <= TOL

    i = 0
    while i < len(segs):
        s = segs[i]
        if i + 2 < len(segs) and along_z(s) and abs(s.start[1] - z_face) <= TOL \
                and s.end[1] < s.start[1] - TOL:
            fl, up = segs[i + 1], segs[i + 2]
            if isinstance(fl, Line) and abs(fl.end[1] - fl.start[1]) <= TOL \
                    and fl.end[0] > fl.start[0] + TOL and along_z(up) \
                    and abs(up.end[1] - z_face) <= TOL and up.start[1] < up.end[1] - TOL:
                found.append(FaceGroove(s.start[0], up.start[0], fl.start[1], z_face))
                bridge: Segment = Line(s.start, up.end)
                if out and isinstance(out[-1], Line) and abs(out[-1].start[1] - z_face) <= TOL \
                        and abs(out[-1].end[1] - z_face) <= TOL:
                    bridge = Line(out.pop().start, up.end)
                out.append(bridge)
                i += 3
                continue
        if out and found and isinstance(s, Line) and isinstance(out[-1], Line) \
                and abs(s.start[1] - z_face) <= TOL and abs(s.end[1] - z_face) <= TOL \
                and abs(out[-1].start[1] - z_face) <= TOL and abs(out[-1].end[1] - z_face) <= TOL \
                and s.end[0] > s.start[0]:
            out.append(Line(out.pop().start, s.end))  # the face on past a bridged groove
        else:
            out.append(s)
        i += 1
    return out, found


def is_monotonic(chain: Sequence[Segment]) -> bool:
    """X never decreases along the (OD-normalised) chain."""
    return all(t[0] >= -1e-6 for s in chain if s.length > 1e-9 for t in tangents(s))


@dataclass
class Pocket:
    """A stretch where the chain dips below the highest X reached before it (an undercut)."""
    segments: list[Segment]
    level: float  # the X the chain had reached before the pocket (radius, normalised)
    entry: Point
    exit: Point | None  # None: the chain ends inside (open toward the chuck)
    max_descent: float  # steepest descending wall, deg
    bottom: float = 0.0  # lowest X
    steep_walls: list[Segment] = field(default_factory=list)

    @property
    def z_right(self) -> float:
        return self.entry[1]

    @property
    def z_left(self) -> float:
        return self.exit[1] if self.exit is not None else min(s.bbox()[1] for s in self.segments)

    @property
    def width(self) -> float:
        return self.z_right - self.z_left

    @property
    def depth(self) -> float:
        return self.level - self.bottom


def _split_line_at_x(s: Line, x: float) -> tuple[Segment, Segment] | None:
    x0, x1 = s.start[0], s.end[0]
    if abs(x1 - x0) < 1e-12:
        return None
    t = (x - x0) / (x1 - x0)
    if t <= 1e-12 or t >= 1 - 1e-12:
        return None
    p = s.point_at(t)
    return Line(s.start, p), Line(p, s.end)


def _split_at_x(s: Segment, x: float) -> tuple[Segment, Segment] | None:
    if isinstance(s, Line):
        return _split_line_at_x(s, x)
    hits = [z for _i, z in horizontal_hits([s], x)]
    best = None
    for z in hits:
        p = (x, z)
        if math.dist(p, s.start) > 1e-9 and math.dist(p, s.end) > 1e-9:
            best = p
    if best is None:
        return None
    return Arc(s.start, best, s.center, s.cw), Arc(best, s.end, s.center, s.cw)


def radius_at(chain: Sequence[Segment], z: float, inner: bool = False) -> float | None:
    """The chain's radius at ``z``: the largest where several elements meet that Z (a face),
    the smallest with ``inner``; None where the chain does not reach ``z``."""
    hits = [x for _i, x in vertical_hits(chain, z)]
    if not hits:
        return None
    return min(hits) if inner else max(hits)


def pockets(chain: Sequence[Segment]) -> tuple[list[Segment], list[Pocket]]:
    """Find the undercut pockets of an OD-normalised chain.

    Returns the *hull chain* (the chain with each closed pocket bridged by a straight line at
    its level, open pockets kept) and the pockets in order from the right face.
    """
    items = pocket_items(chain)
    return assemble(items, bridge=lambda p: p.exit is not None), [
        it for it in items if isinstance(it, Pocket)]


def assemble(items: Sequence["Segment | Pocket"], bridge) -> list[Segment]:
    """The chain from :func:`pocket_items`, each pocket for which ``bridge(pocket)`` is true
    replaced by the straight line across its top."""
    out: list[Segment] = []
    for it in items:
        if isinstance(it, Pocket):
            if bridge(it):
                end = it.exit if it.exit is not None else (it.level, it.segments[-1].end[1])
                out.append(Line(it.entry, end))
            else:
                out.extend(it.segments)
        else:
            out.append(it)
    return out


def pocket_items(chain: Sequence[Segment]) -> list["Segment | Pocket"]:
    """The chain as a sequence of plain segments and :class:`Pocket` s."""
    segs = split_x_extremes(chain)
    hull: list = []
    m = -math.inf
    cur: list[Segment] | None = None
    level = 0.0
    entry: Point = (0.0, 0.0)
    i = 0
    work = list(segs)
    while i < len(work):
        s = work[i]
        i += 1
        if cur is None:
            if s.end[0] < s.start[0] - TOL and s.start[0] >= m - TOL:
                cur, level, entry = [s], max(m, s.start[0]), s.start
            else:
                hull.append(s)
                m = max(m, s.start[0], s.end[0])
            continue
        # inside a pocket: does this segment climb back to the level?
        if s.end[0] >= level - TOL and s.end[0] > s.start[0]:
            if s.end[0] > level + TOL:
                parts = _split_at_x(s, level)
                if parts is not None:
                    cur.append(parts[0])
                    work.insert(i, parts[1])
                    exit_ = parts[0].end
                else:
                    cur.append(s)
                    exit_ = s.end
            else:
                cur.append(s)
                exit_ = s.end
            hull.append(_pocket(cur, level, entry, exit_))
            cur = None
            m = level
            continue
        cur.append(s)
    if cur is not None:
        hull.append(_pocket(cur, level, entry, None))
    return hull


def _pocket(segs: list[Segment], level: float, entry: Point, exit_: Point | None) -> Pocket:
    md = 0.0
    steep: list[Segment] = []
    for s in segs:
        d = max((descent_deg(t) for t in tangents(s)), default=0.0)
        if d > md:
            md = d
        if d > 0:
            steep.append(s)
    bottom = min(s.bbox()[0] for s in segs)
    return Pocket(segments=list(segs), level=level, entry=entry, exit=exit_, max_descent=md,
                  bottom=bottom, steep_walls=steep)


def max_descent(chain: Sequence[Segment]) -> float:
    return max((descent_deg(t) for s in chain if s.length > 1e-9 for t in tangents(s)),
               default=0.0)


def square_groove(p: Pocket) -> tuple[float, float, float] | None:
    """(z_left, z_right, x_bottom) when the pocket is a square groove: vertical walls (within
    2 deg) and a flat bottom; None otherwise."""
    if p.exit is None:
        return None
    bottom_x = p.bottom
    for s in p.segments:
        if isinstance(s, Arc):
            return None
        dx = s.end[0] - s.start[0]
        dz = s.end[1] - s.start[1]
        if abs(dz) < 1e-6:
            continue  # a wall
        if abs(dx) > 1e-6:
            if abs(math.degrees(math.atan2(abs(dx), abs(dz)))) < 88.0:
                return None
            continue
        if abs(s.start[0] - bottom_x) > 1e-6:
            return None  # a flat at another level: a stepped groove
    return (p.exit[1], p.entry[1], bottom_x)
