"""Macro B expressions (manual §3.4.2): compiled once to Python closures.

An expression parsed by :mod:`hnc_cam.nc.parser` is an AST of tuples; :func:`compile_expr`
turns it into Python source and ``eval``s that into a function ``f(L, G, R, A)`` where

* ``L`` is the list of the current level's 50 local variables (``#0``–``#49``),
* ``G`` the list of globals indexed by variable number (``#50``–``#199``),
* ``R(n)`` reads any variable by number (indirect ``#[expr]``, levels, tool registers,
  system variables) and validates the number,
* ``A(n)`` is the ``AR[#n]`` system macro (0 / 90 / 91).

A variable never assigned is *vacant* (``None``). The fast closure indexes ``L``/``G``
directly; Python then raises ``TypeError`` on a vacant operand, and the interpreter
re-evaluates the *strict* closure (every read through ``R``) to name the variable.

Semantics where the manual is silent (documented choices):

* angles in radians (``COS[55*PI/180]`` in the manual);
* comparisons ``EQ NE GT GE LT LE`` use a tolerance of 1e-9 (relative above 1), so that a
  loop stepping by 0.08 reaches its end value 16 as the manual's example %8002 intends;
* ``AND OR NOT`` are logical (non-zero is true) and give 1 or 0; ``TRUE`` = 1, ``FALSE`` = 0;
* ``INT`` truncates toward zero, ``SIGN`` gives -1, 0 or 1;
* precedence, lowest first: ``OR``; ``AND``; ``NOT``; comparisons (not chained);
  ``+ -``; ``* /``; unary ``+ -``; functions, ``[ ]`` and ``#``.

FANUC custom macro B (``docs/FANUC.md`` §10) compiles through :func:`fanuc_source` into a
:class:`FanucExpr`: functions in degrees (the ``K_*`` functions), ``AND OR XOR`` bitwise and
``MOD`` on whole numbers, and FANUC's null rules (a null variable is 0 in arithmetic, ``EQ``/
``NE`` compare it as null, a bare variable keeps it). Its locals ``#1``–``#33`` are read from
``L`` and its commons ``#100``–``#199`` from ``G`` by their own numbers, everything else through
``R``.
"""
from __future__ import annotations

import math
from typing import Any, Callable


class EvalError(Exception):
    """Raised while evaluating; the interpreter turns it into an :class:`NCError` at the
    statement (``col`` 0 = the expression's own column)."""

    def __init__(self, message: str, col: int = 0):
        super().__init__(message)
        self.message = message
        self.col = col


_TOL = 1e-9


def _tol(a: float, b: float) -> float:
    m = abs(a) if abs(a) > abs(b) else abs(b)
    return _TOL * m if m > 1.0 else _TOL


def C_EQ(a, b):
    return 1.0 if abs(a - b) <= _tol(a, b) else 0.0


def C_NE(a, b):
    return 0.0 if abs(a - b) <= _tol(a, b) else 1.0


def C_GT(a, b):
    return 1.0 if a > b + _tol(a, b) else 0.0


def C_GE(a, b):
    return 1.0 if a >= b - _tol(a, b) else 0.0


def C_LT(a, b):
    return 1.0 if a < b - _tol(a, b) else 0.0


def C_LE(a, b):
    return 1.0 if a <= b + _tol(a, b) else 0.0


def AND(a, b):
    return 1.0 if (a + 0.0) != 0.0 and (b + 0.0) != 0.0 else 0.0


def OR(a, b):
    return 1.0 if (a + 0.0) != 0.0 or (b + 0.0) != 0.0 else 0.0


def NOT(a):
    return 0.0 if (a + 0.0) != 0.0 else 1.0


def D(a, b):
    if b == 0:
        raise EvalError("division by zero")
    return a / b


def F_SIN(a):
    return math.sin(a)


def F_COS(a):
    return math.cos(a)


def F_TAN(a):
    return math.tan(a)


def F_ATAN(a, b=None):
    return math.atan(a) if b is None else math.atan2(a, b)


def F_ATAN2(a, b=None):
    if b is None:
        raise EvalError("ATAN2 needs two arguments: ATAN2[y, x]")
    return math.atan2(a, b)


def F_ABS(a):
    return abs(a + 0.0)


def F_INT(a):
    return float(math.trunc(a))


def F_SIGN(a):
    return 1.0 if a > 0 else -1.0 if a < 0 else 0.0


def F_SQRT(a):
    if a < 0:
        raise EvalError(f"SQRT of a negative number ({a:g})")
    return math.sqrt(a)


def F_EXP(a):
    try:
        return math.exp(a)
    except OverflowError:
        raise EvalError(f"EXP[{a:g}] overflows") from None


# -- FANUC custom macro B (docs/FANUC.md §10): functions in degrees, bitwise logic, null ----
_DEG = math.pi / 180.0


