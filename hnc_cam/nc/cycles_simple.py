"""The simple and threading cycles of the HNC-21/22T: G80, G81, G82, G32 and G76.

Sources: the manual §3.3.3(4) (G32), §3.3.7 (G80/G81/G82, figs. 3.3.15–3.3.23), §3.3.8(4)
(G76, figs. 3.3.36–3.3.38) and appendix 1(2), the controller's own macro implementation of
the cycles (%0080, %0081, %0082, %0076), which is the evidence for pass order and retracts.

Everything goes through the :class:`~hnc_cam.nc.context.CycleContext` of the interpreter:
``ctx.word``/``ctx.has`` read the block's words, ``ctx.pos`` is the cycle start point A
(x radius, z), ``ctx.rapid``/``ctx.feed``/``ctx.thread`` emit the legs. Internally X is a
radius; X words are diameters in G36 (``ctx.diameter_mode``); in G91 the X/Z words of a
cycle are the directed distance from A to the end point C.

Paths (letters of the figures; every cycle except G32 ends back on A)

* ``G80 X Z [I] F`` (figs. 3.3.15/3.3.16): B = (C.x + I, A.z).
  A→B rapid, B→C feed, C→D feed out in X to D = (A.x, C.z), D→A rapid.
* ``G81 X Z [K] F`` (figs. 3.3.18/3.3.19): B = (A.x, C.z + K).
  A→B rapid, B→C feed, C→D feed in Z to D = (C.x, A.z), D→A rapid.
* ``G82 X Z [I] [R E] [C P] F`` (figs. 3.3.21/3.3.22): B = (C.x + I, A.z).
  A→B rapid, B→C thread, [C→C' = C + (E, R) thread run-out], C'→(A.x, C'.z) rapid, →A rapid.
  Multi-start: the whole loop once per start.
* ``G32 X(U) Z(W) [R E] [P] F``: one thread move from the current point to the end point,
  then the run-out leg; no return.
* ``G76 C R E A X Z I K U V Q P F`` (figs. 3.3.36/3.3.37, macro %0076): per pass of depth t,
  A→(A.x − s·t, A.z + h) rapid, → (x_t + I, A.z + h) rapid (the thread start B),
  thread to (x_t, C.z + h) then the run-out leg, then back to A in one rapid (a dog-leg),
  where s = +1 for an outside thread (A outside C), −1 for a bore, x_t = C.x + s·(K − t) and
  h = t·tan(A/2) in the cutting direction (single-flank infeed along the trailing flank).

The motion itself is done by engines shared with the FANUC and Haas decoders
(``hnc_cam.dialect.fanuc0it.cycles``): :func:`turn_legs` (G80/G90), :func:`face_legs`
(G81/G94), :func:`thread_loop` (G82/G92), :func:`thread_passes` with :func:`g76_depths`
and :func:`flank_shifts` (G76); the functions here only decode HNC's words.

Thread moves carry the lead F (mm/rev), the spindle start angle and the tool profile angle
(G76: its A word; G32 and G82: 60°).

Choices where the manual is silent or contradicts itself (also in the README):

1. **Leg types.** G80 C→D is a feed (macro %0080 ``N40 G01``; the text layer of fig. 3.3.15
   labels it "3R"); G81 C→D is a feed (fig. 3.3.18 "3F" and macro). G82's retract and return
   are rapids as fig. 3.3.21 ("3R", "4R"): the macro writes ``G01`` for the X retract, which
   would run at the lead read as mm/min, so it is not followed there.
2. **Run-out R/E.** The X/Z words are the effective thread end C; the run-out is an extra
   spindle-synchronised leg C→C + (E, R). R and E are signed in the absolute axis directions
   (§3.3.3(4): positive = toward +Z/+X), are incremental in G90 and G91 alike, and are
   **radius** values (E is "the thread height", never doubled in G36). A warning is given
   when E points from the thread toward the work (toward −X for an outside thread).
3. **Multi-start G82.** C 0 or 1 (or absent): one start, P is its spindle angle (default 0).
   C 2–99: C starts, start j at angle j·P (mod 360), as the macro does; a multi-start block
   without P cuts every start at angle 0 like the macro, with a warning. Other C: alarm.
4. **G76 depths.** Depths are radius values measured from the crest (x = C.x + s·K at C; the
   X word is the root, as example 3338 shows). Roughing pass n goes to
   t_n = Δd·√n, raised to t_(n−1) + Δdmin when the increment would be smaller (the floor
   applies from the second pass on), until t_n reaches K − d; then one roughing pass lies
   exactly at K − d (it is also the first pass when Δd >= K − d; the step to it may be
   smaller than Δdmin). Then c finishing passes at the full depth K. The macro's text adds d
   to every pass including the finishing ones (so the root would never be reached); we
   follow the manual's definition of d as the finishing allowance instead.
5. **G76 words.** Required as in the macro: A X Z K U V Q F (alarm when missing).
   C default 1 (macro), 0 is read as 1 (the thread must reach its depth), range 0–99.
   R default 0; E default = K outward (macro: ``#4 = #10``); I default 0; P default 0.
   K > 0, Q > 0, V >= 0, 0 <= U < K, F > 0; at most 1000 passes (more is taken for a
   unit mistake and alarmed).
6. **U/W.** U and W may not appear on G80/G81/G82 blocks (manual §3.3.2); on G76 U is the
   finishing allowance, so only W is refused there. G32 takes U/W (incremental X/Z), but no
   chamfer C (§3.3.3(2); its R is the run-out).
7. **Lead.** G32/G82/G76 take the lead from their own F word (G82 keeps it between its
   modal blocks); a G32 block without F is alarmed rather than guessing a modal lead.
"""
from __future__ import annotations

