"""One parametric macro program per part family, fitted from per-variant programs and proven.

*Derive* (:func:`derive`): the family is traced (:func:`hnc_cam.plan.macro.load_family`: every
contour point, corner trim and radius an exact expression of the parameters, the family's
checks, the domain box). One stock serves the whole domain: the largest the family's
``STOCK`` gives over the box (or ``--stock``). The per-variant program (``--comp control``:
the contour is the part itself) is generated for the nominal set and for sampled valid
sets; each is cut into blocks and words, and every variant must have the same *skeleton*
(the same blocks with the same letters and G/M/T codes; sequence numbers and comments
aside). Each numeric word that is not the same in every variant is fitted as an exact
expression: a constant, or an affine combination (coefficients snapped to small fractions)
of at most three traced features and parameters, fitted on some variants and held to the
written precision on all the others. An S or F word that fits nothing takes the safe bound
(the lowest of the variants: a slower spindle or feed) and says so in a comment; any other
word that fits nothing is refused, naming it, its line and the parameters that move it.

*Topology* (:func:`derive_pieces`): where a variant's skeleton differs from the nominal's,
the one parameter that changes it is found (moving each parameter alone) and the boundary
found by bisection; the domain is split there and each piece derived on its own (a program
per piece, each checking its own range). A change no single parameter makes is refused,
naming the parameters and the block that changes.

*Render* (:func:`render_program`): HNC-21T macro B — a main program with one
``#n=VALUE (NAME)`` per parameter (or, with a table, one block of them per row under
``IF [#50 EQ k]``, the operator setting the row number ``#50``), the family's checks and the
domain box before any motion, then ``M98 P…`` of the macro subprogram in the same file, whose
temporaries are all assigned before its first block. FANUC 0i macro B — ``G65 P… A… B…``
with the arguments of the FANUC letter table (A #1, B #2, C #3, I #4, ...), checks as
``#3000=n(MESSAGE)``.

*Check* (:func:`check_program`): the macro program, with each sampled set (and every table
row) substituted, is run through :func:`hnc_cam.nc.run`, simulated and verified against that
variant's model as ``verify`` does (:func:`hnc_cam.plan.api._verify`), and its toolpath
compared with the per-variant program's.
"""
from __future__ import annotations

import functools
import math
import random
import re
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from ..errors import HncError, PartError, PlanError
from ..units import round_written
from .macro import (MACRO_OPS, Check, Family, Lets, _ev, _holds, _negate, _node, _num,
                    _params_of, _trace, collinear_fractions, corner_law, features, hnc_checks,
                    render, walk)

#: what a fit may miss a written word by: the written precision (3 decimals, so half of
#: 0.001) and the float noise of the planner's arithmetic
TOL = 0.00055
#: the letters whose value is part of a block's skeleton (a code, not a dimension)
_CODES = set("GMTO")
_WORD = re.compile(r"([A-Z])\s*([-+]?(?:\d+\.?\d*|\.\d+))")
#: FANUC macro arguments (argument specification I): letter -> local variable
FANUC_ARGS = {"A": 1, "B": 2, "C": 3, "I": 4, "J": 5, "K": 6, "D": 7, "E": 8, "F": 9,
              "H": 11, "M": 13, "Q": 17, "R": 18, "S": 19, "T": 20, "U": 21, "V": 22,
              "W": 23, "X": 24, "Y": 25, "Z": 26}
#: HNC-21T globals: the row number, then the parameters, then the temporaries
HNC_FIRST, HNC_LAST = 50, 199
#: SINUMERIK 802 R parameters: the row number, then the parameters, then the temporaries, all
#: below the cycles' transfer parameters R100-R249
S802_FIRST, S802_LAST = 20, 99
#: the per-variant 802 program's header comments the macro replaces with its own
_S802_HEAD = (";$PATH=/_N_MPF_DIR", "; PARAMETERS", "; STOCK", "; COMPENSATION")


# ------------------------------------------------------------------------------------------
# blocks and words
# ------------------------------------------------------------------------------------------

@dataclass
class Word:
    letter: str
    text: str  # the number as written
    span: tuple[int, int]  # of the number in the line
    eq: bool = False  # SINUMERIK: written NAME=number (a fitted word needs the = added if not)

    @property
    def value(self) -> float:
        return float(self.text)


@dataclass
class Block:
    line: int  # 1-based line in the program
    raw: str
    words: list[Word]  # the words outside comments, N aside
    key: tuple  # skeleton

    @property
    def floating(self) -> bool:
        """A block that only switches the spindle's mode (``G96 S…``, ``G97 S…``, ``G50 S…``):
        where the planner puts one follows the diameter at which constant surface speed
        meets the spindle limit, so it moves with the parameters; it is no part of the
        skeleton (the macro keeps the nominal's G96/G50 and leaves the G97 to the control's
        clamp of G96 at its spindle limit)."""
        return (any(w.letter == "S" for w in self.words)
                and all(w.letter == "S" or (w.letter == "G" and float(w.text) in (96, 97, 50))
                        or (w.letter == "M" and float(w.text) in (3, 4))
                        for w in self.words) and self.key[-1] == "")

    @property
    def droppable(self) -> bool:
        """A floating ``G97 S…`` that starts nothing (the control clamps G96 itself)."""
        return self.floating and any(w.letter == "G" and float(w.text) == 97
                                     for w in self.words) \
            and not any(w.letter == "M" for w in self.words)


#: SINUMERIK 802 words: a name and ``=`` before the number (``R105=1``, ``CHF=1.414``,
#: ``X=19.2``), names and strings that are no words (``LCYC95``, ``_CNAME="PIN_C1"``), else a
#: letter and its number
_S_WORD = re.compile(
    r'(?P<str>"[^"]*")'
    r"|(?<![A-Z0-9_])(?P<named>R\d+|CHF|CR|AR|RND|IX|KZ|SF|LIMS|SPOS|[A-Z])\s*=\s*"
    r"(?P<nv>[-+]?(?:\d+\.?\d*|\.\d+))"
    r"|(?<![A-Z0-9_])(?P<name>[A-Z_][A-Z_][A-Z0-9_]*)(?![A-Z0-9_])"
    r"|(?<![A-Z_])(?P<letter>[A-Z])\s*(?P<v>[-+]?(?:\d+\.?\d*|\.\d+))")


def is_siemens(text: str) -> bool:
    """A SINUMERIK 802 program (its ``%_N_NAME_MPF`` header)."""
    return text.lstrip().startswith("%_N_")


def _add_block(out: list[Block], i: int, raw: str, words: list[Word], rest: list[str]) -> None:
    """Line ``i`` as a block of ``out`` unless it has no words and nothing else: its key is
    its letters, the code words' values and the text between the words."""
    other = "".join(rest)
    if not words and not other:
        return
    key = tuple((w.letter, w.text if w.letter in _CODES else None) for w in words) + (other,)
    out.append(Block(i, raw, words, key))


def _siemens_blocks(text: str) -> list[Block]:
    """:func:`blocks` of an 802 program: ``;`` comments, header lines ``%_N_...`` aside;
    a fitted word is written ``X=<expression>`` (:attr:`Word.eq` says whether the ``=`` is
    there)."""
    out: list[Block] = []
    for i, raw in enumerate(text.splitlines(), 1):
        code = raw.split(";", 1)[0]
        if not code.strip() or code.lstrip().startswith("%"):
            continue
        words: list[Word] = []
        rest: list[str] = []
        pos = 0
        for m in _S_WORD.finditer(code):
            if m.group("named") or m.group("letter"):
                letter = m.group("named") or m.group("letter")
                g = "nv" if m.group("named") else "v"
                rest.append(code[pos:m.start()].strip())
                pos = m.end()
                if letter == "N" and not words:
                    continue
                words.append(Word(letter, m.group(g), (m.start(g), m.end(g)),
                                  eq=bool(m.group("named"))))
        rest.append(code[pos:].strip())
        _add_block(out, i, raw, words, rest)
    return out


def blocks(text: str) -> list[Block]:
    """The blocks of a program that carry words (comment-only lines aside)."""
    if is_siemens(text):
        return _siemens_blocks(text)
    out: list[Block] = []
    for i, raw in enumerate(text.splitlines(), 1):
        spans, depth, start = [], 0, 0
        for j, ch in enumerate(raw):  # the parts outside comments
            if ch == "(":
                if depth == 0:
                    spans.append((start, j))
                depth += 1
            elif ch == ")" and depth:
                depth -= 1
                if depth == 0:
                    start = j + 1
        if depth == 0:
            spans.append((start, len(raw)))
        words: list[Word] = []
        rest: list[str] = []
        for a, b in spans:
            seg = raw[a:b]
            pos = 0
            for m in _WORD.finditer(seg):
                rest.append(seg[pos:m.start()].strip())
                pos = m.end()
                if m.group(1) == "N" and not words:
                    continue
                words.append(Word(m.group(1), m.group(2), (a + m.start(2), a + m.end(2))))
            rest.append(seg[pos:].strip())
        _add_block(out, i, raw, words, rest)
    return out


def core(bs: list[Block]) -> list[Block]:
    """The blocks that make the skeleton (floating spindle switches aside)."""
    return [b for b in bs if not b.floating]


def skeleton(bs: list[Block]) -> tuple:
    return tuple(b.key for b in core(bs))


def _first_difference(a: list[Block], b: list[Block]) -> str:
    a, b = core(a), core(b)
    for x, y in zip(a, b):
        if x.key != y.key:
            hint = ""
            cx, cy = _codes(x), _codes(y)
            if (76.0 in cx and 82.0 in cy) or (82.0 in cx and 76.0 in cy):
                hint = (" (the thread's cycle: the multiple-pass cycle's last pass ends "
                        "further along the insert's flank than the relief leaves room for at "
                        "some variants; --thread-cycle g82 cuts every variant with single "
                        "passes)")
            return f"line {x.line} [{x.raw.strip()}] becomes [{y.raw.strip()}]{hint}"
    longer, n = (a, len(b)) if len(a) > len(b) else (b, len(a))
    extra = longer[n] if n < len(longer) else longer[-1]
    return (f"the program has {abs(len(a) - len(b))} block(s) "
            f"{'fewer' if len(a) > len(b) else 'more'} from line {extra.line} "
            f"[{extra.raw.strip()}]")


# ------------------------------------------------------------------------------------------
# variants
# ------------------------------------------------------------------------------------------

def _fmt(v: Any) -> str:
    return _num(float(v)) if isinstance(v, float) else str(v)


def _pset(p: dict[str, Any], free: list[str]) -> str:
    return ", ".join(f"{k}={_fmt(p[k])}" for k in free)


@dataclass
class Ctx:
    """What every variant is generated with."""
    path: str
    opts: dict[str, Any]  # generate() keywords (comp control, no verify)
    stock: str
    dialect: str
    cache: dict = field(default_factory=dict)
    #: the per-variant programs a derivation may generate (a bound on its time)
    budget: int = 1200
    #: the last change of the program's shape the derivation split the domain at: (the
    #: piece's nominal set, the :class:`TopologyChange`), named where the budget runs out
    last_change: Any = None

    def rpm_limit(self, tool: int) -> float:
        """The spindle limit of tool ``tool`` (:func:`planner.rpm_limit`: the lowest of the
        machine's, the chuck's and the tool's)."""
        from .api import _load_machine, _load_tools
        from .planner import rpm_limit
        lib = _load_tools(self.opts.get("tools"))
        mach = _load_machine(self.opts.get("machine"), lib)
        t = lib.by_number(tool) if tool else None
        if t is not None:
            return rpm_limit(t, mach)
        return min(mach.max_rpm, mach.chuck_max_rpm) if mach.chuck_max_rpm > 0 else \
            mach.max_rpm

    def program(self, p: dict[str, Any]) -> str:
        key = tuple(sorted((k, _fmt(v)) for k, v in p.items()))
        if key not in self.cache:
            if len(self.cache) >= self.budget:
                last = ""
                if self.last_change is not None:
                    nom, ch = self.last_change
                    moved = [k for k in ch.p if isinstance(ch.p[k], float)
                             and abs(ch.p[k] - nom.get(k, ch.p[k])) > 1e-9]
                    last = (f"; the last change it split at: {ch.diff}, between "
                            f"{', '.join(f'{k}={_fmt(nom[k])}' for k in moved)} and "
                            f"{', '.join(f'{k}={_fmt(ch.p[k])}' for k in moved)}")
                raise PlanError(f"{self.path}: deriving the macro took {self.budget} "
                                f"per-variant programs without one law over the domain (its "
                                f"program changes in more places than decisions and pieces "
                                f"hold{last}); no macro is written")
            from .api import generate
            try:
                prog = generate(self.path, self.stock, params={k: _fmt(v) for k, v in p.items()},
                                **self.opts)
            except HncError as e:
                raise PlanError(f"{self.path}: the family's program cannot be generated for "
                                f"{', '.join(f'{k}={v}' for k, v in key)} (inside the macro's "
                                f"domain): {str(e).splitlines()[0]}") from None
            self.cache[key] = prog.text
        return self.cache[key]


def _same_branches(tr: Any, p: dict[str, float]) -> bool:
    return all(_holds(c if v else ("not", c), p) for c, v in tr.branches)


def _valid(fam: Family, tr: Any, p: dict[str, float], lo: dict, hi: dict,
           branches: bool = True, extra: list[tuple] = ()) -> bool:
    """``p`` is in the box, passes the family's checks and the ``extra`` conditions (a piece
    cut along a feature) and, with ``branches``, keeps the traced branches."""
    return (all(lo[k] <= p[k] <= hi[k] for k in fam.free)
            and all(_holds(c, p) for c in extra)
            and all(all(_holds(c, p) for c in ch.conds) for ch in tr.checks)
            and (not branches or _same_branches(tr, p)))


def sample(fam: Family, tr: Any, lo: dict, hi: dict, n: int, seed: Any,
           limit: int = 4000, branches: bool = True,
           extra: list[tuple] = ()) -> list[dict[str, Any]]:
    """``n`` parameter sets drawn uniformly from the box ``lo``..``hi`` that pass the family's
    checks (and keep the traced branches: ``branches``), fewer when the box holds few."""
    rnd = random.Random(str(seed))
    out: list[dict[str, Any]] = []
    for _ in range(limit):
        if len(out) >= n:
            break
        p = dict(fam.params)
        for k in fam.free:
            p[k] = round(rnd.uniform(lo[k], hi[k]), 3)  # what a control holds
        if _valid(fam, tr, p, lo, hi, branches, extra):
            out.append(p)
    return out


def _sketch_ok(fam: Family, p: dict[str, Any]) -> None:
    """``sketch()`` must accept a set the family's checks accept."""
    try:
        fam.mod.sketch(**p)
    except Exception as e:  # noqa: BLE001 - the family's own fault, named
        raise PartError(f"{fam.path}: sketch() raises for {_pset(p, fam.free)}, which its "
                        f"checks accept (inside the declared domain): "
                        f"{type(e).__name__}: {e}") from None


def family_stock(fam: Family, lo: dict, hi: dict, sets: list[dict[str, Any]]) -> str:
    """The stock the largest variant needs: the family's ``STOCK`` at the top of the box and at
    every set, the one with the largest diameter, then length; a tube's bore the smallest of
    them (the bore of the largest variant's tube would be wider than a small variant's
    bore)."""
    from ..tooling import Stock
    fn = getattr(fam.mod, "STOCK", None)
    best: Any = None
    bores: list[float] = []
    cands = [dict(fam.params, **hi), dict(fam.params, **lo)] + sets
    for p in cands:
        try:
            spec = fn(**p) if callable(fn) else fn
            if spec is None:
                from .api import _load_part, default_stock_for
                spec = default_stock_for(_load_part(fam.path, {k: _fmt(v) for k, v in
                                                              p.items()})[0])
            st = Stock.parse(str(spec))
        except Exception:  # noqa: BLE001 - an invalid corner of the box says nothing
            continue
        if st.kind == "tube":
            bores.append(st.bore)
        if best is None or (st.diameter, st.length, st.face) > (best.diameter, best.length,
                                                                  best.face):
            best = st
    if best is None:
        raise PartError(f"{fam.path}: no stock for the family's domain (STOCK() fails at every "
                        f"sampled set): give one with --stock")
    if best.kind == "tube" and min(bores) < best.bore:
        return (f"{_fmt(best.diameter)}/{_fmt(min(bores))}x{_fmt(best.length)}"
                + (f"+{_fmt(best.face)}" if best.face else ""))
    return best.spec


# ------------------------------------------------------------------------------------------
# fitting
# ------------------------------------------------------------------------------------------

