"""The SINUMERIK 802S/802C reader: the text side of ``docs/SIEMENS.md``.

:class:`SiemensSyntax` is the dialect's Syntax object (``load``, ``parse_statement``,
``fast_words``); it fills the statement model of :mod:`hnc_cam.nc.parser` (the same
:class:`~hnc_cam.nc.parser.Source` and :class:`~hnc_cam.nc.parser.Parsed`), so the interpreter
runs 802 programs with the machinery it runs HNC's and FANUC's with.

Framing: a file holds one or more programs, each headed ``%_N_NAME_MPF`` (main program) or
``%_N_NAME_SPF`` (subprogram); a file without a header is one main program. The first MPF
(else the first program) runs. ``;`` starts a comment to the end of the line (``;$PATH=...``
lines included); ``( )`` are brackets of expressions, not comments. ``/`` at the start of a
block is a skip block (left out with the switch on). Lower case is read as upper case.

Words: an address letter and a number (``X10``, ``G1``, ``T1 D1``), an address letter with
``=`` and an expression (``X=R1*2``), the named words ``CR= AR= CHF= RND= IX= KZ= SF= LIMS=
SPOS=`` with a number or an expression. Statements: ``R1=expr`` (several per block, also
with words: the assignments run before the block's words), ``_CNAME="KONTUR1"`` (a string
variable), labels ``NAME:`` at the start of a block, ``GOTOF``/``GOTOB`` with a label or a
block number, ``IF cond GOTOF|GOTOB target``, ``RET``, ``STOPRE``, subprogram calls (a
program name alone in its block, with ``P n`` repeats). Expressions: ``+ - * /``, ``( )``,
``== <> > < >= <=`` and the functions ``SIN COS TAN ASIN ACOS ATAN2 SQRT ABS TRUNC POT
LN EXP`` with angles in degrees; ``R0``-``R299`` are the arithmetic parameters.

The statement model stores R parameter ``Rn`` as variable ``#(n+1)`` (the shared
expression compiler reserves ``#0``); :mod:`.memory` keeps them.
"""
from __future__ import annotations

import re
from typing import Optional

from ...errors import NCError
from ...nc import parser as P
from ...nc.expr import FanucExpr, constant_value
from ...nc.lexer import printable

#: named words (``CR=34``)
NAMED = frozenset({"CR", "AR", "CHF", "RND", "IX", "KZ", "SF", "LIMS", "SPOS"})
FUNCTIONS = frozenset({"SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN2", "SQRT", "ABS", "TRUNC",
                       "POT", "LN", "EXP"})
#: words of the language that are not program names
KEYWORDS = frozenset({"IF", "GOTOF", "GOTOB", "RET", "STOPRE"}) | FUNCTIONS | NAMED
_RELOPS = {"==": "EQ", "<>": "NE", ">": "GT", "<": "LT", ">=": "GE", "<=": "LE"}
#: the largest R parameter a program may write (R250-R299: the cycles' internal parameters)
R_PROGRAM_MAX = 249
R_MAX = 299
#: R parameter n is variable number n + R_BASE of the statement model
R_BASE = 1
N_MAX = 4294967295  # the document gives no limit: as the executor's plain blocks
NAME_MAX = 31
#: a block starting with one of these letters and then no letter is a word, never a call
_ADDRESS_FIRST = frozenset("GXZMFSTD")
_NAME_SECOND = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZ_")

# one token: number | letter run (two or more letters/underscores start a name; a single
# letter is an address) | string | operator
_TOKEN = re.compile(r"\s*+(?:(\d+\.?\d*|\.\d+)|([A-Z_][A-Z_]+[A-Z0-9_]*|_[A-Z0-9_]*)|([A-Z])"
                    r"|(\"[^\"]*\"?)|(==|<>|>=|<=|[-+*/()=<>,:\[\]]|\S))", re.A)
