"""Bolt blank: an M``d`` x ``pitch`` thread to Z=-``lt``, a square relief groove ``w`` wide
below the thread's minor diameter, a head ``dh`` x ``lh`` (chamfered 0.5) to the left end."""
from hnc_cam.cad.sketch import Outline, bar_stock, positive, require, revolve
from hnc_cam.geometry import Thread


def STOCK(dh=26.0, lt=22.0, w=3.5, lh=8.0, **_):
    return bar_stock(32.0, 45.0)


def THREADS(d=16.0, pitch=1.5, lt=22.0, **_):
    return [Thread(z_start=0.0, z_end=-lt, diameter=d, pitch=pitch)]


def sketch(d=16.0, pitch=1.5, lt=22.0, w=3.5, dh=26.0, lh=8.0):
    positive(d=d, pitch=pitch, lt=lt, w=w, dh=dh, lh=lh)
    dg = d - 2 * 0.6134 * pitch - 0.4
    require(dg > 4, "thread too coarse")
    require(d + 2 < dh, "need d + 2 < dh")
    s = Outline((0.0, 0.0))
    s.line_to(d / 2 - 1.0, 0.0)
    s.line_to(d / 2, -1.0)
    s.line_to(d / 2, -lt)
    s.line_to(dg / 2, -lt)
    s.line_to(dg / 2, -lt - w)
    s.line_to(dh / 2, -lt - w, chamfer=0.5)
    s.line_to(dh / 2, -lt - w - lh)
    s.line_to(0.0, -lt - w - lh)
    return s.segments()


def part(d=16.0, pitch=1.5, lt=22.0, w=3.5, dh=26.0, lh=8.0):
    return revolve(sketch(d, pitch, lt, w, dh, lh))
