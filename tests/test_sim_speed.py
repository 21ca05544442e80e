"""How the simulator takes its work (short passes move by move, bands cut at the region's
height over each piece, per-move columns read once): the same removal, material and findings
as one move after another."""
from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
import shapely

from hnc_cam.nc.interp import run
from hnc_cam.nc.toolpath import columns
from hnc_cam.sim import simulate, stock_region
from hnc_cam.sim.area import heights_over, region_edges
from hnc_cam.sim.region import diff
from hnc_cam.tooling import Insert, Machine, Register, Stock

S = importlib.import_module("hnc_cam.sim.simulate")

CNMG = Machine(registers={1: Register(number=1, radius=0.8, tip=3,
                                      insert=Insert.parse("CNMG120408"), approach=95.0)})


def _one_by_one(tp, stock, machine):
    """Reference: each move's swept region taken out of the whole material in program order."""
    sweeper = S._Sweeper(machine, tp.moves)
    material = stock_region(stock)
    areas = []
    sweeps, _ = sweeper.sweeps(list(tp.moves))
    for g in sweeps:
        if g is None:
            areas.append(0.0)
            continue
        after = diff(material, g)
        a = material.area - after.area
        areas.append(a if a > 1e-12 else 0.0)
        if a > 1e-12:
            material = after
    return np.array(areas), material


def _g71_like(passes: int) -> str:
    """Roughing passes of a G71 cycle written out: a cut toward the chuck, a 45 deg retract,
    a rapid out and back to the start: five moves a pass, each pass 1 mm deeper."""
    out = ["%1", "T0101", "M03 S800", "G00 X44 Z2"]
    for p in range(passes):
        d = 38 - 2 * p
        out += [f"G00 X{d:.3f} Z2", f"G01 Z{-30 + 2 * p:.3f} F0.25", f"G00 U1 W1",
                f"G00 X44", "G00 Z2"]
    out += ["G00 X80 Z80", "M30"]
    return "\n".join(out) + "\n"


def _counting():
    taken = {"bands": 0, "declined": 0, "moves": 0}
    real_bands, real_moves = S._batch_by_bands, S._batch_by_moves

    def by_bands(*a, **k):
        got = real_bands(*a, **k)
        taken["bands" if got is not None else "declined"] += 1
        return got

    def by_moves(*a, **k):
        taken["moves"] += 1
        return real_moves(*a, **k)

    def restore():
        S._batch_by_bands, S._batch_by_moves = real_bands, real_moves

    S._batch_by_bands, S._batch_by_moves = by_bands, by_moves
    return taken, restore


