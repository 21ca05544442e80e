"""The HNC-21/22T interpreter: program text -> :class:`~hnc_cam.nc.toolpath.Toolpath`.

It executes a loaded :class:`~hnc_cam.nc.parser.Source` statement by statement, as the
controller does, and records what the tool's controlled point does. The controller is a
:class:`~hnc_cam.dialect.Dialect` (``run(..., dialect=)``): its reader loads the text, its
code table drives the walk over a block's G codes (phase, group, the modal setting, the
words each code allows), its power-on codes set the modal state, its cycle table runs the
cycles; :class:`Interp` is the HNC-21T's executor (with the memory map of
``hnc_cam.dialect.hnc21t.memory``) and other dialects subclass it
(``hnc_cam.dialect.fanuc0it.codes.FanucInterp``). GOTO / IF..THEN statements, bare DO
loops and a cycle's ``resume_after`` are executed here for every dialect.

Execution model
---------------
* Statements are compiled lazily, once, on first execution (a loop body is compiled once):
  plain blocks (letters and numbers only) take a regex-only path; blocks with expressions
  keep compiled closures for their words (:mod:`hnc_cam.nc.expr`).
* Order inside a block (manual §3.1, §3.2.3, §3.3.5): G codes of the modal groups, then F,
  S, T (the T word acts before motion), then the before-motion M codes (spindle on, coolant
  on: the machine's ``[m_codes]`` meanings),
  then G04 (the dwell comes first in its block), then the non-modal G code or the motion /
  cycle, then the after-motion M codes (spindle stop, coolant off, optional stop, M00 M02
  M30) and M98/M99. Only M00 M02 M30 M98 M99 are the CNC's own; any other M code must be in
  the machine's ``[m_codes]`` table, else it alarms.
* Limits (machine ``[limits]`` and ``step_limit``): moves in the toolpath (also the
  compensation buffer), subprogram runs (a call's L counted at once), passes per cycle block;
  each exceeded limit alarms at the line that exceeds it.
* A block with M98 or G65 is a call: all its words are arguments (``#0``–``#25``), it does
  not move.

Coordinates and offsets (choices where the manual is silent, also in the README)
------------------------------------------------------------------------------------
* Internally X is a radius; X/U words are diameters in G36 (the default; a machine with
  ``diameter_mode = false`` or ``run(..., diameter=False)`` starts in G37), I K R always radii.
* The tool starts at the machine's reference point (``start="reference"``, the API's default
  as ``hnc-cam run``'s: after homing), or where ``start=(x, z)`` says (work coordinates of
  G54); programs usually set their frame with G92.
* Work position = machine position - (G54..G59 origin + G92 shift + G52 local shift).
  Moves are reported in the work system active when they run (what the control displays);
  a program that switches G54..G59 or G52 between moves shows that jump between moves.
* Reported positions are those of the controlled point in work coordinates. With ``Tttoo``
  the slide is moved by register ``oo``'s offset (geometry + wear); the tool's own
  displacement is taken to be the one recorded in register ``tt`` (the usual setup where
  register tt was measured for tool tt). So with ``oo == tt`` the controlled point is the
  programmed point; with ``oo = 00`` (offset cancelled) it is the programmed point plus
  register tt's offset. The change takes effect at the T word without a move of its own.
* G00 is the real dog-leg: both axes at their own rapid rates until the shorter one
  arrives, then the other alone (two ``rapid`` moves).
* Feeds: F in mm/min (G94) or mm/rev (G95, converted with the spindle speed of the move);
  G96 is resolved per move at the radius of the move's midpoint, clamped to the machine's
  max rpm (the move's ``spindle`` and ``feed``); the duration of a G96 + G95 move integrates
  the speed that changes along it (Simpson's rule over 16 intervals). A feed move before any F uses ``machine.default_feed`` (mm/min) with a warning.
* Arcs: R wins over I/K; a negative R is the arc over 180 deg (FANUC usage); an R smaller
  than half the chord by at most 0.001 mm is read as the half circle (programs round to
  3 decimals); with I/K the end must lie within 0.01 mm of the circle; I/K with the end on
  the start is a full circle (emitted as two half arcs).
* Macro variables read as *vacant* until assigned: reading a vacant variable in an
  expression is an alarm ("undefined variable"); a call fills ``#0``–``#25`` with its words
  (0 when absent, as appendix 1 says), ``#30``/``#32`` with the X (radius) / Z work position.
* Variables: ``#0-#49`` locals of the current level, ``#50-#199`` globals, ``#200+50*L+i``
  local ``i`` of level ``L`` (0 = main program; up to 8 nested calls, the 8th without a
  level block), ``#600+n`` /
  ``#700+n`` register n's Z offset / nose radius (writable, for this run), ``#800+n`` tool
  life (free storage), ``#1000/#1002`` machine X (radius) / Z, ``#1009`` 1 in G36 / 0 in
  G37, ``#1010-#1018`` programmed machine position, ``#1020/#1022`` work X (radius) / Z,
  ``#1030/#1032`` current work zero, ``#1040+10*k`` (+2 for Z) the G54+k origins (writable),
  ``#1110/#1112`` the G28 intermediate point, ``#1150+g`` the modal code of group g of
  table 3.2 (``#1151`` and ``#1152`` both give the motion code: the appendix macros save it
  from ``#1152``; ``#1167`` G96/G97), ``#2000-#2600`` the cycle contour table (storage).
  Other numbers are "undefined variable" alarms. Call arguments keep the values as written
  (X as a diameter in G36), as the manual's O1000 example needs; note that the appendix's
  own cycle macros (%0080, %0073) treat ``#23`` as a radius.
* A subprogram that reaches the end of its text without M99 returns with a warning (the
  manual prints %9990 cut short); the main program must end with M02/M30.

Hooks for the other parts
-------------------------
* Cycles: G32/G80/G81/G82 (modal, run when a block has axis words; the words of the
  previous block of the same cycle are kept for the words a block leaves out) and
  G71/G72/G73/G76 (one block) call the dialect's cycle table (HNC:
  ``hnc_cam.nc.cycles.execute(code, ctx)``) with a :class:`CycleCtx` (also ``store``,
  ``setting`` and ``resume_after`` for the FANUC cycles). ``ctx.profile(ns, nf)`` dry-runs blocks N ns..N nf through the normal
  block executor with emission redirected and the modal state restored afterwards.
  Cycle moves are not nose-radius compensated (a pending compensation run is flushed
  before the cycle and resumes after it). While a cycle module is missing the cycle
  alarms "not yet supported".
* G41/G42: the moves from the G41/G42 block's move to the G40 block's move are buffered as
  ``compensation.CompItem`` and handed to ``compensation.compensate_moves`` (flushed early
  at a cycle, M98/G65, G28/G29, G04, a T word and the program end); with nose radius 0
  the moves pass through. G41/G42/G40 on a G02/G03 move is an alarm.
"""
from __future__ import annotations

import math
from typing import Any, Optional

from ..errors import NCError
from ..geometry import Arc, Line
from ..tooling import Machine, Register, load_machine
from . import parser as P
from .lexer import printable
from .state import ModalState
from ..dialect.hnc21t.memory import HncMemory
from .expr import EvalError, Expr
from .toolpath import Move, Toolpath, Warning_
from .toolpath import core as _core

_hypot = math.hypot
_atan2 = math.atan2
_TWO_PI = 2.0 * math.pi

# the HNC-21T tables (table 2.1 ranges, table 3.2 groups, 3.1.1 M codes) live with its dialect
from ..dialect.hnc21t.codes import CYCLE_MOTION, G_GROUP, M_CNC  # noqa: E402,F401 (HNC tables, as before)
from ..dialect.hnc21t.codes import RANGES as _RANGES  # noqa: E402

_BASE_LETTERS = frozenset("NGMFSTXZUW")
_AXIS = frozenset("XZUW")
_LENGTH_LIMIT = 99999.999
# levels 0 (main) .. 8: "nesting depth at most nine levels" (manual 3.4.4), i.e. the main
# program and 8 nested calls; levels 0..7 are also reachable as #200 .. #599 (3.4.1), level 8
# has no such block (#600 is the tool registers)
_MAX_LEVEL = 8
_ARC_R_SLACK = 1e-3
_ARC_END_TOL = 0.01

_SHAPES: dict = {}  # letters of a plain block -> (letters, extra, axes, uw), shared
_GS = [(0,), (1,), (2,), (3,)]


_GOTO = getattr(P, "GOTO", "goto")
_IFTHEN = getattr(P, "IFTHEN", "ifthen")
_VACANT50 = [None] * 50
_ZERO50 = [0] * 50


class _Halt(Exception):
    """M02/M30 reached."""


# ------------------------------------------------------------------------------------------
# compiled statements
# ------------------------------------------------------------------------------------------

class Blk:
    """A compiled block. ``words`` holds the constant values (letter -> float, without G M N);
    ``dyn`` the expression words [(letter, Expr, col)] evaluated at each execution."""

    __slots__ = ("stmt", "line", "text", "n", "words", "gs", "ms", "dyn", "letters", "extra",
                 "axes", "plain", "uw", "hasf")

    def __init__(self, stmt: int, line: int, text: str):
        self.stmt = stmt
        self.line = line
        self.text = text
        self.n: Optional[int] = None
        self.words: dict[str, float] = {}
        self.gs: tuple = ()
        self.ms: tuple = ()
        self.dyn: Optional[list] = None
        self.letters: frozenset = frozenset()
        self.extra: frozenset = frozenset()
        self.axes = False
        self.plain = False  # only G00-G03 / X Z U W I K R: the fast path
        self.uw = False
        self.hasf = False  # plain blocks: an F word to apply


_new_blk = object.__new__


class Asg:
    __slots__ = ("stmt", "line", "items", "message")

    def __init__(self, stmt: int, line: int, items: list, message: str = ""):
        self.stmt = stmt
        self.line = line
        self.items = items  # [(target int | Expr, Expr, col)]
        self.message = message  # the comment of a #3000/#3006 assignment (FANUC)


class Goto:
    """``GOTO n`` / ``IF [c] GOTO n``: jump to block N n of the current program."""
    __slots__ = ("stmt", "line", "target", "cond")

    def __init__(self, stmt: int, line: int, target: Expr, cond: Optional[Expr]):
        self.stmt = stmt
        self.line = line
        self.target = target
        self.cond = cond


class Cond:
    __slots__ = ("stmt", "line", "expr", "tail")

    def __init__(self, stmt: int, line: int, expr: Expr, tail: Optional[Asg] = None):
        self.stmt = stmt
        self.line = line
        self.expr = expr
        self.tail = tail  # IF cond #n=expr: assignments run when the condition holds


def _range_error(letter: str, v: float, ranges: dict = _RANGES, ref: str = "table 2.1") -> Optional[str]:
    r = ranges.get(letter)
    if r is None:
        if not abs(v) <= _LENGTH_LIMIT:
            return f"value out of range: {letter}{v:g} (limit ±99999.999, {ref})"
        return None
    lo, hi, integer = r
    if not math.isfinite(v):
        return f"value out of range: the number of {letter} is too large ({ref})"
    if integer and not float(v).is_integer():
        return f"value out of range: {letter} must be an integer, got {v:g}"
    if v < lo or v > hi:
        return f"value out of range: {letter}{v:g} (allowed {lo:g}..{hi:g}, {ref})"
    return None


