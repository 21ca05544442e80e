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
