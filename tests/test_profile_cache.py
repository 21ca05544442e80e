"""The profile cache (HNC_CAM_PROFILE_CACHE=DIR): a repeated generate of an unchanged STEP
file does not import the CAD kernel and writes the same program; any change of the file, its
place or the profile options is a miss, never a stale profile; a broken entry or an
unwritable folder only means no caching."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from hnc_cam.cad.loader import CACHE_ENV, ProfileCache, load_part

REPO = Path(__file__).resolve().parents[1]
SHAFT = REPO / "tests" / "data" / "stepped_shaft.step"
KNOB = REPO / "tests" / "data" / "spline_knob.step"

pytestmark = pytest.mark.cad

PROBE = """
import sys
from hnc_cam.cli import main
rc = main(sys.argv[1:])
heavy = sorted(m for m in sys.modules if m.split('.')[0] in ('OCP', 'build123d', 'cadquery'))
print('RC', rc, 'KERNEL', len(heavy), file=sys.stderr)
"""


def _generate(step: Path, out: Path, cache: Path | None) -> tuple[int, int, str]:
    env = dict(os.environ)
    env.pop(CACHE_ENV, None)
    if cache is not None:
        env[CACHE_ENV] = str(cache)
    p = subprocess.run([sys.executable, "-c", PROBE, "generate", str(step), "--stock",
                        "45x120+2", "-o", str(out)], capture_output=True, text=True, env=env,
                       timeout=300)
    last = [ln for ln in p.stderr.splitlines() if ln.startswith("RC ")][-1].split()
    return int(last[1]), int(last[3]), p.stderr


def test_repeated_generate_skips_the_cad_kernel(tmp_path):
    cache = tmp_path / "cache"
    rc1, kernel1, err1 = _generate(SHAFT, tmp_path / "a.nc", cache)
    assert rc1 == 0 and kernel1 > 0, err1
    assert len(list(cache.glob("*.profile"))) == 1
    rc2, kernel2, err2 = _generate(SHAFT, tmp_path / "b.nc", cache)
    assert rc2 == 0 and kernel2 == 0, err2  # OCP/build123d/cadquery never imported
    assert (tmp_path / "a.nc").read_bytes() == (tmp_path / "b.nc").read_bytes()
    rc3, kernel3, _ = _generate(SHAFT, tmp_path / "c.nc", None)  # and as without a cache
    assert rc3 == 0 and kernel3 > 0
    assert (tmp_path / "c.nc").read_bytes() == (tmp_path / "a.nc").read_bytes()


def test_changed_file_at_the_same_path_is_never_served_stale(tmp_path, monkeypatch):
    cache = tmp_path / "cache"
    monkeypatch.setenv(CACHE_ENV, str(cache))
    part = tmp_path / "part.step"
    shutil.copyfile(SHAFT, part)
    first = load_part(part).profile
    assert repr(load_part(part).profile.outside) == repr(first.outside)  # a hit
    shutil.copyfile(KNOB, part)  # another solid, same path, same name
    monkeypatch.delenv(CACHE_ENV)
    fresh = load_part(part).profile
    monkeypatch.setenv(CACHE_ENV, str(cache))
    cached = load_part(part).profile
    assert repr(fresh.outside) != repr(first.outside)
    assert repr(cached.outside) == repr(fresh.outside)
    assert len(list(cache.glob("*.profile"))) == 2


def test_key_covers_contents_place_name_and_options(tmp_path):
    c = ProfileCache(tmp_path)
    a = tmp_path / "a.step"
    shutil.copyfile(SHAFT, a)
    k = c.key(a, "a", {})
    assert k == c.key(a, "a", {})
    assert k != c.key(a, "b", {})
    assert k != c.key(a, "a", {"envelope": True})
    assert c.key(a, "a", {"fit_tol": 0.01}) != c.key(a, "a", {"fit_tol": 0.02})
    b = tmp_path / "b.step"
    shutil.copyfile(SHAFT, b)
    assert c.key(b, "a", {}) != k  # another place
    with a.open("ab") as f:
        f.write(b"\n")
    assert c.key(a, "a", {}) != k  # one byte more


@pytest.mark.parametrize("junk", [b"", b"\x80\x04garbage", b"not a pickle at all" * 100])
def test_broken_entry_is_a_miss_and_is_rewritten(tmp_path, monkeypatch, junk):
    cache = tmp_path / "cache"
    monkeypatch.setenv(CACHE_ENV, str(cache))
    want = repr(load_part(SHAFT).profile.outside)
    (entry,) = cache.glob("*.profile")
    entry.write_bytes(junk)
    assert repr(load_part(SHAFT).profile.outside) == want
    assert entry.read_bytes() != junk  # written again
    assert repr(load_part(SHAFT).profile.outside) == want


def test_entry_of_another_key_is_not_served(tmp_path, monkeypatch):
    """An entry copied under another key's name (or a key collision) is refused: each entry
    carries its key."""
    cache = tmp_path / "cache"
    monkeypatch.setenv(CACHE_ENV, str(cache))
    knob = tmp_path / "k.step"
    shutil.copyfile(KNOB, knob)
    want_knob = repr(load_part(knob).profile.outside)
    (knob_entry,) = cache.glob("*.profile")
    load_part(SHAFT)
    (shaft_entry,) = [e for e in cache.glob("*.profile") if e != knob_entry]
    shutil.copyfile(shaft_entry, knob_entry)
    assert repr(load_part(knob).profile.outside) == want_knob


def test_unwritable_folder_and_python_parts(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    monkeypatch.setenv(CACHE_ENV, str(blocker / "sub"))  # cannot be created
    assert load_part(SHAFT).profile.outside is not None
    cache = tmp_path / "cache"
    monkeypatch.setenv(CACHE_ENV, str(cache))
    load_part(REPO / "parts" / "stepped_shaft.py", {"length": "90"})
    assert not list(cache.glob("*.profile"))  # Python parts are not cached


# --------------------------------------------------------------------------------------------
# Python parts in a long-lived process (a cluster worker, a session calling generate): the
# imported part module is reused only while the part file and the user's helper modules it
# imports are unchanged, compared by contents
# --------------------------------------------------------------------------------------------

HELPER_PART = """
import shapes
from hnc_cam.cad.sketch import revolve


