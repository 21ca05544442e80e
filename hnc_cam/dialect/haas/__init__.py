"""The Haas lathe dialect (``docs/FANUC.md`` §13): FANUC 0i-T's value with the one-block
G71/G72/G73/G76 of ``HAAS_CYCLES`` merged over FANUC's cycles, M97 local calls, G154 P
work offsets refused with a hint, and the FANUC templates as the fallback of its own."""
from __future__ import annotations

from ..fanuc0it import make


def _cycles():
    from ..fanuc0it.cycles import CYCLES, HAAS_CYCLES
    table = dict(CYCLES)
    table.update(HAAS_CYCLES)
    return table


DIALECT = make("haas", "Haas lathe (FANUC-compatible)", "haas", "fanuc0it", _cycles,
               features=frozenset({"haas"}))
