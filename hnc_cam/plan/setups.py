"""Two setups: a part whose left end needs more than the part-off can make.

A feature facing the chuck that no tool reaches from the right (a bore chamfer or a counterbore
widening toward the left end, an outside profile stepping down toward the left end behind a
wall no turning tool's trailing edge clears) makes the part a two-setup part:

* :func:`second_setup_zone` finds the left-end zone ``[z_min, z_s]`` (program coordinates,
  right face at Z0) that holds those features; ``z_s`` is the rightmost place one starts;
* setup 1 is planned as usual on the part with that zone *bridged* (:func:`setup1_profile`):
  the outside continues at the zone's largest radius, the bore at its smallest, to the part's
  left end plus :data:`SETUP2_FACE` of face stock for setup 2; it is parted off there (or, on
  the bar, the material up to there is what setup 2 gets);
* setup 1's program is simulated; the part it leaves (the parted-off piece, else the material
  to the setup-1 part's left end) is mirrored about the part's length (:func:`mirror_region`:
  the new Z0 is the old left end's face after facing, Z' = -L - Z) and is setup 2's stock;
* setup 2 grips the part on a finished diameter of the setup-1 region
  (:func:`grip_diameter`: the largest one the chuck's soft jaws can hold, from the part's new
  left end, whose cylinder is at least the grip long) and is planned by the same planner on
  the mirrored part restricted to the zone (:func:`setup2_profile`), with a stock derived
  from that region (its diameter and bore in the zone, its face stock): it faces to length
  and turns the zone's outside and bore;
* the program of setup 2 is simulated from the mirrored region, with the jaws on the grip
  diameter, and the result is verified against the whole mirrored part.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

from ..errors import PlanError
from ..geometry import Arc, Line, Segment, Thread, TurnedProfile
from ..geometry.intersect import vertical_hits
from ..tooling import Machine, Stock, ToolLibrary
from . import analysis as an
from . import contour as ct
from .tools import back_reach, turning_tools

#: face stock (mm) setup 1 leaves on the left end for setup 2 to face to length
SETUP2_FACE = 0.5


def _fmt(v: float) -> str:
    return f"{v:.3f}".rstrip("0").rstrip(".")


@dataclass
class Zone:
    """The left-end zone setup 2 makes: from the part's left end ``z_min`` to ``z`` (program
    coordinates of setup 1), and what is in it that setup 1 cannot make."""
    z: float
    z_min: float
    features: list[str] = field(default_factory=list)


def _tail(chain: list[Segment]) -> int:
    """Index where the chain's last run of segments descending in X starts (len when none)."""
    k = len(chain)
    while k > 1 and chain[k - 1].end[0] < chain[k - 1].start[0] - 1e-9:
        k -= 1
    return k


