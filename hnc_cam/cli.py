"""The ``hnc-cam`` command. Thin: parse arguments, call the API, print, exit.

Exit codes: 0 ok, 1 verification failed or collision, 2 bad input (one line, no traceback).
Each sub-command's work lives in the module that owns it; this file only wires them.
"""
from __future__ import annotations

import argparse
import math
import sys
from typing import Callable, Sequence


def _positive_mm(s: str) -> float:
    """A tolerance: a finite number of mm above zero."""
    try:
        v = float(s)
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"{s!r}: expected a positive number of mm")
    return v


def _grip(s: str) -> float:
    """A grip length: a finite number of mm above zero."""
    try:
        v = float(s)
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"{s!r}: expected the grip length in the chuck, a "
                                         f"positive number of mm")
    return v


def _add_grip(p: argparse.ArgumentParser) -> None:
    p.add_argument("--grip", type=_grip, metavar="MM", help="mm of the stock's left end held "
                   "in the chuck's jaws (default: the machine file's [chuck] grip; none: the "
                   "jaws are not modelled); stick-out = stock length - grip")


def _jobs(s: str) -> int:
    try:
        v = int(s)
    except ValueError:
        v = -1
    if v < 0:
        raise argparse.ArgumentTypeError(f"{s!r}: expected a whole number of workers (0 = all "
                                         f"cores)")
    return v


def _count(s: str) -> int:
    try:
        v = int(s)
    except ValueError:
        v = -1
    if not 0 <= v <= 10000:
        raise argparse.ArgumentTypeError(f"{s!r}: expected a whole number of parameter sets "
                                         f"(0-10000)")
    return v


def _scheduler(s: str) -> str:
    """A Dask scheduler address, tcp://HOST:PORT (checked here; connected to by family)."""
    import re
    if not re.fullmatch(r"tcp://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9._-]+):[0-9]{1,5}", s) or \
            not 0 < int(s.rsplit(":", 1)[1]) < 65536:
        raise argparse.ArgumentTypeError(f"{s!r}: expected a Dask scheduler address "
                                         f"tcp://HOST:PORT")
    return s


