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

from hnc_cam.cad.sketch import Outline, bar_stock, revolve


def STOCK(length=100.0, d3=40.0, **_):
    return bar_stock(d3, length)


def sketch(length: float = 100.0, d1: float = 20.0, d2: float = 28.0, d3: float = 40.0,
           l1: float = 25.0, l2: float = 50.0, taper_length: float = 15.0,
           dome_radius: float = 16.0, chamfer: float = 1.0, fillet: float = 1.5):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    r1, r2, r3 = d1 / 2, d2 / 2, d3 / 2
    if not (0 < r1 < r2 < r3):
        raise ValueError("need 0 < d1 < d2 < d3")
    if not (0 < l1 < l2 < l2 + taper_length < length):
        raise ValueError("need 0 < l1 < l2 < l2 + taper_length < length")
    if dome_radius < r1:
        raise ValueError("dome_radius must be at least d1/2")
    zd = -dome_radius + math.sqrt(dome_radius ** 2 - r1 ** 2)  # where the dome meets d1
    s = Outline((0.0, 0.0))
    s.arc_to(r1, zd, center=(0.0, -dome_radius), cw=False)
    s.line_to(r1, -l1, fillet=fillet)
    s.line_to(r2, -l1, chamfer=chamfer)
    s.line_to(r2, -l2)
    s.line_to(r3, -l2 - taper_length, fillet=fillet)
    s.line_to(r3, -length, chamfer=chamfer)
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 100.0, d1: float = 20.0, d2: float = 28.0, d3: float = 40.0,
         l1: float = 25.0, l2: float = 50.0, taper_length: float = 15.0,
         dome_radius: float = 16.0, chamfer: float = 1.0, fillet: float = 1.5):
    return revolve(sketch(length, d1, d2, d3, l1, l2, taper_length, dome_radius, chamfer, fillet))
