"""M16x1.5 stud with a 30 deg thread relief and a collar (plain build123d)."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve
from hnc_cam.geometry import Thread

STOCK = "26x50+1"
THREADS = [Thread(z_start=0.0, z_end=-20.0, diameter=16.0, pitch=1.5)]


def part():
    pts = [(0, 0), (7, 0), (8, -1), (8, -20), (6.9, -21.906), (6.9, -24), (12, -24),
           (12, -40), (0, -40)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
