"""Sleeve 40 mm x 45 mm from solid bar with a blind bore 20 mm, 30 mm deep to its
shoulder, ending in the 118 deg drill point; 1 mm chamfers outside and at the bore's mouth,
plain build123d."""
import math

from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "42x60+1"

TIP = 10 / math.tan(math.radians(59))  # the 20 mm drill's point: 6.01 mm high


def part():
    pts = [(11, 0), (19, 0), (20, -1), (20, -45), (0, -45), (0, -30 - TIP), (10, -30),
           (10, -1)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
