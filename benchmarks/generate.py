"""Benchmark of program generation.

* parts/s for a 200-row family of family 1 (parts/stepped_shaft.py) with --jobs 1 and
  --jobs 2, verification included (the default);
* ms per part for generate() alone, warm (CAD kernel imported, one part generated before
  timing), with and without verification, and per stage (part loading, planning, rendering,
  interpreter, simulation + verification);
* the same stages per dialect (HNC-21T, FANUC 0i-T, Haas) on the same part, each as a ratio to
  the HNC-21T figure measured in the same run (``--dialects``).

The machine's load average is printed with the figures: on a shared machine they scale with it.

Run: python benchmarks/generate.py [--rows 200] [--no-family] [--dialects-only]
"""
from __future__ import annotations

import argparse
import csv
import shutil
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
PART = REPO / "parts" / "stepped_shaft.py"


def table(path: Path, rows: int) -> None:
    with path.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["length", "d1", "d2", "program_number"])
        for i in range(rows):
            w.writerow([f"{95 + (i % 10)}", f"{18 + (i % 5) * 0.5:g}", f"{27 + (i % 3) * 0.5:g}",
                        1000 + i])


def family(rows: int, jobs: int) -> float:
    from hnc_cam.cli import main
    tmp = Path(tempfile.mkdtemp(prefix="hnc-bench-"))
    try:
        t = tmp / "t.csv"
        table(t, rows)
        t0 = time.perf_counter()
        rc = main(["family", str(PART), "--table", str(t), "--out", str(tmp / "out"),
                   "--jobs", str(jobs)])
        dt = time.perf_counter() - t0
        n = len(list((tmp / "out").glob("O*.nc")))
        if rc != 0 or n != rows:
            print(f"  warning: exit {rc}, {n} of {rows} programs written")
        return rows / dt
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def warm_generate(n: int, verify: bool) -> float:
    from hnc_cam.plan.api import generate
    generate(PART, verify=verify)  # warm-up: CAD kernel, templates, tool tables
    t0 = time.perf_counter()
    for i in range(n):
        generate(PART, params={"length": str(95 + i % 10)}, verify=verify)
    return (time.perf_counter() - t0) / n * 1000


def stages(n: int = 10, dialect: str = "hnc21t", raw: bool = False):
    """ms per part for each stage of generate (warm): part loading (CAD kernel), planning
    (with the tool-nose compensation), rendering in ``dialect``, the interpreter reading it as
    ``dialect``, simulation + verification. ``raw``: the seconds per stage (a dict)."""
    from hnc_cam.cad import load_part
    from hnc_cam.nc import run
    from hnc_cam.plan import Options, make_plan
    from hnc_cam.plan.api import _load_machine, _load_tools
    from hnc_cam.post import render
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Stock
    lib = _load_tools(None)
    mach = _load_machine(None, lib)
    t = dict.fromkeys(("load", "plan", "render", "interpret", "simulate", "verify"), 0.0)
    for i in range(n + 1):
        t0 = time.perf_counter()
        lp = load_part(str(PART), {"length": str(95 + i % 10)})
        t1 = time.perf_counter()
        st = Stock.parse(lp.stock)
        plan = make_plan(lp.profile, st, lib, mach, Options(), name="b")
        t2 = time.perf_counter()
        text = render(plan, dialect=dialect)
        t3 = time.perf_counter()
        tp = run(text, machine=mach, start="reference", dialect=dialect)
        t4 = time.perf_counter()
        sim = simulate(tp, st, machine=mach, model=plan.profile)
        t5 = time.perf_counter()
        verify(sim, plan.profile, tol=0.01)
        t6 = time.perf_counter()
        if i:  # the first round warms up
            for k, v in zip(t, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t5 - t4, t6 - t5)):
                t[k] += v
    total = sum(t.values())
    if raw:
        return {k: v / n for k, v in t.items()}
    return (", ".join(f"{k} {1000 * v / n:.1f} ({100 * v / total:.0f} %)" for k, v in t.items())
            + f"; total {1000 * total / n:.1f}")


def dialects(n: int = 15) -> list[str]:
    """The stages of :func:`stages` per dialect on the same part, each the median over ``n``
    rounds, with its ratio to HNC-21T's measured in this run (the dialects take turns within
    a round, in a rotating order, so that a change of the machine's load falls on every
    dialect alike)."""
    import statistics
    names = ("hnc21t", "fanuc0it", "haas")
    acc: dict[str, dict[str, list[float]]] = {d: {} for d in names}
    for i in range(n):
        for d in names[i % 3:] + names[:i % 3]:
            for k, v in stages(1, d, raw=True).items():
                acc[d].setdefault(k, []).append(v)
    med = {d: {k: statistics.median(v) for k, v in acc[d].items()} for d in names}
    ref = med["hnc21t"]
    out = []
    for d in names:
        total, rtotal = sum(med[d].values()), sum(ref.values())
        out.append(f"{d}: " + ", ".join(f"{k} {1000 * v:.1f} ms ({v / ref[k]:.2f}x)"
                                        for k, v in med[d].items())
                   + f"; total {1000 * total:.1f} ms ({total / rtotal:.2f}x)")
    return out


