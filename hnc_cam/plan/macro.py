"""The exact parameter side of one parametric macro program per part family.

*Trace*: :func:`_trace` runs the part file's ``sketch(**params)`` once with :class:`Sym`
numbers (the nominal value plus an exact expression of the parameters) in place of the real
parameters, with a tracing :class:`_TraceOutline`, a ``math`` shim and symbolic ``min``/
``max`` in the module's globals. Every contour point, corner trim (a chamfer's legs, a
fillet's tangent points ``r*|u1 x u2|/(1+u1.u2)``) and arc radius becomes an exact expression
(:func:`features`); every ``require``/``positive``/``non_negative`` condition and every corner
that must fit becomes a :class:`Check` (the conditions, the family's message, the parameters
it names); other comparisons the sketch branches on are kept as ``branches`` (the conditions
under which the traced shape holds). Whole-number parameters (a count of waves) stay numbers.

*Write*: :func:`render` writes an expression in the dialect's macro syntax (HNC-21T: ``#50``,
``SQRT[...]``, radians; FANUC: trigonometry in degrees), :class:`Lets` writes a family of
them with their shared parts assigned once to temporaries within the control's variable
range, :func:`_cond` a check's condition.

:func:`load_family` gives the family at its nominal parameters with its domain box.
"""
from __future__ import annotations

import math
import os
import sys
from dataclasses import dataclass, field
from typing import Any, Callable

from ..errors import PartError, PlanError

# ------------------------------------------------------------------------------------------
# symbolic numbers
# ------------------------------------------------------------------------------------------

# expression nodes: ("c", v) | ("p", name) | (op, a, b) for + - * / | ("neg", a) |
# ("f", fname, a) for sqrt sin cos tan atan abs | ("atan2", a, b)


def walk(n: tuple, leaf: Callable[[tuple], Any], fun: dict[str, Callable[..., Any]],
         memo: dict[int, tuple[tuple, Any]]) -> Any:
    """The value of an expression: ``leaf`` gives a constant's (``c``) and a parameter's
    (``p``), ``fun`` the functions (:data:`_FUN` with ``atan2``, ``min`` and ``max``), the
    operators those of the values; each shared subexpression once (the traced expressions
    share their parts: a plain tree walk repeats them exponentially). ``memo`` keeps each
    node with its value (so a node's id stays its own while the memo lives)."""
    k = n[0]
    if k in ("c", "p"):
        return leaf(n)
    got = memo.get(id(n))
    if got is not None and got[0] is n:
        return got[1]
    if k == "neg":
        v = -walk(n[1], leaf, fun, memo)
    elif k == "f":
        v = fun[n[1]](walk(n[2], leaf, fun, memo))
    elif k in ("atan2", "min", "max"):
        v = fun[k](walk(n[1], leaf, fun, memo), walk(n[2], leaf, fun, memo))
    else:
        a, b = walk(n[1], leaf, fun, memo), walk(n[2], leaf, fun, memo)
        v = a + b if k == "+" else a - b if k == "-" else a * b if k == "*" else a / b
    memo[id(n)] = (n, v)
    return v


def _ev(n: tuple, env: dict[str, float]) -> float:
    """The value of an expression at ``env`` (:func:`walk` with :data:`_FUN`: a root of a
    negative number or a division by zero raises)."""
    return walk(n, lambda m: m[1] if m[0] == "c" else env[m[1]], _SCALAR, {})


_FUN: dict[str, Callable[[float], float]] = {
    "sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan, "atan": math.atan,
    "abs": abs}
_SCALAR: dict[str, Callable[..., float]] = dict(_FUN, atan2=math.atan2, min=min, max=max)

#: a comparison as macro B writes it (HNC-21T and FANUC ``IF [a LT b]``)
MACRO_OPS = {"<": "LT", "<=": "LE", ">": "GT", ">=": "GE"}


def _node(v: Any) -> tuple:
    if isinstance(v, Sym):
        return v.n
    return ("c", float(v))


class Sym:
    """A number with its exact expression of the family's parameters."""

    __slots__ = ("v", "n", "tr")

    def __init__(self, v: float, n: tuple, tr: "_Trace"):
        self.v, self.n, self.tr = float(v), n, tr

    def _mk(self, v: float, n: tuple) -> "Sym":
        return Sym(v, n, self.tr)

    def _bin(self, op: str, o: Any, rev: bool = False) -> "Sym":
        if not isinstance(o, (Sym, int, float)) or isinstance(o, bool):
            return NotImplemented
        ov = o.v if isinstance(o, Sym) else float(o)
        a, b = (_node(o), self.n) if rev else (self.n, _node(o))
        x, y = (ov, self.v) if rev else (self.v, ov)
        v = x + y if op == "+" else x - y if op == "-" else x * y if op == "*" else x / y
        return self._mk(v, (op, a, b))

    def __add__(self, o): return self._bin("+", o)
    def __radd__(self, o): return self._bin("+", o, True)
    def __sub__(self, o): return self._bin("-", o)
    def __rsub__(self, o): return self._bin("-", o, True)
    def __mul__(self, o): return self._bin("*", o)
    def __rmul__(self, o): return self._bin("*", o, True)
    def __truediv__(self, o): return self._bin("/", o)
    def __rtruediv__(self, o): return self._bin("/", o, True)

    def __pow__(self, o):
        if o == 2:
            return self * self
        if o == 0.5:
            return self._mk(math.sqrt(self.v), ("f", "sqrt", self.n))
        raise PartError(f"macro: the sketch raises a parameter to the power {o!r}, which the "
                        f"macro cannot write")

    def __neg__(self): return self._mk(-self.v, ("neg", self.n))
    def __pos__(self): return self
    def __abs__(self): return self._mk(abs(self.v), ("f", "abs", self.n))

    def _cmp(self, op: str, o: Any) -> "SymBool":
        ov = o.v if isinstance(o, Sym) else float(o)
        v = {"<": self.v < ov, "<=": self.v <= ov, ">": self.v > ov, ">=": self.v >= ov}[op]
        return SymBool(v, (op, self.n, _node(o)), self.tr)

    def __lt__(self, o): return self._cmp("<", o)
    def __le__(self, o): return self._cmp("<=", o)
    def __gt__(self, o): return self._cmp(">", o)
    def __ge__(self, o): return self._cmp(">=", o)
    def __float__(self):
        # asked by the family's own code (``math.sqrt`` of the real ``math``, ``float()``),
        # the expression is lost there: noted for a refusal of the derivation to name
        # (:func:`macro_program.with_lost`)
        f = sys._getframe(1)
        if self.tr.file is not None and f.f_code.co_filename == self.tr.file:
            at = f"{os.path.basename(self.tr.file)}:{f.f_lineno}"
            if at not in self.tr.floated:
                self.tr.floated.append(at)
        return self.v

    def __format__(self, spec): return format(self.v, spec)
    def __str__(self): return format(self.v, "g")
    __hash__ = None  # type: ignore[assignment]


