"""Profile extraction: a turned solid -> :class:`~hnc_cam.geometry.TurnedProfile`.

How (and the choices made):

1. The object becomes one OCP shape (build123d, CadQuery, OCP or a STEP/BREP file) and is
   placed so that the turning axis is Z (``axis``).
2. Validation: exactly one solid with one shell (no internal void); every face a surface of
   revolution about the axis (see :func:`hnc_cam.cad.occ.classify_faces`). A face that is not
   (flat, keyway, hex, cross hole, off-axis hole) raises :class:`ProfileError` naming the face
   type, the feature it probably is and where it is. With ``envelope=True`` such faces are
   ignored: the profile is taken in a meridian half-plane that does not cut them on the
   outline (the turned envelope the lathe makes before milling), and ``notes`` lists them.
   When every half-plane cuts them on the outline (a hex or square bar, a flat the whole
   length), the envelope is the section through a corner of those faces that contains the
   sections in all other half-planes tried (the circumscribed cylinder of a hex); when no
   single section does, ProfileError says the envelope is not supported for that part.
3. The solid's boundary is cut with the half-plane {y' = 0, x' >= 0} through the axis at a
   fixed polar angle (0.3 rad, clear of the seams that revolves put at angle 0). OpenCascade
   returns the cuts of planes, cylinders and cones as lines and of spheres and tori as
   circles: they become exact ``Line``/``Arc`` (radius, Z). A free-form edge that is a line
   or circle within 1e-6 mm (OpenCascade approximates the cut of a self-intersecting torus,
   and of B-spline surfaces from other CAD systems) becomes that Line/Arc. Any other curve
   (B-spline, ellipse, the cut of a revolved spline) is fitted with arcs (biarcs) within
   ``fit_tol`` and noted in ``notes``.
4. The pieces are chained; split pieces are merged (collinear lines, co-circular arcs).
5. The section's boundary is split into chains:

   * ``outside`` starts at the **innermost point of the right end** (largest Z): on the
     axis for a part without a bore opening on the right face, else at the bore edge of the
     right face (the inner end of the bore chamfer, if any). It includes the right face,
     runs along the outside toward -Z and **includes the left face**, ending at the
     innermost point of the left end (the axis, or the edge of a through bore).
   * ``bore`` runs from the same right-face point into the bore toward -Z: to the left face
     for a through bore, to the axis (the bottom of the hole) for a blind bore. ``None`` for
     a part without a bore opening on the right. A cavity opening only on the left face
     (e.g. a centre hole) is not part of either chain; ``notes`` says so.
6. Program zero: ``zero="right"`` (default) puts the right face at Z0, the part toward -Z;
   ``"left"`` puts the left face at Z0 (part toward +Z); a number ``a`` puts the point of
   the turning axis at coordinate ``a`` along it (model Z for the default axis, model X for
   ``axis="X"``, measured from the axis point for an explicit axis) at Z0.
7. A part refused as not turned about the requested axis gets a hint when every round face
   of the model is about one other axis (``axis="X"``? or the axis through a point).

A solid made by :func:`hnc_cam.cad.sketch.revolve` and still exactly as it made it (the same
object, its shape ``IsEqual`` to the one made: TShape, location, orientation) is not cut:
steps 1 to 4 are taken from the exact outline it was revolved from (:func:`outline_chain`,
which accepts only an outline whose revolution is a valid turned solid and whose pieces the
kernel keeps as they are), then steps 5 and 6 as for any solid, for the default axis. The
result is the one the section gives (``tests/test_cad_revolved.py`` compares the two for every
bundled part and test family), about 20 to 45 times faster than cutting the solid. The part
loader calls a family's ``part()`` with :func:`~hnc_cam.cad.sketch.revolve` deferred: the
:class:`~hnc_cam.cad.sketch.Revolved` it returns is profiled the same way before any solid is
made, and OpenCascade is imported only when a solid is cut (``tests/test_cad_deferred.py``).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from ..errors import ProfileError
from ..geometry.primitives import Arc, Line, Point, Segment, dist, reverse_chain
from ..geometry.profile import TurnedProfile
from .fit import circle3, fit_curve, merge_segments

#: polar angle of the default meridian half-plane (radians): away from the seam at 0
THETA = 0.3
#: half-planes tried in turn should OpenCascade's section misbehave at the first (radians)
THETAS = (THETA, 1.1, 2.3)
#: end points closer than this are joined when chaining (mm; STEP files carry ~1e-7 gaps)
JOIN_TOL = 1e-4
#: a free-form section edge within this of a line or circle is taken as that line/arc (mm)
EXACT_TOL = 1e-6
#: an end point closer than this to the axis is put on it (mm)
AXIS_SNAP = 1e-6
#: coordinates are rounded to this many decimals (1e-9 mm) to drop floating noise
DECIMALS = 9


def profile(obj: Any, axis: Any = "Z", zero: str | float = "right", envelope: bool = False,
            fit_tol: float = 0.001, name: str | None = None) -> TurnedProfile:
    """The exact turned profile of ``obj`` (see the module docstring for the conventions).

    ``obj``: build123d Part/Solid/Compound/BuildPart, CadQuery Workplane/Shape, OCP
    TopoDS_Shape or a path to .step/.stp/.brep. ``axis``: "Z" (default), "X", "Y" or
    ``((px, py, pz), (dx, dy, dz))`` (a leading "-" reverses: the right face is then at the
    smallest model coordinate). ``zero``: "right", "left" or a coordinate along the axis.
    ``envelope``:
    profile the turned envelope of a part with milled features. ``fit_tol``: arc-fitting
    tolerance for free-form curves (mm).
    """
    if not fit_tol > 0:
        raise ProfileError(f"fit_tol must be positive, got {fit_tol!r}")
    if isinstance(axis, str) and axis.strip().upper().lstrip("+") == "Z":
        from .sketch import revolved_outline
        segs = revolved_outline(obj)
        try:
            main = outline_chain(segs) if segs is not None else None
        except (ArithmeticError, ValueError):  # an outline too odd to judge: cut the solid
            main = None
        if main is not None:  # the solid as revolve() made it: its exact outline
            return _finish(main, [], zero, name)
    return extract(obj, axis=axis, zero=zero, envelope=envelope, fit_tol=fit_tol, name=name)


def extract(obj: Any, axis: Any = "Z", zero: str | float = "right", envelope: bool = False,
            fit_tol: float = 0.001, name: str | None = None) -> TurnedProfile:
    """:func:`profile` taken from the solid itself, always (the section of its boundary),
    never from the outline :func:`hnc_cam.cad.sketch.revolve` noted."""
    from . import occ
    if not fit_tol > 0:
        raise ProfileError(f"fit_tol must be positive, got {fit_tol!r}")
    obj_shape = occ.to_shape(obj)
    shape = occ.axis_transform(obj_shape, axis)
    if shape.IsNull():
        raise ProfileError("empty geometry: the shape is null")
    notes: list[str] = []
    sol = occ.solids(shape)
    if not sol:
        nf = len(occ.faces(shape))
        if nf == 0:
            raise ProfileError("empty geometry: the shape holds no solid and no face")
        raise ProfileError(f"not a solid: the shape holds {nf} face(s) but no closed solid "
                           f"(an open shell or a surface model)")
    if len(sol) > 1:
        where = "; ".join(f"solid {i + 1}: z {b[2]:.3f}..{b[5]:.3f}"
                          for i, b in enumerate(occ.bbox(s) for s in sol[:4]))
        raise ProfileError(f"several disconnected solids ({len(sol)}): fuse them into one part "
                           f"or profile them one by one ({where})")
    solid = sol[0]
    if len(occ.shells(solid)) > 1:
        raise ProfileError("the solid has an internal void (more than one shell): a closed "
                           "cavity cannot be turned")
    bb = occ.bbox(solid)
    vol = occ.volume(solid)
    if min(bb[3] - bb[0], bb[4] - bb[1], bb[5] - bb[2]) < 1e-6 or vol < 1e-9:
        raise ProfileError(f"degenerate geometry: the solid has no volume "
                           f"(extent {bb[3] - bb[0]:.3g} x {bb[4] - bb[1]:.3g} x {bb[5] - bb[2]:.3g} mm)")

    problems, fnotes = occ.classify_faces(solid)
    problems = [dataclasses.replace(p, model=occ.to_model(axis, p.where)) for p in problems]
    notes += fnotes
    if problems:
        if not envelope:
            first = problems[0].describe()
            more = f" (and {len(problems) - 1} more such face(s))" if len(problems) > 1 else ""
            raise ProfileError(f"not a body of revolution about the {_axis_name(axis)} axis: "
                               f"{first}{more}; use envelope=True to profile the turned envelope"
                               f"{_axis_hint(obj_shape, axis)}")
        for p in problems:
            notes.append(f"ignored (envelope): {p.describe()}")
        chains, islands = _envelope_section(solid, bb, problems, fit_tol, notes)
        if islands:
            notes.append(f"ignored (envelope): {islands} inner loop(s) of the section cut by "
                         f"non-turned faces")
        main = chains[0]
    else:
        main = _clean_section(solid, bb, vol, fit_tol)
    return _finish(main, notes, zero, name)


def _finish(main: "_Chain", notes: list[str], zero: str | float,
            name: str | None) -> TurnedProfile:
    """The profile of a section boundary: split into outside and bore, merged, placed on
    program zero and rounded (steps 4 to 6 of the module docstring)."""
    notes = notes + main.notes
    outside, bore, left = _split(main.segs)
    if left:
        notes.append(f"a cavity opening on the left face ({len(left)} segment(s), down to "
                     f"z={min(min(s.start[1], s.end[1]) for s in left):.3f} model) is not part "
                     f"of the outside or bore chain")
    if not outside:
        raise ProfileError("cannot find the outside contour between the end faces: the "
                           "section has no extent along the axis at its ends (a ring?)")
    outside = merge_segments(outside)
    bore = merge_segments(bore) if bore else None
    if isinstance(zero, str):
        z0 = {"right": main.zmax, "left": main.zmin}.get(zero.lower())
        if z0 is None:
            raise ProfileError(f"zero {zero!r}: expected 'right', 'left' or a number")
    else:
        z0 = float(zero)
    outside = [_clean(s.translated(0.0, -z0)) for s in outside]
    bore = [_clean(s.translated(0.0, -z0)) for s in bore] if bore else None
    prof = TurnedProfile(outside=outside, bore=bore, name=name or "part", notes=notes)
    if prof.length < 1e-6 or prof.max_radius < 1e-6:
        raise ProfileError("degenerate geometry: zero length or zero diameter")
    return prof


def _axis_hint(shape, axis: Any) -> str:
    """When every round face of the model is about one other axis, say which (the part was
    modelled along another axis, or off the origin)."""
    from . import occ
    try:
        ca = occ.common_axis(shape)
    except Exception:  # noqa: BLE001 - a hint only
        return ""
    if ca is None:
        return ""
    p, d = ca
    names = {(1.0, 0.0, 0.0): "X", (0.0, 1.0, 0.0): "Y", (0.0, 0.0, 1.0): "Z"}
    if p == (0.0, 0.0, 0.0) and d in names:
        if isinstance(axis, str) and axis.strip().upper().lstrip("+") == names[d]:
            return ""
        return (f" (every round face is about the model's {names[d]} axis: axis=\"{names[d]}\" "
                f"or \"-{names[d]}\"?)")
    pt = ", ".join(f"{v:g}" for v in p)
    dr = ", ".join(f"{v:g}" for v in d)
    return f" (every round face is about the axis through ({pt}) along ({dr}): axis=(({pt}), ({dr}))?)"


def _axis_name(axis: Any) -> str:
    return axis.upper() if isinstance(axis, str) else "given"


def _clean(s: Segment) -> Segment:
    def c(p: Point) -> Point:
        x, z = round(p[0], DECIMALS), round(p[1], DECIMALS)
        return (0.0 if x == 0 else x, 0.0 if z == 0 else z)
    if isinstance(s, Line):
        return Line(c(s.start), c(s.end))
    return Arc(c(s.start), c(s.end), c(s.center), s.cw)


# ---------------------------------------------------------------------------- edges -> chains
def _edge_segments(e: occ.SectionEdge, fit_tol: float, notes: list[str]) -> list[Segment]:
    from . import occ
    p0, p1 = e.rz(e.first), e.rz(e.last)
    p0 = (0.0 if abs(p0[0]) < AXIS_SNAP else p0[0], p0[1])
    p1 = (0.0 if abs(p1[0]) < AXIS_SNAP else p1[0], p1[1])
    if e.kind == "line":
        return [Line(p0, p1)] if dist(p0, p1) > 1e-9 else []
    if e.kind == "circle":
        c, r = e.circle()
        pm = e.rz((e.first + e.last) / 2)
        if dist(p0, p1) < 1e-9:  # full circle (a toroidal ring cut through): two halves
            pq = e.rz(e.first + (e.last - e.first) / 4)
            cw = _turn(p0, pq, pm) < 0
            return [Arc(p0, pm, c, cw), Arc(pm, p1, c, cw)]
        cw = _turn(p0, pm, p1) < 0
        return [Arc(p0, p1, c, cw)]
    exact = _recognise(e, p0, p1)
    if exact is not None:
        return exact
    # the section edge may itself lie up to its tolerance off the true cut: fit tighter
    tol = fit_tol - e.tolerance if e.tolerance < fit_tol / 2 else fit_tol / 2
    try:
        segs = fit_curve(e.rz_d1, e.first, e.last, tol)
        segs = _snap_ends(segs, p0, p1)
    except ValueError as ex:
        raise ProfileError(f"{e.curve_type} edge from (r={p0[0]:.4f}, z={p0[1]:.4f}) to "
                           f"(r={p1[0]:.4f}, z={p1[1]:.4f}): {ex}") from None
    notes.append(f"{e.curve_type} edge from (r={p0[0]:.4f}, z={p0[1]:.4f}) to "
                 f"(r={p1[0]:.4f}, z={p1[1]:.4f}) (model) fitted with {len(segs)} "
                 f"arc/line segment(s) within {fit_tol:g} mm")
    return segs


def _recognise(e: occ.SectionEdge, p0: Point, p1: Point) -> list[Segment] | None:
    """A free-form section edge that is a line or a circular arc within ``EXACT_TOL`` at 64
    points (e.g. the cut of a self-intersecting torus, which OpenCascade approximates)
    becomes that Line/Arc; an arc whose centre lies within ``AXIS_SNAP`` of the axis (a sphere
    given as a B-spline) gets its centre exactly on it."""
    from . import occ
    ts = [e.first + (e.last - e.first) * i / 64 for i in range(1, 64)]
    pts = [e.rz(t) for t in ts]
    if dist(p0, p1) < 1e-9:
        return None
    line = Line(p0, p1)
    if all(line.distance_to(p) <= EXACT_TOL for p in pts):
        return [line]
    pm = e.rz((e.first + e.last) / 2)
    circ = circle3(p0, pm, p1)
    if circ is None:
        return None
    c, r = circ
    if abs(c[0]) <= AXIS_SNAP:  # a centre on the axis stays exactly on it
        c = (0.0, c[1])
        r = (dist(c, p0) + dist(c, p1)) / 2
    if all(abs(dist(c, p) - r) <= EXACT_TOL for p in pts):
        arc = Arc(p0, p1, c, _turn(p0, pm, p1) < 0)
        if all(arc.distance_to(p) <= EXACT_TOL for p in pts):
            return [arc]
    return None


def _snap_ends(segs: list[Segment], p0: Point, p1: Point) -> list[Segment]:
    """Put the fitted chain's ends exactly on the (axis-snapped) edge ends."""
    if not segs:
        return segs
    segs = list(segs)
    segs[0] = _with_start(segs[0], p0)
    last = segs[-1]
    segs[-1] = Line(last.start, p1) if isinstance(last, Line) else Arc(last.start, p1, last.center, last.cw)
    return segs


