"""Benchmark of ``hnc-cam family``: rows/s on the local process pool and on a Dask
distributed cluster (``--scheduler``) of 1 and 2 worker processes on the loopback interface,
verification included; the memory of each worker process; the per-row stages of the run.

Each configuration runs the same table of family 1 (parts/stepped_shaft.py) ``--repeat``
times. The first run of a configuration starts cold (the local pool starts its fork server,
which imports the generator and loads the part's nominal row once, the CAD kernel only when the
part needs it, none for family 1; the cluster's fresh workers import them with their first
row); the best of the others is the warm figure (the fork server, or a long-lived cluster,
already running). Every run's programs are compared with the first local run's: they must be
byte-identical.

Reference, measured in the same run: the local pool with workers forked from the family
process itself, each importing the CAD kernel on its own (``--jobs 2``); the pool's figures
are printed as ratios to it.

Memory: a thread samples every process under this one (psutil, every 0.2 s) and keeps each
one's peak resident set (RSS: every page it maps, shared or not), proportional set (PSS: a
shared page counted by the share of each process mapping it; the workers' PSS add up to the
memory they take) and unique set (USS: pages no other process maps). The fork server's pages
are shared by the workers forked from it.

The first row: the seconds from the command's start to its first row finished, cold (the
fork server importing the CAD kernel, the first fork) and warm.

Per-row stages: the seconds each written row spent loading the part (CAD kernel), planning,
rendering, in the interpreter, simulating and verifying (in the workers) and writing its
program (in the family process), summed over the rows of the warm run and divided by its rows,
with each stage's share: where the next speed-up has to come from.

The load average is printed beside the figures: on a shared machine they scale with it. The
workers' CPU per row (their user and system time, sampled with their memory, summed over the
run's workers and divided by its rows) changes much less with it than the wall figures and the
stages (wall time in the workers) do: the figure to compare two trees with on a busy machine.

With ``--baseline REV``, the local pool with ``--jobs 2`` only, for the current code and for
the code of git revision REV (exported with ``git archive`` into a temporary directory), each
run in a fresh process of this script, one after the other for ``--rounds`` rounds (each
``--repeat`` runs: cold, then warm), so that both see about the same load; printed: each
code's best cold and warm seconds and rows/s, the workers' CPU per row (cold, and the least
of the warm runs) and the stages of its best warm run, with the load beside them, and the
ratios REV/current.

Run: python benchmarks/family.py [--rows 200] [--repeat 2] [--no-cluster] [--no-reference]
     python benchmarks/family.py --rows 1000 --repeat 3 --baseline REV [--rounds 2]
"""
from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
#: the hnc_cam to measure: a baseline's exported tree (``--baseline``), else this checkout's
sys.path.insert(0, os.environ.get("HNC_BENCH_CODE") or str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))
PART = REPO / "parts" / "stepped_shaft.py"
STAGES = ("load", "plan", "render", "interpret", "simulate", "verify", "write")


class Memory:
    """Peak RSS, PSS and USS (MB) of every process under this one while it runs, and each one's
    CPU seconds (user and system) at its last sample (``used``). ``cpu``: the CPU seconds all
    samplers have spent (reading /proc/PID/smaps of a process that maps the CAD kernel costs
    milliseconds), taken out of the family process's CPU figure."""

    cpu = 0.0

    def __init__(self, period: float = 0.2):
        self.period = period
        self.peak: dict[int, list[float]] = {}
        self.used: dict[int, float] = {}
        self.names: dict[int, str] = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def __enter__(self) -> "Memory":
        try:
            import psutil  # noqa: F401
        except ImportError:  # pragma: no cover
            return self
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join()

    def _run(self) -> None:
        import psutil
        me = psutil.Process()
        while not self._stop.is_set():
            c0 = time.thread_time()
            try:
                kids = me.children(recursive=True)
            except psutil.Error:
                kids = []
            for p in kids:
                try:
                    m = p.memory_full_info()
                    if p.pid not in self.names:
                        self.names[p.pid] = " ".join(p.cmdline())
                    t = p.cpu_times()
                    self.used[p.pid] = t.user + t.system
                except psutil.Error:
                    continue
                old = self.peak.setdefault(p.pid, [0.0, 0.0, 0.0])
                for i, v in enumerate((m.rss, getattr(m, "pss", 0), m.uss)):
                    old[i] = max(old[i], v / 2 ** 20)
            Memory.cpu += time.thread_time() - c0
            self._stop.wait(self.period)

    def of(self, pids) -> str:
        rows = [self.peak[p] for p in pids if p in self.peak]
        if not rows:
            return "n/a"
        return ", ".join(f"{r:.0f}/{p:.0f}/{u:.0f}" for r, p, u in rows)

    def cpu_ms(self, pids, rows: int) -> str:
        """The CPU of the processes ``pids`` (at their last samples) in ms per row."""
        v = self.cpu_per_row(pids, rows)
        return "n/a" if v is None else f"{v:.1f}"

    def cpu_per_row(self, pids, rows: int) -> float | None:
        """:meth:`cpu_ms` as a number (None when not sampled)."""
        got = [self.used[p] for p in pids if p in self.used]
        return 1000 * sum(got) / rows if got and rows else None

    def server(self, workers) -> str:
        """The fork server(s): what runs the fork server's main and is no worker."""
        rows = [v for p, v in self.peak.items() if "forkserver" in self.names.get(p, "")
                and p not in workers]
        return ", ".join(f"{r:.0f}/{p:.0f}/{u:.0f}" for r, p, u in rows) or "none"


