"""verify(): overcut/undercut measured against exact model geometry, hand-computed cases,
deliberately wrong programs caught with the right line."""
from __future__ import annotations

import math

import numpy as np
import shapely
import pytest

from hnc_cam.geometry import Arc, Line, Thread, TurnedProfile
from hnc_cam.nc.interp import run
from hnc_cam.sim import simulate, verify
from hnc_cam.sim.measure import distances
from hnc_cam.tooling import Machine, Register, Stock

SHARP = Machine()  # no registers: every register is a sharp point (tip 0, default insert)
NOSE08 = Machine(registers={1: Register(number=1, radius=0.8, tip=3)})


def poly(*pts):
    """Line chain through (x radius, z) points."""
    return [Line(a, b) for a, b in zip(pts[:-1], pts[1:])]


def prog(*blocks):
    return "%1\n" + "\n".join(blocks) + "\nM30\n"


def run_verify(text, model, stock="40x60", machine=SHARP, **kw):
    tp = run(text, machine, file="t.nc", start=(60.0, 50.0))
    m = simulate(tp, Stock.parse(stock), machine)
    return m, verify(m, model, **kw)


def line_of(text, needle):
    return next(i for i, l in enumerate(text.splitlines(), 1) if needle in l)


STEP = TurnedProfile(outside=poly((0, 0), (15, 0), (15, -30), (20, -30), (20, -50)))

ROUGH = ["T0101", "M03 S800", "G00 X42 Z2", "G00 X35", "G01 Z-30 F200", "X42", "G00 Z2",
         "X31", "G01 Z-30", "X42", "G00 Z2"]


def test_distances_match_kernel():
    segs = [Line((1.0, 2.0), (4.0, -3.0)), Arc((5.0, 0.0), (15.0, -10.0), (5.0, -10.0), False),
            Arc((15.0, -10.0), (10.0, -15.0), (10.0, -10.0), True)]
    rng = np.random.default_rng(1)
    pts = rng.uniform([-20, -5], [5, 20], size=(300, 2))  # (z, x)
    d, _ = distances(pts, segs)
    for (z, x), dd in zip(pts, d):
        assert dd == pytest.approx(min(s.distance_to((x, z)) for s in segs), abs=1e-12)


def test_exact_program_passes():
    t = prog(*ROUGH, "X30", "G01 Z-30", "X42", "G00 X60 Z50")
    m, r = run_verify(t, STEP)
    assert r.passed, r.summary()
    assert r.max_overcut_mm < 0.001 and r.max_undercut_mm < 0.001
    assert not r.collisions
    # Pappus: bar 40 -> 30 over 30 mm and 40 -> 40 beyond
    assert m.removed_volume_mm3 == pytest.approx(math.pi * (20 ** 2 - 15 ** 2) * 30, rel=1e-6)


def test_contour_shifted_into_part_is_overcut_with_line():
    # finishing at X29.95 instead of X30: 0.025 mm radial gouge, hand-computed
    t = prog(*ROUGH, "X29.95", "G01 Z-30", "X42", "G00 X60 Z50")
    m, r = run_verify(t, STEP)
    assert not r.passed
    assert r.max_overcut_mm == pytest.approx(0.025, abs=0.001)
    assert r.overcut_at.line == line_of(t, "G01 Z-30\nX42\nG00 X60".split("\n")[0]) or True
    # the first move that removed the gouged material is the finishing pass
    fin = [i for i, l in enumerate(t.splitlines(), 1) if l == "G01 Z-30"][-1]
    assert r.overcut_at.line == fin
    assert r.to_json()["pass"] is False


def test_taper_without_compensation_undercut():
    # imaginary tip (code 3, r 0.8) programmed on a taper: the nose leaves
    # r (nx + nz - 1) normal to it, nx, nz the components of the taper's outward normal
    model = TurnedProfile(outside=poly((0, 0), (10, 0), (15, -10), (15, -30), (20, -30), (20, -50)))
    t = prog("T0101", "M03 S800", "G00 X42 Z2", "X35", "G01 Z-30 F200", "X42", "G00 Z2",
             "X31", "G01 Z-30", "X42", "G00 Z2", "X22", "G01 Z0", "X20", "X30 Z-10", "Z-30",
             "X42", "G00 X60 Z50")
    m, r = run_verify(t, model, machine=NOSE08)
    n = np.array([10.0, 5.0]) / math.sqrt(125.0)
    expect = 0.8 * (n.sum() - 1)
    assert r.max_undercut_mm == pytest.approx(expect, abs=0.001)
    assert r.undercut_at.line == line_of(t, "X30 Z-10")
    assert not r.passed
    assert r.max_overcut_mm < 0.001


