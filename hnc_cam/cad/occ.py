"""The thin layer over OCP (OpenCascade): shapes from every front end, file reading,
axis placement, face classification and the meridian section.

Everything that touches OCP lives here, so the rest of :mod:`hnc_cam.cad` reads like
geometry. OCP is imported when this module is imported; :mod:`hnc_cam.cad` imports it lazily.
"""
from __future__ import annotations

import contextlib
import ctypes
import math
import os
import re
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator

from OCP.BRep import BRep_Builder, BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.BRepAlgoAPI import BRepAlgoAPI_Section
from OCP.BRepBndLib import BRepBndLib
from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeVertex,
                                BRepBuilderAPI_Transform)
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
from OCP.BRepGProp import BRepGProp
from OCP.BRepLProp import BRepLProp_SLProps
from OCP.BRepTools import BRepTools
from OCP.Bnd import Bnd_Box
from OCP.GeomAbs import (GeomAbs_Circle, GeomAbs_Cone, GeomAbs_Cylinder, GeomAbs_Line,
                         GeomAbs_Plane, GeomAbs_Sphere, GeomAbs_SurfaceOfRevolution,
                         GeomAbs_Torus)
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_SHELL, TopAbs_SOLID, TopAbs_VERTEX
from OCP.TopExp import TopExp
from OCP.TopTools import TopTools_IndexedMapOfShape
from OCP.TopoDS import TopoDS, TopoDS_Compound, TopoDS_Face, TopoDS_Shape
from OCP.gp import gp_Ax1, gp_Ax3, gp_Dir, gp_Pln, gp_Pnt, gp_Trsf, gp_Vec

from ..errors import ProfileError


def _quick_exit() -> None:
    """At the exit of a process that imported the CAD kernel: the objects alive then are
    frozen out of the cyclic collector, whose passes over the kernel's hundreds of thousands
    of objects while the interpreter tears the modules down took most of a second (seconds
    on a busy machine) of every ``generate``/``verify`` command."""
    import gc
    gc.freeze()


import atexit  # noqa: E402

atexit.register(_quick_exit)

#: angular tolerance for "parallel to / perpendicular to the axis" (radians)
ANG_TOL = 1e-6
#: distance tolerance for "on the axis" (mm)
POS_TOL = 1e-5

_SURF_NAMES = {
    GeomAbs_Plane: "planar", GeomAbs_Cylinder: "cylindrical", GeomAbs_Cone: "conical",
    GeomAbs_Sphere: "spherical", GeomAbs_Torus: "toroidal",
    GeomAbs_SurfaceOfRevolution: "revolved",
}


# ---------------------------------------------------------------------------- input
@contextlib.contextmanager
def _captured_output():
    """Catch what OpenCascade prints (on the process's stdout and stderr file descriptors,
    below Python) while reading a file: stdout stays the program or pure JSON. Yields a
    one-item list that holds the captured text afterwards."""
    said = [""]
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except (OSError, ValueError):
        pass
    saved = []
    try:
        tmp = tempfile.TemporaryFile()
        for fd in (1, 2):
            saved.append((fd, os.dup(fd)))
            os.dup2(tmp.fileno(), fd)
    except OSError:  # no descriptors to spare: read without capturing
        for fd, old in saved:
            os.dup2(old, fd)
            os.close(old)
        yield said
        return
    try:
        yield said
    finally:
        try:
            ctypes.CDLL(None).fflush(None)  # the C library's buffers, before the switch back
        except (OSError, AttributeError):
            pass
        for fd, old in saved:
            os.dup2(old, fd)
            os.close(old)
        tmp.seek(0)
        said[0] = tmp.read(1 << 20).decode("utf-8", "replace")
        tmp.close()


def _step_error(p: Path, said: str) -> str:
    """One line from OpenCascade's STEP parser messages: the file, the line, the reason."""
    text = re.sub(r"\x1b\[[0-9;]*m", "", said)
    m = re.search(r"Line\s*(\d+)\s*:\s*(.*?)\s*\*{2,}", text) or \
        re.search(r"Line\s*(\d+)\s*:\s*([^\n]*)", text)
    if m:
        why = m.group(2).strip().rstrip("*").strip()
        return f"{p}:{m.group(1)}: not a readable STEP file: {why}"
    return f"{p}: not a readable STEP file"


