"""Tool outlines for the material-removal simulation.

A tool is a convex polygon in the simulator's plane (shapely coordinates ``(z, x)``: Z to the
right, X = radius up), given **relative to the controlled point** that the toolpath moves
(:mod:`hnc_cam.nc.toolpath`): the imaginary tip P for tip codes 1-8, the nose centre for 0/9.
The nose centre C is therefore at ``-tip_vector(code, r)`` in the outline's frame.

How an outline is built from an offset register (:class:`hnc_cam.tooling.Register`):

* **Turning inserts** (ISO shapes C D E M V K S W T): the active corner has the nose radius of
  the register and two cutting edges of the insert's edge length meeting at its included angle
  epsilon. For a right-hand outside tool cutting toward the chuck (tip code 3) the main edge
  leaves the nose at the holder's approach angle kappa_r measured from the feed direction -Z
  (kappa_r = 95 deg: the edge points +X and leans 5 deg toward +Z, so a square shoulder can be
  turned); the secondary edge follows at epsilon from it (end cutting edge angle
  180 - kappa_r - epsilon). A rhombic insert is drawn whole (the two back sides are its
  *non-cutting* part); a triangle (T) closes with its third side; a round insert (R) is a circle.
  Tip codes 1, 2, 4 mirror this shape in X and/or Z (2: boring bar toward the chuck; 4: left-hand
  outside tool; 1: left-hand boring bar). Codes 5-8 point the corner straight along that axis,
  symmetric about it. Codes 0 and 9 are oriented as 3 (their controlled point is the centre).
* **Threading inserts** (and every thread move): a symmetric V of the profile angle (the move's
  ``thread_angle`` (G76 A), else the insert's angle, else 60 deg) with the nose radius at its tip,
  pointing to the axis (-X) for an outside register (tip code X sign <= 0), away from it for an
  inside one. Flanks of 6 mm; the back is non-cutting.
* **Grooving inserts**: a square-ended blade of the insert's width with the nose radius at both
  corners, pointing -X (outside) or +X (inside, tip codes 1, 2, 6); tip codes 3/2 reference the
  corner at -Z, 4/1 the corner at +Z, 5, 8, 9 the middle. Its top is non-cutting. Tip code 7
  (the corner pointing at the chuck) is an axial grooving blade for face grooves: pointing -Z,
  its width across X, the controlled point the middle of its end.
* **Drills** (insert kind ``drill``): on the axis, pointing -Z, the controlled point at the
  point's tip: a cone of the point angle to the drill's diameter, then a rectangle of that
  diameter along +Z for the flute length. The back and the sides (the margins) are non-cutting:
  a drill fed across the axis into material is reported.
* **No insert in the register**: the documented default, an 80 deg rhombic insert with 12 mm edges
  (CNMG12-like) on a holder of the register's approach angle (95 deg unless set), with the
  register's nose radius, oriented by the tip code as above. Its sides all remove material,
  but since the insert is a guess, none is reported as a non-cutting side.

The nose arc is sampled as an inscribed polygon with chord error <= ``CHORD`` (0.0005 mm), so a
simulated tool removes at most that much less than the real one.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import shapely

from ..geometry.tip import tip_direction, tip_vector
from ..tooling import Insert, Register

#: chord error of every sampled arc in the simulator (tool noses, arc moves, the model), mm
CHORD = 0.0005

DEFAULT_INSERT = Insert(code="(default 80 deg rhombic 12 mm)", kind="turn", shape="C",
                        nose_angle=80.0, clearance=0.0, edge_length=12.0, nose_radius=0.0)
THREAD_FLANK = 6.0  # mm, length of a threading insert's flanks in the outline


@dataclass(frozen=True)
class ToolShape:
    """A tool outline relative to the controlled point, in (z, x) shapely coordinates.

    ``outline`` is an (N, 2) array of a convex counter-clockwise polygon (not closed).
    ``non_cutting`` lists the sides ((z0, x0), (z1, x1)) that are not cutting edges (the back of
    the insert, the top of a blade); a feed move that removes material with them is reported.
    """
    outline: np.ndarray
    non_cutting: tuple[tuple[tuple[float, float], tuple[float, float]], ...] = ()
    nose_radius: float = 0.0
    tip: int = 3
    description: str = ""
    centre: tuple[float, float] = (0.0, 0.0)  # nose centre (z, x) relative to the controlled point
    key: tuple = field(default=(), compare=True)
    #: an inside tool's bar head across X from its controlled point (its ``min_bore``: in a
    #: bore of that diameter the head's back touches the far wall); 0 where not known
    head: float = 0.0

    @property
    def width(self) -> float:
        """Extent of the outline along Z (mm)."""
        return float(self.outline[:, 0].max() - self.outline[:, 0].min())

    def polygon(self, at: tuple[float, float] = (0.0, 0.0)):
        """The outline as a shapely Polygon with the controlled point at ``at`` = (z, x)."""
        import shapely
        return shapely.Polygon(self.outline + np.asarray(at, dtype=float))


def sweep_hulls(outline: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Polygons ``conv((K + a_i) | (K + b_i))`` for a convex outline K (an (m, 2) array) and
    straight moves a_i -> b_i (arrays (N, 2)): the exact region K sweeps along each move.

    Built directly, without a convex-hull computation: with n the left normal of the move, the
    ring runs over K's vertices from the one extreme in -n to the one extreme in +n (the side
    facing the motion) translated by b, then on round to the first translated by a: m + 2
    vertices per move. A zero-length move gives K itself (with a repeated vertex).
    """
    K = np.asarray(outline, dtype=float)
    z, x = K[:, 0], K[:, 1]
    if float(z[:-1] @ x[1:] - z[1:] @ x[:-1] + z[-1] * x[0] - z[0] * x[-1]) < 0:
        K = K[::-1]  # clockwise given: the ring below needs counter-clockwise order
    a = np.asarray(a, dtype=float).reshape(-1, 2)
    b = np.asarray(b, dtype=float).reshape(-1, 2)
    m, n_moves = len(K), len(a)
    if n_moves == 0:
        return np.zeros(0, dtype=object)
    d = b - a
    nrm = np.column_stack([-d[:, 1], d[:, 0]])
    s = nrm @ K.T  # (N, m)
    i_min, i_max = np.argmin(s, axis=1), np.argmax(s, axis=1)
    c = np.mod(i_max - i_min, m)
    t = np.arange(m + 2)[None, :]
    fwd = t <= c[:, None]
    idx = np.mod(i_min[:, None] + np.where(fwd, t, t - 1), m)
    ring = K[idx] + np.where(fwd[:, :, None], b[:, None, :], a[:, None, :])
    ring = np.concatenate([ring, ring[:, :1]], axis=1)
    return shapely.polygons(ring)