@dataclass
class Slot:
    block: int  # index into the nominal's blocks
    word: int  # index into the block's words
    kind: str  # "const" | "fit" | "bound"
    node: tuple | None = None
    value: float | None = None
    note: str = ""
    #: written rounded to 0.001 at the control (a crossing: the tiny arc left beyond it has
    #: its centre set by the last digit of its ends)
    rounded: bool = False
    #: no set of the control's precision puts the word at a half of the last digit (any
    #: rounding to nearest writes it as the program does: FANUC's shorter ``ROUND``)
    tie_free: bool = False


def normal_features(tr: Any) -> list[tuple[str, tuple]]:
    """At each traced segment's ends, its normal's reciprocal X part and Z-over-X ratio
    (``1/n_x``, ``n_z/n_x``; a line's ``len/dz`` and ``dx/dz``): the planner's finishing
    allowance is ``(margin + gouge(n)) / n_x`` at the steepest normal, affine in these."""
    out: list[tuple[str, tuple]] = []
    for i, seg in enumerate(tr.segments):
        x0, z0, x1, z1 = _n(seg[1][0]), _n(seg[1][1]), _n(seg[2][0]), _n(seg[2][1])
        if seg[0] == "L":
            dx, dz = ("-", x1, x0), ("-", z1, z0)
            ln = ("f", "sqrt", ("+", ("*", dx, dx), ("*", dz, dz)))
            out += [(f"segment {i + 1} length/dz", ("/", ln, dz)),
                    (f"segment {i + 1} dx/dz", ("/", dx, dz))]
            # the unit normal (X on diameter): a path offset from the part by a constant
            # distance (the planner's roughing contours: nose radius plus allowance) has its
            # corners at the part's corner plus that distance times each side's normal
            out += [(f"segment {i + 1} normal X", ("/", ("*", ("c", 2.0), dz), ln)),
                    (f"segment {i + 1} normal Z", ("/", dx, ln))]
            continue
        if seg[3] is None:
            continue
        cx, cz, r = _n(seg[3][0]), _n(seg[3][1]), _n(seg[4])
        for end, (x, z) in (("start", (x0, z0)), ("end", (x1, z1))):
            out += [(f"segment {i + 1} {end} r/nx", ("/", r, ("-", x, cx))),
                    (f"segment {i + 1} {end} nz/nx", ("/", ("-", z, cz), ("-", x, cx))),
                    (f"segment {i + 1} {end} normal X",
                     ("/", ("*", ("c", 2.0), ("-", x, cx)), r)),
                    (f"segment {i + 1} {end} normal Z", ("/", ("-", z, cz), r))]
    return out


def segment_lengths(tr: Any) -> list[tuple[str, tuple]]:
    """Each traced line's length (the 802 writes a chamfer as ``CHF=`` its own length)."""
    from .macro import _Math
    out = []
    for i, s in enumerate(tr.segments):
        if s[0] == "L":
            (x0, z0), (x1, z1) = s[1], s[2]
            n = _node(_Math().sqrt((x1 - x0) * (x1 - x0) + (z1 - z0) * (z1 - z0)))
            out.append((f"segment {i + 1} length", n))
    return out


def _candidates(fam: Family, tr: Any, sets: list[dict[str, Any]], normals: bool = False,
                lengths: bool = False):
    """Columns (values over ``sets``) of the distinct non-constant features and parameters,
    with their expressions (the shortest of equal columns); with ``normals`` also the
    segments' normal ratios (:func:`normal_features`), with ``lengths`` the lines' lengths
    (:func:`segment_lengths`)."""
    import numpy as np
    feats = [(k, ("p", k)) for k in fam.free] + features(tr)
    if normals:
        feats += normal_features(tr)
    if lengths:
        feats += segment_lengths(tr)
    cols: dict[tuple, tuple[tuple, np.ndarray, int]] = {}
    env = {k: np.array([float(p[k]) for p in sets]) for k in fam.free}
    memo: dict[int, Any] = {}
    for _desc, n in feats:
        v = _varying(n, env, memo, sets)
        if v is None:
            continue
        key = tuple(np.round(v, 7))
        size = len(render(n, {k: "#" for k in fam.free})) if n[0] != "p" else 0
        if key not in cols or size < cols[key][2]:
            cols[key] = (n, v, size)
    nodes = [c[0] for c in cols.values()]
    mat = np.array([c[1] for c in cols.values()]).T if cols else np.zeros((len(sets), 0))
    return nodes, mat


def _ev_all(n: tuple, env: dict, memo: dict[int, Any], sets: list[dict]) -> Any:
    """:func:`macro._ev` over every set at once (:func:`macro.walk` on numpy arrays, ``memo``
    shared by the expressions of one call); an undefined value (a root of a negative number,
    a division by zero) is NaN or infinite, which the caller leaves out."""
    import numpy as np

    def leaf(m: tuple) -> Any:
        if m[0] == "c":
            return np.full(len(sets), float(m[1]))
        return env[m[1]] if m[1] in env else np.array([float(p[m[1]]) for p in sets])

    fun = {"sqrt": np.sqrt, "sin": np.sin, "cos": np.cos, "tan": np.tan, "atan": np.arctan,
           "abs": np.abs, "atan2": np.arctan2, "min": np.minimum, "max": np.maximum}
    return walk(n, leaf, fun, memo)


def _defined(n: tuple, env: dict, memo: dict[int, Any], sets: list[dict]) -> Any:
    """:func:`_ev_all`, None where the expression is undefined at one of the sets."""
    import numpy as np
    try:
        with np.errstate(all="ignore"):
            v = _ev_all(n, env, memo, sets)
    except (ValueError, ZeroDivisionError, OverflowError):
        return None
    return v if np.all(np.isfinite(v)) else None


def _varying(n: tuple, env: dict, memo: dict[int, Any], sets: list[dict]) -> Any:
    """:func:`_defined`, None also where the expression is the same at every set (no
    feature to fit with)."""
    import numpy as np
    v = _defined(n, env, memo, sets)
    return None if v is None or np.ptp(v) < 1e-9 else v


def _cross_columns(tr: Any, nb: list[Block], allb: list[list[Block]], allp: list[dict]):
    """The crossings' expressions and values over the sets (those defined at every set)."""
    import numpy as np
    dias = sorted({w.value for bi, b in enumerate(nb) for wi, w in enumerate(b.words)
                   if w.letter == "X" and w.value > 0
                   and all(vb[bi].words[wi].text == w.text for vb in allb)})
    nodes, cols = [], []
    for n in crossings(tr, dias):
        try:
            v = np.array([_ev(n, p) for p in allp])
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        if np.all(np.isfinite(v)):
            nodes.append(n)
            cols.append(v)
    return nodes, cols


def _position_before(bs: list[Block], i: int) -> tuple[float, float] | None:
    """(radius, Z) where the tool is when block ``i`` starts (the last X and Z written
    before it), None when the blocks do not say."""
    x = z = None
    for j in range(i - 1, -1, -1):
        for w in bs[j].words:
            if w.letter == "X" and x is None:
                x = w.value / 2
            elif w.letter == "Z" and z is None:
                z = w.value
        if x is not None and z is not None:
            return x, z
    return None


def _corner_crossing(tr: Any, allb: list[list[Block]], allp: list[dict], bi: int, y):
    """The Z of an arc block that ends on a diameter the program holds constant (a roughing
    cycle split where constant surface speed meets the spindle limit) where the arc is a
    corner of the planner's offset contour: centred at a constant offset from a traced
    contour point, its radius the block's constant R. The offset is read from the first
    variant's arc and must hold on every variant; None where no traced point gives one."""
    import numpy as np
    b = allb[0][bi]
    if not any(w.letter == "G" and float(w.text) in (2, 3) for w in b.words):
        return None
    ix = [i for i, w in enumerate(b.words) if w.letter in "XR"]
    if len(ix) != 2 or any(len({vb[bi].words[i].text for vb in allb}) != 1 for i in ix):
        return None
    rc = next(w.value for w in b.words if w.letter == "X") / 2
    rho = next(w.value for w in b.words if w.letter == "R")
    start = _position_before(allb[0], bi)
    if start is None:
        return None
    (r0, z0), (r1, z1) = start, (rc, float(y[0]))
    dr, dz = r1 - r0, z1 - z0
    chord = math.hypot(dr, dz)
    if chord < 1e-9 or chord > 2 * rho:
        return None
    h = math.sqrt(max(0.0, rho * rho - chord * chord / 4))
    mr, mz, ur, uz = (r0 + r1) / 2, (z0 + z1) / 2, -dz / chord, dr / chord
    verts = list(dict.fromkeys((_n(pt[0]), _n(pt[1])) for sg in tr.segments
                               for pt in sg[1:3]))
    for cr, cz in ((mr + ur * h, mz + uz * h), (mr - ur * h, mz - uz * h)):
        for vx, vz in verts:
            try:
                ox, oz = cr - _ev(vx, allp[0]), cz - _ev(vz, allp[0])
            except (ValueError, ZeroDivisionError, OverflowError):
                continue
            for nd in (1, 2, 3):  # the planner's offsets: nose radii and allowances
                t = ("-", ("c", rc), ("+", vx, ("c", round(ox, nd))))
                q = ("f", "sqrt", ("-", ("c", rho * rho), ("*", t, t)))
                base = ("+", vz, ("c", round(oz, nd)))
                for node in (("+", base, q), ("-", base, q)):
                    try:
                        v = np.array([_ev(node, p) for p in allp])
                    except (ValueError, ZeroDivisionError, OverflowError):
                        continue
                    if np.all(np.isfinite(v)) and np.max(np.abs(v - y)) <= TOL:
                        return node
    return None


@functools.lru_cache(maxsize=64)
def _cycle_contour(text: str) -> frozenset[tuple[int, str]]:
    """The words (line, letter) of the contours the roughing cycles of ``text`` name
    (``G71``/``G72`` ``P``..``Q``; the 802's contour subprograms, which LCYC95 roughs along
    Z) whose last digit moves a pass's end by more than the comparison's 0.001 mm: the ends
    of a line the passes cross at less than atan(1/2), 26.6 deg (a G71's: that near the Z
    axis, not along it; a G72's: the X axis), and of an arc, with its radius and centre. A
    pass ends where it meets the contour, so the radius's 0.00025 mm of a written diameter
    moves the pass's end by it over the line's slope, more than 0.0005 mm below it. (Read
    once per program: every alternative's fit asks for its first variant's.)"""
    lines = text.splitlines()
    runs: list[tuple[list[Block], bool]] = []  # (a contour's blocks, passes along Z)
    bs = blocks(text)
    by_line = {b.line: b for b in bs}
    sub: list[Block] | None = None
    for i, ln in enumerate(lines, 1):
        if ln.startswith("%_N_"):
            sub = [] if ln.endswith("_SPF") else None
            if sub is not None:
                runs.append((sub, True))
        elif sub is not None and i in by_line:
            sub.append(by_line[i])
    at: dict[str, int] = {}
    for k, b in enumerate(bs):
        m = _LEAD_N.match(b.raw)
        if m:
            at[m.group(2)] = k
    for b in bs:
        g = [float(w.text) for w in b.words if w.letter == "G"
             and w.text.replace(".", "", 1).isdigit()]
        if 71 in g or 72 in g:
            pq = {w.letter: w.text for w in b.words if w.letter in "PQ"}
            if pq.get("P") in at and pq.get("Q") in at:
                runs.append((bs[at[pq["P"]]:at[pq["Q"]] + 1], 71 in g))
    out: set[tuple[int, str]] = set()
    for run, along_z in runs:
        x = z = None
        prev: Block | None = None
        for b in run:
            w = {v.letter: v for v in b.words}
            try:
                x1 = float(w["X"].text) if "X" in w else x
                z1 = float(w["Z"].text) if "Z" in w else z
                codes = {float(v.text) for v in b.words if v.letter == "G"}
            except ValueError:
                x, z, prev = None, None, b
                continue
            arc = bool(codes & {2.0, 3.0})
            if x is not None and z is not None and x1 is not None and z1 is not None:
                dr, dz = abs(x1 - x) / 2, abs(z1 - z)
                cross, along = (dr, dz) if along_z else (dz, dr)
                if arc or (cross > 1e-9 and 2 * cross < along):
                    for blk in (prev, b):
                        if blk is not None:
                            out.update((blk.line, v.letter) for v in blk.words
                                       if v.letter in ROUNDED_LETTERS)
            x, z, prev = x1, z1, b
    return frozenset(out)


#: the words of a cycle's contour the macro writes rounded as the program does: its
#: coordinates and an arc's radius and centre
ROUNDED_LETTERS = ("X", "Z", "R", "I", "K", "CR")


def _rounds_all(node: tuple, allp: list[dict], y: Any, free: list[str]) -> bool:
    """The word's written values are its exact law written to 0.001 (the macro then writes
    it rounded as the program does), and no set of the control's precision puts the law at
    a half of the last digit (the planner's arithmetic breaks such a tie either way: the
    exact value is then half a digit from the written one, a rounded one may be a whole)."""
    try:
        if not all(_rounds_to(_ev(node, p), float(b)) for p, b in zip(allp, y)):
            return False
        p0 = {k: (round(v, 3) if k in free else v) for k, v in allp[0].items()}
        probes = [_ev(node, p) for p in allp]
        for k in sorted(_params_of(node) & set(free)):
            probes += [_ev(node, dict(p0, **{k: round(p0[k] + i / 1000, 3)})) for i in (1, 2, 3)]
    except (ValueError, ZeroDivisionError, OverflowError):
        return False
    return not any(abs(abs(v * 1000 - math.floor(v * 1000)) - 0.5) < 1e-6 for v in probes)


def _rounds_to(v: float, written: float) -> bool:
    """``v`` written to 0.001 is ``written``; at a tie (a half of the last digit, which the
    planner's arithmetic and the control's may break either way) either neighbour."""
    if abs(round_written(v) - written) < 1e-9 or abs(round(v, 3) - written) < 1e-9:
        return True
    k = v * 1000.0
    return abs(abs(k - math.floor(k)) - 0.5) < 1e-6 and abs(v - written) < 0.0005 + 1e-9


def _fit_single(y, nodes: list[tuple], cols: list) -> tuple | None:
    """``y`` as one crossing plus a constant."""
    import numpy as np
    for n, v in zip(nodes, cols):
        res = y - v
        mid = float((res.max() + res.min()) / 2)
        for const in (round(mid, 3), round(mid, 4), round(mid, 6)):
            if np.max(np.abs(res - const)) <= TOL:
                return _combine([n], (0,), [1.0], const)
    return None


def _snap(c: float) -> float:
    """The nearest simple fraction (the held-out check decides whether it holds)."""
    f = Fraction(c).limit_denominator(12)
    return float(f) if abs(float(f) - c) < 0.05 * max(1.0, abs(c)) else round(c, 9)


def _fit_word(y, mat, n_fit: int, simple: bool = False):
    """(column indices, coefficients, constant) of the sparsest exact affine fit, else None;
    with ``simple`` only fits whose coefficients are small fractions (:func:`_simple`)."""
    import itertools

    import numpy as np
    n, m = mat.shape

    def attempt(idx: tuple[int, ...]):
        if len(idx) == 2:  # the law of the smallest fractions first
            got = collinear_fractions(y, mat[:, idx[0]], mat[:, idx[1]], n_fit, TOL)
            if got is not None:
                return idx, *got
        a = np.column_stack([mat[:n_fit, list(idx)], np.ones(n_fit)]) if idx else \
            np.ones((n_fit, 1))
        sol, *_ = np.linalg.lstsq(a, y[:n_fit], rcond=None)
        tries = [[_snap(c) for c in sol[:-1]]]
        if not simple:
            tries.append([round(c, 9) for c in sol[:-1]])
        for coefs in tries:
            if simple and not _simple(coefs):
                continue
            pred = mat[:, list(idx)] @ np.array(coefs) if idx else np.zeros(n)
            res = y - pred
            mid = float((res.max() + res.min()) / 2)
            for const in (round(mid, 3), round(mid, 4), round(mid, 6)):
                if np.max(np.abs(res - const)) <= TOL:
                    return idx, coefs, const
        return None

    r = attempt(())
    if r:
        return r
    first = None
    for i in range(m):  # one feature: a simple coefficient (an exact law) before any other
        r = attempt((i,))
        if r and _simple(r[1]):
            return r
        first = first or r
    if first:
        return first
    best: list[tuple[float, tuple[int, int]]] = []
    # of two features, the plainest law that holds (the smallest denominators, then the
    # closest): over the variants of a narrow domain a law of thirds and quarters may hold as
    # well as the exact one of halves, 0.0006 mm off a little further on
    plain = None
    for pair in itertools.combinations(range(m), 2):
        r = attempt(pair)
        if r:
            err = float(np.max(np.abs(y - mat[:, list(r[0])] @ np.array(r[1]) - r[2])))
            key = (sum(Fraction(c).limit_denominator(1000).denominator for c in r[1]), err)
            if key[0] <= 3 and err <= HALF:
                return r
            if plain is None or key < plain[0]:
                plain = (key, r)
            continue
        a = np.column_stack([mat[:n_fit, list(pair)], np.ones(n_fit)])
        sol, *_ = np.linalg.lstsq(a, y[:n_fit], rcond=None)
        best.append((float(np.max(np.abs(a @ sol - y[:n_fit]))), pair))
    if plain:
        return plain[1]
    best.sort()
    for _err, pair in best[:12]:
        for k in range(m):
            if k not in pair:
                r = attempt(pair + (k,))
                if r:
                    return r
    return None


