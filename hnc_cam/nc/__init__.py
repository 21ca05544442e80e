"""The HNC-21/22T interpreter: program text -> :class:`Toolpath` (see ``interp``).

``run(text, machine=None, file=..., step_limit=None, start="reference", diameter=None)`` and
``run_file(path, machine=None)`` are the entry points. Nothing heavy is imported here.
"""
from .interp import run, run_file
from .toolpath import Move, Toolpath

__all__ = ["Move", "Toolpath", "run", "run_file"]
