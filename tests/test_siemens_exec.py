"""The SINUMERIK 802 executor (hnc_cam.dialect.siemens802.codes): positions after each
construct, calls, jumps, R parameters, tools and the cycle context members LCYC cycles use."""
from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import pytest

from hnc_cam import dialect, nc
from hnc_cam.errors import NCError
from hnc_cam.tooling import Register, load_machine

S802 = dialect.get("siemens802")


def run(text, **kw):
    kw.setdefault("start", (50.0, 50.0))
    return nc.run(text, dialect=kw.pop("dialect", S802), **kw)


def pts(tp, kind=None):
    return [(round(m.end[0], 4), round(m.end[1], 4)) for m in tp.moves if kind is None or m.kind == kind]


def test_chamfer_chf_is_the_chamfer_length():
    tp = run("G0 X20 Z0\nG1 X20 Z-10 CHF=2.828427 F100\nX40\nM30\n")
    lines = [m for m in tp.moves if m.kind == "line"]
    # 90 degree corner at X20 Z-10: CHF= 2*sqrt(2) cuts 2 mm along each line
    assert [(round(m.end[0], 4), round(m.end[1], 4)) for m in lines] == [(10.0, -8.0), (12.0, -10.0), (20.0, -10.0)]


def test_round_rnd_is_tangent_to_both_lines():
    tp = run("G0 X20 Z0\nG1 Z-10 RND=3 F100\nX40\nM30\n")
    arc = [m for m in tp.moves if m.kind == "arc"][0]
    assert pts(tp, "line") == [(10.0, -7.0), (20.0, -10.0)]
    assert arc.end == pytest.approx((13.0, -10.0)) and arc.center == pytest.approx((13.0, -7.0))


def test_l10_p3_runs_three_times_and_m2_in_a_subprogram_returns():
    text = ("%_N_MAIN_MPF\nG0 X20 Z0\nL10 P3\nG0 X60\nM30\n"
            "%_N_L10_SPF\nG91 G1 Z-2 F100\nG90\nM2\n")
    tp = run(text)
    assert pts(tp, "line") == [(10.0, -2.0), (10.0, -4.0), (10.0, -6.0)]
    assert pts(tp)[-1] == (30.0, -6.0)


def test_named_subprogram_and_m17():
    text = ("%_N_MAIN_MPF\nG0 X20 Z0\nKONTUR_1\nM30\n%_N_KONTUR_1_SPF\nG1 X30 F100\nM17\n")
    assert pts(run(text), "line") == [(15.0, 0.0)]


def test_call_names_starting_with_an_address_letter():
    """A name such as THREADED_STUD_C1 or GX_SUB is a call, unnumbered or numbered; G0 and
    X20 stay words."""
    text = ("%_N_MAIN_MPF\nG0 X20 Z0\nTHREADED_STUD_C1\nN5 GX_SUB P2\nM30\n"
            "%_N_THREADED_STUD_C1_SPF\nG1 X30 F100\nRET\n%_N_GX_SUB_SPF\nG91 G1 Z-2\nG90\nRET\n")
    assert pts(run(text), "line") == [(15.0, 0.0), (15.0, -2.0), (15.0, -4.0)]


def test_main_program_is_the_first_mpf_even_after_a_subprogram():
    text = "%_N_L1_SPF\nG1 X10 F100\nRET\n%_N_PART_MPF\nG0 X20 Z5\nL1\nM30\n"
    assert pts(run(text))[-1] == (5.0, 5.0)


def test_subprogram_from_a_file_beside_the_program(tmp_path):
    (tmp_path / "L20.SPF").write_text("%_N_L20_SPF\n;$PATH=/_N_SPF_DIR\nG1 X30 F100\nRET\n")
    main = tmp_path / "PART.MPF"
    main.write_text("G0 X20 Z0\nL20 P2\nM30\n")
    tp = nc.run_file(str(main), dialect="siemens802", start=(50.0, 50.0))
    assert pts(tp, "line") == [(15.0, 0.0)]
    (tmp_path / "L21.SPF").write_text("G1 X30 F100\nG1 X=R1+ Z0\nRET\n")
    main.write_text("G0 X20 Z0\nL21\nM30\n")
    with pytest.raises(NCError) as e:
        nc.run_file(str(main), dialect="siemens802", start=(50.0, 50.0))
    assert e.value.file.endswith("L21.SPF") and e.value.line == 2  # the alarm names its own file


def test_missing_subprogram_alarms_at_the_call():
    with pytest.raises(NCError) as e:
        run("G0 X20\nN20 L77\nM30\n")
    assert (e.value.line, e.value.col) == (2, 5) and "subprogram L77 not found" in e.value.message


