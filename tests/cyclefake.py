"""A stand-in for the interpreter's cycle context (``hnc_cam.nc.context.CycleContext`` plus
``store``, ``setting``, ``resume_after``), for testing a dialect's cycle decoders without a
program: the block's words, the tool's position and the profiles are given; each leg the cycle
emits is recorded as ``(kind, (x radius, z), ...)``."""
from __future__ import annotations

from typing import Any, Callable, Optional

from hnc_cam.errors import NCError


class FakeCycleContext:
    """Legs recorded in :attr:`moves`: ``("rapid", end)``, ``("feed", end)``, ``("arc", end)``,
    ``("thread", end, lead, angle, thread_angle)``, ``("dwell", seconds)``; warnings in
    :attr:`warnings`; the block a cycle resumes after in :attr:`resumed`.

    ``profile`` is a dict ``{(ns, nf): items}`` or a callable ``(ns, nf) -> items`` (it may
    raise :class:`NCError` as the interpreter does for a missing block)."""

    def __init__(self, code: int, words: dict, pos=(0.0, 0.0), *, profile: Any = None,
                 store: Optional[dict] = None, settings: Optional[dict] = None,
                 incremental: bool = False, diameter_mode: bool = True, line: int = 40,
                 max_passes: int = 10_000, moves_left: int = 500_000):
        self.code = code
        self.line = line
        self.incremental = incremental
        self.diameter_mode = diameter_mode
        self.words = dict(words)
        self._pos = (float(pos[0]), float(pos[1]))
        self.moves: list[tuple] = []
        self.warnings: list[str] = []
        self.store = {} if store is None else store
        self.settings = settings or {}
        self._profile: Any = profile if profile is not None else {}
        self.resumed: Optional[int] = None
        self.max_passes = max_passes
        self.moves_left = moves_left

    @property
    def pos(self):
        return self._pos

    def word(self, letter: str):
        return self.words.get(letter)

    def has(self, letter: str) -> bool:
        return letter in self.words

    def alarm(self, message: str, letter: Optional[str] = None):
        raise NCError(message, line=self.line, col=0)

    def warn(self, message: str) -> None:
        self.warnings.append(message)

    def setting(self, key: str, default):
        return self.settings.get(key, default)

    def profile(self, ns, nf):
        if callable(self._profile):
            return self._profile(ns, nf)
        if (ns, nf) not in self._profile:
            raise NCError(f"profile start block N{ns} (P) not found", line=self.line, col=0)
        return self._profile[(ns, nf)]

    def resume_after(self, nf: int) -> None:
        self.resumed = nf

    def _leg(self, kind: str, x: float, z: float, *extra) -> None:
        self.moves.append((kind, (x, z), *extra))
        self._pos = (x, z)

    def rapid(self, x, z):
        self._leg("rapid", x, z)

    def feed(self, x, z, feed=None):
        self._leg("feed", x, z)

    def arc(self, x, z, center, cw, feed=None):
        self._leg("arc", x, z)

    def thread(self, x, z, lead, angle=0.0, thread_angle=0.0):
        self._leg("thread", x, z, lead, angle, thread_angle)

    def dwell(self, seconds):
        self.moves.append(("dwell", seconds))


def run_cycle(table: dict[Any, Callable], code, words: dict, pos, **kw) -> FakeCycleContext:
    """Run ``table[code]`` on a fresh context and return it."""
    ctx = FakeCycleContext(code, words, pos, **kw)
    table[code](ctx)
    return ctx