def cold_start() -> str:
    """What a fresh process pays once before its first row (a ``generate`` command every
    time; a family's fork server once for all its workers): interpreter start, the CAD
    kernel import, the rest of the generator's imports, the tables and templates, and the
    exit, when the interpreter tears the imported modules down (the kernel's tens of
    thousands of objects; :mod:`hnc_cam.cad.occ` freezes them out of the cyclic collector at
    exit); measured in child processes, best of 3. The exit is also measured without that
    freeze and with ``os._exit`` (no teardown at all)."""
    import subprocess
    code = (
        "import time, sys; t0 = time.perf_counter()\n"
        "import build123d\n"
        "t1 = time.perf_counter()\n"
        "from hnc_cam.plan.api import generate, warm; import hnc_cam.cad.extract, hnc_cam.nc, "
        "hnc_cam.sim\n"
        "t2 = time.perf_counter()\n"
        "warm()\n"
        "t3 = time.perf_counter()\n"
        "print(t1 - t0, t2 - t1, t3 - t2, time.time(), flush=True)\n"
        "if sys.argv[1] == 'teardown':\n"
        "    import atexit, hnc_cam.cad.occ; atexit.unregister(hnc_cam.cad.occ._quick_exit)\n"
        "elif sys.argv[1] == '_exit':\n"
        "    import os; os._exit(0)\n")

    def once(how: str) -> tuple[float, float, float, float, float]:
        t0 = time.perf_counter()
        out = subprocess.run([sys.executable, "-c", code, how], capture_output=True, text=True,
                             cwd=REPO, check=True).stdout.split()
        end = time.time()
        whole = time.perf_counter() - t0
        kernel, rest, tables, done = (float(x) for x in out)
        return whole, kernel, rest, tables, end - done

    def bare() -> float:
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], check=True)
        return time.perf_counter() - t0

    start = min(bare() for _ in range(3))
    runs = {how: min((once(how) for _ in range(3)), key=lambda r: r[0])
            for how in ("plain", "teardown", "_exit")}
    whole, kernel, rest, tables, exit_ = runs["plain"]
    return (f"process {1000 * whole:.0f} ms: interpreter start {1000 * start:.0f}, CAD kernel "
            f"import {1000 * kernel:.0f}, other imports {1000 * rest:.0f}, tables + templates "
            f"{1000 * tables:.0f}, exit {1000 * exit_:.0f} (the modules' teardown with the "
            f"collector's objects frozen at exit; {1000 * runs['teardown'][4]:.0f} without, "
            f"{1000 * runs['_exit'][4]:.0f} with no teardown at all, os._exit)")


def step_generate(n: int = 3) -> str:
    """Whole ``hnc-cam generate`` processes on a STEP file (best of n): without the profile
    cache, and a repeat with it (the CAD kernel is then neither imported nor run)."""
    import os
    import subprocess
    step = REPO / "tests" / "data" / "stepped_shaft.step"
    tmp = Path(tempfile.mkdtemp(prefix="hnc-bench-cache-"))
    try:
        def once(cache: bool) -> float:
            env = dict(os.environ)
            env.pop("HNC_CAM_PROFILE_CACHE", None)
            if cache:
                env["HNC_CAM_PROFILE_CACHE"] = str(tmp / "cache")
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "hnc_cam.cli", "generate", str(step),
                            "--stock", "45x120+2", "-o", str(tmp / "o.nc")], env=env,
                           check=True, capture_output=True)
            return time.perf_counter() - t0
        once(True)  # fills the cache
        plain = min(once(False) for _ in range(n))
        cached = min(once(True) for _ in range(n))
        return (f"{1000 * plain:.0f} ms without the cache, {1000 * cached:.0f} ms with a "
                f"cached profile ({plain / cached:.1f}x)")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=200)
    ap.add_argument("--no-family", action="store_true")
    ap.add_argument("--dialects-only", action="store_true",
                    help="only the per-dialect stages (ratios to HNC-21T)")
    a = ap.parse_args()
    import os
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    print("stages per dialect, ms/part (warm, ratio to hnc21t in this run):")
    for line in dialects():
        print(f"  {line}")
    if a.dialects_only:
        return
    print(f"generate, warm, family 1: {warm_generate(10, False):.1f} ms/part without "
          f"verification, {warm_generate(5, True):.1f} ms/part with verification")
    print(f"stages, ms/part (warm, share of the row): {stages()}")
    print(f"cold start, once per worker or generate command: {cold_start()}")
    print(f"generate of a STEP file, whole process, best of 3: {step_generate()}")
    if not a.no_family:
        for jobs in (1, 2):
            print(f"family of {a.rows} rows, --jobs {jobs}: {family(a.rows, jobs):.2f} parts/s "
                  f"(verification included)")


if __name__ == "__main__":
    main()
