"""What the planner produces and the templates read: blocks, operations, the plan.

Positions are (x radius, z) in work coordinates with program zero on the part's right face;
the templates write X as a diameter (filter ``dia``).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..geometry import Point, Segment
from ..tooling import Machine, Stock, Tool


def _n(v: float) -> str:
    return f"{float(v):.3f}".rstrip("0").rstrip(".")


@dataclass
class Block:
    """One motion block of a contour: G00/G01 with X and/or Z, or G02/G03 with R or I/K.

    ``x``/``z`` None means the word is not written (a move along the other axis only, as the
    ns block of a G71/G72 needs). ``label`` names the block for a P/Q reference.
    """
    g: int
    x: float | None = None
    z: float | None = None
    r: float | None = None
    i: float | None = None
    k: float | None = None
    label: str = ""
    feed: float | None = None
    comment: str = ""
    #: the X range (radius) an arc sweeps through, where it is not at its end points
    span: tuple[float, float] | None = None
    #: a spindle line written before the block (``G97 S..`` / ``G96 S..``), where the
    #: contour crosses the diameter below which G96 would exceed the spindle limit
    spindle: str = ""

    @property
    def gcode(self) -> str:
        return f"G{self.g:02d}"


@dataclass
class Operation:
    """One step of the program, rendered by ``template``.

    ``name``: face | rough | bore_rough | finish | bore_finish | groove | thread.
    ``cycle``: the code that does the work (G81, G01, G71, G71E, G72, G73, G76, G82, contour).
    ``start``: the cycle start point A (or the approach point of a contour).
    ``words``: the cycle's parameter words (numbers, internal units; templates format them).
    ``blocks``: the contour blocks (finish operations), ``ns``/``nf``: their first/last labels.
    ``passes``: facing Z levels, groove plunge positions, G82 pass diameters ...
    """
    name: str
    cycle: str
    template: str
    tool: Tool
    reason: str
    start: Point
    speed_mode: str = "G96"  # G96 (m/min) or G97 (rpm)
    speed: float = 0.0
    feed: float = 0.0  # mm/rev (G95)
    words: dict[str, Any] = field(default_factory=dict)
    blocks: list[Block] = field(default_factory=list)
    ns: str = ""
    nf: str = ""
    comp: int = 40  # 40 (cam / none), 41, 42 (control)
    passes: list[Any] = field(default_factory=list)
    new_tool: bool = True
    #: False when the previous operation ran the same tool at the same speed: the spindle
    #: line (G96/G97 S.. M03) is not repeated
    set_spindle: bool = True
    contour: list[Segment] = field(default_factory=list)  # program geometry of the blocks
    retract: list[Point] = field(default_factory=list)  # after the operation, G00 in order
    notes: list[str] = field(default_factory=list)  # what the operation leaves undone, why
    #: G00 moves to the start point, (x, z) with None for an axis that does not move; empty:
    #: one move to ``start``
    approach: list[tuple[float | None, float | None]] = field(default_factory=list)
    #: the axis moved first to the tool-change point before this operation's tool change
    leave_first: str = "z"

    @property
    def approach_moves(self) -> list[tuple[float | None, float | None]]:
        return self.approach or [self.start]

    @property
    def note(self) -> str:
        """The operator's comment for the operation (under 60 characters); the planner's
        full reasoning is :attr:`reason` (``generate --explain``)."""
        t = f"T{self.tool.number:02d}"
        f = f"F{_n(self.feed)}"
        w = self.words
        if self.name == "face":
            return f"{t} FACE {self.cycle} {len(self.passes)}X F{_n(self.feed)}"
        if self.name in ("rough", "bore_rough"):
            where = "BORE" if self.name == "bore_rough" else ("FACE" if self.cycle == "G72" else "OD")
            cyc = {"G71E": "G71 II", "G73": "G73"}.get(self.cycle, self.cycle)
            d = w.get("W") if self.cycle == "G72" else w.get("U")
            extra = f" D{_n(d)}" if d is not None and self.cycle != "G73" else ""
            return f"{t} ROUGH {where} {cyc}{extra} {f}"
        if self.name == "rough_zone":
            z = [b.z for b in self.blocks if b.z is not None]
            span = f" Z{_n(max(z))}..{_n(min(z))}" if z else ""
            return f"{t} REST ROUGH{span} G71 II D{_n(w.get('U', 0))} {f}"
        if self.name in ("finish", "bore_finish"):
            return f"{t} FINISH {'BORE' if self.name == 'bore_finish' else 'OD'} {f}"
        if self.name == "profile":
            return f"{t} LEFT END CHAMFER {f}"
        if self.name == "groove":
            return (f"{t} GROOVE Z{_n(self.start[1])} X{_n(2 * w.get('x_bottom', 0))} "
                    f"{len(self.passes)}X {f}")
        if self.name == "thread":
            return f"{t} THREAD LEAD {_n(w.get('F', self.feed))} S{_n(self.speed)}"
        return f"{t} {self.name.upper()} {self.cycle}"

    @property
    def tool_word(self) -> str:
        return f"T{self.tool.number:02d}{self.tool.register:02d}"


@dataclass
class Plan:
    name: str
    params: dict[str, Any]
    stock: Stock
    machine: Machine
    comp: str  # cam | control
    program_number: int
    operations: list[Operation] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    version: str = ""
    tool_change: Point = (100.0, 80.0)
    profile: Any = None  # the TurnedProfile planned (program zero on the right face)
    shift: float = 0.0  # Z shift applied to the model to put its right face at Z0
    leave_first: str = "z"  # the axis moved first to the tool-change point at the end

    @property
    def tools(self) -> list[Tool]:
        seen: dict[int, Tool] = {}
        for op in self.operations:
            seen.setdefault(op.tool.number, op.tool)
        return list(seen.values())

    @property
    def max_rpm(self) -> float:
        return self.machine.max_rpm

    def summary(self) -> str:
        return ", ".join(f"{op.name} {op.cycle}" for op in self.operations)

    def explain(self) -> str:
        """The planner's reasoning, one paragraph per operation (``generate --explain``)."""
        out = [f"{self.name}: stock {self.stock.spec}, compensation {self.comp}"]
        out += [f"  note: {n}" for n in self.notes]
        for i, op in enumerate(self.operations, 1):
            out.append(f"  {i}. {op.note}: {op.reason}")
        return "\n".join(out)
