"""Regions of the half-plane: the stock, the model, conversions.

The simulator works in shapely coordinates ``(z, x)``: Z horizontal, X (radius) vertical, so a
plot shows the part the way the manual's figures do. Everything else in the package uses
``(x, z)`` tuples; :func:`zx` converts.

Arcs of the model are sampled with the chord error :data:`hnc_cam.sim.tool.CHORD` (0.0005 mm)
through the kernel's :func:`hnc_cam.geometry.sample_chain`; distances that the verifier reports
are measured to the exact Line/Arc segments, not to this polygon.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import shapely
import shapely.errors
from shapely.geometry import Polygon, box
from shapely.geometry.base import BaseGeometry

from ..errors import StockError
from ..geometry import Point, Segment, TurnedProfile, sample_chain
from ..tooling import Stock
from .tool import CHORD


def zx(p: Point) -> tuple[float, float]:
    """(x, z) kernel point -> (z, x) simulator point."""
    return (p[1], p[0])


def _chain_zx(segs: Sequence[Segment]) -> list[tuple[float, float]]:
    return [zx(p) for p in sample_chain(segs, CHORD)]


def profile_polygon(profile: TurnedProfile) -> BaseGeometry:
    """The part's cross-section above the axis (X >= 0) as a shapely polygon in (z, x).

    The outside chain runs from the right face toward the chuck; it is closed by a line
    down to the axis (or to the bore's left end) at its Z, and back along the axis (or the bore
    chain) to the start.
    """
    if not profile.outside:
        raise StockError(f"model {profile.name!r}: the profile has no outside contour")
    # the points as an array (the same doubles as the (z, x) tuples, built at once)
    out = np.asarray(sample_chain(profile.outside, CHORD), dtype=float)[:, ::-1]
    if profile.bore:
        bore = np.asarray(sample_chain(profile.bore, CHORD), dtype=float)[:, ::-1]
        ring = np.concatenate([out, bore[::-1]])
    else:
        z_end, z_start = out[-1, 0], out[0, 0]
        ring = np.concatenate([out, [(z_end, 0.0), (z_start, 0.0)]])
    poly = Polygon(ring)
    if not poly.is_valid:
        poly = shapely.make_valid(poly)
        poly = shapely.union_all([g for g in getattr(poly, "geoms", [poly])
                                  if g.geom_type in ("Polygon", "MultiPolygon")])
    half = box(-1e9, 0.0, 1e9, 1e9)
    return poly.intersection(half)


def stock_region(stock: Stock | BaseGeometry, model: TurnedProfile | None = None) -> BaseGeometry:
    """The raw material as a region in (z, x).

    * bar ``DxL[+F]``: Z in [F - L, F], X in [0, D/2];
    * tube ``D/dxL[+F]``: X in [d/2, D/2];
    * ``offset:A``: the model grown by A all round (round joins), clipped to X >= 0; needs
      ``model``.
    A shapely geometry is taken as the region itself.
    """
    if isinstance(stock, BaseGeometry):
        return stock
    if stock.kind == "offset":
        if model is None:
            raise StockError(f"stock {stock.spec!r}: an offset:A stock needs the model "
                             f"(--model PART)")
        grown = profile_polygon(model).buffer(stock.allowance, quad_segs=64)
        return grown.intersection(box(-1e9, 0.0, 1e9, 1e9))
    x0 = stock.bore / 2 if stock.kind == "tube" else 0.0
    return box(stock.z_left, x0, stock.z_right, stock.diameter / 2)


def chuck_zone(region: BaseGeometry, width: float = 1e-3) -> BaseGeometry:
    """The strip at the left (chucked, minimum Z) end of a stock region: material connected to
    it stays on the machine; material cut loose from it falls off."""
    z0, x0, z1, x1 = region.bounds
    return box(z0 - 1.0, x0 - 1.0, z0 + width, x1 + 1.0)


def jaw_region(region: BaseGeometry, machine) -> BaseGeometry | None:
    """The chuck's jaws in (z, x): a solid ``jaw_length`` long in Z whose front face is
    ``grip`` mm in from the stock's left end, from the largest radius of the stock inside
    the grip up ``jaw_height`` mm; None when the machine gives no grip (jaws not modelled)
    or the region is empty."""
    grip = float(getattr(machine, "grip", 0.0) or 0.0)
    if grip <= 0 or region.is_empty:
        return None
    z0 = region.bounds[0]
    held = inter(region, box(z0 - 1.0, -1.0, z0 + grip, 1e9))
    r = held.bounds[3] if not held.is_empty else region.bounds[3]
    return box(z0 + grip - machine.jaw_length, r, z0 + grip, r + machine.jaw_height)


def polygons(g: BaseGeometry) -> list[Polygon]:
    """The polygons of a geometry (ignoring lines and points left by overlays)."""
    if g.is_empty:
        return []
    if g.geom_type == "Polygon":
        return [g]
    if hasattr(g, "geoms"):
        out: list[Polygon] = []
        for p in g.geoms:
            out.extend(polygons(p))
        return out
    return []


def clean(g: BaseGeometry) -> BaseGeometry:
    """Keep only the areal part of an overlay result."""
    t = g.geom_type
    if t == "Polygon":
        return g
    if t == "MultiPolygon":
        return g
    ps = [p for p in polygons(g) if p.area > 0]
    if not ps:
        return Polygon()
    if len(ps) == 1:
        return ps[0]
    return shapely.MultiPolygon(ps)


#: snap-rounding grid (mm) used when GEOS meets a robustness failure on nearly coincident edges
GRID = 1e-6


def _robust(op, *args):
    try:
        return op(*args)
    except shapely.errors.GEOSException:
        return op(*args, grid_size=GRID)


def diff(a: BaseGeometry, b: BaseGeometry) -> BaseGeometry:
    """``a - b`` (areal part), retried on a 1e-6 mm grid if GEOS reports a topology error."""
    return clean(_robust(shapely.difference, a, b))


def inter(a: BaseGeometry, b: BaseGeometry) -> BaseGeometry:
    """``a & b`` (areal part), retried on a 1e-6 mm grid if GEOS reports a topology error."""
    return clean(_robust(shapely.intersection, a, b))


def union(geoms) -> BaseGeometry:
    """Union of many geometries, retried on a 1e-6 mm grid if GEOS reports a topology error."""
    return clean(_robust(shapely.union_all, geoms))
