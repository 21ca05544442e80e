"""The swept region of an arc move built as one polygon, and a small material taken whole,
give the same regions and the same removals as the union of the pieces' hulls and the zone."""
from __future__ import annotations

import importlib

import numpy as np
import pytest
import shapely

from hnc_cam.nc.interp import run
from hnc_cam.sim import simulate
from hnc_cam.sim.tool import CHORD, sweep_hulls, tool_shape
from hnc_cam.tooling import Stock, load_machine

S = importlib.import_module("hnc_cam.sim.simulate")


def _outlines():
    mach = load_machine()
    out = []
    for t in (1, 2, 5, 7, 9):
        reg = mach.register(t)
        out.append(S._ccw_outline(tool_shape(reg)))
        out.append(S._ccw_outline(tool_shape(reg, 60.0)))
    return out


def _arc(c, r, a0, sweep):
    n = max(2, int(np.ceil(abs(sweep) / (2 * np.arccos(max(-1.0, 1 - CHORD / r))))))
    n = min(n, 300)
    t = a0 + sweep * np.arange(n + 1) / n
    return np.asarray(c) + r * np.column_stack([np.cos(t), np.sin(t)])


@pytest.mark.parametrize("seed", range(4))
def test_arc_sweep_is_the_union_of_its_hulls(seed):
    rng = np.random.default_rng(seed)
    outlines = _outlines()
    for _ in range(40):
        K = outlines[rng.integers(len(outlines))]
        r = float(np.exp(rng.uniform(np.log(0.05), np.log(40.0))))
        pts = _arc(rng.uniform(-5, 5, 2), r, rng.uniform(0, 2 * np.pi),
                   rng.uniform(0.02, 2 * np.pi) * rng.choice([-1, 1]))
        P, Q = pts[:-1], pts[1:]
        want = shapely.union_all(sweep_hulls(K, P, Q))
        got = S._path_sweep(K, P, Q)
        assert got.geom_type == "Polygon" and got.is_valid
        assert got.symmetric_difference(want).area <= 1e-9 * max(1.0, want.area)


def test_arc_sweep_of_a_full_circle_and_a_tool_larger_than_the_arc():
    K = _outlines()[0]  # 80 deg rhombic 12 mm edges, r 0.8
    for r, sweep in ((0.05, 2 * np.pi), (0.8, -2 * np.pi), (3.0, np.pi), (30.0, 0.01)):
        pts = _arc((1.0, 2.0), r, 0.3, sweep)
        P, Q = pts[:-1], pts[1:]
        want = shapely.union_all(sweep_hulls(K, P, Q))
        got = S._path_sweep(K, P, Q)
        assert got.symmetric_difference(want).area <= 1e-9 * want.area


def test_arc_sweep_with_a_repeated_point_falls_back_to_the_union():
    K = _outlines()[2]
    pts = _arc((0.0, 0.0), 2.0, 0.0, 1.0)
    pts = np.concatenate([pts[:3], pts[2:]])  # a zero-length piece
    P, Q = pts[:-1], pts[1:]
    want = shapely.union_all(sweep_hulls(K, P, Q))
    assert S._path_sweep(K, P, Q).symmetric_difference(want).area <= 1e-12


PROGRAM = """%1
T0101
M03 S800
G00 X44 Z2
G00 X36 Z1
G01 Z-20 F0.2
G02 X40 Z-22 R2
G01 X44
G00 Z1
G00 X30
G01 Z-10 F0.2
G03 X34 Z-12 R2
G01 Z-20
G01 X44
G00 Z1
G00 X26 Z1
G01 Z0
G03 X32 Z-3 R3
G01 X44
G00 X80 Z80
M30
"""


def test_small_material_taken_whole_removes_what_the_zones_remove(monkeypatch):
    machine = load_machine()
    tp = run(PROGRAM, machine, start=(50.0, 80.0))
    stock = Stock.parse("40x60")
    whole = simulate(tp, stock, machine)
    monkeypatch.setattr(S, "SMALL_MATERIAL", -1)
    zoned = simulate(tp, stock, machine)
    assert (whole.removed_area > 0).sum() >= 6
    assert np.array_equal(whole.removed_area > 0, zoned.removed_area > 0)
    assert np.allclose(whole.removed_area, zoned.removed_area, rtol=0, atol=1e-9)
    assert whole.material.symmetric_difference(zoned.material).area <= 1e-9
    assert [str(i) for i in whole.issues] == [str(i) for i in zoned.issues]
    # the passes cut down to their tip paths (tip code 3: the tip is the tool's lowest point)
    mat = whole.material
    assert not mat.contains(shapely.Point(-15.0, 17.1)) and mat.contains(shapely.Point(-15.0, 16.9))
    assert not mat.contains(shapely.Point(-5.0, 15.1)) and mat.contains(shapely.Point(-5.0, 14.9))
    assert mat.contains(shapely.Point(-25.0, 19.9))
