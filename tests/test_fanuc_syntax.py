"""The FANUC 0i-T reader's text side (hnc_cam/dialect/fanuc0it/syntax.py; docs/FANUC.md §1,
§3): tape framing, program numbers, comments, ``;``, block delete, the decimal-point rule per
address in standard and calculator mode with its note, ``,C``/``,R``, and the alarms of
malformed words with their line and column. The last tests run the same programs through
``hnc_cam.nc.run(..., dialect="fanuc0it")`` and check the positions."""
from __future__ import annotations

import dataclasses
import pathlib

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hnc_cam import nc
from hnc_cam.dialect.fanuc0it.syntax import FanucSyntax
from hnc_cam.errors import NCError
from hnc_cam.nc import parser as P
from hnc_cam.nc.expr import Expr
from hnc_cam.tooling import load_machine

STD = FanucSyntax()
CALC = FanucSyntax(calculator=True)
DATA = pathlib.Path(__file__).parent / "data" / "fanuc"


def words(line: str, syntax: FanucSyntax = STD) -> dict:
    """The words of one block as {letter: value}, checked against the plain-block path:
    when ``fast_words`` takes the block, its numbers read with ``float`` must be the same."""
    src = syntax.load(line)
    assert len(src.text) == 1, src.text
    text = src.text[0]
    p = syntax.parse_statement(text, 1)
    assert p.kind == "block"
    out = {L: v for L, v, _ in p.words}
    fw = syntax.fast_words(text)
    if fw is not None:
        assert {L: float(v) for L, v, _ in fw} == out
    return out


def alarm(text: str, syntax: FanucSyntax = STD) -> NCError:
    """The alarm of loading and parsing every statement of ``text``."""
    with pytest.raises(NCError) as ei:
        src = syntax.load(text, "prog.nc")
        for i, t in enumerate(src.text):
            if src.kind[i] != P.HDR:
                syntax.parse_statement(t, src.lineno[i], "prog.nc", src.block_text(src.lineno[i]))
    return ei.value


def run(text: str, **machine):
    m = load_machine(None)
    if machine:
        m = dataclasses.replace(m, **machine)
    return nc.run(text, m, dialect="fanuc0it", start=(50.0, 100.0))


def moves_of(text: str, **machine) -> list[tuple]:
    """(kind, X diameter, Z) of every move."""
    return [(mv.kind, round(mv.end[0] * 2, 6), round(mv.end[1], 6)) for mv in run(text, **machine).moves]


def ends_of(text: str, **machine) -> list[tuple]:
    """(line, X diameter, Z) where each block's motion ends (a rapid may move in legs)."""
    out: list[tuple] = []
    for mv in run(text, **machine).moves:
        end = (mv.line, round(mv.end[0] * 2, 6), round(mv.end[1], 6))
        if out and out[-1][0] == mv.line:
            out[-1] = end
        else:
            out.append(end)
    return out


# -- framing -------------------------------------------------------------------------------

def test_percent_frames_the_tape_and_text_outside_it_is_not_read():
    src = STD.load("TITLE LINE FROM THE EDITOR\n%\nO0001 (PART)\nG00 X10. Z2.\nM30\n%\nGARBAGE @@\n")
    assert src.text == ["O0001", "G00 X10. Z2.", "M30"]
    assert src.kind[0] == P.HDR and src.number[0] == 1
    assert src.programs == {1: 1}
    assert src.main == (1, 3)
    lines = sorted(n[0] for n in src.notes)
    assert lines == [1, 7]  # both ignored parts are reported, none silently dropped


def test_file_without_percent_is_read_whole():
    src = STD.load("O1234\nG00 X10. Z2.\nM30\n")
    assert src.text == ["O1234", "G00 X10. Z2.", "M30"] and src.notes == []


def test_closing_percent_only():
    src = STD.load("O0007\nG00 X1.\nM30\n%\n")
    assert src.text == ["O0007", "G00 X1.", "M30"] and src.notes == []