_HEADER = re.compile(r"\s*+%_N_([A-Z0-9_]+)_(MPF|SPF)\s*$", re.A)
_LABEL = re.compile(r"([\s/]*+(?:N\s*+\d+\s*+)?)([A-Z_][A-Z_][A-Z0-9_]*)\s*+:(?!=)", re.A)
_CALL = re.compile(r"\s*+(?:N\s*+(\d+)\s*+)?(L\d{1,7}|[A-Z_][A-Z_][A-Z0-9_]*)(?:\s*+P\s*+(\d{1,9}))?\s*$",
                   re.A)
_RET = re.compile(r"(\s*+(?:N\s*+\d+\s*+)?)RET\s*$", re.A)
_SLASH = re.compile(r"\s*+/[0-9]?", re.A)
_BLOCKNO = re.compile(r"\s*+N\s*+(\d{1,10})(?!\d)", re.A)
#: the plain block: (word, number, "") per address letter (not R, U, W) or named word with a
#: number, ("", "", c) at anything else
FAST_SCAN = re.compile(r"\s*+((?:CHF|CR|AR|RND|IX|KZ|SF|LIMS|SPOS)(?=\s*+=)|[A-QSTVXYZ])\s*+=?\s*+"
                       r"([-+]?(?:\d+\.?\d*|\.\d+))(?![\d.])\s*+|\s*+(.)", re.S | re.A)
_FAST = FAST_SCAN.findall
#: an assignment in a line (an R parameter or a text variable)
_ASSIGN = re.compile(r"(?<![A-Z0-9_])(?:R\s*+\d+|_[A-Z0-9_]*)\s*+=", re.A)
#: kind of a string assignment target in :attr:`Parsed.assigns` (a text variable)
TEXT = "text"


def clean(raw: str) -> str:
    """Upper case; ``;`` and what follows blanked away (not inside a string)."""
    s = raw.upper()
    i = s.find(";")
    if i < 0:
        return s
    q = s.find('"')
    if q < 0 or q > i:
        return s[:i]
    inside = False
    for j, ch in enumerate(s):
        if ch == '"':
            inside = not inside
        elif ch == ";" and not inside:
            return s[:j]
    return s


def tokenize(text: str, line: int = 0, file: str = "<program>", block: Optional[str] = None) -> list:
    """Tokens ``(kind, value, col)``: ``num``, ``addr`` (one letter), ``kw`` (keyword,
    function or named word), ``name`` (a program name or label), ``str``, ``op``."""
    toks = []
    pos = 0
    n = len(text)
    match = _TOKEN.match
    blk = block if block is not None else text
    while pos < n:
        m = match(text, pos)
        if m is None:
            break
        num, word, letter, string, other = m.groups()
        if num is not None:
            toks.append(("num", num, m.start(1) + 1))
        elif word is not None:
            col = m.start(2) + 1
            toks.append(("kw" if word in KEYWORDS else "name", word, col))
        elif letter is not None:
            toks.append(("addr", letter, m.start(3) + 1))
        elif string is not None:
            col = m.start(4) + 1
            if len(string) < 2 or not string.endswith('"'):
                raise NCError("a string is not closed by '\"'", line, col, blk, file)
            toks.append(("str", string[1:-1], col))
        elif other is not None:
            col = m.start(5) + 1
            if other not in ("==", "<>", ">=", "<=") and other not in "-+*/()=<>,:[]":
                raise NCError(f"unexpected character {printable(other)!r}", line, col, blk, file)
            toks.append(("op", other, col))
        pos = m.end()
    return toks


def word_col(text: str, letter: str, value: Optional[float] = None) -> int:
    """1-based column of the first word ``letter`` (an address or a named word) in a cleaned
    line (0 if absent); with ``value``, of the first such word written with that number."""
    try:
        toks = tokenize(text)
    except NCError:
        return 0
    first = 0
    for i, (kind, val, col) in enumerate(toks):
        if kind in ("addr", "kw") and val == letter:
            if value is None:
                return col
            first = first or col
            j = i + 1
            if j < len(toks) and toks[j][:2] == ("op", "="):
                j += 1
            neg = False
            if j < len(toks) and toks[j][0] == "op" and toks[j][1] in "+-":
                neg = toks[j][1] == "-"
                j += 1
            if j < len(toks) and toks[j][0] == "num" and (-1 if neg else 1) * float(toks[j][1]) == value:
                return col
    return first