def _arc_points(c: np.ndarray, r: float, a0: float, a1: float) -> list[np.ndarray]:
    """Points of the arc about ``c`` (z, x frame, angle from +Z toward +X) from a0 to a1,
    inscribed chords with sagitta <= CHORD; both ends included."""
    sweep = a1 - a0
    if r <= 0:
        return [c.copy()]
    # split at the axis directions so that the nose's extreme points in X and Z are exact
    # vertices (straight turning and facing then leave exact diameters and faces)
    q = math.pi / 2
    lo, hi = min(a0, a1), max(a0, a1)
    cuts = [k * q for k in range(math.floor(lo / q) + 1, math.ceil(hi / q))
            if lo + 1e-12 < k * q < hi - 1e-12]
    if cuts:
        cuts = cuts if a1 > a0 else cuts[::-1]
        bounds = [a0, *cuts, a1]
        pts: list[np.ndarray] = []
        for s, e in zip(bounds[:-1], bounds[1:]):
            piece = _arc_points(c, r, s, e)
            pts.extend(piece if not pts else piece[1:])
        return pts
    if r <= CHORD:
        n = max(1, int(math.ceil(abs(sweep) / (math.pi / 2))))
    else:
        half = math.acos(max(-1.0, 1.0 - CHORD / r))
        n = max(1, int(math.ceil(abs(sweep) / (2 * half))))
    return [c + r * np.array([math.cos(a0 + sweep * i / n), math.sin(a0 + sweep * i / n)])
            for i in range(n + 1)]


def _unit(a: float) -> np.ndarray:
    return np.array([math.cos(a), math.sin(a)])