def test_program_number_forms_and_subprograms():
    src = STD.load("%\nO0100 (MAIN)\nM98 P200\nM30\n:200\nG00 X1.\nM99\nO12345678\nM99\n%\n")
    assert src.programs == {100: 1, 200: 4, 12345678: 7}
    assert src.spans == [(1, 3), (4, 6), (7, 8)]
    assert src.main == (1, 3)


def test_statements_before_the_first_O_form_the_main_program():
    src = STD.load("G00 X1.\nM30\nO0002\nM99\n")
    assert src.main == (0, 2) and src.programs == {2: 3}


def test_lower_case_and_spaces_between_words():
    assert words("g01 x 12.5 z-3. f0.2") == {"G": 1.0, "X": 12.5, "Z": -3.0, "F": 0.2}
    assert words("G01X12.5Z-3.F.2") == {"G": 1.0, "X": 12.5, "Z": -3.0, "F": 0.2}


def test_comments_are_blanked_with_columns_kept():
    src = STD.load("G00 (APPROACH) X10. (DIA) Z2.\n")
    assert src.text == ["G00            X10.       Z2."]
    p = STD.parse_statement(src.text[0], 1)
    assert [(L, c) for L, _, c in p.words] == [("G", 1), ("X", 16), ("Z", 27)]


def test_semicolon_is_the_end_of_a_block_not_a_comment():
    src = STD.load("G00 X10.;\nG01 Z-5. F0.1; X12.\n")
    assert [t.strip() for t in src.text] == ["G00 X10.", "G01 Z-5. F0.1", "X12."]
    assert src.lineno == [1, 2, 2]
    # the second block on line 2 keeps its column
    p = STD.parse_statement(src.text[2], 2)
    assert p.words[0][2] == 16


def test_block_delete_off_runs_the_block_and_on_drops_it():
    text = "O1\n/G00 X5.\n/1 G00 X6.\nG00 X7.\nM30\n"
    off = FanucSyntax().load(text)
    assert [t.strip() for t in off.text] == ["O1", "G00 X5.", "G00 X6.", "G00 X7.", "M30"]
    assert off.text[1].startswith(" ")  # the slash is blanked, columns kept
    on = FanucSyntax(block_delete=True).load(text)
    assert [t.strip() for t in on.text] == ["O1", "G00 X7.", "M30"]


def test_block_delete_positions_through_the_interpreter():
    text = "O1\nG00 X10. Z5.\n/G00 X20.\nG00 Z1.\nM30\n"
    assert ends_of(text) == [(2, 10.0, 5.0), (3, 20.0, 5.0), (4, 20.0, 1.0)]
    assert ends_of(text, block_delete=True) == [(2, 10.0, 5.0), (4, 10.0, 1.0)]


def test_goto_finds_a_label_searching_forward_then_from_the_start():
    src = STD.load("O1\nN10 G00 X1.\nN20 X2.\nN10 X3.\nM30\nO2\nN10 X5.\nM99\n")
    main = src.spans[0]
    assert src.find_label(10, main, 2) == 3
    assert src.find_label(10, main, 4) == 1  # wraps to the program's start
    assert src.find_label(10, src.spans[1], 0) == 6
    assert src.find_label(30, main, 0) is None


# -- the decimal-point rule ----------------------------------------------------------------

@pytest.mark.parametrize("word, std, calc", [
    ("X20", 0.020, 20.0),
    ("X20.", 20.0, 20.0),
    ("X20.0", 20.0, 20.0),
    ("Z-1500", -1.5, -1500.0),
    ("U.5", 0.5, 0.5),
    ("W-2", -0.002, -2.0),
    ("I1000", 1.0, 1000.0),
    ("K-3.", -3.0, -3.0),
    ("R5", 0.005, 5.0),
    ("C45000", 45.0, 45000.0),
    ("X1.23456", 1.234, 1.234),  # digits below the least increment are cut
    ("Z-0.0009", -0.0, -0.0),
    ("X99999999", 99999.999, None),
])
def test_decimal_point_rule_per_coordinate_address(word, std, calc):
    assert words(f"G01 {word}")[word[0]] == pytest.approx(std, abs=0)
    if calc is not None:
        assert words(f"G01 {word}", CALC)[word[0]] == pytest.approx(calc, abs=0)


