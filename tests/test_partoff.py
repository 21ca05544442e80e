"""Part-off: the parting blade cuts the left end's chamfer or round with its corner and parts
the part off a bar held in the chuck; the simulator separates the part and verify checks the
separated part's left end."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.errors import PlanError
from hnc_cam.plan.api import generate

ROOT = Path(__file__).resolve().parents[1]
PARTS = ROOT / "parts"
FRESH = ROOT / "tests" / "data" / "turning_parts"

ROUND_PIN = '''
import math
from build123d import (BuildLine, BuildPart, BuildSketch, Plane, Line, ThreePointArc, Axis,
                       make_face, revolve)

STOCK = "30x70+1"


def part():
    c = (10, -23)  # a 2 mm round on the left edge of a 24 mm pin, 25 mm long
    m = (c[0] + 2 * math.cos(math.radians(-45)), c[1] + 2 * math.sin(math.radians(-45)))
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Line((0, 0), (11, 0)); Line((11, 0), (12, -1)); Line((12, -1), (12, -23))
                ThreePointArc((12, -23), m, (10, -25)); Line((10, -25), (0, -25))
                Line((0, -25), (0, 0))
            make_face()
        revolve(axis=Axis.Z)
    return p.part
'''


def _partoff_blocks(text: str) -> list[str]:
    lines = text.splitlines()
    i = next(k for k, ln in enumerate(lines) if "PART OFF" in ln)
    out = []
    for ln in lines[i + 1:]:
        if re.search(r"\bM0?5\b|\bT\d{4}|X100\b", ln):  # to the tool-change point
            break
        out.append(re.sub(r"^N\d+ ", "", ln))
    return out


def _words(block: str) -> dict[str, float]:
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"([XZFS])(-?[\d.]+)", block)}


def test_pin_is_parted_off_with_its_chamfer_cut_by_the_blade_corner():
    prog = generate(FRESH / "pin_partoff.py", grip=20)
    assert [op.name for op in prog.plan.operations][-1] == "partoff"
    assert "profile" not in [op.name for op in prog.plan.operations]
    assert prog.report.passed, prog.report.summary()
    blocks = _partoff_blocks(prog.text)
    w = [_words(b) for b in blocks]
    # G97 at 100 m/min on the 25 mm bar: 1273 rpm (under the blade's 1500)
    assert blocks[0] == "G97 S1273 M03"
    # to the part's left end Z-30 above the bar, X first
    assert blocks[1:3] == ["G00 X27", "G00 Z-30"]
    # a groove beside the chamfer to 0.5 mm (radius) below it: diameter 18 - 1 = 17
    assert blocks[3] == "G01 X17 F0.06" and blocks[4] == "G00 X27"
    # the chamfer from diameter 20 at Z-29 to 18 at Z-30 with the corner (r 0.2, tip 4:
    # the controlled point is the corner's imaginary tip, on the part's side)
    chamfer = [x for x in w[5:] if "X" in x and "Z" in x and x["Z"] > -30.0 + 1e-9]
    assert chamfer and max(x["X"] for x in chamfer) == pytest.approx(20.0)
    # the plunge at Z-30: F0.06 down to a quarter of the diameter, then F0.03 to X-1
    plunge = [x for x in w if x.get("F") is not None]
    assert plunge[-2] == {"X": 6.25, "Z": -30.0, "F": 0.06}
    assert plunge[-1] == {"X": -1.0, "F": 0.03}
    assert blocks[-1] == "G00 X27"


def test_the_simulator_separates_the_part_and_verify_checks_its_left_end():
    from hnc_cam.sim import simulate
    from hnc_cam.sim.region import profile_polygon
    from hnc_cam.sim.verify import separated_part
    prog = generate(FRESH / "pin_partoff.py", grip=20)
    m = simulate(prog.toolpath, prog.plan.stock, prog.plan.machine)
    part = separated_part(m, profile_polygon(prog.plan.profile))
    assert part is not None and len(m.fallen) >= 1
    z0, x0, z1, x1 = part.bounds
    assert (z0, z1, x1) == pytest.approx((-30.0, 0.0, 10.0), abs=2e-3)
    # what stays in the chuck: the bar from Z-79 to the blade's far side, Z-33
    assert m.material.bounds[0] == pytest.approx(-79.0) and \
        m.material.bounds[2] == pytest.approx(-33.0, abs=2e-3)
    # the left-end chamfer: 1 mm x 45 deg, measured on the separated part
    from shapely.geometry import LineString
    for z, r in [(-30.0 + 0.25, 9.25), (-30.0 + 0.75, 9.75), (-29.0 + 0.5, 10.0)]:
        cut = part.intersection(LineString([(z, 0.0), (z, 20.0)]))
        assert cut.bounds[3] == pytest.approx(r, abs=3e-3), z


def test_a_part_off_program_edited_to_stop_short_of_the_chamfer_fails_verification(tmp_path,
                                                                                   capsys):
    prog = generate(FRESH / "pin_partoff.py", grip=20, verify=False)
    # the corner's pass along the chamfer goes out of the program: after the groove beside
    # it the blade parts off straight at Z-30, leaving the chamfer's corner on the part
    lines = prog.text.splitlines()
    i = next(k for k, ln in enumerate(lines) if "PART OFF" in ln)
    k0 = next(k for k in range(i, len(lines)) if "G00 Z-28.3" in lines[k])
    k1 = next(k for k in range(k0, len(lines)) if "X6.25 Z-30" in lines[k])
    assert k1 - k0 == 8
    lines = lines[:k0] + lines[k1:]
    p = tmp_path / "e.nc"
    p.write_text("\n".join(lines) + "\n")
    out = tmp_path / "e.json"
    rc = main(["verify", str(p), "--model", str(FRESH / "pin_partoff.py"), "--grip", "20",
               "--json", str(out)])
    assert rc == 1
    import json
    rep = json.loads(out.read_text())
    # the chamfer's corner left on the part's left end (Z-30..-29, diameter 18..20)
    assert rep["max_undercut_mm"] > 0.25 and rep["max_overcut_mm"] < 0.01
    m = re.search(r"max undercut [\d.]+ mm at X([\d.]+) Z(-[\d.]+)", capsys.readouterr().out)
    assert m and 18.0 <= float(m.group(1)) <= 20.0 and -30.0 <= float(m.group(2)) <= -29.0


def test_round_left_end_cut_by_the_blade_corner():
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        f = Path(d) / "round_pin.py"
        f.write_text(ROUND_PIN)
        prog = generate(f, grip=20)
    assert prog.report.passed, prog.report.summary()
    blocks = _partoff_blocks(prog.text)
    # the 2 mm round traced by the corner's tip path: an arc of 2 + 0.2 mm ending on the face
    arc = [b for b in blocks if b.startswith("G03")]
    assert arc == ["G03 X19.6 Z-25 R2.2"]


def test_no_partoff_keeps_the_part_on_the_bar_byte_for_byte():
    old = generate(PARTS / "stepped_shaft.py")
    kept = generate(PARTS / "stepped_shaft.py", grip=10, partoff=False)
    # the same program, its header naming the grip the jaws are verified with
    assert kept.text.replace("(GRIP 10)\n", "", 1) == old.text and "(GRIP 10)" in kept.text
    assert [op.name for op in kept.plan.operations][-1] == "profile"


def test_stock_too_short_to_part_off_falls_back_with_a_warning(capsys, tmp_path):
    # 45x117+2, part 100, blade 3, grip 11, clearance 2: 2 + 100 + 3 + 11 + 2 = 118 > 117
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--grip", "11", "-o",
               str(tmp_path / "o.nc")])
    err = capsys.readouterr().err
    assert rc == 0
    assert ("warning: stock 45x117+2 is too short to part off: part 100 + blade 3 + face 2 + "
            "grip 11 + clearance 2 = 118 mm") in err
    assert "PART OFF" not in (tmp_path / "o.nc").read_text()
    assert "partoff" in [op.name for op in generate(PARTS / "stepped_shaft.py", grip=10)
                         .plan.operations]


def test_partoff_speed_is_capped_by_the_blade_and_a_stem_diameter_by_option(tmp_path):
    lib = (ROOT / "hnc_cam" / "data" / "tools.toml").read_text()
    f = tmp_path / "tools.toml"
    f.write_text(lib.replace("max_rpm = 1500.0", "max_rpm = 600.0"))
    prog = generate(FRESH / "pin_partoff.py", grip=20, tools=f, partoff_dia=3.0)
    blocks = _partoff_blocks(prog.text)
    assert blocks[0] == "G97 S600 M03"
    assert blocks[-2] == "G01 X3 F0.03"
    # a stem holds the part: nothing fell, and the part still verifies on the bar
    assert prog.report.passed


def test_a_blade_too_short_is_refused_naming_the_depth_needed(tmp_path, capsys):
    lib = (ROOT / "hnc_cam" / "data" / "tools.toml").read_text()
    f = tmp_path / "tools.toml"
    f.write_text(lib.replace("max_depth = 26.0", "max_depth = 10.0"))
    out = tmp_path / "o.nc"
    rc = main(["generate", str(FRESH / "pin_partoff.py"), "--grip", "20", "--tools", str(f),
               "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists()
    # the 25 mm bar to the centre: 12.5 mm deep
    assert ("parting off diameter 25 to -1 needs a blade reaching 12.5 mm deep; T08 Parting "
            "blade 3 mm reaches 10 mm") in err


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas"])
def test_partoff_generates_and_verifies_in_every_dialect(dialect):
    prog = generate(FRESH / "pin_partoff.py", grip=20, dialect=dialect)
    assert prog.report.passed and prog.plan.operations[-1].kind == "part"
    assert min(m.end[0] for m in prog.toolpath.moves if m.tool == 8) == pytest.approx(-0.5)


def test_tube_is_parted_off_through_its_wall_to_the_bore(capsys):
    # bushing 40/22 x 30 from tube stock 45/19x47+2: the blade stops 0.5 mm (radius) inside
    # the tube's bore, at the blade's feed all the way (no centre to slow down for)
    prog = generate(PARTS / "bushing.py", grip=10)
    assert prog.report.passed and prog.plan.operations[-1].kind == "part"
    blocks = _partoff_blocks(prog.text)
    assert blocks[-2] == "G01 X18 Z-30 F0.06"
    assert min(m.end[0] for m in prog.toolpath.moves if m.tool == 8) == pytest.approx(9.0)


def test_a_stock_no_grip_can_save_names_only_the_longer_stock(capsys):
    # disc 155x30+1.5: the part's 27 mm and the chamfer's passes leave no room for jaws
    rc = main(["generate", str(FRESH / "disc_hub.py"), "--grip", "10"])
    err = capsys.readouterr().err
    assert rc == 2 and "a stock at least 41.6 mm long" in err and "grip of at most" not in err


@pytest.mark.parametrize("extra,parted", [([], True), (["--no-partoff"], False)])
def test_family_rows_take_grip_and_no_partoff(tmp_path, capsys, extra, parted):
    table = tmp_path / "t.csv"
    table.write_text("length\n100\n95\n")
    out = tmp_path / "out"
    rc = main(["family", str(PARTS / "stepped_shaft.py"), "--table", str(table), "--out",
               str(out), "--grip", "10", "--jobs", "1", *extra])
    assert rc == 0
    for f in ("O0001.nc", "O0002.nc"):
        assert ("PART OFF" in (out / f).read_text()) is parted
    rows = (out / "summary.csv").read_text().splitlines()[1:]
    assert all((",ok," in r) and (("partoff G01" in r) is parted) for r in rows)
