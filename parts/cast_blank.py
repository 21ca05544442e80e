"""Near-net cast (or forged) handle blank with a wavy profile, finished with G73.

From the right face (Z0): the end face up to the base diameter ``diameter``, then ``waves``
full waves of tangent arcs (each wave a crest and a hollow of ``amplitude`` mm, radial, about
the base diameter, ``wave_length`` long), then a plain land of diameter ``diameter`` to the
left end Z=-``length`` (chamfered). The arcs meet tangentially (a smooth cast surface).

The defaults keep the steepest flank at 39 deg to the axis (a 35 deg copying insert in a
93 deg holder reaches every hollow).

Parameters (mm): length, diameter, amplitude, wave_length, waves (count), chamfer.
Stock: the casting, 2 mm all round (``offset:2``).
"""
from __future__ import annotations


from hnc_cam.cad.sketch import Outline, revolve

STOCK = "offset:2"


def sketch(length: float = 90.0, diameter: float = 40.0, amplitude: float = 2.5,
           wave_length: float = 28.0, waves: int = 3, chamfer: float = 1.0):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    Rb = diameter / 2
    h = wave_length / 4  # half-width of each arc
    if not (0 < amplitude < h and amplitude < Rb / 2):
        raise ValueError("need 0 < amplitude < wave_length/4 and amplitude < diameter/4")
    if waves < 1 or waves * wave_length > length - 2 * chamfer - 1:
        raise ValueError("the waves do not fit in the length")
    rho = (h * h + amplitude * amplitude) / (2 * amplitude)  # arc radius
    s = Outline((0.0, 0.0))
    s.line_to(Rb, 0.0)
    z = 0.0
    for _ in range(waves):
        # crest: centre below the base line (convex), then hollow: centre above (concave)
        s.arc_to(Rb, z - 2 * h, center=(Rb - (rho - amplitude), z - h), cw=False)
        s.arc_to(Rb, z - 4 * h, center=(Rb + (rho - amplitude), z - 3 * h), cw=True)
        z -= 4 * h
    s.line_to(Rb, -length, chamfer=chamfer)
    s.line_to(0.0, -length)
    return s.segments()


def part(length: float = 90.0, diameter: float = 40.0, amplitude: float = 2.5,
         wave_length: float = 28.0, waves: int = 3, chamfer: float = 1.0):
    return revolve(sketch(length, diameter, amplitude, wave_length, waves, chamfer))