def read_file(path: str | Path) -> TopoDS_Shape:
    """Read a .step/.stp or .brep file into one shape (ProfileError on failure)."""
    p = Path(path)
    if not p.exists():
        raise ProfileError(f"{p}: no such file")
    ext = p.suffix.lower()
    if ext in (".step", ".stp"):
        r = STEPControl_Reader()
        with _captured_output() as said:
            status = r.ReadFile(str(p))
            if status == IFSelect_RetDone:
                r.TransferRoots()
                shape = r.OneShape()
        if status != IFSelect_RetDone:
            raise ProfileError(_step_error(p, said[0]))
        if shape is None or shape.IsNull():
            raise ProfileError(f"{p}: the STEP file holds no shape")
        return shape
    if ext == ".brep":
        shape = TopoDS_Shape()
        ok = BRepTools.Read_s(shape, str(p), BRep_Builder())
        if not ok or shape.IsNull():
            raise ProfileError(f"{p}: not a readable BREP file")
        return shape
    raise ProfileError(f"{p}: unknown CAD file type {ext!r} (expected .step, .stp or .brep)")


def to_shape(obj: Any) -> TopoDS_Shape:
    """An OCP shape from a build123d/CadQuery object, an OCP shape or a file path."""
    from .sketch import Revolved
    if type(obj) is Revolved:  # the solid revolve() would have made, made now
        obj = obj.solid()
    if isinstance(obj, (str, Path)):
        return read_file(obj)
    if isinstance(obj, TopoDS_Shape):
        return obj
    # build123d BuildPart (builder): its result is .part
    if hasattr(obj, "part") and not hasattr(obj, "wrapped") and hasattr(obj, "builder_parent"):
        obj = obj.part
    # CadQuery Workplane: its objects (solids) on the stack; when the stack holds no solid
    # (a chain ending in .faces(...) or .workplane()), the solid the chain carries
    if hasattr(obj, "vals") and hasattr(obj, "objects") and not hasattr(obj, "wrapped"):
        vals = [v for v in obj.vals() if hasattr(v, "wrapped")]
        if not any(solids(v.wrapped) for v in vals) and hasattr(obj, "findSolid"):
            try:
                found = obj.findSolid()
            except ValueError:
                found = None
            if found is not None and hasattr(found, "wrapped"):
                vals = [found]
        if not vals:
            raise ProfileError("the CadQuery Workplane holds no shape")
        if len(vals) == 1:
            return vals[0].wrapped
        return compound([v.wrapped for v in vals])
    w = getattr(obj, "wrapped", None)
    if isinstance(w, TopoDS_Shape):
        return w
    if isinstance(obj, (list, tuple)) and obj and all(hasattr(o, "wrapped") for o in obj):
        return compound([o.wrapped for o in obj])
    raise ProfileError(f"cannot profile a {type(obj).__name__}: expected a build123d or CadQuery "
                       f"shape, an OCP TopoDS_Shape or a .step/.stp/.brep path")


def compound(shapes: list[TopoDS_Shape]) -> TopoDS_Compound:
    c = TopoDS_Compound()
    b = BRep_Builder()
    b.MakeCompound(c)
    for s in shapes:
        b.Add(c, s)
    return c


