"""``hnc-cam generate`` and ``hnc-cam family``.

generate: writes the program to ``-o`` (atomically) or stdout and a one-line summary to
stderr. Exit 0, 1 when the program fails verification (nothing written), 2 on bad input.

family: one program per CSV row (columns: the part's parameters, optional ``program_number``
and ``stock``), ``DIR/O<number>.nc`` plus ``DIR/summary.csv`` (row, program_number, file,
status, operations, cycle_time_s, verified, max_overcut_mm, max_undercut_mm, message).
Rows run in worker processes (``--jobs``, default all cores) forked from a fork server that
imported the generator and the bundled tables and loaded the part's nominal row once (with the
CAD kernel only when the part needs it: :mod:`hnc_cam.plan.pool`;
spawned workers importing them in the pool initializer where there is no fork server), reused
for every row, or, with ``--scheduler tcp://HOST:PORT``,
as tasks on a Dask distributed cluster whose workers import them with their first row (the
CAD kernel with the first row that needs it; the
same progress bar, summary.csv, order and messages; identical programs). A bad row is reported (stderr and
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
                allowance=getattr(args, "allowance", None),
                dialect=getattr(args, "dialect", None), grip=getattr(args, "grip", None),
                partoff=not getattr(args, "no_partoff", False),
                partoff_dia=getattr(args, "partoff_dia", None),
                drill_style=getattr(args, "drill_style", "blocks") or "blocks")


def user_template_error(e: HncError, templates: Any) -> HncError:
    """A program rendered with a user's templates that raises an alarm is the templates'
    fault, not the generator's: name the template file and line that write the refused word
    (or the folder)."""
    from ..errors import NCError
    cause = e.__cause__
    if templates is None or not isinstance(cause, NCError):
        return e
    from ..post import blame_user_template
    place = blame_user_template(templates, cause.block, cause.col)
    where = place or f"templates folder {templates}"
    return PlanError(f"{where}: the program these templates write raises an alarm at its line "
                     f"{cause.line}: {cause.message} [{cause.block.strip()[:80]}]")


def generate_command(args: argparse.Namespace) -> int:
    try:
        return _generate_command(args)
    except PlanError as e:
        raise user_template_error(e, getattr(args, "templates", None)) from None


def _generate_command(args: argparse.Namespace) -> int:
    from ..cad import load_part, parse_set
    from ..cad.loader import profile_options
    from ..io import write_atomic
    from .api import generate
    from .export import is_folder_target, write_program_folder

    params = parse_set(args.params or [])
    if getattr(args, "json", None) == "-" and not args.output:
        raise PlanError("--json - writes the plan to stdout, where the program goes without "
                        "-o: give the program a file with -o (or the JSON a file)")
    part: Any = args.part
    kw = profile_options(args)
    if kw:  # --axis/--zero/--envelope/--fit-tol: profile here, then plan the loaded part
        part = load_part(args.part, params, **kw)
        params = {}
    if getattr(args, "setups", 1) == 2:
        return _generate_setups(args, part, params)
    from ..report import failure_report
    with failure_report(args):  # --report: the page of a program refused by verification
        prog = generate(part, args.stock, params=params, program_number=args.program_number,
                        file=args.output or "<stdout>", **_options(args))
    if args.output and prog.dialect == "siemens802" and is_folder_target(args.output):
        # -o DIR/: the main program and each subprogram in its own file (NAME.MPF,
        # NAME_C1.SPF, ...), all or none
        write_program_folder(args.output, prog.text)
    elif args.output:
        write_atomic(args.output, prog.text)
    else:
        sys.stdout.write(prog.text)
        sys.stdout.flush()
    if getattr(args, "report", None):
        from ..report import program_report
        program_report(args.report, prog, tol=getattr(args, "tol", 0.01))
    if getattr(args, "json", None):
        from .export import plan_json_text
        write_atomic(args.json, plan_json_text(prog))
    if getattr(args, "explain", False):
        print(prog.plan.explain(prog.labels), file=sys.stderr)
    print(prog.summary(), file=sys.stderr)
    for w in prog.warnings:
        print(f"warning: {w}", file=sys.stderr)
    return 0


def _generate_setups(args: argparse.Namespace, part: Any, params: dict) -> int:
    """``generate --setups 2 -o DIR/``: the two programs of a part turned around for its left
    end (:mod:`hnc_cam.plan.setups`), written as ``DIR/O<n>.nc`` and ``DIR/O<n+1>.nc`` (the
    802: ``NAME.MPF``, ``NAME_2.MPF`` and their subprogram files), all or none."""
    from .export import is_folder_target, write_files
    from .setups import generate_setups
    if not args.output or not is_folder_target(args.output):
        raise PlanError("--setups 2 writes two programs: give -o DIR/ (a folder)")
    for opt in ("json", "report"):
        if getattr(args, opt, None):
            raise PlanError(f"--{opt} is not written for --setups 2 (two programs); verify them "
                            f"with hnc-cam verify P1 P2 --model PART")
    opts = _options(args)
    opts.pop("grip", None)
    res = generate_setups(part, args.stock, params=params, program_number=args.program_number,
                          file=args.output, grip=getattr(args, "grip", None),
                          grip2=getattr(args, "grip2", None), **opts)
    n = res.first.plan.program_number
    if res.first.dialect == "siemens802":  # NAME.MPF, NAME_2.MPF and their subprograms
        from .export import split_programs
        files = split_programs(res.first.text) + split_programs(res.second.text)
    else:
        files = [(f"O{n:04d}.nc", res.first.text), (f"O{n + 1:04d}.nc", res.second.text)]
    write_files(args.output, files)
    if getattr(args, "explain", False):
        print(res.first.plan.explain(res.first.labels), file=sys.stderr)
        print(res.second.plan.explain(res.second.labels), file=sys.stderr)
    for prog in res.programs:
        print(prog.summary(), file=sys.stderr)
    for prog in res.programs:
        for w in prog.warnings:
            print(f"warning: {w}", file=sys.stderr)
    return 0


# ------------------------------------------------------------------------------------------
# family
# ------------------------------------------------------------------------------------------

#: how many times this process ran the worker initializer (a reused worker reports 1)
_INITS = 0
#: the process that counted _INITS (a forked worker starts its own count at 0)
_INIT_PID: list[int | None] = [None]


def _inits() -> int:
    """How many times this process ran the worker initializer."""
    return _INITS if _INIT_PID[0] == os.getpid() else 0


def _bind_to_parent(family: int) -> None:
    """In a worker: ignore Ctrl-C and SIGTERM's default for the group (the family process
    decides), and die with the family process, even when it is killed with SIGKILL. The
    worker's parent is the family process or the fork server it started (which leaves when
    the family process goes): the kernel's parent-death signal on Linux, and a watchdog
    thread that exits when the parent changes."""
    import signal
    import threading
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    parent = os.getppid()
    if sys.platform.startswith("linux"):
        try:
            import ctypes
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):  # pragma: no cover - the watchdog still runs
            pass
    if not _descends_from(parent, family):  # the parent died before the line above
        os._exit(1)

    def watch() -> None:
        # a fork server's worker holds the server's pipe and its task queue's both ends:
        # neither tells it that the family process is gone; the watchdog does
        import time
        while True:
            time.sleep(0.5)
            if os.getppid() != parent or (parent != family and not _alive(family)):
                os._exit(1)

    threading.Thread(target=watch, name="parent-watchdog", daemon=True).start()


def _alive(pid: int) -> bool:
    """Whether process ``pid`` runs (a zombie, killed but not yet waited for, does not)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        return state not in ("Z", "X")
    except OSError:
        if sys.platform.startswith("linux"):
            return False
    except (IndexError, ValueError):  # pragma: no cover - a /proc of another format
        pass
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        pass
    return True