def test_arc_with_nose_radius_undercut_and_unreachable_corner():
    # convex R10 arc programmed with the imaginary tip: leftover 0.8 (sqrt 2 - 1) at 45 deg
    model = TurnedProfile(outside=[Line((0, 0), (5, 0)), Arc((5, 0), (15, -10), (5, -10), False),
                                   *poly((15, -10), (15, -30), (20, -30), (20, -50))])
    t = prog("T0101", "M03 S800", "G00 X42 Z2", "X35", "G01 Z-30 F200", "X42", "G00 Z2",
             "X31", "G01 Z-30", "X42", "G00 Z2", "X20", "G01 Z0", "X10",
             "G03 X30 Z-10 R10", "G01 Z-30", "X42", "G00 X60 Z50")
    m, r = run_verify(t, model, machine=NOSE08)
    assert r.max_undercut_mm == pytest.approx(0.8 * (math.sqrt(2) - 1), abs=0.001)
    assert r.undercut_at.line == line_of(t, "G03")
    # the sharp inner corner at Z-30 keeps the nose fillet: unreachable, listed, not a failure
    corner = [u for u in r.unreachable if abs(u.z + 30) < 1 and abs(u.x - 15) < 1]
    assert corner and corner[0].size_mm == pytest.approx(0.8 * (1 - math.sqrt(0.5)), abs=0.001)
    js = r.to_json()
    assert set(js) == {"pass", "max_overcut_mm", "max_undercut_mm", "unreachable", "collisions",
                       "cycle_time_s", "air_cut_fraction"}
    assert set(js["unreachable"][0]) == {"z", "x", "size_mm"}


def test_strict_counts_unreachable():
    t = prog(*ROUGH, "X30", "G01 Z-30", "X42", "G00 X60 Z50")
    machine = Machine(registers={1: Register(number=1, radius=0.8, tip=3)})
    _, r = run_verify(t, STEP, machine=machine)
    assert r.passed and r.unreachable
    _, r2 = run_verify(t, STEP, machine=machine, strict=True)
    assert not r2.passed


def test_leftover_reachable_when_pass_stops_short():
    t = prog(*ROUGH, "X30", "G01 Z-25", "X42", "G00 X60 Z50")
    _, r = run_verify(t, STEP)
    assert r.max_undercut_mm == pytest.approx(0.5, abs=0.001)  # (31 - 30) / 2
    assert not r.passed


def test_declared_thread_zone_compared_with_standard():
    # M30x2 external thread over Z-5..-25: d3 = 30 - 1.2269 * 2
    model = TurnedProfile(outside=poly((0, 0), (15, 0), (15, -30), (20, -30), (20, -50)),
                          threads=[Thread(z_start=-5, z_end=-25, diameter=30, pitch=2)])
    d3 = 30 - 1.2269 * 2
    passes = [f"G00 X{d3 + 2 * dd:.4f}\nG32 Z-25 F2\nG00 X34\nZ3" for dd in (0.6, 0.3, 0.0)]
    t = prog(*ROUGH, "X30", "G01 Z-30", "X42", "G00 X34 Z3", "T0404", *passes,
             "G00 X60 Z50")
    machine = Machine(registers={4: Register(number=4, radius=0.0, tip=8)})
    _, r = run_verify(t, model, machine=machine)
    assert len(r.threads) == 1
    th = r.threads[0]
    assert th.achieved_diameter == pytest.approx(d3, abs=0.002)
    assert th.ok and r.passed, r.summary()
    # the thread grooves are not counted as overcut
    assert r.max_overcut_mm < 0.001
    # one pass short: the thread is too shallow
    t2 = prog(*ROUGH, "X30", "G01 Z-30", "X42", "G00 X34 Z3", "T0404", *passes[:2],
              "G00 X60 Z50")
    _, r2 = run_verify(t2, model, machine=machine)
    assert not r2.threads[0].ok and not r2.passed


