"""Cap 50 mm x 50 mm from solid bar: a 30 mm counterbore 15 mm deep, then a 12 mm hole
40 mm deep (to its shoulder) ending in the 118 deg drill point; chamfers outside and at
the counterbore's mouth, plain build123d."""
import math

from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "52x70+1"

TIP = 6 / math.tan(math.radians(59))  # the 12 mm drill's point


def part():
    pts = [(16, 0), (24, 0), (25, -1), (25, -50), (0, -50), (0, -40 - TIP), (6, -40),
           (6, -15), (15, -15), (15, -1)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
