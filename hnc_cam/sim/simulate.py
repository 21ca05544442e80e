"""Material removal: the stock minus the tool swept along every move of a toolpath.

Model (the choices made where the issue leaves room):

* 2-D, in the half-plane X >= 0 with true radius geometry, shapely (GEOS) polygons in ``(z, x)``
  coordinates. A turned part is a solid of revolution, so its cross-section above the axis
  is the whole story.
* The tool is the convex outline of :func:`hnc_cam.sim.tool.tool_shape` for the move's offset
  register (``Move.register`` looked up with ``machine.register(n)``); thread moves use a
  threading profile of ``Move.thread_angle`` (else the insert's angle, else 60 deg). A register
  that names no insert but makes thread moves is taken as that threading tool for all its
  moves (approach and retract too). The move's
  positions are the controlled point (the interpreter's contract).
* A line move (``line``, ``thread`` and each straight piece of a G00 dog-leg ``rapid``) sweeps
  the convex hull of the outline at its start and its end (exact for a translated convex
  polygon). An arc is sampled with chord error <= 0.0005 mm and swept as the union of the hulls
  of consecutive placements, built as one polygon (:func:`_path_sweep`: the outline's
  convolution with the sampled arc, the same region).
* Cost linear in the number of moves: the sweeps are built per run of moves (one vectorised
  call per tool shape), then taken out of the material in batches of consecutive moves
  (at most :data:`BATCH`; a batch starts with every pass, a longer pass is cut into the
  fewest equal batches). What each move removes (exact, and as sequential as one move after another)
  comes from :mod:`hnc_cam.sim.area`: the overlap of the material at the batch's start with
  the move's *front band* (its sweep beyond the placement where it starts, which the move
  before swept) is an upper bound of what the move removes after the moves before it; the
  batch's material is the material minus polygons inside the union of its sweeps (where its
  pieces are one path of one outline that does not cross itself, their hulls' union as one
  polygon, built as an arc's sweep is; else one *envelope* per run of pieces with the same
  extreme vertices of the outline, and the outline where a run starts), one overlay for the
  batch. The bounds add up to at least what the sweeps
  remove, which is at least what the envelopes remove; where they add up to what the envelopes
  remove (to ``1e-10 + 1e-13 * area`` mm^2) all are equal, so every bound is exact and the
  material is the material minus the sweeps. Where they do not (a move coming back through
  what its batch cut), the batch is taken move by move: within a zone (the convex
  hull of its sweeps grown by ``SEAM``) each sweep is taken out of the local material in
  program order, one overlay per move that meets it (a material of at most
  :data:`SMALL_MATERIAL` vertices is taken whole, without a zone). A short pass (:data:`SHORT_PASS` moves
  or fewer, from a feed move after a rapid to the next) is taken that way from the start.
  A move's swept region is built only where an overlay or a check needs it; its bounds come
  from its pieces' ends and the outline's.
* Material that is no longer connected to the chucked end (the minimum-Z end of the stock)
  falls off and counts as removed, checked after every batch.

Checks (each an :class:`Issue` with the program line and block):

Each finding is an :class:`Issue` whose ``kind`` names the check and whose message starts with
the check's name (:data:`CHECKS`), e.g. ``"collision: rapid move cuts material ..."``:

* ``collision``: a rapid that removes material;
* ``spindle``: a feed move that touches material with the spindle stopped; ``thread-spindle``: a
  thread move with the spindle stopped (whatever it touches);
* ``feed``: a move at zero feed that touches material with the spindle turning (with the
  spindle stopped, as under G95, the move is one ``spindle`` finding);
* ``non-cutting``: a feed move that removes material with a side of the tool that is not a
  cutting edge (the back of a rhombic insert, the top of a grooving blade);
* ``tool``: thread moves with an offset register whose insert is not a threading insert (the
  tool library does not match the program's tool numbers), once per register;
* ``collision: chuck jaw``: any move whose tool outline touches the chuck's jaws (modelled
  as a solid when the machine gives a grip, :func:`hnc_cam.sim.region.jaw_region`), once per
  program line.

A move "touches" material when it removes more than ``TOUCH_AREA`` (1e-4 mm^2) of a region at
least ``TOUCH_THICK`` (5e-4 mm, the order of the chord error) thick, so that a tool gliding over a
surface it has just cut is not a collision. A rapid is a collision when what it removes is at
least ``RAPID_DEPTH`` (0.1 mm) thick (twice the radius of the largest circle inside it): a rapid
that only shaves a thinner sliver (typically the 5 deg wedge a 95 deg holder's main edge leaves
against a shoulder, which a G71 retract in +X shaves off) is listed in ``Machined.notes`` and the
summary, not as a collision.
"""
from __future__ import annotations

import gc
import math
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable
from ..units import fmt_cycle_time

import numpy as np
import shapely
import shapely.errors
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry

from ..geometry import Arc
from ..nc.toolpath import MOVE_KINDS, Move, Toolpath, columns
from ..tooling import Machine, Stock, ToolLibrary, load_machine
from .region import (chuck_zone, clean, diff, inter, jaw_region, polygons, stock_region,
                     union as union_of)
from .area import (clip_below, clip_outline, envelope, extremes, front_bands, heights_over,
                   overlap_areas, overlap_areas_of, polygon_edges, region_edges, ring_edge_rows)
from .tool import CHORD, ToolShape, sweep_hulls, tool_shape

FEED_KINDS = ("line", "arc", "thread")
#: a move that removes less than this area (mm^2) removed nothing (air cut)
AIR_AREA = 1e-5
#: thresholds for "touches material" in the checks
TOUCH_AREA = 1e-4
TOUCH_THICK = 5e-4
RAPID_DEPTH = 0.1
#: consecutive moves taken out of the material together
BATCH = 512
#: a batch whose bounds do not add up is halved down to this many moves, which are then
#: taken out move by move within one zone of material
MOVE_BATCH = 48
#: a pass (from a feed move after a rapid to the next such move) of at most this many moves is
#: taken move by move: one overlay per move within the pass's zone costs less than the band
#: accounting of :func:`_batch_by_bands` for so few moves, and the result is the same
SHORT_PASS = 32
#: tool outlines of at most this many vertices are taken out a batch at a time with the
#: exact overlap areas of :mod:`hnc_cam.sim.area`; larger ones one overlay per move
PAIR_VERTS = 400

_lib_difference = shapely.lib.difference
_lib_intersects = shapely.lib.intersects
_lib_relate_pattern = shapely.lib.relate_pattern
_lib_area = shapely.lib.area
_lib_bounds = shapely.lib.bounds


_RAPID, _LINE, _ARC, _THREAD, _DWELL = (MOVE_KINDS.index(k) for k in
                                         ("rapid", "line", "arc", "thread", "dwell"))

#: the checks, by ``Issue.kind``: each finding's message starts with its name and a colon
CHECKS = {"collision": "collision",
          "spindle": "spindle stopped",
          "thread-spindle": "spindle stopped",
          "feed": "zero feed",
          "non-cutting": "non-cutting edge",
          "rapid-sliver": "rapid shaves a sliver",
          "tool": "wrong tool"}


@dataclass
class Issue:
    """A finding of the checks, with the program line (1-based) and the block text.

    ``kind`` names the check (a key of :data:`CHECKS`); the message is prefixed with the
    check's name (``"zero feed: ..."``) unless it already starts with it."""
    line: int
    block: str
    message: str
    kind: str = "collision"
    #: (x radius, z) where the move first touched material (:func:`first_contact`), if known
    at: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        label = CHECKS.get(self.kind, self.kind)
        if not self.message.startswith(label + ":"):
            self.message = f"{label}: {self.message}"

    def to_json(self) -> dict[str, Any]:
        d: dict[str, Any] = {"line": self.line, "block": self.block, "message": self.message}
        if self.at is not None:
            d["at"] = [_r(2 * self.at[0]), _r(self.at[1])]
        return d

    def __str__(self) -> str:
        return f"line {self.line}: {self.message}  [{self.block}]"


@dataclass
class ThreadSpan:
    """Where a program cut threads: Z range and X (radius) range of its thread moves."""
    z_min: float
    z_max: float
    x_min: float
    x_max: float
    inside: bool
    lead: float
    angle: float