def _finite_arg(name: str, a: float) -> float:
    if not math.isfinite(a):
        raise EvalError(f"{name} of a number that is not finite")
    return a


def K_SIN(a):
    return math.sin(_finite_arg("SIN", a) * _DEG)


def K_COS(a):
    return math.cos(_finite_arg("COS", a) * _DEG)


def K_TAN(a):
    c = math.cos(_finite_arg("TAN", a) * _DEG)
    if abs(c) < 1e-15:
        raise EvalError(f"TAN[{a:g}] is infinite")
    return math.sin(a * _DEG) / c


def K_ASIN(a):
    """Degrees 270-360 and 0-90 (FANUC's default range, parameter 6004#0 = 0)."""
    if not -1.0 <= a <= 1.0:
        raise EvalError(f"ASIN of {a:g}: the argument must be -1..1")
    d = math.degrees(math.asin(a))
    return d + 360.0 if d < 0.0 else d


def K_ACOS(a):
    if not -1.0 <= a <= 1.0:
        raise EvalError(f"ACOS of {a:g}: the argument must be -1..1")
    return math.degrees(math.acos(a))


def K_ATAN(a, b=1.0):
    """``ATAN[a]/[b]``: the angle of the point (b, a), 0-360 degrees (parameter 6004#0 = 0)."""
    if a == 0.0 and b == 0.0:
        raise EvalError("ATAN[0]/[0]: the angle of the origin is undefined")
    d = math.degrees(math.atan2(a, b))
    return d + 360.0 if d < 0.0 else d


K_SQRT = F_SQRT  # no angle in it: the HNC-21T's function


def K_ABS(a):
    return abs(a + 0.0)


def K_LN(a):
    if a <= 0:
        raise EvalError(f"LN of {a:g}: the argument must be positive")
    return math.log(a)


K_EXP = F_EXP


def K_ROUND(a):
    """Nearest integer, halves away from zero."""
    return float(math.floor(abs(a) + 0.5)) * (1.0 if a >= 0 else -1.0)


K_FIX = F_INT  # toward zero: FIX[1.2] = 1, FIX[-1.2] = -1


def K_FUP(a):
    """Away from zero: FUP[1.2] = 2, FUP[-1.2] = -2."""
    return float(math.ceil(a)) if a >= 0 else float(math.floor(a))


def _whole(name: str, a: float) -> int:
    if not math.isfinite(a) or abs(a) > 1e15:
        raise EvalError(f"{name}: {a:g} is not a whole number the control can hold")
    return int(K_ROUND(a))


def K_BIN(a):
    """BCD to binary: BIN[37] (0x25) = 25."""
    n = _whole("BIN", a)
    if n < 0:
        raise EvalError(f"BIN of {a:g}: a BCD value is not negative")
    out, scale = 0, 1
    while n:
        digit = n & 15
        if digit > 9:
            raise EvalError(f"BIN of {a:g}: not a BCD value (a 4-bit digit above 9)")
        out += digit * scale
        scale *= 10
        n >>= 4
    return float(out)


def K_BCD(a):
    """Binary to BCD: BCD[25] = 37 (0x25)."""
    n = _whole("BCD", a)
    if n < 0:
        raise EvalError(f"BCD of {a:g}: a BCD value is not negative")
    out, shift = 0, 0
    while n:
        out |= (n % 10) << shift
        shift += 4
        n //= 10
    return float(out)


def K_MOD(a, b):
    """Remainder of the whole numbers nearest ``a`` and ``b``, with the sign of ``a``."""
    x, y = _whole("MOD", a), _whole("MOD", b)
    if y == 0:
        raise EvalError("division by zero (MOD 0)")
    return float(math.fmod(x, y))


def K_AND(a, b):
    return float(_whole("AND", a) & _whole("AND", b))


def K_OR(a, b):
    return float(_whole("OR", a) | _whole("OR", b))


def K_XOR(a, b):
    return float(_whole("XOR", a) ^ _whole("XOR", b))


def K_EQ(a, b):
    """EQ with null: null equals only null (``#1 EQ #0``), never a number."""
    if a is None or b is None:
        return 1.0 if a is None and b is None else 0.0
    return 1.0 if abs(a - b) <= _tol(a, b) else 0.0


def K_NE(a, b):
    return 1.0 - K_EQ(a, b)


_NS: dict[str, Any] = {k: v for k, v in globals().items()
                       if k.startswith(("C_", "F_", "K_")) or k in ("AND", "OR", "NOT", "D")}
_NS["__builtins__"] = {}

_CMP = {"EQ": "C_EQ", "NE": "C_NE", "GT": "C_GT", "GE": "C_GE", "LT": "C_LT", "LE": "C_LE"}

Node = tuple