@pytest.mark.parametrize("word, value", [
    ("F100", 100.0), ("F0.2", 0.2), ("F.15", 0.15),  # F as written
    ("P1500", 1500.0), ("Q2500", 2500.0),  # P/Q as written (ms, µm, sequence numbers)
    ("S800", 800.0), ("T0101", 101.0), ("M03", 3.0), ("N120", 120.0), ("H01", 1.0), ("L5", 5.0),
    ("D7000", 7000.0), ("E1.5", 1.5),
])
def test_addresses_read_as_written(word, value):
    assert words(f"G00 {word}")[word[0]] == value
    assert words(f"G00 {word}", CALC)[word[0]] == value


def test_dwell_x_is_thousandths_of_a_second_without_a_point():
    assert words("G04 X2500") == {"G": 4.0, "X": 2.5}
    assert words("G04 U1.5") == {"G": 4.0, "U": 1.5}
    assert words("G04 P1500") == {"G": 4.0, "P": 1500.0}


def test_comma_corners_arrive_as_C_and_R_with_the_rule():
    assert words("G01 X20. ,C1.") == {"G": 1.0, "X": 20.0, "C": 1.0}
    assert words("G01 Z-10.,R500") == {"G": 1.0, "Z": -10.0, "R": 0.5}
    assert words("G01 Z-10.,R500", CALC)["R"] == 500.0


def test_values_in_brackets_and_variables_are_millimetres():
    w = words("G01 X[20] Z-[6] F0.1")
    assert w["X"] == 20.0 and w["Z"] == -6.0
    w = words("G01 X#1 Z-#2")
    assert isinstance(w["X"], Expr) and isinstance(w["Z"], Expr)


def test_note_for_coordinates_without_a_point_standard_mode():
    src = STD.load("O1\nG00 X40. Z2.\nG01 Z-25 F0.2\nX42.\nM30\n")
    assert len(src.notes) == 1
    line, col, msg = src.notes[0]
    assert (line, col) == (3, 5) and "Z-25" in msg


def test_no_note_when_every_coordinate_has_a_point_or_is_zero():
    assert STD.load("O1\nG00 X40. Z0\nG01 X0 Z-25. F0.2\nM30\n").notes == []
    assert STD.load("O1\nIF [#1 GT 0] GOTO 10\n#1=#2 OR 1\nN10 M30\n").notes == []
    assert STD.load("O1\n(X20 IN A COMMENT)\nG00 X1.\nM30\n").notes == []


def test_the_pass_count_of_a_first_g73_block_is_not_a_coordinate():
    # G73 U(Δi) W(Δk) R(d): d is a count, written without a point; the note still finds the
    # first real coordinate without one, also on a G73 block
    assert STD.load("O1\nG00 X52. Z2.\nG73 U3. W0. R3\nM30\n").notes == []
    src = STD.load("O1\nG00 X52. Z2.\nG73 U3 W0. R3\nM30\n")
    assert [(n[0], n[1]) for n in src.notes] == [(3, 5)]
    src = STD.load("O1\nG73 P10 Q20 U0.4 W0.1 R3 F0.2\nM30\n")
    assert [(n[0], n[1]) for n in src.notes] == [(2, 23)]


def test_note_in_calculator_mode_only_when_forms_are_mixed():
    assert CALC.load("O1\nG00 X40 Z2\nG01 Z-25 F0.2\nM30\n").notes == []
    src = CALC.load("O1\nG00 X40. Z2.\nG01 Z-25 F0.2\nM30\n")
    assert [(n[0], n[1]) for n in src.notes] == [(3, 5)]


def test_note_with_the_manual_program_written_without_points():
    # docs/FANUC.md §15.7: every coordinate without a point; the note fires at the first one
    text = (DATA / "macro_a_loop.nc").read_text()
    src = STD.load(text)
    assert [(n[0], n[1]) for n in src.notes] == [(4, 5)]


# -- alarms --------------------------------------------------------------------------------

