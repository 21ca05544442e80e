"""Replay of the fuzzer's corpus (``tests/data/fuzz_corpus``: minimal reproducers of every
failure class found so far) and a fixed-seed sample of the fuzzer itself
(``benchmarks/fuzz.py``): every case ends in a toolpath or in one printable alarm line, in
bounded time."""
from __future__ import annotations

import importlib.util
import time
from pathlib import Path

import pytest

from hnc_cam.errors import HncError
from hnc_cam.nc import run

ROOT = Path(__file__).resolve().parents[1]
CORPUS = sorted((ROOT / "tests" / "data" / "fuzz_corpus").glob("*.nc"))


def _fuzz():
    spec = importlib.util.spec_from_file_location("hnc_fuzz", ROOT / "benchmarks" / "fuzz.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


fuzz = _fuzz()


def test_corpus_is_there():
    assert len(CORPUS) >= 20


@pytest.mark.parametrize("path", CORPUS, ids=[p.name for p in CORPUS])
def test_corpus_case(path):
    text = path.read_bytes().decode("utf-8", errors="replace")
    t0 = time.perf_counter()
    assert fuzz.check(text, fuzz.fuzz_machine(2000)) is None
    assert time.perf_counter() - t0 < fuzz.SLOW_S
    # with the default machine too (its limits far higher): still an alarm or a toolpath
    t0 = time.perf_counter()
    try:
        run(text, file=path.name)
    except HncError as e:
        line = e.one_line()
        assert line.isprintable() and len(line) <= fuzz.MAX_LINE
    assert time.perf_counter() - t0 < 15


def test_fuzz_check_tells_failures_apart():
    # the checker itself: an alarm passes, a toolpath passes, and a raw CR in an alarm would not
    m = fuzz.fuzz_machine(2000)
    assert fuzz.check("%1\nG07\nM30\n", m) is None
    assert fuzz.check("%1\nG0X10\nM30\n", m) is None
    assert fuzz.check("%1\nWHILE 1\nENDW\nM30\n", m) is None  # the step limit's alarm


SAMPLE = 20_000


def test_fixed_seed_sample():
    res = fuzz.fuzz(SAMPLE, seed=20261124, steps=2000)
    assert res["cases"] == SAMPLE
    assert res["kinds"]["grammar"] > SAMPLE // 3 and res["kinds"]["mutation"] > SAMPLE // 3
    bad = {k: (c, first, prog[:300]) for k, (c, first, prog) in res["failures"].items()}
    assert bad == {}
    assert res["slow"] == []