def run(table: Path, out: Path, extra: list[str]) -> tuple[float, dict[str, bytes], dict]:
    import contextlib
    import io
    from hnc_cam.cli import main
    from hnc_cam.plan import command
    shutil.rmtree(out, ignore_errors=True)
    err = io.StringIO()
    t0, c0, s0 = time.perf_counter(), time.process_time(), Memory.cpu
    with contextlib.redirect_stderr(err):
        rc = main(["family", str(PART), "--table", str(table), "--out", str(out)] + extra)
    dt = time.perf_counter() - t0
    cpu = time.process_time() - c0 - (Memory.cpu - s0)
    progs = {p.name: p.read_bytes() for p in out.glob("O*.nc")}
    if rc != 0:
        print(f"  warning: exit {rc}: {err.getvalue().strip()[:200]}")
    return dt, progs, dict(command.LAST_RUN, wall_s=dt, family_cpu_s=cpu)


def stage_line(last: dict) -> str:
    n = last.get("rows") or 0
    st = last.get("stages") or {}
    if not n:
        return "no row written"
    total = sum(st.values())
    return (", ".join(f"{k} {1000 * st.get(k, 0.0) / n:.1f} ({100 * st.get(k, 0.0) / total:.0f} %)"
                      for k in STAGES)
            + f"; total {1000 * total / n:.1f} ms of work per row")


def overhead_line(last: dict, jobs: int) -> str:
    """Where a row's wall time goes besides its stages: the family process's own CPU per row
    (submitting the rows, taking their results, writing the programs and summary.csv: on a
    machine with as many cores as workers it competes with them; the memory sampler's CPU
    left out), and the wall time times the
    workers less the stages' sum, per row (scheduling, pickling, waiting, the cold start)."""
    n = last.get("rows") or 0
    if not n or "wall_s" not in last:
        return "n/a"
    work = sum((last.get("stages") or {}).values()) - (last.get("stages") or {}).get("write", 0)
    return (f"family process CPU {1000 * last['family_cpu_s'] / n:.2f} ms per row; wall x "
            f"{jobs} worker(s) less the workers' stages {1000 * (last['wall_s'] * jobs - work) / n:.2f}"
            f" ms per row")


def first_line(cold: dict, warm: dict) -> str:
    """The seconds from the command's start to its first row finished: the cold start (the
    fork server's imports) and, for comparison, the warm run's."""
    def f(last: dict) -> str:
        v = last.get("first_row_s")
        return "n/a" if v is None else f"{v:.2f} s"
    return f"first row after {f(cold)} (cold), {f(warm)} (warm)"


def counts_line(last: dict) -> str:
    ws = (last.get("workers") or {}).values()
    return "; ".join(f"pid {w['pid']}: {w['inits']} init, kernel "
                     f"{w.get('kernel') or ('inherited' if w['kernel_inherited'] else 'imported')}"
                     f"{', warmed up by the fork server' if w.get('warmed') else ''}, "
                     f"{w['tools']} tool library, {w['machines']} machine, "
                     f"{w['environments']} template environment(s) loaded"
                     for w in ws) or "n/a"


