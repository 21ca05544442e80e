"""The interpreter never crashes, never runs away, and alarms in the right place.

Each case was found by the grammar/mutation fuzzer (``benchmarks/fuzz.py``) or by a user; each
is either an alarm ``FILE:LINE:COL: alarm: ...`` (one printable line, exit 2 on the command
line) or correct behaviour."""
from __future__ import annotations

import os
import subprocess
import sys
import time
from dataclasses import replace

import pytest

from hnc_cam.errors import NCError
from hnc_cam.nc import run, run_file
from hnc_cam.nc.interp import ProgramFileError
from hnc_cam.tooling import Machine, load_machine


def alarm(text: str, **kw) -> NCError:
    with pytest.raises(NCError) as ei:
        run(text, file="t.nc", **kw)
    e = ei.value
    line = e.one_line()
    assert "\n" not in line and "\r" not in line and line.isprintable(), line
    return e


def prog(*blocks: str) -> str:
    return "%1\n" + "\n".join(blocks) + "\nM30\n"


# ---------------------------------------------------------------- exceptions that were not alarms

def test_round_after_a_chamfer_that_took_the_whole_segment():
    # the chamfer C3 of line 2 consumes all of W3; the round R3 has no segment left
    e = alarm(prog("G1U6C3F100", "W3R3", "W4"))
    assert (e.line, e.col) == (3, 3) and "longer than the segment" in e.message


def test_g40_right_after_a_cycle_under_g41_is_a_plain_move():
    tp = run(prog("T4G41G80X1Z7F100", "G40G0X7"), start=(5.0, 10.0))
    last = tp.moves[-1]
    assert last.kind == "rapid" and last.end == pytest.approx((3.5, 10.0))
    assert last.comp == 40


@pytest.mark.parametrize("digits", [300, 400, 5000])
def test_huge_literal_in_an_expression(digits):
    text = prog("IF[[3]EQ1" + "0" * digits + "]", "G0X1", "ENDIF")
    if digits <= 308:  # a finite float: the comparison is false, the body skipped
        assert run(text).moves == []
    else:
        e = alarm(text)
        assert (e.line, e.col) == (2, 9) and "too large" in e.message


def test_block_number_of_5000_digits():
    e = alarm(prog("G0X1", "N" + "9" * 5000))
    assert (e.line, e.col) == (3, 1) and "out of range" in e.message
    assert len(e.block) < 200 and e.block.endswith("…")


@pytest.mark.parametrize("head", ["%³", "O³", "%١٢", "O1²"])
def test_non_ascii_digit_after_a_header_letter(head):
    e = alarm(head + "\nM30\n")
    assert e.line == 1 and "unexpected" in e.message


def test_program_number_too_long_is_not_a_header():
    e = alarm("O" + "1" * 5000 + "\nM30\n")
    assert e.line == 1


# ---------------------------------------------------------------- line ends and bytes

def test_lone_cr_ends_a_line():
    e = alarm("0\r0")
    assert (e.line, e.col) == (1, 1) and e.block == "0"
    # CR, LF and CRLF mixed: lines counted as an editor counts them
    e = alarm("%1\rG0X1\r\nG0X2\nG7\rM30\r")
    assert (e.line, e.col) == (4, 1) and e.block == "G7"
    tp = run("%1\rG0X10Z5\rG1X20F100\rM30\r", start=(0, 0))
    assert [m.line for m in tp.moves] == [2, 2, 3]


def test_nul_byte_is_an_alarm_even_in_a_comment_or_after_m30():
    for text, where in (("%1\nG0X1 (a\0b)\nM30\n", (2, 8)), ("%1\nM30\n\0\n", (3, 1)),
                        ("%1\nG0X1\0\nM30\n", (2, 5))):
        e = alarm(text)
        assert (e.line, e.col) == where and "NUL" in e.message
        assert "\\x00" in e.block


def test_control_bytes_are_escaped_in_the_alarm():
    e = alarm(prog("G0 X1 \x1b[31m \x0b Q\x07"))
    line = e.one_line()
    assert "\x1b" not in line and "\\x1b" in line and "\\x0b" in line
    assert e.line == 2


