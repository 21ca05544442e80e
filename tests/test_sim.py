"""simulate(): material removal and the checks, on small programs and hand-built toolpaths."""
from __future__ import annotations

import math

import pytest
import shapely

from hnc_cam.geometry import Line, TurnedProfile
from hnc_cam.nc.interp import run
from hnc_cam.nc.toolpath import Move, Toolpath
from hnc_cam.sim import simulate, stock_region
from hnc_cam.tooling import Insert, Machine, Register, Stock, load_machine

SHARP = Machine()
CNMG = Machine(registers={1: Register(number=1, radius=0.8, tip=3,
                                      insert=Insert.parse("CNMG120408"), approach=95.0)})


def prog(*blocks):
    return "%1\n" + "\n".join(blocks) + "\nM30\n"


def sim(text, stock="40x60", machine=SHARP, **kw):
    tp = run(text, machine, file="t.nc", start=(60.0, 50.0))
    return simulate(tp, Stock.parse(stock), machine, **kw)


def line_of(text, needle):
    return next(i for i, l in enumerate(text.splitlines(), 1) if l.strip() == needle)


def test_stock_regions():
    assert stock_region(Stock.parse("40x60")).bounds == (-60, 0, 0, 20)
    assert stock_region(Stock.parse("40x60+2")).bounds == (-58, 0, 2, 20)
    t = stock_region(Stock.parse("40/20x60"))
    assert t.bounds == (-60, 10, 0, 20)
    model = TurnedProfile(outside=[Line((0, 0), (10, 0)), Line((10, 0), (10, -20))])
    g = stock_region(Stock.parse("offset:2"), model)
    assert g.bounds == pytest.approx((-22, 0, 2, 12))
    from hnc_cam.errors import StockError
    with pytest.raises(StockError, match="needs the model"):
        stock_region(Stock.parse("offset:2"))


def test_turning_exact_diameter_and_pappus_volume():
    m = sim(prog("M03 S800", "G00 X42 Z2", "X30", "G01 Z-30 F200", "X42", "G00 X60 Z50"))
    assert not m.issues
    # remaining material: 30 dia to Z-30, 40 beyond; the sharp corner is exact
    mat = m.material
    cut = mat.intersection(shapely.LineString([(-15, 0), (-15, 100)]))
    assert cut.bounds[3] == pytest.approx(15.0, abs=1e-9)
    assert m.removed_volume_mm3 == pytest.approx(math.pi * (400 - 225) * 30, rel=1e-9)
    js = m.to_json()
    assert set(js) == {"machined", "collisions", "cycle_time_s", "removed_volume_mm3"}
    ring = js["machined"][0]
    assert [30.0, -30.0] in ring or [30.0, -30.0] in [list(p) for p in ring]


def test_rapid_through_stock_is_a_collision_with_its_line():
    t = prog("M03 S800", "G00 X42 Z2", "X30", "G01 Z-30 F200", "X42", "G00 Z2",
             "G00 X20 Z-10", "G00 X60 Z50")
    m = sim(t)
    col = [i for i in m.issues if i.kind == "collision"]
    assert col and col[0].line == line_of(t, "G00 X20 Z-10")
    assert col[0].block == "G00 X20 Z-10"
    assert m.to_json()["collisions"][0]["line"] == col[0].line


def test_rapid_clear_of_material_is_not_a_collision():
    m = sim(prog("M03 S800", "G00 X42 Z2", "X30", "G01 Z-30 F200", "X42", "G00 Z2",
                 "G00 X30.02", "G00 Z0.5", "G00 X60 Z50"))
    assert not m.issues


def test_thread_with_spindle_stopped():
    t = prog("G00 X42 Z3", "X39", "G32 Z-20 F1.5", "G00 X42", "G00 X60 Z50")
    m = sim(t)
    th = [i for i in m.issues if i.kind == "thread-spindle"]
    assert th and th[0].line == line_of(t, "G32 Z-20 F1.5")


def test_feed_with_spindle_stopped_touching_material():
    t = prog("G00 X42 Z2", "X36", "G01 Z-10 F100", "G00 X42", "G00 X60 Z50")
    m = sim(t)
    sp = [i for i in m.issues if i.kind == "spindle"]
    assert sp and sp[0].line == line_of(t, "G01 Z-10 F100")
    # in the air the stopped spindle does no harm
    m2 = sim(prog("G00 X42 Z2", "G01 X50 Z5 F100", "G00 X60 Z50"))
    assert not m2.issues


