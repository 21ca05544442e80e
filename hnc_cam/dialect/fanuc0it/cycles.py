"""FANUC 0i-T canned cycles (G-code system A) and the Haas one-block forms, on the shared
cycle engines.

Sources and choices: ``docs/FANUC.md`` §5 (G90/G92/G94), §6 (G71/G72/G73), §7 (G74/G75),
§8 (G76), §13 (Haas) and §16. This module only decodes the words; the motion comes from the
engines HNC's cycles use too: :func:`hnc_cam.geometry.roughing.rough_turn` and
:func:`~hnc_cam.geometry.roughing.pattern_repeat` (G71/G72/G73),
:mod:`hnc_cam.nc.cycles_simple` (``turn_legs``, ``face_legs``, ``thread_loop``,
``thread_passes``, ``g76_depths``) and :func:`peck_moves` here (G74/G75).

Every handler takes the interpreter's cycle context (the ``CycleContext`` protocol of
``hnc_cam.nc.context`` plus ``store``, ``setting`` and ``resume_after``). Words arrive with
the decimal-point rule applied: X/U are diameters (radius inside, via
``ctx.diameter_mode``), U/W are increments from the start point A, except where a cycle
gives them another meaning (allowances, depths). Words FANUC writes in least increments
without a decimal point — P/Q of G74/G75/G76, Q of G92 (0.001°), D of the one-block G71/G72
— arrive as written and are scaled here; a fractional value there is an alarm.

Machine-file defaults (``[parameters]``, read through ``ctx.setting``) are listed in
:data:`SETTINGS` with the 0i parameter each stands for; a first cycle block (G71 U R,
G72 W R, G73 U W R, G74/G75 R, G76 P Q R) changes them for the rest of the run, as writing
the parameter does on the control (G71 and G72 share theirs, as do G74 and G75, and G76's r
is also G92's chamfer: one parameter each on the 0i).
"""
from __future__ import annotations

import math
from typing import Any, Optional

from ...geometry.primitives import Point
from ...geometry.roughing import (RoughingError, RoughMove, RoughPlan, first_non_monotonic,
                                  pattern_repeat, rough_turn)
from ...nc import cycles_rough as rough
from ...nc import cycles_simple as simple

_TOL = 1e-9

#: machine-file ``[parameters]`` keys of the cycles: default and the 0i parameter
SETTINGS: dict[str, tuple[Any, str]] = {
    "g71_depth": (2.0, "5132: G71/G72 depth of cut Δd, radius mm"),
    "g71_retract": (1.0, "5133: G71/G72 retract e, mm"),
    "g71_type2": (True, "type II profiles (multiple repetitive cycle II option)"),
    "g73_relief_x": (0.0, "5135: G73 total relief Δi in X, radius mm"),
    "g73_relief_z": (0.0, "5136: G73 total relief Δk in Z, mm"),
    "g73_passes": (1, "5137: G73 number of passes d"),
    "g74_return": (1.0, "5139: G74/G75 return e after each peck, mm"),
    "g76_finish_passes": (1, "5142: G76 finishing passes m"),
    "thread_chamfer": (0, "5130: G76/G92 end chamfer r, 0.1 lead units (0 = none)"),
    "thread_chamfer_angle": (45.0, "5131: chamfer angle, degrees from the Z axis"),
    "g76_angle": (60, "5143: G76 tool angle a"),
    "g76_min_depth": (0.0, "5140: G76 minimum depth of cut Δdmin, radius mm"),
    "g76_allowance": (0.0, "5141: G76 finishing allowance d, radius mm"),
}

_SIGN_WARNING = ("the sign of the finishing allowance U/W points toward the part for this "
                 "quadrant (OD/ID from A→A′, cut direction from A toward the profile end): "
                 "the allowance profile is shifted into the part")
_SIGN_WARNING_G73 = ("the sign of the {name} points toward the part for this quadrant: "
                     "the passes are shifted into the part")


# --------------------------------------------------------------------------- word helpers


def _name(ctx: Any) -> str:
    return f"G{int(ctx.code):02d}"


def _setting(ctx: Any, key: str) -> Any:
    default = SETTINGS[key][0]
    v = ctx.setting(key, default)
    if isinstance(default, bool):
        if not isinstance(v, bool):
            ctx.alarm(f"machine file [parameters] {key} = {v!r}: must be true or false")
        return v
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        ctx.alarm(f"machine file [parameters] {key} = {v!r}: must be a number")
    return float(v)


def _word(ctx: Any, letter: str) -> Optional[float]:
    v = ctx.word(letter)
    return None if v is None else float(v)


def _radius(ctx: Any, value: float) -> float:
    """An X-like word (diameter on a diameter axis) as a radius."""
    return value / 2.0 if ctx.diameter_mode else value


def _whole(ctx: Any, letter: str, what: str, lo: int, hi: int) -> Optional[int]:
    """A count or code written without a decimal point. A value with a fraction that is a
    whole number of thousandths is the same digits read through the decimal-point rule as a
    coordinate (``R4`` → 0.004 at DPI = 0), so it is taken as that whole number."""
    v = _word(ctx, letter)
    if v is None:
        return None
    n = v
    if abs(v - round(v)) > 1e-9:
        n = v * 1000.0
        if abs(n - round(n)) > 1e-6:
            ctx.alarm(f"{_name(ctx)} {letter}{v:g}: {what} must be a whole number", letter)
    n = int(round(n))
    if not lo <= n <= hi:
        ctx.alarm(f"{_name(ctx)} {letter}{n}: {what} must be {lo}..{hi} (PS0062)", letter)
    return n