# ------------------------------------------------------------------------------------------
# the interpreter
# ------------------------------------------------------------------------------------------

class Interp(HncMemory):
    """One run of one program. Use :func:`run` unless you need the object."""

    #: what a compound cycle's dry run sets aside besides the modal state (:class:`ModalState`)
    _STATE = ("x", "z", "tdx", "tdz", "corner", "g92x", "g92z", "g52x", "g52z", "ox", "oz", "g28",
              "last_g00", "cyc_code", "cyc_words", "comp_items", "comp_mode", "op")

    def __init__(self, src: P.Source, machine: Machine | None = None, *,
                 step_limit: int | None = None, start: tuple[float, float] | str = "reference",
                 diameter: bool | None = None, dialect: Any = None):
        self.src = src
        self.m = machine if machine is not None else load_machine(None)
        from .. import dialect as _dialects
        d = self.dialect = _dialects.get(dialect if dialect is not None else _dialects.DEFAULT)
        self.syntax = getattr(src, "syntax", None) or d.syntax()
        self.g_spec = {k[1]: c for k, c in d.codes.items() if k[0] == "G"}
        self.g_group = {g: c.group for g, c in self.g_spec.items()}
        self.m_spec = {k[1]: c for k, c in d.codes.items() if k[0] == "M"}
        self.comp_d = d.has("comp_d_word")  # a D word is allowed with G40/G41/G42
        self.repeatable = d.repeatable_groups
        self.messages = d.messages
        self.m_cnc = d.m_cnc
        self.ranges = d.ranges
        self.range_ref = d.messages.get("range_ref", "table 2.1")  # where the ranges are from
        self.unknown = d.unknown_letters
        self.cycle_motion = d.cycle_motion
        #: cycles whose later blocks keep the words they leave out (HNC G80-G82, FANUC G90/G92/G94)
        self.modal_cycles = frozenset(c for c in d.cycle_motion if c != 32)
        self.cycles: Optional[dict] = None  # the dialect's cycle table, loaded on first use
        self.store: dict = {}  # cycles' values kept across blocks (first-block values)
        self.resume: Optional[int] = None  # statement to continue with after a cycle
        self.params = dict(getattr(self.m, "parameters", {}) or {})
        self.limit = int(step_limit if step_limit is not None else self.m.step_limit)
        self.move_limit = int(getattr(self.m, "move_limit", 500_000))
        self.call_limit = int(getattr(self.m, "call_limit", 1_000_000))
        self.calls = 0
        self.mcodes: dict[int, str] = dict(getattr(self.m, "m_codes", {}))
        self.compiled: list[Any] = [None] * len(src.kind)
        self.moves: list[Move] = []
        self.warnings: list[Warning_] = []
        self._warned: set = set()
        self.blocks = 0
        self.steps = 0
        # modal state: the dialect's power-on codes (HNC: table 3.2 defaults)
        self.motion = 0
        self.absolute = True
        self.diam = True
        self.unit = 1.0
        self.per_rev = False
        self.css = False
        self.comp = 40
        self.wcs = 54
        for code in d.power_on.values():
            c = self.g_spec.get(code)
            if c is None:
                continue
            if c.phase == "motion":
                self.motion = code
            elif c.phase == "comp":
                self.comp = code
            elif c.phase == "wcs":
                self.wcs = code
            elif c.handler is not None:
                setattr(self, c.handler[0], c.handler[1])
        if d.has("g36_g37"):  # the machine's diameter_mode (or the caller) sets G36/G37
            if diameter is None:
                diameter = bool(getattr(self.m, "diameter_mode", True))
            self.diam = diameter
        self.wcs_tab = {int(k[1:]): (float(v[0]), float(v[1])) for k, v in self.m.work_offsets.items()}
        self.g92x = self.g92z = 0.0
        self.g52x = self.g52z = 0.0
        self.ox, self.oz = self.wcs_tab.get(self.wcs, (0.0, 0.0))
        if isinstance(start, str):
            if start != "reference":
                raise ValueError(f"start must be (x, z) or 'reference', got {start!r}")
            rx, rz = self.m.reference  # machine coordinates -> work coordinates of G54
            self.x, self.z = rx - self.ox, rz - self.oz
        else:
            self.x, self.z = float(start[0]), float(start[1])
        self.F: Optional[float] = None
        self.s_rpm = 0.0
        self.vc = 0.0
        self.sdir = 5
        self.coolant = False
        self.tool = 0
        self.reg = 0
        self.tdx = self.tdz = 0.0
        self.regs: dict[int, Register] = {}
        self.life: dict[int, float] = {}
        self.corner: Optional[tuple] = None
        self.g28: Optional[tuple] = None
        self.last_g00 = 0
        self.cyc_code = 0
        self.cyc_words: dict[str, float] = {}
        self.comp_items: list = []
        self.comp_mode = ""
        self.op = "G00"
        self.dry: Optional[list] = None
        self.prof_letters: Optional[tuple] = None  # (ns, nf, cycle stmt, letters) of the last profile
        # macro variables
        self.levels = [[None] * 50 for _ in range(_MAX_LEVEL + 1)]
        self.ars = [[0] * 50 for _ in range(_MAX_LEVEL + 1)]
        self.level = 0
        self.L = self.levels[0]
        self.G: list = [None] * 200
        self.table = [None] * 601  # #2000..#2600
        self.frames: list = []
        self.cur_span = src.main
        self._reader = self._read
        self._ar = self._arflag

    # -- errors and warnings ---------------------------------------------------------------
    def alarm(self, message: str, line: int, col: int = 0) -> NCError:
        return NCError(message, line, col, self.src.block_text(line), self.src.file)

    def balarm(self, b: Blk, message: str, letter: Optional[str] = None,
               value: Optional[float] = None) -> NCError:
        col = P.word_col(b.text, letter, value) if letter else 0
        if col == 0:  # the word is implicit (modal): point at the block
            col = len(b.text) - len(b.text.lstrip()) + 1
        return self.alarm(message, b.line, col)

    def warn(self, line: int, message: str, once: Any = None) -> None:
        if self.dry is not None:
            return
        if once is not None:
            if once in self._warned:
                return
            self._warned.add(once)
        self.warnings.append(Warning_(line, message))

    def _g_named(self, attr: str, value: Any, default: int) -> str:
        """The G code of this dialect that sets modal ``attr`` to ``value`` (G95 per revolution
        on HNC, G99 on FANUC), for the texts of the shared warnings; ``default`` if none."""
        for code, c in self.g_spec.items():
            if c.phase == "modal" and c.handler is not None and tuple(c.handler) == (attr, value):
                return f"G{code:02d}"
        return f"G{default:02d}"

    # -- compile ----------------------------------------------------------------------------
    def _compile(self, i: int):
        src = self.src
        text = src.text[i]
        line = src.lineno[i]
        k = src.kind[i]
        if k is P.OTHER:
            fw = self.syntax.fast_words(text)
            if fw is not None:
                b = self._compile_plain(i, line, text, fw)
                if b is not None:
                    return b
        block = src.block_text(line)
        if k != P.OTHER:
            p = self.syntax.parse_statement(text, line, src.file, block)
            if p.kind in (P.IF, P.WHILE, _IFTHEN):
                return Cond(i, line, p.cond, Asg(i, line, p.assigns, getattr(p, "message", ""))
                            if p.assigns else None)
            if p.kind == _GOTO:
                return Goto(i, line, p.target, p.cond)
            return None
        b = Blk(i, line, text)
        if fw is not None:
            words = [(L, float(v), 0) for L, v, _ in fw]
        else:
            p = self.syntax.parse_statement(text, line, src.file, block)
            if p.kind == "assign":
                return Asg(i, line, p.assigns, getattr(p, "message", ""))
            if p.kind == _GOTO:
                return Goto(i, line, p.target, p.cond)
            if p.kind == _IFTHEN:
                return Cond(i, line, p.cond, Asg(i, line, p.assigns, getattr(p, "message", ""))
                            if p.assigns else None)
            words = p.words
        gs: list = []
        ms: list = []
        dyn: list = []
        w = b.words
        letters = set()
        unknown = self.unknown
        ranges = self.ranges
        for L, v, col in words:
            if L in unknown:
                raise self.alarm(f"unknown word {L}: {unknown[L]}", line,
                                 col or self._word_col(text, L))
            if isinstance(v, Expr):
                if L not in ("G", "M"):
                    if L in letters:
                        raise self.alarm(f"word {L} appears twice in the block", line, col)
                dyn.append((L, v, col))
                letters.add(L)
                continue
            err = _range_error(L, v, ranges, self.range_ref)
            if err:
                raise self.alarm(err, line, col or self._word_col(text, L))
            if L == "G":
                gs.append(int(v))
            elif L == "M":
                ms.append(int(v))
            elif L == "N":
                b.n = int(v)
            else:
                if L in letters:
                    raise self.alarm(f"word {L} appears twice in the block", line,
                                     col or self._word_col(text, L))
                w[L] = v
            letters.add(L)
        letters.discard("N")
        b.gs = tuple(gs)
        b.ms = tuple(ms)
        b.dyn = dyn or None
        b.letters = frozenset(letters)
        b.extra = b.letters - _BASE_LETTERS
        b.axes = bool(b.letters & _AXIS)
        b.uw = "U" in letters or "W" in letters
        b.hasf = "F" in w
        b.plain = (b.dyn is None and not ms and b.letters <= frozenset("GXZUWIKRF")
                   and all(g <= 3 for g in gs) and len(gs) <= 1)
        return b

    #: the column of a word in a cleaned line, for an alarm (a dialect's reader may know
    #: words the HNC lexer does not: SINUMERIK's CR=)
    _word_col = staticmethod(P.word_col)

    def _compile_plain(self, i: int, line: int, text: str, fw: list) -> Optional[Blk]:
        """The hot path of loading: a block of at most one G00-G03 and X Z U W I K R words.
        Returns None for anything else (the general compiler then handles it)."""
        w: dict = {}
        g = -1
        n = None
        for L, v, _ in fw:
            if L in "XZUWIKRF":
                if L in w:
                    return None
                f = float(v)
                if f > _LENGTH_LIMIT or f < -_LENGTH_LIMIT or (L == "F" and not 0 <= f <= 24000):
                    return None
                w[L] = f
            elif L == "N":
                if n is not None or "." in v or v[0] in "+-" or len(v) > 10:
                    return None
                n = int(v)
                if n > 4294967295:
                    return None
            elif L == "G":
                if g >= 0:
                    return None
                f = float(v)
                if f == 0.0 or f == 1.0 or f == 2.0 or f == 3.0:
                    g = int(f)
                else:
                    return None
            else:
                return None
        key = (g >= 0, *w)
        shape = _SHAPES.get(key)
        if shape is None:
            letters = frozenset(w)
            shape = _SHAPES[key] = (letters | {"G"} if g >= 0 else letters, letters - _BASE_LETTERS,
                                    bool(letters & _AXIS), "U" in w or "W" in w, "F" in w)
        b = _new_blk(Blk)  # every slot set once, here (no __init__ defaults to overwrite)
        b.stmt = i
        b.line = line
        b.text = text
        b.n = n
        b.words = w
        b.gs = _GS[g] if g >= 0 else ()
        b.ms = ()
        b.dyn = None
        b.letters, b.extra, b.axes, b.uw, b.hasf = shape
        b.plain = True
        return b

    # -- variables: the HNC-21T memory map (hnc_cam.dialect.hnc21t.memory.HncMemory) ----------
    def _eval(self, e: Expr, line: int):
        try:
            v = e.fn(self.L, self.G, self._reader, self._ar)
            v + 0.0  # vacant (None) -> TypeError
        except EvalError as err:
            raise self.alarm(err.message, line, err.col or e.col) from None
        except (TypeError, ValueError, OverflowError, ZeroDivisionError):
            v = self._eval_strict(e, line)
        if not math.isfinite(v):
            raise self.alarm("bad expression: the value is not a finite number", line, e.col)
        return v

    def _eval_strict(self, e: Expr, line: int) -> float:
        try:
            return e.strict(self.L, self.G, self._reader, self._ar) + 0.0
        except EvalError as err:
            raise self.alarm(err.message, line, err.col or e.col) from None
        except OverflowError:
            raise self.alarm("bad expression: number too large", line, e.col) from None
        except (TypeError, ValueError, ZeroDivisionError) as ex:
            raise self.alarm(f"bad expression: {ex}", line, e.col) from None

    # -- registers and coordinates ------------------------------------------------------------
    def _register(self, n: int) -> Register:
        r = self.regs.get(n)
        if r is None:
            r = self.m.register(n)
        return r

    def _set_tool_delta(self) -> None:
        if self.tool == self.reg:
            self.tdx = self.tdz = 0.0
            return
        g = self._register(self.tool) if self.tool else None
        o = self._register(self.reg) if self.reg else None
        self.tdx = (g.x_total_radius if g else 0.0) - (o.x_total_radius if o else 0.0)
        self.tdz = (g.z_total if g else 0.0) - (o.z_total if o else 0.0)

    def _set_origin(self) -> None:
        """Recompute the work origin; the machine position stays, the work position moves."""
        mx, mz = self.x + self.ox, self.z + self.oz
        wx, wz = self.wcs_tab.get(self.wcs, (0.0, 0.0))
        self.ox = wx + self.g92x + self.g52x
        self.oz = wz + self.g92z + self.g52z
        self.x, self.z = mx - self.ox, mz - self.oz

    # -- running ---------------------------------------------------------------------------
    def run(self) -> Toolpath:
        src = self.src
        kinds = src.kind
        jump = src.jump
        comp = self.compiled
        a, end = src.main
        pc = a
        limit = self.limit
        OTHER, IF, WHILE, ELSE, ENDIF, ENDW = P.OTHER, P.IF, P.WHILE, P.ELSE, P.ENDIF, P.ENDW
        block = self._block
        steps = self.steps
        # runs of plain blocks go to the compiled core when there is one (the HNC reader and
        # this executor only: it does what they do, and hands back before anything else)
        fast = (_core.run_plain if _core is not None and type(self) is Interp
                and getattr(self.syntax, "fast_words", None) is P.fast_words else None)
        stopped = -1  # the statement the core last handed back: Python runs it
        for line, col, msg in getattr(src, "notes", ()) or ():
            self.warn(line, msg)
        try:
            while True:
                if pc >= end or kinds[pc] == P.HDR:
                    # end of the program text
                    if self.frames:
                        steps += 1  # the implicit M99 counts (an empty subprogram with L huge)
                        if steps > limit:
                            raise self.alarm(f"step limit exceeded ({limit} statements executed): "
                                             f"endless loop?", src.lineno[pc - 1] if pc > 0 else 0)
                        last = src.lineno[pc - 1] if pc > 0 else 0
                        self.warn(last, "subprogram ends without M99: returning to the caller",
                                  ("noM99", last))
                        pc, end = self._return(last, implicit=True)
                        continue
                    last = src.lineno[min(pc, len(kinds)) - 1] if pc > 0 else 1
                    raise self.alarm(self._no_end(), last)
                steps += 1
                if steps > limit:
                    self.steps = steps
                    raise self.alarm(f"step limit exceeded ({limit} statements executed): "
                                     f"endless loop?", src.lineno[pc])
                k = kinds[pc]
                if k is OTHER:
                    c = comp[pc]
                    if c is None:
                        if fast is not None and pc != stopped:
                            steps -= 1  # counted again by the core, per statement it runs
                            npc, steps = fast(self, pc, end, steps, OTHER)
                            if npc != pc:
                                stopped = pc = npc
                                continue
                            stopped = pc
                            steps += 1
                        c = comp[pc] = self._compile(pc)
                    if c.__class__ is Blk:
                        self.steps = steps
                        r = block(c)
                        if r is None:
                            pc += 1
                        elif r == 1:  # call
                            pc, end = self._call(c, pc, end)
                        elif r == 2:  # M99
                            pc, end = self._return(c.line)
                        elif r == 4:  # a cycle resumes after its profile, a jump of the dialect
                            pc, end = self._jump(pc, end)
                        else:
                            raise _Halt
                    else:
                        self._assign(c)
                        pc += 1
                elif k == IF or k == WHILE:
                    c = comp[pc]
                    if c is None:
                        if pc in src.bad:
                            raise src.alarm(src.bad[pc], pc, 1)
                        c = comp[pc] = self._compile(pc)
                    if c.expr is None or self._eval(c.expr, c.line) != 0.0:
                        if c.tail is not None:
                            self._assign(c.tail)
                        pc += 1
                    else:
                        pc = jump[pc]
                elif k == ELSE or k == ENDW:
                    if comp[pc] is None:
                        if pc in src.bad:
                            raise src.alarm(src.bad[pc], pc, 1)
                        comp[pc] = self._compile(pc) or True
                    pc = jump[pc]
                elif k == ENDIF:
                    if comp[pc] is None:
                        if pc in src.bad:
                            raise src.alarm(src.bad[pc], pc, 1)
                        comp[pc] = self._compile(pc) or True
                    pc += 1
                elif k == _GOTO:
                    c = comp[pc]
                    if c is None:
                        if pc in src.bad:
                            raise src.alarm(src.bad[pc], pc, 1)
                        c = comp[pc] = self._compile(pc)
                    self.steps = steps
                    pc = self._goto(c, pc)
                elif k == _IFTHEN:
                    c = comp[pc]
                    if c is None:
                        if pc in src.bad:
                            raise src.alarm(src.bad[pc], pc, 1)
                        c = comp[pc] = self._compile(pc)
                    if self._eval(c.expr, c.line) != 0.0 and c.tail is not None:
                        self._assign(c.tail)
                    pc += 1
                else:  # pragma: no cover
                    pc += 1
        except _Halt:
            pass
        self.steps = steps
        if self.corner is not None:
            c = self.corner
            raise self.alarm("chamfer/round at the end of the program: no following G01 line", c[6])
        self._flush_comp()
        tp = Toolpath(moves=self.moves, warnings=self.warnings, blocks_executed=self.blocks,
                      file=src.file, source_lines=src.lines)
        return tp

    def _no_end(self) -> str:
        """The alarm for a main program that runs off its end, saying what the file looks
        like when that explains it (FANUC framing: a lone ``%`` line, then ``O1234``)."""
        src = self.src
        a, e = src.main
        msg = "end of program without M02/M30"
        if a != e or not src.kind:
            return msg
        first = a - 1 if a > 0 and src.kind[a - 1] == P.HDR else None
        if first is not None and src.number[first] is None and e < len(src.kind) \
                and src.kind[e] == P.HDR:
            return (f"{msg}: the file looks like a FANUC-framed program ('%' alone on line "
                    f"{src.lineno[first]}, then the header {src.text[e].strip()} on line "
                    f"{src.lineno[e]}): try --dialect fanuc0it (on the HNC-21T the first header "
                    f"starts the main program: remove the lone '%' lines)")
        if e < len(src.kind) and src.kind[e] == P.HDR:
            return (f"{msg}: the main program is empty (the next header, on line {src.lineno[e]}, "
                    f"starts a subprogram)")
        return msg

    def _goto(self, c: "Goto", pc: int) -> int:
        """``GOTO n`` / ``IF [c] GOTO n``: the statement of block N n in the current program
        (searched forward from the GOTO, then from the program's start), or the next
        statement when the condition does not hold."""
        if c.cond is not None and self._eval(c.cond, c.line) == 0.0:
            return pc + 1
        v = self._eval(c.target, c.line)
        col = c.target.col if c.target is not None else 0
        n = round(v)
        if abs(v - n) > 1e-9 or not 1 <= n <= 99999:
            raise self.alarm(f"GOTO {v:g}: the sequence number must be an integer 1-99999", c.line, col)
        i = self.src.find_label(n, self.cur_span, pc + 1)
        if i is None:
            raise self.alarm(f"GOTO {n}: no block N{n} in this program", c.line, col)
        return i

    def _jump(self, pc: int, end: int) -> tuple[int, int]:
        """Where a block that asked for a jump continues (``self.resume``: a statement)."""
        r = self.resume
        self.resume = None
        return (pc + 1 if r is None else r), end

    def _assign(self, c: Asg) -> None:
        for target, e, col in c.items:
            v = self._eval(e, c.line)
            if isinstance(target, Expr):
                n = self._eval(target, c.line)
            else:
                n = target
            self._write(n, v, c.line, col)

    # -- subprograms ---------------------------------------------------------------------------
    def _call(self, b: Blk, pc: int, end: int) -> tuple[int, int]:
        w = self._words(b)
        pn = w.get("P")
        if pn is None:
            raise self.balarm(b, "missing required word P: the subprogram number", "M" if 98 in b.ms else "G")
        if not float(pn).is_integer() or pn < 0:
            raise self.balarm(b, f"value out of range: P{pn:g} is not a program number", "P")
        start = self.src.programs.get(int(pn))
        if start is None:
            raise self.balarm(b, f"subprogram %{int(pn):04d} not found in this file", "P")
        reps = int(w.get("L", 1) or 0)
        if reps < 1:
            return pc + 1, end
        if self.calls + reps > self.call_limit:
            raise self.balarm(b, f"too many subprogram runs: {self.calls} so far and L{reps} more exceed "
                                 f"the machine's limit of {self.call_limit} ([limits] calls)",
                              "L" if reps > 1 else ("M" if 98 in b.ms else "G"))
        if self.level >= _MAX_LEVEL:
            raise self.balarm(b, f"subprogram nesting too deep (more than {_MAX_LEVEL} nested calls: "
                                 f"the manual allows {_MAX_LEVEL + 1} levels with the main program)")
        if self.dry is not None:
            raise self.balarm(b, "M98/G65 inside the profile of a compound cycle")
        self._flush_comp()
        span = self.src.span_of(start)
        self.calls += reps
        self.frames.append((pc + 1, end, reps - 1, start, span[1], w, self.cur_span))
        self._enter(w)
        self.cur_span = span
        return start, span[1]

    def _enter(self, w: dict) -> None:
        self.level += 1
        loc = self.levels[self.level]
        ar = self.ars[self.level]
        loc[:] = _VACANT50
        ar[:] = _ZERO50
        flag = 90 if self.absolute else 91
        for i in range(26):
            L = chr(65 + i)
            v = w.get(L)
            if v is None:
                loc[i] = 0.0
            else:
                loc[i] = float(v)
                ar[i] = flag
        for i in range(30, 39):
            loc[i] = 0.0
            ar[i] = 90
        loc[30] = self.x
        loc[32] = self.z
        self.L = loc

    def _return(self, line: int, implicit: bool = False) -> tuple[int, int]:
        if not self.frames:
            raise self.alarm("M99 outside a subprogram (the main program ends with M02/M30)", line,
                             P.word_col(self.src.text[self._stmt_of_line(line)], "M") if not implicit else 0)
        ret, end, reps, start, send, w, span = self.frames[-1]
        self._flush_comp()
        if reps > 0:
            self.frames[-1] = (ret, end, reps - 1, start, send, w, span)
            self.level -= 1
            self._enter(w)
            return start, send
        self.frames.pop()
        self.level -= 1
        self.L = self.levels[self.level]
        self.cur_span = span
        return ret, end

    def _stmt_of_line(self, line: int) -> int:
        try:
            return self.src.lineno.index(line)
        except ValueError:
            return 0

    # -- blocks -------------------------------------------------------------------------------
    #: addresses whose computed value is rounded to a whole number before its range check
    #: (none on the HNC-21T, where a fraction there is out of range; FANUC rounds G M S T)
    round_words: frozenset = frozenset()

    def _word_value(self, e: Expr, line: int):
        """The value of a word written as an expression; None leaves the address out (a
        dialect whose null variable in a word means "no word"; never on the HNC-21T)."""
        return self._eval(e, line)

    def _words(self, b: Blk) -> dict:
        """All word values of a block (expressions evaluated), G and M not among them."""
        w = dict(b.words)
        if b.dyn:
            for L, e, col in b.dyn:
                if L in ("G", "M"):
                    continue
                v = self._word_value(e, b.line)
                if v is not None:
                    w[L] = v
        return w

    def _dyn(self, b: Blk, dyn: list | None = None) -> tuple[dict, tuple, tuple]:
        """The block's words with its expression words (``dyn``: ``b.dyn`` unless given)
        evaluated: (words, G codes, M codes)."""
        w = dict(b.words)
        gs = list(b.gs)
        ms = list(b.ms)
        for L, e, col in (b.dyn if dyn is None else dyn):
            v = self._word_value(e, b.line)
            if v is None:
                continue
            if L in self.round_words:
                v = float(round(v))
            err = _range_error(L, v, self.ranges, self.range_ref)
            if err:
                raise self.alarm(err, b.line, col)
            if L == "G":
                gs.append(int(v))
            elif L == "M":
                ms.append(int(v))
            else:
                w[L] = v
        return w, tuple(gs), tuple(ms)

    def _block(self, b: Blk):
        """Execute one block; returns None, 1 (call), 2 (M99) or 3 (end)."""
        self.blocks += 1
        if b.plain:
            w = b.words
            gs = b.gs
            if b.hasf:
                self.F = w["F"] * self.unit
            if gs:
                g = gs[0]
                self.motion = g
                if self.cyc_code:
                    self.cyc_code = 0
            if not b.axes:
                if b.extra:
                    self._check_letters(b, 0, 0)
                return None
            m = self.motion
            if b.extra and m < 2:
                self._check_letters(b, 0, 0)
            if m == 1:
                return self._g01(b, w)
            if m == 0:
                return self._g00(b, w)
            if m <= 3:
                return self._arc(b, w, m == 2)
            return self._cycle(m, b, w)
        if b.dyn is not None:
            w, gs, ms = self._dyn(b)
        else:
            w, gs, ms = b.words, b.gs, b.ms
        g00, g06, comp_cmd = self._gcodes(b, gs)
        is_call = g00 == 65 or 98 in ms
        if b.extra and not is_call:
            self._check_letters(b, g00, g06)
        # F S T
        if not is_call:
            if "F" in w:
                self.F = w["F"] * self.unit
            if "S" in w:
                self._spindle_word(b, w["S"])
            if "T" in w:
                self._tword(b, w["T"])
        elif "T" in w or "F" in w or "S" in w:
            pass  # arguments of the call
        # M before
        flow = -1  # the program-flow M code of the block (M00 is 0)
        m_cnc = self.m_cnc
        for mc in ms:
            if mc in m_cnc:
                if flow >= 0:
                    raise self.balarm(b, f"M{flow:02d} and M{mc:02d} in one block", "M")
                flow = mc
                continue
            meaning = self.mcodes.get(mc)
            if meaning is None:
                self._unknown_m(b, mc)
            elif meaning == "spindle_cw":
                self.sdir = 3
            elif meaning == "spindle_ccw":
                self.sdir = 4
            elif meaning == "coolant_on":
                self.coolant = True
        return self._block_rest(b, w, ms, g00, g06, comp_cmd, is_call, flow)

    def _unknown_m(self, b: Blk, mc: int) -> None:
        raise self.balarm(b, f"unknown M code M{mc:02d} (table 3.1): this machine's PLC does not "
                             f"list it; declare it in the machine file's [m_codes] table with its "
                             f"meaning, e.g. M{mc:02d} = \"other\"", "M", mc)

    def _gcodes(self, b: Blk, gs: tuple) -> tuple[int, int, int]:
        """Walk the block's G codes over the dialect's table: modal settings are applied;
        returns the one-shot code, the one-block cycle and the compensation command (0 if
        none). The motion code becomes modal here."""
        g00 = 0
        g06 = 0
        seen = 0
        comp_cmd = 0
        motion = -1
        spec = self.g_spec
        for g in gs:
            c = spec.get(g)
            if c is None:
                raise self._unknown_g(b, g)
            grp = c.group
            bit = 1 << grp
            if seen & bit and grp not in self.repeatable:
                raise self.balarm(b, self.messages["two_in_group"].format(g=g, grp=grp), "G")
            seen |= bit
            ph = c.phase
            if ph == "motion":
                motion = g
            elif ph == "nonmodal":
                g00 = g
            elif ph == "cycle":
                g06 = g
            elif ph == "comp":
                comp_cmd = g
            elif ph == "wcs":
                if g != self.wcs:
                    self.wcs = g
                    self._set_origin()
            elif c.handler is not None:
                setattr(self, c.handler[0], c.handler[1])
        if motion >= 0:
            if motion != self.motion:
                self.cyc_code = 0
            self.motion = motion
        return g00, g06, comp_cmd

    def _unknown_g(self, b: Blk, g: int) -> NCError:
        return self.balarm(b, self.messages["unknown_g"].format(g=g), "G", g)

    def _block_rest(self, b: Blk, w: dict, ms: tuple, g00: int, g06: int, comp_cmd: int,
                    is_call: bool, flow: int):
        """The block after its modal codes, F S T and before-motion M codes: compensation
        change, the call / one-shot code / cycle / motion, the after-motion M codes, flow."""
        # compensation mode change (flush happens before the block's move)
        if comp_cmd and comp_cmd != self.comp:
            self._comp_command(b, comp_cmd)
        elif comp_cmd == 40 and self.comp == 40:
            pass
        result = None
        if is_call:
            if g00 == 65 and 98 in ms:
                raise self.balarm(b, "G65 and M98 in one block", "G")
            if self.dry is not None:
                raise self.balarm(b, "M98/G65 inside the profile of a compound cycle", "M")
            result = 1
        elif g00 == 4:
            self._dwell(b, w)
        elif g00 and g00 != 53:
            self.last_g00 = g00
            self._nonmodal(b, g00, w)
        elif g06:
            result = self._cycle(g06, b, w)
        elif b.axes:
            if g00 == 53:
                self.last_g00 = 53
            m = self.motion
            if m == 1:
                self._g01(b, w, g00 == 53)
            elif m == 0:
                self._g00(b, w, g00 == 53)
            elif m <= 3:
                self._arc(b, w, m == 2, g00 == 53)
            else:
                if g00 == 53:
                    raise self.balarm(b, "G53 cannot be used with a cycle", "G")
                result = self._cycle(m, b, w)
        # G40 without a (non-zero) move: compensation stays pending ("cancel") and ends with
        # the next move, which goes from the last compensated point to its programmed end
        # M after
        for mc in ms:
            meaning = self.mcodes.get(mc)
            if meaning == "spindle_stop":
                self.sdir = 5
            elif meaning == "coolant_off":
                self.coolant = False
            elif meaning == "optional_stop":
                self.warn(b.line, f"M{mc:02d} optional stop: the run continues (optional-stop switch "
                                  f"off)", ("M01", b.line))
        if flow >= 0:
            if flow in (2, 30):
                return 3
            if flow == 99:
                if self.dry is not None:
                    raise self.balarm(b, "M99 inside the profile of a compound cycle", "M")
                return 2
            if flow == 0:
                self.warn(b.line, "M00 program stop: the run continues as after cycle start", ("M00", b.line))
        return result

    def _check_letters(self, b: Blk, g00: int, g06: int) -> None:
        m = self.motion
        if g06 or (m in self.cycle_motion and b.axes and not g00):
            return
        ok: set = set()
        spec = self.g_spec
        c = spec.get(g00) if g00 else None
        if c is not None and c.letters is not None:
            ok = set(c.letters)  # the one-shot code's own words
        elif b.axes:
            c = spec.get(m)
            if c is not None and c.letters:
                ok = set(c.letters)  # the motion's words (arc I K R, corner C R)
        for mc in b.ms:
            c = self.m_spec.get(mc)
            if c is not None and c.letters:
                ok |= c.letters
        if self.comp_d and (self.comp != 40 or 40 in b.gs or 41 in b.gs or 42 in b.gs):
            ok.add("D")
        for L in sorted(b.extra):
            if L not in ok:
                what = (f"G{g00:02d}" if g00 else f"G{m:02d}" if b.axes else "this")
                raise self.balarm(b, f"word {L} has no meaning in {what} block", L)

    def _spindle_word(self, b: Blk, s: float) -> None:
        if self.css:
            self.vc = s
            return
        mx = self.m.max_rpm
        if s > mx:
            self.warn(b.line, f"S{s:g} exceeds the spindle limit {mx:g} rpm: clamped")
            s = mx
        self.s_rpm = s

    def _tword(self, b: Blk, t: float) -> None:
        t = int(t)
        tt, oo = divmod(t, 100)
        if 0 < t < 100:
            self.warn(b.line, f"T{t} read as T{t:04d}: tool {tt:02d}, offset register {oo:02d}")
        if (tt, oo) == (self.tool, self.reg):
            return
        if self.comp != 40:
            self._flush_comp()
        self.tool, self.reg = tt, oo
        self._set_tool_delta()

    # -- targets ---------------------------------------------------------------------------------
    def _target(self, b: Blk, w: dict, g53: bool = False) -> tuple[float, float]:
        u = self.unit
        x = self._axis(b, w, "X", "U", self.x, 0.5 * u if self.diam else u, self.ox, g53)
        z = self._axis(b, w, "Z", "W", self.z, u, self.oz, g53)
        return x, z

    def _axis(self, b: Blk, w: dict, absolute: str, incremental: str, cur: float,
              scale: float, origin: float, g53: bool) -> float:
        """Target of one axis from its absolute word (X/Z: G90, G91 or G53 machine
        coordinates) or its incremental word (U/W); both in one block alarm."""
        A = w.get(absolute)
        inc = w.get(incremental)
        if A is not None:
            if inc is not None:
                raise self.balarm(b, f"{absolute} and {incremental} in one block", incremental)
            if g53:
                return A * scale - origin
            return A * scale if self.absolute else cur + A * scale
        if inc is not None:
            return cur + inc * scale
        return cur

    # -- motion --------------------------------------------------------------------------------
    def _g00(self, b: Blk, w: dict, g53: bool = False):
        if b.plain and self.absolute and self.diam and self.unit == 1.0 and not b.uw:
            X = w.get("X")
            x1 = X * 0.5 if X is not None else self.x
            Z = w.get("Z")
            z1 = Z if Z is not None else self.z
        else:
            x1, z1 = self._target(b, w, g53)
        if self.corner is not None:
            self._corner_not_followed()
        self.op = "G00"
        x0, z0 = self.x, self.z
        self.x, self.z = x1, z1
        self._emit_line(True, x0, z0, x1, z1, b.line)
        return None

    def _g01(self, b: Blk, w: dict, g53: bool = False):
        if b.plain and self.absolute and self.diam and self.unit == 1.0 and not b.uw:
            X = w.get("X")
            x1 = X * 0.5 if X is not None else self.x
            Z = w.get("Z")
            z1 = Z if Z is not None else self.z
        else:
            x1, z1 = self._target(b, w, g53)
        x0, z0 = self.x, self.z
        self.op = "G01"
        c = self.corner
        if c is not None:
            x0, z0 = self._resolve_corner(c, x1, z1, b.line)
            self.corner = None
        if b.extra and ("C" in w or "R" in w):
            if "C" in w and "R" in w:
                raise self.balarm(b, "C (chamfer) and R (round) in one block", "R")
            kind = "C" if "C" in w else "R"
            size = w[kind] * self.unit
            if size < 0:
                raise self.balarm(b, f"value out of range: {kind} must not be negative", kind)
            if size > 0:
                if _hypot(x1 - self.x, z1 - self.z) < 1e-9:
                    raise self.balarm(b, f"chamfer/round {kind}{w[kind]:g} on a block without movement", kind)
                self.corner = (x0, z0, x1, z1, kind, size, b.line, self.F)
                self.x, self.z = x1, z1
                return None
        self.x, self.z = x1, z1
        self._emit_line(False, x0, z0, x1, z1, b.line)
        return None

    def _corner_not_followed(self) -> None:
        c = self.corner
        raise self.alarm(f"chamfer/round {c[4]}{c[5]:g} must be followed by a G01 line "
                         f"(the manual defines it between two lines)", c[6], P.word_col(
                             self.src.text[self._stmt_of_line(c[6])], c[4]))

    def _resolve_corner(self, c: tuple, x2: float, z2: float, line2: int) -> tuple[float, float]:
        """Emit the corner block's line up to B and the chamfer/round B->C'; return C'."""
        ax, az, gx, gz, kind, size, line, F = c
        l1 = _hypot(gx - ax, gz - az)
        l2 = _hypot(x2 - gx, z2 - gz)
        col = P.word_col(self.src.text[self._stmt_of_line(line)], kind)
        if l2 < 1e-9:
            raise self.alarm(f"chamfer/round {kind}{size:g}: the next block does not move", line2)
        if l1 < 1e-9:  # a chamfer/round of the block before took all of this segment
            raise self.alarm(f"chamfer/round {kind}{size:g} is longer than the segment (nothing is "
                             f"left of it after the previous chamfer/round)", line, col)
        from ..geometry.corner import CornerError, corner as _corner  # chamfers and rounds only
        try:
            k = _corner((ax, az), (gx, gz), (x2, z2), kind, size)
        except CornerError as ce:
            if ce.reason == "straight":  # collinear: nothing to round; the block's line runs whole
                saveF, saveop = self.F, self.op
                self.F, self.op = F, "G01"
                self._emit_line(False, ax, az, gx, gz, line)
                self.F, self.op = saveF, saveop
                return gx, gz
            raise self.alarm(f"chamfer/round {kind}{size:g}: the next line turns back on this one", line, col)
        t = k.trim
        if l1 < t - 1e-9:
            raise self.alarm(f"chamfer/round {kind}{size:g} is longer than the segment "
                             f"({l1:.3f} mm; needs {t:.3f})", line, col)
        if l2 < t - 1e-9:
            raise self.alarm(f"chamfer/round {kind}{size:g} is longer than the next segment "
                             f"({l2:.3f} mm; needs {t:.3f})", line, col)
        (bx, bz), (cx_, cz_) = k.start, k.end
        saveF, saveop = self.F, self.op
        self.F = F
        self.op = "G01"
        self._emit_line(False, ax, az, bx, bz, line)
        if kind == "C":
            self._emit_line(False, bx, bz, cx_, cz_, line)
        else:
            self._emit_arc(bx, bz, cx_, cz_, k.center[0], k.center[1], k.cw, line)
        self.F, self.op = saveF, saveop
        return cx_, cz_

    def _arc(self, b: Blk, w: dict, cw: bool, g53: bool = False):
        x0, z0 = self.x, self.z
        x1, z1 = self._target(b, w, g53)
        if self.corner is not None:
            self._corner_not_followed()
        if self.comp_mode == "start":
            raise self.balarm(b, "tool nose compensation G41/G42 must start on a G00/G01 move, not G02/G03", "G")
        u = self.unit
        R = w.get("R")
        self.op = "G02" if cw else "G03"
        if R is not None:
            R *= u
            chord = _hypot(x1 - x0, z1 - z0)
            if chord < 1e-9:
                raise self.balarm(b, "arc start and end coincide: a full circle needs I/K, not R", "R")
            r = abs(R)
            if r == 0:
                raise self.balarm(b, "value out of range: arc radius R0", "R")
            if r < chord / 2:
                if chord / 2 - r <= _ARC_R_SLACK:
                    R = math.copysign(chord / 2, R)
                else:
                    raise self.balarm(b, f"arc radius R{r:g} too small for the chord: at least "
                                         f"{chord / 2:.4f} needed", "R")
            a = Arc.from_radius((x0, z0), (x1, z1), R, cw)
            cx, cz = a.center
        else:
            I = w.get("I")
            K = w.get("K")
            if I is None and K is None:
                raise self.balarm(b, f"missing required word: G0{2 if cw else 3} needs R or I/K", "G")
            cx = x0 + (I or 0.0) * u
            cz = z0 + (K or 0.0) * u
            r0 = _hypot(x0 - cx, z0 - cz)
            if r0 < 1e-9:
                raise self.balarm(b, "arc centre on the start point (I/K zero)", "I" if I is not None else "K")
            r1 = _hypot(x1 - cx, z1 - cz)
            if abs(r1 - r0) > _ARC_END_TOL:
                raise self.balarm(b, f"arc end not on the circle: radius {r0:.4f} at the start, "
                                     f"{r1:.4f} at the end", "I" if I is not None else "K")
            if _hypot(x1 - x0, z1 - z0) < 1e-9:
                # full circle: two half arcs
                mx, mz = 2 * cx - x0, 2 * cz - z0
                self._emit_arc(x0, z0, mx, mz, cx, cz, cw, b.line)
                self._emit_arc(mx, mz, x1, z1, cx, cz, cw, b.line)
                self.x, self.z = x1, z1
                return None
        self.x, self.z = x1, z1
        self._emit_arc(x0, z0, x1, z1, cx, cz, cw, b.line)
        return None

    def _dwell(self, b: Blk, w: dict) -> None:
        p = w.get("P")
        if p is None:
            p = w.get("X")
        if p is None:
            raise self.balarm(b, "missing required word: G04 needs P (seconds)", "G")
        if p < 0:
            raise self.balarm(b, f"value out of range: dwell P{p:g} is negative", "P")
        if self.corner is not None:
            self._corner_not_followed()
        self.last_g00 = 4
        if self.dry is not None:
            return
        self._flush_comp()  # the dwell happens after the buffered moves
        if len(self.moves) >= self.move_limit:
            self._too_many_moves(b.line)
        x, z = self._comp_point()
        x, z = x + self.tdx, z + self.tdz
        self.moves.append(Move("dwell", (x, z), (x, z), b.line, None, None, None, self.tool, self.reg,
                               self._rpm(self.x), self.sdir, self.coolant, float(p), 0.0, 0.0, 0.0,
                               "G04", self.comp))

    def _nonmodal(self, b: Blk, g: int, w: dict) -> None:
        if self.corner is not None and g in (28, 29):
            self._corner_not_followed()
        if g == 92:
            if "U" in w or "W" in w:
                raise self.balarm(b, "G92 takes absolute X/Z, not U/W", "U" if "U" in w else "W")
            if not b.axes:
                raise self.balarm(b, "missing required word: G92 needs X and/or Z", "G")
            u = self.unit
            if "X" in w:
                nx = w["X"] * (0.5 * u if self.diam else u)
                self.g92x += self.x - nx
                self.ox += self.x - nx
                self.x = nx
            if "Z" in w:
                nz = w["Z"] * u
                self.g92z += self.z - nz
                self.oz += self.z - nz
                self.z = nz
        elif g == 52:
            u = self.unit
            if "U" in w or "W" in w:
                raise self.balarm(b, "G52 takes X/Z, not U/W", "U" if "U" in w else "W")
            if "X" in w:
                self.g52x = w["X"] * (0.5 * u if self.diam else u)
            if "Z" in w:
                self.g52z = w["Z"] * u
            self._set_origin()
        elif g == 28:
            if not b.axes:
                raise self.balarm(b, "missing required word: G28 needs X/Z (intermediate point)", "G")
            self._flush_comp("G28", b.line)
            tx, tz = self._target(b, w)
            hx = "X" in w or "U" in w
            hz = "Z" in w or "W" in w
            self.g28 = (tx if hx else None, tz if hz else None)
            self.op = "G28"
            x0, z0 = self.x, self.z
            self.x, self.z = (tx if hx else x0), (tz if hz else z0)
            self._emit_line(True, x0, z0, self.x, self.z, b.line)
            rx, rz = self.m.reference
            x0, z0 = self.x, self.z
            self.x = rx - self.ox if hx else x0
            self.z = rz - self.oz if hz else z0
            self._emit_line(True, x0, z0, self.x, self.z, b.line)
        elif g == 29:
            if self.g28 is None:
                raise self.balarm(b, "G29 without a previous G28 (no intermediate point)", "G")
            if not b.axes:
                raise self.balarm(b, "missing required word: G29 needs X/Z", "G")
            self._flush_comp("G29", b.line)
            ix, iz = self.g28
            ix = self.x if ix is None else ix
            iz = self.z if iz is None else iz
            # U/W are relative to the intermediate point
            save = self.x, self.z
            self.x, self.z = ix, iz
            tx, tz = self._target(b, w)
            self.x, self.z = save
            hx = "X" in w or "U" in w
            hz = "Z" in w or "W" in w
            self.op = "G29"
            x0, z0 = self.x, self.z
            mx_ = ix if hx else x0
            mz_ = iz if hz else z0
            self._emit_line(True, x0, z0, mx_, mz_, b.line)
            self.x, self.z = (tx if hx else mx_), (tz if hz else mz_)
            self._emit_line(True, mx_, mz_, self.x, self.z, b.line)

    # -- spindle and feed ------------------------------------------------------------------------
    def _rpm(self, x: float) -> float:
        if self.sdir == 5:
            return 0.0
        if not self.css:
            return self.s_rpm
        r = abs(x + self.tdx)
        mx = self.m.max_rpm
        if r < 1e-9:
            return mx
        n = 1000.0 * self.vc / (_TWO_PI * r)
        return mx if n > mx else n

    def _feed(self, rpm: float, line: int, F: Optional[float] = None) -> float:
        if F is None:
            F = self.F
            if F is None:
                self.warn(line, f"feed move before any F: using the machine's default feed "
                                f"{self.m.default_feed:g} mm/min", "nofeed")
                return self.m.default_feed
        if self.per_rev:
            if rpm <= 0:
                self.warn(line, f"feed per revolution ({self._g_named('per_rev', True, 95)}) with the "
                                f"spindle stopped or at S0: the move cannot run; time counted as 0",
                          ("g95", line))
                return 0.0
            return F * rpm
        if F <= 0:
            raise self.alarm("feed rate F is 0: a feed move needs a positive F", line)
        return F

    # -- emission ----------------------------------------------------------------------------------
    def _emit_line(self, rapid: bool, x0: float, z0: float, x1: float, z1: float, line: int,
                   F: Optional[float] = None) -> None:
        dx = x1 - x0
        dz = z1 - z0
        if -1e-9 < dx < 1e-9 and -1e-9 < dz < 1e-9:
            return
        if self.dry is not None:
            self.dry.append((Line((x0, z0), (x1, z1)), line, "rapid" if rapid else "feed"))
            return
        if self.comp_mode:
            self._comp_add(Line((x0, z0), (x1, z1)), "rapid" if rapid else "feed", line, F)
            return
        if len(self.moves) >= self.move_limit:
            self._too_many_moves(line)
        tdx = self.tdx
        tdz = self.tdz
        if rapid:
            self._rapid_moves(x0 + tdx, z0 + tdz, x1 + tdx, z1 + tdz, dx, dz, line)
            return
        L = _hypot(dx, dz)
        rpm = self._rpm((x0 + x1) * 0.5) if self.sdir != 5 else 0.0
        f = self._feed(rpm, line, F) if (F is not None or self.F is None or self.per_rev) else self.F
        if f <= 0 and not self.per_rev:
            raise self.alarm("feed rate F is 0: a feed move needs a positive F", line)
        if f > 0 and rpm > 0 and self.css and self.per_rev and (F is not None or self.F is not None):
            t = self._css_time(L, f / rpm, lambda u: x0 + (x1 - x0) * u)
        else:
            t = L / f * 60.0 if f > 0 else 0.0
        self.moves.append(Move("line", (x0 + tdx, z0 + tdz), (x1 + tdx, z1 + tdz), line, f, None, None,
                               self.tool, self.reg, rpm, self.sdir, self.coolant,
                               t, 0.0, 0.0, 0.0, self.op, self.comp))

    def _too_many_moves(self, line: int):
        raise self.alarm(f"too many moves: the toolpath reaches the machine's limit of {self.move_limit} "
                         f"moves ([limits] moves): an endless loop? (raise the limit in the machine "
                         f"file for a program this long)", line)

    def _css_time(self, L: float, f_rev: float, x_at) -> float:
        """Seconds for a G96 + G95 feed move of length ``L`` at ``f_rev`` mm/rev whose
        radius at fraction u is ``x_at(u)``: the spindle speed (and so the feed) changes
        along the move, time = integral of ds / (f_rev * n(r)), by Simpson's rule over 16
        intervals (exact for lines away from the rpm clamp, where 1/n is linear in r)."""
        n = 16
        acc = 0.0
        for i in range(n + 1):
            rpm = self._rpm(x_at(i / n))
            if rpm <= 0:
                return 0.0
            acc += (1 if i == 0 or i == n else 4 if i % 2 else 2) / rpm
        return L * acc / (3 * n) / f_rev * 60.0

    def _rapid_moves(self, x0, z0, x1, z1, dx, dz, line) -> None:
        m = self.m
        tx = abs(dx) / m.rapid_x
        tz = abs(dz) / m.rapid_z
        rpm = self._rpm(x1 - self.tdx) if self.sdir != 5 else 0.0
        mv = self.moves
        if tx == 0.0 or tz == 0.0 or abs(tx - tz) <= 1e-12 * (tx + tz):
            mv.append(Move("rapid", (x0, z0), (x1, z1), line, None, None, None, self.tool, self.reg,
                           rpm, self.sdir, self.coolant, (tx if tx > tz else tz) * 60.0, 0.0, 0.0, 0.0,
                           self.op, self.comp))
            return
        if tx < tz:
            xm = x1
            zm = z0 + math.copysign(m.rapid_z * tx, dz)
            t1, t2 = tx, tz - tx
        else:
            zm = z1
            xm = x0 + math.copysign(m.rapid_x * tz, dx)
            t1, t2 = tz, tx - tz
        mv.append(Move("rapid", (x0, z0), (xm, zm), line, None, None, None, self.tool, self.reg,
                       rpm, self.sdir, self.coolant, t1 * 60.0, 0.0, 0.0, 0.0, self.op, self.comp))
        mv.append(Move("rapid", (xm, zm), (x1, z1), line, None, None, None, self.tool, self.reg,
                       rpm, self.sdir, self.coolant, t2 * 60.0, 0.0, 0.0, 0.0, self.op, self.comp))

    def _emit_arc(self, x0, z0, x1, z1, cx, cz, cw, line, F: Optional[float] = None) -> None:
        if self.dry is not None:
            self.dry.append((Arc((x0, z0), (x1, z1), (cx, cz), cw), line, "feed"))
            return
        if self.comp_mode:
            self._comp_add(Arc((x0, z0), (x1, z1), (cx, cz), cw), "feed", line, F)
            return
        if len(self.moves) >= self.move_limit:
            self._too_many_moves(line)
        r = _hypot(x0 - cx, z0 - cz)
        a0 = _atan2(x0 - cx, z0 - cz)
        a1 = _atan2(x1 - cx, z1 - cz)
        s = a1 - a0
        if cw:
            while s >= -1e-9:
                s -= _TWO_PI
            while s < -_TWO_PI:
                s += _TWO_PI
        else:
            while s <= 1e-9:
                s += _TWO_PI
            while s > _TWO_PI:
                s -= _TWO_PI
        L = abs(s) * r
        if self.sdir != 5:
            rpm = self._rpm(cx + r * math.sin(a0 + s * 0.5)) if self.css else self.s_rpm
        else:
            rpm = 0.0
        f = self._feed(rpm, line, F) if (F is not None or self.F is None or self.per_rev) else self.F
        if f <= 0 and not self.per_rev:
            raise self.alarm("feed rate F is 0: a feed move needs a positive F", line)
        if f > 0 and rpm > 0 and self.css and self.per_rev and (F is not None or self.F is not None):
            t = self._css_time(L, f / rpm, lambda u: cx + r * math.sin(a0 + s * u))
        else:
            t = L / f * 60.0 if f > 0 else 0.0
        tdx = self.tdx
        tdz = self.tdz
        self.moves.append(Move("arc", (x0 + tdx, z0 + tdz), (x1 + tdx, z1 + tdz), line, f,
                               (cx + tdx, cz + tdz), cw, self.tool, self.reg, rpm, self.sdir,
                               self.coolant, t, 0.0, 0.0, 0.0, self.op, self.comp))

    def _emit_thread(self, x0, z0, x1, z1, lead, angle, thread_angle, line) -> None:
        if self.dry is not None:
            raise self.alarm("a thread move inside the profile of a compound cycle", line)
        L = _hypot(x1 - x0, z1 - z0)
        if L < 1e-9:
            return
        if len(self.moves) >= self.move_limit:
            self._too_many_moves(line)
        rpm = self._rpm((x0 + x1) * 0.5)
        if rpm <= 0:
            self.warn(line, "thread cut with the spindle stopped: time counted as 0", ("thr", line))
        f = lead * rpm
        tdx, tdz = self.tdx, self.tdz
        self.moves.append(Move("thread", (x0 + tdx, z0 + tdz), (x1 + tdx, z1 + tdz), line, f, None, None,
                               self.tool, self.reg, rpm, self.sdir, self.coolant,
                               L / f * 60.0 if f > 0 else 0.0, float(lead), float(angle),
                               float(thread_angle), self.op, self.comp))

    # -- tool nose radius compensation -----------------------------------------------------------
    def _comp_command(self, b: Blk, g: int) -> None:
        if g == 40:
            if b.axes and self.motion in (2, 3) and self.dry is None:
                raise self.balarm(b, "tool nose compensation must be cancelled (G40) on a G00/G01 "
                                     "move, not G02/G03", "G")
            if self.comp_mode == "start" and not self.comp_items:
                self.comp_mode = ""  # G41/G42 never moved: nothing to cancel
            elif self.comp_mode:
                self.comp_mode = "cancel"
            self.comp = 40
            return
        # G41/G42 (possibly switching sides, or after a G40 still waiting for its move:
        # finish the old buffer first)
        if self.comp != 40 or self.comp_mode == "cancel":
            self._flush_comp()
        self.comp = g
        if self.dry is not None:
            return
        m = self.motion
        if b.axes and m in (2, 3):
            raise self.balarm(b, "tool nose compensation G41/G42 must start on a G00/G01 move, "
                                 "not G02/G03", "G")
        reg = self._register(self.reg) if self.reg else None
        if reg is None or reg.radius <= 0:
            self.comp_mode = ""  # radius 0: the programmed path is the controlled point path
            self.comp_items = []  # (no seam to continue)
            return
        if _missing("hnc_cam.nc.compensation"):
            raise self.balarm(b, "G41/G42 not yet supported (tool nose compensation module "
                                 "missing)", "G")
        self.comp_mode = "start"

    def _comp_add(self, seg, kind: str, line: int, F: Optional[float]) -> None:
        from .compensation import CompItem
        if len(self.comp_items) + len(self.moves) >= self.move_limit:
            self._too_many_moves(line)
        mode = self.comp_mode
        if mode == "start":
            self.comp_mode = "normal"
        payload = (self.op, F, self.F, self.per_rev, self.css, self.s_rpm, self.vc, self.sdir,
                   self.coolant, self.tool, self.reg, self.tdx, self.tdz, self.comp)
        self.comp_items.append(CompItem(seg, kind, line, mode, payload))
        if mode == "cancel":
            self.comp_mode = ""
            self._flush_comp()

    def _flush_comp(self, seam: str = "", line: int = 0) -> None:
        """Compensate and emit the buffered run. Flushed in the middle of compensation (G04,
        T, M98/M99, G41<->G42, program end) the run leaves a 'lead' item so that the next run
        continues from where this one stopped (a seam, see hnc_cam.nc.compensation);
        ``seam == "cycle"``: a temporary cancel (back to the programmed point on ``line``; the
        cycle restarts compensation after it); G28/G29 under compensation alarm (the manual:
        cancel compensation before G28)."""
        if seam in ("G28", "G29") and self.comp_mode in ("start", "normal") and self.dry is None:
            raise self.alarm(f"cancel tool nose radius compensation (G40) before {seam} (the "
                             f"manual, G28: compensation must be cancelled first)", line)
        items = self.comp_items
        if not items or self.dry is not None:
            return
        # imported here: a program without G41/G42 never loads the offsetting code
        from .compensation import CompItem, compensate_moves
        self.comp_items = []
        run = [it for it in items if it.mode != "lead"]
        if not run:
            if seam == "cycle" and items[0].mode == "lead":  # temporary cancel at the seam
                cm, self.comp_mode = self.comp_mode, ""
                try:
                    self._emit_line(True, items[0].at[0], items[0].at[1], self.x, self.z, line)
                finally:
                    self.comp_mode = cm
            else:
                self.comp_items = items  # nothing moved since: the seam stays pending
            return
        if items[0].mode == "lead":  # continues a run flushed in the middle (a seam)
            run[0].seam = (items[0].seg, items[0].at, items[0].line)
        items = run
        # flushed mid-compensation (or with a G40 waiting for its move)
        cont = self.comp_mode in ("normal", "cancel") and run[-1].mode != "cancel"
        if cont and seam == "cycle":
            e = run[-1].seg.end
            items = run + [CompItem(Line(e, e), "rapid", line or run[-1].line, "cancel",
                                    run[-1].payload)]
        p0 = run[0].payload
        reg = self._register(p0[10]) if p0[10] else None
        radius = reg.radius if reg else 0.0
        tip = reg.tip if reg else 0
        side = p0[13]
        try:
            out = compensate_moves(items, radius, tip, side)
        except NCError as e:
            if not e.block and e.line:
                e.block = self.src.block_text(e.line)
            if e.file == "<program>":
                e.file = self.src.file
            raise
        save = (self.op, self.F, self.per_rev, self.css, self.s_rpm, self.vc, self.sdir, self.coolant,
                self.tool, self.reg, self.tdx, self.tdz, self.comp, self.comp_mode)
        self.comp_mode = ""
        try:
            for seg, it in out:
                (self.op, F, self.F, self.per_rev, self.css, self.s_rpm, self.vc, self.sdir,
                 self.coolant, self.tool, self.reg, self.tdx, self.tdz, self.comp) = it.payload
                if isinstance(seg, Arc):
                    if it.kind == "rapid":  # a corner arc handed to a rapid: at the slower rapid rate
                        self.per_rev = False
                        F = min(self.m.rapid_x, self.m.rapid_z)
                    self._emit_arc(seg.start[0], seg.start[1], seg.end[0], seg.end[1],
                                   seg.center[0], seg.center[1], seg.cw, it.line, F)
                else:
                    self._emit_line(it.kind == "rapid", seg.start[0], seg.start[1], seg.end[0],
                                    seg.end[1], it.line, F)
        finally:
            (self.op, self.F, self.per_rev, self.css, self.s_rpm, self.vc, self.sdir, self.coolant,
             self.tool, self.reg, self.tdx, self.tdz, self.comp, self.comp_mode) = save
        for it in items:
            for msg in getattr(it, "notes", ()):
                self.warn(it.line, msg)
        if cont and seam != "cycle" and out:
            last = run[-1]
            end = out[-1][0].end
            ctx = last.seg if last.mode == "normal" else Line(end, end)
            self.comp_items = [CompItem(ctx, last.kind, last.line, "lead", last.payload, end)]

    def _comp_point(self) -> tuple[float, float]:
        """Where the controlled point stands (programmed frame): after a run flushed in the
        middle of compensation, the end of its compensated path, else the programmed point."""
        items = self.comp_items
        if items and items[0].mode == "lead":
            return items[0].at
        return self.x, self.z

    # -- cycles ----------------------------------------------------------------------------------
    def _cycle_table(self) -> dict:
        """The dialect's cycle table, loaded on first use ({} when its module is missing)."""
        table = self.cycles
        if table is None:
            try:
                table = dict(self.dialect.cycle_table())
            except ImportError:
                table = {}
            self.cycles = table
        return table

    def _cycle(self, code: int, b: Blk, w: dict):
        if self.dry is not None:
            raise self.balarm(b, f"cycle G{code} inside the profile of a compound cycle", "G")
        if self.corner is not None:
            self._corner_not_followed()
        if self.unit != 1.0:
            raise self.balarm(b, f"G{code} in G20 (inch) is not supported: program cycles in mm (G21)", "G")
        self._flush_comp("cycle", b.line)
        words = {k: v for k, v in w.items() if k not in ("S", "T")}
        if code in self.modal_cycles:
            if self.cyc_code == code:
                merged = dict(self.cyc_words)
                for ab, inc in (("X", "U"), ("Z", "W")):  # a new X drops the kept U, and so on
                    if ab in words:
                        merged.pop(inc, None)
                    if inc in words:
                        merged.pop(ab, None)
                merged.update(words)
                words = merged
            self.cyc_code = code
            self.cyc_words = words
        table = self._cycle_table()
        if not table:
            raise self.balarm(b, f"G{code} not yet supported ({self.dialect.title} cycle module "
                                 f"missing)", "G")
        handler = table.get(code)
        if handler is None:
            raise self.balarm(b, f"G{code:02d} is not a cycle of {self.dialect.title}", "G")
        ctx = CycleCtx(self, code, b, words)
        save_motion = self.motion
        save_comp = self.comp_mode
        self.comp_mode = ""  # cycle moves are emitted as the cycle computes them (see module doc)
        try:
            handler(ctx)
        except NCError:
            raise
        except ImportError as e:
            mod = "hnc_cam.nc.cycles_rough" if code in (71, 72, 73) else "hnc_cam.nc.cycles_simple"
            if _missing(mod):
                raise self.balarm(b, f"G{code} not yet supported (cycle module missing)", "G") from None
            raise self.balarm(b, f"internal error in the G{code} cycle: {type(e).__name__}: {e}", "G") from None
        except Exception as e:  # a bug in a cycle module must still give an alarm, not a traceback
            raise self.balarm(b, f"internal error in the G{code} cycle: {type(e).__name__}: {e}", "G") from None
        finally:
            # compensation restarts (type A) with the first move after the cycle; a pending
            # G40 is done (the cycle began with the move back to the programmed point)
            self.comp_mode = {"normal": "start", "cancel": ""}.get(save_comp, save_comp)
        self.motion = save_motion
        if self.resume is not None:
            return 4
        return None

    # -- compound cycle profile (dry run) ------------------------------------------------------
    def profile(self, ns: int, nf: int, b: Blk) -> list:
        src = self.src
        a, e = src.span_of(b.stmt)
        i_ns = i_nf = None
        for i in range(a, e):
            if src.kind[i] == P.HDR:
                continue
            n = _n_of(src.text[i])
            if n is None:
                continue
            if i_ns is None and n == ns:
                i_ns = i
            if i_ns is not None and n == nf:
                i_nf = i
                break
        if i_ns is None:
            raise self.balarm(b, f"profile start block N{ns} (P) not found in this program", "P")
        if i_nf is None:
            raise self.balarm(b, f"profile end block N{nf} (Q) not found after N{ns} in this program", "Q")
        out, letters = self._dry_run(i_ns, i_nf, b, f"N{ns}")
        self.prof_letters = (ns, nf, b.stmt, letters)
        return out

    def dry_run(self, i_ns: int, i_nf: int, b: Blk) -> list:
        """The statements ``i_ns``..``i_nf`` dry-run as a profile (:meth:`profile` by statement
        index: a dialect's contour subprogram)."""
        src = self.src
        n = _n_of(src.text[i_ns])
        return self._dry_run(i_ns, i_nf, b, f"N{n}" if n is not None else f"on line {src.lineno[i_ns]}")[0]

    def _dry_run(self, i_ns: int, i_nf: int, b: Blk, first: str) -> tuple[list, list]:
        src = self.src
        snap = [getattr(self, k) for k in self._STATE]
        snap_ms = ModalState.of(self)
        snap_cw = dict(self.cyc_words)
        blocks = self.blocks
        self.dry = []
        self.comp_mode = ""
        self.corner = None
        letters = []
        try:
            for i in range(i_ns, i_nf + 1):
                k = src.kind[i]
                if k != P.OTHER:
                    raise src.alarm("macro statements (IF/WHILE) inside the profile of a compound cycle "
                                    "are not supported", i, 1)
                c = self.compiled[i]
                if c is None:
                    c = self.compiled[i] = self._compile(i)
                if c.__class__ is not Blk:
                    raise src.alarm("assignments inside the profile of a compound cycle are not supported", i, 1)
                if any(m in (98, 99) for m in c.ms) or 65 in c.gs:
                    raise self.balarm(c, "M98/M99 inside the profile of a compound cycle", "M")
                letters.append((c.line, c.letters))
                r = self._block(c)
                if r == 3:
                    raise self.balarm(c, "M02/M30 inside the profile of a compound cycle", "M")
                if i == i_ns and self.motion not in (0, 1):
                    raise self.balarm(c, f"the first profile block {first} must be G00 or G01", "G")
            if self.corner is not None:
                self._corner_not_followed()
            out = self.dry
        finally:
            self.dry = None
            for k, v in zip(self._STATE, snap):
                setattr(self, k, v)
            snap_ms.apply(self)
            self.cyc_words = snap_cw
            self.blocks = blocks
        return out, letters