def axis_transform(shape: TopoDS_Shape, axis: Any) -> TopoDS_Shape:
    """The shape in a frame whose Z axis is the turning axis.

    ``axis``: "Z" (default), "X", "Y" (the model axes through the origin; a leading "-"
    flips the direction) or ``((px, py, pz), (dx, dy, dz))``.
    """
    if isinstance(axis, str):
        a = axis.strip().upper()
        sign = -1.0 if a.startswith("-") else 1.0
        a = a.lstrip("+-")
        dirs = {"X": (1, 0, 0), "Y": (0, 1, 0), "Z": (0, 0, 1)}
        if a not in dirs:
            raise ProfileError(f"axis {axis!r}: expected X, Y, Z or ((px,py,pz),(dx,dy,dz))")
        origin, d = (0.0, 0.0, 0.0), tuple(sign * v for v in dirs[a])
    else:
        try:
            origin, d = tuple(map(float, axis[0])), tuple(map(float, axis[1]))
            assert len(origin) == 3 and len(d) == 3 and math.hypot(*d) > 0
        except Exception:
            raise ProfileError(f"axis {axis!r}: expected X, Y, Z or ((px,py,pz),(dx,dy,dz))") from None
    if origin == (0.0, 0.0, 0.0) and d == (0, 0, 1):
        return shape
    t = gp_Trsf()
    t.SetTransformation(gp_Ax3(gp_Pnt(*origin), gp_Dir(*d)))
    return BRepBuilderAPI_Transform(shape, t, True).Shape()


def to_model(shape_axis: Any, p: tuple[float, float, float]) -> tuple[float, float, float]:
    """A point of the turning frame (see :func:`axis_transform`) back in model coordinates."""
    a = shape_axis
    if isinstance(a, str):
        s = a.strip().upper()
        sign = -1.0 if s.startswith("-") else 1.0
        d = {"X": (1, 0, 0), "Y": (0, 1, 0), "Z": (0, 0, 1)}[s.lstrip("+-")]
        origin, d = (0.0, 0.0, 0.0), tuple(sign * v for v in d)
    else:
        origin, d = tuple(map(float, a[0])), tuple(map(float, a[1]))
    if origin == (0.0, 0.0, 0.0) and d == (0, 0, 1):
        return p
    t = gp_Trsf()
    t.SetTransformation(gp_Ax3(gp_Pnt(*origin), gp_Dir(*d)))
    q = gp_Pnt(*p).Transformed(t.Inverted())
    return (q.X(), q.Y(), q.Z())


# ---------------------------------------------------------------------------- topology
def sub_shapes(shape: TopoDS_Shape, kind) -> Iterator[TopoDS_Shape]:
    """The distinct sub-shapes of a kind (each shared face/edge once)."""
    m = TopTools_IndexedMapOfShape()
    TopExp.MapShapes_s(shape, kind, m)
    for i in range(1, m.Extent() + 1):
        yield m.FindKey(i)


def solids(shape: TopoDS_Shape) -> list[TopoDS_Shape]:
    return [TopoDS.Solid_s(s) for s in sub_shapes(shape, TopAbs_SOLID)]


def faces(shape: TopoDS_Shape) -> list[TopoDS_Shape]:
    return [TopoDS.Face_s(s) for s in sub_shapes(shape, TopAbs_FACE)]


def vertex_points(shape: TopoDS_Shape) -> list[tuple[float, float, float]]:
    """The points of the shape's distinct vertices."""
    out = []
    for v in sub_shapes(shape, TopAbs_VERTEX):
        p = BRep_Tool.Pnt_s(TopoDS.Vertex_s(v))
        out.append((p.X(), p.Y(), p.Z()))
    return out


def shells(shape: TopoDS_Shape) -> list[TopoDS_Shape]:
    return list(sub_shapes(shape, TopAbs_SHELL))


def bbox(shape: TopoDS_Shape) -> tuple[float, float, float, float, float, float]:
    b = Bnd_Box()
    BRepBndLib.Add_s(shape, b, False)
    if b.IsVoid():
        raise ProfileError("empty geometry: the shape has no extent")
    return b.Get()


def volume(shape: TopoDS_Shape, adaptive: bool = True, eps: float = 1e-7) -> float:
    """Volume (mm^3). ``adaptive``: adaptive integration to a (requested) relative error of
    ``eps`` (the default Gauss rule is off by ~1% on B-spline faces; at 1e-7 the adaptive
    rule is still off by 2e-5 on a revolved degree-1 B-spline, right at 1e-10); else the
    default Gauss rule, exact to rounding on planes, cones, spheres and tori, where the
    adaptive one is sometimes off by 1e-5 (a revolved chain of tangent tori)."""
    g = GProp_GProps()
    if adaptive:
        BRepGProp.VolumeProperties_s(shape, g, eps)
    else:
        BRepGProp.VolumeProperties_s(shape, g)
    return g.Mass()