class LabelRef:
    """The target of ``GOTOF``/``GOTOB``: a label name or ``N`` + block number, the search
    direction (``"F"`` forward, ``"B"`` backward) and the column of the target."""
    __slots__ = ("name", "direction", "col")

    def __init__(self, name: str, direction: str, col: int):
        self.name = name
        self.direction = direction
        self.col = col


class _SP(P._P):
    """The 802 statement parser over the shared token cursor."""

    expr_type = FanucExpr

    def err(self, msg: str, col: Optional[int] = None) -> NCError:
        if col is None:
            col = self.t[self.i][2] if self.i < len(self.t) else len(self.text.rstrip()) + 1
        return NCError(msg, self.line, col, self.block, self.file)

    # expressions ---------------------------------------------------------------------------
    def expr(self):
        a = self.add()
        k, v, _ = self.peek()
        if k == "op" and v in _RELOPS:
            self.i += 1
            a = ("bin", _RELOPS[v], a, self.add())
        return a

    def primary(self):
        k, v, c = self.peek()
        if k == "num":
            self._finite(v, c)
            self.i += 1
            return ("num", v)
        if k == "addr" and v == "R":
            self.i += 1
            return ("var", ("num", str(self.r_number(c))))
        if k == "op" and v == "(":
            self.i += 1
            self.depth = getattr(self, "depth", 0) + 1
            if self.depth > 20:
                raise self.err("bad expression: brackets nested more than 20 deep", c)
            e = self.expr()
            self.expect_op(")", "to close '('")
            self.depth -= 1
            return e
        if k == "kw" and v in FUNCTIONS:
            self.i += 1
            args = self.arguments(v, "(", ")")
            want = 2 if v == "ATAN2" else 1
            if len(args) != want:
                raise self.err(f"bad expression: {v} takes {want} argument{'s' if want > 1 else ''}", c)
            return _function(v, args)
        found = "the end of the block" if k is None else repr(v)
        raise self.err(f"bad expression: expected a number, R parameter, function or '(', found {found}")

    def r_number(self, col: int) -> int:
        """The number after ``R`` (the ``R`` is taken): R0-R299; returns the variable number."""
        k, v, c = self.peek()
        if k != "num" or not v.isdigit():
            raise self.err("R needs its parameter number, as R1 (R0-R249)", col)
        self.i += 1
        n = int(v) if len(v) <= 6 else R_MAX + 1
        if n > R_MAX:
            raise self.err(f"R{n}: the arithmetic parameters are R0-R249 (R250-R299 belong to the "
                           f"cycles)", col)
        return n + R_BASE

    def value(self, letter: str, col: int):
        """A word's value: a signed number, or after ``=`` an expression."""
        k, v, c = self.peek()
        if k == "op" and v == "=":
            self.i += 1
            if self.peek()[0] is None:
                raise self.err(f"word {letter}= has no value")
            ecol = self.peek()[2]
            node = self.expr()
            cv = constant_value(node)
            return cv if cv is not None else FanucExpr(node, ecol)
        neg = False
        if k == "op" and v in ("+", "-"):
            self.i += 1
            neg = v == "-"
            k, v, c = self.peek()
        if k == "num":
            self._finite(v, c)
            self.i += 1
            f = float(v)
            return -f if neg else f
        found = "the end of the block" if k is None else repr(v)
        raise self.err(f"word {letter} has no value: expected a number (or {letter}=expression), "
                       f"found {found}", col)

    # statements ----------------------------------------------------------------------------
    def items(self) -> tuple[list, list]:
        """Words and assignments of a block, each with the span of columns it covers:
        ([(letter, value, col, end)], [(target, value, col, end)])."""
        words: list = []
        assigns: list = []
        while self.peek()[0] is not None:
            k, v, c = self.take()
            if k == "addr" and v == "R" and self.peek()[0] == "num":
                target = self.r_number(c)
                if target - R_BASE > R_PROGRAM_MAX:
                    raise self.err(f"R{target - R_BASE}: a program writes R0-R249 (R250-R299 are "
                                   f"the cycles' internal parameters)", c)
                self.expect_op("=", f"after R{target - R_BASE} (an assignment R{target - R_BASE}=...)")
                if self.peek()[0] is None:
                    raise self.err("bad expression: nothing after '='")
                ecol = self.peek()[2]
                val = self.expr()
                assigns.append((target, FanucExpr(val, ecol), c, self._end()))
                continue
            if k == "name" and v.startswith("_"):
                self.expect_op("=", f"after {v} (a string assignment {v}=\"...\")")
                k2, v2, c2 = self.take()
                if k2 != "str":
                    raise self.err(f"{v} takes a string, as {v}=\"KONTUR1\"", c2 or None)
                assigns.append(((TEXT, v), v2, c, self._end()))
                continue
            if k == "kw" and v in NAMED:
                if self.peek()[:2] != ("op", "="):
                    raise self.err(f"{v} is written {v}=value", c)
                words.append((v, self.value(v, c), c, self._end()))
                continue
            if k == "addr":
                if v in ("N",):
                    raise self.err("N (block number) stands at the start of the block", c)
                words.append((v, self.value(v, c), c, self._end()))
                continue
            if k == "kw":
                if v == "STOPRE":
                    continue
                raise self.err(f"{v} is not allowed here", c)
            if k == "name":
                raise self.err(f"unknown word {v!r} (a subprogram call stands alone in its block, "
                               f"with P repeats)", c)
            raise self.err(f"unexpected {v!r}: expected an address letter", c)
        return words, assigns

    def _end(self) -> int:
        """The column after the last token taken."""
        if self.i < len(self.t):
            return self.t[self.i][2]
        return len(self.text) + 1


