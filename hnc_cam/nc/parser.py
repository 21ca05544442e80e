"""Parser of HNC-21/22T programs: file structure, statements, expressions.

File structure (manual §2.3, appendix 1):

* a program starts with ``%nnnn`` or ``Onnnn`` (``o100`` too; lower case is read as upper
  case) and the main program ends with ``M02``/``M30``; subprograms follow in the same file,
  each with its own header, ending with ``M99``;
* comment lines (and blank lines) may precede the first header; statements before any header
  form an unnamed main program (the manual prints example 21 without a header);
* blocks run in file order, not N order.

A line is one statement:

* a block of words ``N.. G.. X.. Z.. F.. M..``: an address letter followed by a number,
  a bracketed expression ``X[#10*2]``, or a variable ``X#1`` / ``X-#1``;
* one or more assignments ``#n = expr`` (``#[expr] = expr`` for indirect ones), optionally
  after an ``N`` number;
* ``IF expr`` / ``ELSE`` / ``ENDIF`` / ``WHILE expr`` / ``ENDW`` (optionally after ``N``).

Other dialects' readers (``hnc_cam/dialect/<name>/syntax.py``) fill the same :class:`Source`
and :class:`Parsed`, with two more kinds: ``GOTO`` (a jump to a block number, conditional or
not; :meth:`Source.find_label` finds its target) and ``IFTHEN`` (assignments under a
condition); :attr:`Source.notes` carries the warnings a reader finds while loading.

IF/WHILE structure is matched per program when the file is loaded; an unmatched statement
(``ENDW`` without ``WHILE``, an ``IF`` never closed) alarms at its line when execution reaches
it, so the alarm names the first line the controller stops at in execution order.

Expression AST nodes (tuples): ``("num", text)``, ``("var", index_node)``,
``("neg", n)``, ``("not", n)``, ``("bin", op, a, b)`` with op in ``+ - * / EQ NE GT GE LT LE
AND OR``, ``("call", NAME, [args])``, ``("ar", index_node)``.
"""
from __future__ import annotations

import bisect
import math
import re
from dataclasses import dataclass, field
from typing import Optional

from ..errors import NCError
from . import toolpath as _tp
from .expr import Expr, constant_value
from .lexer import FAST_SCAN, FUNCTIONS, clean, printable, tokenize

# statement kinds
HDR, IF, ELSE, ENDIF, WHILE, ENDW, OTHER = "hdr", "if", "else", "endif", "while", "endw", "x"
#: kinds of other dialects' control statements: an unconditional or conditional jump to a
#: block number (``GOTO n``, ``IF [c] GOTO n``) and a conditional assignment
#: (``IF [c] THEN #i = e``) that never jumps
GOTO, IFTHEN = "goto", "ifthen"
_CONTROL = {"IF": IF, "ELSE": ELSE, "ENDIF": ENDIF, "WHILE": WHILE, "ENDW": ENDW}
#: digits of a program number after ``%``/``O`` (a longer run is not a header)
PROGRAM_NUMBER_DIGITS = 10
#: line ends: CR LF, a lone CR and a lone LF each end a line (as the controller and editors read
#: a file); a lone CR is never part of a block
_EOL = re.compile(r"\r\n|\r|\n")
#: the block number a statement starts with (after blanks and a block-delete slash)
_LABEL = re.compile(r"[\s/]*+N\s*+(\d{1,10})(?![\d.])")