def _combine(nodes: list[tuple], idx, coefs, const) -> tuple:
    out: tuple | None = None
    for i, c in zip(idx, coefs):
        n, neg = nodes[i], c < 0
        term = n if abs(c) == 1 else ("*", ("c", abs(c)), n)
        if out is None:
            out = ("neg", term) if neg else term
        else:
            out = ("-" if neg else "+", out, term)
    if out is None:
        return ("c", const)
    if const > 0:
        return ("+", out, ("c", const))
    if const < 0:
        return ("-", out, ("c", -const))
    return out


def _n(v: Any) -> tuple:
    return _node(v)


def crossings(tr: Any, diameters: list[float]) -> list[tuple]:
    """Where each traced segment crosses each diameter the program holds constant (a roughing
    cycle split at the diameter where constant surface speed meets the spindle limit): Z of
    the crossing as an exact expression (both roots of an arc; the fit keeps the one that
    holds)."""
    out: list[tuple] = []
    for seg in tr.segments:
        x0, z0, x1, z1 = _n(seg[1][0]), _n(seg[1][1]), _n(seg[2][0]), _n(seg[2][1])
        for dia in diameters:
            rc = ("c", dia / 2)
            if seg[0] == "L":
                out.append(("+", z0, ("*", ("/", ("-", rc, x0), ("-", x1, x0)),
                                      ("-", z1, z0))))
                continue
            r = _n(seg[4])
            if seg[3] is not None:
                centers = [(_n(seg[3][0]), _n(seg[3][1]))]
            else:
                dx, dz = ("-", x1, x0), ("-", z1, z0)
                ln = ("f", "sqrt", ("+", ("*", dx, dx), ("*", dz, dz)))
                h = ("f", "sqrt", ("-", ("*", r, r), ("/", ("*", ln, ln), ("c", 4.0))))
                mx, mz = ("/", ("+", x0, x1), ("c", 2.0)), ("/", ("+", z0, z1), ("c", 2.0))
                ux, uz = ("/", ("neg", dz), ln), ("/", dx, ln)
                centers = [(("+", mx, ("*", ux, h)), ("+", mz, ("*", uz, h))),
                           (("-", mx, ("*", ux, h)), ("-", mz, ("*", uz, h)))]
            for cx, cz in centers:
                q = ("f", "sqrt", ("-", ("*", r, r), ("*", ("-", rc, cx), ("-", rc, cx))))
                out += [("+", cz, q), ("-", cz, q)]
    return out


@dataclass
class Piece:
    """One macro program: its domain (the box and the traced conditions) and its words."""
    fam: Family
    tr: Any
    lo: dict[str, float]
    hi: dict[str, float]
    nominal: dict[str, Any]
    text: str  # the nominal variant's program
    blocks: list[Block]
    slots: list[Slot]
    sets: list[dict[str, Any]]  # the variants it was fitted and held to
    bounds: list[str] = field(default_factory=list)  # how this piece's range was cut
    stock: str = ""
    extra: list[tuple] = field(default_factory=list)  # conditions of a cut along a feature
    regions: list = field(default_factory=list)  # Region: the program's sections, decided

    @property
    def fitted(self) -> int:
        """The fitted words of every alternative."""
        return sum(s.kind == "fit" for rg in self.regions for a in rg.alts for s in a.slots)

    @property
    def decisions(self) -> list[str]:
        """The thresholds the program decides at the control."""
        return [lab for rg in self.regions if rg.tree is not None for lab in rg.tree.labels()]


class TopologyChange(Exception):
    """A set where the program is not the nominal's: another skeleton, another traced
    branch, or a word that leaves the law it follows near the nominal (``law``: block, word,
    expression)."""

    def __init__(self, p: dict[str, Any], diff: str, law: tuple | None = None,
                 split: tuple | None = None):
        super().__init__(diff)
        self.p, self.diff, self.law = p, diff, law
        #: a word that follows one of two laws, the planner switching between them: (block
        #: among the alternative's, word, the nominal's law, the other), for a decision
        self.split = split


def _local_law(y, mat, nodes, allp, fam: Family, nominal: dict, near: int = 8):
    """The law a word follows near the nominal (fitted on the ``near`` sets closest to it,
    nominal first), and the sets that break it; None where nothing fits even there."""
    import numpy as np
    span = {k: (max(p[k] for p in allp) - min(p[k] for p in allp)) or 1.0 for k in fam.free}
    dist = np.array([sum(((p[k] - nominal[k]) / span[k]) ** 2 for k in fam.free)
                     for p in allp])
    order = np.argsort(dist, kind="stable")
    rnd = random.Random(0)
    others = [int(i) for i in order if i != 0]

    def nearest(simple: bool):
        for n in range(near, 5, -1):
            r = _fit_word(y[order[:n]], mat[order[:n]], n, simple=simple)
            if r is not None:
                node = _combine(nodes, *_settled(y, mat, r))
                return node, [i for i in order if abs(_ev(node, allp[i]) - y[i]) > TOL]
        return None

    def most(rounds: int, size: int, simple: bool):
        # the law of the most sets with the nominal among them, from small random subsets
        best = None
        for _ in range(rounds):
            sub = [0] + rnd.sample(others, min(size, len(others)))
            r = _fit_word(y[sub], mat[sub], len(sub))
            if r is None or (simple and not _simple(r[1])):
                continue
            node = _combine(nodes, *_settled(y, mat, r))
            off = [i for i in order if abs(_ev(node, allp[i]) - y[i]) > TOL]
            if best is None or len(off) < len(best[1]):
                best = (node, off)
        return best if best is not None and len(best[1]) <= len(allp) - 6 else None

    # a law of small fractions before a near fit: the nearest sets may lie across the change
    # (a split that follows d1 above a kink and stays below it), where a near law of several
    # features fits them and misses sets on the nominal's own side too; then the law of
    # small fractions most sets follow (two laws over about half the sets each), then the
    # near fits
    return nearest(True) or most(48, 3, True) or nearest(False) or most(24, 5, False)


def _movers(ctx: Ctx, fam: Family, tr: Any, nominal: dict, lo: dict, hi: dict,
            bi: int, wi: int, nb: list[Block]) -> list[str]:
    """The parameters whose change alone moves word ``wi`` of block ``bi``."""
    out = []
    base = nb[bi].words[wi].text
    for k in fam.free:
        for t in (0.5, -0.5):
            p = dict(nominal)
            p[k] = nominal[k] + t * (hi[k] - lo[k]) / 2
            if not _valid(fam, tr, p, lo, hi):
                continue
            vb = core(blocks(ctx.program(p)))
            if skeleton(vb) == skeleton(nb) and vb[bi].words[wi].text != base:
                out.append(k)
                break
    return out


#: the fewest variants an alternative of a decision is fitted from
MIN_ALT = 12


@dataclass
class Alt:
    """One alternative of a region: its representative variant's sections, their core
    blocks and fitted words, and the variants it was fitted on."""
    rep: Any  # macro_merge.Prog
    secs: list
    blocks: list[Block]
    slots: list[Slot]
    sets: list[dict[str, Any]]
    #: HNC-21T: the spindle switches the variants make at different blocks, by gap
    #: (:func:`spindle_gaps`)
    spin: dict[int, "SpinGap"] = field(default_factory=dict)


@dataclass
class Region:
    """A run of the nominal's sections and its alternatives (one, or several told apart by
    ``tree``)."""
    span: tuple[int, int]
    alts: list[Alt]
    tree: Any = None  # macro_merge.Node


def _fit_blocks(ctx: Ctx, fam: Family, tr: Any, nominal: dict, lo: dict, hi: dict,
                allb: list[list[Block]], allp: list[dict], n_fit: int,
                law_at: int | None) -> list[Slot]:
    """Each word of blocks that every variant in ``allb`` has alike (same skeleton): a
    constant, an exact expression of the traced features, a crossing, a piecewise law (the
    larger or smaller of two), or for S/F the lowest value. ``law_at``: the offset of these
    blocks among the nominal's core blocks (None: not the nominal's alternative)."""
    import numpy as np
    nb = allb[0]
    contour = _cycle_contour(ctx.program(allp[0]))
    nodes, mat = _candidates(fam, tr, allp, lengths=ctx.dialect == "siemens802")
    nodes2 = mat2 = None
    cross = None
    crossed: list[tuple[Any, Slot]] = []  # the crossings fitted so far, with their values
    slots: list[Slot] = []
    for bi, b in enumerate(nb):
        for wi, w in enumerate(b.words):
            texts = {vb[bi].words[wi].text for vb in allb}
            cycle = w.letter in "PQ" and any(x.letter == "G" and float(x.text) in (70, 71, 72, 73)
                                             for x in b.words)
            if cycle:
                slots.append(Slot(bi, wi, "label"))
                continue
            if len(texts) == 1 or w.letter in _CODES:
                slots.append(Slot(bi, wi, "const"))
                continue
            y = np.array([vb[bi].words[wi].value for vb in allb])
            r = _fit_word(y, mat, min(n_fit + 1, len(allp)))
            if r is not None and not _simple(r[1]):
                # coefficients that are no small fractions fit the few variants of a narrow
                # alternative without being its law (0.001 mm off elsewhere): an exact law of
                # the normals (a rounded corner's end: the corner plus the offset along its
                # sides' normals) comes first where one holds
                if nodes2 is None:
                    nodes2, mat2 = _candidates(fam, tr, allp, normals=True,
                                               lengths=ctx.dialect == "siemens802")
                r2 = _fit_word(y, mat2, min(n_fit + 1, len(allp)), simple=True)
                if r2 is not None:
                    slots.append(Slot(bi, wi, "fit", _combine(nodes2, *r2)))
                    continue
            if r is not None and w.letter == "Z" and _simple(r[1]):
                # a crossing of a line of simple slope (a 45 deg chamfer) at a diameter the
                # program holds constant is an affine law too, but the program writes it
                # rounded; where the rounding shows (a variant off the exact law), the macro
                # rounds it as the program does (the compensated path follows the corner the
                # rounding leaves)
                node = _combine(nodes, *r)
                if max(abs(_ev(node, p) - yy) for p, yy in zip(allp, y)) > 1e-6:
                    if cross is None:
                        cross = _cross_columns(tr, nb, allb, allp)
                    cn = _fit_single(y, *cross)
                    if cn is not None and all(_rounds_to(_ev(cn, p), yy)
                                              for p, yy in zip(allp, y)):
                        slots.append(Slot(bi, wi, "fit", cn, rounded=True))
                        crossed.append((y, slots[-1]))
                        continue
            if r is not None and (_simple(r[1]) or w.letter != "Z"):
                slots.append(Slot(bi, wi, "fit", _combine(nodes, *r)))
                continue
            if w.letter == "Z":  # a crossing before a fit of unrounded coefficients
                if cross is None:
                    cross = _cross_columns(tr, nb, allb, allp)
                node = _fit_single(y, *cross)
                if node is None and r is None:
                    node = _corner_crossing(tr, allb, allp, bi, y)
                if node is None and r is None:  # where an earlier arc ended (G00 X, G01 Z)
                    node = next((sl.node for yy, sl in crossed if np.array_equal(yy, y)), None)
                if node is not None:
                    slots.append(Slot(bi, wi, "fit", node, rounded=True))
                    crossed.append((y, slots[-1]))
                    continue
            # a rounded corner of an offset contour (the 802's RND= corner, a fillet's
            # tangent point) before a fit of unrounded coefficients
            node = corner_law(tr, allb, allp, bi, wi, y, TOL, _varying)
            if node is not None:
                slots.append(Slot(bi, wi, "fit", node))
                continue
            if r is not None:
                slots.append(Slot(bi, wi, "fit", _combine(nodes, *r)))
                continue
            if w.letter in ("S", "F", "R111", "R112"):  # R111/R112: LCYC95's feeds
                v = float(min(y))
                slots.append(Slot(bi, wi, "bound", value=v,
                                  note=f"{w.letter}{'=' if w.eq else ''}{_num(v)}: THE "
                                       f"LOWEST OF {len(y)} VARIANTS"))
                continue
            if nodes2 is None:  # the normals' ratios, for an allowance's law
                nodes2, mat2 = _candidates(fam, tr, allp, normals=True,
                                           lengths=ctx.dialect == "siemens802")
            r = _fit_word(y, mat2, min(n_fit + 1, len(allp)))
            if r is not None:
                slots.append(Slot(bi, wi, "fit", _combine(nodes2, *r)))
                continue
            law = _local_law(y, mat2, nodes2, allp, fam, allp[0])
            node = _piecewise(y, mat2, nodes2, law, allp) if law is not None else None
            if node is not None:
                slots.append(Slot(bi, wi, "fit", node))
                continue
            if law is not None and law[1] and law_at is not None:
                raise TopologyChange(allp[law[1][0]], f"the word {w.letter}{w.text} (line "
                                     f"{b.line}: {b.raw.strip()}) changes its law",
                                     (law_at + bi, wi, law[0]),
                                     _split(y, mat2, nodes2, law, bi, wi))
            kink = _kinked(slots, nb, allp) if law_at is not None else None
            if kink is not None:  # two regimes of an earlier word's switch fitted as one
                kink.law = (law_at + kink.law[0],) + kink.law[1:]
                raise kink
            movers = _movers(ctx, fam, tr, nominal, lo, hi, law_at + bi, wi,
                             core(blocks(ctx.program(nominal)))) if law_at is not None else []
            raise PlanError(f"{fam.path}: the word {w.letter}{w.text} of the family's program "
                            f"(line {b.line}: {b.raw.strip()}) fits no exact expression of the "
                            f"parameters (moved by {', '.join(movers) or 'several parameters together'})"
                            f"; no macro is written")
    # the shallow parts of a roughing cycle's contour as the program writes them
    for sl in slots:
        if (sl.kind == "fit" and not sl.rounded
                and (nb[sl.block].line, nb[sl.block].words[sl.word].letter) in contour):
            y = [vb[sl.block].words[sl.word].value for vb in allb]
            sl.rounded = sl.tie_free = _rounds_all(sl.node, allp, y, fam.free)
    return slots


def _is_kink(sl: Slot) -> bool:
    """A word fitted as the larger or smaller of two laws."""
    return sl.kind == "fit" and isinstance(sl.node, tuple) and sl.node[0] in ("max", "min")


def _kink_change(sl: Slot, ab: list[Block], nominal: dict, p: dict) -> TopologyChange:
    """The kinked word ``sl`` of the blocks ``ab`` as a law change seen at ``p``, its split
    the nominal's law first (the larger of the two at the nominal under ``max``)."""
    kind, n1, n2 = sl.node
    if (_ev(n1, nominal) >= _ev(n2, nominal)) != (kind == "max"):
        n1, n2 = n2, n1
    b = ab[sl.block]
    w = b.words[sl.word]
    return TopologyChange(p, f"the word {w.letter}{w.text} (line {b.line}: {b.raw.strip()}) "
                             f"changes its law", (sl.block, sl.word, n1),
                          (sl.block, sl.word, n1, n2))


def _kinked(slots: list[Slot], nb: list[Block], allp: list[dict]) -> TopologyChange | None:
    """The first word fitted as the larger or smaller of two laws, as a law change at a set
    where its other law holds (:func:`_kink_change`; the law's block among ``nb``). A later
    word that fits nothing over the same variants often follows the planner's two regimes
    of that switch (the G71's split on a taper below a diameter, on the chamfer above):
    deciding the switch first lets each regime fit its own laws."""
    for sl in filter(_is_kink, slots):
        _kind, n1, n2 = sl.node
        try:
            d0 = _ev(n1, allp[0]) - _ev(n2, allp[0])
            other = next((p for p in allp[1:] if (_ev(n1, p) - _ev(n2, p)) * d0 < 0), None)
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        if other is not None:
            return _kink_change(sl, nb, allp[0], other)
    return None


def _simple(coefs) -> bool:
    """Coefficients that are small fractions (a dimension's own law, not a near-fit)."""
    return all(abs(float(Fraction(c).limit_denominator(12)) - c) < 1e-9 for c in coefs)


