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


def distances(points: np.ndarray, segs: Sequence[Segment]) -> tuple[np.ndarray, np.ndarray]:
    """(distance, index of the nearest segment) for each (z, x) point of ``points``."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    pz, px = pts[:, 0], pts[:, 1]
    best = np.full(len(pts), np.inf)
    which = np.full(len(pts), -1, dtype=int)
    for k, s in enumerate(segs):
        if isinstance(s, Arc):
            d = _arc_dist(px, pz, s)
        else:
            d = _line_dist(px, pz, s.start, s.end)
        better = d < best
        best[better] = d[better]
        which[better] = k
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