@dataclass
class Source:
    """A loaded program file: its statements (one per non-empty line) and structure."""
    file: str
    lines: list[str]  # raw source lines
    lineno: list[int] = field(default_factory=list)  # statement -> 1-based line
    text: list[str] = field(default_factory=list)  # statement -> cleaned text
    kind: list[str] = field(default_factory=list)  # statement -> kind
    number: list[Optional[int]] = field(default_factory=list)  # header statements: program no.
    programs: dict[int, int] = field(default_factory=dict)  # program no. -> first statement
    spans: list[tuple[int, int]] = field(default_factory=list)  # program (first, end) statements
    jump: dict[int, int] = field(default_factory=dict)  # IF/ELSE/WHILE/ENDW -> target
    bad: dict[int, str] = field(default_factory=dict)  # unmatched IF/ELSE/.../ENDW -> alarm
    main: tuple[int, int] = (0, 0)
    #: (line, col, message): warnings the interpreter gives once when the run starts
    notes: list[tuple[int, int, str]] = field(default_factory=list)
    #: block number -> statements numbered so, ascending (built on the first GOTO)
    _labels: Optional[dict[int, list[int]]] = field(default=None, repr=False, compare=False)

    def block_text(self, line: int) -> str:
        """The block at ``line`` as an alarm echoes it: stripped, bounded and escaped
        (see :func:`~hnc_cam.nc.lexer.printable`)."""
        if 1 <= line <= len(self.lines):
            return printable(self.lines[line - 1].strip())
        return ""

    def alarm(self, message: str, stmt: int, col: int = 0) -> NCError:
        line = self.lineno[stmt] if 0 <= stmt < len(self.lineno) else 0
        return NCError(message, line, col, self.block_text(line), self.file)

    def find_label(self, n: int, span: tuple[int, int], after: int) -> Optional[int]:
        """The statement numbered ``N n`` inside the program ``span`` (first, end): the first
        one from statement ``after`` to the span's end, else the first from the span's start
        (the search order of a ``GOTO``); None when the program has no such block."""
        labels = self._labels
        if labels is None:
            labels = self._labels = {}
            for i, t in enumerate(self.text):
                m = _LABEL.match(t)
                if m is not None:
                    labels.setdefault(int(m.group(1)), []).append(i)
        found = labels.get(n)
        if not found:
            return None
        a, b = span
        j = bisect.bisect_left(found, max(after, a))
        if j < len(found) and found[j] < b:
            return found[j]
        j = bisect.bisect_left(found, a)
        if j < len(found) and found[j] < b:
            return found[j]
        return None

    def span_of(self, stmt: int) -> tuple[int, int]:
        for a, b in self.spans:
            if a <= stmt < b:
                return (a, b)
        return self.main


def _header(s: str) -> tuple[bool, Optional[int]]:
    t = s.lstrip()
    if not t:
        return (False, None)
    c = t[0]
    if c == "%":
        rest = t[1:].strip()
        if rest and _digits(rest):
            return (True, int(rest))
        if not rest:
            return (True, None)
        return (False, None)
    if c == "O":
        rest = t[1:].strip()
        if _digits(rest):
            return (True, int(rest))
    return (False, None)


def _digits(s: str) -> bool:
    """ASCII digits only (``str.isdigit`` also accepts ``³`` and other Unicode digits), at
    most :data:`PROGRAM_NUMBER_DIGITS` of them."""
    return s.isascii() and s.isdigit() and len(s) <= PROGRAM_NUMBER_DIGITS


def _control(s: str) -> Optional[str]:
    """Kind of a control statement line, or None (quick string tests before the regex-free
    check, so that plain blocks cost almost nothing)."""
    if "IF" not in s and "ELSE" not in s and "WH" not in s and "ENDW" not in s:
        return None
    t = s.lstrip()
    if t.startswith("N"):
        i = 1
        while i < len(t) and (t[i].isdigit() or t[i] == " "):
            i += 1
        t = t[i:]
    j = 0
    while j < len(t) and "A" <= t[j] <= "Z":
        j += 1
    return _CONTROL.get(t[:j])


def split_lines(text: str) -> list[str]:
    """The lines of a program text: CR LF, CR and LF each end a line (an editor's count);
    a final line end does not start another line."""
    raw = _EOL.split(text)
    if raw and raw[-1] == "":
        raw.pop()
    return raw