def _piecewise(y, mat, nodes, law, allp: list[dict]) -> tuple | None:
    """A word that is the larger (or smaller) of two exact laws: the planner's allowance that
    the steepest of several normals decides. ``law``: the law near the nominal and the sets
    it misses; the second law is fitted on those, and max/min of the two must hold on all."""
    import numpy as np
    node1, off = law
    if len(off) < 5:
        return None
    off = list(off)
    r = _fit_word(y[off], mat[off], len(off) - 1)
    if r is None:
        return None
    node2 = _combine(nodes, *r)
    for kind in ("max", "min"):
        n = (kind, node1, node2)
        try:
            if np.max(np.abs(np.array([_ev(n, p) for p in allp]) - y)) <= TOL:
                return n
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
    return None


def _split(y, mat, nodes, law, bi: int, wi: int) -> tuple | None:
    """A word's two laws, the nominal's (``law``: its node and the sets that break it) and
    the one those sets follow: (block, word, first law, second law), else None."""
    node1, off = law
    if len(off) < 3:
        return None
    off = list(off)
    # few sets on the other side (a switch near the domain's edge): only a law of small
    # fractions (a constant, a dimension plus a constant), which the decision's held-out
    # variants and the check then prove
    r = _fit_word(y[off], mat[off], len(off) - 1, simple=True) or \
        (_fit_word(y[off], mat[off], len(off) - 1) if len(off) >= 5 else None)
    if r is None:
        return None
    return bi, wi, node1, _combine(nodes, *_settled(y[off], mat[off], r))


def _settled(y, mat, r: tuple) -> tuple:
    """The fit ``r`` (columns, coefficients, constant) with the constant most of ``y`` follow
    to a quarter of the written digit, then to half of it: a set beside a kink (0.001 off
    the law, inside the fit's tolerance) pulls a least-squares constant half a digit off,
    which then misses half of the law's own sets by the rounding."""
    import numpy as np
    idx, coefs, const = r
    pred = mat[:, list(idx)] @ np.array(coefs) if idx else np.zeros(len(y))
    res = y - pred
    c3 = round(const, 3)
    best = None
    for c in (c3, const, round(c3 + 0.001, 3), round(c3 - 0.001, 3)):
        score = (int(np.sum(np.abs(res - c) <= 0.00025 + 1e-9)),
                 int(np.sum(np.abs(res - c) <= HALF)))
        if best is None or score > best[0]:
            best = (score, c)
    return idx, coefs, best[1]


def _law_label(w: float, p: dict[str, Any], a: tuple, b: tuple) -> int | None:
    """Which of a split's two laws the written ``w`` at ``p`` follows: 0 the first, 1 the
    second, None neither. Beside their crossing, where both hold to the written digit, the
    nearer (a bisection of the planner's switch that lands there is not thrown to either
    side); 2 where both are as near."""
    try:
        da, db = abs(w - _ev(a, p)), abs(w - _ev(b, p))
    except (ValueError, ZeroDivisionError, OverflowError):
        return None
    if da <= TOL and db <= TOL:
        return 0 if da < db - 1e-9 else 1 if db < da - 1e-9 else 2
    return 0 if da <= TOL else 1 if db <= TOL else None


def region_key(nomp: Any, v: Any, reg: tuple, splits: list[tuple] = ()) -> tuple | None:
    """The alternative variant ``v`` takes in region ``reg``: its sections' skeleton, and for
    each of the region's law splits (skeleton, block, word, first law, second law) that
    applies to that skeleton, which law it follows (:func:`_law_label`)."""
    from . import macro_merge as mm
    k = mm.alt_key(nomp, v, reg)
    if k is None or not splits:
        return k
    vb = None
    labs = []
    for sk, bi, wi, a, b in splits:
        if sk != k:
            continue
        if vb is None:
            vb = [x for sec in mm.run_of(nomp, v, reg) for x in sec.blocks]
        if bi >= len(vb) or wi >= len(vb[bi].words):
            return None
        labs.append(_law_label(vb[bi].words[wi].value, v.p, a, b))
    if None in labs:
        return None
    return k + (("law",) + tuple(labs),) if labs else k


#: the law splits (:class:`TopologyChange` ``split``) one piece decides at the control
MAX_SPLITS = 3


class _Resplit(Exception):
    """A word of the nominal's program follows two laws: derive the piece again with that
    split (the nominal's core block, word, its law, the other law)."""

    def __init__(self, split: tuple, change: TopologyChange):
        super().__init__(change.diff)
        self.split, self.change = split, change


def _region_splits(nomp: Any, reg: tuple, splits: list[tuple]) -> list[tuple]:
    """The splits inside region ``reg``, as :func:`region_key` takes them: (the nominal's
    alternative, block among its run's, word, law, law)."""
    from . import macro_merge as mm
    at = {b.line: i for i, b in enumerate(x for sec in nomp.secs[reg[0]:reg[1]]
                                          for x in sec.blocks)}
    sk = mm.alt_key(nomp, nomp, reg)
    return [(sk, at[ln], wi, a, b) for ln, wi, a, b in splits if ln in at]


def _split_sections(nomp: Any, splits: list[tuple]) -> list[int]:
    """The nominal's section of each split's block."""
    return [j for j, sec in enumerate(nomp.secs) for ln, *_ in splits
            if any(b.line == ln for b in sec.blocks)]


def _skeleton_key(key: tuple) -> tuple:
    """An alternative's key without its law labels (:func:`region_key`)."""
    return key[:-1] if key and isinstance(key[-1], tuple) and key[-1][:1] == ("law",) else key


def _ambiguous(key: Any) -> bool:
    """A variant that follows both laws of a split (beside their crossing)."""
    return key is not None and key != _skeleton_key(key) and 2 in key[-1][1:]


def _layout(ctx: Ctx, fam: Family, tr: Any, lo: dict, hi: dict, nb: list[Block], nomp: Any,
            progs: list[Any], add: Any, probed: set, seed: Any, extra: Any,
            splits: list[tuple]) -> tuple[list[tuple], list[Any]]:
    """The program's regions, each with its alternatives (keys), each variant's label and the
    decision tree telling them apart; variants added (``add``) until every alternative has
    :data:`MIN_ALT` and every combination of thresholds was probed. A variant that follows
    both laws of a split takes the alternative the tree picks for it."""
    from . import macro_merge as mm
    edges = [0]  # the edge probes drawn (each draw its own seed)
    edge_memo: dict[tuple, dict] = {}  # by region, the cuts proven on them
    for rnd in range(6):
        allv = [nomp] + progs
        layout = []
        need: list[list[tuple]] = []
        probe: list[list[tuple]] = []
        for reg in mm.regions(nomp, progs, _split_sections(nomp, splits)):
            sp = _region_splits(nomp, reg, splits)
            keys = [region_key(nomp, v, reg, sp) for v in allv]
            amb = [i for i, k in enumerate(keys) if _ambiguous(k)]
            # (every variant beside a crossing of its laws: the one alternative they share)
            distinct = list(dict.fromkeys(k for i, k in enumerate(keys) if i not in amb)) or \
                keys[:1]
            labels = [distinct.index(k) if i not in amb else -1 for i, k in enumerate(keys)]
            tree = None
            if len(distinct) > 1:
                other = next(v for v, lab in zip(allv, labels) if lab > 0)
                diff = _first_difference(nb, core(blocks(other.text)))
                if None in distinct:
                    raise TopologyChange(other.p, diff)
                if ctx.dialect == "siemens802" and any(
                        ln.startswith("%_N_") for ln in nomp.text.splitlines()[
                            nomp.secs[reg[0]].a:nomp.secs[reg[1] - 1].b]):
                    # the 802 jumps (GOTOF) only inside one program: a contour subprogram
                    # the decision changes is decided by pieces of the domain instead
                    raise TopologyChange(other.p, diff)

                def side(p0, p1, t, reg=reg, distinct=distinct, sp=sp):
                    p = {k: (p0[k] + t * (p1[k] - p0[k]) if k in fam.free else p0[k])
                         for k in p0}
                    try:
                        v = mm.prog(p, ctx.program(p), ctx.dialect)
                    except PlanError:
                        return None
                    mm.align(nomp, v)
                    key = region_key(nomp, v, reg, sp)
                    return distinct.index(key) if key in distinct else None
                keep = [i for i in range(len(allv)) if i not in amb]
                def beside(conds: list[tuple], n: int, reg=reg) -> list[dict]:
                    edges[0] += 1
                    return sample(fam, tr, lo, hi, n, ("edge", seed, reg, edges[0]),
                                  limit=1000, branches=False, extra=list(extra) + conds)
                beside.memo = edge_memo.setdefault(reg, {})
                tree = mm.build_tree(fam, tr, [allv[i].p for i in keep],
                                     [labels[i] for i in keep], side, probe=beside)
                if tree is None:
                    raise TopologyChange(other.p, diff)
                for i in amb:
                    labels[i] = tree.pick(allv[i].p)
                paths = tree.paths()
                need += [paths[i] for i in range(len(distinct)) if labels.count(i) < MIN_ALT]
                probe += _cross_probes(tree, probed)
            else:
                labels = [0] * len(allv)
            layout.append((reg, distinct, labels, tree, sp))
        if not (need or probe) or rnd == 5:
            break
        for conds in need:
            add(sample(fam, tr, lo, hi, MIN_ALT, ("more", seed, rnd, len(progs)),
                       branches=False, extra=list(extra) + conds))
        for conds in probe:
            add(sample(fam, tr, lo, hi, 1, ("probe", seed, rnd, len(progs)), limit=1000,
                       branches=False, extra=list(extra) + conds))
    return layout, [nomp] + progs


def _resplit(t: TopologyChange, nb: list[Block]) -> None:
    """Raise :class:`_Resplit` for a law change of the nominal's alternative that a decision
    can hold (the split by its block's line in the nominal's program), else the change."""
    if t.split is None or t.law is None:
        raise t
    raise _Resplit((nb[t.law[0]].line,) + tuple(t.split[1:]), t)


def _fit_regions(ctx: Ctx, fam: Family, tr: Any, lo: dict, hi: dict, nominal: dict,
                 nb: list[Block], nomp: Any, allv: list[Any], layout: list[tuple], n_fit: int,
                 seed: Any, extra: Any) -> tuple[list[Region], list[tuple]]:
    """Each alternative's words fitted on its variants and proven on fresh ones (and beside
    the kinks of its larger-of-two laws); the regions, and the HNC-21T alternatives whose
    spindle switches are still to be placed."""
    from . import macro_merge as mm
    line_ix = {b.line: i for i, b in enumerate(nb)}
    regions: list[Region] = []
    spins: list[tuple] = []  # HNC-21T: (alternative, its variants, conditions, seed)
    for reg, distinct, labels, tree, sp in layout:
        alts = []
        for li in range(len(distinct)):
            members = [v for v, lab in zip(allv, labels) if lab == li]
            if len(members) < 4:
                raise TopologyChange(members[0].p, f"too few variants ({len(members)}) take "
                                     f"one of the program's alternatives "
                                     f"({', '.join(tree.labels())})")
            runs = [mm.run_of(nomp, v, reg) for v in members]
            allb = [[b for s in run for b in s.blocks] for run in runs]
            at = None
            if members[0] is nomp:
                at = line_ix[allb[0][0].line] if allb[0] else 0
            try:
                slots = _fit_blocks(ctx, fam, tr, nominal, lo, hi, allb,
                                    [v.p for v in members], min(n_fit, len(members) - 2),
                                    at) if allb[0] else []
            except TopologyChange as t:
                _resplit(t, nb)
            spare: list[tuple] = []  # the fresh variants the laws held on
            # the alternative's own part of the domain: the piece's and its leaf's conditions
            where = list(extra) + (tree.paths()[li] if tree is not None else [])
            if allb[0]:
                for attempt in range(2):
                    fresh = _held_out(ctx, fam, tr, lo, hi, nomp, reg, distinct[li], where,
                                      allb[0], ("hold", seed, reg, li, attempt), sp)
                    fresh += _kink_probes(ctx, fam, tr, lo, hi, nomp, reg, distinct[li], where,
                                          allb[0], slots, [v.p for v in members], sp)
                    # first to the written half digit: an exact law is within it at every
                    # variant, a near fit passes the fit's 0.00055 only by the margin above it
                    miss = _missed(slots, allb[0], fresh, HALF if attempt == 0 else TOL)
                    if miss is None:
                        spare = fresh
                        break
                    if attempt == 1:
                        s, p, got = miss
                        b = allb[0][s.block]
                        w = b.words[s.word]
                        if at is not None and _is_kink(s):
                            # the planner switches between the two laws away from where
                            # they cross: a decision at its own switch
                            t = _kink_change(s, allb[0], nominal, p)
                            t.law = (at + t.law[0],) + t.law[1:]
                            _resplit(t, nb)
                        movers = _movers(ctx, fam, tr, nominal, lo, hi, at + s.block, s.word,
                                         nb) if at is not None else []
                        raise PlanError(
                            f"{fam.path}: the word {w.letter}{w.text} of the family's program "
                            f"(line {b.line}: {b.raw.strip()}) follows no exact law of the "
                            f"parameters (moved by "
                            f"{', '.join(movers) or 'several parameters together'}): its fit "
                            f"on the sampled variants is {abs(got - _ev(s.node, p)):.4f} mm "
                            f"off at {_pset(p, fam.free)}; no macro is written")
                    # a near fit the fresh sets break: fitted again with them
                    members += [v for v, _run in fresh]
                    runs += [run for _v, run in fresh]
                    allb += [[b for sec in run for b in sec.blocks] for _v, run in fresh]
                    # (the least squares over all of them: the written digits' rounding
                    # averages out)
                    try:
                        slots = _fit_blocks(ctx, fam, tr, nominal, lo, hi, allb,
                                            [v.p for v in members], len(members) - 1, at)
                    except TopologyChange as t:
                        _resplit(t, nb)
            alt = Alt(members[0], runs[0], allb[0], slots, [v.p for v in members])
            if ctx.dialect == "hnc21t" and allb[0]:
                spins.append((alt, list(zip(members, runs)) + spare, where, (seed, reg, li)))
            alts.append(alt)
        regions.append(Region(reg, alts, tree))
    return regions, spins


def derive_piece(ctx: Ctx, fam: Family, lo: dict, hi: dict, nominal: dict[str, Any],
                 n_fit: int = 10, n_hold: int = 8, seed: Any = 0,
                 extra: list[tuple] = ()) -> Piece:
    """Fit one program over the box ``lo``..``hi``: the variants' programs cut into sections
    and aligned (:mod:`hnc_cam.plan.macro_merge`); where they differ, a decision tree on
    traced features picks the alternative at the control; each alternative's words fitted
    on its own variants. Raises :class:`TopologyChange` where no such tree tells the
    variants apart (or a word leaves its law), for :func:`derive_pieces` to split."""
    from . import macro_merge as mm
    tr = _trace(fam.mod, nominal, fam.free)
    _sketch_ok(fam, nominal)
    text = ctx.program(nominal)
    nb = core(blocks(text))
    nomp = mm.prog(nominal, text, ctx.dialect)
    nomp.ops = [("equal", 0, len(nomp.secs), 0, len(nomp.secs))]
    sets = sample(fam, tr, lo, hi, n_fit + n_hold, ("fit", seed), branches=False,
                  extra=extra)
    if len(sets) < 4:
        raise PartError(f"{fam.path}: too few valid parameter sets near "
                        f"{_pset(nominal, fam.free)} to derive a macro ({len(sets)} of the "
                        f"sampled sets pass the family's checks)")
    progs: list[Any] = []

    def add(ps: list[dict]) -> None:
        for p in ps:
            _sketch_ok(fam, p)
            if not _same_branches(tr, p):
                raise TopologyChange(p, "the sketch takes another branch")
            v = mm.prog(p, ctx.program(p), ctx.dialect)
            mm.align(nomp, v)
            progs.append(v)

    add(sets)
    probed: set[frozenset] = set()
    # the words that follow one of two laws, the planner switching between them at its own
    # threshold (not where the laws cross): each a decision at the control like a change of
    # the program's shape, its region taking the cycle and the contour it names together
    splits: list[tuple] = []  # (the line of the nominal's block, word, law, law)
    first: TopologyChange | None = None  # the law change the first split was made for
    for _again in range(MAX_SPLITS + 1):
        try:
            layout, allv = _layout(ctx, fam, tr, lo, hi, nb, nomp, progs, add, probed, seed,
                                   extra, splits)
            regions, spins = _fit_regions(ctx, fam, tr, lo, hi, nominal, nb, nomp, allv,
                                          layout, n_fit, seed, extra)
            break
        except _Resplit as e:
            if _again == MAX_SPLITS or e.split in splits:
                raise (first or e.change) from None
            first = first or e.change
            splits.append(e.split)
        except (PlanError, TopologyChange):
            # no program with the decisions (a second law fitted on a few sets that is not
            # the planner's, a threshold no feature holds): the domain is cut at the first
            # law change instead, as where no decision is tried
            if first is not None:
                raise first from None
            raise
    # the spindle switches, once every alternative's words are fitted: an S may follow an X
    # of another section (a cycle's speed at its contour's largest diameter)
    pool = [n for rg in regions if rg.tree is None for a in rg.alts
            for i, b in enumerate(a.blocks) if _codes(b) & {0.0, 1.0, 2.0, 3.0}
            for n in [_word_node(a.blocks, {(s.block, s.word): s for s in a.slots}, i, "X")]
            if n is not None]
    decisions = []  # the conditions the program decides at the control

    def walk_tree(node: Any) -> None:
        if node is not None and node.leaf is None:
            decisions.append(node.cond)
            walk_tree(node.yes)
            walk_tree(node.no)
    for rg in regions:
        walk_tree(rg.tree)
    for alt, seen, conds, key in spins:
        dom = sample(fam, tr, lo, hi, N_SPIN, ("spin",) + key, extra=conds)
        alt.spin = spindle_gaps(fam, tr, seen, alt.blocks, alt.slots,
                                _prev_x(alt.rep, alt.secs), ctx.rpm_limit, dom, pool,
                                decisions)
    # the nominal's own words, indexed on its blocks (what the fit counts)
    line_ix = {b.line: i for i, b in enumerate(nb)}
    flat = []
    for rg in regions:
        alt = rg.alts[0]
        for s in alt.slots:
            flat.append(Slot(line_ix[alt.blocks[s.block].line], s.word, s.kind, s.node,
                             s.value, s.note, s.rounded, s.tie_free))
    pc = Piece(fam, tr, dict(lo), dict(hi), dict(nominal), text, nb, flat, sets,
               stock=ctx.stock)
    pc.regions = regions
    return pc


