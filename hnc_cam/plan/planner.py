"""Operation choice: from a turned profile, a stock and a tool library to an ordered plan.

Rules (each operation records its reason, which the program prints as a comment):

* **Facing** when a bar or tube has face stock F > 0: G81 passes (or G01 passes) of at most
  the tool's depth, ending exactly on Z0, with the first tool that lists ``face`` (else
  ``rough``).
* **OD roughing**
  - ``offset:A`` stock (a near-net blank) -> ``G73`` with U = W = A and as many passes as the
    tool's depth needs, by the strongest roughing insert that reaches every wall;
  - otherwise the outside chain is analysed for *pockets* (stretches below the diameter
    already reached, i.e. undercuts). A pocket whose steepest descending wall a turning tool
    reaches (back clearance, see :mod:`hnc_cam.plan.tools`) is a *zone*; a square groove no
    turning insert reaches is bridged and plunged with a grooving insert; anything else is
    refused, naming the feature and the tool it needs;
  - no zones -> the library's roughing tool runs ``G71`` type I on the contour (``G72`` when
    the part is *face-dominated*: radial extent, stock radius minus the smallest radius of the
    outside, larger than its length), sharing the finishing contour as ns..nf;
  - zones -> the roughing tool runs ``G71`` type I on the *envelope* (every pocket bridged)
    with its own ns..nf: the envelope offset by the finishing allowance, its tip path, run
    once after the cycle as a semi-finishing pass; then each zone is rest-roughed by the
    strongest insert that reaches it (largest included angle) with ``G71`` type II over that
    zone alone, from the level the envelope left, and its own semi-finishing pass;
  - cycles start on the stock (G71 at its diameter, G72 on its face) and, after facing, the
    contours start near the face's edge (:func:`hnc_cam.plan.contour.drop_face`).
* **Holes from solid**: a bore in a bar is drilled first (:mod:`hnc_cam.plan.drilling`:
  spot drill, pilot, opener, pecks), then the boring bar works from the drilled hole as from a
  tube's bore on what the drills leave.
* **ID roughing** of a bore from a tube: ``G71`` type I with a negative X allowance (type II
  with a negative E for a bore with undercuts) with the boring bar; finished with the same or
  a finishing boring bar.
* **Finishing**: the ns..nf contour after roughing (tool change when the library's finishing
  tool is another tool) at G96 surface speed; a right face that is part of the finished
  contour (a stock not faced first) is finished from its edge toward the centre first, and
  the roughing contour starts at its edge (:func:`_face_to_centre`); the spindle limit is the lowest of the
  machine's max rpm (on the HNC-21T a system parameter, manual 3.3.6, stated in the header),
  the chuck's rated speed (the machine file's ``[chuck] max_rpm``) and the tool's
  ``max_rpm``; every cap below (G97, FANUC/Haas ``G50 S``, threads) uses it. G96 has no clamp word: facing passes, finishing contours and
  grooves switch to G97 at the limit inside the diameter where G96 would exceed it
  (:func:`_cap_contour`). A roughing cycle cannot change speed inside: where an OD G71 type I
  would exceed the limit at the smallest diameter it reaches, the HNC-21T program runs it in
  two, G96 over the contour outside the critical diameter and G97 at the limit inside it
  (:func:`_split_rough`); any other cycle runs wholly in G97 at the rpm of the cutting speed
  at the largest diameter it reaches, at most the limit (:func:`_cap_rough`; the FANUC and
  Haas programs keep G96 under ``G50 S``).
* **Threads** declared by the part: ``G76`` (or ``G82`` passes) to the standard's depth
  (:attr:`hnc_cam.geometry.Thread.depth`); the end runs one lead into the relief where the
  insert's flanks clear what follows; the start is three leads (plus the flank infeed) before
  the thread; G97 capped by the machine and by 1200/lead - 80 rpm. Refused when the relief
  after the thread is shorter than half the lead plus 0.2 mm, or when less than two leads
  of the thread are at full form. A thread (outside or inside, G76 or G82) that runs into a
  shoulder with no relief (inside: also a bore going on at the minor diameter) ends one lead
  (plus the flank's clearance) before it and leaves along the cycle's R/E run-out; refused,
  naming the thread length needed, when the run-out and two full leads do not fit. An inside
  thread through to the left end of a part from bar runs out past that end, in a run-on of
  the hole at the minor diameter (:func:`_run_out_length`), so its full depth reaches the
  left face. A taper
  thread (:attr:`hnc_cam.geometry.Thread.taper`, outside only) is cut along its taper.
* Roughing allowances: 0.4 mm on the diameter / 0.1 mm in Z by default (``--allowance``,
  the material table), increased where the roughing
  tool, following the program contour uncompensated (``--comp control``) or the finishing
  tool's tip path (``--comp cam``), would otherwise come closer than 0.1 mm to the part
  (walls descending into undercuts); type II and G73 allow in X only.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Sequence

from ..errors import PlanError
from ..geometry import Arc, Line, Point, Segment, Thread, TurnedProfile
from ..geometry.intersect import horizontal_hits
from ..geometry.offset import offset_chain
from ..tooling import Machine, Stock, Tool, ToolLibrary
from ..units import round_written
from . import analysis as an
from . import contour as ct
from .model import (Block, FaceCut, FaceGrooveCut, GrooveCut, GrooveFinish, Operation, Plan, RoughCut,
                    RoughSplit, Spindle, ThreadCut)
from .tools import (PARTIAL_PROFILE_PITCH, back_reach, can_square_shoulder, cuts_pitch, describe,
                    groove_plunges,
                    thread_pitch_range, thread_tools, turning_tools)


#: how far finishing contours run past the part's left end into the chuck-side stock, mm
OVERRUN = 0.05
#: the least distance in Z between the deepest cut (tool included) and the jaws' front face, mm
CHUCK_CLEARANCE = 2.0
#: stick-out over stock diameter above which a part held only in the chuck deflects and chatters
STICKOUT_RATIO = 4.0
#: a wall no steeper than a tool's reach by more than this (deg) is reached: the walls come
#: from the solid's section with coordinates good to about 1e-7 mm, so a wall drawn at exactly
#: the reach (a 30 deg thread run-out flank and a 55 deg insert's 30 deg) reads up to ~1e-7 deg
#: steeper or shallower; the tool choice must not follow that noise
REACH_TOL = 1e-4


@dataclass
class Options:
    comp: str = "cam"
    program_number: int = 1
    thread_cycle: str = "g76"  # g76 | g82
    #: the dialect's multiple-pass thread cycle ends each pass its depth x tan(half angle)
    #: further along the thread (HNC-21T G76's single-flank infeed; the dialect feature
    #: ``thread_end_on_flank``); without it every pass ends on the thread's end
    thread_end_shift: bool = True
    face_cycle: str = "g81"  # g81 | g01
    clearance: float = 1.0  # radial clearance of start points above the stock, mm
    z_clear: float = 2.0  # axial clearance in front of the face, mm
    allowance_x: float = 0.2  # radial finishing allowance, mm
    allowance_z: float = 0.1
    margin: float = 0.1  # least stock the roughing tool leaves normal to the part, mm
    retract: float = 0.5  # G71/G72 retract R, mm
    #: part off the finished part from a bar held in the chuck (when the machine gives a grip)
    partoff: bool = True
    #: the diameter the part-off ends at: -1 = past the centre (X-1); a small positive
    #: diameter leaves a stem for a parts catcher
    partoff_dia: float = -1.0
    #: peck drilling as plain blocks or as a WHILE-loop macro subprogram (blocks | macro)
    drill_style: str = "blocks"


def _fmt(v: float) -> str:
    return f"{v:.3f}".rstrip("0").rstrip(".")


def _where(p: Point) -> str:
    return f"X{_fmt(2 * abs(p[0]))} Z{_fmt(p[1])}"


def make_plan(profile: TurnedProfile, stock: Stock, tools: ToolLibrary, machine: Machine,
              opts: Options, *, name: str = "part", params: dict[str, Any] | None = None,
              version: str = "") -> Plan:
    if opts.comp not in ("cam", "control"):
        raise PlanError(f"compensation mode must be cam or control, got {opts.comp!r}")
    if not profile.outside:
        raise PlanError(f"part {name}: the profile has no outside contour")
    shift = -profile.z_max
    outside = an.translate_chain(profile.outside, shift)
    bore = an.translate_chain(profile.bore, shift) if profile.bore else None
    threads = [Thread(t.z_start + shift, t.z_end + shift, t.diameter, t.pitch, t.starts,
                      t.internal, t.standard, t.angle, t.taper) for t in profile.threads]
    prof = TurnedProfile(outside=outside, bore=bore, threads=threads, name=profile.name,
                         params=dict(profile.params), notes=list(profile.notes))
    z_min = prof.z_min
    length = -z_min
    od = ct.trim_left(ct.orient(outside, 0.0), z_min)
    if not od:
        raise PlanError(f"part {name}: the outside contour is empty after trimming")
    # square ring grooves in the right face: bridged (the face is faced and finished across
    # them), cut afterwards with an axial grooving blade
    od, face_grooves = an.face_grooves(od, 0.0)
    an.check_turnable(od, f"part {name} outside")
    r_max = max(max(s.bbox()[2] for s in od), 0.0)
    bore_chain = None
    if bore:
        bore_chain = ct.trim_left(ct.orient(bore, 0.0), z_min)
        an.check_turnable(an.mirror_chain(bore_chain), f"part {name} bore")

    plan = Plan(name=name, params=dict(params or {}), stock=stock, machine=machine,
                comp=opts.comp, program_number=opts.program_number, version=version,
                tool_change=machine.tool_change, profile=prof, shift=shift)
    if abs(shift) > 1e-9:
        plan.notes.append(f"model shifted by {_fmt(shift)} mm in Z to put its right face at Z0")

    # ---------------- stock against part ----------------
    if stock.kind == "offset":
        r_stock = r_max + stock.allowance
        z_face = stock.allowance
    else:
        r_stock = stock.diameter / 2
        z_face = stock.face
        if r_stock < r_max - 1e-6:
            raise PlanError(f"stock {stock.spec}: diameter {_fmt(stock.diameter)} is smaller than "
                            f"the part's largest diameter {_fmt(2 * r_max)}")
        if stock.z_left > z_min + 1e-6:
            raise PlanError(f"stock {stock.spec} is too short: it reaches Z{_fmt(stock.z_left)}, "
                            f"the part needs Z{_fmt(z_min)} (part length {_fmt(length)} mm"
                            + (f" + {_fmt(stock.face)} mm face stock" if stock.face else "") + ")")
        if stock.kind == "tube":
            rb = stock.bore / 2
            if not bore_chain:
                raise PlanError(f"stock {stock.spec}: the tube's bore (diameter {_fmt(stock.bore)}) "
                                f"cuts into the solid part {name}; use a bar")
            rmin = min(s.bbox()[0] for s in bore_chain)
            if rb > rmin + 1e-6:
                raise PlanError(f"stock {stock.spec}: the tube's bore (diameter {_fmt(stock.bore)}) "
                                f"is larger than the part's smallest bore diameter {_fmt(2 * rmin)}")

    if opts.allowance_x < 0 or opts.allowance_z < 0:
        raise PlanError(f"finishing allowance X{_fmt(2 * opts.allowance_x)} Z{_fmt(opts.allowance_z)}: "
                        f"an allowance cannot be negative")
    # the smallest diameter of the outside, the faces (lines along X) left out
    r_low = min((min(s.start[0], s.end[0]) for s in od
                 if abs(s.end[1] - s.start[1]) > 1e-6 and max(s.start[0], s.end[0]) > 1e-6),
                default=0.0)
    if opts.allowance_x >= r_stock - max(r_low, 0.0) - 1e-9 or opts.allowance_z >= length:
        raise PlanError(f"finishing allowance X{_fmt(2 * opts.allowance_x)} Z{_fmt(opts.allowance_z)} "
                        f"is larger than the stock: {_fmt(2 * (r_stock - max(r_low, 0.0)))} mm on "
                        f"the diameter and {_fmt(length)} mm in Z are all there is to remove")
    x_a = r_stock + opts.clearance  # OD start X (radius)
    ops: list[Operation] = []

    # ---------------- facing ----------------
    face_stock = stock.allowance if stock.kind == "offset" else stock.face
    if face_stock > 1e-6:
        ft = (turning_tools(tools, "face") or turning_tools(tools, "rough"))
        if not ft:
            raise PlanError("facing the face stock needs a turning tool with uses 'face' or "
                            "'rough' in the tool library; there is none")
        t = ft[0]
        n = max(1, math.ceil(face_stock / t.depth - 1e-9))
        levels = [face_stock * (1 - i / n) for i in range(1, n + 1)]
        levels[-1] = 0.0
        # past the centre by the nose radius, so that the nose reaches the axis
        x_end = -t.nose_radius if stock.kind != "tube" else max(0.0, stock.bore / 2 - opts.clearance)
        method = "cycle" if opts.face_cycle == "g81" else "passes"
        cut = FaceCut(method=method, x_end=x_end)
        # the HNC-21T's G96 has no clamp word: where the surface speed would need more than
        # the machine's max rpm, the centre of each pass runs G97 at that rpm (G01 passes)
        lim = rpm_limit(t, machine)
        r_cap = t.vc_rough * 1000.0 / (2 * math.pi * lim)
        cap_note = ""
        spindle, speed = "css", t.vc_rough
        if max(x_end, 0.0) < r_cap - 1e-9 and r_cap + 1e-9 >= r_stock:
            # the whole face (and the approach) is inside that diameter: G97 at the limit
            spindle, speed = "rpm", lim
            cap_note = (f"; G96 S{_fmt(t.vc_rough)} needs more than {_fmt(lim)} rpm "
                        f"inside diameter {_fmt(2 * r_cap)}, the whole face: G97 S{_fmt(lim)}")
        elif max(x_end, 0.0) < r_cap - 1e-9 < r_stock:
            cut.method = "passes"
            cut.cap_x, cut.cap_rpm = r_cap, lim
            cap_note = (f"; G96 S{_fmt(t.vc_rough)} needs more than {_fmt(lim)} rpm "
                        f"inside diameter {_fmt(2 * r_cap)}: G97 S{_fmt(lim)} there")
        ops.append(Operation(
            name="face", kind="face", tool=t,
            reason=(f"stock has {_fmt(face_stock)} mm face stock: facing to Z0 in {n} "
                    f"{'G81' if cut.method == 'cycle' else 'G01'} pass{'es' if n > 1 else ''} "
                    f"of at most {_fmt(t.depth)} mm" + cap_note),
            start=(x_a, face_stock + opts.z_clear), spindle=spindle, speed=speed,
            feed=t.feed_rough, passes=levels, face=cut))
        z_face = 0.0
    z_a = z_face + opts.z_clear

    # ---------------- part-off? ----------------
    blade = _partoff_blade(plan, stock, tools, machine, opts, name, z_min, r_stock)

    # ---------------- OD ----------------
    *od_ops, grooves = _plan_od(od, prof, stock, tools, opts, name, x_a, z_a, r_stock, length,
                                faced=face_stock > 1e-6, machine=machine,
                                partoff=blade is not None)

    # ---------------- bore ----------------
    bore_ops: list[Operation] = []
    past = 0.0
    if bore_chain and stock.kind == "bar":
        from .drilling import plan_hole
        run_on, past = _thread_run_out_past(bore_chain, prof.threads, stock, z_min)
        hole = None
        if past > 0:
            hole = plan_hole(run_on, tools, machine, name, z_min - past, z_face, z_a,
                             opts.drill_style)
            more = _run_on_short(hole.ops, stock, machine, z_min - past)
            if more > 0:
                plan.warnings.append(_run_on_warning("hole", past, z_min, stock, machine, more))
                hole, past = None, 0.0
            else:
                bore_chain = run_on
        if hole is None:
            hole = plan_hole(bore_chain, tools, machine, name, z_min, z_face, z_a,
                             opts.drill_style)
        bore_ops = list(hole.ops)
        if hole.bar_chain:
            bore_ops += _plan_bore(hole.bar_chain, stock, tools, opts, name, z_a,
                                   hole=hole.entry, x_hole=hole.radius, machine=machine,
                                   face=_face_room(od))
    elif bore_chain:
        run_on, past = _thread_run_out_past(bore_chain, prof.threads, stock, z_min)
        more = _run_on_short([], stock, machine, z_min - past) if past > 0 else 0.0
        if more > 0:
            plan.warnings.append(_run_on_warning("bore", past, z_min, stock, machine, more))
            past = 0.0
        elif past > 0:
            bore_chain = run_on
        bore_ops = _plan_bore(bore_chain, stock, tools, opts, name, z_a, machine=machine,
                              face=_face_room(od))

    rough_od, finish_od = od_ops  # finish_od: the finisher's operations (a face, the contour)
    ops.extend(rough_od)
    if finish_od[-1].tool.number == rough_od[-1].tool.number:
        ops.extend(finish_od)
        ops.extend(bore_ops)
    else:
        ops.extend(bore_ops)
        ops.extend(finish_od)
    ops.extend(grooves)
    for g in face_grooves:
        ops.append(_face_groove_op(g, tools, machine, name, z_a))

    # ---------------- threads ----------------
    for th in prof.threads:
        ops.append(_plan_thread(th, od, bore_chain, stock, tools, machine, opts, r_stock,
                                params=dict(params or {}), past=past, z_part=z_min))

    # ---------------- part-off ----------------
    if blade is not None:
        ops.append(_partoff_op(blade, od, stock, machine, opts, r_stock, z_min))

    for op in ops:
        op.max_rpm = rpm_limit(op.tool, machine)
        if op.blocks and op.name in ("finish", "bore_finish", "profile", "face") and op.css:
            _cap_contour(op, rpm_limit(op.tool, machine))
        if op.kind == "rough" and op.css and not _split_rough(op, ops, op.max_rpm):
            _cap_rough(op, ops, op.max_rpm)
        plan.notes.extend(op.notes)
        # a start behind the stock's face, outside it: X first, then Z (a combined rapid's
        # dog-leg could run through the stock on the way from the tool-change point)
        if op.start[1] < z_face - 1e-9 and op.start[0] >= r_stock:
            op.approach = [(op.start[0], None), (None, op.start[1])]
        elif op.start[1] < z_face - 1e-9 and op.name == "rough_zone":
            # into an undercut zone: above the stock, along Z, then down to the zone's start
            op.approach = [(x_a, None), (None, op.start[1]), (op.start[0], None)]
    # leaving for a tool change (and at the end): a boring bar leaves the bore along Z
    # first; an outside tool moves X first when the tool-change point is outside the stock,
    # else Z first (every operation ends above what is left of the part)
    prev = None
    for op in ops + [None]:
        kind = prev.tool.kind if prev is not None else "turn"
        first = "z" if kind in ("bore", "groove_id") or \
            machine.tool_change[0] < r_stock + opts.clearance else "x"
        if op is None:
            plan.leave_first = first
        else:
            op.leave_first = first
        prev = op
    prev = None
    for op in ops:
        if prev is not None and prev.tool.number == op.tool.number:
            op.new_tool = False
            if (prev.spindle, prev.speed) == (op.spindle, op.speed) and \
                    not prev.spindle_changed:
                op.set_spindle = False
            op.set_unclamped = op.set_spindle or prev.unclamped != op.unclamped
        prev = op
    plan.operations = ops
    for op in ops:
        # the control's G41/G42 on the contour as written (with the split's blocks): what it
        # alarms on is refused here, as the unsplit part contour's check refuses
        if op.kind == "finish" and op.blocks and op.nose_comp != "none":
            msg = ct.control_alarm(op.blocks, op.start, op.tool.nose_radius, op.tool.tip,
                                   op.nose_comp)
            if msg is not None:
                raise PlanError(f"part {name}: the control's tool-nose radius compensation of "
                                f"the {op.name} contour alarms ({msg}); use --comp cam or a "
                                f"tool with a smaller nose radius")
    _check_chuck(plan, name, z_min, r_stock)
    return plan


#: feed of the part-off inside this share of the stock's diameter, and the share itself
PARTOFF_SLOW = (0.5, 0.25)


def _partoff_blade(plan: Plan, stock: Stock, tools: ToolLibrary, machine: Machine,
                   opts: Options, name: str, z_min: float, r_stock: float) -> Tool | None:
    """The parting blade when the part is to be parted off, else None (the left end is cut
    just past the part, as for a blank made to length). Parted off: a bar or tube held in the
    chuck (the machine gives a grip), ``opts.partoff``, a ``kind = "part"`` tool in the
    library, and a stock long enough for the part, the blade and the jaws' clearance; a
    stock too short falls back with a warning. A blade that cannot reach the cut is
    refused, naming the depth needed."""
    grip = float(getattr(machine, "grip", 0.0) or 0.0)
    if not opts.partoff or grip <= 0 or stock.kind not in ("bar", "tube"):
        return None
    blades = [t for t in tools.tools if t.kind == "part"]
    if not blades:
        plan.warnings.append("no parting tool (kind = \"part\") in the tool library: the part "
                             "stays on the bar, its left end cut just past the part")
        return None
    t = blades[0]
    w = t.insert.width
    need = -z_min + w + CHUCK_CLEARANCE + grip + stock.face
    if stock.length < need - 1e-9:
        plan.warnings.append(
            f"stock {stock.spec} is too short to part off: part {_fmt(-z_min)} + blade "
            f"{_fmt(w)} + face {_fmt(stock.face)} + grip {_fmt(grip)} + clearance "
            f"{_fmt(CHUCK_CLEARANCE)} = {_fmt(need)} mm; the part stays on the bar, its left end "
            f"cut just past the part (as with --no-partoff)")
        return None
    x_stop = _partoff_stop(stock, opts)
    depth = r_stock - max(x_stop, 0.0)
    if t.max_depth > 0 and depth > t.max_depth + 1e-9:
        raise PlanError(f"part {name}: parting off diameter {_fmt(2 * r_stock)} to "
                        f"{_fmt(2 * x_stop)} needs a blade reaching {_fmt(depth)} mm deep; "
                        f"T{t.number:02d} {t.name} reaches {_fmt(t.max_depth)} mm (a blade with "
                        f"max_depth >= {_fmt(depth)}, or --no-partoff)")
    return t


def _partoff_stop(stock: Stock, opts: Options) -> float:
    """The radius the part-off plunge ends at: past the centre by 0.5 mm (X-1), the tube's
    bore less 0.5 mm, or the stem diameter asked for."""
    if stock.kind == "tube":
        return stock.bore / 2 - 0.5
    return opts.partoff_dia / 2 if opts.partoff_dia > 0 else -0.5


def _partoff_op(t: Tool, od: list[Segment], stock: Stock, machine: Machine, opts: Options,
                r_stock: float, z_min: float) -> Operation:
    """Part off at the part's left end with the blade's corner on the part's side (tip 4:
    the controlled point is that corner, so a plunge at Z = the part's left end leaves the
    left face there). A chamfer or round descending to the left end is cut first by that
    corner following it (tip path): a groove beside it to half a millimetre below it, then
    the corner along it and down the face. The plunge to the centre runs at the tool's
    finishing feed, falling to :data:`PARTOFF_SLOW` of it inside that share of the stock's
    diameter, G97 at the speed of the stock's diameter, at most the tool's and machine's
    limit."""
    r, w = t.nose_radius, t.insert.width
    x_a = r_stock + opts.clearance
    f = t.feed_finish
    x_stop = _partoff_stop(stock, opts)
    segs = an.split_x_extremes(list(od))
    k = len(segs)
    while k > 1 and segs[k - 1].end[0] < segs[k - 1].start[0] - 1e-9:
        k -= 1
    tail = segs[k:]
    path: list[Segment] = []
    blocks = []
    from .model import Block
    if tail:
        x_s, z_s = tail[0].start
        x_t = tail[-1].end[0]
        x_pre = max(x_t - 0.5, x_stop)
        blocks += [Block("line", x=x_pre, feed=f), Block("rapid", x=x_a)]
        path += [Line((x_a, z_min), (x_pre, z_min)), Line((x_pre, z_min), (x_a, z_min))]
        base = ([Line((x_s, z_s + 0.5), (x_s, z_s))] + list(tail)
                + [Line(tail[-1].end, (x_pre, tail[-1].end[1]))])
        tp = ct.tip_path(base, r, t.tip, bore=False)
        p0 = tp[0].start
        blocks += [Block("rapid", z=p0[1]), Block("rapid", x=p0[0] + 0.5),
                   Block("line", x=p0[0])]
        path += [Line((x_a, z_min), (x_a, p0[1])), Line((x_a, p0[1]), p0)]
        for b in ct.to_blocks(tp, "x", f, "", "", start=p0)[1:]:
            b.feed = None
            blocks.append(b)
        path += tp
        x_from = tp[-1].end[0]
    else:
        x_from = x_a
    x_slow = PARTOFF_SLOW[1] * r_stock
    if x_slow > x_stop + 1e-6 and x_from > x_slow:
        blocks.append(Block("line", x=x_slow, z=z_min, feed=f))
        blocks.append(Block("line", x=x_stop, feed=f * PARTOFF_SLOW[0]))
    else:  # a tube: no centre to slow down for
        blocks.append(Block("line", x=x_stop, z=z_min, feed=f))
    path += [Line((x_from, z_min), (x_stop, z_min))]
    vc = t.vc_finish
    lim = rpm_limit(t, machine)
    rpm = min(lim, vc * 1000.0 / (2 * math.pi * r_stock))
    stem = (f"to diameter {_fmt(2 * x_stop)} (a stem for the parts catcher)" if x_stop > 0
            else f"past the centre to X{_fmt(2 * x_stop)}")
    return Operation(
        name="partoff", kind="part", tool=t,
        reason=(f"part off at Z{_fmt(z_min)} with {describe(t)} ({_fmt(w)} mm blade), "
                + (f"its corner cutting the left end's {'chamfer' if all(isinstance(s, Line) for s in tail) else 'round'} first, "
                   if tail else "")
                + f"{stem}: F{_fmt(f)}"
                + (f", F{_fmt(f * PARTOFF_SLOW[0])} inside diameter {_fmt(2 * x_slow)}"
                   if x_slow > x_stop + 1e-6 else "")
                + f"; G97 S{_fmt(rpm)} ({_fmt(vc)} m/min at the stock's "
                  f"diameter, at most {_fmt(lim)} rpm)"),
        start=(x_a, z_min), spindle="rpm", speed=round(rpm), feed=f, blocks=blocks,
        nose_comp="none", contour=path, retract=[(x_a, z_min)],
        approach=[(x_a, None), (None, z_min)])


def _check_chuck(plan: Plan, name: str, z_min: float, r_stock: float) -> None:
    """Workholding, when the machine gives a grip: the chuck must hold the stock's diameter,
    the grip must be shorter than the stock, and the deepest cut (the left-end passes run
    the nose radius plus 0.3 mm past the part, contours run on past it, each with a nose
    radius more under G41/G42) must stay :data:`CHUCK_CLEARANCE` clear of the
    jaws' front face; a stick-out over :data:`STICKOUT_RATIO` diameters is a warning (no
    tailstock)."""
    machine, stock = plan.machine, plan.stock
    grip = float(getattr(machine, "grip", 0.0) or 0.0)
    if grip <= 0:
        return
    if stock.kind == "offset":
        length, z_left, z_right = -z_min + 2 * stock.allowance, z_min - stock.allowance, \
            stock.allowance
    else:
        length, z_left, z_right = stock.length, stock.z_left, stock.z_right
    dia = 2 * r_stock
    lo, hi = machine.chuck_clamp
    if grip >= length - 1e-9:
        raise PlanError(f"grip {_fmt(grip)} mm is not shorter than the stock {stock.spec} "
                        f"({_fmt(length)} mm long): nothing would stick out of the chuck")
    if not lo - 1e-9 <= dia <= hi + 1e-9:
        raise PlanError(f"stock {stock.spec}: diameter {_fmt(dia)} mm is outside the chuck's "
                        f"clamping range {_fmt(lo)}-{_fmt(hi)} mm (machine file [chuck] "
                        f"clamp_min/clamp_max)")
    reach = max((op.tool.nose_radius for op in plan.operations), default=0.0) + 0.3
    z_cut = z_min - reach
    if plan.operations and plan.operations[-1].kind == "part":  # the blade's width
        z_cut = min(z_cut, z_min - plan.operations[-1].tool.insert.width)
    for op in plan.operations:  # contours run on past the left end: a tip path is the
        # tool's extent toward the chuck, a compensated contour a nose radius less
        r = op.tool.nose_radius if op.nose_comp != "none" else 0.0
        for seg in op.contour:
            z_cut = min(z_cut, seg.start[1] - r, seg.end[1] - r)
    z_jaw = z_left + grip
    stick = z_right - z_jaw
    if z_cut - CHUCK_CLEARANCE < z_jaw - 1e-9:
        need = z_right - (z_cut - CHUCK_CLEARANCE)
        raise PlanError(f"part {name}: the cut reaches Z{_fmt(z_cut)}, less than "
                        f"{_fmt(CHUCK_CLEARANCE)} mm from the chuck's jaws at Z{_fmt(z_jaw)} "
                        f"(stock {stock.spec}, grip {_fmt(grip)} mm: stick-out {_fmt(stick)} mm); "
                        f"it needs a stick-out of at least {_fmt(need)} mm: a stock at least "
                        f"{_fmt(need + grip)} mm long"
                        + (f", or a grip of at most {_fmt(length - need)} mm"
                           if length - need > 1e-9 else ""))
    if stick > STICKOUT_RATIO * dia:
        plan.warnings.append(
            f"stick-out {_fmt(stick)} mm is {stick / dia:.1f} x the stock diameter "
            f"{_fmt(dia)} mm (more than {_fmt(STICKOUT_RATIO)} without a tailstock): the part "
            f"will deflect and chatter; grip more of it or make it from a shorter stock")


def rpm_limit(t: Tool, machine: Machine | None) -> float:
    """The spindle limit for tool ``t``: the lowest of the machine's max rpm, the chuck's
    rated speed (``[chuck] max_rpm``, when given) and the tool's own ``max_rpm`` (when
    given)."""
    lim = machine.max_rpm if machine is not None else 3000.0
    if machine is not None and machine.chuck_max_rpm > 0:
        lim = min(lim, machine.chuck_max_rpm)
    return min(lim, t.max_rpm) if t.max_rpm > 0 else lim


def _cycle_blocks(op: Operation, owner: Operation) -> list[Block]:
    """The blocks of ``owner`` from the one labelled ``op.ns`` to the one labelled ``op.nf``
    (all of them where ``op`` has no labels): the contour ``op``'s cycle runs."""
    blocks = owner.blocks
    i0 = next((i for i, b in enumerate(blocks) if op.ns and b.label == op.ns), 0)
    i1 = next((i for i, b in enumerate(blocks) if op.nf and b.label == op.nf), len(blocks) - 1)
    return blocks[i0:i1 + 1]


