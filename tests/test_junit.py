"""JUnit XML: the structure of junit-10.xsd (the schema Jenkins, GitLab and GitHub reporters
read), one case per program or row, failures carrying the verdict line and the first findings."""
from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path
from types import SimpleNamespace

import pytest

from hnc_cam.cli import main
from hnc_cam.geometry import Line, TurnedProfile
from hnc_cam.nc.interp import run
from hnc_cam.report import junit
from hnc_cam.sim import simulate, verify
from hnc_cam.tooling import Stock, load_machine

from test_report import SUB

REPO = Path(__file__).resolve().parents[1]

# junit-10.xsd: allowed attributes (required ones first) and children per element
SCHEMA = {
    "testsuites": ({"name", "time", "tests", "failures", "disabled", "errors"}, set(),
                   {"testsuite"}),
    "testsuite": ({"name", "tests", "failures", "errors", "time", "disabled", "skipped",
                   "timestamp", "hostname", "id", "package", "file", "log", "url", "version"},
                  {"name", "tests"}, {"properties", "testcase", "system-out", "system-err"}),
    "testcase": ({"name", "assertions", "time", "classname", "status"}, {"name"},
                 {"skipped", "error", "failure", "system-out", "system-err"}),
    "failure": ({"message", "type"}, set(), set()),
    "error": ({"message", "type"}, set(), set()),
    "skipped": ({"message"}, set(), set()),
    "system-out": (set(), set(), set()),
    "system-err": (set(), set(), set()),
}
DECIMAL = re.compile(r"^-?\d+(\.\d+)?$")
DATETIME = re.compile(r"^\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}$")


def validate(text: str) -> ET.Element:
    """Check a document against junit-10.xsd's structure and types; return the root."""
    assert text.startswith('<?xml version="1.0" encoding="UTF-8"?>')
    root = ET.fromstring(text.encode("utf-8"))

    def walk(el: ET.Element) -> None:
        assert el.tag in SCHEMA, el.tag
        allowed, required, children = SCHEMA[el.tag]
        assert set(el.attrib) <= allowed, (el.tag, set(el.attrib) - allowed)
        assert required <= set(el.attrib), (el.tag, required - set(el.attrib))
        for a in ("time",):
            if a in el.attrib:
                assert DECIMAL.match(el.attrib[a]), (el.tag, a, el.attrib[a])
        for a in ("tests", "failures", "errors", "skipped", "disabled"):
            if a in el.attrib:
                assert el.attrib[a].isdigit(), (el.tag, a)
        if "timestamp" in el.attrib:
            assert DATETIME.match(el.attrib["timestamp"])
        for c in el:
            assert c.tag in children, (el.tag, c.tag)
            walk(c)
    assert root.tag == "testsuites"
    walk(root)
    for ts in root.iter("testsuite"):
        cases = ts.findall("testcase")
        assert int(ts.get("tests")) == len(cases)
        assert int(ts.get("failures")) == sum(1 for c in cases if c.find("failure") is not None)
        assert int(ts.get("errors")) == sum(1 for c in cases if c.find("error") is not None)
    return root


def _fail_case():
    """SUB against a model 0.5 mm thinner than what it cuts: reachable leftover, FAIL."""
    machine = load_machine()
    tp = run(SUB, machine, file="sub.nc", start="reference")
    m = simulate(tp, Stock.parse("40x60+1"), machine)
    model = TurnedProfile(outside=[Line((0.0, 1.0), (17.5, 1.0)), Line((17.5, 1.0), (17.5, -30.0))],
                          name="thin")
    return m, verify(m, model, tol=0.01)


def test_verify_failure_carries_the_verdict_and_first_findings(tmp_path):
    m, rep = _fail_case()
    assert not rep.passed
    out = tmp_path / "r.xml"
    junit.verify_junit(out, m, rep, SimpleNamespace(model="parts/thin.py"))
    root = validate(out.read_text())
    case = root.find("testsuite/testcase")
    assert case.get("name") == "sub.nc" and case.get("classname") == "hnc_cam.verify.thin"
    f = case.find("failure")
    assert f.get("message").startswith("FAIL at tolerance 0.01 mm: max overcut ")
    assert f"max undercut {rep.max_undercut_mm:.4f} mm" in f.get("message")
    assert rep.reasons and rep.reasons[0] in f.get("message")
    assert "\n" not in f.get("message")
    assert f.text == rep.summary()


def test_control_characters_and_markup_in_names_stay_valid(tmp_path):
    cases = [junit.testcase("O0001 <a & b>", "c", 1.5, failure="bad \x01 line\x1b[0m"),
             junit.testcase("row 2", "c", error="cannot read")]
    text = junit.render("suite \x00", cases, 2.0)
    root = validate(text)
    tc = root.findall("testsuite/testcase")
    assert tc[0].get("name") == "O0001 <a & b>"
    assert tc[0].find("failure").get("message") == "bad  line[0m"
    assert tc[1].find("error").get("message") == "cannot read"
    ts = root.find("testsuite")
    assert (ts.get("tests"), ts.get("failures"), ts.get("errors")) == ("2", "1", "1")


def test_unwritable_junit_path_is_one_line(tmp_path):
    m, rep = _fail_case()
    blocker = tmp_path / "f"
    blocker.write_text("")
    from hnc_cam.errors import HncError
    with pytest.raises(HncError) as e:
        junit.verify_junit(blocker / "r.xml", m, rep, SimpleNamespace(model="x.py"))
    assert e.value.one_line().startswith("error: --junit ")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f"]


@pytest.mark.cad
def test_family_junit_and_report_one_case_per_row(tmp_path, capsys):
    table = tmp_path / "shafts.csv"
    # row 2 cannot be made (d1 above d2): an error case; the others pass
    table.write_text("length,d1\n100,20\n100,30\n110,18\n")
    out = tmp_path / "out"
    rc = main(["family", str(REPO / "parts/stepped_shaft.py"), "--table", str(table),
               "--out", str(out), "--jobs", "1", "--junit", str(out / "junit.xml"),
               "--report", str(out / "index.html")])
    assert rc == 2
    root = validate((out / "junit.xml").read_text())
    cases = root.findall("testsuite/testcase")
    assert [c.get("name").split(" ")[0] for c in cases] == ["O0001", "O0002", "O0003"]
    assert "row 2" in cases[1].get("name") and "d1=30" in cases[1].get("name")
    assert cases[0].find("failure") is None and cases[0].find("error") is None
    assert cases[1].find("error") is not None and "d1" in cases[1].find("error").get("message")
    assert cases[2].find("failure") is None
    index = (out / "index.html").read_text()
    assert 'href="O0001.html"' in index and 'href="O0003.html"' in index
    assert 'href="O0002.html"' not in index
    page = (out / "O0003.html").read_text()
    assert 'href="index.html"' in page and 'class="badge pass"' in page
