"""Shaft 63.4 mm, 80 mm long, a blind bore 24.2 mm 40 mm deep whose mouth is rounded R2 into
the face, a 43.2 mm journal 20 mm long."""
from hnc_cam.cad.sketch import Outline, revolve

STOCK = "66x95+1"


def part():
    s = Outline((0, -40))
    s.line_to(12.1, -40)
    s.line_to(12.1, 0, fillet=2)
    s.line_to(21.6, 0, chamfer=1)
    s.line_to(21.6, -20)
    s.line_to(31.7, -20, chamfer=1)
    s.line_to(31.7, -80)
    s.line_to(0, -80)
    return revolve(s.segments())
