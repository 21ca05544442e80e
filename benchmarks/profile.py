"""Profile benchmark: ms per part for build + profile of each parts/ family (defaults), for 200
variants of family 1 (stepped_shaft), STEP files, the turned envelope (keyway, hex), and the
cold import time of build123d (in a fresh subprocess, so it is not hidden by this process's
own import).

A solid made by ``revolve()`` is profiled from the outline it was revolved from
(``profile``); ``extract`` is the same profile cut from the solid, measured in the same run,
and the ratio of the two is printed. The 200 variants through ``load_part`` are split into
the OpenCascade solids made (none: the loader defers ``revolve()``, and the outline is the
profile) and the rest of the load. The cold start of a revolve family's first load
(``hnc_cam.cad`` imported and one part loaded in a fresh interpreter: no CAD kernel) is
printed beside the cold import of build123d.

    /work/venv/bin/python benchmarks/profile.py [--variants N]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

FAMILIES = ["stepped_shaft", "grooved_shaft", "flange", "bushing", "cast_blank",
            "threaded_stud", "cq_pin"]


def cold_import(module: str, repeats: int = 3) -> float:
    """Best wall time (s) of `python -c "import <module>"` in a fresh interpreter, minus the
    bare interpreter start-up."""
    def run(code: str) -> float:
        t = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True)
        return time.perf_counter() - t
    base = min(run("pass") for _ in range(repeats))
    return min(run(f"import {module}") for _ in range(repeats)) - base


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variants", type=int, default=200)
    args = ap.parse_args()

    t0 = time.perf_counter()
    from hnc_cam.cad import load_part, profile
    from hnc_cam.cad.loader import load_module
    import build123d  # noqa: F401
    import cadquery  # noqa: F401
    t_import = time.perf_counter() - t0

    print(f"in-process import of hnc_cam.cad + build123d + cadquery: {t_import:.2f} s")
    print()
    from hnc_cam.cad.extract import extract
    print(f"load average {os.getloadavg()[0]:.2f}")
    print(f"{'family':<16}{'build ms':>10}{'profile ms':>12}{'total ms':>10}{'segments':>10}"
          f"{'extract ms':>12}{'ratio':>8}")
    for fam in FAMILIES:
        mod = load_module(ROOT / "parts" / f"{fam}.py")
        mod.part(); profile(mod.part()); extract(mod.part())  # warm
        n = 10
        tb = tp = te = 0.0
        for _ in range(n):
            t = time.perf_counter()
            solid = mod.part()
            tb += time.perf_counter() - t
            t = time.perf_counter()
            prof = profile(solid)
            tp += time.perf_counter() - t
            t = time.perf_counter()
            extract(solid)
            te += time.perf_counter() - t
        segs = len(prof.outside) + len(prof.bore or [])
        print(f"{fam:<16}{tb / n * 1e3:>10.1f}{tp / n * 1e3:>12.1f}{(tb + tp) / n * 1e3:>10.1f}"
              f"{segs:>10}{te / n * 1e3:>12.1f}{te / tp:>7.1f}x")

    print()
    data = ROOT / "tests" / "data"
    from build123d import Pos, RegularPolygon, extrude
    from build123d import Box
    keyed = load_module(ROOT / "parts" / "stepped_shaft.py").part() - Pos(0, 14, -38) * Box(8, 8, 20)
    hexbar = extrude(RegularPolygon(15, 6), 40)
    cases = [("stepped_shaft.step (read + profile)", lambda: profile(data / "stepped_shaft.step")),
             ("spline_knob.step (B-spline, fitted)", lambda: profile(data / "spline_knob.step")),
             ("keyed shaft, envelope=True", lambda: profile(keyed, envelope=True)),
             ("hex bar, envelope=True", lambda: profile(hexbar, envelope=True))]
    for label, fn in cases:
        fn()  # warm
        t = time.perf_counter()
        for _ in range(5):
            fn()
        print(f"{label:<40}{(time.perf_counter() - t) / 5 * 1e3:>8.1f} ms")

    from hnc_cam.cad import sketch
    n = args.variants
    spent = [0.0]
    made = [0]
    real = sketch._revolve

    def timed(segs):
        t0 = time.perf_counter()
        try:
            made[0] += 1
            return real(segs)
        finally:
            spent[0] += time.perf_counter() - t0
    sketch._revolve = timed
    try:
        t = time.perf_counter()
        for i in range(n):
            k = i / max(1, n - 1)
            load_part(ROOT / "parts" / "stepped_shaft.py",
                      {"length": str(90 + 40 * k), "d1": str(16 + 4 * k), "d2": str(26 + 6 * k),
                       "d3": str(38 + 10 * k), "fillet": str(0.8 + 0.8 * k),
                       "dome_radius": str(12 + 20 * k)})
        dt = time.perf_counter() - t
    finally:
        sketch._revolve = real
    print()
    print(f"stepped_shaft, {n} variants through load_part (build + profile): "
          f"{dt:.2f} s total, {dt / n * 1e3:.2f} ms per part, of which {made[0]} OpenCascade "
          f"solid(s) made in {spent[0] / n * 1e3:.2f} ms per part ({100 * spent[0] / dt:.0f} %), "
          f"the rest {(dt - spent[0]) / n * 1e3:.2f} ms")

    print()
    print(f"cold import of build123d (fresh interpreter): {cold_import('build123d'):.2f} s")
    print(f"cold import of OCP + hnc_cam.cad.occ (STEP path, no build123d): "
          f"{cold_import('hnc_cam.cad.occ'):.2f} s")
    part = str(ROOT / "parts" / "stepped_shaft.py")
    print(f"cold import of hnc_cam.cad + load_part(stepped_shaft) (a revolve family, no CAD "
          f"kernel): {cold_import(f'hnc_cam.cad; hnc_cam.cad.load_part({part!r})'):.2f} s")


if __name__ == "__main__":
    main()