def _x_range(op: Operation, ops: Sequence[Operation]) -> tuple[float, float]:
    """The smallest and largest radius an operation's tool reaches while it runs: its start
    point and every block of its contour (its own blocks or the ns..nf contour of another
    operation it refers to), arcs over the X range they sweep."""
    blocks = op.blocks
    if not blocks and op.ns:
        owner = next((o for o in ops if o.blocks and o.ns == op.ns), None)
        blocks = _cycle_blocks(op, owner) if owner is not None else []
    x = abs(op.start[0])
    lo = hi = x
    for b in blocks:
        nx = abs(b.x) if b.x is not None else x
        lo, hi = min(lo, x, nx), max(hi, x, nx)
        if b.span is not None:
            a, c = b.span
            lo = min(lo, min(abs(a), abs(c)) if a * c > 0 else 0.0)
            hi = max(hi, abs(a), abs(c))
        x = nx
    return lo, hi


def _cap_rough(op: Operation, ops: Sequence[Operation], limit: float) -> None:
    """A roughing cycle cannot change the spindle inside it, and the HNC-21T's G96 has no
    clamp word: where the cycle's G96 would need more than ``limit`` rpm at the smallest
    radius it reaches, a dialect without a clamp word runs the whole cycle (and its
    semi-finishing pass) in G97 at the lower of ``limit`` and the rpm of the cutting speed at
    the largest radius it reaches. No move then cuts faster than the tool's surface speed
    nor spins faster than the limit; the smaller diameters cut slower than G96 would (the
    price of one speed for the cycle). Dialects with a clamp word (``G50 S``) keep G96."""
    vc = op.speed
    lo, hi = _x_range(op, ops)
    if op.rough.strategy == "face":
        hi += op.rough.retract  # a pass's lift: G72 feeds in from the start plus its retract
    r_c = vc * 1000.0 / (2 * math.pi * limit)
    if lo >= r_c - 1e-9:
        return
    rpm = min(limit, vc * 1000.0 / (2 * math.pi * max(hi, 1e-3)))
    rpm = math.floor(rpm + 1e-9)  # whole rpm, never above the limit
    op.unclamped = Spindle("rpm", float(rpm))
    op.reason += (f"; G96 S{_fmt(vc)} needs more than {_fmt(limit)} rpm inside diameter "
                  f"{_fmt(2 * r_c)}, which the cycle reaches: without a G96 clamp word "
                  f"(HNC-21T) it runs G97 S{_fmt(rpm)} (the surface speed at diameter "
                  f"{_fmt(2 * hi)}, at most the limit)")


