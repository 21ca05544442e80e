"""Holes from solid: a bore in a bar is drilled on the axis before the boring bar works.

Rules (each operation records its reason, which the program prints as a comment):

* **Which drills.** The bore's last part must be a drill's work: a blind bore ends in a cone
  of a drill's point angle (the drill point, e.g. 118 deg, down to the axis), a through bore
  runs on to the part's left end. The *pilot* is the largest drill of that point angle (any,
  for a through bore) that fits the bore everywhere with its tip at the cone's apex (through
  the part's left end by the point's height plus :data:`THROUGH`, for a through bore). What
  the pilot leaves of the bore (the bore wider than the drill, nearer the face) is the boring
  bar's: the bar enters a hole of its ``min_bore``; when the pilot is smaller, an *opener* (the
  largest drill at least ``min_bore`` that stays :data:`STOCK` inside the bore) drills as deep
  as it stays that far from the part, before it. A bore the pilot makes whole (its diameter
  a drill's, its bottom that drill's point) is drilled to size.
* **A flat bottom** is the boring bar's: the largest drill whose point stays inside the bore
  drills with its tip :data:`FLAT_TIP` above the bottom; the bar roughs and finishes the bore
  and faces the bottom toward the centre as far as its head lets its tip go (``min_bore``
  less the bore's narrowest radius: the bar's back against the wall across the axis) plus
  :data:`FACE_CLEAR`, and leaves the bottom along +Z. What the drill's point leaves nearer the
  axis is named in a note; a bottom the bar's head leaves no room to face, or a drill under
  the bar's ``min_bore``, is refused.
* **Refused**, naming the feature and the tool it needs: another bottom no drill's point
  makes (a cone of another angle, a curved bottom), a bore no drill fits, a hole deeper than the drill's flutes, a bore whose wider part no drill opens to the
  boring bar's ``min_bore``.
* **Centre drilling**: the library's spot drill (``kind = "center_drill"``) spots the face
  first, its cone to :data:`SPOT_SHARE` of the first drill's diameter, where that cone lies
  inside what the drill removes.
* **Speed and feed**: G97 at the drill's surface speed at its diameter (``vc_rough``, limited
  by the material table), at most the spindle limit; the drill's ``feed_rough``.
* **Pecks**: a hole deeper than :data:`PECK_RATIO` diameters is peck-drilled: pecks of one
  diameter (equal, the last one to the depth), :data:`BACK` mm back after each (chip
  breaking), out to the R plane every :data:`EVERY` pecks (clearing the chips) and back in to
  :data:`BACK` above the hole's bottom; a dwell of the drill's ``dwell_rev`` revolutions at the
  bottom. The HNC-21T has no peck-drilling cycle: the pecks are plain blocks (``--drill-style
  blocks``) or one WHILE-loop macro subprogram called with G65 (``--drill-style macro``), with
  the same moves.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

from ..errors import PlanError
from ..geometry import Line, Segment
from ..tooling import BAR_CLEARANCE, Machine, Tool, ToolLibrary
from .analysis import _split_at_x, radius_at
from .model import DrillCut, Operation, _n as _fmt
from .tools import describe, groove_plunges

#: a hole deeper than this many diameters is peck-drilled
PECK_RATIO = 3.0
#: the drill backs off this far after each peck (chip breaking), mm
BACK = 0.5
#: a full retract to the R plane after this many pecks
EVERY = 3
#: the R plane: the drill rapids to this far in front of the face, then feeds, mm
R_PLANE = 1.0
#: least stock (radial and axial, mm) an opener drill leaves for the boring bar
STOCK = 0.3
#: a through hole's drill runs its full diameter this far past the part's left end, mm
THROUGH = 0.5
#: the spot drill's cone ends at this share of the first drill's diameter
SPOT_SHARE = 0.9
#: the boring bar's contour runs on this far along the drilled hole past where the bore
#: meets it, mm
RUN_ON = 1.0
#: drill point angles that are the same, deg
ANGLE_TOL = 0.5
#: a flat-bottomed bore's drill stops its tip this far above the bottom, mm
FLAT_TIP = 0.001
#: the boring bar faces a flat bottom to this far outside the least radius its head leaves
#: its tip (so the roughing cycle's start, the clearance inside it, stays within reach), mm
FACE_CLEAR = BAR_CLEARANCE


@dataclass
class Hole:
    """What drilling leaves: the operations (in order), the bore chain left for the boring
    bar (None: the drills make the whole bore) and the radius of the drilled hole the bar
    starts from (the smallest hole drilled)."""
    ops: list[Operation]
    bar_chain: list[Segment] | None
    radius: float

    @property
    def entry(self) -> float:
        """The widest hole drilled (diameter): the boring bar enters it."""
        return max(op.drill.diameter for op in self.ops if op.tool.kind == "drill")


def _fits(chain: Sequence[Segment], d: float, angle: float, z_tip: float, z_stop: float,
          margin: float) -> bool:
    """A drill of diameter ``d`` and point ``angle`` with its tip at ``z_tip`` lies inside
    the bore (``margin`` mm from it, radially and along Z) from the face down to ``z_stop``
    (the part's left end: past it is chuck-side stock)."""
    rd = d / 2
    cot = 1.0 / math.tan(math.radians(angle) / 2)
    # the point: its surface at radius r lies at z_tip + r cot; the bore there must be wider
    n = 60
    # samples, and just past each radius where the bore steps (the margin off it)
    rs = [rd * i / n for i in range(n + 1)]
    for s in chain:
        for v in (s.start[0] - margin, s.end[0] - margin):
            rs += [v + 1e-6 for v in (v,) if 0.0 <= v + 1e-6 <= rd]
        # and where the point passes each corner of the bore (just beyond it)
        for zv in (s.start[1], s.end[1]):
            v = (zv + margin - 1e-4 - z_tip) / cot
            rs += [v for v in (v,) if 0.0 <= v <= rd]
    for r in rs:
        z = z_tip + r * cot
        for dz in (margin, 0.0):
            zz = z - dz
            if zz >= 0.0 or zz <= z_stop:
                continue
            rb = radius_at(chain, zz)
            if rb is None or rb < r + margin - 1e-6:
                return False
    # the body: from the point's full diameter to the face
    z_body = z_tip + rd * cot
    lo = max(z_body - margin, z_stop + 1e-6)
    if lo < 0.0:
        k = max(8, int((0.0 - lo) / 0.25))
        for i in range(k + 1):
            zz = lo + (0.0 - lo) * i / k
            zz = min(zz, -1e-6)
            rb = radius_at(chain, zz)
            if rb is None or rb < rd + margin - 1e-6:
                return False
        # every corner of the bore between the samples
        for s in chain:
            for p in (s.start, s.end):
                if lo <= p[1] < 0.0 and p[0] < rd + margin - 1e-6 and p[1] > z_stop:
                    # a point of the bore inside the drill's body (a step face's inner end)
                    r_here = radius_at(chain, p[1] + 1e-4)
                    if r_here is None or r_here < rd + margin - 1e-6:
                        return False
    return True


def _cone(seg: Segment) -> float | None:
    """The included angle of a bottom line down to the axis (deg; 180 for a flat bottom)."""
    if not isinstance(seg, Line):
        return None
    (x0, z0), (_x1, z1) = seg.start, seg.end
    if x0 <= 1e-9:
        return None
    return 2.0 * math.degrees(math.atan2(x0, z0 - z1))


def _split_at_radius(chain: Sequence[Segment], r: float) -> list[Segment]:
    """The chain up to where it last comes down to radius ``r`` for good (from there on the
    drill of that radius made it; the segment that comes down cut there), continued
    :data:`RUN_ON` mm along the drilled surface after it (the bar's nose then rounds the edge
    where the bore meets the drilled hole); empty when the whole chain lies on the drill."""
    def low(s: Segment) -> bool:
        return max(s.start[0], s.end[0], s.bbox()[2]) <= r + 1e-6
    k = len(chain)
    while k > 0 and low(chain[k - 1]):
        k -= 1
    if k == 0:
        return []
    s = chain[k - 1]
    out = list(chain[:k - 1])
    rest = list(chain[k:])
    if s.end[0] <= r + 1e-6 < s.start[0]:
        parts = _split_at_x(s, r)
        out.append(parts[0] if parts else s)
        if parts:
            rest.insert(0, parts[1])
    else:
        out.append(s)
    left = RUN_ON
    for s in rest:
        if left <= 1e-9 or not isinstance(s, Line):
            break
        if s.length <= left:
            out.append(s)
            left -= s.length
        else:
            out.append(Line(s.start, s.point_at(left / s.length)))
            left = 0.0
    return out


def plan_hole(chain: list[Segment], lib: ToolLibrary, machine: Machine, name: str,
              z_min: float, z_face: float, z_a: float, style: str) -> Hole:
    """The drilling of the bore ``chain`` (radius >= 0, from the face toward -Z) of a part
    from solid bar (see the module doc)."""
    from .planner import rpm_limit
    if style not in ("blocks", "macro"):
        raise PlanError(f"drill style must be blocks or macro, got {style!r}")
    drills = sorted([t for t in lib.tools if t.kind == "drill"], key=lambda t: -t.diameter)
    bars = [t for t in lib.tools if t.kind == "bore" and "rough" in t.uses]
    r_mouth = chain[0].start[0]
    blind = chain[-1].end[0] <= 1e-6
    walls = chain[:-1] if blind else chain
    r_min = min((min(s.start[0], s.end[0]) for s in walls), default=r_mouth)
    z_bottom = chain[-1].end[1] if blind else z_min
    feature = (f"blind bore diameter {_fmt(2 * r_min)} to Z{_fmt(chain[-1].start[1])}" if blind
               else f"through bore diameter {_fmt(2 * r_min)}")
    if not drills:
        raise PlanError(f"part {name}: the {feature} from solid bar needs a drill (kind = "
                        f"\"drill\") in the tool library, e.g. diameter {_fmt(_drill_size(r_min))}; "
                        f"there is none (or give a tube stock)")
    flat = blind and isinstance(chain[-1], Line) and abs(chain[-1].start[1] - z_bottom) <= 1e-9 \
        and chain[-1].start[0] > 1e-6
    if flat:
        return _flat_hole(chain, drills, bars, lib, machine, name, feature, z_face, z_a, style)
    if blind:
        ang = _cone(chain[-1])
        if ang is None or not any(abs(ang - t.point_angle) <= ANGLE_TOL for t in drills):
            what = ("a flat bottom" if ang is not None and ang > 179.0
                    else f"a {_fmt(ang)} deg cone" if ang is not None else "a curved bottom")
            pts = sorted({f"{t.point_angle:g}" for t in drills})
            raise PlanError(f"part {name}: the {feature} ends in {what} at Z{_fmt(z_bottom)}: a "
                            f"drill leaves its point there and no boring bar reaches the centre "
                            f"of a hole from solid; model the bottom as the drill's point (a "
                            f"{'/'.join(pts)} deg cone to the axis) or add a drill whose point is "
                            f"that bottom")
        cands = [t for t in drills if abs(ang - t.point_angle) <= ANGLE_TOL]
        # the point's tip on the model's apex, rounded toward the face (the program's 0.001)
        apex = math.ceil(chain[-1].end[1] * 1000 - 1e-6) / 1000
        pilot = next((t for t in cands if _fits(chain, t.diameter, t.point_angle, apex,
                                                -math.inf, 0.0)), None)
        z_tip = apex
    else:
        pilot = None
        z_tip = 0.0
        for t in drills:
            h = t.diameter / 2 / math.tan(math.radians(t.point_angle) / 2)
            zt = math.floor((z_min - THROUGH - h) * 1000 + 1e-6) / 1000
            if _fits(chain, t.diameter, t.point_angle, zt, z_min, 0.0):
                pilot, z_tip = t, zt
                break
        cands = drills
    if pilot is None:
        small = min(cands, key=lambda t: t.diameter)
        raise PlanError(f"part {name}: no drill in the library fits the {feature}: the smallest, "
                        f"T{small.number:02d} ({_fmt(small.diameter)} mm), is wider than the bore; "
                        f"it needs a drill of at most {_fmt(2 * r_min)} mm"
                        + (f" with a {cands[0].point_angle:g} deg point" if blind else ""))
    rp = pilot.diameter / 2
    bar_chain = _split_at_radius(chain, rp)
    hole_ops_tools: list[tuple[Tool, float]] = []  # (drill, tip z), in the order they run
    hole_ops_tools.append((pilot, z_tip))
    hole_r = rp
    if bar_chain:
        if not bars:
            raise PlanError(f"part {name}: the {feature} is wider than the drill T"
                            f"{pilot.number:02d} ({_fmt(pilot.diameter)} mm) near the face: it "
                            f"needs a boring bar (kind bore, uses 'rough'); the library has none")
        bar = min(bars, key=lambda t: t.min_bore)
        if bar.min_bore > pilot.diameter + 1e-9:
            opener = _opener(chain, drills, bar.min_bore, z_min if not blind else -math.inf,
                             pilot)
            if opener is None:
                r_open = min(p[0] for s in bar_chain for p in (s.start, s.end)
                             if p[0] > rp + 1e-6)
                if 2 * (r_open - STOCK) < bar.min_bore - 1e-9:
                    raise PlanError(
                        f"part {name}: the {feature} needs the boring bar where it is diameter "
                        f"{_fmt(2 * r_open)}, under the smallest hole the boring bar "
                        f"T{bar.number:02d} enters (min_bore {_fmt(bar.min_bore)}); the drill "
                        f"T{pilot.number:02d} makes {_fmt(pilot.diameter)} mm: it needs a boring "
                        f"bar with min_bore <= {_fmt(pilot.diameter)} or a drill of diameter "
                        f"{_fmt(2 * r_open)}")
                raise PlanError(
                    f"part {name}: the {feature} is diameter {_fmt(2 * r_open)} near the face, "
                    f"wider than the drill T{pilot.number:02d} ({_fmt(pilot.diameter)} mm) makes "
                    f"it; the boring bar T{bar.number:02d} enters a hole of min_bore "
                    f"{_fmt(bar.min_bore)} and no drill of {_fmt(bar.min_bore)} mm or more opens "
                    f"it while staying {_fmt(STOCK)} mm inside the bore: it needs a boring bar "
                    f"with min_bore <= {_fmt(pilot.diameter)} or a drill of diameter "
                    f"{_fmt(bar.min_bore)} to {_fmt(2 * (r_open - STOCK))} mm")
            hole_ops_tools.append(opener)
        # the bar's head works in the bore where the bar cuts it: the narrowest of that must
        # take its min_bore (an opener lets the bar in; a narrower step deeper it cannot bore)
        cut = [(p[0], p[1]) for seg in bar_chain for p in (seg.start, seg.end) if p[0] > rp + 1e-6]
        cut += [(seg.bbox()[0], seg.start[1]) for seg in bar_chain
                if not isinstance(seg, Line) and seg.bbox()[0] > rp + 1e-6]
        r_cut, z_cut = min(cut, key=lambda p: (round(p[0], 6), -p[1]))  # where it starts
        if not any(b.min_bore <= 2 * r_cut + 1e-9 for b in bars):
            bar = min(bars, key=lambda t: t.min_bore)
            raise PlanError(f"part {name}: the {feature} is diameter {_fmt(2 * r_cut)} from "
                            f"Z{_fmt(z_cut)}, wider than the drill T{pilot.number:02d} "
                            f"({_fmt(pilot.diameter)} mm) makes it: the boring bar must cut it "
                            f"there, and the boring bar T{bar.number:02d}'s head does not fit a "
                            f"bore of that diameter (min_bore {_fmt(bar.min_bore)}): it needs a "
                            f"boring bar with min_bore <= {_fmt(2 * r_cut)} or a drill of "
                            f"diameter {_fmt(2 * r_cut)}")
    # depth: the flutes must reach the hole's bottom from the face
    for t, zt in hole_ops_tools:
        if z_face - zt > t.flute_length + 1e-9:
            raise PlanError(f"part {name}: the {feature} needs T{t.number:02d} {t.name} to drill "
                            f"{_fmt(z_face - zt)} mm deep (to Z{_fmt(zt)}); its flutes reach "
                            f"{_fmt(t.flute_length)} mm: it needs a {_fmt(t.diameter)} mm drill "
                            f"with flute_length >= {_fmt(z_face - zt)}")
    ops: list[Operation] = []
    spots = [t for t in lib.tools if t.kind == "center_drill"]
    first, first_tip = hole_ops_tools[0]
    if spots:
        s = spots[0]
        ds = min(s.diameter, SPOT_SHARE * first.diameter)
        zs = z_face - ds / 2 / math.tan(math.radians(s.point_angle) / 2)
        zs = math.ceil(zs * 1000 - 1e-6) / 1000
        # the spot's cone must lie inside the first drill's hole (never deeper than its cone)
        cot_f = 1.0 / math.tan(math.radians(first.point_angle) / 2)
        cot_s = 1.0 / math.tan(math.radians(s.point_angle) / 2)
        inside = zs >= first_tip - 1e-9 and all(
            z_face - (ds / 2 - r) * cot_s + 0.0 >= first_tip + r * cot_f - 1e-9
            for r in (ds / 2 * i / 20 for i in range(21)))
        if inside and _fits(chain, ds, s.point_angle, zs, z_min if not blind else -math.inf,
                            0.0):
            ops.append(_drill_op(s, zs, ds, z_face, z_a, machine, rpm_limit(s, machine), style,
                                 f"spot the hole's centre for T{first.number:02d}, its "
                                 f"{_fmt(s.point_angle)} deg cone to diameter {_fmt(ds)}"))
    for i, (t, zt) in enumerate(hole_ops_tools):
        if i == 0:
            what = (f"drill the {feature} to size with its point" if not bar_chain
                    else f"drill the {feature}" + (" (the pilot)" if len(hole_ops_tools) > 1
                                                   else " for the boring bar"))
        else:
            what = (f"open the hole to {_fmt(t.diameter)} mm for the boring bar T"
                    f"{min(bars, key=lambda b: b.min_bore).number:02d} (min_bore "
                    f"{_fmt(min(b.min_bore for b in bars))}), as deep as it stays "
                    f"{_fmt(STOCK)} mm inside the bore")
        ops.append(_drill_op(t, zt, t.diameter, z_face, z_a, machine, rpm_limit(t, machine),
                             style, what))
    return Hole(ops=ops, bar_chain=bar_chain or None, radius=hole_r)


def _flat_hole(chain: list[Segment], drills: Sequence[Tool], bars: Sequence[Tool],
               lib: ToolLibrary, machine: Machine, name: str, feature: str, z_face: float,
               z_a: float, style: str) -> Hole:
    """A blind bore with a flat bottom: the largest drill whose point stays inside the bore,
    its tip :data:`FLAT_TIP` above the bottom on the axis; the boring bar roughs and
    finishes the bore and faces the bottom toward the centre down to the radius its head
    leaves it (``min_bore`` less the bore's narrowest radius: the bar's back against the wall
    across the axis) plus :data:`FACE_CLEAR`; what the drill's point leaves inside that
    radius is beyond the bar's reach and left (a note names it)."""
    from .planner import rpm_limit
    z_b = chain[-1].start[1]
    r_b = chain[-1].start[0]
    tip = math.ceil((z_b + FLAT_TIP) * 1000 - 1e-6) / 1000
    pilot = next((t for t in drills if _fits(chain, t.diameter, t.point_angle, tip, -math.inf,
                                             0.0)), None)
    if pilot is None:
        small = drills[-1]
        raise PlanError(f"part {name}: no drill in the library fits the {feature}: the smallest, "
                        f"T{small.number:02d} ({_fmt(small.diameter)} mm), is wider than the "
                        f"bore or its point reaches below the flat bottom at Z{_fmt(z_b)}")
    if not bars:
        raise PlanError(f"part {name}: the {feature} ends in a flat bottom at Z{_fmt(z_b)}: the "
                        f"bottom is faced by a boring bar (kind bore, uses 'rough'); the library "
                        f"has none")
    fits = [t for t in bars if t.min_bore <= pilot.diameter + 1e-9]
    if not fits:
        bar = min(bars, key=lambda t: t.min_bore)
        raise PlanError(f"part {name}: the {feature} ends in a flat bottom at Z{_fmt(z_b)} that "
                        f"the boring bar faces; the largest drill whose point stays above it, "
                        f"T{pilot.number:02d} ({_fmt(pilot.diameter)} mm), makes a hole under the "
                        f"boring bar T{bar.number:02d}'s min_bore {_fmt(bar.min_bore)}: it needs a "
                        f"boring bar with min_bore <= {_fmt(pilot.diameter)}")
    bar = min(fits, key=lambda t: t.min_bore)
    r_narrow = min(min(s.start[0], s.end[0]) for s in chain[:-1]) if len(chain) > 1 else r_b
    r_reach = max(0.0, bar.min_bore - r_narrow)
    r_end = r_reach + FACE_CLEAR if r_reach > 0 else 0.0
    if r_end >= r_b - 1e-6:
        raise PlanError(f"part {name}: the {feature} ends in a flat bottom at Z{_fmt(z_b)} "
                        f"(diameter {_fmt(2 * r_b)}) that the boring bar T{bar.number:02d} "
                        f"(min_bore {_fmt(bar.min_bore)}) cannot face: its head leaves it no room "
                        f"in the bore; it needs a boring bar with min_bore <= "
                        f"{_fmt(r_b + r_narrow - FACE_CLEAR)}")
    bar_chain = list(chain[:-1]) + [Line((r_b, z_b), (r_end, z_b))]
    ops: list[Operation] = []
    if z_face - tip > pilot.flute_length + 1e-9:
        raise PlanError(f"part {name}: the {feature} needs T{pilot.number:02d} {pilot.name} to "
                        f"drill {_fmt(z_face - tip)} mm deep (to Z{_fmt(tip)}); its flutes reach "
                        f"{_fmt(pilot.flute_length)} mm: it needs a {_fmt(pilot.diameter)} mm "
                        f"drill with flute_length >= {_fmt(z_face - tip)}")
    spots = [t for t in lib.tools if t.kind == "center_drill"]
    if spots:
        s = spots[0]
        ds = min(s.diameter, SPOT_SHARE * pilot.diameter)
        zs = math.ceil((z_face - ds / 2 / math.tan(math.radians(s.point_angle) / 2)) * 1000
                       - 1e-6) / 1000
        if zs >= tip - 1e-9 and s.point_angle <= pilot.point_angle + 1e-9:
            ops.append(_drill_op(s, zs, ds, z_face, z_a, machine, rpm_limit(s, machine), style,
                                 f"spot the hole's centre for T{pilot.number:02d}, its "
                                 f"{_fmt(s.point_angle)} deg cone to diameter {_fmt(ds)}"))
    op = _drill_op(pilot, tip, pilot.diameter, z_face, z_a, machine, rpm_limit(pilot, machine),
                   style, f"drill the {feature} for the boring bar, the largest drill whose "
                          f"point stays above the flat bottom at Z{_fmt(z_b)}")
    if r_end > 0:
        left = min(r_end, pilot.diameter / 2) / math.tan(math.radians(pilot.point_angle) / 2)
        op.notes.append(f"the flat bottom at Z{_fmt(z_b)} inside diameter {_fmt(2 * r_end)} is "
                        f"beyond the boring bar T{bar.number:02d}'s reach (its head, min_bore "
                        f"{_fmt(bar.min_bore)}, against the bore of diameter {_fmt(2 * r_narrow)}"
                        f"): the drill's point is left there, up to {_fmt(left + FLAT_TIP)} mm "
                        f"above the bottom")
    ops.append(op)
    return Hole(ops=ops, bar_chain=bar_chain, radius=r_end if r_end > 0 else 0.0)


def _drill_size(r: float) -> float:
    return math.floor(2 * r)


def _opener(chain: Sequence[Segment], drills: Sequence[Tool], min_bore: float, z_stop: float,
            pilot: Tool) -> tuple[Tool, float] | None:
    """The largest drill of at least ``min_bore`` that fits :data:`STOCK` inside the bore,
    with its tip as deep as that allows (bisection to 0.01 mm), or None."""
    for t in drills:
        if t.diameter < min_bore - 1e-9 or t.diameter <= pilot.diameter + 1e-9:
            continue
        h = t.diameter / 2 / math.tan(math.radians(t.point_angle) / 2)
        hi = -h  # the full diameter just inside the face
        if not _fits(chain, t.diameter, t.point_angle, hi, z_stop, STOCK):
            continue
        lo = min(s.bbox()[1] for s in chain) - h
        if _fits(chain, t.diameter, t.point_angle, lo, z_stop, STOCK):
            return t, lo
        while hi - lo > 0.01:
            mid = (hi + lo) / 2
            if _fits(chain, t.diameter, t.point_angle, mid, z_stop, STOCK):
                hi = mid
            else:
                lo = mid
        return t, math.ceil(hi * 100 - 1e-6) / 100
    return None


def _drill_op(t: Tool, z_end: float, d: float, z_face: float, z_a: float, machine: Machine,
              limit: float, style: str, what: str) -> Operation:
    rpm = min(limit, t.vc_rough * 1000.0 / (math.pi * t.diameter))
    rpm = float(math.floor(rpm + 1e-9))
    f = t.feed_rough
    z_clear = z_face + R_PLANE
    depth = z_face - z_end
    cut = DrillCut(z_clear=z_clear, z_end=z_end, back=BACK, every=EVERY, style=style,
                   z_top=z_face, diameter=d,
                   dwell=max(0.05, round(t.dwell_rev * 60.0 / rpm, 2)))
    peck_note = ""
    if depth > PECK_RATIO * t.diameter + 1e-9 and t.kind == "drill":
        n = max(2, math.ceil(depth / t.diameter - 1e-9))
        q = math.ceil(depth / n * 1000 - 1e-6) / 1000
        cut.peck = q
        cut.pecks = [round(z_face - q * i, 6) for i in range(1, n)
                     if z_face - q * i > z_end + 1e-6]
        peck_note = (f"; {_fmt(depth)} mm deep (over {PECK_RATIO:g} x D): {len(cut.pecks) + 1} "
                     f"pecks of {_fmt(q)} mm, {_fmt(BACK)} mm back after each, out to "
                     f"Z{_fmt(z_clear)} every {EVERY}"
                     + (" (a WHILE-loop macro subprogram)" if style == "macro" else ""))
    reason = (f"{what} with {describe(t)} to Z{_fmt(z_end)} (its point's tip); G97 S{_fmt(rpm)} "
              f"({_fmt(t.vc_rough)} m/min at diameter {_fmt(t.diameter)}, at most "
              f"{_fmt(limit)} rpm), F{_fmt(f)}" + peck_note
              + f", a dwell of {_fmt(cut.dwell)} s at the bottom")
    return Operation(name="spot" if t.kind == "center_drill" else "drill", kind="drill", tool=t,
                     reason=reason, start=(0.0, z_a), spindle="rpm", speed=rpm, feed=f,
                     drill=cut, contour=[Line((0.0, z_clear), (0.0, z_end))],
                     retract=[(0.0, z_a)])


# ------------------------------------------------------------------------------------------
# inside reliefs and ring grooves
# ------------------------------------------------------------------------------------------

#: the inside grooving tool backs out this far inside the bore between plunges, mm (radius)
ID_CLEAR = 0.6


def bridge_id_grooves(norm: list[Segment], bars: Sequence[Tool], lib: ToolLibrary,
                      machine: Machine, name: str, z_a: float
                      ) -> tuple[list[Segment], list[Operation]]:
    """Square grooves in the bore (``norm``: the bore mirrored to OD form) that no boring bar
    of ``bars`` reaches: bridged at the bore's diameter for the bar, and plunged with the
    library's inside grooving tool (``kind = "groove_id"``): the widest insert not wider
    than the groove whose bar enters the bore there (``min_bore``) and reaches the groove's
    bottom (``max_depth``). Returns the bridged chain and the grooving operations (after
    the bore's finishing). A square groove no such tool cuts is refused, naming the tool it
    needs; other undercuts are left to the caller."""
    from . import analysis as an
    from .planner import GROOVE_FINISH, rpm_limit
    from .tools import back_reach
    items = an.pocket_items(norm)
    pockets = [it for it in items if isinstance(it, an.Pocket)]
    if not pockets:
        return norm, []
    tools = [t for t in lib.tools if t.kind == "groove_id"]
    bridged: set[int] = set()
    ops: list[Operation] = []
    for p in pockets:
        if any(back_reach(t) >= p.max_descent - 1e-9 for t in bars):
            continue
        sq = an.square_groove(p)
        if sq is None:
            continue
        z_l, z_r, xb = sq
        r_b, r_l = -xb, -p.level
        width = z_r - z_l
        label = (f"inside groove from Z{_fmt(z_r)} to Z{_fmt(z_l)} ({_fmt(width)} mm wide, out to "
                 f"diameter {_fmt(2 * r_b)}) in the bore of diameter {_fmt(2 * r_l)}")
        fits = [t for t in tools if 0 < t.insert.width <= width + 1e-9
                and t.min_bore <= 2 * r_l + 1e-9
                and (t.max_depth <= 0 or t.max_depth >= r_b - r_l - 1e-9)]
        if not fits:
            have = ", ".join(f"T{t.number:02d} {t.insert.width:g} mm (min_bore {t.min_bore:g}, "
                             f"reach {t.max_depth:g})" for t in tools) or "none"
            raise PlanError(f"part {name}: {label}: no boring bar reaches it and no inside "
                            f"grooving tool in the library cuts it; it needs a kind = "
                            f"\"groove_id\" tool at most {_fmt(width)} mm wide entering diameter "
                            f"{_fmt(2 * r_l)} and reaching {_fmt(r_b - r_l)} mm deep (inside "
                            f"grooving tools in the library: {have})")
        t = max(fits, key=lambda t: t.insert.width)
        # inside the bore all the way from the face to the groove
        r_path = min(min(-s.start[0], -s.end[0]) for s in norm
                     if max(s.start[1], s.end[1]) > z_r - 1e-9)
        x_in = max(0.0, min(r_path, r_l) - 1.0)
        bridged.add(id(p))
        ops.append(_groove_id_op(t, z_l, z_r, r_b, r_l, x_in, z_a, rpm_limit(t, machine),
                                 GROOVE_FINISH, label))
    if not bridged:
        return norm, []
    return an.assemble(items, bridge=lambda p: id(p) in bridged), ops


def _groove_id_op(t: Tool, z_l: float, z_r: float, r_b: float, r_l: float, x_in: float,
                  z_a: float, max_rpm: float, finish: float, label: str) -> Operation:
    """Plunges outward with the inside grooving insert (controlled point: its corner at -Z),
    each back in to :data:`ID_CLEAR` inside the bore; a dwell at the bottom; a groove wider
    than the insert plunged leaving ``finish`` on its walls and bottom, then finished in one
    pass (as the outside grooves, mirrored)."""
    from .model import GrooveCut, GrooveFinish
    w = t.insert.width
    pos, fa, rpm, capped, dwell = groove_plunges(t, z_l, z_r, r_b, finish, max_rpm)
    cut = GrooveCut(x_bottom=r_b - fa, x_clear=r_l - ID_CLEAR, dwell=dwell)
    if fa > 0:
        cut.finish = GrooveFinish(z_right=z_r - w, z_left=z_l, x_bottom=r_b)
    op = Operation(
        name="groove", kind="groove", tool=t,
        reason=(f"{label}: no boring bar reaches its walls; plunged with {describe(t)} in "
                f"{len(pos)} plunge{'s' if len(pos) > 1 else ''}"
                + (", then one finishing pass on the walls and bottom" if fa > 0 else "")
                + f", in and out of the bore along Z at diameter {_fmt(2 * x_in)}"),
        start=(x_in, pos[0]), spindle="rpm" if capped else "css",
        speed=rpm if capped else t.vc_finish, feed=t.feed_finish, passes=pos, groove=cut)
    op.approach = [(x_in, z_a), (None, pos[0])]
    op.retract = [(x_in, z_a)]
    return op
