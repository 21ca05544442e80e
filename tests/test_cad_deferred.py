"""The part loader calls a family's ``part()`` with ``revolve()`` deferred: a part that returns
``revolve(outline)`` as it is is profiled from the outline and no solid is made (nor the CAD
kernel imported); a part that uses the solid (a boolean, a move in place, a location, a type
check, a kernel function) gets it made as ``revolve()`` makes it, and its profile is the
solid's section, as without deferring; a part that fails is called again as written and fails
with the same line."""
from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from hnc_cam.cad import load_part
from hnc_cam.cad import sketch
from hnc_cam.cad.extract import extract
from hnc_cam.cad.loader import family_parameters, load_module
from hnc_cam.errors import PartError

from test_cad_revolved import FILES, _same_profile, _variants

pytestmark = pytest.mark.cad

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture()
def made(monkeypatch):
    """The solids revolve() makes, counted."""
    calls: list[int] = []
    real = sketch._revolve

    def counting(segs):
        calls.append(1)
        return real(segs)
    monkeypatch.setattr(sketch, "_revolve", counting)
    return calls


@pytest.mark.parametrize("path", FILES, ids=[f"{f.parent.name}/{f.stem}" for f in FILES])
def test_loaded_profile_is_the_solids_section(path, made):
    """Every bundled part and test family, several parameter sets: the profile load_part
    gives is the section of the solid part() makes when nothing is deferred; a part that
    returns revolve(outline) makes no solid on the way."""
    mod = load_module(path)
    sets = _variants(mod)
    assert sets
    for s in sets:
        full = {**family_parameters(mod), **s}
        del made[:]
        got = load_part(path, {k: str(v) for k, v in s.items()}).profile
        src = path.read_text()
        if "return revolve(" in src and "cadquery" not in src:
            assert not made, f"{path.name} {s}: a solid was made"
        want = extract(mod.part(**full))
        want.params = got.params
        assert _same_profile(got, want), (path.name, s, got.outside, want.outside)


SKETCH = '''
from hnc_cam.cad.sketch import Outline, revolve


def outline(length=40.0, d=20.0):
    s = Outline((0.0, 0.0))
    s.line_to(d / 2, 0.0, chamfer=1.0)
    s.line_to(d / 2, -length)
    s.line_to(0.0, -length)
    return s.segments()


def groove(length=40.0, d=20.0):
    s = Outline((d / 2 - 2, -10.0))
    s.line_to(d, -10.0).line_to(d, -14.0).line_to(d / 2 - 2, -14.0)
    return s.close().segments()
'''

#: part() bodies that use the solid revolve() makes: (name, body, whether the profile differs
#: from the outline's)
USES = [
    ("boolean", "return revolve(outline(length, d)) - revolve(groove(length, d))", True),
    ("moved in place", "from build123d import Location\n"
                       "s = revolve(outline(length, d))\n"
                       "s.move(Location((0, 0, 0), (1, 0, 0), 180))\n"
                       "return s", True),
    ("located", "from build123d import Pos\nreturn Pos(0, 0, 3) * revolve(outline(length, d))",
     False),
    ("type check", "from build123d import Solid\ns = revolve(outline(length, d))\n"
                   "return s if isinstance(s, Solid) else revolve(groove(length, d))", False),
    ("kernel function", "from build123d import Solid\n"
                        "from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy\n"
                        "s = revolve(outline(length, d))\n"
                        "return Solid(BRepBuilderAPI_Copy(s.wrapped).Shape())", False),
    ("exact type", "from build123d import Solid\ns = revolve(outline(length, d))\n"
                   "assert type(s) is Solid, type(s)\nreturn s", False),
    ("read first", "s = revolve(outline(length, d))\nassert s.volume > 0\nreturn s", False),
]


def _part_file(tmp_path: Path, name: str, body: str) -> Path:
    f = tmp_path / f"{name.replace(' ', '_')}.py"
    f.write_text(SKETCH + "\n\ndef part(length=40.0, d=20.0):\n"
                 + textwrap.indent(body, "    ") + "\n")
    return f


@pytest.mark.parametrize("name,body,differs", USES, ids=[u[0] for u in USES])
def test_a_part_that_uses_its_solid_is_profiled_from_it(tmp_path, name, body, differs):
    """A part written the way users write them that uses the solid: its profile is the one
    of the solid it returns without deferring; where that solid is not its outline revolved
    (a groove cut, turned end for end) the profile says so, not the outline."""
    f = _part_file(tmp_path, name, body)
    got = load_part(f, {"length": "42"}).profile
    mod = load_module(f)
    want = extract(mod.part(length=42.0))
    want.params = got.params
    assert _same_profile(got, want), (name, got.outside, want.outside)
    plain = load_part(_part_file(tmp_path, "plain", "return revolve(outline(length, d))"),
                      {"length": "42"}).profile
    plain.params = got.params
    assert _same_profile(got, plain) is not differs


def test_a_failing_part_fails_as_written(tmp_path, made):
    """A part that raises after revolve() is called again without deferring: the same one
    line as before, naming the part and its parameters."""
    f = _part_file(tmp_path, "fails", "s = revolve(outline(length, d))\n"
                                      "raise ValueError(f'no part at length {length:g}')")
    with pytest.raises(PartError) as e:
        load_part(f, {"length": "41"})
    assert str(e.value) == (f"{f}: part(length=41, d=20) raised ValueError: "
                            f"no part at length 41")
    assert len(made) == 1  # the second call, as written, made its solid


def test_refusals_are_not_called_twice(tmp_path):
    """A part refusing its parameters (PartError) is not called again."""
    f = tmp_path / "refuse.py"
    f.write_text(SKETCH + "\nCALLS = []\n\n\ndef part(length=40.0, d=20.0):\n"
                 "    CALLS.append(length)\n"
                 "    from hnc_cam.cad.sketch import require\n"
                 "    require(length < 100, f'length={length:g} is too long')\n"
                 "    return revolve(outline(length, d))\n")
    with pytest.raises(PartError, match="impossible part: length=120 is too long"):
        load_part(f, {"length": "120"})
    assert load_module(f).CALLS == [120.0]


def test_revolve_is_deferred_only_in_the_loader(made):
    segs = load_module(ROOT / "parts" / "stepped_shaft.py").sketch()
    s = sketch.revolve(segs)
    assert type(s) is not sketch.Revolved and len(made) == 1
    with sketch.deferred():
        d = sketch.revolve(segs)
    assert type(d) is sketch.Revolved and len(made) == 1
    assert sketch.revolved_outline(d) == segs
    assert abs(d.volume - s.volume) < 1e-6 and len(made) == 2  # made by its first use
    assert sketch.revolved_outline(d) == segs  # still the shape made


def test_a_revolve_family_needs_no_cad_kernel():
    """Loading a family part that returns revolve(outline) imports neither OpenCascade nor
    build123d (a fresh process)."""
    code = ("import sys; from hnc_cam.cad import load_part; "
            "p = load_part(sys.argv[1], {'length': '96'}).profile; "
            "print(len(p.outside), 'OCP' in sys.modules, 'build123d' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code, str(ROOT / "parts" / "stepped_shaft.py")],
                         capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert out.returncode == 0, out.stderr
    n, ocp, b3d = out.stdout.split()
    assert int(n) > 5 and ocp == "False" and b3d == "False"
