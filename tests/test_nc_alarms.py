"""One test per alarm class of issue 2: the alarm names the problem, the 1-based line and
column, and the block text; the CLI prints it as one line and exits 2."""
from __future__ import annotations

import subprocess
import sys

import pytest

from hnc_cam.errors import NCError
from hnc_cam.nc import run


def alarm(text: str, **kw) -> NCError:
    with pytest.raises(NCError) as ei:
        run(text, file="t.nc", **kw)
    e = ei.value
    assert e.file == "t.nc"
    return e


def prog(*blocks: str) -> str:
    return "%1\n" + "\n".join(blocks) + "\nM30\n"


def test_unknown_g_code():
    e = alarm(prog("G92 X0 Z0", "N2 G00 G07 X1"))
    assert "unknown G code G07" in e.message
    assert (e.line, e.col) == (3, 8)
    assert e.block == "N2 G00 G07 X1"


def test_unknown_m_code():
    # M10 is in neither the CNC's own codes nor the default machine's PLC table
    e = alarm(prog("G00 X10 M10"))
    assert "unknown M code M10" in e.message and (e.line, e.col) == (2, 9)
    assert '[m_codes]' in e.message and 'M10 = "other"' in e.message


def test_unknown_word():
    e = alarm(prog("G00 X10 H5"))
    assert "unknown word H" in e.message and e.col == 9


def test_unknown_keyword():
    e = alarm(prog("#1 = FOO[2]"))
    assert "unknown word 'FOO'" in e.message and e.col == 6


def test_word_without_meaning_in_block():
    e = alarm(prog("G00 X10 K5"))
    assert "word K has no meaning" in e.message and e.col == 9


@pytest.mark.parametrize("block,letter", [
    ("G00 X123456", "X"), ("S10000", "S"), ("G01 Z1 F30000", "F"), ("T10000", "T"), ("M100", "M"),
    ("G1.5", "G"), ("G120", "G"),
])
def test_value_out_of_range(block, letter):
    e = alarm(prog(block))
    assert "value out of range" in e.message
    assert e.col == block.index(letter) + 1


def test_value_out_of_range_from_an_expression():
    e = alarm(prog("#1=200000", "G00 X[#1]"))
    assert "value out of range" in e.message and e.line == 3


def test_missing_required_word_arc():
    e = alarm(prog("G92 X0 Z0", "G02 X10 Z-5 F100"))
    assert "missing required word" in e.message and "R or I/K" in e.message


def test_missing_required_word_dwell_and_call():
    assert "G04 needs P" in alarm(prog("G04")).message
    assert "missing required word P" in alarm(prog("M98 L2")).message


def test_chamfer_longer_than_segment():
    e = alarm(prog("G92 X0 Z0", "G01 Z-2 C3 F100", "X20"))
    assert "longer than the segment" in e.message
    assert (e.line, e.col) == (3, 9)


def test_round_longer_than_next_segment():
    e = alarm(prog("G92 X0 Z0", "G01 Z-20 R5 F100", "X4"))
    assert "longer than the next segment" in e.message


def test_chamfer_must_be_followed_by_a_line():
    e = alarm(prog("G92 X0 Z0", "G01 Z-20 C2 F100", "G02 X10 Z-25 R5"))
    assert "must be followed by a G01 line" in e.message and e.line == 3


def test_arc_radius_too_small():
    e = alarm(prog("G92 X0 Z0", "G02 X20 Z-20 R5 F100"))
    assert "too small for the chord" in e.message and e.col == 14


def test_arc_end_not_on_circle():
    e = alarm(prog("G92 X0 Z0", "G02 X20 Z-20 I0 K-5 F100"))
    assert "arc end not on the circle" in e.message


def test_m99_outside_subprogram():
    e = alarm(prog("M99"))
    assert "M99 outside a subprogram" in e.message and e.line == 2


def test_subprogram_not_found():
    e = alarm(prog("M98 P1234"))
    assert "subprogram %1234 not found" in e.message and e.col == 5


def test_nesting_too_deep():
    text = "%1\nM98 P2\nM30\n%2\nM98 P2\nM99\n"
    e = alarm(text)
    assert "nesting too deep" in e.message and e.line == 5


def test_undefined_variable_read():
    e = alarm(prog("#1=#2+1"))
    assert "undefined variable #2" in e.message and "never assigned" in e.message


def test_undefined_variable_number():
    e = alarm(prog("#1=#5000"))
    assert "undefined variable #5000" in e.message


def test_invalid_variable():
    e = alarm(prog("#1=1.5", "#2=#[#1]"))
    assert "invalid variable" in e.message and e.line == 3


def test_read_only_variable():
    assert "read-only" in alarm(prog("#1000=5")).message


def test_division_by_zero():
    e = alarm(prog("#1=0", "#2=5/#1"))
    assert "division by zero" in e.message and (e.line, e.col) == (3, 4)