def _split_rough(op: Operation, ops: Sequence[Operation], limit: float) -> bool:
    """Keep an OD G71 type I at its surface speed where it can: when its G96 would need more
    than ``limit`` rpm at the smallest radius it reaches, the contour (monotone) is cut where
    it first rises to the radius x_s at which the cycle's offset (x_s plus the X allowance)
    is the critical radius; a dialect without a clamp word then runs the cycle in two
    (:class:`RoughSplit`): the outer at G96 down to that radius only, the inner at G97 at
    the limit. A line or an arc written with R crossing x_s is cut there (both parts of such
    an arc keep its centre), else the contour is cut at that block's end. Under G41/G42 the
    split's blocks must leave the control's compensation as it is (:func:`_comp_split`): a
    split inside the nose's trim of a concave corner moves out along its line. False (nothing
    changed) when the cycle needs no cap or cannot be cut: the whole contour inside, a bore, a
    cycle of type II, G72, G73, or (under G41/G42) a split that falls on a block's end or
    where the control's compensation cannot follow it."""
    r = op.rough
    if r.strategy != "turn" or r.side != "od" or r.pockets:
        return False
    owner = op if op.blocks else next((o for o in ops if o.blocks and o.ns == op.ns), None)
    if owner is None or not owner.blocks:
        return False
    vc = op.speed
    r_c = vc * 1000.0 / (2 * math.pi * limit)
    lo, _hi = _x_range(op, ops)
    if lo >= r_c - 1e-9:
        return False
    ax = round(2 * r.allowance_x, 3) / 2  # as the program writes it
    # the split radius: its diameter a whole micrometre, the offset at least 0.5 um outside
    # the critical radius (G96 there stays under the limit after rounding)
    x_t = math.ceil((r_c - ax) * 2000.0 + 1.0 - 1e-6) / 2000.0
    if x_t <= 0:
        return False
    blocks = _cycle_blocks(op, owner)
    x, z = op.start[0], op.start[1]
    # (x0, z0, x1, z1) per block, X signed: a tip path's lead-in past the centre starts an
    # arc at a negative X, and the split of that arc is computed on its own circle
    ends: list[tuple[float, float, float, float]] = []
    for b in blocks:
        nx = b.x if b.x is not None else x
        nz = b.z if b.z is not None else z
        ends.append((x, z, nx, nz))
        x, z = nx, nz
    if ends[0][2] >= x_t:
        return False
    k = next((i for i in range(1, len(ends)) if ends[i][2] >= x_t - 1e-9), None)
    if k is None or k + 1 >= len(blocks):
        return False

    def low(i: int) -> float:
        x0, _z0, x1, _z1 = ends[i]
        b = blocks[i]
        m = min(abs(x0), abs(x1)) if x0 * x1 > 0 else 0.0
        if b.span is not None:
            m = min(m, min(abs(b.span[0]), abs(b.span[1])) if b.span[0] * b.span[1] > 0 else 0.0)
        return m

    def high(i: int) -> float:
        x0, _z0, x1, _z1 = ends[i]
        b = blocks[i]
        return max(abs(x0), abs(x1), *(abs(v) for v in (b.span or ())))

    # monotone: nothing before the crossing reaches x_t, nothing after comes back inside
    if any(high(i) > x_t + 1e-9 for i in range(1, k)) or \
            any(low(i) < x_t - 1e-9 for i in range(k + 1, len(ends))):
        return False
    blk = blocks[k]
    x0, z0, x1, z1 = ends[k]
    tag = op.ns or owner.ns or "rough"
    ns_s, nf_s = f"{tag}_out", f"{tag}_in"
    z_cut = None
    if x0 < x_t - 1e-9 and x1 > x_t + 1e-9 and high(k) <= x1 + 1e-9:
        if blk.kind == "line":
            z_cut = z0 + (z1 - z0) * (x_t - x0) / (x1 - x0)
        elif blk.arc and blk.r is not None:
            # both parts of an arc of at most 170 deg keep its centre with the same R
            arc = Arc.from_radius((x0, z0), (x1, z1), blk.r, blk.kind == "cw")
            hits = horizontal_hits([arc], x_t)
            z_cut = hits[0][1] if len(hits) == 1 else None
        # both pieces must be more than the written resolution long (a piece of an arc that
        # rounds to no length is a full circle to the control)
        if z_cut is not None and min(math.hypot(x_t - x0, z_cut - z0),
                                     math.hypot(x1 - x_t, z1 - z_cut)) < 0.002:
            z_cut = None
    if z_cut is None and owner.nose_comp != "none":
        # under G41/G42 the two blocks of no length stand only inside a block, where the
        # control's offset vector at the split point is the block's own normal
        return False
    if z_cut is not None and owner.nose_comp != "none":
        moved = _comp_split(owner, blk, x_t, z_cut)
        if moved is None:
            return False
        x_t, z_cut = moved
    x_e = x_t if z_cut is not None else x1
    z_e = round_written(z_cut) if z_cut is not None else z1
    # the inside is only the face's edge: where a semi-finishing pass follows the cycle
    # (op.blocks) and what the outer cycle leaves inside it, behind the face (Z <= 0), is
    # within one depth of cut of the contour in X and in Z, that pass takes it: no inner
    # cycle (it would run mostly in air in front of the faced face)
    top = x_e + ax
    inside = [(ends[i][2], ends[i][3]) for i in range(1, k)] + [(x_e, z_e)]
    thin = bool(op.blocks) and -z_e <= r.depth + 1e-9 and \
        all(top - abs(px) <= r.depth + 1e-9 for px, pz in inside if pz <= 1e-9)
    if thin:
        nf_s = ""
    if z_cut is not None:
        x_s, z_s = x_t, round_written(z_cut)
        first = Block(blk.kind, x=x_s, z=z_s, r=blk.r, feed=blk.feed, label=nf_s)
        if blk.arc:
            first.span = (min(x0, x_s), x_s)
        entry = [first]
        at = blk
    else:
        if low(k + 1) < x1 - 1e-9 or high(k) > x1 + 1e-9:
            return False
        x_s, z_s = x1, z1
        if thin:
            pass
        elif blk.label:
            nf_s = blk.label
        else:
            blk.label = nf_s
        entry = []
        at = blocks[k + 1]
    at.before = entry + [Block("rapid", x=x_s, label=ns_s), Block("line", z=z_s)]
    rpm = 0.0 if thin else min(limit, round(vc * 1000.0 / (2 * math.pi * top)))
    op.split = RoughSplit(x=x_s, z=z_s, ns=ns_s, nf=nf_s, start=(top, op.start[1]), rpm=rpm)
    if not op.blocks:
        op.spindle_changed = True  # the op ends in the inner cycle's G97
    else:
        _cap_contour(op, limit)
        if not thin and op.blocks[0].spindle == Spindle("rpm", rpm):
            op.blocks[0].spindle = None  # the inner cycle's G97 holds
    op.reason += (f"; G96 S{_fmt(vc)} needs more than {_fmt(limit)} rpm inside diameter "
                  f"{_fmt(2 * r_c)}: without a G96 clamp word (HNC-21T) the cycle runs "
                  + (f"G96 down to diameter {_fmt(2 * top)} only, the semi-finishing pass "
                     f"takes the face's edge inside it" if thin else
                     f"in two, G96 down to diameter {_fmt(2 * top)}, then G97 S{_fmt(rpm)} "
                     f"inside it"))
    return True


