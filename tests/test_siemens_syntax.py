"""The SINUMERIK 802 reader (hnc_cam.dialect.siemens802.syntax): framing, comments, skip
blocks, labels, statements, and one placed alarm per faulty construct."""
from __future__ import annotations

import pytest

from hnc_cam import dialect, nc
from hnc_cam.dialect import sniff
from hnc_cam.dialect.siemens802.syntax import SiemensSyntax
from hnc_cam.errors import NCError
from hnc_cam.tooling import load_machine


def run(text, **kw):
    kw.setdefault("start", (20.0, 20.0))
    return nc.run(text, dialect="siemens802", **kw)


def pts(tp):
    return [(round(m.end[0], 4), round(m.end[1], 4)) for m in tp.moves]


def test_registered_with_its_templates():
    d = dialect.get("siemens802")
    assert dialect.names()[-1] == "siemens802"
    assert (d.title, d.templates, d.template_fallback) == ("SINUMERIK 802S/802C (turning)", "siemens802", None)


def test_framing_programs_and_path_lines():
    src = SiemensSyntax().load("%_N_SUB_SPF\n;$PATH=/_N_SPF_DIR\nRET\n%_N_PART_MPF\n;$PATH=/_N_MPF_DIR\n"
                               "G0 X1\nM30\n", "f")
    assert set(src.programs) == {"SUB", "PART"}
    assert src.main == (src.programs["PART"], len(src.kind))  # the first MPF runs


def test_comments_lower_case_and_brackets_are_not_comments():
    tp = run("g0 x10 z5 ; a comment (with a bracket\nR1=(2+3)*2 ; (R1 = 10)\ng1 x=R1*2 f100\nm30\n")
    assert pts(tp)[-1] == (10.0, 5.0)


def test_skip_blocks_follow_the_switch():
    text = "G0 X10 Z5\n/G0 X30\nM30\n"
    assert pts(run(text))[-1] == (15.0, 5.0)
    mach = load_machine(None)
    import dataclasses
    assert pts(run(text, machine=dataclasses.replace(mach, block_delete=True)))[-1] == (5.0, 5.0)


def test_labels_alone_with_block_numbers_and_on_blocks():
    text = ("N10 R1=0\nN15 ANFANG:\nN20 R1=R1+1\nLOOP_2: G91 G1 Z-1 F100\nG90\n"
            "IF R1<2 GOTOB ANFANG\nIF R1==2 GOTOB LOOP_2\nM30\n")
    with pytest.raises(NCError) as e:  # LOOP_2 again and again: R1 stays 2
        run(text, step_limit=200)
    assert "step limit" in e.value.message
    text = "N10 R1=0\nN15 ANFANG:\nN20 R1=R1+1\nG91 G1 Z-1 F100\nG90\nIF R1<3 GOTOB ANFANG\nM30\n"
    assert pts(run(text))[-1] == (20.0, 17.0)


def test_a_string_holding_goto_is_not_a_jump():
    tp = run('_CNAME="GOTOF" R1=2\nIF R1==2 GOTOF END_1\nG0 X90\nEND_1: G0 X10\nM30\n')
    assert pts(tp)[-1] == (5.0, 20.0)


def test_gear_stages_are_accepted():
    assert pts(run("G0 X10 Z5 M41\nM40\nM30\n"))[-1] == (5.0, 5.0)


def test_sniff_recognises_802_programs():
    assert "siemens802" in sniff("%_N_PART_MPF\nG0 X1\n")
    assert "siemens802" in sniff("N10 G0 X1\nN20 R101=5 R102=2\n")
    assert "siemens802" in sniff("N10 LCYC95\n")
    assert "siemens802" in sniff("MA1: G1 X1\nGOTOB MA1\n")
    assert "siemens802" in sniff("G2 X10 Z5 CR=5\n")
    assert sniff("%1234\nG01 X10 Z5 F100\nM30\n") is None


