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
