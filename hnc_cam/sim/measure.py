"""Distances from many points to exact Line/Arc chains (vectorised with numpy).

The same definitions as :meth:`hnc_cam.geometry.Line.distance_to` and
:meth:`hnc_cam.geometry.Arc.distance_to` (closest point on the segment, arc ends included),
evaluated for arrays of points at once; the tests check the two agree.
Points here are in the simulator's (z, x) order; segments are the kernel's (x, z) objects.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from ..geometry import Arc, Segment


#: points measured together against the segments near them (:func:`distances`)
BLOCK = 512


class SegmentTable:
    """Segments as arrays, built once for many :func:`distances` queries: their boxes
    (z0, x0, z1, x1), the lines' ends and the arcs' centres, radii, start angles, sweeps and
    ends, each in the kernel's (x, z)."""

    def __init__(self, segs: Sequence[Segment]):
        self.segs = list(segs)
        m = len(self.segs)
        self.boxes = np.array([(b[1], b[0], b[3], b[2]) for b in (s.bbox() for s in self.segs)],
                              dtype=float).reshape(m, 4)
        self.is_arc = np.array([isinstance(s, Arc) for s in self.segs], dtype=bool)
        self.start = np.array([s.start for s in self.segs], dtype=float).reshape(m, 2)
        self.end = np.array([s.end for s in self.segs], dtype=float).reshape(m, 2)
        self.center = np.full((m, 2), np.nan)
        self.radius = np.full(m, np.nan)
        self.a0 = np.full(m, np.nan)
        self.sweep = np.full(m, np.nan)
        for k in np.flatnonzero(self.is_arc).tolist():
            s = self.segs[k]
            self.center[k], self.radius[k] = s.center, s.radius
            self.a0[k], self.sweep[k] = s.start_angle, s.sweep

        self._all = None  # :meth:`_columns` of every segment, built on first use

    def __len__(self) -> int:
        return len(self.segs)

    def _columns(self, cols: np.ndarray) -> tuple:
        """The arrays :meth:`pairs` measures the segments ``cols`` with."""
        arc = self.is_arc[cols]
        li, ai = np.flatnonzero(~arc), np.flatnonzero(arc)
        lines = arcs = None
        if len(li):
            a = self.start[cols[li]]
            b = self.end[cols[li]]
            dx, dz = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
            L2 = dx * dx + dz * dz
            point = L2 < 1e-18
            lines = (a, dx, dz, point, np.where(point, 1.0, L2), bool(point.any()))
        if len(ai):
            k = cols[ai]
            sw = self.sweep[k]
            ccw = sw > 0
            # the angle from the arc's start in its own sense, and the most it may be
            arcs = (self.center[k, 0], self.center[k, 1], self.radius[k],
                    np.where(ccw, self.a0[k], -self.a0[k]), np.where(ccw, 1.0, -1.0),
                    np.where(ccw, sw, -sw) + 1e-12,
                    self.start[k, 0], self.start[k, 1], self.end[k, 0], self.end[k, 1])
        return len(cols), li, ai, lines, arcs

    def pairs(self, pts: np.ndarray, cols: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """:func:`_all_pairs` of the (z, x) points against the segments ``cols`` (indices,
        default all): the distance and the position in ``cols`` of the nearest, the first on a
        tie."""
        n = len(pts)
        if cols is None:
            if self._all is None:
                self._all = self._columns(np.arange(len(self.segs)))
            m, li, ai, lines, arcs = self._all
        else:
            m, li, ai, lines, arcs = self._columns(cols)
        best = np.full(n, np.inf)
        which = np.full(n, -1, dtype=int)
        if m == 0 or n == 0:
            return best, which
        if len(li):
            a, dx, dz, point, L2s, any_point = lines
            a0_, a1_ = a[:, 0], a[:, 1]
        if len(ai):
            cx, cz, r, a0s, sgn, lim, sx, sz, ex, ez = arcs
        only = m == len(li) or m == len(ai)  # one kind: its matrix is D
        step = max(1, (1 << 16) // m)
        for i0 in range(0, n, step):
            pz, px = pts[i0:i0 + step, 0, None], pts[i0:i0 + step, 1, None]
            D = None if only else np.empty((len(pz), m))
            if len(li):
                ex_ = px - a0_
                ez_ = pz - a1_
                t = ex_ * dx
                t += ez_ * dz
                t /= L2s
                np.clip(t, 0.0, 1.0, out=t)
                u = t * dx
                u += a0_
                np.subtract(px, u, out=u)
                t *= dz
                t += a1_
                np.subtract(pz, t, out=t)
                d = np.hypot(u, t, out=u)
                if any_point:
                    d[:, point] = np.hypot(ex_[:, point], ez_[:, point])
                if only:
                    D = d
                else:
                    D[:, li] = d
            if len(ai):  # as :func:`_arc_dist`, every arc at once
                qx, qz = px - cx, pz - cz
                ang = np.arctan2(qx, qz)
                # mod(ang - a0) for a counter-clockwise arc, mod(a0 - ang) for a clockwise one
                ang *= sgn
                ang -= a0s
                inside = np.mod(ang, 2 * math.pi, out=ang) <= lim
                rc = np.hypot(qx, qz)
                inside &= rc > 1e-12
                d_on = np.abs(rc - r, out=rc)
                d_ends = np.minimum(np.hypot(px - sx, pz - sz), np.hypot(px - ex, pz - ez))
                d = np.where(inside, d_on, d_ends)
                if only:
                    D = d
                else:
                    D[:, ai] = d
            w = np.argmin(D, axis=1)
            best[i0:i0 + step] = D[np.arange(len(w)), w]
            which[i0:i0 + step] = w
        return best, which


def distances(points: np.ndarray, segs: Sequence[Segment] | SegmentTable,
              boxes: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(distance, index of the nearest segment) for each (z, x) point of ``points``.

    Many points against many segments: the points sorted along Z and cut into blocks (at most
    ``BLOCK`` points, within one of 64 equal slices of their Z range, 0.5 mm at least), a
    block is measured against the segments whose boxes come within the block's size of the
    block's box, then against those within the largest distance found (no segment farther
    from the box can be nearer to a point of it): the same distances and nearest segments as
    every point against every segment, ties to the first segment as there. ``segs``: the
    segments or their :class:`SegmentTable` (built once for many queries); ``boxes``: the
    segments' boxes (z0, x0, z1, x1) if known."""
    tab = segs if isinstance(segs, SegmentTable) else SegmentTable(segs)
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(tab) <= 16 or len(pts) * len(tab) <= 1 << 14:
        return tab.pairs(pts)
    if boxes is None:
        boxes = tab.boxes
    best = np.empty(len(pts))
    which = np.empty(len(pts), dtype=int)
    order = np.argsort(pts[:, 0], kind="stable")
    zs = pts[order, 0]
    span = max(0.5, float(zs[-1] - zs[0]) / 64)
    bins = np.floor((zs - zs[0]) / span)
    cuts = np.flatnonzero(np.r_[True, bins[1:] != bins[:-1], True]).tolist()
    for s0, s1 in zip(cuts[:-1], cuts[1:]):
        for i0 in range(s0, s1, BLOCK):
            idx = order[i0:min(i0 + BLOCK, s1)]
            p = pts[idx]
            z0, x0 = p.min(axis=0)
            z1, x1 = p.max(axis=0)
            gap = np.hypot(np.maximum(0.0, np.maximum(boxes[:, 0] - z1, z0 - boxes[:, 2])),
                           np.maximum(0.0, np.maximum(boxes[:, 1] - x1, x0 - boxes[:, 3])))
            cand = np.flatnonzero(gap <= math.hypot(z1 - z0, x1 - x0))
            if not len(cand):
                cand = np.argsort(gap, kind="stable")[:1]
            d, w = tab.pairs(p, cand)
            full = np.flatnonzero(gap <= float(d.max()))
            if not np.isin(full, cand).all():
                cand = full
                d, w = tab.pairs(p, cand)
            best[idx] = d
            which[idx] = cand[w]
    return best, which


def _all_pairs(pts: np.ndarray, segs: Sequence[Segment]) -> tuple[np.ndarray, np.ndarray]:
    """:func:`distances` of every point to every segment: a matrix of the distances of a
    chunk of points to the segments, its smallest entry per point, the first segment on a
    tie."""
    return SegmentTable(segs).pairs(np.asarray(pts, dtype=float).reshape(-1, 2))


def _line_dist(px, pz, a, b) -> np.ndarray:
    dx, dz = b[0] - a[0], b[1] - a[1]
    L2 = dx * dx + dz * dz
    if L2 < 1e-18:
        return np.hypot(px - a[0], pz - a[1])
    t = np.clip(((px - a[0]) * dx + (pz - a[1]) * dz) / L2, 0.0, 1.0)
    return np.hypot(px - (a[0] + t * dx), pz - (a[1] + t * dz))


def _arc_dist(px, pz, arc: Arc) -> np.ndarray:
    cx, cz = arc.center
    r = arc.radius
    a0 = arc.start_angle
    s = arc.sweep
    ang = np.arctan2(px - cx, pz - cz)
    if s > 0:
        inside = np.mod(ang - a0, 2 * math.pi) <= s + 1e-12
    else:
        inside = np.mod(a0 - ang, 2 * math.pi) <= -s + 1e-12
    rc = np.hypot(px - cx, pz - cz)
    d_on = np.abs(rc - r)
    d_ends = np.minimum(np.hypot(px - arc.start[0], pz - arc.start[1]),
                        np.hypot(px - arc.end[0], pz - arc.end[1]))
    return np.where(inside & (rc > 1e-12), d_on, d_ends)
