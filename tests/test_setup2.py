"""Second setup: a part whose left end needs more than the part-off (a bore chamfer facing the
chuck, a journal stepping down toward the chuck) is made in two programs, the second with the
part turned around, gripped on a finished diameter, from what the first program actually
left (simulated)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

pytest.importorskip("shapely")

from shapely.geometry import LineString, box  # noqa: E402

from hnc_cam.cli import main  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
FRESH = ROOT / "tests" / "data" / "turning_parts"
BUSH = FRESH / "bush_chamfers.py"
PIN = FRESH / "pin_left_step.py"


def _run(capsys, argv):
    rc = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


@pytest.fixture(scope="module")
def bush_setups():
    from hnc_cam.plan.setups import generate_setups
    return generate_setups(BUSH, grip=20, grip2=15)


@pytest.fixture(scope="module")
def bush_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("bush")
    rc = main(["generate", str(BUSH), "--grip", "20", "--setups", "2", "--grip2", "15",
               "-o", f"{d}/"])
    assert rc == 0
    return d


def _radius_at(g, z: float, outer: bool = True) -> float:
    """The material's largest (or smallest) radius on the line Z = z."""
    cut = g.intersection(LineString([(z, -1.0), (z, 1e3)]))
    b = cut.bounds
    return b[3] if outer else b[1]


def test_bush_without_setups_2_is_refused_naming_the_chamfer(tmp_path, capsys):
    out = tmp_path / "o.nc"
    rc, _o, err = _run(capsys, ["generate", BUSH, "--grip", "20", "-o", out])
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and not out.exists()
    assert "bore's chamfer from Z-29 to Z-30 (diameter 24 to 26) faces the chuck" in lines[0]
    assert "--setups 2" in lines[0]


def test_pin_without_setups_2_is_refused_naming_setups_2(tmp_path, capsys):
    out = tmp_path / "o.nc"
    rc, _o, err = _run(capsys, ["generate", PIN, "--grip", "20", "-o", out])
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and not out.exists()
    assert "undercut from Z-27 to Z-40 down to diameter 20" in lines[0]
    assert "--setups 2" in lines[0]


def test_bush_zone_grip_and_setup1_left_end(bush_setups):
    s = bush_setups
    # the zone: from the bore chamfer's start (Z-29) on into the cylinders by the largest
    # nose radius (0.8) + 0.5 mm
    assert s.zone.z == pytest.approx(-27.7) and s.zone.z_min == pytest.approx(-30.0)
    assert s.grip.diameter == pytest.approx(40.0) and s.grip.length == pytest.approx(15.0)
    # the jaws 1 mm (the right edge's chamfer) + 15 mm from the chucked end
    assert s.grip.offset == pytest.approx(16.0)
    ops1 = [op.name for op in s.first.plan.operations]
    assert ops1[-1] == "partoff"
    # setup 1 parts off 0.5 mm beyond the left end, leaving face stock for setup 2
    assert s.first.plan.operations[-1].start[1] == pytest.approx(-30.5)
    assert s.report1.passed and s.report.passed, s.report.summary()


def test_setup2_stock_is_setup1s_simulated_part_turned_around(bush_dir, bush_setups):
    """The stock setup 2 is planned and verified from equals the part the written setup-1
    program leaves when run again from the file, mirrored about the part's length: area and
    Hausdorff distance within the simulator's chord error."""
    from hnc_cam.nc.interp import run_file
    from hnc_cam.sim import simulate
    from hnc_cam.sim.verify import separated_part
    from hnc_cam.sim.region import profile_polygon
    from hnc_cam.tooling import Stock, load_machine, with_grip
    from hnc_cam.plan.setups import mirror_region
    mach = with_grip(load_machine(None), 20)
    tp = run_file(str(bush_dir / "O0001.nc"), mach, start="reference")
    m = simulate(tp, Stock.parse("42/20x80+1"), mach)
    part = separated_part(m, profile_polygon(bush_setups.first.plan.profile))
    assert part is not None  # parted off
    mine = mirror_region(part, 30.0)
    st2 = bush_setups.stock2
    assert abs(mine.area - st2.area) < 1e-3
    assert mine.hausdorff_distance(st2) < 1e-3
    # its ends: the chucked end (the right face) at Z-30, the face stock 0.5 beyond Z0
    assert st2.bounds[0] == pytest.approx(-30.0, abs=1e-3)
    assert st2.bounds[2] == pytest.approx(0.5, abs=1e-3)
    # the setup-1 part's bore chamfer is not there yet: the bore at the new face is 24
    assert _radius_at(st2, 0.2, outer=False) < 12.01


