"""Lexer and parser: headers, several programs per file, comments, N numbers, blocks without
spaces, lower case, expression words."""
from __future__ import annotations

import pytest

from hnc_cam.errors import NCError
from hnc_cam.nc import parser, run
from hnc_cam.nc.expr import Expr
from hnc_cam.nc.lexer import clean, tokenize


def test_clean_blanks_comments_and_keeps_columns():
    s = clean("n10 g01 (feed in) x10 ; rest")
    assert s.startswith("N10 G01 ") and s.rstrip().endswith("X10")
    assert s.index("X10") == "n10 g01 (feed in) x10".index("x10")
    assert clean("G00 (unclosed X5").strip() == "G00"


def test_tokens_without_spaces():
    toks = tokenize("N6X28.04Z18.5C2P180F3")
    assert [(k, v) for k, v, _ in toks] == [
        ("addr", "N"), ("num", "6"), ("addr", "X"), ("num", "28.04"), ("addr", "Z"), ("num", "18.5"),
        ("addr", "C"), ("num", "2"), ("addr", "P"), ("num", "180"), ("addr", "F"), ("num", "3")]
    assert [c for _, _, c in toks][:4] == [1, 2, 3, 4]


def test_tokens_of_macro_lines():
    toks = tokenize("WHILE #10LE16")
    assert [(k, v) for k, v, _ in toks] == [("kw", "WHILE"), ("op", "#"), ("num", "10"),
                                             ("kw", "LE"), ("num", "16")]
    assert [v for _, v, _ in tokenize("IF[AR[#23]EQ90]")] == ["IF", "[", "AR", "[", "#", "23", "]",
                                                             "EQ", "90", "]"]
    assert [v for _, v, _ in tokenize("#1=ATAN2[1,2]")][3] == "ATAN2"


def test_unexpected_character():
    with pytest.raises(NCError) as ei:
        tokenize("G01 X10 @", 7, "f.nc")
    assert (ei.value.line, ei.value.col) == (7, 9)


def test_structure_of_a_file_with_subprograms():
    text = ("(title comment)\n(more)\n%3110 (main)\nN1 G92 X16 Z1\nM98 P0003 L2\nM30\n"
            "%0003 (sub)\nN1 G01 U-1 F100\nM99\no100\nM99\n")
    src = parser.load(text, "f.nc")
    assert src.main == (1, 4)
    assert src.programs == {3110: 1, 3: 5, 100: 8}
    assert src.lineno[src.programs[3]] == 8


def test_file_without_header_is_the_main_program():
    tp = run("T0202\nG01 X50 Z100 F100\nM30\n")
    assert len(tp.moves) == 1


def test_lower_case_programs():
    tp = run("o0099\ng92 x0 z0\ng01 x10 z-5 f100\nm30\n")
    assert tp.moves[0].end == pytest.approx((5.0, -5.0))


def test_semicolon_comments_and_blank_lines():
    tp = run("%1\n\nG92 X0 Z0 ; set\n#1=2;\nG01 X[#1] F10;comment\n  \nM30\n")
    assert tp.moves[0].end == pytest.approx((1.0, 0.0))


def test_word_values():
    p = parser.parse_statement("N5 G01 X-[#1*2] Z#2 U+3 W.5 F[10]", 1)
    assert p.kind == "block" and p.n == 5
    w = {L: v for L, v, _ in p.words}
    assert isinstance(w["X"], Expr) and isinstance(w["Z"], Expr)
    assert w["U"] == 3.0 and w["W"] == 0.5 and w["F"] == 10.0


def test_control_statements_with_n_numbers():
    src = parser.load("%1\nN5 #1=1\nN10 IF #1 EQ 1\nN11 ELSE\nN12 ENDIF\nM30\n")
    assert src.kind[2:5] == ["if", "else", "endif"]
    assert src.jump == {2: 4, 3: 5}


def test_n_range():
    with pytest.raises(NCError, match="N must be"):
        parser.parse_statement("N4294967296 G00", 1)


def test_n_numbers_are_not_the_execution_order():
    tp = run("%1\nG92 X0 Z0\nN30 G00 Z-1\nN10 G00 Z-2\nM30\n")
    assert [m.end[1] for m in tp.moves] == [-1, -2]


def test_line_numbers_count_newlines_only():
    tp = run("%1\r\nG92 X0 Z0\r\n(a\x0cb)\r\nG01 Z-1 F10\r\nM30\r\n")
    assert tp.moves[0].line == 4
