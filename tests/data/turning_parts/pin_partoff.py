"""Pin 20 mm x 30 mm with 1 mm chamfers at both ends, parted off from a long 25 mm bar,
plain build123d."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "25x80+1"


def part():
    pts = [(0, 0), (9, 0), (10, -1), (10, -29), (9, -30), (0, -30)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
