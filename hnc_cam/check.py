"""The ``hnc-cam simulate`` and ``hnc-cam verify`` commands.

``simulate PROGRAM --stock SPEC [--model PART] [--set N=V] [--machine FILE] [--tools FILE]
[--json OUT] [--plot OUT]`` prints the summary; ``--json`` writes
``{"machined": [[[X, Z], ...], ...], "collisions": [{"line", "block", "message"}],
"cycle_time_s", "removed_volume_mm3"}`` (rings of the remaining material, X as diameter).
Exit 0, or 1 when there is a collision (or another check finding), 2 on bad input.

The ``collisions`` list (its name is the contract) carries every finding of the simulator's
checks, each with the program line and block; the message starts with the check's name:
``"collision: ..."`` (a rapid that cuts material), ``"spindle stopped: ..."`` (a feed move that
cuts, or any thread move, while the spindle is not turning), ``"zero feed: ..."`` (a move at
feed 0 that cuts), ``"non-cutting edge: ..."`` (a feed move that cuts with the back of a known
insert or the top of a blade). Rapids that only shave a sliver thinner than 0.1 mm are notes in
the printed summary, not findings.

``verify PROGRAM --model PART [--set N=V] --stock SPEC [--tol MM] [--strict] [--machine FILE]
[--tools FILE] [--json OUT] [--plot OUT]`` also compares with the model and writes
``{"pass", "max_overcut_mm", "max_undercut_mm", "unreachable": [{"z", "x", "size_mm"}],
"collisions", "cycle_time_s", "air_cut_fraction"}`` (``x`` as diameter). Exit 0 pass, 1 fail,
2 bad input.

Machine and tools: ``--tools FILE`` replaces the default tool library, whose tools fill the
offset registers; ``--machine FILE`` gives the machine and its own ``[[register]]`` entries
(which win). A register in neither is a sharp point. The model (a part file or a STEP file)
is loaded through :mod:`hnc_cam.cad`, imported only here and only when a model is needed.
"""
from __future__ import annotations

import argparse
import json
import math
import re
import sys

from .errors import HncError, StockError
from .io import write_atomic


def _machine(args: argparse.Namespace):
    from .tooling import load_machine, load_tools, with_grip
    tools = load_tools(args.tools) if getattr(args, "tools", None) else None
    mach = load_machine(getattr(args, "machine", None), tools)
    grip = getattr(args, "grip", None)
    return mach if grip is None else with_grip(mach, grip)


def _toolpath(path: str, machine, dialect: str | None = None):
    """Run the program (read as ``dialect``: default the machine's controller, else HNC); the
    tool starts at the machine's reference point (converted into the active work system by
    the interpreter, as `hnc-cam run` does)."""
    from .nc.interp import run_file
    return run_file(path, machine, start="reference", dialect=dialect)


def _model(path: str, params: list[str] | dict[str, str], args: argparse.Namespace | None = None):
    from .cad import load_part, parse_set
    from .cad.loader import profile_options
    kw = profile_options(args) if args is not None else {}
    return load_part(path, params if isinstance(params, dict) else parse_set(params), **kw)


_HEADER_RE = re.compile(r"^(?:\((PARAMETERS|STOCK|GRIP) (.*)\)|;\s*(PARAMETERS|STOCK|GRIP) (.*?))\s*$")


def program_header(path: str) -> tuple[dict[str, str] | None, str | None]:
    """``(params or None, stock or None)`` of :func:`header_fields`."""
    h = header_fields(path)
    return h.get("PARAMETERS"), h.get("STOCK")