def test_bore_with_boring_bar_passes_and_keeps_corner_unreachable():
    from hnc_cam.tooling import Insert
    model = TurnedProfile(outside=poly((20, 0), (20, -50)),
                          bore=poly((10, 0), (10, -30), (8, -30), (8, -50)))
    t = prog("T0303", "M03 S800", "G00 X14 Z2", "G01 Z-30 F100", "X12", "G00 Z2", "X18",
             "G01 Z-30", "X14", "G00 Z2", "X20", "G01 Z-30", "X14", "G00 Z2", "G00 X60 Z50")
    bar = Machine(registers={3: Register(number=3, radius=0.4, tip=2, approach=95.0,
                                         insert=Insert.parse("CCMT09T304"))})
    m, r = run_verify(t, model, stock="40/16x50", machine=bar)
    assert r.passed and not m.issues, r.summary()
    # the inner corner at the bore bottom keeps the nose: r (1 - cos 45)
    assert len(r.unreachable) == 1
    assert r.unreachable[0].size_mm == pytest.approx(0.4 * (1 - math.sqrt(0.5)), abs=0.001)
    # the first pass at dia 14 is in the air
    assert m.air_cut_fraction > 0.2
    # an 0.05 mm too large bore is an overcut of 0.025 on the right line
    t2 = t.replace("X20\nG01 Z-30", "X20.05\nG01 Z-30")
    _, r2 = run_verify(t2, model, stock="40/16x50", machine=bar)
    assert r2.max_overcut_mm == pytest.approx(0.025, abs=0.001)
    assert r2.overcut_at.line == t2.splitlines().index("X20.05") + 2


def test_g76_thread_reaches_standard_minor_diameter():
    # M20x1.5: K = 0.6134 P = 0.92, root X18.16 = d3 (20 - 1.2269 * 1.5)
    model = TurnedProfile(outside=poly((0, 0), (10, 0), (10, -25), (15, -25), (15, -40)),
                          threads=[Thread(z_start=0, z_end=-20, diameter=20, pitch=1.5)])
    t = prog("T0101", "M03 S800", "G00 X32 Z2", "X20", "G01 Z-25 F100", "X32", "G00 X40 Z20",
             "T0404", "M03 S600", "G00 X24 Z4",
             "G76 C2 R-1 E0.6 A60 X18.16 Z-20 K0.92 U0.1 V0.1 Q0.4 F1.5", "G00 X40 Z20")
    mach = Machine(registers={4: Register(number=4, radius=0.0, tip=8)})
    m, r = run_verify(t, model, stock="30x40", machine=mach)
    assert [s.angle for s in m.thread_spans] == [60.0]
    th = r.threads[0]
    assert th.target_diameter == pytest.approx(20 - 1.2269 * 1.5, abs=1e-3)
    assert th.achieved_diameter == pytest.approx(18.16, abs=0.002)
    assert r.passed and r.max_overcut_mm < 0.001, r.summary()
    # without the declaration the zone comes from the thread moves, nominal from the model
    model.threads = []
    _, r2 = run_verify(t, model, stock="30x40", machine=mach)
    assert len(r2.threads) == 1 and not r2.threads[0].declared
    assert r2.threads[0].target_diameter == pytest.approx(20 - 1.2269 * 1.5, abs=1e-3)
    assert r2.passed, r2.summary()


def test_deepest_point_pruning_is_exact():
    # components far from part of the boundary, and one that does not touch it at all
    from shapely.geometry import box as sbox

    from hnc_cam.sim.region import polygons
    from hnc_cam.sim.verify import _boundary_points, _deepest
    segs = [*poly((0, 0), (10, 0), (10, -20)), Arc((10, -20), (15, -25), (15, -20), True),
            *poly((15, -25), (15, -60))]
    g = shapely.union_all([sbox(-5, 9.5, -1, 10.2), sbox(-40, 15.1, -38, 16.0),
                           sbox(-22, 12.0, -21, 12.5)])
    got = _deepest(g, segs, interior=False)
    pts = np.vstack([_boundary_points(p) for p in polygons(g)])
    d, _ = distances(pts, segs)
    assert got.size_mm == pytest.approx(d.max(), abs=1e-12)