def set_spans(src: Source, starts: list[int]) -> None:
    """The programs of a source whose headers stand at statements ``starts``: the statements
    before the first header form the main program, then one span per header (the first is
    the main program when nothing precedes it); ``src.programs`` maps a header's number to
    its first statement (the first program of a number wins)."""
    number = src.number
    n = len(src.kind)
    spans: list[tuple[int, int]] = []
    if not starts or starts[0] > 0:
        spans.append((0, starts[0] if starts else n))
    for j, i in enumerate(starts):
        end = starts[j + 1] if j + 1 < len(starts) else n
        spans.append((i + 1, end))
        num = number[i]
        if num is not None and num not in src.programs:
            src.programs[num] = i + 1
    src.spans = spans
    src.main = spans[0] if spans else (0, 0)


def load(text: str, file: str = "<program>", line_limit: Optional[int] = None) -> Source:
    """Split ``text`` into statements and programs and match IF/WHILE structure.

    Alarms here (before anything runs) are about the file as a whole, in line order: a NUL
    character (a binary file, not program text), a line longer than ``line_limit``
    characters. A structure error (``ENDW`` without ``WHILE``, an ``IF`` never closed, ...)
    is recorded in :attr:`Source.bad` and alarms when execution reaches that statement, so
    that an earlier line the controller stops at is reported first."""
    core = _tp.core
    got = (core.split(text, -1 if line_limit is None else line_limit, OTHER, HDR, _control, _header)
           if core is not None and text.__class__ is str else None)
    if got is not None:  # the compiled core's split: the same lists as the loop below
        raw, lineno, stext, kind, number = got
        src = Source(file=file, lines=raw, lineno=lineno, text=stext, kind=kind, number=number)
        raw = ()
    else:
        raw = split_lines(text)
        src = Source(file=file, lines=raw)
        lineno, stext, kind, number = src.lineno, src.text, src.kind, src.number
    for i, r in enumerate(raw):
        if line_limit is not None and len(r) > line_limit:
            raise NCError(f"line too long: {len(r)} characters (the machine's limit is {line_limit}, "
                          f"[limits] line_chars)", i + 1, line_limit + 1, printable(r.strip()), file)
        if "\0" in r:
            raise NCError("NUL character: this is not program text (a binary file?)", i + 1,
                          r.index("\0") + 1, printable(r.strip()), file)
        # trailing blanks (a blanked comment) are cut: no scan ever walks them
        s = (clean(r) if ("(" in r or ";" in r) else r.upper()).rstrip()
        if s == r:
            s = r  # one string for the raw and the cleaned line (memory of long programs)
        if not s:
            continue
        h, num = _header(s) if (s.lstrip()[:1] in ("%", "O")) else (False, None)
        lineno.append(i + 1)
        stext.append(s)
        if h:
            kind.append(HDR)
            number.append(num)
            continue
        number.append(None)
        k = _control(s)
        kind.append(k if k is not None else OTHER)
    # programs
    set_spans(src, [i for i in range(len(kind)) if kind[i] == HDR])
    spans = src.spans
    # IF / WHILE structure per program
    bad = src.bad
    for a, b in spans:
        stack: list[tuple[str, int, Optional[int]]] = []  # (kind, stmt, else stmt)
        for i in range(a, b):
            k = kind[i]
            if k is OTHER:
                continue
            if k == IF or k == WHILE:
                stack.append((k, i, None))
            elif k == ELSE:
                if not stack or stack[-1][0] != IF or stack[-1][2] is not None:
                    bad[i] = "ELSE without IF"
                    continue
                stack[-1] = (IF, stack[-1][1], i)
            elif k == ENDIF:
                if not stack or stack[-1][0] != IF:
                    bad[i] = "ENDIF without IF"
                    continue
                _, s0, el = stack.pop()
                if el is None:
                    src.jump[s0] = i + 1
                else:
                    src.jump[s0] = el + 1
                    src.jump[el] = i + 1
            elif k == ENDW:
                if not stack or stack[-1][0] != WHILE:
                    bad[i] = "ENDW without WHILE"
                    continue
                _, s0, _ = stack.pop()
                src.jump[s0] = i + 1
                src.jump[i] = s0
        for k, s0, el in stack:
            bad[s0] = (f"{'IF' if k == IF else 'WHILE'} is never closed by "
                       f"{'ENDIF' if k == IF else 'ENDW'} before the end of the program")
            if el is not None:
                bad[el] = "ELSE of an IF that is never closed by ENDIF"
    return src


