"""Rendering: a plan becomes HNC-21T program text through the Jinja templates.

Python builds no program text here: numbers, words and blocks come from the templates in the
top-level ``templates/`` folder (shipped in the wheel as the package ``hnc_cam._templates``),
formatting from the filters in :mod:`hnc_cam.post.filters`.

A user folder (``--templates DIR``) is searched first: a file there replaces the default of
the same name, so a user can change only ``header.j2`` or only ``g76.j2``.

Templates (one per operation): ``program.j2`` (the whole program), ``header.j2``,
``footer.j2``, ``tool_change.j2``, ``face.j2``, ``g71.j2``, ``g71_type2.j2``, ``g72.j2``,
``g73.j2``, ``bore.j2`` (ID roughing), ``finish.j2`` (the ns..nf contour, OD and ID),
``contour.j2`` (the contour blocks, included by ``finish.j2``), ``spindle.j2`` (G96/G97
with M03, included by every operation), ``groove.j2``, ``g76.j2``, ``g82.j2``.
"""
from __future__ import annotations

from functools import lru_cache
from importlib import resources
from pathlib import Path
from typing import Any

from ..errors import PlanError
from .filters import (BLOCK_NUMBERING, NUMBER_FORMATS, comment, fmt_dia, fmt_num, label,
                      number_blocks, progno, ref)

__all__ = ["render", "environment", "default_template_dir", "NUMBER_FORMATS", "BLOCK_NUMBERING"]


def default_template_dir() -> Path:
    """The bundled templates: ``hnc_cam._templates`` when installed, else the repository's
    top-level ``templates/`` folder."""
    try:
        p = Path(str(resources.files("hnc_cam._templates")))
        if (p / "program.j2").is_file():
            return p
    except (ModuleNotFoundError, TypeError, ValueError):
        pass
    p = Path(__file__).resolve().parents[2] / "templates"
    if (p / "program.j2").is_file():
        return p
    raise PlanError("the bundled templates are missing (no hnc_cam._templates package and no "
                    "templates/ folder beside the package)")


@lru_cache(maxsize=16)
def environment(user_dir: str | None = None, number_format: str = "plain",
                block_numbers: str = "every"):
    """The Jinja environment: user folder first, then the defaults (ChoiceLoader)."""
    import jinja2

    if number_format not in NUMBER_FORMATS:
        raise PlanError(f"number format must be one of {', '.join(NUMBER_FORMATS)}, "
                        f"got {number_format!r}")
    if block_numbers not in BLOCK_NUMBERING:
        raise PlanError(f"block numbering must be one of {', '.join(BLOCK_NUMBERING)}, "
                        f"got {block_numbers!r}")
    loaders = []
    if user_dir is not None:
        d = Path(user_dir)
        if not d.is_dir():
            raise PlanError(f"templates folder {user_dir}: not a directory")
        loaders.append(jinja2.FileSystemLoader(str(d)))
    loaders.append(jinja2.FileSystemLoader(str(default_template_dir())))
    env = jinja2.Environment(loader=jinja2.ChoiceLoader(loaders), trim_blocks=True,
                             lstrip_blocks=True, keep_trailing_newline=True,
                             undefined=jinja2.StrictUndefined, autoescape=False)
    env.filters["num"] = lambda v: fmt_num(v, number_format)
    env.filters["dia"] = lambda v: fmt_dia(v, number_format)
    env.filters["progno"] = progno
    env.filters["comment"] = comment
    env.filters["label"] = label
    env.filters["ref"] = ref
    env.filters["blocks"] = lambda text: number_blocks(text, block_numbers)
    env.globals["number_format"] = number_format
    env.globals["block_numbering"] = block_numbers
    return env


def render(plan: Any, *, templates: str | Path | None = None, number_format: str = "plain",
           block_numbers: str = "every", template: str = "program.j2") -> str:
    """Render ``plan`` (a :class:`hnc_cam.plan.model.Plan`) to program text."""
    import jinja2

    env = environment(None if templates is None else str(templates), number_format, block_numbers)
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
        files = sorted(d.glob("*.j2"))
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
