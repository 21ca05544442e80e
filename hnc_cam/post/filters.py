"""Template filters: they own every formatting decision of the program text.

* ``num``: a number with at most 3 decimals and no trailing noise. Whole numbers follow the
  *number format* option: ``"plain"`` writes ``20`` (as the manual's examples do; the HNC-21T
  reads a word without a decimal point as millimetres), ``"point"`` writes ``20.`` and
  ``"zero"`` writes ``20.0``. ``-0`` is written ``0``.
* ``dia``: a radius value written as a diameter (X words, the G71 X allowance).
* ``progno``: the program number line ``%nnnn`` (4 digits, more when the number needs them).
* ``whole``: a rounded whole number (S, T, counts); ``um``: mm written in micrometres without a
  point (FANUC's G76 P/Q words).
* ``plain``: a number in the plain format whatever the number format option says.
* ``comment``: ``(text)`` with the characters the control cannot take in a comment replaced:
  parentheses become brackets, ``%`` (program start) becomes ``pct``, non-ASCII becomes ``?``.
* ``remark``: ``; text`` (a SINUMERIK comment); ``progname802``: a SINUMERIK program name
  (:func:`program_name`).
* ``label`` / ``ref``: a block that a cycle's P/Q word refers to carries a label, and the
  P/Q words carry a reference; :func:`number_blocks` (applied to the whole program by
  ``program.j2``) turns both into block numbers.

Block numbering (:func:`number_blocks`): ``"every"`` numbers every block N1, N2, ... (comment
lines, blank lines, the ``%`` line and a FANUC ``O`` program number line are not blocks); ``"pq"`` numbers only the blocks that a
P/Q word refers to (N1, N2, ... in program order); ``"none"`` is refused when a P/Q word needs
a number.
"""
from __future__ import annotations

import math
import re

NUMBER_FORMATS = ("plain", "point", "zero")
BLOCK_NUMBERING = ("every", "pq")

_LABEL = "\x01"
_REF = "\x02"


def fmt_num(value: float, style: str = "plain", decimals: int = 3) -> str:
    """Format a number for an address word (see the module docstring)."""
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"cannot write {value!r} in a program")
    s = f"{v:.{decimals}f}"
    if "." in s:
        s = s.rstrip("0")
    if s in ("-0.", "-0", "-."):
        s = "0."
    if s.endswith("."):
        if style == "plain":
            s = s[:-1]
        elif style == "zero":
            s = s + "0"
    if s.startswith("-0") and float(s) == 0:
        s = s[1:]
    return s


def fmt_dia(radius: float, style: str = "plain") -> str:
    return fmt_num(2.0 * float(radius), style)


def whole(value: float) -> str:
    """A whole number (S, T, M, a count), rounded: ``S2865`` for 2864.8."""
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"cannot write {value!r} in a program")
    return str(int(round(v)))


def micrometres(mm: float) -> str:
    """A length in mm written in micrometres without a decimal point (FANUC's G76 P/Q and
    G74/G75 P/Q words): ``1.5`` -> ``1500``."""
    return whole(float(mm) * 1000.0)


def progno(number: int) -> str:
    n = int(number)
    if not 0 <= n <= 99999999:
        raise ValueError(f"program number {number} out of range")
    return f"%{n:04d}"


_BAD = re.compile(r"[^\x20-\x7e]")


def comment(text: object) -> str:
    s = str(text).replace("(", "[").replace(")", "]").replace("%", "pct")
    s = _BAD.sub("?", s.replace("\n", " ").replace("\t", " ")).strip()
    return f"({s})"


def remark(text: object) -> str:
    """A ``;`` comment (SINUMERIK): printable ASCII, on one line."""
    s = _BAD.sub("?", str(text).replace("\n", " ").replace("\t", " ")).strip()
    return f"; {s}" if s else ";"


def program_name(text: object, limit: int = 24) -> str:
    """A SINUMERIK program name from a part's name: upper case letters, digits and
    underscores, the first two characters letters (``PN`` put in front otherwise), at most
    ``limit`` characters (``stepped_shaft`` -> ``STEPPED_SHAFT``)."""
    s = re.sub(r"[^A-Z0-9_]", "_", str(text).upper())
    s = re.sub(r"__+", "_", s).strip("_") or "PART"
    if not (s[:2].isalpha() and s[:2].isascii()):
        s = "PN" + s
    return s[:limit].rstrip("_")


def label(name: str) -> str:
    """Marker for a block that P/Q refer to (resolved by :func:`number_blocks`)."""
    return f"{_LABEL}{name}{_LABEL}"


def ref(name: str) -> str:
    """Marker for a P/Q word's value (resolved by :func:`number_blocks`)."""
    return f"{_REF}{name}{_REF}"


_LABEL_RE = re.compile(f"{_LABEL}([^{_LABEL}]*){_LABEL}")
_REF_RE = re.compile(f"{_REF}([^{_REF}]*){_REF}")


_PROGRAM_NUMBER = re.compile(r"O\d")


def _is_block(line: str) -> bool:
    """A line that gets a block number: not a comment, the ``%`` line or a FANUC program
    number line ``O1234 (NAME)``."""
    s = line.strip()
    return bool(s) and not s.startswith("(") and not s.startswith("%") and not s.startswith(";") \
        and not _PROGRAM_NUMBER.match(s)


def number_blocks(text: str, mode: str = "every", start: int = 1, step: int = 1) -> str:
    """Number the blocks of a rendered program and resolve labels and references.

    Blank lines are dropped, leading spaces of each line stripped.
    """
    if mode not in BLOCK_NUMBERING:
        raise ValueError(f"block numbering must be one of {BLOCK_NUMBERING}, got {mode!r}")
    lines = [ln.strip() for ln in text.splitlines()]
    lines = [ln for ln in lines if ln]
    numbers: dict[str, int] = {}
    out: list[str] = []
    n = start
    for ln in lines:
        labels = _LABEL_RE.findall(ln)
        body = _LABEL_RE.sub("", ln).strip()
        if not _is_block(body):
            if labels:
                raise ValueError(f"label on a line that is not a block: {body!r}")
            out.append(body)
            continue
        if mode == "every" or labels:
            for lb in labels:
                if lb in numbers:
                    raise ValueError(f"label {lb!r} used twice")
                numbers[lb] = n
            body = f"N{n} {body}"
            n += step
        out.append(body)

    def _sub(m: re.Match) -> str:
        name = m.group(1)
        if name not in numbers:
            raise ValueError(f"reference to the unknown block label {name!r}")
        return str(numbers[name])

    return "\n".join(_REF_RE.sub(_sub, ln) for ln in out) + "\n"