def header_fields(path: str) -> dict:
    """The ``(PARAMETERS name=value ...)``, ``(STOCK spec)`` and ``(GRIP mm)`` comments that
    ``generate`` writes at the head of a program (``; PARAMETERS ...`` and so on in an 802
    one): ``{"PARAMETERS": {name: value}, "STOCK": spec, "GRIP": mm}``, the keys found. Only a
    regular file is read here (at most its first 64 KiB, up to the first block that is not a
    comment)."""
    import os
    import stat
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return {}
        with open(path, "rb") as f:
            head = f.read(65536)
    except OSError:
        return {}  # the interpreter reports the file
    out: dict = {}
    for n, raw in enumerate(head.decode("utf-8", "replace").splitlines()):
        line = raw.strip()
        # the program's start: HNC's %nnnn line; FANUC's % line, then O1234 (NAME); the
        # 802's %_N_NAME_MPF line, then ;$PATH=...
        if not line or n < 2 and (line.startswith("%") or re.match(r"O\d", line)):
            continue
        if not line.startswith(("(", ";")):
            break
        m = _HEADER_RE.match(line)
        key, value = (m.group(1) or m.group(3), m.group(2) or m.group(4)) if m else (None, None)
        if key is None or key in out:
            continue
        if key == "PARAMETERS":
            out[key] = dict(t.split("=", 1) for t in value.split() if "=" in t)
        else:
            out[key] = value.strip()
    return out


def _from_header(args: argparse.Namespace, model_needs_params: bool) -> None:
    """Fill ``args.params``, ``args.stock`` and ``args.grip`` from the program's header
    comments where the command line gives none, and say so on stderr."""
    h = header_fields(args.program)
    params, stock = h.get("PARAMETERS"), h.get("STOCK")
    used = []
    if getattr(args, "grip", None) is None and h.get("GRIP"):
        try:
            grip = float(h["GRIP"])
        except ValueError:
            grip = None  # not a number: a comment like any other
        if grip is not None and math.isfinite(grip) and grip > 0:
            args.grip = grip
            used.append(f"grip {h['GRIP']} mm")
    if not args.params and params and model_needs_params:
        from .cad.loader import CAD_SUFFIXES
        from pathlib import Path
        if Path(args.model).suffix.lower() not in CAD_SUFFIXES:
            args.params = dict(params)
            used.append("parameters " + " ".join(f"{k}={v}" for k, v in params.items()))
    if not args.stock and stock:
        args.stock = stock
        used.append(f"stock {stock}")
    if not args.stock:
        import os
        if not os.path.isfile(args.program):  # no program there: the interpreter's one line
            _toolpath(args.program, None)
        raise StockError(f"{args.program}: the program carries no (STOCK ...) line: give "
                         f"--stock SPEC")
    if used:
        print(f"note: {args.program}: {' and '.join(used)} from the program's header "
              f"(--set/--stock/--grip override)", file=sys.stderr)


def _stock(spec: str):
    from .tooling import Stock
    return Stock.parse(spec)


def _write_json(out: str, data: dict) -> None:
    try:
        write_atomic(out, json.dumps(data, separators=(",", ":")) + "\n")
    except OSError as e:
        raise HncError(f"--json {out}: cannot write: {e.strerror or e}") from None


def _plot(m, out: str, **kw) -> None:
    from .sim.plot import plot
    try:
        plot(m, out, **kw)
    except OSError as e:
        raise HncError(f"--plot {out}: cannot write: {e.strerror or e}") from None


def simulate_command(args: argparse.Namespace) -> int:
    from .sim import simulate
    _from_header(args, bool(args.model))
    machine = _machine(args)
    stock = _stock(args.stock)
    model = None
    if stock.kind == "offset" and not args.model:
        raise StockError(f"stock {args.stock!r}: an offset:A stock needs --model PART")
    if args.params and not args.model:
        raise HncError("--set needs --model")
    if args.model:  # the offset:A blank, and the model outline in the plot
        model = _model(args.model, args.params, args).profile
    tp = _toolpath(args.program, machine, getattr(args, "dialect", None))
    for w in tp.warnings:
        print(f"{tp.file}:{w.line}: warning: {w.message}", file=sys.stderr)
    m = simulate(tp, stock, machine, model=model)
    print(m.summary(), file=sys.stderr if args.json == "-" else sys.stdout)
    if args.json:
        _write_json(args.json, m.to_json())
    if args.plot:
        _plot(m, args.plot, model=model)
    return 1 if m.issues else 0


