"""SINUMERIK 802S/802C (turning) codes and their execution (``docs/SIEMENS.md``).

The code table gives each G code its group in the executor's terms (``motion``: the
interpolation group G0 G1 G2 G3 G5 G33; ``nonmodal``: the codes that act in their own block,
G4 G74 G75 G158 G25 G26 G53; ``comp``, ``wcs`` and the modal settings). :class:`SiemensInterp`
is the interpreter with the 802's handlers: arcs by I K / CR= / AR= and G5 through an
intermediate point, CHF= and RND= corners, G33 K/I with SF=, G4 F/S, G74/G75, G158, G25/G26,
G96 S LIMS=, G70/G71 inch/metric, G22/G23 radius/diameter, T t D d, subprogram calls by name
with P repeats, RET/M17, the LCYC cycles, GOTOF/GOTOB with labels and R parameters.
"""
from __future__ import annotations

import math
import os
from typing import Optional

from ...errors import NCError
from ...geometry import Arc, Line
from ...geometry.corner import CornerError, CornerFitError, element_corner
from ...geometry.primitives import point_at_angle
from ...nc import parser as P
from ...nc.interp import _MAX_LEVEL, Asg, Blk, CycleCtx, Interp
from ...tooling import EDGE_KEY
from .. import CodeSpec
from .memory import SiemensMemory
from .syntax import TEXT, word_col

# executor group of each G code: 1 motion, 0 one-shot (own block), 9 nose compensation, 11 work
# offset, 8 unit, 3 absolute/incremental, 14 feed type (G94 G95 G96 G97), 16 plane,
# 2 radius/diameter, 12 exact stop (block-wise)
G_GROUP: dict[int, int] = {
    0: 1, 1: 1, 2: 1, 3: 1, 5: 1, 33: 1,
    4: 0, 25: 0, 26: 0, 53: 0, 74: 0, 75: 0, 158: 0,
    40: 9, 41: 9, 42: 9,
    54: 11, 55: 11, 56: 11, 57: 11, 500: 11,
    70: 8, 71: 8,
    90: 3, 91: 3,
    94: 14, 95: 14, 96: 14, 97: 14,
    17: 16, 18: 16,
    22: 2, 23: 2,
    9: 12,
}
_PHASE = {1: "motion", 0: "nonmodal", 9: "comp", 11: "wcs"}
SETTERS = {8: {70: ("unit", 25.4), 71: ("unit", 1.0)},
           3: {90: ("absolute", True), 91: ("absolute", False)},
           16: {17: ("plane", 17), 18: ("plane", 18)},
           2: {22: ("diam", False), 23: ("diam", True)}}
#: the extra words each code gives a meaning
ARC = frozenset({"I", "K", "CR", "AR", "CHF", "RND"})
LETTERS = {1: frozenset({"CHF", "RND"}), 2: ARC, 3: ARC, 5: frozenset({"IX", "KZ", "CHF", "RND"}),
           33: frozenset({"I", "K", "SF"}), 4: frozenset(), 25: frozenset(), 26: frozenset(),
           74: frozenset(), 75: frozenset(), 158: frozenset(), 53: None}
CODES = {("G", g): CodeSpec(g, grp, _PHASE.get(grp, "modal"), SETTERS.get(grp, {}).get(g),
                            LETTERS.get(g, frozenset()))
         for g, grp in G_GROUP.items()}
#: the CNC's own M codes: stop, optional stop, end of program, subprogram end
M_CNC = frozenset({0, 1, 2, 17, 30})
CODES.update({("M", m): CodeSpec(m, 0, "flow") for m in M_CNC})
MESSAGES = {"unknown_g": "unknown G code G{g} (SINUMERIK 802S/802C turning)",
            "two_in_group": "two G codes of one group in one block (G{g})",
            "range_ref": "SINUMERIK 802S/802C"}
#: motion-group codes that are not G0-G3 (the executor hands them to SiemensInterp._cycle)
CYCLE_MOTION = frozenset({5, 33})
POWER_ON = {1: 0, 9: 40, 11: 500, 8: 71, 3: 90, 14: 94, 16: 18, 2: 23}
#: word ranges of the document's address table (min, max, whole number)
RANGES: dict[str, tuple[float, float, bool]] = {
    "G": (0, 999, True), "M": (0, 99, True), "N": (0, 4294967295, True), "T": (0, 32000, True),
    "D": (0, 9, True), "F": (0, 999999.999, False), "S": (0, 99999.999, False),
    "P": (1, 9999, True), "L": (0, 9999999, True),
    "I": (-99999.999, 99999.999, False), "K": (-99999.999, 99999.999, False),
    "X": (-99999.999, 99999.999, False), "Z": (-99999.999, 99999.999, False),
    "CR": (-99999.999, 99999.999, False), "AR": (0.00001, 359.99999, False),
    "CHF": (0, 999999.999, False), "RND": (0, 99999.999, False),
    "IX": (-99999.999, 99999.999, False), "KZ": (-99999.999, 99999.999, False),
    "SF": (0, 359.999, False), "LIMS": (0, 99999.999, False), "SPOS": (0, 359.9999, False),
}
UNKNOWN_LETTERS = {"U": "the 802 writes incremental moves with G91 (U/W are not its words)",
                   "W": "the 802 writes incremental moves with G91 (U/W are not its words)",
                   "Y": "this lathe has no Y axis", "O": "the 802 names its programs %_N_NAME_MPF",
                   "H": "H is not a word of the 802", "Q": "Q is not a word of the 802",
                   "E": "E is not a word of the 802", "J": "J is not a word of the lathe (ZX plane)"}
