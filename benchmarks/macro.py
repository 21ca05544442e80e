"""Benchmark of ``hnc-cam family PART --macro``: per family, the time to derive the macro
program (trace, stock, per-variant programs, fits, splits) and to check it (``--check N``:
interpreter, simulation and verification of N sets, each compared with its per-variant
program), and the macro program's size against the sum of the per-variant programs of 100
variants of the same domain (the programs a shop would otherwise keep).

A family whose program is refused prints the refusal instead of figures. The load average is
printed beside the figures: on a shared machine they scale with it.

Run: python benchmarks/macro.py [--variants 100] [--check 5] [--dialect hnc21t] [PART ...]
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))


def _families() -> list[Path]:
    out = [p for p in sorted((REPO / "parts").glob("*.py"))
           if "def sketch" in p.read_text(encoding="utf-8")]
    return out + sorted((REPO / "tests" / "data" / "families").glob("*.py"))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("parts", nargs="*")
    ap.add_argument("--variants", type=int, default=100)
    ap.add_argument("--check", type=int, default=5)
    ap.add_argument("--dialect", default="hnc21t")
    a = ap.parse_args()
    from hnc_cam.errors import HncError
    from hnc_cam.plan import macro_command as mc
    from hnc_cam.plan.api import _load_machine, _load_tools, generate
    from hnc_cam.plan.macro import load_family
    from hnc_cam.plan.macro_program import (Ctx, check_program, derive_pieces, family_stock,
                                            fix_unmachinable, render_program, sample)
    lib = _load_tools(None)
    mach = _load_machine(None, lib)
    generate(str(REPO / "parts" / "stepped_shaft.py"), verify=False)  # warm the imports
    print(f"load average {os.getloadavg()[0]:.1f}; dialect {a.dialect}; --check {a.check}; "
          f"{a.variants} variants")
    print(f"{'family':<22} {'pieces':>6} {'decide':>6} {'params':>6} {'fitted':>6} "
          f"{'derive s':>9} {'check s':>8} {'macro B':>8} {'variants B':>11} {'ratio':>7}")
    for path in [Path(p) for p in a.parts] or _families():
        name = path.stem
        t0 = time.perf_counter()
        try:
            fam = load_family(str(path), {}, spread=mc.SPREAD)
            stock = family_stock(fam, fam.lo, fam.hi,
                                 sample(fam, fam.trace, fam.lo, fam.hi, 20, "stock"))
            ctx = Ctx(str(path), dict(comp="control", verify=False, dialect=a.dialect), stock,
                      a.dialect)
            fix_unmachinable(ctx, fam)
            pieces = derive_pieces(ctx, fam)
            t1 = time.perf_counter()
            size = 0
            for i, pc in enumerate(pieces):
                size += len(render_program(pc, a.dialect, number=1 + i).text.encode())
                runs = [(str(j), p, render_program(pc, a.dialect, values=p, number=1 + i))
                        for j, p in enumerate(sample(fam, pc.tr, pc.lo, pc.hi, a.check,
                                                     ("check", i), extra=pc.extra))]
                bad = [r for r in check_program(ctx, pc, runs, mach, lib, 0.01) if not r["ok"]]
                if bad:
                    raise HncError(f"check fails for {bad[0]['params']}: {bad[0]['message']}")
            t2 = time.perf_counter()
        except HncError as e:
            print(f"{name:<22} refused after {time.perf_counter() - t0:.1f} s: "
                  f"{str(e).splitlines()[0][:150]}")
            continue
        total = 0
        sets = [p for pc in pieces for p in sample(fam, pc.tr, pc.lo, pc.hi,
                                                  a.variants // len(pieces), ("size", name),
                                                  extra=pc.extra)]
        for p in sets:
            total += len(ctx.program(p).encode())
        total = total * a.variants // max(1, len(sets))
        fitted = sum(pc.fitted for pc in pieces)
        decide = sum(len(pc.decisions) for pc in pieces)
        print(f"{name:<22} {len(pieces):>6} {decide:>6} {len(fam.free):>6} {fitted:>6} "
              f"{t1 - t0:>9.2f} {t2 - t1:>8.2f} {size:>8} {total:>11} {total / size:>6.0f}x")
        print(f"{'':<22} domain: " + " ".join(f"{k} {fam.lo[k]:.4g}..{fam.hi[k]:.4g}"
                                              for k in fam.free))
        for pc in pieces:
            if pc.bounds or pc.decisions:
                print(f"{'':<22} piece [{', '.join(pc.bounds) or 'whole domain'}]: decides "
                      f"{'; '.join(pc.decisions) or 'nothing'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