import math
from typing import Any

from ..geometry import Point

#: the tool profile angles G76 accepts (manual §3.3.8(4))
THREAD_ANGLES = (80.0, 60.0, 55.0, 30.0, 29.0, 0.0)
#: tool profile angle recorded on G32/G82 thread moves (metric 60° thread)
DEFAULT_THREAD_ANGLE = 60.0
#: more G76 passes than this is taken for a unit mistake
MAX_G76_PASSES = 1000
_TOL = 1e-9


def execute(code: int, ctx: Any) -> None:
    """Run G``code`` (32, 76, 80, 81 or 82) of the current block through ``ctx``."""
    if code == 80:
        _g80(ctx)
    elif code == 81:
        _g81(ctx)
    elif code == 82:
        _g82(ctx)
    elif code == 32:
        _g32(ctx)
    elif code == 76:
        _g76(ctx)
    else:  # pragma: no cover - cycles.execute dispatches only the codes above
        ctx.alarm(f"G{code:02d} is not a simple or threading cycle")


# --------------------------------------------------------------------------- helpers


class _Legs:
    """Emits legs through the context, tracking the current point; zero-length legs are
    dropped (e.g. A→B when A already lies on B's X)."""

    def __init__(self, ctx: Any, start: Point):
        self.ctx = ctx
        self.at: Point = (float(start[0]), float(start[1]))

    def _moved(self, p: Point) -> bool:
        return abs(p[0] - self.at[0]) > _TOL or abs(p[1] - self.at[1]) > _TOL

    def rapid(self, p: Point) -> None:
        if self._moved(p):
            self.ctx.rapid(p[0], p[1])
            self.at = p

    def feed(self, p: Point) -> None:
        if self._moved(p):
            self.ctx.feed(p[0], p[1])
            self.at = p

    def thread(self, p: Point, lead: float, angle: float, thread_angle: float) -> None:
        if self._moved(p):
            self.ctx.thread(p[0], p[1], lead, angle, thread_angle)
            self.at = p


def _name(ctx: Any) -> str:
    return f"G{int(ctx.code):02d}"


