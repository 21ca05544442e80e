"""The batched removal (one overlay per batch, each move's share from its front band) against
move-by-move removal, the material after move k (``material_after``), and the exact overlap
areas of :mod:`hnc_cam.sim.area`."""
from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
import shapely

from hnc_cam.nc.interp import run
from hnc_cam.sim import material_after, simulate, stock_region
from hnc_cam.sim.area import (clip_below, front_bands, overlap_areas, polygon_edges,
                               region_edges, ring_edges)
from hnc_cam.sim.region import diff
from hnc_cam.sim.tool import sweep_hulls, tool_shape
from hnc_cam.tooling import Insert, Machine, Register, Stock

S = importlib.import_module("hnc_cam.sim.simulate")

SHARP = Machine()
CNMG = Machine(registers={1: Register(number=1, radius=0.8, tip=3,
                                      insert=Insert.parse("CNMG120408"), approach=95.0)})
VNMG = Machine(registers={1: Register(number=1, radius=0.4, tip=3,
                                      insert=Insert.parse("VNMG160404"), approach=93.0)})


def line_of(text, needle):
    return next(i for i, l in enumerate(text.splitlines(), 1) if l.strip() == needle)


def _one_by_one(tp, stock, machine):
    """Reference: each move's swept region taken out of the whole material in program order."""
    sweeper = S._Sweeper(machine, tp.moves)
    material = stock_region(stock)
    areas = []
    sweeps, _ = sweeper.sweeps(list(tp.moves))
    for m, g in zip(tp.moves, sweeps):
        if g is None:
            areas.append(0.0)
            continue
        after = diff(material, g)
        a = material.area - after.area
        if a > 1e-12:
            areas.append(a)
            material = after
        else:
            areas.append(0.0)
    return np.array(areas), material