ALARMS = [
    ("G1 X10 CR=\nM30", 1, 11, "word CR= has no value"),
    ("G2 X10 Z5\nM30", 1, 1, "G2 needs I/K, CR= or AR="),
    ("G2 X10 Z5 CR=1\nM30", 1, 11, "too small for the chord"),
    ("G2 X10 Z5 CR=5 I2\nM30", 1, 11, "CR= gives the arc with its end point"),
    ("G3 AR=400 I5\nM30", 1, 4, "AR400"),
    ("G2 X10 Z5 AR=90 I2\nM30", 1, 11, "AR= with the centre"),
    ("G5 X10 Z5\nM30", 1, 1, "G5 needs the intermediate point"),
    ("G5 X10 Z5 IX=10 KZ=5\nM30", 1, 11, "on one line"),
    ("G33 Z-10\nM30", 1, 1, "G33 needs the lead K"),
    ("G33 Z-10 I1 K1\nM30", 1, 10, "I (X) or K (Z)"),
    ("G4\nM30", 1, 1, "G4 needs F (seconds) or S (revolutions)"),
    ("G4 F1 S2\nM30", 1, 7, "not both"),
    ("G4 S10\nM30", 1, 4, "the spindle is stopped"),
    ("G74\nM30", 1, 1, "G74 names the axes"),
    ("G158 X1 F2\nM30", 1, 9, "word F has no meaning in a G158 block"),
    ("G25 S1 X2\nM30", 1, 1, "G25 takes S"),
    ("R1=\nM30", 1, 4, "nothing after '='"),
    ("R300=1\nM30", 1, 1, "R300"),
    ("R250=1\nM30", 1, 1, "R250-R299 are the cycles' internal parameters"),
    ("R1=SIN(\nM30", 1, 8, "bad expression"),
    ("R1=(1+2\nM30", 1, 8, "expected ')'"),
    ("R1=1/0\nM30", 1, 4, "division by zero"),
    ("R1=ATAN2(1)\nM30", 1, 4, "ATAN2 takes 2 arguments"),
    ("G1 U5\nM30", 1, 4, "unknown word U"),
    ("G1 X5 Y2\nM30", 1, 7, "no Y axis"),
    ("G1 X5 R5\nM30", 1, 9, "expected '=' after R5"),
    ("G1 X10 F100 AR=30\nM30", 1, 13, "word AR has no meaning in G1 block"),
    ("G1 X10 CHF=2 RND=1 F100\nM30", 1, 14, "CHF= (chamfer) and RND= (round) in one block"),
    ("G1 X10 CHF=2 F100\nG0 X20\nM30", 1, 8, "CHF=2 must be followed by a contour element"),
    ("G0 X20 Z0\nG1 Z-10 RND=30 F100\nG2 X0 Z-20 CR=10\nM30", 2, 9, "RND=30 does not fit the element it ends"),
    ("G0 X20 Z0\nG1 Z-10 F100\nG2 X0 Z-20 CR=10 RND=2\nG1 X2\nM30", 3, 18,
     "RND=2 does not fit the next element (line 4)"),
    ("G0 X20 Z0\nG1 Z-10 RND=1 F100\nG2 X20 Z-10 I-5\nM30", 2, 9, "RND=1 before a full circle"),
    ("GOTOF\nM30", 1, 6, "GOTOF needs a label or a block number"),
    ("GOTOF NOWHERE\nM30", 1, 7, "no label NOWHERE after this block"),
    ("MA: G0 X1\nGOTOF MA\nM30", 2, 7, "(it is before it: GOTOB)"),
    ("IF R1 GOTO MA\nM30", 1, 7, "IF cond must be followed by GOTOF or GOTOB"),
    ("G99 X1\nM30", 1, 1, "unknown G code G99"),
    ("M17\n", 1, 1, "the main program ends with M2/M30"),
    ("RET\n", 1, 1, "the main program ends with M2/M30"),
    ("%_N_A_MPF\nG0 X1\nM30\n%_N_A_SPF\nRET", 4, 1, "program A is defined twice"),
    ("G0 X1\n%_N_A_MPF\nM30", 1, 1, "a block before the first program header"),
    ("%_N_A\nM30", 1, 1, "a program header is %_N_NAME_MPF"),
    ("_CNAME=5\nM30", 1, 8, "_CNAME takes a string"),
    ('_CNAME="ABC\nM30', 1, 8, "a string is not closed"),
    ("T1 D10\nM30", 1, 4, "D10"),
    ("L10 P3 X5\nM30", 1, 1, "a subprogram call stands alone in its block"),
    ("N10 L77\nM30", 1, 5, "subprogram L77 not found"),
    ("N10 G0 X1 \u20ac\nM30", 1, 11, "unexpected character"),
    ("G1 X10 SF=400\nM30", 1, 8, "SF400"),
    ("LIMS: G0 X1\nM30", 1, 1, "LIMS is a word of the language, not a label"),
    ("G1 X10 Z5 F0\nM30", 1, 0, "feed rate F is 0"),
    ("STOPRE X\nM30", 1, 8, "word X has no value"),
    ("G0 X10 Z5 M77\nM30", 1, 11, "unknown M code M77"),
    ("G17\nG0 G42 X10 Z5\nM30", 2, 4, "G42 needs the ZX plane: G18 must be active"),
]


@pytest.mark.parametrize("text,line,col,fragment", ALARMS)
def test_alarm_per_construct(text, line, col, fragment):
    with pytest.raises(NCError) as e:
        run(text)
    assert (e.value.line, e.value.col) == (line, col), e.value.one_line()
    assert fragment in e.value.message
    assert "\n" not in e.value.one_line()
