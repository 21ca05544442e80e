"""The FANUC 0i-T dialect (G-code system A; ``docs/FANUC.md``): the reader of :mod:`.syntax`,
the code table and executor of :mod:`.codes`, the macro memory map of :mod:`.memory`, the
cycles of :mod:`.cycles` and the ``templates/fanuc0it`` post."""
from __future__ import annotations

from ...errors import NCError
from .. import Dialect


def syntax_factory(calculator: bool = False, block_delete: bool = False):
    try:
        from .syntax import FanucSyntax
    except ImportError:
        raise NCError("the FANUC 0i-T reader (hnc_cam.dialect.fanuc0it.syntax) is not yet "
                      "available") from None
    return FanucSyntax(calculator=calculator, block_delete=block_delete)


def _cycles():
    from .cycles import CYCLES
    return CYCLES


def _executor():
    from .codes import FanucInterp
    return FanucInterp


def _table():
    from . import codes
    return codes


def make(name: str, title: str, templates: str, fallback, cycles, syntax=syntax_factory,
         ranges=None, features=frozenset(), extra_codes=None) -> Dialect:
    """A FANUC-family dialect value (FANUC 0i-T itself, Haas over it); ``extra_codes`` add
    to (or replace entries of) FANUC's code table."""
    from . import codes, memory
    table = dict(codes.CODES)
    table.update(extra_codes or {})
    return Dialect(
        name=name, title=title, templates=templates, template_fallback=fallback,
        syntax_factory=syntax, codes=table, power_on=codes.POWER_ON,
        ranges=ranges if ranges is not None else codes.RANGES,
        unknown_letters=codes.UNKNOWN_LETTERS, memory=memory.MEMORY_MAP,
        call_letters=memory.ARGUMENTS, cycles=cycles, cycle_motion=codes.CYCLE_MOTION,
        m_cnc=codes.M_CNC,
        features=frozenset({"two_block_g71", "decimal_point_input", "block_delete", "macro_b",
                            "goto", "g50", "null_variables"}) | features,
        executor=_executor, messages=codes.MESSAGES)


DIALECT = make("fanuc0it", "FANUC 0i-T (G-code system A)", "fanuc0it", None, _cycles)
