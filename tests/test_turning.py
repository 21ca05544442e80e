"""Outside turning as a lathe programmer writes it: which tool removes what, allowances,
approach and retract, threads, large and small stock; asserted on the toolpath and the
simulated material, not on the program text."""
from __future__ import annotations

import math

import pytest

from hnc_cam.errors import PlanError
from hnc_cam.geometry import Line, TurnedProfile
from hnc_cam.plan import Options, make_plan
from hnc_cam.plan.api import generate
from hnc_cam.tooling import Stock, load_machine, load_tools

from test_plan_shapes import chain

LIB = load_tools(None)
MACH = load_machine(None, tools=LIB)
PARTS = "parts/"


def _plan(profile, stock, comp="cam"):
    return make_plan(profile, Stock.parse(stock), LIB, MACH, Options(comp=comp), name=profile.name)


# ---------------------------------------------------------------- turn-back tolerance

def test_sub_micron_rise_toward_the_face_is_not_a_back_facing_undercut():
    # the face rises 0.00001 mm over its width (noise of a fitted curve)
    prof = TurnedProfile(chain((0, 0), (8, 0.00001), (10, -2), (10, -30), (0, -30)), name="noisy")
    p = _plan(prof, "24x35+1")
    assert [op.name for op in p.operations][:3] == ["face", "rough", "finish"]


def test_a_real_rise_toward_the_face_is_still_refused():
    prof = TurnedProfile(chain((0, 0), (8, 0), (9, 0.2), (10, -2), (10, -30), (0, -30)),
                         name="backface")
    with pytest.raises(PlanError, match="turns back toward the right face at X18.000"):
        _plan(prof, "24x35+1")


# ---------------------------------------------------------------- threads too short

@pytest.mark.parametrize("length", [2.2, 3.0, 3.9])
def test_thread_too_short_for_full_depth_is_refused_naming_the_minimum(length):
    with pytest.raises(PlanError) as e:
        generate(PARTS + "threaded_stud.py", params={"thread_length": str(length)}, verify=False)
    msg = str(e.value)
    assert "too short to reach full depth" in msg
    assert "at least 4 mm" in msg and f"thread_length={length:g}" in msg


def test_thread_just_long_enough_reaches_the_standard_minor_diameter():
    prog = generate(PARTS + "threaded_stud.py", params={"thread_length": "4"})
    assert prog.report.passed
    th = prog.report.threads[0]
    assert abs(th.achieved_diameter - 18.16) <= 0.05


# ---------------------------------------------------------------- solids given directly

def test_generate_accepts_build123d_and_cadquery_solids():
    bd = pytest.importorskip("build123d")
    cq = pytest.importorskip("cadquery")
    solid = bd.Pos(0, 0, -20) * bd.Cylinder(10, 40)
    a = generate(solid, stock="22x45+1")
    w = cq.Workplane("XY").circle(10).extrude(-40)
    b = generate(w, stock="22x45+1")
    for prog in (a, b):
        assert prog.report.passed
        xs = [2 * abs(m.end[0]) for m in prog.toolpath.moves if m.kind in ("line", "arc")]
        assert max(xs) >= 20.0
    with pytest.raises(PlanError, match="parameters given"):
        generate(solid, stock="22x45+1", params={"length": "3"})


# ---------------------------------------------------------------- threads run out

@pytest.mark.parametrize("cycle", ["g76", "g82"])
def test_thread_runs_into_the_relief_and_starts_three_leads_before(cycle):
    prog = generate(PARTS + "threaded_stud.py", thread_cycle=cycle)
    assert prog.report.passed
    th = [m for m in prog.toolpath.moves if m.kind == "thread"]
    z_lo, pitch = -22.0, 1.5  # the stud's M20x1.5 ends at Z-22, its relief begins there
    assert min(min(m.start[1], m.end[1]) for m in th) <= z_lo - pitch + 1e-6
    # the relief's far wall (the collar) is at Z-28.578: the insert's flank stays clear
    assert min(min(m.start[1], m.end[1]) for m in th) >= -28.578 + 0.5 * pitch + 0.2
    assert max(max(m.start[1], m.end[1]) for m in th) >= 0.0 + 3 * pitch - 1e-6
    # the spindle runs G97 within the machine's limit and the 1200/lead - 80 threading rule
    assert all(0 < m.spindle <= min(3000, 1200 / pitch - 80) + 1e-6 for m in th)