#: the sets of an alternative's domain the planner's spindle rule is evaluated at (no
#: per-variant program: the blocks' expressions), for switches no variant showed
N_SPIN = 400

#: the fresh variants each alternative's fitted words are proven on before their laws are taken
N_HELD = 6


def _held_out(ctx: Ctx, fam: Family, tr: Any, lo: dict, hi: dict, nomp: Any, reg: tuple,
              key: tuple, conds: list[tuple], ab: list[Block], seed: Any,
              splits: Any = ()) -> list[tuple]:
    """``N_HELD`` fresh variants inside one alternative (its decision leaf's conditions and
    the piece's own), none of them among those its words were fitted on: (variant, its run
    of sections). A set that falls on the other side of a threshold (exact to its bisection
    only) or takes another branch says nothing about this alternative and is left out."""
    out = []
    for p in sample(fam, tr, lo, hi, N_HELD, seed, limit=1000, branches=False, extra=conds):
        got = _in_alternative(ctx, fam, tr, nomp, reg, key, ab, p, splits)
        if got is not None:
            out.append(got)
    return out


def _in_alternative(ctx: Ctx, fam: Family, tr: Any, nomp: Any, reg: tuple, key: tuple,
                    ab: list[Block], p: dict, splits: Any = ()) -> tuple | None:
    """The variant at ``p`` and its run of sections where it takes the alternative ``key``
    of region ``reg`` with the blocks' words of ``ab``; None where it takes another branch
    of the sketch or another alternative, or the planner makes no program there."""
    from . import macro_merge as mm
    _sketch_ok(fam, p)
    if not _same_branches(tr, p):
        return None
    try:
        v = mm.prog(p, ctx.program(p), ctx.dialect)
    except PlanError:
        return None
    mm.align(nomp, v)
    if mm.alt_key(nomp, v, reg) != _skeleton_key(key):
        return None
    got = region_key(nomp, v, reg, splits)
    if got is not None and got != key and not _ambiguous(got):
        return None  # the other law's side of a split (beyond its threshold's bisection)
    run = mm.run_of(nomp, v, reg)
    shape = [[w.letter for w in b.words] for b in ab]
    if [[w.letter for w in b.words] for sec in run for b in sec.blocks] != shape:
        return None
    return v, run


#: how far beside the kink of a word fitted as the larger or smaller of two laws its probes
#: lie, either way (the word's own units: three written digits, and one)
KINK = (0.003, 0.001)


def _kink_probes(ctx: Ctx, fam: Family, tr: Any, lo: dict, hi: dict, nomp: Any, reg: tuple,
                 key: tuple, conds: list[tuple], ab: list[Block], slots: list[Slot],
                 sets: list[dict], splits: Any = ()) -> list[tuple]:
    """Variants beside the kink of each word fitted as the larger or smaller of two laws:
    where the two laws differ by :data:`KINK` either way, on the line between the two sets
    nearest the kink on either side of it (variant, its run of sections), inside the
    alternative as :func:`_held_out`'s. Sampled sets seldom fall there, and the planner's
    own switch between the laws need not be where they cross: a kink beside it is off in
    between."""
    out: list[tuple] = []
    seen: set[tuple] = set()
    for sl in filter(_is_kink, slots):
        _kind, n1, n2 = sl.node
        try:
            d = [(_ev(n1, p) - _ev(n2, p), p) for p in sets]
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        pos = [x for x in d if x[0] > 0]
        neg = [x for x in d if x[0] < 0]
        if not pos or not neg:
            continue
        da, pa = min(pos, key=lambda x: x[0])
        db, pb = max(neg, key=lambda x: x[0])
        for delta in KINK:
            for want in (delta, -delta):
                t = (da - want) / (da - db)
                p = dict(pa)
                for k in fam.free:
                    p[k] = round(pa[k] + t * (pb[k] - pa[k]), 3)  # what a control holds
                at = tuple(p[k] for k in fam.free)
                if at in seen or not _valid(fam, tr, p, lo, hi, False, conds):
                    continue
                seen.add(at)
                got = _in_alternative(ctx, fam, tr, nomp, reg, key, ab, p, splits)
                if got is not None:
                    out.append(got)
    return out


#: half of the last written digit (0.001 mm), with room for the floating point's error only
HALF = 0.0005 + 1e-6


def _missed(slots: list[Slot], ab: list[Block], fresh: list[tuple], tol: float = TOL):
    """The first fitted word whose law misses a fresh variant's word by more than ``tol``:
    (slot, set, the variant's value); None where every law holds."""
    for v, run in fresh:
        vb = [b for sec in run for b in sec.blocks]
        for s in slots:
            if s.kind != "fit":
                continue
            got = vb[s.block].words[s.word].value
            try:
                want = _ev(s.node, v.p)
            except (ValueError, ZeroDivisionError, OverflowError):
                return s, v.p, got
            if not math.isfinite(want) or abs(want - got) > tol:
                return s, v.p, got
    return None


def _cross_probes(tree: Any, probed: set[frozenset]) -> list[list[tuple]]:
    """Each leaf's conditions with each side of every other threshold of the tree: the
    sampled variants may never have met a combination (a leaf where ``d2 >= 37.6`` was only
    sampled with ``relief_angle >= 30``, so that its alternative holds no insert change), and
    one variant there shows an alternative the tree does not know. New ones only (``probed``
    remembers them)."""
    def coarse(c: tuple) -> tuple:  # a threshold bisected again is the same decision
        return ("not", coarse(c[1])) if c[0] == "not" else (c[0], c[1])

    conds = list(dict.fromkeys(c for path in tree.paths().values() for c in path
                               if c[0] != "not"))
    out = []
    for path in tree.paths().values():
        held = {coarse(c[1] if c[0] == "not" else c) for c in path}
        for c in conds:
            if coarse(c) in held:
                continue
            for side in (c, ("not", c)):
                key = frozenset(coarse(x) for x in list(path) + [side])
                if key not in probed:
                    probed.add(key)
                    out.append(list(path) + [side])
    return out


def _differs(ctx: Ctx, fam: Family, nb_sk: tuple, p: dict, tr: Any = None,
             law: tuple | None = None) -> bool:
    if tr is not None and not _same_branches(tr, p):
        return True
    try:
        vb = core(blocks(ctx.program(p)))
    except PlanError:  # no program there: counted as the other side
        return True
    if skeleton(vb) != nb_sk:
        return True
    if law is not None:
        bi, wi, node = law
        return abs(vb[bi].words[wi].value - _ev(node, p)) > TOL
    return False


def fix_unmachinable(ctx: Ctx, fam: Family) -> dict[str, str]:
    """Parameters the tool library cannot vary (a thread's pitch needs its own insert, a
    groove no narrower than the blade): moved alone to either end of the box, the per-variant
    program cannot be generated. They stay at their value, like whole numbers (the macro says
    so); the reason for each. A parameter the library cuts only part of the way to an end of
    the box keeps the part it cuts; ``fam.narrowed`` then tells it: name -> (the end given,
    the end kept, why)."""
    out: dict[str, str] = {}
    narrowed: dict[str, tuple[float, float, str]] = {}
    for k in list(fam.free):
        for side in ("lo", "hi"):
            box = fam.lo if side == "lo" else fam.hi
            end, why, first = box[k], "", ""
            for frac in (1.0, 0.5, 0.25):  # the box shrinks to where the library cuts it
                v = fam.params[k] + frac * (end - fam.params[k])
                p = dict(fam.params, **{k: v})
                if not _valid(fam, fam.trace, p, fam.lo, fam.hi, False):
                    break
                _sketch_ok(fam, p)  # the family's own failure is no library limit
                try:
                    ctx.program(p)
                    box[k] = v
                    if first:
                        narrowed[k] = (end, v, first)
                    why = ""
                    break
                except PlanError as e:
                    why = str(e).rsplit("): ", 1)[-1]
                    first = first or f"at {k}={_fmt(v)}: {why}"
            if why:
                out[k] = why
                narrowed.pop(k, None)
                break
    fam.narrowed = narrowed
    if out:
        fam.free = [k for k in fam.free if k not in out]
        for k in out:
            fam.lo.pop(k, None)
            fam.hi.pop(k, None)
        fam.trace = _trace(fam.mod, fam.params, fam.free)
    return out


def _feature_cut(ctx: Ctx, fam: Family, tr: Any, sk: tuple, nominal: dict, change: Any,
                 lo: dict, hi: dict, extra: list[tuple], n_probe: int = 16):
    """A change no single parameter makes: the traced feature (a contour coordinate, a
    parameter) whose crossing of one value separates the two programs — the boundary found
    by bisection on the way from ``nominal`` to the changed set, the feature confirmed on
    ``n_probe`` other sets. (condition of the nominal's side, of the other, their labels)."""
    def at(t: float) -> dict:
        return {k: (nominal[k] + t * (change.p[k] - nominal[k]) if k in fam.free else v)
                for k, v in nominal.items()}
    a, b = 0.0, 1.0
    for _ in range(16):
        m = (a + b) / 2
        if _differs(ctx, fam, sk, at(m), tr, change.law):
            b = m
        else:
            a = m
    pa, pb = at(a), at(b)
    mid = at((a + b) / 2)  # probes around the boundary: does the feature separate there?
    near_lo = {k: max(lo[k], mid[k] - 0.5 * (hi[k] - lo[k])) for k in fam.free}
    near_hi = {k: min(hi[k], mid[k] + 0.5 * (hi[k] - lo[k])) for k in fam.free}
    probes = sample(fam, tr, near_lo, near_hi, n_probe, ("probe", len(extra)), branches=False,
                    extra=extra)
    sides = [(p, _differs(ctx, fam, sk, p, tr, change.law)) for p in probes]
    cands = [(k, ("p", k)) for k in fam.free] + features(tr)
    for desc, f in cands:
        try:
            fa, fb = _ev(f, pa), _ev(f, pb)
            if abs(fa - fb) < 1e-9:
                continue
            c = (fa + fb) / 2
            for nd in range(7):
                r = round(c, nd)
                if min(fa, fb) < r < max(fa, fb):
                    c = r
                    break
            below = fa < c  # the nominal's side
            same = ("<", f, ("c", c)) if below else (">=", f, ("c", c))
            other = (">=", f, ("c", c)) if below else ("<", f, ("c", c))
            if all(((_ev(f, p) < c) != below) == d for p, d in sides) \
                    and _holds(same, nominal) and _holds(other, change.p):
                name = desc if f[0] != "p" else f[1]
                return (same, other, f"{name} {'<' if below else '>='} {_num(c)}",
                        f"{name} {'>=' if below else '<'} {_num(c)}")
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
    return None


def _central(fam: Family, lo: dict, hi: dict, extra: list[tuple], fallback: dict,
             pick: int = 0) -> dict:
    """The nominal of a piece cut along a feature: of 30 sets on its side, the one nearest
    their middle (a set far from the piece's other boundaries; ``pick`` 1: the next)."""
    sets = sample(fam, fam.trace, lo, hi, 30, ("central", len(extra)), branches=False,
                  extra=extra)
    if not sets:
        return fallback
    mean = {k: sum(p[k] for p in sets) / len(sets) for k in fam.free}
    span = {k: (hi[k] - lo[k]) or 1.0 for k in fam.free}
    ranked = sorted(sets, key=lambda p: sum(((p[k] - mean[k]) / span[k]) ** 2
                                            for k in fam.free))
    return ranked[min(pick, len(ranked) - 1)]


def with_lost(fam: Family, e: PlanError) -> PlanError:
    """``e`` telling, where the family's sketch made plain numbers of traced expressions
    (the real ``math`` imported inside the function, ``float()``), where it did: the laws the
    derivation misses there are the usual cause of its refusal."""
    if not fam.trace.floated:
        return e
    msg, tail = str(e), "; no macro is written"
    hint = (f" (the sketch turns an expression of the parameters into a plain number at "
            f"{', '.join(fam.trace.floated)}: a math imported inside the function, float(); "
            f"only the module's own math is traced)")
    msg = msg[:-len(tail)] + hint + tail if msg.endswith(tail) else msg + hint
    return PlanError(msg)


def derive_pieces(ctx: Ctx, fam: Family, max_pieces: int = 12, **kw: Any) -> list[Piece]:
    """The fewest pieces (cut along one parameter at a time) that each hold one program."""
    todo = [(dict(fam.lo), dict(fam.hi), dict(fam.params), [], [])]
    done: list[Piece] = []
    while todo:
        lo, hi, nominal, cuts, extra = todo.pop(0)
        try:
            try:
                pc = derive_piece(ctx, fam, lo, hi, nominal, extra=extra, **kw)
            except PlanError:
                if not extra:
                    raise
                # a piece's nominal near a law change of its own: once more from another
                nominal = _central(fam, lo, hi, extra, nominal, pick=1)
                pc = derive_piece(ctx, fam, lo, hi, nominal, extra=extra, **kw)
            pc.bounds, pc.extra = cuts, list(extra)
            done.append(pc)
            continue
        except TopologyChange as t:
            change = t
        ctx.last_change = (dict(nominal), change)
        if len(done) + len(todo) + 2 > max_pieces:
            raise PlanError(f"{fam.path}: the family's program changes shape in more than "
                            f"{max_pieces} places over the domain ({change.diff}); no macro is "
                            f"written")
        tr = _trace(fam.mod, nominal, fam.free)
        sk = skeleton(blocks(ctx.program(nominal)))
        who = None
        for k in fam.free:
            p = dict(nominal, **{k: change.p[k]})
            if _valid(fam, tr, p, lo, hi, False, extra) and \
                    _differs(ctx, fam, sk, p, tr, change.law):
                who = k
                break
        if who is None:  # no parameter alone: a traced feature that separates the programs
            cut = _feature_cut(ctx, fam, tr, sk, nominal, change, lo, hi, extra)
            if cut is not None:
                same, other, label1, label2 = cut
                todo.append((dict(lo), dict(hi), nominal, cuts + [label1], extra + [same]))
                todo.append((dict(lo), dict(hi),
                             _central(fam, lo, hi, extra + [other], change.p),
                             cuts + [label2], extra + [other]))
                continue
            moved = [k for k in fam.free if abs(change.p[k] - nominal[k]) > 1e-9]
            raise PlanError(f"{fam.path}: the family's program changes shape between "
                            f"{_pset(nominal, fam.free)} and {_pset(change.p, fam.free)}, and no "
                            f"single parameter changes it ({', '.join(moved)} together): "
                            f"{change.diff}; no macro is written")
        a, b = nominal[who], change.p[who]
        for _ in range(14):  # the boundary to 1/16000 of the step
            m = (a + b) / 2
            if _differs(ctx, fam, sk, dict(nominal, **{who: m}), tr, change.law):
                b = m
            else:
                a = m
        edge = round((a + b) / 2, 4)
        for nd in range(7):  # the roundest value strictly between the last same set and
            r = round((a + b) / 2, nd)  # the first changed one
            if min(a, b) < r < max(a, b):
                edge = r
                break
        lo1, hi1, lo2, hi2 = dict(lo), dict(hi), dict(lo), dict(hi)
        if change.p[who] > nominal[who]:
            hi1[who], lo2[who] = edge, edge
            c1, c2 = f"{who} < {_num(edge)}", f"{who} >= {_num(edge)}"
        else:
            lo1[who], hi2[who] = edge, edge
            c1, c2 = f"{who} >= {_num(edge)}", f"{who} < {_num(edge)}"
        # the other side's own nominal: the middle of its range, else the set that changed
        mid = dict(nominal, **{who: round((lo2[who] + hi2[who]) / 2, 4)})
        if not _valid(fam, _trace(fam.mod, mid, fam.free), mid, lo2, hi2, True, extra):
            mid = change.p
        todo.append((lo1, hi1, nominal, cuts + [c1], extra))
        todo.append((lo2, hi2, mid, cuts + [c2], extra))
    return done


