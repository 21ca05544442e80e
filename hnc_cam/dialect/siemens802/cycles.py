"""The SINUMERIK 802S/802C turning cycles LCYC82, LCYC83, LCYC840, LCYC85, LCYC93, LCYC94,
LCYC95 and LCYC97 (``CYCLES``: name -> handler of the interpreter's cycle context).

A cycle reads its transfer parameters R100-R249 (``ctx.r(n)``, 0.0 when never set) and emits
its legs through the context (x as radius, z); the executor sets G0 G90 G40 after it. The
parameters, the pass patterns and our reading where the sources are silent are in
``docs/SIEMENS.md`` ("Cycles"). The motion reuses the shared engines: the roughing engine
(:func:`hnc_cam.geometry.roughing.rough_turn`) for LCYC95, the multiple-pass thread engine
(:func:`hnc_cam.nc.cycles_simple.thread_passes`) for LCYC97 and the peck legs of the FANUC
G74/G75 (:func:`hnc_cam.dialect.fanuc0it.cycles.peck_moves`) for the LCYC93 plunges.

Alarms carry the cycle alarm's number and text, then what was wrong:
``61002 machining type wrongly programmed: LCYC95 R105=13 (1-12)``.
"""
from __future__ import annotations

import math
from typing import Any, Callable, Optional

from ...geometry.corner import CornerError, corner
from ...geometry.intersect import horizontal_hits, intersect, vertical_hits
from ...geometry.primitives import Arc, Line, Point, reverse_chain
from ...geometry.roughing import RoughingError, RoughMove, first_non_monotonic, rough_turn
from ...geometry.tip import tip_direction
from ...nc.compensation import CompItem, compensate_moves
from ...nc.cycles_simple import thread_passes
from ..fanuc0it.cycles import peck_moves

_TOL = 1e-9
#: LCYC83 chip breaking: the drill backs off this far (mm) after each stroke (R127=0)
CHIP_BREAK = 1.0
#: LCYC93: the chip-breaking back-off after each infeed and the clearance above the
#: groove's edge from which every plunge starts (mm)
GROOVE_BACKOFF = 1.0
GROOVE_CLEARANCE = 1.0
#: LCYC97: the start point lies this far (mm, radius) outside the crest
THREAD_CLEARANCE = 1.0

ALARM_TEXT = {
    61001: "thread lead wrongly defined",
    61002: "machining type wrongly programmed",
    61101: "reference plane wrongly defined",
    61102: "no spindle direction programmed",
    61107: "first drilling depth wrongly defined",
    61601: "finished part diameter too small",
    61602: "tool width wrongly defined",
    61603: "groove form wrongly defined",
    61605: "contour wrongly defined",
    61606: "error in contour preparation",
    61608: "wrong tool point position programmed",
    61609: "form wrongly defined",
    61610: "no infeed depth programmed",
    17040: "illegal axis index",
}


def _name(ctx: Any) -> str:
    return getattr(ctx, "name", None) or f"LCYC{int(ctx.code)}"


def _alarm(ctx: Any, number: int, detail: str):
    ctx.alarm(f"{number} {ALARM_TEXT[number]}: {_name(ctx)} {detail}")
    raise AssertionError("ctx.alarm returned")  # pragma: no cover


def _r(ctx: Any, n: int) -> float:
    v = float(ctx.r(n))
    if not math.isfinite(v):
        ctx.alarm(f"{_name(ctx)} R{n}={v}: not a finite number")
    return v


def _whole(ctx: Any, n: int, lo: int, hi: int, number: Optional[int], what: str) -> int:
    v = _r(ctx, n)
    if abs(v - round(v)) > 1e-9 or not lo <= round(v) <= hi:
        msg = f"R{n}={v:g}: {what} must be a whole number {lo}-{hi}"
        if number is None:
            ctx.alarm(f"{_name(ctx)} {msg}")
        _alarm(ctx, number, msg)
    return int(round(v))


def _need_plane(ctx: Any, plane: int) -> None:
    got = getattr(ctx, "plane", plane)
    if got != plane:
        _alarm(ctx, 17040, f"needs G{plane} active (G{got} is)")


def _need_g23(ctx: Any) -> None:
    if not ctx.diameter_mode:
        _alarm(ctx, 17040, "needs G23 (diameter programming) active (G22 is)")


def _feed(v: float) -> Optional[float]:
    return v if v > 0 else None


class _Legs:
    """Emits legs through the context from the current point; legs that do not move are
    dropped."""

    def __init__(self, ctx: Any):
        self.ctx = ctx
        self.at: Point = tuple(ctx.pos)

    def _moved(self, p: Point) -> bool:
        return abs(p[0] - self.at[0]) > 1e-7 or abs(p[1] - self.at[1]) > 1e-7

    def rapid(self, p: Point) -> None:
        if self._moved(p):
            self.ctx.rapid(p[0], p[1])
            self.at = (p[0], p[1])

    def feed(self, p: Point, f: Optional[float] = None) -> None:
        if self._moved(p):
            self.ctx.feed(p[0], p[1], f)
            self.at = (p[0], p[1])

    def arc(self, s: Arc, f: Optional[float] = None) -> None:
        self.ctx.arc(s.end[0], s.end[1], s.center, s.cw, f)
        self.at = s.end

    def thread(self, p: Point, lead: float) -> None:
        if self._moved(p):
            self.ctx.thread(p[0], p[1], lead)
            self.at = (p[0], p[1])

    def dwell(self, seconds: float) -> None:
        if seconds > 0:
            self.ctx.dwell(seconds)