def _descends_from(parent: int, family: int) -> bool:
    """``parent`` is the family process or a child of it (the fork server); where /proc
    cannot say, True."""
    if parent == family:
        return True
    try:
        stat_ = Path(f"/proc/{parent}/stat").read_text()
    except OSError:
        return not sys.platform.startswith("linux")
    try:
        return int(stat_.rsplit(")", 1)[1].split()[1]) == family
    except (IndexError, ValueError):  # pragma: no cover - a /proc of another format
        return True


class _Interrupted(Exception):
    """Ctrl-C or SIGTERM during the rows: the rows finished so far, and the signal."""

    def __init__(self, done: list[dict[str, Any]], signum: int):
        super().__init__(signum)
        self.done = done
        self.signum = signum


def _check_part_file(path: str) -> None:
    """File-level faults of the part, found once before any row runs (not once per row):
    missing, not a regular file, not UTF-8, a NUL byte, a Python syntax error."""
    import stat
    from ..cad.loader import CAD_SUFFIXES
    try:
        st = os.stat(path)
    except OSError as e:
        raise PartError(f"{path}: cannot read the part file: {e.strerror or e}") from None
    if stat.S_ISDIR(st.st_mode):
        raise PartError(f"{path}: is a directory, not a part file")
    if not stat.S_ISREG(st.st_mode):
        raise PartError(f"{path}: not a regular file")
    suffix = Path(path).suffix.lower()
    if suffix in CAD_SUFFIXES:
        return
    if suffix != ".py":
        raise PartError(f"{path}: a part file is a .py module (or a .step/.stp/.brep file)")
    from ..io import read_text
    src = read_text(path, "a Python part file", PartError)
    import ast
    try:
        tree = ast.parse(src, path)
    except SyntaxError as e:
        raise PartError(f"{path}:{e.lineno or 0}:{e.offset or 0}: {e.msg}") from None
    except (ValueError, RecursionError, MemoryError) as e:
        raise PartError(f"{path}: not a Python file: {e}") from None
    names = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update((a.asname or a.name).split(".")[0] for a in node.names)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            names.update(t.id for t in targets if isinstance(t, ast.Name))
        else:  # conditional definitions and the like: the loader decides
            names.add("part")
    if "part" not in names and "*" not in names:
        raise PartError(f"{path}: defines no function part(**params)")