def _missing(module: str) -> bool:
    """True when ``module`` does not exist (a part of the interpreter not written yet)."""
    import importlib.util
    try:
        return importlib.util.find_spec(module) is None
    except (ImportError, ValueError):
        return True


def _n_of(text: str) -> Optional[int]:
    t = text.lstrip()
    if not t.startswith("N"):
        return None
    i = 1
    while i < len(t) and t[i] == " ":
        i += 1
    j = i
    while j < len(t) and t[j].isdigit():
        j += 1
    return int(t[i:j]) if j > i else None


class CycleCtx:
    """The :class:`~hnc_cam.nc.context.CycleContext` the interpreter gives a cycle."""

    def __init__(self, it: Interp, code: int, b: Blk, words: dict):
        self._it = it
        self._b = b
        self._w = words
        self.code = code
        #: the cycle's name: the label of its moves (``G71``; a SINUMERIK cycle ``LCYC95``)
        self.name = f"G{code}"
        self.line = b.line
        self.incremental = not it.absolute
        self.diameter_mode = it.diam

    @property
    def pos(self):
        return (self._it.x, self._it.z)

    def word(self, letter: str):
        return self._w.get(letter.upper())

    def has(self, letter: str) -> bool:
        return letter.upper() in self._w

    def alarm(self, message: str, letter: Optional[str] = None):
        raise self._it.balarm(self._b, message, letter.upper() if letter else None)

    def warn(self, message: str) -> None:
        self._it.warn(self.line, message)

    def profile(self, ns: int, nf: int):
        return self._it.profile(int(ns), int(nf), self._b)

    def profile_letters(self, ns: int, nf: int) -> list:
        """The letters written in each block N``ns``..N``nf`` of the profile, in file order:
        [(source line, frozenset of letters)] (a FANUC G71/G72 tells type I from type II by
        the axis words of block ns). Dry-runs the profile unless :meth:`profile` just did."""
        it = self._it
        got = getattr(it, "prof_letters", None)
        if got is None or got[:3] != (int(ns), int(nf), self._b.stmt):
            it.profile(int(ns), int(nf), self._b)
            got = it.prof_letters
        return list(got[3])

    # -- SINUMERIK 802 cycles: R parameters, text variables, contour subprograms, plane, tool
    def r(self, n: int) -> float:
        """R parameter ``n`` (0.0 when never written)."""
        return self._it.r(n)

    def set_r(self, n: int, value: float) -> None:
        self._it.set_r(n, value)

    def text(self, name: str) -> Optional[str]:
        """A string variable (``_CNAME``), None when never assigned."""
        return self._it.texts.get(name.upper())

    def contour(self, name: str) -> list:
        """The subprogram ``name`` dry-run as a profile (the value of :meth:`profile`)."""
        return self._it.contour(str(name).upper(), self._b)

    @property
    def plane(self) -> int:
        return getattr(self._it, "plane", 18)

    def tool_nose(self) -> tuple:
        """(nose radius, tip direction) of the active tool edge; (0.0, 0) without one."""
        return self._it.tool_nose()

    def spindle(self, m: int) -> None:
        """Turn the spindle as M``m`` would (3 cw, 4 ccw, 5 stop) for the cycle's next moves
        (a tapping cycle reverses it for the way out and stops it after)."""
        if m not in (3, 4, 5):
            self.alarm(f"spindle direction M{m}: 3, 4 or 5 expected")
        self._it.sdir = int(m)

    def _op(self):
        self._it.op = self.name

    def rapid(self, x: float, z: float) -> None:
        it = self._it
        self._op()
        x0, z0 = it.x, it.z
        it.x, it.z = float(x), float(z)
        it._emit_line(True, x0, z0, it.x, it.z, self.line)

    def _f(self, feed):
        if feed is None:
            return None
        return float(feed) * self._it.unit

    def feed(self, x: float, z: float, feed: Optional[float] = None) -> None:
        it = self._it
        self._op()
        x0, z0 = it.x, it.z
        it.x, it.z = float(x), float(z)
        it._emit_line(False, x0, z0, it.x, it.z, self.line, self._f(feed))

    def arc(self, x: float, z: float, center, cw: bool, feed: Optional[float] = None) -> None:
        it = self._it
        self._op()
        x0, z0 = it.x, it.z
        it.x, it.z = float(x), float(z)
        if _hypot(it.x - x0, it.z - z0) < 1e-9:
            return
        it._emit_arc(x0, z0, it.x, it.z, float(center[0]), float(center[1]), bool(cw), self.line,
                     self._f(feed))

    def thread(self, x: float, z: float, lead: float, angle: float = 0.0, thread_angle: float = 0.0) -> None:
        it = self._it
        self._op()
        x0, z0 = it.x, it.z
        it.x, it.z = float(x), float(z)
        it._emit_thread(x0, z0, it.x, it.z, lead, angle, thread_angle, self.line)

    @property
    def store(self) -> dict:
        """One dict per run, kept across blocks (a cycle's first-block values)."""
        return self._it.store

    def setting(self, key: str, default):
        """A parameter of the machine file's ``[parameters]`` table, else ``default``."""
        return self._it.params.get(key, default)

    def resume_after(self, nf: int) -> None:
        """After this cycle, execution continues with the statement after block N ``nf``
        (of the current program; searched forward from the cycle block)."""
        it = self._it
        i = it.src.find_label(int(nf), it.cur_span, self._b.stmt + 1) if hasattr(it.src, "find_label") \
            else None
        if i is None:
            self.alarm(f"block N{int(nf)} (Q) not found in this program", "Q")
        it.resume = i + 1

    @property
    def max_passes(self) -> int:
        """The machine's limit of passes of one cycle block ([limits] cycle_passes)."""
        return int(getattr(self._it.m, "pass_limit", 10_000))

    @property
    def moves_left(self) -> int:
        """Moves the toolpath may still take before the machine's [limits] moves."""
        it = self._it
        return it.move_limit - len(it.moves) - len(it.comp_items)

    def dwell(self, seconds: float) -> None:
        it = self._it
        if len(it.moves) >= it.move_limit:
            it._too_many_moves(self.line)
        x, z = it.x + it.tdx, it.z + it.tdz
        it.moves.append(Move("dwell", (x, z), (x, z), self.line, None, None, None, it.tool, it.reg,
                             it._rpm(it.x), it.sdir, it.coolant, float(seconds), 0.0, 0.0, 0.0,
                             self.name, it.comp))