def _refuse_uw(ctx: Any, letters: str = "UW") -> None:
    for letter in letters:
        if ctx.has(letter):
            ctx.alarm(f"{_name(ctx)}: incremental {letter} is not allowed in a cycle block "
                      f"(use G91 with X/Z)", letter)


def _require(ctx: Any, letters: str) -> dict[str, float]:
    out: dict[str, float] = {}
    missing = [c for c in letters if ctx.word(c) is None]
    if missing:
        ctx.alarm(f"{_name(ctx)}: missing word{'s' if len(missing) > 1 else ''} "
                  + " ".join(missing))
    for c in letters:
        out[c] = float(ctx.word(c))
    return out


def _opt(ctx: Any, letter: str, default: float) -> float:
    v = ctx.word(letter)
    return default if v is None else float(v)


def _end_point(ctx: Any, a: Point, xw: float, zw: float) -> Point:
    """End point C from the X/Z words: absolute, or in G91 the distance from A
    (X a diameter in G36 in both forms)."""
    x = xw / 2.0 if ctx.diameter_mode else xw
    if ctx.incremental:
        return (a[0] + x, a[1] + zw)
    return (x, zw)


def _lead(ctx: Any) -> float:
    f = ctx.word("F")
    if f is None:
        ctx.alarm(f"{_name(ctx)}: missing word F (thread lead)", None)
    f = float(f)
    if abs(f) <= _TOL:
        ctx.alarm(f"{_name(ctx)}: thread with lead 0 (F0)", "F")
    if f < 0:
        ctx.alarm(f"{_name(ctx)}: negative thread lead F{f:g}", "F")
    return f


def _int_word(ctx: Any, letter: str, lo: int, hi: int, default: int, what: str) -> int:
    v = ctx.word(letter)
    if v is None:
        return default
    if abs(v - round(v)) > 1e-9 or not lo <= round(v) <= hi:
        ctx.alarm(f"{_name(ctx)}: {what} {letter}{v:g} must be a whole number {lo}..{hi}", letter)
    return int(round(v))


def _runout(ctx: Any, r: float, e: float, s: int) -> None:
    if e * s < -_TOL:
        side = "outside" if s > 0 else "inside"
        ctx.warn(f"{_name(ctx)}: X run-out E{e:g} points into the work for an {side} thread "
                 f"(E is signed: + = toward +X)")


# --------------------------------------------------------------------------- G80 / G81


def turn_legs(ctx: Any, a: Point, c: Point, taper: float = 0.0) -> None:
    """The turning-cycle engine (HNC G80, FANUC G90): from A, B = (C.x + ``taper``, A.z);
    A→B rapid, B→C feed, C→D = (A.x, C.z) feed, D→A rapid (radius x)."""
    legs = _Legs(ctx, a)
    legs.rapid((c[0] + taper, a[1]))  # B
    legs.feed(c)  # C
    legs.feed((a[0], c[1]))  # D
    legs.rapid(a)


def face_legs(ctx: Any, a: Point, c: Point, taper: float = 0.0) -> None:
    """The facing-cycle engine (HNC G81, FANUC G94): from A, B = (A.x, C.z + ``taper``);
    A→B rapid, B→C feed, C→D = (C.x, A.z) feed, D→A rapid."""
    legs = _Legs(ctx, a)
    legs.rapid((a[0], c[1] + taper))  # B
    legs.feed(c)  # C
    legs.feed((c[0], a[1]))  # D
    legs.rapid(a)


def _g80(ctx: Any) -> None:
    """Turning cycle: A→B rapid, B→C feed, C→D feed, D→A rapid (figs. 3.3.15/3.3.16)."""
    _refuse_uw(ctx)
    w = _require(ctx, "XZ")
    a = ctx.pos
    c = _end_point(ctx, a, w["X"], w["Z"])
    turn_legs(ctx, a, c, _opt(ctx, "I", 0.0))


def _g81(ctx: Any) -> None:
    """Facing cycle: A→B rapid, B→C feed, C→D feed, D→A rapid (figs. 3.3.18/3.3.19)."""
    _refuse_uw(ctx)
    w = _require(ctx, "XZ")
    a = ctx.pos
    c = _end_point(ctx, a, w["X"], w["Z"])
    face_legs(ctx, a, c, _opt(ctx, "K", 0.0))