def _micron(ctx: Any, letter: str, what: str) -> Optional[float]:
    """A word in least increments (µm) without a decimal point or sign, as mm."""
    v = _word(ctx, letter)
    if v is None:
        return None
    if abs(v - round(v)) > 1e-9:
        ctx.alarm(f"{_name(ctx)} {letter}{v:g}: {what} is written in µm without a decimal point "
                  f"({letter}{int(round(abs(v) * 1000))} = {abs(v):g} mm)", letter)
    if v < 0:
        ctx.alarm(f"{_name(ctx)} {letter}{v:g}: {what} is written without a sign", letter)
    return round(v) / 1000.0


def _end_point(ctx: Any) -> tuple[Point, bool, bool]:
    """The end point from X(U) Z(W): absolute X/Z, U/W increments from A; missing axes stay
    at A. Returns (point, x given, z given)."""
    a = ctx.pos
    for ab, inc in (("X", "U"), ("Z", "W")):
        if ctx.has(ab) and ctx.has(inc):
            ctx.alarm(f"{_name(ctx)}: both {ab} and {inc} in one block", inc)
    x, z = a
    xw, uw, zw, ww = (_word(ctx, c) for c in "XUZW")
    if xw is not None:
        x = a[0] + _radius(ctx, xw) if ctx.incremental else _radius(ctx, xw)
    elif uw is not None:
        x = a[0] + _radius(ctx, uw)
    if zw is not None:
        z = a[1] + zw if ctx.incremental else zw
    elif ww is not None:
        z = a[1] + ww
    return (x, z), xw is not None or uw is not None, zw is not None or ww is not None


def _need_axes(ctx: Any, x: bool, z: bool) -> None:
    if not x:
        ctx.alarm(f"{_name(ctx)}: missing X(U), the end point", None)
    if not z:
        ctx.alarm(f"{_name(ctx)}: missing Z(W), the end point", None)


def _lead(ctx: Any) -> float:
    f = _word(ctx, "F")
    if f is None:
        ctx.alarm(f"{_name(ctx)}: missing F (thread lead)")
    if f <= _TOL:
        ctx.alarm(f"{_name(ctx)} F{f:g}: the thread lead must be > 0", "F")
    return f


# --------------------------------------------------------------------------- G90 G92 G94


def g90(ctx: Any) -> None:
    """Turning cycle ``G90 X(U) Z(W) [R] F``: rapid in X to C.x + R, feed to C, feed out in
    X to A.x, rapid back to A (§5); HNC's G80 engine."""
    c, hx, hz = _end_point(ctx)
    _need_axes(ctx, hx, hz)
    taper = _word(ctx, "R") or 0.0
    simple.turn_legs(ctx, ctx.pos, c, taper)


def g94(ctx: Any) -> None:
    """Facing cycle ``G94 X(U) Z(W) [R] F``: rapid in Z to C.z + R, feed in X to C, feed in
    Z back to A.z, rapid back to A (§5); HNC's G81 engine."""
    c, hx, hz = _end_point(ctx)
    _need_axes(ctx, hx, hz)
    taper = _word(ctx, "R") or 0.0
    simple.face_legs(ctx, ctx.pos, c, taper)


def _chamfer(ctx: Any, lead: float) -> tuple[float, float]:
    """The thread end chamfer (length along Z, pull-out in X, radius): r × 0.1 × lead at the
    chamfer angle (parameters 5130/5131); r from the last G76 first block, else the machine."""
    st = ctx.store.get(76, {})
    r = st["r"] if "r" in st else _setting(ctx, "thread_chamfer")
    if not 0 <= r <= 99:
        ctx.alarm(f"machine file [parameters] thread_chamfer = {r:g}: must be 0..99")
    if r <= 0:
        return (0.0, 0.0)
    ang = _setting(ctx, "thread_chamfer_angle")
    if not 0 < ang < 90:
        ctx.alarm(f"machine file [parameters] thread_chamfer_angle = {ang:g}: must be "
                  f"between 0 and 90 degrees")
    length = r * 0.1 * lead
    return (length, length * math.tan(math.radians(ang)))


def g92(ctx: Any) -> None:
    """Threading cycle ``G92 X(U) Z(W) [R] F(lead) [Q angle]`` (§5): rapid in X to
    C.x + R, thread to C (with the end chamfer inside the programmed Z when parameter 5130 is
    set), rapid in X back to A.x, rapid in Z back to A; HNC's G82 engine."""
    c, hx, hz = _end_point(ctx)
    _need_axes(ctx, hx, hz)
    lead = _lead(ctx)
    a = ctx.pos
    if abs(c[1] - a[1]) <= _TOL:
        ctx.alarm("G92: the thread has no length (Z of the end point equals Z of the start A)",
                  "Z" if ctx.has("Z") else "W")
    taper = _word(ctx, "R") or 0.0
    q = _micron(ctx, "Q", "the spindle start angle Q (0.001°)")
    angle = (q or 0.0) % 360.0
    b = (c[0] + taper, a[1])
    s = 1 if a[0] >= c[0] else -1
    clen, pull = _chamfer(ctx, lead)
    path: list[Point] = [c]
    if clen > _TOL:
        length = abs(c[1] - a[1])
        if clen >= length - _TOL:
            ctx.alarm(f"G92: the end chamfer ({clen:g} mm, parameter 5130) is not shorter than "
                      f"the thread ({length:g} mm)")
        dirz = 1.0 if c[1] > a[1] else -1.0
        frac = clen / length
        path = [(c[0] + taper * frac, c[1] - dirz * clen), (c[0] + s * pull, c[1])]
    simple.thread_loop(ctx, a, b, path, lead, [angle], simple.DEFAULT_THREAD_ANGLE)


