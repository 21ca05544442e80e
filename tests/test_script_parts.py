"""Plain modelling scripts as part files, a default stock, and where blades reach.

A CAM engineer's first input is often a modelling script written for build123d or CadQuery,
not a part family: the solid is left in a module-level ``part`` (build123d) or ``result``
(CadQuery), there is no ``part()`` function and no ``STOCK``. Such a script is a part without
parameters, made from the next standard bar.

Verification counts leftover as reachable only where some tool of the program could have cut
it. A grooving or parting blade cuts only where the program sends it; the fillet a finishing
nose leaves in a sharp inside corner elsewhere is not reachable leftover just because the
program also holds a blade with a smaller corner radius.
"""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.geometry import TurnedProfile
from test_plan_shapes import chain
from hnc_cam.plan.api import generate

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "tests" / "data" / "scripts"
KNOB = SCRIPTS / "knob_script.py"
SPACER = SCRIPTS / "spacer_cq.py"


def _header(text: str) -> dict[str, str]:
    out = {}
    for line in text.splitlines()[:12]:
        if line.startswith("(") and " " in line:
            k, v = line[1:].rstrip(")").split(" ", 1)
            out[k] = v
    return out


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_build123d_script_generates_and_verifies(comp):
    prog = generate(str(KNOB), comp=comp)
    assert prog.report.passed
    head = _header(prog.text)
    # no parameters, and the next standard bar: 28 mm part + 2 -> 30, 58 + 2 face + 15 grip
    assert "PARAMETERS" not in head
    assert head["STOCK"] == "30x75+2"
    # the M12x1.5 thread is cut to its standard minor diameter
    th = [m for m in prog.toolpath.moves if m.tool == 4 and m.kind in ("line", "thread")]
    assert th and min(2 * min(m.start[0], m.end[0]) for m in th) == pytest.approx(10.16, abs=0.01)


def test_sharp_inside_corner_is_the_finishing_nose_fillet_not_reachable_leftover():
    """The neck (radius 10) meets a shoulder rising at atan(2) = 63.4 deg to the axis in a
    sharp corner at Z-31. The finisher's R0.4 nose leaves a fillet there whose depth,
    measured to either edge, is R (1 - sin(theta/2)) for the corner's opening theta; the
    3 mm grooving blade (R0.2) in the same program only cut the relief at Z-20..-23."""
    prog = generate(str(KNOB), comp="cam")
    rep = prog.report
    assert rep.passed
    theta = math.pi - math.atan2(4.0, 2.0)
    depth = 0.4 * (1 - math.sin(theta / 2))
    at = [u for u in rep.unreachable if abs(u.z + 31.0) < 0.1]
    assert len(at) == 1 and at[0].size_mm == pytest.approx(depth, abs=0.002)
    assert 2 * at[0].x == pytest.approx(20.0, abs=0.2)


def test_grooved_pin_verifies_with_its_inside_corners_unreachable():
    """A 6 mm pin with a square groove to diameter 4: the corners the finisher's nose cannot
    enter are listed as unreachable, the groove's own corners are the blade's."""
    prof = TurnedProfile(chain((0, 0), (2.5, 0), (3, -0.5), (3, -8), (2, -8), (2, -11),
                               (3, -11), (3, -20), (4.5, -21.5), (4.5, -30), (0, -30)),
                         name="pin6g")
    for comp in ("cam", "control"):
        rep = generate(prof, stock="14x36+1", comp=comp).report
        assert rep.passed, comp
        assert rep.max_undercut_mm <= 0.01
        # the inside corner of the head's 45 deg chamfer (Z-20): R0.4 (1 - sin(67.5 deg))
        at = [u for u in rep.unreachable if abs(u.z + 20.0) < 0.1]
        assert at and at[0].size_mm == pytest.approx(0.4 * (1 - math.sin(math.radians(67.5))),
                                                     abs=0.002)


def test_cadquery_script_with_result_generates_and_verifies(tmp_path):
    out = tmp_path / "spacer.nc"
    rc = main(["generate", str(SPACER), "-o", str(out)])
    assert rc == 0
    head = _header(out.read_text())
    assert head["STOCK"] == "28x42+2"  # 24 mm part on a 28 mm bar, 25 + 2 + 15 long
    rc = main(["verify", str(out), "--model", str(SPACER)])
    assert rc == 0


