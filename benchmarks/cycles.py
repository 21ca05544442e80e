"""Benchmark: expanding a G71 with 200 passes over a 50-segment profile (the G71 half of the
cycles benchmark; the G76 half is benchmarks/cycles_thread.py).

    /work/venv/bin/python benchmarks/cycles.py [--repeat N]

Measures, for a type I profile (25 tapers + 25 convex arcs, monotonic, 200 levels of
Δd = 0.5) and a type II profile (the same length with 12 grooves):
(1) the roughing engine alone (``geometry.roughing.rough_turn``),
(2) the cycle module into a recording context (``cycles_rough.execute``: words, profile,
    engine, emission),
(3) the whole program through the interpreter (parse, profile dry run, move records with
    durations), when the interpreter is present.
Prints the median and best wall time of ``--repeat`` runs and the number of passes/moves.
"""
from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from hnc_cam.geometry.primitives import Arc, Line  # noqa: E402
from hnc_cam.geometry.roughing import rough_turn  # noqa: E402
from hnc_cam.nc import cycles_rough  # noqa: E402

A = (101.5, 2.0)  # X203 Z2 (radius 101.5)
DEPTH = 0.5  # 200 levels from radius 101.5 down to radius 1.5


def blocks(grooves: bool) -> list[tuple]:
    """ns (G00 to X2 at Z2) + 49 profile blocks (diameter, absolute): radius 1 -> 99 over
    Z 2 -> -292 with alternating tapers and 29 deg convex arcs; with ``grooves`` every 4th
    taper dips back down by 2 (a groove) and the next one climbs 4."""
    out: list[tuple] = [("G00", 2.0, 2.0)]
    r, z = 1.0, 2.0
    for i in range(49):
        if i % 2 == 0:  # taper
            dr = -2.0 if grooves and i % 8 == 4 else 2.0 + (4.0 if grooves and i % 8 == 6 else 0)
            r, z = r + dr, z - 6.0
            out.append(("G01", 2 * r, z))
        else:  # convex 90 deg-ish blend: R = chord
            r2, z2 = r + 2.0, z - 6.0
            out.append(("G03", 2 * r2, z2, 2 * math.hypot(2.0, 6.0)))
            r, z = r2, z2
    return out


def chain(bl):
    cur = (A[0], A[1])
    segs, mot = [], []
    for b in bl:
        end = (b[1] / 2, b[2])
        if b[0] in ("G00", "G01"):
            segs.append(Line(cur, end))
            mot.append("rapid" if b[0] == "G00" else "feed")
        else:
            segs.append(Arc.from_radius(cur, end, b[3], b[0] == "G02"))
            mot.append("feed")
        cur = end
    return segs, mot


def program(bl, words: str) -> str:
    lines = ["%0071", "T0101", "M03 S800", f"G00 X{2 * A[0]:g} Z{A[1]:g}",
             f"G71 {words} P100 Q{100 + len(bl) - 1} F150"]
    for i, b in enumerate(bl):
        r = f" R{b[3]:.6f}" if len(b) > 3 else ""
        lines.append(f"N{100 + i} {b[0]} X{b[1]:.4f} Z{b[2]:.4f}{r}")
    lines += ["G00 X250 Z50", "M30"]
    return "\n".join(lines) + "\n"


class _Recorder:
    code, line, incremental, diameter_mode = 71, 5, False, True

    def __init__(self, words, prof):
        self.words, self.prof, self.n = words, prof, 0
        self.pos = A

    def word(self, c):
        return self.words.get(c)

    def has(self, c):
        return c in self.words

    def alarm(self, message, letter=None):
        raise RuntimeError(message)

    def warn(self, message):
        pass

    def profile(self, ns, nf):
        segs, mot = self.prof
        return [(s, 100 + i, m) for i, (s, m) in enumerate(zip(segs, mot))]

    def rapid(self, x, z):
        self.n += 1

    def feed(self, x, z, feed=None):
        self.n += 1

    def arc(self, x, z, center, cw, feed=None):
        self.n += 1


def _time(fn, repeat: int) -> tuple[float, float, object]:
    ts, res = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        res = fn()
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts), min(ts), res


def bench_g71(repeat: int = 5) -> None:
    for name, grooves, words in (("type I", False, {"U": DEPTH, "R": 0.5, "X": 0.4, "Z": 0.1}),
                                 ("type II", True, {"U": DEPTH, "R": 0.5, "E": 0.4})):
        bl = blocks(grooves)
        segs, mot = chain(bl)
        allow = (0.2, 0.1) if not grooves else (0.2, 0.0)
        med, best, plan = _time(lambda: rough_turn(A, segs, mot, depth=DEPTH, retract=0.5,
                                                   allowance=allow, pockets=grooves), repeat)
        print(f"G71 {name}: {len(segs)} segments, {plan.levels} levels, {plan.passes} passes, "
              f"{len(plan.moves)} moves")
        print(f"  engine (rough_turn)        median {med * 1e3:8.1f} ms   "
              f"best {best * 1e3:8.1f} ms")
        w = dict(words, P=100, Q=100 + len(bl) - 1)
        med, best, rec = _time(lambda: (lambda r: (cycles_rough.execute(71, r), r)[1])(
            _Recorder(w, (segs, mot))), repeat)
        print(f"  cycle module (execute)     median {med * 1e3:8.1f} ms   "
              f"best {best * 1e3:8.1f} ms")
        try:
            from hnc_cam.nc import run
        except ImportError:  # pragma: no cover
            continue
        text = program(bl, " ".join(f"{k}{v:g}" for k, v in words.items()))
        med, best, tp = _time(lambda: run(text), repeat)
        print(f"  whole program (nc.run)     median {med * 1e3:8.1f} ms   best {best * 1e3:8.1f} ms"
              f"   ({len(tp.moves)} toolpath moves)")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args(argv)
    bench_g71(a.repeat)
    return 0


if __name__ == "__main__":
    sys.exit(main())