def second_setup_zone(prof: TurnedProfile, lib: ToolLibrary) -> Zone | None:
    """The zone of ``prof`` (right face at Z0) that only a second setup makes, or None.

    Outside: an undercut open to the left end (the part steps down toward the chuck and does
    not rise again) whose wall no finishing tool's trailing edge clears; a chamfer or round
    descending to the left end alone is the part-off's (or an end profile's), not a zone.
    Bore: a run widening toward the left end (a chamfer facing the chuck) or an undercut open
    to the left end that no boring bar reaches from the right."""
    z_min = prof.z_min
    feats: list[tuple[float, str]] = []
    od = an.split_x_extremes(ct.trim_left(ct.orient(prof.outside, 0.0), z_min))
    fin = [t for t in turning_tools(lib, "finish")]
    rest = od[:_tail(od)]
    for it in an.pocket_items(rest):
        if isinstance(it, an.Pocket) and it.exit is None and \
                not any(back_reach(t) >= it.max_descent - 1e-9 for t in fin):
            feats.append((it.entry[1], f"the outside from Z{_fmt(it.entry[1])} to the left end "
                          f"(down to diameter {_fmt(2 * it.bottom)}, a wall facing the chuck "
                          f"at {it.max_descent:.0f} deg)"))
    if prof.bore:
        bore = ct.trim_left(ct.orient(prof.bore, 0.0), z_min)
        norm = an.split_x_extremes(an.mirror_chain(bore))
        bars = [t for t in lib.tools if t.kind == "bore"]
        k = _tail(norm)
        reaches_left = abs(norm[-1].end[1] - z_min) < 1e-6
        if k < len(norm) and reaches_left:
            tail = norm[k:]
            md = an.max_descent(tail)
            if not any(back_reach(t) >= md - 1e-9 for t in bars):
                z0 = tail[0].start[1]
                feats.append((z0, f"the bore's chamfer facing the chuck from Z{_fmt(z0)} to "
                              f"Z{_fmt(tail[-1].end[1])} (diameter {_fmt(-2 * tail[0].start[0])} "
                              f"to {_fmt(-2 * tail[-1].end[0])})"))
        for it in an.pocket_items(norm[:k]):
            if isinstance(it, an.Pocket) and it.exit is None and reaches_left and \
                    not any(back_reach(t) >= it.max_descent - 1e-9 for t in bars):
                feats.append((it.entry[1], f"the bore from Z{_fmt(it.entry[1])} to the left "
                              f"end (widening to diameter {_fmt(-2 * it.bottom)}, a wall "
                              f"facing the chuck)"))
    if not feats:
        return None
    z = max(f[0] for f in feats)
    # on into the cylinders the zone starts on, so that the finishing contours of setup 2
    # run on along finished surface past their last feature (a nose finishing a chamfer's
    # end needs the cylinder after it)
    chains = [od] + ([an.mirror_chain(ct.trim_left(ct.orient(prof.bore, 0.0), z_min))]
                     if prof.bore else [])
    run = ZONE_RUN + max((t.nose_radius for t in lib.tools if t.kind in ("turn", "bore")),
                         default=0.0)
    z += min(_run_right(c, z, run) for c in chains)
    return Zone(z=z, z_min=z_min, features=[f[1] for f in sorted(feats, key=lambda f: -f[0])])


#: how far (mm) the second setup's zone runs on into a cylinder past its last feature,
#: beyond the largest nose radius of the library's turning tools and boring bars
ZONE_RUN = 0.5


def _run_right(chain: Sequence[Segment], z: float, run: float) -> float:
    """How far the chain (running toward -Z) stays at one radius right of ``z``, at most
    ``run``: the length the zone may run on along that cylinder."""
    for s in chain:
        z_lo, z_hi = min(s.start[1], s.end[1]), max(s.start[1], s.end[1])
        if z_lo - 1e-9 <= z < z_hi - 1e-9:
            if isinstance(s, Line) and abs(s.start[0] - s.end[0]) < 1e-9:
                return min(run, z_hi - z)
            return 0.0
    return 0.0


# ------------------------------------------------------------------------------------------
# profiles
# ------------------------------------------------------------------------------------------

def _split_at_z(s: Segment, z: float) -> tuple[Segment, Segment] | None:
    """``s`` cut where it crosses Z = ``z`` (None when it does not cross inside)."""
    hits = [x for _i, x in vertical_hits([s], z)]
    for x in hits:
        p = (x, z)
        if math.dist(p, s.start) > 1e-9 and math.dist(p, s.end) > 1e-9:
            if isinstance(s, Arc):
                return Arc(s.start, p, s.center, s.cw), Arc(p, s.end, s.center, s.cw)
            return Line(s.start, p), Line(p, s.end)
    return None


def _clip(chain: Sequence[Segment], z: float) -> tuple[list[Segment], list[Segment]]:
    """A chain running toward -Z cut at Z = ``z``: (the part right of it, the rest)."""
    right: list[Segment] = []
    left: list[Segment] = []
    for s in chain:
        if left:
            left.append(s)
            continue
        if min(s.start[1], s.end[1]) >= z - 1e-9:
            right.append(s)
            continue
        if s.start[1] <= z + 1e-9:
            left.append(s)
            continue
        parts = _split_at_z(s, z)
        if parts is None:
            left.append(s)
        else:
            right.append(parts[0])
            left.append(parts[1])
    return right, left