def test_sqrt_of_negative():
    assert "SQRT of a negative" in alarm(prog("#1=SQRT[-1]")).message


@pytest.mark.parametrize("stmt", ["#1=[1+2", "#1=1+", "#1=", "G01 X[1+]", "#1=[2]]", "#1=SIN 2",
                                  "#1=2 3"])
def test_bad_expression(stmt):
    e = alarm(prog(stmt))
    assert "bad expression" in e.message
    assert e.line == 2 and e.col >= 1


def test_unclosed_if():
    e = alarm(prog("#1=1", "IF #1 EQ 1", "G00 X1"))
    assert "IF is never closed" in e.message and e.line == 3


def test_unclosed_while():
    e = alarm(prog("#1=1", "WHILE #1 LT 5", "#1=#1+1"))
    assert "WHILE is never closed" in e.message and e.line == 3


def test_endw_without_while():
    assert "ENDW without WHILE" in alarm(prog("ENDW")).message


def test_step_limit_exceeded():
    e = alarm(prog("#1=0", "WHILE 1", "#1=#1+1", "ENDW"), step_limit=1000)
    assert "step limit exceeded" in e.message


def test_end_of_file_without_m30():
    e = alarm("%1\nG92 X0 Z0\nG00 X10\n")
    assert "without M02/M30" in e.message and e.line == 3


def test_main_running_into_a_subprogram_header():
    e = alarm("%1\nG00 X10\n%2\nM99\n")
    assert "without M02/M30" in e.message and e.line == 2


def test_x_and_u_in_one_block():
    assert "X and U" in alarm(prog("G00 X1 U2")).message


def test_two_codes_of_one_group():
    assert "modal group 01" in alarm(prog("G00 G01 X1")).message


def test_duplicate_word():
    assert "appears twice" in alarm(prog("G00 X1 X2")).message


def test_compensation_start_on_arc():
    from hnc_cam.tooling import Machine, Register
    m = Machine(registers={1: Register(number=1, radius=0.4, tip=3)})
    e = alarm(prog("T0101", "G92 X0 Z0", "G42 G02 X10 Z-5 R5 F100"), machine=m)
    assert "G00/G01" in e.message


def test_nonfinite_value():
    assert "finite" in alarm(prog("#1=EXP[700]*EXP[700]")).message


def test_cli_alarm_is_one_line_exit_2(tmp_path):
    p = tmp_path / "bad.nc"
    p.write_text("%1\nG92 X0 Z0\nG02 X20 Z-20 R5 F100\nM30\n")
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "run", str(p)], capture_output=True,
                       text=True)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith(f"{p}:3:14: alarm: arc radius R5 too small")
    assert "[G02 X20 Z-20 R5 F100]" in lines[0]
    assert "Traceback" not in r.stderr


def test_cli_missing_file(tmp_path):
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "run", str(tmp_path / "nope.nc")],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    # one line naming the file, without a made-up line/column
    assert r.stderr == f"error: {tmp_path / 'nope.nc'}: cannot read the program: No such file or directory\n"
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "run", str(tmp_path)],
                       capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.startswith(f"error: {tmp_path}: cannot read the program: ")
    assert len(r.stderr.splitlines()) == 1


def _chain(depth: int) -> str:
    """A main program and subprograms %2..%(depth+1), each calling the next: depth nested calls."""
    out = ["%1", "#50=0", "M98 P2", "M30"]
    for k in range(2, depth + 2):
        out += [f"%{k}", "#50=#50+1"] + ([f"M98 P{k + 1}"] if k < depth + 1 else []) + ["M99"]
    return "\n".join(out) + "\n"


def test_nesting_eight_calls_run_and_the_ninth_alarms():
    """Manual 3.4.4: nesting depth at most nine levels (the main program and 8 calls)."""
    from hnc_cam.nc import parser
    from hnc_cam.nc.interp import Interp
    it = Interp(parser.load(_chain(8)))
    it.run()
    assert it._read(50) == 8
    e = alarm(_chain(9))
    # the 9th M98 sits in %9 (the 8th subprogram): line of "M98 P10"
    assert "nesting too deep" in e.message
    assert e.block == "M98 P10" and e.line == _chain(9).splitlines().index("M98 P10") + 1


def test_alarm_inside_a_subprogram_points_at_its_line_in_the_file():
    text = "%1\nG92 X0 Z0\nM98 P2\nM30\n%2\nG01 X10 F100\nG02 X20 Z-20 R1\nM99\n"
    e = alarm(text)
    assert (e.line, e.col) == (7, 14) and e.block == "G02 X20 Z-20 R1"
    e = alarm("%1\nM98 P2\nM30\n%2\n#1=#7/0\nM99\n")
    assert "division by zero" in e.message and e.line == 5
