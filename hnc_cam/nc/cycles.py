"""Dispatch of the canned and compound cycles.

The interpreter calls :func:`execute` for G32/G80/G81/G82 (motion group 01, with axis words)
and G71/G72/G73/G76 (group 06, one block). Simple and threading cycles live in
``cycles_simple``; the stock-removal cycles (one roughing engine, normalised to one quadrant,
in ``hnc_cam.geometry.roughing``) in ``cycles_rough``.
"""
from __future__ import annotations

from typing import Any

SIMPLE = (32, 80, 81, 82, 76)
ROUGH = (71, 72, 73)


def execute(code: int, ctx: Any) -> None:
    """Run cycle G``code`` of the current block through the interpreter's ``ctx``
    (the :class:`CycleContext` protocol in ``hnc_cam.nc.context``)."""
    if code in SIMPLE:
        from . import cycles_simple
        cycles_simple.execute(code, ctx)
    elif code in ROUGH:
        from . import cycles_rough
        cycles_rough.execute(code, ctx)
    else:  # pragma: no cover - the interpreter only dispatches the codes above
        ctx.alarm(f"G{code:02d} is not a cycle")
