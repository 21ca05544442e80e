"""The FANUC 0i-T executor (hnc_cam.dialect.fanuc0it.codes): positions, times and alarms.

The first part runs the FANUC executor behind the HNC reader (the program texts are read by
``hnc_cam.nc.parser``: ``%n`` headers, plain words), so what is asserted is the execution of
the codes, calls and memory, whatever the FANUC reader does; the second part runs FANUC
texts (``%`` / ``O`` framing, decimal points, GOTO, ``,C``) through the FANUC reader and the
``hnc-cam run --dialect fanuc0it`` command.
"""
from __future__ import annotations

import dataclasses
import importlib.util
import math
import subprocess
import sys

import pytest

from hnc_cam import dialect, nc
from hnc_cam.dialect.hnc21t import HncSyntax
from hnc_cam.errors import NCError

EXEC = dataclasses.replace(dialect.get("fanuc0it"), syntax_factory=HncSyntax)
HAAS_EXEC = dataclasses.replace(dialect.get("haas"), syntax_factory=HncSyntax)


def run(text, **kw):
    kw.setdefault("start", (0.0, 0.0))
    return nc.run(text, dialect=kw.pop("dialect", EXEC), **kw)


def ends(tp, kinds=("rapid", "line", "arc")):
    return [tuple(round(v, 6) for v in m.end) for m in tp.moves if m.kind in kinds]


def alarm(text, **kw):
    with pytest.raises(NCError) as e:
        run(text, **kw)
    return e.value


# ------------------------------------------------------------------------------ motion


def test_x_is_a_diameter_and_u_w_are_incremental():
    tp = run("%1\nG00 X40 Z2\nG01 U-10 W-12 F0.2\nX50 W-3\nM30\n")
    assert ends(tp)[-2:] == [(15.0, -10.0), (25.0, -13.0)]


def test_x_and_u_in_one_block_is_an_alarm():
    e = alarm("%1\nG00 X40 U2 Z2\nM30\n")
    assert (e.line, e.col) == (2, 9) and "X and U" in e.message


def test_g90_is_the_turning_cycle_and_g91_does_not_exist():
    e = alarm("%1\nG91 G00 U2\nM30\n")
    assert e.line == 2 and "G91" in e.message and "system A" in e.message


def test_g50_sets_the_position_without_moving():
    tp = run("%1\nG50 X100 Z50\nG00 X20 Z2\nM30\n", start=(30.0, 80.0))
    # the tool stood at X60 Z80 (work); G50 makes that X100 Z50: the move ends at X20 Z2
    assert not any(m.end == (30.0, 80.0) and m.kind != "rapid" for m in tp.moves)
    assert ends(tp)[-1] == (10.0, 2.0)
    assert tp.moves[0].start == (50.0, 50.0)


def test_g50_s_caps_the_constant_surface_speed():
    tp = run("%1\nG50 S300\nM03 S200\nG96 S100\nG01 X2 Z0 F0.1\nG01 X100\nM30\n")
    near_axis, far = tp.moves[0], tp.moves[1]
    assert near_axis.spindle == 300.0  # 100 m/min at r 0.5 would be 31831 rpm
    assert far.spindle <= 300.0
    tp = run("%1\nM03 S200\nG96 S100\nG01 X2 Z0 F0.1\nM30\n")
    assert tp.moves[0].spindle == 3000.0  # no G50 S: the machine's limit


def test_g98_g99_feeds_and_g04_times():
    tp = run("%1\nM03 S500\nG00 X20 Z0\nG01 Z-10 F0.2\nG98 G01 Z-20 F100\nG04 P500\n"
             "G04 X1.5\nG04 U2\nM30\n")
    lines = [m for m in tp.moves if m.kind == "line"]
    assert lines[0].feed == pytest.approx(100.0) and lines[0].duration == pytest.approx(6.0)  # G99
    assert lines[1].feed == 100.0 and lines[1].duration == pytest.approx(6.0)  # G98
    assert [m.duration for m in tp.moves if m.kind == "dwell"] == [0.5, 1.5, 2.0]


