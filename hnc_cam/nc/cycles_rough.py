"""The compound stock-removal cycles of the HNC-21/22T: G71 (type I and II), G72 and G73.

Sources: the manual §3.3.7 "复合循环" (G71 figs. 3.3.24–3.3.29, G72 figs. 3.3.30–3.3.33,
G73 figs. 3.3.34–3.3.35, notes (5)) and appendix 1(2), the controller's own macros %0071,
%0072 and %0073. The planning is done by the one roughing engine,
:mod:`hnc_cam.geometry.roughing` (its docstring states the stock model and the pass order);
this module reads the words, validates them, gets the programmed profile from the
interpreter and emits the moves through the :class:`~hnc_cam.nc.context.CycleContext`.
The dialect-neutral halves (:func:`profile_blocks`, :func:`level_bound`,
:func:`engine_alarm`, :func:`emit`) also serve the FANUC and Haas decoders
(``hnc_cam.dialect.fanuc0it.cycles``).

Words (X is a diameter in G36, as X words always are; U/W/R/E as stated)

* ``G71 U(Δd) R(r) P(ns) Q(nf) X(Δx) Z(Δz) F S T``, type I: Δd depth per pass (radius,
  unsigned; its direction is that of A→A′), r retract, Δx/Δz finishing allowance: the
  profile is translated by (Δx/2, Δz) in G36 (Δx in G37). X and Z default to 0 (macro
  %0071 silently skips the whole cycle when either is missing; we rough with no allowance
  and warn).
* ``G71 U(Δd) R(r) P(ns) Q(nf) E(e) F S T``, type II: e is the X allowance in X-word units
  (e/2 radial in G36), positive for OD and negative for ID; no Z allowance.
* ``G72 W(Δd) R(r) P(ns) Q(nf) X(Δx) Z(Δz) F S T``: as G71 with the passes parallel to X.
* ``G73 U(ΔI) W(ΔK) R(r) P(ns) Q(nf) X(Δx) Z(Δz) F S T``: ΔI/ΔK total roughing stock
  (radius / Z), r the number of passes (a whole number >= 1).

F of the cycle block (or the modal F) is the roughing feed for every move including the
last pass along the offset profile; F/S/T inside ns…nf are for the finishing run of those
blocks after the cycle (the interpreter keeps them out of the cycle). After the cycle the
tool is back on A and execution continues with the next block (there is no G70).

Alarms (at the cycle block; profile problems name the profile block's line)

* P or Q missing; P/Q not found, block ns not G00/G01, M98/M99 inside ns…nf (raised by
  ``ctx.profile``); G72 with an X move in block ns;
* Δd missing or <= 0, R missing or <= 0 (the macros refuse R <= 0 too), G73 R not a whole
  number >= 1, G73 without U and W;
* U/W used as the incremental axis words they are elsewhere: W on G71, U on G72 (manual
  §3.3.2: U/W are not allowed in cycle blocks except as the cycle's own parameters);
  X/Z together with E (type II has no X/Z allowance);
* type I profile not monotonic in X (G71) / Z (G72); a profile that turns back against the
  cutting direction; a profile that does not reach the start side (its end B deeper than
  its start A′ as seen from A); A→A′ without motion along the level axis.
"""
from __future__ import annotations

from typing import Any, NoReturn, Optional

from ..geometry.primitives import Arc
from ..geometry.roughing import RoughingError, RoughPlan, pattern_repeat, rough_turn


def _int_word(ctx: Any, letter: str, what: str) -> int:
    v = ctx.word(letter)
    if v is None:
        ctx.alarm(f"G{ctx.code} needs {letter} ({what})", letter)
    if abs(v - round(v)) > 1e-9 or v < 0:
        ctx.alarm(f"G{ctx.code} {letter}{v:g}: {what} must be a block number", letter)
    return int(round(v))


def _x_units(ctx: Any, value: float) -> float:
    """An X-word-like value as a radius (halved in G36)."""
    return value / 2.0 if ctx.diameter_mode else value


def _profile(ctx: Any):
    ns = _int_word(ctx, "P", "the first block ns of the profile")
    nf = _int_word(ctx, "Q", "the last block nf of the profile")
    return (ns, nf) + profile_blocks(ctx, ns, nf)


def profile_blocks(ctx: Any, ns: int, nf: int):
    """The programmed path N``ns``…N``nf`` from ``ctx.profile`` as (segments, source lines,
    motions); an empty profile alarms at P. Shared by every dialect's decoder."""
    prof = ctx.profile(ns, nf)
    if not prof:
        ctx.alarm(f"G{ctx.code}: the profile N{ns}…N{nf} is empty", "P")
    segs = [p[0] for p in prof]
    lines = [p[1] for p in prof]
    motions = [p[2] for p in prof]
    return segs, lines, motions


def engine_alarm(ctx: Any, err: RoughingError, lines: list[int]) -> NoReturn:
    msg = f"G{ctx.code}: {err.message}"
    if err.index is not None and 0 <= err.index < len(lines):
        msg += f" (profile block at line {lines[err.index]})"
    ctx.alarm(msg)
    raise AssertionError("ctx.alarm returned")  # pragma: no cover


def emit(ctx: Any, plan: RoughPlan) -> None:
    for w in plan.warnings:
        ctx.warn(f"G{ctx.code}: {w}")
    for m in plan.moves:
        s = m.seg
        x, z = s.end
        if m.kind == "rapid":
            ctx.rapid(x, z)
        elif isinstance(s, Arc):
            ctx.arc(x, z, s.center, s.cw)
        else:
            ctx.feed(x, z)