def _check_tables(args: argparse.Namespace) -> None:
    """The tool library, the machine file and the templates folder, checked once before any
    row runs (an error in them is one line, not one per row)."""
    from ..tooling import load_machine, load_tools
    lib = load_tools(args.tools) if getattr(args, "tools", None) else None
    load_machine(getattr(args, "machine", None), lib)
    tpl = getattr(args, "templates", None)
    if tpl is not None and not Path(tpl).is_dir():
        raise PlanError(f"templates folder {tpl}: not a directory")


def _prepare_out(out: str) -> Path:
    """The output folder, created and writable (else one line, before any row runs)."""
    from ..io import clean_stale_temporaries
    d = Path(out)
    try:
        d.mkdir(parents=True, exist_ok=True)
        if not os.access(d, os.W_OK | os.X_OK):
            raise PermissionError(13, "Permission denied")
        probe = d / f".probe.{os.getpid()}.tmp"
        probe.write_bytes(b"")
        probe.unlink()
    except FileExistsError:
        raise HncError(f"--out {out}: cannot create the folder: a file is in the way") from None
    except OSError as e:
        raise HncError(f"--out {out}: cannot write there: {e.strerror or e}") from None
    clean_stale_temporaries(d)
    return d


def _init_worker(opts: dict[str, Any] | None = None, family: int | None = None,
                 environ: dict[str, str] | None = None) -> None:
    """Once per worker process: bind it to the family process ``family`` (see
    :func:`_bind_to_parent`), take the family process's environment ``environ`` (a worker
    forked from the fork server has the server's), import the interpreter and the simulator
    (already there in a worker forked from the fork server, which imported them and loaded the
    family's part: :mod:`hnc_cam.plan.pool`), and load the tool library, the machine and the
    templates (cached in :mod:`hnc_cam.plan.api` for every row the worker runs). The CAD
    kernel is not imported here: the first row whose part needs it does (none, for a family
    whose ``part()`` returns ``revolve(outline)``), unless the fork server already has."""
    global _INITS
    if _INIT_PID[0] != os.getpid():
        _INITS, _INIT_PID[0] = 0, os.getpid()
        _KERNEL_INHERITED[0] = "OCP" in sys.modules
    _INITS += 1
    if family is not None and os.getpid() != family:
        _bind_to_parent(family)
    if environ is not None and environ != os.environ:
        os.environ.clear()
        os.environ.update(environ)
    try:
        from .. import cad  # noqa: F401
        from ..cad import extract  # noqa: F401
        from .. import nc, sim  # noqa: F401
    except Exception:  # pragma: no cover - the row reports the real error
        pass
    if opts:
        try:
            from .api import warm
            warm(opts.get("tools"), opts.get("machine"), opts.get("templates"),
                 opts.get("number_format", "plain"), opts.get("block_numbers", "every"),
                 opts.get("dialect"))
        except Exception:  # pragma: no cover - the rows report the real error
            pass


