"""FANUC custom macro B and macro A as the reader gives them (hnc_cam/dialect/fanuc0it/syntax.py,
hnc_cam/nc/expr.py FanucExpr; docs/FANUC.md §10, §11, §15.6, §15.7): statement kinds and loop
structure, expression values (degrees, rounding, BCD, bitwise logic, null rules), every macro A
H code, the alarms at their line and column, and the passes the loops cut through
``hnc_cam.nc.run(..., dialect="fanuc0it")``."""
from __future__ import annotations

import dataclasses
import math
import pathlib

import pytest

from hnc_cam import nc
from hnc_cam.dialect.fanuc0it.syntax import FanucSyntax, clean
from hnc_cam.errors import NCError
from hnc_cam.nc import parser as P
from hnc_cam.nc.expr import EvalError, FanucExpr
from hnc_cam.tooling import load_machine

S = FanucSyntax()
DATA = pathlib.Path(__file__).parent / "data" / "fanuc"


def parse(stmt: str) -> P.Parsed:
    return S.parse_statement(clean(stmt), 1, "m.nc", stmt)


def value(expr: str, **variables):
    """The value of a FANUC expression with the given variables (``v1=2.0`` -> #1 = 2)."""
    L, G = [None] * 50, [None] * 200
    for k, v in variables.items():
        n = int(k[1:])
        (L if n < 50 else G)[n] = v
    p = parse(f"#100={expr}")
    assert p.kind == "assign"
    e = p.assigns[0][1]
    assert isinstance(e, FanucExpr)
    return e.fn(L, G, lambda n: None, None)


def run(text: str, **machine):
    m = load_machine(None)
    if machine:
        m = dataclasses.replace(m, **machine)
    return nc.run(text, m, dialect="fanuc0it", start=(50.0, 100.0))


def feeds(tp) -> list[tuple]:
    """(X diameter, Z) of the end of every feed move."""
    return [(round(m.end[0] * 2, 6), round(m.end[1], 6)) for m in tp.moves if m.kind == "line"]


# -- statements ----------------------------------------------------------------------------

def test_statement_kinds_and_loop_jumps():
    src = S.load("O1\n#1=0\nN5 WHILE [#1 LT 3] DO1\n#1=#1+1\nIF [#1 EQ 2] GOTO 9\n"
                 "IF [#1 EQ 1] THEN #2=5\nEND1\nN9 GOTO 5\nDO2\nEND2\nM30\n")
    assert src.kind == [P.HDR, P.OTHER, P.WHILE, P.OTHER, P.GOTO, P.IFTHEN, P.ENDW, P.GOTO,
                        P.WHILE, P.ENDW, P.OTHER]
    assert src.jump == {2: 7, 6: 2, 8: 10, 9: 8}
    assert src.bad == {}
    assert parse("DO2").cond is None  # a bare DO loops for ever


def test_goto_forms():
    p = parse("GOTO 10")
    assert p.kind == P.GOTO and p.cond is None and p.target.node == ("num", "10")
    p = parse("GOTO#5")
    assert p.target.node == ("var", ("num", "5"))
    p = parse("N4 GOTO[#1+2]")
    assert p.n == 4 and p.target.node[0] == "bin"
    p = parse("IF[#1GT#2]GOTO20")
    assert p.kind == P.GOTO and p.cond.node == ("bin", "GT", ("var", ("num", "1")), ("var", ("num", "2")))
    p = parse("IF [#1 EQ #0 AND #13 EQ #0] GO 7")  # [PAPER]'s test for missing arguments
    assert p.cond.node[:2] == ("bin", "AND") and p.target.node == ("num", "7")


def test_if_then_assignment_and_its_message():
    p = parse("IF [#3 LE 0] THEN #3000=1 (STEP MUST BE POSITIVE)")
    assert p.kind == P.IFTHEN and p.assigns[0][0] == 3000
    assert p.message == "STEP MUST BE POSITIVE"
    p = parse("#3000=2(NO TOOL)")
    assert p.kind == "assign" and p.message == "NO TOOL"


