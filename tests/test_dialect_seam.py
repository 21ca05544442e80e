"""The dialect seam: the registry, sniffing which dialect a file looks like (and the hint an HNC
alarm then carries), ``--dialect`` on the commands, the machine file's ``controller`` and
the HNC-21T interpreter unchanged behind it."""
from __future__ import annotations

import dataclasses
import subprocess
import sys

import pytest

from hnc_cam import dialect, nc
from hnc_cam.errors import NCError, ToolError
from hnc_cam.tooling import load_machine

FANUC_FILE = "%\nO1234 (SHAFT)\nG21 G99\nT0101\nM03 S800\nG00 X40. Z2.\nG01 Z-20. F0.2\nG00 X100. Z100.\nM30\n%\n"


def cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "hnc_cam.cli", *args], capture_output=True,
                          text=True, cwd=cwd)


# ------------------------------------------------------------------------------ registry

def test_registry_names_and_values():
    assert dialect.names() == ("hnc21t", "fanuc0it", "haas", "siemens802")
    h, f, a, s = (dialect.get(n) for n in dialect.names())
    assert (s.name, s.title, s.templates, s.template_fallback) == (
        "siemens802", "SINUMERIK 802S/802C (turning)", "siemens802", None)
    assert (h.name, h.templates, h.template_fallback) == ("hnc21t", "hnc21t", None)
    assert (f.name, f.title, f.templates, f.template_fallback) == (
        "fanuc0it", "FANUC 0i-T (G-code system A)", "fanuc0it", None)
    assert (a.name, a.templates, a.template_fallback) == ("haas", "haas", "fanuc0it")
    assert dialect.get(f) is f  # a value passes through
    with pytest.raises(dataclasses.FrozenInstanceError):
        f.name = "x"  # type: ignore[misc]


def test_registry_tables_differ_where_the_controls_differ():
    h, f = dialect.get("hnc21t"), dialect.get("fanuc0it")
    # G90 is absolute on the HNC, the turning cycle on the FANUC; G50 exists only on the FANUC
    assert h.codes[("G", 90)].group == 13 and f.codes[("G", 90)].group == 1
    assert 90 in f.cycle_motion and 90 not in h.cycle_motion
    assert ("G", 50) in f.codes and ("G", 50) not in h.codes
    assert f.call_letters["X"] == 24 and f.call_letters["I"] == 4 and h.call_letters["X"] == 23
    assert 71 in dialect.get("haas").cycle_table() and dialect.get("haas").cycle_table()[71] is not \
        f.cycle_table()[71]


def test_unknown_dialect_is_a_value_error_naming_the_known_ones():
    with pytest.raises(ValueError, match="known: hnc21t, fanuc0it, haas"):
        dialect.get("siemens")
    with pytest.raises(NCError, match="unknown dialect 'siemens'"):
        nc.run("%1\nM30\n", dialect="siemens")


# ------------------------------------------------------------------------------ sniffing

@pytest.mark.parametrize("text, why", [
    (FANUC_FILE, "% then O1234"),
    ("%1\nG00 X40 Z2\nG71 U1.5 R0.5\nG71 P10 Q20 U0.4 W0.1 F0.2\nN10 G00 X20\nN20 G01 Z-10\nM30\n",
     "two-block G71 U R / G71 P Q"),
    ("%1\n#1=0\nN5 #1=#1+1\nIF [#1 LT 3] GOTO 5\nM30\n", "IF[...] GOTO"),
    ("%1\nG01 X20 Z-5 ,C1\nG01 X30\nM30\n", ",C / ,R corner words"),
    ("%1\nG01 X20 Z-5 ,R2.\nG01 X30\nM30\n", ",C / ,R corner words"),
    ("%1\nWHILE [#1 LT 3] DO1\n#1=#1+1\nEND1\nM30\n", "WHILE[...] DO"),
])
def test_sniff_recognises_fanuc_shapes(text, why):
    assert dialect.sniff(text) == f"looks like a FANUC program ({why}): try --dialect fanuc0it"


@pytest.mark.parametrize("text", [
    "%1234\nG92 X40 Z5\nG01 X20 Z-5 C1 F100\nG01 X30\nM30\n",  # HNC chamfer C without comma
    "%1\nG71 U1 R0.5 P10 Q20 X0.4 Z0.1 F100\nN10 G00 X20\nN20 G01 Z-10\nM30\n",  # one-block G71
    "%1\n#1=0\nWHILE #1 LT 3\n#1=#1+1\nENDW\nIF #1 EQ 3\nM30\nENDIF\n",
    "", "\n\n", "%\n", "G01 X(1,C2)\n",
])
def test_sniff_leaves_hnc_programs_alone(text):
    assert dialect.sniff(text) is None


def test_hnc_alarm_on_a_fanuc_file_carries_the_hint(tmp_path):
    p = tmp_path / "o1234.nc"
    p.write_text(FANUC_FILE)
    r = cli("run", str(p))
    assert r.returncode == 2
    line = r.stderr.strip().splitlines()[-1]
    assert line.startswith(f"{p}:1:")
    assert "FANUC-framed" in line and line.count("try --dialect fanuc0it") == 1
    p.write_text("%1\nG92 X40 Z2\nG01 X20 Z-5 ,C1 F100\nG01 X30\nM30\n")
    r = cli("run", str(p))
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1
    assert r.stderr.startswith(f"{p}:3:")
    assert r.stderr.rstrip().split("  [")[0].endswith(
        "looks like a FANUC program (,C / ,R corner words): try --dialect fanuc0it")


