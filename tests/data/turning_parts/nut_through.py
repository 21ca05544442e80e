"""Round nut 36 mm x 20 mm from 38 mm bar with an M24x1.5 inside thread through its whole
length: plain build123d. The bore is modelled at the thread's minor diameter
(24 - 1.0825 x 1.5 = 22.376), chamfered at its mouth; both outer edges chamfered 1 mm."""
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

from hnc_cam.geometry import Thread

STOCK = "38x70+1"
MINOR = 24 - 1.0825 * 1.5
THREADS = [Thread(z_start=0.0, z_end=-20.0, diameter=24.0, pitch=1.5, internal=True)]


def part():
    r = MINOR / 2
    pts = [(r + 1, 0), (17, 0), (18, -1), (18, -19), (17, -20), (r, -20), (r, -1)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