# ------------------------------------------------------------------------------------------
# spindle switches (HNC-21T: G96 has no clamp word)
# ------------------------------------------------------------------------------------------

@dataclass
class SpinGap:
    """What the HNC-21T macro writes before core block ``at`` of an alternative (``at`` its
    number of blocks: after the last) where the variants' spindle switches differ.

    ``kind`` "s": every variant switches there with the same blocks, their S words differ:
    each such S is a law of the parameters (``laws``: (block of the gap, word) -> law, see
    :func:`_s_value`). ``kind`` "switch": the variants switch there or not, or to another
    mode: one block ``G[#g] S[#s]`` whose mode and speed are ``yes`` where ``cond`` holds,
    else ``no`` (``cond`` None: always ``yes``, written as it is), the two variables set
    before the alternative's first block (a compound cycle's profile takes no IF)."""
    at: int
    kind: str
    laws: dict = field(default_factory=dict)
    cond: tuple | None = None
    yes: tuple[float, float] = (97.0, 0.0)
    no: tuple[float, float] = (96.0, 0.0)


@dataclass
class _Run:
    """A variant's run of an alternative's sections, by gap: the floating blocks before each
    core block (index ``n``: after the last), the spindle (G96/G97, S) each core block runs
    at (``n``: after the run), the G96 speed last set, the tool in force, and the spindle's
    direction (3, 4, 5) where each gap starts."""
    p: dict[str, Any]
    gaps: list[list[Block]]
    at: list[tuple[float, float]]
    vc: list[float]
    tool: list[int]
    on: list[int]


def _run_gaps(text: str, run: list, n: int, p: dict[str, Any]) -> _Run | None:
    """:class:`_Run` of a variant's text and its run of sections; None where the run does not
    have ``n`` core blocks."""
    lines = {ln for sec in run for ln in range(sec.a + 1, sec.b + 1)}
    r = _Run(p, [[] for _ in range(n + 1)], [(97.0, 0.0)] * (n + 1), [0.0] * (n + 1),
             [0] * (n + 1), [0] * (n + 1))
    mode, s, vc, tool, on = 97.0, 0.0, 0.0, 0, 5
    k, started = 0, False
    for b in blocks(text):
        inside = b.line in lines
        if inside:
            if not started:  # the gap's spindle direction where it starts
                r.on[k], started = on, True
            if b.floating:
                r.gaps[k].append(b)
            else:
                if k >= n:
                    return None
                r.at[k], r.vc[k], r.tool[k] = (mode, s), vc, tool
                k, started = k + 1, False
        for w in b.words:
            if w.letter == "G" and w.value in (96.0, 97.0):
                mode = w.value
            elif w.letter == "S":
                s = w.value
            elif w.letter == "T":
                tool = int(w.value) // 100
            elif w.letter == "M" and w.value in (3.0, 4.0, 5.0):
                on = int(w.value)
        if mode == 96.0:
            vc = s
        if inside:
            r.at[n], r.vc[n], r.tool[n] = (mode, s), vc, tool
    if k != n:
        return None
    for i in range(k, n + 1):
        if not started or i > k:
            r.on[i] = on
    return r


def _gap_sig(gap: list[Block], shape: bool = False) -> tuple:
    return tuple(tuple((w.letter, None if shape and w.letter == "S" else w.text)
                       for w in b.words) for b in gap)


def _codes(b: Block, letter: str = "G") -> set[float]:
    return {w.value for w in b.words if w.letter == letter}


def _word_node(ab: list[Block], words: dict, bi: int, letter: str) -> tuple | None:
    """The expression of block ``bi``'s word ``letter``: its law, or the number written."""
    for wi, w in enumerate(ab[bi].words):
        if w.letter == letter:
            s = words.get((bi, wi))
            return s.node if s is not None and s.kind == "fit" else ("c", w.value)
    return None


def _s_value(law: tuple, p: dict[str, Any]) -> float:
    """An S word's law at ``p``: ``("node", n)`` an expression; ``("rpm", K, x, cap, half)``
    the rpm of a surface speed at the diameter ``x`` (``K`` = 1000 vc / pi), to the nearest
    whole rpm (``half`` 0.5) or the whole rpm below it (0), at most ``cap`` (0: none)."""
    if law[0] == "node":
        return _ev(law[1], p)
    if law[0] == "cond":
        return law[2] if _holds(law[1], p) else law[3]
    _k, k, xn, cap, half = law
    v = float(math.floor(k / abs(_ev(xn, p)) + half))
    return min(cap, v) if cap else v


def _s_text(lets: Lets, law: tuple) -> str:
    if law[0] == "node":
        e = lets.expr(law[1])
        return e if e.startswith("[") else f"[{e}]"
    if law[0] == "cond":  # a variable set before the blocks by the decision's own condition
        key = ("slaw", id(law))
        if key not in lets._memo:
            op, f, c = law[1]
            fx, cx = lets.expr(f), lets.expr(c)
            v = lets._assign(_num(law[3]))
            lets.lines += [f"IF [{fx} {MACRO_OPS[op]} {cx}]", f"{v}={_num(law[2])}", "ENDIF"]
            lets._memo[key] = f"[{v}]"
        return lets._memo[key]
    _k, k, xn, cap, half = law
    e = f"INT[{f'{k:.6f}'.rstrip('0')}/ABS[{lets.expr(xn)}]{'+0.5' if half else ''}]"
    if cap:
        e = f"[{_num(cap)}+{e}-ABS[{_num(cap)}-{e}]]/2"
    return f"[{e}]"


def _s_law(fam: Family, tr: Any, ps: list[dict], ys: list[float], vcs: list[float],
           ab: list[Block], words: dict, at: int, pool: list[tuple] = (),
           decisions: list[tuple] = ()) -> tuple | None:
    """The law of an S word that differs between the variants: the rpm of the cutting speed
    in force (``vcs``, G96) at the diameter of one of the blocks' X, the next ones first (the
    planner's G97 of a roughing cycle's inner part, at the speed of its top, rounded; of a
    cycle run wholly in G97, at the speed of its largest diameter, the whole rpm below),
    capped at the highest value where some variants reach it; else an exact affine fit."""
    import numpy as np
    order = list(range(at, len(ab))) + list(range(at - 1, -1, -1))
    xs = [_word_node(ab, words, bi, "X") for bi in order
          if _codes(ab[bi]) & {0.0, 1.0, 2.0, 3.0}] + list(pool)
    # the speed in force before the switch at any diameter first, then the roundest speed
    # over the roundings and caps together: a speed the window of a few variants' whole rpm
    # admits at one rounding (149.955 at INT[+0.5]) is off by one rpm at others where the
    # planner floors 150
    wins: list[tuple] = []  # (diameter's law, windows of the surface speed)
    for xn in xs:
        if xn is None:
            continue
        try:
            dx = [abs(_ev(xn, p)) for p in ps]
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        if min(dx) <= 1e-6:
            continue
        windows = []
        for cap in (0.0, max(ys)):
            for half in (0.5, 0.0):
                # the surface speeds every variant's S allows (a capped one: at least the cap)
                lo_v, hi_v = 0.0, math.inf
                for d, y in zip(dx, ys):
                    if cap and y >= cap:
                        lo_v = max(lo_v, math.pi * d * (cap - half) / 1000.0)
                    else:
                        lo_v = max(lo_v, math.pi * d * (y - half) / 1000.0)
                        hi_v = min(hi_v, math.pi * d * (y + 1 - half) / 1000.0)
                if lo_v < hi_v:
                    windows.append((cap, half, lo_v, hi_v))
        wins.append((xn, windows))
    for own in (True, False):
        for xn, windows in wins:
            tries = []
            if own:
                tries = [(cap, half, v) for cap, half, lo_v, hi_v in windows
                         for v in dict.fromkeys(vcs) if lo_v <= v < hi_v]
            else:
                for nd in range(0, 4):
                    for cap, half, lo_v, hi_v in windows:
                        c = math.ceil(lo_v * 10 ** nd) / 10 ** nd
                        if c < hi_v:
                            tries.append((cap, half, c))
            for cap, half, vc in tries:
                law = ("rpm", vc * 1000.0 / math.pi, xn, cap, half)
                try:
                    if all(abs(_s_value(law, p) - y) < 1e-6 for p, y in zip(ps, ys)):
                        return law
                except (ValueError, ZeroDivisionError, OverflowError):
                    continue
    # two speeds, one per side of a decision the program takes at the control (the cutting
    # speed of the insert an earlier decision chose)
    if len(set(ys)) == 2:
        a = ys[0]
        for cond in decisions:
            try:
                side = [_holds(cond, p) for p in ps]
            except (ValueError, ZeroDivisionError, OverflowError):
                continue
            for yes in (a, next(y for y in ys if y != a)):
                no = next(y for y in ys if y != yes)
                if all((y == yes) == h for y, h in zip(ys, side)):
                    return ("cond", cond, yes, no)
    nodes, mat = _candidates(fam, tr, ps)
    r = _fit_word(np.array(ys), mat, len(ps))
    if r is not None and _simple(r[1]):
        return ("node", _combine(nodes, *r))
    return None


def _holds_all(cond: tuple, ps: list[dict]):
    """Whether ``cond`` (a comparison with a number) holds at each set, at once; None where
    it is undefined at one of them."""
    import numpy as np
    env = {k: np.array([float(p[k]) for p in ps]) for k in ps[0]
           if isinstance(ps[0][k], (int, float))}
    v = _defined(cond[1], env, {}, ps)
    return None if v is None else v < cond[2][1]


class _Spin:
    """The positions an alternative's blocks start from and end at, as expressions: what the
    planner's switch decides on (:func:`_switch_cond`)."""

    def __init__(self, tr: Any, ab: list[Block], slots: list[Slot], prev_x: tuple | None,
                 limit_of: Any):
        self.tr, self.ab, self.prev_x, self.limit_of = tr, ab, prev_x, limit_of
        self.words = {(s.block, s.word): s for s in slots}

    def motion(self, i: int) -> bool:
        return i < len(self.ab) and bool(_codes(self.ab[i]) & {0.0, 1.0, 2.0, 3.0})

    def low(self, i: int) -> tuple | None:
        """The lowest diameter of block ``i``'s span from where the tool is to its end (the
        planner's ``lo`` of ``_cap_contour``, without an arc's inner lowest point); None where
        the blocks do not say where the tool is (a cycle before it)."""
        if not self.motion(i):
            return None
        prev = self.prev_x
        for j in range(i - 1, -1, -1):
            if any(w.letter == "X" for w in self.ab[j].words):
                prev = _word_node(self.ab, self.words, j, "X") if self.motion(j) else None
                break
        cur = _word_node(self.ab, self.words, i, "X")
        if prev is None:
            return None
        if cur is None or cur is prev or (cur[0] == prev[0] == "c" and cur[1] == prev[1]):
            return ("f", "abs", prev)
        return ("min", ("f", "abs", prev), ("f", "abs", cur))

    def candidates(self, i: int) -> list[tuple]:
        """What decides a switch before block ``i``: its own span's lowest diameter, an arc's
        lowest point, the lowest diameter of the whole contour (a roughing cycle run in G97
        when its G96 would pass the limit anywhere), each X written."""
        out = []
        lo = self.low(i)
        if lo is not None:
            out.append(lo)
            if 2.0 in _codes(self.ab[i]) or 3.0 in _codes(self.ab[i]):
                for seg in self.tr.segments:  # an arc's lowest point: centre less radius
                    if seg[0] == "A" and seg[3] is not None:
                        out.append(("min", lo, ("*", ("c", 2.0),
                                                ("-", _n(seg[3][0]), _n(seg[4])))))
        seen: set = set()
        for j in range(len(self.ab)):
            n = _word_node(self.ab, self.words, j, "X") if self.motion(j) else None
            key = n[1] if n is not None and n[0] == "c" else id(n)
            if n is not None and key not in seen:  # (the shared trees: by identity)
                seen.add(key)
                out.append(("f", "abs", n))
        return out

    def critical(self, vc: float, tool: int) -> float:
        """The diameter inside which G96 at ``vc`` needs more than the tool's limit."""
        return vc * 1000.0 / (math.pi * self.limit_of(tool))


def _switch_cond(sp: _Spin, i: int, runs: list[_Run], targets: list[tuple],
                 states: list[tuple]) -> tuple | None:
    """The condition under which the variants run G97 (the others G96) at core block ``i``:
    one of :meth:`_Spin.candidates` inside the critical diameter 1000 vc / (pi limit) of the
    G96 speed and the tool's limit. (condition, G97 state, G96 state), else None."""
    if sorted(s[0] for s in states) != [96.0, 97.0]:
        return None
    rpm, css = (states[0], states[1]) if states[0][0] == 97.0 else (states[1], states[0])
    tools = {r.tool[i] for r in runs}
    if css[1] <= 0 or len(tools) != 1:
        return None
    dc = sp.critical(css[1], tools.pop())
    want = [t == rpm for t in targets]
    ps = [r.p for r in runs]
    for c in sp.candidates(i):
        cond = ("<", c, ("c", dc - 2e-9))
        got = _holds_all(cond, ps)
        if got is not None and list(got) == want:
            return cond, rpm, css
    return None