def _turn(a: Point, b: Point, c: Point) -> float:
    """> 0 when a->b->c turns counter-clockwise in the z-right/x-up view."""
    u = (b[1] - a[1], b[0] - a[0])  # (dz, dx)
    v = (c[1] - b[1], c[0] - b[0])
    return u[0] * v[1] - u[1] * v[0]


def _with_start(s: Segment, p: Point) -> Segment:
    return Line(p, s.end) if isinstance(s, Line) else Arc(p, s.end, s.center, s.cw)


@dataclass
class _Chain:
    segs: list[Segment]
    notes: list[str]  # fitting notes of the edges in this chain
    zmin: float = 0.0  # Z extent of the true boundary (fitted arcs may bulge past it)
    zmax: float = 0.0

    @property
    def closed(self) -> bool:
        return dist(self.segs[-1].end, self.segs[0].start) <= JOIN_TOL

    @property
    def on_axis(self) -> bool:
        return abs(self.segs[0].start[0]) < 1e-6 and abs(self.segs[-1].end[0]) < 1e-6


def _chains(edges: list[occ.SectionEdge], fit_tol: float) -> list[_Chain]:
    """Connected chains of the section, the one reaching the largest radius first. Each chain
    is either closed (a loop) or open with both ends on the axis."""
    from . import occ
    items: list[tuple[Segment, int]] = []  # (segment, index of its fitting note or -1)
    notes: list[str] = []
    zr: dict[int, tuple[float, float]] = {}  # note index -> true Z range of the fitted edge
    for e in edges:
        n0 = len(notes)
        segs = _edge_segments(e, fit_tol, notes)
        fitted = len(notes) > n0
        items += [(sg, n0 if fitted else -1) for sg in segs]
        if fitted:  # fitted arcs may bulge past the curve's extreme Z by up to fit_tol
            zs = [e.rz(e.first + (e.last - e.first) * i / 512)[1] for i in range(513)]
            zr[n0] = (min(zs), max(zs))
    if not items:
        raise ProfileError("empty section: the meridian half-plane does not cut the solid "
                           "(is the part on the axis?)")
    unused = list(items)
    chains: list[_Chain] = []
    while unused:
        chain = [unused.pop(0)]
        for _pass in range(2):  # grow at the end, then (reversed) at the other end
            grown = True
            while grown and not (len(chain) > 1 and dist(chain[-1][0].end, chain[0][0].start) <= JOIN_TOL):
                grown = False
                end = chain[-1][0].end
                for i, (sg, k) in enumerate(unused):
                    if dist(sg.start, end) <= JOIN_TOL:
                        chain.append((_with_start(sg, end), k))
                    elif dist(sg.end, end) <= JOIN_TOL:
                        chain.append((_with_start(sg.reversed(), end), k))
                    else:
                        continue
                    unused.pop(i)
                    grown = True
                    break
            if len(chain) > 1 and dist(chain[-1][0].end, chain[0][0].start) <= JOIN_TOL:
                last, k = chain[-1]
                p0 = chain[0][0].start
                chain[-1] = (Line(last.start, p0) if isinstance(last, Line)
                             else Arc(last.start, p0, last.center, last.cw), k)
                break
            chain = [(sg.reversed(), k) for sg, k in reversed(chain)]
        ranges = [zr[k] if k >= 0 else (sg.bbox()[1], sg.bbox()[3]) for sg, k in chain]
        ch = _Chain([sg for sg, _ in chain],
                    [notes[k] for k in sorted({k for _, k in chain if k >= 0})],
                    min(r[0] for r in ranges), max(r[1] for r in ranges))
        if not ch.closed and not ch.on_axis:
            a, b = ch.segs[-1].end, ch.segs[0].start
            raise ProfileError(f"the section boundary is open between (r={a[0]:.4f}, z={a[1]:.4f}) "
                               f"and (r={b[0]:.4f}, z={b[1]:.4f}): invalid or non-closed solid")
        chains.append(ch)
    chains.sort(key=lambda ch: -max(sg.bbox()[2] for sg in ch.segs))
    return chains


