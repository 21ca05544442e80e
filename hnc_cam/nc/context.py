"""What a cycle may ask of the interpreter (implemented by the interpreter, used by the
cycle modules). All coordinates are **programmed work coordinates, X as radius**; the
interpreter applies tool offsets and nose-radius compensation, computes durations, and
stamps each move with the cycle block's line, tool and spindle state.
"""
from __future__ import annotations

from typing import NoReturn, Optional, Protocol

from ..geometry import Point, Segment


class CycleContext(Protocol):
    code: int  # the cycle's G code (32, 71, 72, 73, 76, 80, 81, 82)
    line: int  # 1-based source line of the cycle block
    incremental: bool  # G91 active
    diameter_mode: bool  # G36 active (X words are diameters)
    max_passes: int  # the machine's limit of passes of one cycle block ([limits] cycle_passes)
    moves_left: int  # moves the toolpath may still take ([limits] moves)

    @property
    def pos(self) -> Point:
        """Current programmed position (x radius, z): the cycle start point A."""

    def word(self, letter: str) -> Optional[float]:
        """Evaluated value of a word in the cycle block exactly as programmed
        (X still a diameter in G36, still incremental in G91), or None when absent.
        For the modal G80/G81/G82, words not in this block come from the previous
        block of the same cycle (the interpreter keeps them)."""

    def has(self, letter: str) -> bool: ...

    def alarm(self, message: str, letter: Optional[str] = None) -> NoReturn:
        """Raise NCError at the cycle block (at the column of word ``letter`` if given)."""

    def warn(self, message: str) -> None: ...

    def profile(self, ns: int, nf: int) -> list[tuple[Segment, int, str]]:
        """The programmed path of the blocks N``ns``..N``nf`` (in file order, in the current
        program), starting from ``pos``: (segment, source line, motion 'rapid'|'feed').
        Chamfer C / round R words are resolved; G41/G42/G40 and F/S/T words are accepted and
        ignored for the geometry. Alarms: P/Q not found, ns not G00/G01, M98/M99 inside.
        Does not change the interpreter's state."""

    def rapid(self, x: float, z: float) -> None:
        """G00 to (x, z): emitted as the real dog-leg."""

    def feed(self, x: float, z: float, feed: Optional[float] = None) -> None:
        """G01 to (x, z) at ``feed`` (F units as programmed, G94/G95 resolved by the
        interpreter; None = the cycle's F or the modal F)."""

    def arc(self, x: float, z: float, center: Point, cw: bool, feed: Optional[float] = None) -> None: ...

    def thread(self, x: float, z: float, lead: float, angle: float = 0.0,
               thread_angle: float = 0.0) -> None:
        """A threading move to (x, z), synchronised with the spindle: ``lead`` mm/rev along the
        thread, spindle start angle ``angle`` deg, tool profile angle ``thread_angle``."""

    def dwell(self, seconds: float) -> None: ...

    # -- SINUMERIK 802 cycles (LCYC82 ... LCYC97; docs/SIEMENS.md) ------------------------------
    name: str  # the cycle's name, the label of its moves ("G71"; "LCYC95")

    def r(self, n: int) -> float:
        """R parameter ``n`` (0.0 when never written)."""

    def set_r(self, n: int, value: float) -> None:
        """Write R parameter ``n`` (R250-R299: the cycles' internal parameters)."""

    def text(self, name: str) -> Optional[str]:
        """A string variable (``_CNAME``), None when never assigned."""

    def contour(self, name: str) -> list[tuple[Segment, int, str]]:
        """The subprogram ``name`` dry-run as a profile from ``pos`` (the value of
        :meth:`profile`); its RET/M17 ends it; alarms inside it name its lines."""

    @property
    def plane(self) -> int:
        """17 or 18 (G17/G18)."""

    def tool_nose(self) -> tuple[float, int]:
        """(nose radius, tip direction code) of the active T/D; (0.0, 0) without one."""

    def spindle(self, m: int) -> None:
        """Turn the spindle as M``m`` would (3, 4 or 5) for the cycle's next moves."""
