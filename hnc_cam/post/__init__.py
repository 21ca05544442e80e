"""Rendering: a plan becomes program text through the Jinja templates of a dialect.

Python builds no program text here: numbers, words and blocks come from the templates in the
top-level ``templates/<dialect>/`` folders (shipped in the wheel as the package
``hnc_cam._templates``), formatting from the filters in :mod:`hnc_cam.post.filters`.

The plan is neutral (:mod:`hnc_cam.plan.model`); each dialect's ``program.j2`` includes one
template per operation, chosen by the operation's role (:attr:`Operation.role`). Templates
are looked up in this order: the user folder's ``<dialect>/`` subfolder, the user folder
itself (``--templates DIR``: a file there replaces the default of the same name, so a user
can change only ``header.j2``), the dialect's bundled folder, then the folder of the
dialect it falls back to (Haas: only the files that differ, the rest from FANUC 0i-T).

HNC-21T templates (``templates/hnc21t/``): ``program.j2`` (the whole program), ``header.j2``,
``footer.j2``, ``tool_change.j2``, ``face.j2``, ``g71.j2``, ``g71_type2.j2``, ``g72.j2``,
``g73.j2``, ``bore.j2`` (ID roughing), ``finish.j2`` (the ns..nf contour, OD and ID),
``contour.j2`` (the contour blocks, included by ``finish.j2``), ``spindle.j2`` (G96/G97
with M03, included by every operation), ``groove.j2``, ``g76.j2``, ``g82.j2``.
FANUC 0i-T (``templates/fanuc0it/``) names its operation templates by role
(``rough_turn.j2``, ``thread.j2``, ...); ``templates/haas/`` holds the Haas one-block cycles.
"""
from __future__ import annotations

from functools import lru_cache
from importlib import resources
from pathlib import Path
from typing import Any

from ..errors import PlanError
from .filters import (BLOCK_NUMBERING, NUMBER_FORMATS, comment, fmt_dia, fmt_num, label,
                      micrometres, number_blocks, program_name, progno, ref, remark, whole)

__all__ = ["render", "environment", "default_template_dir", "template_dirs", "NUMBER_FORMATS",
           "BLOCK_NUMBERING", "DEFAULT_DIALECT"]

DEFAULT_DIALECT = "hnc21t"


def default_template_dir() -> Path:
    """The bundled templates (one folder per dialect): ``hnc_cam._templates`` when
    installed, else the repository's top-level ``templates/`` folder."""
    try:
        p = Path(str(resources.files("hnc_cam._templates")))
        if (p / DEFAULT_DIALECT / "program.j2").is_file():
            return p
    except (ModuleNotFoundError, TypeError, ValueError):
        pass
    p = Path(__file__).resolve().parents[2] / "templates"
    if (p / DEFAULT_DIALECT / "program.j2").is_file():
        return p
    raise PlanError("the bundled templates are missing (no hnc_cam._templates package and no "
                    "templates/ folder beside the package)")


def _dialect(name: str):
    """The dialect value of ``name`` (:func:`hnc_cam.dialect.get`); an unknown name is a
    PlanError listing the known ones."""
    from .. import dialect
    try:
        return dialect.get(name)
    except (KeyError, ValueError) as e:
        msg = e.args[0] if e.args else str(e)
        raise PlanError(str(msg)) from None


def template_dirs(dialect: str = DEFAULT_DIALECT) -> list[Path]:
    """The bundled folders searched for ``dialect``: its own, then its fallback's."""
    root = default_template_dir()
    d = _dialect(dialect)
    out = [root / d.templates]
    seen = {d.name}
    fb = d.template_fallback
    while fb and fb not in seen:
        seen.add(fb)
        f = _dialect(fb)
        out.append(root / f.templates)
        fb = f.template_fallback
    return out


def _coordinate_format(dialect: str, number_format: str) -> str:
    """A dialect that reads a word without a decimal point in least increments (FANUC:
    ``X20`` is 0.020 mm) gets a point on every whole number (``plain`` becomes ``point``)."""
    if number_format == "plain" and _dialect(dialect).has("decimal_point_input"):
        return "point"
    return number_format


