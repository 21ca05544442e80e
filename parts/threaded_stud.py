"""Threaded stud M20x1.5 with a thread relief groove and a collar.

From the right face (Z0): a 45 deg lead chamfer (to the thread's minor diameter) on the
thread's major diameter ``thread_diameter``, the thread to Z=-``thread_length``, a relief
groove (DIN 76 style: a run-out flank at 30 deg to the axis from the thread down to
``relief_diameter``, then ``relief_width`` long at that diameter, its bottom corners rounded
R``relief_radius``), the
shoulder up to the collar diameter ``collar_diameter`` (chamfered) and the collar to the left
end Z=-``length`` (chamfered).

Parameters (mm): length, thread_diameter, pitch, thread_length, relief_width,
relief_diameter, relief_radius, collar_diameter, chamfer. THREADS: one external metric
60 deg thread from Z0 to Z=-thread_length.
"""
from __future__ import annotations

import math

from hnc_cam.cad.sketch import Outline, bar_stock, non_negative, positive, require, revolve
from hnc_cam.geometry import Thread


def STOCK(length=50.0, collar_diameter=30.0, **_):
    return bar_stock(collar_diameter, length)


def THREADS(thread_diameter=20.0, pitch=1.5, thread_length=22.0, **_):
    return [Thread(z_start=0.0, z_end=-thread_length, diameter=thread_diameter, pitch=pitch,
                   starts=1, internal=False, standard="metric", angle=60.0)]


#: the sizes the family is offered in: the macro program (hnc-cam family --macro) holds
#: over them and refuses a set outside them at the control
DOMAIN = {
    "length": (47.5, 52.5),
    "thread_diameter": (19, 21),
    "thread_length": (21, 23),
    "relief_width": (4.3, 4.7),
    "relief_diameter": (16.8, 18.4),
    "relief_radius": (0.76, 0.84),
    "collar_diameter": (28.5, 31.5),
    "chamfer": (0.95, 1.05),
}


def sketch(length: float = 50.0, thread_diameter: float = 20.0, pitch: float = 1.5,
           thread_length: float = 22.0, relief_width: float = 4.5, relief_diameter: float = 17.6,
           relief_radius: float = 0.8, collar_diameter: float = 30.0, chamfer: float = 1.0):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    positive(length=length, thread_diameter=thread_diameter, pitch=pitch,
             thread_length=thread_length, relief_width=relief_width,
             relief_diameter=relief_diameter, collar_diameter=collar_diameter)
    non_negative(relief_radius=relief_radius, chamfer=chamfer)
    rt, rg, rc = thread_diameter / 2, relief_diameter / 2, collar_diameter / 2
    lead = 0.6134 * pitch + 0.1  # lead chamfer just below the minor diameter
    run = (rt - rg) * math.tan(math.radians(60))  # 30 deg flank: axial run of the relief
    minor = thread_diameter - 2 * 0.6134 * pitch
    require(lead < rt, f"pitch={pitch:g} is too coarse for thread_diameter={thread_diameter:g}")
    require(rg < rt, f"relief_diameter={relief_diameter:g} must be less than "
                     f"thread_diameter={thread_diameter:g}")
    require(relief_diameter <= minor + 1e-9,
            f"relief_diameter={relief_diameter:g} must be at most the thread's minor diameter "
            f"{minor:.3f} (thread_diameter={thread_diameter:g}, pitch={pitch:g}): the tool "
            f"must run out of the thread into the relief")
    require(rt < rc - chamfer, f"need thread_diameter < collar_diameter - 2*chamfer (got "
                               f"thread_diameter={thread_diameter:g}, "
                               f"collar_diameter={collar_diameter:g}, chamfer={chamfer:g})")
    require(lead < thread_length, f"thread_length={thread_length:g} is shorter than the lead "
                                  f"chamfer {lead:.3f} (pitch={pitch:g})")
    require(2 * relief_radius < relief_width and relief_radius < rt - rg,
            f"relief_radius={relief_radius:g} does not fit the relief (relief_width="
            f"{relief_width:g}, depth {rt - rg:g} from thread_diameter/relief_diameter)")
    require(thread_length + run + relief_width < length - 2 * chamfer,
            f"thread_length={thread_length:g} + relief ({run:.3f} run-out + relief_width="
            f"{relief_width:g}) leaves no collar in length={length:g} (chamfer={chamfer:g})")
    z1 = -thread_length
    s = Outline((0.0, 0.0))
    s.line_to(rt - lead, 0.0)
    s.line_to(rt, -lead)
    s.line_to(rt, z1)
    s.line_to(rg, z1 - run, fillet=relief_radius, names="relief_radius, relief_width")
    s.line_to(rg, z1 - run - relief_width, fillet=relief_radius,
              names="relief_radius, relief_width")
    s.line_to(rc, z1 - run - relief_width, chamfer=chamfer,
              names="chamfer, relief_radius, collar_diameter, relief_diameter")
    s.line_to(rc, -length, chamfer=chamfer, names="chamfer, length")
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 50.0, thread_diameter: float = 20.0, pitch: float = 1.5,
         thread_length: float = 22.0, relief_width: float = 4.5, relief_diameter: float = 17.6,
         relief_radius: float = 0.8, collar_diameter: float = 30.0, chamfer: float = 1.0):
    return revolve(sketch(length, thread_diameter, pitch, thread_length, relief_width,
                          relief_diameter, relief_radius, collar_diameter, chamfer))
