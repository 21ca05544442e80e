"""Shaft 43.8 mm, 105 mm long, a blind bore 18.8 mm 25.5 mm deep with a flat bottom, a
fillet R1.55 on the face's edge, a shallow groove 41.56 mm, a chamfer at the left end."""
from hnc_cam.cad.sketch import Outline, revolve

STOCK = "49.8x150"


def part():
    s = Outline((0, -25.5))
    s.line_to(9.4, -25.5)
    s.line_to(9.4, 0)
    s.line_to(21.9, 0, fillet=1.55)
    s.line_to(21.9, -42.2)
    s.line_to(20.78, -42.2)
    s.line_to(20.78, -47.56)
    s.line_to(21.9, -47.56)
    s.line_to(21.9, -105, chamfer=2)
    s.line_to(0, -105)
    return revolve(s.segments())
