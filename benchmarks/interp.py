"""Interpreter throughput.

(a) a generated 100,000-block program of G01/G02/G03 moves (load + run, blocks/s; wall and
    process CPU time, since the machine may be shared);
(b) a macro WHILE loop of 100,000 iterations (statements/s and iterations/s);
(c) pygcode's parse time of the same plain file (its line parser, no machine model), for a
    side-by-side ratio;
(d) the same moves in each dialect (HNC-21T, FANUC 0i-T, Haas, SINUMERIK 802; LinuxCNC's
    interpreter when its Python module is installed), load + run, as ratios to the HNC-21T
    executor's Python code (its compiled core off) measured in the same run;
(e) whole processes on the same file: ``hnc-cam run FILE`` (with the compiled core, and with
    ``HNC_CAM_PURE=1``, the Python code alone) against LinuxCNC's C++ interpreter
    ``rs274 -g FILE /dev/null`` (Debian package ``linuxcnc-uspace``, installed here with apt
    when ``rs274`` is absent and apt can; else that column is skipped, saying why), best of
    N wall times with the load average beside them, as ratios; and the cold start of
    ``hnc-cam run`` on a three-line program beside ``python -c pass``.

Run: ``python benchmarks/interp.py [N] [--whole] [--runs R]`` (``--whole``: only (e)).
"""
from __future__ import annotations

import sys
import time


def moves(n: int, zero: str = "0") -> list[str]:
    """``n`` blocks of a zig-zag: G01 lines and G02/G03 half-arcs (R form and I/K form);
    ``zero`` is how the I word's 0 is written (``"0."`` for a FANUC point on every number)."""
    out = []
    x, z = 40.0, 0.0
    for i in range(n):
        k = i % 4
        if k == 0:
            z -= 1.0
            out.append(f"G01 X{x:.3f} Z{z:.3f}")
        elif k == 1:
            out.append(f"G02 X{x + 2:.3f} Z{z - 1:.3f} R1.000")
            x += 2
            z -= 1
        elif k == 2:
            out.append(f"G03 X{x - 2:.3f} Z{z - 1:.3f} I{zero} K-1.000")
            x -= 2
            z -= 1
        else:
            out.append(f"G01 X{x:.3f} Z{z - 0.5:.3f}")
            z -= 0.5
    return out


def plain_program(n: int) -> str:
    """:func:`moves` as an HNC-21T program, n blocks + 3."""
    return "\n".join(["%1", "G92 X100 Z10", "M03 S800", "G01 X40 Z0 F120"] + moves(n - 1)
                     + ["M30"]) + "\n"


def fanuc_program(n: int) -> str:
    """:func:`plain_program` as a FANUC 0i-T program: % / O framing, G50 for G92, a decimal
    point on every coordinate, feed per minute (G98)."""
    import re
    body = plain_program(n).split("\n", 1)[1]
    body = body.replace("G92 X100 Z10", "G50 X100. Z10.").replace("G01 X40 Z0 F120",
                                                                        "G01 X40. Z0. F120.")
    body = re.sub(r"([IK])(-?\d+)(?![.\d])", r"\1\2.", body)
    return "%\nO0001\nG98\n" + body + "%\n"


def siemens_program(n: int) -> str:
    """:func:`plain_program` as a SINUMERIK 802 program: %_N_ framing, CR= for R, feed per
    minute (G94); a G0 to X100 Z10 stands for G92 (the 802 has no position setting)."""
    body = plain_program(n).split("\n", 1)[1]
    body = body.replace("G92 X100 Z10", "G94 G0 X100 Z10").replace("M03", "M3").replace(" R1.000",
                                                                                          " CR=1.000")
    return "%_N_BENCH_MPF\n;$PATH=/_N_MPF_DIR\n" + body


def macro_program(n: int) -> str:
    return (f"%2\n#1=0\n#2=0\nWHILE #1 LT {n}\n#1=#1+1\n#2=#2+SIN[#1*PI/180]*2\nENDW\nM30\n")


def linuxcnc_program(n: int) -> str:
    """:func:`plain_program` for LinuxCNC's interpreter: lathe plane and diameter mode (G18 G7)
    in mm for the ``%1`` line, M2 at the end (the same moves)."""
    return plain_program(n).replace("%1\n", "G18 G7 G21\n", 1) + "M2\n"


