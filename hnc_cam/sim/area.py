"""Exact areas of overlap between a polygonal region and many small polygons, in numpy.

For closed rings oriented counter-clockwise (holes clockwise) in the (z, x) plane, the
indicator of the region is, at almost every point, ``sum_e s_e [x < h_e(z)]`` over its edges
(``h_e`` the edge's height over its Z span, ``s_e = +1`` for an edge running toward -Z, -1
toward +Z; vertical edges have no Z span). The area of the overlap of two regions P and Q is
therefore

    area(P & Q) = sum_e sum_f s_e s_f  integral over span(e) & span(f) of min(h_e, h_f) dz,

a sum over pairs of edges whose Z spans overlap, each term the integral of the smaller of two
linear functions (closed form, split where they cross). Nothing here depends on convexity or
on the edges meeting in general position: coincident and collinear edges, the usual trouble
of polygon clipping, only make two linear functions equal. Any vertical shift of all heights
leaves the sum unchanged (for every Z, the signs of the edges spanning it sum to zero), so the
heights are taken relative to a reference near the small polygon, which keeps the rounding
of each term to some 1e-16 of (tool size x span).

:func:`front_bands` gives the region a convex outline K sweeps along a straight piece a -> b
beyond its start placement K + a (the sweep minus K + a): the band between K's front chain
(the vertices facing the motion) at a and at b. When K + a was swept by the move before, what
a move newly removes lies in the union of its pieces' bands; :mod:`hnc_cam.sim.simulate` uses
the sum of these overlaps as an upper bound of each move's removal and accepts it only when
the bounds of a batch add up to what the batch removed as a whole.
"""
from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry


def region_edges(g: BaseGeometry) -> np.ndarray:
    """The boundary edges of a polygonal region as rows (z0, x0, z1, x1, s) with the rings
    oriented (exteriors counter-clockwise, holes clockwise) and ``s`` the edge's sign."""
    if g is None or g.is_empty:
        return np.zeros((0, 5))
    g = shapely.orient_polygons(g, exterior_cw=False)
    rings = shapely.get_rings(shapely.get_parts(g))
    coords, ring = shapely.get_coordinates(rings, return_index=True)
    same = ring[1:] == ring[:-1]
    a, b = coords[:-1][same], coords[1:][same]
    return _with_sign(a, b)


