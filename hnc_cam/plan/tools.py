"""Which tool of the library can do what: reach of turning inserts into undercuts, boring
bars into bores, threading inserts for a pitch, grooving inserts for a groove.

Back clearance (the rule the planner applies, stated in the README): an insert of included
angle ``eps`` in a holder of approach angle ``kappa`` has its trailing edge at
``180 - kappa - eps`` degrees above the feed direction. It can follow a wall descending at
an angle ``theta`` below the feed direction only while ``theta <= 180 - kappa - eps - 2``
(2 deg kept as clearance). A CNMG in a 95 deg holder reaches 3 deg, a DNMG in a 93 deg holder
30 deg, a VNMG in a 93 deg holder 50 deg.

Fields the tool library does not have yet and that are derived here: the pitch of a
full-profile threading insert is read from its code (``16ER1.5ISO`` -> 1.5; ``A60`` partial
profiles take any pitch).
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


def thread_pitch(tool: Tool) -> float | None:
    """Pitch of a full-profile threading insert, None for a partial profile (any pitch)."""
    m = re.match(r"^\d{2}[EI]R(\d+(?:\.\d+)?)(ISO|UN|W)?$", tool.insert.code)
    return float(m.group(1)) if m else None


def thread_tools(lib: ToolLibrary, internal: bool) -> list[Tool]:
    use = "thread_id" if internal else "thread"
    out = [t for t in lib.tools if t.kind == "thread" and use in t.uses]
    if not out:  # a library that does not mark the use: internal inserts carry "IR"
        out = [t for t in lib.tools if t.kind == "thread"
               and (("IR" in t.insert.code) == internal)]
    return out


def describe(tool: Tool) -> str:
    return (f"T{tool.number:02d} {tool.name} {tool.insert.code} R{tool.nose_radius:g} "
            f"tip {tool.tip}")
