"""Bush 47.4/20 mm, 25.2 mm long: a convex arc R3.512 rising from a 36.6 mm journal 1 mm
from the face, a shallow 44.8 mm groove, a 47.4 mm step; drilled through."""
from hnc_cam.cad.sketch import Outline, revolve

def part():
    s = Outline((10, 0))
    s.line_to(18.3, 0)
    s.line_to(18.3, -1)
    s.arc_to(18.3, -5.1, radius=3.512, cw=False)
    s.line_to(18.3, -6.1)
    s.line_to(22.9, -6.1, chamfer=1.57)
    s.line_to(22.9, -11.6)
    s.line_to(22.4, -11.6)
    s.line_to(22.4, -15.23)
    s.line_to(22.9, -15.23)
    s.line_to(22.9, -18.2)
    s.line_to(23.7, -18.2)
    s.line_to(23.7, -25.2)
    s.line_to(10, -25.2)
    s.close()
    return revolve(s.segments())
