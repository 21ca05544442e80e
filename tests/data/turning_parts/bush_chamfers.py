"""Bush 40 mm x 30 mm with a 24 mm bore, 1 mm chamfers on both edges of the outside and of
the bore (the bore's left chamfer faces the chuck), plain build123d."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "42/20x80+1"


def part():
    pts = [(13, 0), (19, 0), (20, -1), (20, -29), (19, -30), (13, -30), (12, -29),
           (12, -1), (13, 0)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