@dataclass
class Machined:
    """The result of :func:`simulate`.

    ``material``: what is left on the machine, in (z, x) shapely coordinates; ``stock``: the raw
    material; ``removed_area[i]``: mm^2 the i-th move removed (falling pieces not included);
    ``sweep_bounds[i]``: bounds (z0, x0, z1, x1) of its swept region (NaN for dwells);
    ``issues``: the checks' findings; ``shapes``: the tool outline of each register used.
    """
    material: BaseGeometry
    stock: BaseGeometry
    toolpath: Toolpath
    issues: list[Issue] = field(default_factory=list)
    removed_area: np.ndarray = field(default_factory=lambda: np.zeros(0))
    sweep_bounds: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    shapes: dict[tuple[int, float | None], ToolShape] = field(default_factory=dict)
    thread_spans: list[ThreadSpan] = field(default_factory=list)
    fallen: list[BaseGeometry] = field(default_factory=list)
    machine: Machine | None = None
    notes: list[Issue] = field(default_factory=list)
    #: the chuck's jaws in (z, x) (None: not modelled, the machine gives no grip)
    jaws: BaseGeometry | None = None
    #: per move, read once by :func:`simulate`: ``kind`` (int8, index in MOVE_KINDS),
    #: ``register`` (int32), ``duration`` (s); None: read from the toolpath when needed
    per_move: dict[str, np.ndarray] | None = field(default=None, repr=False, compare=False)
    #: the registers that name no insert but cut threads, with their thread angle
    thread_regs: dict[int, float] = field(default_factory=dict, repr=False, compare=False)

    def move_columns(self, c0: int, c1: int) -> dict[str, np.ndarray]:
        """``kind``, ``register`` and ``duration`` of the moves c0 <= k < c1 (of at most
        :data:`CHUNK` moves when read from the toolpath)."""
        pm = self.per_move
        if pm is not None and len(pm["kind"]) == len(self.toolpath.moves):
            return {k: v[c0:c1] for k, v in pm.items()}
        c = columns(self.toolpath.moves[c0:c1])
        return {"kind": c["kind"], "register": c["register"], "duration": c["duration"]}

    @property
    def collisions(self) -> list[Issue]:
        return self.issues

    @property
    def cycle_time_s(self) -> float:
        """:attr:`Toolpath.cycle_time_s`, read a block of moves at a time."""
        n = len(self.toolpath.moves)
        t = 0.0
        for c0 in range(0, n, CHUNK):
            t = sum(self.move_columns(c0, min(c0 + CHUNK, n))["duration"].tolist(), t)
        return t

    @property
    def removed(self) -> BaseGeometry:
        return diff(self.stock, self.material)

    @property
    def removed_volume_mm3(self) -> float:
        """Volume of the removed material by Pappus: 2 pi * sum(area * centroid radius)."""
        return pappus_volume(self.removed)

    def _feed_times(self) -> tuple[float, float]:
        """(feed time, air-cut time) in seconds, a block of moves at a time."""
        n = len(self.toolpath.moves)
        ft = at = 0.0
        for c0 in range(0, n, CHUNK):
            c = self.move_columns(c0, min(c0 + CHUNK, n))
            k = c["kind"]
            feed = (k == _LINE) | (k == _ARC) | (k == _THREAD)
            d = c["duration"]
            # summed in program order, as a sum over the moves would
            ft = sum(d[feed].tolist(), ft)
            air = feed & (self.removed_area[c0:c0 + len(k)] <= AIR_AREA)
            at = sum(d[air].tolist(), at)
        return ft, at

    @property
    def feed_time_s(self) -> float:
        return self._feed_times()[0]

    @property
    def air_cut_time_s(self) -> float:
        return self._feed_times()[1]

    @property
    def air_cut_fraction(self) -> float:
        """Share of the feed time in which the tool removed nothing."""
        ft, at = self._feed_times()
        return at / ft if ft > 0 else 0.0

    def rings(self) -> list[list[list[float]]]:
        """Boundary rings of the remaining material, points ``[X diameter, Z]``."""
        out = []
        for p in polygons(self.material):
            for ring in [p.exterior, *p.interiors]:
                out.append([[_r(2 * x), _r(z)] for z, x in ring.coords])
        return out

    def to_json(self) -> dict[str, Any]:
        return {"machined": self.rings(),
                "collisions": [i.to_json() for i in self.issues],
                "cycle_time_s": _r(self.cycle_time_s),
                "removed_volume_mm3": _r(self.removed_volume_mm3, 3)}

    def summary(self) -> str:
        t = self.cycle_time_s
        z0, x0, z1, x1 = self.material.bounds if not self.material.is_empty else (0, 0, 0, 0)
        lines = [f"{self.toolpath.file}: {len(self.toolpath.moves)} moves simulated, "
                 f"removed {self.removed_volume_mm3:.1f} mm^3, cycle time "
                 f"{fmt_cycle_time(t)}, air cut {100 * self.air_cut_fraction:.1f} % "
                 f"of feed time",
                 f"remaining material: X {2 * x0:.3f}..{2 * x1:.3f} (dia), Z {z0:.3f}..{z1:.3f}"
                 + (f", {len(self.fallen)} piece(s) fell off" if self.fallen else "")]
        lines += [f"note: {n}" for n in self.notes]
        if self.issues:
            lines.append(f"{len(self.issues)} collision(s)/check finding(s):")
            lines += [f"  {i}" for i in self.issues]
        else:
            lines.append("no collisions")
        return "\n".join(lines)


def _r(v: float, nd: int = 4) -> float:
    v = round(float(v), nd)
    return 0.0 if v == 0 else v


def pappus_volume(region: BaseGeometry) -> float:
    """Volume of revolution of a region of the (z, x) half-plane about the Z axis."""
    return float(sum(2 * math.pi * p.area * p.centroid.y for p in polygons(region)))


def _thickness(g: BaseGeometry) -> float:
    """Rough thickness of a thin region: 2 area / perimeter (exact for a long strip)."""
    L = g.length
    return 2 * g.area / L if L > 0 else 0.0


def _resolve_machine(machine: Machine | None, tools: ToolLibrary | None) -> Machine:
    if machine is None:
        return load_machine(None, tools)
    if tools is not None:
        return machine.with_registers(tools.registers())
    return machine


class _Sweeper:
    """Builds the swept region of each move (cached tool shapes)."""

    def __init__(self, machine: Machine, moves: Iterable[Move] = (),
                 thread_regs: dict[int, float] | None = None, learn: bool = False):
        self.machine = machine
        self.shapes: dict[tuple[int, float | None], ToolShape] = {}
        # a register that names no insert but cuts threads is a threading tool for all its
        # moves (``thread_regs``: as found before for these moves)
        self.thread_regs: dict[int, float] = {}
        if thread_regs is not None:
            self.thread_regs = dict(thread_regs)
            moves = ()
        #: the registers whose insert is not a threading insert but that make thread moves,
        #: each with its first such move
        self.not_threading: dict[int, Move] = {}
        #: the columns of the moves when they are one chunk (:meth:`run` takes them again)
        self.first_columns: tuple[int, dict] | None = None
        #: ``learn``: the thread moves are found by :meth:`run`, from the columns it reads
        #: anyway, instead of from columns read here (``moves`` not given: a toolpath of
        #: several chunks, whose columns would be read twice); ``stale``: a run found a
        #: register that names no insert cutting threads after an earlier run swept its
        #: moves as the insert-less tool (the sweeps must be built again)
        self.learn = learn
        self.stale = False
        self._swept: set[int] = set()
        moves = moves if isinstance(moves, (list, tuple)) else list(moves)
        for c0 in range(0, len(moves), CHUNK):
            cm = moves[c0:c0 + CHUNK]
            cols = columns(cm)
            if len(moves) <= CHUNK:
                self.first_columns = (len(cm), cols)
            self._threads(cm, cols["kind"])

    def _threads(self, moves: list[Move], kind: np.ndarray) -> bool:
        """Take note of the registers of the thread moves among ``moves`` (``kind``: their
        kinds): a register that names no insert is a threading tool, one whose insert is not
        a threading insert a finding. Whether a register became a threading tool."""
        new = False
        for k in np.flatnonzero(kind == _THREAD).tolist():
            m = moves[k]
            if m.register in self.thread_regs or m.register in self.not_threading:
                continue
            ins = self.machine.register(m.register).insert
            if ins is None:
                self.thread_regs[m.register] = m.thread_angle if m.thread_angle > 0 else 60.0
                new = True
                if m.register in self._swept:
                    self.stale = True
            elif ins.kind != "thread":
                self.not_threading[m.register] = m
        return new

    def shape(self, m: Move) -> ToolShape:
        ta = None
        if m.register in self.thread_regs and m.kind != "thread":
            ta = self.thread_regs[m.register]
        elif m.kind == "thread":
            ta = m.thread_angle if m.thread_angle and m.thread_angle > 0 else None
            reg = self.machine.register(m.register)
            if ta is None:
                ta = reg.insert.angle if reg.insert is not None and reg.insert.kind == "thread" else 60.0
        key = (m.register, ta)
        s = self.shapes.get(key)
        if s is None:
            s = tool_shape(self.machine.register(m.register), ta)
            self.shapes[key] = s
        return s

    @staticmethod
    def path_points(m: Move) -> np.ndarray:
        """Controlled-point path of a move as (z, x) points (arcs sampled at CHORD)."""
        if m.kind == "arc":
            return np.ascontiguousarray(Arc(m.start, m.end, m.center, bool(m.cw)).sample_array(CHORD)[:, ::-1])
        return np.array([(m.start[1], m.start[0]), (m.end[1], m.end[0])], dtype=float)

    def sweeps(self, moves: list[Move]) -> tuple[list[BaseGeometry | None], list[np.ndarray]]:
        """Swept region of each move (None for dwells) and its path points.

        Every straight piece (a line, a chord of a sampled arc) sweeps the exact hull of the
        outline at its two ends (:func:`hnc_cam.sim.tool.sweep_hulls`, vectorised per tool)."""
        run = self.run(moves)
        return list(run.sweeps), [run.path(k) for k in range(len(moves))]

    def run(self, moves: list[Move], bands: bool = False, prev: tuple = (None, None)) -> "_Run":
        """The swept regions of a run of moves and the quads swept by their leading
        non-cutting sides, built with one vectorised call per tool shape.

        ``bands``: also the front bands of every straight piece whose tool outline has at most
        :data:`PAIR_VERTS` vertices (:func:`hnc_cam.sim.area.front_bands`; the whole hull where
        the piece's start placement was not swept by the move before: a tool change, a jump,
        the first move). ``prev``: (tool shape, end point) of the move before the run."""
        n = len(moves)
        got, self.first_columns = self.first_columns, None
        cols = got[1] if got is not None and got[0] == n and n else columns(moves)
        kind = cols["kind"]
        live = np.flatnonzero(kind != _DWELL)
        if self.learn:
            self._threads(moves, kind)
            self._swept.update(np.unique(cols["register"][live]).tolist())
        is_arc = kind == _ARC
        # the tool shape of each move, one per (register, thread move, thread angle)
        key = np.column_stack([cols["register"][live], kind[live] == _THREAD,
                               cols["thread_angle"][live]])
        combos, first_of, which = np.unique(key, axis=0, return_index=True, return_inverse=True)
        which = which.reshape(-1)
        shapes = [self.shape(moves[int(live[i])]) for i in first_of]
        sid = np.array([id(sh) for sh in shapes], dtype=np.int64)[which]
        # start placement swept by the move before (the same shape, ending where it starts)
        start, end = cols["start"], cols["end"]
        cont = np.zeros(n, dtype=bool)
        if len(live):
            same = np.zeros(len(live), dtype=bool)
            same[1:] = (sid[1:] == sid[:-1]) & np.all(start[live[1:]] == end[live[:-1]], axis=1)
            prev_shape, prev_end = prev
            same[0] = (shapes[which[0]] is prev_shape and prev_end is not None
                       and tuple(start[live[0]]) == prev_end)
            cont[live] = same
            last = live[-1]
            prev = (shapes[which[-1]], (float(end[last, 0]), float(end[last, 1])))
        groups: dict[tuple, tuple[ToolShape, list[int], list[int]]] = {}  # lines, arcs
        for j, sh in enumerate(shapes):
            ks = live[which == j]
            g = groups.get(sh.key)
            if g is None:
                g = groups[sh.key] = (sh, [], [])
            g[1].extend(ks[~is_arc[ks]].tolist())
            g[2].extend(ks[is_arc[ks]].tolist())
        for sh, lines, arcs in groups.values():
            lines.sort()
            arcs.sort()
        feed = cols["feed"]
        # moves whose checks go beyond the non-cutting sides (see _checked)
        checked = ((kind != _LINE) & (kind != _ARC) & (kind != _THREAD)) | (cols["spindle"] <= 0) \
            | ~(feed > 0)
        threads_stopped = np.flatnonzero((kind == _THREAD) & (cols["spindle"] <= 0))
        # starts of passes: a feed move whose move before (dwells aside) is a rapid
        lk = kind[live]
        feed_k = (lk == _LINE) | (lk == _ARC) | (lk == _THREAD)
        pass_starts = live[1:][feed_k[1:] & (lk[:-1] == _RAPID)]
        quads, quad_owner = [], []
        band_parts: list[tuple] = []
        outlines: list[np.ndarray] = []
        band_ok = np.zeros(n, dtype=bool)
        # the sweeps are built when asked for (_Run.sweep_of); their bounds now, from the
        # pieces' ends and the outline's (the bounds of the hull of two placements)
        bounds = np.full((n, 4), np.nan)
        pieces: list[tuple] = []
        move_group = np.full(n, -1, dtype=np.int64)
        move_p0 = np.zeros(n, dtype=np.int64)
        move_p1 = np.zeros(n, dtype=np.int64)
        for shape, lines, arcs in groups.values():
            own = np.array(lines, dtype=np.int64)
            P = start[own][:, ::-1].reshape(-1, 2)
            Q = end[own][:, ::-1].reshape(-1, 2)
            first = np.ones(len(lines), dtype=bool)
            if arcs:
                # the arcs' sampled paths (path_points) together: piece i of the rows runs
                # from row i to row i + 1 within an arc
                pts, rows = Arc.sample_arrays([Arc(moves[k].start, moves[k].end,
                                                   moves[k].center, bool(moves[k].cw))
                                               for k in arcs], CHORD)
                pts = pts[:, ::-1]
                last = np.cumsum(rows) - 1
                inner = np.ones(len(pts), dtype=bool)
                inner[last] = False
                at = np.flatnonzero(inner)
                P = np.concatenate([P, pts[at]])
                Q = np.concatenate([Q, pts[at + 1]])
                npc = rows - 1
                own = np.concatenate([own, np.repeat(np.asarray(arcs, dtype=np.int64), npc)])
                fa = np.zeros(len(at), dtype=bool)
                fa[np.cumsum(npc) - npc] = True
                first = np.concatenate([first, fa])
            nl = len(lines)
            gi = len(pieces)
            pieces.append((shape.outline, P, Q))
            if len(own):
                ko = np.asarray(shape.outline, dtype=float)
                lo_ = np.minimum(P, Q) + ko.min(axis=0)
                hi_ = np.maximum(P, Q) + ko.max(axis=0)
                pb = np.column_stack([lo_, hi_])
                move_group[own] = gi
                starts = np.flatnonzero(np.r_[True, own[1:] != own[:-1]])
                ends = np.r_[starts[1:], len(own)]
                mo = own[starts]
                move_p0[mo], move_p1[mo] = starts, ends
                bounds[mo, :2] = np.minimum.reduceat(pb[:, :2], starts, axis=0)
                bounds[mo, 2:] = np.maximum.reduceat(pb[:, 2:], starts, axis=0)
            if bands and len(shape.outline) <= PAIR_VERTS and len(own):
                covered = ~first | cont[own]
                K = _ccw_outline(shape)
                i_min, i_max = extremes(K, P, Q)
                band_parts.append((own, P, Q, covered, i_min, i_max,
                                   np.full(len(own), len(outlines))))
                outlines.append(K)
                band_ok[own] = True
            if shape.non_cutting:
                fk = (kind[own] == _LINE) | (kind[own] == _ARC) | (kind[own] == _THREAD)
                a, b, nrm = _sides(shape)
                Pf, Qf, Of = P[fk], Q[fk], own[fk]
                mv = Qf - Pf
                lead = (mv @ nrm.T) > 1e-12 * (np.hypot(mv[:, 0], mv[:, 1])[:, None] + 1e-12)
                pi, si = np.nonzero(lead)
                if len(pi):
                    quads.append(np.stack([a[si] + Pf[pi], b[si] + Pf[pi], b[si] + Qf[pi],
                                           a[si] + Qf[pi]], axis=1))
                    quad_owner.append(Of[pi])
        if quads:
            qo = np.concatenate(quad_owner)
            order = np.argsort(qo, kind="stable")
            qp = shapely.polygons(np.concatenate(quads)[order])
            qo = qo[order]
        else:
            qp, qo = np.zeros(0, dtype=object), np.zeros(0, dtype=np.int64)
        run = _Run(moves, np.full(n, None, dtype=object), qp, qo)
        run.pieces, run.move_group, run.move_p0, run.move_p1 = pieces, move_group, move_p0, move_p1
        run.bounds = bounds
        if n <= EAGER_SWEEPS:
            run.sweep_of(run.live)  # few moves: all at once costs less than batch by batch
        run.columns = {"kind": kind, "register": cols["register"], "duration": cols["duration"]}
        run.last = prev
        run.band_ok = band_ok
        run.checked = checked
        run.threads_stopped = threads_stopped
        run.pass_starts = pass_starts
        if band_parts:
            cols = [np.concatenate([bp[i] for bp in band_parts]) for i in range(7)]
            order = np.argsort(cols[0], kind="stable")
            (run.band_own, run.piece_a, run.piece_b, run.piece_covered, run.piece_min,
             run.piece_max, run.piece_shape) = (c[order] for c in cols)
            run.outlines = outlines
        return run


