"""The wheel ships every package: pyproject.toml lists its packages by hand (the templates
are mapped in), so a package added under hnc_cam/ must be added there too, or a plain
``pip install .`` (the README's first command) fails where an editable install works."""
from __future__ import annotations

import tomllib
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_every_package_under_hnc_cam_is_in_the_wheel():
    listed = set(tomllib.loads((REPO / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {".".join(p.parent.relative_to(REPO).parts) for p in (REPO / "hnc_cam").rglob("__init__.py")}
    assert found - listed == set()
    # and each listed package is a folder that exists (hnc_cam._templates is templates/)
    for name in listed - {"hnc_cam._templates"}:
        assert (REPO / Path(*name.split("."))).is_dir(), name
