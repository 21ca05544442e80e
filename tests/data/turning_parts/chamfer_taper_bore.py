"""Bush 52/21.6 mm, 42.7 mm long: a 32.6 mm journal, a taper to 35 mm, a chamfer between the
35 mm cylinder and the taper up to the 52 mm collar; drilled through."""
from hnc_cam.cad.sketch import Outline, revolve

def part():
    s = Outline((10.8, 0))
    s.line_to(16.3, 0, chamfer=1.29)
    s.line_to(16.3, -12.4, chamfer=0.84)
    s.line_to(17.5, -15.413)
    s.line_to(17.5, -34.4, chamfer=1.67)
    s.line_to(26, -38.55)
    s.line_to(26, -42.7)
    s.line_to(10.8, -42.7)
    s.close()
    return revolve(s.segments())