# --------------------------------------------------------------------------------------------
# statements
# --------------------------------------------------------------------------------------------

@dataclass
class Parsed:
    """One parsed statement. ``kind`` is ``block``, ``assign``, ``if``, ``while``, ``else``,
    ``endif``, ``endw``, ``goto`` or ``ifthen``. Blocks have ``words``
    [(letter, float | Expr, col)]; assignments ``assigns`` [(target: int | Expr, value: Expr,
    col)]; IF/WHILE/IFTHEN ``cond`` (a GOTO's is None when unconditional, a bare ``DO`` loop's
    too); a GOTO the block number it jumps to as ``target``; an assignment to a macro alarm
    variable the comment text of its block as ``message``."""
    kind: str
    n: Optional[int] = None
    words: list = field(default_factory=list)
    assigns: list = field(default_factory=list)
    cond: Optional[Expr] = None
    target: Optional[Expr] = None
    message: str = ""


def fast_words(text: str, scan=FAST_SCAN.findall) -> Optional[list[tuple[str, str, str]]]:
    """Words of a plain block (letters and signed numbers only) as ``(letter, number, "")``
    triples, or None when the line is anything else (one regex pass: the hot path of loading).
    ``scan``: a dialect's scanner of plain-block words (a non-empty third item marks what it
    cannot read)."""
    fw = scan(text)
    if not fw:
        return None
    for w in fw:
        if w[2]:
            return None
    return fw


def word_col(text: str, letter: str, value: Optional[float] = None) -> int:
    """1-based column of the first word ``letter`` in a cleaned line (0 if absent); with
    ``value``, of the first such word whose written number equals it (else the first one)."""
    first = 0
    try:
        toks = tokenize(text)
    except NCError:
        return 0
    for i, (kind, val, col) in enumerate(toks):
        if kind == "addr" and val == letter:
            if value is None:
                return col
            first = first or col
            j = i + 1
            neg = False
            if j < len(toks) and toks[j][0] == "op" and toks[j][1] in "+-":
                neg = toks[j][1] == "-"
                j += 1
            if j < len(toks) and toks[j][0] == "num":
                v = float(toks[j][1])
                if (-v if neg else v) == value:
                    return col
    return first


