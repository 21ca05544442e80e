"""A taper pin: a chamfered small end of diameter ``d1``, a taper up to ``d2`` over ``lt``,
then a ``d2`` journal to the left end at Z=-``length``. The taper is shallow (about 7 deg):
a roughing pass ends on it about eight times as far along Z as the contour's last digit
moves it in X.

Parameters (mm): length, d1, d2, lt, chamfer.
"""
from __future__ import annotations

from hnc_cam.cad.sketch import Outline, bar_stock, positive, require, revolve

DOMAIN = {"d1": (14.0, 22.0)}


def STOCK(length=60.0, d2=28.0, **_):
    return bar_stock(d2 + 4, length)


def sketch(length: float = 60.0, d1: float = 18.0, d2: float = 28.0, lt: float = 30.0,
           chamfer: float = 1.0):
    positive(length=length, d1=d1, d2=d2, lt=lt, chamfer=chamfer)
    require(d1 < d2, f"need d1 < d2 (d1={d1:g}, d2={d2:g})")
    require(lt < length, f"need lt < length (lt={lt:g})")
    s = Outline((0.0, 0.0))
    s.line_to(d1 / 2, 0.0, chamfer=chamfer)
    s.line_to(d2 / 2, -lt)
    s.line_to(d2 / 2, -length)
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 60.0, d1: float = 18.0, d2: float = 28.0, lt: float = 30.0,
         chamfer: float = 1.0):
    return revolve(sketch(length, d1, d2, lt, chamfer))