# ---------------------------------------------------------------------------- validation
@dataclass(frozen=True)
class FaceProblem:
    """A face that is not a surface of revolution about the turning axis."""
    face: Any
    kind: str      # e.g. "planar face parallel to the axis"
    feature: str   # what it probably is: "flat/keyway/hex", "cross hole", ...
    where: tuple[float, float, float]  # a point on the face (turning frame, mm)
    model: tuple[float, float, float] | None = None  # the same point in model coordinates

    def describe(self) -> str:
        x, y, z = self.model or self.where
        return (f"{self.kind} ({self.feature}) at x={x:.3f} y={y:.3f} z={z:.3f} (model), "
                f"radius {math.hypot(self.where[0], self.where[1]):.3f} from the axis")


def _coaxial(ax: gp_Ax1) -> tuple[bool, bool]:
    """(direction parallel to Z, line through the Z axis)."""
    d = ax.Direction()
    par = abs(abs(d.Z()) - 1.0) < ANG_TOL
    p = ax.Location()
    if par:
        on = math.hypot(p.X(), p.Y()) < POS_TOL
    else:
        on = False
    return par, on


def _face_centre(face) -> tuple[float, float, float]:
    g = GProp_GProps()
    BRepGProp.SurfaceProperties_s(face, g)
    c = g.CentreOfMass()
    return (c.X(), c.Y(), c.Z())


def _min_radius(ad: BRepAdaptor_Surface, n: int = 12) -> float:
    """Smallest distance from the Z axis over an n x n grid of the face's (u, v) box."""
    u0, u1 = ad.FirstUParameter(), ad.LastUParameter()
    v0, v1 = ad.FirstVParameter(), ad.LastVParameter()
    best = math.inf
    for i in range(n + 1):
        for j in range(n + 1):
            p = ad.Value(u0 + (u1 - u0) * i / n, v0 + (v1 - v0) * j / n)
            best = min(best, math.hypot(p.X(), p.Y()))
    return best


def _name_flats(problems: list[FaceProblem],
                flats: list[tuple[int, tuple[float, float], float]]) -> None:
    """Name groups of planar faces parallel to the axis: a hex or a square (equal flats at
    60 or 90 deg), a keyway or slot (two opposite walls, with its bottom), else a flat."""
    named: dict[int, str] = {}
    for k, (i, n, c) in enumerate(flats):
        if i in named:
            continue
        for count, step, what in ((6, 60.0, "hex"), (4, 90.0, "square")):
            group = [j for j, m, d in flats if abs(abs(d) - abs(c)) < POS_TOL
                     and _angle_mod(_ang(m) - _ang(n), step) < 1e-4]
            if len(group) >= count:
                for j in group:
                    named[j] = f"a {what}, {2 * abs(c):.3f} across flats"
                break
    for a, (i, n, c) in enumerate(flats):
        for j, m, d in flats[a + 1:]:
            if i in named or j in named:
                continue
            dot = n[0] * m[0] + n[1] * m[1]
            if abs(abs(dot) - 1.0) > 1e-6:
                continue
            width = abs(c - d) if dot > 0 else abs(c + d)  # distance between the planes
            bottoms = [q for q, o, e in flats if q not in named and q not in (i, j)
                       and abs(o[0] * n[0] + o[1] * n[1]) < 1e-6]
            if bottoms:
                named[i] = named[j] = f"a wall of a keyway or slot {width:.3f} wide"
                for q in bottoms:
                    e = next(e for qq, _, e in flats if qq == q)
                    named[q] = (f"the bottom of a keyway or slot {width:.3f} wide, "
                                f"{abs(e):.3f} from the axis")
            else:
                named[i] = named[j] = f"two parallel flats {width:.3f} apart"
    for i, n, c in flats:
        feat = named.get(i, f"a flat {abs(c):.3f} from the axis")
        p = problems[i]
        problems[i] = FaceProblem(p.face, p.kind, feat, p.where)


