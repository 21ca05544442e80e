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


def _wiggle(rng, n):
    """A polyline of n pieces that turns both ways (a wavy finishing pass, zigzags, corners),
    not crossing itself."""
    while True:
        step = float(np.exp(rng.uniform(np.log(0.01), np.log(2.0))))
        turn = rng.normal(0.0, rng.choice([0.02, 0.3, 1.2]), n)
        ang = rng.uniform(0, 2 * np.pi) + np.cumsum(turn)
        pts = np.concatenate([[[0.0, 0.0]], np.cumsum(step * np.column_stack([np.cos(ang),
                                                                             np.sin(ang)]), 0)])
        if shapely.is_simple(shapely.LineString(pts)):
            return pts


@pytest.mark.parametrize("seed", range(4))
def test_sweep_of_a_path_turning_both_ways_is_the_union_of_its_hulls(seed):
    rng = np.random.default_rng(100 + seed)
    outlines = _outlines()
    for _ in range(30):
        K = outlines[rng.integers(len(outlines))]
        pts = _wiggle(rng, int(rng.integers(2, 400)))
        P, Q = pts[:-1], pts[1:]
        want = shapely.union_all(sweep_hulls(K, P, Q))
        got = S._ring_sweep(K, P, Q)
        assert got is not None and got.geom_type == "Polygon" and got.is_valid
        assert got.symmetric_difference(want).area <= 1e-9 * max(1.0, want.area)


def test_a_path_that_crosses_itself_takes_the_envelopes():
    machine = load_machine()
    tp = run(PROGRAM, machine, start=(50.0, 80.0))
    run_ = S._Sweeper(machine, tp.moves).run(list(tp.moves), bands=True)
    n = len(tp.moves)
    # the whole program: rapids back over the passes, the path crosses itself
    assert not shapely.is_simple(shapely.LineString(np.concatenate(
        [run_.piece_a[:1], run_.piece_b])))
    got = run_.batch_region(0, n)
    env = run_.envelopes(0, n)
    assert len(got) == len(env) > 1
    assert all(a.equals_exact(b, 0) for a, b in zip(got, env))
    # one pass (from its rapid down to its retract) is one path: one polygon, the union of
    # its pieces' hulls
    k0, k1 = 1, 5
    lo, hi = np.searchsorted(run_.band_own, [k0, k1])
    got = run_.batch_region(k0, k1)
    assert len(got) == 1
    K = run_.outlines[0]
    want = shapely.union_all(sweep_hulls(K, run_.piece_a[lo:hi], run_.piece_b[lo:hi]))
    assert got[0].symmetric_difference(want).area <= 1e-9 * want.area


WAVY = """%1
T0101
M03 S800
G00 X44 Z2
#1 = 0
WHILE #1 LT 3
G00 X[35 - 2 * #1] Z1
#3 = 0
WHILE #3 LE 400
G01 X[34.4 - 2 * #1 + 0.3 * SIN[#3 * 0.6]] Z[-#3 * 0.05] F0.2
#3 = #3 + 1
ENDW
G01 X44
G00 Z2
#1 = #1 + 1
ENDW
G00 X80 Z80
M30
"""


def test_batches_taken_with_the_path_sweep_remove_what_the_envelopes_remove(monkeypatch):
    machine = load_machine()
    tp = run(WAVY, machine, start=(50.0, 80.0))
    stock = Stock.parse("40x60")
    calls = []
    ring_sweep = S._ring_sweep
    monkeypatch.setattr(S, "_ring_sweep", lambda *a: calls.append(1) or ring_sweep(*a))
    one = simulate(tp, stock, machine)
    assert len(calls) >= 3  # every pass's batches
    monkeypatch.setattr(S._Run, "batch_region", S._Run.envelopes)
    env = simulate(tp, stock, machine)
    assert (one.removed_area > 1e-6).sum() > 1000
    assert np.allclose(one.removed_area, env.removed_area, rtol=0, atol=1e-12)
    assert one.material.symmetric_difference(env.material).area <= 1e-9
    assert [str(i) for i in one.issues] == [str(i) for i in env.issues]
    # the last pass's tip runs on X 30.4 +- 0.3 (diameter): the 0.8 mm nose leaves the
    # material below its wave and takes all above it
    for z in (-1.0, -5.05, -12.85, -19.5):
        assert one.material.contains(shapely.Point(z, 15.05 - 0.01))
        assert not one.material.contains(shapely.Point(z, 15.35 + 0.01))


