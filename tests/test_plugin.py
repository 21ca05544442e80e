"""The pytest plugin, as a shop's test file uses it: a passing and a failing round trip in a
separate pytest run; the failure names the HTML report, which exists."""
from __future__ import annotations

import re
import subprocess
import sys
from importlib import metadata
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]

SHOP_TESTS = '''
def test_shaft(hnc_roundtrip):
    program, report = hnc_roundtrip("parts/stepped_shaft.py", stock="45x100+2", length=80)
    assert report.passed and program.text.startswith("%")


def test_shaft_too_tight(hnc_roundtrip):
    # 0.1 um: the 0.5 um chord error of the simulator alone exceeds it
    hnc_roundtrip("parts/stepped_shaft.py", stock="45x100+2", tol=0.0001, length=80)
'''


def _plugin_args() -> list[str]:
    """Load the plugin by its module when the entry point is not installed (an old editable
    install); an installed entry point loads it by itself."""
    eps = metadata.entry_points(group="pytest11")
    if any(ep.value == "hnc_cam.pytest_plugin" for ep in eps):
        return []
    return ["-p", "hnc_cam.pytest_plugin"]


def test_entry_point_is_declared():
    text = (REPO / "pyproject.toml").read_text()
    assert re.search(r'\[project\.entry-points\.pytest11\]\s*\nhnc_cam = "hnc_cam.pytest_plugin"',
                     text)


@pytest.mark.cad
def test_shop_file_pass_and_failure_with_report(tmp_path):
    shop = tmp_path / "shop"
    (shop / "parts").mkdir(parents=True)
    (shop / "parts" / "stepped_shaft.py").write_text((REPO / "parts/stepped_shaft.py").read_text())
    (shop / "test_parts.py").write_text(SHOP_TESTS)
    reports = tmp_path / "reports"
    r = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                        *_plugin_args(), "--hnc-reports", str(reports), "test_parts.py"],
                       cwd=shop, capture_output=True, text=True, timeout=600)
    out = r.stdout + r.stderr
    assert r.returncode == 1, out
    assert "1 failed, 1 passed" in out, out
    m = re.search(r"HTML report: (\S+\.html)", out)
    assert m, out
    page = Path(m.group(1))
    assert page == reports / "test_shaft_too_tight.html"
    text = page.read_text()
    assert 'class="badge fail"' in text and "FAIL at tolerance 0.0001 mm" in text
    assert sorted(p.name for p in reports.iterdir()) == ["test_shaft_too_tight.html"]
