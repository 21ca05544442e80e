"""The FANUC 0i-T reader (G-code system A): the text side of ``docs/FANUC.md`` §1, §3, §10, §11.

:class:`FanucSyntax` is the dialect's Syntax object (``load``, ``parse_statement``,
``fast_words``); it fills the statement model of :mod:`hnc_cam.nc.parser` (the same
:class:`~hnc_cam.nc.parser.Source` and :class:`~hnc_cam.nc.parser.Parsed`), so the interpreter
runs FANUC statements with the machinery it runs HNC's with.

Framing (§1):

* ``%`` marks the start and the end of the tape. When the first ``%`` line comes before any
  program text it opens the tape and the lines before it are ignored; the next ``%`` closes
  it and everything after it is ignored. A file without ``%`` is read whole. Ignored text is
  reported as a note (a warning when the run starts), never dropped silently.
* ``O1234`` (1-8 digits; ``O1234 (NAME)``; ``:1234`` as older tapes write it) starts a
  program: the first is the main program, later ones are subprograms called by number.
  Statements before the first ``O`` form the main program.
* ``( ... )`` is a comment (no nesting; an unclosed ``(`` comments out the rest of the line).
  ``;`` is the end of a block (the screen shows LF as ``;``): a line ``G00 X1.; G01 Z2.``
  holds two blocks, with the columns of the line. Lower case is read as upper case; blanks
  may stand anywhere between words.
* ``/`` (or ``/1`` ... ``/9``) at the start of a block is block delete: with the switch on
  (``block_delete=True``) the block is left out; off (the default) it runs.

Words (§1, §3): a letter and a number, ``X[expr]``, ``X#1``, ``X-#1``; ``,C`` and ``,R``
arrive as the letters ``C`` and ``R``. The decimal-point rule (parameter 3401#0) is applied
here: at ``X Y Z U V W A B C I J K R`` (also ``,C``/``,R`` and ``G04 X/U`` seconds) a number
without a decimal point counts least input increments, 0.001 (``X20`` = 0.020 mm) unless
``calculator=True`` (``X20`` = 20 mm); digits below 0.001 are cut (``X1.23456`` = 1.234); more
than 8 digits or more than 99999.999 is an alarm. ``F P Q D E`` are read as written (``P``
of G04 in ms, ``P``/``Q`` of G74-G76 in µm are the executor's and the cycles' to scale);
``G`` as written; ``H L M N O S T`` are whole numbers (a decimal point there is PS0007).
A value inside brackets or a variable is in mm whatever the rule says. One note per file
warns of coordinate words written without a decimal point (standard mode: any nonzero one;
calculator mode: when the file mixes both forms).

Macro B (§10): ``#i = e``, ``#[e] = e``, ``GOTO n``, ``IF [c] GOTO n``, ``IF [c] THEN #i = e``,
``WHILE [c] DOm`` ... ``ENDm`` and a bare ``DOm`` (m = 1-3, nesting at most 3, matched per
program into :attr:`Source.jump`; faults into :attr:`Source.bad`), expressions with
``+ - * / MOD``, ``EQ NE GT GE LT LE``, ``AND OR XOR`` and the functions ``SIN COS TAN ASIN
ACOS ATAN SQRT ABS ROUND FIX FUP LN EXP BIN BCD`` in degrees (``ATAN[a]/[b]`` and
``ATAN[a,b]``); keywords may be shortened to their first two letters (``GO``, ``WH``, ``RO``,
``FI``). Precedence, lowest first: ``OR XOR``; ``AND``; comparisons; ``+ -``; ``* / MOD``;
unary signs; functions, ``[ ]`` and ``#`` (our choice: FANUC ranks ``AND`` with ``*`` and
``OR`` with ``+``, which makes ``IF [#2 EQ #0 AND #13 EQ #0]``, the way published macros
combine conditions, mean something else; with this order it means what it says, and bracketed
expressions are the same under both). Brackets nest at most 5 deep (PS0118).

Macro A (§11): ``G65 Hm P#i Q#j R#k`` translates to the same statements: H01-H34 to an
assignment, H80-H86 to a (conditional) GOTO, H99 to an assignment of P to ``#3000``.
"""
from __future__ import annotations

import re
from typing import Optional

from ...errors import NCError
from ...nc import parser as P
from ...nc.expr import FanucExpr, constant_value
from ...nc.lexer import clean as _clean
from ...nc.lexer import printable
from ...nc.lexer import tokenize as _tokenize

#: the multi-letter words of macro B
KEYWORDS = frozenset({
    "IF", "GOTO", "THEN", "WHILE", "DO", "END",
    "EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR", "XOR", "MOD",
    "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP",
    "LN", "EXP", "BIN", "BCD",
})
FUNCTIONS = frozenset({"SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND",
                       "FIX", "FUP", "LN", "EXP", "BIN", "BCD"})