# ------------------------------------------------------------------------------------------
# API
# ------------------------------------------------------------------------------------------

def run(text: str, machine: Machine | None = None, *, file: str = "<program>",
        step_limit: int | None = None, start: tuple[float, float] | str = "reference",
        diameter: bool | None = None, dialect: Any = None, persist: str | None = None) -> Toolpath:
    """Interpret program ``text`` and return its toolpath; raises :class:`NCError` on an alarm.

    ``step_limit`` (default: the machine's) bounds the statements executed; the machine's
    ``[limits]`` bound the moves, subprogram runs, cycle passes, text size and line length.
    ``start`` is the initial work position (x radius, z); the default ``"reference"`` is the
    machine's reference point, as after homing (what ``hnc-cam run`` and ``simulate`` use), so
    the API and the command give the same toolpath and cycle time; pass ``start=(0, 0)`` to
    start on the work zero. ``diameter`` is the power-on G36/G37 state (default: the
    machine's ``diameter_mode`` when it has one, else G36). ``dialect`` is a name of
    :func:`hnc_cam.dialect.names` or a :class:`~hnc_cam.dialect.Dialect` (default: the machine
    file's ``controller``, else ``hnc21t``); after an alarm of the HNC reader on a file that
    looks like another dialect's, the alarm says which (:func:`hnc_cam.dialect.sniff`).
    ``persist`` (FANUC-family dialects) is a JSON file of the variables kept at power-off
    (``#500``-``#999``, ``{"500": 1.5, ...}``): read before the run when it exists, written
    (whole, or not at all) after it, also when an alarm stops it.

    An alarm's message and block are one printable line: the block is an excerpt of at most
    120 characters, control characters are written as escapes (``\\x1b``)."""
    import gc
    enabled = gc.isenabled()
    gc.disable()  # the run allocates many small objects and no cycles: GC passes only cost time
    try:
        m = machine if machine is not None else load_machine(None)
        limit = int(getattr(m, "program_bytes", 64 * 1024 * 1024))
        if len(text) > limit:
            raise NCError(f"program too large: {len(text)} characters (the machine's limit is {limit}, "
                          f"[limits] program_bytes)", 1, 1, "", file)
        d = _dialect_of(dialect, m, file)
        syntax = d.syntax(calculator=getattr(m, "decimal_point", "standard") == "calculator",
                          block_delete=bool(getattr(m, "block_delete", False)))
        src = syntax.load(text, file, int(getattr(m, "line_chars", 65_536)))
        cls = d.executor() if d.executor is not None else Interp
        it = cls(src, m, step_limit=step_limit, start=start, diameter=diameter, dialect=d)
        if persist is not None:
            if not hasattr(it, "keep"):
                from ..errors import HncError
                raise HncError(f"{persist}: kept macro variables (#500-#999) belong to the FANUC-family "
                               f"dialects; the {d.title} has none")
            it.keep.update(_load_vars(persist))
        try:
            return it.run()
        except NCError as e:
            if d.name == "hnc21t":
                _hint(e, text)
            raise
        finally:
            if persist is not None:
                _save_vars(persist, it.keep)
    except NCError as e:
        _tidy(e)
        raise
    except RecursionError:
        raise NCError("program nested too deeply", 0, 0, "", printable(file, 4096)) from None
    finally:
        if enabled:
            gc.enable()


