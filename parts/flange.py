"""Flange blank: a short, wide disc with a hub on the right side (face-dominated part).

From the right face (Z0): the hub face and hub of diameter ``hub_diameter`` (chamfered) to
Z=-``hub_length``, an R``fillet`` at its root, the flange face up to ``diameter``
(chamfered), the rim to the left face at Z=-(``hub_length`` + ``thickness``).

Parameters (mm): diameter, thickness, hub_diameter, hub_length, fillet, chamfer.
"""
from __future__ import annotations

from hnc_cam.cad.sketch import Outline, bar_stock, non_negative, positive, require, revolve


def STOCK(diameter=120.0, thickness=14.0, hub_length=16.0, **_):
    return bar_stock(diameter, thickness + hub_length)


#: the sizes the family is offered in: the macro program (hnc-cam family --macro) holds
#: over them and refuses a set outside them at the control
DOMAIN = {
    "diameter": (100, 140),
    "thickness": (10, 18),
    "hub_diameter": (40, 60),
    "hub_length": (12, 20),
    "fillet": (2, 4),
    "chamfer": (1, 2),
}


def sketch(diameter: float = 120.0, thickness: float = 14.0, hub_diameter: float = 50.0,
           hub_length: float = 16.0, fillet: float = 3.0, chamfer: float = 1.5):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    positive(diameter=diameter, thickness=thickness, hub_diameter=hub_diameter,
             hub_length=hub_length)
    non_negative(fillet=fillet, chamfer=chamfer)
    R, rh = diameter / 2, hub_diameter / 2
    require(rh < R, f"hub_diameter={hub_diameter:g} must be less than diameter={diameter:g}")
    require(rh + fillet + chamfer < R,
            f"the flange face (diameter={diameter:g} - hub_diameter={hub_diameter:g}) is too "
            f"narrow for fillet={fillet:g} + chamfer={chamfer:g}")
    require(chamfer < rh, f"chamfer={chamfer:g} must be less than hub_diameter/2={rh:g}")
    require(chamfer + fillet < hub_length,
            f"chamfer={chamfer:g} + fillet={fillet:g} must be less than hub_length={hub_length:g}")
    require(2 * chamfer < thickness,
            f"two chamfers (chamfer={chamfer:g}) do not fit on the rim (thickness={thickness:g})")
    L = hub_length + thickness
    s = Outline((0.0, 0.0))
    s.line_to(rh, 0.0, chamfer=chamfer, names="chamfer, hub_diameter")
    s.line_to(rh, -hub_length, fillet=fillet, names="fillet, chamfer, hub_length")
    s.line_to(R, -hub_length, chamfer=chamfer, names="chamfer, fillet, diameter, hub_diameter")
    s.line_to(R, -L, chamfer=chamfer, names="chamfer, thickness")
    s.line_to(0.0, -L)
    return s.segments()


def part(diameter: float = 120.0, thickness: float = 14.0, hub_diameter: float = 50.0,
         hub_length: float = 16.0, fillet: float = 3.0, chamfer: float = 1.5):
    return revolve(sketch(diameter, thickness, hub_diameter, hub_length, fillet, chamfer))
