"""``hnc-cam generate`` and ``hnc-cam family``.

generate: writes the program to ``-o`` (atomically) or stdout and a one-line summary to
stderr. Exit 0, 1 when the program fails verification (nothing written), 2 on bad input.

family: one program per CSV row (columns: the part's parameters, optional ``program_number``
and ``stock``), ``DIR/O<number>.nc`` plus ``DIR/summary.csv`` (row, program_number, file,
status, operations, cycle_time_s, verified, max_overcut_mm, max_undercut_mm, message).
Rows run in worker processes (``--jobs``, default all cores) that import the CAD kernel once
(pool initializer) and are reused for every row. A bad row is reported (stderr and
summary.csv) and the others still complete; the exit code is then 2 (1 when the only
failures are verification failures).
"""
from __future__ import annotations

import argparse
import csv
import io
import os
import sys
from pathlib import Path
from typing import Any

from ..errors import HncError, PartError, PlanError


def _options(args: argparse.Namespace) -> dict[str, Any]:
    return dict(tools=getattr(args, "tools", None), machine=getattr(args, "machine", None),
                comp=getattr(args, "comp", "cam") or "cam",
                templates=getattr(args, "templates", None),
                verify=not getattr(args, "no_verify", False), tol=getattr(args, "tol", 0.01),
                number_format=getattr(args, "number_format", "plain") or "plain",
                block_numbers=getattr(args, "block_numbers", "every") or "every",
                thread_cycle=getattr(args, "thread_cycle", "g76") or "g76",
                face_cycle=getattr(args, "face_cycle", "g81") or "g81",
                material=getattr(args, "material", None),
                allowance=getattr(args, "allowance", None))


def generate_command(args: argparse.Namespace) -> int:
    from ..cad import parse_set
    from ..io import write_atomic
    from .api import generate

    params = parse_set(args.params or [])
    from ..report import failure_report
    with failure_report(args):  # --report: the page of a program refused by verification
        prog = generate(args.part, args.stock, params=params, program_number=args.program_number,
                        file=args.output or "<stdout>", **_options(args))
    if args.output:
        write_atomic(args.output, prog.text)
    else:
        sys.stdout.write(prog.text)
        sys.stdout.flush()
    if getattr(args, "report", None):
        from ..report import program_report
        program_report(args.report, prog, tol=getattr(args, "tol", 0.01))
    if getattr(args, "explain", False):
        print(prog.plan.explain(), file=sys.stderr)
    print(prog.summary(), file=sys.stderr)
    for w in prog.warnings:
        print(f"warning: {w}", file=sys.stderr)
    return 0


# ------------------------------------------------------------------------------------------
# family
# ------------------------------------------------------------------------------------------

#: how many times this process ran the worker initializer (a reused worker reports 1)
_INITS = 0


def _init_worker(opts: dict[str, Any] | None = None) -> None:
    """Once per worker process: import the CAD kernel, the interpreter and the simulator, and
    load the tool library, the machine and the templates (cached in :mod:`hnc_cam.plan.api`
    for every row the worker runs)."""
    global _INITS
    _INITS += 1
    try:
        import build123d  # noqa: F401
        from .. import cad  # noqa: F401
        from ..cad import extract  # noqa: F401
        from .. import nc, sim  # noqa: F401
    except Exception:  # pragma: no cover - the row reports the real error
        pass
    if opts:
        try:
            from .api import warm
            warm(opts.get("tools"), opts.get("machine"), opts.get("templates"),
                 opts.get("number_format", "plain"), opts.get("block_numbers", "every"))
        except Exception:  # pragma: no cover - the rows report the real error
            pass


def _row_job(job: tuple) -> dict[str, Any]:
    """Generate one row; never raises (the error becomes the row's result)."""
    idx, line, part, stock, params, number, opts = job
    out: dict[str, Any] = {"row": idx, "line": line, "program_number": number,
                           "worker": (os.getpid(), _INITS)}
    try:
        from .api import VerificationError, generate
        prog = generate(part, stock, params=params, program_number=number,
                        file=f"O{number:04d}.nc", **opts)
        rep = prog.report
        out.update(status="ok", text=prog.text, operations=" ".join(prog.operations),
                   cycle_time_s=round(prog.cycle_time_s, 1),
                   verified=("pass" if rep is not None else "skipped"),
                   max_overcut_mm=(round(rep.max_overcut_mm, 4) if rep is not None else ""),
                   max_undercut_mm=(round(rep.max_undercut_mm, 4) if rep is not None else ""),
                   message="")
    except VerificationError as e:
        out.update(status="failed", message=str(e), verified="fail", exit=1)
    except HncError as e:
        out.update(status="error", message=str(e), exit=2)
    except Exception as e:  # a generator bug must not stop the other rows
        out.update(status="error", message=f"internal error: {type(e).__name__}: {e}", exit=2)
    return out


