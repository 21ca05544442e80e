"""Spacer: a journal d1 long l1, a collar d2 to the left end, chamfers."""
from hnc_cam.cad.sketch import Outline, bar_stock, positive, require, revolve

# d1 17.95-18.6: the G71 is split at the end of the collar's face (the inner cycle at the rpm
# of its top, which moves with d1). Below about 17.9 the split is at X18.7 and jumps to
# d1 + 0.82 where the nose's path along the face begins past it; from about 18.7 it falls on
# the 45 deg chamfer, whose written crossing ties at half the last digit at half the sets
# (the planner's arithmetic breaks the tie either way) and leaves a corner the compensated
# path follows
DOMAIN = {"d1": (17.95, 18.6)}


def STOCK(length=40.0, d2=30.0, **_):
    return bar_stock(d2, length)


def sketch(length: float = 40.0, d1: float = 18.0, d2: float = 30.0, l1: float = 15.0,
           chamfer: float = 0.8):
    positive(length=length, d1=d1, d2=d2, l1=l1, chamfer=chamfer)
    require(d1 < d2 - 2 * chamfer, "need d1 < d2 - 2*chamfer")
    require(l1 + chamfer < length, "need l1 + chamfer < length")
    s = Outline((0.0, 0.0))
    s.line_to(d1 / 2, 0.0, chamfer=chamfer)
    s.line_to(d1 / 2, -l1)
    s.line_to(d2 / 2, -l1, chamfer=chamfer)
    s.line_to(d2 / 2, -length)
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 40.0, d1: float = 18.0, d2: float = 30.0, l1: float = 15.0,
         chamfer: float = 0.8):
    return revolve(sketch(length, d1, d2, l1, chamfer))