def test_g04_p_is_whole_milliseconds():
    e = alarm("%1\nG04 P1.5\nM30\n")
    assert e.line == 2 and "milliseconds" in e.message


def test_g28_u0_w0_goes_straight_to_the_reference_point():
    tp = run("%1\nG00 X50 Z10\nG28 U0 W0\nM30\n")
    assert ends(tp)[-1] == (100.0, 150.0)  # reference X200 (diameter) Z150
    g28 = [m for m in tp.moves if m.op == "G28"]
    assert g28[0].start == (25.0, 10.0)


def test_g28_through_an_intermediate_point():
    tp = run("%1\nG00 X50 Z10\nG28 X80 Z20\nM30\n")
    g28 = [m for m in tp.moves if m.op == "G28"]
    assert (40.0, 20.0) in [m.end for m in g28] and g28[-1].end == (100.0, 150.0)


def test_unknown_m_code_is_a_warning_not_an_alarm():
    tp = run("%1\nM41\nG00 X10 Z0\nM30\n")
    assert any("M41" in w.message for w in tp.warnings)
    assert ends(tp)[-1] == (5.0, 0.0)


# ------------------------------------------------------------------------------ calls


def test_m98_p_four_plus_four_digits_and_p_l():
    tp = run("%1\nM98 P30010\nM98 P10 L2\nM30\n%10\nG00 U2\nM99\n")
    assert ends(tp) == [(1.0, 0.0), (2.0, 0.0), (3.0, 0.0), (4.0, 0.0), (5.0, 0.0)]


def test_m98_shares_the_callers_locals_g65_does_not():
    tp = run("%1\n#1=7\nM98 P10\nG00 X#1 Z0\nG65 P10 A3\nG00 X#1 Z1\nM30\n%10\n#1=#1+1\nM99\n")
    assert ends(tp) == [(4.0, 0.0), (4.0, 1.0)]  # M98 changed #1 to 8; G65's #1 was its own


def test_g65_argument_specification_i():
    tp = run("%1\nG65 P9010 A1 B2 X30 M5 Z-4 R0.5\nG00 X#100 Z#101\nM30\n"
             "%9010\n#100=#24+#1\n#101=#26+#13+#2+#18\nM99\n")
    assert ends(tp)[-1] == (15.5, 3.5)


def test_g65_missing_argument_is_null():
    tp = run("%1\nG65 P9010 A1\nG00 X#100 Z0\nM30\n%9010\n#100=#1+#2+#24\nM99\n")
    assert ends(tp)[-1] == (0.5, 0.0)


def test_g66_calls_after_each_move_until_g67():
    tp = run("%1\nG66 P9011 A1\nG00 X10 Z0\nG00 X20\nG67\nG00 X30\nM30\n%9011\nG01 W-#1 F0.1\nM99\n")
    assert ends(tp) == [(5.0, 0.0), (5.0, -1.0), (10.0, -1.0), (10.0, -2.0), (15.0, -2.0)]


def test_m99_p_returns_to_a_block_of_the_caller():
    tp = run("%1\nM98 P10\nG00 X2 Z0\nN50 G00 X4 Z0\nM30\n%10\nM99 P50\n")
    assert ends(tp) == [(2.0, 0.0)]


def test_m99_p_to_a_missing_block_is_an_alarm():
    e = alarm("%1\nM98 P10\nM30\n%10\nM99 P77\n")
    assert e.line == 5 and "N77" in e.message and e.col == 5


def test_m99_in_the_main_program_is_an_alarm():
    e = alarm("%1\nG00 X2 Z0\nM99\n")
    assert e.line == 3 and e.col == 1 and "main program" in e.message


def test_missing_subprogram_and_nesting_limits():
    e = alarm("%1\nM98 P44\nM30\n")
    assert e.line == 2 and "O0044" in e.message
    e = alarm("%1\nG65 P10\nM30\n%10\nG65 P10\nM99\n")
    assert e.line == 5 and "nested" in e.message
    e = alarm("%1\nM98 P10\nM30\n%10\nM98 P10\nM99\n")
    assert e.line == 5 and "nesting" in e.message


