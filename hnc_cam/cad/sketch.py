"""Helpers for part authors: write the half-section of a turned part as exact lines and arcs
in (radius, Z), with chamfers and fillets at line-line corners, and revolve it.

    s = Outline((0, 0))                       # start on the axis at the right face
    s.line_to(9, 0, chamfer=1)                # corner at (9, 0) gets a 1 mm chamfer
    s.line_to(9, -20, fillet=0.5)             # corner at (9, -20) gets an R0.5 fillet
    s.line_to(15, -20)
    s.arc_to(15, -30, radius=5, cw=True)      # G02-sense arc (view Z right, X up)
    s.line_to(15, -40)
    s.line_to(0, -40)                         # back to the axis: the left face
    segs = s.segments()                       # list[Line | Arc]
    solid = revolve(segs)                     # build123d Solid about the Z axis

The same segment list is what :func:`hnc_cam.cad.profile` returns for the revolved solid
(after merging), which is how ``tests/test_parts.py`` checks each family.

Conventions: points are (radius, Z); the outline either starts and ends on the axis (a solid
part, closed along the axis) or is a closed loop (a part with a through bore). Chamfers are
equal-leg (``c`` along each of the two lines), fillets are tangent arcs; both only at corners
between two lines.

Parameter checks: a family's ``part()`` must refuse a parameter set that makes an impossible
part with a :class:`SketchError` (a :class:`~hnc_cam.errors.PartError`) naming the
parameters, never an OpenCascade exception or a silently different part. :func:`positive`,
:func:`non_negative` and :func:`require` say it in one line each; a corner that does not fit
(a chamfer or fillet longer than a line it sits on) raises from :meth:`Outline.line_to`,
naming the parameters passed as ``names``.
"""
from __future__ import annotations

import math
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, Iterator, Sequence

from ..errors import PartError
from ..geometry.corner import CornerError
from ..geometry.corner import corner as _corner
from ..geometry.primitives import Arc, Line, Point, Segment, dist


class SketchError(PartError, ValueError):
    """A parameter set that makes an impossible part (the message names the parameters).
    A :class:`PartError` (exit 2 through the CLI) and, for older callers, a ValueError."""


def _g(v: float) -> str:
    return f"{v:.3f}".rstrip("0").rstrip(".")


def require(condition: bool, message: str) -> None:
    """Raise :class:`SketchError` with ``message`` unless ``condition``."""
    if not condition:
        raise SketchError(message)


def positive(**params: float) -> None:
    """Every given parameter must be a positive number (``positive(length=length, d1=d1)``)."""
    for k, v in params.items():
        require(v > 0, f"{k}={_g(v)} must be positive")


def non_negative(**params: float) -> None:
    """Every given parameter must be >= 0 (chamfers, fillets: 0 means none)."""
    for k, v in params.items():
        require(v >= 0, f"{k}={_g(v)} must not be negative (0 means none)")