def _corner_shape(eps_deg: float, r: float, length: float, theta1: float, shape: str):
    """Insert corner in the nose-centre frame: edge 1 at polar angle theta1 (rad), edge 2 at
    theta1 - eps; returns (points ccw, non-cutting sides)."""
    eps = math.radians(eps_deg)
    theta2 = theta1 - eps
    e1, e2 = _unit(theta1), _unit(theta2)
    bis = _unit((theta1 + theta2) / 2)
    c = np.zeros(2)
    v0 = c - bis * (r / math.sin(eps / 2))
    # nose arc from the tangent point on edge 2 round the outside to edge 1
    nose = _arc_points(c, r, theta2 - math.pi / 2, theta1 + math.pi / 2 - 2 * math.pi) if r > 0 else [v0]
    v1, v3 = v0 + length * e1, v0 + length * e2
    if shape == "T":  # triangle: third side closes the corner's edges
        pts = nose + [v1] if r > 0 else [v0, v1]
        ring = [v3] + pts if r > 0 else [v3, v0, v1]
        non_cut = [(v1, v3)]
    else:
        v2 = v0 + length * (e1 + e2)
        ring = [v3] + nose + [v1, v2]
        non_cut = [(v1, v2), (v2, v3)]
    return ring, non_cut


def _mirror(points: np.ndarray, mz: bool, mx: bool) -> np.ndarray:
    p = points.copy()
    if mz:
        p[:, 0] = -p[:, 0]
    if mx:
        p[:, 1] = -p[:, 1]
    return p


def _ccw(points: np.ndarray) -> np.ndarray:
    z, x = points[:, 0], points[:, 1]
    area2 = float(np.sum(z * np.roll(x, -1) - np.roll(z, -1) * x))
    return points if area2 >= 0 else points[::-1].copy()


def _dedupe(points: np.ndarray) -> np.ndarray:
    keep = [0]
    for i in range(1, len(points)):
        if np.hypot(*(points[i] - points[keep[-1]])) > 1e-9:
            keep.append(i)
    p = points[keep]
    if len(p) > 1 and np.hypot(*(p[0] - p[-1])) <= 1e-9:
        p = p[:-1]
    return p


def tool_shape(reg: Register, thread_angle: float | None = None) -> ToolShape:
    """The outline of the tool in offset register ``reg`` (see the module doc).

    ``thread_angle``: build a threading profile of this angle (deg) whatever the insert is
    (used for thread moves: G32/G82/G76).
    """
    ins = reg.insert
    key = (reg.radius, reg.tip, reg.approach, ins, thread_angle)
    return _tool_shape_cached(key)


