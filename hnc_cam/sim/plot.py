"""Plots of a simulation or a verification (matplotlib, imported lazily, Agg backend).

One figure in the half-plane, Z to the right and X (radius) up as in the manual's figures:
the stock (light grey), the remaining material (light blue) and its outline, the model outline
(black), the toolpath of the controlled point (rapids dashed, feed moves coloured by operation:
tool and cycle, see :func:`operation`), deviations beyond the tolerance (overcut red, reachable undercut
orange, unreachable leftover purple hatched, each with its deepest point marked), collisions
(red crosses where the move first touched material), the chuck's jaws (grey, hatched) when
the machine gives a grip, the part parted off (green) where it fell from, a legend and the
key figures. PNG or SVG by the file's suffix.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any
from ..units import fmt_cycle_time

from shapely.geometry.base import BaseGeometry

from ..geometry import Arc
from .region import polygons
from .simulate import Machined

#: feed colours, one per operation (tool and cycle), none of them the red of the rapids, the
#: orange of the undercut or the purple of the unreachable leftover
OP_COLOURS = ["#2ca02c", "#1f77b4", "#8c564b", "#17becf", "#bcbd22", "#7f7f7f", "#e377c2",
              "#006d5b", "#393b79"]


def operation(move) -> str:
    """The operation a feed move belongs to, for the legend: its tool and the cycle that made
    it (plain G01/G02/G03 contour moves of one tool are one operation), e.g. ``T01 G71``."""
    op = move.op or ("G32" if move.kind == "thread" else "G01")
    if op in ("G01", "G02", "G03"):
        op = "G01-G03"
    return f"T{move.tool:02d} {op}"


def _fill(ax, g: BaseGeometry, **kw) -> bool:
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MPath
    done = False
    for p in polygons(g):
        verts, codes = [], []
        for ring in [p.exterior, *p.interiors]:
            c = list(ring.coords)
            verts += c
            codes += [MPath.MOVETO] + [MPath.LINETO] * (len(c) - 2) + [MPath.CLOSEPOLY]
        if not done:
            ax.add_patch(PathPatch(MPath(verts, codes), **kw))
            kw.pop("label", None)
            done = True
        else:
            ax.add_patch(PathPatch(MPath(verts, codes), **kw))
    return done


def _outline(ax, g: BaseGeometry, **kw) -> None:
    first = True
    for p in polygons(g):
        for ring in [p.exterior, *p.interiors]:
            z, x = ring.xy
            ax.plot(z, x, **kw)
            if first:
                kw.pop("label", None)
                first = False


def _components_beyond(g: BaseGeometry, segs, tol: float,
                       also: BaseGeometry | None = None) -> BaseGeometry:
    """Components of ``g`` deeper than ``tol`` from the model (and from ``also``, as
    :func:`hnc_cam.sim.verify.verify` measures the reachable leftover)."""
    from shapely import union_all
    from .verify import _deepest
    keep = []
    for p in polygons(g):
        d = _deepest(p, segs, interior=False, also=also)
        if d is not None and d.size_mm > tol:
            keep.append(p)
    return union_all(keep) if keep else g.__class__()


def plot(machined: Machined, out: str | Path, report: Any = None, model: Any = None,
         title: str | None = None) -> None:
    """Write the figure to ``out`` (``.png`` or ``.svg``); bytes are written atomically."""
    import io

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..io import write_atomic

    suffix = Path(out).suffix.lower()
    if suffix not in (".png", ".svg"):
        from ..errors import HncError
        raise HncError(f"--plot {out}: the plot is written as PNG or SVG (.png/.svg)")
    fig = figure(machined, report=report, model=model, title=title)
    buf = io.BytesIO()
    fig.savefig(buf, format=suffix[1:], bbox_inches="tight")
    plt.close(fig)
    write_atomic(out, buf.getvalue())


def figure(machined: Machined, report: Any = None, model: Any = None, title: str | None = None):
    """The matplotlib figure of :func:`plot` (the caller closes it)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    # frame the work (stock and model), not the trips to the tool-change point
    z0, x0, z1, x1 = machined.stock.bounds if not machined.stock.is_empty else (0, 0, 1, 1)
    if model is not None:
        mb = model.bbox()
        z0, x0, z1, x1 = min(z0, mb[1]), min(x0, mb[0]), max(z1, mb[3]), max(x1, mb[2])
    jaws = getattr(machined, "jaws", None)
    if jaws is not None:  # the jaws' front part, in the frame
        jb = jaws.bounds
        z0, x1 = min(z0, max(jb[0], jb[2] - 0.5 * (z1 - z0) - 5.0)), max(x1, jb[3])
    pad = max(3.0, 0.12 * max(z1 - z0, x1 - x0))
    xlim = (z0 - pad, z1 + pad)
    ylim = (min(x0, 0.0) - pad * 0.5, x1 + pad)
    aspect = (ylim[1] - ylim[0]) / (xlim[1] - xlim[0])
    fig, ax = plt.subplots(figsize=(14, min(10.0, max(4.5, 10.0 * aspect + 1.6))), dpi=110)
    _fill(ax, machined.stock, facecolor="#eeeeee", edgecolor="#999999", lw=0.8, label="stock")
    _fill(ax, machined.material, facecolor="#cfe3f5", edgecolor="none", label="remaining material")
    if jaws is not None:
        _fill(ax, jaws, facecolor="#777777", edgecolor="#333333", lw=1.0, alpha=0.7,
              hatch="//", label="chuck jaws")
    fallen = sorted(getattr(machined, "fallen", []) or [], key=lambda g: -g.area)
    if fallen and not machined.stock.is_empty and fallen[0].area > 0.05 * machined.stock.area:
        # the largest piece cut loose (a part parted off), where it was cut off
        _fill(ax, fallen[0], facecolor="#d9ead3", edgecolor="#38761d", lw=1.0,
              label="parted off")
    _outline(ax, machined.material, color="#1f4e79", lw=1.0, label="machined outline")
    if model is not None:
        from .region import profile_polygon
        _outline(ax, profile_polygon(model), color="black", lw=1.2, ls="-", label="model")

    # toolpath, rapids dashed, feeds coloured by operation
    rapid_segs, by_op = [], {}
    for m in machined.toolpath.moves:
        if m.kind == "dwell":
            continue
        if m.kind == "arc":
            pts = Arc(m.start, m.end, m.center, bool(m.cw)).sample(0.01)
        else:
            pts = [m.start, m.end]
        seg = [(p[1], p[0]) for p in pts]
        if m.kind == "rapid":
            rapid_segs.append(seg)
        else:
            by_op.setdefault(operation(m), []).append(seg)  # in program order
    if rapid_segs:
        ax.add_collection(LineCollection(rapid_segs, colors="#d62728", linestyles="dashed",
                                         linewidths=0.6, alpha=0.7, label="rapid (G00)"))
    for i, (op, segs) in enumerate(by_op.items()):
        ax.add_collection(LineCollection(segs, colors=OP_COLOURS[i % len(OP_COLOURS)],
                                         linewidths=0.8, label=f"feed {op}"))

    lines = []
    if report is not None:
        from .verify import model_segments
        segs = model_segments(model) if model is not None else []
        tol = report.tol
        if segs:
            over = _components_beyond(report.overcut, segs, tol)
            if _fill(ax, over, facecolor="#d62728", edgecolor="#d62728", lw=1.5,
                     label=f"overcut > {tol:g} mm"):
                pass
            reach_under = report.undercut.difference(report.unreachable_region) \
                if not report.undercut.is_empty else report.undercut
            under = _components_beyond(reach_under, segs, tol, also=report.unreachable_region)
            _fill(ax, under, facecolor="#ff7f0e", edgecolor="#ff7f0e", lw=1.5,
                  label=f"undercut > {tol:g} mm")
            _fill(ax, report.unreachable_region, facecolor="none", edgecolor="#9467bd",
                  hatch="////", lw=0.8, label="unreachable leftover")
        for k, t in enumerate(report.threads):
            ax.axvspan(t.z_min, t.z_max, color="#2ca02c" if t.ok else "#d62728", alpha=0.08,
                       label="thread zone" if k == 0 else None)
        for k, u in enumerate(report.unreachable):
            ax.plot([u.z], [u.x], marker="D", ms=6, mfc="none", mec="#9467bd", mew=1.5,
                    label="unreachable (size)" if k == 0 else None)
            ax.annotate(f"{u.size_mm:.3f}", (u.z, u.x), textcoords="offset points",
                        xytext=(6, 4), color="#9467bd", fontsize=8)
        for d, c, name in ((report.overcut_at, "#d62728", "max overcut"),
                           (report.undercut_at, "#ff7f0e", "max undercut")):
            if d is not None and d.size_mm > tol:
                ax.plot([d.z], [d.x], marker="o", ms=9, mfc="none", mec=c, mew=2)
                ax.annotate(f"{name} {d.size_mm:.3f}", (d.z, d.x), textcoords="offset points",
                            xytext=(8, 8), color=c, fontsize=9,
                            bbox=dict(boxstyle="round,pad=0.2", fc="white", ec=c, alpha=0.85))
        lines = [f"{'PASS' if report.passed else 'FAIL'} at tol {tol:g} mm",
                 f"max overcut {report.max_overcut_mm:.4f} mm",
                 f"max undercut {report.max_undercut_mm:.4f} mm",
                 f"unreachable: {len(report.unreachable)}"]
        lines += [str(t) for t in report.threads]
    issues = machined.issues
    if issues:
        # each finding where the move first touched material; a finding without that place
        # (a thread move with the spindle stopped) at the end of its line's first move
        xs, zs, marked = [], [], []
        for iss in issues:
            at = getattr(iss, "at", None)
            if at is None:
                at = next((m.end for m in machined.toolpath.moves if m.line == iss.line), None)
            if at is not None:
                xs.append(at[0])
                zs.append(at[1])
                marked.append(iss)
        if zs:
            ax.plot(zs, xs, "x", color="#d62728", ms=10, mew=2.5, label="collision / check")
            for z, x, iss in zip(zs, xs, marked):
                ax.annotate(f"line {iss.line}", (z, x), textcoords="offset points",
                            xytext=(6, -12), color="#d62728", fontsize=8)
    t = machined.cycle_time_s
    lines += [f"collisions/checks: {len(issues)}",
              f"cycle time {fmt_cycle_time(t)}",
              f"removed {machined.removed_volume_mm3:.0f} mm³",
              f"air cut {100 * machined.air_cut_fraction:.1f} % of feed time"]
    # key figures under the plot, three to a row (the legend has the right-hand side)
    rows = ["   |   ".join(lines[i:i + 3]) for i in range(0, len(lines), 3)]
    ax.annotate("\n".join(rows), xy=(0.0, 0.0), xycoords="axes fraction", xytext=(0, -34),
                textcoords="offset points", va="top", ha="left", fontsize=9, family="monospace",
            bbox=dict(boxstyle="round", facecolor="white", alpha=0.9, edgecolor="#999999"))
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="box")
    ax.axhline(0.0, color="#555555", lw=0.6, ls="-.")
    ax.set_xlabel("Z (mm)")
    ax.set_ylabel("X radius (mm)")
    ax.grid(True, lw=0.3, alpha=0.5)
    ax.set_title(title or machined.toolpath.file)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, framealpha=0.85)
    fig.tight_layout()
    return fig
