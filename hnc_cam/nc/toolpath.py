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

import math
import struct
import threading
from array import array
from dataclasses import dataclass, field
from typing import Any, Iterable, Optional
from ..units import fmt_cycle_time

from ..geometry import Arc, Line, Point, Segment

MOVE_KINDS = ("rapid", "line", "arc", "thread", "dwell")


#: the fields of a move, in the order of the constructor's arguments
MOVE_FIELDS = ("kind", "start", "end", "line", "feed", "center", "cw", "tool", "register",
               "spindle", "spindle_dir", "coolant", "duration", "lead", "angle", "thread_angle",
               "op", "comp")
_DEFAULTS = (None, None, 0, 0, 0.0, 5, False, 0.0, 0.0, 0.0, 0.0, "", 40)  # feed .. comp

# A move's values live in a block of columns shared by up to _BLOCK moves made one after the
# other (floats as C doubles, small integers as C ints): some 170 bytes a move instead of the
# 450 of an object with a float object, a tuple and a slot per value. A block is freed with
# the last move in it.
_BLOCK = 2048
_NF = 12  # doubles: start x z, end x z, feed, center x z, spindle, duration, lead, angle, thread angle
_NI = 6  # ints: line, tool, register, spindle_dir, comp, flags
_KIND_CODE = {k: i for i, k in enumerate(MOVE_KINDS)}
_OP_NAMES: list[str] = [""]
_OP_CODE: dict[str, int] = {"": 0}
# flags: kind (bits 0-3), cw (4-5: 0 None, 1 False, 2 True), coolant (6), feed None (7),
# center None (8), op (9-29)
_INT_MIN, _INT_MAX = -(1 << 31), (1 << 31) - 1


class _Block:
    __slots__ = ("f", "i", "used")

    def __init__(self) -> None:
        self.f = array("d", bytes(8 * _NF * _BLOCK))
        self.i = array("i", bytes(4 * _NI * _BLOCK))
        self.used = 0


_local = threading.local()  # the block being filled, per thread
_PF, _PI = struct.Struct(f"{_NF}d"), struct.Struct(f"{_NI}i")
_SF, _SI = _PF.size, _PI.size
_INDEX = tuple(range(_BLOCK))  # one int object per index, shared by the moves


def _op_code(op: str) -> int:
    c = _OP_CODE.get(op)
    if c is None:
        if not isinstance(op, str) or len(_OP_NAMES) >= (1 << 21):
            raise TypeError("op")
        c = _OP_CODE[op] = len(_OP_NAMES)
        _OP_NAMES.append(op)
    return c