@pytest.mark.parametrize("text, line, col, part", [
    ("O1\nG01 X1.2.3\n", 2, 5, "malformed number X1.2.3"),
    ("O1\nG01 Z-.5.5 F1\n", 2, 5, "malformed number Z-.5.5"),
    ("O1\nG01 Z-.5. F1\n", 2, 9, "unexpected character"),
    ("O1\nG01 X-\n", 2, 5, "no value"),
    ("O1\nG01 X123456789.\n", 2, 5, "8 digits"),
    ("O1\nG01 X123456.\n", 2, 5, "99999.999"),
    ("O1\nS1000.0\n", 2, 1, "PS0007"),
    ("O1\nM3.5\n", 2, 1, "PS0007"),
    ("O1\nN123456 G00\n", 2, 1, "sequence number"),
    ("O1\nN1.5 G00\n", 2, 1, "sequence number"),
    ("O1\nG01 X1. $\n", 2, 9, "unexpected character"),
    ("O1\nG01 XX1.\n", 2, 5, "unknown word"),
    ("O1\nG01 X1. ,D1.\n", 2, 9, ",C"),
    ("O1\nG00 X1. O2\n", 2, 9, "program number"),
    ("O1\nG00 X1. #1=2\n", 2, 9, "assignment"),
    ("O1\nG00 X1. GOTO 5\n", 2, 9, "keyword"),
])
def test_malformed_words_alarm_at_line_and_column(text, line, col, part):
    e = alarm(text)
    assert (e.line, e.col) == (line, col), str(e)
    assert part in e.message
    assert e.file == "prog.nc"


@pytest.mark.parametrize("text, line, col", [
    ("%\nO12A\nM30\n%\n", 2, 1),
    ("%\nO0001 G00 X1.\nM30\n%\n", 2, 1),
    ("%\n%1234\nM30\n", 2, 1),
    ("%\nO1\nG00 X1.\n  %5\nM30\n", 4, 3),
    ("O1\nG00\0X1.\n", 2, 4),
])
def test_framing_errors_alarm_when_loading(text, line, col):
    e = alarm(text)
    assert (e.line, e.col) == (line, col), str(e)


def test_hnc_header_in_a_fanuc_file_says_so():
    assert "HNC-21T" in alarm("%1234\nG00 X1.\nM30\n").message


def test_long_line_limit():
    with pytest.raises(NCError) as ei:
        STD.load("O1\nG00 X1." + " " * 100 + "\n", "p", line_limit=50)
    assert (ei.value.line, ei.value.col) == (2, 51)


# -- through the interpreter ---------------------------------------------------------------

def test_x20_without_point_moves_twenty_microns_and_with_point_twenty_mm():
    text = "O1\nG00 X20 Z5.\nG00 X20.\nG01 Z-1500 F0.2\nM30\n"
    assert ends_of(text) == [(2, 0.02, 5.0), (3, 20.0, 5.0), (4, 20.0, -1.5)]
    assert ends_of(text, decimal_point="calculator") == [(2, 20.0, 5.0), (4, 20.0, -1500.0)]


def test_run_gives_the_note_as_a_warning_with_its_line():
    tp = nc.run("O1\nG00 X40. Z2.\nG01 Z-25 F0.2\nM30\n", dialect="fanuc0it", start=(50.0, 100.0))
    assert any(w.line == 3 and "decimal point" in w.message for w in tp.warnings)


def test_comma_chamfer_through_the_interpreter():
    mv = moves_of("O1\nG00 X0. Z2.\nG01 Z0. F0.1\nX20. ,C2.\nZ-10.\nM30\n")
    # the corner (X20, Z0) is cut by a 2 mm chamfer: X16 Z0 -> X20 Z-2
    assert ("line", 16.0, 0.0) in mv and ("line", 20.0, -2.0) in mv and mv[-1] == ("line", 20.0, -10.0)


def test_tape_marks_with_end_of_block_and_comment():
    src = STD.load("%;\nO5;\nG00 X1.;\nM30;\n% (END)\nJUNK\n")
    assert [t.strip() for t in src.text] == ["O5", "G00 X1.", "M30"]
    assert [n[0] for n in src.notes] == [6]