def test_indirect_assignment_and_abbreviations():
    p = parse("#[#1+100]=RO[2.5]+FI[-1.5]")
    target, e, _ = p.assigns[0]
    assert isinstance(target, FanucExpr)
    assert e.fn([None] * 50, [None] * 200, lambda n: None, None) == 3.0 - 1.0
    assert parse("WH [#1 LT 3] DO1").kind == P.WHILE


@pytest.mark.parametrize("text, line, part", [
    ("O1\nWHILE [1] DO4\nEND4\nM30\n", 2, "1, 2 or 3"),
    ("O1\nDO1\nEND2\nM30\n", 3, "END2 without DO2"),
    ("O1\nDO1\nDO2\nEND1\nEND2\nM30\n", 4, "overlap"),
    ("O1\nDO1\nDO1\nEND1\nEND1\nM30\n", 3, "DO1 inside"),
    ("O1\nWHILE [#1 LT 2] DO1\nM30\n", 2, "never closed"),
    ("O1\nEND3\nM30\n", 2, "without DO3"),
    ("O1\nDO\nEND1\nM30\n", 2, "identifier"),
])
def test_loop_structure_faults_alarm_at_their_line(text, line, part):
    src = S.load(text)
    assert any(src.lineno[i] == line and part in msg for i, msg in src.bad.items()), src.bad
    # the run stops at the first faulty statement it reaches
    first = min(src.lineno[i] for i in src.bad)
    with pytest.raises(NCError) as ei:
        run(text)
    assert ei.value.line == first and ei.value.message == src.bad[src.lineno.index(first)]


def test_loops_nest_three_deep_but_not_four():
    ok = "O1\nDO1\nDO2\nDO3\nEND3\nEND2\nEND1\nM30\n"
    assert S.load(ok).bad == {}
    deep = "O1\nWHILE[1]DO1\nWHILE[1]DO2\nWHILE[1]DO3\nWHILE[1]DO1\nEND1\nEND3\nEND2\nEND1\nM30\n"
    assert any("DO1 inside" in m or "3 deep" in m for m in S.load(deep).bad.values())


def test_loops_are_matched_per_program():
    src = S.load("O1\nDO1\nM98 P2\nEND1\nM30\nO2\nEND1\nM99\n")
    assert src.jump == {1: 4, 3: 1}
    assert [src.lineno[i] for i in src.bad] == [7]


@pytest.mark.parametrize("stmt, line, col, part", [
    ("IF #1 GT 0 GOTO 5", 1, 4, "brackets"),
    ("IF [#1 GT 0] M99", 1, 14, "GOTO n or THEN"),
    ("IF [#1 GT 0] THEN M99", 1, 19, "assignment"),
    ("WHILE [#1 GT 0] DO", 1, 19, "identifier"),
    ("WHILE [#1 GT 0]", 1, 16, "DO1"),
    ("GOTO", 1, 5, "sequence number"),
    ("GOTO 5 X1.", 1, 8, "after the GOTO"),
    ("#1=[[[[[[1]]]]]]", 1, 9, "PS0118"),
    ("#1=SIN 30", 1, 8, "'['"),
    ("#1=[1+2", 1, 8, "']'"),
    ("#1=", 1, 4, "nothing after"),
    ("#1=2 X1.", 1, 6, "'#'"),
    ("#1=FOO[2]", 1, 4, "unknown word"),
    ("#-1=2", 1, 2, "negative"),
])
def test_macro_statement_alarms_at_the_column(stmt, line, col, part):
    with pytest.raises(NCError) as ei:
        S.parse_statement(stmt, line, "m.nc", stmt)
    assert (ei.value.line, ei.value.col) == (line, col), str(ei.value)
    assert part in ei.value.message


def test_brackets_five_deep_are_allowed():
    assert value("[[[[[2]]]]]") == 2.0


# -- expression values ---------------------------------------------------------------------