class Outline:
    """Builds a chain of exact Line/Arc segments with optional corner chamfers/fillets."""

    def __init__(self, start: Point):
        self._segs: list[Segment] = []
        self._pos: Point = (float(start[0]), float(start[1]))
        self._corner: tuple[str, float, str] | None = None

    @property
    def pos(self) -> Point:
        return self._pos

    def line_to(self, x: float, z: float, chamfer: float = 0.0, fillet: float = 0.0,
                names: str = "") -> "Outline":
        """Line to (x, z); ``chamfer``/``fillet`` apply at (x, z) with the next segment.
        ``names``: the family parameters that size this corner and its lines, for the error
        raised when the corner does not fit (e.g. ``"fillet, d1, d2"``)."""
        end = (float(x), float(z))
        if dist(self._pos, end) < 1e-12:
            raise SketchError(f"zero-length line at (r={_g(end[0])}, z={_g(end[1])})"
                              + (f" (parameters {names})" if names else ""))
        if chamfer < 0 or fillet < 0:
            raise SketchError(f"negative {'chamfer' if chamfer < 0 else 'fillet'} at "
                              f"(r={_g(end[0])}, z={_g(end[1])})"
                              + (f" (parameters {names})" if names else ""))
        self._add(Line(self._pos, end))
        self._corner = (("C", chamfer, names) if chamfer > 0 else ("R", fillet, names)
                        if fillet > 0 else None)
        return self

    def arc_to(self, x: float, z: float, radius: float | None = None, cw: bool = True,
               center: Point | None = None) -> "Outline":
        """Arc to (x, z): either about ``center`` or with ``radius`` (> 0 the short arc,
        < 0 the long one), clockwise (G02 sense) when ``cw``."""
        end = (float(x), float(z))
        if center is not None:
            arc = Arc(self._pos, end, (float(center[0]), float(center[1])), cw)
            if abs(dist(arc.center, end) - arc.radius) > 1e-9:
                raise SketchError(f"arc end {end} is not on the circle about {center}")
        elif radius is not None:
            arc = Arc.from_radius(self._pos, end, radius, cw)
        else:
            raise SketchError("arc_to needs radius or center")
        self._add(arc)
        self._corner = None
        return self

    def _add(self, seg: Segment) -> None:
        if self._corner and self._segs and isinstance(self._segs[-1], Line) and isinstance(seg, Line):
            kind, size, names = self._corner
            prev = self._segs.pop()
            a, b, mid = corner(prev, seg, kind, size, names)
            self._segs += [a, mid]
            seg = b
        elif self._corner:
            raise SketchError("chamfers and fillets are supported only between two lines")
        self._segs.append(seg)
        self._pos = seg.end

    def close(self) -> "Outline":
        """Close a loop back to the start point with a line (a part with a bore)."""
        start = self._segs[0].start
        if dist(self._pos, start) > 1e-12:
            self.line_to(*start)
        return self

    def segments(self) -> list[Segment]:
        if self._corner:
            raise SketchError("a chamfer/fillet at the last point has no next segment")
        return list(self._segs)


def corner(l1: Line, l2: Line, kind: str, size: float,
           names: str = "") -> tuple[Line, Line, Segment]:
    """Trim the corner l1.end == l2.start with a chamfer ("C", equal legs) or a fillet ("R").
    Returns (l1 trimmed, l2 trimmed, the corner segment). ``names``: the parameters to blame
    when it does not fit."""
    c = l1.end
    what = "chamfer" if kind == "C" else "fillet"
    where = f"(r={_g(c[0])}, z={_g(c[1])})"
    blame = f" (parameters {names})" if names else ""
    try:
        k = _corner(l1.start, c, l2.end, kind, size)
    except CornerError:
        raise SketchError(f"no corner for a {what} at {where}: the lines are collinear{blame}") from None
    t = k.trim
    if t >= l1.length - 1e-12 or t >= l2.length - 1e-12:
        raise SketchError(f"{what} {_g(size)} at {where} does not fit: it needs {_g(t)} mm of "
                          f"each line but they are {_g(l1.length)} and {_g(l2.length)} mm long "
                          f"(what is left of them after the neighbouring corners){blame}")
    p1, p2 = k.start, k.end
    mid: Segment = k.segment()
    return Line(l1.start, p1), Line(p2, l2.end), mid


def _arc_mid(a: Arc) -> Point:
    return a.point_at(0.5)


def closed_outline(segs: Sequence[Segment]) -> list[Segment]:
    """The segments plus the closing line along the axis when the outline is open."""
    segs = list(segs)
    if dist(segs[-1].end, segs[0].start) > 1e-9:
        if abs(segs[0].start[0]) > 1e-9 or abs(segs[-1].end[0]) > 1e-9:
            raise SketchError("an open outline must start and end on the axis (x = 0)")
        segs.append(Line(segs[-1].end, segs[0].start))
    return segs