def _path_sweep(K: np.ndarray, P: np.ndarray, Q: np.ndarray) -> BaseGeometry:
    """The region the convex outline K sweeps along the connected pieces P[i] -> Q[i] of a
    sampled arc: the union of the pieces' hulls (:func:`hnc_cam.sim.tool.sweep_hulls`), built
    as one polygon.

    The ring is the convolution of K with the path traced forward and back: each piece
    translates the vertex of K extreme to the right of its motion (forward) or to its left
    (back); where that vertex changes between pieces, K's vertices between the two are
    inserted in the direction the path turns, and K's chain facing the motion closes the ring
    at the end, the chain behind it at the start. On the inner side of the turn these
    insertions run backwards and make the ring cross itself; the region is the set of points
    it winds round positively, which GEOS's zero-distance buffer returns; where two pieces'
    lines cross at such a turn, :func:`_side` cuts the loop there, and a ring that then does
    not cross itself is that region as it is (:func:`_ring_regions`). A path with a
    zero-length piece, or a result that is not one polygon, takes the union of the hulls."""
    g = _ring_sweep(K, P, Q)
    return g if g is not None else union_of(sweep_hulls(K, P, Q))


def _ring_sweep(K: np.ndarray, P: np.ndarray, Q: np.ndarray) -> BaseGeometry | None:
    """:func:`_path_sweep`'s one polygon, or None where it gives none (a zero-length piece,
    a single piece, a result that is not one polygon)."""
    return _ring_sweeps(K, P, Q, np.zeros(1, dtype=np.int64),
                        np.array([len(P)], dtype=np.int64))[0]


def _ring_sweeps(K: np.ndarray, P: np.ndarray, Q: np.ndarray, p0: np.ndarray,
                 cnt: np.ndarray) -> np.ndarray:
    """:func:`_ring_sweep` of each path k, the pieces p0[k] <= i < p0[k] + cnt[k] of P -> Q:
    the same rings and the same zero-distance buffer, built for all the paths with one
    vectorised call per step (None for a path that gives no polygon)."""
    K = np.asarray(K, dtype=float)
    z, x = K[:, 0], K[:, 1]
    if float(z[:-1] @ x[1:] - z[1:] @ x[:-1] + z[-1] * x[0] - z[0] * x[-1]) < 0:
        K = K[::-1]
    n, m = len(p0), len(K)
    out = np.full(n, None, dtype=object)
    if n == 1:  # one path (a batch's region): the same ring without the paths' bookkeeping
        a, c = int(p0[0]), int(cnt[0])
        A, B = P[a:a + c], Q[a:a + c]
        if c > 1 and np.all(np.any(A != B, axis=1)):
            i_min, i_max = extremes(K, A, B)
            front = K[(i_min[-1] + np.arange((i_max[-1] - i_min[-1]) % m + 1)) % m] + B[-1]
            back = K[(i_max[0] + np.arange((i_min[0] - i_max[0]) % m + 1)) % m] + A[0]
            right, _, loops = _side(K, i_min, A, B)
            left, _, loops_l = _side(K, i_max[::-1], B[::-1], A[::-1])
            ring = np.concatenate([right, front, left, back])
            g = _ring_regions(np.array([shapely.polygons(ring)], dtype=object),
                              np.array([len(loops) + len(loops_l) > 0]))[0]
            if g is not None and g.geom_type == "Polygon" and not g.is_empty:
                out[0] = g
        return out
    return _ring_sweeps_of([(K, P, Q, p0, cnt)])[0]