def test_a_ten_megabyte_line_is_refused_with_a_short_echo():
    big = "G0X1" + "Y" * 10_000_000
    t0 = time.perf_counter()
    e = alarm(prog(big))
    assert time.perf_counter() - t0 < 5
    assert e.line == 2 and "line too long" in e.message
    assert len(e.one_line()) < 400


def test_long_comment_is_linear():
    # 60,000 characters of comment after an assignment: was quadratic in the lexer (about 20 s)
    t0 = time.perf_counter()
    tp = run(prog("#1=1 (" + "a" * 60_000 + ")", "G0X[#1]"), start=(0, 0))
    assert time.perf_counter() - t0 < 2
    assert tp.moves[-1].end == (0.5, 0.0)
    t0 = time.perf_counter()
    alarm(prog("G1 " + " " * 60_000 + "#1=2"))
    assert time.perf_counter() - t0 < 2


# ---------------------------------------------------------------- files

def cli(*args):
    return subprocess.run([sys.executable, "-m", "hnc_cam.cli", *args], capture_output=True,
                          text=True, timeout=60)


def test_fifo_is_refused_without_waiting(tmp_path):
    fifo = tmp_path / "p.nc"
    os.mkfifo(fifo)
    with pytest.raises(ProgramFileError) as ei:
        run_file(str(fifo))
    assert "FIFO" in ei.value.message
    r = cli("run", str(fifo))
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr == f"error: {fifo}: cannot read the program: a FIFO (named pipe), not a regular file\n"


def test_dev_zero_is_refused():
    with pytest.raises(ProgramFileError) as ei:
        run_file("/dev/zero")
    assert "a device, not a regular file" in ei.value.message


def test_program_larger_than_the_limit(tmp_path):
    m = replace(load_machine(None), program_bytes=1000)
    p = tmp_path / "big.nc"
    p.write_text("%1\n" + "G0X1\n" * 300 + "M30\n")
    with pytest.raises(ProgramFileError) as ei:
        run_file(str(p), m)
    assert "1507 bytes" in ei.value.message and "program_bytes" in ei.value.message
    with pytest.raises(NCError):
        run(p.read_text(), m)


def test_binary_file_alarm_is_one_printable_line(tmp_path):
    p = tmp_path / "b.nc"
    p.write_bytes(b"%1\n\x1b[2J\xff\xfe\x07G0\n\x00\x01\n")
    r = cli("run", str(p))
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and r.stderr[:-1].isprintable()
    assert r.stderr.startswith(f"{p}:3:1: alarm: NUL character")


# ---------------------------------------------------------------- runaway programs

def timed_alarm(text: str, machine=None, seconds: float = 8.0) -> NCError:
    t0 = time.perf_counter()
    e = alarm(text, machine=machine)
    assert time.perf_counter() - t0 < seconds, e.one_line()
    return e


def test_endless_loop_of_moves_stops_at_the_move_limit():
    e = timed_alarm(prog("G1F100", "WHILE 1", "U1", "U-1", "ENDW"))
    assert "too many moves" in e.message and e.line in (4, 5)


def test_endless_loop_of_moves_under_compensation_is_bounded():
    m = replace(load_machine(None), move_limit=20_000)
    e = timed_alarm(prog("T0101", "G42 G1 X10 Z0 F100", "WHILE 1", "U1", "U-1", "ENDW"), m)
    assert "too many moves" in e.message and e.line in (5, 6)


def test_g76_with_tiny_q_in_a_loop():
    m = replace(load_machine(None), move_limit=50_000)
    e = timed_alarm(prog("G0X40Z5", "WHILE 1", "G76C1A60X30Z-30K1.3U0.1V0.1Q0.01F2", "ENDW"), m)
    assert e.line == 4


def test_g73_with_a_huge_pass_count():
    e = timed_alarm(prog("G0X100Z10", "G73U5W1R99999P1Q2X0.5Z0.1F100", "N1G1X20Z0", "N2G1Z-20"))
    assert (e.line, e.col) == (3, 8) and "cycle_passes" in e.message


