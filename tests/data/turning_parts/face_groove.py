"""Flange-like disc 60 mm, 20 mm long, with a ring groove in its right face: 4 mm wide
between diameters 36 and 44, 3 mm deep (plain build123d)."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "62x50+1"


def part():
    pts = [(0, 0), (18, 0), (18, -3), (22, -3), (22, 0), (29, 0), (30, -1), (30, -20),
           (0, -20)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