def setup1_profile(prof: TurnedProfile, zone: Zone, face: float = SETUP2_FACE) -> TurnedProfile:
    """The part setup 1 makes: ``prof`` (right face at Z0) with the zone bridged, the outside
    at the zone's largest radius and the bore at its smallest, on to the left end plus
    ``face`` mm (the face stock setup 2 takes)."""
    z_end = zone.z_min - face
    od = ct.trim_left(ct.orient(prof.outside, 0.0), zone.z_min)
    right, left = _clip(od, zone.z)
    if not right or not left or zone.z > -1e-6:
        raise PlanError(f"part {prof.name}: the second setup would make the whole part (its "
                        f"zone from Z{_fmt(zone.z)} reaches the right face): nothing is left "
                        f"for the first setup to hold it by")
    x_top = max(s.bbox()[2] for s in left)
    p = right[-1].end
    out = list(right)
    if x_top > p[0] + 1e-9:
        out.append(Line(p, (x_top, p[1])))
    out.append(Line(out[-1].end, (x_top, z_end)))
    bore_out = None
    x_in = 0.0
    if prof.bore:
        bore = ct.trim_left(ct.orient(prof.bore, 0.0), zone.z_min)
        if abs(bore[-1].end[1] - zone.z_min) < 1e-6:  # a through bore: bridged in the zone
            b_right, b_left = _clip(bore, zone.z)
            if not b_right:
                raise PlanError(f"part {prof.name}: the bore widens toward the left end from "
                                f"its right face on: no setup reaches all of it")
            x_in = min(s.bbox()[0] for s in b_left) if b_left else b_right[-1].end[0]
            q = b_right[-1].end
            bore_out = list(b_right)
            if x_in < q[0] - 1e-9:
                bore_out.append(Line(q, (x_in, q[1])))
            bore_out.append(Line(bore_out[-1].end, (x_in, z_end)))
        else:
            bore_out = list(bore)
    out.append(Line(out[-1].end, (x_in, z_end)))
    for th in prof.threads:
        if min(th.z_start, th.z_end) < zone.z - 1e-9:
            raise PlanError(f"part {prof.name}: the thread from Z{_fmt(th.z_start)} to "
                            f"Z{_fmt(th.z_end)} lies in the left end that the second setup "
                            f"makes (from Z{_fmt(zone.z)}): threads there are not supported")
    return TurnedProfile(outside=out, bore=bore_out, threads=list(prof.threads), name=prof.name,
                         params=dict(prof.params), notes=list(prof.notes))


def _mirror_seg(s: Segment, length: float) -> Segment:
    """``s`` mirrored about the part's length (Z' = -length - Z) and reversed, so that a
    chain mirrored segment by segment, in reverse order, runs toward -Z again."""
    def m(p):
        return (p[0], -length - p[1])
    if isinstance(s, Arc):
        return Arc(m(s.end), m(s.start), m(s.center), s.cw)
    return Line(m(s.end), m(s.start))


def mirror_chain_z(chain: Sequence[Segment], length: float) -> list[Segment]:
    return [_mirror_seg(s, length) for s in reversed(list(chain))]


def mirror_profile(prof: TurnedProfile) -> TurnedProfile:
    """The whole part turned around: ``prof`` (right face at Z0, left end at -L) mirrored so
    that its left end is at Z0 and its right face at -L."""
    length = -prof.z_min
    threads = [Thread(-length - t.z_start, -length - t.z_end, t.diameter, t.pitch, t.starts,
                      t.internal, t.standard, t.angle, t.taper) for t in prof.threads]
    return TurnedProfile(outside=mirror_chain_z(prof.outside, length),
                         bore=mirror_chain_z(prof.bore, length) if prof.bore else None,
                         threads=threads, name=prof.name, params=dict(prof.params),
                         notes=list(prof.notes))


