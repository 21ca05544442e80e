"""simulate() at scale: the batched removal equals removing move after move, whatever the batch,
and a finding deep inside a program of 100,000 moves is still reported on its own line."""
from __future__ import annotations

import random

import numpy as np
import pytest
import shapely

from hnc_cam.geometry import Arc
from hnc_cam.nc.interp import run
from hnc_cam.sim import simulate, stock_region
from hnc_cam.sim.region import diff, union
from hnc_cam.sim.simulate import _Sweeper
from hnc_cam.sim.tool import CHORD, sweep_hulls
from hnc_cam.tooling import Insert, Machine, Register, Stock

CNMG = Machine(registers={1: Register(number=1, radius=0.8, tip=3,
                                      insert=Insert.parse("CNMG120408"), approach=95.0)})


def line_of(text, needle):
    return next(i for i, l in enumerate(text.splitlines(), 1) if l.strip() == needle)


def _random_program(seed: int) -> str:
    """A roughing-like program a user could write: G01 passes toward the chuck at random
    depths, G02/G03 arcs, retracts and rapids (some of them into the material)."""
    rnd = random.Random(seed)
    out = ["%1", "T0101", "M03 S800", "G00 X44 Z2"]
    x = 44.0
    for _ in range(40):
        d = round(rnd.uniform(24.0, 40.0), 3)
        z = round(rnd.uniform(-50.0, -5.0), 3)
        out.append(f"G00 X{d} Z2")
        out.append(f"G01 Z{z} F{rnd.choice([150, 200, 300])}")
        r = round(rnd.uniform(1.0, 4.0), 3)
        out.append(f"G0{rnd.choice([2, 3])} X{d + 2 * r:.3f} Z{z - r:.3f} R{r}")
        out.append(f"G01 X{min(d + 2 * r + 2, 46):.3f}")
        if rnd.random() < 0.2:
            out.append(f"G00 X{round(rnd.uniform(20, 30), 3)} Z{round(rnd.uniform(-40, -5), 3)}")
            out.append("G00 X46")
        out.append("G00 Z2")
        x = d
    out.append("G00 X80 Z80")
    out.append("M30")
    return "\n".join(out) + "\n"


def _one_by_one(tp, stock, machine):
    """Reference: each move's swept region (the union of the exact hulls of its straight
    pieces) taken out of the whole material in program order."""
    sweeper = _Sweeper(machine, tp.moves)
    material = stock_region(stock)
    areas = []
    for m in tp.moves:
        if m.kind == "dwell":
            areas.append(0.0)
            continue
        if m.kind == "arc":
            pts = Arc(m.start, m.end, m.center, bool(m.cw)).sample(CHORD)
        else:
            pts = [m.start, m.end]
        p = np.array([(q[1], q[0]) for q in pts])
        sweep = union(sweep_hulls(sweeper.shape(m).outline, p[:-1], p[1:]))
        after = diff(material, sweep)
        a = material.area - after.area
        areas.append(a if a > 1e-12 else 0.0)
        material = after
    return np.array(areas), material


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_batched_removal_equals_move_by_move(seed):
    text = _random_program(seed)
    tp = run(text, CNMG, file="r.nc", start=(60.0, 50.0))
    stock = Stock.parse("40x60")
    ref_areas, ref_material = _one_by_one(tp, stock, CNMG)
    found = None
    for batch in (1, 7, 48, 1000):
        m = simulate(tp, stock, CNMG, batch=batch)
        assert m.removed_area == pytest.approx(ref_areas, abs=1e-9)
        assert shapely.symmetric_difference(m.material, ref_material).area < 1e-9
        got = [(i.line, i.kind, i.message) for i in m.issues + m.notes]
        if found is None:
            found = got
        assert got == found  # the findings do not depend on the batching
    assert ref_areas.sum() > 100.0


def test_collision_deep_in_100000_moves_is_on_its_line():
    # 2 x 35,000 feed moves in the air above the bar, facing and turning passes that cut, a
    # rapid into the bar, then 2 x 15,000 more moves in the air
    text = "\n".join([
        "%1", "T0101", "M03 S800", "G00 X50 Z5",
        "#1 = 0", "WHILE #1 LT 35000", "G01 Z6 F300", "G01 Z5", "#1 = #1 + 1", "ENDW",
        "G00 X42 Z0", "G01 X-1 F100", "G00 Z2", "X36", "G01 Z-40 F200", "X42", "G00 Z2",
        "G00 X30", "G00 Z-20", "G00 Z2", "G00 X50 Z5",
        "#1 = 0", "WHILE #1 LT 15000", "G01 Z6 F300", "G01 Z5", "#1 = #1 + 1", "ENDW",
        "M30"]) + "\n"
    tp = run(text, CNMG, file="big.nc", start=(60.0, 50.0))
    assert len(tp.moves) > 100_000
    m = simulate(tp, Stock.parse("40x60+1"), CNMG)
    into = line_of(text, "G00 Z-20")
    assert [(i.line, i.kind) for i in m.issues] == [(into, "collision")]
    k = next(i for i, mv in enumerate(tp.moves) if mv.line == into)
    assert k > 70_000
    # the passes before it cut: the face at Z0, then the 36 mm diameter over 40 mm less what
    # the tool leaves at its end (nose fillet (1 - pi/4) 0.8^2 = 0.137 mm^2 and the 5 deg lean
    # of the main edge over the remaining 1.13 mm, 0.056 mm^2)
    turn = line_of(text, "G01 Z-40 F200")
    a = sum(m.removed_area[i] for i, mv in enumerate(tp.moves) if mv.line == turn)
    assert 80.0 - 0.25 < a < 80.0 - 0.15
    assert m.removed_area[k] > 1.0
    # faced to Z0 down to the nose centre at X0.6 (dia): the nose leaves a cusp at the axis
    assert m.material.bounds[2] == pytest.approx(0.8 - (0.8 ** 2 - 0.3 ** 2) ** 0.5, abs=1e-3)