def _ang(n: tuple[float, float]) -> float:
    return math.degrees(math.atan2(n[1], n[0]))


def _angle_mod(a: float, step: float) -> float:
    """Distance of angle ``a`` (deg) from the nearest multiple of ``step``."""
    r = a % step
    return min(r, step - r)


def _sampled_revolution(ad: BRepAdaptor_Surface, n: int = 5) -> bool:
    """True when the surface normal lies in the meridian plane at n x n sample points (a
    surface of revolution about Z, e.g. a B-spline surface written by another CAD system)."""
    u0, u1 = ad.FirstUParameter(), ad.LastUParameter()
    v0, v1 = ad.FirstVParameter(), ad.LastVParameter()
    for i in range(n):
        for j in range(n):
            u = u0 + (u1 - u0) * (i + 0.5) / n
            v = v0 + (v1 - v0) * (j + 0.5) / n
            props = BRepLProp_SLProps(ad, u, v, 1, 1e-9)
            if not props.IsNormalDefined():
                continue
            p, nv = props.Value(), props.Normal()
            r = math.hypot(p.X(), p.Y())
            if r < 1e-6:
                continue
            et = (-p.Y() / r, p.X() / r)
            if abs(nv.X() * et[0] + nv.Y() * et[1]) > 1e-5:
                return False
    return True


def classify_faces(shape: TopoDS_Shape) -> tuple[list[FaceProblem], list[str]]:
    """Check that every face is a surface of revolution about the Z axis.

    Returns the problems (faces that are not) and notes (faces accepted only by sampling).
    Accepted: planes perpendicular to the axis; cylinders, cones, tori and revolved surfaces
    coaxial with it; spheres centred on it; any other surface whose normal lies in the
    meridian plane everywhere (checked on a 5 x 5 grid).
    """
    problems: list[FaceProblem] = []
    notes: list[str] = []
    sampled: list[float] = []
    flats: list[tuple[int, tuple[float, float], float]] = []  # (index, normal, n . location)
    for f in faces(shape):
        ad = BRepAdaptor_Surface(f, True)
        t = ad.GetType()
        name = _SURF_NAMES.get(t, "free-form")
        if t == GeomAbs_Plane:
            n = ad.Plane().Axis().Direction()
            if abs(abs(n.Z()) - 1.0) < ANG_TOL:
                continue
            if abs(n.Z()) < ANG_TOL:
                loc = ad.Plane().Location()
                flats.append((len(problems), (n.X(), n.Y()), n.X() * loc.X() + n.Y() * loc.Y()))
                problems.append(FaceProblem(f, "planar face parallel to the axis",
                                            "a flat, keyway, slot or hex", _face_centre(f)))
            else:
                problems.append(FaceProblem(f, "planar face oblique to the axis",
                                            "a bevel or cut not turned about the axis",
                                            _face_centre(f)))
            continue
        if t in (GeomAbs_Cylinder, GeomAbs_Cone, GeomAbs_Torus, GeomAbs_SurfaceOfRevolution):
            if t == GeomAbs_Cylinder:
                ax = ad.Cylinder().Axis()
            elif t == GeomAbs_Cone:
                ax = ad.Cone().Axis()
            elif t == GeomAbs_Torus:
                ax = ad.Torus().Axis()
            else:
                ax = ad.AxeOfRevolution()
            par, on = _coaxial(ax)
            if par and on:
                continue
            if t == GeomAbs_Cylinder:
                r = ad.Cylinder().Radius()
                if not par and abs(ax.Direction().Z()) < ANG_TOL:
                    if _min_radius(ad) <= r + POS_TOL:
                        feat = f"a cross hole or cross pin of diameter {2 * r:.3f}"
                    else:
                        feat = (f"a radial hole or the round end of a keyway or slot, "
                                f"diameter {2 * r:.3f}")
                elif par:
                    p = ax.Location()
                    feat = (f"an off-axis (eccentric) cylinder or axial hole of diameter "
                            f"{2 * r:.3f}, axis {math.hypot(p.X(), p.Y()):.3f} mm off centre")
                else:
                    feat = f"an inclined hole or boss of diameter {2 * r:.3f}"
                problems.append(FaceProblem(f, f"cylindrical face not coaxial with the axis",
                                            feat, _face_centre(f)))
            else:
                problems.append(FaceProblem(f, f"{name} face not coaxial with the axis",
                                            "an off-axis feature", _face_centre(f)))
            continue
        if t == GeomAbs_Sphere:
            c = ad.Sphere().Location()
            if math.hypot(c.X(), c.Y()) < POS_TOL:
                continue
            problems.append(FaceProblem(f, "spherical face not centred on the axis",
                                        "an off-axis feature", _face_centre(f)))
            continue
        if _sampled_revolution(ad):
            sampled.append(_face_centre(f)[2])
            continue
        problems.append(FaceProblem(f, f"{name} face that is not a surface of revolution",
                                    "a milled or free-form feature", _face_centre(f)))
    _name_flats(problems, flats)
    if sampled:
        notes.append(f"{len(sampled)} free-form (e.g. B-spline) face(s) accepted as surfaces of "
                     f"revolution by sampling their normals (model z "
                     f"{', '.join(f'{z:.3f}' for z in sorted(sampled, reverse=True))})")
    return problems, notes


