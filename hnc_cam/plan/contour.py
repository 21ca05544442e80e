"""The contours a program runs: part chains oriented and trimmed, lead-in and exit lines,
the tool-nose compensated tip path (``--comp cam``, through :mod:`hnc_cam.compensate`),
and their conversion to program blocks.

Choices:

* the outside chain runs from the right face toward the chuck and stops where it first
  reaches the part's left end (the left face is the parting plane, not turned here);
* a contour starts with a lead-in along -Z from the cycle's start Z down to the first profile
  point, and ends with an exit line straight out in X at the last Z up to the start X, so
  that the ns block is a one-axis G00 and the nf block leaves the material;
* before writing, the contour is cleaned by the kernel (:func:`clean`,
  :mod:`hnc_cam.geometry.chain`): collinear lines and co-circular arcs merged, moves shorter
  than the 0.001 mm resolution absorbed; the written path stays within 0.0005 mm (plus
  2 x 1e-7 mm for the merge) of the exact one (before the rounding of the words to 0.001 mm, which adds at most 0.0005 mm in Z
  and 0.00025 mm in X);
* arcs are written with ``R`` when they sweep at most 170 deg (as the manual's examples do),
  otherwise with ``I``/``K`` (radius values, start to centre): near 180 deg the centre an R
  word implies is ill-conditioned once the end points are rounded. An arc ending exactly on
  its X or Z extreme is written as it is: the interpreter's roughing cycles accept the few
  tenths of a micron the rounded arc may pass the extreme by (earlier versions split off a
  0.0001 mm chord there, which left fragments in the program); a segment whose rounded end
  points coincide is dropped, an arc with a chord under 0.01 mm is written as a line (its
  sagitta is then far below the 0.001 mm resolution of the program).
"""
from __future__ import annotations

import math
from typing import Sequence

from ..errors import PlanError
from ..geometry import Arc, Line, Point, Segment, same_point
from ..geometry.chain import absorb_short, merge_segments
from .analysis import mirror_chain
from .model import Block

DEC = 3
#: joints of merged pieces stay this close to the merged line/circle (mm)
MERGE_TOL = 1e-7
#: moves shorter than this are absorbed into their neighbours (the program's resolution, mm);
#: the written path moves by less than half of it (see :func:`hnc_cam.geometry.chain.absorb_short`)
MIN_MOVE = 0.001


def orient(chain: Sequence[Segment], z_right: float) -> list[Segment]:
    """The chain running from the right face toward the chuck."""
    segs = list(chain)
    if not segs:
        return segs
    if abs(segs[0].start[1] - z_right) > abs(segs[-1].end[1] - z_right) + 1e-9:
        segs = [s.reversed() for s in reversed(segs)]
    return segs


def trim_left(chain: Sequence[Segment], z_left: float) -> list[Segment]:
    """Cut the chain where it first reaches the left end ``z_left`` (drops the left face)."""
    out: list[Segment] = []
    for s in chain:
        if s.length < 1e-9:
            continue
        if abs(s.start[1] - z_left) < 1e-6 and out and abs(out[-1].end[1] - z_left) < 1e-6:
            break
        if abs(s.start[1] - z_left) < 1e-6 and abs(s.end[1] - z_left) < 1e-6:
            break  # a segment on the left face
        out.append(s)
        if abs(s.end[1] - z_left) < 1e-6:
            break
    return out


def merge_collinear(segs: Sequence[Segment]) -> list[Segment]:
    """Join consecutive lines that continue each other and co-circular arcs (a bridge and the
    cylinder it continues, an overrun): the compensation would otherwise see a short step.
    The kernel's :func:`hnc_cam.geometry.chain.merge_segments` with the exact tolerance."""
    return merge_segments(segs, MERGE_TOL)


def with_leads(chain: Sequence[Segment], z_start: float, x_exit: float,
               past_centre: float = 0.0, overrun: float = 0.0) -> list[Segment]:
    """Lead-in along Z from ``z_start`` to the first point, exit along X to ``x_exit``.

    A chain that starts on the axis is first extended along X to ``-past_centre`` (the
    finishing tool's nose radius): the tool's tip must pass the centre by its nose radius for
    the nose to reach the axis and leave no pip on the face. ``overrun``: the last segment is
    continued that far (in Z) past the part's left end into the stock that stays in the chuck,
    so that the exit does not leave a sliver on the parting plane."""
    segs = list(chain)
    if past_centre > 0 and abs(segs[0].start[0]) < 1e-9:
        z0 = segs[0].start[1]
        segs.insert(0, Line((-past_centre, z0), segs[0].start))
    if overrun > 0:
        t = segs[-1].tangent_at_end()
        if t[1] < -0.95:  # (nearly) along -Z: continue past the left end into the chuck-side stock
            e = overrun / -t[1]
            end = segs[-1].end
            segs.append(Line(end, (end[0] + e * t[0], end[1] + e * t[1])))
    segs = merge_collinear(segs)
    first, last = segs[0].start, segs[-1].end
    out: list[Segment] = []
    s0 = segs[0]
    if isinstance(s0, Line) and z_start > first[1] + 1e-9 and s0.direction[1] < -0.1 \
            and abs(s0.direction[0]) > 1e-9:
        # a first segment that is a chamfer or taper: lead in along its extension (as the
        # manual's examples do), so that the lead-in makes no corner with it
        d = s0.direction
        k = (z_start - first[1]) / -d[1]
        p = (first[0] - k * d[0], first[1] - k * d[1])
        if p[0] >= 0:
            segs[0] = Line(p, s0.end)
            first = p
    if z_start > first[1] + 1e-9:
        out.append(Line((first[0], z_start), first))
    out.extend(segs)
    if abs(x_exit - last[0]) > 1e-9:
        out.append(Line(last, (x_exit, last[1])))
    return out


