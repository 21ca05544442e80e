"""FANUC 0i-T (G-code system A) codes and their execution (``docs/FANUC.md`` §2–§4, §9, §10, §14).

The code table gives each G code its group in the executor's terms (``motion``: group 01;
``nonmodal``: one-shot group 00; ``cycle``: the one-block multiple repetitive cycles G70–G76)
and its FANUC group for ``#4001``–``#4022``. :class:`FanucInterp` is the interpreter with
FANUC's handlers: X always a diameter, U/W incremental (no G90/G91: G90 is the turning
cycle), G50 coordinate setting and spindle clamp, G04 X/U seconds or P milliseconds,
G98/G99 feed per minute/revolution (G99 at power-on), G28 via the intermediate point, G70,
M98 with P 4+4 digits or P L, M99 and M99 P, G65/G66/G67 macro calls, GOTO and IF..THEN, the
macro B memory of :mod:`.memory` with FANUC's null rules, M codes outside the machine's
``[m_codes]`` as notes.
"""
from __future__ import annotations

import math
from typing import Any, Optional

from ...errors import NCError
from ...nc import parser as P
from ...nc.expr import EvalError, Expr
from ...nc.interp import _MAX_LEVEL, Asg, Blk, Interp
from ...nc.toolpath import Move
from .. import CodeSpec
from . import memory as MEM
from .syntax import CALL_ARGS

# executor group of each G code: 1 motion, 0 one-shot, 6 one-block cycle, 8 unit, 9 nose
# compensation, 11 work system, 12 modal macro call, 14 feed mode, 17 spindle mode, 18 plane,
# 19 stroke check (accepted)
G_GROUP: dict[int, int] = {
    0: 1, 1: 1, 2: 1, 3: 1, 32: 1, 90: 1, 92: 1, 94: 1,
    4: 0, 28: 0, 50: 0, 52: 0, 53: 0, 65: 0,
    70: 6, 71: 6, 72: 6, 73: 6, 74: 6, 75: 6, 76: 6,
    20: 8, 21: 8,
    40: 9, 41: 9, 42: 9,
    54: 11, 55: 11, 56: 11, 57: 11, 58: 11, 59: 11,
    66: 12, 67: 12,
    98: 14, 99: 14,
    96: 17, 97: 17,
    18: 18,
    22: 19, 23: 19,
}
#: the FANUC group number of each executor group (for #4001-#4022)
FANUC_GROUP = {1: 1, 17: 2, 14: 5, 8: 6, 9: 7, 19: 9, 12: 12, 11: 14, 18: 16}
_PHASE = {1: "motion", 0: "nonmodal", 6: "cycle", 9: "comp", 11: "wcs"}
#: the modal settings: group -> code -> (attribute, value); G66 is a call (see FanucInterp)
SETTERS = {14: {99: ("per_rev", True), 98: ("per_rev", False)},
           8: {20: ("unit", 25.4), 21: ("unit", 1.0)},
           17: {96: ("css", True), 97: ("css", False)},
           12: {67: ("modal_call", None)},
           18: {18: ("plane", 18)},
           19: {22: ("stroke", 22), 23: ("stroke", 23)}}
#: the extra words each code gives a meaning; G53 takes the motion's
LETTERS = {1: frozenset("CR"), 2: frozenset("IKR"), 3: frozenset("IKR"), 4: frozenset("P"),
           53: None}
CODES = {("G", g): CodeSpec(g, grp, _PHASE.get(grp, "modal"), SETTERS.get(grp, {}).get(g),
                            LETTERS.get(g, frozenset()))
         for g, grp in G_GROUP.items()}
MESSAGES = {"unknown_g": "unknown G code G{g:02d} (FANUC 0i-T, G-code system A)",
            "two_in_group": "two G codes of one modal group in one block (G{g:02d})",
            "range_ref": "FANUC 0i-T"}
M_CNC = frozenset({0, 1, 2, 30, 98, 99})
CODES.update({("M", m): CodeSpec(m, 0, "flow", None, frozenset("PL") if m in (98, 99) else frozenset())
              for m in M_CNC})