#: a keyword may be written with its first two letters (``RO`` for ROUND, ``GO`` for GOTO)
ABBREVIATIONS = {k[:2]: k for k in KEYWORDS if len(k) > 2}
OPERATORS = frozenset("#[]=+-*/,")
#: addresses the decimal-point rule applies to (least input increment 0.001 mm / deg / s)
SCALED = frozenset("XYZUVWABCIJKR")
#: addresses that take a whole number only (a decimal point is PS0007)
WHOLE = frozenset("HLMNOST")
#: code letters that are plain arguments in a G65/G66 call (#13, #19, #20): a decimal point
#: is allowed there, as in every argument
CALL_ARGS = frozenset("MST")
#: largest value of a scaled word (8 digits, 3 of them decimals)
SCALED_MAX = 99999.999
#: digits a number may have (0i: more than 8 is an alarm)
MAX_DIGITS = 8
#: largest sequence number
N_MAX = 99999
#: ``[ ]`` nesting limit (PS0118)
BRACKETS_MAX = 5
#: DO/END identifiers and the loop nesting limit
LOOP_IDS = (1, 2, 3)
LOOPS_MAX = 3

# ASCII only (re.A): a digit or blank of another script is an unexpected character
_TOKEN = re.compile(r"\s*+(?:(\d+\.?\d*|\.\d+)|([A-Z]+)|(\S))", re.A)


def _fast_scan(calculator: bool) -> "re.Pattern[str]":
    """The plain-block regex: (letter, number, "") for each word whose number ``float`` reads
    exactly as the rule means it, ("", "", c) at anything else (then the slow path decides).
    Scaled words need a decimal point and at most 3 decimals (calculator mode: the point is
    optional); whole-number words no point; G65 (macro A and calls) never is plain."""
    scaled = (r"[-+]?+(?:\d{1,5}(?:\.\d{0,3})?|\.\d{1,3})" if calculator
              else r"[-+]?+(?:\d{1,5}\.\d{0,3}|\.\d{1,3})")
    return re.compile(
        r"\s*+([A-Z])("
        r"(?<=[XYZUVWABCIJKR])" + scaled +
        r"|(?<=[FPQDE])[-+]?+(?:\d{1,4}(?:\.\d{0,4})?|\d{5,8}\.?|\.\d{1,4})"
        r"|(?<=G)(?!0*65(?![\d.]))\d{1,3}"
        r"|(?<=N)\d{1,5}"
        r"|(?<=[HLMST])\d{1,8}"
        r")(?![\d.])\s*+|\s*+(.)", re.S | re.A)


_FAST_STD = _fast_scan(False)
_FAST_CALC = _fast_scan(True)
# a nonzero scaled literal without a decimal point / with one (the note of §1); a letter run
# before the address (OR1, XOR1) is a keyword, not a word
_POINTLESS = re.compile(r"([XYZUVWABCIJKR])(?<![A-Z][XYZUVWABCIJKR])\s*+([-+]?+0*+[1-9]\d*+)(?![\d.])", re.A)
# a quick superset of _POINTLESS (no possessive-free backtracking, no lookbehind)
_POINTLESS_PRE = re.compile(r"[XYZUVWABCIJKR][-+]?+\d++(?:[^.]|\Z)", re.A)
_POINTED = re.compile(r"[XYZUVWABCIJKR](?<![A-Z][XYZUVWABCIJKR])\s*+[-+]?+(?:\d*\.)", re.A)
_HEADER = re.compile(r"\s*+(?:O|:)\s*+(\d{1,8})\s*+$", re.A)
_HEADER_START = re.compile(r"\s*+(?:O|:)", re.A)
_SLASH = re.compile(r"\s*+/[1-9]?", re.A)
# F without a decimal point (not a keyword's letter) and the G98/G99 words
_FEED = re.compile(r"(?<![A-Z])F\s*+(0*+[1-9]\d*+)(?![\d.])", re.A)
_FEED_PRE = re.compile(r"F\s*+0*+[1-9]\d*+(?![\d.])", re.A)
_G9899 = re.compile(r"(?<![A-Z])G\s*+0*+9([89])(?![\d.])", re.A)
#: first characters of a line that is an ordinary block or macro statement (not a blank, a
#: block-delete slash, a tape mark or a program number)
_PLAIN_START = frozenset("ABCDEFGHIJKLMNPQRSTUVWXYZ#0123456789[]=+-*,.")


def clean(raw: str) -> str:
    """Upper case, comments ``( ... )`` blanked (columns kept). ``;`` is not touched: it ends a
    block here, not a comment."""
    return _clean(raw, semicolon=False)


def _tape_mark(raw: str) -> bool:
    """A line that is only ``%`` (a comment or an end-of-block ``;`` may follow)."""
    return clean(raw).strip().rstrip(";").rstrip() == "%"


def comment_of(raw: str) -> str:
    """The text of the first comment of a line (stripped), or ""."""
    i = raw.find("(")
    if i < 0:
        return ""
    j = raw.find(")", i + 1)
    return (raw[i + 1:] if j < 0 else raw[i + 1:j]).strip()


def tokenize(text: str, line: int = 0, file: str = "<program>", block: Optional[str] = None) -> list:
    """Tokens ``(kind, value, col)`` of a cleaned FANUC line: ``num``, ``addr`` (one letter),
    ``kw`` (a macro keyword, abbreviations expanded) and ``op`` (``# [ ] = + - * / ,``)."""
    return _tokenize(text, line, file, block, KEYWORDS, ABBREVIATIONS, _TOKEN, OPERATORS)


def _digits(num: str) -> int:
    """Significant digits written: leading zeros of the whole part and trailing zeros of the
    fraction do not count."""
    whole, _, frac = num.partition(".")
    return len(whole.lstrip("0")) + len(frac.rstrip("0"))