class SymBool:
    """A comparison of :class:`Sym` numbers; asking for its truth records it as a condition
    of the traced path."""

    __slots__ = ("v", "c", "tr")

    def __init__(self, v: bool, c: tuple, tr: "_Trace"):
        self.v, self.c, self.tr = v, c, tr

    def __bool__(self) -> bool:
        self.tr.pending.append((self.c, self.v))
        return self.v


class _Math:
    """``math`` for a traced sketch: the functions take and give :class:`Sym`."""

    pi = math.pi
    e = math.e

    def __getattr__(self, name: str) -> Any:
        return getattr(math, name)

    @staticmethod
    def _f(name: str, x: Any) -> Any:
        if isinstance(x, Sym):
            return x._mk(_FUN[name](x.v), ("f", name, x.n))
        return _FUN[name](x)

    def sqrt(self, x): return self._f("sqrt", x)
    def sin(self, x): return self._f("sin", x)
    def cos(self, x): return self._f("cos", x)
    def tan(self, x): return self._f("tan", x)
    def atan(self, x): return self._f("atan", x)
    def fabs(self, x): return abs(x)

    def radians(self, x): return x * (math.pi / 180.0)
    def degrees(self, x): return x * (180.0 / math.pi)

    def hypot(self, a, b): return self.sqrt(a * a + b * b)

    def atan2(self, y, x):
        if isinstance(y, Sym) or isinstance(x, Sym):
            tr = y.tr if isinstance(y, Sym) else x.tr
            return Sym(math.atan2(float(y), float(x)), ("atan2", _node(y), _node(x)), tr)
        return math.atan2(y, x)


@dataclass
class Check:
    """A parameter check: the conditions that must hold and the family's message."""
    conds: list[tuple]
    message: str
    names: list[str]


@dataclass
class _Trace:
    pending: list[tuple] = field(default_factory=list)
    checks: list[Check] = field(default_factory=list)
    branches: list[tuple] = field(default_factory=list)  # (condition, nominal truth)
    segments: list[tuple] = field(default_factory=list)
    #: the family's file, and where its sketch made a plain number of a traced one (a
    #: ``math`` imported inside the function, ``float()``): "file:line", in order
    file: str | None = None
    floated: list[str] = field(default_factory=list)

    def take(self) -> list[tuple]:
        out = [c if v else ("not", c) for c, v in self.pending]
        self.pending = []
        return out


def _params_of(n: tuple) -> set[str]:
    if n[0] == "p":
        return {n[1]}
    if n[0] == "c":
        return set()
    out: set[str] = set()
    for x in n[1:]:
        if isinstance(x, tuple):
            out |= _params_of(x)
    return out


class _TraceOutline:
    """:class:`hnc_cam.cad.sketch.Outline` on :class:`Sym` points: records the segments with
    the corners cut as exact expressions."""

    def __init__(self, tr: _Trace, start):
        self.tr = tr
        self.segs: list[list] = []  # ["L", p0, p1] | ["A", p0, p1, center_or_None, radius, cw]
        self._pos = (start[0], start[1])
        self._corner: tuple | None = None

    @property
    def pos(self):
        return self._pos

    def line_to(self, x, z, chamfer=0.0, fillet=0.0, names=""):
        end = (x, z)
        corner = None
        if chamfer > 0:
            corner = ("C", chamfer, names)
        elif fillet > 0:
            corner = ("R", fillet, names)
        self._add(["L", self._pos, end])
        self._corner = corner
        return self

    def arc_to(self, x, z, radius=None, cw=True, center=None):
        end = (x, z)
        if center is not None:
            dx, dz = end[0] - center[0], end[1] - center[1]
            r = _Math().sqrt(dx * dx + dz * dz)
        elif radius is not None:
            r = abs(radius)
        else:
            raise PartError("arc_to needs radius or center")
        self._add(["A", self._pos, end, center, r, bool(cw)])
        self._corner = None
        return self

    def _add(self, seg: list) -> None:
        if self._corner and self.segs and self.segs[-1][0] == "L" and seg[0] == "L":
            kind, size, names = self._corner
            prev = self.segs.pop()
            a, g, e = prev[1], prev[2], seg[2]
            m = _Math()
            l1 = m.sqrt((g[0] - a[0]) ** 2 + (g[1] - a[1]) ** 2)
            l2 = m.sqrt((e[0] - g[0]) ** 2 + (e[1] - g[1]) ** 2)
            u1 = ((g[0] - a[0]) / l1, (g[1] - a[1]) / l1)
            u2 = ((e[0] - g[0]) / l2, (e[1] - g[1]) / l2)
            cr = u1[1] * u2[0] - u1[0] * u2[1]  # (z right, x up) view, as geometry.cross
            dot = u1[0] * u2[0] + u1[1] * u2[1]
            t = size if kind == "C" else size * abs(cr) / (1 + dot)
            # the corner fits (what Outline.line_to checks) — a parameter check
            what = "chamfer" if kind == "C" else "fillet"
            blame = names or ", ".join(sorted(_params_of(_node(size))))
            self.tr.pending = []
            self.tr.checks.append(Check([("<", _node(t), _node(l1)), ("<", _node(t), _node(l2))],
                                        f"{what} does not fit (parameters {blame})",
                                        sorted(_params_of(_node(t)) | _params_of(_node(l1))
                                               | _params_of(_node(l2)))))
            p1 = (g[0] - u1[0] * t, g[1] - u1[1] * t)
            p2 = (g[0] + u2[0] * t, g[1] + u2[1] * t)
            self.segs.append(["L", a, p1])
            if kind == "C":
                self.segs.append(["L", p1, p2])
            else:
                self.segs.append(["A", p1, p2, None, size, float(cr) < 0])
            seg = ["L", p2, e]
        self.segs.append(seg)
        self._pos = seg[2]

    def close(self):
        start = self.segs[0][1]
        self.line_to(*start)
        return self

    def segments(self):
        self.tr.segments = self.segs
        return self.segs


