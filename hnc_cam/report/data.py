"""What the HTML report shows, as plain values (JSON-ready): the toolpath in compact columns,
the material keyframes of the step-through, the model, the findings and the setup sheet.

Units: millimetres; **X as radius** in every coordinate array (the page labels diameters);
coordinates are integers in micrometres (the simulator's chord error is 0.5 um, so rounding
to 1 um adds at most 0.71 um to what is drawn). Moves keep their exact geometry: a line is
its two end points, an arc its end points, centre and direction; the page draws arcs as arcs.

Keyframes (the material "as removed up to the selected block"): the stock minus the swept
tool, taken from the simulator itself (:func:`hnc_cam.sim.material_after`: its own state after
k moves, fallen pieces gone), and kept at a bounded number of moves: after the last move of every
operation (a run of moves with the same tool, register and cycle), and after every k-th move
with k = ceil(moves / ``KEYFRAMES``), so at most about ``KEYFRAMES`` + operations frames
whatever the length of the program. A frame whose material did not change refers to the
earlier frame by its index instead of repeating the rings. The page shows the last keyframe at or before the selected
move. The final frame is the simulator's own result (``Machined.material``).
"""
from __future__ import annotations

import math
from typing import Any, Iterable, Sequence

#: target number of evenly spaced keyframes (plus one per operation boundary)
KEYFRAMES = 120
#: the intermediate keyframes are drawn within this many mm (the final one is exact to 1 um)
FRAME_SIMPLIFY = 0.002
KIND_CODES = {"rapid": 0, "line": 1, "arc": 2, "thread": 3, "dwell": 4}


def _um(v: float) -> int:
    return int(round(float(v) * 1000.0))


def rings_of(g, simplify: float = 0.0) -> list[list[int]]:
    """Boundary rings of a shapely region in (z, x) as flat integer um, delta-encoded:
    [z0, x0, z1 - z0, x1 - x0, ...] (the closing point dropped, repeated points too);
    ``simplify`` > 0: Douglas-Peucker within that many mm."""
    from ..sim.region import polygons
    out: list[list[int]] = []
    if simplify > 0 and not g.is_empty:
        g = g.simplify(simplify, preserve_topology=True)
    for p in polygons(g):
        for ring in [p.exterior, *p.interiors]:
            c = list(ring.coords)[:-1]
            flat: list[int] = []
            pz = px = 0
            for z, x in c:
                iz, ix = _um(z), _um(x)
                if flat and iz == pz and ix == px:
                    continue
                flat.append(iz - pz)
                flat.append(ix - px)
                pz, px = iz, ix
            out.append(flat)
    return out


def operation_label(move) -> str:
    """The operation a move belongs to, as the plot names it (tool and cycle)."""
    from ..sim.plot import operation
    return operation(move)


def moves_columns(moves: Sequence[Any]) -> dict[str, Any]:
    """The toolpath as columns: ``k`` kind codes (:data:`KIND_CODES`), ``e`` end points
    [z, x, ...] (um), ``s`` sparse starts [i, z, x, ...] where a move does not start where the
    previous one ended, ``a`` arcs [i, cz, cx, cw, ...], ``l`` program lines, ``g`` operation
    index into ``ops``, ``t`` cumulative time at the end of each move (0.01 s), ``f`` feed
    (mm/min, 0 for rapids and dwells), ``ops`` the operation labels, ``x0z0`` the first start."""
    k: list[int] = []
    e: list[int] = []
    s: list[int] = []
    a: list[int] = []
    lines: list[int] = []
    g: list[int] = []
    t: list[int] = []
    f: list[float] = []
    ops: list[str] = []
    op_index: dict[str, int] = {}
    clock = 0.0
    prev = None
    first = [0, 0]
    for i, m in enumerate(moves):
        start = (_um(m.start[1]), _um(m.start[0]))
        end = (_um(m.end[1]), _um(m.end[0]))
        if i == 0:
            first = [start[0], start[1]]
        elif start != prev:
            s.extend((i, start[0], start[1]))
        prev = end
        k.append(KIND_CODES.get(m.kind, 1))
        e.extend(end)
        if m.kind == "arc" and m.center is not None:
            a.extend((i, _um(m.center[1]), _um(m.center[0]), 1 if m.cw else 0))
        lines.append(int(m.line))
        label = "rapid" if m.kind == "rapid" else operation_label(m)
        gi = op_index.get(label)
        if gi is None:
            gi = op_index[label] = len(ops)
            ops.append(label)
        g.append(gi)
        clock += float(m.duration)
        t.append(int(round(clock * 100)))
        f.append(0 if m.feed is None else round(float(m.feed), 1))
    return {"k": k, "e": e, "s": s, "a": a, "l": lines, "g": g, "t": t, "f": f, "ops": ops,
            "x0z0": first}


