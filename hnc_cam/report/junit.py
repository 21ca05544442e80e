"""JUnit XML for CI: one test case per program (``verify``) or per table row (``family``).

The shape is the one CI systems read (Ant's JUnit task format as Jenkins, GitLab and GitHub
test reporters take it, schema ``junit-10.xsd``)::

    <testsuites name tests failures errors skipped time>
      <testsuite name tests failures errors skipped time timestamp hostname>
        <testcase name classname time>
          <failure message type>full report</failure>      (verification failed)
          <error message type>reason</error>                (bad input: not generated)
          <system-out>the report summary</system-out>
        </testcase>

``failure``/``error`` ``message`` = the verdict line and the first findings (at most
``FIRST_FINDINGS``), on one line; the element's text is the whole report.
"""
from __future__ import annotations

import datetime
import socket
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any, Sequence

FIRST_FINDINGS = 3


def _clean(s: str) -> str:
    """Text XML 1.0 can carry (control characters other than tab/newline dropped)."""
    return "".join(ch for ch in str(s) if ch in "\t\n\r" or (ord(ch) >= 0x20 and ord(ch) not in
                                                               (0xFFFE, 0xFFFF)
                                                               and not 0xD800 <= ord(ch) <= 0xDFFF))


def failure_message(report=None, machined=None, extra: str = "") -> str:
    """The verdict line and the first findings, one line."""
    parts: list[str] = []
    if report is not None:
        parts.append(f"{'PASS' if report.passed else 'FAIL'} at tolerance {report.tol:g} mm: "
                     f"max overcut {report.max_overcut_mm:.4f} mm, max undercut "
                     f"{report.max_undercut_mm:.4f} mm")
        found = list(report.reasons) + [str(c) for c in report.collisions]
        found += [str(t) for t in report.threads if not t.ok]
        if report.strict:
            found += [f"unreachable X{2 * u.x:.3f} Z{u.z:.3f}: {u.size_mm:.4f} mm"
                      for u in report.unreachable]
        parts += found[:FIRST_FINDINGS]
    elif machined is not None:
        parts.append(f"{len(machined.issues)} collision(s)/check finding(s)")
        parts += [str(i) for i in machined.issues[:FIRST_FINDINGS]]
    if extra:
        parts.append(extra)
    return "; ".join(p.replace("\n", " ") for p in parts)


def testcase(name: str, classname: str, time_s: float = 0.0, *, failure: str | None = None,
             failure_text: str = "", error: str | None = None, error_text: str = "",
             out: str = "") -> dict[str, Any]:
    return {"name": name, "classname": classname, "time": max(0.0, float(time_s)),
            "failure": failure, "failure_text": failure_text, "error": error,
            "error_text": error_text, "out": out}


def render(suite: str, cases: Sequence[dict[str, Any]], time_s: float = 0.0) -> str:
    """The XML document."""
    failures = sum(1 for c in cases if c["failure"] is not None and c["error"] is None)
    errors = sum(1 for c in cases if c["error"] is not None)
    counts = {"tests": str(len(cases)), "failures": str(failures), "errors": str(errors),
              "skipped": "0", "time": f"{time_s:.3f}"}
    # junit-10.xsd: <testsuites> has no "skipped" attribute, <testsuite> has
    root = ET.Element("testsuites", {"name": _clean(suite),
                                     **{k: v for k, v in counts.items() if k != "skipped"}})
    ts = ET.SubElement(root, "testsuite", {
        "name": _clean(suite), **counts,
        "timestamp": datetime.datetime.now().replace(microsecond=0).isoformat(),
        "hostname": _clean(socket.gethostname() or "localhost")})
    for c in cases:
        tc = ET.SubElement(ts, "testcase", {"name": _clean(c["name"]),
                                            "classname": _clean(c["classname"]),
                                            "time": f"{c['time']:.3f}"})
        if c["error"] is not None:
            e = ET.SubElement(tc, "error", {"message": _clean(c["error"]), "type": "error"})
            e.text = _clean(c["error_text"] or c["error"])
        elif c["failure"] is not None:
            f = ET.SubElement(tc, "failure", {"message": _clean(c["failure"]),
                                              "type": "verification"})
            f.text = _clean(c["failure_text"] or c["failure"])
        if c["out"]:
            so = ET.SubElement(tc, "system-out")
            so.text = _clean(c["out"])
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write(path: str | Path, text: str) -> None:
    from .html import write_text
    write_text(path, text, option="--junit")


def verify_junit(path: str | Path, machined, report, args, time_s: float = 0.0) -> None:
    """``hnc-cam verify --junit``: one test case, the program against its model."""
    name = str(machined.toolpath.file)
    cls = f"hnc_cam.verify.{Path(str(args.model)).stem}"
    fail = None if report.passed else failure_message(report)
    case = testcase(name, cls, time_s, failure=fail, failure_text=report.summary(),
                    out=report.summary())
    write(path, render(f"hnc-cam verify {name}", [case], time_s))


def family_junit(path: str | Path, args, rows: Sequence[dict[str, Any]]) -> None:
    """``hnc-cam family --junit``: one test case per table row, named by its program (or row)
    and parameters; verification failures are failures, rows that could not be generated are
    errors."""
    part = Path(str(args.part)).stem
    cases = []
    for r in rows:
        name = f"{r['name']} (row {r['row']}{': ' + r['params'] if r.get('params') else ''})"
        status = r.get("status")
        summary = r.get("summary") or ""
        msg = str(r.get("message", "")).replace("\n", " ")
        t = r.get("cycle_time_s")
        if status == "ok":
            cases.append(testcase(name, f"hnc_cam.family.{part}", out=summary or
                                  f"pass, cycle time {t} s"))
        elif status == "failed":
            first = _first_line_and_findings(summary, msg)
            cases.append(testcase(name, f"hnc_cam.family.{part}", failure=first,
                                  failure_text=summary or msg))
        else:
            cases.append(testcase(name, f"hnc_cam.family.{part}", error=msg or "not generated",
                                  error_text=msg))
    write(path, render(f"hnc-cam family {part} {Path(str(args.table)).name}", cases))


def _first_line_and_findings(summary: str, message: str) -> str:
    """Verdict line and first findings from a report summary (or the row's message)."""
    if not summary:
        return message
    lines = [ln.strip() for ln in summary.splitlines() if ln.strip()]
    head = lines[0]
    rest = [ln for ln in lines[1:] if ln.startswith(("line ", "fails:", "thread", "X"))
            or "collision" in ln]
    return "; ".join([head] + rest[:FIRST_FINDINGS])