# --------------------------------------------------------------------------- drilling


def _planes(ctx: Any) -> tuple[float, float, float, float]:
    """R101 retraction plane, R103 reference plane, R104 final depth and the reference plane
    brought forward by the safety distance R102 (toward the retraction side), checked:
    61101 when R103 = R104 or R103 does not lie between R101 and R104."""
    _need_plane(ctx, 17)
    rtp, sdis, rfp, dp = _r(ctx, 101), abs(_r(ctx, 102)), _r(ctx, 103), _r(ctx, 104)
    if abs(rfp - dp) <= _TOL:
        _alarm(ctx, 61101, f"R103={rfp:g} equals R104={dp:g}")
    if not min(rtp, dp) - _TOL <= rfp <= max(rtp, dp) + _TOL:
        _alarm(ctx, 61101, f"R103={rfp:g} does not lie between R101={rtp:g} and R104={dp:g}")
    up = 1.0 if rfp > dp else -1.0
    return rtp, rfp, dp, rfp + up * sdis


def lcyc82(ctx: Any) -> None:
    """Drilling, centring: G0 to the reference plane + safety distance, G1 to R104 at the
    programmed feed, dwell R105, G0 to the retraction plane R101."""
    rtp, _rfp, dp, safe = _planes(ctx)
    x = ctx.pos[0]
    legs = _Legs(ctx)
    legs.rapid((x, safe))
    legs.feed((x, dp))
    legs.dwell(_r(ctx, 105))
    legs.rapid((x, rtp))


def drill_strokes(first: float, total: float, degression: float,
                  max_strokes: int = 10_000) -> list[float]:
    """The depths (from the reference plane, increasing) at which the LCYC83 strokes end.

    The first stroke is ``first``; each next one is the previous minus the degression R111
    while that stays greater than R111, else R111 (R111 = 0: every stroke as the first).
    When the depth left is less than twice the next stroke, it is split into two equal final
    strokes (one stroke when it is not more than the next stroke)."""
    out = [min(first, total)]
    step = first
    while total - out[-1] > 1e-9:
        if len(out) > max_strokes:
            raise ValueError(f"more than {max_strokes} strokes")
        if degression > 0:
            step = step - degression if step - degression > degression else degression
        left = total - out[-1]
        if left <= step + 1e-9:
            out.append(total)
        elif left < 2.0 * step - 1e-9:
            out.append(out[-1] + left / 2.0)
            out.append(total)
        else:
            out.append(out[-1] + step)
    return out


def anticipation(depth: float) -> float:
    """LCYC83 chip removal: how far before the last stroke's depth the drill re-enters in
    rapid (the document: 'calculated in the cycle'): 0.6 mm up to a drilling depth of 30 mm,
    else depth / 50, at most 7 mm."""
    return 0.6 if depth <= 30.0 else min(depth / 50.0, 7.0)


def lcyc83(ctx: Any) -> None:
    """Deep-hole drilling: strokes from R110 with the R111 degression, dwell R105 at each
    depth; R127=0 backs off 1 mm at the drilling feed (chip breaking), R127=1 returns in
    G0 to the reference plane + safety distance, dwells R109 and re-enters in G0 to the
    anticipation distance before the last depth (chip removal); G0 to R101 at the end."""
    rtp, rfp, dp, safe = _planes(ctx)
    mode = _whole(ctx, 127, 0, 1, None, "machining type (0 chip breaking, 1 chip removal)")
    up = 1.0 if rfp > dp else -1.0
    total = abs(rfp - dp)
    first_z = _r(ctx, 110)
    first = (rfp - first_z) * up
    if first <= _TOL or first > total + _TOL:
        _alarm(ctx, 61107, f"R110={first_z:g} does not lie between R103={rfp:g} and "
                           f"R104={dp:g}")
    degression = abs(_r(ctx, 111))
    try:
        strokes = drill_strokes(first, total, degression,
                                int(getattr(ctx, "max_passes", 10_000)))
    except ValueError as exc:
        ctx.alarm(f"{_name(ctx)}: {exc} (R110={first_z:g}, R111={degression:g}), more than "
                  f"the machine's limit ([limits] cycle_passes)")
    f_drill, f_first = _feed(_r(ctx, 107)), _feed(_r(ctx, 108))
    dwell_bottom, dwell_top = _r(ctx, 105), _r(ctx, 109)
    lead = anticipation(total)
    x = ctx.pos[0]
    legs = _Legs(ctx)
    legs.rapid((x, safe))
    for i, d in enumerate(strokes):
        legs.feed((x, rfp - up * d), f_first if i == 0 else f_drill)
        legs.dwell(dwell_bottom)
        if i == len(strokes) - 1:
            break
        if mode == 0:
            legs.feed((x, rfp - up * (d - CHIP_BREAK)), f_drill)
        else:
            legs.rapid((x, safe))
            legs.dwell(dwell_top)
            legs.rapid((x, rfp - up * max(d - lead, 0.0)))
    legs.rapid((x, rtp))