class _FP(P._P):
    """The FANUC statement parser: the expression grammar of the module doc over the
    HNC parser's token cursor."""

    def __init__(self, toks, text, line, file, block, calculator: bool):
        super().__init__(toks, text, line, file, block)
        self.calculator = calculator
        self.depth = 0
        self.call = False  # a G65/G66 block: M, S and T are arguments (#13, #19, #20)

    # expressions: the HNC grammar with XOR beside OR and MOD beside * and / (no NOT) ------
    or_ops = ("OR", "XOR")
    mul_kw = ("MOD",)

    def bracket(self, what: str):
        """``[ expr ]`` (the ``[`` is the current token)."""
        col = self.peek()[2]
        self.depth += 1
        if self.depth > BRACKETS_MAX:
            raise self.err(f"bad expression: brackets nested more than {BRACKETS_MAX} deep (PS0118)", col)
        self.i += 1
        e = self.expr()
        self.expect_op("]", what)
        self.depth -= 1
        return e

    def primary(self):
        k, v, c = self.peek()
        if k == "num":
            self._finite(v, c)
            self.i += 1
            return ("num", v)
        if k == "op" and v == "#":
            self.i += 1
            return ("var", self.var_index())
        if k == "op" and v == "[":
            return self.bracket("to close '['")
        if k == "kw" and v in FUNCTIONS:
            self.i += 1
            if self.peek()[:2] != ("op", "["):
                raise self.err(f"bad expression: expected '[' after {v}")
            col = self.peek()[2]
            self.depth += 1
            if self.depth > BRACKETS_MAX:
                raise self.err(f"bad expression: brackets nested more than {BRACKETS_MAX} deep "
                               f"(PS0118)", col)
            self.i += 1
            args = [self.expr()]
            if v == "ATAN" and self.peek()[:2] == ("op", ","):
                self.i += 1
                args.append(self.expr())
            self.expect_op("]", f"to close {v}[")
            self.depth -= 1
            if v == "ATAN" and len(args) == 1 and self.peek()[:2] == ("op", "/") \
                    and self.i + 1 < len(self.t) and self.t[self.i + 1][:2] == ("op", "["):
                self.i += 1  # ATAN[a]/[b]: the two-argument form
                args.append(self.bracket("to close ATAN[...]/["))
            return ("call", v, args)
        found = "the end of the block" if k is None else repr(v)
        raise self.err(f"bad expression: expected a number, variable, function or '[', found {found}")

    def var_index(self):
        """What follows ``#``; a constant variable number is a whole number, kept in its
        plain digits (``#030.0`` is ``#30``)."""
        k, v, c = self.peek()
        if k == "op" and v == "[":
            return self.bracket("to close #[")
        if k == "num":
            self._finite(v, c)
            f = float(v)
            if not f.is_integer() or f > 99999999:
                raise self.err(f"invalid variable #{v}: a variable number is a whole number up to "
                               f"99999999", c)
            self.i += 1
            return ("num", str(int(f)))
        return super().var_index()

    def condition(self, what: str) -> FanucExpr:
        """The bracketed condition of IF / WHILE."""
        k, v, c = self.peek()
        if not (k == "op" and v == "["):
            found = "the end of the block" if k is None else repr(v)
            raise self.err(f"bad expression: {what} needs a condition in brackets, as in "
                           f"{what} [#1 GT 0], found {found}")
        return FanucExpr(self.expr(), c)

    # words ---------------------------------------------------------------------------------
    def number(self, letter: str, text: str, neg: bool, col: int) -> float:
        """A literal word value with the decimal-point rule applied."""
        if _digits(text) > MAX_DIGITS:
            raise self.err(f"value out of range: {letter}{'-' if neg else ''}{text} has more than "
                           f"{MAX_DIGITS} digits", col)
        point = "." in text
        if letter in SCALED:
            if point:
                whole, _, frac = text.partition(".")
                v = float(f"{whole or '0'}.{frac[:3] or '0'}")  # digits below 0.001 are cut
            elif self.calculator:
                v = float(text)
            else:
                v = int(text) / 1000.0
            if v > SCALED_MAX:
                raise self.err(f"value out of range: {letter}{'-' if neg else ''}{text} is more than "
                               f"{SCALED_MAX:.3f}", col)
        else:
            if point and letter in WHOLE:
                raise self.err(f"{letter}{'-' if neg else ''}{text}: {letter} takes a whole number "
                               f"without a decimal point (PS0007)", col)
            v = float(text)
        return -v if neg else v

    def value(self, letter: str, col: int):
        k, v, c = self.peek()
        neg = False
        if k == "op" and v in ("+", "-"):
            self.i += 1
            neg = v == "-"
            k, v, c = self.peek()
        if k == "num":
            self.i += 1
            k2, v2, c2 = self.peek()
            if k2 == "num" and c2 == c + len(v):  # "1.2.3": a second point
                raise self.err(f"malformed number {letter}{'-' if neg else ''}{v}{v2}", col)
            if self.call and letter in CALL_ARGS:
                # an argument of a macro call takes its decimal point (the code word's whole
                # number does not apply); passed as written, not rounded as an M/S/T code
                if _digits(v) > MAX_DIGITS:
                    raise self.err(f"value out of range: {letter}{'-' if neg else ''}{v} has "
                                   f"more than {MAX_DIGITS} digits", col)
                node = ("num", repr(float(v)))
                return FanucExpr(("neg", node) if neg else node, c)
            return self.number(letter, v, neg, col)
        if k == "op" and v in ("[", "#"):
            node = self.primary()
            if neg:
                node = ("neg", node)
            cv = constant_value(node)
            if cv is not None:
                return cv
            return FanucExpr(node, c)
        found = "the end of the block" if k is None else repr(v)
        raise self.err(f"word {letter} has no value: expected a number or [expression], found {found}",
                       col)

    expr_type = FanucExpr

    def assign_target(self, idx, col: int):
        """A constant target must be a variable number: whole and not negative."""
        cv = constant_value(idx)
        if cv is not None and (not cv.is_integer() or cv < 0):
            raise self.err(f"invalid variable #{cv:g}", col)
        return int(cv) if cv is not None else FanucExpr(idx, col)

    def assignments(self) -> list:
        return P._assignments(self)

    def words(self, n: Optional[int]) -> list:
        words = []
        if n is not None:
            words.append(("N", float(n), 0))
        while self.peek()[0] is not None:
            k, v, c = self.take()
            if k == "op" and v == ",":
                k2, v2, c2 = self.peek()
                if k2 != "addr" or v2 not in ("C", "R"):
                    raise self.err("',' starts a corner word: ,C (chamfer) or ,R (round)", c)
                self.i += 1
                words.append((v2, self.value(v2, c2), c2))
                continue
            if k != "addr":
                if k == "kw":
                    raise self.err(f"{v} is not allowed here (a macro keyword inside a block)", c)
                if k == "op" and v == "#":
                    raise self.err("an assignment cannot follow words in the same block", c)
                raise self.err(f"unexpected {v!r}: expected an address letter", c)
            if v == "O":
                raise self.err("O is a program number: it stands at the start of its own line", c)
            words.append((v, self.value(v, c), c))
        return words


