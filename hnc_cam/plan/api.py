"""``generate``: part (file, loaded part or profile) + stock -> a checked program in a
dialect (HNC-21T by default; FANUC 0i-T, Haas).

Every program is run through the interpreter, reading it as the same dialect, before it is
returned (an alarm there is a bug of the generator and raises), and, when ``verify`` is true
and the simulator is installed,
simulated and compared with the model; a program that fails verification is refused with
:class:`VerificationError` (exit code 1), so no failing program is ever written.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from time import perf_counter
from typing import Any, Mapping
from ..units import fmt_cycle_time

from ..errors import HncError, NCError, PlanError, StockError
from ..geometry import TurnedProfile
from ..tooling import Machine, Stock, ToolLibrary, load_machine, load_tools
from .model import Plan
from .planner import Options, make_plan


class VerificationError(HncError):
    """The generated program failed verification against its model (exit code 1)."""

    exit_code = 1

    def __init__(self, message: str, program: "Program | None" = None):
        super().__init__(message)
        self.program = program


@dataclass
class Program:
    """A generated program: its text, the plan behind it, the interpreter's toolpath and,
    when verified, the simulator's report."""
    text: str
    plan: Plan
    toolpath: Any = None
    report: Any = None
    warnings: list[str] = field(default_factory=list)
    dialect: str = "hnc21t"
    #: the dialect's names of its cycles (:func:`hnc_cam.post.cycle_labels`)
    labels: dict[str, str] = field(default_factory=dict)
    #: seconds spent in each stage: load, plan, render, interpret, simulate, verify
    stages: dict[str, float] = field(default_factory=dict)

    @property
    def cycle_time_s(self) -> float:
        return float(self.toolpath.cycle_time_s) if self.toolpath is not None else 0.0

    @property
    def operations(self) -> list[str]:
        key = self.plan.label_key
        return [f"{op.name} {self.labels.get(key(op, self.labels), op.cycle)}"
                for op in self.plan.operations]

    def summary(self) -> str:
        t = self.cycle_time_s
        from ..dialect import get as get_dialect
        title = get_dialect(self.dialect).program_title
        head = (title(self.plan.program_number, self.plan.name) if title is not None
                else f"O{self.plan.program_number:04d} {self.plan.name}")
        s = (f"{head}: "
             f"{', '.join(self.operations)}; {self.text.count(chr(10))} lines; "
             f"cycle time {fmt_cycle_time(t)}")
        if self.report is not None:
            s += "; verified: " + _report_line(self.report)
        else:
            s += "; not verified"
        return s


def _report_line(rep: Any) -> str:
    ok = getattr(rep, "passed", getattr(rep, "pass_", getattr(rep, "ok", None)))
    parts = ["pass" if ok else "FAIL"]
    for attr, lab in (("max_overcut", "overcut"), ("max_undercut", "undercut")):
        v = getattr(rep, attr, getattr(rep, attr + "_mm", None))
        if v is not None:
            parts.append(f"{lab} {float(v):.4f} mm")
    return ", ".join(parts)


def _load_part(part: Any, params: Mapping[str, str] | None):
    """(profile, default stock, name, params) from a path, a LoadedPart or a profile."""
    if isinstance(part, TurnedProfile):
        if params:
            raise PlanError("parameters given for a profile (they apply to part files only)")
        return part, None, part.name, dict(part.params)
    if isinstance(part, (str, Path)):
        from ..cad import load_part
        loaded = load_part(str(part), {k: str(v) for k, v in (params or {}).items()})
    else:
        from ..cad.loader import LoadedPart
        if params:
            raise PlanError("parameters given for an already loaded part or solid "
                            "(they apply to part files only)")
        if not isinstance(loaded := part, LoadedPart):
            # a build123d/CadQuery/OCP solid: profiled about its Z axis, right face zero
            from ..cad import profile
            prof = profile(part)
            return prof, None, prof.name or "part", dict(prof.params)
    prof = loaded.profile
    mat = getattr(getattr(loaded, "module", None), "MATERIAL", None)
    if mat is not None and "material" not in prof.params:
        prof.notes = list(prof.notes)
        _PART_MATERIAL[id(prof)] = str(mat)
    threads = list(getattr(loaded, "threads", None) or [])
    if threads and not prof.threads:
        prof.threads = threads
    name = getattr(loaded, "name", None) or prof.name
    return prof, getattr(loaded, "stock", None), name, dict(getattr(loaded, "params", {}) or {})


