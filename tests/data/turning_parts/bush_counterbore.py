"""Bush 40 mm x 30 mm with a 20 mm bore and a 28 mm counterbore 8 mm deep from its left end,
1 mm chamfers on the outside's edges and 0.5 mm on the bore's mouth, plain build123d: the
counterbore's floor faces the chuck."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "42/16x80+1"


def part():
    pts = [(10.5, 0), (19, 0), (20, -1), (20, -29), (19, -30), (14, -30), (14, -22),
           (10, -22), (10, -0.5), (10.5, 0)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
