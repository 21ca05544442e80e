"""Benchmark: simulate() on programs whose moves are mostly findings, and how the batches are
taken.

Colliding rapids: R rapids, each plunging 0.5 mm into a 40 mm bar at a fresh place (passes of
300 plunges 0.18 mm apart, each pass 0.5 mm deeper), with a CNMG120408 insert: every one is a
collision, found with its depth and first contact point. The time per collision should not
grow with R (the cost is proportional to the findings).

Batches: for the 100-pass program of ``benchmarks/verify.py`` (100,504 moves) with a sharp tool
and with a 0.8 mm nose, how many batches were taken with one overlay and exact band shares and
how many move by move.

    python benchmarks/sim.py                 # R = 300, 1,000, 3,000
    python benchmarks/sim.py 600 6000        # chosen R

Prints seconds (wall and CPU), findings and milliseconds per finding per R, with the load
average; then the batch counts.
"""
from __future__ import annotations

import importlib
import os
import sys
import time
from pathlib import Path


def rapids_program(r: int) -> str:
    blocks = ["%1", "T0101", "M03 S800", "G00 X42 Z2"]
    for n in range(r):
        j, i = divmod(n, 300)
        blocks += [f"G00 Z{-1.0 - 0.18 * i:.3f}", f"X{39 - 0.5 * j:.3f}", "X42"]
    blocks += ["G00 X80 Z80", "M30"]
    return "\n".join(blocks) + "\n"


def colliding(r: int) -> dict:
    from hnc_cam.nc.interp import run
    from hnc_cam.sim import simulate
    from hnc_cam.tooling import Insert, Machine, Register, Stock
    cnmg = Machine(registers={1: Register(number=1, radius=0.8, tip=3,
                                          insert=Insert.parse("CNMG120408"), approach=95.0)})
    tp = run(rapids_program(r), cnmg, file="rapids.nc", start=(60.0, 50.0))
    load = os.getloadavg()[0]
    t0, c0 = time.perf_counter(), time.process_time()
    m = simulate(tp, Stock.parse("40x60"), cnmg)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return {"rapids": r, "moves": len(tp.moves), "findings": len(m.issues), "wall": wall,
            "cpu": cpu, "load": load}


def batches() -> list[tuple[str, int, int, float]]:
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import verify as bench
    from hnc_cam.nc.interp import run
    from hnc_cam.tooling import Machine, Stock, load_machine
    S = importlib.import_module("hnc_cam.sim.simulate")
    sharp = bench._unlimited(Machine())
    tp = run(bench.program(100), sharp, file="bench100.nc", start=(50.0, 80.0),
             step_limit=1_000_000_000)
    out = []
    for name, machine in (("sharp", sharp), ("r0.8", bench._unlimited(load_machine()))):
        got = {"bands": 0, "moves": 0}
        real_bands, real_moves = S._batch_by_bands, S._batch_by_moves

        def by_bands(*a, **k):
            g = real_bands(*a, **k)
            got["bands"] += g is not None
            return g

        def by_moves(*a, **k):
            got["moves"] += 1
            return real_moves(*a, **k)

        S._batch_by_bands, S._batch_by_moves = by_bands, by_moves
        try:
            t0 = time.perf_counter()
            S.simulate(tp, Stock.parse("40x60"), machine)
            dt = time.perf_counter() - t0
        finally:
            S._batch_by_bands, S._batch_by_moves = real_bands, real_moves
        out.append((name, got["bands"], got["moves"], dt))
    return out


def main(argv: list[str]) -> int:
    sizes = [int(a) for a in argv] or [300, 1000, 3000]
    print(f"{'rapids':>7} {'moves':>7} {'load':>5} {'findings':>8} {'wall s':>7} {'CPU s':>6} "
          f"{'ms/finding':>10}")
    for r in sizes:
        x = colliding(r)
        per = 1000 * x["cpu"] / max(x["findings"], 1)
        print(f"{x['rapids']:>7} {x['moves']:>7} {x['load']:>5.2f} {x['findings']:>8} "
              f"{x['wall']:>7.2f} {x['cpu']:>6.2f} {per:>10.2f}", flush=True)
    print("batches of the 100-pass program (100,504 moves): tool, by bands, move by move, seconds")
    for name, b, m, dt in batches():
        print(f"  {name:>5}: {b:>5} {m:>5} {dt:>6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
