"""One roughing engine for the HNC-21T stock-removal cycles G71 (type I and II), G72 and G73.

Pure geometry on exact :class:`Line`/:class:`Arc` chains (x = radius, z). The interpreter's
cycle module (``hnc_cam.nc.cycles_rough``) reads the words, asks for the programmed profile
``ns…nf`` and turns the returned moves into toolpath moves.

Normalisation
=============
Every G71/G72 job is mapped by a :class:`Frame` (an axis swap and/or mirrors, determinant
±1, so lines stay lines and arcs stay arcs, turning sense flipped on a reflection) into
one canonical quadrant: coordinates ``(u, v)``, used as the ``(x, z)`` of the primitives,

* ``u`` is the *level* axis: the passes lie at ``u = const``, the material is on the +u side
  of the profile and the passes step toward −u (G71: u = ±X; G72: u = ±Z);
* ``v`` is the *cutting* axis: every pass feeds toward −v (G71: v = ±Z; G72: v = ±X).

G72 is G71 with the axes swapped, a bore (ID) is an OD mirrored in X, a cut toward +Z is a
cut toward −Z mirrored. The signs come from the geometry: the direction of Δd is that of the
block ns (A→A′, manual: "方向由矢量AA′决定"), the cutting direction is from A toward the end
of the profile B. The moves are planned in canonical coordinates and mapped back.

The model of the stock (where the manual is silent)
===================================================
* The allowance-offset profile is the programmed path translated by the allowance
  ``(Δx/2, Δz)`` (G71 type II: ``(e/2, 0)``); it is a pure translation, not a tool-nose offset.
* The material is assumed to fill the rectangle between the cycle start point A and the
  offset profile: the region ``u <= u_A``, ``v <= v_A``, beyond the offset profile (on the
  +u side), bounded at the far end by the line through B″ (the offset end point) across the
  passes. Passes start on the face ``v = v_A`` and the levels are ``u_A − k·Δd``, k = 1, 2, …
  (macro %0071 starts from the allowance-shifted point C = A + (Δx, Δz) and puts its first
  level Δd + r below it, i.e. it takes A as lying r outside the stock; we take A as the
  stock corner so that no pass is deeper than Δd).
* At a level, the material is the set of intervals of ``v`` where the offset profile lies
  below the level. Every pass runs along one such interval, from its +v end to its −v end,
  and ends exactly where the offset profile (or the end line through B″) is met; the rest
  of the stair is left to the last pass, which follows the whole offset profile.
* A level's intervals are nested in the intervals of the level above; they form a tree.
  The passes are cut depth-first, children in order of decreasing v (the one nearest to the
  start face first). For type I this is the plain level-by-level order of macro %0071. For
  type II (grooves, pockets) it means (our choice: the manual's fig. 3.3.26 is not legible
  in the extracted text and macro %0071 has no type II): the region that opens on the start
  face is roughed down to its bottom first, then each groove in turn from the start side
  toward the far end, each groove down to its bottom (its own sub-grooves in the same
  order) before the next one. Depth-first keeps every travel inside space already cut.
* Profiles: type I (and G72) must be monotonic along both axes (levels and cut), type II
  along the cut only (alarm otherwise). An arc that runs back past an X/Z extreme by at most
  ``ROUND_TOL`` = 0.001 mm still counts as monotonic: an arc meant to start or end on its
  extreme, written with coordinates rounded to 0.001 mm, passes it by about the rounding
  (the sliver behind such a hair-thin overhang is left to the last pass). "The profile does not reach the start side" is an
  alarm when its end B lies deeper (further from A along the level axis) than its start A′:
  the finished shape must rise back toward the start side, as every profile of the manual
  does.
* Moves between passes never cross material that is not removed yet: after a pass the tool
  retracts by r in u and by min(r, pass length) in v (the macro's 45° retract, clipped so it
  stays over the pass just cut), travels at the higher of its own level and the level of
  the deepest already-cut pass whose interval covers both ends of the travel, and goes down
  over already-cut passes. A pass that starts on the face v = v_A is entered by a rapid
  along the face; a groove is entered by a feed from the parent pass level straight down
  (``v = const``) to the new level (that plunge cuts the stair in front of the pass, so it
  is a feed); a pass that starts on a slanted approach A→A′ (a G71 block ns with a Z
  component) is entered by a feed down along that line, which also cuts the stair between
  the line and the pass. The far side of the approach line is taken as air.
* After the passes, the last pass follows the whole offset profile (A″ … B″) at the cycle's
  feed (G00 blocks of the profile stay rapids; with a slanted approach the tool feeds down
  the approach line from the start of the lowest pass on it), then the tool goes back to A:
  first away from the work across the passes (u up to the higher of A and the profile),
  then along v, then to A. Macro %0071 does the last leg as one G00 from B″ to A; the
  axis-separated return can never pass through the part whatever the rapid rates are.

G73 (pattern repeat) follows macro %0073 with r passes: pass k (k = 1…r) is the whole
programmed path shifted by the remaining stock ``(ΔI, ΔK)·(r − k)/r`` plus the finishing
allowance ``(Δx/2, Δz)``, so the last pass lies on the allowance-offset profile and each
pass removes (ΔI/r, ΔK/r). (Macro %0073 runs r + 1 loops, the first at the full ΔI, which
is an air cut when the blank is exactly ΔI oversize.) Between passes the tool returns to the
next shifted start point along the axes, moving first along the axis that leads away from
the work.

Alarms of the engine are :class:`RoughingError` with the index of the offending profile
segment; the cycle module turns them into NC alarms at the block.
"""
from __future__ import annotations