@pytest.mark.parametrize("expr, expected", [
    ("SIN[30]", 0.5), ("COS[60]", 0.5), ("TAN[45]", 1.0), ("SIN[-90]", -1.0),
    ("ASIN[0.5]", 30.0), ("ASIN[-0.5]", 330.0), ("ACOS[-1]", 180.0), ("ACOS[0.5]", 60.0),
    ("ATAN[1]/[1]", 45.0), ("ATAN[1]/[-1]", 135.0), ("ATAN[-1]/[-1]", 225.0), ("ATAN[-1]/[1]", 315.0),
    ("ATAN[1,-1]", 135.0), ("ATAN[1]", 45.0), ("ATAN[0]/[-5]", 180.0),
    ("SQRT[16]", 4.0), ("ABS[-2.5]", 2.5), ("LN[EXP[2]]", 2.0), ("EXP[0]", 1.0),
    ("ROUND[1.5]", 2.0), ("ROUND[-1.5]", -2.0), ("ROUND[-1.4]", -1.0), ("ROUND[2.4999]", 2.0),
    ("FIX[1.2]", 1.0), ("FIX[-1.2]", -1.0), ("FUP[1.2]", 2.0), ("FUP[-1.2]", -2.0),
    ("FUP[3]", 3.0), ("FIX[-3]", -3.0),
    ("BIN[37]", 25.0), ("BCD[25]", 37.0), ("BCD[1234]", 4660.0), ("BIN[4660]", 1234.0),
    ("7 MOD 3", 1.0), ("-7 MOD 3", -1.0), ("7.6 MOD 3", 2.0),
    ("12 AND 10", 8.0), ("12 OR 3", 15.0), ("12 XOR 10", 6.0),
    ("1+2*3", 7.0), ("[1+2]*3", 9.0), ("8/4/2", 1.0), ("-2*-3", 6.0), ("10-4-3", 3.0),
    ("2 GT 1", 1.0), ("2 LT 1", 0.0), ("2 GE 2", 1.0), ("1 LE 0.5", 0.0), ("3 EQ 3", 1.0), ("3 NE 3", 0.0),
    ("[1 LT 2] AND [3 GT 4]", 0.0), ("1 LT 2 AND 3 LT 4", 1.0), ("1 GT 2 OR 3 LT 4", 1.0),
    ("16 EQ 0.08*200", 1.0),  # the 1e-9 tolerance of comparisons
])
def test_expression_values(expr, expected):
    assert value(expr) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("expr, part", [
    ("1/0", "division by zero"), ("SQRT[-1]", "negative"), ("LN[0]", "LN"), ("LN[-2]", "LN"),
    ("ASIN[2]", "ASIN"), ("ACOS[-1.5]", "ACOS"), ("5 MOD 0", "MOD"), ("BIN[10]", "BCD"),
    ("BCD[-1]", "BCD"), ("TAN[90]", "TAN"), ("EXP[1000]", "EXP"), ("ATAN[0]/[0]", "ATAN"),
])
def test_expression_errors(expr, part):
    with pytest.raises(EvalError) as ei:
        value(expr)
    assert part in ei.value.message


def test_null_rules():
    # arithmetic: a null counts as 0; EQ/NE: null equals only null; a bare variable keeps it
    assert value("#1 EQ #0") == 1.0
    assert value("#1 EQ #0", v1=0.0) == 0.0
    assert value("#1 EQ 0") == 0.0
    assert value("#1 NE 0") == 1.0
    assert value("#1 GT -1") == 1.0 and value("#1 LT 1") == 1.0
    assert value("#1*5") == 0.0 and value("#1+#1") == 0.0
    assert value("#1") is None and value("#1", v1=3.0) == 3.0
    assert value("#0") is None
    assert value("#101 EQ #0", v101=2.0) == 0.0


def test_variable_values_in_expressions():
    assert value("#1*2+#100", v1=3.0, v100=0.5) == 6.5
    # an indirect read goes through the reader R with the computed number
    e = parse("#100=#[#1+1]*2").assigns[0][1]
    L = [None] * 50
    L[1] = 1.0
    assert e.fn(L, [None] * 200, {2.0: 7.0}.get, None) == 14.0


# -- macro A ------------------------------------------------------------------------------