#: named cycles: name -> the number CycleCtx.code carries
CYCLE_NAMES = ("LCYC82", "LCYC83", "LCYC840", "LCYC85", "LCYC93", "LCYC94", "LCYC95", "LCYC97")
#: M40 automatic gear stage, M41-M45 gear stages 1-5 (the document): accepted, no effect
GEARS = frozenset(range(40, 46))
#: words that are always allowed besides the motion's (edge, G96 speed cap, spindle position)
_ALWAYS = frozenset({"D", "LIMS", "SPOS"})
#: the words a block of each motion may carry besides X Z F S T
_MOTION_OK = {g: LETTERS[g] | _ALWAYS for g in (1, 2, 3, 5, 33)}
#: codes that stand in a block of their own (with N, their words and modal codes)
_OWN = frozenset({4, 25, 26, 74, 75, 158})


class SiemensInterp(SiemensMemory, Interp):
    """The interpreter with the 802's codes, calls and memory (see the module doc)."""

    round_words = frozenset("GMTDPL")
    _word_col = staticmethod(word_col)

    def __init__(self, src, machine=None, **kw):
        super().__init__(src, machine, **kw)
        self._init_memory()
        self._calls = getattr(self.src, "calls", {})  # statement -> (name, col, repeats)
        self._reader = self._sread
        self.plane = 18
        self.edge = 1
        self.lims: Optional[float] = None  # G96 LIMS=
        self.s_min = 0.0  # G25
        self.s_max: Optional[float] = None  # G26
        #: G158 X Z: the programmable offset (radius, z) added to absolute targets; the toolpath
        #: stays in the settable work system (G54-G57), where the part is
        self.g158: Optional[tuple[float, float]] = None
        #: the arcs an arc block computes while a corner next to it waits (see _corner_arc)
        self._capture: Optional[list] = None
        #: (x, z, angle, its move): where a G33 chain may go on (when that move is the last one)
        self.thread_start: Optional[tuple] = None
        self.ext: dict[str, int] = {}  # subprograms read from files beside the program

    # -- alarms at a word's column ---------------------------------------------------------
    def alarm(self, message: str, line: int, col: int = 0) -> NCError:
        src = self.src
        if src.parts:  # a line of a subprogram file read beside the program
            f, n = src.locate(line)
            return NCError(message, n, col, src.block_text(line), f)
        return NCError(message, line, col, src.block_text(line), src.file)

    def balarm(self, b: Blk, message: str, letter: Optional[str] = None,
               value: Optional[float] = None) -> NCError:
        col = 0
        if letter:
            col = word_col(b.text, letter, value)
            for named in {"C": ("CHF",), "R": ("CR", "RND")}.get(letter, ()):
                if col == 0:
                    col = word_col(b.text, named)
        if col == 0:
            col = len(b.text) - len(b.text.lstrip()) + 1
        return self.alarm(message, b.line, col)

    # -- compile ---------------------------------------------------------------------------
    def _compile(self, i: int):
        if i not in self._calls:
            try:
                b = Interp._compile(self, i)
            except NCError as e:
                if self.src.parts:  # a line of a subprogram file: name that file and its line
                    e.file, e.line = self.src.locate(e.line)
                raise
            if b.__class__ is Blk and not b.plain:
                if "AR" in b.letters or "CR" in b.letters:
                    b.axes = True  # G2 I.. K.. AR=..: the arc moves without X/Z words
                if "L" in b.letters:
                    raise self.balarm(b, "a subprogram call stands alone in its block, as L10 or "
                                         "L10 P3 (with N and nothing else)", "L")
            return b
        b = Blk(i, self.src.lineno[i], self.src.text[i])
        b.plain = False
        b.letters = frozenset({"L"})
        return b

    def _assign(self, c: Asg) -> None:
        for target, e, col in c.items:
            if isinstance(target, tuple) and target[0] == TEXT:
                self.texts[target[1]] = e
                continue
            self._write(target, self._eval(e, c.line), c.line, col)

    # -- blocks ------------------------------------------------------------------------------
    def _block(self, b: Blk):
        if b.plain:
            return Interp._block(self, b)
        if b.stmt in self._calls:
            self.blocks += 1
            if self.corner is not None:
                self._corner_not_followed()
            return 1
        gs = b.gs
        letters = b.letters
        if gs and not _OWN.isdisjoint(gs):
            return self._own_block(b)
        if "T" in letters or "D" in letters or "LIMS" in letters or "SPOS" in letters:
            w = self._words(b)
            if "T" in w or "D" in w:
                self._select(b, w.get("T"), w.get("D"))
            if "LIMS" in w:
                if w["LIMS"] <= 0:
                    raise self.balarm(b, "value out of range: LIMS= must be positive", "LIMS")
                self.lims = w["LIMS"]
            if "SPOS" in w:
                self.sdir = 5
                self.warn(b.line, "SPOS=: the spindle stops at its position (position control)",
                          ("SPOS", b.line))
        return Interp._block(self, b)

    def _own_block(self, b: Blk):
        """G4, G25/G26, G74/G75, G158: their own block (N, modal codes, their words)."""
        self.blocks += 1
        w = self._words(b) if b.dyn is not None else b.words
        g00, g06, comp = self._gcodes(b, b.gs)
        if b.ms:
            raise self.balarm(b, f"G{g00} stands in a block of its own (no M word)", "M")
        if comp:
            raise self.balarm(b, f"G{g00} stands in a block of its own (no G{comp})", "G")
        if self.corner is not None:
            self._corner_not_followed()
        if g00 == 4:
            self._dwell(b, w)
        elif g00 in (25, 26):
            if set(w) - {"S"} or "S" not in w:
                raise self.balarm(b, f"G{g00} takes S, the spindle speed {'lower' if g00 == 25 else 'upper'} "
                                     f"limit (rev/min), alone", "G")
            if g00 == 25:
                self.s_min = w["S"]
            else:
                self.s_max = w["S"]
        elif g00 in (74, 75):
            self._home(b, g00, w)
        elif g00 == 158:
            extra = set(w) - {"X", "Z"}
            if extra:
                L = sorted(extra)[0]
                raise self.balarm(b, f"word {L} has no meaning in a G158 block (G158 X.. Z..)", L)
            u = self.unit
            # always a radius (the document); a later G158 replaces it, G158 alone cancels it
            gx, gz = w.get("X", 0.0) * u, w.get("Z", 0.0) * u
            self.g158 = (gx, gz) if (gx or gz) else None
        return None

    def _home(self, b: Blk, g: int, w: dict) -> None:
        """G74 reference point / G75 fixed point: the axes named move there in rapid (their
        values are not read)."""
        extra = set(w) - {"X", "Z"}
        if extra:
            L = sorted(extra)[0]
            raise self.balarm(b, f"word {L} has no meaning in a G{g} block (G{g} X0 Z0)", L)
        if not w:
            raise self.balarm(b, f"missing required word: G{g} names the axes, as G{g} X0 Z0", "G")
        self._flush_comp(f"G{g}", b.line)
        if g == 74:
            mx, mz = self.m.reference
        else:
            rx, rz = self.m.reference
            mx = float(self.params.get("fixed_point_x", rx))
            mz = float(self.params.get("fixed_point_z", rz))
        x0, z0 = self.x, self.z
        x1 = mx - self.ox if "X" in w else x0
        z1 = mz - self.oz if "Z" in w else z0
        save, self.op = self.op, f"G{g}"
        self.x, self.z = x1, z1
        self._emit_line(True, x0, z0, x1, z1, b.line)
        self.op = save

    def _gcodes(self, b: Blk, gs: tuple):
        r = Interp._gcodes(self, b, gs)
        for g in gs:
            if 94 <= g <= 97:
                if self.css and g != 96:
                    # G96 off: the spindle keeps the speed it last turned at (the document)
                    sdir, self.sdir = self.sdir, 3
                    self.s_rpm = self._rpm(self.x)
                    self.sdir = sdir
                if g == 94:
                    self.per_rev, self.css = False, False
                elif g == 95:
                    self.per_rev, self.css = True, False
                elif g == 96:
                    self.per_rev, self.css = True, True
                else:
                    self.per_rev, self.css = True, False
        return r

    def _block_rest(self, b: Blk, w: dict, ms: tuple, g00: int, g06: int, comp_cmd: int,
                    is_call: bool, flow: int):
        r = Interp._block_rest(self, b, w, ms, g00, g06, comp_cmd, is_call, flow)
        if flow == 17:
            if self.dry is not None:
                raise self.balarm(b, "RET/M17 inside a contour", "M")
            if not self.frames:
                raise self.balarm(b, "RET/M17 ends a subprogram; the main program ends with M2/M30", "M")
            return 2
        if r == 3 and self.frames:
            return 2  # M2/M30 in a subprogram returns to the caller
        return r

    def _check_letters(self, b: Blk, g00: int, g06: int) -> None:
        if not g00 and b.extra <= _MOTION_OK.get(self.motion, _ALWAYS):
            return  # the common case: the motion's own words
        ok = set(_ALWAYS)
        spec = self.g_spec
        c = spec.get(g00) if g00 else None
        m = self.motion
        if c is not None and c.letters is not None:
            ok |= c.letters
        elif b.axes or b.letters & {"CR", "AR", "I", "K"}:
            c = spec.get(m)
            if c is not None and c.letters:
                ok |= c.letters
        for L in sorted(b.extra):
            if L not in ok:
                what = (f"G{g00}" if g00 else f"G{m}" if (b.axes or m in (2, 3)) else "this")
                raise self.balarm(b, f"word {L} has no meaning in {what} block", L)

    def _comp_command(self, b: Blk, g: int) -> None:
        if g != 40 and self.plane != 18:
            raise self.balarm(b, f"G{g} needs the ZX plane: G18 must be active (G{self.plane} is)", "G", g)
        Interp._comp_command(self, b, g)

    def _unknown_m(self, b: Blk, mc: int) -> None:
        if mc in GEARS:
            return  # gear stages: no effect on the path
        raise self.balarm(b, f"unknown M code M{mc} (SINUMERIK 802S/802C): the machine's PLC does not "
                             f"list it; declare it in the machine file's [m_codes] table with its "
                             f"meaning, e.g. M{mc:02d} = \"other\"", "M", mc)

    # -- tools -------------------------------------------------------------------------------
    def _tword(self, b: Blk, t: float) -> None:
        return None  # T and D are taken by _select before the block runs

    def _select(self, b: Blk, t: Optional[float], d: Optional[float]) -> None:
        """T t selects the tool (edge D1 unless the block writes D), D d its edge; D0 = no
        offset. Edge d of tool t is the machine's register t (edge 1) or ``[[register]] number
        = t, edge = d``."""
        tool = self.tool if t is None else int(t)
        edge = int(d) if d is not None else (1 if t is not None else self.edge)
        reg = 0
        if tool and edge:
            reg = self._edge_register(b, tool, edge)
        if (tool, reg) == (self.tool, self.reg) and edge == self.edge:
            return
        if self.comp != 40:
            self._flush_comp()
        self.tool, self.reg, self.edge = tool, reg, edge
        self.tdx = self.tdz = 0.0

    def _edge_register(self, b: Blk, tool: int, edge: int) -> int:
        """Edge ``edge`` of ``tool``: D1 is the register numbered as the tool; D d the machine
        file's ``[[register]] number = tool, edge = d``, else the register numbered d (the
        tool library's register of a tool whose register is not its number: the post writes
        its D so)."""
        if edge == 1:
            return tool
        reg = EDGE_KEY * edge + tool
        if reg in self.m.registers:
            return reg
        if edge != tool and edge in self.m.registers:
            return edge
        raise self.balarm(b, f"T{tool} D{edge}: the machine file has no register for edge {edge} "
                             f"of tool {tool} ([[register]] number = {tool}, edge = {edge}) nor a "
                             f"register {edge}", "D")

    def tool_nose(self) -> tuple[float, int]:
        reg = self._register(self.reg) if self.reg else None
        if reg is None:
            return (0.0, 0)
        return (float(reg.radius), int(reg.tip))

    # -- spindle -------------------------------------------------------------------------------
    def _rpm(self, x: float) -> float:
        if self.sdir == 5:
            return 0.0
        top = self.m.max_rpm
        if self.s_max is not None and self.s_max < top:
            top = self.s_max
        if not self.css:
            n = self.s_rpm
        else:
            cap = top
            if self.lims is not None and self.lims < cap:
                cap = self.lims
            r = abs(x + self.tdx)
            n = cap if r < 1e-9 else min(cap, 1000.0 * self.vc / (2.0 * math.pi * r))
        if n > top:
            n = top
        if n < self.s_min:
            n = self.s_min
        return n

    def _dwell(self, b: Blk, w: dict) -> None:
        """G4 F.. seconds, G4 S.. spindle revolutions; F and S programmed before stay."""
        if "F" in w and "S" in w:
            raise self.balarm(b, "G4 takes F (seconds) or S (revolutions), not both", "S")
        extra = set(w) - {"F", "S"}
        if extra:
            L = sorted(extra)[0]
            raise self.balarm(b, f"word {L} has no meaning in a G4 block (G4 F.. or G4 S..)", L)
        if "F" in w:
            seconds = w["F"]
        elif "S" in w:
            rpm = self._rpm(self.x)
            if rpm <= 0:
                raise self.balarm(b, f"G4 S{w['S']:g}: the spindle is stopped, so a dwell in "
                                     f"revolutions never ends", "S")
            seconds = w["S"] / rpm * 60.0
        else:
            raise self.balarm(b, "missing required word: G4 needs F (seconds) or S (revolutions)", "G")
        Interp._dwell(self, b, {"P": seconds})

    # -- motion --------------------------------------------------------------------------------
    def _target(self, b: Blk, w: dict, g53: bool = False) -> tuple[float, float]:
        """X/Z targets: in G90 X is a diameter in G23 (a radius in G22); in G91 an X
        increment is a radius value (the document's G0 and G1 examples: from X69, G91 X-10.5
        reaches X48)."""
        if self.absolute or g53:
            return Interp._target(self, b, w, g53)
        u = self.unit
        X = w.get("X")
        Z = w.get("Z")
        return (self.x if X is None else self.x + X * u), (self.z if Z is None else self.z + Z * u)

    def _shift(self, w: dict, g53: bool) -> dict:
        """The words of an absolute move with the G158 offset added (X, Z, and IX, KZ of G5)."""
        if self.g158 is None or g53 or not self.absolute:
            return w
        gx, gz = self.g158
        u = self.unit
        sx = 0.5 * u if self.diam else u
        w = dict(w)
        for a, off, sc in (("X", gx, sx), ("IX", gx, sx), ("Z", gz, u), ("KZ", gz, u)):
            if a in w:
                w[a] = w[a] + off / sc
        return w

    def _g00(self, b: Blk, w: dict, g53: bool = False):
        if self.g158 is not None:
            w = self._shift(w, g53)
        return Interp._g00(self, b, w, g53)

    def _g01(self, b: Blk, w: dict, g53: bool = False):
        if self.g158 is not None:
            w = self._shift(w, g53)
        if b.extra and ("CHF" in w or "RND" in w):
            w = dict(w)
            if "CHF" in w and "RND" in w:
                raise self.balarm(b, "CHF= (chamfer) and RND= (round) in one block", "RND")
            if "CHF" in w:
                w["C"] = w.pop("CHF")  # the corner's size: the chamfer's own length
            else:
                w["R"] = w.pop("RND")
        return Interp._g01(self, b, w, g53)

    def _corner_not_followed(self) -> None:
        c = self.corner
        word = "CHF" if c[4] == "C" else "RND"
        raise self.alarm(f"{word}={c[5]:g} must be followed by a contour element (a G1 line or "
                         f"a G2/G3/G5 arc) to cut the corner against", c[6], self._corner_col(c))

    def _corner_col(self, c: tuple) -> int:
        return word_col(self.src.text[self._stmt_of_line(c[6])], "CHF" if c[4] == "C" else "RND")

    def _emit_arc(self, x0, z0, x1, z1, cx, cz, cw, line, F: Optional[float] = None) -> None:
        cap = self._capture
        if cap is not None:  # an arc block with a corner: held until the corner is cut
            cap.append((x0, z0, x1, z1, cx, cz, cw))
            return
        Interp._emit_arc(self, x0, z0, x1, z1, cx, cz, cw, line, F)

    def _corner_arc(self, b: Blk, w: dict, run) -> None:
        """An arc block (G2/G3 in any form, G5) next to a corner: the corner pending from the
        element before is cut against this arc, and the arc's own CHF=/RND= is held until the
        next element. ``run(w)`` computes the arc (its emission is captured)."""
        word = "CHF" if "CHF" in w else "RND" if "RND" in w else None
        if "CHF" in w and "RND" in w:
            raise self.balarm(b, "CHF= (chamfer) and RND= (round) in one block", "RND")
        size = 0.0
        if word is not None:
            w = dict(w)
            size = w.pop(word) * self.unit
        pending = self.corner
        self.corner = None
        cap = self._capture = []
        try:
            run(w)
        finally:
            self._capture = None
        if not cap:
            return
        if len(cap) != 1:
            if pending is not None:
                raise self.alarm(f"{'CHF' if pending[4] == 'C' else 'RND'}={pending[5]:g} before a "
                                 f"full circle: a corner needs an end of the circle", pending[6],
                                 self._corner_col(pending))
            raise self.balarm(b, f"{word}= on a full circle: a corner needs an end of the circle", word)
        x0, z0, x1, z1, cx, cz, cw = cap[0]
        op = self.op
        if pending is not None:
            x0, z0 = self._cut(pending, Arc((x0, z0), (x1, z1), (cx, cz), cw), b.line)
            self.op = op
        if size > 0.0:
            if math.hypot(x1 - x0, z1 - z0) < 1e-9:
                raise self.balarm(b, f"{word}={size:g}: nothing is left of this arc after the "
                                     f"corner before it", word)
            self.corner = (x0, z0, x1, z1, "C" if word == "CHF" else "R", size, b.line, self.F,
                           (cx, cz, cw, op))
            return
        if math.hypot(x1 - x0, z1 - z0) >= 1e-9:
            Interp._emit_arc(self, x0, z0, x1, z1, cx, cz, cw, b.line)

    def _cut(self, c: tuple, second, line2: int) -> tuple[float, float]:
        """Cut the pending corner ``c`` between its element and ``second`` (a Line or Arc
        from the corner point): emit the element up to the corner and the chamfer or round;
        return where ``second`` now starts."""
        ax, az, gx, gz, kind, size, line, F = c[:8]
        arc = c[8] if len(c) > 8 else None
        word = "CHF" if kind == "C" else "RND"
        col = self._corner_col(c)
        g = (gx, gz)
        first = Line((ax, az), g) if arc is None else Arc((ax, az), g, (arc[0], arc[1]), arc[2])
        if arc is None and math.hypot(gx - ax, gz - az) < 1e-9:
            raise self.alarm(f"{word}={size:g} is longer than the segment (nothing is left of it "
                             f"after the previous chamfer/round)", line, col)
        try:
            k = element_corner(first, second, kind, size)
        except CornerFitError as e:
            which = {"first": "the element it ends", "second": f"the next element (line {line2})",
                     "both": f"between this element and the next (line {line2})"}[e.element]
            raise self.alarm(f"{word}={size:g} does not fit {which}: {e.detail}", line, col) from None
        except CornerError as e:
            if e.reason == "straight":
                self.warn(line, f"{word}={size:g}: the elements meet tangentially (no corner): "
                                f"nothing is cut", (word, line))
                k = None
            elif e.reason == "reverse":
                raise self.alarm(f"{word}={size:g}: the next element turns back on this one",
                                 line, col) from None
            else:
                raise self.alarm(f"{word}={size:g}: the next element does not move", line2) from None
        saveF, saveop = self.F, self.op
        self.F = F
        # the element up to the corner keeps its code; the chamfer or round is the G1 block's
        # (as the corners between two lines)
        segs = [(first if k is None else k.first, "G01" if arc is None else arc[3])]
        if k is not None:
            segs.append((k.segment, "G01"))
        for seg, op in segs:
            if seg is None:
                continue
            self.op = op
            if isinstance(seg, Line):
                self._emit_line(False, seg.start[0], seg.start[1], seg.end[0], seg.end[1], line)
            else:
                Interp._emit_arc(self, seg.start[0], seg.start[1], seg.end[0], seg.end[1],
                                 seg.center[0], seg.center[1], seg.cw, line)
        self.F, self.op = saveF, saveop
        return g if k is None else k.end

    def _resolve_corner(self, c: tuple, x2: float, z2: float, line2: int):
        if len(c) > 8:  # the corner after an arc, against this line
            if math.hypot(x2 - c[2], z2 - c[3]) < 1e-9:
                raise self.alarm(f"{'CHF' if c[4] == 'C' else 'RND'}={c[5]:g}: the next block does "
                                 f"not move", line2)
            return self._cut(c, Line((c[2], c[3]), (x2, z2)), line2)
        ax, az, gx, gz = c[:4]
        l1, l2 = math.hypot(gx - ax, gz - az), math.hypot(x2 - gx, z2 - gz)
        cross = dot = None
        if l1 > 1e-9 and l2 > 1e-9:
            u1 = ((gx - ax) / l1, (gz - az) / l1)
            u2 = ((x2 - gx) / l2, (z2 - gz) / l2)
            cross, dot = u1[0] * u2[1] - u1[1] * u2[0], u1[0] * u2[0] + u1[1] * u2[1]
            if abs(cross) < 1e-12 and dot > 0:
                word = "CHF" if c[4] == "C" else "RND"
                self.warn(c[6], f"{word}={c[5]:g}: the elements meet tangentially (no corner): "
                                f"nothing is cut", (word, c[6]))
                return self._cut(c, Line((gx, gz), (x2, z2)), line2)  # the line runs whole
        if c[4] == "C" and cross is not None:
            # CHF= (the pending corner's own size, not the CHF= of the block that follows it)
            # is the chamfer's length: the distance cut from the corner along each line is
            # length / (2 cos(turn / 2))
            half = math.cos(math.atan2(abs(cross), dot) / 2.0)
            if half > 1e-9:
                c = c[:5] + (c[5] / (2.0 * half),) + c[6:]
        return Interp._resolve_corner(self, c, x2, z2, line2)

    def _arc(self, b: Blk, w: dict, cw: bool, g53: bool = False):
        if self.g158 is not None:
            w = self._shift(w, g53)
        if self.corner is not None or "CHF" in w or "RND" in w:
            return self._corner_arc(b, w, lambda w2: self._arc_block(b, w2, cw, g53))
        return self._arc_block(b, w, cw, g53)

    def _arc_block(self, b: Blk, w: dict, cw: bool, g53: bool = False):
        CR = w.get("CR")
        AR = w.get("AR")
        end = "X" in w or "Z" in w
        if CR is not None:
            if AR is not None or "I" in w or "K" in w:
                raise self.balarm(b, "CR= gives the arc with its end point: not with AR= or I/K", "CR")
            if not end:
                raise self.balarm(b, "missing required word: CR= needs the end point X/Z", "CR")
            w = dict(w)
            w["R"] = w.pop("CR")
            return Interp._arc(self, b, w, cw, g53)
        if AR is None:
            if "I" not in w and "K" not in w:
                raise self.balarm(b, f"missing required word: G{2 if cw else 3} needs I/K, CR= or AR=", "G")
            return Interp._arc(self, b, w, cw, g53)
        if not 0.0 < AR < 360.0:
            raise self.balarm(b, f"value out of range: AR={AR:g} (0-360 degrees)", "AR")
        if self.corner is not None:
            self._corner_not_followed()
        if self.comp_mode == "start":
            raise self.balarm(b, "tool nose compensation G41/G42 must start on a G0/G1 move, not an arc", "G")
        x0, z0 = self.x, self.z
        u = self.unit
        self.op = "G02" if cw else "G03"
        if "I" in w or "K" in w:
            if end:
                raise self.balarm(b, "AR= with the centre (I/K) gives the end point itself: no X/Z", "AR")
            cx = x0 + w.get("I", 0.0) * u
            cz = z0 + w.get("K", 0.0) * u
            r = math.hypot(x0 - cx, z0 - cz)
            if r < 1e-9:
                raise self.balarm(b, "arc centre on the start point (I/K zero)", "I" if "I" in w else "K")
            a0 = math.atan2(x0 - cx, z0 - cz)
            a1 = a0 + math.radians(AR) * (-1.0 if cw else 1.0)
            x1, z1 = point_at_angle((cx, cz), r, a1)
        else:
            x1, z1 = self._target(b, w, g53)
            chord = math.hypot(x1 - x0, z1 - z0)
            if chord < 1e-9:
                raise self.balarm(b, "AR= with the end point: start and end coincide", "AR")
            R = chord / (2.0 * math.sin(math.radians(AR) / 2.0))
            a = Arc.from_radius((x0, z0), (x1, z1), R if AR <= 180.0 else -R, cw)
            cx, cz = a.center
        self.x, self.z = x1, z1
        self._emit_arc(x0, z0, x1, z1, cx, cz, cw, b.line)
        return None

    def _cycle(self, code: int, b: Blk, w: dict):
        if self.g158 is not None:
            w = self._shift(w, False)
        if code == 5:
            if self.corner is not None or "CHF" in w or "RND" in w:
                return self._corner_arc(b, w, lambda w2: self._g5(b, w2))
            return self._g5(b, w)
        if code == 33:
            return self._g33(b, w)
        return Interp._cycle(self, code, b, w)  # pragma: no cover - no other motion cycles

    def _g5(self, b: Blk, w: dict):
        """G5 X.. Z.. IX=.. KZ=..: the arc from here through the intermediate point to the end;
        G90/G91 apply to both points, IX like X (a diameter in G23)."""
        if self.corner is not None:
            self._corner_not_followed()
        if self.comp_mode == "start":
            raise self.balarm(b, "tool nose compensation G41/G42 must start on a G0/G1 move, not an arc", "G")
        if "IX" not in w and "KZ" not in w:
            raise self.balarm(b, "missing required word: G5 needs the intermediate point IX= KZ=", "G")
        x0, z0 = self.x, self.z
        x1, z1 = self._target(b, w)
        u = self.unit
        sx = 0.5 * u if self.diam else u
        if self.absolute:
            xm = w["IX"] * sx if "IX" in w else x0
            zm = w["KZ"] * u if "KZ" in w else z0
        else:
            xm = x0 + w.get("IX", 0.0) * u
            zm = z0 + w.get("KZ", 0.0) * u
        # the circle through the three points
        ax, az = xm - x0, zm - z0
        bx, bz = x1 - x0, z1 - z0
        d = 2.0 * (ax * bz - az * bx)
        if abs(d) < 1e-9 * max(1.0, math.hypot(ax, az) * math.hypot(bx, bz)) or math.hypot(bx, bz) < 1e-9:
            raise self.balarm(b, "G5: the start, intermediate and end points are on one line (or "
                                 "two of them coincide): no arc", "IX" if "IX" in w else "KZ")
        a2, b2 = ax * ax + az * az, bx * bx + bz * bz
        cx = x0 + (bz * a2 - az * b2) / d
        cz = z0 + (ax * b2 - bx * a2) / d
        # clockwise (the G2 sense, Z to the right and X up) when the intermediate point lies
        # to the left of the chord's direction
        cw = (ax * bz - az * bx) > 0.0
        self.op = "G05"
        self.x, self.z = x1, z1
        self._emit_arc(x0, z0, x1, z1, cx, cz, cw, b.line)
        return None

    def _g33(self, b: Blk, w: dict):
        """G33 X.. Z.. K.. (or I..) SF=..: a thread move; blocks that follow each other form
        one thread, whose start angle SF= only the first block sets."""
        if self.corner is not None:
            self._corner_not_followed()
        u = self.unit
        x0, z0 = self.x, self.z
        x1, z1 = self._target(b, w)
        if "I" in w and "K" in w:
            raise self.balarm(b, "G33 takes the lead of the longer axis only: I (X) or K (Z)", "I")
        lead = w.get("K", w.get("I"))
        if lead is None:
            raise self.balarm(b, "missing required word: G33 needs the lead K (or I for a face thread)", "G")
        if lead <= 0:
            raise self.balarm(b, f"value out of range: the lead must be positive", "K" if "K" in w else "I")
        chain = self.thread_start
        if chain is not None and not (self.moves and self.moves[-1] is chain[3]
                                      and abs(chain[0] - x0) <= 1e-9 and abs(chain[1] - z0) <= 1e-9):
            chain = None  # something moved since: a new thread
        angle = w["SF"] if "SF" in w else (chain[2] if chain is not None else
                                           float(self.params.get("thread_start_angle", 0.0)))
        if chain is not None and "SF" in w:
            self.warn(b.line, "SF= in a block that continues a thread: the start offset acts in "
                              "the first block of a thread only", ("SF", b.line))
            angle = chain[2]
        self._flush_comp("G33", b.line)
        self.op = "G33"
        self.x, self.z = x1, z1
        n = len(self.moves)
        self._emit_thread(x0, z0, x1, z1, lead * u, angle, 0.0, b.line)
        self.thread_start = (x1, z1, angle, self.moves[-1] if len(self.moves) > n else None)
        return None

    # -- jumps ---------------------------------------------------------------------------------
    def _goto(self, c, pc: int) -> int:
        if c.cond is not None and self._eval(c.cond, c.line) == 0.0:
            return pc + 1
        t = c.target
        i = self.src.find(t.name, self.cur_span, pc, t.direction)
        if i is None:
            where = "after" if t.direction == "F" else "before"
            other = self.src.find(t.name, self.cur_span, pc, "B" if t.direction == "F" else "F")
            hint = (f" (it is {'before' if t.direction == 'F' else 'after'} it: GOTO"
                    f"{'B' if t.direction == 'F' else 'F'})") if other is not None else ""
            raise self.alarm(f"GOTO{t.direction} {t.name}: no label {t.name} {where} this block in "
                             f"this program{hint}", c.line, t.col)
        return i

    # -- calls ---------------------------------------------------------------------------------
    def _call(self, b: Blk, pc: int, end: int):
        name, col, reps = self.src.calls[b.stmt]
        handler = self._cycle_table().get(name)
        if handler is not None:
            self._lcyc(b, name, handler, col)
            return pc + 1, end
        start = self.src.programs.get(name)
        if start is None:
            start = self._beside(b, name, col)
        if start is None:
            if name in CYCLE_NAMES:
                raise self.alarm(f"{name} not yet supported (the 802 cycle module has no {name})",
                                 b.line, col)
            raise self.alarm(f"subprogram {name} not found", b.line, col)
        if self.dry is not None:
            raise self.alarm("a subprogram call inside a contour", b.line, col)
        if self.calls + reps > self.call_limit:
            raise self.alarm(f"too many subprogram runs: {self.calls} so far and P{reps} more exceed "
                             f"the machine's limit of {self.call_limit} ([limits] calls)", b.line, col)
        if self.level >= _MAX_LEVEL:
            raise self.alarm(f"subprogram nesting too deep (more than {_MAX_LEVEL} nested calls)",
                             b.line, col)
        self._flush_comp()
        span = self.src.span_of(start)
        self.calls += reps
        self.frames.append((pc + 1, end, reps - 1, start, span[1], None, self.cur_span))
        self.level += 1
        self.cur_span = span
        return start, span[1]

    def _return(self, line: int, implicit: bool = False):
        if not self.frames:
            raise self.alarm("RET/M17 ends a subprogram; the main program ends with M2/M30", line)
        ret, end, reps, start, send, w, span = self.frames[-1]
        self._flush_comp()
        if reps > 0:
            self.frames[-1] = (ret, end, reps - 1, start, send, w, span)
            return start, send
        self.frames.pop()
        self.level -= 1
        self.cur_span = span
        return ret, end

    def _beside(self, b: Blk, name: str, col: int) -> Optional[int]:
        """A subprogram from ``NAME.SPF`` beside the program file, appended to the program's
        statements (its alarms name its own file and lines)."""
        if name in self.ext:
            return self.ext[name]
        src = self.src
        folder = os.path.dirname(os.path.abspath(src.file)) if os.path.isfile(src.file) else None
        if folder is None:
            return None
        path = None
        for fn in (f"{name}.SPF", f"{name}.spf", f"{name}.Spf"):
            p = os.path.join(folder, fn)
            if os.path.isfile(p):
                path = p
                break
        if path is None:
            return None
        start = src.attach(path, name, self.syntax, int(getattr(self.m, "line_chars", 65_536)),
                           int(getattr(self.m, "program_bytes", 64 * 1024 * 1024)), b.line, col)
        self.compiled.extend([None] * (len(src.kind) - len(self.compiled)))
        self.ext[name] = start
        return start

    # -- cycles --------------------------------------------------------------------------------
    def _lcyc(self, b: Blk, name: str, handler, col: int) -> None:
        if self.dry is not None:
            raise self.alarm(f"{name} inside a contour", b.line, col)
        if self.corner is not None:
            self._corner_not_followed()
        if self.unit != 1.0:
            raise self.alarm(f"{name} in G70 (inch) is not supported: program cycles in G71 (mm)",
                             b.line, col)
        self._flush_comp("cycle", b.line)
        code = int(name[4:])
        ctx = CycleCtx(self, code, b, {})
        ctx.name = name
        ctx.col = col
        self.comp_mode = ""
        try:
            handler(ctx)
        except NCError:
            raise
        except Exception as e:  # a bug in a cycle must still give an alarm, not a traceback
            raise self.alarm(f"internal error in {name}: {type(e).__name__}: {e}", b.line, col) from None
        # after the cycle G0 G90 G40 are active (the document)
        self.motion = 0
        self.absolute = True
        self.comp = 40
        self.comp_mode = ""

    def contour(self, name: str, b: Blk) -> list:
        """The subprogram ``name`` dry-run as a profile from the current position (the value
        :meth:`Interp.profile` gives the compound cycles); its RET/M17 ends it."""
        start = self.src.programs.get(name)
        if start is None:
            start = self._beside(b, name, 0)
        if start is None:
            raise self.balarm(b, f"contour subprogram {name} not found")
        a, e = self.src.span_of(start)
        last = None
        for i in range(a, e):
            if self.src.kind[i] != P.OTHER:
                raise self.src.alarm("only blocks in a contour subprogram (no jumps)", i, 1)
            if i in self.src.calls:
                raise self.src.alarm("a subprogram call inside a contour", i, 1)
            c = self.compiled[i]
            if c is None:
                c = self.compiled[i] = self._compile(i)
            if c.__class__ is Blk and (17 in c.ms or 2 in c.ms or 30 in c.ms):
                break
            last = i
        if last is None:
            raise self.balarm(b, f"contour subprogram {name} has no blocks")
        return self.dry_run(a, last, b)
