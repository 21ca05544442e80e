"""Pin 20 mm with a ball end R10 (no face: the contour runs from the centre), 40 mm long."""
from hnc_cam.cad.sketch import Outline, revolve

STOCK = "24x60+1"


def part():
    s = Outline((0, 0))
    s.arc_to(10, -10, radius=10, cw=False)
    s.line_to(10, -40)
    s.line_to(0, -40)
    return revolve(s.segments())