def lcyc840(ctx: Any) -> None:
    """Tapping with a compensating chuck: G0 to the reference plane + safety distance, G33
    (lead R106) to R104 in the spindle direction R126, G33 back to the safety plane (the
    spindle reversed), G0 to R101, then M5."""
    rtp, _rfp, dp, safe = _planes(ctx)
    lead = _r(ctx, 106)
    if lead <= 0:
        _alarm(ctx, 61001, f"R106={lead:g}: the thread lead must be > 0")
    sdir = _r(ctx, 126)
    if sdir not in (3.0, 4.0):
        _alarm(ctx, 61102, f"R126={sdir:g}: the spindle direction must be 3 (M3) or 4 (M4)")
    x = ctx.pos[0]
    legs = _Legs(ctx)
    spindle = getattr(ctx, "spindle", None)  # M3/M4/M5 from a cycle, where the context has it
    legs.rapid((x, safe))
    if spindle is not None:
        spindle(int(sdir))
    legs.thread((x, dp), lead)
    if spindle is not None:
        spindle(7 - int(sdir))  # reversed: M3 <-> M4
    legs.thread((x, safe), lead)
    legs.rapid((x, rtp))
    if spindle is not None:
        spindle(5)


def lcyc85(ctx: Any) -> None:
    """Boring: G0 to the reference plane + safety distance, G1 to R104 at R107, dwell R105,
    G1 back to the safety plane at R108, G0 to R101."""
    rtp, _rfp, dp, safe = _planes(ctx)
    x = ctx.pos[0]
    legs = _Legs(ctx)
    legs.rapid((x, safe))
    legs.feed((x, dp), _feed(_r(ctx, 107)))
    legs.dwell(_r(ctx, 105))
    legs.feed((x, safe), _feed(_r(ctx, 108)))
    legs.rapid((x, rtp))


# --------------------------------------------------------------------------- LCYC95

#: R105 -> (face, internal); stage: 0 roughing, 1 finishing, 2 complete
def _lcyc95_type(ctx: Any) -> tuple[bool, bool, int]:
    v = _r(ctx, 105)
    if abs(v - round(v)) > 1e-9 or not 1 <= round(v) <= 12:
        _alarm(ctx, 61002, f"R105={v:g} (1-12)")
    n = int(round(v)) - 1
    kind, stage = n % 4, n // 4
    return kind in (1, 3), kind in (2, 3), stage


def _extent(segs, axis: int) -> tuple[float, float]:
    lo, hi = math.inf, -math.inf
    for s in segs:
        b = s.bbox()
        lo, hi = min(lo, b[axis]), max(hi, b[axis + 2])
    return lo, hi


def _contour(ctx: Any):
    name = ctx.text("_CNAME") if hasattr(ctx, "text") else None
    if not name:
        _alarm(ctx, 61606, "_CNAME does not name a contour subprogram")
    items = ctx.contour(name)
    pos = ctx.pos
    if len(items) > 1 and abs(items[0][0].start[0] - pos[0]) < 1e-6 \
            and abs(items[0][0].start[1] - pos[1]) < 1e-6:
        items = items[1:]  # the move from the tool's position to the contour's first point
    segs = [it[0] for it in items if it[0].length > 1e-9]
    lines = [it[1] for it in items if it[0].length > 1e-9]
    motions = [it[2] for it in items if it[0].length > 1e-9]
    if not segs:
        _alarm(ctx, 61606, f"the contour {name} has no motion")
    return name, segs, lines, motions


