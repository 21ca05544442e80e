"""Pipe nipple with a 1:16 taper thread M20x1.5 (DIN 158 style) narrowing toward its end, a
30 deg relief behind it and a collar (plain build123d)."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve
from hnc_cam.geometry import Thread

STOCK = "30x40+1"
# 20 mm major diameter at the thread's large end (Z-14), 1/16 less per mm toward the face
THREADS = [Thread(z_start=0.0, z_end=-14.0, diameter=20.0, pitch=1.5, taper=1 / 16)]


def part():
    pts = [(0, 0), (8.76, 0), (9.5875, -0.8), (10, -14), (8.9, -15.905), (8.9, -18), (13, -18),
           (13, -35), (0, -35)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