def to_source(node: Node, strict: bool = False) -> str:
    """Python source of an expression AST (see :mod:`hnc_cam.nc.parser` for the node shapes)."""
    k = node[0]
    if k == "num":
        return repr(float(node[1]))
    if k == "var":
        idx = node[1]
        if not strict and idx[0] == "num":
            v = float(idx[1])
            if v.is_integer():
                n = int(v)
                if 0 <= n < 50:
                    return f"L[{n}]"
                if 50 <= n < 200:
                    return f"G[{n}]"
        return f"R({to_source(idx, strict)})"
    if k == "neg":
        return f"(-{to_source(node[1], strict)})"
    if k == "not":
        return f"NOT({to_source(node[1], strict)})"
    if k == "bin":
        op, a, b = node[1], to_source(node[2], strict), to_source(node[3], strict)
        if op in ("+", "-", "*"):
            return f"({a} {op} {b})"
        if op == "/":
            return f"D({a}, {b})"
        if op in _CMP:
            return f"{_CMP[op]}({a}, {b})"
        return f"{op}({a}, {b})"  # AND / OR
    if k == "call":
        return f"F_{node[1]}({', '.join(to_source(a, strict) for a in node[2])})"
    if k == "ar":
        return f"A({to_source(node[1], strict)})"
    raise ValueError(f"bad expression node {node!r}")  # pragma: no cover


def constant_value(node: Node) -> float | None:
    """The value of an expression made of numbers only, else None."""
    k = node[0]
    if k == "num":
        return float(node[1])
    if k == "neg":
        v = constant_value(node[1])
        return None if v is None else -v
    return None


class Expr:
    """A compiled expression with the column it starts at."""

    __slots__ = ("node", "col", "fn", "_strict")

    def __init__(self, node: Node, col: int):
        self.node = node
        self.col = col
        self.fn: Callable = eval("lambda L, G, R, A: " + to_source(node), _NS)  # noqa: S307
        self._strict: Callable | None = None

    @property
    def strict(self) -> Callable:
        if self._strict is None:
            self._strict = eval("lambda L, G, R, A: " + to_source(node=self.node, strict=True), _NS)  # noqa: S307
        return self._strict


def _fanuc_var(idx: Node, raw: bool) -> str:
    """A FANUC variable read. With a constant number: ``#0`` is null, ``#1``–``#33`` index the
    level's locals ``L`` and ``#100``–``#199`` the commons ``G`` by their own numbers, other
    numbers (and indirect ones) go through ``R``. ``raw`` keeps a null (None) as it is;
    otherwise a null counts as 0."""
    if idx[0] == "num":
        v = float(idx[1])
        if v.is_integer():
            n = int(v)
            if n == 0:
                return "None" if raw else "0.0"
            if 1 <= n <= 33:
                src = f"L[{n}]"
            elif 100 <= n <= 199:
                src = f"G[{n}]"
            else:
                src = f"R({n})"
            return src if raw else f"({src} or 0.0)"
    src = f"R({fanuc_source(idx)})"
    return src if raw else f"({src} or 0.0)"


def fanuc_source(node: Node, raw: bool = False) -> str:
    """Python source of a FANUC macro B expression: functions in degrees (``K_*``), ``AND OR
    XOR`` bitwise on whole numbers, ``MOD``, and FANUC's null rules — a null (vacant)
    variable counts as 0 in arithmetic and in ``GT GE LT LE``, while ``EQ``/``NE`` compare a
    bare variable as null. With ``raw`` a bare variable keeps its null (``#i = #j``)."""
    k = node[0]
    if k == "num":
        return repr(float(node[1]))
    if k == "var":
        return _fanuc_var(node[1], raw)
    if k == "neg":
        return f"(-{fanuc_source(node[1])})"
    if k == "bin":
        op = node[1]
        if op in ("EQ", "NE"):
            return f"K_{op}({fanuc_source(node[2], True)}, {fanuc_source(node[3], True)})"
        a, b = fanuc_source(node[2]), fanuc_source(node[3])
        if op in ("+", "-", "*"):
            return f"({a} {op} {b})"
        if op == "/":
            return f"D({a}, {b})"
        if op in _CMP:
            return f"{_CMP[op]}({a}, {b})"
        if op in ("AND", "OR", "XOR", "MOD"):
            return f"K_{op}({a}, {b})"
    if k == "call":
        return f"K_{node[1]}({', '.join(fanuc_source(a) for a in node[2])})"
    raise ValueError(f"bad expression node {node!r}")  # pragma: no cover


class FanucExpr(Expr):
    """A compiled FANUC macro B expression (see :func:`fanuc_source`). ``fn`` returns a
    float, or None when the whole expression is one null variable (``X#1``, ``#2 = #1``:
    the caller leaves the address out or keeps the variable null). ``strict`` is ``fn``:
    a null never raises."""

    __slots__ = ()

    def __init__(self, node: Node, col: int):
        self.node = node
        self.col = col
        self.fn = eval("lambda L, G, R, A: " + fanuc_source(node, True), _NS)  # noqa: S307
        self._strict = self.fn
