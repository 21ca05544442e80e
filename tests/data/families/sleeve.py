"""A flanged sleeve: a bore ``bore`` through, the body ``d`` over ``lb``, a flange ``df``
``lf`` long at the left, outer chamfers ``c`` and a bore chamfer ``ci``. From a tube: the
boring bar's roughing cycle runs in G97 on the HNC-21T at the whole rpm below its cutting
speed at the largest diameter it reaches.

Parameters (mm): d, bore, lb, df, lf, c, ci.
"""
from __future__ import annotations

from hnc_cam.cad.sketch import Outline, positive, require, revolve, tube_stock

DOMAIN = {"d": (34.0, 40.0), "bore": (20.0, 24.0), "lb": (20.0, 30.0)}


def STOCK(df=50.0, bore=22.0, lb=25.0, lf=8.0, **_):
    return tube_stock(df, bore, lb + lf)


def sketch(d=36.0, bore=22.0, lb=25.0, df=50.0, lf=8.0, c=1.0, ci=0.8):
    positive(d=d, bore=bore, lb=lb, df=df, lf=lf, c=c, ci=ci)
    require(bore / 2 + ci + 2 < d / 2 - c, "the wall is too thin")
    require(d + 2 * c < df, "the flange must stand above the body")
    s = Outline((bore / 2 + ci, 0.0))
    s.line_to(d / 2, 0.0, chamfer=c)
    s.line_to(d / 2, -lb)
    s.line_to(df / 2, -lb, chamfer=c)
    s.line_to(df / 2, -lb - lf)
    s.line_to(bore / 2, -lb - lf)
    s.line_to(bore / 2, -ci)
    s.line_to(bore / 2 + ci, 0.0)
    return s.segments()


def part(d=36.0, bore=22.0, lb=25.0, df=50.0, lf=8.0, c=1.0, ci=0.8):
    return revolve(sketch(d=d, bore=bore, lb=lb, df=df, lf=lf, c=c, ci=ci))
