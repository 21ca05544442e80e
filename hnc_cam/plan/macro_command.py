"""``hnc-cam family PART --macro``: one parametric macro program for the family, derived by
:mod:`hnc_cam.plan.macro_program` and proven by ``--check`` before anything is written."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from ..errors import PartError, PlanError

#: the domain box: each real parameter within this fraction of its value (grown to cover the
#: table's rows)
SPREAD = 0.05
#: parameter sets ``--check`` runs by default
DEFAULT_CHECK = 5
#: the dialects a macro program is written in
DIALECTS = ("hnc21t", "fanuc0it", "siemens802")
#: generate() keywords a variant takes from the command line
_GEN_KEYS = ("tools", "machine", "templates", "number_format", "block_numbers", "thread_cycle",
             "face_cycle", "material", "allowance", "grip", "partoff", "partoff_dia")


def _rows(path: str) -> list[tuple[int, dict[str, str]]]:
    from .command import read_table
    _header, rows = read_table(path)
    out = []
    for _idx, line, cells in rows:
        if isinstance(cells, str):
            raise PartError(f"{path}:{line}: {cells}")
        cells = {k: v for k, v in cells.items() if k not in ("program_number", "stock") and v}
        out.append((line, cells))
    if not out:
        raise PartError(f"{path}: the table has no rows")
    return out


def _row_refused(fam: Any, table: str, line: int, r: dict[str, Any]) -> None:
    """A table row the family refuses, named with its line: the sketch's own message with the
    row's values (its ``require`` checks), else the traced check it breaks."""
    from .macro import _holds
    try:
        fam.mod.sketch(**r)
    except PartError as e:  # the family's own checks (require, positive, a corner that fits)
        raise PartError(f"{table}:{line}: the family refuses this row: "
                        f"{str(e).splitlines()[0]}") from None
    except Exception as e:  # noqa: BLE001 - the family's sketch fails on the row: named
        raise PartError(f"{table}:{line}: the family's sketch() fails for this row: "
                        f"{type(e).__name__}: {str(e).splitlines()[0] if str(e) else ''}"
                        .rstrip(": ")) from None
    for ch in fam.trace.checks:
        try:
            ok = all(_holds(c, r) for c in ch.conds)
        except (ArithmeticError, ValueError):  # a check that cannot be evaluated there
            ok = False
        if not ok:
            raise PartError(f"{table}:{line}: the family refuses this row "
                            f"({', '.join(f'{k}={r[k]:g}' for k in ch.names)}): "
                            f"{ch.message}")


