"""Compare a simulated cut with the model: overcut, undercut, threads, the Report.

Choices (the issue leaves them open):

* The comparison covers Z >= the model's left end (``z_min``): stock beyond it toward the chuck
  is the chucking allowance, neither part nor defect.
* **Overcut** (gouge) = model minus remaining material; its depth at a point is the distance to
  the model's boundary (outside and bore chains and the closing faces, exact Line/Arc
  geometry), measured at every vertex of the region's boundary (segmentised every 0.002 mm, so the
  maximum is found to 0.001 mm; the points of an edge are measured only where a bound on the
  distance says they could be deeper than the deepest found, :func:`_depths`: the same maximum
  to 1e-9 mm) and
  on an interior grid (a part that was cut off entirely has its deepest point inside).
* **Undercut** = remaining material minus model, its size at a point the distance to the model;
  the maximum lies on the region's boundary. Components deeper than ``NOISE`` are split into what
  the tools can reach and what they cannot. A tool reaches where its insert K can be while the
  insert and its holder (the insert swept away from the work past the part: radially outward
  for outside tools, along +Z out of the bore for boring bars and other inside tools, by the
  register's tip code, :func:`holder_direction`) stay out of the model (and its mirror image
  below the axis): so an outside tool reaches only from outside, a boring bar only from the
  bore's open end, and neither through the part. That region is computed with exact Minkowski
  sums of the sampled polygons with the convex outlines (each edge swept as an exact hull,
  :func:`hnc_cam.sim.tool.sweep_hulls`), locally: placements within K's extent of the leftover
  no tool before covered, of the obstacles only the edges that face the holder, and only the
  swept edges that meet the leftover are united (:func:`reachable`). The placements the body
  cannot take lie, seen along the holder, under one function of the coordinate across it (the
  holder reaches past the part): the upper envelope of those edges' sums with the body's
  section, computed with its crossings (exact to ``ENVELOPE_EPS``, 1e-10 mm) and taken as one
  polygon (:func:`_blocked_region`), the same region as the union of the swept edges
  (:func:`_blocked`). The
  stock beyond the part's left end (the chucking allowance, where the part is cut off later) is
  an obstacle too, so the nose fillet a pass leaves exactly at the cut-off line is not a defect.
  Leftover outside the union of the openings of every cutting tool the program used (in inner
  corners sharper than the nose radius, in grooves narrower than the insert, under shoulders the
  insert's orientation cannot reach) is *unreachable*: listed with location and size (its
  distance to the model), a failure only with ``strict``. Leftover inside is *reachable*: a
  defect, counted in ``max_undercut_mm`` by its distance to what the tools could at best leave
  there, the model together with the unreachable leftover. Where no unreachable leftover is
  near, that is the distance to the model; a pass that stops 0.005 mm above a face running into
  a square shoulder leaves a 0.005 mm band, not a band as deep as the nose fillet in the corner
  under it. Components no deeper than ``NOISE`` are not classified and count as reachable.
* **Tails**: leftover the tools could reach that lies within the tolerance of unreachable
  leftover in the same connected piece of leftover (the same side of the model) is the tail of
  that unreachable feature and unreachable too: a feature no tool of the program reaches (a
  chamfer facing the chuck inside a bore, which the planner makes in a second setup) is left
  whole, tail included.
* **Part-off**: when the program parts the part off, the piece that fell off (the simulator's
  ``fallen``) holds more of the model than what stays in the chuck: that piece is the part
  compared, its left end (face and chamfer) included (:func:`separated_part`).
* **Stock**: a stock that does not hold the model (some of the model more than ``NOISE``
  outside it) is bad input (:class:`hnc_cam.errors.StockError`, naming both sizes), not a
  verification failure.
* **Threads**: thread zones (the model's declared threads, or the span of the program's thread
  moves) are excluded from the overcut/undercut comparison between the thread's root and its
  nominal diameter. Instead the achieved root diameter at the worst place along the zone
  (external: the largest diameter of the remaining material; internal: the smallest bore
  diameter), one pitch in from each end (3 pitches, about DIN 76-1's run-out, at an end where the
  part has a wall right beyond it), is compared with the standard: external minor
  d3 = d - 1.2269 P, internal major D; a taper thread's root against the taper at each Z.
  A zone passes when it is within ``max(2 tol, 0.05)`` mm on the diameter.
* Distances are reported to 0.1 um; noise below ``NOISE`` (0.002 mm, a few chord errors) is not
  listed as unreachable.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Sequence
from ..units import fmt_cycle_time

import numpy as np
import shapely
import shapely.affinity
from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry

from ..geometry import Line, Segment, Thread, TurnedProfile
from ..geometry.tip import tip_direction
from .measure import SegmentTable, distances
from .region import clean, diff, inter, polygons, profile_polygon, union as union_of
from .simulate import Issue, Machined
from ..tooling import BAR_CLEARANCE
from .tool import ToolShape, sweep_hulls, tool_shape

NOISE = 0.002
#: boundary points every 0.002 mm: the distance is 1-Lipschitz, so the maximum is found to 0.001
SEGMENTIZE = 0.002
MAX_POINTS = 400_000
BIG = 1e4


@dataclass
class Deviation:
    """A place where the result departs from the model: (z, x radius) and size (mm); ``line``
    is the program line to blame (overcut: the first move that removed material there;
    undercut: the nearest feed move), 0 when none."""
    z: float
    x: float
    size_mm: float
    line: int = 0
    block: str = ""

    def to_json(self) -> dict[str, float]:
        return {"z": _r(self.z), "x": _r(2 * self.x), "size_mm": _r(self.size_mm)}


@dataclass
class ThreadResult:
    z_min: float
    z_max: float
    internal: bool
    target_diameter: float  # external: minor d3; internal: major D
    achieved_diameter: float | None
    tolerance: float
    declared: bool

    @property
    def ok(self) -> bool:
        return (self.achieved_diameter is not None
                and abs(self.achieved_diameter - self.target_diameter) <= self.tolerance)

    def __str__(self) -> str:
        what = "major" if self.internal else "minor"
        got = "none" if self.achieved_diameter is None else f"{self.achieved_diameter:.3f}"
        return (f"thread Z {self.z_min:.3f}..{self.z_max:.3f}: {what} diameter {got}, standard "
                f"{self.target_diameter:.3f} (+-{self.tolerance:.3f}): "
                f"{'ok' if self.ok else 'FAIL'}")


@dataclass
class Report:
    """Verification result. Lengths in mm (``x`` of locations as radius internally)."""
    passed: bool
    tol: float
    max_overcut_mm: float
    max_undercut_mm: float
    overcut_at: Deviation | None
    undercut_at: Deviation | None
    unreachable: list[Deviation]
    collisions: list[Issue]
    cycle_time_s: float
    removed_volume_mm3: float
    air_cut_fraction: float
    threads: list[ThreadResult] = field(default_factory=list)
    strict: bool = False
    overcut: BaseGeometry = field(default_factory=Polygon, repr=False)
    undercut: BaseGeometry = field(default_factory=Polygon, repr=False)
    unreachable_region: BaseGeometry = field(default_factory=Polygon, repr=False)
    reasons: list[str] = field(default_factory=list)
    notes: list[Issue] = field(default_factory=list)

    def to_json(self) -> dict[str, Any]:
        return {"pass": bool(self.passed),
                "max_overcut_mm": _r(self.max_overcut_mm),
                "max_undercut_mm": _r(self.max_undercut_mm),
                "unreachable": [u.to_json() for u in self.unreachable],
                "collisions": [c.to_json() for c in self.collisions],
                "cycle_time_s": _r(self.cycle_time_s),
                "air_cut_fraction": _r(self.air_cut_fraction)}

    def summary(self) -> str:
        def at(d: Deviation | None) -> str:
            if d is None or d.size_mm <= 1e-6:
                return ""
            return f" at X{2 * d.x:.3f} Z{d.z:.3f}" + (f", line {d.line} [{d.block}]" if d.line else "")
        t = self.cycle_time_s
        lines = [f"{'PASS' if self.passed else 'FAIL'} at tolerance {self.tol:g} mm",
                 f"max overcut  {self.max_overcut_mm:.4f} mm{at(self.overcut_at)}",
                 f"max undercut {self.max_undercut_mm:.4f} mm{at(self.undercut_at)} "
                 f"(leftover the tools can reach)",
                 f"cycle time {fmt_cycle_time(t)}, removed "
                 f"{self.removed_volume_mm3:.1f} mm^3, air cut {100 * self.air_cut_fraction:.1f} % "
                 f"of feed time"]
        if self.unreachable:
            lines.append(f"leftover the tools cannot reach, {len(self.unreachable)} place(s) "
                         f"({'counted (strict)' if self.strict else 'not counted in max undercut'}):")
            lines += [f"  X{2 * u.x:.3f} Z{u.z:.3f}: {u.size_mm:.4f} mm" for u in self.unreachable]
        lines += [f"  {t}" for t in self.threads]
        lines += [f"note: {n}" for n in self.notes]
        if self.collisions:
            lines.append(f"{len(self.collisions)} collision(s)/check finding(s):")
            lines += [f"  {c}" for c in self.collisions]
        if not self.passed and self.reasons:
            lines.append("fails: " + "; ".join(self.reasons))
        return "\n".join(lines)


def _r(v: float, nd: int = 4) -> float:
    v = round(float(v), nd)
    return 0.0 if v == 0 else v


def model_segments(model: TurnedProfile) -> list[Segment]:
    """The model's boundary as exact segments: outside chain, bore chain (or nothing), and the
    closing faces at the ends (not the axis)."""
    segs: list[Segment] = list(model.outside)
    o0, o1 = model.outside[0].start, model.outside[-1].end
    if model.bore:
        b0, b1 = model.bore[0].start, model.bore[-1].end
        segs += list(model.bore)
        for a, b in ((o1, b1), (o0, b0)):
            if abs(a[0] - b[0]) + abs(a[1] - b[1]) > 1e-9:
                segs.append(Line(a, b))
    else:
        if o1[0] > 1e-9:
            segs.append(Line(o1, (0.0, o1[1])))
        if o0[0] > 1e-9:
            segs.append(Line((0.0, o0[1]), o0))
    return segs


def _boundary_points(g: BaseGeometry) -> np.ndarray:
    if g.is_empty:
        return np.zeros((0, 2))
    bd = shapely.boundary(g)
    step = max(SEGMENTIZE, bd.length / MAX_POINTS)
    b = shapely.segmentize(bd, step)
    return shapely.get_coordinates(b)


def _grid_points(g: BaseGeometry, n: int = 60) -> np.ndarray:
    out = []
    for p in polygons(g):
        z0, x0, z1, x1 = p.bounds
        if p.area < 1e-4:
            continue
        zs, xs = np.meshgrid(np.linspace(z0, z1, n), np.linspace(x0, x1, n))
        pts = np.column_stack([zs.ravel(), xs.ravel()])
        inside = shapely.contains_xy(p, pts[:, 0], pts[:, 1])
        out.append(pts[inside])
    return np.vstack(out) if out else np.zeros((0, 2))


def _deepest(g: BaseGeometry, segs: Sequence[Segment] | SegmentTable, interior: bool,
             also: BaseGeometry | None = None) -> Deviation | None:
    """The point of ``g`` farthest from the model boundary ``segs`` and its distance (the
    deepest of :func:`_depths` over ``g``'s polygons, the first on a tie).

    ``also``: a region that counts as model too (the unreachable leftover when measuring the
    reachable part: its depth is measured from what the tools could at best leave there).
    ``segs``: the model's segments or their :class:`SegmentTable`."""
    best: Deviation | None = None
    for d in _depths(_polys(g), segs, interior, also, mode="max"):
        if d is not None and (best is None or d.size_mm > best.size_mm):
            best = d
    return best


#: an edge of a region is sampled only when the bound on its depth exceeds the deepest point
#: found so far in its component by more than this (mm)
PRUNE_EPS = 1e-9
#: a run of an edge's sample points that :func:`_depths` cannot settle is cut into this many,
#: one of at most ``2 * SPLIT`` points measured whole
SPLIT = 8
#: ... or, in a round that measures at most ``ROUND_POINTS`` points so, cut into ``SPLIT_FEW``
#: and measured whole up to ``WHOLE_FEW`` points: fewer rounds of the bounds' numpy calls,
#: each costing more than measuring a few hundred points
SPLIT_FEW = 32
WHOLE_FEW = 256
ROUND_POINTS = 4096
#: ... against a model of at most this many lines and arcs (a point measured against many
#: costs more than the rounds saved)
FEW_SEGMENTS = 64


def _point_seg_dist(p: np.ndarray, s0: np.ndarray, s1: np.ndarray) -> np.ndarray:
    """Distance from each point p_i to the straight segment s0_i -> s1_i (all (n, 2))."""
    d = s1 - s0
    L2 = np.einsum("ij,ij->i", d, d)
    e = p - s0
    t = np.clip(np.einsum("ij,ij->i", e, d) / np.where(L2 > 1e-300, L2, 1.0), 0.0, 1.0)
    return np.hypot(*(e - t[:, None] * d).T)


#: ``also`` regions of at most this many edges are measured against every point in numpy
#: (:func:`_nearest_edges`) rather than through an STRtree, whose nearest query costs some
#: 3 us a point
ALSO_FEW = 64


def _nearest_edges(q: np.ndarray, a: np.ndarray, b: np.ndarray,
                   step: int = 4096) -> tuple[np.ndarray, np.ndarray]:
    """(index of the nearest edge, its distance) for each point of ``q`` among the straight
    edges a_i -> b_i (the first on a tie): the distance as GEOS computes it between a point and
    a two-point line (``Distance::pointToSegment``, operation for operation, so the same
    doubles as an STRtree's nearest query)."""
    dx, dz = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
    len2 = dx * dx + dz * dz
    same = (a[:, 0] == b[:, 0]) & (a[:, 1] == b[:, 1])
    root = np.sqrt(len2)
    k = np.empty(len(q), dtype=np.int64)
    d = np.empty(len(q))
    with np.errstate(all="ignore"):
        for i0 in range(0, len(q), step):
            pz, px = q[i0:i0 + step, 0, None], q[i0:i0 + step, 1, None]
            ez, ex = pz - a[:, 0], px - a[:, 1]
            r = (ez * dx + ex * dz) / len2
            s = ((a[:, 1] - px) * dx - (a[:, 0] - pz) * dz) / len2
            fz, fx = pz - b[:, 0], px - b[:, 1]
            D = np.where(same | (r <= 0.0), np.sqrt(ez * ez + ex * ex),
                         np.where(r >= 1.0, np.sqrt(fz * fz + fx * fx), np.abs(s) * root))
            w = D.argmin(axis=1)
            k[i0:i0 + step] = w
            d[i0:i0 + step] = D[np.arange(len(w)), w]
    return k, d


class _Depth:
    """Depth of points (z, x): the distance to the nearest of the model boundary's exact lines
    and arcs ``segs`` and of ``also``'s boundary edges; with, per point, that nearest piece
    (model segments first, then ``also``'s edges), for :meth:`bound`."""

    def __init__(self, segs: SegmentTable, also: BaseGeometry | None):
        self.segs = segs
        n = len(segs)
        # per piece: 0 a straight segment p0 -> p1, 1 an arc of at most half a turn (centre,
        # radius, start angle, sweep), 2 neither (no bound); a last row for the index -1
        # that :func:`distances` gives when there is no segment
        arc = np.r_[segs.is_arc, False]
        self.kind = np.where(arc, 2, 0).astype(np.int8)
        self.kind[-1] = 2
        half = np.r_[np.abs(segs.sweep) <= math.pi, False]
        self.kind[arc & half] = 1
        self.p0 = np.vstack([segs.start[:, ::-1], [(np.nan, np.nan)]])
        self.p1 = np.vstack([segs.end[:, ::-1], [(np.nan, np.nan)]])
        self.arc = np.vstack([np.column_stack([segs.center[:, 1], segs.center[:, 0], segs.radius,
                                               segs.a0, segs.sweep]), np.full((1, 5), np.nan)])
        self.tree = None
        self.few: tuple[np.ndarray, np.ndarray] | None = None
        if also is not None and not also.is_empty:
            a, b = _edges(also)
            if len(a):
                if len(a) <= ALSO_FEW:
                    self.few = (a, b)  # measured against every point (_nearest_edges)
                else:
                    self.tree = shapely.STRtree(shapely.linestrings(np.stack([a, b], axis=1)))
                k = len(a)
                self.kind = np.concatenate([self.kind[:n], np.zeros(k, np.int8), self.kind[n:]])
                self.p0 = np.concatenate([self.p0[:n], a, self.p0[n:]])
                self.p1 = np.concatenate([self.p1[:n], b, self.p1[n:]])
                self.arc = np.concatenate([self.arc[:n], np.full((k, 5), np.nan), self.arc[n:]])

    def __call__(self, pts: np.ndarray, use: np.ndarray | None = None
                 ) -> tuple[np.ndarray, np.ndarray]:
        """(depth, index of the nearest piece) per point; ``use``: per point whether ``also``'s
        edges count for it (default all)."""
        d, w = distances(pts, self.segs)
        if use is not None and (self.tree is not None or self.few is not None):
            sel = np.flatnonzero(use)
        else:
            sel = None
        if (self.tree is not None or self.few is not None) and len(pts) and (sel is None or len(sel)):
            w = np.where(w < 0, len(self.kind) - 1, w)
            q = pts if sel is None else pts[sel]
            if self.few is not None:
                k, da = _nearest_edges(q, *self.few)
                i = np.arange(len(q))
            else:
                (i, k), da = self.tree.query_nearest(shapely.points(q), return_distance=True,
                                                     all_matches=False)
            if sel is not None:
                i = sel[i]
            nearer = da < d[i]
            d[i[nearer]] = da[nearer]
            w[i[nearer]] = len(self.segs) + k[nearer]
        return d, w

    def bound(self, k: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """An upper bound of the distance to piece k_i over the straight edge a_i -> b_i
        (inf where none is known): for a straight piece the larger of the ends' distances (the
        distance to a convex set is convex along a line); for an arc of at most half a turn with
        both ends in its sector (a convex cone, so the whole edge is in it, where the distance
        is | |q - c| - r |), the largest of |a - c| - r, |b - c| - r and r - d(c, ab)."""
        ub = np.full(len(k), np.inf)
        kind = self.kind[k]
        li = np.flatnonzero(kind == 0)
        if len(li):
            s0, s1 = self.p0[k[li]], self.p1[k[li]]
            ub[li] = np.maximum(_point_seg_dist(a[li], s0, s1), _point_seg_dist(b[li], s0, s1))
        ar = np.flatnonzero(kind == 1)
        if len(ar):
            cz, cx, r, a0, sw = self.arc[k[ar]].T
            c = np.column_stack([cz, cx])
            aa, bb = a[ar], b[ar]

            def in_sector(p: np.ndarray) -> np.ndarray:
                ang = np.arctan2(p[:, 1] - cx, p[:, 0] - cz)
                return np.where(sw > 0, np.mod(ang - a0, 2 * math.pi) <= sw,
                                np.mod(a0 - ang, 2 * math.pi) <= -sw)
            ok = in_sector(aa) & in_sector(bb)
            v = np.maximum(np.maximum(np.hypot(*(aa - c).T), np.hypot(*(bb - c).T)) - r,
                           r - _point_seg_dist(c, aa, bb))
            ub[ar[ok]] = v[ok]
        return ub


def _depths(polys: Sequence[Polygon], segs: Sequence[Segment] | SegmentTable,
            interior: bool | Sequence[bool] = False, also: BaseGeometry | None = None,
            mode: str | Sequence[str] = "each", noise: float = NOISE,
            also_for: Sequence[bool] | None = None) -> list[Deviation | None]:
    """:func:`_deepest` of each polygon of ``polys`` (None for an empty one), all measured
    together.

    The points that count are those of :func:`_boundary_points` (each boundary edge cut into
    equal pieces of at most the step; with ``interior``, the grid of :func:`_grid_points`
    too), but a run of an edge's points is measured only where it could beat the deepest point
    found in its polygon. The depth f (the distance to the nearest of the model's segments and
    ``also``'s edges) is 1-Lipschitz, so over a run from a to b of length L,
    f <= (f(a) + f(b) + L) / 2; and f is at most the distance to any one piece, bounded over
    the run by :meth:`_Depth.bound` for the pieces nearest to a and to b. A run whose bound is
    no more than ``PRUNE_EPS`` above the deepest point found is skipped; a short one is
    measured whole, a long one measured at ``SPLIT - 1`` of its points and its ``SPLIT`` parts
    bounded again (``SPLIT_FEW`` and ``WHOLE_FEW`` in a round with few points to measure
    against a model of few pieces). So the maximum is that of every point to within ``PRUNE_EPS``, where it
    lies the first of the points measured (vertices in the boundary's order before inner
    points), and a long sliver along a line or an arc of the model costs its vertices.

    ``mode`` says which depths are wanted, so that fewer runs need measuring: ``each`` every
    polygon's; ``max`` only the deepest of all (the others may come out shallower);
    ``split`` whether each is deeper than ``noise`` and the deepest of those that are not
    (a polygon deeper comes out with some point beyond ``noise``, one not with a depth that is
    exact where it is the deepest of them); ``beyond`` the depth of each deeper than ``noise``
    (the others come out no deeper than ``noise``). ``interior`` and ``mode`` may be given per
    polygon (a ``max`` polygon then counts among those of its own mode only); ``also_for``:
    per polygon whether ``also`` counts as model for it (default every polygon)."""
    out: list[Deviation | None] = [None] * len(polys)
    if not polys:
        return out
    depth = _Depth(segs if isinstance(segs, SegmentTable) else SegmentTable(segs), also)
    parr = np.array(polys, dtype=object)
    rings, rp = shapely.get_rings(parr, return_index=True)
    v, ri = shapely.get_coordinates(rings, return_index=True)
    vp = rp[ri]  # polygon of each vertex
    e = np.flatnonzero(ri[:-1] == ri[1:])  # edge e: vertex e -> e + 1 in one ring
    a, b = v[e], v[e + 1]
    L = np.hypot(*(b - a).T)
    ep = vp[e]
    per = np.bincount(ep, weights=L, minlength=len(polys))
    step = np.maximum(SEGMENTIZE, per / MAX_POINTS)
    cnt = np.maximum(np.ceil(L / step[ep]).astype(np.int64) - 1, 0)  # inner points per edge
    pts, pp = [v], [vp]
    inside = np.broadcast_to(np.asarray(interior, dtype=bool), (len(polys),))
    if inside.any():  # (the grid is for polygons of 1e-4 mm^2 or more: see _grid_points)
        for k in np.flatnonzero(inside & (shapely.area(parr) >= 1e-4)).tolist():
            g = _grid_points(polys[k])
            pts.append(g)
            pp.append(np.full(len(g), k))
    pts, pp = np.concatenate(pts), np.concatenate(pp)
    use_of = None if also_for is None else np.asarray(also_for, dtype=bool)
    f, w = depth(pts, None if use_of is None else use_of[pp])
    lower = np.full(len(polys), -np.inf)
    np.maximum.at(lower, pp, f)
    # branch and bound over runs j0..j1 of an edge's sample points (point j of edge e at
    # a + j / n (b - a), n = cnt + 1 pieces; 0 and n its vertices)
    ie = np.flatnonzero(cnt > 0)
    j0, j1 = np.zeros(len(ie), np.int64), cnt[ie] + 1
    f0, f1, w0, w1 = f[e[ie]], f[e[ie] + 1], w[e[ie]], w[e[ie] + 1]
    n_of = cnt + 1

    def at(ee: np.ndarray, j: np.ndarray) -> np.ndarray:
        n = n_of[ee]
        q = a[ee] + (j / n)[:, None] * (b[ee] - a[ee])
        q[j == n] = b[ee[j == n]]
        return q

    more_p, more_f, more_pp = [], [], []

    def measure(ee: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        q = at(ee, j)
        fq, wq = depth(q, None if use_of is None else use_of[ep[ee]])
        more_p.append(q)
        more_f.append(fq)
        more_pp.append(ep[ee])
        np.maximum.at(lower, ep[ee], fq)
        return fq, wq

    modes = np.broadcast_to(np.asarray(mode, dtype=object), (len(polys),))
    groups = [(m, modes == m) for m in dict.fromkeys(modes.tolist()) if m != "each"]

    def need() -> np.ndarray:
        """Per polygon the depth a run must be able to exceed to be measured."""
        out = lower.copy()
        for m, g in groups:
            if m == "max":
                out[g] = lower[g].max()
            elif m == "split":
                shallow = g & (lower <= noise)
                top = lower[shallow].max() if shallow.any() else -np.inf
                out[g] = np.where(shallow[g], top, np.inf)
            elif m == "beyond":
                out[g] = np.maximum(lower[g], noise)
        return out

    cheap = len(depth.segs) <= FEW_SEGMENTS  # a point measured against few pieces
    while len(ie):
        t = need()[ep[ie]] + PRUNE_EPS
        ub = 0.5 * (f0 + f1 + L[ie] * (j1 - j0) / n_of[ie])
        go = ub > t
        ie, j0, j1, f0, f1, w0, w1, t = (x[go] for x in (ie, j0, j1, f0, f1, w0, w1, t))
        pa, pb = at(ie, j0), at(ie, j1)
        k2 = len(ie)
        both = depth.bound(np.concatenate([w0, w1]), np.concatenate([pa, pa]),
                           np.concatenate([pb, pb]))
        go = np.minimum(both[:k2], both[k2:]) > t
        ie, j0, j1, f0, f1, w0, w1 = (x[go] for x in (ie, j0, j1, f0, f1, w0, w1))
        if not len(ie):
            break
        m = j1 - j0
        split, small = SPLIT_FEW, m <= WHOLE_FEW
        if (not cheap or int((m[small] - 1).sum()) + (SPLIT_FEW - 1) * int((~small).sum())
                > ROUND_POINTS):
            split, small = SPLIT, m <= 2 * SPLIT
        # a short run: all its inner points; a long one: split - 1 points that cut it into
        # split runs, bounded again in the next round; measured together
        k = m[small] - 1
        se = np.repeat(ie[small], k)
        sj = np.repeat(j0[small], k) + np.arange(len(se)) - np.repeat(np.cumsum(k) - k, k) + 1
        ie, j0, j1, f0, f1, w0, w1 = (x[~small] for x in (ie, j0, j1, f0, f1, w0, w1))
        kj = j0[:, None] + (np.arange(split + 1)[None, :] * (j1 - j0)[:, None]) // split
        fi, wi = measure(np.concatenate([se, np.repeat(ie, split - 1)]),
                         np.concatenate([sj, kj[:, 1:-1].ravel()]))
        fi, wi = fi[len(se):], wi[len(se):]
        kf = np.column_stack([f0, fi.reshape(-1, split - 1), f1])
        kw = np.column_stack([w0, wi.reshape(-1, split - 1), w1])
        ie = np.repeat(ie, split)
        j0, j1 = kj[:, :-1].ravel(), kj[:, 1:].ravel()
        f0, f1 = kf[:, :-1].ravel(), kf[:, 1:].ravel()
        w0, w1 = kw[:, :-1].ravel(), kw[:, 1:].ravel()
        keep = j1 - j0 >= 2
        ie, j0, j1, f0, f1, w0, w1 = (x[keep] for x in (ie, j0, j1, f0, f1, w0, w1))
    if more_p:
        pts = np.concatenate([pts, *more_p])
        f = np.concatenate([f, *more_f])
        pp = np.concatenate([pp, *more_pp])
    # per polygon the deepest point, the first measured on a tie
    order = np.lexsort((-f, pp))
    first = np.flatnonzero(np.r_[True, pp[order][1:] != pp[order][:-1]])
    top = order[first]
    for k, (z, x), v in zip(pp[top].tolist(), pts[top].tolist(), f[top].tolist()):
        out[k] = Deviation(z=z, x=x, size_mm=v)
    return out


# --- reachability -------------------------------------------------------------------------

def _polys(g: BaseGeometry) -> list[Polygon]:
    """:func:`hnc_cam.sim.region.polygons` of ``g`` (the same polygons in the same order, the
    empty ones left out), taken apart in one vectorised call per level of nesting."""
    if g.is_empty:
        return []
    t = g.geom_type
    if t == "Polygon":
        return [g]
    parts = np.array([g], dtype=object)
    while True:
        t = shapely.get_type_id(parts)
        if not (t >= 4).any():  # no multi-part geometry or collection left
            break
        parts = shapely.get_parts(parts)
    keep = (t == 3) & ~shapely.is_empty(parts)
    return parts[keep].tolist()


def _edges(region: BaseGeometry) -> tuple[np.ndarray, np.ndarray]:
    """(starts, ends) of the boundary edges of a polygonal region, (n, 2) each."""
    ps = _polys(region)
    if not ps:
        return np.zeros((0, 2)), np.zeros((0, 2))
    c, ri = shapely.get_coordinates(shapely.get_rings(np.array(ps, dtype=object)),
                                    return_index=True)
    e = np.flatnonzero(ri[:-1] == ri[1:])
    return c[e], c[e + 1]


#: above this many edge-piece pairs :func:`_minkowski_parts` tests edges against the box of
#: ``near`` as a whole instead of its pieces' boxes
MINKOWSKI_BOXES = 200_000


def _minkowski_parts(region: BaseGeometry, outline: np.ndarray,
                     near: BaseGeometry | None = None) -> list[BaseGeometry]:
    """Pieces whose union is the Minkowski sum of a polygonal region with a convex polygon K
    (exact for the polygons): ``A + K = (A + k0) | (boundary(A) + K)`` for any k0 in K, the
    boundary term as the exact hull of each edge swept by K. With ``near``, only the pieces
    that meet ``near`` (their union equals the sum wherever it meets ``near``)."""
    parts = _polys(region)
    if not parts:
        return []
    a, b = _edges(region)
    if near is not None and len(a):
        # only the edges whose hull's box meets the box of a piece of ``near`` (the hull of
        # a -> b lies in the box of a and b grown by K's extent)
        boxes = shapely.bounds(np.array(_polys(near) or [near], dtype=object))
        if len(boxes) * len(a) > MINKOWSKI_BOXES:
            boxes = np.array([near.bounds])
        k0, k1 = outline.min(axis=0), outline.max(axis=0)
        lo, hi = np.minimum(a, b) + k0, np.maximum(a, b) + k1
        meet = ((lo[:, None, 0] <= boxes[None, :, 2]) & (hi[:, None, 0] >= boxes[None, :, 0])
                & (lo[:, None, 1] <= boxes[None, :, 3]) & (hi[:, None, 1] >= boxes[None, :, 1]))
        keep = meet.any(axis=1)
        a, b = a[keep], b[keep]
    hulls = sweep_hulls(outline, a, b)
    if near is not None and len(hulls):
        shapely.prepare(near)
        hulls = hulls[shapely.intersects(near, hulls)]
    k0 = outline.mean(axis=0)
    moved = shapely.transform(np.array(parts, dtype=object), lambda c: c + k0)
    return [*hulls, *moved]


def _blocked(obst: BaseGeometry, body: np.ndarray, u: tuple[float, float],
             near: BaseGeometry) -> np.ndarray:
    """Pieces whose union is, where it meets ``near`` (the placement window), the set
    ``obst - B`` of the placements P of the controlled point where the body B (:func:`tool_body`,
    the insert swept along the holder's direction u by more than twice the obstacles' extent)
    meets ``obst``: the exact hulls of ``obst``'s edges swept by -B, of the edges that do not
    face away from u only. A point p of ``obst`` has above it (along u, no farther than the
    obstacles' extent) a point q of such an edge, and p - B lies in q - B except where the
    far end of the holder is, far beyond the window; so neither the edges facing away from
    u nor the inside of ``obst`` add anything there."""
    ps = _polys(obst)
    if not ps:
        return np.zeros(0, dtype=object)
    hulls = sweep_hulls(-body, *_facing_edges(ps, u))
    shapely.prepare(near)
    return hulls[shapely.intersects(near, hulls)]


#: an envelope of more chains times breakpoints than this is left to GEOS (:func:`_hypograph`)
ENVELOPE_CELLS = 250_000
#: the regions under at most this many chains are united by GEOS (dearer than the envelope
#: beyond that, cheaper below)
ENVELOPE_MIN = 8
#: at most this many segments go into their sums with a set as they are, hidden ones too
#: (:func:`_profile`: finding those is dearer than summing them)
PROFILE_MIN = 12
#: a line rising less than this (mm) above the crossing of two others in an envelope is not
#: a piece of it (:func:`_envelope`)
ENVELOPE_EPS = 1e-10


def _upper_chain(pts: np.ndarray) -> np.ndarray:
    """The upper chain of the convex hull of the points (h, v): its vertices from the leftmost
    to the rightmost over the top, h strictly increasing (the topmost at an end of equal h),
    no three collinear."""
    up: list[np.ndarray] = []
    for q in np.unique(np.asarray(pts, dtype=float), axis=0):  # by h, then v
        while len(up) >= 2 and ((up[-1][0] - up[-2][0]) * (q[1] - up[-2][1])
                                - (up[-1][1] - up[-2][1]) * (q[0] - up[-2][0])) >= 0:
            up.pop()
        up.append(q)
    c = np.array(up)
    k = 0
    while k + 1 < len(c) and c[k + 1, 0] == c[0, 0]:
        k += 1
    return c[k:]


def _tops(a: np.ndarray, b: np.ndarray, chain: np.ndarray) -> np.ndarray:
    """The upper chains of the sums of the segments a_i b_i ((n, 2) each, (h, v)) with a convex
    set S whose upper chain is ``chain`` ((m + 1, 2), h increasing, slopes decreasing):
    (n, m + 2, 2), h non-decreasing along each. A segment's direction goes in among S's edges
    where its slope fits (the upper chain of a Minkowski sum runs its edges by decreasing
    slope); a vertical segment gives S's chain from its upper end (a vertex repeated)."""
    swap = a[:, 0] > b[:, 0]
    p = np.where(swap[:, None], b, a)
    q = np.where(swap[:, None], a, b)
    d = q - p
    vert = d[:, 0] <= 0.0
    top = np.where((p[:, 1] >= q[:, 1])[:, None], p, q)
    p = np.where(vert[:, None], top, p)
    q = np.where(vert[:, None], top, q)
    e = np.diff(chain, axis=0)  # e_h > 0
    # S's edges steeper than the segment come first: e_v / e_h > d_v / d_h
    j = (e[None, :, 1] * d[:, None, 0] > d[:, None, 1] * e[None, :, 0]).sum(axis=1)
    j[vert] = 0
    k = np.arange(len(chain) + 1)[None, :]
    first = k <= j[:, None]
    return chain[np.where(first, k, k - 1)] + np.where(first[:, :, None], p[:, None, :],
                                                         q[:, None, :])


def _envelope(ch: np.ndarray, floor: float) -> np.ndarray | None:
    """The graph of the pointwise maximum U of the functions whose graphs are the chains
    ``ch`` ((k, n, 2) of (h, v), h non-decreasing along each, continuous; a function is
    undefined outside its chain's h-range), as its vertices by increasing h: at every chain
    vertex's h U's limits from the left and from the right (a vertical step where they
    differ), and between two such h, where all the functions are straight, the crossings at
    which the maximum passes from one line to another (found line by line, each to
    ``ENVELOPE_EPS``); ``floor`` where no function is defined. None when the chains span no
    length in h."""
    H, V = ch[:, :, 0], ch[:, :, 1]
    lo, hi = H[:, 0], H[:, -1]
    bz = np.unique(H)
    if len(bz) < 2:
        return None
    if ch.shape[1] == 2:  # segments: each line at every breakpoint (used inside its range only)
        dh = H[:, 1] - H[:, 0]
        slope = (V[:, 1] - V[:, 0]) / np.where(dh > 0, dh, 1.0)
        E = V[:, :1] + (bz[None, :] - H[:, :1]) * slope[:, None]
        E = np.where(bz[None, :] >= H[:, 1:], V[:, 1:], E)
    else:
        E = np.empty((len(ch), len(bz)))
        for j in range(len(ch)):
            E[j] = np.interp(bz, H[j], V[j])
    right = (lo[:, None] <= bz) & (bz < hi[:, None])  # defined just right of bz_i
    left = (lo[:, None] < bz) & (bz <= hi[:, None])
    UR = np.where(right, E, -np.inf).max(axis=0)
    UL = np.where(left, E, -np.inf).max(axis=0)
    neg = -1e300
    # each line on interval i, from t = 0 (bz_i) to t = 1 (bz_i+1): A + t (B - A)
    A = np.where(right[:, :-1], E[:, :-1], neg)
    D = np.where(right[:, :-1], E[:, 1:], neg) - A
    ni = len(bz) - 1
    it = np.arange(ni)
    t0, t1 = np.zeros(ni), np.ones(ni)
    jl, jr = A.argmax(axis=0), (A + D).argmax(axis=0)
    ci, ct, cv = [it, it], [t0, t1], [UR[:-1], UL[1:]]
    for _ in range(len(ch) + 2):
        vl = A[jl, it] + t1 * D[jl, it]  # the left end's line at the right end
        vr = A[jr, it] + t1 * D[jr, it]
        go = (vl < vr - ENVELOPE_EPS) & np.isfinite(UR[:-1][it])
        it, t0, t1, jl, jr = it[go], t0[go], t1[go], jl[go], jr[go]
        if not len(it):
            break
        # where the two lines cross, and whether a third rises above them there
        den = D[jr, it] - D[jl, it]
        ts = np.clip((A[jl, it] - A[jr, it]) / np.where(den > 0, den, 1.0), t0, t1)
        ts = np.where(den > 0, ts, t1)
        y = A[jl, it] + ts * D[jl, it]
        vals = A[:, it] + ts * D[:, it]
        k = vals.argmax(axis=0)
        above = vals[k, np.arange(len(it))] > y + ENVELOPE_EPS
        ci.append(it[~above])
        ct.append(ts[~above])
        cv.append(y[~above])
        it, t0, t1, ts, jl, jr, k = (x[above] for x in (it, t0, t1, ts, jl, jr, k))
        it, t0, t1 = np.concatenate((it, it)), np.concatenate((t0, ts)), np.concatenate((ts, t1))
        jl, jr = np.concatenate((jl, k)), np.concatenate((k, jr))
    i, t, v = np.concatenate(ci), np.concatenate(ct), np.concatenate(cv)
    order = np.lexsort((t, i))
    i, t, v = i[order], t[order], v[order]
    h = np.where(t >= 1.0, bz[i + 1], bz[i] + t * (bz[i + 1] - bz[i]))
    return _simplified(np.column_stack([h, np.where(np.isfinite(v), v, floor)]))


def _simplified(c: np.ndarray) -> np.ndarray:
    """The polyline ``c`` without the vertices that repeat the one before or lie on the
    straight line through their neighbours going on in the same direction (to 1e-12 of the
    pieces' lengths: the breakpoints of functions hidden under others)."""
    if len(c) < 3 or not np.isfinite(c).all():
        return c
    d = np.diff(c, axis=0)
    c = c[np.concatenate(([True], (d[:, 0] != 0) | (d[:, 1] != 0)))]
    if len(c) < 3:
        return c
    d = np.diff(c, axis=0)
    d1, d2 = d[:-1], d[1:]
    cross = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]
    dot = d1[:, 0] * d2[:, 0] + d1[:, 1] * d2[:, 1]
    n = np.hypot(d[:, 0], d[:, 1])
    keep = np.ones(len(c), dtype=bool)
    keep[1:-1] = (np.abs(cross) > 1e-12 * n[:-1] * n[1:]) | (dot <= 0)
    return c[keep]


def _profile(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The pieces of the segments a_i b_i ((n, 2) each, (h, v)) that bound from above the
    region under them all (:func:`_envelope` of the segments), collinear neighbours joined:
    a point of a segment under another contributes to no sum with a set S above what that
    other's point does (the two sums differ by an upward shift), and a vertical segment
    nothing beyond its upper end, which ends a piece that is not vertical. The segments as
    they are when there are too many for the envelope."""
    sl = a[:, 0] != b[:, 0]
    k = int(sl.sum())
    if k <= PROFILE_MIN or 2 * k * k > ENVELOPE_CELLS:
        return a, b
    a, b = a[sl], b[sl]
    swap = a[:, 0] > b[:, 0]
    ch = np.stack([np.where(swap[:, None], b, a), np.where(swap[:, None], a, b)], axis=1)
    top = _envelope(ch, -np.inf)
    if top is None:
        return a[:0], b[:0]
    p, q = top[:-1], top[1:]
    ok = np.isfinite(p[:, 1]) & np.isfinite(q[:, 1]) & (q[:, 0] > p[:, 0])
    p, q = p[ok], q[ok]
    d = q - p
    # a piece that goes on from where the one before ends, in the same direction
    cross = d[1:, 0] * d[:-1, 1] - d[1:, 1] * d[:-1, 0]
    joins = np.r_[False, (p[1:] == q[:-1]).all(axis=1)
                  & (np.abs(cross) <= 1e-12 * np.hypot(*d[1:].T) * np.hypot(*d[:-1].T))]
    run = np.cumsum(~joins) - 1
    last = np.r_[np.flatnonzero(~joins)[1:] - 1, len(p) - 1]
    return p[~joins], q[last[: run[-1] + 1]] if len(p) else q
def _hypograph(a: np.ndarray, b: np.ndarray, chain: np.ndarray, lo: np.ndarray,
               hi: np.ndarray) -> BaseGeometry | None:
    """Where it meets the boxes lo_i..hi_i ((n, 2) corners (h, v)), the set of the points
    (h, v) below some point of the sum of the segments a_i b_i with the convex set S whose
    upper chain is ``chain``: the region under the maximum of the sums' upper chains
    (:func:`_tops`, :func:`_envelope`) of the segments whose sums reach over a box and not
    wholly below it, or with very few or very many such segments the union of those chains'
    regions down to below the boxes; in frame coordinates (v up). None when it is empty
    there."""
    c0, c1 = float(chain[0, 0]), float(chain[-1, 0])
    top = np.maximum(a[:, 1], b[:, 1]) + float(chain[:, 1].max())
    keep = ((np.minimum(a[:, 0], b[:, 0])[:, None] + c0 <= hi[None, :, 0])
            & (np.maximum(a[:, 0], b[:, 0])[:, None] + c1 >= lo[None, :, 0])
            & (top[:, None] >= lo[None, :, 1])).any(axis=1)
    if not keep.any():
        return None
    v0 = float(lo[:, 1].min())
    a, b = _profile(a[keep], b[keep])
    if not len(a):
        return None
    tops = _tops(a, b, chain)
    floor = min(v0, float(tops[:, :, 1].min())) - 1.0
    n_h = tops.shape[0] * tops.shape[1]
    if tops.shape[0] * n_h > ENVELOPE_CELLS or len(tops) <= ENVELOPE_MIN:
        # each chain's region down to below the boxes, its bottom as far below its own lowest
        # point as the lowest chain's is below the floor (bottoms at one height would be
        # collinear edges, dear to the overlay)
        low = tops[:, :, 1].min(axis=1)
        bottom = low - (float(low.max()) - floor + 1.0)
        ends = np.stack([np.column_stack([tops[:, -1, 0], bottom]),
                         np.column_stack([tops[:, 0, 0], bottom])], axis=1)
        rings = np.concatenate([tops, ends, tops[:, :1]], axis=1)
        return clean(shapely.union_all(shapely.polygons(rings)))
    top = _envelope(tops, floor)
    if top is None:
        return None
    ring = np.vstack([top, [(top[-1, 0], floor - 1.0), (top[0, 0], floor - 1.0)]])
    return Polygon(ring)


#: the upper chains :func:`_blocked_region` sums obstacles' edges with, by outline, tip code,
#: head and holder direction (a few dozen at most)
_CHAINS: dict[tuple, np.ndarray] = {}


def _frame(u: tuple[float, float]) -> bool:
    """Whether the frame in which the holder's direction ``u`` is up swaps Z and X."""
    return u == (1.0, 0.0)


def _blocked_region(edges: tuple[np.ndarray, np.ndarray], s: ToolShape, lo: np.ndarray,
                    hi: np.ndarray) -> BaseGeometry | None:
    """Where it meets the window, the boxes lo_i..hi_i ((n, 2) corners (z, x)), the set of the placements P of the controlled point at which
    the tool's body B (:func:`tool_body`: its section K' swept along the holder's direction u
    past the part) meets the obstacles whose edges facing u are ``edges`` (in the frame of
    :func:`_frame`, u up): P + B meets them exactly where P lies below (along u) a point of
    their sum with -K', and that sum's upper boundary is the sum of those edges' with -K'
    (:func:`_blocked`): a region under one function of the coordinate across u, its
    envelope (:func:`_hypograph`), exact to ``ENVELOPE_EPS``. None when nothing is blocked
    there."""
    u = holder_direction(s.tip)
    swap = _frame(u)
    key = (s.outline.tobytes(), s.outline.shape, s.tip, s.head)
    chain = _CHAINS.get(key)
    if chain is None:
        if len(_CHAINS) >= 64:
            _CHAINS.clear()
        sec = -_section(s)
        chain = _upper_chain(sec[:, ::-1] if swap else sec)
        chain.setflags(write=False)
        _CHAINS[key] = chain
    g = _hypograph(*edges, chain, lo[:, ::-1] if swap else lo, hi[:, ::-1] if swap else hi)
    if g is None or not swap:
        return g
    return shapely.transform(g, lambda c: c[:, ::-1])


def _facing(pieces: Sequence[BaseGeometry], u: tuple[float, float]
            ) -> tuple[np.ndarray, np.ndarray]:
    """The edges (starts, ends) of the polygons of ``pieces`` that do not face away from the
    holder's direction ``u`` (as :func:`_blocked` takes them), in the frame of :func:`_frame`."""
    ps = [p for g in pieces for p in _polys(g)]
    if not ps:
        return np.zeros((0, 2)), np.zeros((0, 2))
    a, b = _facing_edges(ps, u)
    return (a[:, ::-1], b[:, ::-1]) if _frame(u) else (a, b)


def _facing_edges(ps: Sequence[Polygon], u: tuple[float, float]
                  ) -> tuple[np.ndarray, np.ndarray]:
    """The edges (starts, ends; (z, x)) of the polygons ``ps`` that do not face away from the
    holder's direction ``u``."""
    # exteriors counter-clockwise, holes clockwise: the inside on the left of every edge, the
    # outward normal of an edge a -> b is (d_x, -d_z) for d = b - a in (z, x)
    oriented = shapely.orient_polygons(np.array(ps, dtype=object), exterior_cw=False)
    c, ri = shapely.get_coordinates(shapely.get_rings(oriented), return_index=True)
    e = np.flatnonzero(ri[:-1] == ri[1:])
    a, b = c[e], c[e + 1]
    d = b - a
    up = d[:, 1] * u[0] - d[:, 0] * u[1] >= -1e-12 * (np.abs(d[:, 0]) + np.abs(d[:, 1]))
    return a[up], b[up]


def holder_direction(tip: int) -> tuple[float, float]:
    """Unit (z, x) direction in which a tool's holder runs from its insert, by the tip code: a
    tool whose tip points away from the axis (codes 1, 2, 6: boring bars, inside grooving and
    threading tools) or straight at the chuck (7) is held on a bar along the spindle axis
    that enters from the right (+Z); every other tool (outside turning, grooving and threading,
    codes 0, 3, 4, 5, 8, 9) on a shank that runs radially outward (+X)."""
    sx, sz = tip_direction(tip if tip in range(10) else 3)
    return (1.0, 0.0) if sx > 0 or (sx == 0 and sz < 0) else (0.0, 1.0)


def _section(shape: ToolShape) -> np.ndarray:
    """The points whose convex hull K' is the body's section across the holder's direction:
    the insert's outline, and for an inside tool with a known ``head`` the outline moved that
    deep across X (:func:`tool_body` is K' swept along :func:`holder_direction`)."""
    out = shape.outline
    if shape.head > 0 and holder_direction(shape.tip) == (1.0, 0.0):
        sx, _sz = tip_direction(shape.tip)
        back = -shape.head if sx > 0 else shape.head
        out = np.vstack([out, np.column_stack([out[:, 0], np.full(len(out), back)])])
    return out


def tool_body(shape: ToolShape, length: float) -> np.ndarray:
    """The convex outline (ccw, relative to the controlled point) of the insert together with
    its holder: the insert swept ``length`` mm along :func:`holder_direction`, a body as wide as
    the insert across that direction (a real shank is at least that wide). For a boring bar
    that makes the bar as tall as the insert: an inside tool reaches nothing behind a mouth
    narrower than where its tip is (a recess or a chamfer facing the chuck inside the bore),
    as the planner assumes when it leaves such a feature to the second setup. An inside
    tool whose ``head`` is known (its ``min_bore``) has a body that deep across X from its
    controlled point toward the axis and beyond: in a narrow bore the head's back meets the
    far wall before the tip reaches the centre, so a flat bottom near the axis is out of its
    reach."""
    dz, dx = holder_direction(shape.tip)
    out = _section(shape)
    pts = np.vstack([out, out + np.array([dz * length, dx * length])])
    hull = shapely.convex_hull(shapely.multipoints(pts))
    c = shapely.get_coordinates(shapely.normalize(hull).exterior)[:-1]
    z, x = c[:, 0], c[:, 1]
    return c if float(np.sum(z * np.roll(x, -1) - np.roll(z, -1) * x)) >= 0 else c[::-1].copy()


#: the bodies :func:`_body` built, by outline, tip code, head and length (a few dozen at most)
_BODIES: dict[tuple, np.ndarray] = {}


def _body(s: ToolShape, length: float) -> np.ndarray:
    """:func:`tool_body` of ``s``, at least ``length`` long: the length rounded up to a power of
    two (a holder longer than it must be reaches past the part all the same), so that a tool
    is built once for the parts of a family, not once per part."""
    L = 2.0 ** math.ceil(math.log2(max(length, 1.0)))
    key = (s.outline.tobytes(), s.outline.shape, s.tip, s.head, L)
    b = _BODIES.get(key)
    if b is None:
        if len(_BODIES) >= 64:
            _BODIES.clear()
        b = tool_body(s, L)
        b.setflags(write=False)
        _BODIES[key] = b
    return b


def _boxes(lo: np.ndarray, hi: np.ndarray) -> BaseGeometry:
    """The union of the boxes lo_i..hi_i ((n, 2) corners (z, x)); one box as it is."""
    boxes = shapely.box(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1])
    return boxes[0] if len(boxes) == 1 else clean(shapely.union_all(boxes))


#: the covering pieces are cut to the leftover's box grown by this (mm) before their union
CLIP_MARGIN = 0.01


def reachable(model_poly: BaseGeometry, shapes: Sequence[ToolShape], where: BaseGeometry,
              keep: BaseGeometry | None = None) -> BaseGeometry:
    """The part of ``where`` that some tool's insert K can cover while the insert and its
    holder B (:func:`tool_body`, reaching past the part) stay out of the model (and its mirror
    image below the axis) and ``keep`` (the chucking allowance beyond the part's left end).
    The holder fixes where a tool comes from: an outside tool from outside the part, radially,
    a boring bar from the right along the bore; neither through the part.

    Computed locally: a point q is covered by a placement P of the controlled point with q in
    P + K, so P lies in q - K: the placements are looked for, tool by tool, in the boxes of the
    components of the leftover no tool before covered, less the insert's extent. The
    placements the body cannot take there lie under one function of the coordinate across
    the holder (:func:`_blocked_region`, from the obstacles' edges that face the holder); of
    the place's edges swept by K only those that meet the leftover still unclassified are
    united.
    """
    comps = _polys(where)
    if not comps or not shapes:
        return Polygon()
    mirror = shapely.affinity.scale(model_poly, xfact=1.0, yfact=-1.0, origin=(0, 0))
    solids = [model_poly, mirror]
    if keep is not None and not keep.is_empty:
        solids += [keep, shapely.affinity.scale(keep, xfact=1.0, yfact=-1.0, origin=(0, 0))]
    facing: dict[tuple[float, float], tuple[np.ndarray, np.ndarray]] = {}
    left = clean(where)
    for s in shapes:
        if left.is_empty:
            break
        # the placements P with P + K meeting the leftover not yet covered lie in the boxes
        # of its components less K's extent (a millimetre more all round)
        bounds = shapely.bounds(np.array(_polys(left), dtype=object))
        k0, k1 = s.outline.min(axis=0), s.outline.max(axis=0)
        lo, hi = bounds[:, :2] - k1 - 1.0, bounds[:, 2:] - k0 + 1.0
        window = _boxes(lo, hi)
        # placements P of the controlled point with P + B inside the free space
        u = holder_direction(s.tip)
        if u not in facing:
            facing[u] = _facing(solids, u)
        blocked = _blocked_region(facing[u], s, lo, hi)
        place = diff(window, blocked) if blocked is not None else window
        if place.is_empty:
            continue
        covered = _minkowski_parts(place, s.outline, near=left)
        if covered:
            # only what covers the leftover counts: the pieces cut to its box (a margin
            # beyond it, so the cuts stay clear of its boundary) before they are united,
            # where that leaves them less than half their vertices (the cuts' shared
            # straight edges cost the union more than it saves otherwise)
            z0, x0, z1, x1 = left.bounds
            m = CLIP_MARGIN
            pieces = np.array(covered, dtype=object)
            cut = shapely.clip_by_rect(pieces, z0 - m, x0 - m, z1 + m, x1 + m)
            if 2 * shapely.get_num_coordinates(cut).sum() < shapely.get_num_coordinates(pieces).sum():
                pieces = cut
            left = diff(left, shapely.union_all(pieces))
    return diff(where, left)


# --- threads ------------------------------------------------------------------------------

@dataclass
class _Zone:
    z0: float
    z1: float
    r_root: float  # radius of the thread root (ext: minor, int: major)
    r_crest: float  # radius of the crest (ext: major, int: minor)
    internal: bool
    pitch: float
    target: float  # target diameter
    declared: bool
    m0: float = 0.0  # Z range where the root is measured (the thread on the part)
    m1: float = 0.0
    thread: Thread | None = None  # the declared thread (a taper thread's target follows it)
    e0: float = 0.0  # what is not measured at the m0/m1 end: a pitch, or the run-out a wall
    e1: float = 0.0  # there forces (:data:`WALL_RUNOUT` pitches)

    def target_at(self, z: float) -> float:
        """The root diameter the thread must reach at ``z``: ``target`` on a straight thread,
        the taper line less twice the thread's depth on a taper thread."""
        t = self.thread
        if t is None or not t.taper:
            return self.target
        return t.major_at(z) - 2 * t.depth


#: pitches of incomplete thread not measured at a declared thread's end where the part has a
#: wall right beyond it (a shoulder outside, a bottom or step inside): the thread no tool can
#: finish before the wall. DIN 76-1's normal run-out x1 is about 2.5 P; a FANUC G76's run-out,
#: whole tenths of a lead, ends the full form up to 2.6 P before the wall
WALL_RUNOUT = 3.0


def _walled(model_poly: BaseGeometry, t: Thread, z: float, out: float) -> bool:
    """Whether the part stands in the thread's run-out just beyond its end ``z`` (``out``: the
    direction away from the thread, +1 or -1): outside, material above the minor diameter;
    inside, material below the major diameter."""
    zz = z + out * 0.05
    col = model_poly.intersection(shapely.LineString([(zz, 0.0), (zz, BIG)]))
    if col.is_empty:
        return False
    if t.internal:
        return any(g.bounds[1] < t.diameter / 2 - 0.01 for g in getattr(col, "geoms", [col]))
    return col.bounds[3] > t.minor_diameter / 2 + 0.01


def _zones(model: TurnedProfile, machined: Machined, threads: Sequence[Thread] | None,
           model_poly: BaseGeometry | None = None) -> list[_Zone]:
    """The thread zones (declared, else the program's thread moves); ``model_poly``: the
    model's :func:`profile_polygon` if known (built here otherwise, at most once)."""
    declared = list(threads if threads is not None else model.threads)
    zones: list[_Zone] = []
    mp = model_poly
    if mp is None and (declared or machined.thread_spans):
        mp = profile_polygon(model)
    for t in declared:
        z0, z1 = sorted((t.z_start, t.z_end))
        m0, m1 = z0, z1
        e0 = (WALL_RUNOUT if _walled(mp, t, z0, -1.0) else 1.0) * t.pitch
        e1 = (WALL_RUNOUT if _walled(mp, t, z1, 1.0) else 1.0) * t.pitch
        for s in machined.thread_spans:  # include the program's run-in/run-out
            if s.z_max >= z0 - 1e-6 and s.z_min <= z1 + 1e-6 and s.inside == t.internal:
                z0, z1 = min(z0, s.z_min), max(z1, s.z_max)
        if t.internal:
            zones.append(_Zone(z0, z1, t.diameter / 2, t.minor_diameter / 2, True, t.pitch,
                               t.diameter, True, m0, m1, t, e0, e1))
        else:
            zones.append(_Zone(z0, z1, t.minor_diameter / 2, t.diameter / 2, False, t.pitch,
                               t.minor_diameter, True, m0, m1, t, e0, e1))
    for s in machined.thread_spans:
        if any(z.z1 >= s.z_min - 1e-6 and z.z0 <= s.z_max + 1e-6 for z in zones):
            continue
        pitch = s.lead or 1.0
        m0, m1 = max(s.z_min, model.z_min), min(s.z_max, model.z_max)
        if m1 <= m0:
            continue
        mid = box(m0, 0.0, m1, BIG)
        span = mp.intersection(mid)
        if span.is_empty:
            continue
        if s.inside:
            r_nom = _bore_radius(span)
            d = 2 * r_nom + 1.0825 * pitch  # minor diameter given, major = D1 + 1.0825 P
            zones.append(_Zone(s.z_min, s.z_max, d / 2, r_nom, True, pitch, d, False, m0, m1))
        else:
            r_nom = span.bounds[3]
            d3 = 2 * r_nom - 1.2269 * pitch
            zones.append(_Zone(s.z_min, s.z_max, d3 / 2, r_nom, False, pitch, d3, False, m0, m1))
    return zones


def _bore_radius(g: BaseGeometry) -> float:
    zs = np.linspace(g.bounds[0], g.bounds[2], 7)[1:-1]
    lo = []
    for z in zs:
        seg = g.intersection(shapely.LineString([(z, 0), (z, BIG)]))
        if not seg.is_empty:
            lo.append(seg.bounds[1])
    return min(lo) if lo else 0.0


def _achieved(material: BaseGeometry, zone: _Zone) -> float | None:
    a, b = zone.m0 + (zone.e0 or zone.pitch), zone.m1 - (zone.e1 or zone.pitch)
    if b <= a:
        a, b = zone.m0, zone.m1
    zs = np.linspace(a, b, max(50, int((b - a) / max(zone.pitch, 0.1) * 40)))
    lines = shapely.linestrings([[(z, 0.0), (z, BIG)] for z in zs])
    cut = shapely.intersection(lines, material)
    vals = []
    for z, c in zip(zs, cut):
        if c.is_empty:
            if not zone.internal:
                vals.append(0.0)
            continue
        if zone.internal:
            # lowest material above the thread's crest region
            pieces = [g for g in getattr(c, "geoms", [c]) if g.bounds[3] > zone.r_crest - 1e-6]
            if pieces:
                vals.append(min(g.bounds[1] for g in pieces))
        else:
            pieces = [g for g in getattr(c, "geoms", [c]) if g.bounds[1] < zone.r_crest + 1e-6]
            vals.append(max(g.bounds[3] for g in pieces) if pieces else 0.0)
    if not vals:
        return None
    if zone.thread is not None and zone.thread.taper and not zone.internal:
        # a taper thread: the root measured against the taper at each Z; the reading is the
        # small end's target plus the deviation farthest from the taper anywhere
        devs = [2 * v - zone.target_at(z) for z, v in zip(zs, vals)]
        return zone.target + max(devs, key=abs)
    # the worst place: full form is needed along the whole thread, not at one Z of it
    return 2 * (min(vals) if zone.internal else max(vals))


# --- verify -------------------------------------------------------------------------------

#: candidate moves whose swept regions :func:`blame` builds together
BLAME_BLOCK = 32


def blame(machined: Machined, at: Deviation, removed: bool) -> None:
    """Fill ``at.line``/``at.block``: for removed material (overcut) the first move whose swept
    region holds the point, else the feed move whose swept region comes nearest to it."""
    from .simulate import _Sweeper
    if machined.machine is None:
        return
    sweeper = _Sweeper(machined.machine, machined.toolpath.moves,
                       machined.thread_regs if machined.per_move is not None else None)
    p = shapely.Point(at.z, at.x)
    moves = machined.toolpath.moves
    bb = machined.sweep_bounds
    if len(bb) != len(moves):
        return
    # distance from the point to each move's box (inf for dwells): one array of the moves'
    # length at a time, no per-move Python objects
    gap = np.maximum(bb[:, 0] - at.z, at.z - bb[:, 2])
    np.maximum(gap, bb[:, 1] - at.x, out=gap)
    np.maximum(gap, at.x - bb[:, 3], out=gap)
    np.maximum(gap, 0.0, out=gap)
    gap[np.isnan(gap)] = np.inf
    if removed:
        cand = np.flatnonzero((gap <= 1e-6) & (machined.removed_area > 0))
    else:
        cand = np.argsort(gap, kind="stable")  # line and arc moves among them, nearest first
    best, best_d = None, math.inf
    got: dict[int, BaseGeometry | None] = {}  # sweeps built BLAME_BLOCK candidates at a time
    for j, i in enumerate(cand):  # (not as a list: the loop ends early, the array can be long)
        if not removed and gap[i] > best_d:
            break  # sorted by box gap: no later move can come nearer
        m = moves[i]
        if not removed and m.kind not in ("line", "arc"):
            continue
        if int(i) not in got:
            block = [int(k) for k in cand[j:j + BLAME_BLOCK]]
            got = dict(zip(block, sweeper.sweeps([moves[k] for k in block])[0]))
        g = got[int(i)]
        if g is None:
            continue
        d = g.distance(p)
        if removed:
            if d <= 1e-6:
                best = m
                break
        elif d < best_d:
            best, best_d = m, d
    if best is not None:
        at.line = best.line
        at.block = machined.toolpath.block(best.line)


def _with_tails(region: BaseGeometry, reach: BaseGeometry, unreach: BaseGeometry,
                tol: float) -> tuple[BaseGeometry, BaseGeometry]:
    """Move the tails of the unreachable leftover to it: in each connected piece of leftover
    that holds some unreachable leftover, the reachable part within ``tol`` of it. Returns the
    new (reachable, unreachable)."""
    if unreach.is_empty or reach.is_empty:
        return reach, unreach
    tails = []
    for p in _polys(region):
        u = inter(p, unreach)
        if u.is_empty:
            continue
        t = inter(inter(p, reach), u.buffer(tol, quad_segs=8))
        if not t.is_empty:
            tails.append(t)
    if not tails:
        return reach, unreach
    tail = clean(shapely.union_all(tails))
    return diff(reach, tail), clean(shapely.union_all([unreach, tail]))


#: tool kinds that reach leftover only where they went: parting and grooving blades cut
#: where the program sends them (a groove, the part-off line), and drills along the spindle
#: axis only (their point is not a turning tool's), not along the whole contour, so a
#: finishing nose's fillet in a sharp inside corner elsewhere is not theirs to clean
BLADE_KINDS = frozenset({"part", "groove", "groove_id", "groove_face", "drill", "center_drill"})


def _is_blade(m: Machined, reg: int) -> bool:
    """Whether register ``reg`` is a blade (:data:`BLADE_KINDS` in the tool library)."""
    return m.machine is not None and m.machine.register(reg).kind in BLADE_KINDS


def _blade_reach(m: Machined) -> tuple[list[ToolShape], BaseGeometry]:
    """The blades' outlines and where they went (the union of their moves' swept
    boxes): a blade reaches leftover there only."""
    from .simulate import CHUNK
    n = len(m.toolpath.moves)
    regs: set[int] = set()
    boxes = []
    for c0 in range(0, n, CHUNK):
        c = m.move_columns(c0, min(c0 + CHUNK, n))
        reg = c["register"]
        blades = [r for r in np.unique(reg).tolist() if _is_blade(m, r)]
        regs.update(blades)
        for k in np.flatnonzero(np.isin(reg, blades)).tolist():
            b = m.sweep_bounds[c0 + k]
            if np.isfinite(b).all():
                boxes.append(box(*b))
    shapes = [s for (r, t), s in m.shapes.items() if r in regs and t is None]
    return shapes, (union_of(boxes) if boxes else Polygon())


def _cutting_shapes(m: Machined) -> list[ToolShape]:
    """The outlines of the tools whose line and arc moves cut (blades left out: see
    :func:`_blade_reach`)."""
    from ..nc.toolpath import MOVE_KINDS
    from .simulate import CHUNK
    keys = []
    n = len(m.toolpath.moves)
    for c0 in range(0, n, CHUNK):  # registers of the line and arc moves that cut
        c = m.move_columns(c0, min(c0 + CHUNK, n))
        cut = (((c["kind"] == MOVE_KINDS.index("line")) | (c["kind"] == MOVE_KINDS.index("arc")))
               & (m.removed_area[c0:c0 + len(c["kind"])] > 0))
        for r in dict.fromkeys(c["register"][cut].tolist()):
            if (r, None) not in keys and not _is_blade(m, r):
                keys.append((r, None))
    shapes = []
    for k in keys:
        if k not in m.shapes:
            continue
        s = m.shapes[k]
        head = m.machine.register(k[0]).min_bore if m.machine is not None else 0.0
        if head > 0 and holder_direction(s.tip) == (1.0, 0.0):  # a bar's head: see tool_body
            s = dataclasses.replace(s, head=head + BAR_CLEARANCE)
        shapes.append(s)
    if not shapes and m.machine is not None:
        shapes = [tool_shape(m.machine.register(0))]
    return shapes


def _size(g: BaseGeometry) -> str:
    """Diameter(s), length and Z range of a region, as the message of a stock that is too
    small names them."""
    z0, x0, z1, x1 = g.bounds
    bore = f" bore {2 * x0:.3f}" if x0 > 1e-6 else ""
    return f"diameter {2 * x1:.3f}{bore}, {z1 - z0:.3f} long, Z {z0:.3f}..{z1:.3f}"


def _of(ps: Sequence[Polygon]) -> BaseGeometry:
    """One geometry of the polygons ``ps`` (pieces of one valid overlay)."""
    if len(ps) == 1:
        return ps[0]
    return shapely.multipolygons(np.array(ps, dtype=object)) if len(ps) else Polygon()


def _over_under(model_poly: BaseGeometry, material: BaseGeometry, z_min: float
                ) -> tuple[BaseGeometry, BaseGeometry]:
    """(model minus material, material from ``z_min`` on minus model) from one overlay: the
    pieces of their symmetric difference, each the first when a point inside it lies in the
    model, else cut at ``z_min``."""
    ps = np.array(_polys(clean(shapely.symmetric_difference(model_poly, material))),
                  dtype=object)
    if not len(ps):
        return Polygon(), Polygon()
    q = shapely.get_coordinates(shapely.point_on_surface(ps))
    inside = shapely.contains_xy(model_poly, q[:, 0], q[:, 1])
    under = ps[~inside]
    beyond = shapely.bounds(under)[:, 0] < z_min
    if beyond.any():
        cut = shapely.clip_by_rect(under[beyond], z_min, -1.0, BIG, BIG)
        under = [*under[~beyond], *(p for g in cut for p in _polys(g))]
    return _of(ps[inside].tolist()), _of(list(under))


def check_stock_fits(stock: BaseGeometry, model_poly: BaseGeometry) -> None:
    """Refuse (``StockError``, bad input) a stock that does not hold the model: some of the
    model lies more than ``NOISE`` outside the raw material, so no program could make it."""
    from ..errors import StockError
    out = diff(model_poly, stock)
    if out.is_empty or out.area <= 1e-9:
        return
    pts = _boundary_points(out)
    depth = float(shapely.distance(shapely.points(pts), stock).max()) if len(pts) else 0.0
    if depth > NOISE:
        raise StockError(f"the stock ({_size(stock)}) is smaller than the model "
                         f"({_size(model_poly)}): the model stands up to {depth:.3f} mm "
                         f"out of it")


def separated_part(machined: Machined, model_poly: BaseGeometry) -> BaseGeometry | None:
    """The piece parted off from the bar: the fallen piece holding the most of the model, when
    it holds more of it than the material left in the chuck; else None (the part is still on
    the bar)."""
    if not machined.fallen:
        return None
    best, most = None, inter(machined.material, model_poly).area
    for p in machined.fallen:
        a = inter(p, model_poly).area
        if a > most:
            best, most = p, a
    return best


def verify(machined: Machined, model: TurnedProfile, tol: float = 0.01,
           threads: Sequence[Thread] | None = None, strict: bool = False) -> Report:
    """Compare ``machined`` with ``model`` (see the module doc); ``threads`` overrides the
    model's declared threads; ``strict`` counts unreachable leftover as a failure. A stock that
    does not hold the model is bad input (:func:`check_stock_fits`)."""
    if not tol > 0:
        raise ValueError("tolerance must be positive")
    model_poly = profile_polygon(model)
    check_stock_fits(machined.stock, model_poly)
    part = separated_part(machined, model_poly)
    if part is not None:
        from dataclasses import replace
        machined = replace(machined, material=part)
    segs = model_segments(model)
    table = SegmentTable(segs)
    material = machined.material
    zones = _zones(model, machined, threads, model_poly)
    # the zone, widened by half a pitch at each end for the insert's flanks at the run-out
    excl = shapely.union_all([box(z.z0 - 0.5 * z.pitch, min(z.r_root, z.r_crest) - max(0.5 * z.pitch, 0.5),
                                  z.z1 + 0.5 * z.pitch, max(z.r_root, z.r_crest)) for z in zones]) if zones else Polygon()
    over, under = _over_under(model_poly, material, model.z_min)
    if zones:
        over, under = diff(over, excl), diff(under, excl)

    # overcut: the deepest place of all its pieces; undercut: per piece its depth, measured
    # together
    o_parts, parts = _polys(over), _polys(under)
    got = _depths(o_parts + parts, table, interior=[True] * len(o_parts) + [False] * len(parts),
                  mode=["max"] * len(o_parts) + ["split"] * len(parts))
    over_at = None
    for d in got[:len(o_parts)]:
        if d is not None and (over_at is None or d.size_mm > over_at.size_mm):
            over_at = d
    max_over = over_at.size_mm if over_at else 0.0

    # undercut: per component its depth; the components deeper than NOISE are classified into
    # what the tools can reach and what they cannot
    unreach_list: list[Deviation] = []
    unreach_region: BaseGeometry = Polygon()
    under_at: Deviation | None = None
    deep = []
    for p, d in zip(parts, got[len(o_parts):]):
        if d is None:
            continue
        if d.size_mm > NOISE:
            deep.append(p)
        elif under_at is None or d.size_mm > under_at.size_mm:
            under_at = d  # too shallow to classify: counted as reachable
    if deep:
        region = deep[0] if len(deep) == 1 else clean(shapely.union_all(deep))
        chuck_side = clean(machined.stock.intersection(box(-BIG, -1.0, model.z_min, BIG)))
        reach_part = reachable(model_poly, _cutting_shapes(machined), region, chuck_side)
        blades, zone = _blade_reach(machined)
        if blades:  # a blade reaches where it went, not along the whole part
            near = inter(region, zone)
            if not near.is_empty:
                reach_part = union_of([reach_part, inter(
                    reachable(model_poly, blades, near, chuck_side), zone)])
        unreach_region = diff(region, reach_part)
        reach_part, unreach_region = _with_tails(region, reach_part, unreach_region, tol)
        # reachable leftover: its depth beyond what the tools could at best leave (the model,
        # and the unreachable leftover next to it), so a sliver the pass left on top of an
        # unreachable corner counts by its own thickness, not by the corner's depth
        # (measured together with the unreachable pieces, for which only the model counts)
        r_parts, u_parts = _polys(reach_part), _polys(unreach_region)
        got = _depths(r_parts + u_parts, table, also=unreach_region,
                      mode=["max"] * len(r_parts) + ["beyond"] * len(u_parts),
                      also_for=[True] * len(r_parts) + [False] * len(u_parts))
        for d in got[:len(r_parts)]:  # the deepest reachable point, the first on a tie
            if d is not None and (under_at is None or d.size_mm > under_at.size_mm):
                under_at = d
        for d in got[len(r_parts):]:
            if d is not None and d.size_mm > NOISE:
                unreach_list.append(d)
        unreach_list.sort(key=lambda d: -d.z)
    max_under = under_at.size_mm if under_at else 0.0
    if over_at is not None and max_over > tol:
        blame(machined, over_at, removed=True)
    if under_at is not None and max_under > tol:
        blame(machined, under_at, removed=False)

    results = []
    for z in zones:
        ach = _achieved(material, z)
        results.append(ThreadResult(z.m0, z.m1, z.internal, z.target, ach,
                                    max(2 * tol, 0.05), z.declared))
    reasons = []
    if max_over > tol:
        reasons.append(f"overcut {max_over:.4f} mm > {tol:g}")
    if max_under > tol:
        reasons.append(f"undercut {max_under:.4f} mm > {tol:g}")
    if machined.issues:
        reasons.append(f"{len(machined.issues)} collision(s)/check finding(s)")
    for t in results:
        if not t.ok:
            reasons.append(str(t))
    if strict and any(u.size_mm > tol for u in unreach_list):
        reasons.append("unreachable leftover (strict)")
    return Report(passed=not reasons, tol=tol, max_overcut_mm=max_over, max_undercut_mm=max_under,
                  overcut_at=over_at, undercut_at=under_at, unreachable=unreach_list,
                  collisions=list(machined.issues), cycle_time_s=machined.cycle_time_s,
                  removed_volume_mm3=machined.removed_volume_mm3,
                  air_cut_fraction=machined.air_cut_fraction, threads=results, strict=strict,
                  overcut=over, undercut=under, unreachable_region=unreach_region, reasons=reasons,
                  notes=list(machined.notes))