import math
from bisect import bisect_left
from dataclasses import dataclass, field
from typing import Optional, Sequence

from .intersect import horizontal_hits, vertical_hits
from .primitives import TOL, Arc, Line, Point, Segment, dist, point_at_angle, same_point

#: an arc may run back past an X/Z extreme by this much (mm) and still count as monotonic:
#: an arc meant to start or end on its extreme, written with coordinates rounded to
#: 0.001 mm (0.0005 mm in radius), passes the extreme by about the rounding
ROUND_TOL = 1e-3
#: intervals (and pass lengths) shorter than this are not cut (mm)
MIN_PASS = 1e-5
#: refuse to plan more levels than this (a unit mistake, e.g. U0.001)
MAX_LEVELS = 20000


class RoughingError(ValueError):
    """A profile the cycle cannot rough; ``index`` is the offending profile segment
    (0 = the block ns, A→A′) or None."""

    def __init__(self, message: str, index: Optional[int] = None):
        super().__init__(message)
        self.message = message
        self.index = index


@dataclass(frozen=True, slots=True)
class RoughMove:
    """One move of a roughing cycle in work coordinates (x radius, z)."""
    kind: str  # 'rapid' | 'feed'
    seg: Segment
    role: str  # 'approach' | 'cut' | 'plunge' | 'retract' | 'link' | 'finish' | 'return'
    level: Optional[int] = None  # pass number of G71/G72 cuts (1 = first level), G73 pass no.

    @property
    def end(self) -> Point:
        return self.seg.end


@dataclass
class RoughPlan:
    moves: list[RoughMove]
    warnings: list[str] = field(default_factory=list)
    levels: int = 0  # number of pass levels (G71/G72) or passes (G73)
    passes: int = 0  # number of cutting passes (G71/G72: intervals cut)
    #: the allowance-offset profile A″…B″ (without the block ns)
    offset_profile: list[Segment] = field(default_factory=list)


# --------------------------------------------------------------------------- frames