def test_gotob_loop_and_if_gotof():
    text = ("R1=0\nG0 X0 Z0\nMA1: R1=R1+1\nG91 G1 Z-1 F100\nG90\n"
            "IF R1<4 GOTOB MA1\nGOTOF ENDE\nG1 X80\nENDE: M30\n")
    tp = run(text)
    assert pts(tp, "line") == [(0.0, -1.0), (0.0, -2.0), (0.0, -3.0), (0.0, -4.0)]


def test_goto_block_number_and_wrong_direction_alarm():
    assert pts(run("G0 X0 Z0\nGOTOF N40\nG1 X50 F100\nN40 G1 Z-5 F100\nM30\n"), "line") == [(0.0, -5.0)]
    with pytest.raises(NCError) as e:
        run("N10 G0 X0\nGOTOF N10\nM30\n")
    assert e.value.line == 2 and e.value.col == 7 and "GOTOB" in e.value.message


def test_r_parameters_arithmetic_and_degree_functions():
    text = ("R1=30 R2=SIN(R1)*10+SQRT(16)-POT(2)+ABS(-1)+TRUNC(2.7)\n"
            "R3=ATAN2(1,-1) R4=COS(60)*(2+2)\nG0 X=R2*2 Z=-R3\nG1 Z=R4 F100\nM30\n")
    tp = run(text)
    # R2 = 5 + 4 - 4 + 1 + 2 = 8; ATAN2(1,-1) = 135 deg; COS(60)*4 = 2
    assert pts(tp)[-2:] == [(8.0, -135.0), (8.0, 2.0)]


def test_assignment_and_words_in_one_block_assign_first():
    assert pts(run("R1=10 G0 X=R1*2 Z=R1\nM30\n"))[-1] == (10.0, 10.0)


def test_g91_increments_x_as_radius_and_g22():
    tp = run("G0 X40 Z0\nG91 G1 X5 Z-5 F100\nG90 G22 G1 X30\nM30\n")
    assert pts(tp, "line") == [(25.0, -5.0), (30.0, -5.0)]


def test_g70_inch_scales_x_z_and_feed():
    tp = run("G94 G0 X0 Z0\nG70 G1 X2 Z-1 F10\nM30\n")
    m = tp.moves[-1]
    assert m.end == pytest.approx((25.4, -25.4)) and m.feed == pytest.approx(254.0)


def test_g54_g500_g53():
    mach = dataclasses.replace(load_machine(None), work_offsets={"G54": (0.0, 200.0)})
    tp = run("G500 G0 X20 Z300\nG54 G0 X20 Z0\nG53 G0 X20 Z300\nM30\n", machine=mach)
    # G54: Z0 is machine Z200; the G53 block's coordinates are machine coordinates
    assert pts(tp)[-1] == (10.0, 100.0)


def test_t_d_edge_radius_and_compensation():
    mach = load_machine(None).with_registers({3: Register(number=3, radius=0.8, tip=3)})
    tp = run("T3 D1\nG0 X20 Z5\nG42 G1 X20 Z0 F100\nG1 Z-20\nG40 G1 X40\nM30\n", machine=mach)
    cut = [m for m in tp.moves if m.kind == "line" and m.line == 4]
    assert cut and all(m.register == 3 and m.tool == 3 for m in cut)
    tp0 = run("T3 D0\nG0 X20 Z5\nG42 G1 X20 Z0 F100\nG1 Z-20\nG40 G1 X40\nM30\n", machine=mach)
    assert pts(tp0, "line")[:2] == [(10.0, 0.0), (10.0, -20.0)]  # D0: no radius, programmed path
    assert pts(tp, "line") != pts(tp0, "line")


def test_edge_without_a_register_alarms(tmp_path):
    # the default tool library fills registers 1-15: T1 D2 reads register 2; a D that names
    # neither an edge of the tool nor a register alarms at the D word
    assert {m.register for m in run("N10 T1 D2\nG0 X20\nM30\n").moves} == {2}
    p = tmp_path / "m.toml"
    p.write_text('controller = "siemens802"\nuse_tool_library = false\n'
                 "[[register]]\nnumber = 1\nradius = 0.4\n")
    with pytest.raises(NCError) as e:
        nc.run("N10 T1 D2\nM30\n", load_machine(str(p)), start=(50.0, 50.0), dialect=S802)
    assert e.value.col == 8 and "edge 2" in e.value.message


def test_g33_chain_keeps_the_first_start_angle():
    tp = run("G0 X20 Z5 S400 M3\nG33 Z-10 K1.5 SF=90\nG33 X30 Z-20 K1.5\nG0 X40\nM30\n")
    thr = [m for m in tp.moves if m.kind == "thread"]
    assert [m.angle for m in thr] == [90.0, 90.0] and thr[1].end == pytest.approx((15.0, -20.0))


