"""FANUC 0i-T custom macro B memory (``docs/FANUC.md`` §10).

* ``#0`` is always null (vacant) and read-only.
* ``#1``–``#33`` locals: one set per G65/G66 call level (an M98 subprogram shares its
  caller's); null on entry except the arguments (specification I, :data:`ARGUMENTS`).
* ``#100``–``#199`` commons, null at the start of a run (cleared at power-off);
  ``#500``–``#999`` commons kept at power-off (a run starts them null).
* system variables: ``#3000`` (write: macro alarm), ``#3006`` (write: stop with a message,
  the run continues), ``#3001`` ms timer / ``#3002`` hour timer (the run's time so far),
  ``#3003``/``#3004`` (accepted, no effect), ``#3901``/``#3902`` parts counters,
  ``#4001``–``#4022`` the modal G code of each group, ``#4109`` F, ``#4119`` S,
  ``#4120`` T, ``#4111`` H, ``#4113`` M, ``#4114`` N, ``#4115`` O of the program,
  ``#5001``/``#5002`` block end X (diameter) / Z, ``#5021``/``#5022`` machine X (diameter) /
  Z, ``#5041``/``#5042`` work X (diameter) / Z.

Null rules: a null read in arithmetic counts as 0; ``#i = #j`` with ``#j`` null keeps ``#i``
null; an address word whose value is a null variable is left out of its block.
"""
from __future__ import annotations

#: argument specification I: letter -> local variable
ARGUMENTS = {"A": 1, "B": 2, "C": 3, "I": 4, "J": 5, "K": 6, "D": 7, "E": 8, "F": 9, "H": 11,
             "M": 13, "Q": 17, "R": 18, "S": 19, "T": 20, "U": 21, "V": 22, "W": 23, "X": 24,
             "Y": 25, "Z": 26}

LOCALS = range(1, 34)
COMMONS = range(100, 200)
KEPT = range(500, 1000)
MACRO_ALARM = 3000
MESSAGE_STOP = 3006

#: the map the dialect value names: kind -> ranges
MEMORY_MAP = {"null": (0, 0), "local": (1, 33), "common": (100, 199), "kept": (500, 999),
              "system": (1000, 9999)}

#: FANUC modal groups read by #4001-#4022: group -> the internal state it shows
MODAL_GROUPS = {1: "motion", 2: "css", 5: "feed", 6: "unit", 7: "comp", 12: "modal_call",
                14: "wcs", 16: "plane"}