# ------------------------------------------------------------------------------ memory


def test_null_rules():
    tp = run("%1\n#1=#0\n#2=#1*5\n#100=#2+1\nG00 X#100 Z#1\nM30\n")
    assert ends(tp) == [(0.5, 0.0)]  # Z#1 with #1 null is left out


def test_commons_and_kept_commons_and_unknown_variables():
    tp = run("%1\n#100=4\n#500=6\nG00 X#100 Z#500\nM30\n")
    assert ends(tp)[-1] == (2.0, 6.0)
    e = alarm("%1\n#40=1\nM30\n")
    assert e.line == 2 and "#40" in e.message
    e = alarm("%1\n#0=1\nM30\n")
    assert e.line == 2 and "#0" in e.message
    e = alarm("%1\nG00 X[#60+1]\nM30\n")
    assert e.line == 2 and "#60" in e.message


def test_variable_number_written_with_a_decimal_point():
    """``#[30.0]`` in a word is variable #30 (the reader hands the number's text); ``#[30.5]``
    is an alarm at its line, not a crash."""
    text = "%\nO0001\n#30=5.\nG00 X#[30.0] Z#[30.] \nM30\n%\n"
    tp = nc.run(text, dialect="fanuc0it", start=(0.0, 0.0))
    assert ends(tp)[-1] == (2.5, 5.0)
    with pytest.raises(NCError) as e:
        nc.run(text.replace("#[30.]", "#[30.5]"), dialect="fanuc0it", start=(0.0, 0.0))
    assert e.value.line == 4 and "#30.5" in e.value.message


def test_shared_warning_names_the_dialects_g_code():
    """Feed per revolution with the spindle stopped: the warning names FANUC's G99 (HNC's
    text names G95); the move's time is 0 either way."""
    tp = nc.run("%\nO0001\nG99 M05\nG00 X20. Z2.\nG01 Z-5. F0.2\nM30\n%\n", dialect="fanuc0it")
    msgs = [w.message for w in tp.warnings if w.line == 5]
    assert any(m.startswith("feed per revolution (G99) with the spindle stopped") for m in msgs)
    assert not any("G95" in m for w in tp.warnings for m in [w.message])
    assert [m.duration for m in tp.moves if m.line == 5] == [0.0]
    hnc = nc.run("%1\nG95 M05\nG00 X20 Z2\nG01 Z-5 F0.2\nM30\n")
    assert any(w.line == 4 and w.message.startswith("feed per revolution (G95)") for w in hnc.warnings)


def test_system_variables():
    tp = run("%1\nG00 X40 Z2\nG01 Z-5 F0.3\n#100=#5001\n#101=#5002\n#102=#4001\n#103=#4005\n"
             "#104=#4109\n#3901=#3901+1\nG00 X#100 Z[#101+#102+#103/99+#104+#3901]\nM30\n")
    assert ends(tp)[-1] == pytest.approx((20.0, -5.0 + 1 + 1 + 0.3 + 1))


def test_macro_alarm_3000_stops_with_its_number():
    e = alarm("%1\nG00 X10 Z0\n#3000=12\nM30\n")
    assert e.line == 3 and e.message.startswith("macro alarm 3012")


def test_3006_stops_with_a_message_and_the_run_goes_on():
    tp = run("%1\n#3006=1\nG00 X10 Z0\nM30\n")
    assert ends(tp) == [(5.0, 0.0)] and any("#3006" in w.message for w in tp.warnings)


# ------------------------------------------------------------------------------ Haas


def test_haas_m97_local_subprogram():
    tp = run("%1\nM97 P100\nG00 X6 Z0\nM30\nN100 G00 X2 Z0\nM99\n", dialect=HAAS_EXEC)
    assert ends(tp) == [(1.0, 0.0), (3.0, 0.0)]
    e = alarm("%1\nM97 P100\nM30\n", dialect=HAAS_EXEC)
    assert e.line == 2 and "N100" in e.message