@dataclass(frozen=True, slots=True)
class Frame:
    """World (x, z) <-> canonical (u, v): without swap u = su·x, v = sv·z; with swap
    u = su·z, v = sv·x."""
    swap: bool
    su: int
    sv: int

    def fwd(self, p: Point) -> Point:
        x, z = p
        return (self.su * z, self.sv * x) if self.swap else (self.su * x, self.sv * z)

    def inv(self, q: Point) -> Point:
        u, v = q
        return (self.sv * v, self.su * u) if self.swap else (self.su * u, self.sv * v)

    @property
    def reflects(self) -> bool:
        det = self.su * self.sv * (-1 if self.swap else 1)
        return det < 0

    def _map(self, s: Segment, f) -> Segment:
        if isinstance(s, Arc):
            cw = (not s.cw) if self.reflects else s.cw
            return Arc(f(s.start), f(s.end), f(s.center), cw)
        return Line(f(s.start), f(s.end))

    def seg_fwd(self, s: Segment) -> Segment:
        return self._map(s, self.fwd)

    def seg_inv(self, s: Segment) -> Segment:
        return self._map(s, self.inv)


def _sign(v: float) -> int:
    return 1 if v >= 0 else -1


# --------------------------------------------------------------------------- chain helpers

def is_monotonic(seg: Segment, axis: int, sense: int, tol: float = TOL,
                 overshoot: float = ROUND_TOL) -> bool:
    """True when coordinate ``axis`` (0 = x, 1 = z) never decreases (``sense`` = +1) or never
    increases (``sense`` = −1) along the segment: the end must not lie back of the start by
    more than ``tol``, and an arc may pass an extreme point of that coordinate in its
    interior only when the coordinate goes back by at most ``overshoot`` there (an arc meant
    to start or end on its extreme, written with coordinates rounded to 0.001 mm, passes it
    by a hair: see :data:`ROUND_TOL`)."""
    a0, a1 = seg.start[axis], seg.end[axis]
    if sense * (a1 - a0) < -tol:
        return False
    if isinstance(seg, Arc):
        # polar angle atan2(x - xc, z - zc): x is extreme at +-pi/2, z at 0 and pi
        for ang in ((math.pi / 2, -math.pi / 2) if axis == 0 else (0.0, math.pi)):
            if seg.contains_angle(ang):
                p = point_at_angle(seg.center, seg.radius, ang)
                if dist(p, seg.start) > tol and dist(p, seg.end) > tol:
                    # a maximum is passed back toward the end, a minimum toward the start
                    back = max(sense * (p[axis] - a1), sense * (a0 - p[axis]))
                    if back > overshoot:
                        return False
    return True


def first_non_monotonic(chain: Sequence[Segment], axis: int, sense: int,
                        tol: float = TOL) -> Optional[int]:
    """Index of the first segment of ``chain`` that is not monotonic (see
    :func:`is_monotonic`), or None."""
    for i, s in enumerate(chain):
        if not is_monotonic(s, axis, sense, tol):
            return i
    return None


def translate_chain(chain: Sequence[Segment], dx: float, dz: float) -> list[Segment]:
    return [s.translated(dx, dz) for s in chain]


class _TopOfChain:
    """u of a chain that is monotonic in v (non-increasing along it), as a function of v:
    the highest chain point at that v; +inf outside the chain's v range."""

    def __init__(self, chain: Sequence[Segment]):
        self.chain = list(chain)
        # v ranges (arcs: their bounding boxes, which may overshoot the end points by up to
        # ROUND_TOL), descending along the chain up to that overshoot; the search uses the
        # running minimum of vmin and the suffix maximum of vmax, which are monotonic
        boxes = [s.bbox() for s in self.chain]
        self.vmax = [b[3] for b in boxes]
        self.vmin = [b[1] for b in boxes]
        env, m = [], math.inf
        for v in self.vmin:
            m = min(m, v)
            env.append(-m)
        self.neg_vmin = env  # ascending
        suf, m = [0.0] * len(self.vmax), -math.inf
        for j in range(len(self.vmax) - 1, -1, -1):
            m = max(m, self.vmax[j])
            suf[j] = m
        self.vmax_after = suf  # non-increasing
        self.top = max(self.vmax) if self.chain else 0.0
        self.bottom = min(self.vmin) if self.chain else 0.0

    def __call__(self, v: float) -> float:
        if not self.chain or v > self.top + TOL or v < self.bottom - TOL:
            return math.inf
        # first segment whose vmin <= v + TOL  (vmin is non-increasing along the chain)
        i = bisect_left(self.neg_vmin, -(v + TOL))
        best = -math.inf
        n = len(self.chain)
        j = max(0, i - 1)
        while j < n and self.vmax_after[j] >= v - TOL:
            if self.vmin[j] <= v + TOL:
                for _, u in vertical_hits([self.chain[j]], v):
                    best = max(best, u)
                s = self.chain[j]
                for p in (s.start, s.end):
                    if abs(p[1] - v) <= TOL:
                        best = max(best, p[0])
            j += 1
        return best if best > -math.inf else math.inf