def _dialect_of(dialect: Any, machine: Machine, file: str):
    """The Dialect value: the one asked for, else the machine's ``controller``, else HNC."""
    from .. import dialect as dialects
    name = dialect if dialect is not None else (getattr(machine, "controller", None) or dialects.DEFAULT)
    try:
        return dialects.get(name)
    except ValueError as e:
        raise NCError(str(e.args[0]), 0, 0, "", file) from None


def _load_vars(path: str) -> dict:
    """The kept variables of a ``persist`` file (absent file: none yet)."""
    import json
    import os
    from ..errors import HncError
    from ..io import read_text
    if not os.path.exists(path):
        return {}
    text = read_text(path, "a JSON file of macro variables", max_bytes=1024 * 1024)
    try:
        data = json.loads(text)
    except ValueError as e:
        raise HncError(f"{path}: not JSON: {e}") from None
    if not isinstance(data, dict):
        raise HncError(f'{path}: must be a JSON object {{"500": value, ...}}')
    out = {}
    for k, v in data.items():
        if not (isinstance(k, str) and k.isdigit() and 500 <= int(k) <= 999):
            raise HncError(f"{path}: {k!r} is not a kept variable number 500-999")
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))
                              or not math.isfinite(v)):
            raise HncError(f"{path}: #{k} = {v!r}: must be a finite number or null")
        out[int(k)] = None if v is None else float(v)
    return out


