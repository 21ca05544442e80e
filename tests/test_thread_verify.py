"""Verification of threads: full form along the whole declared thread.

The root is measured at the worst place along the thread, one pitch in from each end, or
``verify.WALL_RUNOUT`` pitches where the part has a wall right beyond the end (the run-out no
tool can finish before a shoulder or a bore's bottom)."""
from __future__ import annotations

import pytest

from hnc_cam.geometry import Thread, TurnedProfile
from hnc_cam.plan.api import generate
from hnc_cam.sim.verify import WALL_RUNOUT

from test_plan_shapes import chain


def _nut():
    """A plain nut: 36 mm outside, M20x1.5 inside, through its 20 mm length."""
    r = (20 - 1.0825 * 1.5) / 2
    return TurnedProfile(chain((18, 0), (18, -20), (r, -20)),
                         bore=chain((r + 1, 0), (r, -1), (r, -20)),
                         threads=[Thread(0.0, -20.0, 20.0, 1.5, internal=True)], name="nut20")


def test_a_through_thread_cut_short_of_the_parting_line_fails():
    """Parted off a 40 mm bar, the nut's thread stops short of its left end (the bar beyond
    is taken for a wall), so the last turns of a through thread are not full form: the bore
    there is under the major diameter, which the measurement at the worst place finds."""
    prog = generate(_nut(), stock="40x50", grip=20, verify=False)
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Stock, load_machine, with_grip
    mach = with_grip(load_machine(None), 20.0)
    m = simulate(prog.toolpath, Stock.parse("40x50"), mach)
    (th,) = verify(m, prog.plan.profile).threads
    full = [mv for mv in prog.toolpath.moves if mv.kind == "thread"
            and abs(2 * mv.end[0] - 20.0) < 1e-3 and abs(2 * mv.start[0] - 20.0) < 1e-3]
    assert full and min(min(mv.start[1], mv.end[1]) for mv in full) > -20.0 + 1.5  # short
    assert not th.ok and th.achieved_diameter < 20.0 - 0.05


def test_a_thread_into_a_shoulder_is_measured_up_to_its_run_out():
    """M20x1.5 right up to a 26 mm collar without relief: full depth ends before the collar,
    inside the run-out the verifier leaves unmeasured, and the thread passes."""
    prof = TurnedProfile(chain((0, 0), (9, 0), (10, -1), (10, -25), (13, -25), (13, -45),
                               (0, -45)), threads=[Thread(0.0, -25.0, 20.0, 1.5)],
                         name="stud_no_relief")
    for dialect in ("hnc21t", "fanuc0it"):
        prog = generate(prof, stock="30x50+1", dialect=dialect)
        (th,) = prog.report.threads
        assert th.ok and prog.report.passed
        full = [mv for mv in prog.toolpath.moves if mv.kind == "thread"
                and abs(2 * mv.end[0] - th.target_diameter) < 1e-3
                and abs(2 * mv.start[0] - th.target_diameter) < 1e-3]
        end = min(min(mv.start[1], mv.end[1]) for mv in full)
        assert -25.0 < end <= -25.0 + WALL_RUNOUT * 1.5  # short of the wall, within the run-out