def _trace(mod: Any, params: dict[str, Any], free: list[str] | None = None) -> _Trace:
    """Run ``mod.sketch`` with the ``free`` parameters (default: all) as symbols; the path's
    conditions, checks and segments."""
    tr = _Trace(file=getattr(mod, "__file__", None))
    syms = {k: (Sym(v, ("p", k), tr) if free is None or k in free else v)
            for k, v in params.items()}
    from .model import _n as fmt

    def require(cond, message):
        conds = tr.take()
        if isinstance(cond, SymBool):
            conds.append(cond.c)
        elif not cond:
            raise PartError(f"the sketch refuses the family's default parameters: {message}")
        if conds:
            names: set[str] = set()
            for c in conds:
                names |= _params_of(c)
            tr.checks.append(Check(conds, str(message), sorted(names)))

    def positive(**kw):
        for k, v in kw.items():
            require(v > 0, f"{k}={fmt(v)} must be positive")

    def non_negative(**kw):
        for k, v in kw.items():
            require(v >= 0, f"{k}={fmt(v)} must not be negative (0 means none)")

    def _minmax(kind: str) -> Callable[..., Any]:
        def f(*args: Any) -> Any:
            xs = list(args[0]) if len(args) == 1 else list(args)
            out = xs[0]
            for x in xs[1:]:
                if isinstance(out, Sym) or isinstance(x, Sym):
                    v = (min if kind == "min" else max)(float(out), float(x))
                    out = Sym(v, (kind, _node(out), _node(x)), tr)
                else:
                    out = (min if kind == "min" else max)(out, x)
            return out
        return f

    saved = {k: mod.__dict__.get(k, _MISSING) for k in
             ("Outline", "math", "require", "positive", "non_negative", "min", "max")}
    mod.__dict__.update(Outline=lambda start: _TraceOutline(tr, start), math=_Math(),
                        require=require, positive=positive, non_negative=non_negative,
                        min=_minmax("min"), max=_minmax("max"))
    try:
        mod.sketch(**syms)
    except PartError:
        raise
    except Exception as e:  # noqa: BLE001 - what the sketch does with symbols
        raise PartError(f"{getattr(mod, '__file__', 'part')}: sketch() cannot be traced "
                        f"symbolically ({type(e).__name__}: {e}); the macro needs a sketch "
                        f"built from Outline, require and math") from None
    finally:
        for k, v in saved.items():
            if v is _MISSING:
                mod.__dict__.pop(k, None)
            else:
                mod.__dict__[k] = v
    tr.branches = [(c, v) for c, v in tr.pending]
    tr.pending = []
    if not tr.segments:
        raise PartError(f"{getattr(mod, '__file__', 'part')}: sketch() returned no traced "
                        f"segments")
    return tr


_MISSING = object()


def features(tr: _Trace) -> list[tuple[str, tuple]]:
    """The traced quantities a program word may be made of: (description, expression)."""
    out: list[tuple[str, tuple]] = []
    for i, s in enumerate(tr.segments):
        for j, p in enumerate(s[1:3]):
            out.append((f"segment {i + 1} {'start' if j == 0 else 'end'} X",
                        _node(p[0] * 2 if isinstance(p[0], Sym) else 2 * float(p[0]))))
            out.append((f"segment {i + 1} {'start' if j == 0 else 'end'} Z", _node(p[1])))
        if s[0] == "A":
            out.append((f"segment {i + 1} radius", _node(s[4])))
    return out


# ------------------------------------------------------------------------------------------
# rendering expressions
# ------------------------------------------------------------------------------------------

def _num(v: float) -> str:
    s = f"{v:.12f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


#: how a dialect writes the functions (FANUC's trigonometry is in degrees)
_HNC_FUN = {"sqrt": "SQRT", "sin": "SIN", "cos": "COS", "tan": "TAN", "atan": "ATAN",
            "abs": "ABS"}


def render(n: tuple, var: dict[str, str], dialect: str = "hnc21t") -> str:
    """The expression ``n`` in the dialect's macro syntax; ``var`` maps a parameter to its
    variable (``#50``)."""
    if dialect == "siemens802":
        return _render_802(n, var)
    k = n[0]
    if k == "c":
        s = _num(n[1])
        return f"[{s}]" if s.startswith("-") else s
    if k == "p":
        return var[n[1]]
    if k == "neg":
        return f"[-{render(n[1], var, dialect)}]"
    if k == "f":
        inner = render(n[2], var, dialect)
        if dialect == "fanuc0it" and n[1] in ("sin", "cos", "tan"):
            inner = f"{inner}*180/{_num(math.pi)}"
        if dialect == "fanuc0it" and n[1] == "atan":
            return f"[ATAN[{inner}]/[1]*{_num(math.pi)}/180]"
        return f"{_HNC_FUN[n[1]]}[{inner}]"
    if k in ("min", "max"):  # (a + b -+ |a - b|) / 2: exact, and every dialect has ABS
        a, b = render(n[1], var, dialect), render(n[2], var, dialect)
        return f"[[{a}+{b}{'-' if k == 'min' else '+'}ABS[{a}-{b}]]/2]"
    if k == "atan2":
        a, b = render(n[1], var, dialect), render(n[2], var, dialect)
        if dialect == "fanuc0it":
            return f"[ATAN[{a}]/[{b}]*{_num(math.pi)}/180]"
        return f"ATAN2[{a},{b}]"
    a, b = render(n[1], var, dialect), render(n[2], var, dialect)
    return f"[{a}{k}{b}]"


def _render_802(n: tuple, var: dict[str, str]) -> str:
    """SINUMERIK 802: ``( )`` brackets, ``SQRT( )``, trigonometry in degrees, ``ATAN2(y,x)``
    (no ATAN)."""
    k = n[0]
    if k == "c":
        s = _num(n[1])
        return f"({s})" if s.startswith("-") else s
    if k == "p":
        return var[n[1]]
    if k == "neg":
        return f"(-{_render_802(n[1], var)})"
    deg = f"180/{_num(math.pi)}"
    if k == "f":
        inner = _render_802(n[2], var)
        if n[1] in ("sin", "cos", "tan"):
            return f"{_HNC_FUN[n[1]]}({inner}*{deg})"
        if n[1] == "atan":
            return f"(ATAN2({inner},1)/({deg}))"
        return f"{_HNC_FUN[n[1]]}({inner})"
    if k in ("min", "max"):
        a, b = _render_802(n[1], var), _render_802(n[2], var)
        return f"(({a}+{b}{'-' if k == 'min' else '+'}ABS({a}-{b}))/2)"
    if k == "atan2":
        a, b = _render_802(n[1], var), _render_802(n[2], var)
        return f"(ATAN2({a},{b})/({deg}))"
    a, b = _render_802(n[1], var), _render_802(n[2], var)
    return f"({a}{k}{b})"