def test_g73_whose_passes_would_exceed_the_moves():
    m = replace(load_machine(None), move_limit=1000)
    e = timed_alarm(prog("G0X100Z10", "G73U5W1R900P1Q2X0.5Z0.1F100", "N1G1X20Z0", "N2G1Z-20"), m)
    assert e.line == 3 and "[limits] moves" in e.message


def test_g71_with_a_tiny_depth_of_cut():
    e = timed_alarm(prog("G0X100Z5", "G71U0.0001R1P1Q2X0.4Z0.1F100", "N1G0X20", "N2G1Z-20"))
    assert (e.line, e.col) == (3, 4) and "cycle_passes" in e.message


def test_g71_small_depth_in_a_long_loop_stops_at_the_move_limit():
    m = replace(load_machine(None), move_limit=100_000)
    e = timed_alarm(prog("#1=0", "WHILE #1 LT 1000", "G0X100Z5", "G71U0.01R1P1Q2X0.4Z0.1F100",
                         "N1G0X20", "N2G1Z-20", "#1=#1+1", "ENDW"), m)
    assert "too many moves" in e.message and e.line == 5


def test_endless_loop_around_a_modal_cycle_word():
    e = timed_alarm(prog("WHILE 1", "G80", "ENDW"), seconds=20)
    assert "step limit" in e.message


def test_repeat_count_beyond_the_call_limit_alarms_at_once():
    e = timed_alarm("%1\nM98 P2 L4294967295\nM30\n%2\nM99\n", seconds=1)
    assert (e.line, e.col) == (2, 8) and "[limits] calls" in e.message


def test_calls_in_a_loop_stop_at_the_call_limit():
    m = replace(load_machine(None), call_limit=5000)
    e = timed_alarm("%1\nWHILE 1\nM98 P2 L10\nENDW\nM30\n%2\nM99\n", m)
    assert e.line == 3 and "too many subprogram runs" in e.message


# ---------------------------------------------------------------- the first line in execution order

def test_first_offending_line_before_an_unclosed_while():
    e = alarm(prog("G0X1", "G07", "WHILE 1", "G0X2"))
    assert e.line == 3 and "G07" in e.message


def test_unclosed_structure_is_reported_when_reached():
    e = alarm(prog("G0X1", "IF 1", "WHILE 1", "G0X2"))
    assert e.line == 3 and "IF is never closed" in e.message


def test_unmatched_endif_in_a_subprogram_that_never_runs_is_not_an_alarm():
    tp = run("%1\nG0X10Z5\nM30\n%2\nENDIF\nM99\n", start=(0, 0))
    assert tp.moves[-1].end == (5.0, 5.0)


def test_else_without_if_after_a_bad_block():
    e = alarm(prog("G0X1", "X1X2", "ELSE"))
    assert e.line == 3 and "twice" in e.message


# ---------------------------------------------------------------- M codes

def test_m_codes_come_from_the_machine():
    tp = run(prog("M03 S500", "M08 G0 X10", "G1 Z-5 F100 M09", "G1 Z-10"), start=(20, 5))
    cool = [(m.line, m.coolant) for m in tp.moves]
    assert cool[0] == (3, True) and (4, True) in cool and (5, False) in cool
    m = replace(load_machine(None), m_codes={3: "spindle_cw", 5: "spindle_stop", 20: "coolant_on",
                                             21: "coolant_off", 1: "optional_stop"})
    e = alarm(prog("M08"), machine=m)
    assert "unknown M code M08" in e.message and "[m_codes]" in e.message
    tp = run(prog("M20 G0 X10", "M01 G1 Z-5 F100 M21", "G1 Z-10"), m, start=(20, 5))
    assert [(mv.line, mv.coolant) for mv in tp.moves] == [(2, True), (3, True), (4, False)]
    assert any("optional stop" in w.message and w.line == 3 for w in tp.warnings)