# --------------------------------------------------------------------------- G71 / G72

@dataclass(eq=False)
class _Node:
    u: float
    lo: float
    hi: float
    k: int  # level number (0 = the virtual root over the whole stock)
    parent: Optional["_Node"] = None
    children: list["_Node"] = field(default_factory=list)


def _intervals(chain: Sequence[Segment], top: _TopOfChain, u: float, v_lo: float,
               v_hi: float) -> list[tuple[float, float]]:
    """Material intervals of v at level u (offset chain strictly below u), in [v_lo, v_hi],
    ordered by decreasing v."""
    cuts = {v_lo, v_hi}
    for _, v in horizontal_hits(chain, u):
        if v_lo + TOL < v < v_hi - TOL:
            cuts.add(v)
    pts = sorted(cuts)
    out: list[list[float]] = []
    for a, b in zip(pts, pts[1:]):
        if b - a <= TOL:
            continue
        if top(0.5 * (a + b)) < u - TOL:
            if out and abs(out[-1][1] - a) <= TOL and top(a) <= u + TOL:
                out[-1][1] = b  # the profile only touches the level at a: one interval
            else:
                out.append([a, b])
    res = [(a, b) for a, b in out if b - a > MIN_PASS]
    res.reverse()
    return res


def _frame_for(start: Point, profile: Sequence[Segment], face: bool) -> Frame:
    ap = profile[0].end  # A'
    end = profile[-1].end  # B
    if face:  # G72: levels along Z (direction of A->A'), cut along X (toward B)
        d_level = ap[1] - start[1]
        d_cut = end[0] - start[0]
        axis_l, axis_c = "Z", "X"
    else:  # G71: levels along X, cut along Z
        d_level = ap[0] - start[0]
        d_cut = end[1] - start[1]
        axis_l, axis_c = "X", "Z"
    if abs(d_level) <= TOL:
        raise RoughingError(
            f"the first profile block (A→A′) does not move in {axis_l}: the direction of the "
            f"depth of cut is taken from A→A′", 0)
    if abs(d_cut) <= TOL:
        raise RoughingError(
            f"the profile ends at the {axis_c} of the start point: it does not reach away from "
            f"the start side, there is nothing to cut along {axis_c}", len(profile) - 1)
    return Frame(face, -_sign(d_level), -_sign(d_cut))