def setup2_profile(full2: TurnedProfile, z2: float) -> TurnedProfile:
    """The turned-around part (``full2``, left end at Z0) restricted to the zone setup 2
    makes, Z in [``z2``, 0]: its outside and bore from the new right face to ``z2``, closed
    there by a face."""
    od = ct.orient(full2.outside, 0.0)
    right, _ = _clip(od, z2)
    bore_out = None
    x_in = 0.0
    if full2.bore:
        bore = ct.orient(full2.bore, 0.0)
        if abs(bore[0].start[1]) < 1e-6:  # the bore opens on the zone's face
            b_right, _ = _clip(bore, z2)
            bore_out = b_right
            x_in = b_right[-1].end[0]
    out = list(right) + [Line(right[-1].end, (x_in, right[-1].end[1]))]
    return TurnedProfile(outside=out, bore=bore_out, threads=[], name=full2.name,
                         params=dict(full2.params), notes=list(full2.notes))


# ------------------------------------------------------------------------------------------
# the stock setup 1 leaves, turned around
# ------------------------------------------------------------------------------------------

def setup1_result(machined: Any, model1: TurnedProfile) -> Any:
    """What setup 1 leaves for setup 2, in setup 1's coordinates: the parted-off piece, or
    (the part still on the bar) the material from the setup-1 part's left end on."""
    from shapely.geometry import box
    from ..sim.region import inter, profile_polygon
    from ..sim.verify import separated_part
    part = separated_part(machined, profile_polygon(model1))
    if part is not None:
        return part
    return inter(machined.material, box(model1.z_min, -1.0, 1e9, 1e9))


def mirror_region(region: Any, length: float) -> Any:
    """A region in simulator coordinates (z, x) mirrored about the part's length:
    Z' = -length - Z."""
    from shapely import affinity
    return affinity.translate(affinity.scale(region, xfact=-1.0, yfact=1.0, origin=(0, 0)),
                              xoff=-length)


def _radii_in(region: Any, z0: float, z1: float) -> tuple[float, float]:
    """(smallest inner radius, largest radius) of the material of ``region`` between Z ``z0``
    and ``z1``: the inner radius 0 where the material reaches the axis."""
    from shapely.geometry import box
    from ..sim.region import inter
    g = inter(region, box(z0, -1.0, z1, 1e9))
    if g.is_empty:
        return 0.0, 0.0
    lo = g.bounds[1]
    return (0.0 if lo < 1e-3 else lo), g.bounds[3]


def stock_from_region(region: Any, z2: float) -> Stock:
    """The setup-2 stock the planner plans from: the region's largest radius and its bore
    over the zone ``[z2, 0]`` (a tube where the material stands off the axis there), its face
    stock beyond Z0 and its whole length (the part in the chuck)."""
    z_lo, _x0, z_hi, _x1 = region.bounds
    r_in, r_out = _radii_in(region, z2, max(z_hi, 0.0))
    face = max(0.0, z_hi)
    length = z_hi - z_lo
    d = round(2 * r_out, 3)
    spec = f"{_fmt(d)}" + (f"/{_fmt(round(2 * r_in, 3))}" if r_in > 0 else "") + \
        f"x{_fmt(round(length, 3))}" + (f"+{_fmt(round(face, 3))}" if face > 0 else "")
    return Stock(kind="tube" if r_in > 0 else "bar", diameter=d, bore=round(2 * r_in, 3),
                 length=length, face=face, spec=spec)


@dataclass
class Grip:
    """Setup 2's workholding: the finished diameter the soft jaws hold, the length held on it
    (``length``, the user's) and the jaws' front face from the part's left (chucked) end
    (``offset``, the simulator's grip)."""
    diameter: float
    length: float
    offset: float
    z_front: float  # the jaws' front face in setup 2's coordinates


