"""Benchmark of program generation (issue 5).

* parts/s for a 200-row family of family 1 (parts/stepped_shaft.py) with --jobs 1 and
  --jobs 2, verification included (the default);
* ms per part for generate() alone, warm (CAD kernel imported, one part generated before
  timing), with and without verification.

Run: python benchmarks/generate.py [--rows 200] [--no-family]
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


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rows", type=int, default=200)
    ap.add_argument("--no-family", action="store_true")
    a = ap.parse_args()
    print(f"generate, warm, family 1: {warm_generate(10, False):.1f} ms/part without "
          f"verification, {warm_generate(5, True):.1f} ms/part with verification")
    if not a.no_family:
        for jobs in (1, 2):
            print(f"family of {a.rows} rows, --jobs {jobs}: {family(a.rows, jobs):.2f} parts/s "
                  f"(verification included)")


if __name__ == "__main__":
    main()