#: the outline each solid made by :func:`revolve` was revolved from, by ``id`` of the
#: build123d object: (a weak reference to it, a copy of its ``TopoDS_Shape`` as made, the
#: segments); an entry leaves with its object
_REVOLVED: dict[int, tuple[Any, Any, tuple[Segment, ...]]] = {}


def _forget(key: int, ref: Any) -> None:
    entry = _REVOLVED.get(key)
    if entry is not None and entry[0] is ref:
        del _REVOLVED[key]


def _record(obj: Any, segs: Sequence[Segment]) -> None:
    """Note on ``obj`` (the solid :func:`revolve` returns) the exact segments it was revolved
    from, with a copy of its shape handle as made: same TShape, location and orientation."""
    import weakref
    try:
        w = obj.wrapped
        made = w.Located(w.Location())
        key = id(obj)
        ref = weakref.ref(obj, lambda r, k=key: _forget(k, r))
    except (AttributeError, TypeError):  # pragma: no cover - not a build123d shape
        return
    _REVOLVED[key] = (ref, made, tuple(segs))


def revolved_outline(obj: Any) -> list[Segment] | None:
    """The exact segments :func:`revolve` revolved into ``obj``, when ``obj`` is the very
    object it returned and its shape is still the one it made (``TopoDS_Shape.IsEqual``: the
    same TShape, location and orientation), or a :class:`Revolved` not made yet; None
    otherwise (a solid moved, located or reoriented in place, a copy, a boolean, a mirror,
    any other object: profile those from the solid)."""
    if type(obj) is Revolved:
        made = object.__getattribute__(obj, "_solid")
        if made is None:
            return list(object.__getattribute__(obj, "_segs"))
        obj = made
    entry = _REVOLVED.get(id(obj))
    if entry is None or entry[0]() is not obj:
        return None
    try:
        same = bool(entry[1].IsEqual(obj.wrapped))
    except Exception:  # noqa: BLE001 - a replaced or null shape: not the one made
        return None
    return list(entry[2]) if same else None


def revolve(segs: Sequence[Segment]) -> Any:
    """build123d Solid: the outline (radius, Z) placed in the XZ plane (X = radius) and
    revolved a full turn about the Z axis. The solid keeps a note of the exact segments
    (:func:`revolved_outline`), from which its profile is taken without cutting the solid
    again while it stays the shape made here.

    Inside :func:`deferred` (the part loader's call of a family's ``part()``), a
    :class:`Revolved` instead: the solid made only when something uses it."""
    if _DEFERRED.get():
        return Revolved(segs)
    return _revolve(segs)


def _revolve(segs: Sequence[Segment]) -> Any:
    from build123d import Axis, Edge, Face, Wire
    from build123d import revolve as b3d_revolve

    segs = list(segs)

    def p3(p: Point) -> tuple[float, float, float]:
        return (p[0], 0.0, p[1])

    edges = []
    for s in closed_outline(segs):
        if isinstance(s, Line):
            edges.append(Edge.make_line(p3(s.start), p3(s.end)))
        else:
            edges.append(Edge.make_three_point_arc(p3(s.start), p3(_arc_mid(s)), p3(s.end)))
    face = Face(Wire(edges))
    part = b3d_revolve(face, Axis.Z)
    solids = part.solids()
    if len(solids) != 1:
        return part
    _record(solids[0], segs)
    return solids[0]


_DEFERRED: ContextVar[bool] = ContextVar("hnc_cam_deferred_revolve", default=False)


@contextmanager
def deferred() -> Iterator[None]:
    """While inside, :func:`revolve` returns a :class:`Revolved` (no CAD kernel work until
    its solid is used)."""
    token = _DEFERRED.set(True)
    try:
        yield
    finally:
        _DEFERRED.reset(token)


def _made(self: "Revolved") -> Any:
    return Revolved.solid(self)


def _forward(name: str):
    def method(self, *args, **kwargs):
        return getattr(_made(self), name)(*args, **kwargs)
    method.__name__ = name
    return method