def test_a_path_whose_outline_extremes_move_on_fast_takes_the_envelopes():
    # the 0.8 mm nose along a steep wave: the extreme vertices move on by some 20 vertices a
    # piece (past the insert's long edges), where one ring would cross itself thousands of times
    machine = load_machine()
    steep = WAVY.replace("SIN[#3 * 0.6]", "SIN[#3 * 3]").replace("WHILE #1 LT 3", "WHILE #1 LT 1")
    tp = run(steep, machine, start=(50.0, 80.0))
    moves = list(tp.moves)
    run_ = S._Sweeper(machine, moves).run(moves, bands=True)
    k0 = next(k for k, m in enumerate(moves) if m.kind == "line")  # the wave, to the retract
    k1 = next(k for k, m in enumerate(moves) if k > k0 and m.kind == "rapid")
    got = run_.batch_region(k0, k1)
    env = run_.envelopes(k0, k1)
    assert len(got) == len(env) > 100
    # the gentle wave of WAVY: one ring
    tp = run(WAVY, machine, start=(50.0, 80.0))
    moves = list(tp.moves)
    gentle = S._Sweeper(machine, moves).run(moves, bands=True)
    k0 = next(k for k, m in enumerate(moves) if m.kind == "line")
    k1 = next(k for k, m in enumerate(moves) if k > k0 and m.kind == "rapid")
    assert len(gentle.batch_region(k0, k1)) == 1 < len(gentle.envelopes(k0, k1))


def test_band_bounds_do_not_depend_on_how_the_pieces_are_grouped(monkeypatch):
    # a pass along the wave and its retract up the face: most pieces need a few vertices of
    # the nose below the material's top, the retract all of them; grouped or not, every
    # piece's bound is the same overlap (to rounding)
    machine = load_machine()
    fine = WAVY.replace("2 * #1", "0.2 * #1")  # passes 0.1 mm deep after the first
    tp = run(fine, machine, start=(50.0, 80.0))
    moves = list(tp.moves)
    stock = Stock.parse("40x60")
    after = simulate(tp, stock, machine)
    assert (after.removed_area > 1e-6).sum() > 500
    r = S._Sweeper(machine, moves).run(moves, bands=True)
    # the second pass, over the wave the first one left
    starts = [k for k, m in enumerate(moves) if m.kind == "line" and moves[k - 1].kind == "rapid"]
    k0 = starts[1]
    k1 = next(k for k, m in enumerate(moves) if k > k0 and m.kind == "rapid")
    mat = dict(S.material_after(after, [k0]))[k0]
    region = S.region_edges(mat)
    groups = []
    front_bands = S.front_bands
    monkeypatch.setattr(S, "front_bands", lambda K, *a: groups.append(len(K)) or front_bands(K, *a))
    grouped = r.band_areas(region, k0, k1)
    assert len(set(groups)) >= 2
    monkeypatch.setattr(S, "BAND_GROUP", 10**6)
    groups.clear()
    one = r.band_areas(region, k0, k1)
    assert len(groups) == 1
    assert np.allclose(grouped, one, rtol=0, atol=1e-12)
    assert (one > 1e-4).sum() > 100
    # upper bounds of what each move removed after the moves before it
    assert (grouped >= after.removed_area[k0:k1] - 1e-10).all()


def test_an_arcs_points_come_from_the_one_sampler():
    # Arc.sample is the rows of Arc.sample_array: its ends exact, the chord error met, and
    # each point between on the circle at a0 + sweep * i / n
    from hnc_cam.geometry import Arc
    from hnc_cam.geometry.primitives import point_at_angle
    rng = np.random.default_rng(7)
    for _ in range(300):
        c = tuple(rng.uniform(-50, 50, 2))
        r = float(np.exp(rng.uniform(np.log(0.01), np.log(60.0))))
        a0, a1 = rng.uniform(-4, 4, 2)
        arc = Arc(point_at_angle(c, r, a0), point_at_angle(c, r, a1), c, bool(rng.random() < 0.5))
        got = arc.sample_array(CHORD)
        pts = arc.sample(CHORD)
        assert [tuple(p) for p in got.tolist()] == pts
        n = arc.segments_for(CHORD)
        assert got.shape == (n + 1, 2) and pts[0] == arc.start and pts[-1] == arc.end
        want = [point_at_angle(arc.center, r, arc.start_angle + arc.sweep * i / n)
                for i in range(1, n)]
        assert np.allclose(got[1:-1], np.array(want).reshape(-1, 2), rtol=0, atol=1e-12)
        assert np.allclose(np.hypot(got[:, 0] - c[0], got[:, 1] - c[1]), r, rtol=0, atol=1e-9)
        mid = (got[1:] + got[:-1]) / 2  # sagitta of every chord within the chord error
        assert (r - np.hypot(mid[:, 0] - c[0], mid[:, 1] - c[1]) <= CHORD + 1e-12).all()