# --------------------------------------------------------------------------- threads


def start_angles(starts: int, p: float) -> list[float]:
    """Spindle start angles of a G82 ``C starts P p``: one start at ``p`` for C 0/1, else
    ``j·p`` (mod 360) for j = 0..C−1."""
    if starts <= 1:
        return [p % 360.0]
    return [(j * p) % 360.0 for j in range(starts)]


def _g82(ctx: Any) -> None:
    """Thread cycle (figs. 3.3.21/3.3.22), once per start of a multi-start thread."""
    _refuse_uw(ctx)
    w = _require(ctx, "XZ")
    lead = _lead(ctx)
    a = ctx.pos
    c = _end_point(ctx, a, w["X"], w["Z"])
    if abs(c[1] - a[1]) <= _TOL:
        ctx.alarm("G82: the thread has no length (Z of the end point equals Z of the start A)", "Z")
    i = _opt(ctx, "I", 0.0)
    r = _opt(ctx, "R", 0.0)
    e = _opt(ctx, "E", 0.0)
    starts = _int_word(ctx, "C", 0, 99, 1, "number of starts")
    if starts >= 2 and ctx.word("P") is None:
        ctx.warn(f"G82: C{starts} without P: every start is cut at spindle angle 0 "
                 f"(give P{360.0 / starts:g} for evenly spaced starts)")
    p = _opt(ctx, "P", 0.0)
    s = 1 if a[0] >= c[0] else -1
    _runout(ctx, r, e, s)
    b = (c[0] + i, a[1])
    d = (c[0] + e, c[1] + r)
    thread_loop(ctx, a, b, [c, d], lead, start_angles(starts, p), DEFAULT_THREAD_ANGLE)


def thread_loop(ctx: Any, a: Point, b: Point, path: list[Point], lead: float,
                angles: list[float], tool_angle: float) -> None:
    """The threading-cycle engine (HNC G82, FANUC G92), once per spindle start angle:
    A→B rapid, thread through the points of ``path`` (the thread end, then its run-out or
    chamfer leg), rapid in X back to A.x, rapid in Z back to A."""
    legs = _Legs(ctx, a)
    for ang in angles:
        legs.rapid(b)
        for p in path:
            legs.thread(p, lead, ang, tool_angle)
        legs.rapid((a[0], legs.at[1]))
        legs.rapid(a)


def _g32(ctx: Any) -> None:
    """One thread move to X(U) Z(W), then the run-out R/E (§3.3.3(4))."""
    a = ctx.pos
    for abs_l, inc_l in (("X", "U"), ("Z", "W")):
        if ctx.has(abs_l) and ctx.has(inc_l):
            ctx.alarm(f"G32: both {abs_l} and {inc_l} given", inc_l)
    if not any(ctx.has(c) for c in "XZUW"):
        ctx.alarm("G32: missing end point (X/U or Z/W)")
    if ctx.has("C"):
        ctx.alarm("G32: chamfer C is not allowed in a thread block", "C")
    lead = _lead(ctx)
    scale = 0.5 if ctx.diameter_mode else 1.0
    x, z = a
    xw, zw, uw, ww = (ctx.word(c) for c in "XZUW")
    if xw is not None:
        x = a[0] + xw * scale if ctx.incremental else xw * scale
    if uw is not None:
        x = a[0] + uw * scale
    if zw is not None:
        z = a[1] + zw if ctx.incremental else zw
    if ww is not None:
        z = a[1] + ww
    if abs(x - a[0]) <= _TOL and abs(z - a[1]) <= _TOL:
        ctx.alarm("G32: the thread has no length (end point = start point)")
    r = _opt(ctx, "R", 0.0)
    e = _opt(ctx, "E", 0.0)
    p = _opt(ctx, "P", 0.0) % 360.0
    legs = _Legs(ctx, a)
    legs.thread((x, z), lead, p, DEFAULT_THREAD_ANGLE)
    legs.thread((x + e, z + r), lead, p, DEFAULT_THREAD_ANGLE)