def macro_command(args: argparse.Namespace) -> int:
    from ..cad import parse_set
    from ..io import write_atomic
    from .api import VerificationError, _load_machine, _load_tools, dialect_of
    from .command import _check_part_file, _check_tables, _options
    from .macro import load_family
    from .macro_program import (Ctx, check_program, derive_pieces, family_stock, with_lost,
                                fix_unmachinable, piece_of, render_program, sample)

    if getattr(args, "out", None):
        raise PlanError("--macro writes one program: give it with -o OUT (--out DIR is the "
                        "per-row mode's folder)")
    for opt in ("scheduler", "report", "junit"):
        if getattr(args, opt, None):
            raise PlanError(f"--{opt} belongs to the per-row mode, not to --macro")
    _check_part_file(args.part)
    _check_tables(args)
    if Path(args.part).suffix.lower() != ".py":
        raise PartError(f"{args.part}: --macro derives the program from a family's sketch(): "
                        f"give the part's .py file")
    opts = _options(args)
    lib = _load_tools(opts["tools"])
    mach = _load_machine(opts["machine"], lib)
    if opts["grip"] is not None:
        from ..tooling import with_grip
        mach = with_grip(mach, float(opts["grip"]))
    dia = dialect_of(opts["dialect"], mach)
    if dia not in DIALECTS:
        raise PlanError(f"--macro writes {' and '.join(DIALECTS)} macro programs, not {dia}")
    base = parse_set(args.params or [])
    rows = []
    lines: list[int] = []
    if args.table:
        from ..cad.loader import load_module, resolve_params
        mod = load_module(args.part)
        for line, cells in _rows(args.table):
            try:
                resolve_params(mod, dict(base, **cells), args.part)
            except PartError as e:
                msg = str(e).split(": ", 1)[-1] if str(e).startswith(args.part) else str(e)
                raise PartError(f"{args.table}:{line}: {msg}") from None
            rows.append(cells)
            lines.append(line)
    fam = load_family(args.part, base, rows, spread=SPREAD)
    from ..cad.loader import resolve_params
    full_rows = [dict(fam.params, **resolve_params(fam.mod, r, args.part)) for r in rows]
    for line, r in zip(lines, full_rows):  # a row the family itself refuses: before deriving
        _row_refused(fam, args.table, line, r)
    gen = {k: opts[k] for k in _GEN_KEYS}
    gen.update(comp="control", verify=False, dialect=dia)
    if args.stock:
        from ..tooling import Stock
        if Stock.parse(args.stock).kind == "offset":
            raise PlanError("--macro needs a bar or tube stock (DxL+F), not an offset stock: "
                            "one stock serves every variant")
        stock = Stock.parse(args.stock).spec
    else:
        stock = family_stock(fam, fam.lo, fam.hi,
                             sample(fam, fam.trace, fam.lo, fam.hi, 20, "stock") + full_rows)
    ctx = Ctx(args.part, gen, stock, dia)
    try:  # the derivation's refusal names where the sketch lost an expression
        fixed = fix_unmachinable(ctx, fam)
        for i, r in enumerate(full_rows, 1):
            for k, why in fixed.items():
                if r[k] != fam.params[k]:
                    raise PartError(f"{args.table}: row {i} gives {k}={r[k]:g}: {k} stays "
                                    f"at {fam.params[k]:g} in the macro ({why})")
        pieces = derive_pieces(ctx, fam)
    except PlanError as e:
        raise with_lost(fam, e) from None
    number = args.program_number if args.program_number is not None else 1
    if not 1 <= number <= 8999:
        raise PlanError(f"--program-number {number}: the macro program needs 1-8999 (its "
                        f"subprogram is numbered 1000 above it)")
    # the rows each piece holds
    held: dict[int, list[dict[str, Any]]] = {i: [] for i in range(len(pieces))}
    for i, r in enumerate(full_rows, 1):
        pc = piece_of(pieces, r)
        if pc is None:
            out = [k for k in fam.narrowed if not fam.lo[k] <= r[k] <= fam.hi[k]]
            if out:
                k = out[0]
                raise PartError(f"{args.table}: row {i} gives {k}={r[k]:g}, outside the "
                                f"macro's {k} {fam.lo[k]:g}..{fam.hi[k]:g} (the tool library "
                                f"does not cut {fam.narrowed[k][2]})")
            raise PartError(f"{args.table}: row {i} ({', '.join(f'{k}={r[k]:g}' for k in fam.free)}) "
                            f"fails the family's checks")
        held[pieces.index(pc)].append(r)
    n_check = DEFAULT_CHECK if args.check is None else args.check
    per_piece = -(-n_check // len(pieces))  # N sets over the whole domain, each piece its share
    texts: list[tuple[str, str]] = []
    checked = 0
    for i, pc in enumerate(pieces):
        num = number + i
        prow = held[i]
        final = render_program(pc, dia, rows=prow or None, number=num)
        runs = [(f"sample {j + 1}", p, render_program(pc, dia, values=p, number=num))
                for j, p in enumerate(sample(fam, pc.tr, pc.lo, pc.hi, per_piece, ("check", i),
                                             extra=pc.extra))]
        runs += [(f"table row {j}", r, render_program(pc, dia, rows=prow, row=j, number=num))
                 for j, r in enumerate(prow, 1)]
        for res in check_program(ctx, pc, runs, mach, lib, opts["tol"]):
            checked += 1
            if not res["ok"]:
                raise VerificationError(f"{args.part}: the macro program fails its check for "
                                        f"{res['set']} ({res['params']}): {res['message']}; "
                                        f"nothing written")
        texts.append((f"O{num:04d}.nc", final.text))
    out = args.output
    if dia == "siemens802" and out and (out.endswith("/") or Path(out).is_dir()):
        # -o DIR/: the main program(s) and each subprogram in its own file (NAME.MPF,
        # NAME_C1.SPF, ...), all or none
        from .export import write_program_folder
        write_program_folder(out, "".join(t for _n, t in texts))
        texts = []
    elif dia == "siemens802" and len(texts) > 1:
        raise PlanError(f"{args.part}: the family's program changes shape over the domain, "
                        f"so it is {len(texts)} programs ("
                        + "; ".join(", ".join(pc.bounds) for pc in pieces)
                        + "): give a folder with -o DIR/")
    if not texts:
        pass
    elif len(texts) > 1:
        if not out or not (out.endswith("/") or Path(out).is_dir()):
            raise PlanError(f"{args.part}: the family's program changes shape over the domain, "
                            f"so it is {len(texts)} programs ("
                            + "; ".join(", ".join(pc.bounds) for pc in pieces)
                            + "): give a folder with -o DIR/")
        d = Path(out)
        try:
            d.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            raise PlanError(f"-o {out}: cannot create the folder: {e.strerror or e}") from None
        for name, text in texts:
            write_atomic(d / name, text)
    elif out:
        if out.endswith("/") or Path(out).is_dir():
            Path(out).mkdir(parents=True, exist_ok=True)
            write_atomic(Path(out) / texts[0][0], texts[0][1])
        else:
            write_atomic(out, texts[0][1])
    else:
        sys.stdout.write(texts[0][1])
        sys.stdout.flush()
    fitted = sum(pc.fitted for pc in pieces)
    print(f"{args.part}: {len(pieces)} macro program(s) for {len(fam.free)} parameter(s) "
          f"({', '.join(fam.free)}), {fitted} fitted word(s), stock {stock}; "
          + (f"checked {checked} parameter set(s): pass" if checked else
             "not checked through the interpreter (--check 0)")
          + ("" if len(pieces) == 1 else
             "; pieces: " + "; ".join(", ".join(pc.bounds) for pc in pieces)), file=sys.stderr)
    for k, why in fixed.items():
        print(f"warning: {k} stays at {fam.params[k]:g}: {why}", file=sys.stderr)
    for k, (given, kept, why) in fam.narrowed.items():
        print(f"warning: {k} spans {fam.lo[k]:g}..{fam.hi[k]:g}, not to the DOMAIN's "
              f"{given:g}: the tool library does not cut {why}", file=sys.stderr)
    return 0
