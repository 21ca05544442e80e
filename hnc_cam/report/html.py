"""The self-contained HTML report: one file, CSS and JavaScript inline, the data as JSON in a
``<script type="application/json">`` block; no network access when it is viewed.

The page (``assets/page.html.j2``, ``assets/report.js``, ``assets/report.css``) draws the
backplot on a canvas (lines and true arcs, so 100,000 moves stay one pass of canvas calls),
the program text as a virtual list (only the visible lines are in the DOM), the step-through
from the keyframes of :func:`hnc_cam.report.data.keyframes`, and the setup sheet.
"""
from __future__ import annotations

import html
import json
import math
from functools import lru_cache
from importlib import resources
from pathlib import Path
from typing import Any, Iterable, Sequence

from . import data as D


@lru_cache(maxsize=None)
def _asset(name: str) -> str:
    return resources.files("hnc_cam.report").joinpath("assets", name).read_text("utf-8")


@lru_cache(maxsize=1)
def _template():
    import jinja2
    env = jinja2.Environment(autoescape=True, undefined=jinja2.StrictUndefined,
                             trim_blocks=False, lstrip_blocks=False)
    return env.from_string(_asset("page.html.j2"))


def _json_for_script(obj: Any) -> str:
    """JSON safe inside a <script> element (no "</", no U+2028/2029 surprises)."""
    try:
        s = json.dumps(obj, separators=(",", ":"), allow_nan=False)
    except ValueError:  # a non-finite number somewhere: null in the page, not a broken script
        s = json.dumps(_finite(obj), separators=(",", ":"), allow_nan=False)
    return s.replace("<", "\\u003c").replace("\u2028", "\\u2028").replace("\u2029", "\\u2029")


def _finite(obj: Any) -> Any:
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj


def _view(machined, model) -> list[float]:
    """The frame of the work (stock and model), mm: [zmin, xmin, zmax, xmax]."""
    st = machined.stock
    z0, x0, z1, x1 = st.bounds if not st.is_empty else (0.0, 0.0, 1.0, 1.0)
    if model is not None:
        mb = model.bbox()
        z0, x0, z1, x1 = min(z0, mb[1]), min(x0, mb[0]), max(z1, mb[3]), max(x1, mb[2])
    pad = max(3.0, 0.08 * max(z1 - z0, x1 - x0))
    return [z0 - pad, min(x0, 0.0) - pad * 0.3, z1 + pad, x1 + pad]


def part_svg(model, width: int = 360) -> str:
    """A picture of the part: its exact section (lines and arcs as SVG arcs), mirrored about
    the axis so it reads as the part, not as a half-plane."""
    if model is None:
        return ""
    from ..sim.verify import model_segments
    segs = model_segments(model)
    if not segs:
        return ""
    xb0, zb0, xb1, zb1 = model.bbox()
    zlen = max(zb1 - zb0, 1e-3)
    r = max(xb1, 1e-3)
    pad = 0.05 * max(zlen, 2 * r)
    w_mm, h_mm = zlen + 2 * pad, 2 * r + 2 * pad

    def pt(p) -> tuple[float, float]:
        return (p[1] - zb0 + pad, r + pad - p[0])

    def path(sign: int) -> str:
        d = []
        for s in segs:
            (ax, ay), (bx, by) = pt(s.start), pt(s.end)
            if sign < 0:
                ay, by = h_mm - ay, h_mm - by
            d.append(f"M{ax:.3f},{ay:.3f}")
            c = getattr(s, "center", None)
            if c is not None:
                rad = s.radius
                large = 1 if abs(s.sweep) > 3.141592653589793 else 0
                # SVG y runs down: a world-cw arc (G02) is drawn with sweep-flag 1; mirrored, 0
                flag = (1 if s.cw else 0) if sign > 0 else (0 if s.cw else 1)
                d.append(f"A{rad:.3f},{rad:.3f} 0 {large} {flag} {bx:.3f},{by:.3f}")
            else:
                d.append(f"L{bx:.3f},{by:.3f}")
        return "".join(d)

    h = int(width * h_mm / w_mm) if w_mm > 0 else width
    return (f'<svg id="part-picture" xmlns="http://www.w3.org/2000/svg" width="{width}" '
            f'height="{max(h, 40)}" viewBox="0 0 {w_mm:.3f} {h_mm:.3f}">'
            f'<line x1="0" y1="{r + pad:.3f}" x2="{w_mm:.3f}" y2="{r + pad:.3f}" stroke="#888" '
            f'stroke-width="{0.004 * w_mm:.3f}" stroke-dasharray="{0.03 * w_mm:.3f} '
            f'{0.01 * w_mm:.3f}"/>'
            f'<path d="{path(1)}{path(-1)}" fill="none" stroke="#000" '
            f'stroke-width="{0.006 * w_mm:.3f}"/></svg>')


def page_data(machined, report=None, model=None, *, chuck=None) -> dict[str, Any]:
    """Everything the page's script needs (see :mod:`hnc_cam.report.data`). ``chuck``: rings
    of the jaws (default: the simulator's jaws, when the machine gives a grip)."""
    tp = machined.toolpath
    if chuck is None and getattr(machined, "jaws", None) is not None:
        chuck = D.rings_of(machined.jaws)
    model_json: list = []
    if model is not None:
        from ..sim.verify import model_segments
        model_json = D.segments_json(model_segments(model))
    return {"moves": D.moves_columns(tp.moves),
            "keyframes": D.keyframes(machined),
            "stock": D.rings_of(machined.stock),
            "model": model_json,
            "findings": D.findings(machined, report, model),
            "chuck": chuck,  # rings of the jaws, drawn when the simulator models them
            "view": _view(machined, model),
            "cycle_time_s": round(tp.cycle_time_s, 2),
            "program": {"file": tp.file, "lines": [ln.rstrip("\r\n") for ln in tp.source_lines]}}


