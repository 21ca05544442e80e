"""Axial (face) grooving blades: the tool library's ``kind = "groove_face"`` entries (a grooving
insert's width, the range of face-groove diameters the blade's curvature cuts) and the
simulator's outline of the blade (pointing -Z, the controlled point the middle of its end)."""
from __future__ import annotations

from pathlib import Path

import pytest

from hnc_cam.errors import ToolError
from hnc_cam.tooling import load_machine, load_tools

ROOT = Path(__file__).resolve().parents[1]
#: the bundled library without its own face grooving blade (T16), which these tests replace
LIB = "[[tool]]".join(b for b in (ROOT / "hnc_cam" / "data" / "tools.toml").read_text()
                      .split("[[tool]]") if 'kind = "groove_face"' not in b)

BLADE = '''
[[tool]]
number = 16
name = "Face grooving 3 mm"
insert = "GROOVE3.0"
radius = 0.2
kind = "groove_face"
min_diameter = 24.0
max_diameter = 40.0
feed_finish = 0.04
vc_finish = 90.0
'''


def _lib(tmp_path: Path, extra: str = BLADE) -> Path:
    f = tmp_path / "tools.toml"
    f.write_text(LIB + extra)
    return f


def test_a_face_grooving_blade_in_the_library(tmp_path):
    lib = load_tools(_lib(tmp_path))
    t = lib.by_number(16)
    assert (t.kind, t.uses, t.tip) == ("groove_face", ("groove_face",), 7)
    assert (t.insert.width, t.nose_radius) == (3.0, 0.2)
    assert (t.min_diameter, t.max_diameter) == (24.0, 40.0)
    reg = lib.registers()[16]
    assert reg.tip == 7 and reg.insert.kind == "groove"


@pytest.mark.parametrize("entry,needle", [
    (BLADE.replace("min_diameter = 24.0", "min_diameter = 40.0"),
     r"tools.toml:\d+: tool T16: min_diameter 40 must be under max_diameter 40"),
    (BLADE.replace("max_diameter = 40.0", "max_diameter = 28.0"),
     r"tools.toml:\d+: tool T16: the range 24-28 is narrower than the blade \(3 mm wide\)"),
    (BLADE.replace("max_diameter = 40.0\n", ""),
     r"tools.toml:\d+: tool T16: a groove_face blade needs max_diameter"),
    (BLADE.replace('"GROOVE3.0"', '"CNMG120408"'),
     r"tools.toml:\d+: tool T16: a groove_face blade needs a grooving insert"),
    (BLADE.replace('kind = "groove_face"', 'kind = "groove"'),
     r"tools.toml:\d+: tool T16: min_diameter is an axial grooving blade's key"),
    (BLADE.replace("max_diameter = 40.0", "max_diameter = -1.0"),
     r"tools.toml:\d+: .*max_diameter"),
])
def test_face_grooving_entries_that_are_wrong_name_file_and_line(tmp_path, entry, needle):
    with pytest.raises(ToolError, match=needle):
        load_tools(_lib(tmp_path, entry))


def test_the_simulator_draws_the_blade_pointing_at_the_chuck(tmp_path):
    from hnc_cam.sim.tool import tool_shape
    lib = load_tools(_lib(tmp_path))
    s = tool_shape(load_machine(None, lib).register(16))
    z, x = s.outline[:, 0], s.outline[:, 1]
    # the end at the controlled point (Z0), 3 mm across X centred on it, the blade along +Z
    assert z.min() == pytest.approx(0.0, abs=1e-9) and z.max() > 5.0
    assert x.min() == pytest.approx(-1.5) and x.max() == pytest.approx(1.5)
    assert s.centre == pytest.approx((0.2, 0.0))
    # the back (its top, toward +Z) does not cut
    assert len(s.non_cutting) == 1 and all(p[0] > 5.0 for p in s.non_cutting[0])


def test_a_plunge_along_minus_z_cuts_a_ring_in_the_face(tmp_path):
    from shapely.geometry import Point

    from hnc_cam.nc.interp import run_file
    from hnc_cam.sim import simulate
    from hnc_cam.tooling import Stock
    lib = load_tools(_lib(tmp_path))
    mach = load_machine(None, lib)
    prog = tmp_path / "face_groove.nc"
    prog.write_text("%0001\nN1 G21 G90 G36 G95\nN2 T1616\nN3 M03 S600\nN4 G00 X32 Z2\n"
                    "N5 G01 Z-4 F0.04\nN6 G04 P0.5\nN7 G00 Z2\nN8 G00 X100 Z50\nN9 M30\n")
    tp = run_file(str(prog), mach, start="reference")
    m = simulate(tp, Stock.parse("50x40"), mach)
    assert m.issues == []  # the blade's end and corners cut; its back never touches
    mat = m.material
    # a ring from radius 14.5 to 17.5, 4 mm deep: gone in the middle and near its walls
    for r in (14.6, 16.0, 17.4):
        assert not mat.contains(Point(-3.0, r)), r
    # the walls and the bottom stay
    for z, r in ((-3.0, 14.4), (-3.0, 17.6), (-4.1, 16.0), (-1.0, 10.0), (-1.0, 20.0)):
        assert mat.contains(Point(z, r)), (z, r)
    # the nose radius (0.2) rounds the bottom's corners
    assert mat.contains(Point(-3.97, 14.53)) and mat.contains(Point(-3.97, 17.47))
    assert not mat.contains(Point(-3.97, 14.75)) and not mat.contains(Point(-3.97, 17.25))


def test_a_rapid_of_the_blade_into_the_face_is_a_collision_on_its_line(tmp_path):
    # after the groove, the blade rapids to X40 and into the face there (N8)
    from hnc_cam.nc.interp import run_file
    from hnc_cam.sim import simulate
    from hnc_cam.tooling import Stock
    lib = load_tools(_lib(tmp_path))
    mach = load_machine(None, lib)
    prog = tmp_path / "face_groove.nc"
    prog.write_text("%0001\nN1 G21 G90 G36 G95\nN2 T1616\nN3 M03 S600\nN4 G00 X32 Z2\n"
                    "N5 G01 Z-4 F0.04\nN6 G00 Z2\nN7 G00 X40\nN8 G00 Z-2\nN9 G00 Z2\n"
                    "N10 G00 X100 Z50\nN11 M30\n")
    m = simulate(run_file(str(prog), mach, start="reference"), Stock.parse("50x40"), mach)
    # the rapid into the face beside the groove is a collision, on its line
    assert any("collision" in i.message and i.line == 9 for i in m.issues), m.issues
