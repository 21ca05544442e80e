"""Cup 50 mm x 40 mm from solid bar: a 36 mm bore 25 mm deep with a flat bottom, a chamfer
at its mouth and on the outside edge, plain build123d."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "52x50+1"


def part():
    pts = [(19, 0), (24, 0), (25, -1), (25, -40), (0, -40), (0, -25), (18, -25), (18, -1)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