class _Parser(argparse.ArgumentParser):
    """Bad options are one line on stderr and exit 2 (no usage block)."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _add_profile_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--axis", metavar="AXIS", help="the part's turning axis in the model: Z "
                   "(default), X, Y, -X, -Y, -Z or px,py,pz,dx,dy,dz")
    p.add_argument("--zero", metavar="WHERE", help="program zero: right (default) or left face "
                   "of the part, or a coordinate along the axis")
    p.add_argument("--envelope", action="store_true", help="profile the turned envelope of a "
                   "part with milled features (flats, holes, slots)")
    p.add_argument("--fit-tol", type=_positive_mm, metavar="MM", help="arc-fitting tolerance "
                   "for free-form curves (default 0.001)")
    p.add_argument("--thread", action="append", metavar="SPEC", help="a thread the model "
                   "does not declare (a STEP file cannot): [M]DxP@ZSTART:ZEND[,starts=N]"
                   "[,internal][,angle=DEG], Z with the right face at Z0, e.g. M12x1.5@0:-19 "
                   "(repeatable)")


def _add_set(p: argparse.ArgumentParser) -> None:
    p.add_argument("--set", dest="params", action="append", default=[], metavar="NAME=VALUE",
                   help="part parameter (repeatable)")


def _add_gen_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--stock", metavar="SPEC", help="stock: DxL, DxL+F, D/dxL[+F] or offset:A "
                   "(default: the part file's STOCK)")
    p.add_argument("--tools", metavar="FILE", help="tool library TOML (default: bundled)")
    p.add_argument("--machine", metavar="FILE", help="machine TOML (default: bundled)")
    p.add_argument("--comp", choices=["cam", "control"], default="cam",
                   help="cam: compensated tip path with G40; control: part profile with G41/G42")
    p.add_argument("--templates", metavar="DIR", help="folder of templates overriding the defaults")
    p.add_argument("--program-number", type=int, metavar="N", help="program number (%%nnnn)")
    p.add_argument("--no-verify", action="store_true", help="do not simulate and verify")
    p.add_argument("--tol", type=_positive_mm, default=0.01, metavar="MM",
                   help="verification tolerance")
    p.add_argument("--number-format", choices=["plain", "point", "zero"], default="plain",
                   help="how whole numbers are written: X20 (plain), X20. (point), X20.0 (zero)")
    p.add_argument("--block-numbers", choices=["every", "pq"], default="every",
                   help="N numbers on every block, or only on the blocks P/Q refer to")
    p.add_argument("--thread-cycle", choices=["g76", "g82"], default="g76",
                   help="threads with one G76 block or with G82 passes")
    p.add_argument("--face-cycle", choices=["g81", "g01"], default="g81",
                   help="facing with G81 cycles or with G01 passes")
    p.add_argument("--material", metavar="NAME", help="work material from the bundled table "
                   "(C45, 304, 6061, brass, GG25 or an alias; default: the part file's MATERIAL)")
    p.add_argument("--allowance", metavar="X,Z", help="finishing allowance in mm, X on the "
                   "diameter (default: the material's, else 0.4,0.1)")
    p.add_argument("--explain", action="store_true", help="print the planner's reasoning for "
                   "each operation on stderr")
    _add_grip(p)
    p.add_argument("--no-partoff", action="store_true", help="leave the part on the bar, its "
                   "left end cut just past the part (a blank made to length); by default a "
                   "part held by --grip is parted off")
    p.add_argument("--partoff-dia", type=_positive_mm, metavar="MM", help="end the part-off "
                   "at this diameter (a stem for a parts catcher) instead of past the centre")
    p.add_argument("--drill-style", choices=["blocks", "macro"], default="blocks",
                   help="peck drilling as plain blocks, or as a WHILE-loop macro subprogram "
                   "called with G65 (HNC-21T; the HNC-21T has no peck-drilling cycle)")


def _add_dialect(p: argparse.ArgumentParser) -> None:
    from .dialect import names
    p.add_argument("--dialect", choices=names(), metavar="NAME",
                   help=f"controller dialect: {', '.join(names())} (default: the machine file's "
                        f"controller, else hnc21t)")


def _add_report(p: argparse.ArgumentParser, junit: bool) -> None:
    p.add_argument("--report", metavar="FILE.html", help="write the HTML report (backplot, "
                   "program, step-through, setup sheet)")
    if junit:
        p.add_argument("--junit", metavar="FILE.xml", help="write JUnit XML test results")


def build_parser() -> argparse.ArgumentParser:
    ap = _Parser(prog="hnc-cam", description="Lathe programs for HNC-21/22T, FANUC 0i-T, "
                                 "Haas and SINUMERIK 802 controls: generate from CAD, run, "
                                 "simulate, verify")
    from . import __version__
    ap.add_argument("--version", action="version", version=f"hnc-cam {__version__}")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND",
                            parser_class=_Parser)

    p = sub.add_parser("run", help="interpret a program and print its toolpath summary")
    p.add_argument("program")
    p.add_argument("--machine", metavar="FILE")
    p.add_argument("--json", metavar="OUT", help="write the toolpath as JSON (- = stdout)")
    _add_dialect(p)
    p.add_argument("--vars", metavar="FILE", help="FANUC/Haas: JSON file of the macro variables "
                   "#500-#999, read before the run and written after it")
    p.set_defaults(func=("hnc_cam.nc.command", "run_command"))

    p = sub.add_parser("simulate", help="remove material along a program's toolpath")
    p.add_argument("program")
    p.add_argument("--stock", metavar="SPEC", help="stock (default: the program's (STOCK ...) "
                   "line)")
    p.add_argument("--model", metavar="PART", help="part (needed only for an offset:A stock)")
    _add_set(p)
    _add_profile_options(p)
    p.add_argument("--machine", metavar="FILE")
    p.add_argument("--tools", metavar="FILE")
    p.add_argument("--json", metavar="OUT")
    p.add_argument("--plot", metavar="OUT", help="PNG or SVG")
    _add_grip(p)
    _add_dialect(p)
    p.set_defaults(func=("hnc_cam.check", "simulate_command"))

    p = sub.add_parser("verify", help="simulate a program and compare the result with the model")
    p.add_argument("program")
    p.add_argument("program2", nargs="?", metavar="PROGRAM2", help="the second setup's "
                   "program (generate --setups 2): run from what the first left, turned "
                   "around, and the whole part verified")
    p.add_argument("--model", required=True, metavar="PART")
    _add_set(p)
    _add_profile_options(p)
    p.add_argument("--stock", metavar="SPEC", help="stock (default: the program's (STOCK ...) "
                   "line)")
    p.add_argument("--tol", type=_positive_mm, default=0.01, metavar="MM")
    p.add_argument("--strict", action="store_true",
                   help="count unreachable leftover as a failure too")
    p.add_argument("--machine", metavar="FILE")
    p.add_argument("--tools", metavar="FILE")
    p.add_argument("--json", metavar="OUT")
    p.add_argument("--plot", metavar="OUT")
    _add_report(p, junit=True)
    _add_grip(p)
    _add_dialect(p)
    p.set_defaults(func=("hnc_cam.check", "verify_command"))

    p = sub.add_parser("generate", help="plan and write a lathe program for a part in the "
                                        "dialect of --dialect (HNC-21T, FANUC 0i-T, Haas, "
                                        "SINUMERIK 802)")
    p.add_argument("part", help="part file (parts/....py) or .step/.stp file")
    _add_set(p)
    _add_gen_options(p)
    _add_profile_options(p)
    p.add_argument("-o", "--output", metavar="OUT", help="program file (default: stdout); "
                   "with --setups 2 a folder DIR/ for both programs")
    p.add_argument("--setups", type=int, choices=[1, 2], default=1, metavar="N",
                   help="2: a part whose left end needs more than the part-off (a bore "
                   "chamfer or a step facing the chuck) in two programs, the second with the "
                   "part turned around and gripped on a finished diameter (-o DIR/)")
    p.add_argument("--grip2", type=_grip, metavar="MM", help="with --setups 2: mm of the "
                   "finished diameter the soft jaws hold in the second setup (default: "
                   "--grip)")
    p.add_argument("--json", metavar="OUT", help="write the plan as JSON (each operation's "
                   "cycle, tool, spindle and cap, feed, reason, zone; the verification "
                   "figures); - = stdout")
    _add_report(p, junit=False)
    _add_dialect(p)
    p.set_defaults(func=("hnc_cam.plan.command", "generate_command"))

    p = sub.add_parser("family", help="one program per row of a CSV table, or (--macro) one "
                       "parametric macro program for the whole family")
    p.add_argument("part")
    p.add_argument("--table", metavar="FILE.csv", help="the rows (required without --macro; "
                   "with --macro: the rows the operator selects by number, each checked)")
    p.add_argument("--out", metavar="DIR", help="the programs' folder (required without --macro)")
    p.add_argument("--macro", action="store_true", help="write one macro program whose "
                   "dimensions are variables of the family's parameters, proven by --check")
    p.add_argument("-o", "--output", metavar="OUT", help="with --macro: the program file (a "
                   "folder DIR/ where the family splits into several programs)")
    p.add_argument("--check", type=_count, default=None, metavar="N", help="with --macro: "
                   "run, simulate and verify the macro program for N sampled parameter sets "
                   "(default 5) and every table row")
    p.add_argument("--jobs", type=_jobs, default=0, metavar="N", help="worker processes (0 = all cores)")
    p.add_argument("--scheduler", type=_scheduler, metavar="tcp://HOST:PORT",
                   help="run the rows on this Dask distributed cluster (needs the cluster "
                        "extra: pip install hnc_cam[cluster]); --jobs is then ignored")
    _add_set(p)
    _add_gen_options(p)
    _add_profile_options(p)
    _add_report(p, junit=True)
    _add_dialect(p)
    p.set_defaults(func=("hnc_cam.plan.command", "family_command"))

    p = sub.add_parser("tools", help="tool libraries: import from other CAM systems")
    tsub = p.add_subparsers(dest="tools_command", required=True, metavar="ACTION")
    t = tsub.add_parser("import", help="convert a Fusion 360 tool library (JSON) to our TOML")
    t.add_argument("file", metavar="FILE")
    t.add_argument("-o", "--output", metavar="OUT", help="TOML file (default: stdout)")
    t.set_defaults(func=("hnc_cam.tools_import", "import_command"))
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    ap = build_parser()
    try:
        args = ap.parse_args(argv)
    except SystemExit as e:  # --help, --version, or a bad option (one line already printed)
        return e.code if isinstance(e.code, int) else 2
    from .errors import HncError
    modname, fname = args.func
    try:
        import importlib
        func: Callable[[argparse.Namespace], int] = getattr(importlib.import_module(modname), fname)
        return int(func(args) or 0)
    except HncError as e:
        print(e.one_line(), file=sys.stderr)
        # a program that failed verification: the planner's warnings often say why
        for w in getattr(getattr(e, "program", None), "warnings", None) or ():
            print(f"warning: {w}", file=sys.stderr)
        return e.exit_code
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