class _P:
    #: compiles an expression node of this dialect (HNC-21T: functions in radians)
    expr_type = Expr
    #: the keyword operators of the lowest level (FANUC adds XOR) and of the multiplicative
    #: level (FANUC: MOD)
    or_ops: tuple = ("OR",)
    mul_kw: tuple = ()

    def __init__(self, toks, text, line, file, block):
        self.t = toks
        self.i = 0
        self.text = text
        self.line = line
        self.file = file
        self.block = block

    def assign_target(self, idx, col: int):
        """The target of ``#idx = …``: its number when constant (checked when written), else
        the compiled index expression."""
        cv = constant_value(idx)
        return cv if cv is not None else Expr(idx, col)

    def err(self, msg: str, col: Optional[int] = None) -> NCError:
        if col is None:
            col = self.t[self.i][2] if self.i < len(self.t) else len(self.text.rstrip()) + 1
        return NCError(msg, self.line, col, self.block, self.file)

    def peek(self):
        return self.t[self.i] if self.i < len(self.t) else (None, None, 0)

    def take(self):
        tok = self.peek()
        self.i += 1
        return tok

    def expect_op(self, op: str, what: str):
        k, v, c = self.peek()
        if k != "op" or v != op:
            found = "the end of the block" if k is None else repr(v)
            raise self.err(f"bad expression: expected {op!r} {what}, found {found}")
        self.i += 1

    def arguments(self, name: str, open_: str = "[", close: str = "]") -> list:
        """A function's comma-separated arguments in its brackets (its name is taken)."""
        self.expect_op(open_, f"after {name}")
        args = [self.expr()]
        while self.peek()[:2] == ("op", ","):
            self.i += 1
            args.append(self.expr())
        self.expect_op(close, f"to close {name}{open_}")
        return args

    # expression grammar ---------------------------------------------------------------
    def expr(self):
        a = self.and_()
        while True:
            k, v, _ = self.peek()
            if k == "kw" and v in self.or_ops:
                self.i += 1
                a = ("bin", v, a, self.and_())
            else:
                return a

    def and_(self):
        a = self.not_()
        while self.peek()[:2] == ("kw", "AND"):
            self.i += 1
            a = ("bin", "AND", a, self.not_())
        return a

    def not_(self):
        if self.peek()[:2] == ("kw", "NOT"):
            self.i += 1
            return ("not", self.not_())
        return self.cmp()

    def cmp(self):
        a = self.add()
        k, v, _ = self.peek()
        if k == "kw" and v in ("EQ", "NE", "GT", "GE", "LT", "LE"):
            self.i += 1
            a = ("bin", v, a, self.add())
        return a

    def add(self):
        a = self.mul()
        while True:
            k, v, _ = self.peek()
            if k == "op" and v in ("+", "-"):
                self.i += 1
                a = ("bin", v, a, self.mul())
            else:
                return a

    def mul(self):
        a = self.unary()
        while True:
            k, v, _ = self.peek()
            if (k == "op" and v in ("*", "/")) or (k == "kw" and v in self.mul_kw):
                self.i += 1
                a = ("bin", v, a, self.unary())
            else:
                return a

    def unary(self):
        k, v, _ = self.peek()
        if k == "op" and v in ("+", "-"):
            self.i += 1
            a = self.unary()
            return ("neg", a) if v == "-" else a
        return self.primary()

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
            self.i += 1
            e = self.expr()
            self.expect_op("]", "to close '['")
            return e
        if k == "kw":
            if v in ("PI", "TRUE", "FALSE"):
                self.i += 1
                return ("num", {"PI": repr(3.141592653589793), "TRUE": "1", "FALSE": "0"}[v])
            if v in FUNCTIONS:
                self.i += 1
                args = self.arguments(v)
                if len(args) > 2 or (len(args) == 2 and v not in ("ATAN", "ATAN2")):
                    raise self.err(f"bad expression: {v} takes {'one or two' if v == 'ATAN' else 'one'} "
                                   f"argument{'s' if v == 'ATAN' else ''}", c)
                return ("call", v, args)
            if v == "AR":
                self.i += 1
                self.expect_op("[", "after AR")
                k2, v2, _ = self.peek()
                if not (k2 == "op" and v2 == "#"):
                    raise self.err("bad expression: AR[] takes a variable, as in AR[#8]")
                self.i += 1
                idx = self.var_index()
                self.expect_op("]", "to close AR[")
                return ("ar", idx)
        found = "the end of the block" if k is None else repr(v)
        raise self.err(f"bad expression: expected a number, variable, function or '[', found {found}")

    def _finite(self, text: str, col: int) -> None:
        if not math.isfinite(float(text)):
            raise self.err(f"value out of range: a number of {len(text)} characters is too large", col)

    def var_index(self):
        """What follows ``#``: a number, a bracketed expression or another variable."""
        k, v, c = self.peek()
        if k == "num":
            self._finite(v, c)
            self.i += 1
            return ("num", v)
        if k == "op" and v == "[":
            self.i += 1
            e = self.expr()
            self.expect_op("]", "to close #[")
            return e
        if k == "op" and v == "#":
            self.i += 1
            return ("var", self.var_index())
        if k == "op" and v == "-":
            raise self.err("invalid variable: a variable number cannot be negative")
        found = "the end of the block" if k is None else repr(v)
        raise self.err(f"bad expression: expected a variable number after '#', found {found}")

    # statements -----------------------------------------------------------------------
    def value(self, letter: str, col: int):
        """The value of word ``letter``: signed number, [expr], #var, -#var, -[expr]."""
        sign = 1.0
        k, v, c = self.peek()
        neg = False
        if k == "op" and v in ("+", "-"):
            self.i += 1
            neg = v == "-"
            k, v, c = self.peek()
        if k == "num":
            self.i += 1
            return -float(v) if neg else float(v)
        if k == "op" and v in ("[", "#"):
            node = self.primary()
            if neg:
                node = ("neg", node)
            cv = constant_value(node)
            if cv is not None:
                return cv * sign
            return Expr(node, c)
        found = "the end of the block" if k is None else repr(v)
        raise self.err(f"word {letter} has no value: expected a number or [expression], found {found}",
                       col)


