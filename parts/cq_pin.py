"""Headed pin with a retaining-ring groove, written in CadQuery (the other families use
build123d).

From the right face (Z0): a 30 deg lead-in chamfer ``chamfer`` long (axially) on the shank of
diameter ``diameter``; a retaining-ring groove of width ``groove_width`` and radial depth
``groove_depth`` centred at Z=-``groove_z``; the shank to the head at Z=-``length`` with an
R``fillet`` under the head; the head of diameter ``head_diameter`` and thickness
``head_thickness`` with a 45 deg ``head_chamfer`` on its left edge; a flat left face.

Parameters (mm): length, diameter, chamfer, groove_z, groove_width, groove_depth,
head_diameter, head_thickness, fillet, head_chamfer.
"""
from __future__ import annotations

import math

import cadquery as cq

from hnc_cam.cad.sketch import Outline, bar_stock, positive, require


def STOCK(length=40.0, head_diameter=24.0, head_thickness=6.0, **_):
    return bar_stock(head_diameter, length + head_thickness)


def _dims(length, diameter, chamfer, groove_z, groove_width, groove_depth, head_diameter,
          head_thickness, fillet, head_chamfer):
    positive(length=length, diameter=diameter, chamfer=chamfer, groove_z=groove_z,
             groove_width=groove_width, groove_depth=groove_depth, head_diameter=head_diameter,
             head_thickness=head_thickness, fillet=fillet, head_chamfer=head_chamfer)
    r, rh = diameter / 2, head_diameter / 2
    c_r = chamfer * math.tan(math.radians(30))  # radial size of the 30 deg lead chamfer
    require(r + fillet < rh, f"need diameter + 2*fillet < head_diameter (got diameter="
                             f"{diameter:g}, fillet={fillet:g}, head_diameter={head_diameter:g})")
    require(c_r < r, f"chamfer={chamfer:g} (30 deg) is too long for diameter={diameter:g}")
    require(groove_depth < r - c_r,
            f"groove_depth={groove_depth:g} must be less than the shank radius under the lead "
            f"chamfer ({r - c_r:.3f}: diameter={diameter:g}, chamfer={chamfer:g})")
    g0, g1 = -(groove_z - groove_width / 2), -(groove_z + groove_width / 2)
    require(chamfer < -g0, f"the groove (groove_z={groove_z:g}, groove_width={groove_width:g}) "
                           f"overlaps the lead chamfer (chamfer={chamfer:g})")
    require(-g1 < length - fillet,
            f"the groove (groove_z={groove_z:g}, groove_width={groove_width:g}) runs into the "
            f"fillet under the head (length={length:g}, fillet={fillet:g})")
    require(head_chamfer < min(head_thickness, rh - r - fillet),
            f"head_chamfer={head_chamfer:g} does not fit on the head (head_thickness="
            f"{head_thickness:g}, head_diameter={head_diameter:g} - diameter={diameter:g} - "
            f"2*fillet={fillet:g})")
    return r, rh, c_r, g0, g1, -(length + head_thickness)


#: the sizes the family is offered in: the macro program (hnc-cam family --macro) holds
#: over them and refuses a set outside them at the control
DOMAIN = {
    "length": (36, 44),
    "diameter": (15, 17),
    "chamfer": (1.3, 1.7),
    "groove_z": (7, 9),
    "groove_depth": (0.9, 1.1),
    "head_diameter": (22, 26),
    "head_thickness": (5.5, 6.5),
    "fillet": (0.9, 1.1),
    "head_chamfer": (0.9, 1.1),
}


def sketch(length: float = 40.0, diameter: float = 16.0, chamfer: float = 1.5,
           groove_z: float = 8.0, groove_width: float = 3.0, groove_depth: float = 1.0,
           head_diameter: float = 24.0, head_thickness: float = 6.0, fillet: float = 1.0,
           head_chamfer: float = 1.0):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    r, rh, c_r, g0, g1, zl = _dims(length, diameter, chamfer, groove_z, groove_width,
                                   groove_depth, head_diameter, head_thickness, fillet,
                                   head_chamfer)
    s = Outline((0.0, 0.0))
    s.line_to(r - c_r, 0.0)
    s.line_to(r, -chamfer)
    s.line_to(r, g0)
    s.line_to(r - groove_depth, g0)
    s.line_to(r - groove_depth, g1)
    s.line_to(r, g1)
    s.line_to(r, -length, fillet=fillet)
    s.line_to(rh, -length)
    s.line_to(rh, zl, chamfer=head_chamfer)
    s.line_to(0.0, zl)
    return s.segments()


def part(length: float = 40.0, diameter: float = 16.0, chamfer: float = 1.5,
         groove_z: float = 8.0, groove_width: float = 3.0, groove_depth: float = 1.0,
         head_diameter: float = 24.0, head_thickness: float = 6.0, fillet: float = 1.0,
         head_chamfer: float = 1.0):
    r, rh, c_r, g0, g1, zl = _dims(length, diameter, chamfer, groove_z, groove_width,
                                   groove_depth, head_diameter, head_thickness, fillet,
                                   head_chamfer)
    k = fillet * (1 - math.sqrt(0.5))  # mid point of the fillet, for threePointArc
    # Workplane "XZ": local x = global X (radius), local y = global Z (axis)
    prof = (cq.Workplane("XZ")
            .moveTo(0, 0)
            .lineTo(r - c_r, 0)
            .lineTo(r, -chamfer)
            .lineTo(r, g0)
            .lineTo(r - groove_depth, g0)
            .lineTo(r - groove_depth, g1)
            .lineTo(r, g1)
            .lineTo(r, -length + fillet)
            .threePointArc((r + k, -length + k), (r + fillet, -length))
            .lineTo(rh, -length)
            .lineTo(rh, zl + head_chamfer)
            .lineTo(rh - head_chamfer, zl)
            .lineTo(0, zl)
            .close())
    return prof.revolve(360, (0, 0, 0), (0, 1, 0))
