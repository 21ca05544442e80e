"""Macro B (manual §3.4, appendix 1): variables, levels, expressions, IF/WHILE, calls."""
from __future__ import annotations

import math

import pytest

from hnc_cam.nc import parser
from hnc_cam.nc.interp import Interp
from hnc_cam.tooling import Machine, Register


def interp(text: str, **kw) -> Interp:
    it = Interp(parser.load(text, "t.nc"), kw.pop("machine", None), **kw)
    it.run()
    return it


def g(text: str, *names: int) -> list:
    """Globals #names after running ``text`` (wrapped as a main program)."""
    it = interp("%1\n" + text + "\nM30\n")
    return [it._read(n, strict_vacant=False) for n in names]


@pytest.mark.parametrize("expr,value", [
    ("1+2*3", 7), ("[1+2]*3", 9), ("10-4-3", 3), ("8/4/2", 1), ("-2*3", -6), ("2*-3", -6),
    ("--2", 2), ("1+2 EQ 3", 1), ("2 GT 3", 0), ("3 GE 3", 1), ("2 LT 3 AND 3 LT 4", 1),
    ("1 EQ 2 OR 2 EQ 2", 1), ("NOT 0", 1), ("NOT 1 EQ 1", 0), ("1 NE 2", 1), ("5 LE 5", 1),
    ("ABS[-3]", 3), ("INT[2.7]", 2), ("INT[-2.7]", -2), ("SIGN[-4]", -1), ("SIGN[0]", 0),
    ("SQRT[16]", 4), ("EXP[0]", 1), ("PI", math.pi), ("TRUE", 1), ("FALSE", 0),
    ("COS[55*PI/180]", math.cos(math.radians(55))), ("SIN[PI/2]", 1), ("TAN[PI/4]", 1),
    ("ATAN[1]", math.pi / 4), ("ATAN2[1, -1]", 3 * math.pi / 4), ("175/SQRT[2]*COS[55*PI/180]",
                                                              175 / math.sqrt(2) * math.cos(math.radians(55))),
])
def test_expressions(expr, value):
    (v,) = g(f"#50={expr}", 50)
    assert v == pytest.approx(value)


def test_comparison_tolerance_lets_the_loop_reach_its_end():
    it = interp("%1\n#10=0\n#11=0\nWHILE #10 LE 16\n#11=#11+1\n#10=#10+0.08\nENDW\nM30\n")
    assert it._read(11) == 201


def test_if_else_endif():
    assert g("#1=5\nIF #1 GT 3\n#50=1\nELSE\n#50=2\nENDIF", 50) == [1]
    assert g("#1=1\nIF #1 GT 3\n#50=1\nELSE\n#50=2\nENDIF", 50) == [2]
    assert g("#50=0\nIF [1 EQ 2] OR [2 EQ 2]\n#50=7\nENDIF", 50) == [7]


def test_nested_while_and_if():
    v = g("#50=0\n#1=0\nWHILE #1 LT 10\n#1=#1+1\nIF [#1 / 2] EQ INT[#1 / 2]\n#50=#50+#1\nENDIF\nENDW", 50)
    assert v == [30]


def test_indirect_variables_and_table():
    assert g("#1=3\n#[2100+#1]=7.5\n#50=#2103", 50) == [7.5]
    assert g("#1=60\n#[#1]=2\n#51=#[#1]*3", 60, 51) == [2, 6]


def test_several_assignments_on_one_line():
    assert g("#50=1 #51=#50+1", 50, 51) == [1, 2]


def test_globals_survive_calls_and_locals_do_not():
    text = "%1\n#1=11\n#50=1\nM98 P2\n#52=#1\nM30\n%2\n#1=99\n#50=#50+1\n#51=#1\nM99\n"
    it = interp(text)
    assert [it._read(n) for n in (50, 51, 52)] == [2, 99, 11]


def test_level_blocks_o0099():
    """Appendix 1: the main's #10 is level-0 #210... as the manual lists #200 + 50 * level."""
    text = ("o0099\ng92 X0 Z0\nN100 #10=98\nM98 P100\n#51=#210\nM30\n"
            "o100\nN200 #10=100\n#52=#210\n#53=#260\nM98 P110\nM99\n"
            "o110\nN300 #10=200\n#54=#210\n#55=#260\n#56=#310\nM99\n")
    it = interp(text)
    r = lambda n: it._read(n, strict_vacant=False)  # noqa: E731
    assert r(51) == 98  # main's #10 after the calls is still its own
    assert (r(52), r(53)) == (98, 100)
    assert (r(54), r(55), r(56)) == (98, 100, 200)


