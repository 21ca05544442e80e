"""The simulate and verify commands: exit codes, JSON contract, plots, bad input."""
from __future__ import annotations

import json

import pytest

from hnc_cam.cli import main

GOOD = """%1
T0101
M03 S800
G00 X42 Z2
X30
G01 Z-30 F200
X42
G00 X80 Z80
M30
"""
CRASH = GOOD.replace("G00 X80 Z80", "G00 X20 Z-10\nG00 X80 Z80")
SHARP = "use_tool_library = false\n[machine]\nname = \"sharp\"\n"


@pytest.fixture
def files(tmp_path):
    (tmp_path / "good.nc").write_text(GOOD)
    (tmp_path / "crash.nc").write_text(CRASH)
    (tmp_path / "sharp.toml").write_text(SHARP)
    (tmp_path / "part.py").write_text(
        "from hnc_cam.cad.sketch import Outline, revolve\n"
        "def sketch(d: float = 30.0, length: float = 30.0):\n"
        "    s = Outline((0.0, 0.0))\n"
        "    s.line_to(d / 2, 0.0)\n"
        "    s.line_to(d / 2, -length)\n"
        "    s.line_to(20.0, -length)\n"
        "    s.line_to(20.0, -50.0)\n"
        "    s.line_to(0.0, -50.0)\n"
        "    return s.segments()\n"
        "def part(d: float = 30.0, length: float = 30.0):\n"
        "    return revolve(sketch(d, length))\n")
    return tmp_path


def test_simulate_ok_json_and_plots(files, capsys):
    out = files / "sim.json"
    rc = main(["simulate", str(files / "good.nc"), "--stock", "40x60", "--machine",
               str(files / "sharp.toml"), "--json", str(out), "--plot", str(files / "sim.png")])
    assert rc == 0
    assert "no collisions" in capsys.readouterr().out
    js = json.loads(out.read_text())
    assert set(js) == {"machined", "collisions", "cycle_time_s", "removed_volume_mm3"}
    assert js["collisions"] == []
    assert js["removed_volume_mm3"] == pytest.approx(3.14159265 * 175 * 30, rel=1e-6)
    pts = [p for ring in js["machined"] for p in ring]
    assert [30.0, -30.0] in pts and [40.0, -60.0] in pts  # X as diameter
    assert (files / "sim.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rc = main(["simulate", str(files / "good.nc"), "--stock", "40x60", "--plot",
               str(files / "sim.svg")])
    assert rc == 0 and b"<svg" in (files / "sim.svg").read_bytes()[:400]


def test_simulate_collision_exit_1(files, capsys):
    out = files / "c.json"
    rc = main(["simulate", str(files / "crash.nc"), "--stock", "40x60", "--json", str(out)])
    assert rc == 1
    js = json.loads(out.read_text())
    assert js["collisions"][0]["line"] == CRASH.splitlines().index("G00 X20 Z-10") + 1
    assert js["collisions"][0]["block"] == "G00 X20 Z-10"
    assert "collision" in js["collisions"][0]["message"]


@pytest.mark.parametrize("argv,msg", [
    (["--stock", "40y60"], "stock"),
    (["--stock", "offset:2"], "needs --model"),
    (["--stock", "40x60", "--machine", "/nonexistent.toml"], "cannot read"),
])
def test_simulate_bad_input_exit_2(files, capsys, argv, msg):
    rc = main(["simulate", str(files / "good.nc"), *argv])
    assert rc == 2
    err = capsys.readouterr().err
    assert msg in err and "Traceback" not in err


def test_simulate_missing_program_and_alarm(files, capsys):
    assert main(["simulate", str(files / "nope.nc"), "--stock", "40x60"]) == 2
    (files / "bad.nc").write_text("%1\nG00 X10 Z5\nG999\nM30\n")
    assert main(["simulate", str(files / "bad.nc"), "--stock", "40x60"]) == 2
    assert "alarm" in capsys.readouterr().err


def test_plot_suffix_checked_and_nothing_written(files, capsys):
    rc = main(["simulate", str(files / "good.nc"), "--stock", "40x60", "--plot",
               str(files / "x.jpg")])
    assert rc == 2 and not (files / "x.jpg").exists()


@pytest.mark.cad
def test_verify_pass_fail_and_json(files, capsys):
    out = files / "v.json"
    rc = main(["verify", str(files / "good.nc"), "--model", str(files / "part.py"), "--stock",
               "40x60", "--machine", str(files / "sharp.toml"), "--json", str(out),
               "--plot", str(files / "v.png")])
    assert rc == 0, capsys.readouterr().out
    js = json.loads(out.read_text())
    assert set(js) == {"pass", "max_overcut_mm", "max_undercut_mm", "unreachable", "collisions",
                       "cycle_time_s", "air_cut_fraction"}
    assert js["pass"] is True and js["max_overcut_mm"] < 0.001
    assert (files / "v.png").stat().st_size > 10000
    # the same program against a 28 mm model leaves 1 mm of undercut: fail, exit 1
    rc = main(["verify", str(files / "good.nc"), "--model", str(files / "part.py"), "--set",
               "d=28", "--stock", "40x60", "--machine", str(files / "sharp.toml"), "--json",
               str(out)])
    assert rc == 1
    js = json.loads(out.read_text())
    assert js["pass"] is False and js["max_undercut_mm"] == pytest.approx(1.0, abs=0.001)
    assert main(["verify", str(files / "good.nc"), "--model", str(files / "part.py"),
                 "--stock", "40x60", "--tol", "-1"]) == 2
    assert main(["verify", str(files / "crash.nc"), "--model", str(files / "part.py"),
                 "--stock", "40x60"]) == 1