def lcyc95(ctx: Any) -> None:
    """Stock removal along the contour subprogram ``_CNAME`` (see docs/SIEMENS.md)."""
    _need_g23(ctx)
    face, internal, stage = _lcyc95_type(ctx)
    allowance = abs(_r(ctx, 106))
    infeed = _r(ctx, 108)
    if stage != 1 and infeed <= 0:
        _alarm(ctx, 61610, f"R108={infeed:g}: roughing needs an infeed depth > 0")
    insertion = _r(ctx, 109)
    if not 0 <= insertion < 90:
        _alarm(ctx, 61606, f"R109={insertion:g}: the insertion angle must be 0-89.999")
    retract = abs(_r(ctx, 110))
    f_rough, f_finish = _feed(_r(ctx, 111)), _feed(_r(ctx, 112))
    name, segs, lines, motions = _contour(ctx)
    cut_axis = 0 if face else 1
    lvl_axis = 1 - cut_axis
    lvl_sign = -1.0 if (internal and not face) else 1.0  # the stock lies toward +level

    def level(p: Point) -> float:
        return lvl_sign * p[lvl_axis]

    p0, pn = segs[0].start, segs[-1].end
    flip = level(p0) > level(pn) + 1e-9
    if abs(level(p0) - level(pn)) <= 1e-9:  # no rise: cut toward -Z, faces toward the centre
        want = (1.0 if internal else -1.0) if face else -1.0
        flip = (pn[cut_axis] - p0[cut_axis]) * want < 0
    if flip:
        segs, lines, motions = reverse_chain(segs), lines[::-1], motions[::-1]
        p0, pn = segs[0].start, segs[-1].end
    dcut = pn[cut_axis] - p0[cut_axis]
    if abs(dcut) <= 1e-9:
        _alarm(ctx, 61606, f"the contour {name} does not move along "
                           f"{'X' if face else 'Z'}")
    csign = 1.0 if dcut > 0 else -1.0
    bad = first_non_monotonic(segs, cut_axis, int(csign))
    if bad is not None:
        _alarm(ctx, 61605, f"the contour {name} turns back against the cutting direction "
                           f"at line {lines[bad]} (an undercut the tool cannot reach)")
    # the allowance: a translation by R106 along both axes toward the stock
    lvl_vec = [0.0, 0.0]
    lvl_vec[lvl_axis] = lvl_sign
    cut_vec = [0.0, 0.0]
    cut_vec[cut_axis] = csign
    allow = (allowance * (lvl_vec[0] - cut_vec[0]), allowance * (lvl_vec[1] - cut_vec[1]))
    lo, hi = _extent(segs, lvl_axis)
    top = (hi if lvl_sign > 0 else -lo) + allowance + retract  # the level of the start point
    e = list(p0)
    e[cut_axis] -= csign * (retract + allowance)
    e = (e[0], e[1])
    a = list(e)
    a[lvl_axis] = lvl_sign * top
    a = (a[0], a[1])
    legs = _Legs(ctx)
    order = (lvl_axis, cut_axis) if level(ctx.pos) < top - 1e-9 else (cut_axis, lvl_axis)
    for ax in order:  # to the start point, one axis at a time, outside the stock first
        p = list(legs.at)
        p[ax] = a[ax]
        legs.rapid((p[0], p[1]))
    if stage != 1:
        deepest = level(segs[0].start)
        for s in segs:
            b = s.bbox()
            deepest = min(deepest, lvl_sign * (b[lvl_axis] if lvl_sign > 0 else b[lvl_axis + 2]))
        span = top - (deepest + allowance)
        limit = int(getattr(ctx, "max_passes", 10_000))
        if span / infeed > limit:
            ctx.alarm(f"{_name(ctx)} R108={infeed:g}: about {span / infeed:.0f} cuts, more than "
                      f"the machine's limit of {limit} ([limits] cycle_passes)")
        depth = span / max(1, math.ceil(span / infeed - 1e-9))
        prof = [Line(a, e), Line(e, p0)] + list(segs)
        mot = ["rapid", "feed"] + list(motions)
        try:
            plan = rough_turn(a, prof, mot, depth=depth, retract=retract, allowance=allow,
                              face=face, pockets=True,
                              sign_warning="the finishing allowance points toward the part")
        except RoughingError as err:
            where = ""
            if err.index is not None and 2 <= err.index < len(prof):
                where = f" at line {lines[err.index - 2]}"
            _alarm(ctx, 61606, f"the contour {name}{where}: {err.message}")
        for w in plan.warnings:
            ctx.warn(f"{_name(ctx)}: {w}")

        def at(lv: float, t: float) -> Point:
            p = [0.0, 0.0]
            p[lvl_axis] = lvl_sign * lv
            p[cut_axis] = csign * t
            return (p[0], p[1])

        moves = relief_insertion(plan.moves, insertion, level, lambda p: csign * p[cut_axis],
                                 at, plan.offset_profile, face)
        for m in moves:
            s = m.seg
            if m.kind == "rapid":
                legs.rapid(s.end)
            elif isinstance(s, Arc):
                legs.arc(s, f_rough)
            else:
                legs.feed(s.end, f_rough)
        legs.rapid(a)
    if stage != 0:
        legs.rapid(e)
        p = list(segs[-1].end)
        p[lvl_axis] = lvl_sign * (level(segs[-1].end) + retract)
        out = (p[0], p[1])
        radius, tip = ctx.tool_nose() if hasattr(ctx, "tool_nose") else (0.0, 0)
        if radius > 0:
            # the tool nose radius compensation of the finishing pass: the tool on the stock
            # side of the contour, G41 or G42 by the cutting direction (view Z right, X up)
            side = 41 if -cut_vec[0] * lvl_vec[1] + cut_vec[1] * lvl_vec[0] > 0 else 42
            items = [CompItem(Line(e, p0), "feed", lines[0], "start", None)]
            items += [CompItem(sg, m, ln, "normal", None) for sg, m, ln in zip(segs, motions, lines)]
            items.append(CompItem(Line(segs[-1].end, out), "rapid", lines[-1], "cancel", None))
            path = compensate_moves(items, radius, int(tip), side)
            for it in items:
                for note in it.notes:
                    ctx.warn(f"{_name(ctx)}: {note}")
            path = [(sg, it.kind) for sg, it in path]
        else:
            path = [(Line(e, p0), "feed")] + list(zip(segs, motions)) + \
                [(Line(segs[-1].end, out), "rapid")]
        for sg, m in path:
            if m == "rapid":
                legs.rapid(sg.end)
            elif isinstance(sg, Arc):
                legs.arc(sg, f_finish)
            else:
                legs.feed(sg.end, f_finish)
        legs.rapid(out)
        q = list(out)
        q[lvl_axis] = a[lvl_axis]
        legs.rapid((q[0], q[1]))
        legs.rapid(a)