@pytest.mark.parametrize("seed", range(2))
def test_paths_swept_together_give_each_path_s_own_polygon(seed):
    """The rings of several paths built and buffered at once (as a run's arcs are) are the
    same polygons, vertex for vertex, as each path's alone; a path of one piece or with a
    zero-length piece gives none, and the union of its hulls is taken for it."""
    rng = np.random.default_rng(200 + seed)
    K = _outlines()[int(rng.integers(10))]
    paths = []
    for _ in range(12):
        r = float(np.exp(rng.uniform(np.log(0.1), np.log(30.0))))
        paths.append(_arc(rng.uniform(-5, 5, 2), r, rng.uniform(0, 2 * np.pi),
                          rng.uniform(0.05, np.pi) * rng.choice([-1, 1])))
    paths.insert(3, paths[0][:2])  # one piece
    paths.insert(7, np.concatenate([paths[1][:3], paths[1][2:]]))  # a zero-length piece
    P = np.concatenate([p[:-1] for p in paths])
    Q = np.concatenate([p[1:] for p in paths])
    cnt = np.array([len(p) - 1 for p in paths])
    p0 = np.cumsum(cnt) - cnt
    got = S._ring_sweeps(K, P, Q, p0, cnt)
    assert got[3] is None and got[7] is None
    for k, p in enumerate(paths):
        alone = S._ring_sweep(K, p[:-1], p[1:])
        if alone is None:
            assert got[k] is None
            continue
        assert got[k].equals_exact(alone, 0)
        want = shapely.union_all(sweep_hulls(K, p[:-1], p[1:]))
        assert got[k].symmetric_difference(want).area <= 1e-9 * max(1.0, want.area)
    # a run's sweeps: every arc move's region is the union of its pieces' hulls
    machine = load_machine()
    tp = run(WAVY.replace("G01 X44\n", "G02 X40 Z-24 R6\nG01 X44\n"), machine,
             start=(50.0, 80.0))
    run_ = S._Sweeper(machine, tp.moves).run(list(tp.moves))
    arcs = [k for k, m in enumerate(tp.moves) if m.kind == "arc"]
    assert len(arcs) == 3
    for k in arcs:
        path = run_.path(k)
        want = shapely.union_all(sweep_hulls(run_.pieces[int(run_.move_group[k])][0],
                                             path[:-1], path[1:]))
        assert run_.sweeps[k].symmetric_difference(want).area <= 1e-9 * want.area


def test_arc_rings_cut_at_their_inner_turns_are_the_polygons_they_bound(monkeypatch):
    # a nosed insert along arcs of 1-20 mm radius either way: the ring's loops on the inner
    # side of the turn are cut at the crossing of the two pieces' lines, so the ring does not
    # cross itself and is the region as it is (no zero-distance buffer), the union of the hulls
    buffered = []
    buffer = shapely.buffer
    monkeypatch.setattr(S.shapely, "buffer", lambda *a, **k: buffered.append(1) or buffer(*a, **k))
    for K in (_outlines()[0], _outlines()[4]):
        for r, sweep in ((1.0, 1.2), (5.0, 0.7), (20.0, -0.3), (20.0, 0.3)):
            pts = _arc((3.0, 25.0), r, 0.4, sweep)
            P, Q = pts[:-1], pts[1:]
            got = S._path_sweep(K, P, Q)
            want = shapely.union_all(sweep_hulls(K, P, Q))
            assert got.geom_type == "Polygon" and got.is_valid and not got.exterior.is_ccw
            assert got.symmetric_difference(want).area <= 1e-12 * want.area
            # several arcs at once: the same polygons
            many = S._ring_sweeps(K, np.concatenate([P, P + 1.0]), np.concatenate([Q, Q + 1.0]),
                                  np.array([0, len(P)]), np.array([len(P), len(P)]))
            assert many[0].equals_exact(got, 0)
            assert many[1].symmetric_difference(shapely.affinity.translate(got, 1.0, 1.0)).area \
                <= 1e-12 * want.area
    assert not buffered
    # the insert's far side turning inside an arc of 2 mm: a ring that still crosses itself
    # (other pieces' lines) takes the buffer, the same union
    pts = _arc((3.0, 25.0), 2.0, 0.4, -np.pi / 2)
    got = S._path_sweep(_outlines()[0], pts[:-1], pts[1:])
    assert buffered
    want = shapely.union_all(sweep_hulls(_outlines()[0], pts[:-1], pts[1:]))
    assert got.symmetric_difference(want).area <= 1e-12 * want.area


