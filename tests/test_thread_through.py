"""An inside thread through the whole length of a part from bar (a plain nut): the hole runs
on past the part's left end into the material part-off or the left-end cut removes, and the
thread's full depth reaches the part's left face."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.plan.api import generate
from hnc_cam.plan.planner import _run_out_length
from hnc_cam.geometry import Thread

ROOT = Path(__file__).resolve().parents[1]
NUT = ROOT / "tests" / "data" / "turning_parts" / "nut_through.py"
MINOR = 24 - 1.0825 * 1.5
LEAD = 1.5
#: one lead at full depth, one lead of run-out, the flank's clearance off the drill's shoulder
PAST = _run_out_length(Thread(0.0, -20.0, 24.0, 1.5, internal=True))


def test_the_run_on_is_two_leads_and_the_flanks_clearance():
    # 2 x 1.5 + 0.2 + (6 cos 30 + 0.812) tan 30 = 6.669, up to 0.1 mm
    assert PAST == pytest.approx(6.7)


@pytest.mark.parametrize("grip", [None, 20.0])
@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it"])
def test_through_inside_thread_reaches_the_left_face(dialect, comp, grip):
    prog = generate(NUT, dialect=dialect, comp=comp, grip=grip)
    assert prog.report.passed, prog.report.summary()
    ops = {op.name: op for op in prog.plan.operations}
    if grip:
        assert prog.plan.operations[-1].kind == "part"
    else:
        assert "partoff" not in ops
    # verified at the standard major diameter over the part's whole length
    (th,) = prog.report.threads
    assert th.internal and th.ok
    assert (th.z_min, th.z_max) == (pytest.approx(-20.0), pytest.approx(0.0))
    assert th.achieved_diameter == pytest.approx(24.0, abs=0.05)
    # the cycle's full depth ends at least one lead past the left face, before the run-out
    cut = ops["thread"].thread
    assert cut.z_end <= -20.0 - LEAD + 1e-6
    assert cut.runout_z == pytest.approx(-LEAD)
    # the passes at the major diameter run from before the face to past the left end
    full = [m for m in prog.toolpath.moves if m.kind == "thread"
            and abs(m.start[0] - 12.0) < 1e-3 and abs(m.end[0] - 12.0) < 1e-3]
    assert full
    assert max(max(m.start[1], m.end[1]) for m in full) > 0.0
    assert min(min(m.start[1], m.end[1]) for m in full) <= -20.0 - LEAD + 1e-6
    # the run-out pulls the insert to the minor diameter before the drilled hole's shoulder
    assert min(m.end[1] for m in prog.toolpath.moves if m.kind == "thread") \
        >= -20.0 - PAST + 0.2
    # the drill's full diameter runs past the bored run-on (its point beyond that)
    drill = ops["drill"]
    h = drill.tool.diameter / 2 * 0.6008606190275604  # the point: r / tan 59 deg
    assert drill.drill.z_end == pytest.approx(-20.0 - PAST - 0.5 - h, abs=1e-3)
    # the boring bar bores the minor diameter down to the end of the run-on (its nose's
    # centre, in cam mode, up to the nose radius beyond)
    fin = ops["bore_finish"]
    along = [s for s in fin.contour if abs(s.start[0] - s.end[0]) < 1e-9
             and abs(s.start[0] - MINOR / 2) < 0.01]
    assert along
    assert -20.0 - PAST - fin.tool.nose_radius - 1e-6 <= min(s.end[1] for s in along) \
        <= -20.0 - PAST + 1e-6


@pytest.mark.parametrize("grip", [None, 20.0])
def test_through_inside_thread_from_tube(grip):
    # a 20 mm bore tube: no drill, the boring bar bores the run-on past the left end
    prog = generate(NUT, stock="38/20x70+1", grip=grip)
    assert prog.report.passed, prog.report.summary()
    ops = {op.name: op for op in prog.plan.operations}
    assert "drill" not in ops and ops["thread"].thread.z_end <= -20.0 - LEAD + 1e-6
    (th,) = prog.report.threads
    assert th.ok and th.achieved_diameter == pytest.approx(24.0, abs=0.05)
    bore = [s for op in prog.plan.operations if op.name == "bore_finish" for s in op.contour
            if abs(s.start[0] - MINOR / 2) < 0.01 and abs(s.end[0] - MINOR / 2) < 0.01]
    assert bore and min(s.end[1] for s in bore) <= -20.0 - PAST + 1e-6


def test_through_inside_thread_in_single_passes():
    prog = generate(NUT, thread_cycle="g82", grip=20.0)
    assert prog.report.passed, prog.report.summary()
    full = [m for m in prog.toolpath.moves if m.kind == "thread"
            and abs(m.start[0] - 12.0) < 1e-3 and abs(m.end[0] - 12.0) < 1e-3]
    assert full and min(min(m.start[1], m.end[1]) for m in full) <= -20.0 - LEAD + 1e-6


def _refused(tmp_path, capsys, part: Path, *extra: str) -> str:
    out = tmp_path / "o.nc"
    rc = main(["generate", str(part), "-o", str(out), *extra])
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists(), err
    assert len(err.strip().splitlines()) == 1 and err.startswith("error: ")
    return err


@pytest.mark.parametrize("stock, grip, more, where", [
    # 3 mm of bar past the nut's left end; the run-on needs 6.7
    ("38x24+1", None, 3.7, ""),
    # the jaws at Z-29 (+2 mm clearance): the 20 mm drill's point would reach Z-33.209
    ("38x50+1", 20.0, 6.209, " clear of the chuck's jaws")])
def test_a_bar_too_short_for_the_run_on_keeps_the_thread_short(tmp_path, capsys, stock, grip,
                                                               more, where):
    f = tmp_path / "nut_short.py"
    f.write_text(NUT.read_text().replace('STOCK = "38x70+1"', f'STOCK = "{stock}"'))
    prog = generate(f, grip=grip, verify=False)
    assert (f"the hole would run on 6.7 mm past Z-20, the stock {stock} needs {more:g} mm more "
            f"for that{where}") in " ".join(prog.warnings)
    assert prog.plan.operations[[op.name for op in prog.plan.operations].index("thread")] \
        .thread.z_end > -20.0
    # verified, the short thread fails: nothing is written
    out = tmp_path / "o.nc"
    args = ["generate", str(f), "-o", str(out)] + (["--grip", "20"] if grip else [])
    assert main(args) == 1 and not out.exists()
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("error: ") and "fails verification" in err[0]
    # the planner's warning that says why follows the failure
    assert any(line.startswith("warning: ") and f"needs {more:g} mm more" in line
               for line in err[1:]), err
    # with that much more bar it is made
    longer = f"38x{int(stock.split('x')[1].split('+')[0]) + math.ceil(more)}+1"
    f.write_text(NUT.read_text().replace('STOCK = "38x70+1"', f'STOCK = "{longer}"'))
    prog = generate(f, grip=grip)
    assert prog.report.passed and prog.plan.operations[
        [op.name for op in prog.plan.operations].index("thread")].thread.z_end < -21.5


def test_a_run_on_past_the_boring_bars_reach_is_refused(tmp_path, capsys):
    # a 60 mm long nut: bored 66.7 mm deep with the run-on; the bundled bar reaches 64 mm
    f = tmp_path / "nut_long.py"
    f.write_text(NUT.read_text().replace('STOCK = "38x70+1"', 'STOCK = "38x130+1"')
                 .replace("-20.0", "-60.0").replace("-19)", "-59)").replace("-20)", "-60)"))
    err = _refused(tmp_path, capsys, f)
    assert "the bore runs 66.7 mm deep (to Z-66.7)" in err
    assert "it needs a boring bar reaching 66.7 mm" in err