#: whether this worker process found the CAD kernel already imported when it started (a
#: fork of the fork server) rather than importing it itself
_KERNEL_INHERITED: list[bool] = [False]


def _kernel() -> str:
    """Where this worker's CAD kernel came from: ``inherited`` (imported by the fork server
    before the fork), ``not needed`` (no row of this worker has used it: a family whose
    ``part()`` returns ``revolve(outline)``), ``imported`` (by this worker)."""
    if _KERNEL_INHERITED[0]:
        return "inherited"
    return "imported" if "OCP" in sys.modules else "not needed"


def worker_counts() -> dict[str, Any]:
    """What this process has loaded so far, to show that a worker loads each thing once
    however many rows it runs: pid, initializer runs, where its CAD kernel came from
    (``kernel``: :func:`_kernel`; ``kernel_inherited``: it did not import it itself),
    whether the fork server's warm-up program did (``warmed``: the modules the
    generator imports on first use and the compiled templates), tool libraries and machine files parsed, template environments built, and its
    peak resident memory (MB)."""
    from .api import LOADS
    from ..post import environment
    try:
        import resource
        peak: float | None = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    except ImportError:  # pragma: no cover - Windows
        peak = None
    pool = sys.modules.get(POOL_PRELOAD)
    kernel = _kernel()
    return {"pid": os.getpid(), "inits": _inits(), "kernel_inherited": kernel != "imported",
            "kernel": kernel,
            "warmed": bool(pool is not None and pool.WARMED[0]),
            "tools": LOADS["tools"], "machines": LOADS["machines"],
            "environments": environment.cache_info().misses,
            "peak_rss_mb": (None if peak is None else
                            peak / (2 ** 20 if sys.platform == "darwin" else 2 ** 10))}


def _row_job(job: tuple) -> dict[str, Any]:
    """Generate one row; never raises (the error becomes the row's result). The result
    carries the seconds of each stage of the row (``stages``) and :func:`worker_counts`."""
    import time
    idx, line, part, stock, params, number, opts = job
    out: dict[str, Any] = {"row": idx, "line": line, "program_number": number,
                           "worker": (os.getpid(), _inits())}
    opts = dict(opts)
    kw = opts.pop("profile", None)
    try:
        from .api import VerificationError, generate
        t0 = time.perf_counter()
        if kw:
            from ..cad import load_part
            part = load_part(part, params, **kw)
            params = {}
        loaded = time.perf_counter() - t0
        prog = generate(part, stock, params=params, program_number=number,
                        file=f"O{number:04d}.nc", **opts)
        rep = prog.report
        stages = dict(prog.stages)
        stages["load"] = stages.get("load", 0.0) + loaded
        out.update(status="ok", text=prog.text, operations=" ".join(prog.operations),
                   cycle_time_s=round(prog.cycle_time_s, 1),
                   verified=("pass" if rep is not None else "skipped"),
                   max_overcut_mm=(round(rep.max_overcut_mm, 4) if rep is not None else ""),
                   max_undercut_mm=(round(rep.max_undercut_mm, 4) if rep is not None else ""),
                   message="", stages=stages)
    except VerificationError as e:
        out.update(status="failed", message=str(e), verified="fail", exit=1)
    except HncError as e:
        out.update(status="error", message=str(user_template_error(e, opts.get("templates"))),
                   exit=2)
    except Exception as e:  # a generator bug must not stop the other rows
        out.update(status="error", message=f"internal error: {type(e).__name__}: {e}", exit=2)
    try:
        out["counts"] = worker_counts()
    except Exception:  # pragma: no cover - the counts only inform; the row stands
        pass
    return out