def with_material(lib: ToolLibrary, mat_name: str | None, allowance: Any
                  ) -> tuple[ToolLibrary, float, float]:
    """The library with the material's speeds and feeds (``mat_name``, or none) and the
    finishing allowance (X on the diameter, Z): ``allowance`` if given, else the material's,
    else 0.4 and 0.1."""
    ax, az = 0.4, 0.1
    if mat_name is not None:
        from .tools import apply_material, find_material
        _key, mat = find_material(mat_name)
        lib = apply_material(lib, mat)
        ax, az = (float(v) for v in mat.get("allowance", (ax, az)))
    if allowance is not None:
        ax, az = _parse_allowance(allowance)
    return lib, ax, az


def _parse_allowance(value: Any) -> tuple[float, float]:
    """(X on diameter, Z) from ``"X,Z"`` or a pair; negative values are refused."""
    try:
        if isinstance(value, str):
            parts = [float(v) for v in value.split(",")]
        else:
            parts = [float(v) for v in value]
        if len(parts) != 2:
            raise ValueError
    except (TypeError, ValueError):
        raise PlanError(f"allowance {value!r}: give it as X,Z in mm (X on the diameter), "
                        f"e.g. 0.4,0.1") from None
    if any(v < 0 or v != v for v in parts):
        raise PlanError(f"allowance {value!r}: the finishing allowance cannot be negative")
    return parts[0], parts[1]


def _file_key(path: str | Path | None):
    """Cache key of a table file: None (the bundled default) or (resolved path, mtime, size),
    so that an edited file is read again."""
    if path is None:
        return None
    p = Path(path)
    try:
        st = p.stat()
    except OSError:
        return (str(path), None, None)  # the loader reports the error (not cached)
    return (str(p.resolve()), st.st_mtime_ns, st.st_size)


_TOOLS: dict[Any, ToolLibrary] = {}
#: the MATERIAL a part file declares, by id of the profile loaded from it
_PART_MATERIAL: dict[int, str] = {}
_MACHINES: dict[Any, Machine] = {}
#: how many tool libraries and machine files this process has parsed (a family worker parses
#: each once, not once per row)
LOADS = {"tools": 0, "machines": 0}


def _load_tools(path: str | Path | None) -> ToolLibrary:
    """The tool library, parsed once per process and file version (a family's rows and a
    worker's jobs share it; the tables are frozen dataclasses)."""
    key = _file_key(path)
    lib = _TOOLS.get(key)
    if lib is None:
        lib = load_tools(path)
        LOADS["tools"] += 1
        _TOOLS[key] = lib
    return lib


def _load_machine(path: str | Path | None, lib: ToolLibrary) -> Machine:
    key = (_file_key(path), id(lib))
    mach = _MACHINES.get(key)
    if mach is None:
        mach = load_machine(path, tools=lib)
        LOADS["machines"] += 1
        _MACHINES[key] = mach
    return mach


def warm(tools: str | Path | None = None, machine: str | Path | None = None,
         templates: str | Path | None = None, number_format: str = "plain",
         block_numbers: str = "every", dialect: str | None = None) -> None:
    """Load the tables and the template environment once (a family worker's initializer)."""
    from ..post import environment
    mach = _load_machine(machine, _load_tools(tools))
    environment(None if templates is None else str(templates), number_format, block_numbers,
                dialect_of(dialect, mach))


def dialect_of(dialect: str | None, machine: Machine | None) -> str:
    """The dialect a program is written in: the one asked for, else the machine file's
    ``controller``, else HNC-21T."""
    from ..post import DEFAULT_DIALECT
    return dialect or getattr(machine, "controller", None) or DEFAULT_DIALECT