def _positive(ctx: Any, letter: str, what: str) -> float:
    v = ctx.word(letter)
    if v is None:
        ctx.alarm(f"G{ctx.code} needs {letter} ({what})", letter)
    if v <= 0:
        ctx.alarm(f"G{ctx.code} {letter}{v:g}: {what} must be > 0", letter)
    return float(v)


def _max_passes(ctx: Any) -> int:
    return int(getattr(ctx, "max_passes", 10_000))


def level_bound(ctx: Any, start, segs, allowance, depth: float, face: bool,
                letter: Optional[str]) -> None:
    """Alarm when the depth of cut is so small against the profile's extent along the level
    axis that the cycle would take more levels than the machine's [limits] cycle_passes
    (counted before planning, so that planning never runs away). ``letter``: the word of
    the block that gave the depth, or None when it came from elsewhere (an earlier block,
    the machine)."""
    k = 1 if face else 0
    far = 0.0
    for sg in segs:
        for p in (sg.start, sg.end):
            far = max(far, abs(p[k] - start[k]))
        if isinstance(sg, Arc):
            far = max(far, abs(sg.center[k] - start[k]) + sg.radius)
    far += abs(allowance[k])
    levels = far / depth
    limit = _max_passes(ctx)
    if levels > limit:
        ctx.alarm(f"G{ctx.code} {letter or 'depth of cut '}{depth:g}: about {levels:.0f} pass "
                  f"levels over {far:.3f} mm, more than the machine's limit of {limit} ([limits] cycle_passes)",
                  letter)


def _g71_g72(ctx: Any, face: bool) -> RoughPlan:
    code = ctx.code
    depth_letter, wrong = ("W", "U") if face else ("U", "W")
    if ctx.has(wrong):
        ctx.alarm(f"G{code}: {wrong} is not a word of G{code} (incremental U/W are not allowed "
                  f"in a cycle block; the depth of cut is {depth_letter})", wrong)
    depth = _positive(ctx, depth_letter, "depth of cut Δd")
    retract = _positive(ctx, "R", "retract r")
    pockets = False
    if ctx.has("E"):
        if face:
            ctx.alarm("G72: E is not a word of G72 (type II with E exists for G71 only)", "E")
        if ctx.has("X") or ctx.has("Z"):
            ctx.alarm("G71 type II (E) takes no X/Z allowance: use either E or X/Z",
                      "X" if ctx.has("X") else "Z")
        pockets = True
        allowance = (_x_units(ctx, float(ctx.word("E"))), 0.0)
    else:
        if not (ctx.has("X") and ctx.has("Z")):
            ctx.warn(f"G{code}: finishing allowance X/Z not programmed, taken as 0")
        dx = ctx.word("X")
        dz = ctx.word("Z")
        allowance = (_x_units(ctx, float(dx or 0.0)), float(dz or 0.0))
    ns, nf, segs, lines, motions = _profile(ctx)
    start = ctx.pos
    level_bound(ctx, start, segs, allowance, depth, face, depth_letter)
    if face and segs:
        a1 = segs[0].end
        if abs(a1[0] - start[0]) > 1e-6:
            ctx.alarm(f"G72: block N{ns} (A→A′) moves in X; it must move along Z only "
                      f"(line {lines[0]})", "P")
    try:
        return rough_turn(start, segs, motions, depth=depth, retract=retract,
                          allowance=allowance, face=face, pockets=pockets)
    except RoughingError as err:
        engine_alarm(ctx, err, lines)


def _g73(ctx: Any) -> RoughPlan:
    count_w = _positive(ctx, "R", "number of passes r")
    if abs(count_w - round(count_w)) > 1e-9:
        ctx.alarm(f"G73 R{count_w:g}: the number of passes must be a whole number", "R")
    count = int(round(count_w))
    limit = _max_passes(ctx)
    if count > limit:
        ctx.alarm(f"G73 R{count}: more passes than the machine's limit of {limit} "
                  f"([limits] cycle_passes)", "R")
    if not ctx.has("U") and not ctx.has("W"):
        ctx.alarm("G73 needs U and/or W (total roughing stock ΔI/ΔK)", "U")
    stock = (float(ctx.word("U") or 0.0), float(ctx.word("W") or 0.0))
    if not (ctx.has("X") and ctx.has("Z")):
        ctx.warn("G73: finishing allowance X/Z not programmed, taken as 0")
    allowance = (_x_units(ctx, float(ctx.word("X") or 0.0)), float(ctx.word("Z") or 0.0))
    ns, nf, segs, lines, motions = _profile(ctx)
    left = getattr(ctx, "moves_left", None)
    if left is not None and count * (len(segs) + 2) > left:
        ctx.alarm(f"G73 R{count}: {count} passes over a profile of {len(segs)} blocks exceed the "
                  f"moves the toolpath may still take ({left}, [limits] moves)", "R")
    try:
        return pattern_repeat(ctx.pos, segs, motions, stock=stock, allowance=allowance,
                              count=count)
    except RoughingError as err:
        engine_alarm(ctx, err, lines)


def plan_cycle(code: int, ctx: Any) -> RoughPlan:
    """Validate the block and plan G``code`` without emitting anything (alarms as
    :func:`execute`)."""
    if code == 71:
        return _g71_g72(ctx, face=False)
    if code == 72:
        return _g71_g72(ctx, face=True)
    if code == 73:
        return _g73(ctx)
    ctx.alarm(f"G{code:02d} is not a stock-removal cycle")
    raise AssertionError("unreachable")  # pragma: no cover


def execute(code: int, ctx: Any) -> None:
    """Run G71/G72/G73 of the current block through the interpreter's ``ctx``."""
    emit(ctx, plan_cycle(code, ctx))