# ------------------------------------------------------------------------------ FANUC reader

HAVE_READER = importlib.util.find_spec("hnc_cam.dialect.fanuc0it.syntax") is not None
needs_reader = pytest.mark.skipif(not HAVE_READER, reason="the FANUC reader is not there yet")


def cli(*args):
    return subprocess.run([sys.executable, "-m", "hnc_cam.cli", *args], capture_output=True,
                          text=True)


@needs_reader
def test_reproducer_fanuc_framed_program_runs(tmp_path):
    p = tmp_path / "o1234.nc"
    p.write_text("%\nO1234 (SHAFT)\nG21 G99 G40\nT0101\nG50 S2000\nG96 S180 M03\n"
                 "G00 X52. Z2.\nG01 Z-30. F0.25\nX56.\nG00 X100. Z100.\nM30\n%\n")
    r = cli("run", str(p), "--dialect", "fanuc0it")
    assert r.returncode == 0, r.stderr
    tp = nc.run_file(str(p), dialect="fanuc0it")
    assert (26.0, -30.0) in [m.end for m in tp.moves]
    assert max(m.spindle for m in tp.moves) <= 2000.0
    r = cli("run", str(p))  # as HNC: the alarm says what the file looks like
    assert r.returncode == 2 and "FANUC" in r.stderr


@needs_reader
def test_reproducer_two_block_g71_runs(tmp_path):
    p = tmp_path / "g71.nc"
    p.write_text("%\nO0071\nT0101\nM03 S600\nG00 X52. Z2.\nG71 U1.5 R0.5\n"
                 "G71 P10 Q20 U0.4 W0.1 F0.25\nN10 G00 X30.\nG01 Z-20.\nX50. Z-30.\nN20 Z-40.\n"
                 "G70 P10 Q20 F0.1\nG00 X100. Z100.\nM30\n%\n")
    r = cli("run", str(p), "--dialect", "fanuc0it")
    assert r.returncode == 0, r.stderr
    tp = nc.run_file(str(p), dialect="fanuc0it")
    last_g71 = max(i for i, m in enumerate(tp.moves) if m.op == "G71")
    g70 = tp.moves[last_g71 + 1:]  # G70 runs N10..N20 themselves, at the G70 block's F0.1
    assert [(m.line, m.end) for m in g70 if m.kind == "line"] == [
        (9, (15.0, -20.0)), (10, (25.0, -30.0)), (11, (25.0, -40.0))]
    assert all(m.feed == pytest.approx(60.0) for m in g70 if m.kind == "line")  # 0.1 x 600 rpm
    assert tp.moves[-1].end == (50.0, 100.0)  # then the block after G70


@needs_reader
def test_goto_if_while_through_the_reader():
    text = ("%\nO0001\n#1=0\nN10 #1=#1+1\nIF [#1 LT 3] GOTO 10\n#2=0\nWHILE [#2 LT 2] DO1\n"
            "#2=#2+1\nEND1\nIF [#1 EQ 3] THEN #3=5\nG00 X[#1*2] Z[#2+#3]\nGOTO 99\nG00 X80.\n"
            "N99 M30\n%\n")
    tp = nc.run(text, dialect="fanuc0it", start=(0.0, 0.0))
    assert [m.end for m in tp.moves if m.kind == "rapid"][-1] == (3.0, 7.0)
    with pytest.raises(NCError) as e:
        nc.run("%\nO0001\nGOTO 55\nM30\n%\n", dialect="fanuc0it")
    assert e.value.line == 3 and "N55" in e.value.message


@needs_reader
def test_corner_words_through_the_reader():
    tp = nc.run("%\nO0001\nG00 X20. Z0.\nG01 Z-10. ,C2. F0.2\nX40.\nM30\n%\n", dialect="fanuc0it",
                start=(0.0, 0.0))
    ends_ = [m.end for m in tp.moves if m.kind == "line"]
    assert ends_[0] == (10.0, -8.0) and ends_[1] == (12.0, -10.0)
    assert all(math.isfinite(v) for m in tp.moves for v in m.end)