# --------------------------------------------------------------------------- G71 G72 G73


def _pq(ctx: Any) -> tuple[int, int]:
    out = []
    for letter, what in (("P", "the first block ns of the profile"),
                         ("Q", "the last block nf of the profile")):
        v = _word(ctx, letter)
        if v is None:
            ctx.alarm(f"{_name(ctx)}: missing {letter} ({what}) (PS0061)", None)
        if abs(v - round(v)) > 1e-9 or not 1 <= round(v) <= 99999:
            ctx.alarm(f"{_name(ctx)} {letter}{v:g}: {what} must be a sequence number "
                      f"1..99999", letter)
        out.append(int(round(v)))
    return out[0], out[1]


def _ns_axes(item: tuple) -> Optional[set[str]]:
    """The axis letters written in block ns, when the profile item carries them (its
    fourth element: a string or set of letters such as ``"XW"``)."""
    if len(item) > 3 and item[3] is not None:
        return {str(c).upper() for c in item[3]} & set("XZUW")
    return None


def _is_type2(ctx: Any, items: list, segs: list, face: bool, ns: int = 0, nf: int = 0) -> bool:
    """Type II when block ns writes both axes (§6), ``W0`` included: the letters come from
    ``ctx.profile_letters`` (or a fourth element of the profile item). A context that gives
    neither: type II when the move of block ns has both components, or when the rest of the
    profile is not monotonic along the level axis."""
    axes = _ns_axes(items[0])
    if axes is None and hasattr(ctx, "profile_letters"):
        blocks = ctx.profile_letters(ns, nf)
        if blocks:
            axes = set(blocks[0][1]) & set("XZUW")
    if axes is not None:
        return bool(axes & {"X", "U"}) and bool(axes & {"Z", "W"})
    s0 = segs[0]
    dx = abs(s0.end[0] - s0.start[0])
    dz = abs(s0.end[1] - s0.start[1])
    if dx > 1e-6 and dz > 1e-6:
        return True
    return _non_monotonic_level(segs, face) is not None


def _non_monotonic_level(segs: list, face: bool) -> Optional[int]:
    """Index of the first profile segment after ns that turns back along the level axis
    (X for G71, Z for G72), or None."""
    if len(segs) < 2:
        return None
    axis = 1 if face else 0
    sense = 1 if segs[-1].end[axis] >= segs[0].end[axis] else -1
    bad = first_non_monotonic(segs[1:], axis, sense)
    return None if bad is None else bad + 1


def _infeed_by_ns(plan: RoughPlan, motion_ns: str) -> RoughPlan:
    """Block ns's G00/G01 decides whether the infeed to each level is rapid or feed (§6)."""
    if motion_ns != "feed":
        return plan
    moves = [RoughMove("feed", m.seg, m.role, m.level) if m.role == "approach" else m
             for m in plan.moves]
    return RoughPlan(moves, plan.warnings, plan.levels, plan.passes, plan.offset_profile)


def _no_first_block_words(ctx: Any, letters: str, first: str) -> None:
    """The block with P and Q is the second one: a word of the first block there (an HNC-style
    one-block ``G71 U R P Q X Z`` read as FANUC's) would silently change meaning."""
    for c in letters:
        if ctx.has(c):
            ctx.alarm(f"{_name(ctx)}: {c} is a word of the first {_name(ctx)} block "
                      f"({_name(ctx)} {first}); the block with P and Q takes P Q U W F", c)


def _first_block_g71(ctx: Any, face: bool) -> None:
    code = ctx.code
    depth_l, other = ("W", "U") if face else ("U", "W")
    if ctx.has(other) or any(ctx.has(c) for c in "XZD"):
        bad = next(c for c in (other, "X", "Z", "D") if ctx.has(c))
        ctx.alarm(f"G{code}: {bad} is not a word of the first G{code} block "
                  f"(G{code} {depth_l}(Δd) R(e); the second block has P and Q)", bad)
    if not ctx.has(depth_l) and not ctx.has("R"):
        ctx.alarm(f"G{code} without P/Q is the first block: it needs {depth_l} (depth of cut "
                  f"Δd) and/or R (retract e)", None)
    st = ctx.store.setdefault(71, {})
    d = _word(ctx, depth_l)
    if d is not None:
        if d <= 0:
            ctx.alarm(f"G{code} {depth_l}{d:g}: the depth of cut must be > 0 (PS0062)", depth_l)
        st["depth"] = d
    e = _word(ctx, "R")
    if e is not None:
        if e < 0:
            ctx.alarm(f"G{code} R{e:g}: the retract must be >= 0", "R")
        st["retract"] = e