def render_page(machined, report=None, model=None, *, title: str | None = None, plan=None,
                params: dict | None = None, stock: str | None = None, library=None,
                part: str | None = None, comp: str | None = None,
                warnings: Sequence[str] = (), index_href: str | None = None,
                chuck=None, labels: dict | None = None) -> str:
    """The whole page as text. ``plan`` (a generated program's plan) and ``library`` (a tool
    library) are read as plain values for the setup sheet."""
    from .. import __version__
    tp = machined.toolpath
    data = page_data(machined, report, model, chuck=chuck)
    chuck = data["chuck"]
    stock_spec = stock or (getattr(getattr(plan, "stock", None), "spec", None))
    z0, x0, z1, x1 = machined.stock.bounds if not machined.stock.is_empty else (0, 0, 0, 0)
    if params is None:
        params = dict(getattr(plan, "params", None) or getattr(model, "params", None) or {})
    setup = {
        "part": part or getattr(plan, "name", None) or getattr(model, "name", ""),
        "program": tp.file,
        "params": {str(k): v for k, v in params.items()},
        "stock": stock_spec or "",
        "stock_size": (f"diameter {2 * x1:.3f} mm" + (f", bore {2 * x0:.3f} mm" if x0 > 1e-9 else "")
                       + f", Z {z0:.3f}..{z1:.3f} ({z1 - z0:.3f} mm)"),
        "work_offset": "G54 (the machine file's origin)",
        "workholding": ("chuck at the left (minimum Z) end of the stock; material cut loose "
                        "from it falls off; the jaws are not modelled"
                        if chuck is None else "chuck jaws as drawn"),
        "comp": {"cam": "CAM: compensated tip path, G40",
                 "control": "control: part profile with G41/G42"}.get(comp or getattr(plan, "comp", ""),
                                                                        "as programmed"),
        "tools": D.tools_table(tp.moves, machined.machine, plan=plan, library=library),
        "operations": D.operations_run(tp.moves),
        "plan_ops": D.plan_operations(plan, labels) if plan is not None else [],
    }
    verdict = D.verdict(report, machined)
    warn_rows = []
    for iss in machined.issues:
        warn_rows.append({"cls": "bad", "where": f"line {iss.line}", "text": f"{iss.message}  [{iss.block}]"})
    for w in tp.warnings:
        warn_rows.append({"cls": "warn", "where": f"line {w.line}", "text": w.message})
    for n in machined.notes:
        warn_rows.append({"cls": "warn", "where": f"line {n.line}", "text": n.message})
    for note in getattr(plan, "notes", None) or []:
        warn_rows.append({"cls": "warn", "where": "plan", "text": str(note)})
    for w in warnings:
        warn_rows.append({"cls": "warn", "where": "", "text": str(w)})
    return _template().render(
        title=title or f"{tp.file}", version=__version__, css=_asset("report.css"),
        js=_asset("report.js"), data_json=_json_for_script(data), verdict=verdict,
        setup=setup, part_svg=part_svg(model), warnings=warn_rows,
        cycle_time_s=tp.cycle_time_s, index_href=index_href)


def render_index(title: str, rows: Iterable[dict[str, Any]]) -> str:
    """The family's index page: one row per program (row, program, verdict, figures, link)."""
    from .. import __version__
    body = []
    for r in rows:
        verdict = r.get("verdict", "")
        cls = "pass" if verdict == "pass" else ("fail" if verdict in ("fail", "error") else "none")
        link = (f'<a href="{html.escape(r["href"])}">{html.escape(r["name"])}</a>'
                if r.get("href") else html.escape(r["name"]))
        body.append(
            f'<tr><td class="num">{html.escape(str(r.get("row", "")))}</td><td>{link}</td>'
            f'<td><span class="badge {cls}">{html.escape(str(verdict).upper())}</span></td>'
            f'<td>{html.escape(str(r.get("params", "")))}</td>'
            f'<td class="num">{html.escape(str(r.get("cycle_time_s", "")))}</td>'
            f'<td class="num">{html.escape(str(r.get("max_overcut_mm", "")))}</td>'
            f'<td class="num">{html.escape(str(r.get("max_undercut_mm", "")))}</td>'
            f'<td>{html.escape(str(r.get("message", "")))}</td></tr>')
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<meta name=\"generator\" content=\"hnc_cam {__version__}\">"
            f"<title>{html.escape(title)}</title><style>{_asset('report.css')}</style></head><body>"
            f"<header><h1>{html.escape(title)}</h1></header><section class=\"sheet\">"
            "<table id=\"index\"><tr><th>row</th><th>program</th><th>verdict</th><th>parameters</th>"
            "<th>cycle time (s)</th><th>max overcut (mm)</th><th>max undercut (mm)</th>"
            "<th>message</th></tr>" + "".join(body) + "</table></section></body></html>\n")


def write_text(path: str | Path, text: str, option: str = "--report") -> None:
    """Write a page whole or not at all; an unwritable path is one line (exit 2)."""
    from ..errors import HncError
    from ..io import write_atomic
    if str(path) == "-":
        raise HncError(f"{option} -: the report is a file, give a path")
    try:
        write_atomic(path, text)
    except HncError as e:
        raise HncError(f"{option} {e}") from None
    except OSError as e:
        raise HncError(f"{option} {path}: cannot write: {e.strerror or e}") from None
