"""Benchmark: interpreter, simulate and verify time and peak memory for programs of about 1,000,
10,000, 100,000 and 1,000,000 moves.

The program is macro-generated (WHILE loops): K passes along a fine wavy profile of 1,000 G01
segments over 50 mm (X = 30 + 0.2 sin(Z/2) diameter plus the pass's allowance), stepping in from a
40 mm bar, so every pass removes material; K = 1, 10, 100, 1000 gives the four sizes. The model
is the final profile (1,000 exact lines). Each size runs in its own process so that the peak
resident memory (ru_maxrss, which includes GEOS and the interpreter's toolpath) is its own.

Two verifications per size: with a sharp tool (the program lands on the model: the report
passes) and with the default library's 0.8 mm nose on the same tip path (uncompensated: the
report fails, and the leftover is classified reachable/unreachable, the expensive branch).

    python benchmarks/verify.py                    # all four sizes
    python benchmarks/verify.py 1 10               # chosen pass counts
    python benchmarks/verify.py --repeat 5         # best of 5 (default 3; --repeat-large N, default 2,
                                                   # for 1,000 passes)
    python benchmarks/verify.py --baseline REV     # also the code of git revision REV, same run
    python benchmarks/verify.py --shaft            # only the per-part figure for parts/stepped_shaft.py
    python benchmarks/verify.py --shaft --baseline REV   # the per-part figure, REV's code beside it
                                                   # (--repeat N: best of N processes per code,
                                                   # the codes one after the other)

Prints per size, best of N with the load average beside it: moves, interpreter time, simulate
time, verify time (wall; and the CPU time of simulate+verify per round), simulate+verify as a
multiple of the interpreter's time for the same program in the same process (``/interp``),
its growth against the row before scaled to 10x moves (``growth``, x10 = linear), peak memory
(of the process, toolpath included, and the part of it that simulate and verify added above
the interpreter's);
with ``--baseline REV`` the same figures for the code of REV (exported with ``git archive``
into a temporary directory and imported from there, each size measured right after the
current code's) and the ratio REV/current per size; the targets (100,000 moves simulated and
verified in under 2 s with either tool, growth at most x10.5 per 10x moves, under 300 MB at
1,000,000 moves) against the rows measured; then (the default sizes, or ``--shaft``) the
per-part simulate and verify time of generated programs for parts/stepped_shaft.py, each
separately, with REV's code on the same programs beside it.
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


def _best(f, repeat: int):
    """(best wall time, last result) of ``repeat`` calls of f() (each result dropped before the
    next call, so that the peak memory is one call's)."""
    best, out = math.inf, None
    for _ in range(repeat):
        out = None
        t0 = time.perf_counter()
        out = f()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _unlimited(machine):
    """``machine`` with room for the largest size (the default limit is 500,000 moves)."""
    import dataclasses
    if any(f.name == "move_limit" for f in dataclasses.fields(machine)):
        return dataclasses.replace(machine, move_limit=100_000_000)
    return machine


def one(passes: int, repeat: int = 1, r08: bool = True) -> dict:
    from hnc_cam.nc.interp import run
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Machine, Stock, load_machine
    machine = _unlimited(Machine())  # sharp tool: the final pass lands on the profile
    text, prof, stock = program(passes), model(), Stock.parse("40x60")
    t_int, tp = _best(lambda: run(text, machine, file=f"bench{passes}.nc", start=(50.0, 80.0),
                                  step_limit=1_000_000_000), repeat)
    interp_mb = _rss_mb()
    c0 = time.process_time()
    t_sim, m = _best(lambda: simulate(tp, stock, machine), repeat)
    t_ver, rep = _best(lambda: verify(m, prof, tol=0.01), repeat)
    cpu = (time.process_time() - c0) / repeat
    out = {"passes": passes, "moves": len(tp.moves), "interp_s": t_int, "simulate_s": t_sim,
           "verify_s": t_ver, "pass": rep.passed, "max_overcut": rep.max_overcut_mm,
           "max_undercut": rep.max_undercut_mm, "repeat": repeat, "cpu_s": cpu}
    del m, rep
    if r08:
        lib = _unlimited(load_machine())  # T0101: CNMG120408, r 0.8, tip 3
        c0 = time.process_time()
        t_sim2, m2 = _best(lambda: simulate(tp, stock, lib), repeat)
        t_ver2, rep2 = _best(lambda: verify(m2, prof, tol=0.01), repeat)
        out.update(simulate_r08_s=t_sim2, verify_r08_s=t_ver2, pass_r08=rep2.passed,
                   cpu_r08_s=(time.process_time() - c0) / repeat)
    out["peak_mb"] = _rss_mb()
    out["sim_mb"] = out["peak_mb"] - interp_mb
    return out


SHAFT = "parts/stepped_shaft.py"


def shaft_programs() -> list[dict]:
    """Generated programs of parts/stepped_shaft.py (both comp modes, three lengths), by the
    current code: the same programs for the current code's and a baseline's measurement."""
    from pathlib import Path

    import hnc_cam
    part = str(Path(__file__).resolve().parents[1] / SHAFT)
    out = []
    for comp in ("cam", "control"):
        for length in (95, 100, 104):
            params = {"length": str(length)}
            prog = hnc_cam.generate(part, params=params, verify=False, comp=comp)
            out.append({"params": params, "text": prog.text})
    return out


def shaft(programs: list[dict] | None = None, rounds: int = 5) -> dict:
    """Per-part simulate and verify time for generated programs of parts/stepped_shaft.py
    (medians over the programs and ``rounds`` rounds, and the CPU time of both per part): the
    cost that generate and family pay per part for their verification."""
    import statistics
    from pathlib import Path

    from hnc_cam.cad import load_part
    from hnc_cam.nc.interp import run
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Stock, load_machine
    part = str(Path(__file__).resolve().parents[1] / SHAFT)
    machine = load_machine()
    cases = []
    for p in programs if programs is not None else shaft_programs():
        loaded = load_part(part, p["params"])
        tp = run(p["text"], machine, start="reference")
        cases.append((tp, Stock.parse(loaded.stock), loaded.profile))
    for tp, stock, prof in cases:  # warm: first calls build caches
        verify(simulate(tp, stock, machine, model=prof), prof)
    ts, tv, cs, cv, ok = [], [], [], [], True
    for _ in range(rounds):
        for tp, stock, prof in cases:
            c0, t0 = time.process_time(), time.perf_counter()
            m = simulate(tp, stock, machine, model=prof)
            c1, t1 = time.process_time(), time.perf_counter()
            ok = verify(m, prof).passed and ok
            ts.append(t1 - t0)
            tv.append(time.perf_counter() - t1)
            cs.append(c1 - c0)
            cv.append(time.process_time() - c1)
    n = rounds * len(cases)
    return {"simulate_ms": 1000 * statistics.median(ts), "verify_ms": 1000 * statistics.median(tv),
            "cpu_ms": 1000 * (sum(cs) + sum(cv)) / n, "cpu_simulate_ms": 1000 * sum(cs) / n,
            "cpu_verify_ms": 1000 * sum(cv) / n, "pass": ok, "moves": len(cases[0][0].moves)}


def _shaft_measure(programs_file: str, code: str | None = None) -> dict:
    """:func:`shaft` in a fresh process (``code``: a directory holding another hnc_cam)."""
    import os
    env = dict(os.environ)
    if code is not None:
        env["PYTHONPATH"] = code + os.pathsep + env.get("PYTHONPATH", "")
    load = os.getloadavg()[0]
    out = subprocess.run([sys.executable, __file__, "--shaft-run", programs_file],
                         capture_output=True, text=True, env=env, cwd=code or None)
    if out.returncode != 0:
        raise SystemExit(f"error: per-part benchmark failed:\n{out.stderr}")
    r = json.loads(out.stdout.strip().splitlines()[-1])
    r["load"] = (load + os.getloadavg()[0]) / 2
    return r


def _shaft_report(baseline: str | None, code: str | None, repeat: int = 1) -> None:
    """Print the per-part figure of the current code (and of the baseline's code in ``code``)
    on the same generated programs: best of ``repeat`` processes per code (the lowest
    simulate+verify time, and the lowest CPU time), the two codes' processes one after the
    other."""
    import os
    import tempfile
    fd, path = tempfile.mkstemp(prefix="hnc_shaft_", suffix=".json")
    os.close(fd)
    runs: dict[str, list[dict]] = {}
    try:
        gen = subprocess.run([sys.executable, __file__, "--shaft-gen", path], capture_output=True,
                             text=True)
        if gen.returncode != 0:
            raise SystemExit(f"error: generating the per-part programs failed:\n{gen.stderr}")
        for _ in range(max(1, repeat)):
            runs.setdefault("current", []).append(_shaft_measure(path))
            if code is not None:
                runs.setdefault(f"baseline {baseline}", []).append(_shaft_measure(path, code))
    finally:
        os.unlink(path)
    rows = []
    for name, rs in runs.items():
        r = dict(min(rs, key=lambda r: r["simulate_ms"] + r["verify_ms"]))
        cpu = min(rs, key=lambda r: r["cpu_ms"])
        r.update({k: cpu[k] for k in ("cpu_ms", "cpu_simulate_ms", "cpu_verify_ms")})
        r["pass"] = all(x["pass"] for x in rs)
        rows.append((name, r))
    moves = rows[0][1]["moves"]
    best = f", best of {repeat} processes" if repeat > 1 else ""
    print(f"{SHAFT}, generated programs (~{moves} moves; per part, median{best}):")
    for name, r in rows:
        print(f"  {name:>20}: simulate {r['simulate_ms']:6.1f} ms + verify {r['verify_ms']:6.1f} ms"
              f" = {r['simulate_ms'] + r['verify_ms']:6.1f} ms (CPU {r['cpu_simulate_ms']:.1f} + "
              f"{r['cpu_verify_ms']:.1f} = {r['cpu_ms']:.1f} ms), "
              f"load {r['load']:.2f}, {'all pass' if r['pass'] else 'SOME FAIL'}")
    if len(rows) > 1:
        a, b = rows[1][1], rows[0][1]
        print(f"  ratio baseline / current: simulate x{a['simulate_ms'] / b['simulate_ms']:.2f}, "
              f"verify x{a['verify_ms'] / b['verify_ms']:.2f}, both "
              f"x{(a['simulate_ms'] + a['verify_ms']) / (b['simulate_ms'] + b['verify_ms']):.2f} "
              f"(CPU x{a['cpu_ms'] / b['cpu_ms']:.2f})")


def _measure(passes: int, repeat: int, r08: bool, code: str | None = None) -> dict:
    """One size in a fresh process; ``code``: a directory holding another hnc_cam to import."""
    import os
    env = dict(os.environ)
    if code is not None:
        env["PYTHONPATH"] = code + os.pathsep + env.get("PYTHONPATH", "")
    load = os.getloadavg()[0]
    out = subprocess.run([sys.executable, __file__, "--one", str(passes), str(repeat),
                          "1" if r08 else "0"], capture_output=True, text=True, env=env,
                         cwd=code or None)
    if out.returncode != 0:
        raise SystemExit(f"error: benchmark of {passes} passes failed:\n{out.stderr}")
    r = json.loads(out.stdout.strip().splitlines()[-1])
    r["load"] = (load + os.getloadavg()[0]) / 2
    r["total"] = r["simulate_s"] + r["verify_s"]
    return r


def _table(title: str, rows: list[dict]) -> None:
    print(title)
    print(f"{'moves':>9} {'best of':>7} {'load':>5} {'interp s':>9} {'simulate s':>11} "
          f"{'verify s':>9} {'sim+ver s':>10} {'(CPU s)':>8} {'/interp':>7} {'growth':>7} "
          f"{'peak MB':>8} {'sim MB':>7}  {'sim r0.8 s':>10} {'ver r0.8 s':>10}  "
          f"result (sharp; r0.8)")
    prev = None
    for r in rows:
        r08 = "simulate_r08_s" in r
        # growth: simulate+verify time per 10x moves against the row before (x10 is linear)
        g = (f"x{(r['total'] / prev['total']) / (r['moves'] / prev['moves']) * 10:.1f}"
             if prev is not None and prev["total"] > 0 else "-")
        print(f"{r['moves']:>9} {r['repeat']:>7} {r['load']:>5.2f} {r['interp_s']:>9.2f} "
              f"{r['simulate_s']:>11.2f} {r['verify_s']:>9.2f} {r['total']:>10.2f} "
              f"{r.get('cpu_s', math.nan):>8.2f} {r['total'] / r['interp_s']:>7.2f} {g:>7} "
              f"{r['peak_mb']:>8.0f} {r['sim_mb']:>7.0f}  "
              + (f"{r['simulate_r08_s']:>10.2f} {r['verify_r08_s']:>10.2f}  " if r08
                 else f"{'-':>10} {'-':>10}  ")
              + f"{'PASS' if r['pass'] else 'FAIL'} (over {r['max_overcut']:.4f}, under "
              f"{r['max_undercut']:.4f})" + (f"; {'PASS' if r['pass_r08'] else 'FAIL'}" if r08 else ""),
              flush=True)
        prev = r
    for a, b in zip(rows, rows[1:]):
        f = (b["total"] / a["total"]) / (b["moves"] / a["moves"]) * 10
        print(f"  growth {a['moves']} -> {b['moves']} moves: simulate+verify x{b['total'] / a['total']:.1f} "
              f"(x{f:.1f} per 10x moves)")


def _export(rev: str) -> str:
    """The hnc_cam package of git revision ``rev`` in a temporary directory."""
    import tempfile
    from pathlib import Path
    root = Path(__file__).resolve().parents[1]
    d = tempfile.mkdtemp(prefix="hnc_cam_baseline_")
    arch = subprocess.run(["git", "-C", str(root), "archive", "--format=tar", rev, "hnc_cam",
                           "templates"], capture_output=True)
    if arch.returncode != 0:
        raise SystemExit(f"error: git archive {rev}: {arch.stderr.decode().strip()}")
    subprocess.run(["tar", "-x", "-C", d], input=arch.stdout, check=True)
    tpl = Path(d) / "templates"
    if tpl.is_dir() and not (Path(d) / "hnc_cam" / "_templates").exists():
        tpl.rename(Path(d) / "hnc_cam" / "_templates")
    return d


def main(argv: list[str]) -> int:
    if argv and argv[0] == "--one":
        print(json.dumps(one(int(argv[1]), int(argv[2]) if len(argv) > 2 else 1,
                             argv[3] != "0" if len(argv) > 3 else True)))
        return 0
    if argv and argv[0] == "--shaft-gen":
        with open(argv[1], "w") as f:
            json.dump(shaft_programs(), f)
        return 0
    if argv and argv[0] == "--shaft-run":
        with open(argv[1]) as f:
            print(json.dumps(shaft(json.load(f))))
        return 0
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("passes", nargs="*", type=int, help="pass counts (default 1 10 100 1000)")
    ap.add_argument("--repeat", type=int, default=3,
                    help="best of N (1,000 passes: --repeat-large)")
    ap.add_argument("--repeat-large", type=int, default=2, metavar="N",
                    help="best of N at 1,000 passes (default 2: a single run there against "
                         "best of 3 below it would bias the growth upward)")
    ap.add_argument("--baseline", metavar="REV", help="also measure the code of git revision REV")
    ap.add_argument("--no-r08", action="store_true", help="skip the 0.8 mm nose verification")
    ap.add_argument("--shaft", action="store_true",
                    help="only the per-part figure (parts/stepped_shaft.py)")
    args = ap.parse_args(argv)
    sizes = args.passes or [1, 10, 100, 1000]
    import shutil
    if args.shaft:
        d = _export(args.baseline) if args.baseline else None
        try:
            _shaft_report(args.baseline, d, args.repeat)
        finally:
            if d is not None:
                shutil.rmtree(d, ignore_errors=True)
        return 0

    def rep(k: int) -> int:
        return max(1, args.repeat_large if k >= 1000 else args.repeat)

    # with a baseline, each size is measured for both codes one after the other, so that both
    # see about the same load
    d = _export(args.baseline) if args.baseline else None
    rows, base = [], []
    try:
        for k in sizes:
            rows.append(_measure(k, rep(k), not args.no_r08))
            if d is not None:
                base.append(_measure(k, rep(k), not args.no_r08, code=d))
        if not args.passes:
            _shaft_report(args.baseline, d)
    finally:
        if d is not None:
            shutil.rmtree(d, ignore_errors=True)
    _table("current code:", rows)
    _targets(rows)
    if args.baseline:
        _table(f"baseline {args.baseline}:", base)
        print(f"ratio baseline {args.baseline} / current (time: simulate+verify sharp"
              + ("" if args.no_r08 else ", simulate+verify r0.8") + "; peak memory):")
        for a, b in zip(base, rows):
            line = (f"  {b['moves']:>9} moves: x{a['total'] / b['total']:.2f} "
                    f"(CPU x{a['cpu_s'] / b['cpu_s']:.2f})")
            if not args.no_r08:
                line += (f", x{(a['simulate_r08_s'] + a['verify_r08_s']) / (b['simulate_r08_s'] + b['verify_r08_s']):.2f}"
                         f" (CPU x{a['cpu_r08_s'] / b['cpu_r08_s']:.2f})")
            print(line + f"; memory x{a['peak_mb'] / b['peak_mb']:.2f}")
    return 0


def _targets(rows: list[dict]) -> None:
    """The issue's targets against the rows measured (current code)."""
    print("targets:")
    for r in rows:
        if 50_000 <= r["moves"] <= 200_000:
            t = r["total"]
            print(f"  {r['moves']} moves simulated and verified, sharp tool: {t:.2f} s "
                  f"(target < 2 s: {'met' if t < 2 else 'NOT met'}; CPU {r['cpu_s']:.2f} s, "
                  f"load {r['load']:.2f})")
            if "simulate_r08_s" in r:
                t = r["simulate_r08_s"] + r["verify_r08_s"]
                print(f"  {r['moves']} moves simulated and verified, 0.8 mm nose: {t:.2f} s "
                      f"(target < 2 s: {'met' if t < 2 else 'NOT met'}; CPU "
                      f"{r.get('cpu_r08_s', math.nan):.2f} s, load {r['load']:.2f})")
        if r["moves"] >= 500_000:
            print(f"  {r['moves']} moves: peak {r['peak_mb']:.0f} MB "
                  f"(target < 300 MB: {'met' if r['peak_mb'] < 300 else 'NOT met'})")
    for a, b in zip(rows, rows[1:]):
        f = (b["total"] / a["total"]) / (b["moves"] / a["moves"]) * 10
        print(f"  growth {a['moves']} -> {b['moves']} moves: x{f:.1f} per 10x moves "
              f"(target <= x10.5: {'met' if f <= 10.5 else 'NOT met'})")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