def relief_insertion(moves: list, angle: float, level: Callable[[Point], float],
                     along: Callable[[Point], float], at: Callable[[float, float], Point],
                     wall: list, face: bool) -> list:
    """The roughing ``moves`` (:class:`RoughMove`) with each plunge into a relief cut entered
    at ``angle`` (degrees, R109) to the longitudinal axis of the cut (Z for longitudinal
    machining, X for face machining), descending in the cutting direction.

    ``level(p)`` is a point's depth coordinate (larger toward the stock), ``along(p)`` its
    place along the cut (growing in the cutting direction), ``at(level, along)`` the point,
    ``wall`` the allowance-offset contour (the part the entry must not enter). A relief pass
    at level ``u`` below the level ``w`` above it, starting at ``s`` (on the relief's wall):
    the entry is the line at ``angle`` that ends at ``(u, s)``, from the level ``w`` (the
    tool comes down to its start in rapid over the cleared level). Where the relief's wall
    is steeper than ``angle``, that line would enter the part: the entry then starts where
    the line leaves the wall, and the tool reaches that point by a straight plunge from the
    level ``w``; a vertical wall leaves the straight plunge at ``s``. The pass's level is
    cut whole from ``s``, so no wedge is left. ``angle`` 0 (R109 not set): the moves
    unchanged, a straight plunge."""
    if angle <= 0.0:
        return list(moves)
    run = 1.0 / math.tan(math.radians(angle))  # the advance along the cut per mm of depth

    def inside(p: Point) -> bool:
        hits = horizontal_hits(wall, p[0]) if face else vertical_hits(wall, p[1])
        if not hits:
            return False
        top = max(level(at_axis(v, p)) for _, v in hits)
        return level(p) < top - 1e-7

    def at_axis(v: float, p: Point) -> Point:
        return (p[0], v) if face else (v, p[1])

    def free_rise(u: float, s: float, w: float) -> float:
        """How far (in depth) the entry line rises from (u, s) toward the level w before it
        would enter the part."""
        p0, p1 = at(u, s), at(w, s - (w - u) * run)
        line = Line(p0, p1)
        cuts = {0.0, w - u}
        for seg in wall:
            for q in intersect(line, seg):
                lam = level(q) - u
                if 0.0 < lam < w - u:
                    cuts.add(lam)
        marks = sorted(cuts)
        for a, b in zip(marks, marks[1:]):
            m = 0.5 * (a + b)
            if inside(at(u + m, s - m * run)):
                return a
        return w - u

    out: list = []
    for i, m in enumerate(moves):
        if (m.role == "plunge" and i + 1 < len(moves) and moves[i + 1].role == "cut" and out
                and out[-1].role in ("approach", "link") and out[-1].kind == "rapid"
                and math.dist(out[-1].seg.end, m.seg.start) < 1e-9):
            w, s = level(m.seg.start), along(m.seg.start)
            u = level(m.seg.end)
            lam = free_rise(u, s, w)
            tc = s - lam * run
            ap = out.pop()
            src = ap.seg.start
            prev = out[-1] if out else None
            if (prev is not None and prev.kind == "rapid" and prev.role == "link"
                    and math.dist(prev.seg.end, src) < 1e-9
                    and abs(level(prev.seg.start) - level(src)) < 1e-9):
                out.pop()  # the travel along the level: straight to the entry's start
                src = prev.seg.start
            mid = at(level(src), tc)
            if math.dist(src, mid) > 1e-12:
                out.append(RoughMove("rapid", Line(src, mid), "link", ap.level))
            top = at(w, tc)
            if math.dist(mid, top) > 1e-12:
                out.append(RoughMove("rapid", Line(mid, top), "approach", ap.level))
            low = at(u + lam, tc)
            if lam < w - u - 1e-9:
                out.append(RoughMove("feed", Line(top, low), "plunge", m.level))
            if lam > 1e-9:
                out.append(RoughMove("feed", Line(low, m.seg.end), "plunge", m.level))
            continue
        out.append(m)
    return out


# --------------------------------------------------------------------------- LCYC97


def thread_depths(depth: float, allowance: float, cuts: int) -> list[float]:
    """LCYC97 pass depths (from the crest): ``cuts`` roughing cuts of constant chip area to
    ``depth - allowance`` (cut n at (depth - allowance)·√(n/cuts)), then one finishing cut at
    ``depth`` when there is an allowance."""
    rough = depth - allowance
    out = [rough * math.sqrt(n / cuts) for n in range(1, cuts + 1)]
    if allowance > _TOL:
        out.append(depth)
    return out


