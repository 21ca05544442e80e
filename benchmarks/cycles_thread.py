"""Benchmark: expanding a G76 thread cycle with 40 passes (the G76 half of the cycles
benchmark; the G71 half lives in benchmarks/cycles.py).

    /work/venv/bin/python benchmarks/cycles_thread.py [--repeat N]

Measures (1) the cycle expansion alone (``cycles_simple.execute`` into a recording context
that does nothing but store the legs) and (2) the whole program through the interpreter
(parse, modal state, move records with durations), when the interpreter is present.
Prints the median and best wall time of ``--repeat`` runs.
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from hnc_cam.nc.cycles_simple import execute, g76_depths  # noqa: E402

# M24x2 outside thread, K1.3, Q0.2, V0.02, U0.05, C2: 38 roughing + 2 finishing = 40 passes
WORDS = {"C": 2, "R": -2, "E": 1.3, "A": 60, "X": 21.4, "Z": -30, "K": 1.3, "U": 0.05,
         "V": 0.02, "Q": 0.2, "P": 0, "F": 2}
START = (14.0, 5.0)  # X28 Z5 (radius 14)
PROGRAM = f"""%0001
T0101
M03 S300
G00 X28 Z5
G76 {' '.join(f'{k}{v:g}' for k, v in WORDS.items())}
G00 X100 Z100
M30
"""


class _Recorder:
    """The minimal CycleContext: words of one block, legs appended to a list."""

    code, line, incremental, diameter_mode = 76, 5, False, True

    def __init__(self) -> None:
        self.legs: list[tuple] = []
        self.pos = START

    def word(self, c):
        return WORDS.get(c)

    def has(self, c):
        return c in WORDS

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


def _time(fn, repeat: int) -> tuple[float, float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), min(times), out


def _expand():
    ctx = _Recorder()
    execute(76, ctx)
    return ctx.legs


def _interpreter():
    """The interpreter's entry point, or None while it is not there."""
    try:
        from hnc_cam.nc import interp  # type: ignore
    except ImportError:
        return None
    return getattr(interp, "run", None)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=50)
    args = ap.parse_args(argv)

    passes = g76_depths(WORDS["K"], WORDS["U"], WORDS["Q"], WORDS["V"], int(WORDS["C"]))
    assert len(passes) == 40, len(passes)
    med, best, legs = _time(_expand, args.repeat)
    n_thread = sum(1 for leg in legs if leg[0] == "thread")
    print(f"G76 expansion: {len(passes)} passes, {len(legs)} legs ({n_thread} thread legs): "
          f"median {med * 1e3:.3f} ms, best {best * 1e3:.3f} ms over {args.repeat} runs "
          f"({med / len(passes) * 1e6:.1f} us per pass)")

    run = _interpreter()
    if run is None:
        print("interpreter: hnc_cam.nc.interp.run not available, whole-program figure skipped")
        return 0
    med, best, tp = _time(lambda: run(PROGRAM), max(5, args.repeat // 5))
    moves = getattr(tp, "moves", [])
    print(f"G76 program through the interpreter: {len(moves)} moves: "
          f"median {med * 1e3:.3f} ms, best {best * 1e3:.3f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
