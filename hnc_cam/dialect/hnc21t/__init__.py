"""The HNC-21/22T dialect: the reader of ``hnc_cam.nc.parser``, the tables of
:mod:`.codes`, the cycles of ``hnc_cam.nc.cycles`` and the ``templates/hnc21t`` post."""
from __future__ import annotations

from .. import Dialect
from . import codes


class HncSyntax:
    """The HNC-21T reader (``hnc_cam.nc.parser``): ``%`` headers, ``;`` and ``()`` comments,
    IF/ELSE/ENDIF/WHILE/ENDW, functions in radians. It has no decimal-point rule and no
    block delete, so both options are accepted and ignored."""

    functions_in_degrees = False

    def __init__(self, calculator: bool = False, block_delete: bool = False):
        from ...nc import parser
        self.calculator = calculator
        self.block_delete = block_delete
        # the parser's functions themselves (no wrapper call on the interpreter's hot path)
        self.load = parser.load
        self.parse_statement = parser.parse_statement
        self.fast_words = parser.fast_words


def _cycles():
    from ...nc import cycles
    return {c: (lambda ctx, c=c: cycles.execute(c, ctx)) for c in cycles.SIMPLE + cycles.ROUGH}


def _executor():
    from ...nc.interp import Interp
    return Interp


DIALECT = Dialect(
    name="hnc21t",
    title="HNC-21/22T",
    templates="hnc21t",
    template_fallback=None,
    syntax_factory=HncSyntax,
    codes=codes.CODES,
    power_on=codes.POWER_ON,
    ranges=codes.RANGES,
    unknown_letters=codes.UNKNOWN_LETTERS,
    memory="hnc21t",
    call_letters={chr(65 + i): i for i in range(26)},
    cycles=_cycles,
    cycle_motion=codes.CYCLE_MOTION,
    m_cnc=codes.M_CNC,
    # thread_end_on_flank: G76's single-flank infeed shifts each pass, its end too, by its
    # depth x tan(half angle) toward the thread's end (the other dialects' multiple-pass
    # thread cycles end every pass on the programmed Z)
    features=frozenset({"g90_g91", "g36_g37", "if_while", "level_locals", "comp_d_word",
                        "thread_end_on_flank"}),
    executor=_executor,
    repeatable_groups=codes.REPEATABLE,
    messages=codes.MESSAGES,
)
