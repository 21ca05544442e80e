"""Workholding: the chuck's jaws in the machine file, --grip, the planner's reach and
stick-out checks, the simulator's jaw collisions and the plot's jaws."""
from __future__ import annotations

from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.errors import HncError, PlanError
from hnc_cam.plan.api import generate
from hnc_cam.tooling import load_machine, with_grip

ROOT = Path(__file__).resolve().parents[1]
PARTS = ROOT / "parts"
FRESH = ROOT / "tests" / "data" / "turning_parts"


def _sim(text: str, grip: float | None, stock: str):
    from hnc_cam.nc import run
    from hnc_cam.sim import simulate
    from hnc_cam.tooling import Stock
    mach = load_machine()
    if grip is not None:
        mach = with_grip(mach, grip)
    tp = run(text, machine=mach, file="edited.nc", start="reference")
    return simulate(tp, Stock.parse(stock), mach)


def test_bundled_machine_describes_the_jaws_and_no_grip_models_none():
    m = load_machine()
    assert m.chuck_clamp == (2.0, 250.0) and m.jaw_length == 30.0 and m.jaw_height == 25.0
    assert m.grip == 0.0
    prog = generate(PARTS / "stepped_shaft.py")
    assert prog.report.passed


def test_cut_that_clears_the_jaws_verifies_with_the_jaws_modelled():
    # stock 45x117+2 spans Z-115..2; part left end Z-99: the left-end passes reach Z-101.1
    prog = generate(PARTS / "stepped_shaft.py", grip=11.6, partoff=False)
    assert prog.report.passed and not prog.warnings
    with pytest.raises(PlanError):
        generate(PARTS / "stepped_shaft.py", grip=11.7, partoff=False)
    from hnc_cam.sim import simulate
    m = simulate(prog.toolpath, prog.plan.stock, prog.plan.machine)
    z0, x0, z1, x1 = m.jaws.bounds
    assert (z0, x0, z1, x1) == pytest.approx((-115 + 11.6 - 30, 22.5, -103.4, 47.5))
    assert not m.issues


def test_a_cut_reaching_the_jaws_plus_clearance_is_refused_with_the_stick_out_needed():
    with pytest.raises(PlanError) as e:
        generate(PARTS / "stepped_shaft.py", grip=14)
    msg = str(e.value)
    # jaws' face at Z-115+14 = -101; the left-end chamfer's tip path (T05, r 0.4) runs on to
    # Z-101.383 (the G01 the simulator flags below); 2 mm clearance: stick-out
    # 2 + 103.383 = 105.383, stock 119.383, grip at most 117 - 105.383 = 11.617
    assert "the cut reaches Z-101.383," in msg and "jaws at Z-101 " in msg
    assert "stick-out 103 mm" in msg and "at least 105.383 mm" in msg
    assert "119.383 mm long" in msg and "at most 11.617 mm" in msg


def test_refusal_writes_nothing_and_exits_2(tmp_path, capsys):
    out = tmp_path / "o.nc"
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--grip", "14", "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists()
    assert err.startswith("error: part stepped_shaft: the cut reaches Z-101.383") and \
        err.count("\n") == 1


def test_program_edited_to_cut_into_the_jaws_is_caught_at_its_line():
    prog = generate(PARTS / "stepped_shaft.py", grip=10, verify=False)
    lines = prog.text.splitlines()
    end = next(i for i, ln in enumerate(lines) if "M30" in ln)
    # an extra pass along the bar toward the chuck: at X60 (radius 30) it is above the stock
    # (radius 22.5) but inside the jaws (radius 22.5..47.5 from Z-105 toward the chuck)
    lines[end:end] = ["G00 X60 Z-90", "G01 Z-108 F0.2", "G00 X100"]
    text = "\n".join(lines) + "\n"
    m = _sim(text, 10, "45x117+2")
    jaw = [i for i in m.issues if "chuck jaw" in i.message]
    # the pass into the jaws and the retract from inside them
    assert [i.line for i in jaw] == [end + 2, end + 3]
    assert jaw[0].kind == "collision" and jaw[0].message.startswith("collision: chuck jaw")
    z, x = jaw[0].at[1], 2 * jaw[0].at[0]
    assert -106.0 < z < -104.9
    assert 45.0 < x < 95.0
    # the same program without a grip: no jaws, no finding
    assert not [i for i in _sim(text, None, "45x117+2").issues if "chuck jaw" in i.message]


def test_simulate_and_verify_take_grip_and_exit_1_on_a_jaw_collision(tmp_path, capsys):
    prog = generate(PARTS / "stepped_shaft.py", grip=10, verify=False, partoff=False)
    p = tmp_path / "p.nc"
    p.write_text(prog.text)
    assert main(["simulate", str(p), "--grip", "13"]) == 0
    capsys.readouterr()
    # a grip of 14.5 puts the jaws' face at Z-100.5: the left-end passes (to Z-101.1) hit them
    assert main(["simulate", str(p), "--grip", "14.5", "--plot", str(tmp_path / "j.png")]) == 1
    out = capsys.readouterr().out
    assert "collision: chuck jaw" in out and (tmp_path / "j.png").stat().st_size > 1000
    rc = main(["verify", str(p), "--model", str(PARTS / "stepped_shaft.py"), "--grip", "14.5"])
    assert rc == 1
    assert main(["verify", str(p), "--model", str(PARTS / "stepped_shaft.py"),
                 "--grip", "11.6"]) == 0


