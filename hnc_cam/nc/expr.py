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


_NS: dict[str, Any] = {k: v for k, v in globals().items()
                       if k.startswith(("C_", "F_")) or k in ("AND", "OR", "NOT", "D")}
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