def test_script_without_a_solid_is_refused(tmp_path, capsys):
    f = tmp_path / "empty.py"
    f.write_text("x = 1\nresult = 'not a solid'\n")
    out = tmp_path / "o.nc"
    rc = main(["generate", str(f), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1
    assert str(f) in err[0] and "no solid named part or result" in err[0]


def test_script_part_has_no_parameters(tmp_path, capsys):
    out = tmp_path / "o.nc"
    rc = main(["generate", str(SPACER), "--set", "length=10", "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1
    assert "unknown parameter length" in err[0] and "(none)" in err[0]


# ---------------------------------------------------------------- --thread (STEP files)

@pytest.fixture(scope="module")
def knob_step(tmp_path_factory):
    from build123d import export_step
    from hnc_cam.cad.loader import load_module
    path = tmp_path_factory.mktemp("step") / "knob.step"
    export_step(load_module(KNOB).part(), str(path))
    return path


def _thread_moves(text):
    from hnc_cam.nc import run
    from hnc_cam.tooling import load_machine
    tp = run(text, load_machine(None))
    return [m for m in tp.moves if m.kind == "thread"]


def test_step_file_with_thread_option_cuts_and_verifies_the_thread(knob_step, tmp_path):
    out = tmp_path / "k.nc"
    assert main(["generate", str(knob_step), "-o", str(out)]) == 0
    assert not _thread_moves(out.read_text())  # a STEP file declares no thread
    assert main(["generate", str(knob_step), "--thread", "M12x1.5@0:-19", "-o", str(out)]) == 0
    th = _thread_moves(out.read_text())
    assert th and min(2 * m.end[0] for m in th) == pytest.approx(10.16, abs=0.01)
    assert min(m.end[1] for m in th) < -19.0 + 1e-6  # runs out past the thread's end
    assert main(["verify", str(out), "--model", str(knob_step), "--thread",
                 "M12x1.5@0:-19"]) == 0


@pytest.mark.parametrize("spec, says", [
    ("M12x@0:-19", "expected [M]DxP@ZSTART:ZEND"),
    ("M12x1.5@0:-19,left", "not understood: 'left'"),
    ("M12x0@0:-19", "pitch=0.0 must be positive"),
    ("M12x1.5@-19:0", "z_start=-19.0 must be greater"),
    ("M12x1.5@0:-19,starts=1.5", "not understood: 'starts=1.5'"),
    ("M12x1.5@0:-30", "larger than the major diameter"),  # runs onto the 20 mm cone
])
def test_bad_thread_option_is_one_line_and_writes_nothing(knob_step, tmp_path, capsys, spec,
                                                          says):
    out = tmp_path / "k.nc"
    rc = main(["generate", str(knob_step), "--thread", spec, "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1
    assert says in err[0]


def test_thread_option_adds_to_a_part_files_threads():
    """The knob script declares M12x1.5 on the shank; a second, internal thread cannot be
    added to a part without a bore, and says so against the part."""
    from hnc_cam.cad import load_part
    from hnc_cam.cad.loader import parse_thread
    from hnc_cam.errors import PartError
    lp = load_part(str(KNOB))
    assert len(lp.threads) == 1
    with pytest.raises(PartError, match="internal thread"):
        load_part(str(KNOB), threads=[parse_thread("M8x1.25@0:-10,internal")])


def test_a_script_solid_that_is_not_turned_is_one_line_naming_the_file(tmp_path, capsys):
    f = tmp_path / "cube.py"
    f.write_text("from build123d import Box\npart = Box(10, 10, 10)\n")
    out = tmp_path / "o.nc"
    rc = main(["generate", str(f), "-o", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and not out.exists() and len(err) == 1
    assert err[0].startswith(f"error: {f}: not a body of revolution")  # no empty "()"


def test_default_stock_is_a_bar_unless_a_through_bore_takes_a_tube():
    from hnc_cam.plan.api import default_stock_for
    from hnc_cam.tooling import Stock
    solid = TurnedProfile(chain((0, 0), (12, 0), (12, -30), (0, -30)), name="pin")
    small = TurnedProfile(chain((9, 0), (18, 0), (18, -20), (9, -20)),
                          bore=chain((9, 0), (9, -20)), name="nut")  # 18 mm bore: drilled
    large = TurnedProfile(chain((20, 0), (30, 0), (30, -40), (20, -40)),
                          bore=chain((20, 0), (20, -40)), name="bush")  # 40 mm bore: a tube
    blind = TurnedProfile(chain((0, 0), (30, 0), (30, -40), (0, -40)),
                          bore=chain((20, 0), (20, -20), (0, -20)), name="cup")
    assert default_stock_for(solid) == "28x47+2"  # the bar size over 24 + 2; 30 + 2 + 15 long
    assert Stock.parse(default_stock_for(small)).kind == "bar"
    assert Stock.parse(default_stock_for(blind)).kind == "bar"
    tube = Stock.parse(default_stock_for(large))
    assert tube.kind == "tube" and tube.bore == pytest.approx(37.0)
