"""The planner fuzzer (``benchmarks/planner_fuzz.py``) in a bounded run: random fresh parts
written as part files, each through ``hnc-cam generate`` in both compensation modes and
every dialect; every run a verified program (exit 0) or a one-line refusal (exit 2). The
longer run is by hand: ``python benchmarks/planner_fuzz.py --parts 40 --seed S``."""
from __future__ import annotations

import random
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import planner_fuzz  # noqa: E402
from hnc_cam.plan.api import VerificationError  # noqa: E402


def test_random_part_files_are_parts():
    """The generator writes part files the loader takes: 30 in a row of one seed load and
    revolve (sketch and plain build123d alike)."""
    rng = random.Random(7)
    styles = set()
    for i in range(30):
        text = planner_fuzz.random_part(rng, f"t{i}")
        styles.add("build123d" if "Polyline" in text else "sketch")
        ns: dict = {}
        exec(compile(text, f"t{i}.py", "exec"), ns)
        solid = ns["part"]()
        assert solid is not None and solid.volume > 0
    assert styles == {"build123d", "sketch"}


@pytest.mark.parametrize("seed", [101])
def test_bounded_fuzz_run_has_no_failure(seed, tmp_path, capsys):
    rc = planner_fuzz.main(["--parts", "3", "--seed", str(seed), "--save", str(tmp_path)])
    out = capsys.readouterr().out
    assert rc == 0, out
    last = out.strip().splitlines()[-1]
    assert "3 parts x 2 modes x 4 dialects = 24 runs" in last and "0 failed" in last


def test_the_verdicts_are_told_apart(tmp_path):
    """A refusal is one ``error:`` line and exit 2; a part file that is not a part is a
    refusal too, never a pass."""
    bad = tmp_path / "bad.py"
    bad.write_text("def part():\n    raise ValueError('no part here')\n")
    verdict, msg = planner_fuzz.run_generate(bad, "cam", "hnc21t", tmp_path / "bad.nc")
    assert verdict == "refused" and msg.startswith("error: ")
    assert not (tmp_path / "bad.nc").exists()
    good = ROOT / "tests" / "data" / "turning_parts" / "spacer_collar.py"
    verdict, msg = planner_fuzz.run_generate(good, "control", "hnc21t", tmp_path / "g.nc")
    assert verdict == "pass" and (tmp_path / "g.nc").read_text().startswith("%")


FRESH = ROOT / "tests" / "data" / "turning_parts"


@pytest.mark.parametrize("name", ["bulge_bore", "chamfer_taper_bore"])
def test_fuzz_found_obtuse_outside_corners_of_drilled_parts_verify(name):
    """A part with a spot-drilled and drilled hole and an obtuse concave outside corner: the
    finishing nose leaves its fillet in that corner, and the drills (which cut along the axis
    only) are not counted among the tools that reach it, so the program verifies."""
    from hnc_cam.plan.api import generate
    prog = generate(str(FRESH / f"{name}.py"), comp="cam")
    assert prog.report.passed
    assert prog.report.max_undercut_mm < 0.005