def test_m_codes_table_in_a_machine_file(tmp_path):
    p = tmp_path / "m.toml"
    p.write_text('[m_codes]\nM10 = "other"\nM13 = "spindle_cw"\n')
    m = load_machine(p)
    assert m.m_codes[10] == "other" and m.m_codes[13] == "spindle_cw" and m.m_codes[8] == "coolant_on"
    tp = run(prog("M13 S400 M10", "G1 X10 F100"), m, start=(20, 5))
    assert tp.moves[0].spindle_dir == 3
    from hnc_cam.errors import ToolError
    for bad, words in (('M30 = "other"', "fixed by the CNC"), ('M10 = "coolant"', "is not one of"),
                       ('X10 = "other"', "not an M code")):
        p.write_text(f"[m_codes]\n{bad}\n")
        with pytest.raises(ToolError, match=words):
            load_machine(p)


def test_limits_table_in_a_machine_file(tmp_path):
    p = tmp_path / "m.toml"
    p.write_text("[limits]\nmoves = 10\ncycle_passes = 7\ncalls = 3\nline_chars = 80\n")
    m = load_machine(p)
    assert (m.move_limit, m.pass_limit, m.call_limit, m.line_chars) == (10, 7, 3, 80)
    e = alarm(prog("G1F100", "WHILE 1", "U1", "U-1", "ENDW"), machine=m)
    assert "limit of 10 moves" in e.message
    from hnc_cam.errors import ToolError
    # the machine file's keys go through hnc_cam.schema: FILE:LINE, did-you-mean, ranges
    p.write_text("[limits]\nmoves = 10\nmovez = 10\n")
    with pytest.raises(ToolError, match=rf"^{p}:3: unknown key 'movez' \(did you mean 'moves'\?\)"):
        load_machine(p)
    p.write_text("[limits]\n\nmoves = 0\n")
    with pytest.raises(ToolError, match=rf"^{p}:3: moves = 0 is out of range"):
        load_machine(p)
    p.write_text("[machine]\nrapid_x = 4000\nstep_limt = 5\n")
    with pytest.raises(ToolError, match=rf"^{p}:3: unknown key 'step_limt' \(did you mean 'step_limit'\?\)"):
        load_machine(p)
    p.write_text('[m_codes]\nM08 = "coolnt_on"\n')
    with pytest.raises(ToolError, match=rf'^{p}:2: M08 = "coolnt_on" is not one of: .*did you mean "coolant_on"'):
        load_machine(p)


# ---------------------------------------------------------------- messages

def test_fanuc_framed_program_is_named():
    e = alarm("%\nO1234\nG0X10\nM30\n%\n")
    assert e.line == 1 and "FANUC-framed" in e.message and "line 2" in e.message


def test_api_and_cli_start_at_the_reference_point(tmp_path):
    text = prog("G0 X20 Z5", "G1 Z-10 F100")
    p = tmp_path / "a.nc"
    p.write_text(text)
    tp = run(text, file=str(p))
    assert tp.moves[0].start == pytest.approx(load_machine(None).reference)
    assert run(text, Machine()).moves[0].start == Machine().reference
    r = cli("run", str(p))
    assert r.returncode == 0
    assert tp.summary() in r.stdout


def test_css_per_rev_feed_without_f_and_spindle_stopped():
    # G95 G96 and no F yet: the machine's default feed (mm/min, with a warning); the spindle is
    # stopped, so there is no speed to integrate over (was a ZeroDivisionError)
    tp = run("%1\nG95 G97\nG96 G1 X0 Z9\nM30\n", start=(0, 0))
    assert [(m.kind, m.end) for m in tp.moves] == [("line", (0.0, 9.0))]
    assert tp.moves[0].duration == pytest.approx(9 / 100 * 60)
    assert any("default feed" in w.message for w in tp.warnings)


@pytest.mark.parametrize("bom", [b"\xff\xfe", b"\xfe\xff"])
def test_utf16_program_is_one_line_naming_the_encoding(tmp_path, bom):
    body = "%1\nG00 X20 Z2\nM30\n".encode("utf-16-le" if bom == b"\xff\xfe" else "utf-16-be")
    p = tmp_path / "u16.nc"
    p.write_bytes(bom + body)
    r = cli("run", str(p))
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and r.stderr.startswith(f"error: {p}: cannot read the program: UTF-16")
    assert all(c.isprintable() for c in r.stderr.rstrip("\n"))