def _loop_id(toks: list, i: int) -> Optional[int]:
    """The identifier after DO/END at token ``i`` (None when it is not 1-9 written plainly)."""
    if i < len(toks) and toks[i][0] == "num" and toks[i][1].isdigit() and len(toks[i][1]) <= 3:
        return int(toks[i][1])
    return None


def _skip_n(toks: list) -> int:
    if len(toks) >= 2 and toks[0][:2] == ("addr", "N") and toks[1][0] == "num":
        return 2
    return 0


def _classify(s: str) -> tuple[str, Optional[int]]:
    """Kind of a cleaned statement line (and the DO/END identifier of a loop statement)."""
    if "IF" not in s and "GO" not in s and "WH" not in s and "DO" not in s and "EN" not in s \
            and "H" not in s:
        return P.OTHER, None
    try:
        toks = tokenize(s)
    except NCError:
        return P.OTHER, None  # the statement alarms when it is parsed
    i = _skip_n(toks)
    if i >= len(toks):
        return P.OTHER, None
    k, v, _ = toks[i]
    if k == "kw":
        if v == "IF":
            for t in toks[i + 1:]:
                if t[0] == "kw" and t[1] in ("GOTO", "THEN"):
                    return (P.GOTO if t[1] == "GOTO" else P.IFTHEN), None
            return P.OTHER, None
        if v == "GOTO":
            return P.GOTO, None
        if v == "WHILE":
            for j in range(len(toks) - 1, i, -1):
                if toks[j][:2] == ("kw", "DO"):
                    return P.WHILE, _loop_id(toks, j + 1)
            return P.WHILE, None
        if v == "DO":
            return P.WHILE, _loop_id(toks, i + 1)
        if v == "END":
            return P.ENDW, _loop_id(toks, i + 1)
        return P.OTHER, None
    h = _macro_a_h(toks)
    if h is not None and 80 <= h <= 86:
        return P.GOTO, None
    return P.OTHER, None


def _macro_call(toks: list) -> bool:
    """A block with a literal G65 or G66 (a macro call with arguments)."""
    return any(k == "addr" and v == "G" and toks[j + 1][0] == "num"
               and toks[j + 1][1].isdigit() and int(toks[j + 1][1]) in (65, 66)
               for j, (k, v, _c) in enumerate(toks[:-1]))


def _macro_a_h(toks: list) -> Optional[int]:
    """The H number of a macro A block (``G65 H..``), else None."""
    g65 = False
    h = None
    for j in range(len(toks) - 1):
        k, v, _ = toks[j]
        if k == "addr" and toks[j + 1][0] == "num":
            if v == "G" and toks[j + 1][1].isdigit() and int(toks[j + 1][1]) == 65:
                g65 = True
            elif v == "H" and h is None:
                try:
                    h = int(float(toks[j + 1][1]))
                except ValueError:  # pragma: no cover - num tokens are numbers
                    h = -1
    return h if g65 and h is not None else None