def lcyc97(ctx: Any) -> None:
    """Thread cutting from (R100, R101) to (R102, R103) with lead R104 (see docs/SIEMENS.md)."""
    _need_g23(ctx)
    v = _r(ctx, 105)
    if v not in (1.0, 2.0):
        _alarm(ctx, 61002, f"R105={v:g} (1 external, 2 internal)")
    s = 1.0 if v == 1.0 else -1.0
    lead = _r(ctx, 104)
    if lead <= 0:
        _alarm(ctx, 61001, f"R104={lead:g}: the thread lead must be > 0")
    x1, z1, x2, z2 = _r(ctx, 100) / 2.0, _r(ctx, 101), _r(ctx, 102) / 2.0, _r(ctx, 103)
    length = abs(z2 - z1)
    if length <= _TOL:
        ctx.alarm(f"{_name(ctx)}: the thread has no length along Z (R101=R103={z1:g})")
    if abs(x2 - x1) > length:
        ctx.alarm(f"{_name(ctx)}: a thread steeper than 45 degrees (a face thread) is not "
                  f"cut by this cycle (R100={2 * x1:g} R102={2 * x2:g} over {length:g} in Z)")
    depth = _r(ctx, 111)
    if depth <= 0:
        ctx.alarm(f"{_name(ctx)} R111={depth:g}: the thread depth must be > 0")
    allowance = abs(_r(ctx, 106))
    if allowance >= depth:
        ctx.alarm(f"{_name(ctx)} R106={allowance:g}: the finishing allowance must be smaller "
                  f"than the thread depth R111={depth:g}")
    run_in, run_out = abs(_r(ctx, 109)), abs(_r(ctx, 110))
    limit = int(getattr(ctx, "max_passes", 10_000))
    cuts = _whole(ctx, 113, 1, limit, None, "the number of roughing cuts")
    starts = _whole(ctx, 114, 1, 99, None, "the number of thread starts")
    if cuts * starts > limit:
        ctx.alarm(f"{_name(ctx)}: {cuts} cuts of {starts} starts, more passes than the machine's "
                  f"limit of {limit} ([limits] cycle_passes)")
    offset = _r(ctx, 112) % 360.0
    dz = 1.0 if z2 > z1 else -1.0
    slope = (x2 - x1) / (z2 - z1)
    zs, ze = z1 - dz * run_in, z2 + dz * run_out
    crest_s, crest_e = x1 + slope * (zs - z1), x1 + slope * (ze - z1)
    if min(crest_s, crest_e) - (depth if s > 0 else 0.0) <= 0:
        ctx.alarm(f"{_name(ctx)}: the thread root lies on or beyond the axis")
    far = max(crest_s, crest_e) if s > 0 else min(crest_s, crest_e)
    a = (far + s * THREAD_CLEARANCE, zs)
    c = (crest_e - s * depth, ze)
    legs = _Legs(ctx)
    pos = ctx.pos
    if s * (pos[0] - a[0]) < 0:  # below the start point's X: out in X first
        legs.rapid((a[0], pos[1]))
    legs.rapid(a)
    for t in thread_depths(depth, allowance, cuts):
        for j in range(starts):
            thread_passes(ctx, a, c, [(t, 0.0)], height=depth, taper=crest_s - crest_e,
                          lead=lead, start_angle=(offset + j * 360.0 / starts) % 360.0,
                          tool_angle=60.0, axes_return=True)


# --------------------------------------------------------------------------- LCYC93

#: R105 -> (face, internal, start on the right)
_GROOVE_TYPES = {1: (False, False, False), 2: (True, False, False), 3: (False, True, False),
                 4: (True, True, False), 5: (False, False, True), 6: (True, False, True),
                 7: (False, True, True), 8: (True, True, True)}


def groove_outline(width: float, depth: float, angle: float, edge: float,
                   base: float) -> list[tuple[float, float]]:
    """The groove's outline in its own frame (w across the width from the start edge, d into
    the part), from the surface left of the groove to the surface right of it: the flanks at
    ``angle`` degrees to the depth direction (the width is measured at the surface), the
    edge chamfers ``edge`` and the base chamfers ``base`` cut along both lines from the
    corner (hnc_cam.geometry.corner). Raises ValueError when the form does not close."""
    t = math.tan(math.radians(angle))
    bw = width - 2.0 * depth * t
    if bw <= _TOL:
        raise ValueError(f"the flanks meet above the base (base width {bw:g})")
    far = max(edge, 1.0) * 2.0 + 1.0
    pts = [(-far, 0.0), (0.0, 0.0), (depth * t, depth), (width - depth * t, depth),
           (width, 0.0), (width + far, 0.0)]
    sizes = {1: edge, 2: base, 3: base, 4: edge}
    out = [pts[0]]
    for i in range(1, 5):
        size = sizes[i]
        if size <= _TOL:
            out.append(pts[i])
            continue
        try:
            cn = corner(out[-1], pts[i], pts[i + 1], "C", size)
        except CornerError:
            raise ValueError("a chamfer on a straight corner")
        if not cn.fits:
            raise ValueError(f"the chamfer {size:g} does not fit its corner")
        if math.hypot(cn.start[0] - out[-1][0], cn.start[1] - out[-1][1]) < -_TOL:
            raise ValueError("chamfers overlap")
        out.extend([cn.start, cn.end])
    out.append(pts[5])
    # the base chamfers must leave a base: the inner points keep their order along w
    ws = [p[0] for p in out[1:-1]]
    if any(b < a - 1e-9 for a, b in zip(ws, ws[1:])):
        raise ValueError("the chamfers overlap")
    return out


def _bottom(outline, w: float) -> float:
    """The depth of the outline below ``w`` (its deepest point on that vertical line)."""
    best = -math.inf
    for (w0, d0), (w1, d1) in zip(outline, outline[1:]):
        lo, hi = min(w0, w1), max(w0, w1)
        if lo - 1e-9 <= w <= hi + 1e-9:
            if abs(w1 - w0) <= 1e-12:
                best = max(best, d0, d1)
            else:
                best = max(best, d0 + (d1 - d0) * (w - w0) / (w1 - w0))
    return best