def read_table(path: str) -> tuple[list[str], list[tuple[int, int, dict[str, str] | str]]]:
    """Rows of the CSV: (row index from 1, file line, cells or an error message)."""
    from ..io import read_text
    text = read_text(path, "a CSV table", PartError, 64 * 1024 * 1024)
    rdr = csv.reader(io.StringIO(text))
    try:
        header = next(rdr)
    except StopIteration:
        raise PartError(f"{path}: the table is empty (no header row)") from None
    except csv.Error as e:
        raise PartError(f"{path}:{rdr.line_num}: not a CSV table: {e}") from None
    header = [h.strip() for h in header]
    if not header or any(not h for h in header):
        raise PartError(f"{path}:1: the header has an empty column name")
    if len(set(header)) != len(header):
        raise PartError(f"{path}:1: the header names a column twice")
    rows: list[tuple[int, int, dict[str, str] | str]] = []
    n = 0
    while True:
        try:
            cells = next(rdr)
        except StopIteration:
            break
        except csv.Error as e:
            raise PartError(f"{path}:{rdr.line_num}: not a CSV table: {e}") from None
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
    import signal
    import time

    started = time.perf_counter()
    first: list[float] = []  # seconds from the start to the first row finished

    from ..cad import parse_set
    from ..cad.loader import profile_options
    from ..io import write_atomic

    if getattr(args, "macro", False):
        from .macro_command import macro_command
        return macro_command(args)
    for opt, v in (("-o/--output", getattr(args, "output", None)),
                   ("--check", getattr(args, "check", None))):
        if v is not None:
            raise PlanError(f"{opt} belongs to --macro; the per-row mode writes to --out DIR")
    missing = [o for o, v in (("--table", args.table), ("--out", args.out)) if v is None]
    if missing:
        raise PlanError(f"family needs {' and '.join(missing)} (or --macro for one macro "
                        f"program)")
    _check_part_file(args.part)
    _check_tables(args)
    _header, rows = read_table(args.table)
    base_params = parse_set(args.params or [])
    opts = _options(args)
    kw = profile_options(args)
    if kw:
        opts["profile"] = kw
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
    if not getattr(args, "scheduler", None) and n_jobs > 1 and len(jobs) > 1:
        start_pool_server(args.part)  # loads the part while the output folder is prepared
    out_dir = _prepare_out(args.out)

    def done(r: dict[str, Any]) -> None:  # each program is written as soon as its row ends
        if not first:
            first.append(time.perf_counter() - started)
        if r.get("status") == "ok":
            t0 = time.perf_counter()
            name = f"O{int(r['program_number']):04d}.nc"
            write_atomic(out_dir / name, r["text"], clean_folder=False)  # cleaned by _prepare_out
            r["file"] = name
            r.setdefault("stages", {})["write"] = time.perf_counter() - t0

    interrupted = 0
    try:
        results.extend(_run_jobs(jobs, n_jobs, opts, on_done=done,
                                 scheduler=getattr(args, "scheduler", None)))
    except _Interrupted as e:
        interrupted = e.signum
        results.extend(e.done)
        finished = {r["row"] for r in results}
        for j in jobs:
            if j[0] not in finished:
                results.append({"row": j[0], "line": j[1], "program_number": j[5],
                                "status": "interrupted", "exit": 2,
                                "message": f"not finished: interrupted by "
                                           f"{signal.Signals(e.signum).name}"})
    results.sort(key=lambda r: r["row"])
    _record_run(results, first[0] if first else None)
    worst = 0
    fields = ["row", "program_number", "file", "status", "operations", "cycle_time_s",
              "verified", "max_overcut_mm", "max_undercut_mm", "message"]
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=fields, extrasaction="ignore", lineterminator="\n")
    w.writeheader()
    ok = 0
    errors: dict[str, list[dict[str, Any]]] = {}  # one line per distinct message
    for r in results:
        if r.get("status") == "ok":
            ok += 1
        elif r.get("status") != "interrupted":
            worst = max(worst, int(r.get("exit", 2)))
            errors.setdefault(str(r["message"]), []).append(r)
        w.writerow({k: r.get(k, "") for k in fields})
    write_atomic(out_dir / "summary.csv", buf.getvalue())
    for msg, rs in errors.items():
        which = (f"row {rs[0]['row']} (line {rs[0]['line']})" if len(rs) == 1 else
                 f"rows {', '.join(str(r['row']) for r in rs)}")
        print(f"error: {args.table} {which}: {msg}", file=sys.stderr)
    if getattr(args, "report", None) or getattr(args, "junit", None):
        from ..report import family_outputs
        family_outputs(args, jobs, results)
    if interrupted:
        print(f"interrupted ({signal.Signals(interrupted).name}): {ok} of {len(results)} "
              f"program(s) written to {out_dir}; {out_dir / 'summary.csv'} lists the rows not "
              f"finished", file=sys.stderr)
        return 128 + interrupted
    if not errors or ok:
        print(f"{ok} of {len(results)} program(s) written to {out_dir}"
              + (f", {len(results) - ok} failed" if ok < len(results) else ""), file=sys.stderr)
    return worst