def test_arcs_sampled_together_give_each_arc_s_own_points():
    from hnc_cam.geometry import Arc
    rng = np.random.default_rng(5)
    arcs = []
    for _ in range(60):
        c = rng.uniform(-50, 50, 2)
        r = float(np.exp(rng.uniform(np.log(0.01), np.log(100.0))))
        a0, a1 = rng.uniform(-np.pi, np.pi, 2)
        if abs(a0 - a1) < 1e-3:
            continue
        arcs.append(Arc((c[0] + r * np.sin(a0), c[1] + r * np.cos(a0)),
                        (c[0] + r * np.sin(a1), c[1] + r * np.cos(a1)), tuple(c),
                        bool(rng.integers(2))))
    pts, rows = Arc.sample_arrays(arcs, CHORD)
    assert rows.tolist() == [len(a.sample_array(CHORD)) for a in arcs]
    assert np.array_equal(pts, np.concatenate([a.sample_array(CHORD) for a in arcs]))
    # the ends exact, every point on its circle
    first = np.cumsum(rows) - rows
    assert [tuple(p) for p in pts[first]] == [a.start for a in arcs]
    own = np.repeat(np.arange(len(arcs)), rows)
    cen = np.array([a.center for a in arcs])[own]
    rad = np.array([a.radius for a in arcs])[own]
    assert np.allclose(np.hypot(*(pts - cen).T), rad, rtol=1e-12, atol=1e-12)


RETRACE = """%1
T0101
M03 S800
G00 X44 Z2
G00 X30 Z1
G01 Z-20 F0.2
G00 Z1
G00 X29.9
G00 Z-15
G00 X44
G00 X80 Z80
M30
"""


def test_a_rapid_back_along_its_cut_removes_nothing_and_one_below_it_a_layer():
    machine = load_machine()
    tp = run(RETRACE, machine, start=(50.0, 80.0))
    m = simulate(tp, Stock.parse("40x60"), machine)
    kinds = [mv.kind for mv in tp.moves]
    cut = kinds.index("line")
    back, down, under = cut + 1, cut + 2, cut + 3
    assert kinds[back] == kinds[down] == kinds[under] == "rapid"
    assert m.removed_area[cut] > 20 * 4.9  # the 5 mm layer over 20 mm and the nose's end
    assert m.removed_area[back] == 0.0  # over the cut it made, touching its floor only
    # 0.05 mm below it over the bar from Z0 to Z-15, less what the nose's front leaves at its
    # end (within its 0.8 mm radius): a sliver, not a collision
    assert 0.05 * (15 - 0.8) < m.removed_area[under] < 0.05 * 15
    assert not m.issues
    assert any(n.line == tp.moves[under].line for n in m.notes)


THREE_TOOLS = """%1
T0101
M03 S800
G00 X44 Z2
G00 X30 Z1
G01 Z-10 F0.2
G02 X36 Z-13 R3
G01 X44
G00 Z2
T0202
G00 X28 Z1
G01 Z-5 F0.1
G03 X32 Z-7 R2
G02 X36 Z-9 R2
G01 X44
G00 Z2
T0505
G00 X26 Z1
G01 Z-3 F0.1
G01 X44
G00 X80 Z80
M30
"""


def test_every_move_of_a_run_of_several_tools_has_its_sweep():
    """A run of three tools, the first two with arcs: every move's swept region is built
    (all tools' arcs at once), each the union of its pieces' hulls, and a move's region does
    not depend on which moves were asked for with it."""
    machine = load_machine()
    tp = run(THREE_TOOLS, machine, start=(50.0, 80.0))
    moves = list(tp.moves)
    assert len({m.register for m in moves}) == 3
    sweeps, paths = S._Sweeper(machine, moves).sweeps(moves)
    for k, (m, g) in enumerate(zip(moves, sweeps)):
        assert g is not None, (k, m.kind, m.register)
        K = S._Sweeper(machine, moves).shape(m).outline
        want = shapely.union_all(sweep_hulls(K, paths[k][:-1], paths[k][1:]))
        assert g.symmetric_difference(want).area <= 1e-9 * want.area
    # asked for one tool's moves at a time, and for the last tool's first
    run_ = S._Sweeper(machine, moves).run(moves)
    by_reg = {}
    for k, m in enumerate(moves):
        by_reg.setdefault(m.register, []).append(k)
    run2 = S._Sweeper(machine, moves).run(moves)
    run2._sweeps[:] = None
    for reg in sorted(by_reg, reverse=True):
        got = run2.sweep_of(np.array(by_reg[reg]))
        for k, g in zip(by_reg[reg], got):
            assert g is not None and g.equals_exact(run_.sweeps[k], 0)