def lcyc93(ctx: Any) -> None:
    """Grooving (see docs/SIEMENS.md): plunges across the width at most the tool width
    apart, each to the groove less the allowance R106 in infeeds of R108 with a 1 mm
    chip-breaking back-off; then the finishing of both flanks and the base."""
    _need_g23(ctx)
    t = _whole(ctx, 105, 1, 8, 61002, "machining type")
    face, internal, right = _GROOVE_TYPES[t]
    allowance = abs(_r(ctx, 106))
    tool = _r(ctx, 107)
    infeed = abs(_r(ctx, 108))
    width, depth, angle = _r(ctx, 114), _r(ctx, 115), _r(ctx, 116)
    edge, base, dwell = abs(_r(ctx, 117)), abs(_r(ctx, 118)), _r(ctx, 119)
    if width <= 0 or depth <= 0:
        _alarm(ctx, 61603, f"R114={width:g} R115={depth:g}: width and depth must be > 0")
    if not 0 <= angle < 90:
        _alarm(ctx, 61603, f"R116={angle:g}: the flank angle must be 0-89.999")
    try:
        outline = groove_outline(width, depth, angle, edge, base)
        rough_outline = groove_outline(width - 2 * allowance, depth - allowance, angle,
                                       0.0, max(base - allowance, 0.0)) \
            if depth - allowance > _TOL else None
    except ValueError as exc:
        _alarm(ctx, 61603, f"R114={width:g} R115={depth:g} R116={angle:g} R117={edge:g} "
                           f"R118={base:g} R106={allowance:g}: {exc}")
    flat = [p for p in outline if abs(p[1] - depth) <= 1e-9]
    base_w = flat[-1][0] - flat[0][0] if flat else 0.0
    if tool <= 0 or tool > base_w + 1e-9:
        _alarm(ctx, 61602, f"R107={tool:g}: the tool must be > 0 and fit the groove's base "
                           f"({base_w:g} wide)")
    if infeed <= 0:
        infeed = depth + GROOVE_CLEARANCE  # no R108: one infeed to the bottom
    # the frame: w across the width, d into the part
    sx, sz = _r(ctx, 100) / 2.0, _r(ctx, 101)
    ws = -1.0 if right else 1.0
    ds = 1.0 if internal else -1.0

    def world(w: float, d: float) -> Point:
        return (sx + ws * w, sz + ds * d) if face else (sx + ds * d, sz + ws * w)

    # the programmed point is the corner the tool's point position names (tip 3: the -Z
    # corner of a longitudinal groove's tool, the -X corner of a face groove's); the width
    # R107 lies from it toward +Z (+X), or toward -Z (-X) for a tip on the + side
    _radius, tip = ctx.tool_nose() if hasattr(ctx, "tool_nose") else (0.0, 0)
    try:
        tx, tz = tip_direction(int(tip))
    except (KeyError, ValueError):
        tx, tz = 0, 0
    toward = -(tx if face else tz) or 1  # the world sign of the width from the point
    flip = toward * ws < 0  # the point is the corner at the far (high w) side

    def tool_at(w: float, d: float) -> Point:
        """The programmed point of the tool whose start-side corner is at ``w``."""
        return world(w + tool if flip else w, d)

    legs = _Legs(ctx)
    top = -GROOVE_CLEARANCE
    p = ctx.pos
    pw = ((p[0] - sx) if face else (p[1] - sz)) * ws - (tool if flip else 0.0)
    pd = ((p[1] - sz) if face else (p[0] - sx)) * ds
    if pd > top + 1e-9:  # inside the surface: out along the depth first
        legs.rapid(tool_at(pw, top))
        pd = top
    first = allowance if depth - allowance > _TOL else 0.0
    legs.rapid(tool_at(first, pd))  # across at the start depth, then down to the clearance
    # roughing: columns from the start edge across, each plunged in R108 infeeds
    cols: list[float] = []
    if rough_outline is not None:
        lo, hi = allowance, width - allowance - tool
        if hi < lo - 1e-9:
            _alarm(ctx, 61602, f"R107={tool:g} is wider than the groove less its allowance")
        n = max(1, math.ceil((hi - lo) / tool - 1e-9)) if hi - lo > 1e-9 else 0
        limit = int(getattr(ctx, "max_passes", 10_000))
        if (n + 1) * ((depth + GROOVE_CLEARANCE) / infeed) > limit:
            ctx.alarm(f"{_name(ctx)}: more infeeds than the machine's limit of {limit} "
                      f"([limits] cycle_passes): R107={tool:g} R108={infeed:g}")
        cols = [lo + (hi - lo) * k / n for k in range(n + 1)] if n else [lo]
    for w in cols:
        d = min(_bottom(rough_outline, w - allowance), _bottom(rough_outline, w + tool - allowance))
        if d <= 0:
            continue
        legs.rapid(tool_at(w, top))
        a, c = (top, 0.0), (d, 0.0)
        for kind, q in peck_moves(a, c, infeed, 1.0, GROOVE_BACKOFF, 0.0, along_z=False):
            if kind == "feed":
                legs.feed(tool_at(w, q[0]))
                if abs(q[0] - d) <= 1e-9:
                    legs.dwell(dwell)
            else:
                legs.rapid(tool_at(w, q[0]))
    # finishing: the start-side flank and the base with the tool's start-side corner, then
    # the far flank and the base with its far corner (the reference point a tool width back)
    inner = [q for q in outline[1:-1]]
    mid = len(inner) // 2
    left = inner[:mid] + [(inner[mid][0] - tool, inner[mid][1])]
    right_pts = [(q[0] - tool, q[1]) for q in reversed(inner[mid:])]
    right_pts.append((inner[mid - 1][0], inner[mid - 1][1]))
    for path in (left, right_pts):
        legs.rapid(tool_at(path[0][0], top))
        for q in path:
            legs.feed(tool_at(q[0], q[1]))
        legs.dwell(dwell)
        legs.rapid(tool_at(path[-1][0], top))
    legs.rapid(tool_at(0.0, top))


