"""Units as people read them. No imports beyond the standard library: the interpreter and the
simulator use this on their fast path."""
from __future__ import annotations

import math

__all__ = ["fmt_cycle_time"]


def fmt_cycle_time(seconds: float) -> str:
    """``"300.0 s (5:00.0)"``: seconds to 0.1 s, then minutes:seconds of the same rounded
    value (so 299.97 s is ``5:00.0``, never ``4:60.0``); hours as ``h:mm:ss.s``."""
    if not math.isfinite(seconds):
        return f"{seconds} s"
    tenths = int(round(abs(seconds) * 10))
    sign = "-" if seconds < 0 and tenths else ""
    m, t = divmod(tenths, 600)
    clock = f"{m}:{t // 10:02d}.{t % 10}"
    if m >= 60:
        h, m = divmod(m, 60)
        clock = f"{h}:{m:02d}:{t // 10:02d}.{t % 10}"
    return f"{sign}{tenths // 10}.{tenths % 10} s ({sign}{clock})"


def round_written(v: float, digits: int = 3) -> float:
    """``v`` to ``digits`` decimals, a half of the last digit (to a millionth of it) rounded
    up, toward +inf: the rule a computed coordinate the planner writes rounded (a roughing
    cycle's split on a chamfer) follows, and the one a macro program reproduces at the
    control in every dialect (``INT``/``FIX``/``TRUNC`` of a positive number, the same
    millionth added). A rounding of the binary value (Python's ``round``) breaks an exact
    tie either way, the control's arithmetic another."""
    s = 10.0 ** digits
    return math.floor(v * s + 0.500001) / s
