"""Shaft with undercuts: a relief groove at the root of a shoulder and a round (arc) groove.

From the right face (Z0): journal of diameter ``d1`` with a ``chamfer``; a rectangular relief
groove ``relief_width`` wide and ``relief_depth`` deep (radial) ending at the shoulder at
Z=-``l1``, its bottom corners rounded R``relief_radius``; the shoulder up to diameter ``d2``
(chamfered); a round groove of radius ``arc_radius`` and depth ``arc_depth`` (radial) centred
at Z=-``arc_z``; diameter ``d2`` to the left end Z=-``length`` (chamfered).

Parameters (mm): length, d1, d2, l1, relief_width, relief_depth, relief_radius, arc_z,
arc_radius, arc_depth, chamfer.
"""
from __future__ import annotations

import math

from hnc_cam.cad.sketch import Outline, bar_stock, revolve


def STOCK(length=80.0, d2=36.0, **_):
    return bar_stock(d2, length)


def sketch(length: float = 80.0, d1: float = 25.0, d2: float = 36.0, l1: float = 30.0,
           relief_width: float = 4.0, relief_depth: float = 1.0, relief_radius: float = 0.5,
           arc_z: float = 55.0, arc_radius: float = 4.0, arc_depth: float = 2.5,
           chamfer: float = 1.0):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    r1, r2 = d1 / 2, d2 / 2
    rg = r1 - relief_depth
    if not (0 < rg < r1 < r2 - chamfer):
        raise ValueError("need 0 < d1 - 2*relief_depth < d1 < d2 - 2*chamfer")
    if not 0 < arc_depth <= arc_radius:
        raise ValueError("need 0 < arc_depth <= arc_radius")
    hw = math.sqrt(arc_radius ** 2 - (arc_radius - arc_depth) ** 2)  # half-width at d2
    if not (chamfer < l1 - relief_width and 2 * relief_radius < relief_width
            and relief_radius < relief_depth
            and l1 + chamfer < arc_z - hw and arc_z + hw < length - chamfer):
        raise ValueError("grooves overlap each other or the ends")
    s = Outline((0.0, 0.0))
    s.line_to(r1, 0.0, chamfer=chamfer)
    s.line_to(r1, -(l1 - relief_width))
    s.line_to(rg, -(l1 - relief_width), fillet=relief_radius)
    s.line_to(rg, -l1, fillet=relief_radius)
    s.line_to(r2, -l1, chamfer=chamfer)
    s.line_to(r2, -(arc_z - hw))
    s.arc_to(r2, -(arc_z + hw), center=(r2 - arc_depth + arc_radius, -arc_z), cw=True)
    s.line_to(r2, -length, chamfer=chamfer)
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 80.0, d1: float = 25.0, d2: float = 36.0, l1: float = 30.0,
         relief_width: float = 4.0, relief_depth: float = 1.0, relief_radius: float = 0.5,
         arc_z: float = 55.0, arc_radius: float = 4.0, arc_depth: float = 2.5,
         chamfer: float = 1.0):
    return revolve(sketch(length, d1, d2, l1, relief_width, relief_depth, relief_radius, arc_z,
                          arc_radius, arc_depth, chamfer))