def thread_end_on_flank(dialect: str) -> bool:
    """Whether ``dialect``'s multiple-pass thread cycle ends each pass further along the
    thread by its depth x tan(half angle) (:class:`~hnc_cam.plan.planner.Options`
    ``thread_end_shift``); an unknown name is taken for the worst case."""
    from ..dialect import get
    try:
        return get(dialect).has("thread_end_on_flank")
    except ValueError:
        return True


def _interpret(text: str, machine: Machine, file: str, dialect: str = "hnc21t"):
    try:
        from ..nc import run
    except ImportError:
        return None
    try:
        return run(text, machine=machine, file=file, start="reference", dialect=dialect)
    except NCError as e:
        raise PlanError(f"internal error: the generated program raises an alarm in the "
                        f"interpreter (a generator bug, please report): {e.one_line()}") from e


def _verify(prof: TurnedProfile, plan: Plan, stock: Stock, toolpath, machine: Machine,
            tools: ToolLibrary, tol: float, stages: dict[str, float] | None = None):
    try:
        from .. import sim
        simulate = sim.simulate
        verify = sim.verify
    except (ImportError, AttributeError):
        return None
    t0 = perf_counter()
    machined = simulate(toolpath, stock, machine=machine, model=prof)
    t1 = perf_counter()
    rep = verify(machined, prof, tol=tol)
    if stages is not None:
        stages["simulate"], stages["verify"] = t1 - t0, perf_counter() - t1
    return rep


#: the smallest tube bore a part without a stock is given (a smaller bore is drilled from bar)
MIN_TUBE_BORE = 20.0


def default_stock_for(prof: TurnedProfile) -> str:
    """The stock of a part that names none: the smallest standard bar 2 mm (diameter) over
    the part, 2 mm of face stock and 15 mm beyond the left end for the chuck
    (:func:`hnc_cam.cad.sketch.bar_stock`); a part with a through bore large enough for a
    tube 3 mm under it of at least :data:`MIN_TUBE_BORE` gets that tube."""
    from ..cad.sketch import bar_stock, tube_stock
    bore = prof.min_bore_radius
    through = bool(prof.bore) and min(s.bbox()[1] for s in prof.bore) <= prof.z_min + 1e-6
    if bore is not None and through and 2 * bore - 3.0 >= MIN_TUBE_BORE:
        return tube_stock(prof.max_diameter, 2 * bore, prof.length)
    return bar_stock(prof.max_diameter, prof.length)


