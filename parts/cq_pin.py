"""Clevis pin with a head, written in CadQuery (the other families use build123d).

From the right face (Z0): a 30 deg lead-in chamfer ``chamfer`` long (axially) on the shank of
diameter ``diameter``, a split-pin groove of width ``groove_width`` and radial depth
``groove_depth`` at Z=-``groove_z``, the shank to the head at Z=-``length``, the head of diameter ``head_diameter`` and thickness ``head_thickness`` with a
spherical crown of radius ``crown_radius`` on its left end.

Parameters (mm): length, diameter, chamfer, groove_z, groove_width, groove_depth,
head_diameter, head_thickness, crown_radius.
"""
from __future__ import annotations

import math

import cadquery as cq

from hnc_cam.cad.sketch import Outline, bar_stock


def STOCK(length=40.0, diameter=16.0, chamfer=1.5, groove_z=8.0, groove_width=2.0,
          groove_depth=1.0, head_diameter=24.0, head_thickness=6.0, crown_radius=30.0):
    *_, zl, crown_h = _dims(length, diameter, chamfer, groove_z, groove_width, groove_depth,
                            head_diameter, head_thickness, crown_radius)
    return bar_stock(head_diameter, -zl + crown_h)


def _dims(length, diameter, chamfer, groove_z, groove_width, groove_depth, head_diameter,
          head_thickness, crown_radius):
    r, rh = diameter / 2, head_diameter / 2
    c_r = chamfer * math.tan(math.radians(30))  # radial size of the 30 deg chamfer
    if not (0 < c_r < r < rh and 0 < groove_depth < r - c_r):
        raise ValueError("need 0 < diameter < head_diameter and a groove shallower than the shank")
    if not (chamfer < groove_z - groove_width / 2 and groove_z + groove_width / 2 < length - 1):
        raise ValueError("the groove must lie on the shank")
    if crown_radius < rh:
        raise ValueError("crown_radius must be at least head_diameter/2")
    zl = -(length + head_thickness)  # left end (edge of the crown)
    crown_h = crown_radius - math.sqrt(crown_radius ** 2 - rh ** 2)
    return r, rh, c_r, zl, crown_h


def sketch(length: float = 40.0, diameter: float = 16.0, chamfer: float = 1.5,
           groove_z: float = 8.0, groove_width: float = 2.0, groove_depth: float = 1.0,
           head_diameter: float = 24.0, head_thickness: float = 6.0, crown_radius: float = 30.0):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    r, rh, c_r, zl, crown_h = _dims(length, diameter, chamfer, groove_z, groove_width,
                                    groove_depth, head_diameter, head_thickness, crown_radius)
    g0, g1 = -(groove_z - groove_width / 2), -(groove_z + groove_width / 2)
    s = Outline((0.0, 0.0))
    s.line_to(r - c_r, 0.0)
    s.line_to(r, -chamfer)
    s.line_to(r, g0)
    s.line_to(r - groove_depth, g0)
    s.line_to(r - groove_depth, g1)
    s.line_to(r, g1)
    s.line_to(r, -length)
    s.line_to(rh, -length)
    s.line_to(rh, zl)
    s.arc_to(0.0, zl - crown_h, center=(0.0, zl - crown_h + crown_radius), cw=False)
    return s.segments()


def part(length: float = 40.0, diameter: float = 16.0, chamfer: float = 1.5,
         groove_z: float = 8.0, groove_width: float = 2.0, groove_depth: float = 1.0,
         head_diameter: float = 24.0, head_thickness: float = 6.0, crown_radius: float = 30.0):
    r, rh, c_r, zl, crown_h = _dims(length, diameter, chamfer, groove_z, groove_width,
                                    groove_depth, head_diameter, head_thickness, crown_radius)
    g0, g1 = -(groove_z - groove_width / 2), -(groove_z + groove_width / 2)
    zc = zl - crown_h + crown_radius  # crown centre (on the axis)
    xm = rh / 2  # a point of the crown for threePointArc
    zm = zc - math.sqrt(crown_radius ** 2 - xm ** 2)
    # Workplane "XZ": local x = global X (radius), local y = global Z (axis)
    prof = (cq.Workplane("XZ")
            .moveTo(0, 0)
            .lineTo(r - c_r, 0)
            .lineTo(r, -chamfer)
            .lineTo(r, g0)
            .lineTo(r - groove_depth, g0)
            .lineTo(r - groove_depth, g1)
            .lineTo(r, g1)
            .lineTo(r, -length)
            .lineTo(rh, -length)
            .lineTo(rh, zl)
            .threePointArc((xm, zm), (0, zl - crown_h))
            .close())
    return prof.revolve(360, (0, 0, 0), (0, 1, 0))
