"""HNC-21/22T code tables (manual table 2.1 word ranges, table 3.2 modal groups, 3.1.1 M codes).

The interpreter reads these through the :class:`~hnc_cam.dialect.Dialect` value; the group
numbers are those of table 3.2 (17 = G96/G97, which the table lists without a group number).
"""
from __future__ import annotations

from .. import CodeSpec

# modal groups of table 3.2 (17 = G96/G97, which the table lists without a group number)
G_GROUP: dict[int, int] = {
    0: 1, 1: 1, 2: 1, 3: 1, 32: 1, 80: 1, 81: 1, 82: 1,
    4: 0, 28: 0, 29: 0, 52: 0, 53: 0, 65: 0, 92: 0,
    71: 6, 72: 6, 73: 6, 76: 6,
    20: 8, 21: 8,
    40: 9, 41: 9, 42: 9,
    54: 11, 55: 11, 56: 11, 57: 11, 58: 11, 59: 11,
    90: 13, 91: 13,
    94: 14, 95: 14,
    36: 16, 37: 16,
    96: 17, 97: 17,
}
#: groups whose codes may repeat in one block (G90 X.. G91 Z..: table 3.2 allows it)
REPEATABLE = frozenset({13})
#: the execution phase of each group: motion, one-shot (non-modal), compound cycle, or a
#: modal setting applied when the block starts
PHASE = {1: "motion", 0: "nonmodal", 6: "cycle"}
#: M codes of the CNC itself (manual 3.1.1); every other M code is the PLC's and must be listed
#: with its meaning in the machine file's [m_codes]
M_CNC = frozenset({0, 2, 30, 98, 99})
#: cycles of the motion group: a later block with axis words repeats them
CYCLE_MOTION = frozenset({32, 80, 81, 82})
#: power-on modal codes (table 3.2 defaults; G36/G37 from the machine's diameter_mode)
POWER_ON = {1: 0, 8: 21, 9: 40, 11: 54, 13: 90, 14: 94, 16: 36, 17: 97}

# word value ranges of table 2.1
RANGES: dict[str, tuple[float, float, bool]] = {  # letter -> (min, max, integer)
    "G": (0, 99, True), "M": (0, 99, True), "N": (0, 4294967295, True), "T": (0, 9999, True),
    "F": (0, 24000, False), "S": (0, 9999, False), "D": (0, 99, True),
    "P": (-4294967295, 4294967295, False), "L": (0, 4294967295, True),
}
UNKNOWN_LETTERS = {"H": "H is not an HNC-21T address (table 2.1)",
                   "O": "O is a program header, not a word inside a block",
                   "Y": "this lathe has no Y axis"}

#: the modal settings of the other groups: group -> code -> (attribute, value)
SETTERS = {13: {90: ("absolute", True), 91: ("absolute", False)},
           16: {36: ("diam", True), 37: ("diam", False)},
           14: {95: ("per_rev", True), 94: ("per_rev", False)},
           8: {20: ("unit", 25.4), 21: ("unit", 1.0)},
           17: {96: ("css", True), 97: ("css", False)}}
PHASE.update({9: "comp", 11: "wcs"})
#: the extra words each code gives a meaning (table 2.1); G53 takes the motion's
LETTERS = {1: frozenset("CR"), 2: frozenset("IKR"), 3: frozenset("IKR"), 4: frozenset("P"),
           53: None}
CODES = {("G", g): CodeSpec(g, grp, PHASE.get(grp, "modal"), SETTERS.get(grp, {}).get(g),
                            LETTERS.get(g, frozenset()))
         for g, grp in G_GROUP.items()}
MESSAGES = {"unknown_g": "unknown G code G{g:02d} (table 3.2)",
            "two_in_group": "two G codes of modal group {grp:02d} in one block",
            "range_ref": "table 2.1"}
CODES.update({("M", m): CodeSpec(m, 0, "flow") for m in M_CNC})