def _with_sign(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    s = -np.sign(b[:, 0] - a[:, 0])
    out = np.column_stack([a, b, s])
    return out[s != 0]


def front_bands(outline: np.ndarray, a: np.ndarray, b: np.ndarray,
                whole: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closed rings (n, W, 2) of what the convex outline K (ccw, (m, 2)) sweeps along each
    straight piece a_i -> b_i beyond K + a_i (the band between K's front chain at a_i and at
    b_i), or of the whole swept hull where ``whole[i]``; padded by repeating the closing
    vertex. Also the indices of K's vertices extreme to the right and to the left of each
    piece's motion (the ends of its front chain)."""
    K = np.asarray(outline, dtype=float)
    m, n = len(K), len(a)
    if n == 0:
        return np.zeros((0, 2, 2)), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    i_min, i_max = extremes(K, a, b)
    c = np.mod(i_max - i_min, m)  # front chain: i_min .. i_max counter-clockwise, c + 1 vertices
    width = max(2 * int(c.max()) + 3, m + 3)
    t = np.arange(width)[None, :]
    # band: front chain at b (t = 0..c), then the chain backwards at a (t = c+1 .. 2c+1),
    # closed at t = 2c+2, padded with the closing vertex
    cc = c[:, None]
    at_b = t <= cc
    back = np.clip(2 * cc + 1 - t, 0, None)
    idx_band = np.where(at_b, i_min[:, None] + t, i_min[:, None] + np.minimum(back, cc))
    end_band = t > 2 * cc + 1
    idx_band = np.where(end_band, i_min[:, None], idx_band)
    use_b = at_b | end_band
    # whole hull (as sweep_hulls): front chain at b, the rest at a, closed, padded
    fwd = t <= cc
    idx_hull = np.where(fwd, i_min[:, None] + t, i_min[:, None] + t - 1)
    end_hull = t > m + 1
    idx_hull = np.where(end_hull, i_min[:, None], idx_hull)
    hull_b = fwd | end_hull
    w = whole[:, None]
    idx = np.mod(np.where(w, idx_hull, idx_band), m)
    on_b = np.where(w, hull_b, use_b)
    ring = K[idx] + np.where(on_b[:, :, None], b[:, None, :], a[:, None, :])
    return ring, i_min, i_max


def extremes(outline: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the vertices of K extreme to the right and to the left of each piece's
    motion a_i -> b_i (the ends of its front chain)."""
    d = b - a
    s = np.column_stack([-d[:, 1], d[:, 0]]) @ np.asarray(outline, dtype=float).T
    return np.argmin(s, axis=1), np.argmax(s, axis=1)


def polygon_edges(geoms) -> np.ndarray:
    """Edges (n, P, 5) of polygonal geometries (rows z0 x0 z1 x1 s as :func:`region_edges`,
    padded with zero rows)."""
    n = len(geoms)
    if n == 0:
        return np.zeros((0, 1, 5))
    parts, pidx = shapely.get_parts(shapely.orient_polygons(np.asarray(geoms, dtype=object),
                                                            exterior_cw=False), return_index=True)
    rings, ridx = shapely.get_rings(parts, return_index=True)
    coords, cidx = shapely.get_coordinates(rings, return_index=True)
    same = cidx[1:] == cidx[:-1]
    e = _with_sign_all(coords[:-1][same], coords[1:][same])
    owner = pidx[ridx[cidx[:-1][same]]]
    if not len(owner):
        return np.zeros((n, 1, 5))
    order = np.argsort(owner, kind="stable")
    owner, e = owner[order], e[order]
    cnt = np.bincount(owner, minlength=n)
    out = np.zeros((n, max(int(cnt.max()), 1), 5))
    pos = np.arange(len(owner)) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    out[owner, pos] = e
    return out


def _with_sign_all(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.column_stack([a, b, -np.sign(b[:, 0] - a[:, 0])])


def heights_over(region: np.ndarray, z0: np.ndarray, z1: np.ndarray) -> np.ndarray:
    """For each Z interval [z0_i, z1_i], a height X_i that no point of the region (edges of
    :func:`region_edges`) over the interval lies above: the highest end of the edges whose
    Z span may meet it (a vertical line through a point of the region leaves it through an
    edge above the point); -inf where no edge does."""
    n = len(z0)
    out = np.full(n, -np.inf)
    if n == 0 or not len(region):
        return out
    elo = np.minimum(region[:, 0], region[:, 2])
    ehi = np.maximum(region[:, 0], region[:, 2])
    top = np.maximum(region[:, 1], region[:, 3])
    span = ehi - elo
    T = max(4.0 * float(np.partition(span, len(span) // 2)[len(span) // 2]), 1e-9)
    long_ = np.flatnonzero(span > T)
    if len(long_):
        meet = (elo[long_][None, :] <= z1[:, None]) & (ehi[long_][None, :] >= z0[:, None])
        out = np.max(np.where(meet, top[long_][None, :], -np.inf), axis=1)
    short = np.flatnonzero(span <= T)
    if len(short):
        # the short edges that start within T before an interval's start up to its end: a
        # contiguous run of them sorted by start (a superset of those that meet it)
        short = short[np.argsort(elo[short], kind="stable")]
        h = np.append(top[short], -np.inf)
        i0 = np.searchsorted(elo[short], z0 - T, "left")
        i1 = np.searchsorted(elo[short], z1, "right")
        some = i1 > i0
        if some.any():
            idx = np.column_stack([i0[some], i1[some]]).ravel()
            m = np.maximum.reduceat(h, idx)[::2]
            out[some] = np.maximum(out[some], m)
    return out


def clip_below(rings: np.ndarray, X) -> np.ndarray:
    """The closed rings (n, W, 2) clipped to the half-plane x <= X (one Sutherland-Hodgman
    step; the result's signed area is that of the ring's part in the half-plane, whatever its
    shape), padded with repeated vertices: (n, 2W - 1, 2). ``X``: one height, or one per ring."""
    n, W = rings.shape[:2]
    if n == 0:
        return rings
    X = np.asarray(X, dtype=float)
    if X.ndim:
        X = X[:, None]
    inside = rings[:, :, 1] <= X
    p, q = rings[:, :-1], rings[:, 1:]
    ip, iq = inside[:, :-1], inside[:, 1:]
    cross = ip != iq
    dx = q[:, :, 1] - p[:, :, 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(cross, (X - p[:, :, 1]) / np.where(cross, dx, 1.0), 0.0)
    cut = p + t[:, :, None] * (q - p)
    cut[:, :, 1] = np.where(cross, X, cut[:, :, 1])
    S = 2 * (W - 1)
    # each edge's start (if inside) and its crossing (if it crosses), in ring order
    slots = np.empty((n, W - 1, 2, 2))
    slots[:, :, 0] = p
    slots[:, :, 1] = cut
    valid = np.empty((n, W - 1, 2), dtype=bool)
    valid[:, :, 0] = ip
    valid[:, :, 1] = cross
    valid = valid.reshape(n, S)
    # every slot takes the last valid one up to it (the first valid one before any), and the
    # ring is closed with the first valid one: one gather from the flat slots
    pos = np.empty((n, S + 1), dtype=np.int64)
    pos[:, :S] = np.where(valid, np.arange(S)[None, :], -1)
    np.maximum.accumulate(pos[:, :S], axis=1, out=pos[:, :S])
    first = np.argmax(valid, axis=1)
    pos[:, S] = first
    np.copyto(pos, first[:, None], where=pos < 0)
    pos += (np.arange(n) * S)[:, None]
    return slots.reshape(n * S, 2)[pos]


def clip_outline(outline: np.ndarray, X: float) -> np.ndarray | None:
    """The convex outline (ccw) cut to x <= X, or None when less than a polygon is left."""
    K = np.asarray(outline, dtype=float)
    if K[:, 1].max() <= X:
        return K
    r = clip_below(np.concatenate([K, K[:1]])[None], X)[0][:-1]
    keep = np.ones(len(r), dtype=bool)
    keep[1:] = np.any(r[1:] != r[:-1], axis=1)
    r = r[keep]
    if len(r) > 1 and np.all(r[0] == r[-1]):
        r = r[:-1]
    if len(r) < 3:
        return None
    return r


def ring_edges(rings: np.ndarray) -> np.ndarray:
    """Edges (n, W - 1, 5) of closed rings (n, W, 2): z0 x0 z1 x1 s (s = 0 for the edges
    without Z span, which add nothing)."""
    p, q = rings[:, :-1], rings[:, 1:]
    sgn = -np.sign(q[:, :, 0] - p[:, :, 0])
    return np.concatenate([p, q, sgn[:, :, None]], axis=2)


def ring_edge_rows(rings: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`edge_rows` of :func:`ring_edges`, built without the edges that have no Z span:
    rows (E, 5) z0 x0 z1 x1 s and each one's ring (E,)."""
    z = rings[:, :, 0]
    own, i = np.nonzero(z[:, 1:] != z[:, :-1])
    p, q = rings[own, i], rings[own, i + 1]
    return np.column_stack([p, q, -np.sign(q[:, 0] - p[:, 0])]), own


def envelope(outline: np.ndarray, i_min: int, i_max: int, pts: np.ndarray) -> np.ndarray:
    """Closed ring of the region that the convex outline K covers when moved along the
    polyline ``pts`` whose every piece has the same extreme vertices ``i_min`` (right of the
    motion) and ``i_max`` (left): K at the start, the chord from K[i_min] to K[i_max] swept
    along the path, K at the end. The chord always advances to the same side, so when the
    ring is simple (a valid polygon) the region is the chord's embedded sweep together with
    the two placements: it lies inside the union of the pieces' swept hulls (it may be
    smaller than that union where another part of K reaches past the chord's sweep)."""
    K = np.asarray(outline, dtype=float)
    m = len(K)
    c = (i_max - i_min) % m
    front = K[(i_min + np.arange(c + 1)) % m]
    back = K[(i_max + np.arange(m - c + 1)) % m]
    return np.concatenate([K[i_min] + pts, front[1:] + pts[-1], (K[i_max] + pts[::-1])[1:],
                           back[1:] + pts[0]])


def overlap_areas(region: np.ndarray, pieces: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """area(R & Q_i) for the region R (edges of :func:`region_edges`) and each small polygon
    Q_i (edges (n, P, 5) padded with zero rows, ``ref[i]`` a height near it)."""
    f, fown = edge_rows(pieces)
    return overlap_areas_of(region, f, fown, ref, len(pieces))


def edge_rows(pieces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The edges with a Z span of the polygons ``pieces`` (edges (n, P, 5) padded with zero
    rows), as rows (E, 5), and each one's polygon (E,)."""
    P = pieces.shape[1] if pieces.ndim == 3 else 1
    f = pieces.reshape(-1, 5)
    live = np.flatnonzero(f[:, 4] != 0)
    return f[live], live // P


#: edges of the small polygons taken together by :func:`overlap_areas_of` (whole polygons;
#: bounds the memory of the pairs of edges at some 10 MB)
EDGE_BLOCK = 8192


def overlap_areas_of(region: np.ndarray, f: np.ndarray, fown: np.ndarray, ref: np.ndarray,
                     n: int) -> np.ndarray:
    """:func:`overlap_areas` of the polygons Q_0 .. Q_n-1 given as their edges with a Z span
    (:func:`edge_rows`): rows ``f`` (E, 5) of the polygons ``fown`` (E,), each polygon's
    edges one after another; in blocks of about :data:`EDGE_BLOCK` edges."""
    if len(f) <= EDGE_BLOCK:
        return _overlap_areas(region, f, fown, ref, n)
    # blocks end where a polygon's edges end: the sums below hold for whole polygons
    cut = np.flatnonzero(fown[1:] != fown[:-1]) + 1
    at = np.searchsorted(cut, np.arange(EDGE_BLOCK, len(f), EDGE_BLOCK))
    ends = np.unique(cut[at[at < len(cut)]]).tolist() + [len(f)]
    out = np.zeros(n)
    for b0, b1 in zip([0] + ends[:-1], ends):
        out += _overlap_areas(region, f[b0:b1], fown[b0:b1], ref, n)
    return out


def _overlap_areas(region: np.ndarray, f: np.ndarray, fown: np.ndarray, ref: np.ndarray,
                   n: int) -> np.ndarray:
    out = np.zeros(n)
    if n == 0 or not len(region) or not len(f):
        return out
    fz0, fx0, fz1, fx1, fs = (np.ascontiguousarray(c) for c in f.T)
    flo, fhi = np.minimum(fz0, fz1), np.maximum(fz0, fz1)
    # region edges within the pieces' Z range and not wholly below every piece (an edge wholly
    # below a piece contributes nothing to it: the piece's signs cancel on every vertical line)
    e = region
    elo, ehi = np.minimum(e[:, 0], e[:, 2]), np.maximum(e[:, 0], e[:, 2])
    near = np.flatnonzero((elo < fhi.max()) & (ehi > flo.min())
                          & (np.maximum(e[:, 1], e[:, 3]) > min(fx0.min(), fx1.min())))
    if not len(near):
        return out
    e, elo, ehi = e[near], elo[near], ehi[near]
    ez0, ex0, ez1, ex1, es = (np.ascontiguousarray(c) for c in e.T)
    # pairs (region edge, piece edge) whose Z spans overlap: long region edges against every
    # piece edge, the short ones by a sorted sweep (a short edge starts within T before the
    # piece edge's end)
    span = ehi - elo
    T = max(4.0 * float(np.partition(span, len(span) // 2)[len(span) // 2]), 1e-9)
    is_long = span > T
    short = np.flatnonzero(~is_long)
    short = short[np.argsort(elo[short], kind="stable")]
    s_lo = elo[short]
    i0 = np.searchsorted(s_lo, flo - T, "left")
    i1 = np.searchsorted(s_lo, fhi, "left")
    cnt = i1 - i0
    tot = int(cnt.sum())
    fi = np.repeat(np.arange(len(fz0)), cnt)
    ei = short[np.arange(tot) + np.repeat(i0 - (np.cumsum(cnt) - cnt), cnt)]
    longe = np.flatnonzero(is_long)
    if len(longe):
        lf, le = np.nonzero((elo[longe][None, :] < fhi[:, None]) & (ehi[longe][None, :] > flo[:, None]))
        fi = np.concatenate([fi, lf])
        ei = np.concatenate([ei, longe[le]])
    lo = np.maximum(elo[ei], flo[fi])
    hi = np.minimum(ehi[ei], fhi[fi])
    ok = np.flatnonzero(hi > lo)
    if not len(ok):
        return out
    fi, ei, lo, hi = fi[ok], ei[ok], lo[ok], hi[ok]
    # heights relative to the piece's reference: h(z) = x0 + slope (z - z0)
    es_, fs_ = (ex1 - ex0) / np.where(ez1 != ez0, ez1 - ez0, 1.0), (fx1 - fx0) / np.where(fz1 != fz0, fz1 - fz0, 1.0)
    r = ref[fown[fi]]
    a0, az, ak = ex0[ei] - r, ez0[ei], es_[ei]
    b0, bz, bk = fx0[fi] - r, fz0[fi], fs_[fi]
    e0 = a0 + ak * (lo - az)
    e1 = a0 + ak * (hi - az)
    f0 = b0 + bk * (lo - bz)
    f1 = b0 + bk * (hi - bz)
    d0, d1 = e0 - f0, e1 - f1
    m0, m1 = np.minimum(e0, f0), np.minimum(e1, f1)
    val = m0 + m1
    cross = np.flatnonzero(d0 * d1 < 0)
    if len(cross):
        tt = d0[cross] / (d0[cross] - d1[cross])
        cv = e0[cross] + tt * (e1[cross] - e0[cross])
        val[cross] = tt * (m0[cross] + cv) + (1 - tt) * (cv + m1[cross])
    val *= 0.5 * (hi - lo) * es[ei] * fs[fi]
    return np.bincount(fown[fi], weights=val, minlength=n)