O1000 = """%
O1000
T0101
G99 G97 S800 M03
G00 X42.0 Z2.0
G65 P9010 A40.0 B30.0 C{step}
G00 X100.0 Z100.0
M30
O9010 (ROUGH OD BY PASSES: A START DIA, B FINAL DIA, C STEP DIA)
IF [#3 LE 0] THEN #3000=1 (STEP MUST BE POSITIVE)
#10=#1
WHILE [#10 GT #2] DO1
#10=#10-#3
IF [#10 LT #2] THEN #10=#2
G01 X#10 F0.2
Z-25.0
G00 U2.0
Z2.0
END1
M99
%
"""


@needs_reader
def test_macro_b_loop_of_the_reference_page():
    """docs/FANUC.md §15.6: passes at X38 .. X30 from Z2 to Z-25; C0 is macro alarm 3001."""
    tp = nc.run(O1000.format(step="2.0"), dialect="fanuc0it")
    cuts = [m for m in tp.moves if m.kind == "line" and m.end[1] == -25.0]
    assert [round(m.end[0] * 2, 6) for m in cuts] == [38.0, 36.0, 34.0, 32.0, 30.0]
    with pytest.raises(NCError) as e:
        nc.run(O1000.format(step="0"), dialect="fanuc0it")
    assert (e.value.line, e.value.col) == (10, 19)
    assert e.value.message == "macro alarm 3001: STEP MUST BE POSITIVE"


@needs_reader
def test_calls_through_the_reader(tmp_path):
    text = ("%\nO0001\nG00 X0. Z0.\nM98 P20010\nM98 P11 L2\nG66 P12 A1.\nG00 X10.\nG67\n"
            "M98 P13\nG00 X90.\nN40 M30\nO0010\nG00 W-1.\nM99\nO0011\nG00 U2.\nM99\nO0012\n"
            "G01 W-#1 F0.1\nM99\nO0013\nM99 P40\n%\n")
    p = tmp_path / "calls.nc"
    p.write_text(text)
    r = cli("run", str(p), "--dialect", "fanuc0it", "--json", "-")
    assert r.returncode == 0, r.stderr
    tp = nc.run(text, dialect="fanuc0it", start=(0.0, 0.0))
    assert [tuple(round(v, 6) for v in m.end) for m in tp.moves if m.kind != "dwell"][-6:] == [
        (0.0, -1.0), (0.0, -2.0), (1.0, -2.0), (2.0, -2.0), (5.0, -2.0), (5.0, -3.0)]


@needs_reader
def test_kept_variables_persist_between_runs(tmp_path):
    p = tmp_path / "count.nc"
    p.write_text("%\nO0001\n#500=#500+1\n#501=#0\nG00 X[#500*2] Z0.\nM30\n%\n")
    v = tmp_path / "vars.json"
    for n in (1, 2):
        r = cli("run", str(p), "--dialect", "fanuc0it", "--vars", str(v), "--json", "-")
        assert r.returncode == 0, r.stderr
        assert '"500": %d.0' % n in v.read_text() and '"501"' not in v.read_text()
    tp = nc.run(p.read_text(), dialect="fanuc0it", start=(0.0, 0.0), persist=str(v))
    assert tp.moves[-1].end == (3.0, 0.0)
    # an alarm stops the run: what was written before it is kept
    q = tmp_path / "alarm.nc"
    q.write_text("%\nO0002\n#502=7\n#3000=1 (STOP)\nM30\n%\n")
    r = cli("run", str(q), "--dialect", "fanuc0it", "--vars", str(v))
    assert r.returncode == 2 and "macro alarm 3001: STOP" in r.stderr
    assert '"502": 7.0' in v.read_text()


