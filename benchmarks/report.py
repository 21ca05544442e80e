"""Benchmark: size of the HTML report and its load time in headless Chromium.

    python benchmarks/report.py              # every bundled part, then a 100,000-move program
    python benchmarks/report.py --parts      # only the bundled parts
    python benchmarks/report.py --moves 10   # only the long program, 10 passes (10,000 moves)

Per bundled part (its defaults, ``hnc-cam generate``'s program): moves, report size (KiB) and
the share of it that is data, time to build the page, and the load time in headless Chromium
(navigation until the page's script is ready: data parsed, first frame drawn) and the time of
one full redraw. The long program is benchmarks/verify.py's WHILE-loop program (K passes of
1,000 G01 segments): 100 passes give about 100,000 moves. Without Chromium the browser
columns say so.
"""
from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))


def browser_times(page: Path, b) -> tuple[float, float]:
    load = b.open(page, timeout=300)
    assert not b.errors(), b.errors()
    draw = b.eval("(function(){var t=performance.now(); window.hncReport.draw(); "
                  "return performance.now()-t;})()")
    assert b.eval("window.hncReport.drawnMoves()") == b.eval("window.hncReport.moves")
    return load, draw / 1000.0


def row(name: str, moves: int, page: Path, build_s: float, b) -> None:
    text = page.read_text()
    size = len(text.encode())
    i = text.find('<script id="hnc-data"')
    data = len(text[i:text.find("</script>", i)].encode())
    if b is not None:
        load, draw = browser_times(page, b)
        tail = f"{load:8.2f} s {draw * 1000:8.1f} ms"
    else:
        tail = "   (no Chromium)"
    print(f"{name:28s} {moves:8d} {size / 1024:10.1f} {100 * data / size:6.1f} % "
          f"{build_s:8.2f} s {tail}", flush=True)


def parts(b, out: Path) -> None:
    import hnc_cam
    from hnc_cam.report import program_report
    for part in sorted((ROOT / "parts").glob("*.py")):
        try:
            prog = hnc_cam.generate(str(part), verify=False)
        except Exception as e:  # a part that needs parameters or cannot be generated
            print(f"{part.name:28s} not generated: {e}")
            continue
        page = out / f"{part.stem}.html"
        t0 = time.perf_counter()
        program_report(page, prog)
        row(part.name, len(prog.toolpath.moves), page, time.perf_counter() - t0, b)


def long_program(b, out: Path, passes: int) -> None:
    import verify as vb

    from hnc_cam.nc.interp import run
    from hnc_cam.report import write_report
    from hnc_cam.sim import simulate
    from hnc_cam.tooling import Machine, Stock
    machine = Machine()
    tp = run(vb.program(passes), machine, file=f"bench{passes}.nc", start=(50.0, 80.0))
    t0 = time.perf_counter()
    m = simulate(tp, Stock.parse("40x60"), machine)
    t1 = time.perf_counter()
    page = out / f"bench{passes}.html"
    write_report(page, m, None, None, title=f"{len(tp.moves)} moves")
    t2 = time.perf_counter()
    print(f"(simulate {t1 - t0:.1f} s; the page's keyframes replay the sweeps: build below)")
    row(f"WHILE program, {passes} passes", len(tp.moves), page, t2 - t1, b)


def main(argv: list[str]) -> None:
    from hnc_cam.report.browser import Chromium, find_chromium
    do_parts = "--moves" not in argv
    do_long = "--parts" not in argv
    passes = int(argv[argv.index("--moves") + 1]) if "--moves" in argv else 100
    b = Chromium() if find_chromium() else None
    print(f"{'program':28s} {'moves':>8s} {'size KiB':>10s} {'data':>8s} {'build':>10s} "
          f"{'load':>10s} {'redraw':>11s}")
    try:
        with tempfile.TemporaryDirectory() as d:
            if do_parts:
                parts(b, Path(d))
            if do_long:
                long_program(b, Path(d), passes)
    finally:
        if b is not None:
            b.close()


if __name__ == "__main__":
    main(sys.argv[1:])