#: motion-group codes that are cycles: G32 threads, G90/G92/G94 repeat on later axis blocks
CYCLE_MOTION = frozenset({32, 90, 92, 94})
POWER_ON = {1: 0, 2: 97, 5: 99, 6: 21, 7: 40, 12: 67, 14: 54, 16: 18}

RANGES: dict[str, tuple[float, float, bool]] = {
    "G": (0, 999, True), "M": (0, 999, True), "N": (0, 99999, True), "T": (0, 9999, True),
    "F": (0, 100000, False), "S": (0, 99999, False), "P": (-99999999, 99999999, False),
    "L": (0, 9999, True), "H": (0, 999, True),
    # Q: also the thread start angle of G92/G76 in 0.001° (up to 360000)
    "Q": (-360000, 360000, False),
}
UNKNOWN_LETTERS = {"O": "O is a program number, not a word inside a block",
                   "Y": "this lathe has no Y axis"}
#: codes of other FANUC systems or options, with the reason they are refused
_REFUSED = {77: "G77 is system B/C's G90: only G-code system A is read (G90 is the turning cycle)",
            78: "G78 is system B/C's G92: only G-code system A is read",
            79: "G79 is system B/C's G94: only G-code system A is read",
            91: "G91 (incremental) does not exist in G-code system A: write U/W",
            17: "the lathe works in the ZX plane (G18)", 19: "the lathe works in the ZX plane (G18)",
            10: "G10 (programmable data input) is not simulated: set the offsets in the machine file",
            27: "G27 (reference return check) is not simulated",
            30: "G30 (second reference point) is not simulated: use G28",
            154: "G154 P1-P99 (Haas additional work offsets) is not simulated: use G54-G59"}
_MAX_MACRO_LEVELS = 4


