"""Program quality of the bundled part families: what a lathe programmer looks at.

Per part (default parameters and stock, ``--comp cam``): cycle time, air cut (share of the
feed time in which the simulator removed nothing), program blocks, tools, and a lower bound
of the cycle time:

    bound = removed volume / (ap * f * vc of the library's roughing tool)
            + the finishing contours' length at their feed (G96 resolved at each piece's
              diameter, capped by the machine's max rpm)

and cycle / bound (1.0 would be a program that cuts at full rate all the time and never
moves in air; rapids, tool changes and threads are all in the cycle time, not in the bound).

Then the workholding parts (:data:`HELD`), each held in the chuck by its grip: parted off
from the bar (the part-off in the cycle time; the bound counts the stub left in the chuck
as removed, so their ratio is low) or, for the long thin shaft, with the stick-out warning.
Last the parts with holes from solid bar (:data:`FROM_SOLID`): the drilling is in the cycle
time, not in the bound (its volume counts as removed at the roughing tool's rate). Last the
two-setup parts (:data:`TWO_SETUPS`, ``generate --setups 2``), a row per setup (``#1``,
``#2``): setup 2 runs from setup 1's simulated part turned around.

Run: python benchmarks/quality.py [--comp cam|control] [PART ...]
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

#: parts held in the chuck: (part file, grip mm)
HELD = [(REPO / "tests" / "data" / "turning_parts" / "pin_partoff.py", 20.0),
        (REPO / "tests" / "data" / "turning_parts" / "thin_shaft.py", 15.0)]
#: holes from solid bar: drilled (spot, pilot, opener, pecks), then bored
FROM_SOLID = [REPO / "tests" / "data" / "turning_parts" / "blind_bore.py",
              REPO / "tests" / "data" / "turning_parts" / "stepped_blind_bore.py",
              REPO / "tests" / "data" / "turning_parts" / "nut_m24.py",
              REPO / "tests" / "data" / "turning_parts" / "nut_through.py",
              REPO / "tests" / "data" / "turning_parts" / "face_groove.py"]
#: two-setup parts (generate --setups 2): (part file, grip mm, grip2 mm); a row per setup
TWO_SETUPS = [(REPO / "tests" / "data" / "turning_parts" / "bush_chamfers.py", 20.0, 15.0),
              (REPO / "tests" / "data" / "turning_parts" / "pin_left_step.py", 20.0, 15.0)]


def _finish_time(op, max_rpm: float) -> float:
    """Seconds for the operation's contour at its feed, G96 per piece's mean diameter."""
    t = 0.0
    for s in op.contour:
        x0, z0 = s.start
        x1, z1 = s.end
        r = max(0.5, (abs(x0) + abs(x1)) / 2)
        if op.speed_mode == "G96":
            rpm = min(max_rpm, op.speed * 1000.0 / (2 * math.pi * r))
        else:
            rpm = op.speed
        t += s.length / (op.feed * rpm) * 60.0
    return t


def measure(part: Path, comp: str, grip: float | None = None) -> dict:
    from hnc_cam.plan.api import _load_tools, generate
    from hnc_cam.plan.tools import turning_tools
    t0 = time.perf_counter()
    prog = generate(part, comp=comp, grip=grip)
    dt = time.perf_counter() - t0
    plan = prog.plan
    rep = prog.report
    lib = _load_tools(None)
    rough = [t for t in turning_tools(lib, "rough")]
    rough = rough[0]
    mrr = rough.depth * rough.feed_rough * rough.vc_rough * 1000.0 / 60.0  # mm^3/s
    removed = float(rep.removed_volume_mm3) if hasattr(rep, "removed_volume_mm3") else 0.0
    fin = sum(_finish_time(op, plan.machine.max_rpm) for op in plan.operations
              if op.name in ("finish", "bore_finish") and op.contour)
    bound = removed / mrr + fin
    blocks = sum(1 for ln in prog.text.splitlines() if ln.strip() and not ln.startswith("%")
                 and not ln.lstrip("N0123456789 ").startswith("("))
    name = part.stem if grip is None else f"{part.stem}@{grip:g}"
    return {"part": name, "cycle": prog.cycle_time_s, "air": rep.air_cut_fraction,
            "blocks": blocks, "tools": len(plan.tools), "bound": bound,
            "ratio": prog.cycle_time_s / bound if bound > 0 else float("nan"), "gen_s": dt}


def measure_setups(part: Path, comp: str, grip: float, grip2: float) -> list[dict]:
    """One row per setup of a two-setup part: setup 1 against the bridged part (its removed
    volume from its simulation), setup 2 from setup 1's simulated part turned around."""
    from hnc_cam.plan.api import _load_tools
    from hnc_cam.plan.setups import generate_setups
    from hnc_cam.plan.tools import turning_tools
    t0 = time.perf_counter()
    res = generate_setups(part, comp=comp, grip=grip, grip2=grip2)
    dt = time.perf_counter() - t0
    rough = turning_tools(_load_tools(None), "rough")[0]
    mrr = rough.depth * rough.feed_rough * rough.vc_rough * 1000.0 / 60.0  # mm^3/s
    rows = []
    for i, (prog, m) in enumerate(((res.first, res.machined1), (res.second, res.machined2)), 1):
        plan = prog.plan
        fin = sum(_finish_time(op, plan.machine.max_rpm) for op in plan.operations
                  if op.name in ("finish", "bore_finish") and op.contour)
        bound = m.removed_volume_mm3 / mrr + fin
        blocks = sum(1 for ln in prog.text.splitlines() if ln.strip() and not ln.startswith("%")
                     and not ln.lstrip("N0123456789 ").startswith("("))
        rows.append({"part": f"{part.stem[:12]}#{i}", "cycle": prog.cycle_time_s,
                     "air": m.air_cut_fraction, "blocks": blocks, "tools": len(plan.tools),
                     "bound": bound, "ratio": prog.cycle_time_s / bound if bound > 0
                     else float("nan"), "gen_s": dt})
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("parts", nargs="*")
    ap.add_argument("--comp", default="cam", choices=("cam", "control"))
    a = ap.parse_args(argv)
    parts = [(Path(p), None) for p in a.parts] or \
        [(p, None) for p in sorted((REPO / "parts").glob("*.py"))] + HELD + \
        [(p, None) for p in FROM_SOLID]
    print(f"comp {a.comp}; load average {os.getloadavg()[0]:.2f}")
    print(f"{'part':16s} {'cycle s':>8s} {'air %':>6s} {'blocks':>6s} {'tools':>5s} "
          f"{'bound s':>8s} {'cycle/bound':>11s}")
    for p, grip in parts:
        try:
            r = measure(p, a.comp, grip)
        except Exception as e:  # a part that does not generate is a row, not a crash
            print(f"{p.stem:16s} fails: {str(e).splitlines()[0][:100]}")
            continue
        print(f"{r['part']:16s} {r['cycle']:8.1f} {100 * r['air']:6.1f} {r['blocks']:6d} "
              f"{r['tools']:5d} {r['bound']:8.1f} {r['ratio']:11.2f}")
    for p, grip, grip2 in ([] if a.parts else TWO_SETUPS):
        try:
            rows = measure_setups(p, a.comp, grip, grip2)
        except Exception as e:  # a part that does not generate is a row, not a crash
            print(f"{p.stem:16s} fails: {str(e).splitlines()[0][:100]}")
            continue
        for r in rows:
            print(f"{r['part']:16s} {r['cycle']:8.1f} {100 * r['air']:6.1f} {r['blocks']:6d} "
                  f"{r['tools']:5d} {r['bound']:8.1f} {r['ratio']:11.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