#: the last family run in this process (what ``benchmarks/family.py`` prints): ``stages``,
#: the seconds of each stage (load, plan, render, interpret, simulate, verify, write) summed
#: over the rows written; ``rows``, how many; ``workers``, each worker process's last
#: :func:`worker_counts` by pid; ``first_row_s``, the seconds from the command's start to
#: its first row finished (the cold start: the fork server's imports, the first fork)
LAST_RUN: dict[str, Any] = {}


def _record_run(results: list[dict[str, Any]], first_row_s: float | None = None) -> None:
    stages: dict[str, float] = {}
    workers: dict[int, dict[str, Any]] = {}
    rows = 0
    for r in results:
        if r.get("stages") and r.get("status") == "ok":
            rows += 1
            for k, v in r["stages"].items():
                stages[k] = stages.get(k, 0.0) + v
        c = r.get("counts")
        if c:  # the counts only grow: a worker's largest are its last
            w = workers.setdefault(c["pid"], dict(c))
            for k, v in c.items():
                if isinstance(v, (int, float)) and not isinstance(v, bool):
                    w[k] = max(w[k] or 0, v)
    LAST_RUN.clear()
    LAST_RUN.update(stages=stages, rows=rows, workers=workers, first_row_s=first_row_s)


def _run_jobs(jobs: list[tuple], n_jobs: int, opts: dict[str, Any] | None = None,
              on_done: Any = None, scheduler: str | None = None) -> list[dict[str, Any]]:
    """Run the rows (in worker processes for ``n_jobs`` > 1, or on the Dask cluster whose
    scheduler listens at ``scheduler``); ``on_done(result)`` in this process as each ends.
    Ctrl-C or SIGTERM stops the workers (cancels the cluster's rows) and raises
    :class:`_Interrupted` with the rows finished so far."""
    import signal
    if not jobs:
        return []
    out: list[dict[str, Any]] = []

    def on_term(signum, _frame):
        raise _Interrupted(out, signum)

    old_term = signal.signal(signal.SIGTERM, on_term)
    try:
        if scheduler:
            return _run_cluster(jobs, scheduler, opts, on_done, out)
        return _run_pool(jobs, n_jobs, opts, on_done, out)
    except KeyboardInterrupt:
        raise _Interrupted(out, signal.SIGINT) from None
    finally:
        signal.signal(signal.SIGTERM, old_term)