def _wavy(passes: int, depth: float, arcs: bool) -> str:
    """Passes toward the chuck along a wavy profile of short G01 steps (and G02/G03 bumps),
    stepping in from a 40 mm bar, retracting at 45 deg and returning in rapid."""
    out = ["%1", "T0101", "M03 S800", "G00 X44 Z2"]
    for p in range(passes):
        r = 20 - depth * (p + 1)
        out.append(f"G00 X{2 * r + 0.6:.4f} Z1")
        out.append(f"G01 X{2 * r:.4f} Z0 F200")
        z = 0.0
        for i in range(120):
            z -= 0.25
            x = r + 0.15 * math.sin(z * 0.9)
            if arcs and i % 30 == 29:
                out.append(f"G0{2 + (i // 30) % 2} X{2 * x:.4f} Z{z:.4f} R3")
            else:
                out.append(f"G01 X{2 * x:.4f} Z{z:.4f}")
        out.append(f"G01 U2 W1")
        out.append("G00 Z2")
    out += ["G00 X80 Z80", "M30"]
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("machine,arcs", [(SHARP, False), (CNMG, True), (VNMG, True)])
def test_band_batches_equal_move_by_move(machine, arcs):
    text = _wavy(6, 0.7, arcs)
    tp = run(text, machine, file="w.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    ref_areas, ref_material = _one_by_one(tp, stock, machine)
    taken = {"bands": 0, "moves": 0}
    real_bands, real_moves = S._batch_by_bands, S._batch_by_moves

    def by_bands(*a, **k):
        got = real_bands(*a, **k)
        taken["bands"] += got is not None
        return got

    def by_moves(*a, **k):
        taken["moves"] += 1
        return real_moves(*a, **k)

    S._batch_by_bands, S._batch_by_moves = by_bands, by_moves
    try:
        for batch in (5, 64, 256):
            m = simulate(tp, stock, machine, batch=batch)
            assert m.removed_area == pytest.approx(ref_areas, abs=1e-9)
            assert shapely.symmetric_difference(m.material, ref_material).area < 1e-9
    finally:
        S._batch_by_bands, S._batch_by_moves = real_bands, real_moves
    assert ref_areas.sum() > 100.0
    # the passes are taken a batch at a time (the bounds add up), not move by move
    assert taken["bands"] > 0 and taken["bands"] >= taken["moves"]


def test_bounds_that_do_not_add_up_fall_back_to_move_by_move(monkeypatch):
    # a pass, then rapids that return through the pass's own cut and on through the bar, in
    # the same batch: the bands count what the pass removed again, so the batch is taken move
    # by move, with the same removal and findings as without the bands (a pass this short is
    # taken move by move from the start: here its bands are tried)
    monkeypatch.setattr(S, "SHORT_PASS", 0)
    text = "\n".join(["%1", "T0101", "M03 S800", "G00 X36 Z2", "G01 Z-30 F200", "G00 X30 Z-20",
                      "G00 X30 Z2", "G00 X80 Z80", "M30"]) + "\n"
    tp = run(text, CNMG, file="c.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    ref_areas, ref_material = _one_by_one(tp, stock, CNMG)
    real_bands = S._batch_by_bands
    fell = []

    def by_bands(*a, **k):
        got = real_bands(*a, **k)
        fell.append(got is None)
        return got

    S._batch_by_bands = by_bands
    try:
        m = simulate(tp, stock, CNMG)
        S._batch_by_bands = lambda *a, **k: None
        plain = simulate(tp, stock, CNMG)
    finally:
        S._batch_by_bands = real_bands
    assert any(fell)
    assert m.removed_area == pytest.approx(ref_areas, abs=1e-9)
    assert shapely.symmetric_difference(m.material, ref_material).area < 1e-9
    got = [(i.line, i.kind, i.message) for i in m.issues]
    assert got == [(i.line, i.kind, i.message) for i in plain.issues]
    assert {(ln, kind) for ln, kind, _ in got} == {(line_of(text, "G00 X30 Z-20"), "collision"),
                                                   (line_of(text, "G00 X30 Z2"), "collision")}


def test_many_colliding_rapids_are_each_on_their_line():
    # a fresh program of 300 rapids, each plunging 0.5 mm into the bar at a new Z and back:
    # every one is a collision on its own line, at its own place
    blocks = ["%1", "T0101", "M03 S800", "G00 X42 Z2"]
    for i in range(300):
        z = -1.0 - 0.15 * i
        blocks += [f"G00 Z{z:.2f}", f"X39 (R{i})", "X42"]
    blocks += ["G00 X80 Z80", "M30"]
    text = "\n".join(blocks) + "\n"
    tp = run(text, CNMG, file="r.nc", start=(60.0, 50.0))
    m = simulate(tp, Stock.parse("40x60"), CNMG)
    lines = [line_of(text, f"X39 (R{i})") for i in range(300)]
    assert [(i.line, i.kind) for i in m.issues] == [(ln, "collision") for ln in lines]
    for i, iss in enumerate(m.issues):
        z = -1.0 - 0.15 * i
        assert iss.at is not None and abs(iss.at[1] - z) < 1.0 and iss.at[0] > 19.0


def test_material_after_move_k():
    # sharp tool: turn X30 to Z-30, retract, face the end
    text = "\n".join(["%1", "M03 S800", "G00 X42 Z2", "X30", "G01 Z-30 F200", "X42",
                      "G00 Z0.5", "X32", "G01 Z0", "X-1", "G00 Z2", "G00 X60 Z50", "M30"]) + "\n"
    tp = run(text, SHARP, file="k.nc", start=(60.0, 50.0))
    m = simulate(tp, Stock.parse("40x60+0.5"), SHARP)
    turn = next(i for i, mv in enumerate(tp.moves) if mv.line == line_of(text, "G01 Z-30 F200"))
    up = turn + 1
    face = next(i for i, mv in enumerate(tp.moves) if mv.line == line_of(text, "X-1"))
    got = dict(material_after(m, [up + 1, 0, turn + 1, face + 1, len(tp.moves), 10 ** 9, -1]))
    assert sorted(got) == [0, turn + 1, up + 1, face + 1, len(tp.moves)]
    bar = shapely.box(-59.5, 0, 0.5, 20)
    assert shapely.symmetric_difference(got[0], bar).area < 1e-12
    # after the turning pass the main edge's 5 deg lean leaves a wedge at the shoulder
    after_turn = shapely.box(-59.5, 0, -30, 20).union(shapely.box(-30, 0, 0.5, 15))
    wedge = got[turn + 1].difference(after_turn)
    assert 0.5 < wedge.area < 2.0 and wedge.bounds[0] == pytest.approx(-30, abs=1e-9)
    # the retract along +X squares the shoulder: exactly the turned bar
    assert shapely.symmetric_difference(got[up + 1], after_turn).area < 1e-9
    # then the face at Z0 takes the 0.5 mm off the end down to the axis
    faced = shapely.box(-59.5, 0, -30, 20).union(shapely.box(-30, 0, 0, 15))
    assert shapely.symmetric_difference(got[face + 1], faced).area < 1e-9
    assert shapely.symmetric_difference(got[len(tp.moves)], m.material).area == 0.0


def test_snapshots_do_not_change_the_simulation():
    text = _wavy(3, 0.7, True)
    tp = run(text, CNMG, file="w.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    plain = simulate(tp, stock, CNMG)
    seen = []
    snap = simulate(tp, stock, CNMG, snapshots=range(0, len(tp.moves) + 1, 37),
                    on_snapshot=lambda k, g: seen.append((k, g.area)))
    assert [k for k, _ in seen] == list(range(0, len(tp.moves) + 1, 37))
    assert all(a >= b for (_, a), (_, b) in zip(seen, seen[1:]))  # material only shrinks
    assert snap.removed_area == pytest.approx(plain.removed_area, abs=1e-9)
    assert shapely.symmetric_difference(plain.material, snap.material).area < 1e-9
    # what the moves up to k removed is the sum of their shares
    for k, a in seen:
        assert plain.stock.area - a == pytest.approx(plain.removed_area[:k].sum(), abs=1e-8)


def test_overlap_areas_equal_overlays():
    rnd = np.random.default_rng(7)
    K = tool_shape(CNMG.register(1)).outline
    region = shapely.box(-60, 0, 0, 20).difference(shapely.Point(-10, 15).buffer(3))
    region = shapely.union_all([region.difference(shapely.box(-30, 19, -20, 30)),
                                shapely.box(-70, 25, -65, 30)])
    E = region_edges(region)
    a = rnd.uniform([-65, 10], [5, 25], (400, 2))
    b = a + rnd.normal(0, 2, (400, 2))
    whole = rnd.random(400) < 0.5
    rings, _, _ = front_bands(K, a, b, whole)
    hulls = sweep_hulls(K, a, b)
    bands = shapely.difference(hulls, shapely.polygons(K[None] + a[:, None, :]))
    want = shapely.area(shapely.intersection(region, np.where(whole, hulls, bands)))
    got = overlap_areas(E, ring_edges(rings), rings[:, :, 1].min(axis=1))
    assert np.abs(got - want).max() < 1e-9
    # cut at a height: the same overlap with what lies below it
    X = 18.0
    cut = overlap_areas(E, ring_edges(clip_below(rings, X)), rings[:, :, 1].min(axis=1))
    below = shapely.box(-100, -100, 100, X)
    want2 = shapely.area(shapely.intersection(shapely.intersection(region, below),
                                              np.where(whole, hulls, bands)))
    assert np.abs(cut - want2).max() < 1e-9
    # and for arbitrary polygons with holes
    polys = np.array([shapely.Point(-20 + 3 * i, 19).buffer(2).difference(
        shapely.Point(-20 + 3 * i, 19).buffer(0.5)) for i in range(5)], dtype=object)
    got3 = overlap_areas(E, polygon_edges(polys), np.full(5, 17.0))
    assert got3 == pytest.approx(shapely.area(shapely.intersection(region, polys)), abs=1e-9)


def test_short_passes_over_the_same_path_are_batched_per_pass():
    # 12 passes of some 40 moves each, 0.05 mm apart along the same wavy path: a batch of 256
    # moves would hold six passes, each coming back over what the one before cut; batches start
    # with every pass, so each is taken with bands, and the result is the move-by-move one
    blocks = ["%1", "T0101", "M03 S800", "G00 X44 Z2"]
    for p in range(12):
        r = 19.5 - 0.05 * p
        blocks += [f"G00 X{2 * r + 0.4:.4f} Z1", f"G01 X{2 * r:.4f} Z0 F200"]
        blocks += [f"G01 X{2 * (r + 0.1 * math.sin(0.3 * i)):.4f} Z{-0.5 * i:.3f}"
                   for i in range(1, 40)]
        blocks += ["G01 U1 W0.5", "G00 Z2"]
    text = "\n".join(blocks + ["G00 X80 Z80", "M30"]) + "\n"
    tp = run(text, CNMG, file="p.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    ref_areas, ref_material = _one_by_one(tp, stock, CNMG)
    taken = {"bands": 0, "failed": 0, "moves": 0}
    real_bands, real_moves = S._batch_by_bands, S._batch_by_moves

    def by_bands(*a, **k):
        got = real_bands(*a, **k)
        taken["bands" if got is not None else "failed"] += 1
        return got

    def by_moves(*a, **k):
        taken["moves"] += 1
        return real_moves(*a, **k)

    S._batch_by_bands, S._batch_by_moves = by_bands, by_moves
    try:
        m = simulate(tp, stock, CNMG)
    finally:
        S._batch_by_bands, S._batch_by_moves = real_bands, real_moves
    assert m.removed_area == pytest.approx(ref_areas, abs=1e-9)
    assert shapely.symmetric_difference(m.material, ref_material).area < 1e-9
    # every pass is one batch tried with bands (a pass whose rapid return crosses its own cut
    # can make its batch go move by move)
    assert taken["bands"] + taken["failed"] == 12
    assert taken["failed"] <= 1 and taken["moves"] <= 1


def test_a_long_pass_is_cut_into_equal_batches(monkeypatch):
    # one pass of 401 moves along a wave and its retract; batches of at most 150 moves: three
    # of 134, 134 and 135 (not 150, 150 and 101), the same removal as with one batch
    blocks = ["%1", "T0101", "M03 S800", "G00 X44 Z2", "G00 X38.4 Z1", "G01 X38 Z0 F200"]
    blocks += [f"G01 X{38 + 0.1 * math.sin(0.05 * i):.4f} Z{-0.05 * i:.3f}" for i in range(1, 400)]
    blocks += ["G01 X44", "G00 Z2", "G00 X80 Z80", "M30"]
    # the wave rises less steeply than the default insert's 5 deg end cutting edge: no move
    # cuts back into what the ones before it cut, the bounds add up, no batch is halved
    sharp = Machine()
    tp = run("\n".join(blocks) + "\n", sharp, file="w.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    sizes = []
    real = S._batch_by_bands

    def by_bands(material, edges_of, run_, c0, b0, b1, *a):
        sizes.append(b1 - b0)
        return real(material, edges_of, run_, c0, b0, b1, *a)

    monkeypatch.setattr(S, "_batch_by_bands", by_bands)
    m = simulate(tp, stock, sharp, batch=150)
    starts = [k for k, mv in enumerate(tp.moves) if mv.kind == "line" and tp.moves[k - 1].kind == "rapid"]
    assert len(starts) == 1
    n_pass = len(tp.moves) - starts[0]
    assert sorted(sizes) == sorted(n_pass * (i + 1) // 3 - n_pass * i // 3 for i in range(3))
    assert max(sizes) - min(sizes) <= 1
    sizes.clear()
    one = simulate(tp, stock, sharp, batch=10_000)
    assert sizes == [n_pass]
    assert np.allclose(m.removed_area, one.removed_area, rtol=0, atol=1e-12)
    assert (m.removed_area > 1e-4).sum() > 300
    assert m.material.symmetric_difference(one.material).area <= 1e-9


def test_overlap_areas_in_blocks_of_whole_polygons(monkeypatch):
    # 1,500 small polygons over a disc's edge: taken in blocks of about 100 edges (each block
    # ending where a polygon's edges end), the same areas as in one block, and GEOS's
    import hnc_cam.sim.area as A
    rng = np.random.default_rng(3)
    disc = shapely.buffer(shapely.Point(0, 0), 5, quad_segs=64)
    polys = [shapely.buffer(shapely.Point(*rng.uniform(-6, 6, 2)), rng.uniform(0.1, 1),
                            quad_segs=int(rng.integers(1, 6))) for _ in range(1500)]
    f, fown = A.edge_rows(polygon_edges(polys))
    ref = np.array([p.bounds[1] for p in polys])
    region = A.region_edges(disc)
    monkeypatch.setattr(A, "EDGE_BLOCK", 10**9)
    one = A.overlap_areas_of(region, f, fown, ref, len(polys))
    calls = []
    inner = A._overlap_areas
    monkeypatch.setattr(A, "_overlap_areas", lambda r, ff, fo, *a: calls.append(fo) or inner(r, ff, fo, *a))
    monkeypatch.setattr(A, "EDGE_BLOCK", 100)
    got = A.overlap_areas_of(region, f, fown, ref, len(polys))
    assert len(calls) > 100
    assert all(not set(a.tolist()) & set(b.tolist()) for a, b in zip(calls, calls[1:]))
    assert sum(len(c) for c in calls) == len(f)
    assert np.allclose(got, one, rtol=0, atol=1e-13)
    want = shapely.area(shapely.intersection(disc, np.array(polys, dtype=object)))
    assert np.allclose(got, want, rtol=0, atol=1e-12)
    assert (want > 0.01).sum() > 100 and (want < 1e-12).sum() > 100


def test_ring_edge_rows_are_the_ring_edges_with_a_z_span():
    import hnc_cam.sim.area as A
    rng = np.random.default_rng(1)
    rings = rng.uniform(0, 1, (300, 40, 2))
    rings[:, 5:9] = rings[:, 4:5]  # repeated vertices (a clipped ring's padding)
    rings[:, :, 0] = np.round(rings[:, :, 0], 1)  # vertical edges
    f, own = A.ring_edge_rows(rings)
    g, gown = A.edge_rows(ring_edges(rings))
    assert np.array_equal(f, g) and np.array_equal(own, gown)
    assert 0 < len(f) < 300 * 39 and (f[:, 4] != 0).all()


def _shoulder_passes(passes: int, step: float = 0.05) -> str:
    """Roughing passes ``step`` mm apart (radius) to one shoulder at Z-30, each of 40 feed
    moves (a pass long enough to be taken by bands) and fed out along the shoulder face:
    every pass ends on the same line."""
    out = ["%1", "T0101", "M03 S800", "G00 X44 Z2"]
    for p in range(passes):
        d = 40 - 2 * step * (p + 1)
        out += [f"G00 X{d:.4f} Z1", "G01 Z0 F200"]
        out += [f"G01 Z{-0.75 * (k + 1):.2f}" for k in range(40)]
        out += ["G01 X44", "G00 Z1"]
    out += ["G00 X80 Z80", "M30"]
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("passes", [5, 60])
def test_passes_ending_on_one_shoulder_leave_no_vertex_each(passes, monkeypatch):
    # each pass's end lies on the shoulder face; the material keeps the face as one edge
    # (a vertex per pass on it made every later overlay along the face slower), and the
    # material is the move-by-move material to 1e-9 mm^2
    monkeypatch.setattr(S, "LEAN_FROM", 0)
    tp = run(_shoulder_passes(passes), SHARP, file="s.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    m = simulate(tp, stock, SHARP)
    _, ref = _one_by_one(tp, stock, SHARP)
    assert shapely.symmetric_difference(m.material, ref).area < 1e-9
    assert shapely.get_num_coordinates(ref) >= passes  # the overlays' own vertices, one a pass
    assert shapely.get_num_coordinates(m.material) <= 10
    assert m.material.bounds == pytest.approx((-60.0, 0.0, 0.0, 20.0))


def test_many_passes_on_one_shoulder_keep_the_material_small():
    # the threshold as it is: 700 passes leave fewer vertices than half their number (745
    # when each leaves its own)
    tp = run(_shoulder_passes(700, 0.02), SHARP, file="s.nc", start=(60.0, 50.0))
    m = simulate(tp, Stock.parse("40x60"), SHARP)
    assert shapely.get_num_coordinates(m.material) < 350
    assert m.material.bounds == pytest.approx((-60.0, 0.0, 0.0, 20.0))
    assert m.material.area == pytest.approx(60 * 20 - 30 * 14.0, abs=1e-6)