def rough_turn(start: Point, profile: Sequence[Segment], motions: Sequence[str], *,
               depth: float, retract: float, allowance: Point, face: bool = False,
               pockets: bool = False, finish_allowance: Optional[Point] = None,
               sign_warning: Optional[str] = None) -> RoughPlan:
    """Plan G71 (``face=False``) or G72 (``face=True``) roughing.

    ``profile``: the programmed path ns…nf from the start point A (segment 0 is A→A′);
    ``motions``: 'rapid'/'feed' per segment (as programmed, used for the last pass);
    ``depth`` Δd (> 0), ``retract`` r (> 0), ``allowance`` (dx radius, dz) translation of the
    profile; ``pockets``: G71 type II (profile monotonic only along the cut).
    ``finish_allowance`` (dx radius, dz): the last pass follows the profile translated by it
    instead of ``allowance`` (Haas's rough-pass allowance I/K: the level passes stop at
    ``allowance``, the last pass leaves only ``finish_allowance``); it must lie between the
    profile and ``allowance``. ``sign_warning``: the text of the warning given when the
    allowance points toward the part (default: the HNC manual's figure).
    Returns the moves in work coordinates, starting at ``start`` and ending there."""
    if depth <= 0:
        raise RoughingError(f"depth of cut must be > 0, got {depth:g}")
    if retract < 0:
        raise RoughingError(f"retract must be >= 0, got {retract:g}")
    segs = [(s, m) for s, m in zip(profile, motions) if s.length > TOL]
    index = [i for i, s in enumerate(profile) if s.length > TOL]
    if not segs:
        raise RoughingError("the profile ns…nf has no motion")
    if not same_point(segs[0][0].start, start, 1e-6):
        raise RoughingError("the profile does not start at the cycle start point", 0)
    path = [s for s, _ in segs]
    mot = [m for _, m in segs]
    if len(path) < 2:
        raise RoughingError("the profile ns…nf has only the approach block A→A′", index[0])
    fr = _frame_for(start, path, face)
    warnings: list[str] = []

    A = fr.fwd(start)
    canon = [fr.seg_fwd(s) for s in path]
    du, dv = fr.fwd(allowance)  # a vector: the frame is linear
    if du < -TOL or dv < -TOL:
        warnings.append(sign_warning or
                        "the sign of the finishing allowance is opposite to fig. %s for this "
                        "quadrant: the offset profile is shifted toward the part"
                        % ("3.3.31" if face else "3.3.25"))
    fin_du, fin_dv = (du, dv) if finish_allowance is None else fr.fwd(finish_allowance)
    if (fin_du - du > TOL or fin_dv - dv > TOL or (fin_du < -TOL and du >= -TOL)
            or (fin_dv < -TOL and dv >= -TOL)):
        raise RoughingError("the finishing allowance of the last pass lies outside the "
                            "allowance of the roughing passes")

    # --- checks on the programmed (canonical) profile
    bad = first_non_monotonic(canon, 1, -1)
    if bad is not None:
        raise RoughingError(
            "the profile turns back against the cutting direction (%s must be monotonic "
            "along the passes)" % ("X" if face else "Z"), index[bad])
    if canon[-1].end[0] < canon[0].end[0] - TOL:
        raise RoughingError(
            "the profile does not reach the start side: its end B lies deeper than its start "
            "A′ as seen from the start point", index[-1])
    if not pockets:
        bad = first_non_monotonic(canon[1:], 0, +1)
        if bad is not None:
            raise RoughingError(
                "profile is not monotonic in Z (G72 has no type II for grooves)" if face else
                "type I profile is not monotonic in X (use type II, the E word, for grooves)",
                index[bad + 1])

    off = translate_chain(canon, du, dv)  # offset path C -> A'' -> ... -> B''
    top = _TopOfChain(off)
    uA, vA = A
    B2 = off[-1].end
    v_lo = B2[1]
    if v_lo >= vA - TOL:
        raise RoughingError("the offset profile ends in front of the start point: nothing to "
                            "rough", index[-1])

    # --- levels and the tree of intervals
    root = _Node(uA, v_lo, vA, 0)
    prev = [root]
    nodes: list[_Node] = []
    (cu, cv), (au, av) = off[0].start, off[0].end
    slanted = abs(au - cu) > TOL and abs(av - cv) > TOL  # block ns moves in both axes
    k = 0
    n_int = 0
    while True:
        k += 1
        if k > MAX_LEVELS:
            raise RoughingError(f"more than {MAX_LEVELS} pass levels: depth of cut {depth:g} "
                                f"is too small for this stock")
        u = uA - k * depth
        ivs = _intervals(off, top, u, v_lo, vA)
        if not ivs:
            break
        cur = []
        for lo, hi in ivs:
            par = None
            for p in prev:
                if lo >= p.lo - 1e-6 and hi <= p.hi + 1e-6:
                    par = p
                    break
            if par is None:  # numerical fringe: the one with the largest overlap
                par = max(prev, key=lambda p: min(hi, p.hi) - max(lo, p.lo))
            node = _Node(u, lo, hi, k, par)
            par.children.append(node)
            cur.append(node)
            nodes.append(node)
            n_int += 1
        prev = cur
    levels = k - 1

    # --- emit in canonical coordinates
    out: list[tuple[str, Segment, str, Optional[int]]] = []
    pos = [A]

    def go(kind: str, p: Point, role: str, lev: Optional[int] = None) -> None:
        if not same_point(pos[0], p, 1e-9):
            out.append((kind, Line(pos[0], p), role, lev))
            pos[0] = p

    def travel(frm: _Node, to_v: float, role: str) -> float:
        """From the current point (over node ``frm``'s cut) to (h, to_v); returns h."""
        x = frm
        while x.parent is not None and not (x.lo - 1e-6 <= to_v <= x.hi + 1e-6):
            x = x.parent
        h = max(pos[0][0], x.u)
        go("rapid", (h, pos[0][1]), role)
        go("rapid", (h, to_v), role)
        return h

    last: _Node = root
    stack = list(reversed(root.children))
    while stack:
        node = stack.pop()
        if node.hi >= vA - TOL:
            travel(last, node.hi, "link")
            go("rapid", (node.u, node.hi), "approach", node.k)
        else:
            par = node.parent
            assert par is not None
            wu, wv = par.u, node.hi
            if slanted and off[0].distance_to((node.u, node.hi)) < 1e-7:
                # the pass starts on a slanted approach line C→A″: come down along it from
                # the parent level (or from the face), so that the stair in front of the
                # pass is cut too
                wv = cv + (par.u - cu) * (av - cv) / (au - cu)
                if wv > par.hi:
                    wu, wv = cu + (par.hi - cv) * (au - cu) / (av - cv), par.hi
            travel(last, wv, "link")
            go("rapid", (wu, wv), "approach", node.k)
            out.append(("feed", Line(pos[0], (node.u, node.hi)), "plunge", node.k))
            pos[0] = (node.u, node.hi)
        out.append(("feed", Line(pos[0], (node.u, node.lo)), "cut", node.k))
        pos[0] = (node.u, node.lo)
        rz = min(retract, node.hi - node.lo)
        go("rapid", (node.u + retract, node.lo + rz), "retract", node.k)
        last = node
        stack.extend(reversed(node.children))

    # last pass: along the whole offset profile
    if finish_allowance is not None:
        off = translate_chain(canon, fin_du, fin_dv)
    A2 = off[0].end
    on_ns = [n for n in nodes if slanted and finish_allowance is None
             and off[0].distance_to((n.u, n.hi)) < 1e-7]
    if on_ns:
        # slanted approach: from the start of the lowest pass on it, feed down the approach
        # line to A″ (this cuts the last stair between that line and the profile)
        nk = min(on_ns, key=lambda n: n.u)
        travel(last, nk.hi, "link")
        go("rapid", (nk.u, nk.hi), "link")
        out.append(("feed", Line(pos[0], A2), "finish", None))
    else:
        h = travel(last, vA, "link")
        if off[0].start[1] > vA + TOL:
            go("rapid", (h, off[0].start[1]), "link")
        out.append(("rapid" if mot[0] == "rapid" else "feed", Line(pos[0], A2), "finish", None))
    pos[0] = A2
    for s, m in zip(off[1:], mot[1:]):
        if m == "rapid":
            out.append(("rapid", Line(s.start, s.end), "finish", None))
        else:
            out.append(("feed", s, "finish", None))
        pos[0] = s.end
    # back to A, away from the work first
    u_top = max(uA, max(max(s.start[0], s.end[0], s.bbox()[2]) for s in off))
    go("rapid", (u_top, pos[0][1]), "return")
    go("rapid", (u_top, vA), "return")
    go("rapid", A, "return")

    moves = [RoughMove(kind, fr.seg_inv(seg), role, lev) for kind, seg, role, lev in out]
    return RoughPlan(moves, warnings, levels, n_int,
                     [fr.seg_inv(s) for s in off[1:]])


