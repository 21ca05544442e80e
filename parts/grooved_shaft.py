"""Shaft with undercuts: a relief groove at the root of a shoulder and a round (arc) groove.

From the right face (Z0): journal of diameter ``d1`` with a ``chamfer``; a relief groove
(DIN 509 style) at the shoulder at Z=-``l1``: ``relief_width`` long at the journal diameter,
entered by a ramp at ``relief_angle`` deg to the axis down to ``relief_depth`` (radial) below
the journal, its bottom corners rounded R``relief_radius``; the shoulder up to diameter
``d2`` (chamfered); a round groove of radius ``arc_radius`` and radial depth ``arc_depth``
centred at Z=-``arc_z``; diameter ``d2`` to the left end Z=-``length`` (chamfered).

The defaults keep every descending wall at or under 45 deg to the axis, so a 35 deg
copying insert in a 93 deg holder reaches both grooves.

Parameters (mm, deg): length, d1, d2, l1, relief_width, relief_depth, relief_angle,
relief_radius, arc_z, arc_radius, arc_depth, chamfer.
"""
from __future__ import annotations

import math

from hnc_cam.cad.sketch import Outline, bar_stock, non_negative, positive, require, revolve


def STOCK(length=80.0, d2=36.0, **_):
    return bar_stock(d2, length)


#: the sizes the family is offered in: the macro program (hnc-cam family --macro) holds
#: over them and refuses a set outside them at the control
DOMAIN = {
    "length": (76, 84),
    "d1": (24, 26),
    "d2": (34.5, 38),
    "l1": (28.5, 31.5),
    "relief_width": (3.8, 4.2),
    "relief_depth": (0.76, 0.84),
    "relief_angle": (28.5, 31.5),
    "relief_radius": (0.57, 0.63),
    "arc_z": (52.5, 57.5),
    "arc_radius": (4.75, 5.25),
    "arc_depth": (1.14, 1.26),
    "chamfer": (0.95, 1.05),
}


def sketch(length: float = 80.0, d1: float = 25.0, d2: float = 36.0, l1: float = 30.0,
           relief_width: float = 4.0, relief_depth: float = 0.8, relief_angle: float = 30.0,
           relief_radius: float = 0.6, arc_z: float = 55.0, arc_radius: float = 5.0,
           arc_depth: float = 1.2, chamfer: float = 1.0):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    positive(length=length, d1=d1, d2=d2, l1=l1, relief_width=relief_width,
             relief_depth=relief_depth, relief_angle=relief_angle, arc_z=arc_z,
             arc_radius=arc_radius, arc_depth=arc_depth)
    non_negative(relief_radius=relief_radius, chamfer=chamfer)
    r1, r2 = d1 / 2, d2 / 2
    rg = r1 - relief_depth
    require(rg > 0, f"relief_depth={relief_depth:g} must be less than d1/2={r1:g}")
    require(r1 < r2 - chamfer, f"need d1 < d2 - 2*chamfer (a shoulder to chamfer; got "
                               f"d1={d1:g}, d2={d2:g}, chamfer={chamfer:g})")
    require(relief_angle <= 90, f"relief_angle={relief_angle:g} must be in (0, 90] deg")
    require(arc_depth <= arc_radius, f"arc_depth={arc_depth:g} must not exceed "
                                     f"arc_radius={arc_radius:g}")
    run = relief_depth / math.tan(math.radians(relief_angle))  # axial length of the ramp
    hw = math.sqrt(arc_radius ** 2 - (arc_radius - arc_depth) ** 2)  # half-width at d2
    za = -(l1 - relief_width)  # where the ramp leaves the journal
    t_ramp = relief_radius * math.tan(math.radians(relief_angle) / 2)  # fillet tangent lengths
    require(relief_width < l1, f"relief_width={relief_width:g} must be less than l1={l1:g}")
    require(chamfer < l1 - relief_width,
            f"chamfer={chamfer:g} does not fit on the journal (l1 - relief_width = "
            f"{l1 - relief_width:g})")
    require(relief_radius < relief_depth,
            f"relief_radius={relief_radius:g} must be less than relief_depth={relief_depth:g}")
    require(run + t_ramp + relief_radius < relief_width,
            f"relief_width={relief_width:g} is too short for the ramp ({run:.3f} mm at "
            f"relief_angle={relief_angle:g}, relief_depth={relief_depth:g}) and the "
            f"relief_radius={relief_radius:g} corners")
    require(l1 + chamfer < arc_z - hw,
            f"the arc groove (arc_z={arc_z:g}, {2 * hw:.3f} wide from arc_radius={arc_radius:g}, "
            f"arc_depth={arc_depth:g}) overlaps the shoulder at l1={l1:g} and its chamfer")
    require(arc_z + hw < length - chamfer,
            f"the arc groove (arc_z={arc_z:g}, {2 * hw:.3f} wide) runs past the left end "
            f"(length={length:g}, chamfer={chamfer:g})")
    s = Outline((0.0, 0.0))
    s.line_to(r1, 0.0, chamfer=chamfer, names="chamfer, d1")
    s.line_to(r1, za)
    s.line_to(rg, za - run, fillet=relief_radius,
              names="relief_radius, relief_depth, relief_angle, relief_width")
    s.line_to(rg, -l1, fillet=relief_radius, names="relief_radius, relief_width")
    s.line_to(r2, -l1, chamfer=chamfer, names="chamfer, relief_radius, d1, d2")
    s.line_to(r2, -(arc_z - hw))
    s.arc_to(r2, -(arc_z + hw), center=(r2 - arc_depth + arc_radius, -arc_z), cw=True)
    s.line_to(r2, -length, chamfer=chamfer, names="chamfer, d2, length")
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 80.0, d1: float = 25.0, d2: float = 36.0, l1: float = 30.0,
         relief_width: float = 4.0, relief_depth: float = 0.8, relief_angle: float = 30.0,
         relief_radius: float = 0.6, arc_z: float = 55.0, arc_radius: float = 5.0,
         arc_depth: float = 1.2, chamfer: float = 1.0):
    return revolve(sketch(length, d1, d2, l1, relief_width, relief_depth, relief_angle,
                          relief_radius, arc_z, arc_radius, arc_depth, chamfer))
