# A knob as a plain build123d modelling script: no part() function, no STOCK.
# M12x1.5 shank at the right, thread relief, 45 deg cone, neck, 63 deg shoulder, head.
from build123d import *
from hnc_cam.geometry import Thread

with BuildPart() as p:
    with BuildSketch(Plane.XZ) as s:
        with BuildLine():
            Polyline((0, 0), (5, 0), (6, -1), (6, -20), (4.9, -20), (4.9, -23), (7, -23),
                     (10, -26), (10, -31), (14, -33), (14, -55), (12, -58), (0, -58),
                     close=True)
        make_face()
    revolve(axis=Axis.Z)

part = p.part
THREADS = [Thread(z_start=0.0, z_end=-19.0, diameter=12.0, pitch=1.5)]