def _signed_area(ch: list[Segment]) -> float:
    """Signed area in the (u = z, v = r) view, closing open chains along the axis."""
    pts: list[Point] = []
    for s in ch:
        pts += s.sample(0.05)[:-1] if isinstance(s, Arc) else [s.start]
    pts.append(ch[-1].end)
    a = 0.0
    for (r0, z0), (r1, z1) in zip(pts, pts[1:] + pts[:1]):
        a += z0 * r1 - z1 * r0
    return a / 2


AXIS = "axis"  # marker in a loop for the closing run along the axis


def _clean_section(solid, bb, vol: float, fit_tol: float) -> "_Chain":
    """The section boundary of a validated turned solid, checked against its volume; another
    half-plane is tried when a section comes out broken."""
    from . import occ
    first: ProfileError | None = None
    for theta in THETAS:
        try:
            chains = _chains(occ.meridian_section(solid, theta, bb), fit_tol)
            if len(chains) != 1:
                raise ProfileError(f"the meridian section has {len(chains)} separate "
                                   f"boundaries: the part is not one connected turned body")
            _check_volume(vol, chains[0], fit_tol, solid)
            return chains[0]
        except ProfileError as e:
            first = first or e
    assert first is not None
    raise first


def outline_chain(segs: Any) -> "_Chain | None":
    """The section boundary of the solid :func:`hnc_cam.cad.sketch.revolve` makes of the
    outline ``segs`` (radius, Z), as the solid's section gives it (ends near the axis put on
    it, each segment starting where the one before ends), when the outline is one whose
    revolution is a valid turned solid: contiguous lines and arcs; simple (neighbours meet
    only at their shared end, no other two segments meet); in r >= 0, touching the axis only
    at the ends of an open outline or with one line along it closing the loop (a segment
    there an arc about a point of the axis: a sphere); enclosing a volume. None for any other
    outline: its solid is then profiled from its section, which says what is wrong with it.
    Neighbours that merge (collinear lines, co-circular arcs) are left to the section too:
    the kernel unifies their faces, and the chain's pieces decide where its ends are found."""
    from ..geometry.intersect import intersect
    try:
        segs = list(segs)
    except TypeError:
        return None
    if not segs or not all(type(sg) in (Line, Arc) for sg in segs):
        return None

    def snap(p: Point) -> Point:
        return (0.0 if abs(p[0]) < AXIS_SNAP else p[0], p[1])

    chain: list[Segment] = []
    for sg in segs:
        a = snap(sg.start) if not chain else chain[-1].end
        if chain and dist(sg.start, chain[-1].end) > 1e-9:
            return None  # not contiguous: the wire's own business
        b = snap(sg.end)
        if dist(a, b) < 1e-9 or not all(map(math.isfinite, (*a, *b))):
            return None
        chain.append(Line(a, b) if isinstance(sg, Line) else Arc(a, b, sg.center, sg.cw))
    on_axis = [isinstance(sg, Line) and sg.start[0] == 0.0 and sg.end[0] == 0.0
               for sg in chain]
    closed = dist(chain[-1].end, chain[0].start) <= 1e-9
    if closed:
        chain[-1] = _with_end(chain[-1], chain[0].start)
        if sum(on_axis) == 1:  # closed along the axis by the outline itself: open it there
            k = on_axis.index(True)
            chain = chain[k + 1:] + chain[:k]
            closed = False
        elif any(on_axis):
            return None
    elif any(on_axis) or chain[0].start[0] != 0.0 or chain[-1].end[0] != 0.0:
        return None
    if not chain:
        return None
    n = len(chain)
    for i in range(0 if closed else 1, n):
        if len(merge_segments([chain[i - 1], chain[i]])) == 1:
            return None  # pieces the kernel may unify (and split where it likes)
    boxes = [sg.bbox() for sg in chain]
    for i, (sg, bx) in enumerate(zip(chain, boxes)):
        if bx[0] < -1e-12:
            return None  # crosses the axis
        if bx[0] >= AXIS_SNAP:
            continue
        if closed or not ((i == 0 and sg.start[0] == 0.0) or (i == n - 1 and sg.end[0] == 0.0)):
            return None  # touches the axis between its ends
        if isinstance(sg, Arc) and (abs(sg.center[0]) > AXIS_SNAP
                                    or abs(sg.sweep) > math.pi + 1e-12):
            return None  # an arc from the axis not about it: a self-intersecting torus
        if isinstance(sg, Arc) and n > 1 and sg.start[0] == 0.0 and sg.end[0] == 0.0:
            return None
    for i in range(n):
        for j in range(i + 1, n):
            bi, bj = boxes[i], boxes[j]
            if bi[0] > bj[2] + 1e-6 or bj[0] > bi[2] + 1e-6 or bi[1] > bj[3] + 1e-6 \
                    or bj[1] > bi[3] + 1e-6:
                continue
            hits = intersect(chain[i], chain[j])
            shared = ([chain[i].end] if j == i + 1 else []) \
                + ([chain[j].end] if closed and i == 0 and j == n - 1 else [])
            if shared:
                if any(min(dist(p, q) for q in shared) > JOIN_TOL for p in hits):
                    return None  # folds back or crosses its neighbour
            elif hits:
                return None  # the outline meets itself
    zmin, zmax = min(b[1] for b in boxes), max(b[3] for b in boxes)
    if zmax - zmin < 1e-6 or max(b[2] for b in boxes) < 1e-6 or revolved_volume(chain) < 1e-9:
        return None
    return _Chain(chain, [], zmin, zmax)


