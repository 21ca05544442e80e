"""FANUC 0i-T reader throughput against the HNC-21T reader on the same moves.

The program of ``benchmarks/interp.py`` (a zig-zag of G01 lines and G02/G03 half-arcs,
N blocks), written once for each controller: HNC-21T as there, FANUC with ``%``/``O`` framing
and a decimal point on every coordinate (the form the FANUC post writes, which the reader's
plain-block path takes). Three figures, each the best of 5, printed as FANUC/HNC ratios:

(a) load (split, frame, classify, the decimal-point note);
(b) load + reading every statement as the interpreter's compile does (``fast_words``, else
    ``parse_statement``);
(c) ``hnc_cam.nc.run`` end to end (load, compile, execute).

Run: ``python benchmarks/fanuc_reader.py [N]`` (default 100,000).
"""
from __future__ import annotations

import sys
import time

from interp import moves


def hnc_program(n: int) -> str:
    return "\n".join(["%1", "G92 X100 Z10", "M03 S800", "G94 G01 X40 Z0 F120"] + moves(n, zero="0.")
                     + ["M30"]) + "\n"


def fanuc_program(n: int) -> str:
    return "\n".join(["%", "O0001", "G50 X100. Z10.", "M03 S800", "G98 G01 X40. Z0. F120."]
                     + moves(n, zero="0.") + ["M30", "%"]) + "\n"


def best(fn, k: int = 5) -> float:
    out = None
    for _ in range(k):
        t0 = time.perf_counter()
        fn()
        dt = time.perf_counter() - t0
        out = dt if out is None or dt < out else out
    return out


def read_all(syntax, text: str) -> None:
    src = syntax.load(text)
    fast, parse = syntax.fast_words, syntax.parse_statement
    for i, t in enumerate(src.text):
        if src.kind[i] == "x" and fast(t) is None:
            parse(t, src.lineno[i])


def main(argv: list[str]) -> int:
    n = int(argv[1]) if len(argv) > 1 else 100_000
    from hnc_cam import dialect
    from hnc_cam.nc import run
    from hnc_cam.tooling import load_machine

    mach = load_machine(None)
    h_text, f_text = hnc_program(n), fanuc_program(n)
    hs, fs = dialect.get("hnc21t").syntax(), dialect.get("fanuc0it").syntax()
    assert not fs.load(f_text).notes, "the FANUC program should need no decimal-point note"
    rows = [
        ("load", lambda: hs.load(h_text), lambda: fs.load(f_text)),
        ("load + read statements", lambda: read_all(hs, h_text), lambda: read_all(fs, f_text)),
        ("nc.run (load, compile, execute)", lambda: run(h_text, mach, dialect="hnc21t"),
         lambda: run(f_text, mach, dialect="fanuc0it")),
    ]
    print(f"{n:,} blocks, best of 5")
    for name, h, f in rows:
        th, tf = best(h), best(f)
        print(f"  {name:34s} HNC {th:.3f} s  FANUC {tf:.3f} s  ratio FANUC/HNC {tf / th:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