def _ring_sweeps_of(groups: list[tuple]) -> list[np.ndarray]:
    """:func:`_ring_sweeps` of the paths of several outlines, ``groups`` of (K, P, Q, p0, cnt)
    each: the same rings, vertex for vertex, and the same polygons as each group's alone,
    built for all the groups' paths with one vectorised call per step (a run's arcs of
    every tool at once)."""
    outs: list[np.ndarray] = []
    parts: list[tuple] = []
    Ks: list[np.ndarray] = []
    koff = 0
    for gi, (K, P, Q, p0, cnt) in enumerate(groups):
        K = np.asarray(K, dtype=float)
        z, x = K[:, 0], K[:, 1]
        if float(z[:-1] @ x[1:] - z[1:] @ x[:-1] + z[-1] * x[0] - z[0] * x[-1]) < 0:
            K = K[::-1]
        p0 = np.asarray(p0, dtype=np.int64)
        cnt = np.asarray(cnt, dtype=np.int64)
        n = len(p0)
        outs.append(np.full(n, None, dtype=object))
        # the paths of two pieces or more, none of zero length
        own = np.repeat(np.arange(n), cnt)
        idx = np.arange(len(own)) - np.repeat(np.cumsum(cnt) - cnt, cnt) + p0[own]
        zero = ~np.any(P[idx] != Q[idx], axis=1)
        use = (cnt > 1) & (np.bincount(own[zero], minlength=n) == 0)
        if not use.any():
            continue
        ks = np.flatnonzero(use)
        c = cnt[ks]
        own = np.repeat(np.arange(len(ks)), c)
        first = np.cumsum(c) - c
        idx = np.arange(len(own)) - first[own] + p0[ks][own]
        A, B = P[idx], Q[idx]
        i_min, i_max = extremes(K, A, B)
        parts.append((gi, ks, c, A, B, i_min, i_max, len(K), koff))
        Ks.append(K)
        koff += len(K)
    if not parts:
        return outs
    # every group's outline in one array: a path's vertex i is K[pk + i mod pm]
    K = Ks[0] if len(Ks) == 1 else np.concatenate(Ks)
    c = np.concatenate([q[2] for q in parts])
    A = np.concatenate([q[3] for q in parts])
    B = np.concatenate([q[4] for q in parts])
    i_min = np.concatenate([q[5] for q in parts])
    i_max = np.concatenate([q[6] for q in parts])
    pm = np.repeat([q[7] for q in parts], [len(q[1]) for q in parts])
    pk = np.repeat([q[8] for q in parts], [len(q[1]) for q in parts])
    npath = len(c)
    own = np.repeat(np.arange(npath), c)
    first = np.cumsum(c) - c
    last = first + c - 1
    m_own, k_own = pm[own], pk[own]
    # K's chain facing the motion at each path's end, the chain behind it at its start
    nf = (i_max[last] - i_min[last]) % pm + 1
    fo = np.repeat(np.arange(npath), nf)
    fj = np.arange(int(nf.sum())) - np.repeat(np.cumsum(nf) - nf, nf)
    front = K[pk[fo] + (i_min[last][fo] + fj) % pm[fo]] + B[last][fo]
    nb = (i_min[first] - i_max[first]) % pm + 1
    bo = np.repeat(np.arange(npath), nb)
    bj = np.arange(int(nb.sum())) - np.repeat(np.cumsum(nb) - nb, nb)
    back = K[pk[bo] + (i_max[first][bo] + bj) % pm[bo]] + A[first][bo]
    right, ro, loops = _side(K, i_min, A, B, own, last, m_own, k_own)
    rev = first[own] + last[own] - np.arange(len(own))  # each path's pieces backwards
    left, lo, loops_l = _side(K, i_max[rev], B[rev], A[rev], own, last, m_own, k_own)
    key = np.concatenate([4 * ro, 4 * fo + 1, 4 * lo + 2, 4 * bo + 3])
    order = np.argsort(key, kind="stable")
    coords = np.concatenate([right, front, left, back])[order]
    crossing = np.zeros(npath, dtype=bool)
    crossing[own[loops]] = True
    crossing[own[rev[loops_l]]] = True
    gs = _ring_regions(shapely.polygons(shapely.linearrings(coords, indices=key[order] // 4)),
                       crossing)
    good = np.array([g is not None for g in gs.tolist()], dtype=bool)
    good[good] = (shapely.get_type_id(gs[good]) == 3) & ~shapely.is_empty(gs[good])
    at = 0
    for gi, ks, *_ in parts:
        g, ok = gs[at:at + len(ks)], good[at:at + len(ks)]
        outs[gi][ks[ok]] = g[ok]
        at += len(ks)
    return outs


def _ring_regions(polys: np.ndarray, crossing: np.ndarray) -> np.ndarray:
    """The region each of :func:`_ring_sweeps`' rings (polygons of counter-clockwise rings)
    winds round positively, clockwise as GEOS's zero-distance buffer gives it (None where that
    fails): a ring that does not cross itself (most, once :func:`_side` has cut the loops at
    the turns) is the polygon it bounds; the others, and those known to cross themselves
    (``crossing``: a loop :func:`_side` could not cut), take the buffer."""
    out = np.full(len(polys), None, dtype=object)
    if not len(polys):
        return out
    simple = ~crossing
    if simple.any():
        simple[simple] = shapely.is_valid(polys[simple])
    if simple.any():
        out[simple] = shapely.orient_polygons(polys[simple], exterior_cw=True)
    rest = np.flatnonzero(~simple)
    if len(rest):
        try:
            out[rest] = shapely.buffer(polys[rest], 0)
        except shapely.errors.GEOSException:
            for i in rest.tolist():
                try:
                    out[i] = shapely.buffer(polys[i], 0)
                except shapely.errors.GEOSException:
                    pass
    return out


def _side(K: np.ndarray, ext: np.ndarray, P: np.ndarray, Q: np.ndarray,
          own: np.ndarray | None = None, last: np.ndarray | None = None,
          m: np.ndarray | None = None, koff: np.ndarray | None = None
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One side of :func:`_path_sweep`'s ring: for each piece P[i] -> Q[i], the outline's
    vertex ``ext[i]`` at both ends, then the outline's vertices on to ``ext[i + 1]`` at Q[i]
    in the direction the path turns there. With ``own`` (each piece's path) and ``last``
    (the last piece of each path), the sides of several paths at once; with ``m`` and ``koff``
    (per piece) each path's outline is ``K[koff:koff + m]`` (several outlines in one array).
    Returns the points, each point's path and the pieces whose loop at their end is left as
    it is (see below)."""
    n = len(P)
    if m is None:
        m = np.full(n, len(K), dtype=np.int64)
        koff = np.zeros(n, dtype=np.int64)
    d = Q - P
    cr = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]
    nxt = ext[1:]
    sgn = np.ones(n, dtype=np.int64)
    cnt = np.zeros(n, dtype=np.int64)
    sgn[:-1] = np.where(cr >= 0, 1, -1)
    cnt[:-1] = np.where(cr >= 0, (nxt - ext[:-1]) % m[:-1], (ext[:-1] - nxt) % m[:-1])
    if last is not None:
        sgn[last], cnt[last] = 1, 0
    L = 2 + cnt
    off = np.cumsum(L) - L
    owner = np.repeat(np.arange(n), L)
    j = np.arange(int(L.sum())) - off[owner]
    kidx = koff[owner] + (ext[owner] + sgn[owner] * np.maximum(j - 1, 0)) % m[owner]
    pts = K[kidx] + np.where((j == 0)[:, None], P[owner], Q[owner])
    # where the path turns toward this side and the extreme vertex changes, the inserted
    # vertices run back along the outline (a thin loop that crosses the two pieces' lines,
    # which the buffer has to node at near-parallel edges): where the two lines cross within
    # both pieces, the crossing takes the place of the piece's end, the inserted vertices and
    # the next piece's start (the loop lies inside the next piece's hull)
    w = np.flatnonzero((sgn[:-1] < 0) & (cnt[:-1] > 0))
    loops = w[:0]
    if len(w):
        a1 = K[koff[w] + ext[w]] + P[w]
        a2 = K[koff[w] + ext[w + 1]] + Q[w]
        e1, e2 = d[w], d[w + 1]
        r = a2 - a1
        den = cr[w]
        t = (r[:, 0] * e2[:, 1] - r[:, 1] * e2[:, 0]) / den
        s = (r[:, 0] * e1[:, 1] - r[:, 1] * e1[:, 0]) / den
        ok = (t >= 0) & (t <= 1) & (s >= 0) & (s <= 1)
        loops = w[~ok]
        if len(loops):  # a path with a loop left crosses itself: as it is, for the buffer
            ok &= False if own is None else ~np.isin(own[w], own[loops])
        w, t = w[ok], t[ok]
        if len(w):
            pts[off[w] + 1] = a1[ok] + t[:, None] * e1[ok]
            nd = cnt[w] + 1  # the inserted vertices and the next piece's start
            keep = np.ones(len(pts), dtype=bool)
            keep[np.repeat(off[w] + 2 - (np.cumsum(nd) - nd), nd) + np.arange(int(nd.sum()))] = False
            pts, owner = pts[keep], owner[keep]
    return pts, (np.zeros(len(pts), dtype=np.int64) if own is None else own[owner]), loops


def _polygons(rings: list[np.ndarray]) -> np.ndarray:
    """Polygons of closed rings (arrays (n_i, 2)) with one vectorised call."""
    sizes = [len(r) for r in rings]
    return shapely.polygons(shapely.linearrings(np.concatenate(rings),
                                                indices=np.repeat(np.arange(len(rings)), sizes)))


#: :func:`_ccw_outline` by the shape's key (a tool's outline is the same for every program)
_CCW: dict[tuple, np.ndarray] = {}


def _ccw_outline(shape: ToolShape) -> np.ndarray:
    K = _CCW.get(shape.key) if shape.key else None
    if K is not None:
        return K
    K = np.asarray(shape.outline, dtype=float)
    if float(np.sum(K[:, 0] * np.roll(K[:, 1], -1) - np.roll(K[:, 0], -1) * K[:, 1])) < 0:
        K = K[::-1]
    if shape.key:
        if len(_CCW) >= 256:
            _CCW.clear()
        _CCW[shape.key] = K
    return K


class _Run:
    """Sweeps of a run of consecutive moves (index k in the run) and the parallelograms
    ``quads`` swept by leading non-cutting sides, sorted by their move ``quad_owner``; with
    bands, the front bands of the pieces of the moves where ``band_ok`` (sorted by move)."""

    def __init__(self, moves: list[Move], sweeps: np.ndarray, quads: np.ndarray,
                 quad_owner: np.ndarray):
        self.moves, self._sweeps, self.quads, self.quad_owner = moves, sweeps, quads, quad_owner
        # the straight pieces per tool outline (outline, starts, ends) and each move's: the
        # outline's index (-1: a dwell, no sweep) and its pieces' range
        self.pieces: list[tuple] = []
        self.move_group = np.full(len(moves), -1, dtype=np.int64)
        self.move_p0 = self.move_p1 = np.zeros(len(moves), dtype=np.int64)
        self.bounds = np.full((len(moves), 4), np.nan)
        self.last: tuple = (None, None)
        self.columns: dict[str, np.ndarray] = {}
        self.band_ok = np.zeros(len(moves), dtype=bool)
        self.checked = np.ones(len(moves), dtype=bool)
        self.threads_stopped = np.zeros(0, dtype=np.int64)
        self.pass_starts = np.zeros(0, dtype=np.int64)
        # the straight pieces of the moves where band_ok, in program order: their move, ends,
        # whether the start placement was swept before, the extreme vertices of the outline
        # across the motion, the outline
        self.band_own = np.zeros(0, dtype=np.int64)
        self.piece_a = self.piece_b = np.zeros((0, 2))
        self.piece_covered = np.zeros(0, dtype=bool)
        self.piece_min = self.piece_max = self.piece_shape = np.zeros(0, dtype=np.int64)
        self.outlines: list[np.ndarray] = []

    @property
    def live(self) -> np.ndarray:
        """The moves that sweep a region (all but dwells)."""
        return np.flatnonzero(self.move_group >= 0)

    @property
    def sweeps(self) -> np.ndarray:
        """The swept region of every move (None for dwells)."""
        self.sweep_of(self.live)
        return self._sweeps

    def sweep_of(self, idx: np.ndarray) -> np.ndarray:
        """The swept regions of the moves ``idx`` (built once, with one vectorised call per
        tool outline): the exact hull of each straight piece (:func:`sweep_hulls`), their
        union for a sampled arc."""
        idx = np.asarray(idx, dtype=np.int64)
        sw = self._sweeps
        todo = idx[(self.move_group[idx] >= 0) & (sw[idx] == None)]  # noqa: E711
        if len(todo):
            todo = np.unique(todo)
            grp = self.move_group[todo]
            paths: list[tuple] = []  # per group with paths of several pieces: (its moves, ...)
            for gi in np.unique(grp).tolist():
                ks = todo[grp == gi]
                K, P, Q = self.pieces[gi]
                p0, p1 = self.move_p0[ks], self.move_p1[ks]
                cnt = p1 - p0
                one = cnt == 1
                sw[ks[one]] = sweep_hulls(K, P[p0[one]], Q[p0[one]])
                if not one.all():
                    paths.append((ks[~one], (K, P, Q, p0[~one], cnt[~one])))
            if paths:
                # the paths of several pieces (sampled arcs) of every outline: their rings
                # built and buffered together, the union of the hulls where that gives none
                for (many, (K, P, Q, p0, cnt)), gs in zip(
                        paths, _ring_sweeps_of([q for _, q in paths])):
                    for k, g, a, c in zip(many.tolist(), gs.tolist(), p0.tolist(),
                                          cnt.tolist()):
                        sw[k] = g if g is not None else union_of(sweep_hulls(K, P[a:a + c],
                                                                             Q[a:a + c]))
        return sw[idx]

    def sweep(self, k: int) -> BaseGeometry | None:
        return self.sweep_of(np.array([k]))[0]

    def pass_length(self, k: int) -> int:
        """The number of moves of the pass that move k is in: from the pass's start (a feed
        move after a rapid, or the run's start) to the next pass's start (or the run's end)."""
        ps = self.pass_starts
        i = int(np.searchsorted(ps, k, "right"))
        return (int(ps[i]) if i < len(ps) else len(self.moves)) - (int(ps[i - 1]) if i else 0)

    def path(self, k: int) -> np.ndarray:
        m = self.moves[k]
        return np.zeros((0, 2)) if m.kind == "dwell" else _Sweeper.path_points(m)

    def band_areas(self, region: np.ndarray, k0: int, k1: int) -> np.ndarray:
        """Upper bounds of what each move k0 <= k < k1 removes from the region (edges of
        :func:`hnc_cam.sim.area.region_edges`) when the moves before it in the run have
        already been taken out of it: the overlap of the region with the move's front bands
        (exact as soon as the bounds of a batch add up to what it removed as a whole). The
        bands are first cut at the highest point of the region over their Z range (nothing
        above it can meet the region)."""
        lo, hi = np.searchsorted(self.band_own, [k0, k1])
        out = np.zeros(k1 - k0)
        if hi <= lo or not len(region):
            return out
        p0 = max(lo - 1, 0)  # with the piece before (a change of extreme vertices at lo)
        A, B, sh = self.piece_a[p0:hi], self.piece_b[p0:hi], self.piece_shape[p0:hi]
        kx = np.array([K[:, 1].min() for K in self.outlines])[sh]
        kz0 = np.array([K[:, 0].min() for K in self.outlines])[sh]
        kz1 = np.array([K[:, 0].max() for K in self.outlines])[sh]
        z0 = float((np.minimum(A[:, 0], B[:, 0]) + kz0).min())
        z1 = float((np.maximum(A[:, 0], B[:, 0]) + kz1).max())
        ez = region[:, [0, 2]]
        over = (ez.min(axis=1) <= z1) & (ez.max(axis=1) >= z0)
        if not over.any():
            return out
        # nothing of the region over the pieces' Z range lies above X: a piece's sweep below X
        # is that of the outline's part below X - (the piece's lowest end), so the bands are
        # built for that part of the outline (a few vertices of a sampled nose) and cut at X
        near = region[over]
        X = float(near[:, [1, 3]].max())
        low = np.minimum(A[:, 1], B[:, 1])
        x0 = low + kx  # lowest point of each piece's sweep
        cov = self.piece_covered[p0:hi]
        edges, owners, sw_rings, sw_prev, sw_own = [], [], [], [], []
        zlo, zhi = np.minimum(A[:, 0], B[:, 0]), np.maximum(A[:, 0], B[:, 0])
        for s_ in np.unique(sh).tolist():
            js = np.flatnonzero(sh == s_)
            K0 = clip_outline(self.outlines[s_], X - float(low[js].min()))
            if K0 is None:
                continue
            # each band is cut at the highest point of the region over its own Z range
            Xi = heights_over(near, zlo[js] + float(K0[:, 0].min()),
                              zhi[js] + float(K0[:, 0].max()))
            inb = (js + p0 >= lo) & (x0[js] < Xi)
            if not inb.any():
                continue
            jb, Xb = js[inb], Xi[inb]
            # where a piece continues the one before it (its start placement swept by that
            # one), its band may reach back into that piece's hull beside the start placement
            # (where the extreme vertices change): that part is taken off the bound (it stays
            # an upper bound), with the outline holding what the piece before reaches below Xb
            jp = np.maximum(jb - 1, 0)
            prev = cov[jb] & (jb > 0) & (sh[jp] == s_)
            need = np.where(prev, np.maximum(Xb - low[jb], Xb - low[jp]), Xb - low[jb])
            # the outline is cut at the most a piece reaches below Xb, for groups of pieces
            # that keep about as many of its vertices (a sampled nose: a few for most pieces,
            # all for a retract up a face), so that a band has about the vertices it needs
            cnt = np.searchsorted(np.sort(K0[:, 1]), need, "right")
            grp = (cnt + BAND_GROUP - 1) // BAND_GROUP
            for g_ in np.unique(grp).tolist():
                sel = np.flatnonzero(grp == g_)
                K = clip_outline(K0, float(need[sel].max()))
                if K is None:
                    continue
                # the cut outline spans less Z than K0: the region's top over the bands' own
                # Z range is lower still, and the outline is cut again at what that needs
                j, Xs = jb[sel], heights_over(near, zlo[jb[sel]] + float(K[:, 0].min()),
                                              zhi[jb[sel]] + float(K[:, 0].max()))
                Xs = np.minimum(Xs, Xb[sel])
                low_p = np.where(prev[sel], np.minimum(low[j], low[jp[sel]]), low[j])
                keep = x0[j] < Xs  # the others' bands lie wholly above the region
                if not keep.all():
                    sel, j, Xs, low_p = sel[keep], j[keep], Xs[keep], low_p[keep]
                    if not len(j):
                        continue
                K = clip_outline(K, float((Xs - low_p).max()))
                if K is None:
                    continue
                # BAND_BLOCK pieces at a time (bounds the memory of the rings and their clips)
                for q0 in range(0, len(j), BAND_BLOCK):
                    jq, Xq = j[q0:q0 + BAND_BLOCK], Xs[q0:q0 + BAND_BLOCK]
                    rings, imin, imax = front_bands(K, A[jq], B[jq], ~cov[jq])
                    e, eo = ring_edge_rows(clip_below(rings, Xq))
                    edges.append(e)
                    owners.append(jq[eo])
                    w = np.flatnonzero(prev[sel[q0:q0 + BAND_BLOCK]])
                    if len(w):
                        pmin, pmax = extremes(K, A[jq[w] - 1], B[jq[w] - 1])
                        w = w[(pmin != imin[w]) | (pmax != imax[w])]
                    if len(w):
                        sw_rings.append(shapely.polygons(rings[w]))
                        sw_prev.append(sweep_hulls(K, A[jq[w] - 1], B[jq[w] - 1]))
                        sw_own.append(jq[w])
        if not edges:
            return out
        f, fo = np.concatenate(edges), np.concatenate(owners)
        ks, fo = np.unique(fo, return_inverse=True)
        a = overlap_areas_of(region, f, fo.reshape(-1), x0[ks], len(ks))
        out += np.bincount(self.band_own[p0 + ks] - k0, weights=a, minlength=k1 - k0)
        if sw_own:
            both = shapely.intersection(np.concatenate(sw_rings), np.concatenate(sw_prev))
            ss = np.concatenate(sw_own)
            nz = np.flatnonzero(shapely.area(both) > 0)
            if len(nz):
                sub = overlap_areas(region, polygon_edges(both[nz]), x0[ss[nz]])
                np.subtract.at(out, self.band_own[p0 + ss[nz]] - k0, sub)
        return out

    def batch_region(self, k0: int, k1: int) -> np.ndarray | list | None:
        """Polygons inside the union of the sweeps of the moves k0 <= k < k1 (where band_ok):
        where their pieces are one path (each starts where the one before ends) of one
        outline that does not cross itself, the union of the pieces' hulls as one polygon
        (:func:`_ring_sweep`, as an arc's sweep; one zero-distance buffer costs about half
        the union of the envelopes) when the outline's extreme vertices move on by at most
        :data:`RING_TURN` vertices a piece (the ring gains those vertices where they move,
        crossing itself on the inside of the turn, and the buffer's cost grows faster than
        the union's with them); else, or where that gives no polygon, the
        :meth:`envelopes`."""
        lo, hi = np.searchsorted(self.band_own, [k0, k1])
        sh = self.piece_shape[lo:hi]
        if hi - lo > 1 and self.piece_covered[lo + 1:hi].all() and (sh == sh[0]).all():
            K = self.outlines[int(sh[0])]
            turn = 0
            for ext in (self.piece_min[lo:hi], self.piece_max[lo:hi]):
                d = np.abs(np.diff(ext))
                turn += int(np.minimum(d, len(K) - d).sum())
            A, B = self.piece_a[lo:hi], self.piece_b[lo:hi]
            if (turn <= RING_TURN * (hi - lo)
                    and shapely.is_simple(shapely.linestrings(np.concatenate([A[:1], B])))):
                g = _ring_sweep(K, A, B)
                if g is not None:
                    return [g]
        return self.envelopes(k0, k1)

    def envelopes(self, k0: int, k1: int) -> np.ndarray | list | None:
        """Polygons inside the union of the sweeps of the moves k0 <= k < k1 (where
        band_ok): per run of pieces with one outline, continuous, with the same extreme
        vertices, its :func:`hnc_cam.sim.area.envelope`, and the outline where a run starts
        (unless the batch's first piece continues from a placement already swept). None when an envelope is not a simple polygon."""
        lo, hi = np.searchsorted(self.band_own, [k0, k1])
        if hi <= lo:
            return []
        cov = self.piece_covered[lo:hi]
        sh, mn, mx = self.piece_shape[lo:hi], self.piece_min[lo:hi], self.piece_max[lo:hi]
        brk = np.ones(hi - lo, dtype=bool)
        brk[1:] = ~cov[1:] | (sh[1:] != sh[:-1]) | (mn[1:] != mn[:-1]) | (mx[1:] != mx[:-1])
        starts = np.flatnonzero(brk).tolist() + [hi - lo]
        A, B = self.piece_a[lo:hi], self.piece_b[lo:hi]
        rings = []
        extra = []
        for r0, r1 in zip(starts[:-1], starts[1:]):
            K = self.outlines[int(sh[r0])]
            pts = np.concatenate([A[r0:r0 + 1], B[r0:r1]])
            rings.append(envelope(K, int(mn[r0]), int(mx[r0]), pts))
            if r0 > 0 or not cov[r0]:
                # the whole outline where a run starts: the envelopes on either side hold
                # only its parts behind and ahead of their own chords
                extra.append(np.concatenate([K, K[:1]]) + A[r0])
        polys = _polygons(rings)
        if not shapely.is_valid(polys).all():
            return None
        return np.concatenate([polys, _polygons(extra)]) if extra else polys

    def non_cutting_candidates(self, local: BaseGeometry, k0: int, k1: int) -> set[int]:
        """Moves k0 <= k < k1 whose leading non-cutting sides pass through ``local`` (prepared;
        the material at the start of their batch, a superset of what each move meets): only
        these need the exact check."""
        lo, hi = np.searchsorted(self.quad_owner, [k0, k1])
        if hi <= lo:
            return set()
        hit = shapely.intersects(local, self.quads[lo:hi])
        return set(self.quad_owner[lo:hi][hit].tolist())


#: a batch's region is built as one ring (:meth:`_Run.batch_region`) where the outline's
#: extreme vertices move on by at most this many vertices a piece (on average)
RING_TURN = 4
#: the front bands of a batch's pieces are built for groups of pieces that keep this many
#: more of the outline's vertices below the region's top than the group before
BAND_GROUP = 8
#: front bands built at once (their rings and clips some 3 MB for a sampled nose)
BAND_BLOCK = 256
#: margin (mm) of a batch's zone round the convex hull of its sweeps
SEAM = 0.01
#: a material of at most this many vertices is taken move by move whole: the overlays of a
#: zone (cutting it out and putting the material back together) cost more than they save
SMALL_MATERIAL = 1000
#: moves whose sweeps are built together (bounds the memory held for sweeps)
CHUNK = 4096
#: a run of at most this many moves has its sweeps built at once; a longer one builds them for
#: the batches taken move by move and the moves checked (a batch taken with bands needs none)
EAGER_SWEEPS = 1024


def _difference(a: BaseGeometry, b: BaseGeometry) -> BaseGeometry:
    """``a - b`` for polygonal a and b (the result is polygonal), retried on the snap grid
    when GEOS meets a robustness failure."""
    try:
        return _lib_difference(a, b)
    except shapely.errors.GEOSException:
        return diff(a, b)


#: pieces and holes of material smaller than this (mm^2) are rounding specks, not material
SPECK = 1e-9


def _drop_specks(g: BaseGeometry) -> BaseGeometry:
    """``g`` without the polygons and holes of area below :data:`SPECK`: where what a batch
    removed meets the material its boundary vertices are rounded intersection points, and the
    overlay can leave slivers some 1e-15 mm wide there."""
    if (shapely.get_type_id(g) == 3 and shapely.get_num_interior_rings(g) == 0
            and _lib_area(g) >= SPECK):
        return g  # one polygon without holes, not a speck (most batches): as it is
    parts = polygons(g)
    if not parts:
        return g
    arr = np.array(parts, dtype=object)
    small = shapely.area(arr) < SPECK
    holes = shapely.get_num_interior_rings(arr) > 0
    if not small.any() and not holes.any():
        return g
    keep = []
    for p, sm, ho in zip(parts, small, holes):
        if sm:
            continue
        if ho:
            inner = [r for r in p.interiors if Polygon(r).area >= SPECK]
            if len(inner) < len(p.interiors):
                p = Polygon(p.exterior, inner)
        keep.append(p)
    if len(keep) == len(parts) and all(a is b for a, b in zip(keep, parts)):
        return g
    if not keep:
        return Polygon()
    return keep[0] if len(keep) == 1 else shapely.MultiPolygon(keep)


def simulate(toolpath: Toolpath, stock: Stock | BaseGeometry, machine: Machine | None = None,
             tools: ToolLibrary | None = None, model=None, batch: int = BATCH,
             snapshots: Iterable[int] = (),
             on_snapshot: Callable[[int, BaseGeometry], None] | None = None) -> Machined:
    """Remove material from ``stock`` along ``toolpath`` and run the checks.

    ``stock``: a :class:`hnc_cam.tooling.Stock` (``offset:A`` needs ``model``, a
    :class:`hnc_cam.geometry.TurnedProfile`) or a shapely region in (z, x).
    ``machine``: offset registers for the tool outlines (default: the bundled machine filled from
    the default tool library); ``tools``: a tool library whose registers override the machine's.
    ``snapshots``/``on_snapshot``: ``on_snapshot(k, material)`` is called, in increasing k, with
    the material on the machine after the first k moves for every k of ``snapshots`` (0 <= k
    <= number of moves; others are ignored): the same region the simulation goes on from
    (fallen pieces gone), so the last one is ``Machined.material``. See :func:`material_after`.
    """
    # the simulation makes many short-lived objects and no reference cycles: the cyclic
    # collector would only rescan the toolpath's moves, more of them the longer the program
    with _gc_paused():
        return _simulate(toolpath, stock, machine, tools, model, batch, snapshots, on_snapshot)


def _simulate(toolpath, stock, machine, tools, model, batch, snapshots, on_snapshot,
              scan: bool = False) -> Machined:
    machine = _resolve_machine(machine, tools)
    start_region = clean(stock_region(stock, model))
    material: BaseGeometry = start_region
    chuck = chuck_zone(start_region) if not start_region.is_empty else None
    jaws = jaw_region(start_region, machine)
    jaw_lines: set[int] = set()
    moves = toolpath.moves
    n = len(moves)
    removed_area = np.zeros(n)
    boxes = np.full((n, 4), np.nan)  # bounds (z0, x0, z1, x1) of each move's swept region
    issues: list[Issue] = []
    notes: list[Issue] = []
    # the thread moves' registers: found while the runs read the moves' columns where the
    # toolpath is longer than one chunk (not read twice), else before; before as well with
    # snapshots (which cannot be taken back) and with ``scan``: the simulation again after a
    # run found a register's thread moves when earlier runs had swept its other moves
    if n > CHUNK and on_snapshot is None and not scan:
        sweeper = _Sweeper(machine, learn=True)
    else:
        sweeper = _Sweeper(machine, moves)
    fallen: list[BaseGeometry] = []
    per_move = {"kind": np.zeros(n, dtype=np.int8), "register": np.zeros(n, dtype=np.int32),
                "duration": np.zeros(n)}

    edges_of: list = [None, None]  # (material, its edges): recomputed when the material changes
    prev: tuple = (None, None)
    stops = sorted({int(k) for k in snapshots if 0 <= int(k) <= n}) if on_snapshot else []
    si = 0  # next snapshot
    with _gc_paused():
        for c0 in range(0, n, CHUNK):
            cm = moves[c0:c0 + CHUNK]
            run = sweeper.run(cm, bands=True, prev=prev)
            if sweeper.stale:
                return _simulate(toolpath, stock, machine, None, model, batch, snapshots,
                                 on_snapshot, scan=True)
            prev = run.last
            for key, col in per_move.items():
                col[c0:c0 + len(cm)] = run.columns[key]
            for k in run.threads_stopped.tolist():
                m = cm[k]
                issues.append(Issue(m.line, toolpath.block(m.line),
                                    "thread move while the spindle is not turning",
                                    "thread-spindle"))
            has = run.live
            if len(has):
                boxes[c0 + has] = run.bounds[has]
                if jaws is not None:
                    _jaw_hits(jaws, run, has, cm, sweeper, toolpath, issues, jaw_lines)
            # batches also start with every pass (a feed move after a rapid): a pass that comes
            # back over the one before it would not be taken with bands in the same batch; a
            # pass longer than a batch is cut into equal batches of at most ``batch`` moves
            # (the fewest, each paying the per-batch work on the whole material once)
            ends = sorted({0, len(cm), *run.pass_starts.tolist(),
                           *(k - c0 for k in stops[si:] if c0 < k < c0 + len(cm))})
            cuts = [len(cm)]
            for e0, e1 in zip(ends[:-1], ends[1:]):
                parts = -(-(e1 - e0) // batch)
                cuts += [e0 + (e1 - e0) * i // parts for i in range(parts)]
            cuts.sort()
            for b0, b1 in zip(cuts[:-1], cuts[1:]):
                while si < len(stops) and stops[si] <= c0 + b0:
                    on_snapshot(stops[si], material)
                    si += 1
                # a batch whose bounds do not add up is halved (a short pass that comes back
                # over the one before it in the same batch), down to MOVE_BATCH moves, which
                # are then taken move by move
                todo = [(b0, b1)]
                while todo and not material.is_empty:
                    s0, s1 = todo.pop()
                    lo, hi = np.searchsorted(has, [s0, s1])
                    if hi <= lo:
                        continue
                    idx = has[lo:hi]
                    if not _boxes_meet(material, boxes[c0 + idx]):
                        continue
                    if s1 - s0 <= MOVE_BATCH and run.pass_length(s0) <= SHORT_PASS:
                        # a short pass: move by move from the start (see _batch_by_bands)
                        got = _batch_by_moves(material, run, c0, s0, s1, idx, run.sweep_of(idx),
                                              removed_area, sweeper, toolpath, issues, notes)
                        if got is not material:
                            material = _settle(got, chuck, fallen)
                        continue
                    if run.band_ok[idx].all():
                        got = _batch_by_bands(material, edges_of, run, c0, s0, s1, idx, None,
                                              removed_area, sweeper, toolpath, issues, notes)
                        if got is not None:
                            if got is not material:
                                material = _settle(got, chuck, fallen)
                            continue
                        if s1 - s0 > MOVE_BATCH:
                            # at the start of the pass (a feed move after a rapid) nearest
                            # the middle, else in the middle
                            mid = (s0 + s1) // 2
                            ps = run.pass_starts[(run.pass_starts > s0) & (run.pass_starts < s1)]
                            if len(ps):
                                mid = int(ps[np.argmin(np.abs(ps - mid))])
                            todo += [(mid, s1), (s0, mid)]  # the first half first
                            continue
                    for t0 in range(s0, s1, MOVE_BATCH):
                        t1 = min(t0 + MOVE_BATCH, s1)
                        lo, hi = np.searchsorted(has, [t0, t1])
                        if hi <= lo or material.is_empty:
                            continue
                        sub = has[lo:hi]
                        got = _batch_by_moves(material, run, c0, t0, t1, sub, run.sweep_of(sub),
                                              removed_area, sweeper, toolpath, issues, notes)
                        if got is not material:
                            material = _settle(got, chuck, fallen)

    while si < len(stops):
        on_snapshot(stops[si], material)
        si += 1
    tool = []
    for reg, m in sweeper.not_threading.items():
        ins = machine.register(reg).insert
        tool.append(Issue(m.line, toolpath.block(m.line),
                          f"thread move with offset register {reg}, whose tool is not a "
                          f"threading tool (its insert {ins.code} is a {ins.kind} insert): "
                          f"the program's tool numbers do not match the tool library's "
                          f"(--tools FILE gives the shop's)", "tool"))
    issues[:0] = tool
    issues.sort(key=lambda i: i.line)
    return Machined(material=material, stock=start_region, toolpath=toolpath, issues=issues,
                    removed_area=removed_area, sweep_bounds=boxes, shapes=dict(sweeper.shapes),
                    thread_spans=_thread_spans(moves, machine, per_move["kind"]), fallen=fallen,
                    machine=machine, notes=notes, jaws=jaws, per_move=per_move,
                    thread_regs=dict(sweeper.thread_regs))


def _jaw_hits(jaws: BaseGeometry, run: "_Run", idx: np.ndarray, cm: list[Move],
              sweeper: "_Sweeper", tp: Toolpath, issues: list[Issue], seen: set[int]) -> None:
    """A ``collision: chuck jaw`` finding for each program line with a move whose sweep
    touches the jaws (as a cut touches material: :func:`_touches`)."""
    z0, x0, z1, x1 = jaws.bounds
    bb = run.bounds[idx]
    idx = idx[(bb[:, 0] <= z1) & (bb[:, 2] >= z0) & (bb[:, 1] <= x1) & (bb[:, 3] >= x0)]
    if not len(idx):
        return
    sweeps = run.sweep_of(idx)
    hit = np.flatnonzero(shapely.intersects(jaws, sweeps))
    for j, k in zip(hit.tolist(), idx[hit].tolist()):
        m = cm[k]
        if m.line in seen:
            continue
        rem = inter(jaws, sweeps[j])
        if not _touches(rem):
            continue
        seen.add(m.line)
        shape = sweeper.shape(m)
        issues.append(Issue(m.line, tp.block(m.line),
                            f"chuck jaw: the tool (register {m.register}) runs into the jaws "
                            f"({rem.area:.3f} mm^2 at {_where(rem)})", "collision",
                            first_contact(jaws, shape, sweeper.path_points(m))))


#: the material's vertex count from which each batch drops its collinear vertices
LEAN_FROM = 256


def _settle(material: BaseGeometry, chuck: BaseGeometry | None,
            fallen: list[BaseGeometry]) -> BaseGeometry:
    """The material after a batch: rounding specks dropped, vertices that lie exactly on the
    line of their neighbours dropped (the same point set: passes that end on one shoulder face
    each left a vertex on it, and every later overlay along the face paid for them all; only
    in material of :data:`LEAN_FROM` vertices or more, where they cost more than the pass that
    finds them), pieces cut loose from the chucked end fallen off (into ``fallen``)."""
    material = _drop_specks(material)
    if shapely.get_num_coordinates(material) >= LEAN_FROM:
        material = shapely.simplify(material, 0.0, preserve_topology=False)
    if shapely.get_type_id(material) == 3:
        return material  # one piece: nothing falls
    parts = polygons(material)
    if len(parts) > 1 and chuck is not None:
        keep = [p for p in parts if p.intersects(chuck)]
        lost = [p for p in parts if not p.intersects(chuck)]
        if lost:
            fallen.extend(lost)
            material = clean(shapely.union_all(keep)) if keep else Polygon()
    return material


def _batch_by_bands(material, edges_of, run: "_Run", c0, b0, b1, idx, geoms, removed_area,
                    sweeper, toolpath, issues, notes):
    """Take a batch out of the material with one overlay, each move's share from
    :meth:`_Run.band_areas`.

    The bands give upper bounds: each at least what its move removes after the moves before
    it, so they add up to at least what the whole batch removes, which is at least what the
    envelopes (:meth:`_Run.envelopes`, inside the union of the sweeps) take out of the
    material. When the bounds add up to what the envelopes take out (to ``1e-10 + 1e-13 *
    area`` mm^2), all of these are equal: every bound is the move's exact removal and the
    material minus the envelopes is the material minus the sweeps. Returns the material after
    the batch (``material`` itself when the batch removed nothing), or None when the bounds
    do not add up (the batch is then taken move by move), and for a batch of a short pass
    (:data:`SHORT_PASS`), which costs less move by move."""
    if run.pass_length(b0) <= SHORT_PASS:
        return None
    try:
        with np.errstate(all="ignore"):
            if edges_of[0] is not material:
                edges_of[0], edges_of[1] = material, region_edges(material)
            ub = run.band_areas(edges_of[1], b0, b1)
            if not np.isfinite(ub).all():
                return None
            if not len(ub) or float(ub.max()) <= 1e-12:
                return material  # no move removed more than this: nothing (as move by move)
            env = run.batch_region(b0, b1)
            if env is None:
                return None
            after = _difference(material, env[0] if len(env) == 1 else union_of(env))
    except (shapely.errors.GEOSException, ValueError):
        return None
    a0 = _lib_area(material)
    total = a0 - _lib_area(after)
    tol = 1e-10 + 1e-13 * a0
    if not (abs(float(ub.sum()) - total) <= tol and float(ub.min()) >= -tol):
        return None
    ks = np.flatnonzero(ub > 1e-12)
    removed_area[c0 + b0 + ks] = ub[ks]
    touch = ks[ub[ks] > TOUCH_AREA] + b0
    if len(touch):
        nc_hit: set[int] = set()
        lo, hi = np.searchsorted(run.quad_owner, [b0, b1])
        if hi > lo:
            shapely.prepare(material)
            nc_hit = run.non_cutting_candidates(material, b0, b1)
            shapely.destroy_prepared(material)
        for k in touch.tolist():
            nc = k in nc_hit
            if nc or run.checked[k]:
                m = run.moves[k]
                g = run.sweep(k)
                before = list(run.sweep_of(idx[idx < k]))
                _check_move(m, _local_before(material, g, before), g, sweeper.shape(m),
                            run.path(k), toolpath, issues, notes, nc)
    return after


def _local_before(material: BaseGeometry, g: BaseGeometry, before: list) -> BaseGeometry:
    """The material round the sweep ``g`` (within SEAM of it) once the sweeps ``before`` (the
    moves before it in its batch) are taken out."""
    zone = shapely.buffer(g, SEAM, join_style="mitre")
    local = inter(material, zone)
    if before and not local.is_empty:
        near = [h for h in before if h is not None and shapely.intersects(h, zone)]
        if near:
            local = diff(local, union_of(near))
    return local


def _batch_by_moves(material, run: "_Run", c0, b0, b1, idx, geoms, removed_area, sweeper,
                    toolpath, issues, notes):
    """Take a batch out of the material move after move (one overlay per move that meets the
    material, within the batch's zone, or in the whole material when it is small:
    :data:`SMALL_MATERIAL`). Returns the material after it (``material`` itself
    when the batch removed nothing)."""
    # the material the batch can meet: inside the convex hull of its sweeps, grown by SEAM so
    # that the zone's boundary lies off every sweep (an overlay, not GEOS's rectangle clip,
    # which can return a wrong region for a valid polygon)
    if shapely.get_num_coordinates(material) <= SMALL_MATERIAL:
        zone = None  # a small material: taken whole, without a zone's two overlays
        local0 = material
    else:
        hull = shapely.convex_hull(shapely.geometrycollections(geoms))
        zone = shapely.buffer(hull, SEAM, join_style="mitre")
        local0 = inter(material, zone)
    if local0.is_empty:
        return material
    shapely.prepare(local0)
    # the local material only shrinks: a sweep that misses it now misses it later too
    hit = shapely.intersects(local0, geoms)
    nc_hit = run.non_cutting_candidates(local0, b0, b1)
    shapely.destroy_prepared(local0)
    local = local0
    local_area = _lib_area(local)
    cm = run.moves
    kinds = run.columns["kind"]
    for k, g in zip(idx[hit].tolist(), geoms[hit].tolist()):
        # a sweep that missed the batch's material may still miss what the moves before it
        # in the batch left (a rapid back over their cut): a test, no overlay (not prepared:
        # the material changes after most moves, and preparing it costs more than one test);
        # a rapid mostly runs along what was cut, meeting it on its boundary only: its
        # interior is tested against the material's (it removes nothing unless they meet),
        # after the cheaper test that it meets the material at all (most rapids of a short
        # pass, back over what the pass cut, no longer do)
        if kinds[k] == _RAPID:
            if ((local is not local0 and not _lib_intersects(local, g))
                    or not _lib_relate_pattern(local, g, "T********")):
                continue
        elif local is not local0 and not _lib_intersects(local, g):
            continue
        after = _difference(local, g)
        after_area = _lib_area(after)
        a = local_area - after_area
        if a > 1e-12 + 1e-15 * local_area:  # more than the rounding of the areas
            removed_area[c0 + k] = a
            if a > TOUCH_AREA:
                nc = k in nc_hit
                if nc or run.checked[k]:
                    m = cm[k]
                    _check_move(m, local, g, sweeper.shape(m), run.path(k),
                                toolpath, issues, notes, nc)
            local, local_area = after, after_area
    if local is local0:
        return material
    if zone is None:
        return local
    # the material outside the zone is untouched; both pieces meet on the zone's boundary at
    # the same nodes (one noding of the material with the zone for both overlays)
    return union_of([diff(material, zone), local])


def material_after(machined: Machined, moves: Iterable[int]) -> list[tuple[int, BaseGeometry]]:
    """The material on the machine after the first k moves of ``machined``'s toolpath, for each
    k of ``moves`` (0 <= k <= number of moves), as ``[(k, region), ...]`` in increasing k: the
    toolpath simulated again from ``machined.stock`` with ``machined.machine``
    (:func:`simulate` with ``snapshots``), so each region is exactly the simulation's state
    there, fallen pieces gone; k = 0 gives the stock, the last move the final material. What
    the first k moves removed is ``machined.stock`` minus that region."""
    out: list[tuple[int, BaseGeometry]] = []
    simulate(machined.toolpath, machined.stock, machined.machine, snapshots=moves,
             on_snapshot=lambda k, g: out.append((k, g)))
    return out


@contextmanager
def _gc_paused():
    """The cyclic garbage collector off for the block (as it was after)."""
    was = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was:
            gc.enable()


def _boxes_meet(g: BaseGeometry, bb: np.ndarray) -> bool:
    """Whether the bounds of ``g`` meet the box round the bounds ``bb`` (rows z0, x0, z1, x1)."""
    z0, x0, z1, x1 = _lib_bounds(g).tolist()
    lo, hi = bb.min(axis=0).tolist(), bb.max(axis=0).tolist()
    return not (lo[0] > z1 or hi[2] < z0 or lo[1] > x1 or hi[3] < x0)


def _checked(m: Move) -> bool:
    """Whether :func:`_check_move` can find anything for ``m`` other than a non-cutting side
    (those are found by their candidates): a rapid, or a move with the spindle stopped or at
    zero feed."""
    return (m.kind not in FEED_KINDS or m.spindle <= 0 or m.feed is None or m.feed <= 0)


def _where(rem: BaseGeometry) -> str:
    z0, x0, z1, x1 = rem.bounds
    return f"Z {z0:.3f}..{z1:.3f}, X {2 * x0:.3f}..{2 * x1:.3f} (dia)"


def _touches(rem: BaseGeometry) -> bool:
    return rem.area > TOUCH_AREA and _thickness(rem) > TOUCH_THICK


def first_contact(local: BaseGeometry, shape: ToolShape, path: np.ndarray) -> tuple[float, float] | None:
    """(x radius, z) where the tool moving along ``path`` ((z, x) points of the controlled
    point) first touches ``local`` (the material before the move), as :func:`_check_move`
    counts touching: the first straight piece whose sweep touches it, then the shortest
    stretch of that piece that does (bisection to 1e-6 of the piece), and the centre of what
    that stretch removes (a sliver about as deep as the touch thresholds allow: some 0.002 mm
    under a nose radius of 0.8 mm, so the point lies that close to the first contact)."""
    if len(path) < 2:
        return None
    hulls = sweep_hulls(shape.outline, path[:-1], path[1:])
    try:
        areas = shapely.area(shapely.intersection(local, hulls))
    except shapely.errors.GEOSException:
        areas = np.array([inter(local, h).area for h in hulls])
    K = _ccw_outline(shape)
    m = len(K)
    for k in np.flatnonzero(areas > TOUCH_AREA).tolist():
        near = inter(local, hulls[k])  # the material the piece meets: all its stretches need
        if not _touches(near):
            continue
        p, q = path[k], path[k + 1]
        # the hull of a stretch p -> p + t (q - p): the same vertices of K at either end for
        # every t > 0 (the ring of sweep_hulls)
        nrm = np.array([p[1] - q[1], q[0] - p[0]])
        sv = K @ nrm
        i_min, i_max = int(np.argmin(sv)), int(np.argmax(sv))
        c = (i_max - i_min) % m
        t = np.arange(m + 2)
        fwd = t <= c
        base = K[(i_min + np.where(fwd, t, t - 1)) % m]

        def stretch(u: float) -> BaseGeometry:
            ring = base + np.where(fwd[:, None], p + u * (q - p), p)
            return Polygon(np.concatenate([ring, ring[:1]]))

        lo, hi = 0.0, 1.0
        for _ in range(20):
            mid = (lo + hi) / 2
            if _touches(inter(near, stretch(mid))):
                hi = mid
            else:
                lo = mid
        rem = inter(near, stretch(hi))
        if rem.is_empty:
            return None
        a = rem.centroid
        if not rem.contains(a):
            a = rem.point_on_surface()
        return (float(a.y), float(a.x))
    return None


def _check_move(m: Move, local: BaseGeometry, sweep: BaseGeometry, shape: ToolShape,
                path: np.ndarray, tp: Toolpath, issues: list[Issue], notes: list[Issue],
                maybe_non_cutting: bool = True) -> None:
    """The checks for a move that removed more than TOUCH_AREA from ``local`` (the material
    around it just before the move) with its swept region ``sweep``."""
    stopped = m.kind in FEED_KINDS and m.spindle <= 0  # thread moves: found before the cut
    no_feed = m.kind in FEED_KINDS and (m.feed is None or m.feed <= 0)
    if m.kind == "rapid" or stopped or no_feed:
        rem = inter(local, sweep)
        if not (rem.area > TOUCH_AREA and _thickness(rem) > TOUCH_THICK):
            return
        block = tp.block(m.line)
        if m.kind == "rapid":
            depth = 2 * shapely.maximum_inscribed_circle(rem, 1e-3).length
            if depth >= RAPID_DEPTH:
                issues.append(Issue(m.line, block, f"rapid move cuts material ({rem.area:.3f} mm^2, "
                                    f"{depth:.3f} mm deep at {_where(rem)})", "collision",
                                    first_contact(local, shape, path)))
            else:
                notes.append(Issue(m.line, block, f"rapid move shaves a sliver {depth:.3f} mm thick "
                                   f"({rem.area:.4f} mm^2 at {_where(rem)})", "rapid-sliver"))
            return
        if stopped:
            if m.kind != "thread":
                issues.append(Issue(m.line, block, f"feed move cuts material while the spindle is not turning "
                                    f"({rem.area:.3f} mm^2 at {_where(rem)})", "spindle",
                                    first_contact(local, shape, path)))
        elif no_feed:  # a stopped spindle is one finding (under G95 its feed is 0 as well)
            issues.append(Issue(m.line, block, f"move at feed 0 cuts material "
                                f"({rem.area:.3f} mm^2 at {_where(rem)})", "feed",
                                first_contact(local, shape, path)))
    if maybe_non_cutting and m.kind in FEED_KINDS and shape.non_cutting and len(path) >= 2:
        hit = _non_cutting_hit(shape, path, local)
        if hit is not None:
            issues.append(Issue(m.line, tp.block(m.line), f"cuts with a non-cutting side of the "
                                f"tool ({shape.description}): {hit.area:.3f} mm^2 at {_where(hit)}",
                                "non-cutting"))


_SIDES: dict[tuple, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}


def _sides(shape: ToolShape) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(starts, ends, outward normals) of a shape's non-cutting sides, cached."""
    got = _SIDES.get(shape.key)
    if got is None:
        a = np.array([s[0] for s in shape.non_cutting], dtype=float)
        b = np.array([s[1] for s in shape.non_cutting], dtype=float)
        d = b - a
        nrm = np.column_stack([d[:, 1], -d[:, 0]])
        out = np.einsum("ij,ij->i", nrm, (a + b) / 2 - shape.outline.mean(axis=0)) < 0
        nrm[out] = -nrm[out]
        got = (a, b, nrm)
        _SIDES[shape.key] = got
    return got


def _leading_quads(shape: ToolShape, path: np.ndarray) -> np.ndarray:
    """(n, 4, 2) parallelograms swept by the non-cutting sides that lead along ``path``."""
    a, b, nrm = _sides(shape)
    p, q = path[:-1], path[1:]
    mv = q - p
    lead = (mv @ nrm.T) > 1e-12 * (np.hypot(mv[:, 0], mv[:, 1])[:, None] + 1e-12)
    pi, si = np.nonzero(lead)
    return np.stack([a[si] + p[pi], b[si] + p[pi], b[si] + q[pi], a[si] + q[pi]], axis=1)


def _non_cutting_hit(shape: ToolShape, path: np.ndarray, rem: BaseGeometry) -> BaseGeometry | None:
    """Material of ``rem`` (the material before the move) swept by a leading non-cutting side
    of the tool, if significant.

    Only sides whose outward normal has a positive component along the motion lead; a trailing
    side passes only where the tool body already was. A side translated along a straight piece
    of the path sweeps a parallelogram."""
    quads = _leading_quads(shape, path)
    if not len(quads):
        return None
    polys = shapely.polygons(quads)
    hits = polys[shapely.intersects(rem, polys)]
    if not len(hits):
        return None
    hit = clean(rem.intersection(shapely.union_all(hits)))
    if hit.area > 1e-3 and _thickness(hit) > 2e-3:
        return hit
    return None


def _thread_spans(moves: Iterable[Move], machine: Machine,
                  kind: np.ndarray | None = None) -> list[ThreadSpan]:
    """Z/X extent of each run of thread moves with the same register and lead (``kind``: the
    moves' kinds if known)."""
    spans: list[ThreadSpan] = []
    moves = moves if isinstance(moves, (list, tuple)) else list(moves)
    if kind is not None and len(kind) == len(moves):
        threads = [moves[k] for k in np.flatnonzero(kind == _THREAD).tolist()]
    else:
        threads = []
        for c0 in range(0, len(moves), CHUNK):
            cm = moves[c0:c0 + CHUNK]
            threads += [cm[k] for k in np.flatnonzero(columns(cm)["kind"] == _THREAD).tolist()]
    for m in threads:
        reg = machine.register(m.register)
        inside = reg.tip in (1, 2, 6)
        z0, z1 = sorted((m.start[1], m.end[1]))
        x0, x1 = sorted((m.start[0], m.end[0]))
        for s in spans:
            if s.inside == inside and z0 <= s.z_max + 1e-6 and z1 >= s.z_min - 1e-6:
                s.z_min, s.z_max = min(s.z_min, z0), max(s.z_max, z1)
                s.x_min, s.x_max = min(s.x_min, x0), max(s.x_max, x1)
                break
        else:
            spans.append(ThreadSpan(z0, z1, x0, x1, inside, m.lead, m.thread_angle or 60.0))
    return spans