def _save_vars(path: str, keep: dict) -> None:
    import json
    from ..io import write_atomic
    data = {str(k): keep[k] for k in sorted(keep) if keep[k] is not None}
    try:
        write_atomic(path, json.dumps(data, indent=1) + "\n")
    except OSError as e:
        from ..errors import HncError
        raise HncError(f"cannot write {path}: {e.strerror or e}") from None


def _hint(e: NCError, text: str) -> None:
    """Add to an alarm of the HNC reader which dialect the file looks like, if it does."""
    if "FANUC" in str(e.message):
        return
    from ..dialect import sniff
    h = sniff(text)
    if h:
        e.message = f"{e.message}: {h}"
        e.args = (e.message,)


def _tidy(e: NCError) -> None:
    """Make an alarm one printable line of bounded length (message, block and file name)."""
    e.message = printable(str(e.message), 600)
    e.args = (e.message,)
    e.block = printable(str(e.block).strip())
    e.file = printable(str(e.file), 4096)


class ProgramFileError(NCError):
    """The program file itself cannot be read: no line or column to point at, so the CLI
    line is ``error: FILE: cannot read the program: REASON``, the shape of every other
    unreadable input file (machine, tools, part)."""

    def one_line(self) -> str:
        return f"error: {self.file}: {self.message}"