def _comp_split(owner: Operation, blk: Block, x_t: float, z_t: float
                ) -> tuple[float, float] | None:
    """Where a roughing cycle in two may cut the block ``blk`` of a contour run under G41/G42
    (``owner``), at radius ``x_t`` or further out along it: the split's blocks (the block's
    first part, the X and Z moves of no length) must leave the control's compensation of the
    contour as it is. A split the nose's path along the block does not reach (inside the trim
    of a concave corner before it: a face beside a journal cut less than a nose radius from
    it) leaves a first part the offset cannot follow; the split then moves out along a line to
    just past where the nose's path along it begins. None where no such point is inside the
    block (or the block is an arc the nose does not follow at ``x_t``): the cycle is not cut."""
    r, tip, side = owner.tool.nose_radius, owner.tool.tip, owner.nose_comp

    def alarm(xs: float, zs: float) -> str | None:
        saved = blk.before
        blk.before = [Block(blk.kind, x=xs, z=zs, r=blk.r, feed=blk.feed),
                      Block("rapid", x=xs), Block("line", z=zs)]
        try:
            return ct.control_alarm(owner.blocks, owner.start, r, tip, side)
        finally:
            blk.before = saved

    if ct.control_alarm(owner.blocks, owner.start, r, tip, side) is not None:
        return None  # the contour itself alarms: refused by the planner's check of it
    if alarm(x_t, round_written(z_t)) is None:
        return x_t, z_t
    if blk.kind != "line":
        return None
    path = ct.block_path(owner.blocks, owner.start)
    i = 0
    for b in owner.blocks:
        i += len(b.before)
        if b is blk:
            break
        i += 1
    seg = path[i][0]
    res = offset_chain([g for g, _ in path], r, -1 if side == "right" else 1,
                       lookahead=None, measure=())
    pieces = [g for g, o in zip(res.segments, res.origins) if o.kind == "seg" and o.before == i]
    if not pieces or seg.length <= 1e-9:
        return None
    (px, pz), (qx, qz) = seg.start, seg.end
    dx, dz = (qx - px) / seg.length, (qz - pz) / seg.length
    c = pieces[0].start
    s_a = (c[0] - px) * dx + (c[1] - pz) * dz  # where the nose's path along the block begins
    e = pieces[-1].end
    s_b = (e[0] - px) * dx + (e[1] - pz) * dz  # ... and ends
    if dx <= 1e-9:
        return None
    # just past it, the diameter a whole micrometre
    x_s = math.ceil((px + (s_a + 0.01) * dx) * 2000.0 - 1e-6) / 2000.0
    if x_s < x_t:
        return None
    s_s = (x_s - px) / dx
    if s_s > s_b - 0.01:
        return None
    z_s = pz + s_s * dz
    if alarm(x_s, round_written(z_s)) is not None:
        return None
    return x_s, z_s


def _cap_contour(op: Operation, limit: float) -> None:
    """The HNC-21T's G96 has no clamp word: a contour run at G96 switches to G97 at ``limit``
    rpm before each move that comes inside the diameter where G96 would need more, and back
    to G96 before the first move that stays outside it. The op starts in G97 when its start
    point is inside that diameter already."""
    vc = op.speed
    r_c = vc * 1000.0 / (2 * math.pi * limit)
    x, z = abs(op.start[0]), op.start[1]
    mode = "css" if x >= r_c - 1e-9 else "rpm"
    if mode == "rpm":
        op.spindle, op.speed = "rpm", limit
    first = mode
    for b in op.blocks:
        nx = abs(b.x) if b.x is not None else x
        lo = min(x, nx)
        if b.span is not None:
            lo = min(lo, min(abs(b.span[0]), abs(b.span[1])) if b.span[0] * b.span[1] > 0 else 0.0)
        need = "rpm" if lo < r_c - 1e-9 else "css"
        if need != mode:
            b.spindle = Spindle("rpm", limit) if need == "rpm" else Spindle("css", vc)
            mode = need
        x = nx
    if mode != first:
        op.spindle_changed = True
    if any(b.spindle for b in op.blocks) or first == "rpm":
        op.reason += (f"; G96 S{_fmt(vc)} needs more than {_fmt(limit)} rpm inside diameter "
                      f"{_fmt(2 * r_c)}: G97 S{_fmt(limit)} there")


# ------------------------------------------------------------------------------------------
# OD
# ------------------------------------------------------------------------------------------

#: the wall (its descent + 2 deg clearance) no turning tool cutting toward the chuck reaches
WALL_NO_TRAILING_EDGE = 90.0


def _pocket_text(p: an.Pocket, bore: bool = False) -> str:
    kind = "bore undercut" if bore else "undercut"
    return (f"{kind} from Z{_fmt(p.z_right)} to Z{_fmt(p.z_left)} down to diameter "
            f"{_fmt(2 * abs(p.bottom))} (walls descending at up to {p.max_descent:.0f} deg)")


def _plan_od(od: list[Segment], prof: TurnedProfile, stock: Stock, lib: ToolLibrary,
             opts: Options, name: str, x_a: float, z_a: float, r_stock: float,
             length: float, faced: bool = False, machine: Machine | None = None,
             partoff: bool = False) -> tuple[list[Operation], list[Operation], list[Operation]]:
    profilers = [t for t in lib.tools if t.kind == "turn" and
                 ("profile" in t.uses or "finish" in t.uses)]
    end_ops: list[Operation] = []
    overrun = OVERRUN
    # a descending run at the very end (the chamfer of the left edge): bridged in the main
    # contour and made afterwards in one pass by a tool that reaches it, when it is shallow
    od = an.split_x_extremes(od)
    k = len(od)
    while k > 1 and od[k - 1].end[0] < od[k - 1].start[0] - 1e-9:
        k -= 1
    if k < len(od):
        tail = od[k:]
        tp = an._pocket(list(tail), tail[0].start[0], tail[0].start, None)
        pt = [t for t in profilers if back_reach(t) >= tp.max_descent - REACH_TOL]
        if partoff:  # the parting blade's corner cuts it (_partoff_op)
            od = od[:k] + [Line(tail[0].start, (tail[0].start[0], tail[-1].end[1]))]
        elif pt:
            end_ops.append(_end_pocket_op(tp, pt[0], opts, x_a, name))
            od = od[:k] + [Line(tail[0].start, (tail[0].start[0], tail[-1].end[1]))]
            # the roughing and finishing run on past the left end at the part's diameter, so
            # that the chamfer's passes dip into turned stock, not into the bar's wall
            relief = tp.depth + pt[0].nose_radius + 0.3 + 1.5
            if stock.kind != "offset" and r_stock - tail[0].start[0] > 3.0:
                room = tail[-1].end[1] - stock.z_left - 2.0
                grip = float(getattr(machine, "grip", 0.0) or 0.0)
                if grip > 0:  # and the passes stay clear of the chuck's jaws
                    room = min(room, tail[-1].end[1] - (stock.z_left + grip + CHUCK_CLEARANCE)
                               - max(t.nose_radius for t in lib.tools) - 0.3)
                overrun = max(OVERRUN, min(relief, room))
    items = an.pocket_items(od)
    pockets = [it for it in items if isinstance(it, an.Pocket)]
    finishers = [t for t in turning_tools(lib, "finish") if can_square_shoulder(t)]
    roughers = [t for t in turning_tools(lib, "rough") if can_square_shoulder(t)]
    if not finishers:
        raise PlanError("the tool library has no OD finishing tool (kind turn, uses 'finish')")
    if not roughers:
        raise PlanError("the tool library has no OD roughing tool (kind turn, uses 'rough')")
    if stock.kind != "offset" and od and stock.z_left > od[-1].end[1] - 1e-6:
        # the bar ends at the part's left end: a nose that stops short of the corner by its
        # radius leaves that corner rounded, so the passes run on past it by the largest nose
        overrun = max(overrun, OVERRUN + max(t.nose_radius for t in finishers + roughers))
    best_reach = max(back_reach(t) for t in finishers)
    grooving = [t for t in lib.tools if t.kind == "groove"]
    groove_ops: list[Operation] = []
    bridged: set[int] = set()
    for p in pockets:
        if stock.kind != "offset" and p.max_descent <= best_reach + REACH_TOL \
                and any(back_reach(t) >= p.max_descent - REACH_TOL and t in roughers for t in finishers):
            continue  # turned: kept in the contour (G71 type II)
        if stock.kind == "offset" and p.max_descent <= best_reach + REACH_TOL:
            continue
        sq = an.square_groove(p)
        if sq is None:
            need = p.max_descent + 2.0
            if need >= WALL_NO_TRAILING_EDGE:
                # a trailing edge clears 180 deg less the holder's approach (90 deg or more
                # for a square shoulder) less the insert's angle: always under 90 deg
                raise PlanError(f"part {name}: {_pocket_text(p)}: its wall facing the chuck "
                                f"descends at {p.max_descent:.0f} deg, steeper than the trailing "
                                f"edge of any turning tool cutting toward the chuck clears (a 35 "
                                f"deg VNMG in a 93 deg holder: 50 deg); it needs a second setup "
                                f"(the part turned around) or a tool cutting toward +Z"
                                + (": generate --setups 2 -o DIR/ --grip2 MM" if p.exit is None
                                   else ""))
            raise PlanError(f"part {name}: {_pocket_text(p)}: no tool in the library can reach "
                            f"it; it needs a turning tool whose trailing edge clears {need:.0f} deg "
                            f"(e.g. a 35 deg VNMG in a 93 deg holder reaches 50 deg)"
                            + ("" if p.max_descent < 89 else " or a form/grooving tool for this shape"))
        z_l, z_r, x_b = sq
        width = z_r - z_l
        fits = [t for t in grooving if 0 < t.insert.width <= width + 1e-9]
        if not fits:
            have = ", ".join(f"T{t.number:02d} {t.insert.width:g} mm" for t in grooving) or "none"
            raise PlanError(f"part {name}: square groove from Z{_fmt(z_r)} to Z{_fmt(z_l)} "
                            f"({_fmt(width)} mm wide, down to diameter {_fmt(2 * x_b)}) is "
                            f"unreachable: no tool in the library can cut it; it needs a grooving "
                            f"insert at most {_fmt(width)} mm wide (grooving tools in the library: {have})")
        t = max(fits, key=lambda t: t.insert.width)
        bridged.add(id(p))
        groove_ops.append(_groove_op(t, z_l, z_r, x_b, p.level, x_a,
                                         rpm_limit(t, machine)))
    contour = an.assemble(items, bridge=lambda p: id(p) in bridged)
    if faced:
        # enough of the face for the finishing nose to enter the edge along it
        keep = 2 * (max(t.nose_radius for t in finishers) + opts.allowance_x) + 0.2
        contour = ct.drop_face(contour, 0.0, keep)
    groove_ops = end_ops + groove_ops
    kept = [p for p in pockets if id(p) not in bridged]
    reach_needed = an.max_descent(contour)
    fin = [t for t in finishers if back_reach(t) >= reach_needed - REACH_TOL]
    if not fin:
        raise PlanError(f"part {name}: no finishing tool reaches walls descending at "
                        f"{reach_needed:.0f} deg")
    finisher = fin[0]
    zoned = bool(kept) and stock.kind != "offset"
    if not kept:
        rougher = roughers[0]
    elif stock.kind == "offset":
        rr = _by_rigidity([t for t in lib.tools if t.kind == "turn" and "rough" in t.uses
                           and can_square_shoulder(t) and back_reach(t) >= reach_needed - REACH_TOL])
        if not rr:
            raise PlanError(f"part {name}: no roughing tool reaches walls descending at "
                            f"{reach_needed:.0f} deg")
        rougher = rr[0]
    else:
        rougher = roughers[0]

    envelope = contour if not zoned else an.assemble(
        [it for it in items], bridge=lambda p: True)
    if zoned and faced:
        envelope = ct.drop_face(envelope, 0.0)
    xs = [s.bbox()[0] for s in contour]
    radial_extent = r_stock - min(xs)
    # passes each cycle would make: G71 levels from the stock's diameter down to where the
    # contour starts, G72 levels from the face down to the deepest Z still under the stock
    n71 = math.ceil(max(0.0, r_stock - contour[0].start[0]) / rougher.depth - 1e-9)
    deep = min((s.bbox()[1] for s in contour if s.bbox()[0] < r_stock - 1e-6), default=0.0)
    n72 = math.ceil(max(0.0, -deep) / rougher.depth - 1e-9)
    if stock.kind == "offset":
        strategy = "pattern"
        reason = (f"near-net blank (stock {stock.spec}): G73 repeats the contour "
                  f"offset by the blank allowance")
        base_dir = (1.0, 0.0)
    elif not zoned and radial_extent > length and n72 < n71:
        strategy = "face"
        reason = (f"face-dominated: radial extent {_fmt(radial_extent)} mm > length "
                  f"{_fmt(length)} mm and G72 needs {n72} passes parallel to X where G71 "
                  f"needs {n71}")
        base_dir = (opts.allowance_x, opts.allowance_z)
    else:
        strategy = "turn"
        reason = ("outside contour monotonic in X: G71 type I" if not zoned else
                  f"G71 type I on the outside envelope ({len(kept)} undercut zone"
                  f"{'s' if len(kept) > 1 else ''} bridged, roughed after), then one "
                  f"semi-finishing pass along the envelope leaving the finishing allowance")
        if bridged:
            reason += f" (with {len(bridged)} groove(s) bridged, plunged later)"
        base_dir = (opts.allowance_x, opts.allowance_z)

    base = ct.with_leads(contour, z_a, x_a, past_centre=2 * finisher.nose_radius + 0.1,
                         overrun=overrun)
    if opts.comp == "cam":
        prog = ct.tip_path(base, finisher.nose_radius, finisher.tip, bore=False)
        delta = rougher.nose_radius - finisher.nose_radius
    else:
        # the control's G42 alarms where the nose cannot follow the contour: refused here
        ct.tip_path(base, finisher.nose_radius, finisher.tip, bore=False)
        prog = base
        delta = rougher.nose_radius
    # the finishing contour is the roughing cycle's ns..nf unless the roughing runs its own
    ns, nf = ("", "") if zoned else ("od_ns", "od_nf")
    if strategy == "face":
        prog_run = [s.reversed() for s in reversed(prog)]
        first_axis, comp = "z", "left"
    else:
        prog_run, first_axis, comp = prog, "x", "right"
    blocks = ct.to_blocks(prog_run, first_axis, finisher.feed_finish, ns, nf,
                          start=(x_a, z_a))
    face_op = None
    if strategy == "turn" and not faced and stock.kind != "offset":
        blocks, prog_run, face_op = _face_to_centre(blocks, prog_run, contour, finisher, x_a,
                                                      z_a, opts.comp)
    if opts.comp == "cam":
        comp = "none"
    start = (x_a, z_a)
    # the cycle starts on the stock: G71 at the stock's diameter (its first level one full
    # depth in), G72 on the stock's face (no pass in front of it)
    if strategy == "turn":
        rough_start = (r_stock, z_a)
    elif strategy == "face":
        rough_start = (x_a, z_a - opts.z_clear)
    else:
        rough_start = start
    rough_ops: list[Operation] = []
    if not zoned:
        ax, az = _allowance(contour, delta, base_dir, opts, what=f"part {name} outside")
        cut = RoughCut(strategy=strategy, side="od", pockets=False, depth=rougher.depth,
                       retract=opts.retract, allowance_x=ax, allowance_z=az)
        if strategy == "pattern":
            a = stock.allowance
            # the face was faced first: the passes step in X only (relief Z 0), so no pass
            # climbs the face with the insert's back
            cut.relief_x, cut.relief_z = a, 0.0
            cut.count = max(1, math.ceil(a / rougher.depth - 1e-9))
        rough_ops.append(Operation(name="rough", kind="rough", tool=rougher,
                                   reason=reason, start=rough_start, speed=rougher.vc_rough,
                                   feed=rougher.feed_rough, rough=cut, ns=ns, nf=nf))
    else:
        rough_ops.append(_semi_op("rough", rougher, envelope, opts, rough_start, reason,
                                  x_a, z_a, "env", overrun))
        for i, p in enumerate(kept):
            tools = _by_rigidity([t for t in lib.tools if t.kind == "turn"
                                  and ("rough" in t.uses or "profile" in t.uses)
                                  and can_square_shoulder(t)
                                  and back_reach(t) >= p.max_descent - REACH_TOL])
            if not tools:
                raise PlanError(f"part {name}: {_pocket_text(p)}: no roughing tool in the library "
                                f"reaches it; it needs a turning tool whose trailing edge clears "
                                f"{p.max_descent + 2:.0f} deg")
            rough_ops.append(_zone_op(p, tools[0], opts, r_stock, f"z{i + 1}", name, od))
    last = prog_run[-1].end
    if strategy == "face":
        retract = [(x_a, z_a)]
    else:
        retract = [(x_a, last[1]), (x_a, z_a)]
    finish = Operation(name="finish", kind="finish", tool=finisher,
                       reason=(f"finish the outside contour with {describe(finisher)}"
                               + (" (tip path of this tool, G40)" if opts.comp == "cam"
                                  else f" (G{41 if comp == 'left' else 42} from register "
                                       f"{finisher.register})")),
                       start=start, speed=finisher.vc_finish, feed=finisher.feed_finish,
                       blocks=blocks, ns=ns, nf=nf, nose_comp=comp, contour=prog_run,
                       retract=_retract(retract, blocks))
    return rough_ops, ([face_op] if face_op is not None else []) + [finish], groove_ops