def keyframe_ends(moves: Sequence[Any], target: int = KEYFRAMES) -> list[int]:
    """Move counts after which a keyframe is kept: every operation boundary and every k-th
    move (k = ceil(n / target)), always including n."""
    n = len(moves)
    if n == 0:
        return []
    step = max(1, math.ceil(n / max(1, target)))
    ends = set(range(step, n, step))
    for i in range(1, n):
        a, b = moves[i - 1], moves[i]
        if (a.tool, a.register, a.op) != (b.tool, b.register, b.op) and a.kind != "rapid":
            ends.add(i)
    ends.add(n)
    return sorted(ends)


def keyframes(machined, target: int = KEYFRAMES) -> list[dict[str, Any]]:
    """The material after selected moves (see the module doc): ``[{"n": moves done,
    "t": seconds, "rings": [...]}, ...]``, the first frame the stock (n = 0), the last the
    simulator's final material."""
    from ..sim import material_after

    tp = machined.toolpath
    moves = tp.moves
    frames = [{"n": 0, "t": 0.0, "rings": rings_of(machined.stock)}]
    ends = keyframe_ends(moves, target)
    if not ends:
        return frames
    cum = [0.0]
    for m in moves:
        cum.append(cum[-1] + float(m.duration))
    inner = [e for e in ends if e < len(moves)]
    mats = dict(material_after(machined, inner)) if inner else {}
    last = (frames[0]["rings"], 0)  # rings of the last frame that carries them, its index
    for end in ends:
        if end == len(moves):
            frames.append({"n": end, "t": round(cum[end], 2),
                           "rings": rings_of(machined.material)})
            break
        rings = rings_of(mats[end], FRAME_SIMPLIFY)
        if rings == last[0]:
            frames.append({"n": end, "t": round(cum[end], 2), "rings": last[1]})
        else:
            last = (rings, len(frames))
            frames.append({"n": end, "t": round(cum[end], 2), "rings": rings})
    return frames


def segments_json(segs: Iterable[Any]) -> list[list[int]]:
    """Exact Line/Arc segments as [z0, x0, z1, x1] or [z0, x0, z1, x1, cz, cx, cw] (um)."""
    out: list[list[int]] = []
    for s in segs:
        row = [_um(s.start[1]), _um(s.start[0]), _um(s.end[1]), _um(s.end[0])]
        c = getattr(s, "center", None)
        if c is not None:
            row += [_um(c[1]), _um(c[0]), 1 if s.cw else 0]
        out.append(row)
    return out