def generate(part: Any, stock: str | Stock | None = None, *, params: Mapping[str, str] | None = None,
             tools: str | Path | ToolLibrary | None = None,
             machine: str | Path | Machine | None = None, comp: str = "cam",
             templates: str | Path | None = None, program_number: int | None = None,
             verify: bool = True, tol: float = 0.01, number_format: str = "plain",
             block_numbers: str = "every", thread_cycle: str = "g76",
             face_cycle: str = "g81", file: str = "<generated>",
             material: str | None = None, allowance: Any = None,
             dialect: str | None = None, grip: float | None = None, partoff: bool = True,
             partoff_dia: float | None = None, drill_style: str = "blocks") -> Program:
    """Plan, render, interpret (and verify) a program for ``part``.

    ``part``: a part file path (``parts/*.py``, ``.step``/``.stp``), a loaded part
    (``hnc_cam.cad.load_part``), a build123d/CadQuery/OCP solid (profiled about its Z axis)
    or a :class:`TurnedProfile` (the model itself); the right face is program zero. ``stock``: a spec string or :class:`Stock`;
    default: the part file's ``STOCK``. ``tools``/``machine``: files or loaded tables
    (defaults: the bundled library, whose registers also fill the default machine).
    ``material``: a name or alias from ``hnc_cam/data/materials.toml`` (default: the part
    file's ``MATERIAL``, else none: the tool library's cutting data as it is); the tools'
    speeds, feeds and depths are limited to the material's ranges. ``allowance``: the
    finishing allowance ``(X on diameter, Z)`` in mm or ``"X,Z"`` (default: the material's,
    else 0.4, 0.1 as in the manual's examples). ``dialect``: the controller the program is
    written for and read back as (``hnc21t``, ``fanuc0it``, ``haas``; default: the machine
    file's ``controller``, else ``hnc21t``). ``grip``: mm of the stock held in the chuck's
    jaws (default: the machine file's ``[chuck] grip``; none: the jaws are not modelled).
    ``partoff``: a part held in the chuck (a grip given) is parted off with the library's
    parting blade (False: it stays on the bar, its left end cut just past the part);
    ``partoff_dia``: the part-off ends at this diameter instead of past the centre.
    ``drill_style``: peck drilling as plain blocks (``blocks``) or, on the HNC-21T, a WHILE-loop
    macro subprogram (``macro``).
    """
    from .. import __version__
    from ..post import cycle_labels, render

    t0 = perf_counter()
    prof, default_stock, name, pparams = _load_part(part, params)
    t_load = perf_counter() - t0
    if stock is None:
        stock = default_stock
    if stock is None:
        stock = default_stock_for(prof)
    st = stock if isinstance(stock, Stock) else Stock.parse(str(stock))
    lib = tools if isinstance(tools, ToolLibrary) else _load_tools(tools)
    if isinstance(machine, Machine):
        mach = machine
    else:
        mach = _load_machine(machine, lib)
    if grip is not None:
        from ..tooling import with_grip
        mach = with_grip(mach, float(grip))
    if program_number is None:
        program_number = 1
    if not 0 <= int(program_number) <= 9999:
        raise PlanError(f"program number {program_number} out of range 0-9999")
    if thread_cycle not in ("g76", "g82"):
        raise PlanError(f"thread cycle must be g76 or g82, got {thread_cycle!r}")
    if face_cycle not in ("g81", "g01"):
        raise PlanError(f"face cycle must be g81 or g01, got {face_cycle!r}")
    mat_name = material if material is not None else _PART_MATERIAL.pop(id(prof), None)
    lib, ax, az = with_material(lib, mat_name, allowance)
    dia = dialect_of(dialect, mach)
    opts = Options(comp=comp, program_number=int(program_number), thread_cycle=thread_cycle,
                   face_cycle=face_cycle, allowance_x=ax / 2, allowance_z=az,
                   partoff=bool(partoff),
                   partoff_dia=float(partoff_dia) if partoff_dia is not None else -1.0,
                   drill_style=drill_style, thread_end_shift=thread_end_on_flank(dia))
    t1 = perf_counter()
    plan = make_plan(prof, st, lib, mach, opts, name=name, params=pparams, version=__version__)
    t2 = perf_counter()
    text = render(plan, dialect=dia, templates=templates, number_format=number_format,
                  block_numbers=block_numbers)
    t3 = perf_counter()
    tp = _interpret(text, mach, file, dia)
    prog = Program(text=text, plan=plan, toolpath=tp, dialect=dia,
                   labels=cycle_labels(dia, templates))
    prog.stages.update(load=t_load, plan=t2 - t1, render=t3 - t2,
                       interpret=perf_counter() - t3)
    prog.warnings.extend(plan.warnings)
    if drill_style == "macro" and dia != "hnc21t" and any(
            op.kind == "drill" and op.drill is not None and op.drill.pecks
            for op in plan.operations):
        how = "G74" if dia in ("fanuc0it", "haas") else "plain blocks"
        prog.warnings.append(f"--drill-style macro is the HNC-21T's WHILE-loop subprogram: the "
                             f"{dia} program pecks with {how}")
    if tp is None:
        prog.warnings.append("the interpreter is not available: program not run")
        return prog
    if verify:
        rep = _verify(plan.profile, plan, st if st.kind != "offset" else st, tp, mach, lib, tol,
                      prog.stages)
        prog.report = rep
        if rep is None:
            prog.warnings.append("the simulator is not available: program not verified")
        else:
            ok = getattr(rep, "passed", getattr(rep, "pass_", getattr(rep, "ok", True)))
            if not ok:
                detail = rep.summary().replace("\n", "; ") if hasattr(rep, "summary") \
                    else _report_line(rep)
                raise VerificationError(f"{name}: the generated program fails verification "
                                        f"(tol {tol:g} mm): {detail}", prog)
    return prog
