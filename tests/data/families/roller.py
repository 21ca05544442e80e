"""A roller: a domed right end (radius ``dome``), the barrel ``d`` with a square groove
``gw`` wide and ``gd`` deep at ``gz``, a fillet ``r`` up to the shoulder ``ds`` at ``ls``.

Parameters (mm): length, d, dome, gz, gw, gd, ds, ls, r.
"""
from __future__ import annotations

import math

from hnc_cam.cad.sketch import Outline, bar_stock, positive, require, revolve

DOMAIN = {"d": (28.0, 34.0), "gz": (18.0, 24.0)}


def STOCK(length=70.0, ds=44.0, **_):
    return bar_stock(ds + 2, length)


def sketch(length=70.0, d=30.0, dome=20.0, gz=20.0, gw=4.0, gd=1.5, ds=44.0, ls=45.0, r=2.0):
    positive(length=length, d=d, dome=dome, gz=gz, gw=gw, gd=gd, ds=ds, ls=ls, r=r)
    require(d / 2 < dome, "the dome must be larger than the barrel's radius")
    require(d + 2 * r < ds, "the fillet must fit below the shoulder")
    h = dome - math.sqrt(dome * dome - (d / 2) ** 2)  # the dome's depth at the barrel
    require(h + 1 < gz and gz + gw + r < ls, "the groove must fit on the barrel")
    s = Outline((0.0, 0.0))
    s.arc_to(d / 2, -h, radius=dome, cw=False)
    s.line_to(d / 2, -gz)
    s.line_to(d / 2 - gd, -gz)
    s.line_to(d / 2 - gd, -gz - gw)
    s.line_to(d / 2, -gz - gw)
    s.line_to(d / 2, -ls, fillet=r)
    s.line_to(ds / 2, -ls)
    s.line_to(ds / 2, -length)
    s.line_to(0.0, -length)
    return s.segments()


def part(length=70.0, d=30.0, dome=20.0, gz=20.0, gw=4.0, gd=1.5, ds=44.0, ls=45.0, r=2.0):
    return revolve(sketch(length=length, d=d, dome=dome, gz=gz, gw=gw, gd=gd, ds=ds, ls=ls, r=r))