def test_setup2_program_header_face_and_chamfers(bush_dir, bush_setups):
    text = (bush_dir / "O0002.nc").read_text()
    assert text.startswith("%0002")
    assert "(GRIP 16)" in text
    assert "held in soft jaws on diameter 40 over 15 mm" in text
    # faced to length: the G81 ends on Z0 (the new face)
    assert re.search(r"G81 X[\d.]+ Z0 F", text)
    m2 = bush_setups.machined2
    g = m2.material
    # the part's length: its faces at Z0 and Z-30
    assert g.bounds[2] == pytest.approx(0.0, abs=0.01)
    assert g.bounds[0] == pytest.approx(-30.0, abs=0.01)
    # the bore chamfer's end points: diameter 26 at the face, 24 at Z-1 (1 mm x 45 deg)
    assert 2 * _radius_at(g, -0.001, outer=False) == pytest.approx(26.0, abs=0.02)
    assert 2 * _radius_at(g, -0.5, outer=False) == pytest.approx(25.0, abs=0.02)
    assert 2 * _radius_at(g, -1.2, outer=False) == pytest.approx(24.0, abs=0.02)
    # and the outside's: 38 at the face, 40 from Z-1
    assert 2 * _radius_at(g, -0.001) == pytest.approx(38.0, abs=0.02)
    assert 2 * _radius_at(g, -0.5) == pytest.approx(39.0, abs=0.02)
    # the jaws on diameter 40, their front face 16 mm from the chucked end (Z-30)
    jb = m2.jaws.bounds
    assert jb[2] == pytest.approx(-14.0) and jb[1] == pytest.approx(20.0, abs=1e-3)
    assert not m2.issues


def test_verify_two_programs_passes(bush_dir, capsys):
    rc, out, _err = _run(capsys, ["verify", bush_dir / "O0001.nc", bush_dir / "O0002.nc",
                                  "--model", BUSH])
    assert rc == 0, out
    assert "PASS" in out


def test_verify_fails_a_setup2_program_cut_into_the_jaws(bush_dir, tmp_path, capsys):
    text = (bush_dir / "O0002.nc").read_text().splitlines()
    i = next(k for k, ln in enumerate(text) if re.search(r"\bM30\b", ln))
    # a rapid down the outside to Z-20: the jaws stand from Z-14 on diameter 40
    text[i:i] = ["G00 X50", "G00 Z-20"]
    bad = tmp_path / "O0002.nc"
    bad.write_text("\n".join(text) + "\n")
    rc, out, _err = _run(capsys, ["verify", bush_dir / "O0001.nc", bad, "--model", BUSH])
    assert rc == 1
    assert re.search(rf"line {i + 2}\b.*chuck jaw|chuck jaw.*line {i + 2}\b", out), out


def test_verify_fails_a_setup2_program_that_leaves_the_bore_chamfer(bush_dir, tmp_path, capsys):
    """The bore's contour edited to run straight in at the bore's diameter (the chamfer's
    block from diameter 26 at the face to 24 at Z-1 made a plain plunge): the boring bar still
    runs, the chamfer is left, and verify names it and the line."""
    lines = (bush_dir / "O0002.nc").read_text().splitlines()
    a = next(k for k, ln in enumerate(lines) if "FINISH BORE" in ln)
    k = next(k for k in range(a, len(lines)) if re.search(r"G01 X[\d.]+ Z-1\b", lines[k]))
    x = re.search(r"X([\d.]+)", lines[k]).group(1)
    assert re.search(r"G00 X[\d.]+$", lines[k - 1])
    lines[k - 1] = re.sub(r"X[\d.]+$", f"X{x}", lines[k - 1])
    bad = tmp_path / "O0002.nc"
    bad.write_text("\n".join(lines) + "\n")
    rc, out, _err = _run(capsys, ["verify", bush_dir / "O0001.nc", bad, "--model", BUSH])
    assert rc == 1
    assert "FAIL" in out
    # the leftover named at the bore's mouth (diameter 24-26 at Z0..Z-1), with a line
    m = re.search(r"max undercut\s+([\d.]+) mm at X([\d.]+) Z(-?[\d.]+), line \d+", out)
    assert m, out
    assert float(m.group(1)) > 0.3
    assert 24.0 <= float(m.group(2)) <= 26.0 and -1.0 <= float(m.group(3)) <= 0.0