def _stock_removal(ctx: Any, face: bool, depth: Optional[float] = None,
                   extra: Point = (0.0, 0.0), yasnac_type2: bool = False) -> None:
    """The second G71/G72 block (or a one-block form with ``depth`` given): plan with the
    roughing engine, emit, resume after nf."""
    code = ctx.code
    ns, nf = _pq(ctx)
    st = ctx.store.get(71, {})
    if depth is None:
        depth = st["depth"] if "depth" in st else _setting(ctx, "g71_depth")
        if depth <= 0:
            ctx.alarm(f"G{code}: the depth of cut Δd is {depth:g} (first block or "
                      f"[parameters] g71_depth); it must be > 0 (PS0062)")
    retract = st["retract"] if "retract" in st else _setting(ctx, "g71_retract")
    if retract < 0:
        ctx.alarm(f"G{code}: the retract e is {retract:g} ([parameters] g71_retract); it must "
                  f"be >= 0")
    du = _radius(ctx, _word(ctx, "U") or 0.0)
    dw = _word(ctx, "W") or 0.0
    items = ctx.profile(ns, nf)
    if not items:
        ctx.alarm(f"G{code}: the profile N{ns}…N{nf} is empty", "P")
    segs = [p[0] for p in items]
    lines = [p[1] for p in items]
    motions = [p[2] for p in items]
    type2 = yasnac_type2 or _is_type2(ctx, items, segs, face, ns, nf)
    if type2 and not _setting(ctx, "g71_type2"):
        ctx.alarm(f"G{code}: block N{ns} (line {lines[0]}) writes both X(U) and Z(W), a type "
                  f"II profile; this machine has no type II ([parameters] g71_type2 = false)",
                  "P")
    if type2 and abs(dw if not face else du) > _TOL:
        ctx.warn(f"G{code} type II: the {'Z' if not face else 'X'} allowance "
                 f"{'W' if not face else 'U'} is planned as programmed; it also leaves stock "
                 f"on the pocket walls")
    if not type2:
        bad = _non_monotonic_level(segs, face)
        if bad is not None:
            ctx.alarm(f"G{code}: type I profile is not monotonic in {'Z' if face else 'X'} "
                      f"(profile block at line {lines[bad]}); for pockets write both "
                      f"{'Z(W) and X(U)' if face else 'X(U) and Z(W)'} in block N{ns} "
                      f"(type II) (PS0064)", "P")
        s0 = segs[0]
        k = 0 if face else 1
        if abs(s0.end[k] - s0.start[k]) > 1e-6:
            ctx.alarm(f"G{code}: type I block N{ns} (line {lines[0]}) moves in "
                      f"{'X' if face else 'Z'}; it must move in {'Z' if face else 'X'} only",
                      "P")
    allowance = (du, dw)
    passes_allowance = (du + extra[0], dw + extra[1])
    start = ctx.pos
    rough.level_bound(ctx, start, segs, passes_allowance, depth, face,
                      "D" if ctx.has("D") else None)
    try:
        plan = rough_turn(start, segs, motions, depth=depth, retract=retract,
                          allowance=passes_allowance, face=face, pockets=type2,
                          finish_allowance=allowance if extra != (0.0, 0.0) else None,
                          sign_warning=_SIGN_WARNING)
    except RoughingError as err:
        rough.engine_alarm(ctx, err, lines)
    first = next((m for s, m in zip(segs, motions) if s.length > 1e-6), motions[0])
    rough.emit(ctx, _infeed_by_ns(plan, first))
    ctx.resume_after(nf)


def _g71_g72(ctx: Any, face: bool) -> None:
    if not ctx.has("P") and not ctx.has("Q"):
        if ctx.has("D"):
            ctx.alarm(f"{_name(ctx)}: the one-block form with D needs P and Q (PS0061)", "D")
        _first_block_g71(ctx, face)
        return
    _no_first_block_words(ctx, "R", f"{'W' if face else 'U'}(Δd) R(e)")
    depth = None
    if ctx.has("D"):  # FANUC Series 10/11 one-block form: D in least increments
        depth = _micron(ctx, "D", "the depth of cut D")
        if depth <= 0:
            ctx.alarm(f"{_name(ctx)} D0: the depth of cut must be > 0 (PS0062)", "D")
    _stock_removal(ctx, face, depth)


def g71(ctx: Any) -> None:
    """``G71 U(Δd) R(e)`` / ``G71 P(ns) Q(nf) U(Δu) W(Δw) F S T`` (§6); also the one-block
    ``G71 P Q U W D(µm) F``."""
    _g71_g72(ctx, face=False)


def g72(ctx: Any) -> None:
    """``G72 W(Δd) R(e)`` / ``G72 P(ns) Q(nf) U(Δu) W(Δw) F S T`` (§6)."""
    _g71_g72(ctx, face=True)


def _g73_passes(ctx: Any, relief: Point, count: int, ns: int, nf: int,
                allowance: Point) -> None:
    """G73 with total relief ``relief`` (x radius, z) from the first pass to the last and
    ``count`` passes spaced (d − k)/(d − 1) (§6): the engine's r-pass spacing with the relief
    scaled by d/(d − 1)."""
    code = ctx.code
    limit = int(getattr(ctx, "max_passes", 10_000))
    if count > limit:
        ctx.alarm(f"{_name(ctx)}: {count} passes, more than the machine's limit of {limit} "
                  f"([limits] cycle_passes)")
    items = ctx.profile(ns, nf)
    if not items:
        ctx.alarm(f"G{code}: the profile N{ns}…N{nf} is empty", "P")
    segs = [p[0] for p in items]
    lines = [p[1] for p in items]
    motions = [p[2] for p in items]
    left = getattr(ctx, "moves_left", None)
    if left is not None and count * (len(segs) + 2) > left:
        ctx.alarm(f"{_name(ctx)}: {count} passes over a profile of {len(segs)} blocks exceed "
                  f"the moves the toolpath may still take ({left}, [limits] moves)")
    if count == 1:
        ctx.warn(f"{_name(ctx)}: one pass (d = 1): it lies on the allowance profile, the relief "
                 f"Δi/Δk is not used")
        stock = (0.0, 0.0)
    else:
        stock = (relief[0] * count / (count - 1), relief[1] * count / (count - 1))
    try:
        plan = pattern_repeat(ctx.pos, segs, motions, stock=stock, allowance=allowance,
                              count=count, sign_warning=_SIGN_WARNING_G73)
    except RoughingError as err:
        rough.engine_alarm(ctx, err, lines)
    rough.emit(ctx, plan)
    ctx.resume_after(nf)