class Move:
    """One move of the controlled point (see the module doc). Constructed as
    ``Move(kind, start, end, line, feed=None, center=None, cw=None, tool=0, register=0,
    spindle=0.0, spindle_dir=5, coolant=False, duration=0.0, lead=0.0, angle=0.0,
    thread_angle=0.0, op="", comp=40)``; every field is a readable and writable attribute:

    ``kind`` rapid | line | arc | thread | dwell; ``start``/``end`` (x radius, z); ``line``
    1-based source line; ``feed`` mm/min (None for rapid and dwell); ``center`` (arcs only);
    ``cw`` (arcs only, G02 = True); ``tool`` tool number tt of the active T word;
    ``register`` offset register oo; ``spindle`` rpm actually turning (0 = stopped), G96
    resolved; ``spindle_dir`` 3 cw, 4 ccw, 5 stopped; ``coolant``; ``duration`` seconds;
    ``lead`` thread lead (mm/rev); ``angle`` spindle start angle of a thread pass (deg);
    ``thread_angle`` tool profile angle of the thread cycle (G76 A, deg; 0 = unknown); ``op``
    what produced it (G00 G01 G02 G03 G32 G80 G81 G82 G71 G72 G73 G76 ...); ``comp`` 40/41/42
    active when the move was made.

    Moves compare equal when all their fields do. Coordinates and the other real values are
    kept as C doubles (read back as Python floats), the integers as C ints; a move whose
    values do not fit (an integer beyond 32 bits, a value of another type) keeps them as
    given."""

    __slots__ = ("_b", "_k")

    def __init__(self, kind, start, end, line, feed=None, center=None, cw=None, tool=0,
                 register=0, spindle=0.0, spindle_dir=5, coolant=False, duration=0.0, lead=0.0,
                 angle=0.0, thread_angle=0.0, op="", comp=40):
        try:
            if (type(line) is not int or type(tool) is not int or type(register) is not int
                    or type(spindle_dir) is not int or type(comp) is not int
                    or type(coolant) is not bool or not (cw is None or type(cw) is bool)):
                raise TypeError("type")
            oc = _OP_CODE.get(op)
            if oc is None:
                oc = _op_code(op)
            flags = (_KIND_CODE[kind] | (0 if cw is None else 2 if cw else 1) << 4
                     | (64 if coolant else 0) | (128 if feed is None else 0)
                     | (256 if center is None else 0) | oc << 9)
            blk = getattr(_local, "block", None)
            if blk is None or blk.used >= _BLOCK:
                blk = _local.block = _Block()
            k = blk.used
            blk.used = k + 1
            if center is None:
                _PF.pack_into(blk.f, k * _SF, start[0], start[1], end[0], end[1],
                              0.0 if feed is None else feed, 0.0, 0.0, spindle, duration, lead,
                              angle, thread_angle)
            else:
                _PF.pack_into(blk.f, k * _SF, start[0], start[1], end[0], end[1],
                              0.0 if feed is None else feed, center[0], center[1], spindle,
                              duration, lead, angle, thread_angle)
            _PI.pack_into(blk.i, k * _SI, line, tool, register, spindle_dir, comp, flags)
        except (KeyError, TypeError, ValueError, IndexError, OverflowError, struct.error):
            self._b = None
            self._k = [kind, start, end, line, feed, center, cw, tool, register, spindle,
                       spindle_dir, coolant, duration, lead, angle, thread_angle, op, comp]
            return
        self._b, self._k = blk, _INDEX[k]

    def _set(self, n: int, v) -> None:
        """Set field n: kept in the block when it fits, else the move keeps its values as
        given from now on."""
        if self._b is None:
            self._k[n] = v
            return
        vals = [getattr(self, f) for f in MOVE_FIELDS]
        vals[n] = v
        Move.__init__(self, *vals)

    @property
    def kind(self) -> str:
        b = self._b
        if b is None:
            return self._k[0]
        return MOVE_KINDS[b.i[self._k * _NI + 5] & 15]

    @property
    def start(self) -> Point:
        b = self._b
        if b is None:
            return self._k[1]
        f, j = b.f, self._k * _NF
        return (f[j], f[j + 1])

    @property
    def end(self) -> Point:
        b = self._b
        if b is None:
            return self._k[2]
        f, j = b.f, self._k * _NF
        return (f[j + 2], f[j + 3])

    @property
    def line(self) -> int:
        b = self._b
        return self._k[3] if b is None else b.i[self._k * _NI]

    @property
    def feed(self) -> Optional[float]:
        b = self._b
        if b is None:
            return self._k[4]
        k = self._k
        return None if b.i[k * _NI + 5] & 128 else b.f[k * _NF + 4]

    @property
    def center(self) -> Optional[Point]:
        b = self._b
        if b is None:
            return self._k[5]
        k = self._k
        if b.i[k * _NI + 5] & 256:
            return None
        return (b.f[k * _NF + 5], b.f[k * _NF + 6])

    @property
    def cw(self) -> Optional[bool]:
        b = self._b
        if b is None:
            return self._k[6]
        c = (b.i[self._k * _NI + 5] >> 4) & 3
        return None if c == 0 else c == 2

    @property
    def tool(self) -> int:
        b = self._b
        return self._k[7] if b is None else b.i[self._k * _NI + 1]

    @property
    def register(self) -> int:
        b = self._b
        return self._k[8] if b is None else b.i[self._k * _NI + 2]

    @property
    def spindle(self) -> float:
        b = self._b
        return self._k[9] if b is None else b.f[self._k * _NF + 7]

    @property
    def spindle_dir(self) -> int:
        b = self._b
        return self._k[10] if b is None else b.i[self._k * _NI + 3]

    @property
    def coolant(self) -> bool:
        b = self._b
        return self._k[11] if b is None else bool(b.i[self._k * _NI + 5] & 64)

    @property
    def duration(self) -> float:
        b = self._b
        return self._k[12] if b is None else b.f[self._k * _NF + 8]

    @property
    def lead(self) -> float:
        b = self._b
        return self._k[13] if b is None else b.f[self._k * _NF + 9]

    @property
    def angle(self) -> float:
        b = self._b
        return self._k[14] if b is None else b.f[self._k * _NF + 10]

    @property
    def thread_angle(self) -> float:
        b = self._b
        return self._k[15] if b is None else b.f[self._k * _NF + 11]

    @property
    def op(self) -> str:
        b = self._b
        return self._k[16] if b is None else _OP_NAMES[b.i[self._k * _NI + 5] >> 9]

    @property
    def comp(self) -> int:
        b = self._b
        return self._k[17] if b is None else b.i[self._k * _NI + 4]

    def _values(self) -> tuple:
        return tuple(getattr(self, f) for f in MOVE_FIELDS)

    def __eq__(self, other):
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self._values() == other._values()

    __hash__ = None  # type: ignore[assignment]  (mutable, as a dataclass with eq)

    def __repr__(self) -> str:
        return "Move(" + ", ".join(f"{f}={v!r}" for f, v in zip(MOVE_FIELDS, self._values())) + ")"

    def __reduce__(self):
        return (Move, self._values())

    def __copy__(self) -> "Move":
        return Move(*self._values())

    def __deepcopy__(self, memo) -> "Move":
        return Move(*self._values())

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


