"""SINUMERIK 802 arithmetic parameters (``docs/SIEMENS.md`` §3).

``R0``-``R249`` are the program's parameters (``R100``-``R249`` the cycles' transfer
parameters by convention), ``R250``-``R299`` the cycles' internal ones; every parameter is
0.0 until it is written, and keeps its value across subprogram calls (one global set).
``_CNAME``-style names hold text (the contour name of LCYC95). In the shared statement model
parameter ``Rn`` is variable ``#(n+1)`` (:data:`~.syntax.R_BASE`): the store is a list indexed
by the variable number, so the expression compiler's fast paths (``L[n]``, ``G[n]``) and the
executor's reader both land on it.
"""
from __future__ import annotations

from ...nc.expr import EvalError
from .syntax import R_BASE, R_MAX

#: the map the dialect value names: kind -> R number ranges
MEMORY_MAP = {"program": (0, 99), "transfer": (100, 249), "cycle": (250, 299)}
SIZE = R_MAX + R_BASE + 1


class SiemensMemory:
    """Reads and writes of R parameters and text variables (methods of the interpreter)."""

    def _init_memory(self) -> None:
        self.rstore = [0.0] * SIZE
        self.L = self.G = self.rstore
        self.levels = [self.rstore]
        self.texts: dict[str, str] = {}

    def _read(self, n, strict_vacant: bool = True):
        if n is None:
            raise EvalError("undefined parameter")
        if isinstance(n, float) and not n.is_integer() or n != n:
            raise EvalError(f"invalid parameter number {n - R_BASE:g}")
        i = int(n)
        if not R_BASE <= i < SIZE:
            raise EvalError(f"R{i - R_BASE}: the arithmetic parameters are R0-R{R_MAX}")
        return self.rstore[i]

    _sread = _read

    def _write(self, n, v, line: int, col: int) -> None:
        i = int(n)
        if not R_BASE <= i < SIZE:
            raise self.alarm(f"R{i - R_BASE}: the arithmetic parameters are R0-R{R_MAX}", line, col)
        self.rstore[i] = float(v)

    def r(self, n: int) -> float:
        """The value of ``Rn`` (0.0 when never written)."""
        return self.rstore[int(n) + R_BASE]

    def set_r(self, n: int, value: float) -> None:
        n = int(n)
        if not 0 <= n <= R_MAX:
            raise ValueError(f"R{n}: the arithmetic parameters are R0-R{R_MAX}")
        self.rstore[n + R_BASE] = float(value)

    def _modal(self, grp: int) -> int:  # pragma: no cover - no system variables on the 802
        return 0