def test_cutting_with_the_back_of_the_insert():
    # a right-hand tool feeding toward +Z 5 mm deep into the stock's left end: the back of
    # the insert leads (the secondary edge rises only 12 sin 5 deg = 1.05 mm)
    t = prog("T0101", "M03 S800", "G00 X42 Z2", "Z-70", "X30", "G01 Z-50 F50", "G00 X42",
             "G00 X60 Z50")
    m = sim(t, stock="40x60", machine=CNMG)
    nc = [i for i in m.issues if i.kind == "non-cutting"]
    assert nc and nc[0].line == line_of(t, "G01 Z-50 F50")
    # back-turning 0.5 mm deep is done by the secondary cutting edge: not reported
    t3 = prog("T0101", "M03 S800", "G00 X42 Z-70", "X39", "G01 Z-50 F50", "G00 X42",
              "G00 X60 Z50")
    assert not sim(t3, machine=CNMG).issues
    # the same cut toward the chuck is fine
    m2 = sim(prog("T0101", "M03 S800", "G00 X42 Z2", "X30", "G01 Z-10 F50", "X42",
                  "G00 X60 Z50"), machine=CNMG)
    assert not m2.issues


def test_parted_off_piece_falls_off():
    grooving = Machine(registers={7: Register(number=7, radius=0.0, tip=3,
                                              insert=Insert.parse("GROOVE3.0"))})
    t = prog("T0707", "M03 S500", "G00 X42 Z2", "Z-23", "G01 X0 F30", "G00 X42",
             "G00 X60 Z50")
    m = sim(t, machine=grooving)
    assert m.fallen
    assert m.material.bounds == pytest.approx((-60, 0, -23, 20))
    # everything right of the cut counts as removed
    assert m.removed_volume_mm3 == pytest.approx(math.pi * 400 * 23, rel=1e-6)


def test_air_cut_fraction():
    moves = [Move("line", (30.0, 5.0), (30.0, 15.0), 1, feed=100.0, spindle=500, duration=6.0),
             Move("line", (19.0, 2.0), (19.0, -8.0), 2, feed=100.0, spindle=500, duration=6.0)]
    tp = Toolpath(moves=moves, source_lines=["G01 Z15", "G01 Z-8"])
    m = simulate(tp, Stock.parse("40x60"), SHARP)
    assert m.removed_area[0] == 0 and m.removed_area[1] > 0
    assert m.air_cut_fraction == pytest.approx(0.5)


def test_arc_sweep_matches_exact_arc():
    # G02 from X20 Z0 to X30 Z-5 R5 with a sharp tool: concave quarter round left exact
    t = prog("M03 S800", "G00 X42 Z2", "X30", "G01 Z-5 F100", "X42", "G00 Z2", "X20",
             "G01 Z0", "G02 X30 Z-5 R5", "G01 X42", "G00 X60 Z50")
    m = sim(t)
    # material boundary between Z-5 and 0 follows the R5 arc (G02: centre X30 Z0)
    c = (0.0, 15.0)  # (z, x) centre
    b = m.material.boundary
    pts = [p for p in b.coords if -4.9 < p[0] < -0.1 and 10.1 < p[1] < 14.9]
    assert pts
    for z, x in pts:
        assert math.hypot(z - c[0], x - c[1]) == pytest.approx(5.0, abs=0.0006)


def test_default_machine_and_tools_fill_registers():
    m = sim(prog("T0101", "M03 S800", "G00 X42 Z2", "X30", "G01 Z-30 F200", "X42",
                 "G00 X60 Z50"), machine=load_machine())
    shapes = {k: s for k, s in m.shapes.items()}
    assert shapes[(1, None)].nose_radius == pytest.approx(0.8)
    # a register in neither the machine file nor the tool library is a sharp point: the
    # default 80 deg outline with its corner exactly at the controlled point
    m2 = sim(prog("T0909", "M03 S800", "G00 X42 Z2", "X30", "G01 Z-30 F200", "X42",
                  "G00 X60 Z50"), machine=load_machine())
    s9 = m2.shapes[(9, None)]
    assert s9.nose_radius == 0.0 and s9.centre == (0.0, 0.0)
    assert min(float(abs(p).sum()) for p in s9.outline) == pytest.approx(0.0, abs=1e-12)
    # with the sharp point the shoulder at Z-30 is square: no nose fillet left in the corner
    corner = m2.material.intersection(shapely.box(-30.0, 15.0, -29.0, 16.0))
    assert corner.area < 1e-6


