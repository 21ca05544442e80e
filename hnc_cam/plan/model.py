"""What the planner produces and the templates read: blocks, operations, the plan.

The plan is neutral: numbers and kinds only, no controller's letters, codes or template
names. Each dialect's templates (``templates/<dialect>/``) write the words; the post
(:mod:`hnc_cam.post`) chooses the template from the operation's kind.

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


#: segment kinds of a contour block
SEGMENT_KINDS = ("rapid", "line", "cw", "ccw")
#: operation kinds (the post chooses a template per kind, see :func:`Operation.role`)
KINDS = ("face", "rough", "finish", "groove", "thread", "part", "drill")


@dataclass
class Spindle:
    """A spindle speed: ``css`` (constant surface speed, m/min) or ``rpm``."""
    mode: str
    value: float

    @property
    def css(self) -> bool:
        return self.mode == "css"


@dataclass
class Block:
    """One motion segment of a contour: ``kind`` rapid | line | cw | ccw (arcs with ``r`` or
    ``i``/``k``, start to centre, radius values).

    ``x``/``z`` None means the axis does not move (a move along the other axis only, as the
    ns block of a G71/G72 needs). ``label`` names the block for a cycle's reference to it.
    """
    kind: str
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
    #: a spindle change written before the block, where the contour crosses the diameter
    #: below which the surface speed would exceed the spindle limit
    spindle: Spindle | None = None
    #: blocks a dialect without a G96 clamp word writes before this one, after ``spindle``
    #: (:class:`RoughSplit`): the first part of this block up to the split point, and the
    #: X move and Z move, of no length where the tool already is, that start the outer
    #: roughing cycle's contour
    before: list["Block"] = field(default_factory=list)

    def __post_init__(self) -> None:
        if self.kind not in SEGMENT_KINDS:
            raise ValueError(f"block kind must be one of {SEGMENT_KINDS}, got {self.kind!r}")

    @property
    def arc(self) -> bool:
        return self.kind in ("cw", "ccw")


@dataclass
class FaceCut:
    """Facing passes at Z ``levels`` (the operation's ``passes``) from the start X to
    ``x_end`` (radius; past the centre by the nose radius on a bar). ``method``: ``cycle``
    (one facing-cycle block per pass) or ``passes`` (plain moves). ``cap_x``/``cap_rpm``: the
    radius inside which each pass runs at ``cap_rpm`` (the surface speed would need more)."""
    method: str
    x_end: float
    cap_x: float | None = None
    cap_rpm: float | None = None


@dataclass
class RoughCut:
    """Stock removal along the ns..nf contour.

    ``strategy``: ``turn`` (passes parallel to Z), ``face`` (parallel to X) or ``pattern``
    (the contour repeated, shifted). ``side``: ``od`` or ``id``. ``pockets``: the contour
    goes up and down in X (a cycle of type II). ``depth``: cut per pass (radius for turn,
    Z for face); ``retract``: lift after each pass; ``allowance_x`` (radius, a magnitude: an
    ``id`` contour leaves it inward) and ``allowance_z``: finishing stock. Pattern only:
    ``relief_x`` (radius) / ``relief_z``, the total roughing stock of the pattern (as the
    HNC-21T's ΔI/ΔK: pass k of ``count`` lies ``relief·(count − k)/count`` outside the last, so
    the first pass's distance from the last is ``relief·(count − 1)/count``, FANUC's Δi), and
    ``count`` passes."""
    strategy: str
    side: str
    pockets: bool
    depth: float
    retract: float
    allowance_x: float
    allowance_z: float = 0.0
    relief_x: float = 0.0
    relief_z: float = 0.0
    count: int = 1

    @property
    def x_sign(self) -> int:
        """+1 for an outside contour, -1 for a bore (the sign of the X allowance word)."""
        return -1 if self.side == "id" else 1


@dataclass
class RoughSplit:
    """A G71 whose G96 would exceed the spindle limit inside radius ``x`` (+ the allowance),
    cut in two there by a dialect without a G96 clamp word (the HNC-21T): the outer cycle at
    the operation's surface speed over the contour from the block labelled ``ns`` (an X move
    to ``x``, then a Z move to ``z``, then the rest of the contour to the operation's nf),
    then the inner cycle at G97 ``rpm`` from ``start`` over the operation's ns to the block
    labelled ``nf`` (ending at (``x``, ``z``)). Both with the operation's words. ``nf`` empty:
    no inner cycle (only the face's edge is inside; the semi-finishing pass takes it)."""
    x: float
    z: float
    ns: str
    nf: str
    start: Point
    rpm: float


@dataclass
class GrooveFinish:
    z_right: float
    z_left: float
    x_bottom: float


@dataclass
class GrooveCut:
    """Plunges at the Z positions of the operation's ``passes`` (the insert's left corner)
    to ``x_bottom``, out to ``x_clear`` between them, a ``dwell`` (s) at the bottom; a wide
    groove's finishing pass ``finish``."""
    x_bottom: float
    x_clear: float
    dwell: float
    finish: GrooveFinish | None = None


@dataclass
class FaceGrooveCut:
    """An axial groove in the right face: plunges along -Z at the X positions of the
    operation's ``passes`` (radius of the blade's controlled point, the middle of its end) to
    ``z_bottom``, back out along +Z to ``z_clear`` after each, a ``dwell`` (s) at the bottom;
    where the groove is wider than the blade, one finishing pass: down at ``x_inner`` (the
    inner wall), along the floor at ``z_floor`` to ``x_outer`` (the outer wall), back up
    (``finish``)."""
    z_bottom: float
    z_clear: float
    dwell: float
    finish: bool = False
    x_outer: float = 0.0
    x_inner: float = 0.0
    z_floor: float = 0.0
    #: the groove (radii of its walls), for the operator's comment
    r_in: float = 0.0
    r_out: float = 0.0


@dataclass
class ThreadCut:
    """A thread from the start point to ``z_end`` at root ``x_root`` (radius).

    ``method``: ``cycle`` (a multiple-pass threading cycle) or ``passes`` (one single-pass
    cycle block per radius of the operation's ``passes``, the last repeated). ``height``:
    thread depth (radius); ``first_depth``, ``min_depth``, ``finish_allowance`` (radius);
    ``finish_passes``; ``runout_z``/``runout_x``: the run-out at the end (Z length, X rise,
    radius; 0 = none); ``angle`` of the profile; ``starts`` and the spindle ``start_angles``;
    ``taper``: the root's radius change per mm toward +Z (a taper thread; 0 straight): a
    dialect's taper word is ``taper`` times the Z from its cycle's start to its end."""
    method: str
    x_root: float
    z_end: float
    height: float
    lead: float
    angle: float
    starts: int
    start_angles: list[float]
    first_depth: float
    min_depth: float
    finish_allowance: float
    finish_passes: int = 1
    runout_z: float = 0.0
    runout_x: float = 0.0
    taper: float = 0.0


@dataclass
class DrillCut:
    """Drilling on the axis from ``z_clear`` (the R plane in front of the hole) to ``z_end``
    (the point's tip). ``pecks``: the Z each peck feeds to before ``z_end`` (empty: one
    feed); after a peck the drill backs off ``back`` mm (chip breaking), or every ``every``
    pecks rapids out to ``z_clear`` (clearing the chips) and back to ``back`` above the
    peck's depth; ``dwell`` s at the bottom. ``style``: ``blocks`` (plain moves) or ``macro``
    (a WHILE-loop subprogram called with the numbers: ``z_top`` the first peck's start,
    ``peck`` the depth per peck)."""
    z_clear: float
    z_end: float
    pecks: list[float] = field(default_factory=list)
    back: float = 0.5
    every: int = 3
    dwell: float = 0.0
    style: str = "blocks"
    z_top: float = 0.0
    peck: float = 0.0
    diameter: float = 0.0

    @property
    def steps(self) -> list[tuple[float, str]]:
        """Each peck's depth and what follows it: ``back`` (chip breaking) or ``out`` (a full
        retract, then back in)."""
        return [(z, "out" if (i + 1) % self.every == 0 else "back")
                for i, z in enumerate(self.pecks)]


@dataclass
class Operation:
    """One step of the program.

    ``name``: face | rough | bore_rough | rough_zone | finish | bore_finish | profile |
    groove | thread (what the step is for); ``kind``: face | rough | finish | groove | thread
    (how it cuts; with the parameters in ``face``/``rough``/``groove``/``thread``).
    ``start``: the cycle start point (or the approach point of a contour).
    ``blocks``: contour segments (finishing, and a roughing tool's own semi-finishing pass),
    ``ns``/``nf``: the labels of their first/last block (the contour a roughing cycle refers
    to). ``passes``: facing Z levels, groove plunge positions, thread pass radii.
    ``spindle``: ``css`` (``speed`` m/min) or ``rpm``; ``nose_comp``: none (the program
    carries the tip path) | left | right (the control offsets the part contour).
    """
    name: str
    kind: str
    tool: Tool
    reason: str
    start: Point
    spindle: str = "css"
    speed: float = 0.0
    #: the spindle limit for this operation's tool (rpm): the lower of the machine's and the
    #: tool's; a dialect with a clamp word writes it before a constant surface speed
    max_rpm: float = 0.0
    #: the spindle a dialect without a clamp word (the HNC-21T) writes instead of
    #: ``spindle``/``speed``: G97 rpm for a roughing cycle whose G96 would need more than
    #: ``max_rpm`` at the smallest diameter it reaches (None: ``spindle``/``speed``)
    unclamped: Spindle | None = None
    #: the same, kept at the surface speed outside a radius: the cycle in two (G71 only)
    split: RoughSplit | None = None
    feed: float = 0.0  # mm/rev
    blocks: list[Block] = field(default_factory=list)
    ns: str = ""
    nf: str = ""
    nose_comp: str = "none"
    passes: list[Any] = field(default_factory=list)
    face: FaceCut | None = None
    rough: RoughCut | None = None
    groove: GrooveCut | None = None
    face_groove: FaceGrooveCut | None = None
    thread: ThreadCut | None = None
    drill: DrillCut | None = None
    new_tool: bool = True
    #: False when the previous operation ran the same tool at the same speed: the spindle
    #: is not set again
    set_spindle: bool = True
    #: as ``set_spindle`` for a dialect that writes ``unclamped``: the previous operation
    #: ran the same tool but one of the two at the unclamped G97 speed
    set_unclamped: bool = True
    #: the operation ends at another speed than it started (a spindle limit inside it)
    spindle_changed: bool = False
    contour: list[Segment] = field(default_factory=list)  # program geometry of the blocks
    retract: list[Point] = field(default_factory=list)  # after the operation, rapid in order
    notes: list[str] = field(default_factory=list)  # what the operation leaves undone, why
    #: rapid moves to the start point, (x, z) with None for an axis that does not move;
    #: empty: one move to ``start``
    approach: list[tuple[float | None, float | None]] = field(default_factory=list)
    #: the axis moved first to the tool-change point before this operation's tool change
    leave_first: str = "z"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"operation kind must be one of {KINDS}, got {self.kind!r}")

    @property
    def css(self) -> bool:
        return self.spindle == "css"

    @property
    def approach_moves(self) -> list[tuple[float | None, float | None]]:
        return self.approach or [self.start]

    @property
    def role(self) -> str:
        """What the post chooses the template by: face | rough_turn | rough_turn_pockets |
        rough_face | rough_pattern | rough_bore | finish | groove | groove_id (inside) |
        groove_face (axial, in the right face) | thread | thread_passes | part | drill."""
        if self.kind == "rough":
            r = self.rough
            if r.side == "id":
                return "rough_bore"
            if r.strategy == "turn":
                return "rough_turn_pockets" if r.pockets else "rough_turn"
            return f"rough_{r.strategy}"
        if self.kind == "thread" and self.thread.method == "passes":
            return "thread_passes"
        if self.kind == "groove" and self.tool.kind == "groove_id":
            return "groove_id"
        if self.kind == "groove" and self.face_groove is not None:
            return "groove_face"
        return self.kind

    # -- labels: the HNC-21T code that does the work, kept as the operation's name in
    # summaries, family tables and reports
    @property
    def cycle(self) -> str:
        if self.kind == "face":
            return "G81" if self.face.method == "cycle" else "G01"
        if self.kind == "rough":
            r = self.rough
            if r.strategy == "face":
                return "G72"
            if r.strategy == "pattern":
                return "G73"
            return "G71E" if r.pockets else "G71"
        if self.kind == "thread":
            return "G76" if self.thread.method == "cycle" else "G82"
        if self.kind in ("groove", "part", "drill"):
            return "G01"
        return "contour"

    @property
    def speed_mode(self) -> str:
        return "G96" if self.css else "G97"

    @property
    def comp(self) -> int:
        return {"none": 40, "left": 41, "right": 42}[self.nose_comp]

    @property
    def note(self) -> str:
        """The operator's comment for the operation, with the HNC-21T cycle names."""
        cyc = {"G71E": "G71 II"}.get(self.cycle, self.cycle)
        return self.describe(cyc)

    def describe(self, cycle: str) -> str:
        """The operator's comment for the operation (under 60 characters) naming the cycle
        ``cycle`` as the dialect writes it; the planner's full reasoning is :attr:`reason`
        (``generate --explain``)."""
        t = f"T{self.tool.number:02d}"
        f = f"F{_n(self.feed)}"
        if self.name == "face" and self.kind == "finish":  # the finisher's pass to the centre
            return f"{t} FINISH FACE {f}"
        if self.name == "face":
            return f"{t} FACE {cycle} {len(self.passes)}X F{_n(self.feed)}"
        if self.name in ("rough", "bore_rough"):
            r = self.rough
            where = "BORE" if self.name == "bore_rough" else ("FACE" if r.strategy == "face" else "OD")
            extra = f" D{_n(r.depth)}" if r.strategy != "pattern" else ""
            return f"{t} ROUGH {where} {cycle}{extra} {f}"
        if self.name == "rough_zone":
            z = [b.z for b in self.blocks if b.z is not None]
            span = f" Z{_n(max(z))}..{_n(min(z))}" if z else ""
            return f"{t} REST ROUGH{span} {cycle} D{_n(self.rough.depth)} {f}"
        if self.name in ("finish", "bore_finish"):
            return f"{t} FINISH {'BORE' if self.name == 'bore_finish' else 'OD'} {f}"
        if self.name == "profile":
            return f"{t} LEFT END CHAMFER {f}"
        if self.name == "groove":
            return (f"{t} GROOVE Z{_n(self.start[1])} X{_n(2 * self.groove.x_bottom)} "
                    f"{len(self.passes)}X {f}")
        if self.name == "groove_face":
            g = self.face_groove
            return (f"{t} FACE GROOVE X{_n(2 * g.r_in)}-{_n(2 * g.r_out)} Z{_n(g.z_floor)} "
                    f"{len(self.passes)}X S{_n(self.speed)} {f}")
        if self.name == "thread":
            return f"{t} THREAD LEAD {_n(self.thread.lead)} S{_n(self.speed)}"
        if self.kind == "drill":
            d = self.drill
            what = "SPOT" if self.tool.kind == "center_drill" else "DRILL"
            pk = f" PECK {_n(d.peck)}" if d.pecks else ""
            return f"{t} {what} D{_n(d.diameter)} Z{_n(d.z_end)}{pk} S{_n(self.speed)} {f}"
        if self.name == "partoff":
            return f"{t} PART OFF Z{_n(self.start[1])} S{_n(self.speed)} {f}"
        return f"{t} {self.name.upper()} {cycle}"


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
    #: what the user should know but that does not stop the program (stick-out, ...): said
    #: on stderr as ``warning:`` lines, not written into the program
    warnings: list[str] = field(default_factory=list)

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

    def contour_owner(self, op: Operation) -> Operation:
        """The operation whose blocks are ``op``'s ns..nf contour: ``op`` itself when it has
        blocks, else the one with blocks labelled ``op.ns`` (the finishing contour a roughing
        cycle refers to)."""
        if op.blocks or not op.ns:
            return op
        for o in self.operations:
            if o.blocks and o.ns == op.ns:
                return o
        raise ValueError(f"no operation has the contour labelled {op.ns!r}")

    def label_key(self, op: Operation, labels: Any = None) -> str:
        """The key of ``op`` in a dialect's cycle names (``labels.j2``): its role, with
        ``_cycle``/``_passes`` for facing, ``_pockets`` for a bore with undercuts,
        ``_roughed`` for a finishing contour a roughing cycle carries and ``_peck`` for a
        pecked hole. Given the dialect's
        ``labels``, a key they name more precisely is preferred: ``finish_roughed_comp`` for
        such a finish the control compensates, carried by a stock-removal (not a
        pattern-repeat) roughing (the SINUMERIK runs it as LCYC95 finishing)."""
        if op.kind == "face":
            return f"face_{op.face.method}"
        if op.kind == "rough" and op.rough.side == "id" and op.rough.pockets:
            return "rough_bore_pockets"
        if op.kind == "finish" and self.roughed(op):
            if (labels is not None and op.nose_comp != "none" and "finish_roughed_comp" in labels
                    and not any(o.kind == "rough" and o.ns == op.ns and o.rough is not None
                                and o.rough.strategy == "pattern" for o in self.operations)):
                return "finish_roughed_comp"
            return "finish_roughed"
        if op.kind == "drill" and op.drill is not None and op.drill.pecks:
            return "drill_peck"
        return op.role

    def roughed(self, op: Operation) -> bool:
        """True when a roughing operation before ``op`` refers to ``op``'s contour (a dialect
        whose roughing cycle needs its contour right after it writes it there, and finishes
        with a cycle that runs it again)."""
        return bool(op.ns) and any(o is not op and o.kind == "rough" and not o.blocks
                                   and o.ns == op.ns for o in self.operations)

    def explain(self, labels: dict[str, str] | None = None) -> str:
        """The planner's reasoning, one paragraph per operation (``generate --explain``);
        ``labels``: the dialect's cycle names (:func:`hnc_cam.post.cycle_labels`)."""
        out = [f"{self.name}: stock {self.stock.spec}, compensation {self.comp}"]
        out += [f"  note: {n}" for n in self.notes]
        for i, op in enumerate(self.operations, 1):
            label = (labels or {}).get(self.label_key(op, labels))
            out.append(f"  {i}. {op.describe(label) if label else op.note}: {op.reason}")
        return "\n".join(out)
