"""Lexer of HNC-21/22T program text.

The controller reads a program line by line; one line is one block (or one macro statement).
This module does the character-level work:

* :func:`clean` upper-cases a line and blanks its comments: ``( ... )`` and ``;`` to the end
  of the line. Blanking (not deleting) keeps the 1-based columns of the words for alarms.
  An unclosed ``(`` comments out the rest of the line (the controller reads to the end of
  the block).
* :func:`tokenize` splits a cleaned line into tokens ``(kind, value, col)``:
  ``num`` (unsigned number text), ``addr`` (a single address letter such as ``X``),
  ``kw`` (a multi-letter keyword: ``IF WHILE EQ SIN PI AR ...``) and ``op``
  (one of ``# [ ] = + - * / ,``). Words may be written without spaces
  (``N6X28.04Z18.5C2P180F3``, ``WHILE #10LE16``): a run of letters of length one is an
  address, a longer run must be a keyword.
* :data:`FAST_SCAN` recognises the plain block (letters followed by signed numbers only),
  which is by far the commonest line, in one regex pass; the parser takes a tokenizer-free
  path for it.
"""
from __future__ import annotations

import re

from ..errors import NCError

#: multi-letter keywords of the macro language (manual §3.4)
KEYWORDS = frozenset({
    "IF", "ELSE", "ENDIF", "WHILE", "ENDW",
    "EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR", "NOT",
    "SIN", "COS", "TAN", "ATAN", "ATAN2", "ABS", "INT", "SIGN", "SQRT", "EXP",
    "PI", "TRUE", "FALSE", "AR",
})
FUNCTIONS = frozenset({"SIN", "COS", "TAN", "ATAN", "ATAN2", "ABS", "INT", "SIGN", "SQRT", "EXP"})
OPERATORS = frozenset("#[]=+-*/,")

# blanks are matched possessively (``\s*+``): a long run of blanks (a blanked comment) is
# read once, never re-scanned from each of its positions (linear time in the line length)
_TOKEN = re.compile(r"\s*+(?:(\d+\.?\d*|\.\d+)|([A-Z]+)|(\S))")
# one pass over a line: (letter, number, "") per word, ("", "", c) for a character that is
# not part of a plain word (so the line is not a plain block)
FAST_SCAN = re.compile(r"\s*+([A-Z])\s*+([-+]?(?:\d+\.?\d*|\.\d+))\s*+|\s*+(.)", re.S)

Token = tuple  # (kind, value, col)


def clean(raw: str, semicolon: bool = True) -> str:
    """Upper-case ``raw`` and replace its comments ``( ... )`` by blanks (columns are kept);
    with ``semicolon`` (the HNC-21T), a ``;`` starts a comment to the end of the line."""
    s = raw.upper()
    if "(" not in s and (not semicolon or ";" not in s):
        return s
    out = []
    depth = False
    for ch in s:
        if depth:
            out.append(" ")
            if ch == ")":
                depth = False
        elif ch == "(":
            depth = True
            out.append(" ")
        elif ch == ";" and semicolon:
            break
        else:
            out.append(ch)
    return "".join(out)


def tokenize(text: str, line: int = 0, file: str = "<program>", block: str | None = None,
             keywords: frozenset = KEYWORDS, abbreviations: dict | None = None,
             token: re.Pattern = _TOKEN, operators: frozenset = OPERATORS) -> list[Token]:
    """Tokens of one cleaned line. Raises :class:`NCError` on a character or letter run
    that is not part of the language. A dialect gives its ``keywords`` (``ATAN 2[`` is read
    as ``ATAN2`` where that is one), the ``abbreviations`` it expands (FANUC ``SI`` for
    ``SIN``), its ``token`` pattern and ``operators``."""
    toks: list[Token] = []
    pos = 0
    n = len(text)
    match = token.match
    while pos < n:
        m = match(text, pos)
        if m is None:  # only trailing blanks
            break
        num, word, other = m.groups()
        if num is not None:
            toks.append(("num", num, m.start(1) + 1))
        elif word is not None:
            col = m.start(2) + 1
            if word == "ATAN" and "ATAN2" in keywords and text.startswith("2", m.end()) and \
                    text[m.end() + 1:].lstrip().startswith("["):
                word = "ATAN2"
                toks.append(("kw", word, col))
                pos = m.end() + 1
                continue
            if len(word) == 1:
                toks.append(("addr", word, col))
            elif word in keywords:
                toks.append(("kw", word, col))
            elif abbreviations and word in abbreviations:
                toks.append(("kw", abbreviations[word], col))
            else:
                raise NCError(f"unknown word {word!r} (not an address letter followed by a value, "
                              f"nor a macro keyword)", line, col, block if block is not None else text, file)
        elif other is not None:
            col = m.start(3) + 1
            if other not in operators:
                raise NCError(f"unexpected character {other!r}", line, col,
                              block if block is not None else text, file)
            toks.append(("op", other, col))
        else:
            break
        pos = m.end()
    return toks


#: characters of a block echoed in an alarm (the rest is cut with "…")
EXCERPT_CHARS = 120


def printable(text: str, limit: int = EXCERPT_CHARS) -> str:
    """``text`` made safe for one terminal line: at most ``limit`` characters of it (then
    "…"), every character that is not printable (control bytes, NUL, ESC, CR, line and
    paragraph separators, ...) written as a Python escape (``\\x1b``, ``\\u2028``)."""
    cut = len(text) > limit
    if cut:
        text = text[:limit]
    if not text.isprintable():
        text = "".join(c if c.isprintable() else ascii(c)[1:-1] for c in text)
    return text + "…" if cut else text