def grip_diameter(full2: TurnedProfile, zone_z2: float, grip: float, machine: Machine,
                  clearance: float) -> Grip:
    """The diameter setup 2 is gripped on: among the cylinders of the turned-around part
    outside the zone (Z below ``zone_z2``) that nothing between them and the chucked end
    stands above, the largest the chuck clamps; the jaws hold ``grip`` mm of it from its
    chuck-side end. Refused, naming both numbers: a grip longer than every such cylinder, a
    diameter outside the chuck's range, jaws that reach the zone less ``clearance``."""
    od = ct.orient(full2.outside, 0.0)
    z_end = full2.z_min
    cands = []
    for s in od:
        if isinstance(s, Line) and abs(s.start[0] - s.end[0]) < 1e-9 and s.start[0] > 0 \
                and abs(s.start[1] - s.end[1]) > 1e-6:
            z_l, z_r = min(s.start[1], s.end[1]), max(s.start[1], s.end[1])
            z_r = min(z_r, zone_z2)
            if z_r <= z_l + 1e-9:
                continue
            r = s.start[0]
            # nothing between the cylinder's chuck-side end and the chucked end stands above it
            higher = any(q.bbox()[2] > r + 1e-9 for q in od if q.bbox()[1] < z_l - 1e-9)
            if not higher:
                cands.append((r, z_l, z_r))
    if not cands:
        raise PlanError(f"part {full2.name}: no finished cylinder outside the second setup's "
                        f"zone for the soft jaws to hold")
    lo, hi = machine.chuck_clamp
    cands.sort(key=lambda c: -c[0])
    held = [c for c in cands if lo - 1e-9 <= 2 * c[0] <= hi + 1e-9]
    if not held:
        r = cands[0][0]
        raise PlanError(f"second setup: the grip diameter {_fmt(2 * r)} mm is outside the "
                        f"chuck's clamping range {_fmt(lo)}-{_fmt(hi)} mm (machine file [chuck] "
                        f"clamp_min/clamp_max)")
    long_ = [c for c in held if c[2] - c[1] >= grip - 1e-9]
    if not long_:
        r, z_l, z_r = held[0]
        raise PlanError(f"second setup: the grip {_fmt(grip)} mm is longer than the finished "
                        f"diameter {_fmt(2 * r)} mm the jaws hold ({_fmt(z_r - z_l)} mm long "
                        f"outside the second setup's zone): give --grip2 of at most "
                        f"{_fmt(z_r - z_l)}")
    r, z_l, z_r = long_[0]
    offset = z_l - z_end + grip
    if offset > machine.jaw_length + 1e-9:
        raise PlanError(f"second setup: gripping diameter {_fmt(2 * r)} mm over {_fmt(grip)} mm "
                        f"puts the jaws' front face {_fmt(offset)} mm from the part's end, more "
                        f"than the jaws are long ({_fmt(machine.jaw_length)} mm)")
    z_front = z_l + grip
    if z_front + clearance > zone_z2 + 1e-9:
        raise PlanError(f"second setup: the jaws holding diameter {_fmt(2 * r)} mm over "
                        f"{_fmt(grip)} mm reach Z{_fmt(z_front)}, less than {_fmt(clearance)} mm "
                        f"from the zone it machines (from Z{_fmt(zone_z2)}): give --grip2 of at "
                        f"most {_fmt(max(0.0, zone_z2 - clearance - z_l))}")
    return Grip(diameter=2 * r, length=grip, offset=offset, z_front=z_front)


# ------------------------------------------------------------------------------------------
# the two programs
# ------------------------------------------------------------------------------------------

@dataclass
class Setups:
    """The two programs and what links them."""
    first: Any  # api.Program
    second: Any  # api.Program
    zone: Zone
    grip: Grip
    region1: Any  # what setup 1 leaves (setup 1's coordinates)
    stock2: Any  # that region turned around: setup 2's stock
    machined1: Any = None
    machined2: Any = None
    report1: Any = None
    report: Any = None  # setup 2's, against the whole part

    @property
    def programs(self) -> list[Any]:
        return [self.first, self.second]