class Revolved:
    """What :func:`revolve` returns inside :func:`deferred`: the outline it is to revolve,
    and the build123d solid :func:`revolve` would have returned, made (once) the first time
    anything asks the object for more than its outline: an attribute, a method, an operator,
    a copy, a pickle, its class (``isinstance(s, Solid)`` is true as for the solid). Until
    then the solid is not made, and a profile taken of the object is its outline's
    (:func:`revolved_outline`), which is what the solid made of it gives too, untouched.
    As an argument of the kernel's own functions (OCP) it does not stand in for a solid: the
    part loader then calls ``part()`` again outside :func:`deferred`."""

    __slots__ = ("_segs", "_solid", "__weakref__")

    def __init__(self, segs: Sequence[Segment]):
        object.__setattr__(self, "_segs", tuple(segs))
        object.__setattr__(self, "_solid", None)

    def solid(self) -> Any:
        """The build123d solid (made on the first call; as :func:`revolve` makes it)."""
        made = object.__getattribute__(self, "_solid")
        if made is None:
            made = _revolve(object.__getattribute__(self, "_segs"))
            object.__setattr__(self, "_solid", made)
        return made

    def __getattr__(self, name: str) -> Any:  # what the object itself does not have
        return getattr(_made(self), name)

    def __setattr__(self, name: str, value: Any) -> None:
        setattr(_made(self), name, value)

    def __delattr__(self, name: str) -> None:
        delattr(_made(self), name)

    @property  # type: ignore[misc]
    def __class__(self):  # noqa: D105 - isinstance() asks it: the solid's class
        return type(_made(self))

    def __dir__(self):
        return dir(_made(self))

    def __repr__(self) -> str:
        return repr(_made(self))

    def __str__(self) -> str:
        return str(_made(self))

    def __eq__(self, other: Any) -> bool:
        if type(other) is Revolved:
            other = _made(other)
        return _made(self) == other

    def __hash__(self) -> int:
        return hash(_made(self))


# the special methods a build123d shape has (looked up on the type, not through
# __getattr__), and pickling's
for _name in ("__add__", "__sub__", "__and__", "__rmul__", "__bool__", "__copy__",
              "__deepcopy__", "__reduce__", "__reduce_ex__"):
    setattr(Revolved, _name, _forward(_name))
del _name


#: standard bright/hot-rolled round bar diameters (mm) used for default stock
BAR_SIZES = (6, 8, 10, 12, 14, 16, 18, 20, 22, 25, 28, 30, 32, 35, 36, 40, 45, 50, 55, 60, 65,
             70, 75, 80, 85, 90, 95, 100, 110, 120, 125, 130, 140, 150, 160, 170, 180, 190, 200,
             220, 250, 280, 300)


def bar_size(diameter: float, allowance: float = 2.0) -> float:
    """The smallest standard bar at least ``allowance`` mm (on the diameter) above ``diameter``."""
    need = diameter + allowance
    for d in BAR_SIZES:
        if d >= need - 1e-9:
            return float(d)
    return float(math.ceil(need / 10.0) * 10)


def bar_stock(max_diameter: float, length: float, face: float = 2.0, grip: float = 15.0) -> str:
    """Stock string ``DxL+F`` for a part of ``length`` and ``max_diameter``: a standard bar,
    ``face`` mm of face stock on the right, ``grip`` mm beyond the left end for the chuck."""
    return f"{_g(bar_size(max_diameter))}x{_g(length + face + grip)}+{_g(face)}"


def tube_stock(max_diameter: float, bore_diameter: float, length: float, face: float = 2.0,
               grip: float = 15.0, bore_allowance: float = 3.0) -> str:
    """Stock string ``D/dxL+F``: a tube whose bore is ``bore_allowance`` mm (diameter) under
    the part's smallest bore."""
    d = max(bore_diameter - bore_allowance, 1.0)
    return f"{_g(bar_size(max_diameter))}/{_g(d)}x{_g(length + face + grip)}+{_g(face)}"