def _face_to_centre(blocks: list[Block], path: list[Segment], contour: Sequence[Segment],
                    finisher: Tool, x_a: float, z_a: float, comp: str
                    ) -> tuple[list[Block], list[Segment], Operation | None]:
    """A finishing contour that starts on the axis with the right face (a stock not faced
    first: the face is part of the finished contour): the face is finished toward the
    centre by an operation of its own before the contour, with the finisher, when its
    trailing edge can lead a cut along -X (:func:`back_reach`). That operation is the tip
    path in both compensation modes (G40: a face is a line along X, the imaginary tip's
    Z is the face's): fed down 1 mm in front of the face's edge, along the face until the
    nose's centre is past the axis, lifted 1 mm. The contour then starts at the face's
    edge: its first block (the roughing cycle's ns) goes there along X, the next feeds down
    to the face, so that the cycle makes no passes in front of the face. Under G42
    (``comp`` control) it comes down 1 mm inside the edge and runs that last millimetre of
    the face outward, so that the control rolls the nose around the edge into the next
    element as it does on the part's contour. ``blocks``/``path``: the contour as
    ``to_blocks`` wrote it (cam: the tip path; control: the part); ``contour``: the part's
    outside chain. Unchanged (and no operation) when it does not start so."""
    if len(blocks) < 4 or not contour or back_reach(finisher) <= 1.0:
        return blocks, path, None
    s0 = contour[0]
    if not (isinstance(s0, Line) and abs(s0.start[0]) < 1e-9
            and abs(s0.end[1] - s0.start[1]) < 1e-9 and s0.end[0] > 0.5):
        return blocks, path, None
    b0, b1, b2 = blocks[:3]
    if not (b0.kind == "rapid" and b0.x is not None and b0.z is None and b0.x <= 1e-9
            and b1.kind == "line" and b1.x is not None and abs(b1.x - b0.x) < 1e-9
            and b1.z is not None and b2.kind == "line" and b2.z is not None
            and abs(b2.z - b1.z) < 1e-9 and b2.x is not None and b2.x > 0.5 and not b2.label):
        return blocks, path, None
    z0, x_e = b1.z, b2.x
    k = next((i for i, sg in enumerate(path) if isinstance(sg, Line)
              and abs(sg.end[0] - x_e) < 1e-6 and abs(sg.end[1] - z0) < 1e-6
              and abs(sg.start[1] - z0) < 1e-6), None)
    if k is None:
        return blocks, path, None
    feed = finisher.feed_finish
    x_in = x_e - min(1.0, x_e / 2) if comp == "control" else x_e
    run = [Block("rapid", x=x_in, label=b0.label), Block("line", z=z0, feed=feed)]
    geo = [Line((x_in, z_a), (x_in, z0))]
    if x_in < x_e:
        run.append(Block("line", x=x_e))
        geo.append(Line((x_in, z0), (x_e, z0)))
    run += blocks[3:]
    geo += list(path[k + 1:])
    # the face op: the nose's centre 1 mm above the face at its edge, down onto it, along it
    # to 0.1 mm past the axis, up again; the program carries the imaginary tip
    from ..geometry.tip import tip_vector
    r = finisher.nose_radius
    vx, vz = tip_vector(finisher.tip, r)
    x_f, z_f = s0.end[0] + vx, s0.start[1] + r + vz
    x_c = -0.1 + vx
    up = z_f + 1.0
    fblocks = [Block("rapid", z=up), Block("line", z=z_f, feed=feed), Block("line", x=x_c),
               Block("rapid", z=up)]
    fgeo = [Line((x_f, up), (x_f, z_f)), Line((x_f, z_f), (x_c, z_f))]
    face = Operation(name="face", kind="finish", tool=finisher,
                     reason=(f"the right face is part of the finished contour (a stock not "
                             f"faced first): finished from its edge at diameter "
                             f"{_fmt(2 * s0.end[0])} toward the centre with "
                             f"{describe(finisher)} (tip path, G40), before the contour"),
                     start=(x_f, z_a), speed=finisher.vc_finish, feed=feed, blocks=fblocks,
                     passes=[s0.start[1]], contour=fgeo, retract=[],
                     # in front of the stock first (an operation before may end inside an
                     # undercut), then along X to the face's edge
                     approach=[(x_a, z_a), (x_f, None)])
    return run, geo, face


#: semi-finishing stock the roughing cycle leaves above the finishing allowance, radial and
#: axial mm: the cycle's offset is a translation, the semi-finishing pass that follows
#: leaves the finishing allowance normal to the part everywhere
SEMI_X = 0.3
SEMI_Z = 0.1


def _allowance_path(chain: Sequence[Segment], t: Tool, opts: Options) -> list[Segment]:
    """The tip path of ``t`` that leaves the finishing allowance on ``chain``: X
    (``opts.allowance_x``, radial) on diameters, Z (``opts.allowance_z``) on faces and
    shoulders. The nose rolls at the smaller of the two normal to the part (an exact offset:
    undercut walls facing the chuck keep it too), then the path moves out along X by what
    the X allowance exceeds it, which a face slides along and a diameter gains in full (a
    taper or an arc gets its share by its normal's X part). A Z allowance larger than the X
    one is left as the X one: moved along Z, a wall facing the chuck would be cut into."""
    ax, az = opts.allowance_x, opts.allowance_z
    a0 = min(ax, az)
    path = ct.allowance_path(chain, t.nose_radius, t.tip, a0)
    if ax - a0 > 1e-9:
        path = [s.translated(ax - a0, 0.0) for s in path]
    return path


def _by_rigidity(tools: list[Tool]) -> list[Tool]:
    """Strongest insert first: the larger included angle, then a tool meant for roughing."""
    return sorted(tools, key=lambda t: (-t.insert.nose_angle, "rough" not in t.uses))


def _semi_op(name: str, t: Tool, chain: list[Segment], opts: Options,
             start: Point, reason: str, x_a: float, z_a: float, tag: str,
             overrun: float = OVERRUN) -> Operation:
    """G71 type I over ``chain`` (monotone) with the tool's own semi-finishing contour as
    ns..nf: the cycle leaves the finishing allowance plus (SEMI_X, SEMI_Z), the ns..nf blocks
    that follow it take that off, leaving the finishing allowance normal to the part."""
    base = ct.with_leads(chain, z_a, x_a, past_centre=2 * t.nose_radius + 0.1, overrun=overrun)
    path = _allowance_path(base, t, opts)
    ns, nf = f"{tag}_ns", f"{tag}_nf"
    blocks = ct.to_blocks(path, "x", t.feed_rough, ns, nf, start=start)
    last = path[-1].end
    cut = RoughCut(strategy="turn", side="od", pockets=False, depth=t.depth,
                   retract=opts.retract, allowance_x=SEMI_X, allowance_z=SEMI_Z)
    return Operation(name=name, kind="rough", tool=t, reason=reason,
                     start=start, speed=t.vc_rough, feed=t.feed_rough, rough=cut, ns=ns,
                     nf=nf, blocks=blocks, contour=path,
                     retract=_retract([(x_a, last[1]), (x_a, z_a)], blocks))


def _zone_op(p: an.Pocket, t: Tool, opts: Options, r_stock: float, tag: str,
             name: str, part: Sequence[Segment] = ()) -> Operation:
    """Rest-roughing of one undercut zone by a tool that reaches it: G71 type II over the
    zone alone, from the material the envelope's semi-finishing pass left (its level plus
    the finishing allowance), then the zone's semi-finishing pass."""
    a = opts.allowance_x
    z_in = p.entry[1] + max(1.0, 2 * t.nose_radius + a)
    exit_ = p.exit if p.exit is not None else (p.level, p.segments[-1].end[1])
    chain = [Line((p.level, z_in), p.entry)] + list(p.segments)
    if p.exit is None:
        chain.append(Line(p.segments[-1].end, exit_))
    # the rising wall past the exit, so that the offset reaches the level plus the allowance:
    # the part's own contour where the exit lies on it (a fillet cut at the level turns on
    # into a shoulder: its tangent there would run into the shoulder), else the tangent
    up = chain[-1]
    tx, tz = up.tangent_at_end()
    after = _contour_after(part, up.end, p.level + a + t.nose_radius + 0.5)
    if after:
        chain += after
    elif tx > 0.05:
        k = (a + t.nose_radius + 0.5) / tx
        chain.append(Line(up.end, (up.end[0] + k * tx, up.end[1] + k * tz)))
    path = _allowance_path(chain, t, opts)
    top = p.level + a
    path = _clip_above(path, top)
    # the points at the level (the start, the cut where the path rises back to it) are that
    # level, one value written alike (the last bit rounded the other way can write the end
    # one digit below the start, a profile G71 refuses)
    path = [replace(q, **{k: (top, getattr(q, k)[1]) for k in ("start", "end")
                          if abs(getattr(q, k)[0] - top) < 1e-7})
            for q in path]
    x_start = top + opts.retract + 0.5
    start = (x_start, path[0].start[1])
    ns, nf = f"{tag}_ns", f"{tag}_nf"
    blocks = ct.to_blocks(path, "x", t.feed_rough, ns, nf, start=start)
    # the ns block ends on the semi-finished surface: fed, not rapid (G01 is allowed there)
    blocks[0].kind, blocks[0].feed = "line", t.feed_rough
    cut = RoughCut(strategy="turn", side="od", pockets=True, depth=t.depth,
                   retract=opts.retract, allowance_x=SEMI_X)
    last = path[-1].end
    reason = (f"rest-rough {_pocket_text(p)} with {describe(t)} (reaches "
              f"{back_reach(t):.0f} deg): G71 type II over this zone, then its semi-finishing "
              f"pass")
    return Operation(name="rough_zone", kind="rough", tool=t,
                     reason=reason, start=start, speed=t.vc_rough, feed=t.feed_rough,
                     rough=cut, ns=ns, nf=nf, blocks=blocks, contour=path,
                     retract=_retract([(x_start, min(last[1] + 0.8, start[1])),
                                       (x_start, start[1])], blocks))


