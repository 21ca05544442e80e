"""Face grooves planned: an axial ring groove in the right face is bridged in the face and
cut with the library's face grooving blade (plunges along -Z, a dwell at the floor, a
finishing pass where the groove is wider than the blade), in every dialect and both
compensation modes, and verified; a groove no blade cuts is refused with its numbers."""
from __future__ import annotations

from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.plan.api import generate

ROOT = Path(__file__).resolve().parents[1]
FRESH = ROOT / "tests" / "data" / "turning_parts"

#: a part as a user writes it: a closed polyline revolved about Z
PART = '''
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "{stock}"


def part():
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*{pts!r}, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
'''


def _part(tmp_path: Path, name: str, pts, stock: str = "62x50+1") -> Path:
    f = tmp_path / f"{name}.py"
    f.write_text(PART.format(pts=[tuple(p) for p in pts], stock=stock))
    return f


def _disc(r_in: float, r_out: float, depth: float):
    """A 60 mm disc 20 mm long with a ring groove between radii r_in and r_out."""
    return [(0, 0), (r_in, 0), (r_in, -depth), (r_out, -depth), (r_out, 0), (29, 0), (30, -1),
            (30, -20), (0, -20)]


def _blade_moves(prog):
    return [m for m in prog.toolpath.moves if m.tool == 16]


def _plunges(prog):
    """(X radius, floor Z) of each feed move of the blade along -Z."""
    return [(m.start[0], m.end[1]) for m in _blade_moves(prog)
            if m.kind == "line" and abs(m.end[0] - m.start[0]) < 1e-9 and m.end[1] < m.start[1]]


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas", "siemens802"])
def test_the_flange_groove_is_plunged_finished_and_verified(dialect):
    # 4 mm wide (diameters 36 to 44), 3 mm deep; the 3 mm blade T16
    for comp in ("cam", "control"):
        prog = generate(FRESH / "face_groove.py", comp=comp, dialect=dialect)
        assert prog.report.passed, (dialect, comp, prog.report.summary())
        op = next(o for o in prog.plan.operations if o.name == "groove_face")
        assert op.tool.number == 16 and op.role == "groove_face" and op.nose_comp == "none"
        assert op.spindle == "rpm" and op.speed == 651.0  # 90 m/min at diameter 44
        # two plunges leaving 0.1 mm on the walls and floor (the blade's middle at 20.4 and
        # 19.6: its sides at 21.9 and 18.1), then down the inner wall to the floor Z-3,
        # along it to the outer wall (the blade's middle at 20.5: its side at 22), back up
        assert _plunges(prog) == [(pytest.approx(20.4), pytest.approx(-2.9)),
                                  (pytest.approx(19.6), pytest.approx(-2.9)),
                                  (pytest.approx(19.5), pytest.approx(-3.0))]
        feeds = [m for m in _blade_moves(prog) if m.kind == "line"]
        floor, up = feeds[-2], feeds[-1]
        assert floor.start == pytest.approx((19.5, -3.0)) and floor.end == pytest.approx((20.5, -3.0))
        assert up.end == pytest.approx((20.5, 0.6))
        # a dwell at the floor after each plunge and at the end of the floor: 2 rev at 651 rpm
        kinds = [m.kind for m in _blade_moves(prog)]
        dwells = [m for m in _blade_moves(prog) if m.kind == "dwell"]
        assert len(dwells) == 3 and all(d.duration == pytest.approx(0.18) for d in dwells)
        assert [dwells[0].end[1], dwells[1].end[1], dwells[2].end] == \
            [pytest.approx(-2.9), pytest.approx(-2.9), pytest.approx((20.5, -3.0))]
        assert kinds.count("line") == 5
        # between plunges the blade is out of the groove, in front of the face
        rapids = [m for m in _blade_moves(prog) if m.kind == "rapid"]
        assert all(m.end[1] > 0 for m in rapids if m.end[0] < 23)
        # nothing is left in the groove but the blade's corner radius (0.2) in its floor's
        # corners
        near = [u for u in prog.report.unreachable if 17 < u.x < 23]
        assert len(near) == 2 and all(u.size_mm < 0.2 * (2 ** 0.5 - 1) + 0.01 for u in near)


def test_a_groove_of_the_blades_width_is_one_plunge_without_finishing(tmp_path):
    f = _part(tmp_path, "narrow", _disc(18, 21, 2.5))
    prog = generate(f)
    assert prog.report.passed, prog.report.summary()
    assert _plunges(prog) == [(pytest.approx(19.5), pytest.approx(-2.5))]
    assert "G01 X" not in prog.text.split("FACE GROOVE")[1]


def test_a_wide_groove_steps_across_by_at_most_the_blade_less_its_corners(tmp_path):
    # 10 mm wide (diameters 30 to 50), 4 mm deep: the plunges from the outer wall inward
    f = _part(tmp_path, "wide", _disc(15, 25, 4))
    for comp in ("cam", "control"):
        prog = generate(f, comp=comp)
        assert prog.report.passed, prog.report.summary()
        pl = _plunges(prog)
        xs = [x for x, _ in pl[:-1]]
        assert xs[0] == pytest.approx(25 - 1.5 - 0.1) and xs[-1] == pytest.approx(15 + 1.5 + 0.1)
        steps = [a - b for a, b in zip(xs, xs[1:])]
        assert len(xs) == 4 and all(0 < s <= 3 - 2 * 0.2 - 0.05 + 1e-9 for s in steps)
        assert all(z == pytest.approx(-3.9) for _, z in pl[:-1])
        assert pl[-1] == (pytest.approx(16.5), pytest.approx(-4.0))  # the finishing pass
        op = next(o for o in prog.plan.operations if o.name == "groove_face")
        assert op.speed == 573.0  # 90 m/min at diameter 50


