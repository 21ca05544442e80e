"""Controller dialects: a controller is a value, not a branch.

``get(name)`` gives the :class:`Dialect` of a controller (``names()`` lists them); the
interpreter (:func:`hnc_cam.nc.run`), the post and the commands take it by name. A dialect
holds what differs between controllers: the reader (:meth:`Dialect.syntax`), the G/M code
table with each code's modal group, the power-on modal codes, word ranges and the hints for
letters the control does not know, the macro memory map, the call-argument letters, the
cycle table, the CNC's own M codes, feature flags and the template folder of the post.

``sniff(text)`` says which other dialect a program looks like (a hint added to an alarm of
the HNC reader). Nothing heavy is imported here, and a dialect's module is imported only
when it is asked for.
"""
from __future__ import annotations

import importlib
import re
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Optional

DEFAULT = "hnc21t"
_NAMES = ("hnc21t", "fanuc0it", "haas", "siemens802")


@dataclass(frozen=True)
class CodeSpec:
    """One G or M code of a dialect: its modal ``group`` (0 = one-shot), the execution
    ``phase`` inside a block and the executor's ``handler`` (a name the executor resolves,
    or a callable), ``letters`` the extra words the code gives a meaning."""
    code: int
    group: int
    phase: str = "modal"
    handler: Any = None
    #: the extra words the code gives a meaning (arc I K R, G04 P, M99 P); for a one-shot
    #: code None means "the words of the modal motion"
    letters: Optional[frozenset] = frozenset()


#: the phases of a G code in the executor's walk over a block's codes: ``motion`` (the modal
#: motion group), ``nonmodal`` (one-shot), ``cycle`` (a one-block cycle), ``comp`` (nose
#: compensation command), ``wcs`` (work coordinate system), ``modal`` (``handler`` is the
#: ``(attribute, value)`` the code sets), ``flow`` (the CNC's M codes)
PHASES = ("motion", "nonmodal", "cycle", "comp", "wcs", "modal", "flow")


@dataclass(frozen=True)
class Dialect:
    """What a controller is made of (see the module doc). Frozen: one value per controller."""
    name: str
    title: str
    templates: str
    template_fallback: Optional[str]
    syntax_factory: Callable[..., Any]
    #: ("G"|"M", n) -> CodeSpec
    codes: Mapping[tuple, CodeSpec] = field(default_factory=dict)
    #: the power-on modal G codes (group -> code)
    power_on: Mapping[int, int] = field(default_factory=dict)
    #: word letter -> (min, max, integer)
    ranges: Mapping[str, tuple] = field(default_factory=dict)
    #: letters the control does not know -> the hint of the alarm
    unknown_letters: Mapping[str, str] = field(default_factory=dict)
    #: the macro memory map (a dialect-specific object; see the dialect's memory module)
    memory: Any = None
    #: call argument letter -> local variable number (argument specification I for FANUC)
    call_letters: Mapping[str, int] = field(default_factory=dict)
    #: G code -> cycle handler(ctx), loaded on first use (see :meth:`cycle_table`)
    cycles: Optional[Callable[[], Mapping[int, Callable]]] = None
    #: cycles of the modal motion group (later blocks with axis words repeat them)
    cycle_motion: frozenset = frozenset()
    #: the CNC's own M codes (the others are the PLC's: the machine file's [m_codes])
    m_cnc: frozenset = frozenset()
    #: feature flags ("two_block_g71", "decimal_point_input", "macro_b", ...)
    features: frozenset = frozenset()
    #: the interpreter class that executes this dialect (a subclass of nc.interp.Interp)
    executor: Optional[Callable[[], type]] = None
    #: modal groups whose codes may appear twice in one block
    repeatable_groups: frozenset = frozenset()
    #: alarm texts of the shared executor: "unknown_g" (format fields g), "two_in_group" (g, grp)
    messages: Mapping[str, str] = field(default_factory=dict)
    #: the name a generated program is shown by, from its number and the part's name (None:
    #: ``O0001 NAME``, the HNC/FANUC program number)
    program_title: Optional[Callable[[int, str], str]] = None

    def syntax(self, calculator: bool = False, block_delete: bool = False):
        """The reader of this dialect (``load``, ``parse_statement``, ``fast_words``)."""
        return self.syntax_factory(calculator=calculator, block_delete=block_delete)

    def cycle_table(self) -> Mapping[int, Callable]:
        return self.cycles() if self.cycles is not None else {}

    def has(self, feature: str) -> bool:
        return feature in self.features


_CACHE: dict[str, Dialect] = {}


def names() -> tuple[str, ...]:
    """The known dialect names."""
    return _NAMES