def _with_end(s: Segment, p: Point) -> Segment:
    return Line(s.start, p) if isinstance(s, Line) else Arc(s.start, p, s.center, s.cw)


def revolved_volume(segs: list[Segment]) -> float:
    """Volume (mm^3) of the solid swept by the closed section boundary ``segs`` (an open
    chain is closed along the axis) about the Z axis: Pappus/Green, V = pi |closed integral
    of r^2 dz|, exact for lines and arcs."""
    total = 0.0
    for sg in segs:
        if isinstance(sg, Line):
            (r0, z0), (r1, z1) = sg.start, sg.end
            dr = r1 - r0
            total += (z1 - z0) * (r0 * r0 + r0 * dr + dr * dr / 3)
        else:
            xc, R = sg.center[0], sg.radius
            a0 = sg.start_angle
            a1 = a0 + sg.sweep

            def F(a: float) -> float:
                c = math.cos(a)
                return (xc * xc * (-c) + 2 * xc * R * (a / 2 - math.sin(2 * a) / 4)
                        + R * R * (-c + c ** 3 / 3))
            total += -R * (F(a1) - F(a0))
    return math.pi * abs(total)


def _check_volume(vol: float, main: "_Chain", fit_tol: float, solid: Any = None) -> None:
    """The solid must be the revolution of its section: a last check that catches what the
    face classification might let through. The solid's volume is integrated adaptively
    (``vol``); should that disagree, the default Gauss rule (exact on analytic faces) and
    then the adaptive rule at 1e-10 (C0 B-spline faces) are asked too; any agreeing passes."""
    from . import occ
    v2 = revolved_volume(main.segs)
    rmax = max(sg.bbox()[2] for sg in main.segs)
    zs = [sg.bbox()[1] for sg in main.segs] + [sg.bbox()[3] for sg in main.segs]
    allowed = 1e-5 * vol + 1e-6
    if main.notes:  # fitted edges: each mm of fit tolerance is worth 2 pi r L of volume
        allowed += 2 * math.pi * rmax * (max(zs) - min(zs)) * fit_tol
    if abs(v2 - vol) > allowed and solid is not None:
        for other in (lambda: occ.volume(solid, adaptive=False),
                      lambda: occ.volume(solid, eps=1e-10)):
            if abs(v2 - other()) <= allowed:
                return
    if abs(v2 - vol) > allowed:
        raise ProfileError(f"not a body of revolution: the solid's volume {vol:.3f} mm^3 differs "
                           f"from the revolution of its section {v2:.3f} mm^3")


