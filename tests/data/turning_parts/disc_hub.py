"""Disc 150 mm with a 50 mm hub on the right (face-dominated), plain build123d."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "155x30+1.5"


def part():
    pts = [(0, 0), (24, 0), (25, -1), (25, -15), (74, -15), (75, -16), (75, -27), (0, -27)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