def _cancel(op: str, a: tuple, b: tuple) -> tuple | None:
    """``a op b`` where a term cancels exactly (the same expression added and taken away, a
    zero divided): ``x-x``, ``x-[x-y]``, ``[x+y]-x``, ``[x-y]-x``, ``0/y``; else None."""
    if op == "-":
        if a == b:
            return ("c", 0.0)
        if b[0] == "-" and b[1] == a:
            return b[2]
        if a[0] == "+" and a[1] == b:
            return a[2]
        if a[0] == "+" and a[2] == b:
            return a[1]
        if a[0] == "-" and a[1] == b:
            return ("neg", a[2])
    if op == "/" and a[0] == "c" and a[1] == 0 and not (b[0] == "c" and b[1] == 0):
        return ("c", 0.0)
    return None


def _simplify(n: tuple) -> tuple:
    """Constant folding and the neutral elements (exact: only operations on literal
    constants and x*1, x+0)."""
    if n[0] in ("c", "p"):
        return n
    if n[0] == "neg":
        a = _simplify(n[1])
        return ("c", -a[1]) if a[0] == "c" else a[1] if a[0] == "neg" else ("neg", a)
    if n[0] == "f":
        a = _simplify(n[2])
        if n[1] == "sqrt" and a[0] == "*" and a[1] == a[2]:  # a line's length along one axis
            return _simplify(("f", "abs", a[1]))
        return ("c", _FUN[n[1]](a[1])) if a[0] == "c" else ("f", n[1], a)
    if n[0] in ("atan2", "min", "max"):
        return (n[0], _simplify(n[1]), _simplify(n[2]))
    op, a, b = n[0], _simplify(n[1]), _simplify(n[2])
    if a[0] == "c" and b[0] == "c":
        return ("c", _ev((op, a, b), {}))
    if op == "*":
        if a[0] == "c" and a[1] == 1:
            return b
        if b[0] == "c" and b[1] == 1:
            return a
        if (a[0] == "c" and a[1] == 0) or (b[0] == "c" and b[1] == 0):
            return ("c", 0.0)
        if a[0] == "c" and a[1] == -1:
            return ("neg", b)
    if op == "/" and b[0] == "c" and b[1] == 1:
        return a
    if op == "+":
        if a[0] == "c" and a[1] == 0:
            return b
        if b[0] == "c" and b[1] == 0:
            return a
        if b[0] == "c" and b[1] < 0:
            return ("-", a, ("c", -b[1]))
        if b[0] == "neg":
            return ("-", a, b[1])
    c = _cancel(op, a, b)  # a vertical line's dx, a corner's leg along one axis
    if c is not None:
        return _simplify(c)
    if op == "-":
        if b[0] == "c" and b[1] == 0:
            return a
        if a[0] == "c" and a[1] == 0:
            return ("neg", b)
        if b[0] == "c" and b[1] < 0:
            return ("+", a, ("c", -b[1]))
    return (op, a, b)


def _fold(n: tuple) -> tuple:
    """One level of exact simplification of ``n`` (its operands already simplified):
    operations on constants folded, ``x*1``, ``x/1``, ``x+0``, ``x-0``, ``0-x``, ``--x``,
    ``x+[-y]``, ``x-[-y]`` and ``[-x]-[-y]`` written plainly."""
    k = n[0]
    if k == "neg":
        a = n[1]
        return ("c", -a[1]) if a[0] == "c" else a[1] if a[0] == "neg" else n
    if k == "f":
        a = n[2]
        if n[1] == "sqrt" and a[0] == "*" and a[1] == a[2]:
            return _fold(("f", "abs", a[1]))
        return ("c", _FUN[n[1]](a[1])) if a[0] == "c" else n
    if k not in ("+", "-", "*", "/"):
        return n
    a, b = n[1], n[2]
    if a[0] == "c" and b[0] == "c":
        try:
            return ("c", _ev(n, {}))
        except ZeroDivisionError:
            return n
    if k == "*":
        if a[0] == "c" and a[1] == 1:
            return b
        if b[0] == "c" and b[1] == 1:
            return a
        if (a[0] == "c" and a[1] == 0) or (b[0] == "c" and b[1] == 0):
            return ("c", 0.0)
    if k == "/" and b[0] == "c" and b[1] == 1:
        return a
    if k == "+":
        if a[0] == "c" and a[1] == 0:
            return b
        if b[0] == "c" and b[1] == 0:
            return a
        if b[0] == "neg":
            return ("-", a, b[1])
        if b[0] == "c" and b[1] < 0:
            return ("-", a, ("c", -b[1]))
    c = _cancel(k, a, b)
    if c is not None:
        return _fold(c)
    if k == "-":
        if b[0] == "c" and b[1] == 0:
            return a
        if a[0] == "c" and a[1] == 0:
            return _fold(("neg", b))
        if a[0] == "neg" and b[0] == "neg":
            return ("-", b[1], a[1])
        if b[0] == "neg":
            return ("+", a, b[1])
        if b[0] == "c" and b[1] < 0:
            return ("+", a, ("c", -b[1]))
    return n


def _cond(c: tuple, var: dict[str, str], dialect: str) -> str:
    """A condition as the dialect writes it, bracketed."""
    if c[0] == "not":
        return f"[NOT {_cond(c[1], var, dialect)}]" if dialect == "hnc21t" else \
            _cond(_negate(c[1]), var, dialect)
    return (f"[{render(_simplify(c[1]), var, dialect)} {MACRO_OPS[c[0]]} "
            f"{render(_simplify(c[2]), var, dialect)}]")


def _negate(c: tuple) -> tuple:
    if c[0] == "not":
        return c[1]
    return ({"<": ">=", "<=": ">", ">": "<=", ">=": "<"}[c[0]], c[1], c[2])


