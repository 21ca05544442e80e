"""Stepped shaft: domed right end, three diameters, a taper, chamfers and fillets.

From the right face (Z0) toward the chuck: a spherical dome of radius ``dome_radius`` on the
small journal (diameter ``d1``, to Z=-``l1``); a step with an R``fillet`` fillet at its root
and a ``chamfer`` on its edge up to diameter ``d2`` (to Z=-``l2``); a taper of length
``taper_length`` from ``d2`` up to ``d3`` (with an R``fillet`` blend into ``d3``); diameter
``d3`` to the left end Z=-``length`` with a ``chamfer``.

Parameters (mm): length, d1, d2, d3, l1, l2, taper_length, dome_radius, chamfer, fillet.
"""
from __future__ import annotations

import math

from hnc_cam.cad.sketch import Outline, bar_stock, non_negative, positive, require, revolve


def STOCK(length=100.0, d3=40.0, **_):
    return bar_stock(d3, length)


#: the sizes the family is offered in: the macro program (hnc-cam family --macro) holds
#: over them and refuses a set outside them at the control
DOMAIN = {
    "length": (95, 105),
    "d1": (19, 21),
    "d2": (27, 29),
    "d3": (38, 42),
    "l1": (24, 26),
    "l2": (48, 52),
    "taper_length": (14, 16),
    "dome_radius": (15, 17),
    "chamfer": (0.9, 1.1),
    "fillet": (1.4, 1.6),
}


def sketch(length: float = 100.0, d1: float = 20.0, d2: float = 28.0, d3: float = 40.0,
           l1: float = 25.0, l2: float = 50.0, taper_length: float = 15.0,
           dome_radius: float = 16.0, chamfer: float = 1.0, fillet: float = 1.5):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    positive(length=length, d1=d1, d2=d2, d3=d3, l1=l1, l2=l2, taper_length=taper_length,
             dome_radius=dome_radius)
    non_negative(chamfer=chamfer, fillet=fillet)
    r1, r2, r3 = d1 / 2, d2 / 2, d3 / 2
    require(r1 < r2 < r3, f"need d1 < d2 < d3 (got d1={d1:g}, d2={d2:g}, d3={d3:g})")
    require(l1 < l2 < l2 + taper_length < length,
            f"need l1 < l2 and l2 + taper_length < length (got l1={l1:g}, l2={l2:g}, "
            f"taper_length={taper_length:g}, length={length:g})")
    require(dome_radius >= r1, f"dome_radius={dome_radius:g} must be at least d1/2={r1:g}")
    zd = -dome_radius + math.sqrt(dome_radius ** 2 - r1 ** 2)  # where the dome meets d1
    require(-zd < l1, f"the dome (dome_radius={dome_radius:g} on d1={d1:g}) is "
                      f"{-zd:g} mm high, longer than l1={l1:g}")
    s = Outline((0.0, 0.0))
    s.arc_to(r1, zd, center=(0.0, -dome_radius), cw=False)
    s.line_to(r1, -l1, fillet=fillet, names="fillet, l1, dome_radius, d1, d2")
    s.line_to(r2, -l1, chamfer=chamfer, names="chamfer, fillet, d1, d2, l2 - l1")
    s.line_to(r2, -l2)
    s.line_to(r3, -l2 - taper_length, fillet=fillet, names="fillet, taper_length, d2, d3")
    s.line_to(r3, -length, chamfer=chamfer,
              names="chamfer, fillet, length - l2 - taper_length, d3")
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 100.0, d1: float = 20.0, d2: float = 28.0, d3: float = 40.0,
         l1: float = 25.0, l2: float = 50.0, taper_length: float = 15.0,
         dome_radius: float = 16.0, chamfer: float = 1.0, fillet: float = 1.5):
    return revolve(sketch(length, d1, d2, d3, l1, l2, taper_length, dome_radius, chamfer, fillet))
