"""What a reviewer opens: the HTML report (backplot, program text, step-through, setup
sheet) and JUnit XML for CI.

The package reads the interpreter's :class:`~hnc_cam.nc.toolpath.Toolpath`, the simulator's
:class:`~hnc_cam.sim.simulate.Machined` and the verifier's :class:`~hnc_cam.sim.verify.Report`;
planner data (a generated program's plan, a tool library) arrive as plain values read by
attribute, never by importing the planner.

Entry points used by the commands (one call each):

* :func:`verify_report` — ``hnc-cam verify --report FILE.html``;
* :func:`program_report` — ``hnc-cam generate --report FILE.html``;
* :func:`family_outputs` — ``hnc-cam family --report FILE.html --junit FILE.xml``;
* :func:`hnc_cam.report.junit.verify_junit` — ``hnc-cam verify --junit FILE.xml``.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

from .html import page_data, render_index, render_page, write_text

__all__ = ["page_data", "render_page", "render_index", "write_report", "verify_report",
           "verify_outputs",
           "program_report", "family_outputs"]


def write_report(path: str | Path, machined, report=None, model=None, **kw: Any) -> None:
    """Render the page for a simulation (and its verification) and write it atomically."""
    write_text(path, render_page(machined, report, model, **kw))


def verify_report(path: str | Path, machined, report, loaded, args) -> None:
    """``hnc-cam verify --report``: the page of a verified program."""
    lib = None
    if getattr(args, "tools", None):
        from ..tooling import load_tools
        lib = load_tools(args.tools)
    write_report(path, machined, report, loaded.profile,
                 title=f"{machined.toolpath.file} against {args.model}",
                 params=dict(getattr(loaded, "params", None) or {}), stock=args.stock,
                 library=lib, part=getattr(loaded, "name", None) or args.model)


def verify_outputs(args, machined, report, loaded) -> None:
    """``hnc-cam verify --report FILE.html --junit FILE.xml``."""
    if getattr(args, "report", None):
        verify_report(args.report, machined, report, loaded, args)
    if getattr(args, "junit", None):
        from .junit import verify_junit
        verify_junit(args.junit, machined, report, args)


def simulate_program(prog, tol: float = 0.01):
    """Simulate (and, when the program carries no report, verify) a generated program for its
    page: ``(machined, report)``."""
    from ..sim import simulate, verify
    plan = prog.plan
    machined = simulate(prog.toolpath, plan.stock, plan.machine, model=plan.profile)
    report = prog.report
    if report is None:
        report = verify(machined, plan.profile, tol=tol, threads=plan.profile.threads or None)
    return machined, report


def program_report(path: str | Path, prog, tol: float = 0.01, index_href: str | None = None,
                   title: str | None = None) -> Any:
    """``hnc-cam generate --report``: the page of a generated program (its plan gives the
    setup sheet). Returns the verification report shown."""
    machined, report = simulate_program(prog, tol)
    plan = prog.plan
    write_report(path, machined, report, plan.profile,
                 title=title or f"O{plan.program_number:04d} {plan.name}", plan=plan,
                 warnings=list(getattr(prog, "warnings", []) or []), index_href=index_href,
                 comp=getattr(plan, "comp", None), labels=getattr(prog, "labels", None))
    return report


def family_outputs(args, jobs, results) -> None:
    """``hnc-cam family --report INDEX.html`` and/or ``--junit FILE.xml``.

    ``jobs``: the family's row jobs ``(row, line, part, stock, params, number, options)``;
    ``results``: the rows' results (``status`` ok/failed/error, ``message``...). The report
    writes one page per generated row beside the index (``O<number>.html``), rebuilding the
    row's program without its verification so that a row that failed verification has its
    page too, and the index page; the JUnit file has one test case per row."""
    report_path = getattr(args, "report", None)
    junit_path = getattr(args, "junit", None)
    if not report_path and not junit_path:
        return
    by_row = {j[0]: j for j in jobs}
    rows: list[dict[str, Any]] = []
    index_dir = Path(report_path).parent if report_path else None
    pages: dict[int, dict[str, Any] | None] = {}
    if report_path:
        todo = [(str(index_dir / f"O{int(r['program_number']):04d}.html"), by_row[r["row"]],
                 Path(report_path).name) for r in results
                if r.get("status") in ("ok", "failed") and r["row"] in by_row
                and str(r.get("program_number")).isdigit()]
        pages = _pages(todo, getattr(args, "jobs", 0) or 0)
    for r in sorted(results, key=lambda r: r["row"]):
        job = by_row.get(r["row"])
        number = r.get("program_number")
        name = f"O{int(number):04d}" if str(number).isdigit() else f"row {r['row']}"
        params = job[4] if job else {}
        row = {"row": r["row"], "name": name, "status": r.get("status", "error"),
               "verdict": {"ok": "pass", "failed": "fail"}.get(r.get("status", ""), "error"),
               "params": " ".join(f"{k}={v}" for k, v in params.items()),
               "cycle_time_s": r.get("cycle_time_s", ""),
               "max_overcut_mm": r.get("max_overcut_mm", ""),
               "max_undercut_mm": r.get("max_undercut_mm", ""),
               "message": r.get("message", ""), "summary": ""}
        got = pages.get(r["row"])
        if got is not None:
            row.update(got)
        rows.append(row)
    if report_path:
        write_text(report_path, render_index(f"{Path(args.part).name}: {Path(args.table).name}",
                                             rows))
    if junit_path:
        from .junit import family_junit
        family_junit(junit_path, args, rows)


def _pages(todo: list[tuple[str, tuple, str]], jobs: int) -> dict[int, dict[str, Any] | None]:
    """The rows' pages, in worker processes like the family itself (``--jobs``, 0 = all
    cores): row -> its index fields, or None when the row could not be rebuilt."""
    import os
    n = min(jobs or os.cpu_count() or 1, len(todo))
    if n <= 1:
        return {job[0]: _page_job((path, job, name)) for path, job, name in todo}
    from concurrent.futures import ProcessPoolExecutor
    with ProcessPoolExecutor(max_workers=n) as ex:
        return dict(zip((job[0] for _p, job, _n in todo), ex.map(_page_job, todo)))


def _page_job(item: tuple[str, tuple, str]) -> dict[str, Any] | None:
    """Write one row's page (in a worker); the fields the index shows for it. A page that
    cannot be written is an error of the whole command (one line, exit 2)."""
    path, job, index_name = item
    rep = _row_page(Path(path), job, index_name)
    if rep is None:
        return None
    return {"href": Path(path).name, "summary": rep.summary(),
            "max_overcut_mm": round(rep.max_overcut_mm, 4),
            "max_undercut_mm": round(rep.max_undercut_mm, 4)}


def _row_page(path: Path, job, index_name: str):
    """Regenerate a row's program (unverified) and write its page; None if it cannot be
    generated (the row's own error is already in the summary)."""
    from ..errors import HncError
    from ..plan.api import generate
    idx, _line, part, stock, params, number, opts = job
    o = dict(opts)
    tol = o.pop("tol", 0.01)
    o["verify"] = False
    try:
        prog = generate(part, stock, params=params, program_number=number,
                        file=f"O{number:04d}.nc", tol=tol, **o)
    except HncError:
        return None
    return program_report(path, prog, tol=tol, index_href=index_name)


class failure_report:
    """``with failure_report(args): prog = generate(...)``: when ``generate --report`` refuses a
    program that fails verification, the page of that program is still written (the
    reviewer's most useful case), then the refusal goes on (exit 1)."""

    def __init__(self, args) -> None:
        self.path = getattr(args, "report", None)
        self.tol = getattr(args, "tol", 0.01)

    def __enter__(self) -> "failure_report":
        return self

    def __exit__(self, typ, exc, tb) -> bool:
        prog = getattr(exc, "program", None)
        if self.path and prog is not None and getattr(exc, "exit_code", 2) == 1:
            program_report(self.path, prog, tol=self.tol)
        return False