def findings(machined, report=None, model=None) -> dict[str, Any]:
    """Deviations beyond the tolerance (regions and deepest points with values), unreachable
    leftover, thread zones, collisions/check findings with the move they belong to."""
    out: dict[str, Any] = {"overcut": [], "undercut": [], "unreachable_region": [],
                           "marks": [], "threads": [], "issues": [], "notes": []}
    tp = machined.toolpath
    first_move: dict[int, int] = {}
    for i, m in enumerate(tp.moves):
        first_move.setdefault(m.line, i)
    for iss in machined.issues:
        out["issues"].append({"line": iss.line, "block": iss.block, "message": iss.message,
                              "move": first_move.get(iss.line, -1)})
    for n in machined.notes:
        out["notes"].append({"line": n.line, "block": n.block, "message": n.message})
    for s in machined.thread_spans:
        out["threads"].append({"z0": _um(s.z_min), "z1": _um(s.z_max), "x0": _um(s.x_min),
                               "x1": _um(s.x_max), "inside": bool(s.inside), "lead": s.lead,
                               "ok": None, "text": ""})
    if report is None:
        return out
    tol = report.tol
    if model is not None:
        from ..sim.plot import _components_beyond
        from ..sim.verify import model_segments
        segs = model_segments(model)
        if not report.overcut.is_empty:
            out["overcut"] = rings_of(_components_beyond(report.overcut, segs, tol))
        if not report.undercut.is_empty:
            reach = report.undercut.difference(report.unreachable_region)
            out["undercut"] = rings_of(_components_beyond(reach, segs, tol,
                                                          also=report.unreachable_region))
    out["unreachable_region"] = rings_of(report.unreachable_region)
    for d, kind, name in ((report.overcut_at, "overcut", "max overcut"),
                          (report.undercut_at, "undercut", "max undercut")):
        if d is not None and d.size_mm > tol:
            out["marks"].append({"kind": kind, "z": _um(d.z), "x": _um(d.x),
                                 "size": round(d.size_mm, 4), "line": d.line,
                                 "label": f"{name} {d.size_mm:.4f} mm"})
    for u in report.unreachable:
        out["marks"].append({"kind": "unreachable", "z": _um(u.z), "x": _um(u.x),
                             "size": round(u.size_mm, 4), "line": u.line,
                             "label": f"unreachable {u.size_mm:.4f} mm"})
    if report.threads:
        out["threads"] = [{"z0": _um(t.z_min), "z1": _um(t.z_max), "x0": None, "x1": None,
                           "inside": bool(t.internal), "lead": None, "ok": bool(t.ok),
                           "text": str(t)} for t in report.threads]
    return out


def verdict(report=None, machined=None) -> dict[str, Any]:
    """The verdict line and the key figures."""
    if report is None:
        n = len(machined.issues) if machined is not None else 0
        return {"pass": n == 0 if machined is not None else None,
                "line": ("simulated, no verification: " +
                         (f"{n} collision(s)/check finding(s)" if n else "no collisions")),
                "figures": {}, "reasons": [], "summary": machined.summary() if machined else ""}
    line = (f"{'PASS' if report.passed else 'FAIL'} at tolerance {report.tol:g} mm: "
            f"max overcut {report.max_overcut_mm:.4f} mm, max undercut "
            f"{report.max_undercut_mm:.4f} mm, {len(report.unreachable)} unreachable, "
            f"{len(report.collisions)} collision(s)/finding(s)")
    return {"pass": bool(report.passed), "line": line,
            "figures": {"tolerance_mm": report.tol,
                        "max_overcut_mm": round(report.max_overcut_mm, 4),
                        "max_undercut_mm": round(report.max_undercut_mm, 4),
                        "unreachable": len(report.unreachable),
                        "collisions": len(report.collisions),
                        "cycle_time_s": round(report.cycle_time_s, 1),
                        "removed_volume_mm3": round(report.removed_volume_mm3, 1),
                        "air_cut_percent": round(100 * report.air_cut_fraction, 1),
                        "strict": bool(report.strict)},
            "reasons": list(report.reasons), "summary": report.summary()}


def _fmt_range(vals: list[float], unit: str) -> str:
    vals = [v for v in vals if v > 0]
    if not vals:
        return ""
    lo, hi = min(vals), max(vals)
    return f"{lo:.0f} {unit}" if abs(hi - lo) < 0.5 else f"{lo:.0f}-{hi:.0f} {unit}"