def test_text_variable_r_parameters_and_contour_reach_a_cycle():
    seen = {}

    def fake(ctx):
        seen["name"] = (ctx.name, ctx.code, ctx.text("_CNAME"), ctx.r(105), ctx.plane, ctx.tool_nose())
        seen["contour"] = [(s.start, s.end, kind) for s, line, kind in ctx.contour(ctx.text("_CNAME"))]
        ctx.set_r(250, 7.0)
        ctx.feed(10.0, -5.0, 100.0)

    d = dataclasses.replace(S802, cycles=lambda: {"LCYC95": fake})
    text = ('%_N_MAIN_MPF\nG0 G91 X20 Z2 G42\n_CNAME="KONTUR1" R105=1\nLCYC95\nX2\nM30\n'
            "%_N_KONTUR1_SPF\nG90 G1 X10 Z0\nZ-10\nRET\n")
    tp = run(text, dialect=d)
    assert seen["name"] == ("LCYC95", 95, "KONTUR1", 1.0, 18, (0.0, 0))
    assert seen["contour"] == [((70.0, 52.0), (5.0, 0.0), "feed"), ((5.0, 0.0), (5.0, -10.0), "feed")]
    last = tp.moves[-1]
    # after the cycle G0 G90 G40: X2 is an absolute diameter, in rapid
    assert last.kind == "rapid" and last.end == pytest.approx((1.0, -5.0))
    assert [m.op for m in tp.moves if m.kind == "line"] == ["LCYC95"]


def test_cli_run_with_dialect_and_the_sniff_hint(tmp_path):
    p = tmp_path / "A.MPF"
    p.write_text("%_N_A_MPF\nG0 X20 Z5\nR1=2\nG1 X=R1 F100\nM30\n")
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "run", "--dialect", "siemens802", str(p)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "run", str(p)], capture_output=True, text=True)
    assert r.returncode == 2 and "try --dialect siemens802" in r.stderr
    assert r.stderr.count("\n") == 1 and f"{p}:1:1:" in r.stderr


def test_machine_file_controller_and_tool_edges(tmp_path):
    p = tmp_path / "m.toml"
    p.write_text('controller = "siemens802"\nuse_tool_library = false\n'
                 "[[register]]\nnumber = 3\nradius = 0.4\ntip = 3\n"
                 "[[register]]\nnumber = 3\nedge = 2\nradius = 1.2\ntip = 2\n")
    mach = load_machine(str(p))
    seen = []
    d = dataclasses.replace(S802, cycles=lambda: {"LCYC93": lambda ctx: seen.append(ctx.tool_nose())})
    # the machine's controller picks the dialect; T3 D2 is the register with edge = 2
    tp = nc.run("T3 D2\nG0 X20 Z5\nLCYC93\nT3\nLCYC93\nD0\nLCYC93\nM30\n", mach, start=(50.0, 50.0),
                dialect=d)
    assert seen == [(1.2, 2), (0.4, 3), (0.0, 0)]
    assert nc.run("G0 X20 Z5\nR1=1\nM30\n", mach).moves  # read as an 802 program
    p.write_text('controller = "siemens802"\n[[register]]\nnumber = 3\nedge = 12\n')
    with pytest.raises(Exception) as e:
        load_machine(str(p))
    assert "edge" in str(e.value)


def test_cli_simulate_an_802_program(tmp_path):
    p = tmp_path / "P.MPF"
    p.write_text("%_N_P_MPF\nG0 G95 X50 Z5 T1 D1 S800 M3\nG1 X40 Z0 F0.2\nZ-20 RND=2\nX48 CHF=1.414\n"
                 "Z-40\nG0 X60\nZ5\nM30\n")
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "simulate", "--dialect", "siemens802",
                        "--stock", "50x60", str(p)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "no collisions" in r.stdout


def test_d_without_an_edge_register_is_the_register_of_that_number(tmp_path):
    p = tmp_path / "m.toml"
    p.write_text('controller = "siemens802"\nuse_tool_library = false\n'
                 "[[register]]\nnumber = 3\nradius = 0.4\ntip = 3\n"
                 "[[register]]\nnumber = 5\nradius = 0.8\ntip = 2\n")
    mach = load_machine(str(p))
    seen = []
    d = dataclasses.replace(S802, cycles=lambda: {"LCYC93": lambda ctx: seen.append(ctx.tool_nose())})
    # T3 D5: tool 3 has no edge 5, register 5 is the tool library's register of this tool
    tp = nc.run("T3 D5\nG0 X20 Z5\nLCYC93\nM30\n", mach, start=(50.0, 50.0), dialect=d)
    assert seen == [(0.8, 2)] and {(m.tool, m.register) for m in tp.moves} == {(3, 5)}
    with pytest.raises(NCError) as e:
        nc.run("T3 D4\nG0 X20 Z5\nM30\n", mach, start=(50.0, 50.0), dialect=S802)
    assert (e.value.line, e.value.col) == (1, 4) and "nor a register 4" in e.value.one_line()