def g73(ctx: Any) -> None:
    """``G73 U(Δi) W(Δk) R(d)`` / ``G73 P(ns) Q(nf) U(Δu) W(Δw) F S T`` (§6): d passes, pass
    k the profile shifted by (Δi, Δk)·(d − k)/(d − 1) + (Δu/2, Δw)."""
    if not ctx.has("P") and not ctx.has("Q"):
        if not any(ctx.has(c) for c in "UWR"):
            ctx.alarm("G73 without P/Q is the first block: it needs U (Δi), W (Δk) and/or "
                      "R (number of passes d)", None)
        st = ctx.store.setdefault(73, {})
        if ctx.has("U"):
            st["relief_x"] = _word(ctx, "U")  # a radius value, not a diameter
        if ctx.has("W"):
            st["relief_z"] = _word(ctx, "W")
        d = _whole(ctx, "R", "the number of passes d", 1, 99999)
        if d is not None:
            st["passes"] = d
        return
    _no_first_block_words(ctx, "R", "U(Δi) W(Δk) R(d)")
    ns, nf = _pq(ctx)
    st = ctx.store.get(73, {})
    rx = st["relief_x"] if "relief_x" in st else _setting(ctx, "g73_relief_x")
    rz = st["relief_z"] if "relief_z" in st else _setting(ctx, "g73_relief_z")
    d = st["passes"] if "passes" in st else _setting(ctx, "g73_passes")
    if d < 1 or abs(d - round(d)) > 1e-9:
        ctx.alarm(f"G73: the number of passes d is {d:g} ([parameters] g73_passes); it must "
                  f"be a whole number >= 1 (PS0062)")
    allowance = (_radius(ctx, _word(ctx, "U") or 0.0), _word(ctx, "W") or 0.0)
    _g73_passes(ctx, (rx, rz), int(round(d)), ns, nf, allowance)


# --------------------------------------------------------------------------- G74 G75


def peck_moves(a: Point, c: Point, peck: float, shift: float, back: float, relief: float,
               along_z: bool, max_moves: int = 10**9) -> list[tuple[str, Point]]:
    """The legs of G74 (``along_z``: pecks along Z, columns shifted in X) or G75 (pecks
    along X, columns shifted in Z) from A to the far corner C (radius x), as
    ``(kind, end point)`` with kind 'rapid' or 'feed' (§7).

    Each column starts on A's peck coordinate; the pecks go ``peck`` deeper each, after
    each but the last the tool rapids back ``back`` and feeds on (``peck`` + ``back``); the
    last peck lands exactly on C. At the bottom the tool moves ``relief`` along the shift
    axis (a feed; away from the shift when there are several columns, with the word's
    sign when there is one), rapids back to A's peck coordinate and shifts by ``shift``
    (rapid), the last shift landing exactly on C. After the last column, back to A.
    Raises ValueError when the legs would exceed ``max_moves``."""
    pi, qi = (1, 0) if along_z else (0, 1)
    pa, pc, qa, qc = a[pi], c[pi], a[qi], c[qi]
    dp = 1.0 if pc >= pa else -1.0
    dq = 1.0 if qc >= qa else -1.0
    span_p, span_q = abs(pc - pa), abs(qc - qa)
    n_pecks = max(1, math.ceil(span_p / peck - 1e-9)) if span_p > _TOL else 0
    n_cols = (math.ceil(span_q / shift - 1e-9) + 1) if span_q > _TOL else 1
    if n_cols * (2 * n_pecks + 4) + 1 > max_moves:
        raise ValueError(f"{n_cols} columns of {n_pecks} pecks")

    def pt(p: float, q: float) -> Point:
        return (q, p) if along_z else (p, q)

    out: list[tuple[str, Point]] = []
    for j in range(n_cols):
        q = qc if j == n_cols - 1 and n_cols > 1 else qa + dq * j * shift
        if j:
            out.append(("rapid", pt(pa, q)))
        for i in range(1, n_pecks + 1):
            p = pc if i == n_pecks else pa + dp * i * peck
            out.append(("feed", pt(p, q)))
            if i < n_pecks and back > _TOL:
                out.append(("rapid", pt(p - dp * back, q)))
        qr = q
        if abs(relief) > _TOL and n_pecks:
            qr = q + (-dq * abs(relief) if n_cols > 1 else relief)
            out.append(("feed", pt(pc, qr)))
        if n_pecks:
            out.append(("rapid", pt(pa, qr)))
    out.append(("rapid", a))
    legs: list[tuple[str, Point]] = []
    at = a
    for kind, p in out:  # drop the legs that do not move (a retract e = 0, a return on A)
        if abs(p[0] - at[0]) > _TOL or abs(p[1] - at[1]) > _TOL:
            legs.append((kind, p))
            at = p
    return legs