def test_call_arguments_and_ar():
    text = ("%1\nG92 X10 Z5\nG91\nM98 P2 X4 K2\nG90\nG65 P2 X4\nM30\n"
            "%2\n#50=#50+1\n#[60+#50*10]=AR[#23]\n#[61+#50*10]=AR[#10]\n#[62+#50*10]=AR[#25]\n"
            "#[63+#50*10]=#23\n#[64+#50*10]=#30\n#[65+#50*10]=#32\n#[66+#50*10]=#25\nM99\n")
    it = interp(text.replace("#50=#50+1", "IF AR[#1] EQ 0\n#50=#50+1\nENDIF").replace(
        "%1\n", "%1\n#50=0\n"))
    r = lambda n: it._read(n, strict_vacant=False)  # noqa: E731
    # first call in G91: X given incremental, K given, Z absent (reads 0)
    assert [r(n) for n in (70, 71, 72, 73, 74, 75, 76)] == [91, 91, 0, 4, 5.0, 5.0, 0]
    # second call (G65) in G90
    assert [r(n) for n in (80, 81, 82)] == [90, 0, 0]


def test_m98_repeat_count():
    it = interp("%1\n#50=0\nM98 P2 L4\nM30\n%2\n#50=#50+1\nM99\n")
    assert it._read(50) == 4


def test_g_from_a_variable_restores_modal_state():
    text = "%1\n#50=#1163\nG91\n#51=#1163\nG[#50]\n#52=#1163\nM30\n"
    it = interp(text)
    assert [it._read(n) for n in (50, 51, 52)] == [90, 91, 90]


def test_system_variables():
    m = Machine(work_offsets={"G54": (5.0, -7.0), "G55": (0.0, 0.0), "G56": (0.0, 0.0),
                              "G57": (0.0, 0.0), "G58": (0.0, 0.0), "G59": (0.0, 0.0)})
    text = ("%1\nG92 X40 Z10\n#50=#1020\n#51=#1022\n#52=#1009\nG37\n#53=#1009\n#54=#1040\n#55=#1042\n"
            "#56=#1152\nG01 X1 F10\n#57=#1152\n#58=#1000\n#59=#1030\nM30\n")
    it = interp(text, machine=m)
    r = lambda n: it._read(n)  # noqa: E731
    assert (r(50), r(51)) == (20.0, 10.0)  # positions: X as radius
    assert (r(52), r(53)) == (1.0, 0.0)
    assert (r(54), r(55)) == (5.0, -7.0)  # G54 origin, X as radius like every position
    assert (r(56), r(57)) == (0, 1)
    assert r(58) == pytest.approx(1.0 + r(59))


def test_tool_registers_readable_and_writable():
    m = Machine(registers={3: Register(number=3, z=-2.0, radius=0.8, tip=3)})
    it = interp("%1\n#50=#603\n#51=#703\n#703=0.4\n#52=#703\n#803=5\n#53=#803\nM30\n", machine=m)
    assert [it._read(n) for n in (50, 51, 52, 53)] == [-2.0, 0.8, 0.4, 5.0]


def test_expression_words():
    it = interp("%1\nG92 X0 Z0\n#1=10\nG01 X[#1*2] Z-#1 F100\nX#1 W-[#1/2]\nM30\n")
    assert [m.end for m in it.moves] == [pytest.approx((10.0, -10.0)), pytest.approx((5.0, -15.0))]


def test_the_manual_8002_parabola():
    text = ("%8002\n#10=0\n#11=0\nN10 G92 X0.0 Z0.0\nM03 S600\nWHILE #10LE16\n"
            "G90 G01 X[#10] Z[#11] F500\n#10=#10+0.08\n#11=#10*#10/8\nENDW\nG00 Z0 M05\nG00 X0\nM30\n")
    it = interp(text)
    feeds = [m for m in it.moves if m.kind == "line"]
    assert len(feeds) == 200
    for m in feeds:
        X = 2 * m.end[0]
        assert m.end[1] == pytest.approx(X * X / 8, abs=1e-9)
    assert 2 * feeds[-1].end[0] == pytest.approx(16.0)