def test_text_before_percent_without_an_O_after_it_is_read():
    # the '%' closes a tape that had no opening mark: nothing before it is dropped
    src = STD.load("G00 X1.\nM30\n%\n")
    assert [t.strip() for t in src.text] == ["G00 X1.", "M30"] and src.notes == []


# -- the plain-block path agrees with the slow path ----------------------------------------

def test_fast_path_declines_what_the_rule_changes():
    assert STD.fast_words("G01 X20 Z1.") is None  # X20 is 0.020: the slow path converts it
    assert CALC.fast_words("G01 X20 Z1.") == [("G", "01", ""), ("X", "20", ""), ("Z", "1.", "")]
    assert STD.fast_words("G01 X20.1234") is None  # cut to 0.001 by the slow path
    assert STD.fast_words("G01 X20. ,C1.") is None
    assert STD.fast_words("G65 P9010 A1.") is None
    assert STD.fast_words("S1000.") is None
    assert STD.fast_words("G01 X20. Z-3.5 F0.2 S800 T0101 M03 N10") is not None


_NUMBERS = st.one_of(
    st.integers(-10 ** 9, 10 ** 9).map(str),
    st.tuples(st.integers(-10 ** 6, 10 ** 6), st.integers(0, 10 ** 6), st.integers(0, 6)).map(
        lambda t: f"{t[0]}.{str(t[1]).zfill(6)[:t[2]]}"),
    st.sampled_from(["0", "0.", ".5", "-.5", "+1.", "00012.", "1.23456", "99999.999", "100000."]))


@settings(max_examples=400, deadline=None)
@given(st.lists(st.tuples(st.sampled_from("GXZUWIKRFPQSTMNHDEABC"), _NUMBERS), min_size=1, max_size=6),
       st.booleans())
def test_fast_words_equal_the_slow_path(pairs, calc):
    syntax = CALC if calc else STD
    text = " ".join(f"{L}{n}" for L, n in pairs)
    fw = syntax.fast_words(text)
    try:
        p = syntax.parse_statement(text, 1)
    except NCError as e:
        assert fw is None, (text, str(e))  # the plain path never takes a block that alarms
        return
    if fw is not None:
        assert [(L, float(v)) for L, v, _ in fw] == [(L, v) for L, v, _ in p.words], text


def test_dwell_x_without_point_through_the_interpreter():
    tp = run("O1\nG04 X2500\nG04 U1.5\nG04 P500\nM30\n")
    assert [round(m.duration, 6) for m in tp.moves if m.kind == "dwell"] == [2.5, 1.5, 0.5]


def test_note_for_a_feed_without_point_in_g99_only():
    src = STD.load("O1\nG98 G01 X1. F100\nG99\nG01 X2. F0.2\nG01 X3. F2\nM30\n")
    assert [(n[0], n[1]) for n in src.notes] == [(5, 9)] and "G99" in src.notes[0][2]
    assert STD.load("O1\nG98\nG01 X1. F100\nM30\n").notes == []
    assert STD.load("O1\nG01 X1. F2.\nM30\n").notes == []
    # power-on is G99
    assert [(n[0], n[1]) for n in STD.load("O1\nG01 X1. F1\nM30\n").notes] == [(2, 9)]


def test_digits_and_blanks_of_other_scripts_are_not_numbers():
    e = alarm("O1\nG01 X\u0663.\n")  # ARABIC-INDIC DIGIT THREE
    assert (e.line, e.col) == (2, 6) and "unexpected character" in e.message
    e = alarm("O1\nG01\u00a0X3.\n")  # NO-BREAK SPACE
    assert (e.line, e.col) == (2, 4) and "unexpected character" in e.message


def test_many_semicolon_blocks_on_long_lines_are_bounded():
    line = "G01 X1.;" * 5000  # 5,000 blocks on a 40,000-character line
    with pytest.raises(NCError) as ei:
        STD.load("O1\n" + (line + "\n") * 20 + "M30\n")
    assert ei.value.line >= 2 and "';' blocks" in ei.value.message
    src = STD.load("O1\n" + "G01 X1.;" * 50 + "\nM30\n")
    assert len(src.text) == 52
