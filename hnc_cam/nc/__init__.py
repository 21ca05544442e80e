"""The interpreter: program text -> :class:`Toolpath` (see ``interp``), for the HNC-21/22T
and the other dialects of :mod:`hnc_cam.dialect` (FANUC 0i-T, Haas).

``run(text, machine=None, *, dialect=None, file=..., step_limit=None, start="reference",
diameter=None, persist=None)`` and ``run_file(path, machine=None, **same)`` are the entry
points; ``dialect`` is a name or a Dialect value (default: the machine file's
``controller``, else ``hnc21t``). Nothing heavy is imported here.
"""
from .interp import run, run_file
from .toolpath import Move, Toolpath

__all__ = ["Move", "Toolpath", "run", "run_file"]