def _assignments(p: _P) -> list:
    """``#n = expr`` (one or more) up to the end of the line: ``(target, value, col)`` with the
    target a number or an expression; ``p.expr_type`` compiles the expressions (the dialect's
    functions) and ``p.assign_target`` may refuse a constant target."""
    assigns = []
    make = p.expr_type
    while p.peek()[0] is not None:
        k, v, c = p.peek()
        if not (k == "op" and v == "#"):
            raise p.err(f"bad expression: expected '#' to start an assignment, found {v!r}")
        p.i += 1
        idx = p.var_index()
        p.expect_op("=", "in the assignment")
        if p.peek()[0] is None:
            raise p.err("bad expression: nothing after '='")
        ecol = p.peek()[2]
        val = p.expr()
        assigns.append((p.assign_target(idx, c), make(val, ecol), c))
    return assigns


def parse_statement(text: str, line: int, file: str = "<program>", block: str | None = None,
                    parse=None) -> Parsed:
    """Parse one cleaned line (not a header); ``parse(text, line, file, block)``: a dialect's
    statement parser (default the HNC-21T's). An expression nested too deeply for Python is an
    alarm at its line."""
    blk = block if block is not None else text.strip()
    try:
        return (parse or _parse_statement)(text, line, file, blk)
    except (RecursionError, MemoryError, SyntaxError):
        raise NCError("bad expression: nested too deeply", line, 1, blk, file) from None


def _parse_statement(text: str, line: int, file: str, block: str | None) -> Parsed:
    blk = block if block is not None else text.strip()
    toks = tokenize(text, line, file, blk)
    p = _P(toks, text, line, file, blk)
    n = None
    k, v, c = p.peek()
    if k == "addr" and v == "N" and p.i + 1 < len(toks) and toks[p.i + 1][0] == "num":
        p.i += 1
        nt = p.take()[1]
        nv = float(nt) if len(nt) <= 20 else float("inf")
        if not nv.is_integer() or nv > 4294967295:
            raise p.err("value out of range: N must be an integer 0-4294967295", c)
        n = int(nv)
        k, v, c = p.peek()
    if k == "kw" and v in _CONTROL:
        p.i += 1
        kind = _CONTROL[v]
        if kind in (IF, WHILE):
            if p.peek()[0] is None:
                raise p.err(f"bad expression: {v} needs a condition")
            col = p.peek()[2]
            cond = p.expr()
            tail: list = []
            if kind == IF and p.peek()[:2] == ("op", "#"):
                # "IF cond #n=expr" (as the appendix macros are printed): the assignments
                # are the first statements of the IF body
                tail = _assignments(p)
            elif p.peek()[0] is not None:
                raise p.err(f"bad expression: unexpected {p.peek()[1]!r} after the {v} condition")
            return Parsed(kind, n, cond=Expr(cond, col), assigns=tail)
        if p.peek()[0] is not None:
            raise p.err(f"unexpected {p.peek()[1]!r} after {v}")
        return Parsed(kind, n)
    if k == "op" and v == "#":
        return Parsed("assign", n, assigns=_assignments(p))
    words = []
    if n is not None:
        words.append(("N", float(n), 0))
    while p.peek()[0] is not None:
        k, v, c = p.take()
        if k != "addr":
            if k == "kw":
                raise p.err(f"{v} is not allowed here (a keyword inside a block)", c)
            if k == "op" and v == "#":
                raise p.err("an assignment cannot follow words in the same block", c)
            raise p.err(f"unexpected {v!r}: expected an address letter", c)
        words.append((v, p.value(v, c), c))
    return Parsed("block", n, words=words)