# --------------------------------------------------------------------------- G73

def pattern_repeat(start: Point, profile: Sequence[Segment], motions: Sequence[str], *,
                   stock: Point, allowance: Point, count: int,
                   sign_warning: Optional[str] = None) -> RoughPlan:
    """Plan G73: ``count`` passes, pass k the programmed path (from A) shifted by
    ``allowance + stock·(count − k)/count`` (all (dx radius, dz)); back to A at the end.
    (FANUC's spacing (d − k)/(d − 1) is this with ``stock`` scaled by d/(d − 1).)
    ``sign_warning``: the text of the warning given when a shift points toward the part,
    ``{name}`` standing for the word pair (default: the HNC manual's figure)."""
    if count < 1:
        raise RoughingError(f"number of passes must be >= 1, got {count}")
    segs = [(s, m) for s, m in zip(profile, motions) if s.length > TOL]
    if not segs:
        raise RoughingError("the profile ns…nf has no motion")
    if not same_point(segs[0][0].start, start, 1e-6):
        raise RoughingError("the profile does not start at the cycle start point", 0)
    path = [s for s, _ in segs]
    mot = [m for _, m in segs]
    ap, end = path[0].end, path[-1].end
    # outward direction in X: toward A from the profile (OD when A' lies below A)
    sx = 1 if ap[0] < start[0] - TOL else (-1 if ap[0] > start[0] + TOL else
                                           (1 if end[0] <= start[0] else -1))
    sz = 1 if end[1] < start[1] else -1
    fr = Frame(False, sx, sz)
    warnings: list[str] = []
    for name, (dx, dz) in (("finishing allowance X/Z", allowance), ("roughing stock U/W", stock)):
        if sx * dx < -TOL or sz * dz < -TOL:
            warnings.append(sign_warning.format(name=name) if sign_warning else
                            f"the sign of the {name} is opposite to fig. 3.3.34 for this "
                            f"quadrant: the passes are shifted toward the part")
    A = fr.fwd(start)
    canon = [fr.seg_fwd(s) for s in path]
    out: list[tuple[str, Segment, str, Optional[int]]] = []
    pos = [A]

    def go(kind: str, p: Point, role: str, lev: Optional[int]) -> None:
        if not same_point(pos[0], p, 1e-9):
            out.append((kind, Line(pos[0], p), role, lev))
            pos[0] = p

    def axis_path(target: Point, role: str, lev: Optional[int]) -> None:
        # move first along the axis that leads away from the work
        if target[0] >= pos[0][0]:
            go("rapid", (target[0], pos[0][1]), role, lev)
        else:
            go("rapid", (pos[0][0], target[1]), role, lev)
        go("rapid", target, role, lev)

    def shift(k: int) -> Point:
        f = (count - k) / count
        return (sx * (allowance[0] + stock[0] * f), sz * (allowance[1] + stock[1] * f))

    for k in range(1, count + 1):
        du, dv = shift(k)
        s0 = (A[0] + du, A[1] + dv)
        if k == 1:
            go("rapid", s0, "approach", k)
        for s, m in zip(canon, mot):
            t = s.translated(du, dv)
            if m == "rapid":
                out.append(("rapid", Line(pos[0], t.end), "cut", k))
            else:
                out.append(("feed", t, "cut", k))
            pos[0] = t.end
        if k < count:
            nu, nv = shift(k + 1)
            axis_path((A[0] + nu, A[1] + nv), "link", k)
    axis_path(A, "return", None)
    du, dv = shift(count)
    moves = [RoughMove(kind, fr.seg_inv(seg), role, lev) for kind, seg, role, lev in out]
    return RoughPlan(moves, warnings, count, count,
                     [fr.seg_inv(s.translated(du, dv)) for s in canon[1:]])