class _Finished:
    """Where a finished row goes: the caller's ``on_done``, the result list, and the rich
    progress bar on stderr when it is a terminal."""

    def __init__(self, total: int, on_done: Any, out: list[dict[str, Any]]):
        self.on_done, self.out = on_done, out
        self.progress = self.task = None
        if sys.stderr.isatty():
            from rich.console import Console
            from rich.progress import Progress
            self.progress = Progress(console=Console(stderr=True), transient=True)
            self.progress.start()
            self.task = self.progress.add_task("generating", total=total)

    def add(self, r: dict[str, Any]) -> None:
        from ..io import signals_held
        with signals_held():  # a program written is a row recorded, even under Ctrl-C
            if self.on_done is not None:
                self.on_done(r)
            self.out.append(r)
        if self.progress is not None:
            self.progress.advance(self.task)

    def stop(self) -> None:
        if self.progress is not None:
            self.progress.stop()


#: what the fork server imports before it forks the workers
POOL_PRELOAD = "hnc_cam.plan.pool"
#: environment variable naming the family's part file to the fork server as it starts
POOL_PART_ENV = "HNC_CAM_POOL_PART"


def pool_context(part: str | os.PathLike | None = None) -> Any:
    """The multiprocessing context of the local pool: workers forked from a fork server that
    imported the generator and the bundled tables once and loaded the family's ``part``
    with its defaults (:mod:`hnc_cam.plan.pool`; without ``part``, the CAD kernel): no worker
    imports what its rows need itself, the workers share its memory (copy on write), and the
    family process stays free of it. The server is started here when it does not run yet (it
    imports in the background; the pool's first worker waits for it). Where there is no fork
    server (Windows) or it cannot start (no folder for its socket), spawned workers that
    import the kernel in their initializer."""
    import multiprocessing as mp
    if "forkserver" in mp.get_all_start_methods():
        from multiprocessing import forkserver
        ctx = mp.get_context("forkserver")
        ctx.set_forkserver_preload([POOL_PRELOAD])
        old = os.environ.pop(POOL_PART_ENV, None)
        if part is not None:  # read by the server as it starts; not left to anyone else
            os.environ[POOL_PART_ENV] = os.path.abspath(part)
        try:
            forkserver.ensure_running()
            return ctx
        except OSError:
            pass
        finally:
            os.environ.pop(POOL_PART_ENV, None)
            if old is not None:
                os.environ[POOL_PART_ENV] = old
    return mp.get_context("spawn")


def start_pool_server(part: str | os.PathLike | None = None) -> None:
    """Start the fork server now, so that it loads ``part`` (or imports the CAD kernel)
    while this process gets on with the rows' preparation (see :func:`pool_context`)."""
    pool_context(part)


def _run_pool(jobs: list[tuple], n_jobs: int, opts: dict[str, Any] | None, on_done: Any,
              out: list[dict[str, Any]]) -> list[dict[str, Any]]:
    finished = _Finished(len(jobs), on_done, out)
    try:
        if n_jobs <= 1 or len(jobs) == 1:
            _init_worker(opts)
            for j in jobs:
                finished.add(_row_job(j))
        else:
            from concurrent.futures import ProcessPoolExecutor, as_completed
            ex = ProcessPoolExecutor(max_workers=min(n_jobs, len(jobs)),
                                     mp_context=pool_context(jobs[0][2]),
                                     initializer=_init_worker,
                                     initargs=(opts, os.getpid(), dict(os.environ)))
            try:
                futs = [ex.submit(_row_job, j) for j in jobs]
                for f in as_completed(futs):
                    finished.add(f.result())
            except BaseException:
                procs = list((getattr(ex, "_processes", None) or {}).values())
                ex.shutdown(wait=False, cancel_futures=True)
                for p in procs:
                    try:
                        p.kill()
                        p.join(5)
                    except (OSError, ValueError, AssertionError):
                        pass
                raise
            ex.shutdown(wait=True)
    finally:
        finished.stop()
    return out