def _function(name: str, args: list) -> tuple:
    """A function call as nodes of the shared (degrees) expression compiler."""
    if name == "TRUNC":
        return ("call", "FIX", args)
    if name == "POT":
        return ("bin", "*", args[0], args[0])
    if name == "ATAN2":
        # the shared ATAN(a, b) is 0..360; ATAN2 is -180..180
        at = ("call", "ATAN", args)
        return ("bin", "-", at, ("bin", "*", ("num", "360"), ("bin", "GT", at, ("num", "180"))))
    return ("call", name, args)


def _is_jump(text: str) -> bool:
    """A statement whose first word (after N) is IF, GOTOF or GOTOB (not a string holding the
    letters GOTO)."""
    try:
        toks = tokenize(text)
    except NCError:
        return False  # the statement alarms when it is parsed
    i = 2 if len(toks) >= 2 and toks[0][:2] == ("addr", "N") and toks[1][0] == "num" else 0
    return i < len(toks) and toks[i][0] == "kw" and toks[i][1] in ("IF", "GOTOF", "GOTOB")


class SiemensSource(P.Source):
    """A loaded 802 file: the statement model plus the labels (name -> statements, in
    order), the subprogram calls (statement -> (name, col, repeats)) and program names."""

    def __init__(self, file: str, lines: list):
        super().__init__(file=file, lines=lines)
        self.labels: dict[str, list[int]] = {}
        self.calls: dict[int, tuple[str, int, int]] = {}
        self.names: list[Optional[str]] = []  # per span: the program's name (None: no header)
        self.parts: list[tuple[int, str]] = []  # (line offset, file) of attached subprogram files
        self._nums: Optional[dict[str, list[int]]] = None

    def attach(self, path: str, name: str, syntax: "SiemensSyntax", line_limit: int, max_bytes: int,
               line: int, col: int) -> int:
        """Append the subprogram file ``path`` (one program, its header optional) to the
        statements; its lines are numbered after the ones before (:attr:`parts` maps them back
        to its file). Returns its first statement."""
        try:
            with open(path, "rb") as f:
                data = f.read(max_bytes + 1)
        except OSError as e:
            raise NCError(f"subprogram {name}: cannot read {path}: {e.strerror or e}", line, col,
                          self.block_text(line), self.file) from None
        if len(data) > max_bytes:
            raise NCError(f"subprogram {name}: {path} is larger than the machine's limit of "
                          f"{max_bytes} bytes", line, col, self.block_text(line), self.file)
        try:
            sub = syntax.load(data.decode("utf-8", errors="replace"), path, line_limit)
        except NCError as e:
            raise NCError(e.message, e.line, e.col, e.block, path) from None
        off = len(self.lines)
        base = len(self.kind)
        self.parts.append((off, path))
        self.lines.extend(sub.lines)
        a, e = sub.main
        self.lineno.extend(n + off for n in sub.lineno)
        self.text.extend(sub.text)
        self.kind.extend(sub.kind)
        self.number.extend(sub.number)
        for i, m in sub.bad.items():
            self.bad[i + base] = m
        for k, lst in sub.labels.items():
            self.labels.setdefault(k, []).extend(i + base for i in lst)
        for i, c in sub.calls.items():
            self.calls[i + base] = c
        for i, j in sub.jump.items():
            self.jump[i + base] = j + base
        self.spans.append((a + base, e + base))
        self.names.append(name)
        self.programs[name] = a + base
        self._nums = None
        self._labels = None
        return a + base

    def locate(self, line: int) -> tuple[str, int]:
        """The file and its own line number of a line of :attr:`lines`."""
        for off, path in reversed(self.parts):
            if line > off:
                return path, line - off
        return self.file, line

    def alarm(self, message: str, stmt: int, col: int = 0) -> NCError:
        line = self.lineno[stmt] if 0 <= stmt < len(self.lineno) else 0
        f, n = self.locate(line)
        return NCError(message, n, col, self.block_text(line), f)

    def find(self, target: str, span: tuple[int, int], at: int, direction: str) -> Optional[int]:
        """The statement of label or block number ``target`` in ``span``: forward (the first
        after statement ``at``) or backward (the last at or before it)."""
        if target.startswith("N") and target[1:].isdigit():
            if self._nums is None:
                nums: dict[str, list[int]] = {}
                for i, t in enumerate(self.text):
                    m = _BLOCKNO.match(t)
                    if m is not None:
                        nums.setdefault(f"N{int(m.group(1))}", []).append(i)
                self._nums = nums
            found = self._nums.get(f"N{int(target[1:])}", [])
        else:
            found = self.labels.get(target, [])
        a, b = span
        if direction == "F":
            for i in found:
                if at < i < b:
                    return i
            return None
        for i in reversed(found):
            if a <= i <= at:
                return i
        return None


