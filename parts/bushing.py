"""Bushing: a plain sleeve with a through bore, outer chamfers at both ends and a chamfer at
the bore's right edge (the bore's left edge takes ``back_chamfer``, 0 by default: from the
right it needs a back-chamfering tool or a second setup).

Parameters (mm): outer_diameter, bore_diameter, length, chamfer (outer edges, 45 deg),
inner_chamfer (right bore edge, 45 deg), back_chamfer (left bore edge, 45 deg).
Stock: a tube with a bore 3 mm under the part's bore.
"""
from __future__ import annotations

from hnc_cam.cad.sketch import Outline, non_negative, positive, require, revolve, tube_stock


def STOCK(outer_diameter=40.0, bore_diameter=22.0, length=30.0, **_):
    return tube_stock(outer_diameter, bore_diameter, length)


#: the sizes the family is offered in: the macro program (hnc-cam family --macro) holds
#: over them and refuses a set outside them at the control
DOMAIN = {
    "outer_diameter": (36, 48),
    "bore_diameter": (19, 26),
    "length": (24, 40),
    "chamfer": (0.5, 1.5),
    "inner_chamfer": (0.5, 1.5),
}


def sketch(outer_diameter: float = 40.0, bore_diameter: float = 22.0, length: float = 30.0,
           chamfer: float = 1.0, inner_chamfer: float = 1.0, back_chamfer: float = 0.0):
    """The closed half-section (radius, Z): from the bore edge of the right face outward,
    along the outside to the left face, then back along the bore (ccw in the Z-right view)."""
    positive(outer_diameter=outer_diameter, bore_diameter=bore_diameter, length=length)
    non_negative(chamfer=chamfer, inner_chamfer=inner_chamfer, back_chamfer=back_chamfer)
    R, rb, c, ci, cb = outer_diameter / 2, bore_diameter / 2, chamfer, inner_chamfer, back_chamfer
    require(rb < R, f"bore_diameter={bore_diameter:g} must be less than "
                    f"outer_diameter={outer_diameter:g}")
    require(rb + max(ci, cb) < R - c,
            f"the wall ((outer_diameter - bore_diameter)/2 = {R - rb:g}) is too thin for "
            f"chamfer={c:g} and inner_chamfer={ci:g}/back_chamfer={cb:g}")
    require(2 * c < length, f"two chamfers (chamfer={c:g}) do not fit on length={length:g}")
    require(ci + cb < length, f"inner_chamfer={ci:g} + back_chamfer={cb:g} must be less than "
                              f"length={length:g}")
    s = Outline((rb + ci, 0.0))
    s.line_to(R, 0.0, chamfer=c)
    s.line_to(R, -length, chamfer=c)
    if cb > 0:
        s.line_to(rb + cb, -length)
        s.line_to(rb, -length + cb)
    else:
        s.line_to(rb, -length)
    if ci > 0:
        s.line_to(rb, -ci)
        s.line_to(rb + ci, 0.0)
    else:
        s.line_to(rb, 0.0)
    return s.segments()


def part(outer_diameter: float = 40.0, bore_diameter: float = 22.0, length: float = 30.0,
         chamfer: float = 1.0, inner_chamfer: float = 1.0, back_chamfer: float = 0.0):
    return revolve(sketch(outer_diameter, bore_diameter, length, chamfer, inner_chamfer,
                          back_chamfer))