# ------------------------------------------------------------------------------------------
# family on a Dask distributed cluster
# ------------------------------------------------------------------------------------------

def _cluster_row_job(job: tuple) -> dict[str, Any]:
    """One row on a Dask worker. The first row a worker process runs imports the interpreter
    and the simulator and loads the tables (module state, so a long-lived worker does it once
    for all the families it runs; the tables are reloaded only when their file changes); the
    CAD kernel is imported by the first row whose part needs it (none for a family whose
    ``part()`` returns ``revolve(outline)``); then as :func:`_row_job`."""
    if _inits() == 0:
        _init_worker(job[6])
    return _row_job(job)


#: seconds to wait for the Dask scheduler to answer
CONNECT_TIMEOUT_S = 10.0


def _cluster_client(scheduler: str) -> Any:
    """A client of the Dask scheduler at ``scheduler`` (one line when distributed is absent or
    the scheduler does not answer)."""
    try:
        from distributed import Client
    except ImportError:
        raise HncError(f"--scheduler {scheduler}: the distributed package is not installed "
                       f"(pip install 'hnc_cam[cluster]')") from None
    try:
        return Client(scheduler, timeout=CONNECT_TIMEOUT_S, set_as_default=False)
    except (OSError, TimeoutError) as e:
        raise HncError(f"--scheduler {scheduler}: cannot connect to the Dask scheduler: "
                       f"{str(e).splitlines()[0] if str(e) else type(e).__name__}") from None


def _run_cluster(jobs: list[tuple], scheduler: str, opts: dict[str, Any] | None, on_done: Any,
                 out: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The rows as tasks on a Dask cluster: the same results, progress bar and on_done as the
    local pool; a row whose worker is lost becomes that row's error. The part file, the tool
    library, the machine file and the templates are read by the workers at the paths given
    (the same files on every machine: a shared folder)."""
    import uuid
    # workers may run in another folder: they get absolute paths, and the messages they
    # return name the files as the user gave them
    given: dict[str, str] = {}

    def absolute(path: Any) -> Any:
        if path is None or os.path.isabs(str(path)):
            return path
        given[os.path.abspath(str(path))] = str(path)
        return os.path.abspath(str(path))

    wopts = dict(opts or {})
    for k in ("tools", "machine", "templates"):
        wopts[k] = absolute(wopts.get(k))
    sent = [(j[0], j[1], absolute(j[2]), j[3], j[4], j[5], wopts) for j in jobs]
    client = _cluster_client(scheduler)
    finished = _Finished(len(jobs), on_done, out)
    futs: list[Any] = []
    try:
        from distributed import as_completed
        tag = uuid.uuid4().hex[:12]
        futs = [client.submit(_cluster_row_job, j, key=f"hnc-family-{tag}-{j[0]}", pure=False)
                for j in sent]
        by_key = {f.key: j for f, j in zip(futs, jobs)}
        for f in as_completed(futs, loop=client.loop):
            try:
                r = f.result()
            except Exception as e:  # the worker died or the task could not run
                j = by_key[f.key]
                msg = str(e).splitlines()[0] if str(e) else ""
                r = {"row": j[0], "line": j[1], "program_number": j[5], "status": "error",
                     "exit": 2, "message": f"cluster error: {type(e).__name__}: {msg}".rstrip()}
            if r.get("message"):
                for full, as_given in given.items():
                    r["message"] = r["message"].replace(full, as_given)
            finished.add(r)
    except BaseException:
        try:
            client.cancel(futs, force=True)
        except Exception:  # pragma: no cover - the client is closed below anyway
            pass
        raise
    finally:
        finished.stop()
        try:
            client.close(timeout=10)
        except Exception:  # pragma: no cover - closing a client whose scheduler went away
            pass
    return out
