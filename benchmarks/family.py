"""Benchmark of ``hnc-cam family``: rows/s on the local process pool and on a Dask
distributed cluster (``--scheduler``) of 1 and 2 worker processes on the loopback interface,
verification included, and the peak memory of the workers.

Each configuration runs the same table of family 1 (parts/stepped_shaft.py) ``--repeat``
times; the first run of a configuration starts cold (the local pool starts its workers, the
cluster's fresh workers import the CAD kernel with their first row), the best of the others is
the warm figure (a long-lived cluster). Every run's programs are compared with the first
local run's: they must be byte-identical.

The load average is printed beside the figures: on a shared machine they scale with it.

Run: python benchmarks/family.py [--rows 200] [--repeat 2] [--no-cluster]
"""
from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))
PART = REPO / "parts" / "stepped_shaft.py"


def run(table: Path, out: Path, extra: list[str]) -> tuple[float, dict[str, bytes]]:
    import contextlib
    import io
    from hnc_cam.cli import main
    shutil.rmtree(out, ignore_errors=True)
    err = io.StringIO()
    t0 = time.perf_counter()
    with contextlib.redirect_stderr(err):
        rc = main(["family", str(PART), "--table", str(table), "--out", str(out)] + extra)
    dt = time.perf_counter() - t0
    progs = {p.name: p.read_bytes() for p in out.glob("O*.nc")}
    if rc != 0:
        print(f"  warning: exit {rc}: {err.getvalue().strip()[:200]}")
    return dt, progs


def rss_mb(pids: list[int]) -> str:
    try:
        import psutil
    except ImportError:  # pragma: no cover
        return "n/a"
    out = []
    for pid in pids:
        try:
            out.append(psutil.Process(pid).memory_info().rss / 2**20)
        except psutil.Error:
            pass
    return "/".join(f"{m:.0f}" for m in out) + " MB" if out else "n/a"


def main() -> None:
    from generate import table as write_table
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--no-cluster", action="store_true")
    a = ap.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="hnc-bench-family-"))
    try:
        t = tmp / "t.csv"
        write_table(t, a.rows)
        print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; "
              f"{a.rows} rows, verification included")
        ref: dict[str, bytes] | None = None

        def report(name: str, times: list[float], progs_all: list[dict[str, bytes]],
                   mem: str) -> None:
            nonlocal ref
            for p in progs_all:
                if ref is None:
                    ref = p
                if p != ref:
                    print(f"  warning: {name}: programs differ from the local run")
            warm = min(times[1:]) if len(times) > 1 else times[0]
            print(f"{name:28s} cold {a.rows / times[0]:6.1f} rows/s ({times[0]:.1f} s), "
                  f"warm best of {max(1, len(times) - 1)} {a.rows / warm:6.1f} rows/s "
                  f"({warm:.1f} s); workers {mem}; load {os.getloadavg()[0]:.2f}")

        for jobs in (1, 2):
            times, progs = [], []
            for _ in range(a.repeat):
                dt, p = run(t, tmp / "out", ["--jobs", str(jobs)])
                times.append(dt)
                progs.append(p)
            report(f"local pool --jobs {jobs}", times, progs, "n/a (pool ends with the run)")
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
                for _ in range(a.repeat):
                    dt, p = run(t, tmp / "out", ["--scheduler", c.scheduler_address])
                    times.append(dt)
                    progs.append(p)
                with Client(c.scheduler_address, set_as_default=False) as cl:
                    pids = list(cl.run(os.getpid).values())
                report(f"dask cluster, {n} worker(s)", times, progs, rss_mb(pids))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