def get(name: "str | Dialect") -> Dialect:
    """The dialect called ``name`` (a :class:`Dialect` passes through); an unknown name is a
    ValueError naming the known ones."""
    if isinstance(name, Dialect):
        return name
    d = _CACHE.get(name)
    if d is not None:
        return d
    if not isinstance(name, str) or name not in _NAMES:
        raise ValueError(f"unknown dialect {name!r} (known: {', '.join(_NAMES)})")
    mod = importlib.import_module(f"{__name__}.{name}")
    d = _CACHE[name] = mod.DIALECT
    return d


# ------------------------------------------------------------------------------------------
# sniffing: which dialect a program looks like
# ------------------------------------------------------------------------------------------

_SNIFF_LINES = 5000  # lines looked at (the hint is about the file's shape, not every line)
_FANUC = "looks like a FANUC program ({why}): try --dialect fanuc0it"
_O_HEADER = re.compile(r"\s*O\s*\d{1,5}\b")
_G71 = re.compile(r"G0*7[123](?![0-9.])")
_G71_SECOND = re.compile(r"G\s*0*7[123](?![0-9.])\s*P\s*\d+\s*Q\s*\d+")
_IF_GOTO = re.compile(r"IF\s*\[.*\]\s*GOTO\s*[#\d\[]")
_GOTO = re.compile(r"(?:^|[\s\d\]])GOTO\s*[#\d\[]")
_COMMA_CORNER = re.compile(r"[\d.]\s*,\s*[CR]\s*[-+]?[\d.]")
_DO_END = re.compile(r"\bDO\s*[123]\b")
_SIEMENS = "looks like a SINUMERIK 802 program ({why}): try --dialect siemens802"
_S_HEADER = re.compile(r"%_N_\w+_(?:MPF|SPF)\s*$")
_S_WORDS = ((re.compile(r"(?:^|[\s\d])R\d{1,3}\s*=\s*[-+(\dR.]"), "R parameter assignments Rn="),
            (re.compile(r"\bLCYC\d{2,3}\b"), "an LCYC cycle call"),
            (re.compile(r"\bGOTO[FB]\b"), "GOTOF/GOTOB"),
            (re.compile(r"(?:^|[\s\d])(?:CR|AR|RND|CHF|LIMS)\s*=\s*[-+\d.R]"), "CR=/AR=/RND=/CHF=/LIMS= words"))


def _strip_comment(s: str) -> str:
    i = s.find("(")
    if i >= 0:
        s = s[:i]
    i = s.find(";")
    return s[:i] if i >= 0 else s


def sniff(text: str) -> Optional[str]:
    """A hint when ``text`` looks like a program of another dialect than HNC-21T
    (``"looks like a FANUC program (% then O1234): try --dialect fanuc0it"``), else None.
    Looks at the first lines only; never raises."""
    try:
        lines = text.splitlines()[:_SNIFF_LINES]
    except Exception:  # pragma: no cover - text is a str
        return None
    body = [(i, _strip_comment(s).strip().upper()) for i, s in enumerate(lines)]
    body = [(i, s) for i, s in body if s]
    if not body:
        return None
    for i, s in body:
        if s.startswith("%_N_") and _S_HEADER.match(s):
            return _SIEMENS.format(why=f"a program header {s.split()[0]}")
    for i, s in body:
        if "=" in s or "LCYC" in s or "GOTO" in s:
            for rx, why in _S_WORDS:
                if rx.search(s):
                    return _SIEMENS.format(why=why)
    # FANUC framing: '%' alone, then an O number
    if body[0][1] == "%" and len(body) > 1 and _O_HEADER.match(body[1][1]):
        return _FANUC.format(why=f"% then {body[1][1].split()[0]}")
    if _O_HEADER.match(body[0][1]) and not body[0][1].startswith("%"):
        return _FANUC.format(why=f"a program header {body[0][1].split()[0]}")
    first_g71 = None
    for i, s in body:
        if _G71_SECOND.search(s) and first_g71 is not None:
            return _FANUC.format(why="two-block G71 U R / G71 P Q")
        if "P" not in s and "R" in s and ("U" in s or "W" in s) and _G71.search(s.replace(" ", "")):
            first_g71 = i
        if "IF" in s and _IF_GOTO.search(s):
            return _FANUC.format(why="IF[...] GOTO")
        if "GOTO" in s and _GOTO.search(s):
            return _FANUC.format(why="GOTO")
        if "," in s and _COMMA_CORNER.search(s):
            return _FANUC.format(why=",C / ,R corner words")
        if "WHILE" in s and _DO_END.search(s):
            return _FANUC.format(why="WHILE[...] DO")
    return None