def columns(moves) -> dict[str, Any]:
    """The values of ``moves`` (a sequence of :class:`Move`) as numpy columns, read from the
    moves' blocks without making a Python object per value: ``kind`` (int8, the index in
    :data:`MOVE_KINDS`, -1 for another kind), ``start``/``end``/``center`` ((n, 2) x z;
    ``center`` NaN where None), ``feed`` (NaN where None), ``spindle``, ``duration``,
    ``lead``, ``angle``, ``thread_angle`` (float64), ``line``, ``tool``, ``register``,
    ``spindle_dir``, ``comp`` (int64), ``cw`` (int8: -1 None, 0, 1), ``coolant`` (bool).
    numpy is imported here, not with the module (``hnc-cam run`` does without it)."""
    import numpy as np
    n = len(moves)
    F = np.zeros((n, _NF))
    Iv = np.zeros((n, _NI), dtype=np.int64)
    bs = [m._b for m in moves]
    ks = np.fromiter((m._k if m._b is not None else 0 for m in moves), dtype=np.int64, count=n)
    where: dict[int, list] = {}
    wide = []
    for i, b in enumerate(bs):
        if b is None:
            wide.append(i)
            continue
        w = where.get(id(b))
        if w is None:
            where[id(b)] = w = [b, i, i + 1, []]
        if w[2] == i:
            w[2] = i + 1  # extends the block's current run of consecutive moves
        else:
            w[3].append((w[1], w[2]))
            w[1], w[2] = i, i + 1
    for b, r0, r1, runs in where.values():
        f = np.frombuffer(b.f, dtype=np.float64).reshape(-1, _NF)
        iv = np.frombuffer(b.i, dtype=np.int32).reshape(-1, _NI)
        for a0, a1 in [*runs, (r0, r1)]:
            F[a0:a1] = f[ks[a0:a1]]
            Iv[a0:a1] = iv[ks[a0:a1]]
    flags = Iv[:, 5]
    kind = (flags & 15).astype(np.int8)
    cwc = (flags >> 4) & 3
    out = {"kind": kind, "start": F[:, 0:2], "end": F[:, 2:4],
           "feed": np.where(flags & 128, np.nan, F[:, 4]),
           "center": np.where((flags & 256)[:, None] != 0, np.nan, F[:, 5:7]),
           "spindle": F[:, 7], "duration": F[:, 8], "lead": F[:, 9], "angle": F[:, 10],
           "thread_angle": F[:, 11], "line": Iv[:, 0], "tool": Iv[:, 1], "register": Iv[:, 2],
           "spindle_dir": Iv[:, 3], "comp": Iv[:, 4],
           "cw": np.where(cwc == 0, -1, cwc - 1).astype(np.int8), "coolant": (flags & 64) != 0}
    for i in wide:  # values kept as given: through the attributes (floats where they can be)
        m = moves[i]
        out["kind"][i] = _KIND_CODE.get(m.kind, -1) if isinstance(m.kind, str) else -1
        for name in ("start", "end", "center"):
            v = getattr(m, name)
            try:
                out[name][i] = (np.nan, np.nan) if v is None else (float(v[0]), float(v[1]))
            except (TypeError, ValueError, IndexError):
                out[name][i] = (np.nan, np.nan)
        for name in ("feed", "spindle", "duration", "lead", "angle", "thread_angle"):
            try:
                v = getattr(m, name)
                out[name][i] = np.nan if v is None else float(v)
            except (TypeError, ValueError, OverflowError):
                out[name][i] = np.nan
        for name in ("line", "tool", "register", "spindle_dir", "comp"):
            try:
                out[name][i] = int(getattr(m, name))
            except (TypeError, ValueError, OverflowError):
                out[name][i] = 0
        out["cw"][i] = -1 if m.cw is None else int(bool(m.cw))
        out["coolant"][i] = bool(m.coolant)
    return out


