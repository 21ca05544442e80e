"""Which tool of the library can do what: reach of turning inserts into undercuts, boring
bars into bores, threading inserts for a pitch, grooving inserts for a groove.

Back clearance (the rule the planner applies, stated in the README): an insert of included
angle ``eps`` in a holder of approach angle ``kappa`` has its trailing edge at
``180 - kappa - eps`` degrees above the feed direction. It can follow a wall descending at
an angle ``theta`` below the feed direction only while ``theta <= 180 - kappa - eps - 2``
(2 deg kept as clearance). A CNMG in a 95 deg holder reaches 3 deg, a DNMG in a 93 deg holder
30 deg, a VNMG in a 93 deg holder 50 deg.

Threading inserts: the pitch of a program's thread always comes from the part's
:class:`~hnc_cam.geometry.Thread` declaration; the insert only limits which pitches it can
cut (:func:`thread_pitch_range`, read from the insert code as ISO threading inserts name it):

* a full-profile insert cuts one pitch: ``16ER1.5ISO`` 1.5 mm, ``16ER16UN`` 16 threads per
  inch (1.5875 mm), ``16ER11W`` 11 tpi (Whitworth);
* a partial-profile insert (the letters before the angle) cuts a range: ``A`` 0.5-1.5 mm,
  ``AG`` 0.5-3.0 mm, ``G`` 1.75-3.0 mm, ``N`` 3.5-5.0 mm, ``Q`` 5.5-6.0 mm (the common
  makers' ranges for ``A60``/``AG60``/``G60``/``N60``/``Q60``, and the same for 55 deg).
"""
from __future__ import annotations

import re

from ..tooling import Tool, ToolLibrary

CLEARANCE_MARGIN = 2.0  # deg


def trailing_angle(tool: Tool) -> float:
    """Angle of the trailing (minor) edge above the feed direction, deg."""
    return 180.0 - tool.approach - tool.insert.nose_angle


def back_reach(tool: Tool) -> float:
    """Steepest descending wall (deg below the feed direction) the tool can follow."""
    return trailing_angle(tool) - CLEARANCE_MARGIN


def can_square_shoulder(tool: Tool) -> bool:
    return tool.approach >= 90.0 + CLEARANCE_MARGIN / 2


def turning_tools(lib: ToolLibrary, use: str, kind: str = "turn") -> list[Tool]:
    return [t for t in lib.tools if use in t.uses and t.kind == kind]


#: partial-profile letters -> the pitch range (mm) such an insert cuts
PARTIAL_PROFILE_PITCH: dict[str, tuple[float, float]] = {
    "A": (0.5, 1.5), "AG": (0.5, 3.0), "G": (1.75, 3.0), "N": (3.5, 5.0), "Q": (5.5, 6.0)}

_FULL = re.compile(r"^\d{2}[EI]R(\d+(?:\.\d+)?)(ISO|UN|W)?$")
_PARTIAL = re.compile(r"^\d{2}[EI]R(AG|A|G|N|Q)(\d+)$")


def thread_pitch_range(tool: Tool) -> tuple[float, float] | None:
    """(smallest, largest) pitch in mm the threading insert cuts, or None when its code names
    neither a full profile nor a known partial profile (such an insert is not chosen)."""
    code = tool.insert.code
    m = _FULL.match(code)
    if m:
        v = float(m.group(1))
        p = 25.4 / v if m.group(2) in ("UN", "W") else v  # UN/W: threads per inch
        return (p, p)
    m = _PARTIAL.match(code)
    if m:
        return PARTIAL_PROFILE_PITCH[m.group(1)]
    return None


def thread_pitch(tool: Tool) -> float | None:
    """Pitch of a full-profile threading insert, None for a partial profile (a range, see
    :func:`thread_pitch_range`) or an unknown code."""
    r = thread_pitch_range(tool)
    return r[0] if r is not None and r[0] == r[1] and _FULL.match(tool.insert.code) else None


def cuts_pitch(tool: Tool, pitch: float) -> bool:
    """True when the threading insert's pitch range covers ``pitch`` (mm)."""
    r = thread_pitch_range(tool)
    return r is not None and r[0] - 1e-6 <= pitch <= r[1] + 1e-6


def thread_tools(lib: ToolLibrary, internal: bool) -> list[Tool]:
    use = "thread_id" if internal else "thread"
    out = [t for t in lib.tools if t.kind == "thread" and use in t.uses]
    if not out:  # a library that does not mark the use: internal inserts carry "IR"
        out = [t for t in lib.tools if t.kind == "thread"
               and (("IR" in t.insert.code) == internal)]
    return out