MACRO_A = [
    ("H01", "Q7", None, 7.0), ("H01", "Q-#102", None, -3.0),
    ("H02", "Q#102", "R#103", 7.0), ("H03", "Q#102", "R#103", -1.0), ("H04", "Q#102", "R#103", 12.0),
    ("H05", "Q#102", "R#103", 0.75), ("H11", "Q12", "R3", 15.0), ("H12", "Q12", "R10", 8.0),
    ("H13", "Q12", "R10", 6.0), ("H21", "Q#103", None, 2.0), ("H22", "Q-5", None, 5.0),
    ("H23", "Q#107", "R#102", 2.0), ("H24", "Q37", None, 25.0), ("H25", "Q25", None, 37.0),
    ("H26", "Q#102", "R#103", 1.5 * 3.0 / 4.0), ("H27", "Q3", "R#103", 5.0), ("H28", "Q5", "R3", 4.0),
    ("H31", "Q2", "R30", 1.0), ("H32", "Q2", "R60", 1.0), ("H33", "Q2", "R45", 2.0),
    ("H34", "Q1", "R-1", 135.0),
]


@pytest.mark.parametrize("h, q, r, expected", MACRO_A)
def test_every_macro_a_operation(h, q, r, expected):
    p = parse(f"G65 {h} P#101 {q} {r or ''}")
    assert p.kind == "assign"
    target, e, _ = p.assigns[0]
    assert target == 101
    G = [None] * 200
    G[101], G[102], G[103], G[107] = 1.5, 3.0, 4.0, 11.0
    assert e.fn([None] * 50, G, lambda n: None, None) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("h, op", [(81, "EQ"), (82, "NE"), (83, "GT"), (84, "LT"), (85, "GE"), (86, "LE")])
def test_macro_a_jumps(h, op):
    p = parse(f"N5 G65 H{h} P120 Q#101 R30")
    assert p.kind == P.GOTO and p.n == 5
    assert p.target.node == ("num", "120")
    assert p.cond.node == ("bin", op, ("var", ("num", "101")), ("num", "30"))
    assert S.load(f"O1\nG65 H{h} P120 Q#101 R30\nM30\n").kind[1] == P.GOTO


def test_macro_a_unconditional_jump_and_alarm():
    p = parse("G65 H80 P120")
    assert p.kind == P.GOTO and p.cond is None and p.target.node == ("num", "120")
    p = parse("G65 H99 P15")
    assert p.kind == "assign" and p.assigns[0][0] == 3000 and p.assigns[0][1].node == ("num", "15")


@pytest.mark.parametrize("stmt, col, part", [
    ("G65 H07 P#101 Q1", 5, "H7"),
    ("G65 H02 P#101 Q1", 5, "missing R"),
    ("G65 H01 P101 Q1", 9, "result variable"),
    ("G65 H81 P10 Q1", 5, "missing R"),
    ("G65 H01 P#101 Q1 X5.", 18, "not a word"),
    ("G65 H01 H02 P#101 Q1", 9, "twice"),
])
def test_macro_a_errors(stmt, col, part):
    with pytest.raises(NCError) as ei:
        S.parse_statement(stmt, 3, "m.nc", stmt)
    assert (ei.value.line, ei.value.col) == (3, col), str(ei.value)
    assert part in ei.value.message


# -- through the interpreter ----------------------------------------------------------------

def test_manual_macro_b_loop_passes():
    # docs/FANUC.md §15.6: passes at X38, X36, X34, X32, X30, each from Z2 to Z-25
    tp = run((DATA / "macro_b_loop.nc").read_text())
    f = feeds(tp)
    assert f == [(d, z) for d in (38.0, 36.0, 34.0, 32.0, 30.0) for z in (2.0, -25.0)]
    assert not [w for w in tp.warnings if "decimal point" in w.message]


def test_manual_macro_b_loop_step_zero_is_macro_alarm_3001():
    text = (DATA / "macro_b_loop.nc").read_text().replace("C2.0", "C0")
    with pytest.raises(NCError) as ei:
        run(text)
    assert ei.value.line == 10 and "3001" in ei.value.message and "STEP MUST BE POSITIVE" in ei.value.message


