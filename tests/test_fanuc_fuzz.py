"""Bounded fuzzing of the FANUC 0i-T reader through the interpreter: random bytes, a grammar of
FANUC words and macro statements, and seeded mutations of the programs in tests/data/fanuc.
Any input ends in a toolpath or one NCError whose line lies in the file; never another
exception, never a hang (a small step limit bounds every loop)."""
from __future__ import annotations

import dataclasses
import pathlib
import random

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hnc_cam.errors import NCError
from hnc_cam.nc.toolpath import Toolpath
from hnc_cam.tooling import load_machine

from fuzzcheck import outcome as check

LIMIT = 2000
SETTINGS = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
DATA = pathlib.Path(__file__).parent / "data" / "fanuc"
MACHINE = load_machine(None)
MACHINES = [MACHINE, dataclasses.replace(MACHINE, decimal_point="calculator", block_delete=True)]


def outcome(text: str, machine=MACHINE):
    return check(text, machine, step_limit=LIMIT, dialect="fanuc0it")


@SETTINGS
@given(st.binary(max_size=300), st.sampled_from(MACHINES))
def test_random_bytes(data, machine):
    outcome(data.decode("latin-1"), machine)


WORDS = ["G00", "G01", "G02", "G03", "G04", "G28", "G32", "G40", "G41", "G42", "G50", "G65", "G66",
         "G67", "G70", "G71", "G72", "G73", "G74", "G75", "G76", "G90", "G92", "G94", "G96", "G97",
         "G98", "G99", "M03", "M05", "M98", "M99", "M30", "M00", "X10", "X10.", "X-5.5", "Z-20.",
         "Z3", "U4.", "W-2", "R5.", "R-3", "I2.", "K-4.", ",C1.", ",R2", ",X", "C1.", "F100", "F0.2",
         "S500", "S1.5", "T0101", "P2", "P1500", "P10", "Q20", "Q2.5", "L3", "H01", "H80", "H99",
         "D7000", "E1", "N10", "N20", "N999999", "O3", "%", ":5", "/", "/2", "(C)", "(", ")", ";",
         "#1=", "#2=#1+1", "#[#1]=3", "#0", "#1", "#3000=1", "#3006=2", "[", "]", "+", "-", "*",
         "/", "EQ", "LT", "AND", "XOR", "MOD", "SIN[", "ATAN[1]/[", "BCD[", "BIN[", "FUP[", "RO[",
         "IF", "THEN", "GOTO", "GO", "WHILE", "DO1", "DO4", "END1", "END2", "X[#1]", "X#1", "X-#2",
         "#5001", "#4001", "#100", "#500", "2", "0", "-1", "1.5", "99999999", ".", "1.2.3", "e5"]


@SETTINGS
@given(st.lists(st.lists(st.sampled_from(WORDS), max_size=7), max_size=25), st.booleans(),
       st.sampled_from(MACHINES))
def test_random_token_soup(lines, end, machine):
    text = "\n".join(" ".join(ws) for ws in lines) + ("\nM30\n" if end else "")
    outcome(text, machine)


STATEMENTS = ["#1=#1+1", "#2=#2-1", "WHILE [#1 LT 1000000] DO1", "WHILE [1] DO2", "DO3", "END1",
              "END2", "END3", "GOTO 10", "N10 #3=#3+1", "IF [#1 GT 3] GOTO 10", "IF [#2 LT 0] THEN #1=0",
              "M98 P2", "M99", "M99 P10", "G65 P2 A1.", "G65 H02 P#1 Q#1 R1", "G65 H83 P10 Q#1 R5",
              "G65 H80 P10", "G01 X#1 Z-#2 F0.2", "O2", "#1=0", "G65 H99 P3", "#3000=4 (STOP)"]


@SETTINGS
@given(st.lists(st.sampled_from(STATEMENTS), max_size=15))
def test_loops_jumps_and_calls_never_hang(lines):
    outcome("%\nO1\n#1=0\n#2=0\n#3=0\nG00 X50. Z5.\n" + "\n".join(lines) + "\nM30\n%\n")


def _mutate(text: str, rng: random.Random) -> str:
    """One random edit: delete, duplicate or swap a line; delete, insert or replace a
    character; cut the file; splice a word."""
    lines = text.split("\n")
    op = rng.randrange(8)
    if op == 0 and lines:
        del lines[rng.randrange(len(lines))]
    elif op == 1 and lines:
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif op == 2 and len(lines) > 1:
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    else:
        s = "\n".join(lines)
        if not s:
            return rng.choice(WORDS)
        k = rng.randrange(len(s))
        if op == 3:
            return s[:k] + s[k + 1:]
        if op == 4:
            return s[:k] + rng.choice("0123456789.-+#[]=/;%(),XZUWGMNOPQRSHIFTDEL \n\t\r\0") + s[k:]
        if op == 5:
            return s[:k] + rng.choice("0123456789.-XZ#[]") + s[k + 1:]
        if op == 6:
            return s[:k]
        return s[:k] + " " + rng.choice(WORDS) + " " + s[k:]
    return "\n".join(lines)


CORPUS = sorted(DATA.glob("*.nc"))


@pytest.mark.parametrize("path", CORPUS, ids=[p.name for p in CORPUS])
def test_mutations_of_the_corpus(path):
    """300 seeded mutants of each corpus program (1 to 3 edits each), in both machine
    settings: every one a toolpath or an alarm in the file."""
    base = path.read_text()
    rng = random.Random(path.name)
    outcome(base)
    for k in range(300):
        text = base
        for _ in range(rng.randrange(1, 4)):
            text = _mutate(text, rng)
        outcome(text, MACHINES[k % 2])


def test_corpus_programs_run_clean():
    for path in CORPUS:
        r = outcome(path.read_text(), MACHINES[1] if "calc" in path.name or path.name == "macro_a_loop.nc"
                    else MACHINE)
        assert isinstance(r, Toolpath), (path.name, str(r))


def test_endless_loops_stop_at_the_step_limit():
    for text in ("O1\nDO1\nEND1\nM30\n", "O1\nN10 GOTO 10\nM30\n", "O1\nN5 G65 H80 P5\nM30\n",
                 "O1\nWHILE [#0 EQ #0] DO3\nEND3\nM30\n"):
        r = outcome(text)
        assert isinstance(r, NCError) and "step limit" in r.message, (text, str(r))


def test_deeply_nested_expressions_alarm():
    for text in ("#1=" + "[" * 3000 + "1" + "]" * 3000, "#1=" + "-" * 5000 + "1",
                 "#1=" + "SIN[" * 2000 + "1" + "]" * 2000, "G01 X" + "-" * 5000 + "#1",
                 "IF [" + "[" * 3000 + "1" + "]" * 3000 + "] GOTO 5"):
        r = outcome("O1\n" + text + "\nM30\n")
        assert isinstance(r, NCError) and r.line == 2