class FanucInterp(Interp):
    """The interpreter with FANUC 0i-T's codes, calls and memory (see the module doc)."""

    #: integer addresses: a computed real value is rounded
    round_words = frozenset("GMST")

    def __init__(self, src, machine=None, **kw):
        super().__init__(src, machine, **kw)
        self.diam = True  # X is a diameter (parameter 1006#3)
        self.absolute = True  # system A: X/Z absolute, U/W incremental
        self.plane = 18  # (G99, G97, G21, ... come from the power-on codes of POWER_ON)
        self.stroke = 22
        self.spindle_cap: Optional[float] = None  # G50 S
        self.modal_call: Optional[tuple] = None  # G66: (program, repeats, arguments, line)
        self.in_modal = 0
        self._call_req: Optional[tuple] = None  # the call the current block asks for
        self._m99p: Optional[float] = None
        self.keep: dict[int, Any] = {}  # #500-#999
        self.counters = {3901: 0.0, 3902: 0.0}
        self.last_m = 0
        self.last_n = 0
        self.macro_levels = 0
        self.L = [None] * 50
        self.G = [None] * 200
        self._reader = self._fread

    # -- reading the block -------------------------------------------------------------------
    def _word_value(self, e: Expr, line: int):
        """A word's value, None when it is a bare null variable (the address is left out)."""
        node = e.node
        if node[0] == "var" and node[1][0] == "num":
            try:
                v = self._read(node[1][1], False)
            except EvalError as err:
                raise self.alarm(err.message, line, err.col or e.col) from None
            if v is None:
                return None
        return self._eval(e, line)

    # -- blocks ------------------------------------------------------------------------------
    def _block(self, b: Blk):
        if b.plain:
            if b.n is not None:
                self.last_n = b.n
            r = Interp._block(self, b)
        else:
            if b.dyn is not None and (65 in b.gs or 66 in b.gs):
                w, gs, ms = self._call_words(b)
            elif b.dyn is not None:
                w, gs, ms = self._dyn(b)
            else:
                w, gs, ms = b.words, b.gs, b.ms
            if 65 in gs or 66 in gs:
                return self._macro_call_block(b, w, gs, ms)
            if b.n is not None:
                self.last_n = b.n
            if ms:
                self.last_m = ms[-1]
            if 97 in ms and self.dialect.has("haas"):
                return self._m97(b, w)
            r = Interp._block(self, b)
            if r == 2:
                self._m99p = w.get("P")
        if r is None and self.modal_call is not None and b.axes and not self.in_modal \
                and self.dry is None:
            self._call_req = ("G66",) + self.modal_call
            return 1
        return r

    def _call_words(self, b: Blk) -> tuple[dict, tuple, tuple]:
        """The words of a G65/G66 block: M, S and T are arguments (#13, #19, #20) with their
        decimals, as the reader passes them (:data:`syntax.CALL_ARGS`), not rounded to codes."""
        w, gs, ms = self._dyn(b, [d for d in b.dyn if d[0] not in CALL_ARGS])
        ms = list(ms)
        for L, e, col in (d for d in b.dyn if d[0] in CALL_ARGS):
            v = self._word_value(e, b.line)
            if v is None:
                continue
            if not math.isfinite(v) or abs(v) > 99999999:
                raise self.alarm(f"value out of range: the argument {L} is too large", b.line, col)
            if L == "M":
                ms.append(v)
            else:
                w[L] = v
        return w, gs, tuple(ms)

    def _macro_call_block(self, b: Blk, w: dict, gs: tuple, ms: tuple):
        if 65 in gs and 66 in gs:
            raise self.balarm(b, "G65 and G66 in one block", "G")
        if 98 in ms:
            raise self.balarm(b, "G65/G66 and M98 in one block", "M")
        if self.dry is not None:
            raise self.balarm(b, "G65/G66 inside the profile of a compound cycle", "G")
        self.blocks += 1
        args = {k: v for k, v in w.items() if k in MEM.ARGUMENTS}
        if ms:  # M in a call block is argument #13
            args["M"] = float(ms[-1])
            if len(ms) > 1:
                raise self.balarm(b, "word M appears twice in the block", "M")
        prog = self._program_word(b, w)
        reps = self._repeats(b, w)
        if 66 in gs:
            self.modal_call = (prog, reps, args, b.line)
            return None
        self._call_req = ("G65", prog, reps, args, b.line)
        return 1

    def _program_word(self, b: Blk, w: dict) -> int:
        p = w.get("P")
        if p is None:
            raise self.balarm(b, "missing required word P: the program number", "G")
        if not float(p).is_integer() or p < 0:
            raise self.balarm(b, f"value out of range: P{p:g} is not a program number", "P")
        return int(p)

    def _repeats(self, b: Blk, w: dict) -> int:
        L = w.get("L", 1)
        if not float(L).is_integer() or L < 0:
            raise self.balarm(b, f"value out of range: L{L:g} must be a whole number of runs", "L")
        return int(L)

    def _unknown_g(self, b: Blk, g: int) -> NCError:
        why = _REFUSED.get(g)
        if why is None:
            return Interp._unknown_g(self, b, g)
        return self.balarm(b, f"unknown G code G{g:02d}: {why}", "G", g)

    def _unknown_m(self, b: Blk, mc: int) -> None:
        self.warn(b.line, f"M{mc:02d} is not in the machine's [m_codes]: a machine-specific code, "
                          f"no effect in the simulation", ("M?", mc))

    # -- one-shot codes -----------------------------------------------------------------------
    def _nonmodal(self, b: Blk, g: int, w: dict) -> None:
        if g == 50:
            if self.corner is not None:
                self._corner_not_followed()
            if "S" in w:
                s = w["S"]
                if s <= 0:
                    raise self.balarm(b, f"value out of range: G50 S{s:g} must be positive", "S")
                self.spindle_cap = s
            if "U" in w or "W" in w:
                raise self.balarm(b, "G50 sets the position with X/Z, not U/W", "U" if "U" in w else "W")
            u = self.unit
            if "X" in w:
                nx = w["X"] * 0.5 * u
                self.g92x += self.x - nx
                self.ox += self.x - nx
                self.x = nx
            if "Z" in w:
                nz = w["Z"] * u
                self.g92z += self.z - nz
                self.oz += self.z - nz
                self.z = nz
            if not ("S" in w or "X" in w or "Z" in w):
                raise self.balarm(b, "missing required word: G50 needs X/Z (coordinate setting) or S "
                                     "(spindle limit)", "G")
            return
        Interp._nonmodal(self, b, g, w)

    def _spindle_word(self, b: Blk, s: float) -> None:
        if self.css:
            self.vc = s
            return
        mx = self.m.max_rpm
        if s > mx:
            self.warn(b.line, f"S{s:g} exceeds the spindle limit {mx:g} rpm: clamped")
            s = mx
        self.s_rpm = s

    def _rpm(self, x: float) -> float:
        if self.sdir == 5:
            return 0.0
        if not self.css:
            return self.s_rpm
        mx = self.m.max_rpm
        cap = self.spindle_cap
        if cap is not None and cap < mx:
            mx = cap
        r = abs(x + self.tdx)
        if r < 1e-9:
            return mx
        n = 1000.0 * self.vc / (2.0 * math.pi * r)
        return mx if n > mx else n

    def _dwell(self, b: Blk, w: dict) -> None:
        if "P" in w:
            if "X" in w or "U" in w:
                raise self.balarm(b, "G04 takes X/U (seconds) or P (milliseconds), not both", "P")
            p = w["P"]
            if not float(p).is_integer():
                raise self.balarm(b, f"value out of range: G04 P{p:g} is whole milliseconds", "P")
            seconds = p / 1000.0
            letter = "P"
        else:
            letter = "X" if "X" in w else "U"
            if letter not in w:
                raise self.balarm(b, "missing required word: G04 needs X/U (seconds) or P "
                                     "(milliseconds)", "G")
            seconds = w[letter]
        if seconds < 0:
            raise self.balarm(b, f"value out of range: the dwell is negative", letter)
        Interp._dwell(self, b, {"P": seconds})

    def _target(self, b: Blk, w: dict, g53: bool = False):
        if self.absolute:
            return Interp._target(self, b, w, g53)
        return Interp._target(self, b, w, g53)  # pragma: no cover - always absolute

    # -- cycles --------------------------------------------------------------------------------
    def _cycle(self, code: int, b: Blk, w: dict):
        if code == 70:
            return self._g70(b, w)
        if code == 32 and 32 not in (self.cycles or {}):
            table = self._cycle_table()
            from ...nc import cycles_simple
            table[32] = lambda ctx: cycles_simple.execute(32, ctx)
        return Interp._cycle(self, code, b, w)

    def _label(self, n: int, after: int) -> Optional[int]:
        src = self.src
        if hasattr(src, "find_label"):
            return src.find_label(n, self.cur_span, after)
        a, e = self.cur_span
        for i in list(range(after, e)) + list(range(a, after)):
            if src.kind[i] != P.HDR and _n_of(src.text[i]) == n:
                return i
        return None

    def _g70(self, b: Blk, w: dict):
        """G70 P(ns) Q(nf): the blocks N ns..N nf run through the executor (compensation,
        F S T of the profile included), then the tool returns in rapid to the cycle start
        point A (where it stood before the G70 block); execution then continues after the
        G70 block."""
        if self.dry is not None:
            raise self.balarm(b, "G70 inside the profile of a compound cycle", "G")
        if self.corner is not None:
            self._corner_not_followed()
        for L in ("P", "Q"):
            if L not in w:
                raise self.balarm(b, f"missing required word {L}: G70 P(ns) Q(nf)", "G")
            v = w[L]
            if not float(v).is_integer() or not 1 <= v <= 99999:
                raise self.balarm(b, f"value out of range: {L}{v:g} is not a sequence number", L)
        ns, nf = int(w["P"]), int(w["Q"])
        i_ns = self._label(ns, b.stmt + 1)
        if i_ns is None:
            raise self.balarm(b, f"G70: no block N{ns} (P) in this program", "P")
        i_nf = self._label(nf, i_ns)
        if i_nf is None or i_nf < i_ns:
            raise self.balarm(b, f"G70: no block N{nf} (Q) after N{ns} in this program", "Q")
        if b.stmt in range(i_ns, i_nf + 1):
            raise self.balarm(b, "G70 inside its own profile", "P")
        src = self.src
        ax, az = self.x, self.z
        for i in range(i_ns, i_nf + 1):
            k = src.kind[i]
            if k == P.HDR:
                break
            if k != P.OTHER:
                raise src.alarm("macro statements inside the profile of G70 are not supported", i, 1)
            c = self.compiled[i]
            if c is None:
                c = self.compiled[i] = self._compile(i)
            if c.__class__ is Asg:
                self._assign(c)
                continue
            if c.__class__ is not Blk:
                raise src.alarm("macro statements inside the profile of G70 are not supported", i, 1)
            if 70 in c.gs:
                raise self.balarm(c, "G70 inside the profile of G70", "G")
            r = self._block(c)
            if r is not None:
                self._call_req = None
                what = {1: "a subprogram or macro call", 2: "M99", 3: "M02/M30",
                        4: "a multiple repetitive cycle"}.get(r, "a jump")
                raise self.balarm(c, f"{what} inside the profile of G70 (N{ns}-N{nf})",
                                  "G" if r == 4 else "M")
        if self.corner is not None:
            self._corner_not_followed()
        x0, z0 = self.x, self.z
        save_op, self.op = self.op, "G70"
        self.x, self.z = ax, az
        try:
            self._emit_line(True, x0, z0, ax, az, b.line)
        finally:
            self.op = save_op
        return None

    # -- calls ----------------------------------------------------------------------------------
    def _call(self, b: Blk, pc: int, end: int):
        req = self._call_req
        self._call_req = None
        if req is None:  # M98
            w = self._words(b)
            p = w.get("P")
            if p is None:
                raise self.balarm(b, "missing required word P: the subprogram number", "M")
            if not float(p).is_integer() or p < 0:
                raise self.balarm(b, f"value out of range: P{p:g} is not a program number", "P")
            p = int(p)
            if "L" in w:
                prog, reps = p, self._repeats(b, w)
            elif p > 9999:
                reps, prog = divmod(p, 10000)
            else:
                prog, reps = p, 1
            kind, args, line = "M98", None, b.line
        else:
            kind, prog, reps, args, line = req
        start = self.src.programs.get(prog)
        letter = "P" if kind != "G66" else "G"
        if start is None:
            raise self.alarm(f"program O{prog:04d} not found in this file", line,
                             P.word_col(self.src.text[self._stmt_of_line(line)], letter) if kind != "G66" else 0)
        if reps < 1:
            return pc + 1, end
        if self.calls + reps > self.call_limit:
            raise self.balarm(b, f"too many subprogram runs: {self.calls} so far and L{reps} more exceed "
                                 f"the machine's limit of {self.call_limit} ([limits] calls)", letter)
        if self.level >= _MAX_LEVEL:
            raise self.balarm(b, f"subprogram and macro nesting too deep (more than {_MAX_LEVEL} "
                                 f"nested calls)", letter)
        macro = kind != "M98"
        if macro and self.macro_levels >= _MAX_MACRO_LEVELS:
            raise self.balarm(b, f"macro calls nested too deep (more than {_MAX_MACRO_LEVELS} G65/G66 "
                                 f"levels)", letter)
        self._flush_comp()
        span = self.src.span_of(start)
        self.calls += reps
        self.frames.append([pc + 1, end, reps - 1, start, span[1], args, self.cur_span, kind, self.L])
        self._fenter(kind, args)
        self.cur_span = span
        return start, span[1]

    def _fenter(self, kind: str, args: Optional[dict]) -> None:
        self.level += 1
        if kind == "M98":
            return  # a subprogram shares its caller's locals
        self.macro_levels += 1
        if kind == "G66":
            self.in_modal += 1
        loc = [None] * 50
        for letter, v in (args or {}).items():
            loc[MEM.ARGUMENTS[letter]] = float(v)
        self.L = loc

    def _return(self, line: int, implicit: bool = False):
        p99 = self._m99p
        self._m99p = None
        if not self.frames:
            raise self.alarm("M99 in the main program: the control would run it again from its "
                             "start forever; end the main program with M30", line,
                             P.word_col(self.src.text[self._stmt_of_line(line)], "M") if not implicit else 0)
        fr = self.frames[-1]
        ret, end, reps, start, send, args, span, kind, saved = fr
        self._flush_comp()
        if reps > 0 and p99 is None:
            fr[2] = reps - 1
            self._fleave(kind, saved)
            self._fenter(kind, args)
            return start, send
        self.frames.pop()
        self._fleave(kind, saved)
        self.cur_span = span
        if p99 is not None:
            n = int(p99) if float(p99).is_integer() else -1
            i = self._label(n, ret) if 1 <= n <= 99999 else None
            if i is None:
                raise self.alarm(f"M99 P{p99:g}: no block N{p99:g} in the calling program", line,
                                 P.word_col(self.src.text[self._stmt_of_line(line)], "P"))
            return i, end
        return ret, end

    def _fleave(self, kind: str, saved: list) -> None:
        self.level -= 1
        if kind != "M98":
            self.macro_levels -= 1
            if kind == "G66":
                self.in_modal -= 1
            self.L = saved

    def _m97(self, b: Blk, w: dict):
        """Haas M97 P(n): a local subprogram at block N n of this program (returns on M99)."""
        p = w.get("P")
        if p is None or not float(p).is_integer() or not 1 <= p <= 99999:
            raise self.balarm(b, "M97 needs P(n): the block number of the local subprogram", "M")
        i = self._label(int(p), b.stmt + 1)
        if i is None:
            raise self.balarm(b, f"M97 P{int(p)}: no block N{int(p)} in this program", "P")
        if self.level >= _MAX_LEVEL:
            raise self.balarm(b, f"subprogram nesting too deep (more than {_MAX_LEVEL} nested calls)", "M")
        self.blocks += 1
        self._flush_comp()
        self.frames.append([b.stmt + 1, self.cur_span[1], 0, i, self.cur_span[1], None, self.cur_span,
                            "M98", self.L])
        self.level += 1
        self.resume = i
        return 4

    # -- memory -----------------------------------------------------------------------------------
    def _fread(self, n, strict_vacant: bool = True):
        """The reader of expressions: a null variable counts as 0 (FANUC's arithmetic rule)."""
        v = self._read(n, False)
        return 0.0 if v is None else v

    def _read(self, n, strict_vacant: bool = True):
        if n is None:
            return None
        if isinstance(n, str):  # the number's text of ``#30.0`` / ``#[30.0]``
            try:
                n = float(n)
            except ValueError:
                raise EvalError(f"invalid variable #{n}: not a number") from None
        if isinstance(n, float) and not n.is_integer() or n != n:
            raise EvalError(f"invalid variable #{n:g}: not an integer")
        n = int(n)
        if 1 <= n <= 33:
            return self.L[n]
        if 100 <= n <= 199:
            return self.G[n]
        if n == 0:
            return None
        if 500 <= n <= 999:
            return self.keep.get(n)
        if n >= 1000:
            v = self._sysvar(n)
            if v is not None:
                return v
        raise EvalError(f"undefined variable #{n}: no such variable on the FANUC 0i-T "
                        f"(docs/FANUC.md §10)")

    def _sysvar(self, n: int):
        if n in (3901, 3902):
            return self.counters[n]
        if n == 3001:
            return sum(m.duration for m in self.moves) * 1000.0
        if n == 3002:
            return sum(m.duration for m in self.moves) / 3600.0
        if n in (3003, 3004):
            return 0.0
        if 4001 <= n <= 4022:
            return float(self._fmodal(n - 4000))
        if n == 4109:
            return (self.F or 0.0) / self.unit
        if n == 4119:
            return self.vc if self.css else self.s_rpm
        if n == 4120:
            return float(self.tool * 100 + self.reg)
        if n == 4113:
            return float(self.last_m)
        if n == 4114:
            return float(self.last_n)
        if n == 4115:
            a = self.cur_span[0]
            hdr = a - 1 if a > 0 and self.src.kind[a - 1] == P.HDR else None
            num = self.src.number[hdr] if hdr is not None else None
            return float(num or 0)
        if n in (5001, 5041):
            return self.x * 2.0
        if n in (5002, 5042):
            return self.z
        if n == 5021:
            return (self.x + self.ox) * 2.0
        if n == 5022:
            return self.z + self.oz
        return None

    def _fmodal(self, grp: int) -> int:
        return {1: self.motion, 2: 96 if self.css else 97, 5: 99 if self.per_rev else 98,
                6: 20 if self.unit != 1.0 else 21, 7: self.comp,
                9: self.stroke, 12: 66 if self.modal_call else 67, 14: self.wcs,
                16: self.plane}.get(grp, 0)

    def _modal(self, grp: int) -> int:
        return self._fmodal(grp)

    def _write(self, n: float, v, line: int, col: int) -> None:
        if isinstance(n, float) and not n.is_integer() or n != n:
            raise self.alarm(f"invalid variable #{n:g}: not an integer", line, col)
        n = int(n)
        if 1 <= n <= 33:
            self.L[n] = v
        elif 100 <= n <= 199:
            self.G[n] = v
        elif 500 <= n <= 999:
            self.keep[n] = v
        elif n == 0:
            raise self.alarm("variable #0 is always null and cannot be written", line, col)
        elif n in (3901, 3902):
            self.counters[n] = 0.0 if v is None else float(v)
        elif n in (3003, 3004):
            pass  # single-block / feed-hold suppression: no effect in a simulation
        else:
            raise self.alarm(f"variable #{n} cannot be written (docs/FANUC.md §10)" if n >= 1000
                             else f"undefined variable #{n}: no such variable on the FANUC 0i-T "
                                  f"(docs/FANUC.md §10)", line, col)

    def _assign(self, c: Asg) -> None:
        for target, e, col in c.items:
            if isinstance(target, Expr):
                n = self._eval(target, c.line)
            else:
                n = target
            node = e.node
            if node[0] == "var":  # #i = #j keeps a null #j null
                try:
                    j = node[1][1] if node[1][0] == "num" else self._eval(Expr(node[1], e.col), c.line)
                    v = self._read(j, False)
                except EvalError as err:
                    raise self.alarm(err.message, c.line, err.col or e.col) from None
                if v is not None:
                    v = self._eval(e, c.line)
            else:
                v = self._eval(e, c.line)
            if n == MEM.MACRO_ALARM or n == MEM.MESSAGE_STOP:
                self._message(int(n), v, c, col)
                continue
            self._write(n, v, c.line, col)

    def _message(self, n: int, v, c: Asg, col: int) -> None:
        num = 0.0 if v is None else v
        if not float(num).is_integer() or not 0 <= num <= 9999:
            raise self.alarm(f"#{n} = {num:g}: the number must be a whole number 0-9999", c.line, col)
        text = getattr(c, "message", "") or ""
        if n == MEM.MACRO_ALARM:
            raise self.alarm(f"macro alarm {3000 + int(num)}: {text}".rstrip(": ").rstrip(),
                             c.line, col)
        self.warn(c.line, f"#3006 program stop {int(num)}: {text}".rstrip(": ").rstrip()
                  + " (the run continues as after cycle start)")

    def _no_end(self) -> str:
        return "end of program without M02/M30"


def _n_of(text: str) -> Optional[int]:
    from ...nc.interp import _n_of as n_of
    return n_of(text)


__all__ = ["CODES", "CYCLE_MOTION", "FanucInterp", "G_GROUP", "M_CNC", "NCError", "POWER_ON",
           "RANGES", "UNKNOWN_LETTERS", "Move"]
