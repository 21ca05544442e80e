"""A plain turned pin: a journal of diameter ``d`` with a chamfer on the right end, a
shoulder up to ``collar`` (chamfered) and the collar to the left end at Z=-``length``.

Parameters (mm): length, d, l, collar, chamfer.
"""
from __future__ import annotations

from hnc_cam.cad.sketch import Outline, bar_stock, positive, require, revolve


def STOCK(length=60.0, collar=34.0, **_):
    return bar_stock(collar, length)


def sketch(length: float = 60.0, d: float = 24.0, l: float = 30.0, collar: float = 34.0,
           chamfer: float = 1.0):
    positive(length=length, d=d, l=l, collar=collar, chamfer=chamfer)
    require(d + 2 * chamfer < collar, f"need d + 2*chamfer < collar (d={d:g}, collar={collar:g})")
    require(chamfer < l < length - chamfer, f"need chamfer < l < length - chamfer (l={l:g})")
    s = Outline((0.0, 0.0))
    s.line_to(d / 2, 0.0, chamfer=chamfer)
    s.line_to(d / 2, -l)
    s.line_to(collar / 2, -l, chamfer=chamfer)
    s.line_to(collar / 2, -length)
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 60.0, d: float = 24.0, l: float = 30.0, collar: float = 34.0,
         chamfer: float = 1.0):
    return revolve(sketch(length, d, l, collar, chamfer))