# macro A: H code -> the value from the operand nodes q, r and the result variable's node p
_H_ASSIGN = {
    1: lambda q, r, p: q,
    2: lambda q, r, p: ("bin", "+", q, r),
    3: lambda q, r, p: ("bin", "-", q, r),
    4: lambda q, r, p: ("bin", "*", q, r),
    5: lambda q, r, p: ("bin", "/", q, r),
    11: lambda q, r, p: ("bin", "OR", q, r),
    12: lambda q, r, p: ("bin", "AND", q, r),
    13: lambda q, r, p: ("bin", "XOR", q, r),
    21: lambda q, r, p: ("call", "SQRT", [q]),
    22: lambda q, r, p: ("call", "ABS", [q]),
    23: lambda q, r, p: ("bin", "-", q, ("bin", "*", ("call", "FIX", [("bin", "/", q, r)]), r)),
    24: lambda q, r, p: ("call", "BIN", [q]),
    25: lambda q, r, p: ("call", "BCD", [q]),
    26: lambda q, r, p: ("bin", "/", ("bin", "*", p, q), r),
    27: lambda q, r, p: ("call", "SQRT", [("bin", "+", ("bin", "*", q, q), ("bin", "*", r, r))]),
    28: lambda q, r, p: ("call", "SQRT", [("bin", "-", ("bin", "*", q, q), ("bin", "*", r, r))]),
    31: lambda q, r, p: ("bin", "*", q, ("call", "SIN", [r])),
    32: lambda q, r, p: ("bin", "*", q, ("call", "COS", [r])),
    33: lambda q, r, p: ("bin", "*", q, ("call", "TAN", [r])),
    34: lambda q, r, p: ("call", "ATAN", [q, r]),
}
#: H codes whose result needs R as well as Q
_H_NEEDS_R = frozenset({2, 3, 4, 5, 11, 12, 13, 23, 26, 27, 28, 31, 32, 33, 34})
_H_JUMP = {81: "EQ", 82: "NE", 83: "GT", 84: "LT", 85: "GE", 86: "LE"}


def _macro_a(p: _FP, n: Optional[int]) -> P.Parsed:
    """``G65 Hm P.. Q.. R..`` as assignment / GOTO statements (§11). Operands are ``#i``
    (also ``-#i`` and ``#[e]``) or constants taken as written (no decimal-point rule)."""
    ops: dict[str, tuple] = {}
    hcol = 0
    h = None
    while p.peek()[0] is not None:
        k, v, c = p.take()
        if k != "addr":
            raise p.err(f"unexpected {v!r}: a macro A block is G65 Hm P.. Q.. R..", c)
        if v in ops or (v == "H" and h is not None):
            raise p.err(f"word {v} appears twice in the block", c)
        k2, v2, c2 = p.peek()
        neg = False
        if k2 == "op" and v2 in ("+", "-"):
            neg = v2 == "-"
            p.i += 1
            k2, v2, c2 = p.peek()
        if k2 == "num":
            p._finite(v2, c2)
            p.i += 1
            node: tuple = ("num", v2)
        elif k2 == "op" and v2 in ("#", "["):
            node = p.primary()
        else:
            found = "the end of the block" if k2 is None else repr(v2)
            raise p.err(f"word {v} has no value: expected a number or #variable, found {found}", c)
        if neg:
            node = ("neg", node)
        if v == "G":
            if node != ("num", v2) or not v2.isdigit() or int(v2) != 65:
                raise p.err("a macro A block has one G word, G65", c)
            ops["G"] = (node, c)
        elif v == "H":
            if node[0] != "num" or neg or not v2.isdigit():
                raise p.err("H of a macro A block is the operation number written plainly (H01-H99)", c)
            h, hcol = int(v2), c
        elif v in ("P", "Q", "R"):
            ops[v] = (node, c)
        else:
            raise p.err(f"{v} is not a word of a macro A block (G65 Hm P#i Q#j R#k)", c)
    if h is None:  # pragma: no cover - only called for blocks with H
        raise p.err("macro A block without H", 1)

    def need(letter: str, what: str) -> tuple:
        if letter not in ops:
            raise p.err(f"G65 H{h:02d}: missing {letter} ({what})", hcol)
        return ops[letter]

    if h in _H_ASSIGN or h == 99:
        if h == 99:
            pn, pc = need("P", "the alarm number")
            return P.Parsed("assign", n, assigns=[(3000, FanucExpr(pn, pc), pc)])
        pn, pc = need("P", "the result variable #i")
        if pn[0] != "var":
            raise p.err(f"G65 H{h:02d}: P names the result variable, as in P#101", pc)
        qn, qc = need("Q", "the first operand")
        rn = need("R", "the second operand")[0] if h in _H_NEEDS_R else None
        idx = pn[1]
        cv = constant_value(idx)
        if cv is not None and (not cv.is_integer() or cv < 0):
            raise p.err(f"invalid variable #{cv:g}", pc)
        target = int(cv) if cv is not None else FanucExpr(idx, pc)
        return P.Parsed("assign", n, assigns=[(target, FanucExpr(_H_ASSIGN[h](qn, rn, pn), qc), pc)])
    if h == 80 or h in _H_JUMP:
        pn, pc = need("P", "the sequence number to jump to")
        cond = None
        if h in _H_JUMP:
            qn, qc = need("Q", "the first operand")
            rn = need("R", "the second operand")[0]
            cond = FanucExpr(("bin", _H_JUMP[h], qn, rn), qc)
        return P.Parsed(P.GOTO, n, target=FanucExpr(pn, pc), cond=cond)
    raise p.err(f"G65 H{h}: no such macro A operation (H01-H05, H11-H13, H21-H28, H31-H34, "
                f"H80-H86, H99)", hcol)


_G73_FIRST = re.compile(r"G0*73(?!\d)", re.A)


def _count_word(s: str, m: "re.Match[str]") -> bool:
    """Whether the pointless word ``m`` of statement ``s`` is the pass count ``R`` of a first
    G73 block (``G73 U W R(d)``, no P): a count, not a coordinate, so not a decimal-point case."""
    return m.group(1) == "R" and _G73_FIRST.search(s) is not None and "P" not in s