def test_short_passes_go_move_by_move_with_the_reference_result():
    text = _g71_like(6)
    tp = run(text, CNMG, file="g71.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    ref_areas, ref_material = _one_by_one(tp, stock, CNMG)
    taken, restore = _counting()
    try:
        m = simulate(tp, stock, CNMG)
    finally:
        restore()
    # every pass is short: no batch is taken with bands, each one move by move
    assert taken["bands"] == 0 and taken["moves"] >= 6
    assert m.removed_area == pytest.approx(ref_areas, abs=1e-9)
    assert shapely.symmetric_difference(m.material, ref_material).area < 1e-9
    # each pass's cut removes material, its rapids nothing (they run in what the cut left)
    cuts = [k for k, mv in enumerate(tp.moves) if mv.kind == "line"]
    assert len(cuts) == 6 and all(m.removed_area[k] > 1.0 for k in cuts)
    assert not m.issues


def test_short_pass_rule_changes_nothing_the_simulator_reports():
    # the same program with the rule off (every pass tried with bands first): the same
    # removal, material, findings and notes
    text = _g71_like(4).replace("G00 X44\n", "G00 X30 W-5\nG00 X44\n", 1)  # a rapid into material
    tp = run(text, CNMG, file="g71c.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    m = simulate(tp, stock, CNMG)
    old = S.SHORT_PASS
    S.SHORT_PASS = 0
    try:
        ref = simulate(tp, stock, CNMG)
    finally:
        S.SHORT_PASS = old
    assert m.removed_area == pytest.approx(ref.removed_area, abs=1e-9)
    assert shapely.symmetric_difference(m.material, ref.material).area < 1e-9
    assert [(i.line, i.kind, i.message, i.at) for i in m.issues] == \
        [(i.line, i.kind, i.message, i.at) for i in ref.issues]
    assert [(i.line, i.kind) for i in m.notes] == [(i.line, i.kind) for i in ref.notes]
    assert any(i.kind == "collision" for i in m.issues)


def test_long_passes_still_take_bands_and_equal_the_reference():
    # passes of 62 moves along a wavy path: taken a batch at a time with bands
    blocks = ["%1", "T0101", "M03 S800", "G00 X44 Z2"]
    for p in range(4):
        r = 19.5 - 0.3 * p
        blocks += [f"G00 X{2 * r + 0.4:.4f} Z1", f"G01 X{2 * r:.4f} Z0 F200"]
        blocks += [f"G01 X{2 * (r + 0.1 * math.sin(0.3 * i)):.4f} Z{-0.5 * i:.3f}"
                   for i in range(1, 60)]
        blocks += ["G01 U1 W0.5", "G00 Z2"]
    text = "\n".join(blocks + ["G00 X80 Z80", "M30"]) + "\n"
    tp = run(text, CNMG, file="w.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    ref_areas, ref_material = _one_by_one(tp, stock, CNMG)
    taken, restore = _counting()
    try:
        m = simulate(tp, stock, CNMG)
    finally:
        restore()
    assert taken["bands"] >= 4
    assert m.removed_area == pytest.approx(ref_areas, abs=1e-9)
    assert shapely.symmetric_difference(m.material, ref_material).area < 1e-9


def test_heights_over_bounds_the_region_over_each_interval():
    rnd = np.random.default_rng(3)
    # a long top face, a wavy cut of short edges, a hole and a step
    wave = [(-0.05 * i, 10 + 0.3 * math.sin(0.2 * i)) for i in range(400)]
    ring = [(1.0, 0.0), (1.0, 12.0), (0.0, 12.0)] + wave + [(-20.0, 14.0), (-40.0, 14.0),
                                                          (-40.0, 0.0)]
    region = shapely.Polygon(ring).difference(shapely.Point(-30, 5).buffer(2))
    E = region_edges(region)
    z0 = rnd.uniform(-42, 2, 300)
    z1 = z0 + rnd.uniform(0, 3, 300)
    X = heights_over(E, z0, z1)
    for a, b, x in zip(z0, z1, X):
        strip = shapely.intersection(region, shapely.box(a, -1, b, 100))
        if strip.is_empty or strip.area == 0:
            continue
        top = strip.bounds[3]
        assert x >= top - 1e-12  # no point of the region over the interval above X
    # and tight where the region is a long flat face: its height exactly
    Xf = heights_over(E, np.array([-39.0]), np.array([-21.0]))
    assert Xf[0] == pytest.approx(14.0)
    # nothing over an interval off the region
    assert heights_over(E, np.array([50.0]), np.array([51.0]))[0] == -np.inf


def test_per_move_columns_are_the_toolpath_s():
    text = _g71_like(3)
    tp = run(text, CNMG, file="g71.nc", start=(60.0, 50.0))
    m = simulate(tp, Stock.parse("40x60"), CNMG)
    c = columns(tp.moves)
    got = m.move_columns(0, len(tp.moves))
    assert got["kind"].tolist() == c["kind"].tolist()
    assert got["register"].tolist() == c["register"].tolist()
    assert got["duration"].tolist() == c["duration"].tolist()
    # cycle time and air cut as read from the moves themselves
    assert m.cycle_time_s == pytest.approx(sum(mv.duration for mv in tp.moves), rel=1e-12)
    bare = S.Machined(material=m.material, stock=m.stock, toolpath=tp,
                      removed_area=m.removed_area, sweep_bounds=m.sweep_bounds,
                      shapes=m.shapes, machine=m.machine)
    assert bare.cycle_time_s == m.cycle_time_s
    assert bare.air_cut_fraction == m.air_cut_fraction


def test_shaft_program_verifies_the_same_with_the_rule_off():
    # a turned part with facing, G71 roughing and a finishing pass written out move by move
    text = "\n".join([
        "%1", "T0101", "M03 S800", "G00 X44 Z2", "G01 Z0.5 F0.2", "G01 X-1.6", "G00 Z2",
        "G00 X36", "G01 Z-40 F0.25", "G00 U1 W1", "G00 X44", "G00 Z2",
        "G00 X32", "G01 Z-25", "G00 U1 W1", "G00 X44", "G00 Z2",
        "G00 X28", "G01 Z0 F0.15", "G03 X30 Z-1 R1", "G01 Z-25", "G01 X34", "G02 X35 Z-25.5 R0.5",
        "G01 Z-40", "G01 X42", "G00 X80 Z80", "M30"]) + "\n"
    tp = run(text, CNMG, file="s.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    m = simulate(tp, stock, CNMG)
    old = S.SHORT_PASS
    S.SHORT_PASS = 0
    try:
        ref = simulate(tp, stock, CNMG)
    finally:
        S.SHORT_PASS = old
    assert m.removed_area == pytest.approx(ref.removed_area, abs=1e-9)
    assert shapely.symmetric_difference(m.material, ref.material).area < 1e-9
    # the finished diameters: 30 over Z 0..-25 and 35 beyond, with a 0.8 mm nose
    z0, x0, z1, x1 = m.material.bounds
    assert x1 == pytest.approx(20.0)  # the chucked stock beyond Z-40 is untouched
    col = shapely.intersection(m.material, shapely.LineString([(-10, 0), (-10, 30)]))
    assert col.bounds[3] == pytest.approx(15.0, abs=1e-6)



def _each_segment_in_turn(pts, segs):
    """The reference: each segment's distance in turn, the first nearest kept."""
    from hnc_cam.geometry import Arc
    from hnc_cam.sim.measure import _arc_dist, _line_dist
    px, pz = pts[:, 1], pts[:, 0]
    best = np.full(len(pts), np.inf)
    which = np.full(len(pts), -1)
    for k, s in enumerate(segs):
        dk = _arc_dist(px, pz, s) if isinstance(s, Arc) else _line_dist(px, pz, s.start, s.end)
        better = dk < best
        best[better], which[better] = dk[better], k
    return best, which

def test_distances_by_blocks_equal_every_point_against_every_segment():
    from hnc_cam.geometry import Arc, Line
    from hnc_cam.sim.measure import distances
    # a wavy chain of 400 short lines, two arcs and a zero-length line; points along it (a
    # boundary's order) and scattered
    pts_chain = [(15 + 0.1 * math.sin(-0.1 * i * 0.5), -0.1 * i) for i in range(401)]
    segs = [Line(a, b) for a, b in zip(pts_chain[:-1], pts_chain[1:])]
    segs += [Arc((20.0, -50.0), (22.0, -52.0), (20.0, -52.0), True),
             Arc((5.0, -60.0), (3.0, -62.0), (5.0, -62.0), False), Line((15.0, -10.0), (15.0, -10.0))]
    rnd = np.random.default_rng(5)
    t = np.linspace(0, 1, 20000)
    pts = np.column_stack([-40 * t, 15 + 0.1 * np.sin(-40 * t * 0.5) + rnd.normal(0, 0.05, len(t))])
    pts = np.vstack([pts, rnd.uniform([-70, -5], [5, 30], (2000, 2))])
    d, w = distances(pts, segs)
    best, which = _each_segment_in_turn(pts, segs)  # the first nearest kept
    assert np.array_equal(d, best) and np.array_equal(w, which)
    # and the kernel's own distances
    for i in rnd.choice(len(pts), 50, replace=False).tolist():
        p = (float(pts[i, 1]), float(pts[i, 0]))
        assert d[i] == pytest.approx(min(s.distance_to(p) for s in segs), abs=1e-9)


@pytest.mark.parametrize("kinds", ["lines", "arcs", "both"])
def test_pairs_of_one_kind_of_segment_equal_each_segment_s_distance(kinds):
    from hnc_cam.geometry import Arc, Line
    from hnc_cam.sim.measure import SegmentTable
    rnd = np.random.default_rng(11)
    lines = [Line((10.0, 0.0), (10.0, -8.0)), Line((10.0, -8.0), (14.0, -12.0)),
             Line((3.0, -3.0), (3.0, -3.0))]
    arcs = [Arc((14.0, -12.0), (16.0, -14.0), (14.0, -14.0), True),
            Arc((16.0, -14.0), (18.0, -16.0), (18.0, -14.0), False),
            Arc((5.0, 0.0), (5.0, -10.0), (5.0, -5.0), True)]  # half a turn
    segs = {"lines": lines, "arcs": arcs, "both": arcs[:1] + lines + arcs[1:]}[kinds]
    pts = rnd.uniform([-20, -2], [4, 22], (3000, 2))
    pts[:50] = [(s.end[1], s.end[0]) for s in segs] * (50 // len(segs)) + \
        [(segs[0].start[1], segs[0].start[0])] * (50 % len(segs))
    d, w = SegmentTable(segs).pairs(pts)
    best, which = _each_segment_in_turn(pts, segs)
    assert np.array_equal(d, best) and np.array_equal(w, which)
