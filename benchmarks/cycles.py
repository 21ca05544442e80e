"""Benchmark of the cycles (issue 3): expanding a G71 with 200 passes over a 50-segment
profile and a G76 with 40 passes.

    /work/venv/bin/python benchmarks/cycles.py [--repeat N] [--only g71|g76]

G71, for a type I profile (25 tapers + 25 convex arcs, monotonic, 200 levels of Δd = 0.5)
and a type II profile (the same length with 12 grooves):
(1) the roughing engine alone (``geometry.roughing.rough_turn``),
(2) the cycle module into a recording context (``cycles_rough.execute``: words, profile,
    engine, emission),
(3) the whole program through the interpreter (parse, profile dry run, move records with
    durations).
G76 (M24x2, 38 roughing + 2 finishing passes): (1) the cycle expansion alone
(``cycles_simple.execute`` into a recording context), (2) the whole program through the
interpreter.
Prints the median and best wall time of ``--repeat`` runs and the number of passes/moves
(G76: ``--repeat`` × 10 runs of the expansion, which takes well under a millisecond).
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
from hnc_cam.nc.cycles_simple import execute as execute_simple, g76_depths  # noqa: E402

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
        from hnc_cam.nc import run
        text = program(bl, " ".join(f"{k}{v:g}" for k, v in words.items()))
        med, best, tp = _time(lambda: run(text), repeat)
        print(f"  whole program (nc.run)     median {med * 1e3:8.1f} ms   best {best * 1e3:8.1f} ms"
              f"   ({len(tp.moves)} toolpath moves)")


# --------------------------------------------------------------------------- G76

# M24x2 outside thread, K1.3, Q0.2, V0.02, U0.05, C2: 38 roughing + 2 finishing = 40 passes
G76_WORDS = {"C": 2, "R": -2, "E": 1.3, "A": 60, "X": 21.4, "Z": -30, "K": 1.3, "U": 0.05,
             "V": 0.02, "Q": 0.2, "P": 0, "F": 2}
G76_START = (14.0, 5.0)  # X28 Z5 (radius 14)
G76_PROGRAM = f"""%0001
T0101
M03 S300
G00 X28 Z5
G76 {' '.join(f'{k}{v:g}' for k, v in G76_WORDS.items())}
G00 X100 Z100
M30
"""


class _ThreadRecorder:
    """The minimal CycleContext for G76: words of one block, legs appended to a list."""

    code, line, incremental, diameter_mode = 76, 5, False, True

    def __init__(self) -> None:
        self.legs: list[tuple] = []
        self.pos = G76_START

    def word(self, c):
        return G76_WORDS.get(c)

    def has(self, c):
        return c in G76_WORDS

    def alarm(self, message, letter=None):
        raise RuntimeError(message)

    def warn(self, message):
        pass

    def rapid(self, x, z):
        self.legs.append(("rapid", x, z))

    def feed(self, x, z, feed=None):
        self.legs.append(("feed", x, z))

    def thread(self, x, z, lead, angle=0.0, thread_angle=0.0):
        self.legs.append(("thread", x, z, lead, angle, thread_angle))


def _expand_g76():
    ctx = _ThreadRecorder()
    execute_simple(76, ctx)
    return ctx.legs


def bench_g76(repeat: int = 5) -> None:
    w = G76_WORDS
    passes = g76_depths(w["K"], w["U"], w["Q"], w["V"], int(w["C"]))
    assert len(passes) == 40, len(passes)
    med, best, legs = _time(_expand_g76, 10 * repeat)
    n_thread = sum(1 for leg in legs if leg[0] == "thread")
    print(f"G76: {len(passes)} passes, {len(legs)} legs ({n_thread} thread legs)")
    print(f"  cycle module (execute)     median {med * 1e3:8.3f} ms   best {best * 1e3:8.3f} ms"
          f"   ({med / len(passes) * 1e6:.1f} us per pass)")
    from hnc_cam.nc import run
    med, best, tp = _time(lambda: run(G76_PROGRAM), repeat)
    print(f"  whole program (nc.run)     median {med * 1e3:8.3f} ms   best {best * 1e3:8.3f} ms"
          f"   ({len(tp.moves)} toolpath moves)")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--only", choices=("g71", "g76"))
    a = ap.parse_args(argv)
    if a.only != "g76":
        bench_g71(a.repeat)
    if a.only != "g71":
        bench_g76(a.repeat)
    return 0


if __name__ == "__main__":
    sys.exit(main())
