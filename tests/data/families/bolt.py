"""Bolt blank: a thread d x pitch to Z=-lt, a square relief groove w wide down to dg, a head
dh x lh with a chamfered edge.

Over this domain the program decides at the control: the groove's speed (G96 at 120 m/min
until the groove's bottom comes inside the diameter where that needs more than 3000 rpm, d
about 14.97; G97 S3000 below) and, on the HNC-21T, whether the thread is one G76 block or
G82 passes (G76's last pass ends its depth x tan 30 deg further along the insert's flank,
which the head's edge leaves room for at some variants only: a test of d, w and dh
together)."""
from hnc_cam.cad.sketch import Outline, bar_stock, positive, require, revolve
from hnc_cam.geometry import Thread

DOMAIN = {"pitch": 1.5, "d": (14.0, 18.0), "lt": (18.0, 28.0), "w": (3.0, 4.0),
          "dh": (24.0, 30.0), "lh": (6.0, 10.0)}


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
