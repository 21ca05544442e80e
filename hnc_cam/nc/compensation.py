"""G41/G42/G40 for the interpreter: the programmed moves of one compensated run in, the
controlled-point path out. The offset is the kernel's :func:`hnc_cam.geometry.offset.offset_chain`
(the same routine as the CAM side's :func:`hnc_cam.compensate.compensate`).

Contract (the interpreter calls :func:`compensate_moves`):

* ``items``: the moves of one run, in order and contiguous: optionally first a ``'start'``
  item (the move of the G41/G42 block), then the ``'normal'`` moves, optionally last a
  ``'cancel'`` item (the move of the G40 block). Programmed geometry, X as radius.
* Returns ``[(segment, item), ...]``: the **controlled point** path (nose centre plus
  ``tip_vector(tip, radius)``; for codes 0/9 the centre), contiguous, one or more segments per
  item, in item order.

Choices where the manual is silent (it only says that start and cancel are G00/G01 moves):

* **Start-up is type A**: the start move goes straight from its programmed (uncompensated)
  start point to the first point of the compensated path, i.e. the point at ``r`` normal to the
  start of the first normal move (plus the tip vector). If that point would gouge a
  neighbouring move (the first move is shorter than the trim at a concave corner), it goes to
  the first point of the path that does not.
* **Cancel**: the cancel move goes from the compensated end of the last normal move straight
  to its programmed end point (uncompensated from there on). A G40 block without a move
  leaves the cancel pending: the interpreter makes the next move the cancel move.
* A start immediately followed by a cancel (no normal move) leaves both moves uncompensated.
* **Corner arcs** (convex corners) are executed with, and returned paired with, the move
  that **ends** at the corner (the item the arc leads out of), as a controller does in single
  block mode. A rapid item can therefore receive an arc.
* **Lookahead**: the gouge check and the trimming consider the moves up to
  :data:`LOOKAHEAD` positions before and after each move (a controller's block buffer), and
  every move within :data:`LOOKAHEAD_RADII` nose radii of contour length (so an inside arc
  written as many short chords is still seen whole), so a short move between two corners,
  an inside arc and a narrow groove are handled, while a program that comes back over ground
  it cut earlier is followed as written.
* **Seams** (the interpreter flushes a run in the middle: G04, a T word, M98/M99, a G41<->G42
  switch without G40): the first item of the next run carries ``seam = (previous run's last
  programmed move, the controlled point where that run ended, its line)``; the move is of
  zero length when that run ended on its start-up move. The joint is then handled as a
  corner, the way a controller whose block buffer was interrupted does: the previous run has
  already stopped at the point ``r`` normal to the end of its last move (it could not see the
  next move); the new run is offset together with that last move, so a convex seam gets the
  corner arc about the joint (which starts exactly at the stop point) and a concave seam is
  trimmed at the intersection of the two offsets, reached from the stop point straight back
  along the previous offset. At a concave seam the stop overcuts the next move (inherent to
  the interrupted buffer): the overcut depth is appended to that move's ``notes`` (the
  interpreter turns it into a warning). After a G41<->G42 switch the start move goes
  straight from the stop point to the first point of the new side (type A). The previous
  move's own offset is not returned again, and departures on it are not alarmed again. The
  interpreter treats a cycle (G71 ... G82) as a temporary cancel instead: the run ends with
  a rapid back to the programmed point, the cycle runs uncompensated and compensation starts
  up again (type A) with the first move after it; G28/G29 under compensation alarm (the
  manual: cancel compensation before G28).
* A normal move whose compensated path vanishes entirely (it lies inside the trim of a
  concave corner, or it has zero length) is returned as one zero-length line at the current
  point, so that every item keeps at least one segment.

Alarms (``NCError`` with the item's line): start or cancel on an arc; an inside arc whose
radius is smaller than the nose radius; a concave step or groove the nose cannot enter
(narrower than ``2r``: one or more feed moves the nose cannot touch at all); a feed move
longer than ``r`` at the start or end of the run that the nose cannot touch at all; a run in
which the nose can follow none of the moves. The ordinary fillet the nose leaves in a sharp
concave corner, rapids the nose cannot follow, and a move shorter than ``r`` at the very end
of the run (a short retract after a concave corner) are not alarms.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from ..errors import NCError
from ..geometry.offset import offset_chain, translate_chain
from ..geometry.primitives import Arc, Line, Point, Segment, dist
from ..geometry.tip import tip_vector

#: moves before/after each move that the gouge check looks at
LOOKAHEAD = 3
#: ... widened to every move within this many nose radii of contour length
LOOKAHEAD_RADII = 4.0


@dataclass
class CompItem:
    seg: Segment      # programmed geometry, x radius, from the programmed start to the programmed end
    kind: str         # 'rapid' | 'feed' (line or arc by the segment type)
    line: int         # 1-based source line
    mode: str         # 'start' (the G41/G42 block's move), 'normal', 'cancel' (the G40 block's
    #                   move), or 'lead' (the interpreter's placeholder for a seam, never passed in)
    payload: object   # opaque, handed back
    at: Optional[Point] = None  # 'lead' only: the controlled point where the previous run ended
    #: first item of a run that continues at a seam: (the previous run's last programmed move,
    #: the controlled point where that run ended, its line)
    seam: Optional[tuple] = None
    notes: list = field(default_factory=list)  # warnings about this move, filled in by the offset


def compensate_moves(items: list[CompItem], radius: float, tip: int, side: int
                     ) -> list[tuple[Segment, CompItem]]:
    """Controlled-point path of one compensated run (see the module docstring).

    ``radius``: nose radius (mm); ``tip``: tip direction code 0-9; ``side``: 41 (tool left of
    the path looking along the motion, view Z right / X up) or 42 (right). Warnings (the
    overcut at a concave seam) are appended to the ``notes`` of the item concerned.
    """
    if items and items[0].seam is not None:
        return _continue(items[0].seam, items, radius, tip, side)
    return _compensate(items, radius, tip, side, None)


def _continue(seam: tuple, items: list[CompItem], radius: float, tip: int, side: int
              ) -> list[tuple[Segment, CompItem]]:
    """A run that continues at a seam (see the module docstring)."""
    prev, at, prev_line = seam
    if any(it.mode == "normal" for it in items):
        ctx = prev if items[0].mode != "start" and prev.length > 1e-9 else None
        out = _compensate(items, radius, tip, side, ctx)
    else:  # start and/or cancel only: uncompensated moves
        out = [(it.seg, it) for it in items]
    first_seg, first_it = out[0]
    if first_it.mode in ("start", "cancel"):
        out[0] = (Line(at, first_seg.end), first_it)
    elif dist(at, first_seg.start) > 1e-9:
        out.insert(0, (Line(at, first_seg.start), first_it))
    if radius > 0 and prev.length > 1e-9 and items[0].mode == "normal":
        # the previous run stopped at ``at``: how far its nose reaches into the next moves
        tv = tip_vector(int(tip), radius)
        c = (at[0] - tv[0], at[1] - tv[1])
        near, L = [], 0.0
        for it in items:
            if it.mode != "normal":
                break
            near.append(it)
            L += it.seg.length
            if len(near) > LOOKAHEAD and L > LOOKAHEAD_RADII * radius:
                break
        over, where = 0.0, None
        for it in near:
            if it.kind != "feed" or it.seg.length <= 1e-9:
                continue
            d = radius - it.seg.distance_to(c)
            if d > over:
                over, where = d, it
        if where is not None and over > 1e-6:
            where.notes.append(f"tool-nose radius compensation interrupted at a concave "
                               f"corner (line {prev_line}): the nose stops at the end of "
                               f"that move and overcuts this one by {over:.3f} mm")
    return out


def _compensate(items: list[CompItem], radius: float, tip: int, side: int,
                ctx: Optional[Segment]) -> list[tuple[Segment, CompItem]]:
    """One run; ``ctx``: the previous run's last programmed move, offset with this run as
    context for the joint and then dropped (a seam)."""
    if not items:
        return []
    for it in items:
        if it.mode not in ("start", "normal", "cancel"):
            raise ValueError(f"CompItem.mode must be start/normal/cancel (lead first only), "
                             f"got {it.mode!r}")
        if it.mode in ("start", "cancel") and isinstance(it.seg, Arc):
            what = "start" if it.mode == "start" else "cancel"
            raise NCError(f"tool-nose radius compensation cannot {what} on an arc (G02/G03); "
                          f"use G00 or G01", line=it.line)
    if side not in (41, 42):
        raise ValueError(f"side must be 41 or 42, got {side!r}")
    try:
        tv = tip_vector(int(tip), max(0.0, radius))
    except (ValueError, TypeError):
        raise NCError(f"tip direction code must be 0-9, got {tip!r}", line=items[0].line) from None
    if radius < 0:
        raise NCError(f"nose radius must not be negative, got {radius:g}", line=items[0].line)

    start = items[0] if items[0].mode == "start" else None
    cancel = items[-1] if items[-1].mode == "cancel" and items[-1] is not start else None
    normals = items[(1 if start else 0):(len(items) - 1 if cancel else len(items))]
    for it in normals:
        if it.mode != "normal":
            raise ValueError(f"a {it.mode!r} item may only be the first ('start') or the last "
                             f"('cancel') of a run (line {it.line})")

    if not normals:
        return [(it.seg, it) for it in items]

    k0 = 1 if ctx is not None else 0  # chain index of the first normal move
    chain = ([ctx] if ctx is not None else []) + [it.seg for it in normals]
    try:
        res = offset_chain(chain, radius, 1 if side == 41 else -1, lookahead=LOOKAHEAD,
                           measure=("radius", "groove", "end"),
                           lookahead_length=LOOKAHEAD_RADII * radius)
    except ValueError as e:
        raise NCError(f"tool-nose radius compensation: {e}", line=normals[0].line) from None
    if k0:
        # drop the context move's own offset; the corner arc at the seam goes with the first
        # normal move; indices back to ``normals``
        keep = [(g, o) for g, o in zip(res.segments, res.origins)
                if not (o.kind != "corner" and o.before == 0)]
        res.segments = [g for g, _ in keep]
        res.origins = [type(o)(o.kind, max(0, o.before - 1), o.after - 1) for _, o in keep]
        deps = []
        for d in res.departures:
            segs = tuple(i - 1 for i in d.segments if i > 0)
            if segs:
                deps.append(type(d)(d.kind, segs, d.start, d.end, d.departure, d.at, d.message))
        res.departures = deps
        chain = chain[1:]

    touched = {o.before for o in res.origins if o.kind == "seg"}
    for d in res.departures:
        if d.kind == "radius":
            i = next((i for i in d.segments if isinstance(chain[i], Arc) and i not in touched),
                     d.segments[0])
            raise NCError(f"tool-nose radius compensation: {d.message}", line=normals[i].line)
        if d.kind == "groove" and any(normals[i].kind == "feed" for i in d.segments):
            i = next((i for i in d.segments if i not in touched), d.segments[0])
            raise NCError(f"tool-nose radius compensation: {d.message}", line=normals[i].line)
        if d.kind == "end":
            skipped = [i for i in d.segments if i not in touched and normals[i].kind == "feed"
                       and chain[i].length > radius]
            if skipped:
                raise NCError(f"tool-nose radius compensation: {d.message}",
                              line=normals[skipped[0]].line)

    if not res.segments:
        if res.radius > 0 and any(it.kind == "feed" for it in normals):
            it = next(it for it in normals if it.kind == "feed")
            raise NCError(f"tool-nose radius compensation: the nose (radius {radius:g}) cannot "
                          f"follow any of the moves on this side without gouging", line=it.line)
        return [(it.seg, it) for it in items]

    path = translate_chain(res.segments, tv)
    owner = [o.before for o in res.origins]  # corner arcs go with the move they leave
    out: list[tuple[Segment, CompItem]] = []
    cur = path[0].start
    if start is not None:
        out.append((Line(start.seg.start, cur), start))
    k = 0
    for i, it in enumerate(normals):
        n0 = len(out)
        while k < len(path) and owner[k] == i:
            out.append((path[k], it))
            cur = path[k].end
            k += 1
        if len(out) == n0:
            out.append((Line(cur, cur), it))
    assert k == len(path), "offset pieces out of item order"
    if cancel is not None:
        out.append((Line(cur, cancel.seg.end), cancel))
    return out