def test_loop_is_compiled_once_and_fast():
    import time
    t0 = time.perf_counter()
    it = interp("%1\n#1=0\nWHILE #1 LT 20000\n#1=#1+1\nENDW\nM30\n")
    assert it._read(1) == 20000
    assert time.perf_counter() - t0 < 2.0


def test_if_with_assignment_on_its_line_as_the_appendix_prints_it():
    assert g("#1=91\nIF #1 EQ 91 #50=1 #51=2\n#52=3\nENDIF", 50, 51, 52) == [1, 2, 3]
    assert g("#50=0\n#1=90\nIF #1 EQ 91 #50=1\nENDIF", 50) == [0]


def test_parametric_family_macro_with_g65():
    """The family idea: one macro, dimensions as G65 arguments (D dia, Q length, C chamfer;
    L would be the repeat count)."""
    macro = ("%9001\nIF [AR[#3] EQ 0] OR [AR[#16] EQ 0]\nM99\nENDIF\n"
             "G00 X[#3-2*#2-4] Z2\nG01 X[#3-2*#2] Z0 F[#5]\nX#3 Z-#2 C0\nZ-#16\nG00 X[#3+4]\nZ2\nM99\n")
    main = "%1\nG92 X100 Z50\nM03 S800\nG65 P9001 D20 Q30 C1 F80\nG65 P9001 D30 Q10 C2 F80\nM30\n"
    it = interp(main + macro)
    ends = [(round(2 * m.end[0], 6), round(m.end[1], 6)) for m in it.moves if m.kind == "line"]
    assert ends == [(18, 0), (20, -1), (20, -30), (26, 0), (30, -2), (30, -10)]
    assert all(m.feed == 80 for m in it.moves if m.kind == "line")


def test_tool_registers_read_the_machine_files_registers(tmp_path):
    """#600+n / #700+n read register n of the machine in use (machine file entries win over the
    tool library; the default library's register 01 carries a CNMG120408, r 0.8)."""
    from hnc_cam.tooling import load_machine
    f = tmp_path / "m.toml"
    f.write_text("[[register]]\nnumber = 7\nx = -4.0\nz = 12.5\nz_wear = -0.05\nradius = 0.4\ntip = 2\n")
    m = load_machine(str(f))
    it = interp("%1\n#50=#607\n#51=#707\n#52=#701\n#53=#612\n#54=#712\nM30\n", machine=m)
    # #6nn is register n's Z geometry offset (the length register), #7nn its nose radius;
    # a register absent from the table reads 0 (a sharp point)
    assert [it._read(n) for n in (50, 51, 52, 53, 54)] == [12.5, 0.4, 0.8, 0.0, 0.0]


def test_locals_of_the_eighth_nested_call_are_its_own():
    calls = "".join(f"%{k}\n#5={k}\n" + (f"M98 P{k + 1}\n" if k < 9 else "#60=#5\n") + f"#[60+{k}]=#5\nM99\n"
                    for k in range(2, 10))
    it = interp("%1\n#5=1\nM98 P2\n#61=#5\nM30\n" + calls)
    # every level kept its own #5 through the calls below it; level k-1's block shows it
    assert [it._read(n) for n in range(60, 70)] == [9, 1, 2, 3, 4, 5, 6, 7, 8, 9]
    assert [it._read(200 + 50 * lv + 5) for lv in range(8)] == [1, 2, 3, 4, 5, 6, 7, 8]


def test_writing_a_work_origin_moves_the_work_system_not_the_tool():
    m = Machine(work_offsets={f"G{n}": (0.0, 0.0) for n in range(54, 60)})
    it = interp("%1\nG00 X40 Z10\n#1042=-50\n#1060=7\n#50=#1022\n#51=#1062\nG56\n#52=#1020\n"
                "G00 X40 Z10\nM30\n", machine=m)
    # G54's Z origin moved 50 toward the chuck: the same machine point reads Z60
    assert it._read(50) == 60.0 and it._read(51) == 0.0
    assert it._read(52) == 20.0 - 7.0  # G56 X origin 7 (radius)
    assert it.moves[-1].end == pytest.approx((20.0, 10.0))
    assert it.moves[-1].start[0] == pytest.approx(13.0)
