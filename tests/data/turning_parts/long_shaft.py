"""Long stepped shaft (30 mm) turned from a bar twice its diameter, plain build123d."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "60x92+1"


def part():
    pts = [(0, 0), (9, 0), (10, -1), (10, -40), (14, -40), (15, -41), (15, -79), (14, -80),
           (0, -80)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
