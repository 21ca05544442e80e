"""Long thin shaft, 12 mm turned 100 mm long from a 16 mm bar, plain build123d."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "16x125+1"


def part():
    pts = [(0, 0), (5, 0), (6, -1), (6, -60), (7, -60), (7.5, -60.5), (7.5, -99), (7, -100),
           (0, -100)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