def generate_setups(part: Any, stock: Any = None, *, params: Any = None, tools: Any = None,
                    machine: Any = None, comp: str = "cam", templates: Any = None,
                    program_number: int | None = None, verify: bool = True, tol: float = 0.01,
                    number_format: str = "plain", block_numbers: str = "every",
                    thread_cycle: str = "g76", face_cycle: str = "g81",
                    file: str = "<generated>", material: str | None = None,
                    allowance: Any = None, dialect: str | None = None,
                    grip: float | None = None, grip2: float | None = None,
                    partoff: bool = True, partoff_dia: float | None = None,
                    drill_style: str = "blocks") -> Setups:
    """Two programs for a part whose left end needs a second setup (see the module doc)."""
    from .. import __version__
    from ..post import cycle_labels, render
    from ..tooling import with_grip
    from . import api
    from .planner import CHUCK_CLEARANCE, Options, make_plan

    prof, default_stock, name, pparams = api._load_part(part, params)
    mat_name = material if material is not None else api._PART_MATERIAL.pop(id(prof), None)
    lib = tools if isinstance(tools, ToolLibrary) else api._load_tools(tools)
    mach = machine if isinstance(machine, Machine) else api._load_machine(machine, lib)
    if grip is not None:
        mach = with_grip(mach, float(grip))
    shift = -prof.z_max
    shifted = TurnedProfile(
        outside=an.translate_chain(prof.outside, shift),
        bore=an.translate_chain(prof.bore, shift) if prof.bore else None,
        threads=[Thread(t.z_start + shift, t.z_end + shift, t.diameter, t.pitch, t.starts,
                        t.internal, t.standard, t.angle, t.taper) for t in prof.threads],
        name=prof.name, params=dict(prof.params), notes=list(prof.notes))
    zone = second_setup_zone(shifted, lib)
    if zone is None:
        raise PlanError(f"part {name}: --setups 2: nothing on the part needs a second setup "
                        f"(every feature is reached from the right); generate it in one setup")
    length = -zone.z_min
    if grip2 is None:
        grip2 = mach.grip if mach.grip > 0 else None
    if grip2 is None:
        raise PlanError("--setups 2: give --grip2 MM, the length of the finished diameter the "
                        "soft jaws hold in the second setup")
    z2 = -length - zone.z
    full2 = mirror_profile(shifted)
    nose = max((t.nose_radius for t in lib.tools), default=0.0)
    g = grip_diameter(full2, z2, float(grip2), mach, CHUCK_CLEARANCE + nose + 0.3)
    prof1 = setup1_profile(shifted, zone)
    if stock is None:
        stock = default_stock
    if stock is None:
        stock = api.default_stock_for(prof)
    # setup 1: the part with its left-end zone bridged, plus setup 2's face stock
    n1 = 1 if program_number is None else int(program_number)
    kw = dict(tools=lib, machine=mach, comp=comp, templates=templates, tol=tol,
              number_format=number_format, block_numbers=block_numbers,
              thread_cycle=thread_cycle, face_cycle=face_cycle, material=mat_name,
              allowance=allowance, dialect=dialect, partoff=partoff, partoff_dia=partoff_dia,
              drill_style=drill_style)
    prof1.name = name
    first = api.generate(prof1, stock, program_number=n1, file=file, verify=False, **kw)
    first.plan.name = name
    first.plan.params = dict(pparams)
    note1 = (f"SETUP 1 OF 2: the left end from Z{_fmt(zone.z)} is made in setup 2 "
             f"({'; '.join(zone.features)}); {_fmt(SETUP2_FACE)} mm left on the left end for "
             f"setup 2 to face")
    first.plan.notes.insert(0, note1)
    dia = first.dialect
    first.text = render(first.plan, dialect=dia, templates=templates,
                        number_format=number_format, block_numbers=block_numbers)
    first.toolpath = api._interpret(first.text, mach, file, dia)
    st1 = first.plan.stock
    try:
        from .. import sim
    except ImportError as e:
        raise PlanError(f"--setups 2 plans the second setup from the first one's simulated "
                        f"result: the simulator is not installed ({e})") from None
    m1 = sim.simulate(first.toolpath, st1, machine=mach, model=first.plan.profile)
    rep1 = sim.verify(m1, first.plan.profile, tol=tol)
    region1 = setup1_result(m1, first.plan.profile)
    region2 = mirror_region(region1, length)
    # setup 2: the zone of the part turned around, from that region, gripped on g
    prof2 = setup2_profile(full2, z2)
    st2 = stock_from_region(region2, z2)
    mach2 = replace(mach, grip=g.offset)
    lib2, ax, az = api.with_material(lib, mat_name, allowance)
    opts = Options(comp=comp, program_number=n1 + 1, thread_cycle=thread_cycle,
                   face_cycle=face_cycle, allowance_x=ax / 2, allowance_z=az, partoff=False,
                   drill_style=drill_style, thread_end_shift=api.thread_end_on_flank(dia))
    plan2 = make_plan(prof2, st2, lib2, mach2, opts, name=name, params=pparams,
                      version=__version__)
    plan2.notes.insert(0, f"SETUP 2 OF 2: the part turned around, held in soft jaws on "
                          f"diameter {_fmt(g.diameter)} over {_fmt(g.length)} mm (jaws "
                          f"{_fmt(g.offset)} mm from its end); Z0 on the left end's face "
                          f"after facing to length {_fmt(length)}; the stock is what setup 1 "
                          f"left")
    if dia == "siemens802":  # its program and subprogram files are named after the part
        plan2.name = f"{name}_2"
    text2 = render(plan2, dialect=dia, templates=templates, number_format=number_format,
                   block_numbers=block_numbers)
    tp2 = api._interpret(text2, mach2, file, dia)
    second = api.Program(text=text2, plan=plan2, toolpath=tp2, dialect=dia,
                         labels=cycle_labels(dia, templates))
    second.warnings.extend(plan2.warnings)
    out = Setups(first=first, second=second, zone=zone, grip=g, region1=region1,
                 stock2=region2, machined1=m1, report1=rep1)
    if verify:
        m2 = sim.simulate(tp2, region2, machine=mach2, model=full2)
        rep = sim.verify(m2, full2, tol=tol)
        out.machined2, out.report = m2, rep
        first.report, second.report = rep1, rep
        bad = [] if rep1.passed else [f"setup 1: {rep1.summary()}"]
        if not rep.passed:
            bad.append(f"setup 2: {rep.summary()}")
        if bad:
            raise api.VerificationError(f"{name}: the generated programs fail verification "
                                        f"(tol {tol:g} mm): " + "; ".join(bad).replace("\n", "; "),
                                        second)
    return out