def _holds(c: tuple, env: dict[str, float]) -> bool:
    if c[0] == "not":
        return not _holds(c[1], env)
    a, b = _ev(c[1], env), _ev(c[2], env)
    return {"<": a < b, "<=": a <= b, ">": a > b, ">=": a >= b}[c[0]]


# ------------------------------------------------------------------------------------------
# sampling and fitting
# ------------------------------------------------------------------------------------------

@dataclass
class Family:
    """What the macro is derived from."""
    path: str
    mod: Any
    params: dict[str, Any]  # the nominal set (defaults, --set)
    free: list[str]  # the parameters that become macro variables
    trace: _Trace
    lo: dict[str, float]
    hi: dict[str, float]
    #: parameters whose range the tool library cuts only in part: name -> (the end the
    #: DOMAIN gives, the end kept, why) (:func:`macro_program.fix_unmachinable`)
    narrowed: dict[str, tuple[float, float, str]] = field(default_factory=dict)


def _declared_domain(mod: Any, path: str, full: dict[str, Any],
                     free: list[str]) -> dict[str, tuple[float, float]]:
    """The family's own ``DOMAIN = {"name": (low, high), ...}``: the range over which each
    named parameter is valid (the macro holds over it instead of the box around the
    nominal)."""
    dom = getattr(mod, "DOMAIN", None)
    if dom is None:
        return {}
    if not isinstance(dom, dict):
        raise PartError(f"{path}: DOMAIN must be a dict of parameter name: (low, high)")
    out: dict[str, tuple[float, float]] = {}
    for k, rng in dom.items():
        if k not in full:
            from ..cad.loader import kwargs_hint
            raise PartError(f"{path}: DOMAIN names {k!r}, which is not one of the family's "
                            f"parameters ({', '.join(full) or 'none'})" + kwargs_hint(mod))
        if isinstance(rng, (int, float)) and not isinstance(rng, bool):
            # one number: the parameter stays at that value (a thread's pitch, a standard
            # size): the macro's constant, not a variable
            v = float(rng)
            if not math.isfinite(v):
                raise PartError(f"{path}: DOMAIN[{k!r}] = {rng!r} is not a number")
            if abs(full[k] - v) > 1e-12:
                raise PartError(f"{path}: {k}={full[k]:g}, where the family's DOMAIN holds "
                                f"{k} at {v:g}")
            out[k] = (v, v)
            continue
        try:
            a, b = (float(x) for x in rng)
        except (TypeError, ValueError):
            raise PartError(f"{path}: DOMAIN[{k!r}] must be two numbers (low, high) or one "
                            f"(the value it stays at), not {rng!r}") from None
        if not (math.isfinite(a) and math.isfinite(b) and a < b):
            raise PartError(f"{path}: DOMAIN[{k!r}] = ({a:g}, {b:g}) is no range (low < high)")
        if k not in free:
            continue  # a whole number stays at its value
        if not a <= full[k] <= b:
            raise PartError(f"{path}: {k}={full[k]:g} is outside the family's DOMAIN "
                            f"{a:g}..{b:g}")
        out[k] = (a, b)
    return out


def load_family(path: str, base: dict[str, Any], rows: list[dict[str, Any]] | None = None,
                spread: float = 0.15) -> Family:
    """The family at ``path`` traced at ``base`` (defaults updated by ``--set``), its domain
    box: each real parameter within ``spread`` of its value (a parameter at 0 stays 0), grown
    to cover every table row. Whole-number parameters (a count of waves) stay as given: they
    change the program's shape, so each value is its own macro."""
    from ..cad.loader import load_module, resolve_params
    mod = load_module(path)
    if not callable(getattr(mod, "sketch", None)):
        raise PartError(f"{path}: defines no sketch(**params): the macro is derived from the "
                        f"family's exact sketch")
    full = resolve_params(mod, base, path)
    rows = [resolve_params(mod, r, path) for r in (rows or [])]
    free = [k for k, v in full.items() if isinstance(v, float)]
    for r in rows:
        for k, v in r.items():
            if k not in free and v != full[k]:
                raise PartError(f"{path}: the table gives {k}={v:g} and {full[k]:g}: a "
                                f"whole-number parameter changes the program's shape, so one "
                                f"macro holds one value (give it with --set)")
    lo = {k: (full[k] * (1 - spread) if full[k] > 0 else full[k] * (1 + spread)) for k in free}
    hi = {k: (full[k] * (1 + spread) if full[k] > 0 else full[k] * (1 - spread)) for k in free}
    declared = _declared_domain(mod, path, full, free)
    for k, (a, b) in declared.items():
        lo[k], hi[k] = a, b
    held = [k for k, (a, b) in declared.items() if a == b]  # DOMAIN's single values
    for r in rows:
        for k in held:
            if r[k] != full[k]:
                raise PartError(f"{path}: the table gives {k}={r[k]:g}, where the family's "
                                f"DOMAIN holds {k} at {full[k]:g}")
    free = [k for k in free if k not in held]
    for k in held:
        del lo[k], hi[k]
    for r in rows:
        for k in free:
            if k in declared and not lo[k] <= r[k] <= hi[k]:
                raise PartError(f"{path}: the table gives {k}={r[k]:g}, outside the family's "
                                f"DOMAIN {lo[k]:g}..{hi[k]:g}")
            lo[k], hi[k] = min(lo[k], r[k]), max(hi[k], r[k])
    tr = _trace(mod, full, free)
    return Family(path, mod, full, free, tr, lo, hi)