def tip_path(contour: Sequence[Segment], radius: float, tip: int, bore: bool) -> list[Segment]:
    """The imaginary-tip path of a tool with nose ``radius`` and ``tip`` code following the
    part contour (OD toward -Z: tool on the right, G42 side; bore: G41 side).

    The offset itself is :func:`hnc_cam.compensate.compensate` (one implementation, shared
    with the interpreter's G41/G42); a feature the nose cannot reach is refused here.
    """
    if radius <= 0:
        return list(contour)
    try:
        from ..compensate import compensate
    except ImportError:
        raise PlanError("--comp cam needs hnc_cam.compensate, which is not available in this "
                        "installation; use --comp control") from None
    side = "left" if bore else "right"
    res = compensate(list(contour), radius, tip, side)
    bad = [d for d in res.unreachable if d.kind != "end"]
    if bad:
        raise PlanError(f"the finishing tool's nose (radius {radius:g}) cannot follow the "
                        "part: " + "; ".join(d.message for d in bad)
                        + " (a tool with a smaller nose radius would, or a wider feature)")
    return list(res.segments)


def allowance_path(contour: Sequence[Segment], radius: float, tip: int, allowance: float,
                   bore: bool = False) -> list[Segment]:
    """The imaginary-tip path of a tool with nose ``radius`` that leaves ``allowance`` mm
    normal to the part everywhere: the nose centre rolls at ``radius + allowance`` from the
    contour (the kernel's exact offset), the controlled point is ``radius`` from the centre in
    the tip direction. Where the larger rolling radius cannot follow (an inside arc or
    corner tighter than it), the path stays further out: the finishing tool finds more stock
    there, never less."""
    from ..compensate import compensate
    from ..geometry.tip import tip_vector
    res = compensate(list(contour), radius + allowance, tip, "left" if bore else "right")
    path = list(res.segments)
    vx, vz = tip_vector(tip, allowance)
    if bore:
        vx = -vx
    return [s.translated(-vx, -vz) for s in path]


def drop_face(chain: Sequence[Segment], z_face: float = 0.0, keep: float = 2.5) -> list[Segment]:
    """The chain without its leading segments on the face plane ``z_face`` (already faced)
    but the last ``keep`` mm of them: a roughing or finishing contour then starts near the
    face's edge, where stock is, and still enters the edge along the face."""
    segs = list(chain)
    k = 0
    while k < len(segs) - 1 and abs(segs[k].start[1] - z_face) < 1e-6 \
            and abs(segs[k].end[1] - z_face) < 1e-6:
        k += 1
    if k == 0:
        return segs
    edge = segs[k - 1].end
    x0 = max(segs[0].start[0], edge[0] - keep)
    if edge[0] - x0 < 1e-6:
        return segs[k:]
    return [Line((x0, z_face), edge)] + segs[k:]


def _r(v: float) -> float:
    return round(v, DEC)


def _key(p: Point) -> tuple[float, float]:
    return (round(2 * p[0], DEC), round(p[1], DEC))


def _from_start_side(segs: list[Segment], start: Point, first_axis: str) -> list[Segment]:
    """Make the contour begin exactly where the one-axis ns block from ``start`` lands: on the
    line Z = start z (ns along X) or X = start x (ns along Z). The first segment (a line) is
    extended or cut along its own carrier; a compensated lead-in starts a nose radius off."""
    s0 = segs[0]
    k = 1 if first_axis == "x" else 0
    target = start[k]
    if isinstance(s0, Line):
        d = s0.direction
        if abs(d[k]) > 0.05:
            t = (target - s0.end[k]) / d[k]
            if t < -1e-9:
                p = (s0.end[0] + t * d[0], s0.end[1] + t * d[1])
                return [Line(p, s0.end)] + segs[1:]
    p = s0.start
    q = (p[0], target) if first_axis == "x" else (target, p[1])
    if math.dist(p, q) < 1e-9:
        return segs
    return [Line(q, p)] + segs