def _contour_after(part: Sequence[Segment], pt: Point, x_out: float) -> list[Segment]:
    """The segments of the chain ``part`` from the point ``pt`` on it onward, up to where
    they first reach radius ``x_out`` (cut there); empty where ``pt`` is not on ``part``
    or the chain never gets out so far."""
    out: list[Segment | None] = []  # None: the start found
    for s in part:
        if not out:
            if math.dist(s.end, pt) < 1e-7:
                out.append(None)  # pt is this segment's end: start with the next one
                continue
            parts = an._split_at_x(s, pt[0]) if min(s.start[0], s.end[0]) < pt[0] - 1e-9 < \
                max(s.start[0], s.end[0]) or isinstance(s, Arc) else None
            rest = next((q for q in (parts or ()) if math.dist(q.start, pt) < 1e-7), None)
            if rest is None:
                continue
            out.append(None)
            s = rest
        if s.bbox()[2] >= x_out - 1e-9:
            parts = an._split_at_x(s, x_out)
            out.append(parts[0] if parts and math.dist(parts[0].start, s.start) < 1e-9 else s)
            return [q for q in out if q is not None]
        out.append(s)
    return []


def _clip_above(path: list[Segment], top: float) -> list[Segment]:
    """The zone path up to where, after dipping below ``top``, it first rises back to
    ``top`` (cut there: beyond, the envelope's semi-finishing pass has already been)."""
    out: list[Segment] = []
    down = False
    for s in path:
        if down and s.end[0] > top + 1e-9:
            if s.start[0] < top - 1e-9:
                parts = an._split_at_x(s, top)
                out.append(parts[0] if parts else s)
            break
        out.append(s)
        if s.bbox()[0] < top - 1e-6:
            down = True
    return out


def _retract(points: list[Point], blocks) -> list[Point]:
    """The retract moves after a contour, without those that go nowhere (the exit line of a
    control-mode contour already ends at the first retract point; the G40 that the template
    puts on the first retract move then cancels on a move that leaves)."""
    last = blocks[-1]
    end = (last.x, last.z)
    out = list(points)
    while len(out) > 1 and end[0] is not None and end[1] is not None \
            and round(2 * out[0][0], 3) == round(2 * end[0], 3) and round(out[0][1], 3) == round(end[1], 3):
        out.pop(0)
    return out


def _end_pocket_op(p: an.Pocket, t: Tool, opts: Options, x_a: float, name: str) -> Operation:
    """Profile a descending run at the left end (e.g. the left edge's chamfer or a dome
    toward the chuck; bridged in the main contour) with a tool that reaches it.

    Passes follow the run shifted outward in X (as G73 does, at most the tool's depth apart);
    each continues past the part's left end by the nose radius plus 0.3 mm, into the stock
    that stays in the chuck, so that no wedge is left between the run and the parting plane,
    then returns along its own path. These passes are always written as the tool's tip path
    (G40), in both compensation modes: a control compensating a path that reverses on itself
    would put the nose on the wrong side.
    """
    z_in = p.entry[1] + 0.5
    segs = list(p.segments)
    last = segs[-1]
    tx, tz = last.tangent_at_end()
    e = (t.nose_radius + 0.3) / max(abs(tz), 0.3)
    ext = Line(last.end, (last.end[0] + e * tx, last.end[1] + e * tz))
    base = [Line((p.entry[0], z_in), p.entry)] + segs + [ext]
    prog = ct.tip_path(base, t.nose_radius, t.tip, bore=False)
    n = max(1, math.ceil(p.depth / t.depth - 1e-9))
    path: list[Segment] = []
    for k in range(n - 1, -1, -1):
        dx = p.depth * k / n
        fwd = [s.translated(dx, 0.0) for s in prog]
        back = [s.reversed() for s in reversed(fwd)]
        if path:
            path.append(Line(path[-1].end, fwd[0].start))
        path += fwd + back
    # the rapid ends 0.5 mm above the first pass, the rest is fed (the surface is finished)
    p0 = path[0].start
    path.insert(0, Line((p0[0] + 0.5, p0[1]), p0))
    blocks = ct.to_blocks(path, "x", t.feed_finish, "", "", start=(x_a, z_in))
    return Operation(
        name="profile", kind="finish", tool=t,
        reason=(f"{_pocket_text(p)} at the left end: {n} pass{'es' if n > 1 else ''} with "
                f"{describe(t)}, which reaches {back_reach(t):.0f} deg, past the end into the "
                f"chuck-side stock and back (tip path, G40)"),
        start=(x_a, z_in), speed=t.vc_finish, feed=t.feed_finish, blocks=blocks, nose_comp="none",
        contour=path, retract=[(x_a, path[-1].end[1]), (x_a, z_in)])


def _allowance(chain: Sequence[Segment], delta: float, base: Point, opts: Options,
               what: str) -> tuple[float, float]:
    """Radial and axial finishing allowance (ax, az) along ``base`` direction, scaled so that
    the roughing tool stays >= margin from the part where the allowance can act (see the
    module docstring). ``chain`` is OD-normalised."""
    bx, bz = base
    if bz == 0:
        bx = opts.allowance_x
    scale = 1.0
    for s in chain:
        if s.length < 1e-9:
            continue
        for n in an.normals(s):
            g = delta * (1.0 - (n[0] + n[1]))  # gouge the tool offset would cause
            ns_ = n[0] * bx + n[1] * bz
            if ns_ > 0.05 * math.hypot(bx, bz):
                scale = max(scale, (opts.margin + g) / ns_)
            elif g > 0.002:
                raise PlanError(f"{what}: the roughing tool would cut {g:.3f} mm into the wall at "
                                f"{_where(s.start)} and no finishing allowance can prevent it; "
                                f"use the same tool for roughing and finishing")
    return bx * scale, bz * scale


#: stock left on a wide groove's walls and bottom by the plunges, for the finishing pass, mm
GROOVE_FINISH = 0.1


def _groove_op(t: Tool, z_l: float, z_r: float, x_b: float, level: float,
               x_a: float, max_rpm: float = 3000.0) -> Operation:
    """Plunges with the grooving insert (controlled point: its left corner), each back out
    only to 0.6 mm above the groove's top; a dwell of the tool's ``dwell_rev`` revolutions
    at the bottom. A groove wider than the insert is plunged leaving :data:`GROOVE_FINISH` on the
    walls and the bottom, then finished in one pass: down the right wall, along the bottom,
    up the left wall."""
    w = t.insert.width
    pos, fa, rpm, capped, dwell = groove_plunges(t, z_l, z_r, x_b, GROOVE_FINISH, max_rpm)
    cut = GrooveCut(x_bottom=x_b + fa, x_clear=level + 0.6, dwell=dwell)
    if fa > 0:
        cut.finish = GrooveFinish(z_right=z_r - w, z_left=z_l, x_bottom=x_b)
    return Operation(
        name="groove", kind="groove", tool=t,
        reason=(f"square groove Z{_fmt(z_r)}..Z{_fmt(z_l)} to diameter {_fmt(2 * x_b)}: walls "
                f"steeper than any turning insert reaches, plunged with {describe(t)} in "
                f"{len(pos)} plunge{'s' if len(pos) > 1 else ''}"
                + (", then one finishing pass on the walls and bottom" if fa > 0 else "")),
        start=(x_a, pos[0]), spindle="rpm" if capped else "css",
        speed=rpm if capped else t.vc_finish, feed=t.feed_finish, passes=pos, groove=cut)


def _face_groove_op(g: an.FaceGroove, lib: ToolLibrary, machine: Machine, name: str,
                    z_a: float) -> Operation:
    """An axial ring groove in the right face, cut with the widest library ``groove_face``
    blade no wider than the groove whose diameter range holds both walls (and whose
    ``max_depth``, when given, reaches the floor): plunges along -Z (the controlled point the
    middle of the blade's end) from the outer wall inward, stepping by at most the blade's
    width less its corner radii, a dwell of ``dwell_rev`` revolutions at the floor, back out
    along +Z to 0.6 mm in front of the face after each. G97 at the blade's finishing surface
    speed at the groove's outer diameter, at most the spindle limit. A groove wider than the
    blade is plunged leaving :data:`GROOVE_FINISH` on its walls and floor (where there is
    room), then finished in one pass: down the inner wall, along the floor, up the outer."""
    d_in, d_out = 2 * g.r_in, 2 * g.r_out
    blades = [t for t in lib.tools if t.kind == "groove_face"]
    fits = [t for t in blades if 0 < t.insert.width <= g.width + 1e-9
            and t.min_diameter <= d_in + 1e-9 and t.max_diameter >= d_out - 1e-9
            and (t.max_depth <= 0 or t.max_depth >= g.depth - 1e-9)]
    if not fits:
        have = ", ".join(f"T{t.number:02d} {t.insert.width:g} mm for diameters "
                         f"{t.min_diameter:g}-{t.max_diameter:g}" for t in blades) or "none"
        raise PlanError(f"part {name}: face groove between diameters {_fmt(d_in)} and "
                        f"{_fmt(d_out)} ({_fmt(g.width)} mm wide, {_fmt(g.depth)} mm deep, floor "
                        f"at Z{_fmt(g.z_floor)}) is unreachable: it needs a face grooving blade "
                        f"(kind groove_face) at most {_fmt(g.width)} mm wide whose diameter range "
                        f"holds {_fmt(d_in)}-{_fmt(d_out)} (face grooving blades in the library: "
                        f"{have})")
    t = max(fits, key=lambda t: (t.insert.width, -t.number))
    w = t.insert.width
    wide = g.width - w > 1e-6
    fa = GROOVE_FINISH if wide and g.width - w > 2 * GROOVE_FINISH + 1e-6 else 0.0
    first, last = g.r_out - w / 2 - fa, g.r_in + w / 2 + fa
    step = max(0.1 * w, w - 2 * t.nose_radius - 0.05)
    n = max(1, math.ceil((first - last) / step - 1e-9) + 1) if first - last > 1e-9 else 1
    pos = [first - (first - last) * i / (n - 1) for i in range(n)] if n > 1 else [first]
    lim = rpm_limit(t, machine)
    rpm = t.vc_finish * 1000.0 / (math.pi * d_out)
    capped = rpm > lim
    rpm = float(min(lim, round(rpm)))
    dwell = max(round(t.dwell_rev * 60.0 / rpm, 2), 0.05)
    cut = FaceGrooveCut(z_bottom=g.z_floor + fa, z_clear=g.z_top + 0.6, dwell=dwell,
                        finish=wide, x_outer=g.r_out - w / 2, x_inner=g.r_in + w / 2,
                        z_floor=g.z_floor, r_in=g.r_in, r_out=g.r_out)
    return Operation(
        name="groove_face", kind="groove", tool=t,
        reason=(f"face groove between diameters {_fmt(d_in)} and {_fmt(d_out)} to Z{_fmt(g.z_floor)}: "
                f"open toward +Z, plunged along -Z with {describe(t)} in {n} plunge"
                f"{'s' if n > 1 else ''} at G97 S{_fmt(rpm)} (its surface speed at diameter "
                f"{_fmt(d_out)}" + (f", capped at {_fmt(lim)} rpm" if capped else "") + ")"
                + (", then one finishing pass down the inner wall, along the floor, up the "
                   "outer wall" if wide else "")),
        start=(pos[0], z_a), spindle="rpm", speed=rpm, feed=t.feed_finish, passes=pos,
        face_groove=cut)


# ------------------------------------------------------------------------------------------
# bore
# ------------------------------------------------------------------------------------------

def _face_room(od: Sequence[Segment]) -> float:
    """How far the right face runs out from the bore's mouth: the length of the outside
    chain's first segment where it lies on the face (0 where it does not)."""
    s0 = od[0] if od else None
    if isinstance(s0, Line) and abs(s0.start[1]) < 1e-9 and abs(s0.end[1]) < 1e-9:
        return s0.length
    return 0.0