def run_file(path: str, machine: Machine | None = None, **kw) -> Toolpath:
    """:func:`run` on the file ``path`` (bytes that are not UTF-8 become U+FFFD, which then
    alarm as unexpected characters where they matter); an unreadable file raises
    :class:`ProgramFileError`, and so does a file that is not a regular file (a directory,
    a device such as ``/dev/zero``, a FIFO: never opened, so never waited on) or one larger
    than the machine's ``[limits] program_bytes``."""
    import os
    import stat
    name = printable(str(path), 4096)
    m = machine if machine is not None else load_machine(None)
    limit = int(getattr(m, "program_bytes", 64 * 1024 * 1024))
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode):
            what = ("a directory" if stat.S_ISDIR(st.st_mode) else "a FIFO (named pipe)"
                    if stat.S_ISFIFO(st.st_mode) else "a device" if stat.S_ISCHR(st.st_mode)
                    or stat.S_ISBLK(st.st_mode) else "a socket" if stat.S_ISSOCK(st.st_mode)
                    else "not a regular file")
            raise ProgramFileError(f"cannot read the program: {what}, not a regular file", 0, 0, "", name)
        if st.st_size > limit:
            raise ProgramFileError(f"cannot read the program: {st.st_size} bytes, more than the "
                                   f"machine's limit of {limit} ([limits] program_bytes)", 0, 0, "", name)
        with open(path, "rb") as f:
            data = f.read(limit + 1)
    except OSError as e:
        reason = e.strerror or type(e).__name__
        raise ProgramFileError(f"cannot read the program: {reason}", 0, 0, "", name) from None
    if len(data) > limit:  # grew while we read it
        raise ProgramFileError(f"cannot read the program: more than the machine's limit of {limit} "
                               f"bytes ([limits] program_bytes)", 0, 0, "", name)
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise ProgramFileError("cannot read the program: UTF-16 text (it starts with a byte-order "
                               "mark); save it as ASCII or UTF-8", 0, 0, "", name)
    text = data.decode("utf-8", errors="replace")
    return run(text, m, file=str(path), **kw)