def read_table(path: str) -> tuple[list[str], list[tuple[int, int, dict[str, str] | str]]]:
    """Rows of the CSV: (row index from 1, file line, cells or an error message)."""
    try:
        text = Path(path).read_text("utf-8-sig")
    except OSError as e:
        raise PartError(f"{path}: cannot read the table: {e.strerror or e}") from None
    rdr = csv.reader(io.StringIO(text))
    try:
        header = next(rdr)
    except StopIteration:
        raise PartError(f"{path}: the table is empty (no header row)") from None
    header = [h.strip() for h in header]
    if not header or any(not h for h in header):
        raise PartError(f"{path}:1: the header has an empty column name")
    if len(set(header)) != len(header):
        raise PartError(f"{path}:1: the header names a column twice")
    rows: list[tuple[int, int, dict[str, str] | str]] = []
    n = 0
    for cells in rdr:
        line = rdr.line_num
        if not cells or all(not c.strip() for c in cells):
            continue
        n += 1
        if len(cells) != len(header):
            rows.append((n, line, f"{path}:{line}: row has {len(cells)} field(s), the header "
                                  f"has {len(header)}"))
            continue
        rows.append((n, line, {h: c.strip() for h, c in zip(header, cells)}))
    if not rows:
        raise PartError(f"{path}: the table has no data rows")
    return header, rows


def family_command(args: argparse.Namespace) -> int:
    from ..cad import parse_set
    from ..io import write_atomic

    _header, rows = read_table(args.table)
    base_params = parse_set(args.params or [])
    opts = _options(args)
    out_dir = Path(args.out)
    base_number = args.program_number if args.program_number is not None else 1
    jobs: list[tuple] = []
    results: list[dict[str, Any]] = []
    for idx, line, cells in rows:
        if isinstance(cells, str):
            results.append({"row": idx, "line": line, "program_number": "", "status": "error",
                            "message": cells, "exit": 2})
            continue
        cells = dict(cells)
        num_s = cells.pop("program_number", "") or ""
        stock = cells.pop("stock", "") or args.stock
        try:
            number = int(num_s) if num_s else base_number + idx - 1
        except ValueError:
            results.append({"row": idx, "line": line, "program_number": num_s, "status": "error",
                            "message": f"{args.table}:{line}: program_number {num_s!r} is not an "
                                       f"integer", "exit": 2})
            continue
        params = dict(base_params)
        params.update({k: v for k, v in cells.items() if v != ""})
        jobs.append((idx, line, args.part, stock, params, number, opts))

    numbers = [j[5] for j in jobs]
    dup = {n for n in numbers if numbers.count(n) > 1}
    if dup:
        raise PlanError(f"{args.table}: program number(s) {sorted(dup)} appear in several rows")
    n_jobs = args.jobs or os.cpu_count() or 1
    results.extend(_run_jobs(jobs, n_jobs, opts))
    results.sort(key=lambda r: r["row"])
    out_dir.mkdir(parents=True, exist_ok=True)
    worst = 0
    fields = ["row", "program_number", "file", "status", "operations", "cycle_time_s",
              "verified", "max_overcut_mm", "max_undercut_mm", "message"]
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=fields, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    ok = 0
    for r in results:
        if r.get("status") == "ok":
            name = f"O{int(r['program_number']):04d}.nc"
            write_atomic(out_dir / name, r["text"])
            r["file"] = name
            ok += 1
        else:
            worst = max(worst, int(r.get("exit", 2)))
            print(f"error: {args.table} row {r['row']} (line {r['line']}): {r['message']}",
                  file=sys.stderr)
        w.writerow({k: r.get(k, "") for k in fields})
    write_atomic(out_dir / "summary.csv", buf.getvalue())
    if getattr(args, "report", None) or getattr(args, "junit", None):
        from ..report import family_outputs
        family_outputs(args, jobs, results)
    print(f"{ok} of {len(results)} program(s) written to {out_dir}"
          + (f", {len(results) - ok} failed" if ok < len(results) else ""), file=sys.stderr)
    return worst


def _run_jobs(jobs: list[tuple], n_jobs: int,
              opts: dict[str, Any] | None = None) -> list[dict[str, Any]]:
    if not jobs:
        return []
    progress = None
    if sys.stderr.isatty():
        from rich.console import Console
        from rich.progress import Progress
        progress = Progress(console=Console(stderr=True), transient=True)
    out: list[dict[str, Any]] = []
    task = None
    if progress is not None:
        progress.start()
        task = progress.add_task("generating", total=len(jobs))
    try:
        if n_jobs <= 1 or len(jobs) == 1:
            _init_worker(opts)
            for j in jobs:
                out.append(_row_job(j))
                if progress is not None:
                    progress.advance(task)
        else:
            from concurrent.futures import ProcessPoolExecutor, as_completed
            with ProcessPoolExecutor(max_workers=min(n_jobs, len(jobs)),
                                     initializer=_init_worker, initargs=(opts,)) as ex:
                futs = [ex.submit(_row_job, j) for j in jobs]
                for f in as_completed(futs):
                    out.append(f.result())
                    if progress is not None:
                        progress.advance(task)
    finally:
        if progress is not None:
            progress.stop()
    return out