def _first_block_peck(ctx: Any) -> None:
    bad = next((c for c in "PQFD" if ctx.has(c)), None)
    if bad is not None:
        ctx.alarm(f"{_name(ctx)}: {bad} is not a word of the first {_name(ctx)} block "
                  f"({_name(ctx)} R(e); the second block has X(U)/Z(W))", bad)
    e = _word(ctx, "R")
    if e is None:
        ctx.alarm(f"{_name(ctx)} without X(U)/Z(W) is the first block: it needs R (the return "
                  f"e after each peck)", None)
    if e < 0:
        ctx.alarm(f"{_name(ctx)} R{e:g}: the return must be >= 0", "R")
    ctx.store.setdefault(74, {})["return"] = e


def _peck(ctx: Any, along_z: bool) -> None:
    if not any(ctx.has(c) for c in "XZUW"):
        _first_block_peck(ctx)
        return
    name = _name(ctx)
    a = ctx.pos
    c, hx, hz = _end_point(ctx)
    peck_l, shift_l = ("Q", "P") if along_z else ("P", "Q")
    peck_axis, shift_axis = ("Z", "X") if along_z else ("X", "Z")
    pi, qi = (1, 0) if along_z else (0, 1)
    if not (hz if along_z else hx):
        ctx.alarm(f"{name}: missing {peck_axis}({'W' if along_z else 'U'}), the bottom of the "
                  f"pecks", None)
    peck = _micron(ctx, peck_l, f"the peck depth {peck_l}")
    shift = _micron(ctx, shift_l, f"the shift {shift_l}")
    if abs(c[pi] - a[pi]) <= _TOL:
        ctx.alarm(f"{name}: the end point lies on the start point's {peck_axis}: nothing to "
                  f"peck", peck_axis)
    if peck is None or peck <= _TOL:
        ctx.alarm(f"{name}: the peck depth {peck_l} must be given and > 0 (PS0062)", peck_l)
    span_q = abs(c[qi] - a[qi])
    if span_q > _TOL and (shift is None or shift <= _TOL):
        ctx.alarm(f"{name}: the end point's {shift_axis} differs from the start's; the shift "
                  f"{shift_l} must be given and > 0 (PS0062)", shift_l)
    back = ctx.store.get(74, {}).get("return")
    if back is None:
        back = _setting(ctx, "g74_return")
        if back < 0:
            ctx.alarm(f"{name}: [parameters] g74_return = {back:g} must be >= 0")
    relief = _word(ctx, "R") or 0.0
    limit = int(getattr(ctx, "max_passes", 10_000))
    n_pecks = math.ceil(abs(c[pi] - a[pi]) / peck - 1e-9)
    n_cols = (math.ceil(span_q / shift - 1e-9) + 1) if span_q > _TOL else 1
    if n_pecks * n_cols > limit:
        ctx.alarm(f"{name}: {n_cols} × {n_pecks} pecks, more than the machine's limit of "
                  f"{limit} ([limits] cycle_passes)", peck_l)
    left = int(getattr(ctx, "moves_left", 10**9))
    try:
        legs = peck_moves(a, c, peck, shift or 1.0, back, relief, along_z, left)
    except ValueError as exc:
        ctx.alarm(f"{name}: {exc} exceed the moves the toolpath may still take ({left}, "
                  f"[limits] moves)", peck_l)
    for kind, p in legs:
        if kind == "rapid":
            ctx.rapid(p[0], p[1])
        else:
            ctx.feed(p[0], p[1])


def g74(ctx: Any) -> None:
    """``G74 R(e)`` / ``G74 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F`` (§7): face grooving or peck
    drilling along Z, columns shifted by Δi in X."""
    _peck(ctx, along_z=True)


def g75(ctx: Any) -> None:
    """``G75 R(e)`` / ``G75 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F`` (§7): grooving along X, pecks
    of Δi, columns shifted by Δk in Z."""
    _peck(ctx, along_z=False)


# --------------------------------------------------------------------------- G76


def _thread_setup(ctx: Any) -> tuple[Point, Point, int]:
    c, hx, hz = _end_point(ctx)
    _need_axes(ctx, hx, hz)
    a = ctx.pos
    if abs(c[1] - a[1]) <= _TOL:
        ctx.alarm(f"{_name(ctx)}: the thread has no length (Z of the end point equals Z of the "
                  f"start A)", "Z" if ctx.has("Z") else "W")
    if abs(c[0] - a[0]) <= _TOL:
        ctx.alarm(f"{_name(ctx)}: the start point A lies on the thread root X; start outside "
                  f"the thread", "X" if ctx.has("X") else "U")
    return a, c, (1 if a[0] > c[0] else -1)


def _crest_check(ctx: Any, a: Point, c: Point, s: int, k: float, taper: float) -> None:
    crest_b = c[0] + taper + s * k
    if s * (a[0] - crest_b) < -_TOL:
        ctx.warn(f"{_name(ctx)}: the start point A lies inside the thread crest at the start")