class Lets:
    """Writes expressions with their shared parts computed once: a subexpression longer than
    ``inline`` characters goes to its own variable (``#first``, ``#first+1``, ... up to
    ``#last``), assigned on a line of its own before the word that uses it. Expressions are
    shared sub-trees (a fillet's tangent point reuses the lines it joins), so writing them out
    without this would grow exponentially. More temporaries than the range holds is a
    :class:`PlanError` (the control's variable range)."""

    def __init__(self, var: dict[str, str], dialect: str = "hnc21t", first: int = 100,
                 last: int = 199, inline: int = 40, depth: int | None = None):
        self.var, self.dialect, self.next, self.last, self.inline = var, dialect, first, last, inline
        #: the first variable of the control's range for temporaries (a branch's writer
        #: starts further on)
        self.base = first
        #: how a variable is named: ``#n`` (macro B), ``Rn`` (SINUMERIK 802)
        self.prefix = "R" if dialect == "siemens802" else "#"
        # FANUC nests brackets at most 5 deep (PS0118): 4 here, the word's own makes 5
        self.depth = depth if depth is not None else (4 if dialect == "fanuc0it" else 64)
        self.lines: list[str] = []
        self._memo: dict[int, str] = {}
        self._keep: list[tuple] = []

    def simple(self, n: tuple) -> tuple:
        """``n`` with constants folded and neutral terms gone, shared sub-trees kept shared."""
        memo = self.__dict__.setdefault("_simple", {})
        key = id(n)
        if key in memo:
            return memo[key]
        k = n[0]
        if k in ("c", "p", "atan2", "min", "max"):
            kids = [self.simple(x) for x in n[1:]] if k != "c" and k != "p" else []
            out = n if all(x is y for x, y in zip(kids, n[1:])) else (k, *kids)
        elif k == "neg":
            a = self.simple(n[1])
            out = _fold(n if a is n[1] else ("neg", a))
        elif k == "f":
            a = self.simple(n[2])
            out = _fold(n if a is n[2] else ("f", n[1], a))
        else:
            a, b = self.simple(n[1]), self.simple(n[2])
            out = _fold(n if (a is n[1] and b is n[2]) else (k, a, b))
        memo[key] = out
        memo[id(out)] = out  # simple already
        self._keep += [n, out]
        return out

    def rounded(self, n: tuple, tie_free: bool = False) -> str:
        """``n`` rounded at the control to the 0.001 mm the per-variant program writes, as
        the planner rounds it (:func:`hnc_cam.units.round_written`: a half up, to a
        millionth of the digit): the floor of a positive number, ``INT`` (HNC-21T), ``FIX``
        (FANUC), ``TRUNC`` (802) of ``e*1000 + 1000000.500001``, less 1000000 (a coordinate
        under 1000 mm). ``tie_free``: ``n`` is never at a half of the digit, so any rounding
        to nearest writes it alike: FANUC's ``ROUND`` (halves away from zero), else the
        offset floor without the millionth and the offset taken off after the division,
        short enough to stay in its word (no temporary)."""
        key = ("r", id(n))
        if key in self._memo:
            return self._memo[key]
        inner = self.expr(n)
        if tie_free:
            # no half to break: FANUC's ROUND, else the floor of the value moved positive
            # (a coordinate under 1000 mm), the offset taken off after the division
            form = ("[ROUND[{}*1000]/1000]" if self.dialect == "fanuc0it" else
                    "(TRUNC({}*1000+1000000.5)/1000-1000)" if self.dialect == "siemens802"
                    else "[INT[[{}*1000]+1000000.5]/1000-1000]")
            s = form.format(inner)
            if len(s) > self.inline or _depth(s) > self.depth:
                s = form.format(self._assign(inner))
            self._memo[key] = s
            return s
        if not (inner.startswith(self.prefix) or _depth(inner) == 0):
            inner = self._assign(inner)  # FANUC nests brackets 5 deep at most
        if self.dialect == "siemens802":
            s = f"((TRUNC({inner}*1000+1000000.500001)-1000000)/1000)"
        else:
            f = "FIX" if self.dialect == "fanuc0it" else "INT"
            s = f"[[{f}[[{inner}*1000]+1000000.500001]-1000000]/1000]"
        if len(s) > self.inline or _depth(s) > self.depth:
            s = self._assign(s)
        self._memo[key] = s
        return s

    def _held(self, n: tuple) -> str:
        """``n`` as a variable or a plain number (assigned now if it is neither)."""
        e = self.expr(n)
        if _depth(e) == 0 and " " not in e:
            return e
        name = self._assign(e)
        self._memo[id(n)] = name
        return name

    def _assign(self, s: str) -> str:
        if self.next > self.last:
            raise PlanError(f"the macro needs more variables for its expressions than the "
                            f"control's range for them holds ({self.last - self.base + 1}: "
                            f"{self.prefix}{self.base}..{self.prefix}{self.last})")
        name = f"{self.prefix}{self.next}"
        self.next += 1
        self.lines.append(f"{name}={s}")
        return name

    def fork(self) -> "Lets":
        """A branch's writer: it sees what is assigned so far, its own temporaries start at
        the next free variable and stay its own (a sibling branch reuses those numbers)."""
        child = Lets(self.var, self.dialect, self.next, self.last, self.inline, self.depth)
        child.base = self.base
        child._memo, child._keep = dict(self._memo), list(self._keep)
        return child

    def expr(self, n: tuple) -> str:
        """The expression of ``n`` (assignments it needs are appended to :attr:`lines`),
        simplified where that is exact (:func:`_fold`)."""
        key = id(n)
        if key in self._memo:
            return self._memo[key]
        m = self.simple(n)
        if m is not n:
            s = self.expr(m)
            self._memo[key] = s
            self._keep.append(n)
            return s
        k = n[0]
        if k in ("c", "p"):
            s = render(n, self.var, self.dialect)
        elif k == "neg":
            s = (f"(-{self.expr(n[1])})" if self.dialect == "siemens802" else
                 f"[-{self.expr(n[1])}]")
        elif k == "f":
            s = render(("f", n[1], ("p", "\0")), {"\0": self.expr(n[2])}, self.dialect)
        else:
            s = render((k, ("p", "\0a"), ("p", "\0b")),
                       {"\0a": self.expr(n[1]), "\0b": self.expr(n[2])}, self.dialect)
            if _depth(s) > self.depth:  # its operands in variables first (FANUC: 5 deep)
                s = render((k, ("p", "\0a"), ("p", "\0b")),
                           {"\0a": self._held(n[1]), "\0b": self._held(n[2])}, self.dialect)
        if len(s) > self.inline or _depth(s) > self.depth:
            s = self._assign(s)
        self._memo[key] = s
        self._keep.append(n)
        return s