def verify_command(args: argparse.Namespace) -> int:
    from .sim import simulate, verify
    if not (isinstance(args.tol, float) and math.isfinite(args.tol) and args.tol > 0):
        raise HncError(f"--tol {args.tol}: the tolerance must be a positive number of mm")
    _from_header(args, True)
    if getattr(args, "program2", None):
        return _verify_setups(args)
    machine = _machine(args)
    stock = _stock(args.stock)
    loaded = _model(args.model, args.params, args)
    tp = _toolpath(args.program, machine, getattr(args, "dialect", None))
    for w in tp.warnings:
        print(f"{tp.file}:{w.line}: warning: {w.message}", file=sys.stderr)
    m = simulate(tp, stock, machine, model=loaded.profile)
    rep = verify(m, loaded.profile, tol=args.tol, threads=loaded.threads, strict=args.strict)
    out = sys.stderr if args.json == "-" else sys.stdout  # stdout carries only the JSON
    print(f"{tp.file} against {args.model}:", file=out)
    print(rep.summary(), file=out)
    if args.json:
        _write_json(args.json, rep.to_json())
    if args.plot:
        _plot(m, args.plot, report=rep, model=loaded.profile, title=f"{tp.file} vs {loaded.name}")
    if getattr(args, "report", None) or getattr(args, "junit", None):
        from .report import verify_outputs
        verify_outputs(args, m, rep, loaded)
    return 0 if rep.passed else 1


def _verify_setups(args: argparse.Namespace) -> int:
    """``verify P1 P2 --model PART``: a part made in two setups (``generate --setups 2``).
    P1 runs from the stock (its header's, or ``--stock``) held by ``--grip`` (or its header's
    GRIP); P2 from what P1 left, turned around, held by the jaws its own header's GRIP names;
    the final material is compared with the whole part turned around."""
    from .plan.setups import verify_setups
    from .tooling import with_grip
    if getattr(args, "plot", None) or getattr(args, "report", None) or \
            getattr(args, "junit", None):
        raise HncError("--plot, --report and --junit are written for one program; verify "
                       "P1 P2 prints and writes --json")
    machine1 = _machine(args)
    stock = _stock(args.stock)
    h2 = header_fields(args.program2)
    try:
        grip2 = float(h2.get("GRIP", "nan"))
    except ValueError:
        grip2 = math.nan
    if not (math.isfinite(grip2) and grip2 > 0):
        raise StockError(f"{args.program2}: the second setup's program carries no (GRIP mm) "
                         f"line: the jaws holding the turned-around part are not known")
    from dataclasses import replace
    from .tooling import load_machine, load_tools
    tools = load_tools(args.tools) if getattr(args, "tools", None) else None
    base = load_machine(getattr(args, "machine", None), tools)
    machine2 = with_grip(base, grip2)
    loaded = _model(args.model, args.params, args)
    dialect = getattr(args, "dialect", None)
    tp1 = _toolpath(args.program, machine1, dialect)
    tp2 = _toolpath(args.program2, replace(machine2), dialect)
    for tp in (tp1, tp2):
        for w in tp.warnings:
            print(f"{tp.file}:{w.line}: warning: {w.message}", file=sys.stderr)
    m1, m2, rep = verify_setups(tp1, tp2, stock, machine1, machine2, loaded.profile,
                                tol=args.tol, strict=args.strict, threads=loaded.threads)
    out = sys.stderr if args.json == "-" else sys.stdout
    print(f"{tp1.file} then {tp2.file} (turned around) against {args.model}:", file=out)
    for i in m1.issues:
        print(f"setup 1: {i}", file=out)
    print(f"setup 1: cycle time {m1.cycle_time_s:.1f} s, air cut "
          f"{100 * m1.air_cut_fraction:.1f} % of feed time", file=out)
    print(rep.summary(), file=out)
    if args.json:
        data = rep.to_json()
        data["setups"] = [{"cycle_time_s": round(m.cycle_time_s, 3),
                           "air_cut_fraction": round(m.air_cut_fraction, 4),
                           "collisions": [i.to_json() for i in m.issues]} for m in (m1, m2)]
        _write_json(args.json, data)
    return 0 if rep.passed else 1