# --------------------------------------------------------------------------- G76


def g76_depths(k: float, d: float, dd: float, ddmin: float, finishing: int = 1,
               max_passes: int = MAX_G76_PASSES) -> list[tuple[float, bool]]:
    """The pass depths of a G76 (radius, from the crest) as ``(depth, is_finishing)``.

    Roughing: t_n = Δd·√n with the increment floored at Δdmin from the second pass on,
    until K − d is reached, then one pass exactly at K − d; then ``finishing`` (>= 1)
    passes at K. Raises ValueError with a message on bad parameters."""
    if not k > 0:
        raise ValueError(f"thread height K{k:g} must be > 0")
    if not dd > 0:
        raise ValueError(f"first depth Q{dd:g} (Δd) must be > 0")
    if ddmin < 0:
        raise ValueError(f"minimum depth V{ddmin:g} must be >= 0")
    if not 0 <= d < k:
        raise ValueError(f"finishing allowance U{d:g} must be >= 0 and smaller than K{k:g}")
    rough_end = k - d
    out: list[tuple[float, bool]] = []
    prev = 0.0
    n = 1
    while True:
        t = dd * math.sqrt(n)
        if n > 1 and t - prev < ddmin:
            t = prev + ddmin
        if t >= rough_end - _TOL:
            break
        out.append((t, False))
        if len(out) + 1 + max(finishing, 1) > max_passes:
            raise ValueError(f"more than {max_passes} passes (K{k:g}, Q{dd:g}, V{ddmin:g}): "
                             f"check the units of Q and V")
        prev = t
        n += 1
    if d > _TOL:
        out.append((rough_end, False))
    out.extend((k, True) for _ in range(max(finishing, 1)))
    if len(out) > max_passes:
        raise ValueError(f"more than {max_passes} passes: check C")
    return out


def _g76(ctx: Any) -> None:
    """Thread cutting compound cycle (figs. 3.3.36/3.3.37, macro %0076)."""
    _refuse_uw(ctx, "W")
    w = _require(ctx, "AXZKUVQF")
    angle = w["A"]
    if not any(abs(angle - t) <= 1e-9 for t in THREAD_ANGLES):
        ctx.alarm(f"G76: tool angle A{angle:g} must be one of 80, 60, 55, 30, 29, 0", "A")
    lead = _lead(ctx)
    k, d, ddmin, dd = w["K"], w["U"], w["V"], w["Q"]
    if dd <= 0:
        ctx.alarm(f"G76: first depth Q{dd:g} (Δd) must be > 0", "Q")
    if k <= 0:
        ctx.alarm(f"G76: thread height K{k:g} must be > 0", "K")
    if ddmin < 0:
        ctx.alarm(f"G76: minimum depth V{ddmin:g} must be >= 0", "V")
    if not 0 <= d < k:
        ctx.alarm(f"G76: finishing allowance U{d:g} must be >= 0 and smaller than K{k:g}", "U")
    finishing = _int_word(ctx, "C", 0, 99, 1, "finishing pass count")
    a = ctx.pos
    c = _end_point(ctx, a, w["X"], w["Z"])
    if abs(c[1] - a[1]) <= _TOL:
        ctx.alarm("G76: the thread has no length (Z of the end point equals Z of the start A)", "Z")
    if abs(c[0] - a[0]) <= _TOL:
        ctx.alarm("G76: the start point A lies on the thread root X; start outside the thread", "X")
    s = 1 if a[0] > c[0] else -1
    i = _opt(ctx, "I", 0.0)
    r = _opt(ctx, "R", 0.0)
    e = _opt(ctx, "E", s * k)
    p = _opt(ctx, "P", 0.0) % 360.0
    _runout(ctx, r, e, s)
    crest_b = c[0] + i + s * k
    if s * (a[0] - crest_b) < -_TOL:
        ctx.warn(f"G76: the start point A (X{a[0] * (2 if ctx.diameter_mode else 1):g}) lies "
                 f"inside the thread crest at the start")
    try:
        depths = g76_depths(k, d, dd, ddmin, finishing,
                            min(MAX_G76_PASSES, int(getattr(ctx, "max_passes", MAX_G76_PASSES))))
    except ValueError as exc:
        ctx.alarm(f"G76: {exc}")
    thread_passes(ctx, a, c, flank_shifts(depths, angle, a, c), height=k, taper=i, lead=lead,
                  start_angle=p, tool_angle=angle, runout=(e, r))