def _split(ch: list[Segment]) -> tuple[list[Segment], list[Segment] | None, list[Segment]]:
    """(outside, bore or None, left cavity) of a section boundary (see module docstring)."""
    if _signed_area(ch) < 0:
        ch = reverse_chain(ch)
    closed = dist(ch[-1].end, ch[0].start) <= JOIN_TOL
    loop: list[Any] = list(ch) + ([] if closed else [AXIS])
    n = len(loop)

    def start_of(i: int) -> Point:
        s = loop[i]
        return loop[i - 1].end if s is AXIS else s.start

    zs = [start_of(i)[1] for i in range(n)]
    zmax, zmin = max(zs), min(zs)
    right = min((i for i in range(n) if zs[i] >= zmax - 1e-7), key=lambda i: start_of(i)[0])
    left = min((i for i in range(n) if zs[i] <= zmin + 1e-7), key=lambda i: start_of(i)[0])
    # loop is counter-clockwise in the (z, r) view: from the right face it runs outward first
    outside = []
    i = right
    while i != left:
        if loop[i] is AXIS:
            raise ProfileError("cannot find the outside contour between the end faces")
        outside.append(loop[i])
        i = (i + 1) % n
    back = []
    while i != right:
        back.append(loop[i])
        i = (i + 1) % n
    # back runs from the left point around the bore side to the right point
    if AXIS in back:
        k = back.index(AXIS)
        left_cavity, bore_rev = back[:k], back[k + 1:]
    else:
        left_cavity, bore_rev = [], back
    bore = reverse_chain(bore_rev) if bore_rev else None
    return outside, bore, left_cavity