# --------------------------------------------------------------------------- LCYC94

#: DIN 509 undercut sizes by finished diameter (series 1 of the standard): (diameter up to,
#: radius r, depth t1, length f, face depth t2 of form F); from 3 mm (61601 below)
UNDERCUTS = ((3.0, 0.2, 0.1, 1.0, 0.1), (10.0, 0.2, 0.2, 2.0, 0.1),
             (18.0, 0.6, 0.2, 2.0, 0.1), (80.0, 0.6, 0.3, 2.5, 0.2),
             (math.inf, 1.0, 0.4, 4.0, 0.3))
#: the run-out flank toward the shaft and the face flank of form F (degrees, DIN 509)
UNDERCUT_RUNOUT = 15.0
UNDERCUT_FACE = 8.0
#: LCYC94 starts and ends this far (mm) outside the shaft and beyond the undercut's length
UNDERCUT_CLEARANCE = 1.0


def undercut_outline(form: str, diameter: float) -> list:
    """The finished DIN 509 undercut (form ``"E"`` or ``"F"``) in its own frame: ``a`` along
    the shaft away from the shoulder face (a = 0 on the face), ``d`` into the shaft (d = 0
    on its surface). Items: ``("line", end)`` and ``("arc", end, centre)`` from the point
    where the run-out leaves the shaft surface to the point where the outline meets the
    shoulder face again."""
    r, t, f, t2 = next((r, t, f, t2) for top, r, t, f, t2 in UNDERCUTS if diameter <= top)
    back = t2 if form == "F" else 0.0
    out = [("line", (f, 0.0)), ("line", (f - t / math.tan(math.radians(UNDERCUT_RUNOUT)), t)),
           ("line", (r - back, t)), ("arc", (-back, t - r), (r - back, t - r))]
    if back:
        out.append(("line", (0.0, t - r - back / math.tan(math.radians(UNDERCUT_FACE)))))
    return out


def lcyc94(ctx: Any) -> None:
    """Undercut form E or F (DIN 509) at the corner (R100, R101) in the direction of the tool
    tip R107: rapid to the start point, the outline in one feed pass, rapid back."""
    _need_g23(ctx)
    form = {55.0: "E", 56.0: "F"}.get(_r(ctx, 105))
    if form is None:
        _alarm(ctx, 61609, f"R105={_r(ctx, 105):g}: the form must be 55 (E) or 56 (F)")
    tip = _r(ctx, 107)
    if tip not in (1.0, 2.0, 3.0, 4.0):
        _alarm(ctx, 61608, f"R107={tip:g}: the tool point position must be 1-4 for an undercut")
    diameter = _r(ctx, 100)
    if diameter < 3.0:
        _alarm(ctx, 61601, f"R100={diameter:g}: the finished diameter must be at least 3 mm")
    sx, sz = tip_direction(int(tip))
    x0, z0 = diameter / 2.0, _r(ctx, 101)

    def world(a: float, d: float) -> Point:
        return (x0 + sx * d, z0 - sz * a)

    outline = undercut_outline(form, diameter)
    length = outline[0][1][0]
    start = world(length + UNDERCUT_CLEARANCE, -UNDERCUT_CLEARANCE)
    legs = _Legs(ctx)
    p = ctx.pos
    if sx * (p[0] - start[0]) > 1e-9:  # inside the shaft's diameter: out along X first
        legs.rapid((start[0], p[1]))
    legs.rapid(start)
    legs.rapid(world(length + UNDERCUT_CLEARANCE, 0.0))
    for item in outline:
        end = world(*item[1])
        if item[0] == "line":
            legs.feed(end)
            continue
        c = world(*item[2])
        arc = Arc(legs.at, end, c, True)
        if abs(arc.sweep) > math.pi:
            arc = Arc(legs.at, end, c, False)
        legs.arc(arc)
    a_face = outline[-1][1]
    if a_face[1] > -UNDERCUT_CLEARANCE:
        legs.feed(world(0.0, -UNDERCUT_CLEARANCE))
    legs.rapid(start)


# --------------------------------------------------------------------------- table

CYCLES: dict[str, Callable[[Any], None]] = {
    "LCYC82": lcyc82,
    "LCYC83": lcyc83,
    "LCYC840": lcyc840,
    "LCYC85": lcyc85,
    "LCYC93": lcyc93,
    "LCYC94": lcyc94,
    "LCYC95": lcyc95,
    "LCYC97": lcyc97,
}