def clean(contour: Sequence[Segment]) -> list[Segment]:
    """The contour as it is written: collinear lines and co-circular arcs merged (joints
    within :data:`MERGE_TOL`), then moves shorter than :data:`MIN_MOVE` absorbed (the path
    moves by less than ``MIN_MOVE / 2`` = 0.0005 mm), then merged again (an absorbed piece can
    leave two lines that continue each other)."""
    segs = merge_segments([s for s in contour if s.length > 0.0], MERGE_TOL)
    segs = absorb_short(segs, MIN_MOVE)
    return merge_segments(segs, MERGE_TOL)


def to_blocks(contour: Sequence[Segment], first_axis: str, feed: float,
              ns: str, nf: str, start: Point | None = None) -> list[Block]:
    """Program blocks for a contour: the first block is a rapid along ``first_axis`` ("x" or
    "z") to the contour's first point, the rest lines and arcs with end points; labels ``ns``
    on the first and ``nf`` on the last block."""
    segs = clean(contour)
    if not segs:
        raise PlanError("empty contour")
    if start is not None:
        segs = _from_start_side(segs, start, first_axis)
    p0 = segs[0].start
    blocks = [Block("rapid", x=p0[0] if first_axis == "x" else None,
                    z=p0[1] if first_axis == "z" else None, label=ns)]
    cur = _key(p0)
    fed = False
    for s in segs:
        k = _key(s.end)
        if k == cur:
            continue
        if isinstance(s, Arc) and math.dist(s.start, s.end) >= 0.01:
            sweep = abs(math.degrees(s.sweep))
            g = "cw" if s.cw else "ccw"
            if sweep <= 170.0:
                b = Block(g, x=s.end[0], z=s.end[1], r=s.radius)
            else:
                b = Block(g, x=s.end[0], z=s.end[1], i=s.center[0] - s.start[0],
                          k=s.center[1] - s.start[1])
            bb = s.bbox()
            b.span = (bb[0], bb[2])
        else:
            b = Block("line", x=s.end[0], z=s.end[1])
        if not fed:
            b.feed = feed
            fed = True
        blocks.append(b)
        cur = k
    if len(blocks) < 2:
        raise PlanError("contour too short to write")
    if nf:
        blocks[-1].label = nf
    return blocks


def mirror_if(chain: Sequence[Segment], bore: bool) -> list[Segment]:
    return mirror_chain(chain) if bore else list(chain)


def join_ok(chain: Sequence[Segment]) -> bool:
    return all(same_point(a.end, b.start, 1e-5) for a, b in zip(chain, chain[1:]))


def _written(v: float, dia: bool = False) -> float:
    """A word's value as the program writes it (X on the diameter)."""
    return round(2 * v, DEC) / 2 if dia else round(v, DEC)


def block_path(blocks: Sequence[Block], start: Point) -> list[tuple[Segment, str]]:
    """The programmed path of ``blocks`` from ``start`` as the control reads the program: each
    block's ``before`` blocks, then the block, with their words as written (X to 0.001 mm on
    the diameter, Z and R to 0.001 mm); ``(segment, kind)`` per move, kind ``rapid`` or
    ``feed``; a move of no length is a line of no length where the tool is."""
    x, z = _written(start[0], True), _written(start[1])
    out: list[tuple[Segment, str]] = []
    for blk in blocks:
        for b in list(blk.before) + [blk]:
            nx = _written(b.x, True) if b.x is not None else x
            nz = _written(b.z, False) if b.z is not None else z
            p, q = (x, z), (nx, nz)
            if b.arc and math.dist(p, q) > 1e-9:
                if b.r is not None:
                    seg: Segment = Arc.from_radius(p, q, _written(b.r), b.kind == "cw")
                else:
                    c = (x + _written(b.i or 0.0), z + _written(b.k or 0.0))
                    seg = Arc(p, q, c, b.kind == "cw")
            else:
                seg = Line(p, q)
            out.append((seg, "rapid" if b.kind == "rapid" else "feed"))
            x, z = nx, nz
    return out


def control_alarm(blocks: Sequence[Block], start: Point, radius: float, tip: int,
                  side: str) -> str | None:
    """What the control's tool-nose radius compensation (G41 ``side`` left, G42 right) says
    of the contour ``blocks`` run from ``start``: the alarm text, or None when it follows
    them. The interpreter's own :func:`hnc_cam.nc.compensation.compensate_moves` on the
    blocks as written (with the blocks of no length a roughing cycle in two puts in), so
    that what the planner accepts is what the control runs."""
    if radius <= 0:
        return None
    from ..errors import NCError
    from ..nc.compensation import CompItem, compensate_moves
    try:
        items = [CompItem(seg, kind, i + 1, "normal", None)
                 for i, (seg, kind) in enumerate(block_path(blocks, start))]
        compensate_moves(items, radius, tip, 41 if side == "left" else 42)
    except (NCError, ValueError) as e:
        return str(getattr(e, "message", None) or e)
    return None