# ---------------------------------------------------------------------------- envelope
def _envelope_section(solid, bb, problems, fit_tol: float, notes: list[str]):
    """The first meridian half-plane whose outline (main chain) no non-turned face touches."""
    from . import occ
    bad = occ.face_compound([p.face for p in problems])
    for k in range(72):
        theta = THETA + k * 2 * math.pi / 72
        try:
            chains = _chains(occ.meridian_section(solid, theta, bb), fit_tol)
        except ProfileError:
            continue
        main = chains[0].segs
        bad_pts: list[Point] = []
        for e in occ.meridian_section(bad, theta, bb):
            for j in range(5):
                bad_pts.append(e.rz(e.first + (e.last - e.first) * j / 4))
        if any(min(s.distance_to(p) for s in main) < 1e-4 for p in bad_pts):
            continue
        notes.append(f"envelope taken in the meridian half-plane at {math.degrees(theta):.1f} deg")
        return chains, len(chains) - 1
    return _dominant_section(solid, bb, problems, bad, fit_tol, notes)


#: half-planes (evenly spaced) whose sections the chosen envelope section must contain
ENVELOPE_CHECKS = 36


def _region(chains: list["_Chain"]):
    """The section's region (shapely), outer loop closed along the axis, sampled within
    1e-4 mm."""
    from shapely.geometry import Polygon
    from ..geometry.primitives import sample_chain
    pts = sample_chain(chains[0].segs, 1e-4)
    return Polygon([(z, r) for r, z in pts]).buffer(0)