def spindle_gaps(fam: Family, tr: Any, seen: list[tuple[Any, list]], ab: list[Block],
                 slots: list[Slot], prev_x: tuple | None, limit_of: Any,
                 dom: list[dict[str, Any]], pool: list[tuple] = (),
                 decisions: list[tuple] = ()) -> dict[int, SpinGap]:
    """The HNC-21T's G96 has no clamp word: where G96 would need more than the tool's limit
    (the lowest of the machine's, the chuck's and the tool's), the per-variant program runs
    G97 (``_cap_contour``: G97 S<limit> before each block that comes inside the critical
    diameter and back to G96 after; a roughing cycle that reaches inside it run wholly in
    G97, or split with its inner part in G97; the facing passes' centre). Which block that
    is follows the parameters. Over the variants ``seen`` (each with its run of this
    alternative's sections), each gap between core blocks where their switches differ
    becomes a :class:`SpinGap` written at the control; so does each block whose switch the
    planner's rule (its span inside the critical diameter) moves over the sets ``dom`` of
    the alternative's domain though no variant showed it, and the block after each such
    block. A gap whose switch follows no condition the macro can write is refused."""
    n = len(ab)
    runs = [r for v, run in seen if (r := _run_gaps(v.text, run, n, v.p)) is not None]
    if not runs:
        return {}
    sp = _Spin(tr, ab, slots, prev_x, limit_of)
    ps = [r.p for r in runs]
    out: dict[int, SpinGap] = {}
    for i in range(n + 1):
        if len({_gap_sig(r.gaps[i]) for r in runs}) <= 1:
            continue
        where = (f"before line {ab[i].line} [{ab[i].raw.strip()}]" if i < n else
                 f"after line {ab[-1].line} [{ab[-1].raw.strip()}]")
        if len({_gap_sig(r.gaps[i], True) for r in runs}) == 1:
            laws = {}
            for j, b in enumerate(runs[0].gaps[i]):
                for wi, w in enumerate(b.words):
                    ys = [r.gaps[i][j].words[wi].value for r in runs]
                    if w.letter != "S" or len(set(ys)) == 1:
                        continue
                    vcs = [r.vc[i] for r in runs]  # the G96 speed before the switch
                    law = _s_law(fam, tr, ps, ys, vcs, ab, sp.words, i, pool, decisions)
                    if law is None:
                        raise PlanError(
                            f"{fam.path}: the spindle speed {where} of the family's program "
                            f"(S{_num(min(ys))} to S{_num(max(ys))} over the variants) follows "
                            f"no law of the parameters; no macro is written")
                    laws[(j, wi)] = law
            out[i] = SpinGap(i, "s", laws=laws)
            continue
        # a spindle start in a switch: only where the spindle turns that way already
        if any(w.letter == "M" and (w.value not in (3.0, 4.0) or w.value != r.on[i])
               for r in runs for b in r.gaps[i] for w in b.words):
            raise PlanError(f"{fam.path}: the spindle starts {where} in some variants of the "
                            f"family's program only; no macro is written")
        targets = [r.at[i] for r in runs]
        states = list(dict.fromkeys(targets))
        if len(states) == 1:
            out[i] = SpinGap(i, "switch", yes=states[0])
            continue
        got = _switch_cond(sp, i, runs, targets, states) if len(states) == 2 else None
        if got is None:
            raise PlanError(
                f"{fam.path}: the spindle switch {where} of the family's program ("
                + ", ".join(f"G{s[0]:g} S{_num(s[1])}" for s in states)
                + " over the variants) follows no condition on the diameters the HNC-21T "
                  "macro can write; no macro is written")
        cond, yes, no = got
        out[i] = SpinGap(i, "switch", cond=cond, yes=yes, no=no)
    if not dom:
        return out
    # the planner's rule over the domain: a block whose span comes inside the critical
    # diameter at some sets though at none of the variants, and the block after each block
    # whose spindle the parameters decide (where the spindle goes back)
    after_cond = False
    for i in range(n):
        if i in out:
            after_cond = out[i].kind == "switch" and out[i].cond is not None
            continue
        lo = sp.low(i)
        vcs, tools = {r.vc[i] for r in runs}, {r.tool[i] for r in runs}
        if lo is None or len(vcs) != 1 or len(tools) != 1 or min(vcs) <= 0:
            after_cond = False
            continue
        vc, tool = vcs.pop(), tools.pop()
        lim, dc = sp.limit_of(tool), sp.critical(vc, tool)
        cond = ("<", lo, ("c", dc - 2e-9))
        on_runs = _holds_all(cond, ps)
        if on_runs is None or any(((97.0, lim) if h else (96.0, vc)) != r.at[i]
                                  for h, r in zip(on_runs.tolist(), runs)):
            after_cond = False  # no block the planner switches before (an approach, a cycle)
            continue
        on_dom = _holds_all(cond, dom)
        seen_on = set(on_runs.tolist()) | (set(on_dom.tolist()) if on_dom is not None else set())
        if len(seen_on) > 1:
            out[i] = SpinGap(i, "switch", cond=cond, yes=(97.0, lim), no=(96.0, vc))
            after_cond = True
        elif after_cond:  # every set runs this block alike, the block before it not
            out[i] = SpinGap(i, "switch", yes=(97.0, lim) if seen_on.pop() else (96.0, vc))
            after_cond = False
    return out


def _prev_x(alt_rep: Any, secs: list) -> tuple | None:
    """The X the tool is at when an alternative's first block starts, as the representative
    program writes it before the alternative (a number; None where it writes none)."""
    if not secs:
        return None
    first = secs[0].a + 1
    x = None
    for b in blocks(alt_rep.text):
        if b.line >= first:
            break
        for w in b.words:
            if w.letter == "X":
                x = ("c", w.value)
    return x


# ------------------------------------------------------------------------------------------
# rendering
# ------------------------------------------------------------------------------------------

@dataclass
class Rendered:
    text: str
    var: dict[str, str]
    dialect: str


def _letters(free: list[str]) -> dict[str, str]:
    """FANUC argument letters for the parameters: the name's first letter where free, else
    the next free one in the table's order."""
    if len(free) > len(FANUC_ARGS):
        raise PlanError(f"the family has {len(free)} parameters; a FANUC G65 call passes at "
                        f"most {len(FANUC_ARGS)} (its argument letters)")
    out: dict[str, str] = {}
    # H last: a G65 with an H word reads as a macro A call (G65 Hm P#i Q#j R#k) to our
    # interpreter; it is taken only when every other letter is (M, S and T are arguments with
    # their decimal point like any other)
    last = "H"
    left = [c for c in FANUC_ARGS if c not in last] + list(last)
    for k in free:
        first = k[0].upper()
        letter = first if first in left and first not in last else left[0]
        left.remove(letter)
        out[k] = letter
    return out


_HEADER_COMMENTS = ("(PARAMETERS", "(STOCK", "(PART", "(COMPENSATION")
_LEAD_N = re.compile(r"^(\s*)N(\d+)")


def _word(lets: Lets, s: Slot) -> str:
    return lets.rounded(s.node, s.tie_free) if s.rounded else lets.expr(s.node)


def _spin_vars(lets: Lets, alt: Alt) -> None:
    """The variables of an alternative's conditional spindle switches (:class:`SpinGap`),
    assigned once per writer: ``#g=96``, ``#s=<vc>``, then ``IF [cond]`` ``#g=97``
    ``#s=<limit>`` ``ENDIF`` (a comment names the critical diameter)."""
    for i, g in sorted(alt.spin.items()):
        key = ("spin", id(alt), i)
        for law in g.laws.values():  # an S law's parts: assigned before the blocks
            _s_text(lets, law)
        if g.kind != "switch" or g.cond is None or key in lets._memo:
            continue
        op, a, c = g.cond
        parts, todo = [], [a]
        while todo:  # the lower of several diameters inside: any of them inside
            x = todo.pop(0)
            if x[0] == "min":
                todo[:0] = [x[1], x[2]]
            else:
                parts.append(x)
        cx = lets.expr(c)
        test = " OR ".join(f"[{lets.expr(x)} {MACRO_OPS[op]} {cx}]" for x in parts)
        same = ("spin", test, g.yes, g.no)  # another block of the same condition: its pair
        if same in lets._memo:
            lets._memo[key] = lets._memo[same]
            continue
        gv, sv = lets._assign(_num(g.no[0])), lets._assign(_num(g.no[1]))
        lets._memo[same] = (gv, sv)
        lets.lines += [f"(G{_num(g.yes[0])} S{_num(g.yes[1])} INSIDE DIAMETER "
                       f"{_num(round(g.cond[2][1], 3))}, ELSE G{_num(g.no[0])} "
                       f"S{_num(g.no[1])})",
                       f"IF [{test}]" if len(parts) > 1 else f"IF {test}",
                       f"{gv}={_num(g.yes[0])}",
                       f"{sv}={_num(g.yes[1])}", "ENDIF"]
        lets._memo[key] = (gv, sv)


def _spin_line(lets: Lets, alt: Alt, g: SpinGap) -> str:
    """The block of a switch gap: ``G[#g] S[#s]``, or the one state all variants take."""
    if g.cond is None:
        return f"G{_num(g.yes[0])} S{_num(g.yes[1])}"
    gv, sv = lets._memo[("spin", id(alt), g.at)]
    return f"G[{gv}] S[{sv}]"


def _emit_alt(alt: Alt, lets: Lets, body: list[str], notes: list[str], counter: list[int],
              fanuc: bool) -> None:
    """An alternative's lines from its representative program, its words replaced by their
    expressions (temporaries not yet assigned: just before), its blocks renumbered in the
    macro's sequence and its cycles' P/Q following them."""
    if not alt.secs:
        return
    for s in alt.slots:
        if s.kind == "fit":
            _word(lets, s)
    _spin_vars(lets, alt)
    body += lets.lines
    lets.lines.clear()
    lines = alt.rep.text.splitlines()
    a, b = alt.secs[0].a, alt.secs[-1].b
    bmap = {blk.line: i for i, blk in enumerate(alt.blocks)}
    hnc = lets.dialect == "hnc21t"
    # the HNC-21T keeps every spindle switch (its G96 has no clamp word); the others leave a
    # G97 at the limit to the clamp their program sets (G50 S, LIMS=)
    floating = {blk.line: blk.droppable and not hnc
                for blk in blocks(alt.rep.text) if blk.floating}
    # each floating block's gap (the core block it comes before) and place in it
    gap_of: dict[int, tuple[int, int, Block]] = {}
    k, j = 0, 0
    for blk in blocks(alt.rep.text):
        if not a < blk.line <= b:
            continue
        if blk.line in bmap:
            k, j = bmap[blk.line] + 1, 0
        elif blk.floating:
            gap_of[blk.line] = (k, j, blk)
            j += 1
    spin = alt.spin if hnc else {}
    # the switch gaps' own blocks give way to one block each (:func:`_spin_line`)
    gone = {ln for ln, (gi, _j, _b) in gap_of.items()
            if gi in spin and spin[gi].kind == "switch"}
    nmap: dict[str, int] = {}
    for i in range(a, b):
        m = _LEAD_N.match(lines[i])
        if m and i + 1 not in gone:
            counter[0] += 1
            nmap[m.group(2)] = counter[0]
    for k, v in nmap.items():
        counter[1][(id(alt.rep), k)] = v
    written: set[int] = set()
    by_block: dict[int, list[Slot]] = {}
    for s in alt.slots:
        by_block.setdefault(s.block, []).append(s)

    def renum(t: str) -> str:
        m = _LEAD_N.match(t)
        return t if not m else f"{m.group(1)}N{nmap[m.group(2)]}{t[m.end():]}"

    def switch(gi: int) -> None:  # a switch gap's block, once, where its gap begins
        g = spin.get(gi)
        if g is not None and g.kind == "switch" and gi not in written:
            written.add(gi)
            body.append(_spin_line(lets, alt, g))
    for i in range(a, b):
        raw, ln = lines[i], i + 1
        if raw.strip() == "%":
            continue
        bi = bmap.get(ln)
        if bi is None and ln in gap_of and spin:
            gi, gj, blk = gap_of[ln]
            g = spin.get(gi)
            switch(gi)
            if g is not None and g.kind == "switch":
                continue  # the gap's own switches: the one block above holds them
            if g is not None:  # "s": the same blocks, each S its law
                out = raw
                for wi, w in sorted(enumerate(blk.words), key=lambda t: -t[1].span[0]):
                    law = g.laws.get((gj, wi))
                    if law is not None:
                        out = out[:w.span[0]] + _s_text(lets, law) + out[w.span[1]:]
                body.append(renum(out))
                continue
        if bi is not None:
            switch(bi)
        if bi is None:
            if ln in floating and floating[ln]:
                continue
            if raw.lstrip().startswith(_HEADER_COMMENTS):
                continue
            if lets.dialect == "siemens802" and (raw.startswith(_S802_HEAD)
                                                  or raw.endswith("_MPF")):
                continue
            body.append(renum(raw))
            continue
        blk = alt.blocks[bi]
        out = raw
        for s in sorted(by_block.get(bi, []), key=lambda s: -blk.words[s.word].span[0]):
            w = blk.words[s.word]
            ws, we = w.span
            if s.kind == "fit":
                rep = _word(lets, s)
                if lets.dialect == "siemens802":  # X=<expression>, R105=<expression>
                    rep = rep if w.eq else f"={rep}"
                else:
                    rep = rep if rep.startswith("[") else f"[{rep}]"
            elif s.kind == "bound":
                rep = _num(s.value)
                notes.append(s.note)
            elif s.kind == "label":  # resolved when every block has its number
                counter[2][id(alt.rep)] = alt.rep
                rep = f"\0{id(alt.rep)}:{w.text}\0"
            else:
                continue
            out = out[:ws] + rep + out[we:]
        out = renum(out)
        if lets.dialect != "siemens802" and re.search(r"\bM30\b", out):
            out = re.sub(r"\bM30\b", "M99", out)
        body.append(out)
    switch(len(alt.blocks))  # after the last block, where no floating block of it was


def _resolve_labels(line: str, counter: list[Any], pc: Piece) -> str:
    """A cycle's P/Q in the macro's numbering: the block it names in its own program, else
    (that block in a section the program shares with the nominal) the nominal's block."""
    def one(m: re.Match) -> str:
        pid, old = int(m.group(1)), m.group(2)
        got = counter[1].get((pid, old))
        if got is None:
            got = _through_nominal(counter[2][pid], old, pc, counter[1])
        if got is None:
            raise PlanError(f"{pc.fam.path}: a cycle names block N{old} of a program "
                            f"alternative that the macro does not hold; no macro is written")
        return str(got)
    return re.sub(r"\0(\d+):(\d+)\0", one, line)


def _through_nominal(prog: Any, old: str, pc: Piece, done: dict) -> int | None:
    for j, sec in enumerate(prog.secs):
        for k, b in enumerate(sec.blocks):
            m = _LEAD_N.match(b.raw)
            if m and m.group(2) == old:
                for tag, i1, i2, j1, j2 in prog.ops:
                    if tag == "equal" and j1 <= j < j2:
                        for rg in pc.regions:
                            rep = rg.alts[0].rep
                            if rg.tree is None and rg.span[0] <= i1 + j - j1 < rg.span[1]:
                                nb = rep.secs[i1 + j - j1].blocks[k]
                                mm_ = _LEAD_N.match(nb.raw)
                                return done.get((id(rep), mm_.group(2))) if mm_ else None
                return None
    return None



def _emit_tree(node: Any, alts: list[Alt], lets: Lets, body: list[str], notes: list[str],
               counter: list[int], labels: list[int], fanuc: bool) -> None:
    """A decision at the control: HNC-21T ``IF [cond]`` / ``ELSE`` / ``ENDIF``, FANUC
    ``IF [not cond] GOTO n`` ... ``GOTO m`` ``Nn`` ... ``Nm``. Each branch's temporaries are
    its own (one branch runs), numbered from the same variable."""
    if node.leaf is not None:
        _emit_alt(alts[node.leaf], lets, body, notes, counter, fanuc)
        return
    op, f, c = node.cond
    fx, cx = lets.expr(f), lets.expr(c)
    body += lets.lines
    lets.lines.clear()
    siemens = lets.dialect == "siemens802"
    body.append(f"; {node.label.upper()}?" if siemens else f"({node.label.upper()}?)")
    forks = []
    if siemens:  # IF cond GOTOF label: the 802 has no ELSE
        l_no, l_end = labels[0] + 1, labels[0] + 2
        labels[0] += 2
        body.append(f"IF {fx}{_S802_OPS[_negate(node.cond)[0]]}{cx} GOTOF MD{l_no}")
        at = len(body)
        fy = lets.fork()
        _emit_tree(node.yes, alts, fy, body, notes, counter, labels, fanuc)
        body += [f"GOTOF MD{l_end}", f"MD{l_no}:"]
        fn = lets.fork()
        _emit_tree(node.no, alts, fn, body, notes, counter, labels, fanuc)
        body.append(f"MD{l_end}:")
        forks = [fy, fn]
        if any(ln.startswith("%_N_") for ln in body[at:]):
            raise PlanError("the 802 macro program decides at the control inside a "
                            "subprogram (a contour the decision changes): a jump cannot "
                            "leave its program; no macro is written")
    elif fanuc:
        l_no, l_end = labels[0] + 1, labels[0] + 2
        labels[0] += 2
        body.append(f"IF [{fx} {MACRO_OPS[_negate(node.cond)[0]]} {cx}] GOTO {l_no}")
        fy = lets.fork()
        _emit_tree(node.yes, alts, fy, body, notes, counter, labels, fanuc)
        body += [f"GOTO {l_end}", f"N{l_no}"]
        fn = lets.fork()
        _emit_tree(node.no, alts, fn, body, notes, counter, labels, fanuc)
        body.append(f"N{l_end}")
        forks = [fy, fn]
    else:
        body.append(f"IF [{fx} {MACRO_OPS[op]} {cx}]")
        fy = lets.fork()
        _emit_tree(node.yes, alts, fy, body, notes, counter, labels, fanuc)
        body.append("ELSE")
        fn = lets.fork()
        _emit_tree(node.no, alts, fn, body, notes, counter, labels, fanuc)
        body.append("ENDIF")
        forks = [fy, fn]
    lets.next = max(f.next for f in forks)



def _box_checks(pc: Piece) -> list[Check]:
    out = []
    for k in pc.fam.free:
        out.append(Check([(">=", ("p", k), ("c", pc.lo[k])), ("<=", ("p", k), ("c", pc.hi[k]))],
                         f"{k} outside {_num(pc.lo[k])}..{_num(pc.hi[k])}", [k]))
    for c, v in pc.tr.branches:
        out.append(Check([c if v else ("not", c)], "shape changes", sorted(_params_of(c))))
    for c in pc.extra:
        out.append(Check([c], "another program holds here", sorted(_params_of(c))))
    return out


class _Checks:
    def __init__(self, checks: list[Check]):
        self.checks = checks


_S802_OPS = {"<": "<", "<=": "<=", ">": ">", ">=": ">="}