def part(length: float = 30.0):
    return revolve(shapes.outline(length))
"""

HELPER = """
from hnc_cam.cad.sketch import Outline

DIAMETER = {d}


def outline(length):
    r = DIAMETER / 2
    return Outline((0.0, 0.0)).line_to(r, 0.0).line_to(r, -length).line_to(0.0, -length).segments()
"""

LAZY_PART = """
from hnc_cam.cad.sketch import revolve


def part(length: float = 30.0):
    from lazyshapes import outline   # imported when part() runs
    return revolve(outline(length))
"""


def _max_dia(lp) -> float:
    return round(2 * lp.profile.max_radius, 6)


@pytest.fixture
def helper_dir(tmp_path, monkeypatch):
    d = tmp_path / "fam"
    d.mkdir()
    monkeypatch.syspath_prepend(str(d))
    yield d
    for name in ("shapes", "lazyshapes"):
        sys.modules.pop(name, None)


def test_edited_helper_module_is_imported_again(helper_dir):
    """A part file importing a helper module beside it: the helper edited between two loads
    in one process (the part file untouched) gives the new part, not the old one."""
    part = helper_dir / "shaft.py"
    part.write_text(HELPER_PART)
    (helper_dir / "shapes.py").write_text(HELPER.format(d=20.0))
    assert _max_dia(load_part(part, {"length": "30"})) == 20.0
    assert _max_dia(load_part(part, {"length": "30"})) == 20.0  # reused
    (helper_dir / "shapes.py").write_text(HELPER.format(d=24.0))
    assert _max_dia(load_part(part, {"length": "30"})) == 24.0
    assert _max_dia(load_part(part, {"length": "31"})) == 24.0


def test_helper_imported_inside_part_is_tracked_too(helper_dir):
    part = helper_dir / "lazy.py"
    part.write_text(LAZY_PART)
    (helper_dir / "lazyshapes.py").write_text(HELPER.format(d=18.0))
    assert _max_dia(load_part(part)) == 18.0
    (helper_dir / "lazyshapes.py").write_text(HELPER.format(d=22.0))
    assert _max_dia(load_part(part)) == 22.0


def test_part_file_edited_within_the_same_second_is_imported_again(helper_dir):
    """Compared by contents: an edit that leaves the modification time as it was (a coarse
    clock, a copy keeping times) still reloads the part."""
    part = helper_dir / "same.py"
    (helper_dir / "shapes.py").write_text(HELPER.format(d=20.0))
    part.write_text(HELPER_PART)
    st = part.stat()
    assert _max_dia(load_part(part)) == 20.0
    part.write_text(HELPER_PART.replace("shapes.outline(length)", "shapes.outline(length)[:]")
                    .replace("length: float = 30.0", "length: float = 40.0"))
    os.utime(part, ns=(st.st_atime_ns, st.st_mtime_ns))
    assert load_part(part).params == {"length": 40.0}