def test_plot_shows_what_the_issue_names(tmp_path):
    # arc cut with an uncompensated 0.8 nose (undercut beyond tol), a gouge at the end face
    # (overcut), a corner the nose cannot reach, and a rapid through the stock
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    from hnc_cam.sim.plot import figure, plot
    model = TurnedProfile(outside=[Line((0, 0), (5, 0)), Arc((5, 0), (15, -10), (5, -10), False),
                                   *poly((15, -10), (15, -30), (20, -30), (20, -50))])
    t = prog("T0101", "M03 S800", "G00 X42 Z2", "X35", "G01 Z-30 F200", "X42", "G00 Z2",
             "X31", "G01 Z-30", "X42", "G00 Z2", "X20", "G01 Z-0.05", "X10",
             "G03 X30 Z-10 R10", "G01 Z-30", "X42", "G00 X42 Z-58", "G00 X39", "G00 X60 Z50")
    m, r = run_verify(t, model, machine=NOSE08)
    assert not r.passed and r.max_overcut_mm > 0.01 and r.overcut_at.z > -0.06
    assert r.max_undercut_mm > 0.01
    assert [c.line for c in r.collisions] == [line_of(t, "G00 X39")]
    fig = figure(m, report=r, model=model, title="case")
    try:
        ax = fig.axes[0]
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        for want in ("stock", "remaining material", "machined outline", "model", "rapid (G00)",
                     "feed T01 G01-G03", "overcut > 0.01 mm", "undercut > 0.01 mm",
                     "unreachable leftover", "collision / check"):
            assert want in labels, (want, labels)
        rapid = next(c for c in ax.collections
                     if isinstance(c, LineCollection) and c.get_label() == "rapid (G00)")
        assert rapid.get_linestyle()[0][1] is not None  # dashed
        # the deviations are drawn where they are: the overcut patch holds the gouge at Z0
        over = next(p for p in ax.patches if p.get_label() == "overcut > 0.01 mm")
        ext = over.get_path().get_extents()
        assert ext.x0 > -0.06 and ext.x1 <= 1e-6 and ext.y1 > 4
        keys = "\n".join(t.get_text() for t in ax.texts)
        for want in ("FAIL at tol 0.01 mm", f"max overcut {r.max_overcut_mm:.4f} mm",
                     f"max undercut {r.max_undercut_mm:.4f} mm", "cycle time", "removed",
                     "air cut", "collisions/checks: 1"):
            assert want in keys, want
    finally:
        plt.close(fig)
    plot(m, tmp_path / "case.png", report=r, model=model, title="case")
    assert (tmp_path / "case.png").read_bytes()[:4] == b"\x89PNG"


def test_reachable_sliver_over_an_unreachable_corner_counts_by_its_own_thickness():
    # the finishing pass runs 0.005 mm (radius) above the dia 30 face into a square shoulder
    # with a 0.8 nose: the band it leaves is reachable and 0.005 deep; the nose fillet in the
    # corner, r (1 - cos 45) deep from the model, cannot be reached. The band must not be
    # measured by the corner's depth where it meets the fillet.
    t = prog(*ROUGH, "X30.01", "G01 Z-30", "X42", "G00 X60 Z50")
    _, r = run_verify(t, STEP, machine=NOSE08)
    assert r.max_undercut_mm == pytest.approx(0.005, abs=0.001), r.summary()
    assert r.passed
    (u,) = r.unreachable
    # the fillet of the nose whose centre is 0.005 above the ideal corner placement: the part
    # beyond the ideal fillet (a 0.005 crescent) is its tail; deepest where the distances to
    # both faces are equal: 0.805 - 0.8 sin(t) = 0.8 - 0.8 cos(t)
    t = math.pi / 4 + math.asin(0.005 / 0.8 / math.sqrt(2))
    assert u.size_mm == pytest.approx(0.805 - 0.8 * math.sin(t), abs=0.0005)
    assert abs(u.z + 30) < 0.5 and abs(u.x - 15) < 0.5
    # the same band 0.02 mm thick fails, located on the band, not in the corner
    _, r2 = run_verify(prog(*ROUGH, "X30.04", "G01 Z-30", "X42", "G00 X60 Z50"), STEP,
                       machine=NOSE08)
    assert r2.max_undercut_mm == pytest.approx(0.02, abs=0.001) and not r2.passed


def test_wavy_part_with_control_compensation_verifies():
    # the reachable leftover's depth is measured against the unreachable leftover near it: a
    # piece of it cut to a box must stay a region (GEOS's rectangle clip built a ring of 3
    # points from this program's leftover)
    import sys
    from pathlib import Path
    sys.path.insert(0, str(Path(__file__).parent))
    from test_plan_shapes import wavy

    from hnc_cam import generate
    prog = generate(wavy(), "offset:2", comp="control")
    assert prog.report.passed, prog.report.summary()
    assert prog.report.max_overcut_mm < 0.01 and prog.report.max_undercut_mm < 0.01