def hnc_checks(tr: _Trace, lets: Lets) -> list[str]:
    """The HNC-21T lines that check the parameters before any motion: for each check,
    ``IF`` its conditions do not all hold, a comment naming the parameters and ``M30`` (the
    HNC-21T has no program-generated alarm: the program ends with the comment on the
    screen). The temporaries a condition needs are assigned just before its ``IF``."""
    out: list[str] = []
    for ch in tr.checks:
        parts = []
        for c in ch.conds:
            parts.append(f"[{lets.expr(c[1][1] if c[0] == 'not' else c[1])} "
                         f"{MACRO_OPS[c[1][0] if c[0] == 'not' else c[0]]} "
                         f"{lets.expr(c[1][2] if c[0] == 'not' else c[2])}]"
                         if c[0] != "not" else
                         f"[NOT [{lets.expr(c[1][1])} {MACRO_OPS[c[1][0]]} {lets.expr(c[1][2])}]]")
        out.extend(lets.lines)
        lets.lines.clear()
        names = " ".join(n.upper() for n in ch.names) or "PARAMETERS"
        out += [f"IF [NOT [{' AND '.join(parts)}]]",
                f"(PARAMETER CHECK FAILED: {names})", "M30", "ENDIF"]
    return out


def _depth(s: str) -> int:
    """How deep the brackets of ``s`` nest."""
    d = m = 0
    for ch in s:
        if ch in "[(":
            d += 1
            m = max(m, d)
        elif ch in "])":
            d -= 1
    return m


# ------------------------------------------------------------------------------------------
# rounded corners of offset contours
# ------------------------------------------------------------------------------------------

def _a(a: tuple, b: tuple) -> tuple: return ("+", a, b)
def _s(a: tuple, b: tuple) -> tuple: return ("-", a, b)
def _m(a: tuple, b: tuple) -> tuple: return ("*", a, b)
def _d(a: tuple, b: tuple) -> tuple: return ("/", a, b)
def _k(v: float) -> tuple: return ("c", float(v))


def _elements(tr: _Trace) -> list[list[tuple]]:
    """Each traced segment as the element a path offset from it follows, per segment (an arc
    drawn by its radius alone has two possible centres: both): ``("L", (x0, z0), (ux, uz),
    (nx, nz))`` a line through its start, its unit direction and normal (radius and Z);
    ``("C", (cx, cz), r)`` a circle."""
    out: list[list[tuple]] = []
    for seg in tr.segments:
        x0, z0, x1, z1 = _node(seg[1][0]), _node(seg[1][1]), _node(seg[2][0]), _node(seg[2][1])
        dx, dz = _s(x1, x0), _s(z1, z0)
        ln = ("f", "sqrt", _a(_m(dx, dx), _m(dz, dz)))
        if seg[0] == "L":
            out.append([("L", (x0, z0), (_d(dx, ln), _d(dz, ln)),
                         (("neg", _d(dz, ln)), _d(dx, ln)))])
            continue
        r = _node(seg[4])
        if seg[3] is not None:
            out.append([("C", (_node(seg[3][0]), _node(seg[3][1])), r)])
            continue
        h = ("f", "sqrt", _s(_m(r, r), _d(_m(ln, ln), _k(4.0))))
        mx, mz = _d(_a(x0, x1), _k(2.0)), _d(_a(z0, z1), _k(2.0))
        ux, uz = _d(("neg", dz), ln), _d(dx, ln)
        out.append([("C", (_a(mx, _m(ux, h)), _a(mz, _m(uz, h))), r),
                    ("C", (_s(mx, _m(ux, h)), _s(mz, _m(uz, h))), r)])
    return out


def _offset(el: tuple, o: float) -> tuple:
    """``el`` offset by ``o`` (a line along its normal, a circle's radius)."""
    if el[0] == "L":
        (x, z), u, n = el[1], el[2], el[3]
        return ("L", (_a(x, _m(_k(o), n[0])), _a(z, _m(_k(o), n[1]))), u, n)
    return ("C", el[1], _a(el[2], _k(o)))


def _meet(e1: tuple, e2: tuple) -> list[tuple[tuple, tuple]]:
    """Where two elements meet, in closed form (both roots where there are two): a line and a
    line, a line and a circle (the circle's centre projected on the line, plus or less the
    root of the radius squared less the centre's distance squared), two circles."""
    if e1[0] == "C" and e2[0] == "L":
        e1, e2 = e2, e1
    if e1[0] == "L" and e2[0] == "L":
        (q1, u1), (q2, u2) = (e1[1], e1[2]), (e2[1], e2[2])
        cross = _s(_m(u1[0], u2[1]), _m(u1[1], u2[0]))
        wx, wz = _s(q2[0], q1[0]), _s(q2[1], q1[1])
        t = _d(_s(_m(wx, u2[1]), _m(wz, u2[0])), cross)
        return [(_a(q1[0], _m(t, u1[0])), _a(q1[1], _m(t, u1[1])))]
    if e1[0] == "L":
        (q, u), (c, rho) = (e1[1], e1[2]), (e2[1], e2[2])
        wx, wz = _s(c[0], q[0]), _s(c[1], q[1])
        along = _a(_m(u[0], wx), _m(u[1], wz))
        h = _s(_m(wx, u[1]), _m(wz, u[0]))
        sq = ("f", "sqrt", _s(_m(rho, rho), _m(h, h)))
        return [(_a(q[0], _m(t, u[0])), _a(q[1], _m(t, u[1])))
                for t in (_a(along, sq), _s(along, sq))]
    (c1, r1), (c2, r2) = (e1[1], e1[2]), (e2[1], e2[2])
    dx, dz = _s(c2[0], c1[0]), _s(c2[1], c1[1])
    d2 = _a(_m(dx, dx), _m(dz, dz))
    dd = ("f", "sqrt", d2)
    a = _d(_a(_s(_m(r1, r1), _m(r2, r2)), d2), _m(_k(2.0), dd))
    h = ("f", "sqrt", _s(_m(r1, r1), _m(a, a)))
    ex, ez = _d(dx, dd), _d(dz, dd)
    bx, bz = _a(c1[0], _m(a, ex)), _a(c1[1], _m(a, ez))
    return [(_s(bx, _m(h, ez)), _a(bz, _m(h, ex))), (_a(bx, _m(h, ez)), _s(bz, _m(h, ex)))]


def _touch(el: tuple, o: float, f: tuple, of: float) -> tuple:
    """Where a circle centred at ``f`` on ``el`` offset by ``of`` touches ``el`` offset by
    ``o`` (a fillet's tangent point): on a line the centre moved back along the normal, on a
    circle the centre scaled from the circle's centre."""
    if el[0] == "L":
        n = el[3]
        return (_s(f[0], _m(_k(of - o), n[0])), _s(f[1], _m(_k(of - o), n[1])))
    c, r = el[1], el[2]
    k = _d(_a(r, _k(o)), _a(r, _k(of)))
    return (_a(c[0], _m(_s(f[0], c[0]), k)), _a(c[1], _m(_s(f[1], c[1]), k)))


