"""``hnc-cam run``: summary, warnings, JSON contract, fast start without CAD imports."""
from __future__ import annotations

import json
import subprocess
import sys

PROG = "%1\nG92 X40 Z5\nM03 S400\nG00 X0\nG01 Z0\nG03 U24 W-24 R15 F60\nG00 X40 Z5\nM30\n"


def cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "hnc_cam.cli", *args], capture_output=True,
                          text=True, cwd=cwd)


def test_run_prints_summary_and_warnings(tmp_path):
    p = tmp_path / "a.nc"
    p.write_text(PROG)
    r = cli("run", str(p))
    assert r.returncode == 0, r.stderr
    out = r.stdout.strip()
    assert out.startswith(f"{p}: 7 blocks executed, 5 moves")
    for part in ("feed ", "rapid ", "cycle time", "X 0.000..40.000 (dia)", "Z -24.000..5.000"):
        assert part in out
    assert f"{p}:5: warning: feed move before any F" in r.stderr


def test_run_json_to_file_and_stdout(tmp_path):
    p = tmp_path / "a.nc"
    p.write_text(PROG)
    out = tmp_path / "o" / "a.json"
    r = cli("run", str(p), "--json", str(out))
    assert r.returncode == 0, r.stderr
    d = json.loads(out.read_text())
    assert [m["type"] for m in d["moves"]] == ["rapid", "line", "arc", "rapid", "rapid"]
    assert d["moves"][2]["center"] == [0.0, -15.0] and d["moves"][2]["cw"] is False
    assert d["warnings"][0]["line"] == 5
    assert d["cycle_time_s"] > 0
    r = cli("run", str(p), "--json", "-")
    assert json.loads(r.stdout) == d
    assert "blocks executed" in r.stderr


def test_run_with_machine_file(tmp_path):
    p = tmp_path / "a.nc"
    p.write_text(PROG)
    m = tmp_path / "m.toml"
    m.write_text("[machine]\nrapid_x = 1000.0\nrapid_z = 1000.0\ndefault_feed = 30.0\n")
    out = tmp_path / "a.json"
    assert cli("run", str(p), "--machine", str(m), "--json", str(out)).returncode == 0
    d = json.loads(out.read_text())
    assert d["moves"][1]["feed"] == 30.0
    assert d["moves"][0]["end"] == [0.0, 5.0]


def test_run_does_not_import_cad_packages(tmp_path):
    p = tmp_path / "a.nc"
    p.write_text(PROG)
    r = subprocess.run([sys.executable, "-X", "importtime", "-m", "hnc_cam.cli", "run", str(p)],
                       capture_output=True, text=True)
    assert r.returncode == 0
    mods = {ln.split("|")[-1].strip().split(".")[0] for ln in r.stderr.splitlines()
            if ln.startswith("import time:")}
    for heavy in ("OCP", "build123d", "cadquery", "shapely", "numpy", "matplotlib"):
        assert heavy not in mods


def test_unwritable_json_is_an_error_not_a_traceback(tmp_path):
    p = tmp_path / "a.nc"
    p.write_text(PROG)
    (tmp_path / "f").write_text("")
    r = cli("run", str(p), "--json", str(tmp_path / "f" / "x.json"))
    assert r.returncode == 2 and "cannot write" in r.stderr and "Traceback" not in r.stderr


def test_run_starts_at_the_reference_point(tmp_path):
    p = tmp_path / "a.nc"
    p.write_text("%1\nG91 G00 W-1\nM30\n")
    out = tmp_path / "a.json"
    assert cli("run", str(p), "--json", str(out)).returncode == 0
    from hnc_cam.tooling import load_machine
    rx, rz = load_machine(None).reference
    assert json.loads(out.read_text())["moves"][0]["start"] == [2 * rx, rz]
