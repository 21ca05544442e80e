"""The SINUMERIK 802S/802C turning dialect (``docs/SIEMENS.md``): the reader of
:mod:`.syntax`, the code table and executor of :mod:`.codes`, the R parameters of
:mod:`.memory`, the LCYC cycles of :mod:`.cycles` and the ``templates/siemens802`` post."""
from __future__ import annotations

from .. import Dialect


def syntax_factory(calculator: bool = False, block_delete: bool = False):
    from .syntax import SiemensSyntax
    return SiemensSyntax(calculator=calculator, block_delete=block_delete)


def _cycles():
    from .cycles import CYCLES
    return CYCLES


def _executor():
    from .codes import SiemensInterp
    return SiemensInterp


def program_title(number: int, name: str) -> str:
    """The main program's name as the post writes it: ``%_N_NAME_MPF`` (the number is not
    the 802's)."""
    from ...post.filters import program_name
    return f"%_N_{program_name(name)}_MPF"


def _make() -> Dialect:
    from . import codes, memory
    return Dialect(
        name="siemens802", title="SINUMERIK 802S/802C (turning)", templates="siemens802",
        template_fallback=None, syntax_factory=syntax_factory, codes=codes.CODES,
        power_on=codes.POWER_ON, ranges=codes.RANGES, unknown_letters=codes.UNKNOWN_LETTERS,
        memory=memory.MEMORY_MAP, call_letters={}, cycles=_cycles,
        cycle_motion=codes.CYCLE_MOTION, m_cnc=codes.M_CNC,
        features=frozenset({"block_delete", "r_parameters", "named_calls", "labels"}),
        executor=_executor, messages=codes.MESSAGES, program_title=program_title)


DIALECT = _make()
