"""The plan as JSON (``generate --json OUT``): per operation what ``--explain`` says (its
label line and reason), its cycle as the program's dialect names it, tool, spindle with its
limit, feed and the zone it works in; plus the verification figures when verified.

Positions in the JSON are as the programs write them: X as a diameter, Z from the part's
right face (program zero).

Also here: a SINUMERIK program's main program and subprograms written one per file into a
folder (``generate --dialect siemens802 -o DIR/``), all of them or none."""
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
        label = labels.get(plan.label_key(op, labels))
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


# ------------------------------------------------------------------------------------------
# one file per program (SINUMERIK: NAME.MPF and its subprograms NAME_C1.SPF ... in a folder)
# ------------------------------------------------------------------------------------------

def split_programs(text: str) -> list[tuple[str, str]]:
    """The programs of a SINUMERIK file, in order: ``(file name, text)``, ``NAME.MPF`` for a
    main program headed ``%_N_NAME_MPF`` and ``NAME.SPF`` for a subprogram headed
    ``%_N_NAME_SPF``; each text starts with its header line. Lines before the first header
    belong to the first program."""
    import re
    head = re.compile(r"%_N_([A-Za-z0-9_]+)_(MPF|SPF)\s*$")
    out: list[tuple[str, list[str]]] = []
    lead: list[str] = []
    for line in text.splitlines(keepends=True):
        m = head.match(line.strip())
        if m:
            out.append((f"{m.group(1)}.{m.group(2)}", [line]))
        elif out:
            out[-1][1].append(line)
        else:
            lead.append(line)
    if not out:
        raise ValueError("the text holds no %_N_NAME_MPF / %_N_NAME_SPF program")
    out[0][1][0:0] = lead
    names = [n for n, _ in out]
    if len(set(n.upper() for n in names)) != len(names):
        raise ValueError(f"a program name appears twice: {', '.join(names)}")
    return [(n, "".join(lines)) for n, lines in out]


def is_folder_target(path: str) -> bool:
    """``-o`` names a folder: it ends with ``/`` (created when missing) or is an existing
    directory."""
    import os
    return path.endswith(("/", os.sep)) or os.path.isdir(path)


def write_program_folder(folder: str, text: str) -> list[str]:
    """Write each program of ``text`` (:func:`split_programs`) as its own file in ``folder``,
    all of them or none (:func:`write_files`). Returns the paths written. Errors are one line
    (HncError)."""
    from ..errors import HncError
    try:
        programs = split_programs(text)
    except ValueError as e:
        raise HncError(f"{folder}: cannot write the programs one per file: {e}") from None
    return write_files(folder, programs)


def write_files(folder: str, programs: list[tuple[str, str]]) -> list[str]:
    """Write each ``(name, text)`` of ``programs`` as its own file in ``folder`` (created when
    missing), all of them or none: every target is checked first (an existing file must be a
    regular file, not a symbolic link, a device or a folder, so nothing outside the folder is
    replaced), every file is written to a temporary file beside its target, and only then are
    they renamed into place. Returns the paths written. Errors are one line (HncError)."""
    import os
    import stat
    import tempfile
    from ..errors import HncError
    from ..io import clean_stale_temporaries, signals_held
    d = folder.rstrip("/" + os.sep) or folder
    try:
        os.makedirs(d, exist_ok=True)
    except FileExistsError:
        raise HncError(f"{folder}: cannot write: a file is in the way of the folder") from None
    except OSError as e:
        raise HncError(f"{folder}: cannot create the folder: {e.strerror or e}") from None
    if not os.path.isdir(d):
        raise HncError(f"{folder}: cannot write: not a folder")
    targets = [os.path.join(d, name) for name, _ in programs]
    for t in targets:
        try:
            st = os.lstat(t)
        except FileNotFoundError:
            continue
        except OSError as e:
            raise HncError(f"{t}: cannot write: {e.strerror or e}") from None
        if stat.S_ISLNK(st.st_mode):
            raise HncError(f"{t}: cannot write: a symbolic link is there (not replaced)")
        if not stat.S_ISREG(st.st_mode):
            what = "a folder" if stat.S_ISDIR(st.st_mode) else "not a regular file"
            raise HncError(f"{t}: cannot write: {what} is there (not replaced)")
    clean_stale_temporaries(d)
    umask = os.umask(0)
    os.umask(umask)
    staged: list[tuple[str, str]] = []
    with signals_held():  # all programs or none, even under Ctrl-C; no temporary left
        try:
            for (name, body), t in zip(programs, targets):
                fd, tmp = tempfile.mkstemp(prefix=f".{name}.{os.getpid()}.", suffix=".tmp", dir=d)
                staged.append((tmp, t))
                with os.fdopen(fd, "wb") as f:
                    f.write(body.encode("utf-8"))
                try:
                    mode = stat.S_IMODE(os.stat(t).st_mode)
                except FileNotFoundError:
                    mode = 0o666 & ~umask
                os.chmod(tmp, mode)
            for tmp, t in staged:
                os.replace(tmp, t)
        except OSError as e:
            for tmp, _ in staged:
                try:
                    os.unlink(tmp)
                except OSError:
                    pass
            raise HncError(f"{folder}: cannot write: {e.strerror or e}") from None
        except BaseException:
            for tmp, _ in staged:
                try:
                    os.unlink(tmp)
                except OSError:
                    pass
            raise
    return targets
