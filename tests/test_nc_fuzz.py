"""Property tests: any input gives an alarm (NCError) or a toolpath; never another exception,
never a hang (a small step limit bounds every loop)."""
from __future__ import annotations

import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hnc_cam.errors import NCError
from hnc_cam.nc import run
from hnc_cam.nc.toolpath import Toolpath

LIMIT = 2000
SETTINGS = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def outcome(text: str):
    try:
        tp = run(text, step_limit=LIMIT)
    except NCError as e:
        assert isinstance(e.message, str) and e.message
        assert isinstance(e.line, int) and e.line >= 0 and isinstance(e.col, int) and e.col >= 0
        line = e.one_line()
        assert line.isprintable() and len(line) < 1200, line  # one printable line, bounded
        return e
    assert isinstance(tp, Toolpath)
    for m in tp.moves:
        assert math.isfinite(m.start[0]) and math.isfinite(m.end[1])
        assert m.duration >= 0
    tp.dumps()
    tp.summary()
    return tp


@SETTINGS
@given(st.binary(max_size=300))
def test_random_bytes(data):
    outcome(data.decode("latin-1"))


@SETTINGS
@given(st.lists(st.sampled_from(["G01 X10 Z-5 F100", "G00 X20", "#1=1", "(c)", "M30", "%1", "O2",
                                 "\r", "\n", "\r\n", "\0", "\x1b[2J", "\x0b", "\u00b3", "\u2028",
                                 "9" * 400, "IF 1", "ENDIF", "WHILE 1", "ENDW", "G41 G01 X5",
                                 "G40 G00 X30", "C1", "R1"]), max_size=30))
def test_line_ends_and_control_characters(parts):
    outcome("".join(parts))


WORDS = ["G00", "G01", "G02", "G03", "G04", "G90", "G91", "G36", "G37", "G20", "G21", "G92", "G28",
         "G29", "G52", "G53", "G54", "G59", "G94", "G95", "G96", "G97", "G40", "G41", "G42", "G65",
         "G80", "G81", "G82", "G32", "G71", "G72", "G73", "G76", "G07",
         "M03", "M04", "M05", "M07", "M09", "M00", "M06", "M98", "M99", "M30", "M02", "M08",
         "X10", "X-5.5", "Z-20", "Z3", "U4", "W-2", "R5", "R-3", "I2", "K-4", "C1", "F100", "F0.2",
         "S500", "T0101", "T0200", "P2", "P1", "L3", "Q9", "E1", "H3", "N10", "N20", "%1", "%2", "O3",
         "#1=", "#2=#1+1", "#[#1]=3", "#1", "[", "]", "+", "-", "*", "/", "EQ", "LT", "AND", "NOT",
         "SIN[", "SQRT[", "AR[#1]", "PI", "IF", "ELSE", "ENDIF", "WHILE", "ENDW", "(c)", ";", "X[#1]",
         "G[#1]", "#1=#1+1", "#1000", "#5000", "2", "0", "-1", "1.5"]


@SETTINGS
@given(st.lists(st.lists(st.sampled_from(WORDS), max_size=7), max_size=25),
       st.booleans())
def test_random_token_soup(lines, end):
    text = "\n".join(" ".join(ws) for ws in lines) + ("\nM30\n" if end else "")
    outcome(text)


@SETTINGS
@given(st.lists(st.sampled_from(["#1=#1+1", "WHILE #1 LT 1E9", "WHILE 1", "ENDW", "M98 P1",
                                 "M99", "G01 X1 F10", "IF #1 GT 3", "ENDIF", "%1", "#1=0"]),
                max_size=15))
def test_loops_and_calls_never_hang(lines):
    outcome("%1\n#1=0\n" + "\n".join(lines) + "\nM30\n")


def test_endless_loop_stops_at_the_step_limit():
    r = outcome("%1\nWHILE 1\nENDW\nM30\n")
    assert isinstance(r, NCError) and "step limit" in r.message


def test_endless_recursion_stops():
    r = outcome("%1\nM98 P1\nM30\n")
    assert isinstance(r, NCError) and "nesting too deep" in r.message


def test_empty_subprogram_repeated_forever_stops():
    r = outcome("%1\nM98 P2 L4294967295\nM30\n%2\n")
    assert isinstance(r, NCError) and "too many subprogram runs" in r.message and r.line == 2


def test_deeply_nested_expressions_alarm():
    for text in ("#1=" + "[" * 3000 + "1" + "]" * 3000, "#1=" + "-" * 5000 + "1",
                 "#1=" + "SIN[" * 2000 + "1" + "]" * 2000):
        r = outcome("%1\n" + text + "\nM30\n")
        assert isinstance(r, NCError)
    r = outcome("%1\n#1=" + "[" * 20 + "2" + "]" * 20 + "\nM30\n")
    assert not isinstance(r, NCError)
