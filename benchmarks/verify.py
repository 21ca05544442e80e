"""Benchmark: simulate + verify time and peak memory for programs of about 1,000, 10,000 and
100,000 moves.

The program is macro-generated (WHILE loops): K passes along a fine wavy profile of 1,000 G01
segments over 50 mm (X = 30 + 0.2 sin(Z/2) diameter plus the pass's allowance), stepping in from a
40 mm bar, so every pass removes material; K = 1, 10, 100 gives the three sizes. The model is
the final profile (1,000 exact lines). Each size runs in its own process so that the peak
resident memory (ru_maxrss, which includes GEOS) is its own.

Two verifications per size: with a sharp tool (the program lands on the model: the report
passes) and with the default library's 0.8 mm nose on the same tip path (uncompensated: the
report fails, and the leftover is classified reachable/unreachable, the expensive branch).

    python benchmarks/verify.py            # all three sizes
    python benchmarks/verify.py 1 10       # chosen pass counts
    python benchmarks/verify.py --shaft    # only the per-part figure for parts/stepped_shaft.py

Prints per size: moves, interpreter time, simulate time, verify time, peak memory, and the
growth factor of simulate+verify time per 10x moves; then (all sizes run) the per-part
simulate and verify time of generated programs for parts/stepped_shaft.py.
"""
from __future__ import annotations

import json
import math
import resource
import subprocess
import sys
import time

SEGMENTS = 1000
LENGTH = 50.0
DZ = LENGTH / SEGMENTS


def program(passes: int) -> str:
    step = 4.0 / passes  # radial stock per pass from the 40 mm bar down to the profile
    return f"""%1
T0101
M03 S800
G00 X44 Z2
#1 = 0
WHILE #1 LT {passes}
#2 = [{passes} - #1 - 1] * {step:.6f}
G00 X[2 * [15.5 + #2]] Z1
#3 = 0
WHILE #3 LE {SEGMENTS}
#4 = -#3 * {DZ:.6f}
G01 X[2 * [15 + #2 + 0.1 * SIN[#4 * 0.5]]] Z[#4] F300
#3 = #3 + 1
ENDW
G01 X44
G00 Z2
#1 = #1 + 1
ENDW
G00 X80 Z80
M30
"""


def model():
    from hnc_cam.geometry import Line, TurnedProfile
    pts = [(0.0, 0.0), (15.0, 0.0)]
    pts += [(15 + 0.1 * math.sin(-i * DZ * 0.5), -i * DZ) for i in range(SEGMENTS + 1)]
    pts += [(20.0, -LENGTH), (20.0, -60.0), (0.0, -60.0)]
    segs = [Line(a, b) for a, b in zip(pts[:-1], pts[1:]) if a != b]
    return TurnedProfile(outside=segs)


def one(passes: int) -> dict:
    from hnc_cam.nc.interp import run
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Machine, Stock
    machine = Machine()  # sharp tool: the final pass lands on the profile
    t0 = time.perf_counter()
    tp = run(program(passes), machine, file=f"bench{passes}.nc", start=(50.0, 80.0))
    t1 = time.perf_counter()
    m = simulate(tp, Stock.parse("40x60"), machine)
    t2 = time.perf_counter()
    rep = verify(m, model(), tol=0.01)
    t3 = time.perf_counter()
    from hnc_cam.tooling import load_machine
    lib = load_machine()  # T0101: CNMG120408, r 0.8, tip 3
    m2 = simulate(tp, Stock.parse("40x60"), lib)
    t4 = time.perf_counter()
    rep2 = verify(m2, model(), tol=0.01)
    t5 = time.perf_counter()
    peak_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {"passes": passes, "moves": len(tp.moves), "interp_s": t1 - t0, "simulate_s": t2 - t1,
            "verify_s": t3 - t2, "peak_mb": peak_kb / 1024, "pass": rep.passed,
            "max_overcut": rep.max_overcut_mm, "max_undercut": rep.max_undercut_mm,
            "simulate_r08_s": t4 - t3, "verify_r08_s": t5 - t4, "pass_r08": rep2.passed}


def shaft() -> dict:
    """Per-part simulate and verify time for generated programs of parts/stepped_shaft.py
    (both comp modes, three lengths; medians of three rounds): the cost that generate and
    family pay per part for their verification."""
    import statistics
    from pathlib import Path

    import hnc_cam
    from hnc_cam.cad import load_part
    from hnc_cam.nc.interp import run
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Stock, load_machine
    part = str(Path(__file__).resolve().parents[1] / "parts" / "stepped_shaft.py")
    machine = load_machine()
    cases = []
    for comp in ("cam", "control"):
        for length in (95, 100, 104):
            params = {"length": str(length)}
            prog = hnc_cam.generate(part, params=params, verify=False, comp=comp)
            loaded = load_part(part, params)
            tp = run(prog.text, machine, start="reference")
            cases.append((tp, Stock.parse(loaded.stock), loaded.profile))
    ts, tv, ok = [], [], True
    for _ in range(3):
        for tp, stock, prof in cases:
            t0 = time.perf_counter()
            m = simulate(tp, stock, machine, model=prof)
            t1 = time.perf_counter()
            ok = verify(m, prof).passed and ok
            ts.append(t1 - t0)
            tv.append(time.perf_counter() - t1)
    return {"simulate_ms": 1000 * statistics.median(ts), "verify_ms": 1000 * statistics.median(tv),
            "pass": ok, "moves": len(cases[0][0].moves)}


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--one":
        print(json.dumps(one(int(argv[1]))))
        return 0
    if argv and argv[0] == "--shaft":
        print(json.dumps(shaft()))
        return 0
    sizes = [int(a) for a in argv] or [1, 10, 100]
    rows = []
    print(f"{'moves':>8} {'interp s':>9} {'simulate s':>11} {'verify s':>9} {'sim+ver s':>10} "
          f"{'peak MB':>8}  {'sim r0.8 s':>10} {'ver r0.8 s':>10}  result (sharp; r0.8)")
    for k in sizes:
        out = subprocess.run([sys.executable, __file__, "--one", str(k)], capture_output=True,
                             text=True, check=True)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        r["total"] = r["simulate_s"] + r["verify_s"]
        rows.append(r)
        print(f"{r['moves']:>8} {r['interp_s']:>9.2f} {r['simulate_s']:>11.2f} "
              f"{r['verify_s']:>9.2f} {r['total']:>10.2f} {r['peak_mb']:>8.0f}  "
              f"{r['simulate_r08_s']:>10.2f} {r['verify_r08_s']:>10.2f}  "
              f"{'PASS' if r['pass'] else 'FAIL'} (over {r['max_overcut']:.4f}, "
              f"under {r['max_undercut']:.4f}); {'PASS' if r['pass_r08'] else 'FAIL'}",
              flush=True)
    for a, b in zip(rows, rows[1:]):
        f = (b["total"] / a["total"]) / (b["moves"] / a["moves"]) * 10
        print(f"growth {a['moves']} -> {b['moves']} moves: simulate+verify x{b['total'] / a['total']:.1f} "
              f"(x{f:.1f} per 10x moves)")
    if not argv:
        out = subprocess.run([sys.executable, __file__, "--shaft"], capture_output=True,
                             text=True, check=True)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        print(f"parts/stepped_shaft.py, generated programs (~{r['moves']} moves): simulate "
              f"{r['simulate_ms']:.0f} ms + verify {r['verify_ms']:.0f} ms per part (median), "
              f"{'all pass' if r['pass'] else 'SOME FAIL'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