def flank_shifts(depths: list[tuple[float, bool]], angle: float, a: Point, c: Point,
                 alternate: bool = False) -> list[tuple[float, float]]:
    """``(depth, z shift)`` of each pass of a multiple-pass thread: single-flank infeed
    shifts pass t by t·tan(angle/2) in the cutting direction (A toward C), so that one flank
    of the tool stays on one flank of the finished thread. ``alternate``: flanks in turn
    (double-flank infeed): the even passes are shifted by (2K − t)·tan(angle/2), K the final
    depth, so that the other flank stays on the other side of the same finished thread."""
    dirz = 1.0 if c[1] > a[1] else -1.0
    tan_half = math.tan(math.radians(angle) / 2.0)
    full = max((t for t, _ in depths), default=0.0)
    out = []
    for n, (t, _finish) in enumerate(depths):
        if alternate and n % 2 == 1:
            out.append((t, dirz * (2.0 * full - t) * tan_half))
        else:
            out.append((t, dirz * t * tan_half))
    return out


def thread_passes(ctx: Any, a: Point, c: Point, passes: list[tuple[float, float]], *,
                  height: float, taper: float, lead: float, start_angle: float,
                  tool_angle: float, runout: Point = (0.0, 0.0), chamfer: Point = (0.0, 0.0),
                  axes_return: bool = False, shift_end: bool = True) -> None:
    """The multiple-pass threading engine (HNC G76, FANUC and Haas G76).

    ``c`` is the root end point (radius x), ``height`` the thread height K, ``taper`` the
    radius difference start − end; per pass ``(t, h)`` (depth below the crest, z shift):
    A→(A.x − s·t, A.z + h) rapid, → (x_t + taper, A.z + h) rapid (the pass start), thread to
    (x_t, C.z + h) where x_t = C.x + s·(K − t) and s = +1 outside, −1 inside. ``chamfer``
    (length along Z, pull-out in X, radius) ends the thread inside that end: the straight
    thread stops the length before it and a second thread leg pulls out to
    (x_t + s·pull-out, C.z + h). ``runout`` (dx, dz) is a further thread leg after the end.
    Then back to A: one rapid, or with ``axes_return`` rapid in X to A.x, then in Z.
    Without ``shift_end`` only the pass start is shifted by h: every pass ends on C.z."""
    s = 1 if a[0] > c[0] else -1
    length = abs(c[1] - a[1])
    dirz = 1.0 if c[1] > a[1] else -1.0
    legs = _Legs(ctx, a)
    for t, h in passes:
        x_end = c[0] + s * (height - t)
        legs.rapid((a[0] - s * t, a[1] + h))
        legs.rapid((x_end + taper, a[1] + h))
        end = (x_end, c[1] + h if shift_end else c[1])
        if chamfer[0] > _TOL and length > _TOL:
            frac = min(chamfer[0] / length, 1.0)
            legs.thread((x_end + taper * frac, end[1] - dirz * min(chamfer[0], length)), lead,
                        start_angle, tool_angle)
            end = (x_end + s * chamfer[1], end[1])
        legs.thread(end, lead, start_angle, tool_angle)
        legs.thread((end[0] + runout[0], end[1] + runout[1]), lead, start_angle, tool_angle)
        if axes_return:
            legs.rapid((a[0], legs.at[1]))
        legs.rapid(a)
