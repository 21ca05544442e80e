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


def distances(points: np.ndarray, segs: Sequence[Segment]) -> tuple[np.ndarray, np.ndarray]:
    """(distance, index of the nearest segment) for each (z, x) point of ``points``.

    Many points against many segments: a block of consecutive points (a boundary's, so near
    each other) is measured against the segments whose boxes come within the block's size of
    the block's box, then against those within the largest distance found (no segment farther
    from the box can be nearer to a point of it): the same distances and nearest segments as
    every point against every segment, ties to the first segment as there."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(segs) <= 16 or len(pts) * len(segs) <= 1 << 18:
        return _all_pairs(pts, segs)
    boxes = np.array([(b[1], b[0], b[3], b[2]) for b in (s.bbox() for s in segs)])  # z0 x0 z1 x1
    best = np.empty(len(pts))
    which = np.empty(len(pts), dtype=int)
    for i0 in range(0, len(pts), BLOCK):
        p = pts[i0:i0 + BLOCK]
        z0, x0 = p.min(axis=0)
        z1, x1 = p.max(axis=0)
        gap = np.hypot(np.maximum(0.0, np.maximum(boxes[:, 0] - z1, z0 - boxes[:, 2])),
                       np.maximum(0.0, np.maximum(boxes[:, 1] - x1, x0 - boxes[:, 3])))
        cand = np.flatnonzero(gap <= math.hypot(z1 - z0, x1 - x0))
        if not len(cand):
            cand = np.argsort(gap, kind="stable")[:1]
        d, w = _all_pairs(p, [segs[k] for k in cand.tolist()])
        full = np.flatnonzero(gap <= float(d.max()))
        if not np.isin(full, cand).all():
            cand = full
            d, w = _all_pairs(p, [segs[k] for k in cand.tolist()])
        best[i0:i0 + BLOCK] = d
        which[i0:i0 + BLOCK] = cand[w]
    return best, which


def _all_pairs(pts: np.ndarray, segs: Sequence[Segment]) -> tuple[np.ndarray, np.ndarray]:
    """:func:`distances` of every point to every segment: a matrix of the distances of a
    chunk of points to the segments (the lines at once, as :func:`_line_dist` computes them
    one by one), its smallest entry per point, the first segment on a tie."""
    n, m = len(pts), len(segs)
    best = np.full(n, np.inf)
    which = np.full(n, -1, dtype=int)
    if m == 0 or n == 0:
        return best, which
    if m <= 8:  # a few segments: one after another costs less than the matrix
        pz, px = pts[:, 0], pts[:, 1]
        for k, s in enumerate(segs):
            d = _arc_dist(px, pz, s) if isinstance(s, Arc) else _line_dist(px, pz, s.start, s.end)
            better = d < best
            best[better] = d[better]
            which[better] = k
        return best, which
    li = [k for k, s in enumerate(segs) if not isinstance(s, Arc)]
    arcs = [(k, s) for k, s in enumerate(segs) if isinstance(s, Arc)]
    if li:
        a = np.array([segs[k].start for k in li], dtype=float)
        b = np.array([segs[k].end for k in li], dtype=float)
        dx, dz = b[:, 0] - a[:, 0], b[:, 1] - a[:, 1]
        L2 = dx * dx + dz * dz
        point = L2 < 1e-18
        L2s = np.where(point, 1.0, L2)
    step = max(1, (1 << 16) // m)
    for i0 in range(0, n, step):
        pz, px = pts[i0:i0 + step, 0], pts[i0:i0 + step, 1]
        D = np.empty((len(pz), m))
        if li:
            ex = px[:, None] - a[:, 0]
            ez = pz[:, None] - a[:, 1]
            t = np.clip((ex * dx + ez * dz) / L2s, 0.0, 1.0)
            d = np.hypot(px[:, None] - (a[:, 0] + t * dx), pz[:, None] - (a[:, 1] + t * dz))
            if point.any():
                d[:, point] = np.hypot(ex[:, point], ez[:, point])
            D[:, li] = d
        for k, s in arcs:
            D[:, k] = _arc_dist(px, pz, s)
        w = np.argmin(D, axis=1)
        best[i0:i0 + step] = D[np.arange(len(w)), w]
        which[i0:i0 + step] = w
    return best, which


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
