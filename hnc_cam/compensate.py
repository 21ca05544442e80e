"""Tool-nose compensated contours for the CAM side (issue 4, "Tool-nose compensation").

``compensate(contour, nose_radius, tip_code, side, output="tip")`` offsets a part contour for
a round insert nose and returns exact lines and arcs: the **nose-centre** path
(``output="centre"``) or the path of the **imaginary tip** (``output="tip"``: the centre path
moved by :func:`hnc_cam.geometry.tip.tip_vector`, fig. 3.3.44; for codes 0 and 9 the tip is
the centre). The offset itself is :func:`hnc_cam.geometry.offset.offset_chain`, the same
routine the interpreter's G41/G42 uses (one implementation).

Side: looking along the motion in the view Z right / X up, ``"left"`` (G41, ``41``) or
``"right"`` (G42, ``42``). For a :class:`~hnc_cam.geometry.profile.TurnedProfile` the chain
and side follow the manual's usage (digest §7): the outside contour is cut toward -Z with the
tool on the right (G42), the bore toward -Z on the left (G41); ``which`` picks the chain.

Nothing the nose cannot reach is gouged: the path only runs where the nose stays at ``r``
from the whole contour. ``Compensated.unreachable`` lists the features it cannot make (an
inside radius smaller than ``r``, a groove or step narrower than ``2r``, a stretch at an
open end of the chain), each with where (contour points, segment indices) and by how much
(``departure``: the largest distance, mm, from that stretch of the part to the reachable
contour); ``departures`` also lists the ordinary nose fillet left in each sharp concave
corner (kind ``corner``). Given the insert's approach and included angles (or its edge
directions), the insert's flanks are checked too (kind ``insert``: a plunge steeper than the
trailing edge allows, a face leaning over the tool, a concave corner sharper than the insert):
locally, along the contour; a collision of the holder or of the insert with a far feature is
the simulator's check.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

from .errors import ProfileError, ToolError
from .geometry.offset import (Departure, Origin, insert_check, insert_edges, offset_chain,
                              side_sign, translate_chain)
from .geometry.primitives import Point, Segment
from .geometry.tip import tip_vector

OUTPUTS = ("tip", "centre")


@dataclass
class Compensated:
    """A compensated contour.

    ``segments``: the requested path (imaginary tip or nose centre), exact Line/Arc, connected;
    ``centre``: the nose-centre path (same structure); ``origins[k]``: where ``segments[k]``
    comes from (offset of input segment ``i`` or the arc about the corner ``i``/``k``);
    ``departures``: every stretch of the contour the nose does not touch; ``unreachable``:
    those that are real misses (not the inherent corner fillet).
    """
    segments: list[Segment]
    centre: list[Segment]
    origins: list[Origin]
    departures: list[Departure]
    nose_radius: float
    tip_code: int
    side: str
    output: str
    tip_vector: Point
    contour: list[Segment] = field(default_factory=list)

    @property
    def unreachable(self) -> list[Departure]:
        return [d for d in self.departures if d.unreachable]

    @property
    def ok(self) -> bool:
        """True when the nose can make every feature of the contour."""
        return not self.unreachable

    @property
    def start(self) -> Point:
        return self.segments[0].start

    @property
    def end(self) -> Point:
        return self.segments[-1].end

    def to_json(self) -> dict[str, Any]:
        """A plain summary (X as diameter, like every JSON of the package)."""
        def seg(g: Segment) -> dict[str, Any]:
            d: dict[str, Any] = {"type": g.kind, "start": [2 * g.start[0], g.start[1]],
                                 "end": [2 * g.end[0], g.end[1]]}
            if g.kind == "arc":
                d["center"] = [2 * g.center[0], g.center[1]]
                d["radius"] = g.radius
                d["cw"] = g.cw
            return d
        return {
            "output": self.output, "side": self.side, "nose_radius": self.nose_radius,
            "tip_code": self.tip_code, "segments": [seg(g) for g in self.segments],
            "unreachable": [{"kind": d.kind, "segments": list(d.segments),
                             "start": [2 * d.start[0], d.start[1]],
                             "end": [2 * d.end[0], d.end[1]],
                             "at": [2 * d.at[0], d.at[1]], "departure": d.departure,
                             "message": d.message} for d in self.unreachable],
        }


def _chain_and_side(contour, side, which: str) -> tuple[list[Segment], Any]:
    if hasattr(contour, "outside") and hasattr(contour, "bore"):
        if which == "outside":
            chain = list(contour.outside)
            default = "right"
        elif which == "bore":
            if not contour.bore:
                raise ProfileError(f"part {getattr(contour, 'name', '')!r} has no bore to compensate")
            chain = list(contour.bore)
            default = "left"
        else:
            raise ValueError(f"which must be 'outside' or 'bore', got {which!r}")
        return chain, default if side is None else side
    if side is None:
        raise ValueError("side is required for a plain chain: 'left'/'right' or 41/42")
    return list(contour), side


def compensate(contour: Sequence[Segment] | Any, nose_radius: float, tip_code: int,
               side=None, output: str = "tip", which: str = "outside",
               lookahead: int | None = None, insert: tuple[float, float] | None = None,
               edges: tuple[float, float] | None = None) -> Compensated:
    """Exact tool-nose compensated path of ``contour``.

    ``contour``: a connected chain of :class:`Line`/:class:`Arc` in (x radius, z), in cutting
    order, or a ``TurnedProfile`` (then ``which`` = ``"outside"`` | ``"bore"`` picks the chain
    and ``side`` defaults to right for the outside, left for the bore). ``nose_radius`` in mm;
    ``tip_code`` 0-9 (fig. 3.3.44); ``side`` ``"left"``/``"right"`` or 41/42; ``output``
    ``"tip"`` (imaginary tip path; the centre for codes 0/9) or ``"centre"``; ``lookahead``
    limits the gouge check to that many neighbouring segments (default: the whole contour).
    ``insert=(approach, nose_angle)`` (holder kappa_r and insert included angle, degrees;
    tip codes 1-4) or ``edges=(a1, a2)`` (the cutting-edge directions as view angles, see
    :func:`hnc_cam.geometry.offset.insert_edges`) add the check of the insert's flanks:
    stretches the insert keeps the nose from following are reported as kind ``insert``.

    Raises :class:`ToolError` for a negative radius or a bad tip code,
    :class:`ProfileError` for a chain that is not connected or a missing bore.
    """
    if output not in OUTPUTS:
        raise ValueError(f"output must be one of {OUTPUTS}, got {output!r}")
    if nose_radius is None or nose_radius < 0:
        raise ToolError(f"nose radius must be >= 0, got {nose_radius!r}")
    try:
        tv = tip_vector(int(tip_code), nose_radius)
    except (ValueError, TypeError):
        raise ToolError(f"tip direction code must be 0-9, got {tip_code!r}") from None
    chain, side = _chain_and_side(contour, side, which)
    s = side_sign(side)
    try:
        res = offset_chain(chain, nose_radius, s, lookahead=lookahead)
    except ValueError as e:
        raise ProfileError(f"cannot compensate the contour: {e}") from None
    centre = res.segments
    departures = list(res.departures)
    if insert is not None and edges is None:
        try:
            edges = insert_edges(int(tip_code), float(insert[0]), float(insert[1]))
        except ValueError as e:
            raise ToolError(str(e)) from None
    if edges is not None:
        departures += insert_check(res, (float(edges[0]), float(edges[1])))
    path = centre if output == "centre" else translate_chain(centre, tv)
    return Compensated(segments=path, centre=centre, origins=res.origins,
                       departures=departures, nose_radius=nose_radius,
                       tip_code=int(tip_code), side="left" if s > 0 else "right",
                       output=output, tip_vector=tv if output == "tip" else (0.0, 0.0),
                       contour=chain)
