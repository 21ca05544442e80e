"""Shaft 78 mm, 137 mm long, plain build123d: a blind bore 33 mm 59.3 mm deep whose flat
bottom the boring bar faces to the centre, grooves and steps on the outside."""
from build123d import Axis, BuildLine, BuildPart, BuildSketch, Plane, Polyline, make_face, revolve


def part():
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline((0, -59.3), (16.5, -59.3), (16.5, 0), (30.5, 0), (30.5, -46.9),
                         (33.6, -46.9), (33.6, -70.8), (30.75, -70.8), (30.75, -78.18),
                         (33.6, -78.18), (33.6, -111.6), (39, -111.6), (39, -122.9),
                         (36.16, -122.9), (36.16, -129.81), (39, -129.81), (39, -137),
                         (0, -137), close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