def pool_figures(rows: int, repeat: int) -> dict:
    """One code's figures for :func:`baseline`: ``repeat`` runs of the local pool with
    ``--jobs 2`` on a table of ``rows`` rows (the first cold)."""
    from generate import table as write_table
    tmp = Path(tempfile.mkdtemp(prefix="hnc-bench-family-"))
    try:
        t = tmp / "t.csv"
        write_table(t, rows)
        load = os.getloadavg()[0]
        times, lasts = [], []
        with Memory() as mem:
            for _ in range(repeat):
                dt, _p, last = run(t, tmp / "out", ["--jobs", "2"])
                times.append(dt)
                lasts.append(last)
        cpu = [mem.cpu_per_row(x.get("workers", {}), x.get("rows") or 0) for x in lasts]
        warm = min(range(1, len(times)), key=times.__getitem__) if len(times) > 1 else 0
        n = lasts[warm].get("rows") or 1
        return {"cold_s": times[0], "warm_s": times[warm], "cpu_cold": cpu[0],
                "cpu_warm": min((c for c in cpu[1:] if c is not None), default=None),
                "stages": {k: 1000 * v / n for k, v in (lasts[warm].get("stages") or {}).items()},
                "load": (load + os.getloadavg()[0]) / 2, "rows": lasts[warm].get("rows")}
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def baseline(rev: str, rows: int, repeat: int, rounds: int) -> None:
    """The local pool (``--jobs 2``) of the current code and of git revision ``rev``'s, each
    run in a fresh process of this script, alternately for ``rounds`` rounds; each code's
    best figures and the ratios."""
    import json
    import subprocess
    from verify import _export
    code = _export(rev)
    res: dict[str, list[dict]] = {"current": [], rev: []}
    try:
        for _ in range(rounds):
            for name, d in (("current", None), (rev, code)):
                env = dict(os.environ)
                env.pop("HNC_BENCH_CODE", None)
                if d is not None:
                    env["HNC_BENCH_CODE"] = d
                out = subprocess.run([sys.executable, __file__, "--figures", str(rows),
                                      str(repeat)], capture_output=True, text=True, env=env,
                                     cwd=d or None)
                if out.returncode != 0:
                    raise SystemExit(f"error: the {name} code's run failed:\n{out.stderr}")
                res[name].append(json.loads(out.stdout.strip().splitlines()[-1]))
    finally:
        shutil.rmtree(code, ignore_errors=True)

    def best(rs: list[dict]) -> dict:
        def low(key: str) -> float:
            v = [r[key] for r in rs if r[key] is not None]
            return min(v) if v else math.nan
        warm = min(rs, key=lambda r: r["warm_s"])
        return {"cold_s": low("cold_s"), "warm_s": low("warm_s"), "cpu_cold": low("cpu_cold"),
                "cpu_warm": low("cpu_warm"), "stages": warm["stages"], "load": warm["load"],
                "loads": [r["load"] for r in rs]}

    import math
    print(f"local pool --jobs 2, {rows} rows, verification included; {rounds} round(s) of "
          f"{repeat} run(s) (cold, then warm) per code, one code after the other; best of the "
          f"rounds; load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    got = {}
    for name in ("current", rev):
        b = got[name] = best(res[name])
        label = "current" if name == "current" else f"baseline {rev}"
        print(f"  {label:>20}: cold {b['cold_s']:.1f} s ({rows / b['cold_s']:.1f} rows/s), "
              f"warm {b['warm_s']:.1f} s ({rows / b['warm_s']:.1f} rows/s); workers' CPU per "
              f"row {b['cpu_cold']:.1f} ms cold, {b['cpu_warm']:.1f} ms warm; load "
              + ", ".join(f"{x:.2f}" for x in b["loads"]))
        st = b["stages"]
        print(f"  {'':>20}  per row, ms: " + ", ".join(f"{k} {st.get(k, 0.0):.1f}"
                                                       for k in STAGES))
    c, r = got["current"], got[rev]
    print(f"  ratio baseline {rev} / current: cold x{r['cold_s'] / c['cold_s']:.2f}, warm "
          f"x{r['warm_s'] / c['warm_s']:.2f}, workers' CPU per row cold "
          f"x{r['cpu_cold'] / c['cpu_cold']:.2f}, warm x{r['cpu_warm'] / c['cpu_warm']:.2f}; "
          f"simulate+verify per row x{(r['stages'].get('simulate', 0) + r['stages'].get('verify', 0)) / max(1e-9, c['stages'].get('simulate', 0) + c['stages'].get('verify', 0)):.2f}")


def main() -> None:
    from generate import table as write_table
    if len(sys.argv) > 1 and sys.argv[1] == "--figures":  # a run of baseline(): one code
        import json
        print(json.dumps(pool_figures(int(sys.argv[2]), int(sys.argv[3]))))
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--no-cluster", action="store_true")
    ap.add_argument("--no-reference", action="store_true",
                    help="skip the reference pool (workers importing the kernel themselves)")
    ap.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--baseline", metavar="REV",
                    help="only the local pool with --jobs 2, for the current code and the code "
                         "of git revision REV, alternately (--rounds), and the ratios")
    ap.add_argument("--rounds", type=int, default=2,
                    help="with --baseline: rounds of one run of each code (default 2)")
    a = ap.parse_args()
    if a.baseline:
        baseline(a.baseline, a.rows, max(1, a.repeat), max(1, a.rounds))
        return
    tmp = Path(tempfile.mkdtemp(prefix="hnc-bench-family-"))
    try:
        t = tmp / "t.csv"
        write_table(t, a.rows)
        print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; "
              f"{a.rows} rows, verification included; memory per process as peak "
              f"RSS/PSS/USS MB")
        ref: dict[str, bytes] | None = None

        def report(name: str, times: list[float], progs_all: list[dict[str, bytes]],
                   mem: str, base: float | None = None) -> float:
            nonlocal ref
            for p in progs_all:
                if ref is None:
                    ref = p
                if p != ref:
                    print(f"  warning: {name}: programs differ from the local run")
            warm = min(times[1:]) if len(times) > 1 else times[0]
            ratio = (f" ({a.rows / times[0] / base:.2f}x the reference's cold)"
                     if base else "")
            print(f"{name:34s} cold {a.rows / times[0]:6.1f} rows/s ({times[0]:.1f} s){ratio}, "
                  f"warm best of {max(1, len(times) - 1)} {a.rows / warm:6.1f} rows/s "
                  f"({warm:.1f} s); load {os.getloadavg()[0]:.2f}")
            print(f"  {'':32s}workers {mem}")
            return a.rows / times[0]

        base = None
        if not a.no_reference:
            import multiprocessing as mp
            from hnc_cam.plan import command
            own, init = command.pool_context, command._init_worker

            def own_kernel(*a):  # each worker imports the CAD kernel itself
                init(*a)
                import build123d  # noqa: F401
            command.pool_context = lambda part=None: mp.get_context("fork")
            command._init_worker = own_kernel
            try:
                times, progs = [], []
                with Memory() as mem:
                    for _ in range(a.repeat):
                        dt, p, last = run(t, tmp / "out", ["--jobs", "2"])
                        times.append(dt)
                        progs.append(p)
                base = report("reference: fork, own kernel, -j2", times, progs,
                              mem.of(last.get("workers", {})))
            finally:
                command.pool_context, command._init_worker = own, init
        for jobs in a.jobs:
            times, progs, lasts = [], [], []
            with Memory() as mem:
                for _ in range(a.repeat):
                    dt, p, last = run(t, tmp / "out", ["--jobs", str(jobs)])
                    times.append(dt)
                    progs.append(p)
                    lasts.append(last)
            best = lasts[times.index(min(times[1:]))] if len(times) > 1 else lasts[0]
            pids = set()
            for last in lasts:
                pids.update(last.get("workers", {}))
            mem_s = ("in the family process" if jobs == 1 else
                     f"{mem.of(sorted(pids))}; fork server {mem.server(pids)}")
            report(f"local pool --jobs {jobs}", times, progs, mem_s,
                   base if jobs == 2 else None)
            print(f"  {'':32s}per row, ms: {stage_line(best)}")
            if jobs > 1:
                print(f"  {'':32s}workers' CPU per row, ms: cold "
                      f"{mem.cpu_ms(lasts[0].get('workers', {}), lasts[0].get('rows') or 0)}, "
                      f"warm " + ", ".join(mem.cpu_ms(x.get('workers', {}), x.get('rows') or 0)
                                           for x in lasts[1:]))
            print(f"  {'':32s}{first_line(lasts[0], best)}")
            print(f"  {'':32s}overhead: {overhead_line(best, jobs)}")
            print(f"  {'':32s}{counts_line(best)}")
        if a.no_cluster:
            return
        try:
            from distributed import Client, LocalCluster
        except ImportError:
            print("cluster: skipped (the distributed package is not installed: "
                  "pip install 'hnc_cam[cluster]')")
            return
        for n in (1, 2):
            with LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                              host="127.0.0.1", dashboard_address=None) as c:
                times, progs = [], []
                with Memory() as mem:
                    for _ in range(a.repeat):
                        dt, p, last = run(t, tmp / "out", ["--scheduler", c.scheduler_address])
                        times.append(dt)
                        progs.append(p)
                    with Client(c.scheduler_address, set_as_default=False) as cl:
                        pids = list(cl.run(os.getpid).values())
                report(f"dask cluster, {n} worker(s)", times, progs, mem.of(pids))
                print(f"  {'':32s}per row, ms: {stage_line(last)}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
