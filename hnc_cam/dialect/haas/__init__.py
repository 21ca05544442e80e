"""The Haas lathe dialect (``docs/FANUC.md`` §13): FANUC 0i-T's value with the one-block
G71/G72/G73/G76 of ``HAAS_CYCLES`` merged over FANUC's cycles, M97 local calls (the
executor's ``haas`` feature), G10 and G187 accepted with no effect, G154 P work offsets
refused with the reason, and the FANUC templates as the fallback of its own."""
from __future__ import annotations

from .. import CodeSpec
from ..fanuc0it import make

#: accepted with no effect on the path (docs/FANUC.md §13): G10 data setting, G187 smoothness
EXTRA_CODES = {("G", 10): CodeSpec(10, 0, "nonmodal", None, frozenset("PRQL")),
               ("G", 187): CodeSpec(187, 0, "nonmodal", None, frozenset("PE"))}


def _cycles():
    from ..fanuc0it.cycles import CYCLES, HAAS_CYCLES
    table = dict(CYCLES)
    table.update(HAAS_CYCLES)
    return table


DIALECT = make("haas", "Haas lathe (FANUC-compatible)", "haas", "fanuc0it", _cycles,
               features=frozenset({"haas"}), extra_codes=EXTRA_CODES)
