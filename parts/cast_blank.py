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


from hnc_cam.cad.sketch import Outline, non_negative, positive, require, revolve

STOCK = "offset:2"


#: the sizes the family is offered in: the macro program (hnc-cam family --macro) holds
#: over them and refuses a set outside them at the control
DOMAIN = {
    "length": (85, 95),
    "diameter": (38, 42),
    "amplitude": (2.3, 2.7),
    "wave_length": (26.5, 29.5),
    "chamfer": (0.8, 1.2),
}


def sketch(length: float = 90.0, diameter: float = 40.0, amplitude: float = 2.5,
           wave_length: float = 28.0, waves: int = 3, chamfer: float = 1.0):
    """The half-section (radius, Z) as exact lines and arcs, right face first."""
    positive(length=length, diameter=diameter, amplitude=amplitude, wave_length=wave_length)
    non_negative(chamfer=chamfer)
    Rb = diameter / 2
    h = wave_length / 4  # half-width of each arc
    require(amplitude < h, f"amplitude={amplitude:g} must be less than wave_length/4={h:g} "
                           f"(the arcs would fold over)")
    require(amplitude < Rb / 2, f"amplitude={amplitude:g} must be less than diameter/4={Rb / 2:g}")
    require(waves >= 1, f"waves={waves} must be at least 1")
    require(waves * wave_length <= length - 2 * chamfer - 1,
            f"waves={waves} of wave_length={wave_length:g} do not fit in length={length:g} "
            f"(with chamfer={chamfer:g} and a 1 mm land)")
    require(chamfer < Rb, f"chamfer={chamfer:g} must be less than diameter/2={Rb:g}")
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
