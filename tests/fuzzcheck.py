"""What every run of an arbitrary program must give, in any dialect: a toolpath of finite
moves, or an alarm that is one printable line placed inside the text — never another
exception."""
from __future__ import annotations

import math

from hnc_cam.errors import NCError
from hnc_cam.nc import parser as P
from hnc_cam.nc import run
from hnc_cam.nc.toolpath import Toolpath


def outcome(text: str, machine=None, **kw):
    """Run ``text`` (``kw``: :func:`hnc_cam.nc.run`'s options, e.g. ``dialect``,
    ``step_limit``, ``start``) and check the result; returns the toolpath or the alarm."""
    lines = max(1, len(P.split_lines(text)))
    try:
        tp = run(text, machine, **kw)
    except NCError as e:
        assert isinstance(e.message, str) and e.message
        assert isinstance(e.line, int) and isinstance(e.col, int) and e.col >= 0
        assert 0 <= e.line <= lines, (e.line, str(e))
        line = e.one_line()
        assert line.isprintable() and len(line) < 1200, line  # one printable line, bounded
        return e
    assert isinstance(tp, Toolpath)
    for m in tp.moves:
        assert math.isfinite(m.start[0]) and math.isfinite(m.end[0]) and math.isfinite(m.end[1])
        assert m.duration >= 0
    for w in tp.warnings:
        assert 0 <= w.line <= lines
    return tp