def test_generate_cli_writes_the_face_groove_and_run_reads_it(tmp_path):
    out = tmp_path / "fg.nc"
    assert main(["generate", str(FRESH / "face_groove.py"), "-o", str(out)]) == 0
    text = out.read_text()
    assert "T1616" in text and "G04 P0.18" in text
    assert main(["verify", str(out), "--model", str(FRESH / "face_groove.py")]) == 0


def _refused(tmp_path, capsys, part: Path, *extra: str) -> str:
    out = tmp_path / "o.nc"
    rc = main(["generate", str(part), "-o", str(out), *extra])
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists(), err
    assert len(err.strip().splitlines()) == 1 and err.startswith("error: ")
    return err


def test_a_groove_narrower_than_any_blade_is_refused_with_its_numbers(tmp_path, capsys):
    f = _part(tmp_path, "slot", _disc(19, 21, 3))
    err = _refused(tmp_path, capsys, f)
    assert ("face groove between diameters 38 and 42 (2 mm wide, 3 mm deep, floor at Z-3) is "
            "unreachable: it needs a face grooving blade (kind groove_face) at most 2 mm wide "
            "whose diameter range holds 38-42 (face grooving blades in the library: T16 3 mm "
            "for diameters 20-80)") in err


def test_a_groove_outside_the_blades_diameter_range_is_refused(tmp_path, capsys):
    # diameters 16 to 24: the blade's curvature cuts from diameter 20 outward
    f = _part(tmp_path, "small", _disc(8, 12, 2))
    err = _refused(tmp_path, capsys, f)
    assert "face groove between diameters 16 and 24 (4 mm wide, 2 mm deep" in err
    assert "whose diameter range holds 16-24" in err


def test_without_a_face_grooving_blade_the_groove_is_refused(tmp_path, capsys):
    lib = tmp_path / "tools.toml"
    text = (ROOT / "hnc_cam" / "data" / "tools.toml").read_text()
    lib.write_text("[[tool]]".join(b for b in text.split("[[tool]]")
                                   if 'kind = "groove_face"' not in b))
    err = _refused(tmp_path, capsys, FRESH / "face_groove.py", "--tools", str(lib))
    assert "face grooving blades in the library: none" in err


def test_verify_finds_the_groove_left_in_a_program_without_the_blade(tmp_path):
    # the generated program with the blade's operation cut out: verify lists the groove's
    # 2 mm ring as leftover (the groove itself), where the full program leaves only corners
    out = tmp_path / "fg.nc"
    assert main(["generate", str(FRESH / "face_groove.py"), "-o", str(out), "--no-verify"]) == 0
    lines = out.read_text().splitlines()
    i = next(k for k, l in enumerate(lines) if "FACE GROOVE" in l)
    j = next(k for k in range(i, len(lines)) if lines[k].endswith("G00 Z2"))
    cut = tmp_path / "cut.nc"
    cut.write_text("\n".join(lines[:i + 1] + lines[j:]) + "\n")
    import json
    for prog, worst in ((out, 0.1), (cut, 1.9)):
        js = tmp_path / "v.json"
        assert main(["verify", str(prog), "--model", str(FRESH / "face_groove.py"),
                     "--json", str(js)]) == 0
        near = [u for u in json.loads(js.read_text())["unreachable"] if 34 < u["x"] < 46]
        assert (max(u["size_mm"] for u in near) > worst) == (prog == cut), (prog, near)


@pytest.mark.parametrize("name,pts,stock,walls", [
    # no face stock: the finisher finishes the face across the bridged groove (G72 roughing)
    ("unfaced", _disc(18, 22, 3), "62x50", (18, 22)),
    # a ring drilled from solid bar, the groove between the bore and the outside
    ("ring", [(8, 0), (18, 0), (18, -3), (22, -3), (22, 0), (29, 0), (30, -1), (30, -20),
              (8, -20)], "62x50+1", (18, 22)),
    # a tube's ring
    ("tube", [(10, 0), (18, 0), (18, -3), (22, -3), (22, 0), (29, 0), (30, -1), (30, -20),
              (10, -20)], "62/16x30+1", (18, 22)),
    # a 150 mm disc, the groove 6 mm wide between diameters 40 and 52
    ("disc", [(0, 0), (20, 0), (20, -4), (26, -4), (26, 0), (74, 0), (75, -1), (75, -15),
              (0, -15)], "152x30+1.5", (20, 26)),
])
def test_face_grooves_in_other_parts_are_cut_to_their_corners(tmp_path, name, pts, stock, walls):
    f = _part(tmp_path, name, pts, stock)
    for comp in ("cam", "control"):
        prog = generate(f, comp=comp)
        assert prog.report.passed, (name, comp, prog.report.summary())
        pl = _plunges(prog)
        # every plunge inside the walls, the last (the finishing pass) on the floor at the
        # inner wall
        assert all(walls[0] + 1.5 - 1e-9 <= x <= walls[1] - 1.5 + 1e-9 for x, _ in pl)
        assert pl[-1][0] == pytest.approx(walls[0] + 1.5)
        near = [u for u in prog.report.unreachable if walls[0] - 1 < u.x < walls[1] + 1]
        assert len(near) == 2 and all(u.size_mm < 0.1 for u in near), near