def groove_plunges(t: Tool, z_l: float, z_r: float, r_bottom: float, finish: float,
                   max_rpm: float) -> tuple[list[float], float, float, bool, float]:
    """How a grooving insert of width ``w`` cuts a square groove Z ``z_r``..``z_l`` whose
    bottom is at radius ``r_bottom``, outside or inside: the plunges' Z (the insert's corner
    at -Z, from the right wall leftward, overlapping by its corner radii), the finishing
    stock each plunge leaves on the walls and the bottom (``finish`` where the groove is
    wider than the insert by more than twice it, else 0: one finishing pass then follows),
    the spindle speed at the bottom (the insert's finishing surface speed, at most
    ``max_rpm``: the HNC-21T's G96 has no clamp word, so a capped groove runs G97 there),
    whether it is capped, and the dwell at the bottom (the tool's ``dwell_rev`` revolutions,
    at least 0.05 s)."""
    import math
    w = t.insert.width
    wide = z_r - z_l - w > 1e-6
    fa = finish if wide and z_r - z_l - w > 2 * finish + 1e-6 else 0.0
    first, last = z_r - w - fa, z_l + fa
    step = max(0.1 * w, w - 2 * t.nose_radius - 0.05)
    n = max(1, math.ceil((first - last) / step - 1e-9) + 1) if first - last > 1e-9 else 1
    pos = [first - (first - last) * i / (n - 1) for i in range(n)] if n > 1 else [last]
    rpm = t.vc_finish * 1000.0 / (2 * math.pi * max(r_bottom, 1e-3))
    capped = rpm > max_rpm
    rpm = min(max_rpm, rpm)
    dwell = max(round(t.dwell_rev * 60.0 / rpm, 2), 0.05)
    return pos, fa, rpm, capped, dwell


def describe(tool: Tool) -> str:
    return (f"T{tool.number:02d} {tool.name} {tool.insert.code} R{tool.nose_radius:g} "
            f"tip {tool.tip}")


# ------------------------------------------------------------------------------------------
# work materials (hnc_cam/data/materials.toml)
# ------------------------------------------------------------------------------------------

_MATERIALS: dict | None = None


def load_materials() -> dict[str, dict]:
    """The bundled material table, keyed by its section name (read once)."""
    global _MATERIALS
    if _MATERIALS is None:
        import tomllib
        from importlib import resources
        text = resources.files("hnc_cam.data").joinpath("materials.toml").read_text("utf-8")
        _MATERIALS = tomllib.loads(text)
    return _MATERIALS


def find_material(name: str) -> tuple[str, dict]:
    """(key, entry) for a material name or alias (case-insensitive); an unknown name is a
    PlanError naming the known ones."""
    from ..errors import PlanError
    table = load_materials()
    want = str(name).strip().upper()
    for key, m in table.items():
        if want == key.upper() or want in (a.upper() for a in m.get("aliases", [])):
            return key, m
    known = ", ".join(f"{k} ({m.get('name', k)})" for k, m in table.items())
    raise PlanError(f"unknown material {name!r}: the known materials are {known}")


def _clip(v: float, rng) -> float:
    lo, hi = float(rng[0]), float(rng[1])
    return min(max(v, lo), hi)


def apply_material(lib: ToolLibrary, material: dict) -> ToolLibrary:
    """The library with each tool's cutting data limited to the material's ranges: a
    library value inside the range is kept, one outside becomes the nearer end."""
    from dataclasses import replace
    r, f, g = material.get("rough", {}), material.get("finish", {}), material.get("groove", {})
    out = []
    for t in lib.tools:
        kw: dict = {}
        if t.kind in ("turn", "bore"):
            if "vc" in r:
                kw["vc_rough"] = _clip(t.vc_rough, r["vc"])
            if "feed" in r:
                kw["feed_rough"] = _clip(t.feed_rough, r["feed"])
            if "depth" in r and t.kind == "turn":
                kw["depth"] = _clip(t.depth, r["depth"])
            if "vc" in f:
                kw["vc_finish"] = _clip(t.vc_finish, f["vc"])
            if "feed" in f:
                kw["feed_finish"] = _clip(t.feed_finish, f["feed"])
        elif t.kind in ("drill", "center_drill"):
            d = material.get("drill", {})
            if "vc" in d:
                kw["vc_rough"] = _clip(t.vc_rough, d["vc"])
            if "feed" in d:
                kw["feed_rough"] = _clip(t.feed_rough, d["feed"])
        elif t.kind in ("groove", "groove_id", "groove_face"):
            if "vc" in g:
                kw["vc_finish"] = _clip(t.vc_finish, g["vc"])
            if "feed" in g:
                kw["feed_finish"] = _clip(t.feed_finish, g["feed"])
        out.append(replace(t, **kw) if kw else t)
    return ToolLibrary(tuple(out), lib.source)