def g76(ctx: Any) -> None:
    """``G76 P(m r a) Q(Δdmin) R(d)`` / ``G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L)`` (§8): HNC's
    depth law (Δd·√n, Δdmin floor, a pass on k − d, m finishing passes at k), one-flank
    infeed, the chamfer r·0.1·L inside the programmed Z, back to A by X then Z."""
    if not any(ctx.has(c) for c in "XZUW"):
        bad = next((c for c in "FDK" if ctx.has(c)), None)
        if bad is not None:
            ctx.alarm(f"G76: {bad} is not a word of the first G76 block (G76 P(m r a) "
                      f"Q(Δdmin) R(d); the second block has X(U) Z(W))", bad)
        if not any(ctx.has(c) for c in "PQR"):
            ctx.alarm("G76 without X(U)/Z(W) is the first block: it needs P(m r a), "
                      "Q(Δdmin) and/or R(d)", None)
        st = ctx.store.setdefault(76, {})
        p = _whole(ctx, "P", "P (m r a: finishing passes, chamfer, angle)", 0, 999999)
        if p is not None:
            m, r, ang = p // 10000, (p // 100) % 100, p % 100
            if m < 1:
                ctx.alarm(f"G76 P{p:06d}: the finishing pass count m (first two digits) must "
                          f"be 01..99 (PS0062)", "P")
            if not any(abs(ang - t) < 1e-9 for t in simple.THREAD_ANGLES):
                ctx.alarm(f"G76 P{p:06d}: the tool angle a (last two digits) must be one of "
                          f"80, 60, 55, 30, 29, 00 (PS0062)", "P")
            st.update(m=m, r=r, a=ang)
        q = _micron(ctx, "Q", "the minimum depth of cut Δdmin")
        if q is not None:
            st["min_depth"] = q
        d = _word(ctx, "R")
        if d is not None:
            if d < 0:
                ctx.alarm(f"G76 R{d:g}: the finishing allowance must be >= 0 (PS0062)", "R")
            st["allowance"] = d
        return
    a, c, s = _thread_setup(ctx)
    lead = _lead(ctx)
    k = _micron(ctx, "P", "the thread height k")
    dd = _micron(ctx, "Q", "the first depth of cut Δd")
    if k is None or k <= 0:
        ctx.alarm("G76: the thread height P(k) must be given and > 0 (PS0062)", "P")
    if dd is None or dd <= 0:
        ctx.alarm("G76: the first depth of cut Q(Δd) must be given and > 0 (PS0062)", "Q")
    st = ctx.store.get(76, {})
    m = st["m"] if "m" in st else _setting(ctx, "g76_finish_passes")
    ang = st["a"] if "a" in st else _setting(ctx, "g76_angle")
    ddmin = st["min_depth"] if "min_depth" in st else _setting(ctx, "g76_min_depth")
    d = st["allowance"] if "allowance" in st else _setting(ctx, "g76_allowance")
    if not any(abs(ang - t) < 1e-9 for t in simple.THREAD_ANGLES):
        ctx.alarm(f"G76: the tool angle {ang:g} ([parameters] g76_angle) must be one of "
                  f"80, 60, 55, 30, 29, 0")
    if m < 1 or m > 99 or abs(m - round(m)) > 1e-9:
        ctx.alarm(f"G76: the finishing pass count {m:g} ([parameters] g76_finish_passes) "
                  f"must be 1..99")
    if d >= k:
        ctx.alarm(f"G76: the finishing allowance d = {d:g} is not smaller than the thread "
                  f"height k = {k:g} (PS0062)", "P")
    taper = _word(ctx, "R") or 0.0
    _crest_check(ctx, a, c, s, k, taper)
    limit = min(simple.MAX_G76_PASSES, int(getattr(ctx, "max_passes", simple.MAX_G76_PASSES)))
    try:
        depths = simple.g76_depths(k, d, dd, max(ddmin, 0.0), int(round(m)), limit)
    except ValueError as exc:
        ctx.alarm(f"G76: {exc}")
    chamfer = _chamfer(ctx, lead)
    if chamfer[0] >= abs(c[1] - a[1]) - _TOL:
        ctx.alarm(f"G76: the end chamfer ({chamfer[0]:g} mm) is not shorter than the thread")
    simple.thread_passes(ctx, a, c, simple.flank_shifts(depths, ang, a, c), height=k,
                         taper=taper, lead=lead, start_angle=0.0, tool_angle=ang,
                         chamfer=chamfer, axes_return=True, shift_end=False)


# --------------------------------------------------------------------------- Haas


def _haas_one_block(ctx: Any, face: bool) -> None:
    if not ctx.has("D"):  # the FANUC two-block form, also read by current Haas software
        _g71_g72(ctx, face)
        return
    if not ctx.has("P") and not ctx.has("Q"):
        ctx.alarm(f"{_name(ctx)}: missing P and Q (the profile N numbers); Haas does not "
                  f"carry P over from an earlier block here", None)
    depth = _word(ctx, "D")
    if depth <= 0:
        ctx.alarm(f"{_name(ctx)} D{depth:g}: the depth of cut must be > 0", "D")
    extra = (_word(ctx, "I") or 0.0, _word(ctx, "K") or 0.0)
    r = _word(ctx, "R")
    if r is not None and abs(r - 1.0) > 1e-9 and abs(r - 0.001) > 1e-12:
        ctx.alarm(f"{_name(ctx)} R{r:g}: only R1 (type II) is a word of the one-block form", "R")
    _stock_removal(ctx, face, depth, extra, yasnac_type2=r is not None)


def haas_g71(ctx: Any) -> None:
    """Haas ``G71 P Q [U W] D [I K] [F S T] [R1]`` (§13): D depth per pass (radius, with a
    decimal point), I/K a further allowance the level passes leave and the last pass takes,
    R1 type II; without D the FANUC two-block form."""
    _haas_one_block(ctx, face=False)


