"""The plan as JSON (``generate --json OUT``): per operation what ``--explain`` says (its
label line and reason), its cycle as the program's dialect names it, tool, spindle with its
limit, feed and the zone it works in; plus the verification figures when verified.

Positions in the JSON are as the programs write them: X as a diameter, Z from the part's
right face (program zero)."""
from __future__ import annotations

import json
from typing import Any

from .model import Operation, Plan


def _r(v: float) -> float:
    return round(float(v), 4)


def _zone(op: Operation, plan: Plan) -> dict[str, float]:
    """The smallest box (diameters, Z) holding the operation's start point, its contour (its
    own blocks or the ns..nf contour it refers to, arcs over the X range they sweep) and the
    positions of its passes."""
    xs, zs = [abs(op.start[0])], [op.start[1]]
    owner = plan.contour_owner(op)
    x, z = op.start
    for b in owner.blocks:
        x = b.x if b.x is not None else x
        z = b.z if b.z is not None else z
        xs.append(abs(x))
        zs.append(z)
        if b.span is not None:
            a, c = b.span
            xs += [abs(a), abs(c)] + ([0.0] if a * c < 0 else [])
    if op.face is not None:
        xs.append(max(op.face.x_end, 0.0))
        zs += [float(p) for p in op.passes]
    if op.groove is not None:
        xs.append(abs(op.groove.x_bottom))
        w = op.tool.insert.width
        zs += [float(p) for p in op.passes] + [float(p) + w for p in op.passes]
    if op.thread is not None:
        xs.append(abs(op.thread.x_root))
        zs.append(op.thread.z_end)
    return {"diameter_min": _r(2 * min(xs)), "diameter_max": _r(2 * max(xs)),
            "z_min": _r(min(zs)), "z_max": _r(max(zs))}


def plan_json(prog: Any) -> dict[str, Any]:
    """The JSON document of a generated program (:class:`hnc_cam.plan.api.Program`)."""
    plan: Plan = prog.plan
    labels = prog.labels or {}
    ops = []
    for i, op in enumerate(plan.operations, 1):
        label = labels.get(plan.label_key(op))
        ops.append({
            "index": i,
            "name": op.name,
            "kind": op.kind,
            "cycle": label or op.cycle,
            "summary": op.describe(label) if label else op.note,
            "tool": {"number": op.tool.number, "register": op.tool.register,
                     "name": op.tool.name, "insert": op.tool.insert.code},
            "spindle": {"mode": op.spindle, "value": _r(op.speed),
                        "cap_rpm": _r(op.max_rpm),
                        # a dialect without a G96 clamp word runs this G97 speed instead
                        "unclamped_rpm": (_r(op.unclamped.value) if op.unclamped else None)},
            "feed_mm_rev": _r(op.feed),
            "reason": op.reason,
            "zone": _zone(op, plan),
            "notes": list(op.notes),
        })
    rep = prog.report
    return {
        "part": plan.name,
        "program_number": plan.program_number,
        "dialect": prog.dialect,
        "stock": plan.stock.spec,
        "compensation": plan.comp,
        "machine_max_rpm": _r(plan.machine.max_rpm),
        "chuck_max_rpm": _r(plan.machine.chuck_max_rpm) if plan.machine.chuck_max_rpm else None,
        "notes": list(plan.notes),
        "operations": ops,
        "cycle_time_s": _r(prog.cycle_time_s),
        "verification": rep.to_json() if rep is not None and hasattr(rep, "to_json") else None,
    }


def plan_json_text(prog: Any) -> str:
    return json.dumps(plan_json(prog), indent=2, ensure_ascii=False) + "\n"