def _dominant_section(solid, bb, problems, bad, fit_tol: float, notes: list[str]):
    """Every half-plane cuts a non-turned face on the outline (a hex or square bar, a flat
    along the whole part): the turned envelope is then the section through the farthest
    points. Candidates are the half-planes through the vertices of the non-turned faces
    (for planar faces parallel to the axis, the distance from the axis at a given Z is
    largest at the face's edges, i.e. at the polygon's corners); the one whose section
    contains the sections of all the others and of ``ENVELOPE_CHECKS`` evenly spaced
    half-planes (checked on polylines within 1e-4 mm) is taken. When none does (the
    envelope is the union of several sections), ProfileError says so."""
    from . import occ
    angles: list[float] = []
    for f in (p.face for p in problems):
        for x, y, _z in occ.vertex_points(f):
            if math.hypot(x, y) > 1e-6:
                a = math.atan2(y, x) % (2 * math.pi)
                a = 0.0 if a > 2 * math.pi - 1e-9 else a
                if all(abs(a - b) > 1e-7 and abs(abs(a - b) - 2 * math.pi) > 1e-7 for b in angles):
                    angles.append(a)
    checks = [THETA + k * 2 * math.pi / ENVELOPE_CHECKS for k in range(ENVELOPE_CHECKS)]
    sections: dict[float, tuple[list[_Chain], Any]] = {}
    for theta in angles + checks:
        try:
            chains = _chains(occ.meridian_section(solid, theta, bb), fit_tol)
        except ProfileError:
            continue
        sections[theta] = (chains, _region(chains))
    cands = sorted((a for a in angles if a in sections),
                   key=lambda a: (-round(sections[a][1].area, 6), a))
    for a in cands:
        grown = sections[a][1].buffer(1e-4)
        if all(reg.difference(grown).area < 1e-6 for _, reg in sections.values()):
            notes.append(f"envelope taken in the meridian half-plane at {math.degrees(a):.1f} deg "
                         f"(through a corner of the non-turned faces): its section contains the "
                         f"sections in {len(sections) - 1} other half-planes")
            return sections[a][0], len(sections[a][0]) - 1
    raise ProfileError("envelope: every meridian half-plane cuts a non-turned face on the "
                       "outline and no single section through a corner of those faces "
                       f"contains the others ({len(cands)} tried): the turned envelope is the "
                       "union of several sections, which is not supported; profile the "
                       "turned part without the milled features")