def _rs274() -> tuple[str | None, str]:
    """LinuxCNC's stand-alone interpreter, installed with apt when absent and possible."""
    import os
    import shutil
    import subprocess
    rs = shutil.which("rs274")
    if rs:
        return rs, ""
    if not shutil.which("apt-get"):
        return None, "rs274 is not installed and there is no apt-get to install linuxcnc-uspace"
    if os.geteuid() != 0:
        return None, "rs274 is not installed (apt-get install linuxcnc-uspace needs root)"
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    for cmd in (["apt-get", "install", "-y", "-qq", "linuxcnc-uspace"],
                ["apt-get", "update", "-qq"], ["apt-get", "install", "-y", "-qq", "linuxcnc-uspace"]):
        r = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode == 0 and cmd[1] == "install":
            break
    rs = shutil.which("rs274")
    if rs:
        return rs, ""
    return None, f"rs274 is not installed and apt-get could not install linuxcnc-uspace ({r.stderr.strip()[-200:]})"


def _timed(cmd: list[str], env=None) -> tuple[float, float, int]:
    """(wall s, CPU s of the child, peak RSS MB or -1) of one process run to its end. The
    peak RSS comes from ``/usr/bin/time`` when there is one (a forked child's own figure
    would start from this process's size)."""
    import os
    import subprocess
    timer = ["/usr/bin/time", "-f", "%M"] if os.path.exists("/usr/bin/time") else []
    t0 = time.perf_counter()
    p = subprocess.Popen(timer + cmd, stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE if timer else subprocess.DEVNULL, env=env)
    err = p.stderr.read() if timer else b""
    _, status, ru = os.wait4(p.pid, 0)
    dt = time.perf_counter() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.stderr:
        p.stderr.close()
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited with {p.returncode}")
    try:
        rss = int(err.decode().strip().splitlines()[-1]) // 1024
    except (ValueError, IndexError):
        rss = -1
    return dt, ru.ru_utime + ru.ru_stime, rss


def whole_process(n: int, runs: int = 7) -> None:
    import os
    import tempfile
    hnc = os.path.join(os.path.dirname(sys.executable), "hnc-cam")
    if not os.path.exists(hnc):
        hnc_cmd = [sys.executable, "-c", "import sys; from hnc_cam.cli import main; sys.exit(main())"]
    else:
        hnc_cmd = [hnc]
    rs, why = _rs274()
    # the Python processes as installed: with their bytecode cached (pip writes it at install)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.pop("HNC_CAM_PURE", None)
    pure_env = dict(env, HNC_CAM_PURE="1")
    from hnc_cam.nc import toolpath
    core = "built" if toolpath.core is not None else "NOT built (both rows are the Python code)"
    with tempfile.TemporaryDirectory() as d:
        nc = os.path.join(d, "plain.nc")
        ngc = os.path.join(d, "plain.ngc")
        tiny = os.path.join(d, "tiny.nc")
        with open(nc, "w") as f:
            f.write(plain_program(n))
        with open(ngc, "w") as f:
            f.write(linuxcnc_program(n))
        with open(tiny, "w") as f:
            f.write("%1\nG01 X1 Z1 F100\nM30\n")
        rows = {"hnc-cam run": (hnc_cmd + ["run", nc], env),
                "hnc-cam run, HNC_CAM_PURE=1": (hnc_cmd + ["run", nc], pure_env)}
        if rs:
            rows["rs274 -g (LinuxCNC)"] = ([rs, "-g", ngc, os.devnull], None)
        cold = {"hnc-cam run (3 lines)": (hnc_cmd + ["run", tiny], env),
                "python -c pass": ([sys.executable, "-c", "pass"], env)}
        _timed(hnc_cmd + ["run", tiny], env)  # writes the bytecode cache if it is missing
        best: dict[str, tuple] = {}
        loads = []
        for _ in range(runs):
            loads.append(os.getloadavg()[0])
            for name, (cmd, env) in {**rows, **cold}.items():
                r = _timed(cmd, env)
                if name not in best or r[0] < best[name][0]:
                    best[name] = r
    print(f"(e) whole processes, {n} plain blocks, best of {runs} (load average "
          f"{min(loads):.2f}..{max(loads):.2f}; compiled core {core}):")
    ref = best.get("rs274 -g (LinuxCNC)")
    for name in rows:
        wall, cpu, rss = best[name]
        ratio = f", {ref[0] / wall:.2f}x LinuxCNC's speed" if ref else ""
        print(f"    {name:30s} {wall:.3f} s wall ({n / wall:,.0f} blocks/s), {cpu:.3f} s CPU, "
              f"{rss} MB peak{ratio}")
    if not ref:
        print(f"    rs274: skipped: {why}")
    for name in cold:
        wall, cpu, rss = best[name]
        print(f"    cold start: {name:24s} {wall:.3f} s wall, {cpu:.3f} s CPU, {rss} MB peak")


