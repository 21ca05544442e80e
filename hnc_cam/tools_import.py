"""``hnc-cam tools import FILE [-o OUT]``: a Fusion 360 tool library (its JSON export) to our
tool library TOML, with a note for every field that could not be mapped.

The export is ``{"data": [tool, ...], "version": N}`` (a bare list is accepted too). Turning
tools are those whose ``type`` is ``turning general``, ``turning boring``,
``turning grooving`` or ``turning threading``; every other type (mills, drills, probes,
holders, tool blocks) is skipped and counted. Per tool:

=============================================  =============================================
Fusion 360                                     ours
=============================================  =============================================
``post-process.number``                        ``number`` (turret position, T01)
``post-process.diameter-offset`` (else number)  ``register`` (offset register, T0101)
``description`` (+ ``product-id``)             ``name``
``type``                                       ``kind`` / ``uses`` / ``tip`` (general: turn,
                                               rough+finish+face, tip 3; boring: bore, tip 2;
                                               threading: thread, tip 8 (6 when the holder or
                                               name says internal); grooving: groove, tip 3)
``geometry.SC`` shape letter, ``RA`` relief    ``insert``: the ISO code ``SC RA TC SCTY size
angle, ``TC`` tolerance, ``SCTY`` type,        thickness radius`` (``CNMG120408``); the size
``INSD`` inscribed circle, ``S`` thickness,    is the edge length from the inscribed circle
``RE`` corner radius                           and the shape; ``RE`` also gives ``radius``
``geometry.CW`` (grooving: cutting width)      ``insert = "GROOVE<width>"``
``geometry.TP`` thread pitch (threading)       ``insert = "16ER<pitch>ISO"`` / ``"16IR..."``
``holder.product-id`` / ``holder.description``  ``holder`` (its 3rd letter gives the approach)
``geometry.HAND`` / ``holder.HAND``            ``hand`` (R/L)
``start-values.presets[0].v_c`` / ``f_n``      ``vc_rough``/``vc_finish``, ``feed_rough``/
(``presets`` named *finish* for the finish)    ``feed_finish`` (mm/rev, m/min)
``start-values.presets[0].stepdown``           ``depth`` (roughing depth per side)
``unit`` ``inches``                            lengths x 25.4, feeds x 25.4, speeds ft/min
                                               x 0.3048
=============================================  =============================================

Not mapped (reported per tool): coolant, the holder's and the tool block's dimensions and
3-D geometry, tool-length compensation values, the insert's grade, material and coating,
vendor data, and presets other than the first roughing and finishing ones. A field that is
missing or not understood is named in the report; a tool without what the insert needs
(shape and corner radius, or the groove width, or the thread pitch) is skipped with the
reason.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .errors import ToolError

TURNING_TYPES = ("turning general", "turning boring", "turning grooving", "turning threading")
#: relief (clearance) angle in degrees -> ISO clearance letter
RELIEF_LETTER = {0: "N", 3: "A", 5: "B", 7: "C", 11: "P", 15: "D", 20: "E", 25: "F", 30: "G"}
#: included angle per ISO shape letter (degrees), for the edge length from the inscribed circle
SHAPE_ANGLE = {"C": 80.0, "D": 55.0, "E": 75.0, "M": 86.0, "V": 35.0, "K": 55.0, "S": 90.0,
               "T": 60.0, "W": 80.0, "R": 0.0}
#: Fusion's descriptive shape names seen in exports -> the ISO letter
SHAPE_NAMES = {"diamond 80": "C", "diamond 55": "D", "diamond 75": "E", "diamond 86": "M",
               "diamond 35": "V", "square": "S", "triangle": "T", "trigon": "W", "round": "R"}
#: fields we read; anything else in a tool is listed as not mapped
MAPPED = {"type", "description", "product-id", "unit", "geometry", "holder", "post-process",
          "start-values", "guid", "vendor", "BMC", "GRADE", "last_modified", "reference_guid"}
GEOMETRY_READ = {"SC", "RA", "TC", "SCTY", "INSD", "S", "RE", "CW", "TP", "HAND"}


@dataclass
class Imported:
    tools: list[dict[str, Any]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    skipped: dict[str, int] = field(default_factory=dict)


def _num(v: Any) -> float | None:
    if isinstance(v, bool):
        return None
    if isinstance(v, (int, float)) and math.isfinite(v):
        return float(v)
    if isinstance(v, str):
        try:
            f = float(v.strip())
        except ValueError:
            return None
        return f if math.isfinite(f) else None
    if isinstance(v, dict) and "value" in v:  # some exports wrap values
        return _num(v["value"])
    return None


def _edge_code(shape: str, ic: float) -> str:
    """ISO size digits: the cutting-edge length (mm, whole) from the inscribed circle."""
    if shape == "R":
        length = ic
    elif shape == "S":
        length = ic
    elif shape == "T":
        length = ic * math.sqrt(3.0)
    elif shape == "W":
        length = ic * 0.6869  # 80 deg trigon: 12.7 IC -> 08
    else:
        length = ic / math.sin(math.radians(SHAPE_ANGLE[shape]))
    return f"{int(length + 1e-6):02d}"


def _thickness_code(s: float) -> str:
    if abs(s - 3.97) < 0.05:
        return "T3"
    return f"{int(s + 1e-6):02d}"


def _shape_letter(sc: Any) -> str | None:
    if not isinstance(sc, str):
        return None
    s = sc.strip()
    if len(s) == 1 and s.upper() in SHAPE_ANGLE:
        return s.upper()
    return SHAPE_NAMES.get(s.lower())


def convert(data: Any, source: str = "<library>") -> Imported:
    """Map a parsed Fusion 360 library to our tool entries (dicts in TOML order)."""
    if isinstance(data, dict):
        items = data.get("data")
        if not isinstance(items, list):
            raise ToolError(f"{source}: not a Fusion 360 tool library: expected a JSON object "
                            f"with a \"data\" list of tools")
    elif isinstance(data, list):
        items = data
    else:
        raise ToolError(f"{source}: not a Fusion 360 tool library: expected a JSON object with a "
                        f"\"data\" list of tools")
    out = Imported()
    used_numbers: set[int] = set()
    for i, t in enumerate(items):
        if not isinstance(t, dict) or not isinstance(t.get("type"), str):
            out.skipped["entries without a type"] = out.skipped.get("entries without a type", 0) + 1
            continue
        typ = t["type"].strip().lower()
        if typ not in TURNING_TYPES:
            out.skipped[typ] = out.skipped.get(typ, 0) + 1
            continue
        entry, notes = _tool(t, i, used_numbers)
        out.notes.extend(notes)
        if entry is not None:
            used_numbers.add(entry["number"])
            out.tools.append(entry)
    if not out.tools:
        found = ", ".join(f"{k} x{v}" for k, v in sorted(out.skipped.items())) or "no tools"
        why = ("; " + "; ".join(out.notes)) if out.notes else ""
        raise ToolError(f"{source}: no turning tools (expected types "
                        f"{', '.join(TURNING_TYPES)}); found: {found}{why}")
    return out


def _tool(t: dict[str, Any], index: int, used: set[int]) -> tuple[dict[str, Any] | None, list[str]]:
    notes: list[str] = []
    typ = t["type"].strip().lower()
    desc = str(t.get("description") or t.get("product-id") or typ)
    label = f"tool[{index}] ({desc})"
    geo = t.get("geometry") if isinstance(t.get("geometry"), dict) else {}
    holder = t.get("holder") if isinstance(t.get("holder"), dict) else {}
    pp = t.get("post-process") if isinstance(t.get("post-process"), dict) else {}
    unit = str(t.get("unit", "millimeters")).lower()
    inch = unit.startswith("inch")
    k_len = 25.4 if inch else 1.0

    number = _num(pp.get("number"))
    if number is None or number != int(number) or not 0 < number < 100:
        n = 1
        while n in used:
            n += 1
        notes.append(f"{label}: post-process.number {pp.get('number')!r} is not 1-99; "
                     f"given T{n:02d}")
        number = n
    number = int(number)
    if number in used:
        return None, [f"{label}: skipped: turret position T{number:02d} is used by an earlier tool"]
    reg = _num(pp.get("diameter-offset"))
    register = int(reg) if reg is not None and reg == int(reg) and 0 < reg < 100 else number

    entry: dict[str, Any] = {"number": number, "register": register, "name": desc}
    hand = str(geo.get("HAND") or holder.get("HAND") or "R").strip().upper()[:1]
    if hand not in ("R", "L"):
        notes.append(f"{label}: hand {hand!r} not understood; R assumed")
        hand = "R"
    internal = typ == "turning boring" or "internal" in desc.lower() or " id " in f" {desc.lower()} "
    re_ = _num(geo.get("RE"))
    if typ == "turning grooving":
        w = _num(geo.get("CW"))
        if w is None or w <= 0:
            return None, notes + [f"{label}: skipped: grooving tool without geometry.CW (width)"]
        entry["insert"] = f"GROOVE{w * k_len:g}"
        if re_ is not None:
            entry["radius"] = round(re_ * k_len, 4)
        entry.update(kind="groove", uses=["groove"], tip=3)
    elif typ == "turning threading":
        p = _num(geo.get("TP"))
        if p is None or p <= 0:
            return None, notes + [f"{label}: skipped: threading tool without geometry.TP (pitch)"]
        pitch = p * k_len
        entry["insert"] = f"{'11I' if internal else '16E'}R{pitch:g}ISO"
        entry.update(kind="thread", uses=["thread_id" if internal else "thread"],
                     tip=6 if internal else 8)
    else:
        shape = _shape_letter(geo.get("SC"))
        ic = _num(geo.get("INSD"))
        if shape is None or re_ is None:
            return None, notes + [f"{label}: skipped: the insert needs geometry.SC (shape) and "
                                  f"geometry.RE (corner radius), got SC={geo.get('SC')!r} "
                                  f"RE={geo.get('RE')!r}"]
        ra = _num(geo.get("RA"))
        clr = RELIEF_LETTER.get(int(round(ra))) if ra is not None else None
        if clr is None:
            notes.append(f"{label}: relief angle RA={geo.get('RA')!r} not an ISO clearance; N "
                         f"(0 deg) assumed")
            clr = "N"
        tol = str(geo.get("TC") or "M").strip().upper()[:1] or "M"
        if not tol.isalpha():
            tol = "M"
        kind_l = str(geo.get("SCTY") or "G").strip().upper()[:1] or "G"
        if not kind_l.isalpha():
            kind_l = "G"
        if ic is None or ic <= 0:
            ic = 12.7 / k_len
            notes.append(f"{label}: no geometry.INSD (inscribed circle); 12.7 mm assumed for "
                         f"the insert's size")
        s = _num(geo.get("S"))
        if s is None or s <= 0:
            s = 4.76 / k_len
            notes.append(f"{label}: no geometry.S (thickness); 4.76 mm assumed")
        r_mm = re_ * k_len
        rcode = "M0" if r_mm < 0.05 else f"{int(round(r_mm * 10)):02d}"
        entry["insert"] = (f"{shape}{clr}{tol}{kind_l}{_edge_code(shape, ic * k_len)}"
                           f"{_thickness_code(s * k_len)}{rcode}")
        if rcode != "M0" and abs(int(rcode) / 10 - r_mm) > 1e-6:
            entry["radius"] = round(r_mm, 4)
        if typ == "turning boring":
            entry.update(kind="bore", uses=["rough", "finish"], tip=2)
        else:
            entry.update(kind="turn", uses=["rough", "finish", "face"], tip=3)
    hcode = str(holder.get("product-id") or holder.get("description") or "").strip()
    if hcode:
        entry["holder"] = hcode
    entry["hand"] = hand
    _presets(t, entry, inch, label, notes)
    ignored = sorted(k for k in t if k not in MAPPED)
    if ignored:
        notes.append(f"{label}: not mapped: {', '.join(ignored)}")
    gi = sorted(k for k in geo if k not in GEOMETRY_READ)
    if gi:
        notes.append(f"{label}: geometry not mapped: {', '.join(gi)}")
    if holder:
        notes.append(f"{label}: holder dimensions not mapped (the simulator draws the insert only)")
    return entry, notes


def _presets(t: dict[str, Any], entry: dict[str, Any], inch: bool, label: str,
             notes: list[str]) -> None:
    sv = t.get("start-values") if isinstance(t.get("start-values"), dict) else {}
    presets = sv.get("presets") if isinstance(sv.get("presets"), list) else []
    presets = [p for p in presets if isinstance(p, dict)]
    if not presets:
        notes.append(f"{label}: no start-values presets; the library's default feeds and "
                     f"speeds apply")
        return
    fin = next((p for p in presets if "finish" in str(p.get("name", "")).lower()), None)
    rough = next((p for p in presets if p is not fin), presets[0])
    k_len, k_vc = (25.4, 0.3048) if inch else (1.0, 1.0)
    for p, sfx in ((rough, "rough"), (fin or rough, "finish")):
        vc, fn = _num(p.get("v_c")), _num(p.get("f_n"))
        if vc is not None and vc > 0:
            entry[f"vc_{sfx}"] = round(vc * k_vc, 2)
        if fn is not None and fn > 0:
            entry[f"feed_{sfx}"] = round(fn * k_len, 4)
    sd = _num(rough.get("stepdown"))
    if sd is not None and sd > 0:
        entry["depth"] = round(sd * k_len, 3)
    if len(presets) > 2:
        notes.append(f"{label}: {len(presets) - 2} further preset(s) not mapped")


def _toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return json.dumps(str(v), ensure_ascii=False)  # a TOML basic string is a JSON string


def to_toml(imp: Imported, source: str) -> str:
    lines = [f"# Tool library imported from {Path(source).name} (Fusion 360 JSON) by hnc-cam "
             f"tools import.", "# Check the tip codes and offsets against the machine before use.",
             ""]
    for e in imp.tools:
        lines.append("[[tool]]")
        for k, v in e.items():
            lines.append(f"{k} = {_toml_value(v)}")
        lines.append("")
    return "\n".join(lines)


def import_file(path: str) -> tuple[str, Imported]:
    """Read, convert and check (the TOML must load as our tool library)."""
    try:
        raw = Path(path).read_bytes()
    except OSError as e:
        raise ToolError(f"{path}: cannot read the tool library: {e.strerror or e}") from None
    try:
        data = json.loads(raw.decode("utf-8-sig"))
    except UnicodeDecodeError:
        raise ToolError(f"{path}: not a Fusion 360 tool library: not UTF-8 text (expected its "
                        f"JSON export)") from None
    except json.JSONDecodeError as e:
        raise ToolError(f"{path}:{e.lineno}:{e.colno}: not a Fusion 360 tool library: not JSON "
                        f"({e.msg})") from None
    except RecursionError:
        raise ToolError(f"{path}: not a Fusion 360 tool library: JSON nested too deeply") from None
    imp = convert(data, path)
    text = to_toml(imp, path)
    _check(text, path)
    return text, imp


def _check(text: str, source: str) -> None:
    """The written TOML loads as our tool library (an insert code we cannot parse is an
    error naming the tool, not a file that fails later)."""
    import tempfile

    from .tooling import load_tools
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "tools.toml"
        p.write_text(text, "utf-8")
        try:
            load_tools(p)
        except ToolError as e:
            raise ToolError(f"{source}: the converted library does not load: "
                            f"{str(e).replace(str(p), 'tools.toml')}") from None


def import_command(args: argparse.Namespace) -> int:
    from .io import write_atomic
    text, imp = import_file(args.file)
    if args.output:
        write_atomic(args.output, text)
    else:
        sys.stdout.write(text)
        sys.stdout.flush()
    for n in imp.notes:
        print(f"note: {n}", file=sys.stderr)
    skipped = ", ".join(f"{k} x{v}" for k, v in sorted(imp.skipped.items()))
    print(f"{len(imp.tools)} turning tool(s) imported"
          + (f"; skipped (not turning tools): {skipped}" if skipped else ""), file=sys.stderr)
    return 0