def common_axis(shape: TopoDS_Shape) -> tuple[tuple[float, float, float],
                                              tuple[float, float, float]] | None:
    """The one axis every cylindrical, conical and toroidal face of the shape is about
    (point nearest the origin, unit direction), when there is such an axis and at least one
    such face, else None: a hint for a turned part modelled along another axis."""
    axes = []
    for f in faces(shape):
        ad = BRepAdaptor_Surface(f, True)
        t = ad.GetType()
        if t == GeomAbs_Cylinder:
            axes.append(ad.Cylinder().Axis())
        elif t == GeomAbs_Cone:
            axes.append(ad.Cone().Axis())
        elif t == GeomAbs_Torus:
            axes.append(ad.Torus().Axis())
    if not axes:
        return None
    a0 = axes[0]
    d0, p0 = a0.Direction(), a0.Location()
    for a in axes[1:]:
        d, p = a.Direction(), a.Location()
        if abs(abs(d.X() * d0.X() + d.Y() * d0.Y() + d.Z() * d0.Z()) - 1.0) > ANG_TOL:
            return None
        v = gp_Vec(p0, p)
        if v.Crossed(gp_Vec(d0)).Magnitude() > POS_TOL:
            return None
    d = (d0.X(), d0.Y(), d0.Z())
    k = max(range(3), key=lambda i: abs(d[i]))
    if d[k] < 0:
        d = (-d[0], -d[1], -d[2])
    t = p0.X() * d[0] + p0.Y() * d[1] + p0.Z() * d[2]
    q = (p0.X() - t * d[0], p0.Y() - t * d[1], p0.Z() - t * d[2])
    clean = lambda v: 0.0 if abs(v) < 1e-9 else round(v, 6)  # noqa: E731
    return tuple(map(clean, q)), tuple(map(clean, d))