def main(argv: list[str]) -> int:
    runs = 7
    if "--runs" in argv:
        i = argv.index("--runs")
        runs = int(argv[i + 1])
        del argv[i:i + 2]
    whole = "--whole" in argv
    argv = [a for a in argv if a != "--whole"]
    n = int(argv[1]) if len(argv) > 1 else 100_000
    if whole:
        whole_process(n, runs)
        return 0
    from hnc_cam.nc.interp import Interp, run
    from hnc_cam.nc import parser
    from hnc_cam.tooling import load_machine

    mach = load_machine(None)
    text = plain_program(n)
    nblocks = text.count("\n")
    run("%1\nG01 X1 Z1 F100\nM30\n", mach)  # warm imports
    best = cpu = None
    for _ in range(5):
        t0 = time.perf_counter()
        c0 = time.process_time()
        tp = run(text, mach)
        dt = time.perf_counter() - t0
        dc = time.process_time() - c0
        best = dt if best is None else min(best, dt)
        cpu = dc if cpu is None else min(cpu, dc)
    print(f"(a) plain G01/G02/G03 file: {nblocks} blocks, {len(tp.moves)} moves, "
          f"{best:.3f} s  ->  {nblocks / best:,.0f} blocks/s (load + run, best of 5; "
          f"CPU time {cpu:.3f} s -> {nblocks / cpu:,.0f} blocks/s: on a shared machine the CPU "
          f"figure is the one to compare)")
    import gc
    gc.disable()  # as run() does
    t0 = time.perf_counter()
    src = parser.load(text)
    t_load = time.perf_counter() - t0
    t0 = time.perf_counter()
    Interp(src, mach).run()
    t_run = time.perf_counter() - t0
    print(f"    of which: load/split {t_load:.3f} s, compile+execute {t_run:.3f} s")
    gc.enable()

    mtext = macro_program(n)
    dt = dc = None
    for _ in range(3):
        t0 = time.perf_counter()
        c0 = time.process_time()
        it = Interp(parser.load(mtext), mach)
        it.run()
        d = time.perf_counter() - t0
        c = time.process_time() - c0
        dt = d if dt is None else min(dt, d)
        dc = c if dc is None else min(dc, c)
    print(f"(b) macro WHILE loop: {n} iterations, {it.steps} statements, {dt:.3f} s  ->  "
          f"{it.steps / dt:,.0f} statements/s, {n / dt:,.0f} iterations/s (best of 3; CPU time "
          f"{dc:.3f} s -> {n / dc:,.0f} iterations/s)")

    dialects(n, mach)
    whole_process(n, runs)
    try:
        from pygcode import Line as PLine
    except ImportError:
        print("(c) pygcode not installed: no comparison")
        return 0
    lines = text.splitlines()
    m = min(len(lines), 20_000)
    t0 = time.perf_counter()
    c0 = time.process_time()
    for ln in lines[:m]:
        if ln.startswith("%"):
            continue
        PLine(ln)
    dt_pg = (time.perf_counter() - t0) * (len(lines) / m)
    dc_pg = (time.process_time() - c0) * (len(lines) / m)
    print(f"(c) pygcode Line() parse of the same file: {dt_pg:.3f} s "
          f"({len(lines) / dt_pg:,.0f} lines/s{', extrapolated from the first %d lines' % m if m < len(lines) else ''})"
          f"  ->  hnc_cam load+run is {dt_pg / best:.1f}x faster than pygcode's parse alone "
          f"(CPU time: pygcode {dc_pg:.3f} s, {dc_pg / cpu:.1f}x)")
    return 0


def dialects(n: int, mach) -> None:
    from hnc_cam import nc
    texts = {"hnc21t": plain_program(n), "fanuc0it": fanuc_program(n), "haas": fanuc_program(n),
             "siemens802": siemens_program(n)}
    from hnc_cam.nc import interp, toolpath
    best: dict[str, float] = {}
    moves: dict[str, int] = {}
    core = toolpath.core, interp._core
    for _ in range(3):
        for name, text in [*texts.items(), ("hnc21t Python code", texts["hnc21t"])]:
            if name == "hnc21t Python code":  # the HNC executor without its compiled core
                toolpath.core = interp._core = None
            try:
                c0 = time.process_time()
                tp = nc.run(text, mach, dialect=name.split()[0])
                c = time.process_time() - c0
            finally:
                toolpath.core, interp._core = core
            best[name] = min(best.get(name, c), c)
            moves[name] = len(tp.moves)
    ref = best["hnc21t Python code"]
    print("(d) the same moves per dialect (load + run, best of 3, CPU time; the ratios are to the "
          "HNC-21T executor's Python code, which the other dialects' executors extend):  " + ",  ".join(
              f"{k} {v:.3f} s ({moves[k]} moves, {v / ref:.2f}x)" for k, v in best.items()))
    try:
        import linuxcnc  # noqa: F401
    except ImportError:
        print("    LinuxCNC's Python module is not installed: no LinuxCNC figure")


if __name__ == "__main__":
    sys.exit(main(sys.argv))