def test_hnc_alarm_without_fanuc_shape_has_no_hint():
    with pytest.raises(NCError) as e:
        nc.run("%1\nG01 X20 Z-5 Q1\nM30\n")
    assert "FANUC" not in e.value.message and "try --dialect" not in e.value.message


# ------------------------------------------------------------------------------ commands

@pytest.mark.parametrize("command", ["run", "simulate", "verify", "generate", "family"])
def test_every_command_refuses_an_unknown_dialect_in_one_line(command, tmp_path):
    args = {"run": ["x.nc"], "simulate": ["x.nc"], "verify": ["x.nc", "--model", "p.py"],
            "generate": ["p.py"], "family": ["p.py", "--table", "t.csv", "--out", "o"]}[command]
    r = cli(command, *args, "--dialect", "siemens", cwd=tmp_path)
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and "--dialect" in r.stderr and "siemens" in r.stderr
    assert "hnc21t" in r.stderr and "fanuc0it" in r.stderr


def test_run_and_simulate_take_dialect_hnc21t(tmp_path):
    p = tmp_path / "a.nc"
    p.write_text("%1\nG92 X40 Z2\nM03 S500\nG01 X36 F100\nZ-10\nX40\nG00 Z2\nM30\n")
    r = cli("run", str(p), "--dialect", "hnc21t")
    assert r.returncode == 0, r.stderr
    assert "6 moves" in r.stdout or "moves" in r.stdout
    r2 = cli("run", str(p))
    assert r2.stdout == r.stdout
    r = cli("simulate", str(p), "--stock", "40x30", "--dialect", "hnc21t")
    assert r.returncode == 0, r.stderr


# ------------------------------------------------------------------------------ machine file

def test_machine_controller_and_parameters(tmp_path):
    m = tmp_path / "m.toml"
    m.write_text('controller = "haas"\ndecimal_point = "calculator"\nblock_delete = true\n'
                 '[parameters]\ng71_depth = 1.5\ng71_type2 = false\n')
    mach = load_machine(m)
    assert (mach.controller, mach.decimal_point, mach.block_delete) == ("haas", "calculator", True)
    assert mach.parameters == {"g71_depth": 1.5, "g71_type2": False}
    assert load_machine(None).controller is None


@pytest.mark.parametrize("body, what", [
    ('controller = "siemens"\n', "controller"),
    ('decimal_point = "metric"\n', "decimal_point"),
    ('block_delete = 1\n', "block_delete"),
    ('[parameters]\ng71_depth = "two"\n', "g71_depth"),
])
def test_machine_bad_dialect_keys_are_one_line_errors(tmp_path, body, what):
    m = tmp_path / "m.toml"
    m.write_text(body)
    with pytest.raises(ToolError, match=what):
        load_machine(m)
    p = tmp_path / "a.nc"
    p.write_text("%1\nM30\n")
    r = cli("run", str(p), "--machine", str(m))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and str(m) in r.stderr


def test_machine_controller_selects_the_executor_and_the_option_wins(tmp_path):
    """The same program text means different things per controller: G04 P500 is 500 s on the
    HNC-21T and 500 ms on the FANUC (read here with the HNC reader, so only the executor
    differs)."""
    from hnc_cam.dialect.hnc21t import HncSyntax
    fanuc_exec = dataclasses.replace(dialect.get("fanuc0it"), syntax_factory=HncSyntax)
    text = "%1\nG04 P500\nM30\n"
    assert nc.run(text).moves[0].duration == 500.0
    assert nc.run(text, dialect=fanuc_exec).moves[0].duration == 0.5
    m = tmp_path / "m.toml"
    m.write_text('controller = "hnc21t"\n')
    assert nc.run(text, load_machine(m)).moves[0].duration == 500.0


def test_hnc_output_is_unchanged_by_the_seam():
    """Positions, times and warnings of an HNC program through the seam (dialect given by
    name, by value and by default) are the same."""
    text = ("%1\nG92 X50 Z10\nM03 S600\nG00 X30 Z2\nG01 Z-10 F80\nG02 X40 Z-15 R5\n"
            "G01 X44 C1\nZ-30\nG04 P1\nG00 X50 Z10\nM30\n")
    a = nc.run(text)
    b = nc.run(text, dialect="hnc21t")
    c = nc.run(text, dialect=dialect.get("hnc21t"))
    assert a.dumps() == b.dumps() == c.dumps()
    assert a.moves[-1].end == (25.0, 10.0)


def test_fanuc_file_through_run_and_simulate_and_the_machine_controller(tmp_path):
    p = tmp_path / "o1234.nc"
    p.write_text(FANUC_FILE)
    r = cli("run", str(p), "--dialect", "fanuc0it")
    assert r.returncode == 0, r.stderr
    r = cli("simulate", str(p), "--stock", "50x40", "--dialect", "fanuc0it")
    assert r.returncode == 0, r.stderr
    m = tmp_path / "m.toml"
    m.write_text('controller = "fanuc0it"\n')
    r2 = cli("run", str(p), "--machine", str(m))
    assert r2.returncode == 0, r2.stderr
    r3 = cli("run", str(p), "--machine", str(m), "--dialect", "hnc21t")  # the option wins
    assert r3.returncode == 2 and "FANUC" in r3.stderr
    tp = nc.run(FANUC_FILE, load_machine(m))
    assert (20.0, -20.0) in [mv.end for mv in tp.moves]  # X40. is a diameter
    m.write_text('controller = "fanuc0it"\ndecimal_point = "calculator"\nblock_delete = true\n')
    tp = nc.run("%\nO0001\nG00 X40 Z2\n/G00 X80 Z2\nM30\n%\n", load_machine(m), start=(0.0, 0.0))
    assert tp.moves[-1].end == (20.0, 2.0) and not tp.warnings