def test_zero_feed_touching_material():
    moves = [Move("line", (19.0, 2.0), (19.0, -8.0), 3, feed=0.0, spindle=500, duration=0.0)]
    tp = Toolpath(moves=moves, source_lines=["", "", "G01 Z-8 F0"])
    m = simulate(tp, Stock.parse("40x60"), SHARP)
    assert [(i.kind, i.line, i.block) for i in m.issues] == [("feed", 3, "G01 Z-8 F0")]


def test_sim_is_independent_of_planner_post_and_cad():
    import subprocess
    import sys
    code = ("import sys, hnc_cam.sim, hnc_cam.sim.plot, hnc_cam.sim.verify, hnc_cam.check; "
            "bad = [m for m in sys.modules if m.startswith(('hnc_cam.plan', 'hnc_cam.post', "
            "'hnc_cam.cad', 'hnc_cam._templates', 'OCP', 'build123d', 'cadquery', 'jinja2', "
            "'matplotlib'))]; print(bad); sys.exit(1 if bad else 0)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr


def test_rapid_shaving_a_sliver_is_a_note_not_a_collision():
    # after turning dia 30, a rapid back along Z 0.04 mm (radial) into the surface
    t = prog("M03 S800", "G00 X42 Z2", "X30", "G01 Z-30 F200", "X42", "G00 Z2", "X29.92",
             "G00 Z-20", "G00 X42", "G00 X60 Z50")
    m = sim(t)
    assert not m.issues
    assert m.notes and m.notes[0].line == line_of(t, "G00 Z-20") and m.notes[0].kind == "rapid-sliver"
    assert "sliver" in m.summary()


def test_round_and_grooving_outlines_cut_their_shape():
    rnd = Machine(registers={1: Register(number=1, radius=4.0, tip=0,
                                         insert=Insert.parse("RCMT0803M0", 4.0))})
    # a round insert (tip 0: centre programmed) plunged 2 mm leaves a circular groove of R4
    m = sim(prog("T0101", "M03 S500", "G00 X50 Z-20", "G01 X44 F50", "G00 X50",
                 "G00 X60 Z50"), machine=rnd)
    cut = m.material.intersection(shapely.LineString([(-20, 0), (-20, 100)]))
    assert cut.bounds[3] == pytest.approx(22 - 4, abs=1e-6)
    removed = m.stock.difference(m.material)
    assert removed.bounds == pytest.approx((-20 - math.sqrt(16 - 4), 18, -20 + math.sqrt(16 - 4), 20), abs=1e-3)


def test_every_finding_names_its_check_in_the_json_message():
    from hnc_cam.sim.simulate import CHECKS
    # a rapid through the stock, a feed with the spindle stopped, a thread with it stopped,
    # a move at feed 0 and a cut with the back of the insert, in one program
    moves = [Move("line", (19.0, 2.0), (19.0, -8.0), 3, feed=0.0, spindle=500, duration=0.0)]
    tp = Toolpath(moves=moves, source_lines=["", "", "G01 Z-8 F0"])
    js = simulate(tp, Stock.parse("40x60"), SHARP).to_json()["collisions"]
    assert [c["message"].split(":")[0] for c in js] == ["zero feed"]
    t = prog("G00 X42 Z2", "X36", "G01 Z-10 F100", "G00 X42", "X39 Z3", "G32 Z-20 F1.5",
             "G00 X42", "G00 X20 Z-10", "G00 X60 Z50")
    m = sim(t)
    got = {(c["line"], c["message"].split(":")[0]) for c in m.to_json()["collisions"]}
    # (the stopped spindle also makes the thread's feed 0: one finding, and the rapid out of
    # the stock from inside it is a collision too)
    assert got == {(line_of(t, "G01 Z-10 F100"), "spindle stopped"),
                   (line_of(t, "G32 Z-20 F1.5"), "spindle stopped"),
                   (line_of(t, "G00 X20 Z-10"), "collision"),
                   (line_of(t, "G00 X60 Z50"), "collision")}
    t2 = prog("T0101", "M03 S800", "G00 X42 Z2", "Z-70", "X30", "G01 Z-50 F50", "G00 X42",
              "G00 X60 Z50")
    m2 = sim(t2, machine=CNMG)
    got2 = [(c["line"], c["message"].split(":")[0]) for c in m2.to_json()["collisions"]]
    assert (line_of(t2, "G01 Z-50 F50"), "non-cutting edge") in got2
    for i in [*m.issues, *m2.issues]:
        assert i.message.startswith(CHECKS[i.kind] + ": ")
