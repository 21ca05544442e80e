"""The turned part as the rest of the pipeline sees it: exact chains in (radius, Z).

Produced by :func:`hnc_cam.cad.profile` from a solid; read by the planner and by the
verifier (which must not import the CAD front end, hence this lives in the kernel).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

from .primitives import Segment, iter_points


@dataclass(frozen=True)
class Thread:
    """A thread the part declares (the solid models only its major diameter, or the bore's
    minor diameter for an internal thread).

    ``z_start`` is the end nearer the right face (larger Z), ``z_end`` the end toward the
    chuck; ``diameter`` the nominal (major) diameter; ``pitch`` the pitch; ``starts`` the
    number of starts (lead = pitch * starts); ``internal`` for a thread in the bore;
    ``standard`` such as ``"metric"`` (ISO 60 deg); ``angle`` the profile angle; ``taper``
    the change of the diameter per mm of length from ``z_start`` toward ``z_end`` (a taper
    thread: 1/16 = 0.0625 for NPT/BSPT, whose diameter grows toward the chuck; negative for
    one narrowing toward the chuck; 0 straight). On a taper thread ``diameter`` is the
    largest major diameter: at ``z_end`` for a positive taper, at ``z_start`` for a negative.
    """
    z_start: float
    z_end: float
    diameter: float
    pitch: float
    starts: int = 1
    internal: bool = False
    standard: str = "metric"
    angle: float = 60.0
    taper: float = 0.0

    @property
    def lead(self) -> float:
        return self.pitch * self.starts

    def major_at(self, z: float) -> float:
        """The major diameter at ``z`` (the taper line, also beyond the thread's ends)."""
        if self.taper >= 0:
            return self.diameter - self.taper * (z - self.z_end)
        return self.diameter + self.taper * (self.z_start - z)

    @property
    def depth(self) -> float:
        """Radial thread depth of the ISO metric basic profile, external: 0.6134 P
        (internal: 0.5413 P)."""
        return (0.5413 if self.internal else 0.6134) * self.pitch

    @property
    def minor_diameter(self) -> float:
        """Minor diameter the thread must reach (external: d3 = d - 1.2269 P). On a taper
        thread the smallest along its full form, one pitch in from its small end (where
        verification measures the thread from)."""
        d = self.diameter
        if self.taper > 0:
            d = self.major_at(self.z_start - self.pitch)
        elif self.taper < 0:
            d = self.major_at(self.z_end + self.pitch)
        return d - 2 * self.depth if not self.internal else d - 1.0825 * self.pitch


@dataclass
class TurnedProfile:
    """Exact outline of a turned part in the half-plane X >= 0 (X = radius).

    ``outside``: the outer contour from the right end (largest Z, usually starting on the
    axis at the right face) toward the chuck (smallest Z), as a connected chain of Line/Arc.
    ``bore``: the bore contour in the same direction (from the right face to the left end),
    or None for a solid part. ``z_max`` is the right face (program zero by default),
    ``z_min`` the left end.
    """
    outside: list[Segment]
    bore: list[Segment] | None = None
    threads: list[Thread] = field(default_factory=list)
    name: str = "part"
    params: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)  # what profiling ignored or fitted

    @property
    def z_max(self) -> float:
        return max(p[1] for p in self._all_points())

    @property
    def z_min(self) -> float:
        return min(p[1] for p in self._all_points())

    @property
    def length(self) -> float:
        return self.z_max - self.z_min

    @property
    def max_radius(self) -> float:
        return max(max(s.bbox()[2] for s in self.outside), 0.0)

    @property
    def max_diameter(self) -> float:
        return 2 * self.max_radius

    @property
    def min_bore_radius(self) -> float | None:
        if not self.bore:
            return None
        return min(s.bbox()[0] for s in self.bore)

    def _all_points(self) -> list:
        pts = list(iter_points(self.outside))
        if self.bore:
            pts += list(iter_points(self.bore))
        return pts

    def bbox(self) -> tuple[float, float, float, float]:
        """(xmin, zmin, xmax, zmax) with x as radius."""
        segs: Sequence[Segment] = list(self.outside) + list(self.bore or [])
        bbs = [s.bbox() for s in segs]
        return (min(b[0] for b in bbs), min(b[1] for b in bbs),
                max(b[2] for b in bbs), max(b[3] for b in bbs))