def test_the_program_header_carries_the_grip_for_simulate_and_verify(tmp_path, capsys):
    """generate writes (GRIP mm) beside (STOCK ...); simulate and verify read it when the
    command line gives no --grip, and --grip overrides it."""
    prog = generate(PARTS / "stepped_shaft.py", grip=10, verify=False, partoff=False)
    assert "(GRIP 10)" in prog.text.splitlines()[:6]
    p = tmp_path / "p.nc"
    p.write_text(prog.text.replace("(GRIP 10)", "(GRIP 14.5)"))
    assert main(["simulate", str(p)]) == 1  # jaws' face at Z-100.5: the left-end passes hit it
    cap = capsys.readouterr()
    assert "collision: chuck jaw" in cap.out and "grip 14.5 mm" in cap.err
    assert main(["simulate", str(p), "--grip", "13"]) == 0
    capsys.readouterr()
    assert main(["verify", str(p), "--model", str(PARTS / "stepped_shaft.py")]) == 1
    assert main(["verify", str(p), "--model", str(PARTS / "stepped_shaft.py"),
                 "--grip", "11.6"]) == 0
    # without a grip no line is written and the jaws are not modelled
    assert "(GRIP" not in generate(PARTS / "stepped_shaft.py", verify=False).text


def test_long_thin_shaft_warns_with_the_stick_out_ratio(capsys, tmp_path):
    rc = main(["generate", str(FRESH / "thin_shaft.py"), "--grip", "20", "-o",
               str(tmp_path / "t.nc")])
    err = capsys.readouterr().err
    assert rc == 0
    # stock 16x125+1: stick-out 125 - 20 = 105 mm, 105 / 16 = 6.6
    assert "warning: stick-out 105 mm is 6.6 x the stock diameter 16 mm" in err
    prog = generate(FRESH / "thin_shaft.py", grip=15)
    assert len(prog.warnings) == 1 and "stick-out 110 mm is 6.9 x" in prog.warnings[0]
    assert prog.report.passed


def test_grip_longer_than_the_stock_names_both_numbers(tmp_path, capsys):
    mf = tmp_path / "m.toml"
    mf.write_text("[chuck]\njaw_length = 200\n")
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--machine", str(mf),
               "--grip", "120", "-o", str(tmp_path / "o.nc")])
    err = capsys.readouterr().err
    assert rc == 2 and not (tmp_path / "o.nc").exists()
    assert "error: grip 120 mm is not shorter than the stock 45x117+2 (117 mm long)" in err


def test_chuck_that_cannot_hold_the_stock_diameter_names_both_numbers(tmp_path, capsys):
    mf = tmp_path / "m.toml"
    mf.write_text("[chuck]\nclamp_min = 5\nclamp_max = 40\n")
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--machine", str(mf),
               "--grip", "10", "-o", str(tmp_path / "o.nc")])
    err = capsys.readouterr().err
    assert rc == 2 and not (tmp_path / "o.nc").exists()
    assert "diameter 45 mm is outside the chuck's clamping range 5-40 mm" in err


def test_grip_longer_than_the_jaws_and_bad_chuck_keys(tmp_path, capsys):
    with pytest.raises(HncError, match=r"grip 35 mm is longer than the chuck's jaws \(30 mm"):
        generate(PARTS / "stepped_shaft.py", grip=35)
    for body, want in [("clamp_min = 50\nclamp_max = 40\n", "m.toml:2: [chuck] clamp_min 50 mm is "
                        "not below clamp_max 40 mm"),
                       ("grip = 40\n", "m.toml:2: [chuck] grip 40 mm is longer than the jaws"),
                       ("jaw_heigth = 3\n", "m.toml:2: unknown key 'jaw_heigth' (did you mean "
                        "'jaw_height'?)"),
                       ("jaw_length = -3\n", "m.toml:2: jaw_length = -3 is out of range")]:
        mf = tmp_path / "m.toml"
        mf.write_text("[chuck]\n" + body)
        rc = main(["generate", str(FRESH / "thin_shaft.py"), "--machine", str(mf), "-o",
                   str(tmp_path / "o.nc")])
        err = capsys.readouterr().err
        assert rc == 2 and want in err, err
    assert main(["simulate", "x.nc", "--grip", "0"]) == 2
    assert "expected the grip length" in capsys.readouterr().err


def test_machine_file_grip_is_the_default_and_the_option_overrides_it(tmp_path):
    mf = tmp_path / "m.toml"
    mf.write_text("[chuck]\ngrip = 14\n")
    with pytest.raises(PlanError, match="at least 105.383 mm"):
        generate(PARTS / "stepped_shaft.py", machine=mf)
    assert generate(PARTS / "stepped_shaft.py", machine=mf, grip=10).report.passed
