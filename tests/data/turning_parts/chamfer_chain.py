"""Shaft 37.2 mm with a 19.6 mm journal 4.4 mm long and a 24.2 mm neck: a chamfer on every
corner, the journal's root (a concave corner) too."""
from hnc_cam.cad.sketch import Outline, revolve


def part():
    s = Outline((0, 0))
    s.line_to(9.8, 0)
    s.line_to(9.8, -4.4, chamfer=0.55)
    s.line_to(12.1, -4.4, chamfer=0.73)
    s.line_to(12.1, -36.1, chamfer=1.47)
    s.line_to(18.6, -36.1, chamfer=1.04)
    s.line_to(18.6, -41.7)
    s.line_to(0, -41.7)
    return revolve(s.segments())
