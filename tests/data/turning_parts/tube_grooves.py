"""Tube 40/24 with two OD grooves, 3 mm and 4 mm wide (the second wider than the insert)."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "42/20x45+1"


def part():
    pts = [(12, 0), (19, 0), (20, -1), (20, -10), (18, -10), (18, -13), (20, -13), (20, -25),
           (18, -25), (18, -29), (20, -29), (20, -39), (19, -40), (12, -40)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