def test_grip_longer_than_the_finished_diameter_is_refused(tmp_path, capsys):
    rc, _o, err = _run(capsys, ["generate", BUSH, "--grip", "20", "--setups", "2",
                                "--grip2", "28", "-o", f"{tmp_path}/out/"])
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and lines[0].startswith("error:")
    assert "grip 28 mm is longer than the finished diameter 40 mm" in lines[0]
    assert "(26.7 mm long" in lines[0]
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_grip_diameter_the_chuck_cannot_hold_is_refused(tmp_path, capsys):
    src = (ROOT / "hnc_cam" / "data" / "machine.toml").read_text()
    mfile = tmp_path / "small_chuck.toml"
    mfile.write_text(src.replace("clamp_max = 250.0", "clamp_max = 28.0"))
    rc, _o, err = _run(capsys, ["generate", PIN, "--machine", mfile, "--grip", "20",
                                "--setups", "2", "--grip2", "15", "-o", f"{tmp_path}/out/"])
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and lines[0].startswith("error:")
    assert "grip diameter 30 mm is outside the chuck's clamping range 2-28 mm" in lines[0]
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_setups_2_needs_a_folder(tmp_path, capsys):
    out = tmp_path / "o.nc"
    rc, _o, err = _run(capsys, ["generate", BUSH, "--grip", "20", "--setups", "2",
                                "-o", out])
    assert rc == 2 and "-o DIR/" in err and not out.exists()


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_pin_with_a_left_journal_in_two_setups(tmp_path, capsys, comp):
    d = tmp_path / "pin"
    rc, _o, err = _run(capsys, ["generate", PIN, "--grip", "20", "--setups", "2", "--grip2",
                                "15", "--comp", comp, "-o", f"{d}/"])
    assert rc == 0, err
    p2 = (d / "O0002.nc").read_text()
    assert "held in soft jaws on diameter 30 over 15 mm" in p2
    # setup 1 turns diameter 30 on to the part-off: no journal, no shoulder
    p1 = (d / "O0001.nc").read_text()
    assert "X20 " not in p1 and "X20\n" not in p1
    if comp == "control":  # the program carries the part's contour: the journal and shoulder
        assert re.search(r"G01 (?:G42 )?X20 Z-12\b|X20 Z-12\b", p2) or "Z-12" in p2
    rc, out, _e = _run(capsys, ["verify", d / "O0001.nc", d / "O0002.nc", "--model", PIN])
    assert rc == 0, out


def test_pin_journal_positions_after_setup2():
    from hnc_cam.plan.setups import generate_setups
    s = generate_setups(PIN, grip=20, grip2=15)
    g = s.machined2.material
    assert 2 * _radius_at(g, -6.0) == pytest.approx(20.0, abs=0.02)  # the journal
    assert 2 * _radius_at(g, -20.0) == pytest.approx(30.0, abs=0.02)  # the body
    assert 2 * _radius_at(g, -0.001) == pytest.approx(18.0, abs=0.02)  # its chamfer
    # the shoulder at Z-12 (1 mm chamfer up to 30 at Z-13)
    assert 2 * _radius_at(g, -12.05) == pytest.approx(28.1, abs=0.05)
    assert g.bounds[2] == pytest.approx(0.0, abs=0.01)
    assert g.bounds[0] == pytest.approx(-40.0, abs=0.01)
    assert s.report.passed


@pytest.mark.parametrize("dialect,names", [
    ("fanuc0it", ("O0001.nc", "O0002.nc")), ("haas", ("O0001.nc", "O0002.nc")),
    ("siemens802", ("BUSH_CHAMFERS.MPF", "BUSH_CHAMFERS_2.MPF"))])
def test_bush_two_setups_in_other_dialects(tmp_path, capsys, dialect, names):
    d = tmp_path / dialect
    rc, _o, err = _run(capsys, ["generate", BUSH, "--grip", "20", "--setups", "2", "--grip2",
                                "15", "--dialect", dialect, "-o", f"{d}/"])
    assert rc == 0, err
    rc, out, _e = _run(capsys, ["verify", d / names[0], d / names[1], "--model", BUSH,
                                "--dialect", dialect])
    assert rc == 0, out