class FanucSyntax:
    """The FANUC 0i-T reader (module doc). ``calculator``: parameter 3401#0 DPI = 1 (a number
    without a decimal point is mm); ``block_delete``: the block-delete switch is on."""

    functions_in_degrees = True

    def __init__(self, calculator: bool = False, block_delete: bool = False):
        self.calculator = bool(calculator)
        self.block_delete = bool(block_delete)
        self._fast = (_FAST_CALC if self.calculator else _FAST_STD).findall

    # -- the file ------------------------------------------------------------------------
    def load(self, text: str, file: str = "<program>", line_limit: Optional[int] = None) -> P.Source:
        raw = P.split_lines(text)
        src = P.Source(file=file, lines=raw)
        src.syntax = self  # the reader the interpreter compiles this source's statements with
        lineno, stext, kind, number = src.lineno, src.text, src.kind, src.number
        loop_id: dict[int, Optional[int]] = {}
        notes = src.notes
        # the tape: the first '%' before any program text opens it, the next one closes it
        first, last = 0, len(raw)
        opened = False
        for i, r in enumerate(raw):
            if "%" not in r:
                if clean(r).strip():
                    break
                continue
            if _tape_mark(r):
                first, opened = i + 1, True
            break
        if not opened:
            # text before a '%': skipped (the tape starts there) when no O line precedes the
            # '%' and one follows it
            for i, r in enumerate(raw):
                if "%" in r and _tape_mark(r):
                    if not any(_HEADER_START.match(clean(raw[j])) for j in range(i)) and \
                            any(_HEADER_START.match(clean(x)) for x in raw[i + 1:]):
                        before = [j for j in range(i) if clean(raw[j]).strip()]
                        first, opened = i + 1, True
                        notes.append((before[0] + 1, 1, f"{len(before)} line(s) before the '%' on "
                                      f"line {i + 1} are not read (the tape starts at '%')"))
                    break
        for i in range(first, len(raw)):
            r = raw[i]
            if "%" in r and _tape_mark(r):
                last = i
                rest = [j for j in range(i + 1, len(raw)) if clean(raw[j]).strip()]
                if rest:
                    notes.append((rest[0] + 1, 1, f"the tape ends with the '%' on line {i + 1}: "
                                  f"{len(rest)} line(s) after it are not read"))
                break
        bdel = self.block_delete
        hdr_at: list[int] = []
        loops: list[int] = []
        padded, budget = 0, 4 * len(text) + 1_000_000
        OTHER, HDR, WHILE, ENDW = P.OTHER, P.HDR, P.WHILE, P.ENDW
        for i in range(first, last):
            r = raw[i]
            if line_limit is not None and len(r) > line_limit:
                raise NCError(f"line too long: {len(r)} characters (the machine's limit is {line_limit}, "
                              f"[limits] line_chars)", i + 1, line_limit + 1, printable(r.strip()), file)
            if "\0" in r:
                raise NCError("NUL character: this is not program text (a binary file?)", i + 1,
                              r.index("\0") + 1, printable(r.strip()), file)
            s = (clean(r) if "(" in r else r.upper()).rstrip()
            if s == r:
                s = r  # one string for the raw and the cleaned line
            if not s:
                continue
            if ";" in s:
                # each block keeps its columns by leading blanks: bounded (before the blocks
                # are built), so that a long line of many ';' blocks cannot take memory
                # quadratic in its length
                j = s.find(";")
                while j >= 0 and padded <= budget:
                    padded += j
                    j = s.find(";", j + 1)
                padded += len(s)
                if padded > budget:
                    raise NCError(f"too many ';' blocks on long lines (more than {budget} characters "
                                  f"once each block keeps its columns): put the blocks on lines of "
                                  f"their own", i + 1, 1, printable(r.strip()), file)
                parts = self._split_blocks(s)
            else:
                parts = (s,)
            for s in parts:
                c0 = s[0]
                if c0 not in _PLAIN_START:
                    # not the common block starting with a word or a macro statement
                    if c0 == " " or c0 == "\t":
                        c0 = s.lstrip()[:1]
                    if c0 == "/":
                        if bdel:
                            continue
                        m = _SLASH.match(s)
                        s = " " * m.end() + s[m.end():]
                        if not s.strip():
                            continue
                        c0 = s.lstrip()[:1]
                    if c0 == "%":
                        raise NCError(self._percent_message(s), i + 1, s.index("%") + 1,
                                      printable(r.strip()), file)
                    if c0 == "O" or c0 == ":":
                        m = _HEADER.match(s)
                        if m is None:
                            raise NCError("a program starts with O and its number (1-8 digits) alone "
                                          "on its line, as O1234 (a comment may follow)", i + 1,
                                          s.index(c0) + 1, printable(r.strip()), file)
                        hdr_at.append(len(kind))
                        lineno.append(i + 1)
                        stext.append(s)
                        kind.append(HDR)
                        number.append(int(m.group(1)))
                        continue
                lineno.append(i + 1)
                stext.append(s)
                number.append(None)
                if "IF" not in s and "GO" not in s and "WH" not in s and "DO" not in s \
                        and "EN" not in s and "H" not in s:
                    kind.append(OTHER)
                    continue
                k, lid = _classify(s)
                kind.append(k)
                if k is WHILE or k is ENDW:
                    loop_id[len(kind) - 1] = lid
                    loops.append(len(kind) - 1)
        P.set_spans(src, hdr_at)  # before the first O: the main program
        self._loops(src, loops, loop_id)
        up = text.upper()
        for note in (self._decimal_note(src, up), self._feed_note(src, up)):
            if note is not None:
                notes.append(note)
        return src

    @staticmethod
    def _feed_note(src: P.Source, text: str) -> Optional[tuple[int, int, str]]:
        """A note at the first ``F`` without a decimal point written while G99 (feed per
        revolution, FANUC's power-on mode) is in effect in file order: the reader takes it as
        written, a control may count it in increments. ``text``: the file in upper case."""
        if _FEED_PRE.search(text) is None:
            return None
        per_rev = True
        for i, s in enumerate(src.text):
            if src.kind[i] is not P.OTHER:
                continue
            if "G" in s:
                for m in _G9899.finditer(s):
                    per_rev = m.group(1) == "9"
            if per_rev and "F" in s:
                m = _FEED.search(s)
                if m is not None:
                    return (src.lineno[i], m.start() + 1,
                            f"F{m.group(1)} has no decimal point in G99 (feed per revolution): read as "
                            f"{m.group(1)} mm/rev as written; write F{m.group(1)}. to say so, or F0.… "
                            f"for a fraction of a millimetre")
        return None

    def _decimal_note(self, src: P.Source, text: str) -> Optional[tuple[int, int, str]]:
        """The note of §1 about coordinate words without a decimal point (one per file):
        standard mode, the first nonzero one; calculator mode, the first one when others have
        a point. One search over the whole text finds none in a program written with points;
        only then are the statements looked at one by one."""
        calc = self.calculator
        up = text  # the file in upper case
        m = _POINTLESS_PRE.search(up)
        if m is None or _POINTLESS.search(up, m.start()) is None:
            return None
        if calc and _POINTED.search(up) is None:
            return None
        pointless = None
        pointed = False
        for i, s in enumerate(src.text):
            if src.kind[i] is not P.OTHER:
                continue
            if pointless is None:
                m = next((m for m in _POINTLESS.finditer(s) if not _count_word(s, m)), None)
                if m is not None and not self._macro_a_line(s):
                    pointless = (src.lineno[i], m.start(1) + 1, m.group(1), m.group(2))
            if not pointed and _POINTED.search(s) and not self._macro_a_line(s):
                pointed = True
            if pointless is not None and (pointed or not calc):
                break
        if pointless is None or (calc and not pointed):
            return None
        line, col, letter, digits = pointless
        if calc:
            return (line, col, f"{letter}{digits} has no decimal point while other coordinate words "
                               f"have one: with decimal_point = \"calculator\" both mean mm; check "
                               f"the program was written for this setting")
        v = int(digits) / 1000.0
        return (line, col, f"{letter}{digits} has no decimal point: read as {letter}{v:g} mm (least "
                           f"input increment 0.001; FANUC parameter 3401#0 = 0); write {letter}{digits}. "
                           f"for millimetres, or set decimal_point = \"calculator\" in the machine file"
                           f"{' (the program also writes coordinates with a decimal point)' if pointed else ''}")

    @staticmethod
    def _macro_a_line(s: str) -> bool:
        if "H" not in s:
            return False
        try:
            return _macro_a_h(tokenize(s)) is not None
        except NCError:
            return False

    @staticmethod
    def _split_blocks(s: str) -> list[str]:
        """The blocks of a line with ``;`` end-of-block marks, each the width of the line
        (columns kept); an empty block is dropped."""
        out = []
        start = 0
        n = len(s)
        while start <= n:
            j = s.find(";", start)
            end = n if j < 0 else j
            part = (" " * start + s[start:end]).rstrip()
            if part.strip():
                out.append(part)
            if j < 0:
                break
            start = j + 1
        return out

    @staticmethod
    def _percent_message(s: str) -> str:
        rest = s.strip()[1:].strip()
        if rest.isdigit():
            return (f"%{rest} is an HNC-21T program header; a FANUC program starts with O{rest} "
                    f"(or read the file with --dialect hnc21t)")
        return "'%' marks the start or end of the tape and stands alone on its line"

    @staticmethod
    def _loops(src: P.Source, loops: list[int], loop_id: dict) -> None:
        """Match WHILE/DO and END per program (``loops``: their statements in order):
        WHILE -> the statement after its END, END -> its WHILE; faults into ``src.bad``."""
        if not loops:
            return
        kind, bad, jump = src.kind, src.bad, src.jump
        for a, b in src.spans:
            stack: list[tuple[int, int]] = []  # (id, stmt)
            for i in loops:
                if not a <= i < b:
                    continue
                k = kind[i]
                m = loop_id.get(i)
                word = "DO" if k is P.WHILE else "END"
                if m is None:
                    bad[i] = f"{word} needs its identifier 1, 2 or 3 (as {word}1) (PS0126)"
                    continue
                if m not in LOOP_IDS:
                    bad[i] = f"{word}{m}: the loop identifier must be 1, 2 or 3 (PS0126)"
                    continue
                if k is P.WHILE:
                    if len(stack) >= LOOPS_MAX:
                        bad[i] = f"DO{m}: loops nest at most {LOOPS_MAX} deep (PS0124)"
                        continue
                    if any(mm == m for mm, _ in stack):
                        bad[i] = f"DO{m} inside the loop DO{m} it would close (PS0124)"
                        continue
                    stack.append((m, i))
                    continue
                if not stack or stack[-1][0] != m:
                    if any(mm == m for mm, _ in stack):
                        bad[i] = (f"END{m} closes DO{m} while the inner loop DO{stack[-1][0]} is still "
                                  f"open: loops must not overlap (PS0124)")
                    else:
                        bad[i] = f"END{m} without DO{m} (PS0124)"
                    continue
                _, s0 = stack.pop()
                jump[s0] = i + 1
                jump[i] = s0
            for m, s0 in stack:
                bad[s0] = f"DO{m} is never closed by END{m} before the end of the program (PS0124)"

    # -- statements ----------------------------------------------------------------------
    def fast_words(self, text: str) -> Optional[list[tuple[str, str, str]]]:
        """``(letter, number, "")`` per word of a plain block whose numbers ``float`` reads
        as the decimal-point rule means them; None for anything else (the slow path)."""
        return P.fast_words(text, self._fast)

    def parse_statement(self, text: str, line: int, file: str = "<program>",
                        block: Optional[str] = None) -> P.Parsed:
        return P.parse_statement(text, line, file, block, self._parse)

    def _parse(self, text: str, line: int, file: str, blk: str) -> P.Parsed:
        toks = tokenize(text, line, file, blk)
        p = _FP(toks, text, line, file, blk, self.calculator)
        n = None
        k, v, c = p.peek()
        if k == "addr" and v == "N" and len(toks) > 1 and toks[1][0] == "num":
            p.i += 1
            nt = p.take()[1]
            if "." in nt or _digits(nt) > 5 or int(nt) > N_MAX:
                raise p.err(f"value out of range: N{nt}: a sequence number is a whole number "
                            f"0-{N_MAX}", c)
            n = int(nt)
            k, v, c = p.peek()
        if k == "kw":
            return self._control(p, n, k, v, c, blk)
        if k == "op" and v == "#":
            return P.Parsed("assign", n, assigns=p.assignments(), message=comment_of(blk))
        if "H" in text and _macro_a_h(toks) is not None:
            return _macro_a(p, n)
        p.call = "6" in text and _macro_call(toks)
        return P.Parsed("block", n, words=p.words(n))

    @staticmethod
    def _control(p: _FP, n: Optional[int], k: str, v: str, c: int, blk: str) -> P.Parsed:
        p.i += 1
        if v == "GOTO":
            if p.peek()[0] is None:
                raise p.err("GOTO needs a sequence number, as GOTO 10 or GOTO #1")
            col = p.peek()[2]
            target = FanucExpr(p.expr(), col)
            if p.peek()[0] is not None:
                raise p.err(f"unexpected {p.peek()[1]!r} after the GOTO target")
            return P.Parsed(P.GOTO, n, target=target)
        if v == "IF":
            cond = p.condition("IF")
            k2, v2, c2 = p.peek()
            if (k2, v2) == ("kw", "GOTO"):
                p.i += 1
                if p.peek()[0] is None:
                    raise p.err("GOTO needs a sequence number, as GOTO 10 or GOTO #1")
                col = p.peek()[2]
                target = FanucExpr(p.expr(), col)
                if p.peek()[0] is not None:
                    raise p.err(f"unexpected {p.peek()[1]!r} after the GOTO target")
                return P.Parsed(P.GOTO, n, cond=cond, target=target)
            if (k2, v2) == ("kw", "THEN"):
                p.i += 1
                if p.peek()[:2] != ("op", "#"):
                    found = "the end of the block" if p.peek()[0] is None else repr(p.peek()[1])
                    raise p.err(f"IF [..] THEN takes an assignment #i = expression, found {found} "
                                f"(for a jump write IF [..] GOTO n)")
                return P.Parsed(P.IFTHEN, n, cond=cond, assigns=p.assignments(),
                                message=comment_of(blk))
            found = "the end of the block" if k2 is None else repr(v2)
            raise p.err(f"IF [..] must be followed by GOTO n or THEN #i = expression, found {found}")
        if v == "WHILE":
            cond = p.condition("WHILE")
            if p.peek()[:2] != ("kw", "DO"):
                found = "the end of the block" if p.peek()[0] is None else repr(p.peek()[1])
                raise p.err(f"WHILE [..] must be followed by DO1, DO2 or DO3, found {found}")
            p.i += 1
            _loop_word(p, "DO")
            return P.Parsed(P.WHILE, n, cond=cond)
        if v == "DO":
            _loop_word(p, "DO")
            return P.Parsed(P.WHILE, n)
        if v == "END":
            _loop_word(p, "END")
            return P.Parsed(P.ENDW, n)
        raise p.err(f"{v} cannot start a statement", c)


def _loop_word(p: _FP, word: str) -> int:
    """The identifier after DO / END (1-3) and nothing after it."""
    k, v, c = p.peek()
    if k != "num" or not v.isdigit() or int(v) not in LOOP_IDS:
        found = "the end of the block" if k is None else repr(v)
        raise p.err(f"{word} needs its identifier 1, 2 or 3, found {found} (PS0126)")
    p.i += 1
    if p.peek()[0] is not None:
        raise p.err(f"unexpected {p.peek()[1]!r} after {word}{v}")
    return int(v)