class SiemensSyntax:
    """The 802 reader (``load``, ``parse_statement``, ``fast_words``)."""

    def __init__(self, calculator: bool = False, block_delete: bool = False):
        self.block_delete = block_delete

    def load(self, text: str, file: str = "<program>", line_limit: Optional[int] = None) -> SiemensSource:
        raw = P.split_lines(text)
        src = SiemensSource(file, raw)
        lineno, stext, kind, number = src.lineno, src.text, src.kind, src.number
        headers: list[tuple[int, str, str]] = []  # (statement, name, MPF|SPF)
        pending: list[tuple[str, int]] = []  # labels waiting for their statement
        bdel = self.block_delete
        for i, r in enumerate(raw):
            if line_limit is not None and len(r) > line_limit:
                raise NCError(f"line too long: {len(r)} characters (the machine's limit is {line_limit}, "
                              f"[limits] line_chars)", i + 1, line_limit + 1, printable(r.strip()), file)
            if "\0" in r:
                raise NCError("NUL character: this is not program text (a binary file?)", i + 1,
                              r.index("\0") + 1, printable(r.strip()), file)
            s = clean(r).rstrip()
            if not s.strip():
                continue
            c0 = s.lstrip()[:1]
            if c0 == "%":
                m = _HEADER.match(s)
                if m is None:
                    raise NCError("a program header is %_N_NAME_MPF (main program) or %_N_NAME_SPF "
                                  "(subprogram) alone on its line", i + 1, s.index("%") + 1,
                                  printable(r.strip()), file)
                for name, _ in pending:
                    src.labels.setdefault(name, []).append(len(kind))
                pending = []
                headers.append((len(kind), m.group(1), m.group(2)))
                lineno.append(i + 1)
                stext.append(s)
                kind.append(P.HDR)
                number.append(None)
                continue
            if c0 == "/":
                if bdel:
                    continue
                m = _SLASH.match(s)
                s = " " * m.end() + s[m.end():]
                if not s.strip():
                    continue
            if ":" in s:
                m = _LABEL.match(s)
                if m is not None:
                    name = m.group(2)
                    if name in KEYWORDS:
                        raise NCError(f"{name} is a word of the language, not a label", i + 1,
                                      m.start(2) + 1, printable(r.strip()), file)
                    pending.append((name, i + 1))
                    s = m.group(1) + " " * (m.end() - m.end(1)) + s[m.end():]
                    if not s.strip() or _BLOCKNO.fullmatch(s.rstrip()):
                        # a label alone (or with its block number) marks the next statement
                        continue
            for name, _ in pending:
                src.labels.setdefault(name, []).append(len(kind))
            pending = []
            if "RET" in s:
                m = _RET.match(s)
                if m is not None:
                    s = m.group(1) + "M17"
            if "=" in s and "GOTO" not in s and _ASSIGN.search(s):
                parts = self._split(s, i + 1, file, printable(r.strip()))
            else:
                parts = (s,)
            for part in parts:
                lineno.append(i + 1)
                stext.append(part)
                number.append(None)
                k = P.OTHER
                if "GOTO" in part and _is_jump(part):
                    k = P.GOTO
                elif "=" not in part and (part.lstrip()[:1] not in _ADDRESS_FIRST
                                          or part.lstrip()[1:2] in _NAME_SECOND):
                    m = _CALL.match(part)
                    if m is not None and m.group(2) not in KEYWORDS:
                        name = m.group(2)
                        if len(name) > NAME_MAX:
                            raise NCError(f"program name {name} is longer than {NAME_MAX} characters",
                                          i + 1, m.start(2) + 1, printable(r.strip()), file)
                        src.calls[len(kind)] = (name, m.start(2) + 1,
                                                int(m.group(3)) if m.group(3) is not None else 1)
                kind.append(k)
        for name, _ in pending:
            src.labels.setdefault(name, []).append(len(kind))
        self._frame(src, headers)
        return src

    def _split(self, s: str, line: int, file: str, blk: str) -> tuple:
        """A line with assignments and words: the assignments' statement first, then the
        words' (each keeps the line's columns; the other part blanked)."""
        try:
            toks = tokenize(s, line, file, blk)
        except NCError:
            return (s,)  # the statement alarms when it runs
        p = _SP(toks, s, line, file, blk)
        n_end = 0
        if len(toks) >= 2 and toks[0][:2] == ("addr", "N") and toks[1][0] == "num":
            p.i = 2
            n_end = p._end() - 1
        try:
            words, assigns = p.items()
        except NCError:
            return (s,)
        if not words or not assigns:
            return (s,)
        a_text = list(" " * len(s))
        w_text = list(s)
        for _, _, c, e in assigns:
            a_text[c - 1:e - 1] = s[c - 1:e - 1]
            w_text[c - 1:e - 1] = " " * (e - c)
        a_text[:n_end] = s[:n_end]
        return ("".join(a_text).rstrip(), "".join(w_text).rstrip())

    @staticmethod
    def _frame(src: SiemensSource, headers: list) -> None:
        n = len(src.kind)
        spans: list[tuple[int, int]] = []
        names: list[Optional[str]] = []
        if not headers:
            spans.append((0, n))
            names.append(None)
        elif headers[0][0] > 0:
            i = 0
            raise src.alarm("a block before the first program header %_N_NAME_MPF", i, 1)
        main = None
        for j, (i, name, typ) in enumerate(headers):
            end = headers[j + 1][0] if j + 1 < len(headers) else n
            spans.append((i + 1, end))
            names.append(name)
            if name in src.programs:
                raise src.alarm(f"program {name} is defined twice in this file", i, 1)
            src.programs[name] = i + 1
            if typ == "MPF" and main is None:
                main = (i + 1, end)
        src.spans = spans
        src.names = names
        src.main = main if main is not None else (spans[0] if spans else (0, 0))

    # -- statements ------------------------------------------------------------------------
    def fast_words(self, text: str) -> Optional[list]:
        """``(word, number, "")`` per word of a plain block (letters but R, U and W, and named
        words written ``CR=5``), None for anything else."""
        return P.fast_words(text, _FAST)

    def parse_statement(self, text: str, line: int, file: str = "<program>",
                        block: Optional[str] = None) -> P.Parsed:
        return P.parse_statement(text, line, file, block, self._parse)

    def _parse(self, text: str, line: int, file: str, blk: str) -> P.Parsed:
        toks = tokenize(text, line, file, blk)
        p = _SP(toks, text, line, file, blk)
        n = None
        k, v, c = p.peek()
        if k == "addr" and v == "N" and len(toks) > 1 and toks[1][0] == "num":
            p.i += 1
            nt = p.take()[1]
            if "." in nt or len(nt) > 10 or int(nt) > N_MAX:
                raise p.err(f"value out of range: N{nt}: a block number is a whole number 0-{N_MAX}", c)
            n = int(nt)
            k, v, c = p.peek()
        if k == "kw" and v in ("IF", "GOTOF", "GOTOB"):
            return self._jump(p, n, v, c)
        words, assigns = p.items()
        if assigns and not words:
            return P.Parsed("assign", n, assigns=[(t, val, col) for t, val, col, _ in assigns])
        if assigns:  # pragma: no cover - load splits such lines
            raise p.err("assignments and words in one statement")
        out = [("N", float(n), 0)] if n is not None else []
        out += [(L, val, col) for L, val, col, _ in words]
        return P.Parsed("block", n, words=out)

    @staticmethod
    def _jump(p: _SP, n: Optional[int], v: str, c: int) -> P.Parsed:
        p.i += 1
        cond = None
        if v == "IF":
            if p.peek()[0] is None:
                raise p.err("IF needs a condition, as IF R1>5 GOTOF LABEL")
            ccol = p.peek()[2]
            cond = FanucExpr(p.expr(), ccol)
            k2, v2, c2 = p.peek()
            if (k2, v2) not in (("kw", "GOTOF"), ("kw", "GOTOB")):
                found = "the end of the block" if k2 is None else repr(v2)
                raise p.err(f"IF cond must be followed by GOTOF or GOTOB and a label, found {found}")
            p.i += 1
            v = v2
        k, t, tc = p.peek()
        if k == "name":
            target = t
            p.i += 1
        elif k == "addr" and t == "N" and p.i + 1 < len(p.t) and p.t[p.i + 1][0] == "num" \
                and p.t[p.i + 1][1].isdigit() and len(p.t[p.i + 1][1]) <= 10:
            target = f"N{int(p.t[p.i + 1][1])}"
            p.i += 2
        else:
            found = "the end of the block" if k is None else repr(t)
            raise p.err(f"{v} needs a label or a block number, as {v} MARKE1 or {v} N100, found {found}")
        if p.peek()[0] is not None:
            raise p.err(f"unexpected {p.peek()[1]!r} after the {v} target")
        return P.Parsed(P.GOTO, n, cond=cond, target=LabelRef(target, v[-1], tc))