def _setter(n: int):
    return lambda self, v: self._set(n, v)


for _n, _f in enumerate(MOVE_FIELDS):
    _p = Move.__dict__[_f]
    setattr(Move, _f, property(_p.fget, _setter(_n), doc=_p.__doc__))
del _n, _f, _p


def _bind_core():
    """The compiled core (``hnc_cam/nc/_core.c``, built by the package's install) bound to
    these column blocks; None when it is not built or ``HNC_CAM_PURE`` is set in the
    environment (then everything runs the Python code, which the core matches bit for bit)."""
    import os
    if os.environ.get("HNC_CAM_PURE"):
        return None
    try:
        from . import _core
    except ImportError:
        return None
    _core.bind(Move, _Block, _local, _INDEX, _NF, _NI, _BLOCK,
               [(op, _op_code(op)) for op in ("G00", "G01", "G02", "G03")], math.hypot)
    return _core


#: the compiled core, or None (pure Python)
core = _bind_core()


def _doubles(data: bytes) -> array:
    return array("d", data)


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
        import json  # here: `hnc-cam run` without --json does without it
        return json.dumps(self.to_json(), indent=None, separators=(",", ":"))

    def _figures(self) -> tuple:
        """(extents, feed length, rapid length, cycle time): from the compiled core when the
        moves are all in column blocks (the same values: the same operations in the same
        order, the sums by Python's ``sum``), else from the properties."""
        moves = self.moves
        if core is not None and moves.__class__ is list and moves:
            r = core.stats(moves, _doubles)
            if r is not None:
                return (r[0], r[1], r[2], r[3]), sum(r[4]), sum(r[5]), sum(r[6])
        return self.extents(), self.feed_length, self.rapid_length, self.cycle_time_s

    def summary(self) -> str:
        (x0, z0, x1, z1), feed, rapid, t = self._figures()
        return (f"{self.file}: {self.blocks_executed} blocks executed, {len(self.moves)} moves, "
                f"feed {feed:.3f} mm, rapid {rapid:.3f} mm, "
                f"cycle time {fmt_cycle_time(t)}, "
                f"X {2 * x0:.3f}..{2 * x1:.3f} (dia), Z {z0:.3f}..{z1:.3f}"
                + (f", {len(self.warnings)} warning(s)" if self.warnings else ""))


def rapid_time(machine_rapid_x: float, machine_rapid_z: float, dx: float, dz: float) -> float:
    """Seconds for a rapid with each axis at its own rate (the slower axis decides)."""
    return max(abs(dx) / machine_rapid_x, abs(dz) / machine_rapid_z) * 60.0


def feed_time(length: float, feed_mm_min: float) -> float:
    return 0.0 if feed_mm_min <= 0 or not math.isfinite(feed_mm_min) else length / feed_mm_min * 60.0