# ---------------------------------------------------------------------------- section
@dataclass
class SectionEdge:
    """One edge of the meridian section, as a curve in (radius, Z)."""
    kind: str  # "line" | "circle" | "other"
    curve_type: str
    first: float
    last: float
    adaptor: Any
    u: tuple[float, float]  # unit direction of the half-plane (x, y)
    tolerance: float = 0.0  # the edge's own tolerance (how far it may be from the true cut)
    projector: Any = None  # GeomAPI_ProjectPointOnSurf on the face the edge was cut from

    def rz(self, t: float) -> tuple[float, float]:
        """Point at parameter t. For a free-form edge (which OpenCascade approximates, to
        ~1e-5 mm) the point is projected onto the face it was cut from: the nearest point of
        a surface of revolution to a point of a meridian half-plane lies in that half-plane,
        so this is the exact cut."""
        p = self.adaptor.Value(t)
        if self.projector is not None:
            p = self._project(p)
        return (p.X() * self.u[0] + p.Y() * self.u[1], p.Z())

    def _project(self, p: gp_Pnt) -> gp_Pnt:
        pr = self.projector
        pr.Perform(p)
        if pr.IsDone() and pr.NbPoints() > 0 and pr.LowerDistance() <= max(1e-3, 10 * self.tolerance):
            return pr.NearestPoint()
        return p

    def rz_d1(self, t: float):
        p = gp_Pnt()
        v = gp_Vec()
        self.adaptor.D1(t, p, v)
        if self.projector is not None:
            p = self._project(p)
        return ((p.X() * self.u[0] + p.Y() * self.u[1], p.Z()),
                (v.X() * self.u[0] + v.Y() * self.u[1], v.Z()))

    def circle(self) -> tuple[tuple[float, float], float]:
        c = self.adaptor.Circle()
        loc = c.Location()
        return (loc.X() * self.u[0] + loc.Y() * self.u[1], loc.Z()), c.Radius()


def _projector(face) -> Any:
    surf = BRep_Tool.Surface_s(face)
    ad = BRepAdaptor_Surface(face, True)
    pr = GeomAPI_ProjectPointOnSurf()
    pr.Init(surf, ad.FirstUParameter(), ad.LastUParameter(), ad.FirstVParameter(),
            ad.LastVParameter(), 1e-9)
    return pr


def _source_face(sec: BRepAlgoAPI_Section, edge, shape: TopoDS_Shape, ad: BRepAdaptor_Curve):
    """The face of ``shape`` a section edge was cut from."""
    f = TopoDS_Face()
    if sec.HasAncestorFaceOn1(edge, f) and not f.IsNull():
        return TopoDS.Face_s(f)
    mid = BRepBuilderAPI_MakeVertex(ad.Value((ad.FirstParameter() + ad.LastParameter()) / 2)).Vertex()
    best, best_d = None, math.inf
    for fc in faces(shape):
        d = BRepExtrema_DistShapeShape(mid, fc)
        if d.IsDone() and d.Value() < best_d:
            best, best_d = fc, d.Value()
    return best


def meridian_section(shape: TopoDS_Shape, theta: float,
                     bb: tuple[float, float, float, float, float, float]) -> list[SectionEdge]:
    """Edges of the intersection of the shape's boundary with the half-plane through the Z
    axis at polar angle ``theta`` (radians from +X toward +Y)."""
    rmax = max(abs(v) for v in (bb[0], bb[1], bb[3], bb[4])) * 1.5 + 10.0
    zlo, zhi = bb[2] - 10.0, bb[5] + 10.0
    ux, uy = math.cos(theta), math.sin(theta)
    ax3 = gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(uy, -ux, 0), gp_Dir(ux, uy, 0))  # v along +Z
    face = BRepBuilderAPI_MakeFace(gp_Pln(ax3), 0.0, rmax, zlo, zhi).Face()
    sec = BRepAlgoAPI_Section(shape, face, False)
    sec.Approximation(True)
    sec.ComputePCurveOn1(False)
    sec.Build()
    if not sec.IsDone():
        raise ProfileError("the meridian section of the solid failed (invalid geometry?)")
    out: list[SectionEdge] = []
    for e in sub_shapes(sec.Shape(), TopAbs_EDGE):
        edge = TopoDS.Edge_s(e)
        ad = BRepAdaptor_Curve(edge)
        t = ad.GetType()
        kind = "line" if t == GeomAbs_Line else "circle" if t == GeomAbs_Circle else "other"
        proj = None
        if kind == "other":
            src = _source_face(sec, edge, shape, ad)
            proj = _projector(src) if src is not None else None
        out.append(SectionEdge(kind, str(t).split(".")[-1].replace("GeomAbs_", ""),
                               ad.FirstParameter(), ad.LastParameter(), ad, (ux, uy),
                               BRep_Tool.Tolerance_s(edge), proj))
    return out


def face_compound(fs: list) -> TopoDS_Compound:
    return compound(list(fs))