@lru_cache(maxsize=256)
def _tool_shape_cached(key) -> ToolShape:
    radius, tip, approach, ins, thread_angle = key
    r = float(radius)
    code = tip if tip in range(1, 9) else 3
    sx, sz = tip_direction(code)
    tv = tip_vector(tip, r)  # (dx, dz) from nose centre to the controlled point
    centre = np.array([-tv[1], -tv[0]])  # nose centre relative to P, in (z, x)
    inside = sx > 0
    kind = ins.kind if ins is not None else "turn"
    non_cut: list = []
    if thread_angle is not None or kind == "thread":
        ang = thread_angle or (ins.angle if ins is not None and ins.kind == "thread" else 0) or 60.0
        # V pointing -X (outside) with the body up; mirrored for inside tools
        ring, non_cut = _corner_shape(float(ang), r, THREAD_FLANK, math.pi / 2 + math.radians(ang) / 2, "T")
        pts = np.array(ring)
        non_cut = [(a, b) for a, b in non_cut]
        if inside:
            pts = _mirror(pts, False, True)
            non_cut = [(a * [1, -1], b * [1, -1]) for a, b in non_cut]
        desc = f"thread {ang:g} deg, r {r:g}"
    elif kind == "drill":
        # on the axis, pointing -Z: the point's cone from the controlled point (the tip) to
        # the full diameter, then the body of the flute length; the back and the body's
        # sides (the margins) do not cut
        rd = ins.width / 2
        h = rd / math.tan(math.radians(ins.angle) / 2)
        top = max(ins.edge_length, h + 1e-3)
        pts = np.array([[0.0, 0.0], [h, rd], [top, rd], [top, -rd], [h, -rd]])
        non_cut = [(pts[1], pts[2]), (pts[2], pts[3]), (pts[3], pts[4])]
        centre = np.zeros(2)
        desc = f"drill {ins.width:g} mm, point {ins.angle:g} deg"
    elif kind == "groove" and code == 7:
        # an axial (face) grooving blade: pointing -Z, its width across X, the controlled
        # point the middle of its end; built about the nose centre a radius above P
        w = max(ins.width, 2 * r + 1e-6)
        h = max(ins.edge_length, 5.0)
        c = w / 2 - r
        ring = ([np.array([h, w / 2])]
                + _arc_points(np.array([0.0, c]), r, 0.5 * math.pi, math.pi)
                + _arc_points(np.array([0.0, -c]), r, math.pi, 1.5 * math.pi)
                + [np.array([h, -w / 2])])
        pts = np.array(ring)
        non_cut = [(np.array([h, w / 2]), np.array([h, -w / 2]))]
        desc = f"face groove {w:g} mm, r {r:g}"
    elif kind == "groove":
        w = max(ins.width, 2 * r + 1e-6)
        h = max(ins.edge_length, 5.0)
        # reference corner at -Z for codes 3/2 (and 0/9), +Z for 4/1, middle for 5-8
        if code in (3, 2):
            zl = -r
        elif code in (4, 1):
            zl = -(w - r)
        else:
            zl = -w / 2
        zr = zl + w
        cl, cr = np.array([zl + r, 0.0]), np.array([zr - r, 0.0])
        ring = (_arc_points(cr, r, -math.pi / 2, 0.0) + [np.array([zr, h]), np.array([zl, h])]
                + _arc_points(cl, r, math.pi, 1.5 * math.pi))
        pts = np.array(ring)
        non_cut = [(np.array([zr, h]), np.array([zl, h]))]
        if inside:
            pts = _mirror(pts, False, True)
            non_cut = [(a * [1, -1], b * [1, -1]) for a, b in non_cut]
        # the groove outline is built about the nose centre of the reference corner
        desc = f"groove {w:g} mm, r {r:g}"
    else:
        base = ins if ins is not None and ins.kind == "turn" else DEFAULT_INSERT
        if base.shape == "R":
            rr = r if r > 0 else base.edge_length / 2
            pts = np.array(_arc_points(np.zeros(2), rr, 0.0, 2 * math.pi)[:-1])
            desc = f"round insert r {rr:g}"
        else:
            eps = base.nose_angle
            length = base.edge_length
            if code in (1, 2, 3, 4):
                kr = float(approach)
                if kr + eps > 179.0:  # impossible holder/insert pair: keep 1 deg end clearance
                    kr = 179.0 - eps
                theta1 = math.pi - math.radians(kr)  # for code 3; mirrored below
                ring, non_cut = _corner_shape(eps, r, length, theta1, base.shape)
                pts = np.array(ring)
                mz, mx = sz > 0, sx > 0
                pts = _mirror(pts, mz, mx)
                non_cut = [(_mirror(np.array([a]), mz, mx)[0], _mirror(np.array([b]), mz, mx)[0])
                           for a, b in non_cut]
            else:
                # codes 5-8: corner pointing along the axis, symmetric about it
                point_dir = {5: 0.0, 6: math.pi / 2, 7: math.pi, 8: -math.pi / 2}[code]
                body = point_dir + math.pi
                theta1 = body + math.radians(eps) / 2
                ring, non_cut = _corner_shape(eps, r, length, theta1, base.shape)
                pts = np.array(ring)
            desc = (f"{base.code if ins is not None else 'default 80 deg rhombic 12 mm'} "
                    f"eps {eps:g} kr {approach:g}, r {r:g}")
    pts = pts + centre
    if ins is None:
        # the default outline is a guess: its back is not reported as cutting (issue: "when the
        # insert is known")
        non_cut = []
    non_cut = tuple((tuple(map(float, a + centre)), tuple(map(float, b + centre))) for a, b in non_cut)
    pts = _ccw(_dedupe(pts))
    return ToolShape(outline=pts, non_cutting=non_cut, nose_radius=r, tip=int(tip),
                     description=desc, centre=(float(centre[0]), float(centre[1])), key=key)
