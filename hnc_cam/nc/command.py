"""``hnc-cam run PROGRAM [--machine FILE] [--json OUT] [--dialect NAME] [--vars FILE]``.

The tool starts at the machine's reference point (as after homing, and as ``simulate``
does). Prints the toolpath summary on stdout (or on stderr when the JSON goes to stdout), the
warnings on stderr as ``FILE:LINE: warning: MESSAGE``, and writes the JSON when asked.
Alarms propagate as :class:`~hnc_cam.errors.NCError`; the CLI prints them as
``FILE:LINE:COL: alarm: MESSAGE  [block]`` and exits 2 (LINE is the line in the file, also
inside subprograms). A program file that cannot be read is ``error: FILE: cannot read the
program: REASON`` (exit 2; no line or column to point at), as for any unreadable input file.

Only light modules are imported here: no OCP, build123d, cadquery, shapely or numpy.
"""
from __future__ import annotations

import sys


def run_command(args) -> int:
    import gc
    gc.disable()  # a short-lived process building many small objects: GC passes only cost time
    from ..io import write_atomic
    from ..tooling import load_machine
    from .interp import run_file

    machine = load_machine(getattr(args, "machine", None))
    tp = run_file(args.program, machine, start="reference",  # as `simulate`: after homing
                  dialect=getattr(args, "dialect", None), persist=getattr(args, "vars", None))
    for w in tp.warnings:
        print(f"{tp.file}:{w.line}: warning: {w.message}", file=sys.stderr)
    out = getattr(args, "json", None)
    summary_stream = sys.stderr if out == "-" else sys.stdout
    print(tp.summary(), file=summary_stream)
    if out:
        try:
            write_atomic(out, tp.dumps() + "\n")
        except OSError as e:
            from ..errors import HncError
            raise HncError(f"cannot write {out}: {e.strerror or e}") from None
    return 0