@lru_cache(maxsize=32)
def environment(user_dir: str | None = None, number_format: str = "plain",
                block_numbers: str = "every", dialect: str = DEFAULT_DIALECT):
    """The Jinja environment of ``dialect``: the user folder first, then the defaults
    (ChoiceLoader, in the order of the module docstring)."""
    import jinja2

    if number_format not in NUMBER_FORMATS:
        raise PlanError(f"number format must be one of {', '.join(NUMBER_FORMATS)}, "
                        f"got {number_format!r}")
    if block_numbers not in BLOCK_NUMBERING:
        raise PlanError(f"block numbering must be one of {', '.join(BLOCK_NUMBERING)}, "
                        f"got {block_numbers!r}")
    dirs = template_dirs(dialect)
    fmt = _coordinate_format(dialect, number_format)
    loaders = []
    if user_dir is not None:
        d = Path(user_dir)
        if not d.is_dir():
            raise PlanError(f"templates folder {user_dir}: not a directory")
        sub = d / _dialect(dialect).templates
        if sub.is_dir():
            loaders.append(jinja2.FileSystemLoader(str(sub)))
        loaders.append(jinja2.FileSystemLoader(str(d)))
    loaders += [jinja2.FileSystemLoader(str(p)) for p in dirs]
    env = jinja2.Environment(loader=jinja2.ChoiceLoader(loaders), trim_blocks=True,
                             lstrip_blocks=True, keep_trailing_newline=True,
                             undefined=jinja2.StrictUndefined, autoescape=False)
    env.filters["num"] = lambda v: fmt_num(v, fmt)
    env.filters["dia"] = lambda v: fmt_dia(v, fmt)
    env.filters["plain"] = lambda v: fmt_num(v, "plain")
    env.filters["whole"] = whole
    env.filters["um"] = micrometres
    env.filters["progno"] = progno
    env.filters["comment"] = comment
    env.filters["label"] = label
    env.filters["ref"] = ref
    env.filters["blocks"] = lambda text: number_blocks(text, block_numbers)
    env.filters["remark"] = remark
    env.filters["progname802"] = program_name
    env.filters["corners"] = _corner_blocks
    env.filters["bottom_exit"] = bottom_exit
    env.filters["subprograms"] = contour_subprograms
    env.filters["contour_number"] = contour_number
    env.globals["number_format"] = fmt
    env.globals["block_numbering"] = block_numbers
    env.globals["dialect"] = dialect
    return env


def render(plan: Any, *, dialect: str = DEFAULT_DIALECT, templates: str | Path | None = None,
           number_format: str = "plain", block_numbers: str = "every",
           template: str = "program.j2") -> str:
    """Render ``plan`` (a :class:`hnc_cam.plan.model.Plan`) to ``dialect``'s program text."""
    import jinja2

    env = environment(None if templates is None else str(templates), number_format,
                      block_numbers, dialect)
    try:
        return env.get_template(template).render(plan=plan)
    except jinja2.TemplateNotFound as e:
        raise PlanError(f"template {e.name} not found (in {templates or 'the defaults'})") from None
    except jinja2.TemplateSyntaxError as e:
        raise PlanError(f"{e.filename or e.name}:{e.lineno}: template syntax: {e.message}") from None
    except PlanError:
        raise
    except Exception as e:  # noqa: BLE001 - an error raised while a template runs: say where
        where = _template_place(e.__traceback__)
        why = getattr(e, "message", None) or str(e) or type(e).__name__
        if not isinstance(e, (jinja2.TemplateError, ValueError)):
            why = f"{type(e).__name__}: {why}"
        raise PlanError(f"{where or 'template'}: {why}") from None


#: how far a compensated contour that ends cutting along X toward the axis runs on (mm)
EXIT_RUN_ON = 0.5