@pytest.mark.parametrize("body, what", [('{"400": 1}', "'400'"), ("[1]", "JSON object"),
                                        ('{"500": "x"}', "#500"), ("{", "not JSON")])
def test_bad_kept_variables_file_is_one_line(tmp_path, body, what):
    p = tmp_path / "a.nc"
    p.write_text("%\nO0001\n#500=1\nM30\n%\n")
    v = tmp_path / "v.json"
    v.write_text(body)
    r = cli("run", str(p), "--dialect", "fanuc0it", "--vars", str(v))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and what in r.stderr
    assert r.stderr.startswith(f"error: {v}: ")
    assert v.read_text() == body  # untouched
    r = cli("run", str(p), "--vars", str(v))  # the HNC-21T has no kept variables
    assert r.returncode == 2 and "FANUC-family" in r.stderr


@needs_reader
@pytest.mark.parametrize("body, line, col, text", [
    ("G00 X10. Z0.\nGOTO 55\n", 4, 6, "GOTO 55: no block N55 in this program"),
    ("#1=2.5\nGOTO #1\n", 4, 6, "the sequence number must be an integer 1-99999"),
    ("G70 P10\n", 3, 1, "missing required word Q"),
    ("G70 P10 Q20\n", 3, 5, "no block N10 (P)"),
    ("G65 A1.\n", 3, 1, "missing required word P"),
    ("M98 P44\n", 3, 5, "program O0044 not found"),
    ("#0=1\n", 3, 1, "#0 is always null"),
    ("M99\n", 3, 1, "M99 in the main program"),
    ("G00 X10. U2.\n", 3, 10, "X and U in one block"),
    ("G91 G00 U2.\n", 3, 1, "G-code system A"),
    ("G50\n", 3, 1, "G50 needs X/Z"),
    ("G50 U10.\n", 3, 5, "not U/W"),
    ("#3000=7 (BAD)\n", 3, 1, "macro alarm 3007: BAD"),
])
def test_alarms_point_at_their_line_and_column(body, line, col, text, tmp_path):
    src = "%\nO0001\n" + body + "M30\n%\n"
    with pytest.raises(NCError) as e:
        nc.run(src, dialect="fanuc0it")
    assert (e.value.line, e.value.col) == (line, col) and text in e.value.message
    p = tmp_path / "a.nc"
    p.write_text(src)
    r = cli("run", str(p), "--dialect", "fanuc0it")
    assert r.returncode == 2 and r.stderr.startswith(f"{p}:{line}:{col}: alarm: ")
    assert r.stderr.count("\n") == 1


def test_g65_l_repeats_with_fresh_locals_m98_l_shares_them():
    tp = run("%1\nG65 P10 L3 A1\nM30\n%10\n#1=#1+1\nG00 U#1\nM99\n")
    assert ends(tp) == [(1.0, 0.0), (2.0, 0.0), (3.0, 0.0)]  # #1 = 2 on every run
    tp = run("%1\n#1=1\nM98 P10 L3\nM30\n%10\n#1=#1+1\nG00 U#1\nM99\n")
    assert ends(tp) == [(1.0, 0.0), (2.5, 0.0), (4.5, 0.0)]  # 2, 3, 4: the caller's #1


@needs_reader
def test_haas_accepts_g10_and_g187_without_effect_and_refuses_g154():
    tp = nc.run("%\nO0001\nG187 P1 E0.01\nG10 P1 X0. Z0.\nG00 X10. Z0.\nM30\n%\n", dialect="haas",
                start=(0.0, 0.0))
    assert [m.end for m in tp.moves] == [(5.0, 0.0)]
    with pytest.raises(NCError) as e:
        nc.run("%\nO0001\nG187 P1\nM30\n%\n", dialect="fanuc0it")
    assert e.value.line == 3 and "G187" in e.value.message
    with pytest.raises(NCError) as e:
        nc.run("%\nO0001\nG154 P1\nM30\n%\n", dialect="haas")
    assert e.value.line == 3 and "G54-G59" in e.value.message