def _s802_checks(checks: list[Check], lets: Lets, rows: int = 0) -> list[str]:
    """The 802's checks before any motion: one ``IF <failing condition> GOTOF ERn`` per
    condition (the 802's IF takes one comparison), then, jumped over when every check holds,
    each check's label with a comment naming its parameters and ``M30`` (the 802S/C has no
    program-generated alarm: the program ends with the comment on the screen)."""
    out: list[str] = []
    stops: list[str] = []
    if rows:
        first = f"R{S802_FIRST}"
        out += [f"IF {first}<1 GOTOF ER0", f"IF {first}>{rows} GOTOF ER0"]
        stops += ["ER0:", "; NO SUCH TABLE ROW", "M30"]
    for i, ch in enumerate(checks, 1):
        names = " ".join(n.upper() for n in ch.names) or "PARAMETERS"
        for c in ch.conds:
            if c[0] == "not":
                op, a, b = c[1]
            else:
                op, a, b = _negate(c)
            line = f"IF {lets.expr(a)}{op}{lets.expr(b)} GOTOF ER{i}"
            out.extend(lets.lines)
            lets.lines.clear()
            out.append(line)
        stops += [f"ER{i}:", f"; PARAMETER CHECK FAILED: {names}", "M30"]
    return out + ["GOTOF CHECKED"] + stops + ["CHECKED:"]


def _fanuc_checks(checks: list[Check], lets: Lets) -> list[str]:
    out = []
    for i, ch in enumerate(checks):
        names = " ".join(n.upper() for n in ch.names)[:26] or "PARAMETERS"
        for c in ch.conds:  # FANUC: one IF per failing condition, GOTO-free
            if c[0] == "not":
                c2 = c[1]
                line = f"IF [{lets.expr(c2[1])} {MACRO_OPS[c2[0]]} {lets.expr(c2[2])}]"
            else:
                line = f"IF [{lets.expr(c[1])} {MACRO_OPS[_negate(c)[0]]} {lets.expr(c[2])}]"
            out.extend(lets.lines)
            lets.lines.clear()
            out.append(f"{line} THEN #3000={min(100 + i, 200)}({names})")
    return out


_TOOL_LINE = re.compile(r"^(?:\((T\d{2,4} .*)\)|; (T\d+ D\d+ .*))$")


def program_tools(pc: Piece) -> list[str]:
    """The tool lines of the headers of every alternative the program can run (a decision
    that changes an insert brings its tool in), by tool number, each once."""
    seen: dict[str, str] = {}
    for rg in pc.regions:
        for alt in rg.alts:
            for line in alt.rep.text.splitlines():
                line = line.strip()
                m = _TOOL_LINE.match(line)
                if m:
                    t = m.group(1) or m.group(2)
                    seen.setdefault(t.split()[0], t)
                elif line and not line.startswith(("(", ";", "%", "O")):
                    break  # the header ends at the first block
    return [seen[k] for k in sorted(seen, key=lambda k: int(re.sub(r"\D", "", k)))]


def render_program(pieces_or_one: Piece, dialect: str = "hnc21t", values: dict | None = None,
                   rows: list[dict[str, Any]] | None = None, row: int = 1, number: int = 1,
                   note: str = "") -> Rendered:
    """The macro program of one piece: the main program with ``values`` (default: the
    nominal set) or with the table ``rows`` (the operator's row number ``row``), and the
    macro subprogram."""
    pc = pieces_or_one
    fam = pc.fam
    vals = dict(pc.nominal, **(values or {}))
    sub = 1000 + number if number < 9000 else number - 1000
    fanuc = dialect == "fanuc0it"
    siemens = dialect == "siemens802"
    checks = list(pc.tr.checks) + _box_checks(pc)
    if siemens:
        first = S802_FIRST + (1 if rows else 0)
        var = {k: f"R{first + i}" for i, k in enumerate(fam.free)}
        if first + len(fam.free) > S802_LAST:
            raise PlanError(f"the family has {len(fam.free)} parameters: more than the "
                            f"802's R{S802_FIRST}-R{S802_LAST} hold below the cycles' "
                            f"R100-R249")
        lets = Lets(var, dialect, first=first + len(fam.free), last=S802_LAST)
    elif fanuc:
        letters = _letters(fam.free)
        var = {k: f"#{FANUC_ARGS[letters[k]]}" for k in fam.free}
        lets = Lets(var, dialect, first=100, last=199)
    else:
        first = HNC_FIRST + (1 if rows else 0)
        var = {k: f"#{first + i}" for i, k in enumerate(fam.free)}
        if first + len(fam.free) > HNC_LAST:
            raise PlanError(f"the family has {len(fam.free)} parameters: more than the "
                            f"HNC-21T's globals #{HNC_FIRST}-#{HNC_LAST} hold")
        lets = Lets(var, dialect, first=first + len(fam.free), last=HNC_LAST)
    from pathlib import Path
    head = [f"(MACRO PROGRAM OF THE FAMILY {Path(fam.path).stem})",
            f"(STOCK {pc.stock} - ONE STOCK FOR THE WHOLE DOMAIN, THE LARGEST VARIANT'S)",
            "(COMPENSATION CONTROL: PART PROFILE WITH G41/G42)",
            "(DOMAIN " + " ".join(f"{k.upper()} {_num(pc.lo[k])}..{_num(pc.hi[k])}"
                                      for k in fam.free) + ")"]
    if pc.bounds:
        head.append("(THIS PIECE OF THE DOMAIN: " + ", ".join(b.upper() for b in pc.bounds) + ")")
    if note:
        head.append(f"({note})")
    head += [f"({t})" for t in program_tools(pc)]
    fixed = [k for k, v in fam.params.items() if k not in fam.free]
    if fixed:
        head.append("(FIXED " + " ".join(f"{k.upper()}={_fmt(fam.params[k])}" for k in fixed) + ")")
    main: list[str] = []
    if siemens:
        name = pc.regions[0].alts[0].rep.text.splitlines()[0].strip()  # %_N_NAME_MPF
        main += [name, ";$PATH=/_N_MPF_DIR"] + ["; " + h[1:-1] for h in head]
        if rows:
            rv_ = f"R{S802_FIRST}"
            main.append(f"{rv_}={row} ; ROW: THE TABLE ROW TO MAKE, 1-{len(rows)}")
            for i, r in enumerate(rows, 1):
                rv = dict(vals, **r)
                main.append(f"IF {rv_}<>{i} GOTOF RW{i}")
                main += [f"{var[k]}={_num(float(rv[k]))} ; {k.upper()}" for k in fam.free]
                main.append(f"RW{i}:")
        else:
            main += [f"{var[k]}={_num(float(vals[k]))} ; {k.upper()}" for k in fam.free]
        main += _s802_checks(checks, lets, len(rows) if rows else 0)
        check_lines = []
    elif fanuc:
        main += ["%", f"O{number:04d}"] + head
        def argtext(p):
            return " ".join(f"{letters[k]}{_num(float(p[k]))}" + ("." if "." not in _num(float(p[k])) else "")
                            for k in fam.free)
        main += [f"({letters[k]} = {k.upper()})" for k in fam.free]
        if rows:  # the operator selects the row by number, as in the HNC-21T form
            main.append(f"#33={row} (ROW: THE TABLE ROW TO MAKE, 1-{len(rows)})")
            main += [f"IF [#33 EQ {i}] GOTO {i}" for i in range(1, len(rows) + 1)]
            main.append("#3000=1(NO SUCH TABLE ROW)")
            for i, r in enumerate(rows, 1):
                main += [f"N{i} G65 P{sub} {argtext(dict(vals, **r))}", "GOTO 9999"]
            main.append("N9999 M30")
        else:
            main.append(f"G65 P{sub} {argtext(vals)}")
        if not rows:
            main.append("M30")
        check_lines = _fanuc_checks(checks, lets)  # in the macro: G65 passes the arguments
    else:
        main += [f"%{number:04d}"] + head
        if rows:
            main.append(f"#{HNC_FIRST}={row} (ROW: THE TABLE ROW TO MAKE, 1-{len(rows)})")
            for i, r in enumerate(rows, 1):
                rv = dict(vals, **r)
                main.append(f"IF [#{HNC_FIRST} EQ {i}]")
                main += [f"{var[k]}={_num(float(rv[k]))} ({k.upper()})" for k in fam.free]
                main.append("ENDIF")
            main += [f"IF [[#{HNC_FIRST} LT 1] OR [#{HNC_FIRST} GT {len(rows)}]]",
                     "(NO SUCH TABLE ROW)", "M30", "ENDIF"]
        else:
            main += [f"{var[k]}={_num(float(vals[k]))} ({k.upper()})" for k in fam.free]
        main += hnc_checks(_Checks(checks), lets)
        main += [f"M98 P{sub}", "M30"]
        check_lines = []
    body: list[str] = []
    for rg in pc.regions:  # every single alternative's words: before the first block
        if rg.tree is None:
            for s in rg.alts[0].slots:
                if s.kind == "fit":
                    _word(lets, s)
            if dialect == "hnc21t":
                _spin_vars(lets, rg.alts[0])
    pre = list(lets.lines)
    lets.lines.clear()
    notes: list[str] = []
    counter: list[Any] = [0, {}, {}]  # last number, (program, old N) -> new, programs
    labels = [9000]
    for rg in pc.regions:
        if rg.tree is None:
            _emit_alt(rg.alts[0], lets, body, notes, counter, fanuc)
        else:
            _emit_tree(rg.tree, rg.alts, lets, body, notes, counter, labels, fanuc)
    body = [_resolve_labels(ln, counter, pc) if "\0" in ln else ln for ln in body]
    if siemens:  # one main program, its contour subprograms after it
        text = "\n".join(main + [f"; {n}" for n in dict.fromkeys(notes)] + pre + body) + "\n"
        if number != 1:  # another program of the family: its own names
            stem = name[len("%_N_"):-len("_MPF")]
            # the program and its contour subprograms, wherever named: %_N_..., _CNAME="...",
            # a direct call (N23 NAME_C1)
            text = re.sub(rf"(?:(?<=%_N_)|(?<![A-Z0-9_])){re.escape(stem)}_(?=MPF|SPF|C\d)",
                          f"{stem}{number}_", text)
        return Rendered(text, var, dialect)
    sub_head = [f"%{sub}" if not fanuc else f"O{sub}"]
    sub_head += [f"({n})" for n in dict.fromkeys(notes)]
    text = "\n".join(main + sub_head + check_lines + pre + body) + "\n"
    if fanuc:
        text += "%\n"
    return Rendered(text, var, dialect)


# ------------------------------------------------------------------------------------------
# proof
# ------------------------------------------------------------------------------------------

def _moving(moves: Any) -> list:
    """The moves a toolpath comparison takes: a move of no length (a compensation corner at a
    tangent) moves nothing, and a compensation corner (an arc a line block makes) that
    leaves its chord by less than half the comparison's 0.001 mm (the corner the written
    0.001 mm leaves between two pieces of one line, 0.0005 mm off its direction) is one in
    one program and none in the other: both are left out, the moves around them compared."""
    out = []
    for m in moves:
        if m.kind == "dwell":
            continue
        dx, dz = m.end[0] - m.start[0], m.end[1] - m.start[1]
        if abs(dx) <= 1e-3 and abs(dz) <= 1e-3:
            continue
        if m.kind == "arc" and m.op in ("G00", "G01") and m.center is not None:
            r = math.hypot(m.start[0] - m.center[0], m.start[1] - m.center[1])
            d = math.hypot(dx, dz)
            if r - math.sqrt(max(0.0, r * r - d * d / 4)) < 0.0005:
                continue
        out.append(m)
    return out


def _compare(a: Any, b: Any, where: str) -> str | None:
    ma, mb = _moving(a.moves), _moving(b.moves)
    if len(ma) != len(mb):
        return f"{where}: {len(ma)} moves where the per-variant program makes {len(mb)}"
    worst = 0.0
    for x, y in zip(ma, mb):
        if x.kind != y.kind:
            return f"{where}: a {x.kind} move (line {x.line}) where the per-variant program " \
                   f"makes a {y.kind} (line {y.line})"
        if x.tool != y.tool:  # the same path with another insert is another program
            return f"{where}: a move with tool {x.tool} (line {x.line}) where the " \
                   f"per-variant program has tool {y.tool} (line {y.line})"
        # the tool's distance in the plane (x is the radius in a toolpath)
        worst = max(worst, math.hypot(x.end[0] - y.end[0], x.end[1] - y.end[1]))
    if worst > 0.001:
        return f"{where}: the toolpath is {worst:.5f} mm from the per-variant program's"
    return None


def _over_limit(tp: Any, machine: Any, tools: Any) -> str | None:
    """A move whose spindle exceeds its tool's limit (:func:`planner.rpm_limit`: the lowest of
    the machine's, the chuck's and the tool's): the macro leaves the limit near the axis to the
    control's G96 clamp, which knows only the machine's."""
    from .planner import rpm_limit
    for m in tp.moves:
        t = tools.by_number(m.tool) if m.tool else None
        if t is None:
            continue
        lim = rpm_limit(t, machine)
        if m.spindle > lim + 1.0:
            return (f"toolpath: the spindle turns at {m.spindle:.0f} rpm (line {m.line}), above "
                    f"T{m.tool:02d}'s limit of {lim:.0f} rpm (the control clamps G96 at the "
                    f"machine's {machine.max_rpm:.0f} only)")
    return None


def _spindle_compare(text: str, ref_text: str, machine: Any, dialect: str) -> str | None:
    """The commanded spindle of each move (mode and S) against the per-variant program's:
    both run on the machine without its G96 clamp (a G96 move then turns at the rpm of its
    own surface speed, G97 at its S, so a mode or a speed that differs shows), each move's
    rpm within 0.5 rpm and 0.01 % (the 0.001 mm the positions may differ by)."""
    import dataclasses

    from ..nc import run
    free = dataclasses.replace(machine, max_rpm=1.0e9)
    a = run(text, machine=free, file="<macro>", start="reference", dialect=dialect).moves
    b = run(ref_text, machine=free, file="<variant>", start="reference", dialect=dialect).moves

    a, b = _moving(a), _moving(b)
    if len(a) != len(b):
        return f"spindle: {len(a)} moves where the per-variant program makes {len(b)}"
    for x, y in zip(a, b):
        if abs(x.spindle - y.spindle) > 0.5 + 1e-4 * abs(y.spindle):
            return (f"spindle: the move of line {x.line} turns at {x.spindle:.0f} rpm unclamped "
                    f"where the per-variant program's (line {y.line}) turns at "
                    f"{y.spindle:.0f} rpm: another spindle mode or speed")
    return None


def check_program(ctx: Ctx, pc: Piece, sets: list[tuple[str, dict[str, Any], Any]],
                  machine: Any, tools: Any, tol: float) -> list[dict[str, Any]]:
    """Run each (label, parameter set, rendered program) through the interpreter, simulate
    and verify it against its variant's model; the results (``ok``, ``message``)."""
    from ..errors import NCError
    from ..nc import run
    from ..tooling import Stock
    from .api import _load_part, _verify
    stock = Stock.parse(ctx.stock)
    out = []
    for label, p, rend in sets:
        res: dict[str, Any] = {"set": label, "params": _pset(p, pc.fam.free), "ok": False}
        try:
            tp = run(rend.text, machine=machine, file="<macro>", start="reference",
                     dialect=ctx.dialect)
        except NCError as e:
            res["message"] = f"the macro program raises an alarm: {e.one_line()}"
            out.append(res)
            continue
        ref = run(ctx.program(p), machine=machine, file="<variant>", start="reference",
                  dialect=ctx.dialect)
        diff = _compare(tp, ref, "toolpath") or _over_limit(tp, machine, tools)
        if diff is None and ctx.dialect == "hnc21t":  # its G96 has no clamp word
            diff = _spindle_compare(rend.text, ctx.program(p), machine, ctx.dialect)
        if diff:
            res["message"] = diff
            out.append(res)
            continue
        prof = _load_part(pc.fam.path, {k: _fmt(v) for k, v in p.items()})[0]
        rep = _verify(prof, None, stock, tp, machine, tools, tol)
        if rep is None:
            res.update(ok=True, message="not verified: the simulator is not available")
        elif not rep.passed:
            res["message"] = "fails verification: " + rep.summary().replace("\n", "; ")
        else:
            res.update(ok=True, message="pass", overcut=rep.max_overcut_mm,
                       undercut=rep.max_undercut_mm)
        out.append(res)
    return out


def piece_of(pieces: list[Piece], p: dict[str, Any]) -> Piece | None:
    for pc in pieces:
        if _valid(pc.fam, pc.tr, p, pc.lo, pc.hi, True, pc.extra):
            return pc
    return None