def test_jaws_reaching_the_zone_are_refused(tmp_path, capsys):
    """A grip of 24 mm on the bush's 40 mm diameter (26.7 mm of it outside the zone) puts
    the jaws' front face at Z-5, within the clearance (2 mm + the largest nose + 0.3) of the
    zone setup 2 machines from Z-2.3."""
    rc, _o, err = _run(capsys, ["generate", BUSH, "--grip", "20", "--setups", "2",
                                "--grip2", "24", "-o", f"{tmp_path}/out/"])
    lines = err.strip().splitlines()
    assert rc == 2 and len(lines) == 1 and lines[0].startswith("error:")
    assert "reach Z-5, less than 3.1 mm from the zone it machines (from Z-2.3)" in lines[0]
    assert "--grip2 of at most 23.6" in lines[0]
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


def test_a_part_without_a_second_setup_feature_is_refused_with_setups_2(tmp_path, capsys):
    rc, _o, err = _run(capsys, ["generate", FRESH / "pin_partoff.py", "--grip", "20",
                                "--setups", "2", "-o", f"{tmp_path}/out/"])
    assert rc == 2 and "nothing on the part needs a second setup" in err


def test_counterbore_from_the_left_end_in_two_setups(tmp_path, capsys):
    """A second bore from the left end: a 28 mm counterbore 8 mm deep on a 20 mm bore. One
    setup refuses it naming --setups 2; two setups bore it from the turned-around part."""
    part = FRESH / "bush_counterbore.py"
    rc, _o, err = _run(capsys, ["generate", part, "--grip", "20", "-o", tmp_path / "o.nc"])
    assert rc == 2 and "--setups 2" in err and not (tmp_path / "o.nc").exists()
    from hnc_cam.plan.setups import generate_setups
    s = generate_setups(part, grip=20, grip2=12)
    assert s.zone.z == pytest.approx(-20.7)  # the counterbore's floor at Z-22, on 1.3 mm
    g = s.machined2.material
    assert 2 * _radius_at(g, -4.0, outer=False) == pytest.approx(28.0, abs=0.02)
    assert 2 * _radius_at(g, -9.0, outer=False) == pytest.approx(20.0, abs=0.02)
    # the floor at Z-8: the material's inner radius steps from 14 to 10 there (the nose's
    # 0.4 mm fillet in the floor's inner corner)
    assert 2 * _radius_at(g, -7.5, outer=False) == pytest.approx(28.0, abs=0.02)
    assert 2 * _radius_at(g, -7.95, outer=False) == pytest.approx(27.59, abs=0.02)
    assert 2 * _radius_at(g, -8.05, outer=False) == pytest.approx(20.0, abs=0.05)
    # setup 1 bored 20 mm through (the counterbore bridged): its stock for setup 2
    assert 2 * _radius_at(s.stock2, -4.0, outer=False) == pytest.approx(20.0, abs=0.02)
    assert s.report.passed, s.report.summary()
    d = tmp_path / "cb"
    rc, _o, err = _run(capsys, ["generate", part, "--grip", "20", "--setups", "2", "--grip2",
                                "12", "-o", f"{d}/"])
    assert rc == 0, err
    js = tmp_path / "v.json"
    rc, out, _e = _run(capsys, ["verify", d / "O0001.nc", d / "O0002.nc", "--model", part,
                                "--json", js])
    assert rc == 0, out
    import json
    data = json.loads(js.read_text())
    assert data["pass"] is True and len(data["setups"]) == 2
    assert all(not st["collisions"] for st in data["setups"])


def test_bush_from_solid_bar_in_two_setups():
    """The bush from a 42 mm bar: setup 1 drills and bores it through (the chuck-side chamfer
    bridged), setup 2 makes the chamfer from the part turned around."""
    from hnc_cam.plan.setups import generate_setups
    s = generate_setups(BUSH, "42x80+1", grip=20, grip2=15)
    assert "drill" in [op.kind for op in s.first.plan.operations]
    assert s.report1.passed and s.report.passed, s.report.summary()
    g = s.machined2.material
    assert 2 * _radius_at(g, -0.5, outer=False) == pytest.approx(25.0, abs=0.02)
    assert 2 * _radius_at(g, -0.5) == pytest.approx(39.0, abs=0.02)
