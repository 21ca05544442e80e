"""A pin that gets a relief groove when it is long: below ``length`` 52 mm a plain journal of
diameter ``d``, from 52 mm a square groove ``width`` wide and ``depth`` deep at the
journal's root (a shop's rule for its long pins: the groove clears the thread run-out).

Parameters (mm): length, d, l, collar, width, depth, chamfer.
"""
from __future__ import annotations

from hnc_cam.cad.sketch import Outline, bar_stock, positive, require, revolve


def STOCK(length=50.0, collar=34.0, **_):
    return bar_stock(collar, length)


def sketch(length: float = 50.0, d: float = 24.0, l: float = 30.0, collar: float = 34.0,
           width: float = 4.0, depth: float = 1.0, chamfer: float = 1.0):
    positive(length=length, d=d, l=l, collar=collar, width=width, depth=depth, chamfer=chamfer)
    require(d + 2 * chamfer < collar, f"need d + 2*chamfer < collar (d={d:g}, collar={collar:g})")
    require(chamfer + width < l < length - chamfer, f"need chamfer + width < l < length - chamfer")
    require(depth < d / 4, f"depth={depth:g} must be less than d/4")
    s = Outline((0.0, 0.0))
    s.line_to(d / 2, 0.0, chamfer=chamfer)
    if length > 52:  # the long pins get the groove
        s.line_to(d / 2, -(l - width))
        s.line_to(d / 2 - depth, -(l - width))
        s.line_to(d / 2 - depth, -l)
    else:
        s.line_to(d / 2, -l)
    s.line_to(collar / 2, -l, chamfer=chamfer)
    s.line_to(collar / 2, -length)
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 50.0, d: float = 24.0, l: float = 30.0, collar: float = 34.0,
         width: float = 4.0, depth: float = 1.0, chamfer: float = 1.0):
    return revolve(sketch(length, d, l, collar, width, depth, chamfer))
