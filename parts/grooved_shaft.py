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

from hnc_cam.cad.sketch import Outline, bar_stock, revolve


def STOCK(length=80.0, d2=36.0, **_):
    return bar_stock(d2, length)


def sketch(length: float = 80.0, d1: float = 25.0, d2: float = 36.0, l1: float = 30.0,
           relief_width: float = 4.0, relief_depth: float = 0.8, relief_angle: float = 30.0,
           relief_radius: float = 0.6, arc_z: float = 55.0, arc_radius: float = 5.0,
           arc_depth: float = 1.2, chamfer: float = 1.0):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    r1, r2 = d1 / 2, d2 / 2
    rg = r1 - relief_depth
    if not (0 < rg < r1 < r2 - chamfer):
        raise ValueError("need 0 < d1 - 2*relief_depth < d1 < d2 - 2*chamfer")
    if not 0 < relief_angle <= 90:
        raise ValueError("relief_angle must be in (0, 90] deg")
    if not 0 < arc_depth <= arc_radius:
        raise ValueError("need 0 < arc_depth <= arc_radius")
    run = relief_depth / math.tan(math.radians(relief_angle))  # axial length of the ramp
    hw = math.sqrt(arc_radius ** 2 - (arc_radius - arc_depth) ** 2)  # half-width at d2
    za = -(l1 - relief_width)  # where the ramp leaves the journal
    t_ramp = relief_radius * math.tan(math.radians(relief_angle) / 2)  # fillet tangent lengths
    if not (chamfer < l1 - relief_width and run + t_ramp + relief_radius < relief_width
            and relief_radius < relief_depth
            and l1 + chamfer < arc_z - hw and arc_z + hw < length - chamfer):
        raise ValueError("grooves overlap each other or the ends")
    s = Outline((0.0, 0.0))
    s.line_to(r1, 0.0, chamfer=chamfer)
    s.line_to(r1, za)
    s.line_to(rg, za - run, fillet=relief_radius)
    s.line_to(rg, -l1, fillet=relief_radius)
    s.line_to(r2, -l1, chamfer=chamfer)
    s.line_to(r2, -(arc_z - hw))
    s.arc_to(r2, -(arc_z + hw), center=(r2 - arc_depth + arc_radius, -arc_z), cw=True)
    s.line_to(r2, -length, chamfer=chamfer)
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 80.0, d1: float = 25.0, d2: float = 36.0, l1: float = 30.0,
         relief_width: float = 4.0, relief_depth: float = 0.8, relief_angle: float = 30.0,
         relief_radius: float = 0.6, arc_z: float = 55.0, arc_radius: float = 5.0,
         arc_depth: float = 1.2, chamfer: float = 1.0):
    return revolve(sketch(length, d1, d2, l1, relief_width, relief_depth, relief_angle,
                          relief_radius, arc_z, arc_radius, arc_depth, chamfer))
