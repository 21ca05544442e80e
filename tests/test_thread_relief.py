"""A thread ending in a narrow square relief in front of a high wall (a bolt's head): the
threading insert's flank toward the wall must clear it with the tip at the thread's end. The
multiple-pass cycle's single-flank infeed (HNC-21T G76) ends its last pass its depth x
tan(30 deg) further, so where that brings the flank into the wall the thread is cut in single
passes with radial infeed, which end at the thread's end; where even those meet the wall, the
part is refused. Positions come from the interpreted toolpath, verdicts from the simulation."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from hnc_cam.errors import PlanError
from hnc_cam.plan.api import generate

PART = Path(__file__).parent / "data" / "turning_parts" / "relief_bolt.py"
DEPTH = 0.6134 * 1.5  # the M16x1.5 thread's depth (radius)


def _thread_ends(prog):
    """The Z where each threading pass ends (its longest leg along -Z)."""
    legs = [m for m in prog.toolpath.moves if m.kind == "thread" and m.start[1] - m.end[1] > 5]
    return [m.end[1] for m in legs]


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas", "siemens802"])
def test_a_relief_too_narrow_for_the_flank_infeed(dialect):
    """Relief 3.5 mm, head at diameter 26. HNC-21T: G76's last pass would end 0.531 mm past
    Z-22, its flank 3 mm further at Z-25.53 and above diameter 24 — into the head's face at
    Z-25.5; radial passes end at Z-22, the flank at Z-25. The other dialects' cycles end
    every pass on Z-22 and keep their cycle. Either way the part verifies."""
    prog = generate(PART, dialect=dialect)
    assert prog.report is not None and prog.report.passed
    ends = _thread_ends(prog)
    assert len(ends) >= 4
    assert ends == pytest.approx([-22.0] * len(ends), abs=1e-6)
    thread = next(op for op in prog.plan.operations if op.kind == "thread")
    assert thread.thread.method == ("passes" if dialect == "hnc21t" else "cycle")


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas", "siemens802"])
def test_the_cycle_is_kept_where_its_flank_clears_the_wall(dialect):
    """A head no higher than diameter 19 stands below the flank wherever the last pass ends:
    the multiple-pass cycle stays; the HNC-21T's passes end further by their depth along the
    flank (the dialect feature thread_end_on_flank the planner reads), the others' on Z-22."""
    from hnc_cam.dialect import get
    prog = generate(PART, params={"dh": "19"}, dialect=dialect)
    assert prog.report is not None and prog.report.passed
    thread = next(op for op in prog.plan.operations if op.kind == "thread")
    assert thread.thread.method == "cycle"
    shifted = get(dialect).has("thread_end_on_flank")
    assert shifted == (dialect == "hnc21t")
    want = -22.0 - (DEPTH * math.tan(math.radians(30)) if shifted else 0.0)
    assert min(_thread_ends(prog)) == pytest.approx(want, abs=2e-3)


def test_a_relief_shorter_than_the_flank_is_refused():
    """Relief 3 mm: even a radial pass's flank (3 mm along Z) reaches the head's face."""
    with pytest.raises(PlanError) as e:
        generate(PART, params={"w": "3.0"})
    assert "Z-25" in str(e.value) and "relief" in str(e.value)
