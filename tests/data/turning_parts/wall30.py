"""Shaft whose middle steps down along a 30 deg descending wall, plain build123d."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "34x60+1"


def part():
    pts = [(0, 0), (9, 0), (10, -1), (10, -15), (14, -15), (14, -25), (11, -30.197),
           (11, -40), (16, -40), (16, -55), (0, -55)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
