"""The interpreter's modal state as one value.

:class:`ModalState` holds the modal values a block leaves behind (motion code, absolute or
incremental, diameter or radius X, unit, feed mode, spindle mode and speed, compensation,
work system, F, tool). The interpreter keeps them as plain attributes (its plain-block path
reads and writes them without allocating); where the state must be set aside and put back —
a compound cycle's dry run of its profile — it takes a ``ModalState`` and restores it, so a
cycle's save and restore is one value and not a list of names.
"""
from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any, Optional


@dataclass(frozen=True, slots=True)
class ModalState:
    motion: int = 0
    absolute: bool = True
    diam: bool = True
    unit: float = 1.0
    per_rev: bool = False
    css: bool = False
    comp: int = 40
    wcs: int = 54
    F: Optional[float] = None
    s_rpm: float = 0.0
    vc: float = 0.0
    sdir: int = 5
    coolant: bool = False
    tool: int = 0
    reg: int = 0

    @classmethod
    def of(cls, obj: Any) -> "ModalState":
        """The modal state of an interpreter (any object with these attributes)."""
        return cls(*[getattr(obj, n) for n in MODAL_FIELDS])

    def apply(self, obj: Any) -> None:
        """Put this state back on ``obj``."""
        for n in MODAL_FIELDS:
            setattr(obj, n, getattr(self, n))


MODAL_FIELDS = tuple(f.name for f in fields(ModalState))