def _plan_bore(chain: list[Segment], stock: Stock, lib: ToolLibrary, opts: Options, name: str,
               z_a: float, hole: float | None = None,
               x_hole: float | None = None, machine: Machine | None = None,
               face: float = 0.0) -> list[Operation]:
    """Rough and finish a bore from the tube's hole, or from a drilled ``hole`` (the diameter
    the bar enters; ``x_hole``: the radius the roughing cycle starts from, the smallest hole
    drilled). ``face``: how far the right face runs out from the bore's mouth
    (:func:`_face_room`): a mouth rounded into the face is entered along the face."""
    drilled = hole is not None
    rb = (x_hole if drilled else stock.bore / 2)
    # a flat bottom faced from the drilled hole: the chain ends along it, toward the axis
    faced = drilled and isinstance(chain[-1], Line) and chain[-1].end[0] < chain[-1].start[0] \
        and abs(chain[-1].start[1] - chain[-1].end[1]) <= 1e-9
    entry = hole if drilled else stock.bore
    bars = [t for t in lib.tools if t.kind == "bore" and "rough" in t.uses]
    if not bars:
        raise PlanError(f"part {name} has a bore: the tool library has no boring bar "
                        f"(kind bore, uses 'rough')")
    fits = [t for t in bars if t.min_bore <= entry + 1e-9]
    if not fits:
        t = min(bars, key=lambda t: t.min_bore)
        if drilled:
            raise PlanError(f"part {name}: the drilled hole (diameter {_fmt(entry)}) is smaller "
                            f"than the smallest bore the boring bar T{t.number:02d} enters "
                            f"(min_bore {_fmt(t.min_bore)}): it needs a boring bar for diameter "
                            f"{_fmt(entry)}")
        raise PlanError(f"part {name}: the stock's hole (diameter {_fmt(stock.bore)}) is smaller "
                        f"than the smallest bore the boring bar T{t.number:02d} enters (diameter "
                        f"{_fmt(t.min_bore)}): it needs a boring bar for diameter "
                        f"{_fmt(stock.bore)} or a larger pre-drilled hole")
    # the bar's reach along Z (its max_depth; 0: not limited) against the bore's depth
    depth = -min(s.bbox()[1] for s in chain)
    reach = [t for t in fits if t.max_depth <= 0 or t.max_depth >= depth - 1e-9]
    if not reach:
        t = max(fits, key=lambda t: t.max_depth)
        raise PlanError(f"part {name}: the bore runs {_fmt(depth)} mm deep (to Z{_fmt(-depth)}); "
                        f"the boring bar T{t.number:02d} reaches {_fmt(t.max_depth)} mm "
                        f"(max_depth): it needs a boring bar reaching {_fmt(depth)} mm")
    fits = reach
    norm = an.mirror_chain(chain)
    notes: list[str] = []
    # a bore widening at the very end (the chamfer of the bore's left edge) faces the chuck:
    # no boring bar reaches it from the right; the part needs a second setup (--setups 2,
    # :mod:`hnc_cam.plan.setups`)
    k = len(norm)
    while k > 1 and norm[k - 1].end[0] < norm[k - 1].start[0] - 1e-9:
        k -= 1
    if k < len(norm):
        tail = norm[k:]
        tp = an._pocket(list(tail), tail[0].start[0], tail[0].start, None)
        if not any(back_reach(t) >= tp.max_descent - REACH_TOL for t in fits):
            z0, z1 = tail[0].start[1], tail[-1].end[1]
            raise PlanError(f"part {name}: the bore's chamfer from Z{_fmt(z0)} to Z{_fmt(z1)} "
                            f"(diameter {_fmt(-2 * tail[0].start[0])} to "
                            f"{_fmt(-2 * tail[-1].end[0])}) faces the chuck: no boring bar "
                            f"reaches it from the right; it needs a second setup with the part "
                            f"turned around: generate --setups 2 -o DIR/ --grip2 MM")
    # square grooves no boring bar reaches (reliefs, ring grooves): plunged with the inside
    # grooving tool after the finishing, bridged for the bar
    from .drilling import bridge_id_grooves
    norm, id_grooves = bridge_id_grooves(norm, fits, lib, machine, name, z_a)
    if drilled and max(-p[0] for s in norm for p in (s.start, s.end)) <= rb + 1e-6:
        return id_grooves  # the drill made the rest: the grooves alone are left
    chain = an.mirror_chain(norm)
    items = an.pocket_items(norm)
    pockets = [it for it in items if isinstance(it, an.Pocket)]
    monotonic = not pockets
    need = an.max_descent(norm)
    ok = [t for t in fits if back_reach(t) >= need - REACH_TOL]
    if not ok:
        p = max(pockets, key=lambda p: p.max_descent)
        q = an.Pocket([an.mirror_x(s) for s in p.segments], -p.level, (-p.entry[0], p.entry[1]),
                      None if p.exit is None else (-p.exit[0], p.exit[1]), p.max_descent,
                      -p.bottom)
        raise PlanError(f"part {name}: {_pocket_text(q, bore=True)}: no boring bar in the library "
                        f"reaches it; it needs a boring bar whose trailing edge clears "
                        f"{need + 2:.0f} deg"
                        + (" or a second setup with the part turned around: generate "
                           "--setups 2 -o DIR/ --grip2 MM" if p.exit is None else ""))
    rough_t = ok[0]
    fin = [t for t in ok if "finish" in t.uses]
    fin_t = rough_t if "finish" in rough_t.uses else (fin[0] if fin else rough_t)
    x_a = max(0.0, rb - opts.clearance)
    s0 = chain[0]
    run_in = min(face, 2 * fin_t.nose_radius + 0.1)
    if isinstance(s0, Arc) and s0.tangent_at_start()[0] < -0.99 and \
            run_in > fin_t.nose_radius + 0.05:
        # a round from the face into the bore: the finisher comes down onto the face and
        # rolls along it into the round (straight down onto the round's start, the nose's
        # offset meets the round's past where it leaves the face: a sliver left there)
        x0, z0 = s0.start
        chain = [Line((x0 + run_in, z0), (x0, z0))] + list(chain)
    base = ct.with_leads(chain, z_a, x_a, overrun=OVERRUN)
    if opts.comp == "cam":
        prog = ct.tip_path(base, fin_t.nose_radius, fin_t.tip, bore=True)
        delta = rough_t.nose_radius - fin_t.nose_radius
        comp = "none"
    else:
        ct.tip_path(base, fin_t.nose_radius, fin_t.tip, bore=True)  # as the control's G41 alarms
        prog = base
        delta = rough_t.nose_radius
        comp = "left"
    base_dir = (opts.allowance_x, opts.allowance_z) if monotonic else (1.0, 0.0)
    ax, az = _allowance(norm, delta, base_dir, opts, what=f"part {name} bore")
    ns, nf = "id_ns", "id_nf"
    blocks = ct.to_blocks(prog, "x", fin_t.feed_finish, ns, nf, start=(x_a, z_a))
    start = (x_a, z_a)
    rough_start = (rb, z_a)  # on the stock's hole: the first level one full depth in
    rough = Operation(
        name="bore_rough", kind="rough", tool=rough_t,
        reason=((f"drilled hole diameter {_fmt(entry)}, its flat bottom faced toward the "
                 f"centre to diameter {_fmt(2 * rb)}" if faced
                 else f"drilled hole diameter {_fmt(2 * rb)}" if drilled
                 else f"tube stock {stock.spec}") + f": bore roughed with {describe(rough_t)}, "
                + ("G71 type I with a negative X allowance" if monotonic
                   else "G71 type II with a negative E (bore undercuts)")),
        start=rough_start, speed=rough_t.vc_rough, feed=rough_t.feed_rough, ns=ns, nf=nf,
        rough=RoughCut(strategy="turn", side="id", pockets=not monotonic, depth=rough_t.depth,
                       retract=opts.retract, allowance_x=ax, allowance_z=az),
        notes=notes)
    last = prog[-1].end
    finish = Operation(
        name="bore_finish", kind="finish", tool=fin_t,
        reason=(f"finish the bore with {describe(fin_t)}"
                + (" (tip path of this tool, G40)" if opts.comp == "cam"
                   else f" (G41 from register {fin_t.register})")),
        start=start, speed=fin_t.vc_finish, feed=fin_t.feed_finish, blocks=blocks, ns=ns,
        nf=nf, nose_comp=comp, contour=prog,
        # off a faced bottom straight along +Z: toward the axis is what the bar leaves there
        retract=_retract([(last[0], z_a)] + ([(x_a, z_a)] if abs(last[0] - x_a) > 1e-9 else [])
                         if faced else [(x_a, last[1]), (x_a, z_a)], blocks))
    return [rough, finish] + id_grooves


# ------------------------------------------------------------------------------------------
# threads
# ------------------------------------------------------------------------------------------

def _pitch_text(t: Tool) -> str:
    r = thread_pitch_range(t)
    if r is None:
        return "pitch unknown from its code"
    return f"pitch {_fmt(r[0])}" if r[0] == r[1] else f"pitch {_fmt(r[0])}-{_fmt(r[1])}"


def _run_out_length(th: Thread) -> float:
    """How far past the part's left end a through inside thread's hole runs on at the minor
    diameter: one lead at full depth past the end, one lead for the cycle's run-out (R/E),
    and the insert's leading flank's clearance (0.2 mm at the crest, as far as the simulator
    draws the flank, 6 mm) off the drilled hole's shoulder after it; rounded up to 0.1 mm."""
    half = math.radians(th.angle / 2)
    gap = 0.2 + (6.0 * math.cos(half) + th.depth) * math.tan(half)
    return math.ceil((2 * th.lead + gap) * 10 - 1e-6) / 10


def _thread_run_out_past(chain: list[Segment], threads: Sequence[Thread], stock: Stock,
                         z_min: float) -> tuple[list[Segment], float]:
    """A through bore of a part from bar or tube whose inside thread reaches the part's left
    end: the material past that end is not the part's (parted off or cut off), so the hole
    runs on past it at the thread's minor diameter by :func:`_run_out_length`, and the
    thread's full depth reaches the left face. Returns the extended chain and how far it runs past (the
    chain as it is and 0 where no thread needs it)."""
    end = chain[-1].end
    if end[0] <= 1e-6 or abs(end[1] - z_min) > 1e-6 or stock.z_left >= z_min - 1e-6:
        return chain, 0.0
    past = 0.0
    for th in threads:
        if th.internal and not th.taper and min(th.z_start, th.z_end) <= z_min + 1e-6 \
                and abs(end[0] - (th.diameter / 2 - th.depth)) <= 0.02:
            past = max(past, _run_out_length(th))
    if past <= 0:
        return chain, 0.0
    return list(chain) + [Line(end, (end[0], z_min - past))], past


def _grip(machine: Machine) -> float:
    return float(getattr(machine, "grip", 0.0) or 0.0)


def _run_on_short(hole_ops: Sequence[Operation], stock: Stock, machine: Machine,
                  z_run: float) -> float:
    """How much more stock a hole run on to ``z_run`` needs (0: it fits): the run-on within
    the stock, and, held in the chuck, the drills' points :data:`CHUCK_CLEARANCE` clear of
    the jaws' front face."""
    more = stock.z_left - z_run
    grip = _grip(machine)
    if grip > 0:
        z_jaw = stock.z_left + grip
        tips = [op.drill.z_end for op in hole_ops if op.drill is not None]
        more = max([more, z_jaw + CHUCK_CLEARANCE - z_run]
                   + [z_jaw + CHUCK_CLEARANCE - z for z in tips])
    return max(0.0, math.ceil(more * 1000 - 1e-6) / 1000)


def _run_on_warning(what: str, past: float, z_min: float, stock: Stock, machine: Machine,
                    more: float) -> str:
    """The warning of an inside thread kept short of the left end: the ``what`` (hole, bore)
    would run on ``past`` mm past ``z_min`` and the stock needs ``more`` mm for that."""
    return (f"the inside thread cannot run out past the part's left end: the {what} would run "
            f"on {_fmt(past)} mm past Z{_fmt(z_min)}, the stock {stock.spec} needs {_fmt(more)} "
            f"mm more for that" + (" clear of the chuck's jaws" if _grip(machine) > 0 else "")
            + "; the thread's full depth stops short of the left end")


def _flank_hits(chain: Sequence[Segment], internal: bool, z_tip: float, r_tip: float,
                half: float, z_thread_end: float, crest: Any) -> tuple[float, float] | None:
    """Where the part stands inside a threading insert's flank toward -Z (6 mm long, as the
    simulator draws it), the insert's tip at ``(r_tip, z_tip)``, and beyond the thread's
    crest ``crest(z)`` (a wall; what the flank takes below the crest is the thread's own
    run-out): the first such (z, radius) from the tip on, or None. The scan starts past the
    thread's own end ``z_thread_end``."""
    span = 6.0 * math.sin(half)
    sgn = -1.0 if internal else 1.0
    lo, hi = z_tip - span, min(z_tip, z_thread_end) - 1e-4
    if hi <= lo:
        return None
    n = max(2, int((hi - lo) / 0.01) + 1)
    zs = {hi - (hi - lo) * i / n for i in range(n + 1)}
    zs |= {p[1] for s in chain for p in (s.start, s.end) if lo <= p[1] <= hi}
    zs |= {p[1] - 1e-4 for s in chain for p in (s.start, s.end) if lo <= p[1] - 1e-4 <= hi}
    for z in sorted(zs, reverse=True):
        r = an.radius_at(chain, z, internal)
        if r is None:
            continue
        flank = r_tip + sgn * (z_tip - z) / math.tan(half)
        if sgn * (r - flank) > 0.005 and sgn * (r - crest(z)) > 0.005:
            return z, r
    return None


