"""SINUMERIK 802 ``CHF=`` on consecutive blocks: each corner is cut by the chamfer its own
block names (the chamfer's length), whatever the next block's ``CHF=`` is: positions of
the executed moves, and a fresh part whose contour carries a chamfer on every corner."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from hnc_cam import dialect, nc

S802 = dialect.get("siemens802")
FRESH = Path(__file__).parent / "data" / "turning_parts"


def _ends(tp):
    return [(round(m.end[0], 4), round(m.end[1], 4)) for m in tp.moves if m.kind == "line"]


def test_each_chf_cuts_its_own_corner_when_the_next_block_has_one_too():
    # X20 Z0 -> Z-10 (CHF 1 mm legs) -> X40 (CHF 3 mm legs) -> Z-30 (CHF 0.5 mm legs) -> X60
    r2 = math.sqrt(2)
    tp = nc.run(f"G0 X20 Z0\nG1 Z-10 CHF={r2:.6f} F100\nX40 CHF={3 * r2:.6f}\n"
                f"Z-30 CHF={0.5 * r2:.6f}\nX60\nM30\n", dialect=S802, start=(50.0, 50.0))
    assert _ends(tp) == [(10.0, -9.0), (11.0, -10.0),       # 1 mm along each line at X20 Z-10
                         (17.0, -10.0), (20.0, -13.0),      # 3 mm at X40 Z-10
                         (20.0, -29.5), (20.5, -30.0),      # 0.5 mm at X40 Z-30
                         (30.0, -30.0)]


def test_a_chf_after_an_unchamfered_corner_keeps_its_size():
    r2 = math.sqrt(2)
    tp = nc.run(f"G0 X20 Z0\nG1 Z-10 F100\nX40 CHF={2 * r2:.6f}\nZ-30\nM30\n", dialect=S802,
                start=(50.0, 50.0))
    assert _ends(tp) == [(10.0, -10.0), (18.0, -10.0), (20.0, -12.0), (20.0, -30.0)]


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_a_part_with_a_chamfer_on_every_corner_verifies_on_the_802(comp):
    """A journal with a chamfered root, a chamfered shoulder and collar: the control-mode
    LCYC95 contour carries CHF= on four blocks in a row."""
    from hnc_cam.plan.api import generate
    prog = generate(str(FRESH / "chamfer_chain.py"), comp=comp, dialect="siemens802")
    assert prog.report.passed, prog.report.summary()
    assert prog.report.max_overcut_mm <= 0.01 and prog.report.max_undercut_mm <= 0.01
    if comp == "control":
        assert prog.text.count("CHF=") >= 4