def operations_run(moves: Sequence[Any]) -> list[dict[str, Any]]:
    """The program's operations in order, from the toolpath: runs of moves of one tool,
    register and cycle (the rapids before a run belong to it), with lines, feeds, spindle
    speeds and time."""
    runs: list[dict[str, Any]] = []
    cur: dict[str, Any] | None = None
    pending: list[Any] = []
    for i, m in enumerate(moves):
        if m.kind == "rapid":
            pending.append((i, m))
            continue
        label = operation_label(m)
        key = (m.tool, m.register, label)
        if cur is None or cur["key"] != key:
            cur = {"key": key, "moves": []}
            runs.append(cur)
        cur["moves"].extend(pending)
        pending = []
        cur["moves"].append((i, m))
    if pending:
        if cur is None:
            cur = {"key": (pending[0][1].tool, pending[0][1].register, "rapid"), "moves": []}
            runs.append(cur)
        cur["moves"].extend(pending)
    out = []
    for r in runs:
        ms = [m for _i, m in r["moves"]]
        tool, reg, label = r["key"]
        feeds = [m for m in ms if m.kind != "rapid" and m.kind != "dwell"]
        out.append({"tool": f"T{tool:02d}{reg:02d}", "operation": label,
                    "first_move": r["moves"][0][0], "last_move": r["moves"][-1][0],
                    "lines": f"{min(m.line for m in ms)}-{max(m.line for m in ms)}",
                    "moves": len(ms),
                    "feed": _fmt_range([float(m.feed or 0) for m in feeds], "mm/min"),
                    "spindle": _fmt_range([float(m.spindle) for m in feeds], "rpm"),
                    "time_s": round(sum(float(m.duration) for m in ms), 1)})
    return out


def tools_table(moves: Sequence[Any], machine, plan=None, library=None) -> list[dict[str, Any]]:
    """One row per tool/register the program uses: T word, name, insert, holder, nose radius,
    tip code, offsets (geometry and wear, X on the diameter)."""
    by_number: dict[int, Any] = {}
    for src in (getattr(library, "tools", None) or (),
                [op.tool for op in getattr(plan, "operations", None) or ()]):
        for t in src:
            by_number[int(t.number)] = t
    seen: list[tuple[int, int]] = []
    for m in moves:
        key = (int(m.tool), int(m.register))
        if key not in seen and key != (0, 0):
            seen.append(key)
    rows = []
    for tool, reg in seen:
        r = machine.register(reg) if machine is not None else None
        t = by_number.get(tool)
        ins = getattr(r, "insert", None)
        rows.append({"t": f"T{tool:02d}{reg:02d}",
                     "name": getattr(t, "name", "") if t is not None else "",
                     "insert": (t.insert.code if t is not None else (ins.code if ins else "")),
                     "holder": getattr(t, "holder", "") if t is not None else "",
                     "nose_radius": round(float(r.radius), 3) if r is not None else None,
                     "tip": int(r.tip) if r is not None else None,
                     "x_offset": round(float(r.x), 3) if r is not None else None,
                     "z_offset": round(float(r.z), 3) if r is not None else None,
                     "x_wear": round(float(r.x_wear), 3) if r is not None else None,
                     "z_wear": round(float(r.z_wear), 3) if r is not None else None})
    return rows


def plan_operations(plan, labels: dict[str, str] | None = None) -> list[dict[str, Any]]:
    """The planner's operations as plain values (read duck-typed: name, cycle, tool, speed,
    feed, reason, notes); ``labels``: the program's dialect's names of its cycles (a generated
    program's ``labels``), so a FANUC program's page says G70 where the HNC-21T's says contour."""
    out = []
    key = getattr(plan, "label_key", None)
    for op in getattr(plan, "operations", None) or ():
        unit = "m/min" if getattr(op, "speed_mode", "G96") == "G96" else "rpm"
        cycle = (labels or {}).get(key(op, labels), op.cycle) if key is not None else op.cycle
        out.append({"name": op.name, "cycle": cycle,
                    "tool": f"T{op.tool.number:02d}{op.tool.register:02d}",
                    "speed": f"{op.speed_mode} {op.speed:g} {unit}",
                    "feed": f"{op.feed:g} mm/rev", "reason": op.reason,
                    "notes": list(getattr(op, "notes", []) or [])})
    return out