def bottom_exit(op: Any, plan: Any = None) -> float | None:
    """Where a contour under G41/G42 whose last block cuts along X toward the axis inside the
    part (a bore's bottom; not the exit past the part's left end of a through bore) runs on
    to: the X (radius) :data:`EXIT_RUN_ON` further along that block, past the axis where the
    bottom is faced to the centre (the bar's nose is past it there already; the bottom's
    plane runs on across it); None for any other contour. A dialect that cancels the compensation in
    the contour's last block (FANUC, Haas: G40 in block nf) writes this run-on as that block,
    so that the cancel leaves the material straight on instead of being the bottom's own
    cut, whose concave corner with the wall the control cancels into (the nose a radius
    deep into the bottom)."""
    blocks = getattr(op, "blocks", None) or []
    if getattr(op, "nose_comp", "none") == "none" or len(blocks) < 2:
        return None
    x, z = op.start
    prev = (x, z)
    for b in blocks:
        prev = (x, z)
        x = b.x if b.x is not None else x
        z = b.z if b.z is not None else z
    last = blocks[-1]
    if last.kind != "line" or abs(z - prev[1]) > 1e-9 or not x < prev[0] - 1e-9:
        return None
    prof = getattr(plan, "profile", None)
    if prof is not None and z < prof.z_min + 1e-6:
        return None  # past the part's left end: nothing of the part beside it
    return x - EXIT_RUN_ON


def _corner_blocks(blocks, start=None):
    from .corners import corner_blocks
    return corner_blocks(blocks, start)


def contour_subprograms(plan: Any) -> list:
    """The operations whose contours a roughing cycle refers to, once each in the order of
    the program (the SINUMERIK post writes each as a subprogram ``NAME_C1``, ``NAME_C2``...)."""
    out: list = []
    for op in plan.operations:
        if op.kind == "rough":
            owner = plan.contour_owner(op)
            if not any(o is owner for o in out):
                out.append(owner)
    return out


def contour_number(plan: Any, op: Any) -> int:
    """1-based place of ``op``'s contour (:meth:`Plan.contour_owner`) among
    :func:`contour_subprograms`."""
    owner = plan.contour_owner(op)
    for i, o in enumerate(contour_subprograms(plan), 1):
        if o is owner:
            return i
    raise ValueError(f"operation {op.name}: its contour is not a subprogram")


def cycle_labels(dialect: str = DEFAULT_DIALECT, templates: str | Path | None = None
                 ) -> dict[str, str]:
    """The dialect's names of its cycles by operation (:meth:`Plan.label_key`), from its
    ``labels.j2`` (``{% set labels = {...} %}``); empty where the dialect has none (the
    operations are then named by their HNC-21T code, :attr:`Operation.cycle`)."""
    import jinja2
    env = environment(None if templates is None else str(templates), "plain", "every",
                      dialect)
    try:
        return dict(env.get_template("labels.j2").module.labels)
    except jinja2.TemplateNotFound:
        return {}
    except Exception as e:  # noqa: BLE001 - a user's labels.j2 that does not define labels
        raise PlanError(f"labels.j2: {getattr(e, 'message', None) or e}") from None


def _template_place(tb) -> str | None:
    """``FILE:LINE`` of the innermost template frame of a traceback (Jinja maps its frames
    to the template source)."""
    place = None
    while tb is not None:
        fn = tb.tb_frame.f_code.co_filename
        if fn.endswith(".j2"):
            place = f"{fn}:{tb.tb_lineno}"
        tb = tb.tb_next
    return place


def blame_user_template(templates: str | Path | None, block: str, col: int) -> str | None:
    """When a program rendered with a user's templates folder raises an alarm: the
    ``FILE:LINE`` of the user template that writes the refused word (the word at ``col`` of
    ``block``, found in the template's literal text), or None."""
    import re
    if templates is None or not block:
        return None
    words = block[max(col - 1, 0):].split()
    word = words[0] if words else ""
    if not word:
        return None
    candidates = [word]
    d = Path(templates)
    try:
        files = sorted(d.glob("*/*.j2")) + sorted(d.glob("*.j2"))
    except OSError:
        return None
    for cand in candidates:
        pat = re.compile(rf"(?<![A-Za-z0-9.]){re.escape(cand)}(?![0-9.])", re.I)
        for f in files:
            try:
                text = f.read_text("utf-8", "replace")
            except OSError:
                continue
            for n, line in enumerate(text.splitlines(), 1):
                literal = re.sub(r"\{\{.*?\}\}|\{%.*?%\}|\{#.*?#\}", " ", line)
                if pat.search(literal):
                    return f"{f}:{n}"
    return None
