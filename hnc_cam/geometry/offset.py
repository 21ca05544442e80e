"""Exact offset of an open chain of lines and arcs: the path of a round nose of radius ``r``
that rolls along one side of a contour. The one offset routine of the package: the CAM side
(:func:`hnc_cam.compensate.compensate`) and the interpreter's G41/G42
(:func:`hnc_cam.nc.compensation.compensate_moves`) both call :func:`offset_chain`.

Method (exact, no sampling of the path):

0. *Regularise.* An arc whose end misses the circle through its start (an I/K arc; the
   manual allows 0.01 mm) gets the centre on the chord's bisector nearest to the given one
   (:func:`regularise_arc`), so that each arc's offset ends exactly ``r`` from the joint.
1. *Raw offset.* Every segment is offset to the tool side at distance ``r``: a line is
   translated along its normal, an arc keeps its centre and gets radius ``R + r`` (tool on its
   convex side) or ``R - r`` (concave side; when ``R - r <= 0`` the arc **vanishes**: the nose
   cannot follow it). At each joint the turn of the contour decides: a **convex** corner
   (the contour turns away from the tool, or reverses) gets an arc of radius ``r`` centred on
   the corner, from the offset end of one segment to the offset start of the next; a
   **concave** corner gets nothing, its two offsets cross and are trimmed below; a tangent
   joint needs nothing.
2. *Split.* Every raw element is cut where it crosses the boundary of the ``r``-neighbourhood
   of any contour segment within the lookahead window (the carriers of both offset lines or
   circles ``R + r`` and ``|R - r|``, and the circles of radius ``r`` about its end points).
   Between two cuts a piece is either wholly at distance ``>= r`` from the contour or wholly
   closer.
3. *Validate.* A piece is kept when its midpoint is at least ``r`` from every segment of the
   window (exact ``distance_to``). Concave corners are thereby trimmed exactly at the
   intersection of the two offsets; short segments between corners, arcs that vanish and
   grooves narrower than ``2r`` lose all pieces that would gouge.
4. *Walk.* From each valid piece the path continues with the valid piece starting at its
   end that lies furthest along the raw offset (this skips any loop). Where the valid pieces
   fall apart into several runs (a stub at an open end that a later move cuts off, an island
   the nose cannot reach from outside), the longest run is the path. Contiguous pieces of
   one element are merged back into one line or arc.
5. *Report.* Each output segment carries its :class:`Origin` (offset of input segment ``i``
   or corner arc at the joint ``i``/``k``). From these, the stretches of the contour the nose
   never touches are collected into :class:`Departure` records: kind ``corner`` (the nose
   radius left in a sharp concave corner, inherent to a round nose), ``radius`` (an inside
   arc smaller than ``r``), ``groove`` (a concave step or groove the nose cannot enter: a
   whole segment or several concave corners not touched), ``end`` (a stretch at an open end
   of the chain the nose cannot touch, e.g. a final face shorter than ``r`` after a concave
   corner). ``departure`` is the largest distance from that stretch of the part to the
   reachable contour (the envelope of the nose along the path): the exact distance to the
   path is maximised over the stretch by branch-and-bound on its Lipschitz bound (to
   ``MEASURE_TOL`` = 1e-5 mm, at most ``MEASURE_MAX_EVALS`` evaluations, fewer past ten
   departures in one chain: ``MEASURE_TOTAL_EVALS`` shared, never below
   ``MEASURE_MIN_EVALS``; stopped early, the figure is still within 0.05 mm below the true
   maximum, the start grid being 0.1 mm) and polished by golden-section search to 1e-7 mm.
   The distances come from a uniform grid over the path's segments (exact minimum; a path
   that runs over itself is searched near the point only, its repeated segments once).

``lookahead`` limits steps 2-4 to segments at most that many positions away in the chain
(``None``: the whole chain), widened by ``lookahead_length`` to every segment within that
length along the chain. The CAM side offsets whole part contours and uses ``None``; the
interpreter uses a small window like a controller's block buffer (3 moves, and 4 r of
contour length), so that a program that comes back with compensation active over regions
cut earlier is not trimmed against them.

Cost: O(n^2) carrier cuts for the whole-chain check (bounding boxes prune most; about 50 ms
for 50 segments, 0.3 s for 200), O(n) with a window (about 0.1 ms per move).

Conventions: points are ``(x radius, z)``; sides are judged looking along the motion in the
view Z right / X up (``side=+1`` left = G41, ``-1`` right = G42).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterable, Sequence

from .intersect import circle_circle_carriers, line_circle_carriers, line_line_carriers
from .primitives import EPS, TOL, Arc, Line, Point, Segment, cross, dist, left_normal, polar_angle

LEFT = 1
RIGHT = -1

#: a piece is valid when its distance to the contour is at least r - VALID_TOL
VALID_TOL = 1e-7
#: end points closer than this are joined when walking the pieces
MATCH_TOL = 1e-6
#: a gap up to this (numerical trouble at near-tangent cuts) is bridged by a straight link
LINK_TOL = 1e-4
#: untouched stretches shorter than this (mm) are ignored
GAP_TOL = 1e-6
#: departures below this (mm) are not reported
DEPARTURE_TOL = 1e-6
#: the departure's maximum is found to this tolerance (mm) before polishing
MEASURE_TOL = 1e-5
#: distance evaluations per departure, at most
MEASURE_MAX_EVALS = 5000
#: distance evaluations over all the departures of one chain: past ten departures each gets
#: an equal share of what is left, but never fewer than ``MEASURE_MIN_EVALS`` (so the work
#: grows linearly with the number of departures; the start grid is always evaluated)
MEASURE_TOTAL_EVALS = 50000
MEASURE_MIN_EVALS = 500


def side_sign(side) -> int:
    """+1 for the left side (``"left"``, ``41``, ``+1``), -1 for the right (``"right"``, 42, -1)."""
    if isinstance(side, str):
        s = side.strip().lower()
        if s in ("left", "l", "g41", "41"):
            return LEFT
        if s in ("right", "r", "g42", "42"):
            return RIGHT
    elif side in (41, 1):
        return LEFT
    elif side in (42, -1):
        return RIGHT
    raise ValueError(f"side must be 'left'/'right' or 41/42, got {side!r}")


@dataclass(frozen=True, slots=True)
class Origin:
    """Where an output segment comes from: ``kind == "seg"``: the offset of input segment
    ``before`` (== ``after``); ``kind == "corner"``: the arc about the corner between input
    segments ``before`` and ``after`` (indices into the chain given to :func:`offset_chain`);
    ``kind == "link"``: a straight bridge (shorter than ``LINK_TOL``) into the offset of
    ``before``/``after`` where near-tangent cuts left a numerical gap."""
    kind: str
    before: int
    after: int


@dataclass(frozen=True)
class Departure:
    """A stretch of the contour the nose does not touch.

    ``kind``: ``corner`` | ``radius`` | ``groove`` | ``end`` (see the module doc);
    ``segments``: input indices of the segments the stretch covers (in order);
    ``start``/``end``: its end points on the contour; ``departure``: largest distance (mm,
    normal to the part) from the stretch to the reachable contour, at the contour point
    ``at``; ``message``: one line for a human (X as diameter there).
    """
    kind: str
    segments: tuple[int, ...]
    start: Point
    end: Point
    departure: float
    at: Point
    message: str

    @property
    def unreachable(self) -> bool:
        """True for a feature the nose cannot make (everything but the inherent corner fillet)."""
        return self.kind != "corner"


@dataclass
class OffsetResult:
    """The nose-centre path of :func:`offset_chain` with its provenance and the departures."""
    segments: list[Segment]
    origins: list[Origin]
    departures: list[Departure]
    radius: float
    side: int
    source: list[Segment] = field(default_factory=list)

    @property
    def unreachable(self) -> list[Departure]:
        return [d for d in self.departures if d.unreachable]

    def distance_to(self, p: Point) -> float:
        """Exact distance from ``p`` to the offset path."""
        return min((s.distance_to(p) for s in self.segments), default=math.inf)


# ---------------------------------------------------------------------------------------------
# small exact helpers

def _normal(seg: Segment, at_end: bool, s: int) -> Point:
    t = seg.tangent_at_end() if at_end else seg.tangent_at_start()
    n = left_normal(t)
    return (s * n[0], s * n[1])


def _offset_radius(arc: Arc, r: float, s: int) -> float:
    # the left normal of a ccw arc points to its centre
    k = -1.0 if arc.cw else 1.0
    return arc.radius - s * k * r


def offset_segment(seg: Segment, r: float, side) -> Segment | None:
    """The exact offset of one segment to ``side`` at distance ``r``; ``None`` when an arc
    vanishes (radius ``<= r`` on its concave side)."""
    s = side_sign(side)
    if isinstance(seg, Line):
        n = _normal(seg, False, s)
        return seg.translated(r * n[0], r * n[1])
    R = seg.radius
    R2 = _offset_radius(seg, r, s)
    if R2 <= TOL:
        return None
    c = seg.center
    k = R2 / R
    a = (c[0] + (seg.start[0] - c[0]) * k, c[1] + (seg.start[1] - c[1]) * k)
    b = (c[0] + (seg.end[0] - c[0]) * k, c[1] + (seg.end[1] - c[1]) * k)
    return Arc(a, b, c, seg.cw)


def regularise_arc(seg: Segment) -> Segment:
    """``seg`` with its end points exactly on one circle: an :class:`Arc` whose end lies off the
    circle through its start (an I/K arc: the manual lets the end miss the circle by up to
    0.01 mm) gets the centre on the chord's perpendicular bisector nearest to the given centre,
    as an R arc would have; lines and consistent arcs are returned unchanged.

    Without this, the offset of such an arc ends ``|R_end - R_start|`` closer to the next
    segment's start than ``r``: its last piece fails the validation, the valid pieces fall apart
    at the joint, and a whole stretch of the contour is reported unreachable.
    """
    if not isinstance(seg, Arc):
        return seg
    c, a, b = seg.center, seg.start, seg.end
    da, db = dist(c, a), dist(c, b)
    if abs(da - db) <= 1e-12 * max(1.0, da):
        return seg
    mx, mz = (a[0] + b[0]) / 2, (a[1] + b[1]) / 2
    ux, uz = b[0] - a[0], b[1] - a[1]
    L2 = ux * ux + uz * uz
    if L2 <= EPS * EPS:
        return seg
    # remove from c - m its component along the chord
    k = ((c[0] - mx) * ux + (c[1] - mz) * uz) / L2
    c2 = (c[0] - k * ux, c[1] - k * uz)
    return Arc(a, b, c2, seg.cw)


def _param(e: Segment, p: Point) -> float:
    """Parameter of a point (on the carrier of ``e``) along ``e``: 0 at start, 1 at end."""
    if isinstance(e, Line):
        dx, dz = e.end[0] - e.start[0], e.end[1] - e.start[1]
        L2 = dx * dx + dz * dz
        return ((p[0] - e.start[0]) * dx + (p[1] - e.start[1]) * dz) / L2
    sw = e.sweep
    d = polar_angle(e.center, p) - e.start_angle
    if sw > 0:
        return (d % (2 * math.pi)) / sw
    return ((-d) % (2 * math.pi)) / (-sw)


def _point(e: Segment, t: float) -> Point:
    if t <= 0.0:
        return e.start
    if t >= 1.0:
        return e.end
    return e.point_at(t)


def _sub(e: Segment, a: Point, b: Point) -> Segment:
    if isinstance(e, Line):
        return Line(a, b)
    return Arc(a, b, e.center, e.cw)


def _bbox_gap(b1, b2) -> float:
    """Lower bound of the distance between two boxes (xmin, zmin, xmax, zmax)."""
    dx = max(0.0, b1[0] - b2[2], b2[0] - b1[2])
    dz = max(0.0, b1[1] - b2[3], b2[1] - b1[3])
    return math.hypot(dx, dz)


def _point_box_gap(p: Point, b) -> float:
    dx = max(0.0, b[0] - p[0], p[0] - b[2])
    dz = max(0.0, b[1] - p[1], p[1] - b[3])
    return math.hypot(dx, dz)


def _carriers(seg: Segment, r: float) -> list[tuple]:
    """Carriers of the boundary of the r-neighbourhood of ``seg``: ('l', p0, p1) lines and
    ('c', centre, radius) circles."""
    out: list[tuple] = [("c", seg.start, r), ("c", seg.end, r)]
    if isinstance(seg, Line):
        n = left_normal(seg.direction)
        for k in (r, -r):
            out.append(("l", (seg.start[0] + k * n[0], seg.start[1] + k * n[1]),
                        (seg.end[0] + k * n[0], seg.end[1] + k * n[1])))
    else:
        out.append(("c", seg.center, seg.radius + r))
        if abs(seg.radius - r) > TOL:
            out.append(("c", seg.center, abs(seg.radius - r)))
    return out


def _cuts(e: Segment, carrier: tuple) -> list[Point]:
    if isinstance(e, Line):
        if carrier[0] == "l":
            p = line_line_carriers(e.start, e.end, carrier[1], carrier[2])
            return [] if p is None else [p]
        return line_circle_carriers(e.start, e.end, carrier[1], carrier[2])
    if carrier[0] == "l":
        return line_circle_carriers(carrier[1], carrier[2], e.center, e.radius)
    return circle_circle_carriers(e.center, e.radius, carrier[1], carrier[2])


# ---------------------------------------------------------------------------------------------
# the offset

@dataclass
class _Elem:
    seg: Segment
    origin: Origin          # in input indices
    owners: tuple[int, int]  # kept indices (lo, hi)


@dataclass
class _Piece:
    elem: int
    t0: float
    t1: float
    seg: Segment
    valid: bool = False


ALL_KINDS = ("corner", "radius", "groove", "end")


def offset_chain(chain: Sequence[Segment], r: float, side, lookahead: int | None = None,
                 measure: Sequence[str] = ALL_KINDS, lookahead_length: float = 0.0
                 ) -> OffsetResult:
    """Exact offset (nose-centre path) of the open, connected chain ``chain`` at distance
    ``r`` on ``side`` ('left'/'right', 41/42, +1/-1). See the module docstring for the method,
    the departures and ``lookahead``; ``lookahead_length`` (mm) widens the window to every
    segment within that length along the chain (so that many short moves, e.g. an arc written
    as chords, are checked over a stretch comparable to the nose). Departures of kinds not in ``measure`` are listed with
    ``departure = nan`` and ``at`` = their start (saves time where only some kinds matter).

    Zero-length segments are skipped (their index never appears in the result). Raises
    ``ValueError`` for a negative radius or a chain that is not connected.
    """
    s = side_sign(side)
    if r < 0:
        raise ValueError(f"nose radius must not be negative, got {r:g}")
    chain = list(chain)
    for i in range(len(chain) - 1):
        if dist(chain[i].end, chain[i + 1].start) > 1e-5:
            raise ValueError(f"chain is not connected between segment {i} and {i + 1}: "
                             f"{chain[i].end} -> {chain[i + 1].start}")
    kept = [i for i, g in enumerate(chain) if g.length > TOL]
    part = [regularise_arc(chain[i]) for i in kept]
    if not part:
        return OffsetResult([], [], [], r, s, chain)
    if r <= TOL:
        return OffsetResult(list(part), [Origin("seg", i, i) for i in kept], [], r, s, chain)
    K = len(part) if lookahead is None else max(1, int(lookahead))
    nseg = len(part)
    if lookahead is None:
        def window(a: int, b: int) -> tuple[int, int]:
            return 0, nseg - 1
    else:
        import bisect
        cum = [0.0]
        for g in part:
            cum.append(cum[-1] + g.length)
        Lw = max(0.0, lookahead_length)

        def window(a: int, b: int) -> tuple[int, int]:
            lo, hi = a - K, b + K
            if Lw > 0:
                # segments j whose span [cum[j], cum[j+1]] comes within Lw of [cum[a], cum[b+1]]
                lo = min(lo, bisect.bisect_left(cum, cum[a] - Lw) - 1)
                hi = max(hi, bisect.bisect_right(cum, cum[b + 1] + Lw) - 1)
            return max(0, lo), min(nseg - 1, hi)

    # 1. raw offset ------------------------------------------------------------------------
    offs = [offset_segment(g, r, s) for g in part]
    elems: list[_Elem] = []
    for q, g in enumerate(part):
        if q > 0:
            a = part[q - 1]
            v = g.start
            t0, t1 = a.tangent_at_end(), g.tangent_at_start()
            n0, n1 = _normal(a, True, s), _normal(g, False, s)
            p0 = (v[0] + r * n0[0], v[1] + r * n0[1])
            p1 = (v[0] + r * n1[0], v[1] + r * n1[1])
            turn = cross(t0, t1)
            dot = t0[0] * t1[0] + t0[1] * t1[1]
            reverse = abs(turn) < 1e-12 and dot < 0
            if dist(p0, p1) > TOL and (s * turn < 0 or reverse):
                elems.append(_Elem(Arc(p0, p1, v, s > 0), Origin("corner", kept[q - 1], kept[q]),
                                   (q - 1, q)))
        if offs[q] is not None and offs[q].length > EPS:
            elems.append(_Elem(offs[q], Origin("seg", kept[q], kept[q]), (q, q)))

    # 2. split --------------------------------------------------------------------------------
    pboxes = [g.bbox() for g in part]
    carriers = [None] * len(part)
    pieces: list[_Piece] = []
    for ei, el in enumerate(elems):
        e = el.seg
        eb = e.bbox()
        lo, hi = window(*el.owners)
        ts: list[float] = []
        L = e.length
        for j in range(lo, hi + 1):
            if _bbox_gap(eb, pboxes[j]) > r + TOL:
                continue
            if carriers[j] is None:
                carriers[j] = _carriers(part[j], r)
            for c in carriers[j]:
                for p in _cuts(e, c):
                    # cuts at the element's own ends are ill-conditioned at tangent
                    # joints and never needed: drop those within TOL of an end
                    if dist(p, e.start) <= TOL or dist(p, e.end) <= TOL:
                        continue
                    t = _param(e, p)
                    if 0.0 < t < 1.0:
                        ts.append(t)
        ts.sort()
        cuts = [0.0]
        for t in ts:
            if (t - cuts[-1]) * L > 1e-9:
                cuts.append(t)
        if (1.0 - cuts[-1]) * L <= 1e-9:
            cuts.pop()
        cuts.append(1.0)
        pts = [_point(e, t) for t in cuts]
        for k in range(len(cuts) - 1):
            pieces.append(_Piece(ei, cuts[k], cuts[k + 1], _sub(e, pts[k], pts[k + 1])))

    # 3. validate -----------------------------------------------------------------------------
    lim = r - VALID_TOL
    for pc in pieces:
        el = elems[pc.elem]
        m = pc.seg.point_at(0.5)
        lo, hi = window(*el.owners)
        ok = True
        for j in range(lo, hi + 1):
            if _point_box_gap(m, pboxes[j]) >= lim:
                continue
            if part[j].distance_to(m) < lim:
                ok = False
                break
        pc.valid = ok

    # 4. walk ---------------------------------------------------------------------------------
    grid: dict[tuple[int, int], list[int]] = {}
    cell = 1e-4

    def key(p: Point) -> tuple[int, int]:
        return (int(math.floor(p[0] / cell)), int(math.floor(p[1] / cell)))

    for pi, pc in enumerate(pieces):
        if pc.valid:
            grid.setdefault(key(pc.seg.start), []).append(pi)

    def near(p: Point, after: int, owner_hi: int, tol: float) -> int | None:
        reach = window(owner_hi, owner_hi)[1]
        kx, kz = key(p)
        best = None
        span = 1 if tol <= cell else int(math.ceil(tol / cell))
        for dx in range(-span, span + 1):
            for dz in range(-span, span + 1):
                for qi in grid.get((kx + dx, kz + dz), ()):
                    if qi <= after or (best is not None and qi <= best):
                        continue
                    if elems[pieces[qi].elem].owners[0] > reach:
                        continue
                    if dist(pieces[qi].seg.start, p) <= tol:
                        best = qi
        return best

    # successor of every valid piece: the valid piece starting at its end that lies furthest
    # along the raw offset (this cuts loops); a gap up to LINK_TOL (numerical) is bridged
    nxt: dict[int, int | None] = {}
    linked: set[int] = set()
    for pi, pc in enumerate(pieces):
        if not pc.valid:
            continue
        q = near(pc.seg.end, pi, elems[pc.elem].owners[1], MATCH_TOL)
        if q is None:
            q = near(pc.seg.end, pi, elems[pc.elem].owners[1], LINK_TOL)
            if q is not None:
                linked.add(q)
        nxt[pi] = q
    # the valid set can fall apart (a stub at an open end cut off by a later move, an
    # unreachable island): keep the longest connected run
    total: dict[int, float] = {}
    for pi in sorted(nxt, reverse=True):
        q = nxt[pi]
        total[pi] = pieces[pi].seg.length + (total[q] if q is not None else 0.0)
    route: list[int] = []
    cur = max(total, key=lambda k: (total[k], -k)) if total else None
    while cur is not None:
        route.append(cur)
        cur = nxt[cur]

    # merge contiguous pieces of one element; snap ends together
    out_segs: list[Segment] = []
    out_orig: list[Origin] = []
    spans: list[tuple[int, float, float]] = []  # elem, t0, t1 of each output segment
    for pi in route:
        pc = pieces[pi]
        if pi in linked and out_segs and dist(out_segs[-1].end, pc.seg.start) > MATCH_TOL:
            o = elems[pc.elem].origin
            out_segs.append(Line(out_segs[-1].end, pc.seg.start))
            out_orig.append(Origin("link", o.before, o.after))
            spans.append((-1, 0.0, 0.0))
            out_segs.append(pc.seg)
            out_orig.append(o)
            spans.append((pc.elem, pc.t0, pc.t1))
            continue
        if spans and spans[-1][0] == pc.elem and abs(spans[-1][2] - pc.t0) < 1e-12:
            e0, t0, _ = spans[-1]
            spans[-1] = (e0, t0, pc.t1)
            prev = out_segs[-1]
            out_segs[-1] = _sub(elems[pc.elem].seg, prev.start, pc.seg.end)
            continue
        seg = pc.seg
        if seg.length < 2 * MATCH_TOL:
            # a sliver between two cuts: keep the path on the neighbours (snapping its start
            # could flip a tiny arc into a near-full circle)
            if out_segs:
                continue
        elif out_segs:
            seg = _sub(seg, out_segs[-1].end, seg.end)
        out_segs.append(seg)
        out_orig.append(elems[pc.elem].origin)
        spans.append((pc.elem, pc.t0, pc.t1))

    res = OffsetResult(out_segs, out_orig, [], r, s, chain)
    res.departures = _departures(res, part, kept, offs, elems, spans, s, K, tuple(measure))
    return res


# ---------------------------------------------------------------------------------------------
# departures

def _touched(part, elems, spans) -> tuple[list[list[tuple[float, float]]], set[int]]:
    """Touched parameter intervals per kept segment and the kept joints q (between q-1 and q)
    a corner arc touches."""
    touched: list[list[tuple[float, float]]] = [[] for _ in part]
    corners: set[int] = set()
    for ei, t0, t1 in spans:
        if ei < 0:
            continue
        el = elems[ei]
        if el.origin.kind == "seg":
            touched[el.owners[0]].append((t0, t1))
        else:
            corners.add(el.owners[1])
    return touched, corners


def _untouched(iv: list[tuple[float, float]], L: float) -> list[tuple[float, float]]:
    gap = GAP_TOL / L if L > 0 else 0.0
    out = []
    t = 0.0
    for a, b in sorted(iv):
        if a - t > gap:
            out.append((t, a))
        t = max(t, b)
    if 1.0 - t > gap:
        out.append((t, 1.0))
    return out


def _fmt(p: Point) -> str:
    return f"X{2 * p[0]:.3f} Z{p[1]:.3f}"


def _departures(res: OffsetResult, part, kept, offs, elems, spans, s: int, K: int,
                measure: tuple[str, ...]) -> list[Departure]:
    touched, corners = _touched(part, elems, spans)
    n = len(part)
    # regions: lists of (q, a, b)
    regions: list[list[tuple[int, float, float]]] = []
    for q in range(n):
        L = part[q].length
        for a, b in _untouched(touched[q], L):
            joins = (a * L <= GAP_TOL and regions and regions[-1][-1][0] == q - 1
                     and (1.0 - regions[-1][-1][2]) * part[q - 1].length <= GAP_TOL
                     and q not in corners)
            if joins:
                regions[-1].append((q, a, b))
            else:
                regions.append([(q, a, b)])
    out: list[Departure] = []
    r = res.radius
    index: list[_SegmentGrid] = []  # built on the first measured region, shared by all
    granted = 0
    for ri, reg in enumerate(regions):
        qs = [q for q, _, _ in reg]
        vanished = [q for q in qs if offs[q] is None]
        whole = [q for q, a, b in reg if a * part[q].length <= GAP_TOL
                 and (1 - b) * part[q].length <= GAP_TOL]
        inner_vertices = len(reg) - 1
        at_start = reg[0][0] == 0 and reg[0][1] * part[0].length <= GAP_TOL
        at_end = reg[-1][0] == n - 1 and (1 - reg[-1][2]) * part[-1].length <= GAP_TOL
        if vanished:
            kind = "radius"
        elif at_start or at_end:
            kind = "end"
        elif whole or inner_vertices >= 2:
            kind = "groove"
        else:
            kind = "corner"
        p0 = _point(part[reg[0][0]], reg[0][1])
        p1 = _point(part[reg[-1][0]], reg[-1][2])
        if kind in measure:
            if not index and res.segments:
                index.append(_SegmentGrid(res.segments))
            budget = max(MEASURE_MIN_EVALS,
                         min(MEASURE_MAX_EVALS,
                             (MEASURE_TOTAL_EVALS - granted) // (len(regions) - ri)))
            granted += budget
            dep, at = _measure(res, part, reg, index[0] if index else None, budget)
            if dep <= DEPARTURE_TOL:
                continue
        else:
            if dist(p0, p1) <= GAP_TOL and kind != "radius":
                continue
            dep, at = math.nan, p0
        segs = tuple(kept[q] for q in qs)
        if math.isfinite(dep):
            how = f": left up to {dep:.3f} mm oversize (at {_fmt(at)})"
        else:
            how = ": no position of the nose reaches it" if dep > 0 else ""
        if kind == "radius":
            R = min(part[q].radius for q in vanished)
            msg = (f"inside arc R{R:g} is smaller than the nose radius {r:g}: the contour from "
                   f"{_fmt(p0)} to {_fmt(p1)} cannot be cut{how}")
        elif kind == "groove":
            msg = (f"concave step/groove from {_fmt(p0)} to {_fmt(p1)} is too narrow for the "
                   f"nose radius {r:g} (needs width >= {2 * r:g}){how}")
        elif kind == "end":
            msg = (f"the nose cannot reach the contour from {_fmt(p0)} to {_fmt(p1)} at the "
                   f"end of the chain{how}")
        else:
            msg = (f"concave corner from {_fmt(p0)} to {_fmt(p1)} keeps the nose radius {r:g}"
                   f"{how}")
        out.append(Departure(kind, segs, p0, p1, dep, at, msg))
    return out


class _SegmentGrid:
    """Uniform grid over the path segments' boxes for exact nearest-distance queries.

    A query visits the cells in square rings about the point's cell and stops once the
    nearest distance found is no larger than the distance to the outside of the rings
    visited: the result is the exact minimum over all segments (the same value a scan of
    every segment gives), at a cost that depends on how many segments lie near the point,
    not on the length of the path.
    """

    def __init__(self, segs: Sequence[Segment]):
        # a path that runs over itself repeats segments exactly: one copy gives the same
        # minimum
        uniq: dict[tuple, Segment] = {}
        for g in segs:
            if isinstance(g, Line):
                k = ("L", g.start, g.end)
            else:
                k = ("A", g.start, g.end, g.center, g.cw)
            uniq.setdefault(k, g)
        self.segs = list(uniq.values())
        self.boxes = [g.bbox() for g in self.segs]
        self.dist = [_distance_fn(g) for g in self.segs]
        n = len(self.segs)
        x0 = min(b[0] for b in self.boxes)
        z0 = min(b[1] for b in self.boxes)
        x1 = max(b[2] for b in self.boxes)
        z1 = max(b[3] for b in self.boxes)
        w, hgt = x1 - x0, z1 - z0
        # about one cell per segment over the path's box, no finer than 1e-3 mm
        h = max(math.sqrt(max(w * hgt, 1e-12) / max(n, 1)), (w + hgt) / (4.0 * n + 4.0), 1e-3)
        # coarser while long segments would fill too many cells (memory stays O(n))
        while sum((int((b[2] - b[0]) / h) + 2) * (int((b[3] - b[1]) / h) + 2)
                  for b in self.boxes) > 32 * n + 1024:
            h *= 2.0
        self.h = h
        self.x0, self.z0 = x0, z0
        self.nx = int(w / h) + 1
        self.nz = int(hgt / h) + 1
        cells: dict[tuple[int, int], list[int]] = {}
        for i, b in enumerate(self.boxes):
            for ix in range(self._ix(b[0]), self._ix(b[2]) + 1):
                for iz in range(self._iz(b[1]), self._iz(b[3]) + 1):
                    cells.setdefault((ix, iz), []).append(i)
        self.cells = cells
        self.stamp = [0] * n
        self.tick = 0

    def _ix(self, x: float) -> int:
        return min(self.nx - 1, max(0, int((x - self.x0) / self.h)))

    def _iz(self, z: float) -> int:
        return min(self.nz - 1, max(0, int((z - self.z0) / self.h)))

    def distance(self, p: Point) -> float:
        """Exact distance from ``p`` to the nearest segment."""
        h, x0, z0, nx, nz = self.h, self.x0, self.z0, self.nx, self.nz
        fns, boxes, cells, stamp = self.dist, self.boxes, self.cells, self.stamp
        hypot = math.hypot
        px, pz = p
        self.tick += 1
        tick = self.tick
        cx, cz = self._ix(p[0]), self._iz(p[1])
        best = math.inf
        k = 0
        while True:
            lo_x, hi_x, lo_z, hi_z = cx - k, cx + k, cz - k, cz + k
            for ix in range(max(0, lo_x), min(nx - 1, hi_x) + 1):
                edge_x = ix == lo_x or ix == hi_x
                for iz in (range(max(0, lo_z), min(nz - 1, hi_z) + 1) if edge_x
                           else [z for z in (lo_z, hi_z) if 0 <= z < nz]):
                    for i in cells.get((ix, iz), ()):
                        if stamp[i] == tick:
                            continue
                        stamp[i] = tick
                        b = boxes[i]  # _point_box_gap, inline
                        if hypot(max(0.0, b[0] - px, px - b[2]),
                                 max(0.0, b[1] - pz, pz - b[3])) >= best:
                            continue
                        d = fns[i](p)
                        if d < best:
                            best = d
            if lo_x <= 0 and lo_z <= 0 and hi_x >= nx - 1 and hi_z >= nz - 1:
                return best  # every cell visited
            # any segment not yet seen lies wholly outside the visited block of cells
            margin = min(p[0] - (x0 + lo_x * h) if lo_x > 0 else math.inf,
                         (x0 + (hi_x + 1) * h) - p[0] if hi_x < nx - 1 else math.inf,
                         p[1] - (z0 + lo_z * h) if lo_z > 0 else math.inf,
                         (z0 + (hi_z + 1) * h) - p[1] if hi_z < nz - 1 else math.inf)
            if best <= margin:
                return best
            k += 1


def _distance_fn(g: Segment):
    """``g.distance_to`` as a function of the point with the segment's own quantities (an
    arc's radius, start angle and sweep; a line's direction) worked out once: the same
    arithmetic in the same order, so the same value bit for bit."""
    hypot, atan2, sin, cos = math.hypot, math.atan2, math.sin, math.cos
    if type(g) is Line:
        s0, s1 = g.start
        dx, dz = g.end[0] - s0, g.end[1] - s1
        L2 = dx * dx + dz * dz
        if L2 < EPS * EPS:
            return lambda p: hypot(p[0] - s0, p[1] - s1)

        def line(p: Point) -> float:
            t = ((p[0] - s0) * dx + (p[1] - s1) * dz) / L2
            t = min(1.0, max(0.0, t))
            return hypot(p[0] - (s0 + t * dx), p[1] - (s1 + t * dz))
        return line
    if type(g) is Arc:
        c0, c1 = g.center
        r, a0, sw = g.radius, g.start_angle, g.sweep
        st, en = g.start, g.end
        two_pi = 2 * math.pi

        def arc(p: Point) -> float:
            ang = atan2(p[0] - c0, p[1] - c1)
            if hypot(p[0] - c0, p[1] - c1) > EPS:
                d = ang - a0
                if sw > 0:
                    on = d % two_pi <= sw + 1e-12
                else:
                    on = (-d) % two_pi <= -sw + 1e-12
                if on:
                    q = (c0 + r * sin(ang), c1 + r * cos(ang))
                    return hypot(p[0] - q[0], p[1] - q[1])
            q = st if hypot(p[0] - st[0], p[1] - st[1]) <= hypot(p[0] - en[0], p[1] - en[1]) else en
            return hypot(p[0] - q[0], p[1] - q[1])
        return arc
    return g.distance_to


def _point_fn(e: Segment):
    """:func:`_point` of ``e`` as a function of t, an arc's radius, start angle and sweep
    worked out once (the same arithmetic, the same points bit for bit)."""
    s, n = e.start, e.end
    if type(e) is Arc:
        c0, c1 = e.center
        r, a0, sw = e.radius, e.start_angle, e.sweep
        sin, cos = math.sin, math.cos

        def arc(t: float) -> Point:
            if t <= 0.0:
                return s
            if t >= 1.0:
                return n
            ang = a0 + sw * t
            return (c0 + r * sin(ang), c1 + r * cos(ang))
        return arc
    if type(e) is Line:
        dx, dz = n[0] - s[0], n[1] - s[1]

        def line(t: float) -> Point:
            if t <= 0.0:
                return s
            if t >= 1.0:
                return n
            return (s[0] + dx * t, s[1] + dz * t)
        return line
    return lambda t: _point(e, t)


def _measure(res: OffsetResult, part, reg, index: _SegmentGrid | None = None,
             max_evals: int = MEASURE_MAX_EVALS) -> tuple[float, Point]:
    """Largest (distance to the path - r) over the stretch, with the contour point.

    The distance to the path is 1-Lipschitz along the contour, so a branch-and-bound over
    the stretch (start grid 0.1 mm, intervals kept while their bound ``(f(a) + f(b)) / 2 +
    length / 2`` exceeds the best value by more than ``MEASURE_TOL``) finds the maximum to
    that tolerance; the best point is then polished by golden-section search to 1e-7 mm.
    At most ``max_evals`` evaluations before the polish. Distances come from ``index`` (a
    :class:`_SegmentGrid` of ``res.segments``, built here when not given), exact.
    """
    import heapq

    path = res.segments
    r = res.radius
    if not path:
        p = _point(part[reg[0][0]], reg[0][1])
        return math.inf, p
    grid = index if index is not None else _SegmentGrid(path)

    at = {q: _point_fn(part[q]) for q, _, _ in reg}
    distance = grid.distance

    def f(q: int, t: float) -> float:
        return distance(at[q](t)) - r

    best_v, best_at = -math.inf, (reg[0][0], reg[0][1])
    heap: list[tuple[float, int, float, float, float, float]] = []
    evals = 0
    for q, a, b in reg:
        L = part[q].length
        m = max(2, min(100, int(math.ceil(L * (b - a) / 0.1))))
        ts = [a + (b - a) * k / m for k in range(m + 1)]
        vs = [f(q, t) for t in ts]
        evals += len(ts)
        for t, v in zip(ts, vs):
            if v > best_v:
                best_v, best_at = v, (q, t)
        for k in range(m):
            ub = (vs[k] + vs[k + 1]) / 2 + L * (ts[k + 1] - ts[k]) / 2
            heapq.heappush(heap, (-ub, q, ts[k], ts[k + 1], vs[k], vs[k + 1]))
    while heap and evals < max_evals:
        nub, q, a, b, va, vb = heapq.heappop(heap)
        if -nub <= best_v + MEASURE_TOL:
            break
        m = (a + b) / 2
        vm = f(q, m)
        evals += 1
        if vm > best_v:
            best_v, best_at = vm, (q, m)
        L = part[q].length
        for lo, hi, vl, vh in ((a, m, va, vm), (m, b, vm, vb)):
            ub = (vl + vh) / 2 + L * (hi - lo) / 2
            if ub > best_v + MEASURE_TOL:
                heapq.heappush(heap, (-ub, q, lo, hi, vl, vh))
    # polish
    q, t = best_at
    g = part[q]
    lo_lim = min(a for qq, a, _ in reg if qq == q)
    hi_lim = max(b for qq, _, b in reg if qq == q)
    h = 2 * MEASURE_TOL / max(g.length, EPS) + 1e-9
    lo, hi = max(lo_lim, t - h), min(hi_lim, t + h)
    gr = (math.sqrt(5) - 1) / 2
    x1, x2 = hi - gr * (hi - lo), lo + gr * (hi - lo)
    f1, f2 = f(q, x1), f(q, x2)
    while (hi - lo) * g.length > 1e-7:
        if f1 > f2:
            hi, x2, f2 = x2, x1, f1
            x1 = hi - gr * (hi - lo)
            f1 = f(q, x1)
        else:
            lo, x1, f1 = x1, x2, f2
            x2 = lo + gr * (hi - lo)
            f2 = f(q, x2)
    tm = (lo + hi) / 2
    vm = f(q, tm)
    if vm > best_v:
        best_v, best_at = vm, (q, tm)
    return best_v, _point(part[best_at[0]], best_at[1])


def translate_chain(chain: Iterable[Segment], v: Point) -> list[Segment]:
    """Every segment moved by the vector ``v`` (e.g. nose centre -> imaginary tip)."""
    return [g.translated(v[0], v[1]) for g in chain]


# ---------------------------------------------------------------------------------------------
# the insert's flanks

def insert_edges(tip_code: int, approach: float, nose_angle: float) -> tuple[float, float]:
    """Directions of the two cutting edges from the nose into the insert body, as angles in
    degrees in the view Z right / X up (0 = +Z, 90 = +X), for a tool of tip code 1-4 with
    holder approach angle ``approach`` (kappa_r, deg, between the main edge and the feed)
    and insert included angle ``nose_angle`` (epsilon, deg).

    Code 3 (OD tool feeding toward -Z): main edge at 180 - kappa_r, secondary edge at
    180 - kappa_r - epsilon (a 95 deg holder with an 80 deg insert: 85 and 5 deg); codes 2, 4
    and 1 are its mirrors in X, in Z, and in both. Codes 0 and 5-9 do not say which way the
    tool feeds: give the edges explicitly.
    """
    a1, a2 = 180.0 - approach, 180.0 - approach - nose_angle
    if tip_code == 3:
        return a1, a2
    if tip_code == 2:
        return -a1, -a2
    if tip_code == 4:
        return 180.0 - a1, 180.0 - a2
    if tip_code == 1:
        return a1 - 180.0, a2 - 180.0
    raise ValueError(f"insert edges are known from the tip code only for codes 1-4, got {tip_code}")


def _unit_deg(a: float) -> Point:
    t = math.radians(a)
    return (math.sin(t), math.cos(t))  # (x, z) of the view angle a


def _tangent_at(g: Segment, t: float) -> Point:
    if isinstance(g, Line):
        return g.direction
    p = _point(g, t)
    rx, rz = p[0] - g.center[0], p[1] - g.center[1]
    R = math.hypot(rx, rz) or 1.0
    tx, tz = rz / R, -rx / R
    return (-tx, -tz) if g.cw else (tx, tz)


def _ray_hits(o: Point, d: Point, path: list[Segment]) -> list[tuple[float, int, float]]:
    """(ray parameter u > 0, path index, path parameter) where the ray o + u d meets the path."""
    far = (o[0] + d[0], o[1] + d[1])
    out = []
    for i, g in enumerate(path):
        pts = ([line_line_carriers(o, far, g.start, g.end)] if isinstance(g, Line)
               else line_circle_carriers(o, far, g.center, g.radius))
        for p in pts:
            if p is None:
                continue
            u = (p[0] - o[0]) * d[0] + (p[1] - o[1]) * d[1]
            if u <= 1e-7:
                continue
            t = _param(g, p) if g.length > EPS else 0.0
            if -1e-9 <= t <= 1 + 1e-9 and g.distance_to(p) < 1e-7:
                out.append((u, i, min(1.0, max(0.0, t))))
    out.sort()
    return out


def insert_check(res: OffsetResult, edges: tuple[float, float]) -> list[Departure]:
    """Stretches of the contour the insert's flanks keep the nose from following.

    ``edges``: the two cutting-edge directions from the nose into the insert body (view
    angles in degrees, see :func:`insert_edges`). With the tool at nose-centre position ``c``,
    the insert occupies the nose disc plus the wedge between the edges; it stays clear of
    the part where the path's tool-side normal has a non-negative component along both
    edges. Where it has not (a plunge steeper than the trailing edge's clearance, a face
    leaning over the tool, a corner sharper than the insert), the reachable nose path
    follows the edge instead: a straight **shadow** along the edge from where the path
    turns away (forward) or back to where it returns (backward), to where it meets the path
    again. Each such stretch is a :class:`Departure` of kind ``insert`` (``end`` when the
    shadow runs off an open end of the chain, e.g. the back face at the chuck end of an
    outside contour, which a tool feeding toward the chuck cannot cut); ``departure`` is
    the largest distance from the part there to the nose along the shadowed path (measured
    like the other departures). The returned path itself is not altered.
    """
    path = res.segments
    if not path or res.radius <= 0:
        return []
    r, s = res.radius, res.side
    e = [_unit_deg(a) for a in edges]

    def normal(i: int, t: float) -> Point:
        tg = _tangent_at(path[i], t)
        n = left_normal(tg)
        return (s * n[0], s * n[1])

    def worst(n: Point) -> tuple[float, int]:
        d = [n[0] * v[0] + n[1] * v[1] for v in e]
        k = 0 if d[0] <= d[1] else 1
        return d[k], k

    # hidden pieces: split arcs where the normal is perpendicular to an edge
    marks: list[tuple[int, float, float, bool]] = []
    for i, g in enumerate(path):
        ts = [0.0, 1.0]
        if isinstance(g, Arc) and g.length > EPS:
            for v in e:
                for sg in (1, -1):
                    # normal perpendicular to v <=> radial direction is +-v rotated 90 deg
                    q = (g.center[0] + g.radius * sg * v[1], g.center[1] - g.radius * sg * v[0])
                    if dist(q, g.start) > TOL and dist(q, g.end) > TOL:
                        t = _param(g, q)
                        if 0.0 < t < 1.0 and abs(dist(q, g.center) - g.radius) < 1e-9:
                            ts.append(t)
        ts = sorted(set(ts))
        for a, b in zip(ts, ts[1:]):
            hid = worst(normal(i, (a + b) / 2))[0] < -1e-7
            marks.append((i, a, b, hid))
    stretches: list[list[tuple[int, float, float]]] = []
    prev = False
    for i, a, b, hid in marks:
        if hid:
            if prev:
                stretches[-1].append((i, a, b))
            else:
                stretches.append([(i, a, b)])
        prev = hid
    out: list[Departure] = []
    covered = (-1, 0.0)  # end of the last shadow: stretches inside it are already reported
    for st in stretches:
        (ia, ta, _), (ib, _, tb) = st[0], st[-1]
        if (ia, ta) < covered:
            continue
        A, B = _point(path[ia], ta), _point(path[ib], tb)
        ka = worst(normal(ia, (st[0][1] + st[0][2]) / 2))[1]
        kb = worst(normal(ib, (st[-1][1] + st[-1][2]) / 2))[1]
        dA = (-e[ka][0], -e[ka][1])
        dB = (-e[kb][0], -e[kb][1])
        tA, tB = _tangent_at(path[ia], ta), _tangent_at(path[ib], tb)
        fwd = dA[0] * tA[0] + dA[1] * tA[1] > 1e-9
        bwd = dB[0] * tB[0] + dB[1] * tB[1] < -1e-9
        pos_a, pos_b = (ia, ta), (ib, tb)
        env: list[Segment] = []
        kind = "insert"
        lo, hi = pos_a, pos_b
        hitA = next(((u, i, t) for u, i, t in _ray_hits(A, dA, path) if (i, t) > (ia, ta + 1e-9)),
                    None) if fwd else None
        hitB = next(((u, i, t) for u, i, t in _ray_hits(B, dB, path) if (i, t) < (ib, tb - 1e-9)),
                    None) if bwd else None
        X = line_line_carriers(A, (A[0] + dA[0], A[1] + dA[1]), B, (B[0] + dB[0], B[1] + dB[1])) \
            if fwd and bwd else None
        if X is not None:
            uA = (X[0] - A[0]) * dA[0] + (X[1] - A[1]) * dA[1]
            uB = (X[0] - B[0]) * dB[0] + (X[1] - B[1]) * dB[1]
            if uA > 0 and uB > 0 and (hitA is None or uA <= hitA[0]) and (hitB is None or uB <= hitB[0]):
                env = [Line(A, X), Line(X, B)]
        if not env and hitA is not None:
            C = _point(path[hitA[1]], hitA[2])
            env, hi = [Line(A, C)], (hitA[1], hitA[2])
        elif not env and hitB is not None:
            C = _point(path[hitB[1]], hitB[2])
            env, lo = [Line(C, B)], (hitB[1], hitB[2])
        elif not env and fwd:
            # the shadow runs off the open end of the path
            L = sum(g.length for g in path) + 1.0
            env, hi = [Line(A, (A[0] + L * dA[0], A[1] + L * dA[1]))], (len(path) - 1, 1.0)
            kind = "end"
        elif not env and bwd:
            L = sum(g.length for g in path) + 1.0
            env, lo = [Line((B[0] + L * dB[0], B[1] + L * dB[1]), B)], (0, 0.0)
            kind = "end"
        if not env:
            continue
        covered = max(covered, hi)
        # the shadowed path: before lo, the envelope, after hi
        new: list[Segment] = []
        for i, g in enumerate(path):
            if i < lo[0] or i > hi[0]:
                new.append(g)
                continue
            if i == lo[0] and lo[1] > 0:
                p = _point(g, lo[1])
                if dist(g.start, p) > TOL:
                    new.append(_sub(g, g.start, p))
            if i == hi[0] and hi[1] < 1:
                p = _point(g, hi[1])
                if dist(p, g.end) > TOL:
                    new.append(_sub(g, p, g.end))
        new += env
        boxes = [g.bbox() for g in new]

        def f(i: int, t: float) -> tuple[float, Point]:
            c = _point(path[i], t)
            n = normal(i, t)
            p = (c[0] - r * n[0], c[1] - r * n[1])
            best = math.inf
            for g, bx in zip(new, boxes):
                if _point_box_gap(p, bx) >= best:
                    continue
                best = min(best, g.distance_to(p))
            return best - r, p

        # evaluate along the replaced stretch of the path (step <= 0.05 mm) and polish
        best_v, best_p, best_at = -math.inf, A, (lo[0], lo[1])
        for i in range(lo[0], hi[0] + 1):
            a = lo[1] if i == lo[0] else 0.0
            b = hi[1] if i == hi[0] else 1.0
            if b <= a:
                continue
            m = max(4, min(2000, int(math.ceil(path[i].length * (b - a) / 0.05))))
            for k in range(m + 1):
                t = a + (b - a) * k / m
                v, p = f(i, t)
                if v > best_v:
                    best_v, best_p, best_at = v, p, (i, t, (b - a) / m, a, b)
        if len(best_at) == 5:
            i, t, h, a, b = best_at
            x0, x1 = max(a, t - h), min(b, t + h)
            gr = (math.sqrt(5) - 1) / 2
            while (x1 - x0) * path[i].length > 1e-7:
                y0, y1 = x1 - gr * (x1 - x0), x0 + gr * (x1 - x0)
                if f(i, y0)[0] > f(i, y1)[0]:
                    x1 = y1
                else:
                    x0 = y0
            v, p = f(i, (x0 + x1) / 2)
            if v > best_v:
                best_v, best_p = v, p
        # part corners and segments the path skips at its kinks (not reached by c - r n)
        src = res.source
        for i in range(lo[0], hi[0]):
            o0, o1 = res.origins[i], res.origins[i + 1]
            if o0.kind == "link" or o1.kind == "link" or o1.before <= o0.after:
                continue
            for k in range(o0.after, o1.before + 1):
                g = src[k]
                ts = [0.0] if k > o0.after else []
                if o0.after < k < o1.before:
                    ts += [j / 20 for j in range(1, 21)]
                for t in ts:
                    p = _point(g, t)
                    v = min(x.distance_to(p) for x in new) - r
                    if v > best_v:
                        best_v, best_p = v, p
        if best_v <= DEPARTURE_TOL:
            continue
        segs = sorted({o.before for o in res.origins[lo[0]:hi[0] + 1]}
                      | {o.after for o in res.origins[lo[0]:hi[0] + 1]})
        c0, c1 = _point(path[lo[0]], lo[1]), _point(path[hi[0]], hi[1])
        n0, n1 = normal(lo[0], lo[1]), normal(hi[0], hi[1])
        p0 = (c0[0] - r * n0[0], c0[1] - r * n0[1])
        p1 = (c1[0] - r * n1[0], c1[1] - r * n1[1])
        msg = (f"the insert's edge at {edges[ka if fwd else kb]:g} deg keeps the nose off the "
               f"contour from {_fmt(p0)} to {_fmt(p1)}"
               + (" (to the end of the chain)" if kind == "end" else "")
               + f": left up to {best_v:.3f} mm oversize (at {_fmt(best_p)})")
        out.append(Departure(kind, tuple(segs), p0, p1, best_v, best_p, msg))
    return out
