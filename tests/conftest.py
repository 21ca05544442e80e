"""Shared test fixtures: the manual's example programs live outside the repo in
../shared/examples/manual (never copied in); tests skip with a reason where it is absent."""
from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
MANUAL = REPO.parent / "shared" / "examples" / "manual"


def manual_file(name: str) -> Path:
    """Path of a manual example (e.g. ``"3327.nc"``), or skip the test when the checkout has
    no ../shared beside it."""
    p = MANUAL / name
    if not p.exists():
        pytest.skip(f"manual example {name} not available: no ../shared/examples/manual beside this checkout")
    return p


@pytest.fixture
def manual():
    return manual_file


# Property tests: reproducible in CI (same examples every run, no wall-clock deadline on a
# loaded 2-core machine); locally HYPOTHESIS_PROFILE=dev explores new examples each run.
try:
    import os

    from hypothesis import HealthCheck, settings

    settings.register_profile("ci", derandomize=True, deadline=None,
                              suppress_health_check=[HealthCheck.too_slow])
    settings.register_profile("dev", deadline=None, suppress_health_check=[HealthCheck.too_slow])
    settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
except ImportError:  # pragma: no cover - hypothesis is a test dependency
    pass