def haas_g72(ctx: Any) -> None:
    """Haas ``G72 P Q [U W] D [I K] F``: as G71 with the passes parallel to X."""
    _haas_one_block(ctx, face=True)


def haas_g73(ctx: Any) -> None:
    """Haas ``G73 P Q D(passes) I K U W F`` (§13): I/K the relief from the first cut to the
    last (X radius, Z), D passes, spaced as FANUC's G73; without D the FANUC form."""
    if not ctx.has("D"):
        g73(ctx)
        return
    ns, nf = _pq(ctx)
    d = _whole(ctx, "D", "the number of passes D", 1, 99999)
    relief = (_word(ctx, "I") or 0.0, _word(ctx, "K") or 0.0)
    allowance = (_radius(ctx, _word(ctx, "U") or 0.0), _word(ctx, "W") or 0.0)
    _g73_passes(ctx, relief, d, ns, nf, allowance)


def constant_depths(k: float, d: float, step: float, finishing: int = 1,
                    max_passes: int = simple.MAX_G76_PASSES) -> list[tuple[float, bool]]:
    """Pass depths with a constant depth of cut: ``step``, 2·step, … up to k − d, a pass on
    k − d, then ``finishing`` passes at k (as :func:`~hnc_cam.nc.cycles_simple.g76_depths`)."""
    if not k > 0 or not step > 0 or not 0 <= d < k:
        raise ValueError(f"bad thread parameters (K{k:g}, D{step:g}, allowance {d:g})")
    out: list[tuple[float, bool]] = []
    n = 1
    while n * step < k - d - _TOL:
        out.append((n * step, False))
        if len(out) + 1 + finishing > max_passes:
            raise ValueError(f"more than {max_passes} passes (K{k:g}, D{step:g}): check the "
                             f"units")
        n += 1
    if d > _TOL:
        out.append((k - d, False))
    out.extend((k, True) for _ in range(max(finishing, 1)))
    return out


def haas_g76(ctx: Any) -> None:
    """Haas ``G76 X(U) Z(W) K D F [I A P Q]`` (§13): K thread height, D first depth
    (radius), I taper, A tool angle 0–120, P1–P4 infeed (1 single flank constant amount,
    2 alternate flanks constant amount, 3 single flank constant depth, 4 alternate flanks
    constant depth), Q start angle (0.001°). Finishing allowance, minimum cut and chamfer
    from the machine ([parameters] g76_allowance, g76_min_depth, thread_chamfer)."""
    if not ctx.has("K") and not ctx.has("D"):
        ctx.alarm("G76: the Haas G76 is one block, G76 X(U) Z(W) K(height) D(first cut) F(lead); "
                  "the FANUC two-block form is not read under haas", None)
    a, c, s = _thread_setup(ctx)
    lead = _lead(ctx)
    k = _word(ctx, "K")
    dd = _word(ctx, "D")
    if k is None or k <= 0:
        ctx.alarm("G76: the thread height K must be given and > 0", "K")
    if dd is None or dd <= 0:
        ctx.alarm("G76: the first depth of cut D must be given and > 0", "D")
    ang = _whole(ctx, "A", "the tool angle A", 0, 120)
    ang = 60 if ang is None else ang
    mode = _whole(ctx, "P", "the infeed P", 1, 4) or 1
    q = _micron(ctx, "Q", "the spindle start angle Q (0.001°)")
    d = _setting(ctx, "g76_allowance")
    ddmin = _setting(ctx, "g76_min_depth")
    if not 0 <= d < k:
        ctx.alarm(f"G76: the finishing allowance {d:g} ([parameters] g76_allowance) must be "
                  f">= 0 and smaller than K{k:g}", "K")
    taper = _word(ctx, "I") or 0.0
    _crest_check(ctx, a, c, s, k, taper)
    limit = min(simple.MAX_G76_PASSES, int(getattr(ctx, "max_passes", simple.MAX_G76_PASSES)))
    try:
        if mode in (1, 2):
            depths = simple.g76_depths(k, d, dd, max(ddmin, 0.0), 1, limit)
        else:
            depths = constant_depths(k, d, dd, 1, limit)
    except ValueError as exc:
        ctx.alarm(f"G76: {exc}")
    chamfer = _chamfer(ctx, lead)
    if chamfer[0] >= abs(c[1] - a[1]) - _TOL:
        ctx.alarm(f"G76: the end chamfer ({chamfer[0]:g} mm) is not shorter than the thread")
    simple.thread_passes(ctx, a, c, simple.flank_shifts(depths, ang, a, c, mode in (2, 4)),
                         height=k, taper=taper, lead=lead, start_angle=(q or 0.0) % 360.0,
                         tool_angle=float(ang), chamfer=chamfer, axes_return=True,
                         shift_end=False)


# --------------------------------------------------------------------------- tables

#: FANUC 0i-T cycles by G code (system A)
CYCLES = {71: g71, 72: g72, 73: g73, 74: g74, 75: g75, 76: g76, 90: g90, 92: g92, 94: g94}
#: the Haas differences, merged over :data:`CYCLES`
HAAS_CYCLES = {71: haas_g71, 72: haas_g72, 73: haas_g73, 76: haas_g76}
#: group-01 cycles: later blocks with axis words repeat the cycle, missing words kept
MODAL_CYCLES = frozenset({90, 92, 94})