def verify_setups(tp1: Any, tp2: Any, stock: Any, machine1: Machine, machine2: Machine,
                  model: TurnedProfile, tol: float = 0.01, strict: bool = False,
                  threads: Sequence[Thread] | None = None) -> tuple[Any, Any, Any]:
    """Prove a two-setup part: setup 1 simulated from ``stock``, setup 2 from what setup 1
    left turned around (jaws of ``machine2``), the final material against the whole part
    turned around. Returns (setup 1's machined, setup 2's machined, the report)."""
    from .. import sim
    from ..sim.region import inter
    from shapely.geometry import box
    shift = -model.z_max
    shifted = TurnedProfile(
        outside=an.translate_chain(model.outside, shift),
        bore=an.translate_chain(model.bore, shift) if model.bore else None,
        threads=[Thread(t.z_start + shift, t.z_end + shift, t.diameter, t.pitch, t.starts,
                        t.internal, t.standard, t.angle, t.taper)
                 for t in (threads if threads is not None else model.threads)],
        name=model.name, params=dict(model.params), notes=list(model.notes))
    length = -shifted.z_min
    m1 = sim.simulate(tp1, stock, machine=machine1, model=shifted)
    from ..sim.region import profile_polygon
    from ..sim.verify import separated_part
    part = separated_part(m1, profile_polygon(shifted))
    region1 = part if part is not None else inter(
        m1.material, box(shifted.z_min - SETUP2_FACE, -1.0, 1e9, 1e9))
    region2 = mirror_region(region1, length)
    full2 = mirror_profile(shifted)
    m2 = sim.simulate(tp2, region2, machine=machine2, model=full2)
    rep = sim.verify(m2, full2, tol=tol, threads=full2.threads, strict=strict)
    if m1.issues:
        rep.collisions = list(m1.issues) + list(rep.collisions)
        rep.reasons.insert(0, f"setup 1: {len(m1.issues)} collision(s)/check finding(s)")
        rep.passed = False
    return m1, m2, rep
