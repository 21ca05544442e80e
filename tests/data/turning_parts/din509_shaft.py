"""Shaft with a DIN 509-style undercut (15 deg run-in, R0.6 into the shoulder), plain build123d."""
from build123d import (BuildLine, BuildPart, BuildSketch, Line, Plane, Polyline, ThreePointArc,
                       Axis, make_face, revolve)

STOCK = "42x65+1"


def part():
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline((0, 0), (14, 0), (15, -1), (15, -26.5), (14.7, -27.62), (14.7, -29.4))
                ThreePointArc((14.7, -29.4), (14.876, -29.824), (15.3, -30))
                Polyline((15.3, -30), (19, -30), (20, -31), (20, -60), (0, -60))
                Line((0, -60), (0, 0))
            make_face()
        revolve(axis=Axis.Z)
    return p.part