def corner_points(tr: _Trace, offsets: list[float], roundings: list[float],
                  reach: int = 2) -> list[tuple[tuple, tuple]]:
    """The corners of a path offset from the traced contour (a rest-roughing contour: the part
    offset by the nose radius plus the allowance; the part itself at offset 0, where the
    802 writes a traced fillet as ``RND=`` at its lines' corner), as (radius, Z) expressions: for each two
    segments at most ``reach`` apart (a traced fillet or chamfer between them) and each
    offset ``d`` (either side of each), the point where the offset elements meet (the corner
    the SINUMERIK 802 writes with ``RND=``), and for each rounding ``r`` the tangent points
    of the fillet of radius ``r`` between them (its centre where the elements offset by
    ``d + r`` or ``d - r`` meet)."""
    els = _elements(tr)
    out: list[tuple[tuple, tuple]] = []
    for i in range(len(els)):
        for j in range(i + 1, min(len(els), i + 1 + reach)):
            for e1 in els[i]:
                for e2 in els[j]:
                    for d in offsets:
                        for s1 in (1.0, -1.0):
                            for s2 in (1.0, -1.0):
                                o1, o2 = s1 * d, s2 * d
                                if d or s1 == s2 == 1.0:  # (no offset: the traced corner)
                                    out += _meet(_offset(e1, o1), _offset(e2, o2))
                                for rf in roundings:
                                    for g in (1.0, -1.0):
                                        f1, f2 = o1 + s1 * g * rf, o2 + s2 * g * rf
                                        for f in _meet(_offset(e1, f1), _offset(e2, f2)):
                                            out += [_touch(e1, o1, f, f1), _touch(e2, o2, f, f2)]
    return out


def corner_law(tr: _Trace, allb: list, allp: list[dict], bi: int, wi: int, y: Any,
               tol: float, varying: Callable[..., Any]) -> tuple | None:
    """Word ``wi`` of block ``bi`` (an X on diameter or a Z, ``y`` its values over the
    variants ``allb`` at the sets ``allp``) as a corner of a path offset from the traced
    contour (:func:`corner_points`) shifted by a constant (the tool's tip from its nose's
    centre, an allowance), within ``tol`` at every variant; None where none is. The offsets
    are 0 and the alternative's radii that no variant changes (``RND=``, ``CR=``, ``R``),
    the roundings those of the block and the next. ``varying(n, env, memo, sets)``: an
    expression's values over the sets, None where it is undefined at one or the same at
    all."""
    import numpy as np
    letter = allb[0][bi].words[wi].letter
    if letter not in ("X", "Z"):
        return None

    def radii(rows: range) -> list[float]:
        out: list[float] = []
        for k in rows:
            for m, w in enumerate(allb[0][k].words):
                if w.letter in ("RND", "CR", "R") and 0 < w.value <= 3 and all(
                        vb[k].words[m].text == w.text for vb in allb) and w.value not in out:
                    out.append(w.value)
        return out

    offsets = [0.0] + radii(range(len(allb[0])))
    roundings = radii(range(bi, min(bi + 2, len(allb[0]))))
    env = {k: np.array([float(p[k]) for p in allp]) for k in allp[0]
           if isinstance(allp[0][k], float)}
    memo: dict[int, Any] = {}
    for px, pz in corner_points(tr, offsets, roundings):
        n = _m(_k(2.0), px) if letter == "X" else pz
        v = varying(n, env, memo, allp)
        if v is None:
            continue
        for nd in (1, 2, 3):
            const = round(float(y[0] - v[0]), nd)
            if np.max(np.abs(v + const - y)) <= tol:
                return _a(n, _k(const)) if const else n
    return None


# ------------------------------------------------------------------------------------------
# laws of two features that move together
# ------------------------------------------------------------------------------------------

#: the largest denominator of a law's coefficient (a dimension's own law: halves, fifths, ...)
DENOMINATOR = 12


def collinear_fractions(y: Any, x1: Any, x2: Any, n_fit: int,
                        tol: float) -> tuple[list[float], float] | None:
    """``y = a*x1 + b*x2 + c`` within ``tol`` at every row, ``a`` and ``b`` small fractions
    (denominators up to :data:`DENOMINATOR`) and ``c`` a number of 3, 4 or 6 decimals: (``[a,
    b]``, ``c``), else None. For two features that move together over the variants (a
    segment's ``1/n_x`` and ``n_z/n_x`` over a narrow range of angles), least squares over
    the written values (rounded to 0.001) leaves the coefficients far from the law's
    (0.56 and 0.36 for the planner's allowance 1/2 and 2/5): each fraction ``a`` near the
    least-squares value is tried, ``b`` then fitted alone (no longer collinear) and snapped;
    of the laws that hold, the one of the smallest denominators, then the closest."""
    import numpy as np
    from fractions import Fraction
    one = np.ones(n_fit)
    a0 = np.column_stack([x1[:n_fit], x2[:n_fit], one])
    sol, *_ = np.linalg.lstsq(a0, y[:n_fit], rcond=None)
    if np.max(np.abs(a0 @ sol - y[:n_fit])) > 4 * tol:
        return None  # the two features do not make the word
    span = max(0.5, abs(float(sol[0])))
    lo_, hi_ = float(sol[0]) - span, float(sol[0]) + span
    fr = {Fraction(p, q) for q in range(1, DENOMINATOR + 1)
          for p in range(math.floor(lo_ * q), math.ceil(hi_ * q) + 1)}
    best: tuple | None = None
    b0 = np.column_stack([x2[:n_fit], one])
    for a in fr:
        if a == 0:
            continue
        r = y - float(a) * x1
        (b, _c), *_ = np.linalg.lstsq(b0, r[:n_fit], rcond=None)
        bf = Fraction(float(b)).limit_denominator(DENOMINATOR)
        if bf == 0 or abs(float(bf) - b) > 0.05 * max(1.0, abs(b)):
            continue
        res = r - float(bf) * x2
        mid = float((res.max() + res.min()) / 2)
        for const in (round(mid, 3), round(mid, 4), round(mid, 6)):
            err = float(np.max(np.abs(res - const)))
            if err <= tol:
                key = (a.denominator + bf.denominator, err)
                if best is None or key < best[0]:
                    best = (key, [float(a), float(bf)], const)
                break
    return None if best is None else (best[1], best[2])
