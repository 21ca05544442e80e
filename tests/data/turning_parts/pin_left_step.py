"""Pin 30 mm x 40 mm with a 20 mm journal 12 mm long on its left end, 1 mm chamfers on
every edge, plain build123d: the journal's shoulder faces the chuck."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "32x100+1"


def part():
    pts = [(0, 0), (14, 0), (15, -1), (15, -27), (14, -28), (10, -28), (10, -39),
           (9, -40), (0, -40)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