def test_unwritable_outputs_exit_2(files, capsys):
    (files / "blocker").write_text("a file, not a folder")
    rc = main(["simulate", str(files / "good.nc"), "--stock", "40x60", "--json",
               str(files / "blocker" / "x.json")])
    assert rc == 2 and "cannot write" in capsys.readouterr().err
    rc = main(["simulate", str(files / "good.nc"), "--stock", "40x60", "--plot",
               str(files / "blocker" / "x.png")])
    assert rc == 2 and "cannot write" in capsys.readouterr().err


@pytest.mark.cad
def test_simulate_offset_stock_with_model(files, capsys):
    out = files / "o.json"
    rc = main(["simulate", str(files / "good.nc"), "--stock", "offset:1", "--model",
               str(files / "part.py"), "--set", "d=30", "--json", str(out)])
    assert rc == 0, capsys.readouterr().err
    js = json.loads(out.read_text())
    xs = [p[0] for ring in js["machined"] for p in ring]
    assert max(xs) == pytest.approx(42.0, abs=1e-6)  # the dia 40 part grown by 1 mm radially


@pytest.mark.cad
def test_generated_program_verifies_with_the_default_tables(tmp_path, capsys):
    # defaults agree: the tool library generate uses fills the default machine's registers, so
    # the program verifies without --tools/--machine; a machine whose registers are sharp
    # points makes the same program leave the nose fillets' worth of material off the model
    from pathlib import Path
    part = str(Path(__file__).resolve().parents[1] / "parts" / "stepped_shaft.py")
    nc = tmp_path / "o.nc"
    assert main(["generate", part, "--no-verify", "-o", str(nc)]) == 0
    out = tmp_path / "v.json"
    rc = main(["verify", str(nc), "--model", part, "--stock", "45x117+2", "--json", str(out)])
    js = json.loads(out.read_text())
    assert rc == 0 and js["pass"] is True and js["collisions"] == [], capsys.readouterr().out
    (tmp_path / "sharp.toml").write_text(SHARP)
    rc2 = main(["verify", str(nc), "--model", part, "--stock", "45x117+2", "--machine",
                str(tmp_path / "sharp.toml"), "--json", str(out)])
    js2 = json.loads(out.read_text())
    assert rc2 == 1 and js2["pass"] is False and js2["max_overcut_mm"] > 0.1


@pytest.mark.cad
def test_verify_json_unreachable_in_diameter_and_bad_model(files, capsys):
    # T0101 of the default library has a 0.8 nose: the square shoulder at X30 Z-30 keeps its
    # fillet, listed as unreachable with x as a diameter, not counted: exit 0
    out = files / "u.json"
    rc = main(["verify", str(files / "good.nc"), "--model", str(files / "part.py"), "--stock",
               "40x60", "--json", str(out)])
    js = json.loads(out.read_text())
    assert rc == 0 and js["pass"] is True, capsys.readouterr().out
    (u,) = js["unreachable"]
    assert u["x"] == pytest.approx(30.0, abs=0.6) and u["z"] == pytest.approx(-30.0, abs=0.3)
    assert u["size_mm"] == pytest.approx(0.8 * (1 - 0.5 ** 0.5), abs=0.002)
    assert "cannot reach" in capsys.readouterr().out
    rc = main(["verify", str(files / "good.nc"), "--model", str(files / "nosuch.py"),
               "--stock", "40x60"])
    assert rc == 2 and "nosuch" in capsys.readouterr().err


def test_json_to_stdout_is_pure_json_and_unwritable_output_is_bad_input(tmp_path):
    """`--json -` keeps the summary off stdout; an output path that cannot be created is
    exit 2 with one line, no traceback; written files get the umask's mode, not 0600."""
    import json as _json
    import os
    import stat
    import subprocess
    import sys as _sys
    prog = tmp_path / "p.nc"
    prog.write_text("%1\nG00 X20 Z2\nM03 S500\nG01 X20 Z-10 F100\nG00 X40\nM30\n")
    exe = [_sys.executable, "-m", "hnc_cam.cli"]
    r = subprocess.run(exe + ["simulate", str(prog), "--stock", "30x50", "--json", "-"],
                       capture_output=True, text=True)
    assert "removed_volume_mm3" in _json.loads(r.stdout)
    blocker = tmp_path / "file"
    blocker.write_text("x")
    r = subprocess.run(exe + ["simulate", str(prog), "--stock", "30x50", "--json",
                              str(blocker / "out.json")], capture_output=True, text=True)
    assert r.returncode == 2 and "Traceback" not in r.stderr and "cannot write" in r.stderr
    out = tmp_path / "o.json"
    subprocess.run(exe + ["simulate", str(prog), "--stock", "30x50", "--json", str(out)],
                   capture_output=True, text=True)
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(out.stat().st_mode) == 0o666 & ~umask


@pytest.mark.parametrize("cmd", ["simulate", "verify"])
def test_a_path_that_is_no_program_is_said_before_the_missing_stock(files, capsys, cmd):
    """Without --stock the stock comes from the program's header; a directory or a missing
    file named as the program is said as such (one line, exit 2), not as a program without
    a (STOCK ...) line."""
    for bad, what in ((files, "a directory"), (files / "none.nc", "No such file")):
        args = [cmd, str(bad)] + (["--model", str(files / "part.py")] if cmd == "verify" else [])
        assert main(args) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and what in err[0] and "STOCK" not in err[0], err
    assert main([cmd, str(files / "good.nc")]
                + (["--model", str(files / "part.py")] if cmd == "verify" else [])) == 2
    assert "STOCK" in capsys.readouterr().err