def test_manual_macro_a_loop_passes_in_calculator_mode():
    # docs/FANUC.md §15.7 (GSK style: numbers without a point are mm)
    tp = run((DATA / "macro_a_loop.nc").read_text(), decimal_point="calculator")
    assert feeds(tp) == [(d, z) for d in (38.0, 36.0, 34.0, 32.0, 30.0) for z in (2.0, -25.0)]


def test_manual_macro_a_loop_in_standard_mode_reads_thousandths_and_warns():
    tp = run((DATA / "macro_a_loop.nc").read_text())
    assert any(w.line == 4 and "decimal point" in w.message for w in tp.warnings)
    # X#101 is a variable (mm), Z-25 is 0.025 mm
    assert feeds(tp)[:2] == [(38.0, 0.002), (38.0, -0.025)]


def test_if_goto_forward_and_backward():
    text = ("O1\nG00 X50. Z10.\n#1=0\nN10 #1=#1+1\nG01 X[40-#1*2] F0.2\n"
            "IF [#1 LT 3] GOTO 10\nIF [#1 EQ 3] GOTO 30\nG01 Z-99.\nN30 G01 Z-5.\nM30\n")
    f = feeds(run(text))
    assert f == [(38.0, 10.0), (36.0, 10.0), (34.0, 10.0), (34.0, -5.0)]


def test_if_then_and_nested_loops():
    text = ("O1\nG00 X60. Z5.\n#1=0\nWHILE [#1 LT 2] DO1\n#2=0\nWHILE [#2 LT 2] DO2\n"
            "#3=0\nWHILE [#3 LT 2] DO3\n#3=#3+1\nEND3\n#2=#2+1\nIF [#2 EQ 2] THEN #4=[#1*10+#2]\n"
            "G01 X[50-#4] F0.2\nEND2\n#1=#1+1\nEND1\nM30\n")
    # #4 is null (X50.) until the second inner pass sets it to 2 (X48.), then 12 (X38.); the
    # X48. of the second outer pass's first inner pass does not move
    assert [x for x, z in feeds(run(text))] == [50.0, 48.0, 38.0]


def test_null_word_is_left_out_of_its_block():
    f = feeds(run("O1\nG00 X50. Z5.\nG01 X#1 Z2. F0.2\nM30\n"))
    assert f == [(50.0, 2.0)]


def test_goto_to_a_missing_block_alarms_at_the_goto():
    with pytest.raises(NCError) as ei:
        run("O1\nG00 X50. Z5.\nGOTO 99\nM30\n")
    assert ei.value.line == 3 and "N99" in ei.value.message


def test_macro_a_jump_through_the_interpreter():
    text = "O1\nG00 X50. Z5.\nG65 H01 P#101 Q3\nN10 G01 Z#101 F0.2\nG65 H03 P#101 Q#101 R1\nG65 H83 P10 Q#101 R0\nM30\n"
    assert [z for x, z in feeds(run(text))] == [3.0, 2.0, 1.0]


def test_degrees_in_a_move():
    f = feeds(run("O1\nG00 X50. Z5.\n#1=30\nG01 X[40*SIN[#1]] Z[10*COS[60]] F0.2\nM30\n"))
    assert f == [(pytest.approx(20.0), pytest.approx(5.0))]
    assert math.isclose(f[0][0], 20.0)


@pytest.mark.parametrize("stmt, col, part", [
    ("#2=5/#1", 4, "division by zero"),
    ("#2=SQRT[#1-1]", 4, "SQRT"),
    ("#2=LN[#1]", 4, "LN"),
    ("G01 X[4/#1] F0.2", 6, "division by zero"),
    ("IF [1/#1 GT 0] GOTO 5", 4, "division by zero"),
])
def test_expression_errors_alarm_at_the_expression_through_the_interpreter(stmt, col, part):
    with pytest.raises(NCError) as ei:
        run(f"O1\nG00 X50. Z5.\n#1=0\n{stmt}\nN5 M30\n")
    assert (ei.value.line, ei.value.col) == (4, col), str(ei.value)
    assert part in ei.value.message
