"""The interpreter's output: what the controlled point of the tool does, move by move.

Positions are of the tool's **controlled point** (the imaginary tip for tip codes 1-8, the
nose centre for 0/9) in **work coordinates**, after tool offsets and nose-radius
compensation, with X as **radius** (physical). JSON and display use diameters.

JSON of a move (``Move.to_json``): the issue's contract ``type start end [center cw] feed tool
line`` (X as diameter, ``feed`` in mm/min or null, ``line`` 1-based in the file), plus
``register`` (offset register oo), ``spindle`` (rpm, G96 resolved per move; 0 = stopped),
``spindle_dir`` (3/4/5), ``op`` (the G code or cycle that made it), ``lead``/``angle`` on
threads and ``seconds`` on dwells.

A G00 is carried as the real dog-leg: one ``rapid`` move per straight piece (both axes at
their own rates until the shorter one arrives, then the other alone).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any, Iterable, Optional
from ..units import fmt_cycle_time

from ..geometry import Arc, Line, Point, Segment

MOVE_KINDS = ("rapid", "line", "arc", "thread", "dwell")


@dataclass(slots=True)
class Move:
    kind: str  # rapid | line | arc | thread | dwell
    start: Point  # (x radius, z)
    end: Point
    line: int  # 1-based source line
    feed: Optional[float] = None  # mm/min (None for rapid and dwell)
    center: Optional[Point] = None  # arcs only
    cw: Optional[bool] = None  # arcs only (G02 = True)
    tool: int = 0  # tool number tt of the active T word
    register: int = 0  # offset register oo
    spindle: float = 0.0  # rpm actually turning (0 = stopped), G96 resolved
    spindle_dir: int = 5  # 3 cw, 4 ccw, 5 stopped
    coolant: bool = False
    duration: float = 0.0  # seconds
    lead: float = 0.0  # thread lead (mm/rev), thread moves
    angle: float = 0.0  # spindle start angle of a thread pass, deg
    thread_angle: float = 0.0  # tool profile angle of the thread cycle (G76 A), deg; 0 = unknown
    op: str = ""  # what produced it: G00 G01 G02 G03 G32 G80 G81 G82 G71 G72 G73 G76 ...
    comp: int = 40  # 40/41/42 active when the move was made

    def segment(self) -> Segment:
        """The exact geometry of the move (dwells are a zero-length line)."""
        if self.kind == "arc":
            assert self.center is not None and self.cw is not None
            return Arc(self.start, self.end, self.center, self.cw)
        return Line(self.start, self.end)

    @property
    def length(self) -> float:
        if self.kind == "dwell":
            return 0.0
        return self.segment().length

    def to_json(self) -> dict[str, Any]:
        d: dict[str, Any] = {
            "type": self.kind,
            "start": [_r(2 * self.start[0]), _r(self.start[1])],
            "end": [_r(2 * self.end[0]), _r(self.end[1])],
        }
        if self.kind == "arc":
            assert self.center is not None
            d["center"] = [_r(2 * self.center[0]), _r(self.center[1])]
            d["cw"] = bool(self.cw)
        d["feed"] = None if self.feed is None else _r(self.feed)
        d["tool"] = self.tool
        d["line"] = self.line
        # additions to the contract (consumers may ignore them)
        d["register"] = self.register
        d["spindle"] = _r(self.spindle)  # rpm turning during the move (G96 resolved), 0 = stopped
        d["spindle_dir"] = self.spindle_dir  # 3 M03, 4 M04, 5 stopped
        d["op"] = self.op
        if self.kind == "thread":
            d["lead"] = _r(self.lead)
            d["angle"] = _r(self.angle)
        if self.kind == "dwell":
            d["seconds"] = _r(self.duration)
        return d


def _r(v: float) -> float:
    v = round(float(v), 6)
    return 0.0 if v == 0 else v


@dataclass(slots=True)
class Warning_:
    line: int
    message: str


@dataclass
class Toolpath:
    moves: list[Move] = field(default_factory=list)
    warnings: list[Warning_] = field(default_factory=list)
    blocks_executed: int = 0
    file: str = "<program>"
    source_lines: list[str] = field(default_factory=list)

    def block(self, line: int) -> str:
        """The text of 1-based source line ``line``."""
        if 1 <= line <= len(self.source_lines):
            return self.source_lines[line - 1].strip()
        return ""

    @property
    def cycle_time_s(self) -> float:
        return sum(m.duration for m in self.moves)

    def length(self, kinds: Iterable[str]) -> float:
        ks = set(kinds)
        return sum(m.length for m in self.moves if m.kind in ks)

    @property
    def feed_length(self) -> float:
        return self.length(("line", "arc", "thread"))

    @property
    def rapid_length(self) -> float:
        return self.length(("rapid",))

    def extents(self) -> tuple[float, float, float, float]:
        """(xmin, zmin, xmax, zmax) over all moves (x radius), arcs by their true bounds."""
        if not self.moves:
            return (0.0, 0.0, 0.0, 0.0)
        xs0, zs0, xs1, zs1 = [], [], [], []
        for m in self.moves:
            b = m.segment().bbox()
            xs0.append(b[0]); zs0.append(b[1]); xs1.append(b[2]); zs1.append(b[3])
        return (min(xs0), min(zs0), max(xs1), max(zs1))

    def to_json(self) -> dict[str, Any]:
        return {
            "moves": [m.to_json() for m in self.moves],
            "cycle_time_s": _r(self.cycle_time_s),
            "warnings": [{"line": w.line, "message": w.message} for w in self.warnings],
        }

    def dumps(self) -> str:
        return json.dumps(self.to_json(), indent=None, separators=(",", ":"))

    def summary(self) -> str:
        x0, z0, x1, z1 = self.extents()
        t = self.cycle_time_s
        return (f"{self.file}: {self.blocks_executed} blocks executed, {len(self.moves)} moves, "
                f"feed {self.feed_length:.3f} mm, rapid {self.rapid_length:.3f} mm, "
                f"cycle time {fmt_cycle_time(t)}, "
                f"X {2 * x0:.3f}..{2 * x1:.3f} (dia), Z {z0:.3f}..{z1:.3f}"
                + (f", {len(self.warnings)} warning(s)" if self.warnings else ""))


def rapid_time(machine_rapid_x: float, machine_rapid_z: float, dx: float, dz: float) -> float:
    """Seconds for a rapid with each axis at its own rate (the slower axis decides)."""
    return max(abs(dx) / machine_rapid_x, abs(dz) / machine_rapid_z) * 60.0


def feed_time(length: float, feed_mm_min: float) -> float:
    return 0.0 if feed_mm_min <= 0 or not math.isfinite(feed_mm_min) else length / feed_mm_min * 60.0