def _plan_thread(th: Thread, od: list[Segment], bore: list[Segment] | None, stock: Stock,
                 lib: ToolLibrary, machine: Machine, opts: Options, r_stock: float,
                 params: dict[str, Any] | None = None, past: float = 0.0,
                 z_part: float | None = None) -> Operation:
    label = (f"{'internal' if th.internal else 'external'} thread M{_fmt(th.diameter)}x"
             f"{_fmt(th.pitch)}" + (f" {th.starts}-start" if th.starts > 1 else "")
             + f" from Z{_fmt(th.z_start)} to Z{_fmt(th.z_end)}")
    cands = thread_tools(lib, th.internal)
    if not cands:
        raise PlanError(f"{label}: no {'internal' if th.internal else 'external'} threading tool "
                        f"in the library (needs e.g. "
                        f"{'11IR' if th.internal else '16ER'}{_fmt(th.pitch)}ISO)")
    fits = [t for t in cands if cuts_pitch(t, th.pitch) and abs(t.insert.angle - th.angle) < 1e-6]
    if not fits:
        have = ", ".join(f"T{t.number:02d} {t.insert.code} ({_pitch_text(t)}, "
                         f"{t.insert.angle:g} deg)" for t in cands)
        ei = "IR" if th.internal else "ER"
        full = f"16{ei}{_fmt(th.pitch)}ISO" if th.angle == 60 else f"16{ei}{_fmt(th.pitch)}"
        part = [k for k, (lo, hi) in PARTIAL_PROFILE_PITCH.items() if lo <= th.pitch <= hi]
        alt = f" or a partial profile 16{ei}{part[0]}{th.angle:g}" if part else ""
        raise PlanError(f"{label}: no threading insert in the library cuts pitch "
                        f"{_fmt(th.pitch)} mm at {th.angle:g} deg (have {have}); it needs a "
                        f"threading insert for pitch {_fmt(th.pitch)}, e.g. {full}{alt}")
    t = fits[0]
    chain = bore if th.internal else od
    if chain is None:
        raise PlanError(f"{label}: the part has no bore for an internal thread")
    if th.internal and th.taper:
        raise PlanError(f"{label}: an internal taper thread is not supported (only external "
                        f"taper threads)")
    sgn = -1.0 if th.internal else 1.0
    r_major = th.diameter / 2

    def dr(z: float) -> float:
        """The taper: the thread's radii at ``z`` less those at its largest diameter."""
        return (th.major_at(z) - th.diameter) / 2

    depth = th.depth
    r_root = r_major - depth if not th.internal else r_major
    r_crest = r_major if not th.internal else r_major - depth  # the surface the thread is cut in
    z_lo = min(th.z_start, th.z_end)
    z_hi = max(th.z_start, th.z_end)
    # the thread zone must not lie under a larger diameter (smaller for internal)
    n = 40
    for i in range(n + 1):
        # inside the ends by 0.1 um: a shoulder wall at the thread's end is not above it
        z = min(max(z_hi - (z_hi - z_lo) * i / n, z_lo + 1e-4), z_hi - 1e-4)
        r = an.radius_at(chain, z, th.internal)
        if r is not None and sgn * (r - r_crest - dr(z)) > 0.01:
            raise PlanError(f"{label}: the part is at diameter {_fmt(2 * r)} at Z{_fmt(z)}, "
                            f"beyond the thread's diameter {_fmt(2 * (r_crest + dr(z)))}")
    # full form: the thread needs at least two leads where the part stands at the crest
    # diameter (a chamfer at its start is below it); shorter, no turn reaches full depth
    lead = th.lead
    m = max(200, int((z_hi - z_lo) / 0.01))
    full = 0.0
    for i in range(m):
        z = z_hi - (z_hi - z_lo) * (i + 0.5) / m
        r = an.radius_at(chain, z, th.internal)
        if r is not None and sgn * (r - r_crest - dr(z)) >= -0.02:
            full += (z_hi - z_lo) / m
    if full < 2 * lead - 1e-6:
        length = z_hi - z_lo
        need = length - full + 2 * lead
        named = [k for k, v in sorted((params or {}).items())
                 if isinstance(v, (int, float)) and abs(float(v) - length) < 1e-6]
        raise PlanError(f"{label} is too short to reach full depth: {_fmt(full)} mm of it is at "
                        f"the {'minor' if th.internal else 'major'} diameter, a thread needs two "
                        f"leads ({_fmt(2 * lead)} mm) there; the thread must be at least "
                        f"{_fmt(math.ceil(need * 10 - 1e-6) / 10)} mm long"
                        + (f" ({named[0]}={_fmt(length)})" if len(named) == 1 else ""))
    # relief after the thread end: the thread runs on past its end by one lead where the
    # relief leaves room (so that the last turn is whole), else as far as it does
    need = 0.5 * lead + 0.2
    step = min(0.05, lead / 20)
    z_stop = stock.z_left if stock.kind != "offset" else z_lo - 10 * lead
    part_left = min(s.bbox()[1] for s in chain)

    def wall_after(z_end: float, span: float = need) -> float | None:
        z = z_end
        while z > z_end - span - step:
            z -= step
            if z < part_left - 1e-9:
                # beyond the part: the remaining stock (bar) is a wall at the part's left end
                if stock.kind != "offset" and z > z_stop:
                    return part_left
                return None
            r = an.radius_at(chain, z, th.internal)
            # the insert's leading flank rises from the root at the thread end at the
            # profile's half angle; within half a pitch of the end the flank may cut the
            # run-out (the thread's own run-out zone); the part must stay below the flank
            # and the crest
            beyond = z_end - z
            limit = r_crest + dr(z) + 0.005
            if beyond > 0.5 * th.pitch:
                limit = min(limit, r_root + dr(z_end)
                            + beyond / math.tan(math.radians(th.angle / 2)))
            if r is not None and sgn * (r - (limit if not th.internal else r_root)) > 0.005 \
                    if not th.internal else (r is not None and r - r_root < -0.005):
                return z
        return None

    z_end = z_lo
    # an inside thread run out past the part's left end, in the hole's run-on at the minor
    # diameter: the shoulder is where the run-on ends (the drilled hole beyond is narrower)
    run_past = th.internal and past > 0 and z_part is not None and z_lo <= z_part + 1e-6
    z_wall = part_left if run_past else wall_after(z_lo)
    # past the end, the insert's flanks (6 mm long, as the simulator draws them) must clear
    # everything the thread ends in front of
    reach = need + 6.0 * math.sin(math.radians(th.angle / 2))
    ran_on = False
    for frac in (1.0, 0.75, 0.5, 0.25) if not run_past else ():
        ze = z_lo - frac * lead
        if ze < part_left + 1e-9 and stock.kind == "offset":
            continue
        if wall_after(ze, reach) is None:
            z_end, z_wall, ran_on = ze, None, True
            break
    if not ran_on and z_wall is None:
        # no run-on clears the flanks: a shoulder a little beyond the end (a short plain
        # length before it) is in the flanks' way as a wall at the end would be
        z_wall = wall_after(z_lo, reach)
    run_r = run_e = 0.0
    half = math.radians(th.angle / 2)
    at_wall = an.radius_at(chain, z_wall + 0.05, th.internal) if z_wall is not None else None
    if z_wall is not None and (z_end - z_wall < need - 1e-9 or not ran_on) \
            and at_wall is not None and sgn * (at_wall - r_crest - dr(z_wall)) >= -0.02:
        # no relief (a shoulder outside, a shoulder or the bore going on at the minor
        # diameter inside): the cycle's run-out (R toward the wall, E out to the crest, G76
        # and G82) pulls the insert out over one lead; it ends where the leading flank, at
        # the crest, clears the shoulder (as far as the simulator draws the flank, 6 mm) by
        # 0.2 mm
        r_sh = [r for r in (an.radius_at(chain, z_wall - d, th.internal) for d in (0.05, 0.5, 2.0))
                if r is not None]
        rise = max((sgn * (r - r_crest - dr(z_wall)) for r in r_sh), default=0.0)
        if run_past:
            rise = 6.0 * math.cos(half)  # the drilled hole's shoulder, as high as the flank
        # (G76 shifts each pass's end by its depth along the flank, toward the wall)
        gap = 0.2 + (min(max(rise, 0.0), 6.0 * math.cos(half)) + depth) * math.tan(half)
        z_full = z_wall + gap + lead
        cyc = "G76" if opts.thread_cycle == "g76" else "G82"
        if z_hi - z_full < 2 * lead - 1e-9:
            raise PlanError(f"{label} runs into the shoulder at Z{_fmt(z_wall)} with no relief, and "
                            f"even {cyc}'s run-out does not fit: the run-out needs "
                            f"{_fmt(gap + lead)} mm before the shoulder and two leads "
                            f"({_fmt(2 * lead)} mm) at full depth before that; the thread is "
                            f"{_fmt(z_hi - z_wall)} mm long, it needs at least "
                            f"{_fmt(math.ceil((gap + 3 * lead) * 10 - 1e-6) / 10)} mm "
                            f"(cut a relief groove or shorten it)")
        z_end, z_wall = z_full, None
        run_r, run_e = -lead, sgn * depth
    if z_wall is not None and z_end - z_wall < need - 1e-9:
        raise PlanError(f"{label} is longer than the relief allows: it ends "
                        f"{_fmt(max(0.0, z_lo - z_wall))} mm before the wall at Z{_fmt(z_wall)}, and "
                        f"the threading insert needs {_fmt(need)} mm (half the lead plus 0.2 mm) "
                        f"clear of its flank")
    method = "passes" if opts.thread_cycle == "g82" else "cycle"
    shifted = ""
    if z_wall is not None and not ran_on and not run_r:
        # the thread ends in a relief in front of a wall: the insert's flank toward the wall
        # (6 mm long, as the simulator draws it) must clear it with the tip at the end; a
        # multiple-pass cycle's single-flank infeed ends each pass its depth x tan(half angle)
        # further (HNC-21T G76), which a narrow relief does not leave room for: then single
        # passes with radial infeed, which end at the thread's end
        shift = depth * math.tan(half) if method == "cycle" and opts.thread_end_shift else 0.0

        def crest(z: float) -> float:
            return r_crest + dr(z)

        hit = _flank_hits(chain, th.internal, z_end - shift, r_root + dr(z_end), half, z_lo,
                          crest)
        if hit is not None and method == "cycle" and _flank_hits(
                chain, th.internal, z_end, r_root + dr(z_end), half, z_lo, crest) is None:
            method = "passes"
            shifted = (f"; single passes with radial infeed: the multiple-pass cycle's flank "
                       f"infeed ends its last pass {_fmt(shift)} mm further, where the "
                       f"insert's flank meets the part at Z{_fmt(hit[0])} (diameter "
                       f"{_fmt(2 * hit[1])})")
        elif hit is not None:
            room = z_end - z_wall
            span = 6.0 * math.sin(half)
            raise PlanError(f"{label}: the relief after the thread is {_fmt(room)} mm long, and "
                            f"the threading insert's flank, {_fmt(span)} mm long along Z, meets "
                            f"the part at Z{_fmt(hit[0])} (diameter {_fmt(2 * hit[1])}) with its "
                            f"tip at the thread's end Z{_fmt(z_end)}: the relief must reach "
                            f"further, or the wall after it must stand lower")
    # start point: clear of everything to the right of the thread
    xs = [s.bbox()[2] if not th.internal else s.bbox()[0] for s in chain
          if s.bbox()[3] >= z_hi - 1e-9]
    if th.internal:
        x_a = min([r_crest] + xs) - opts.clearance
        x_a = max(0.0, x_a)
    else:
        x_a = max([r_crest] + xs) + opts.clearance
    # three leads before the thread for the axis to reach the spindle's speed
    # (plus G76's infeed along the flank, which moves the start toward the thread)
    z_a = max(z_hi, 0.0) + max(3.0, 3 * lead) + depth * math.tan(math.radians(th.angle / 2))
    # G97: the insert's speed, the machine's limit and the shop rule for threading on the
    # HNC-21T's encoder-following spindle, n <= 1200 / lead - 80
    rpm = min(t.rpm or 500.0, rpm_limit(t, machine), max(50.0, 1200.0 / lead - 80.0))
    q = round(min(0.5, max(0.1, depth * 0.4)), 3)
    cut = ThreadCut(method="cycle", x_root=r_root + dr(z_end), z_end=z_end, height=depth,
                    lead=lead, angle=th.angle, starts=th.starts,
                    start_angles=[360.0 * i / th.starts for i in range(th.starts)],
                    first_depth=q, min_depth=0.05, finish_allowance=0.05, finish_passes=1,
                    runout_z=run_r, runout_x=run_e, taper=-th.taper / 2)
    if method == "passes":
        npass = max(3, math.ceil((depth / q) ** 2))
        passes = [r_crest + dr(z_end) - sgn * depth * math.sqrt(i / npass)
                  for i in range(1, npass + 1)]
        passes.append(passes[-1])  # spring pass
        cut.method = "passes"
        how = f"{len(passes)} single-pass threading cycles (the last a spring pass)"
    else:
        passes = []
        how = "the multiple-pass threading cycle"
    if th.taper:
        how += f" along a taper of {_fmt(abs(th.taper))} on the diameter per mm"
    return Operation(
        name="thread", kind="thread", tool=t,
        reason=(f"{label}: {how}, depth {_fmt(depth)} mm ("
                f"{'0.5413' if th.internal else '0.6134'} x pitch), with {describe(t)}{shifted}"),
        start=(x_a, z_a), spindle="rpm", speed=rpm, feed=lead, thread=cut, passes=passes)
