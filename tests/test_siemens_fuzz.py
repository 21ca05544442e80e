"""Bounded fuzzing of the SINUMERIK 802 reader through the interpreter: random bytes, a grammar
of 802 words and statements, and seeded mutations of the transcribed document examples in
tests/data/siemens802. Any input ends in a toolpath or one NCError whose line lies in the
file; never another exception, never a hang (a small step limit bounds every loop)."""
from __future__ import annotations

import dataclasses
import pathlib
import random

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hnc_cam.errors import NCError
from hnc_cam.tooling import load_machine

from fuzzcheck import outcome as check

LIMIT = 2000
SETTINGS = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
DATA = pathlib.Path(__file__).parent / "data" / "siemens802"
MACHINE = load_machine(None)
MACHINES = [MACHINE, dataclasses.replace(MACHINE, block_delete=True)]


def outcome(text: str, machine=MACHINE):
    return check(text, machine, step_limit=LIMIT, dialect="siemens802", start=(40.0, 60.0))


@SETTINGS
@given(st.binary(max_size=300), st.sampled_from(MACHINES))
def test_random_bytes(data, machine):
    outcome(data.decode("latin-1"), machine)


WORDS = ["G0", "G1", "G2", "G3", "G4", "G5", "G9", "G17", "G18", "G22", "G23", "G25", "G26", "G33",
         "G40", "G41", "G42", "G53", "G54", "G500", "G70", "G71", "G74", "G75", "G90", "G91", "G94",
         "G95", "G96", "G97", "G158", "M3", "M5", "M17", "M2", "M30", "RET", "STOPRE", "X10", "X-5.5",
         "Z-20", "Z3", "I2", "K-4", "CR=5", "CR=-3", "AR=60", "AR=270", "AR=0", "IX=40", "KZ=37",
         "CHF=2", "RND=1.5", "SF=180", "LIMS=2500", "SPOS=90", "F100", "F0.2", "S500", "T1", "D1",
         "D0", "D3", "L10", "P3", "L123", "KONTUR", "LCYC82", "LCYC95", "N10", "N20", "N99999",
         "MA1:", "GOTOF", "GOTOB", "MA1", "N10", "IF", "R1=", "R1", "R2=R1+1", "R250=1", "R300",
         "X=R1*2", "Z=-R2", "(", ")", "+", "-", "*", "/", "==", "<>", ">=", "<", "SIN(", "ATAN2(1,",
         "POT(", "TRUNC(", ",", "_CNAME=", '"K1"', '"GOTOF"', '"', "%_N_A_MPF", "%_N_L10_SPF", "%_N_KONTUR_SPF",
         "%", ";C", "/", "U4", "W-2", "Y1", "2", "0", "-1", "1.5", "99999999", ".", "1.2.3", "e5"]


@SETTINGS
@given(st.lists(st.lists(st.sampled_from(WORDS), max_size=7), max_size=25), st.booleans(),
       st.sampled_from(MACHINES))
def test_random_token_soup(lines, end, machine):
    text = "\n".join(" ".join(ws) for ws in lines) + ("\nM30\n" if end else "")
    outcome(text, machine)


STATEMENTS = ["R1=R1+1", "R2=R2-1", "MA1: R3=R3+1", "IF R1<100000 GOTOB MA1", "GOTOF MA2", "MA2:",
              "GOTOB MA1", "IF R2>0 GOTOF MA2", "L10", "L10 P5", "KONTUR P2", "RET", "M17", "M2",
              "G1 X=R1 Z=-R2 F100", "%_N_L10_SPF", "%_N_KONTUR_SPF", "R1=0", "N10 R3=SIN(R1)",
              "G2 X20 Z-10 CR=8", "G1 X30 CHF=1", "G1 Z-30 RND=2", "G33 Z-20 K2 SF=90"]


@SETTINGS
@given(st.lists(st.sampled_from(STATEMENTS), max_size=30))
def test_random_statements(stmts):
    outcome("\n".join(["%_N_MAIN_MPF"] + stmts + ["M30"]))


def _examples():
    return sorted(DATA.glob("*.mpf"))


def test_mutations_of_the_examples():
    rng = random.Random(802)
    files = _examples()
    assert files
    alphabet = "GXZIKRFSTDLPN0123456789.-+=;:/()%_ \nCRANDHFIXKZGOTOB\"<>*"
    for _ in range(400):
        text = rng.choice(files).read_text()
        chars = list(text)
        for _ in range(rng.randint(1, 6)):
            op = rng.random()
            i = rng.randrange(len(chars) + 1)
            if op < 0.4 and chars:
                chars[min(i, len(chars) - 1)] = rng.choice(alphabet)
            elif op < 0.7:
                chars.insert(i, rng.choice(alphabet))
            elif chars:
                del chars[min(i, len(chars) - 1)]
        outcome("".join(chars))


def test_deep_brackets_and_long_lines_alarm():
    e = outcome("R1=" + "(" * 5000 + "1" + ")" * 5000 + "\nM30\n")
    assert isinstance(e, NCError) and e.line == 1
    e = outcome("G1 X" + "9" * 400 + " F100\nM30\n")
    assert isinstance(e, NCError) and e.line == 1
    for text in ("N" + "9" * 5000 + " G0 X1\nM30", "R" + "1" * 5000 + "=1\nM30",
                 "GOTOF N" + "1" * 5000 + "\nM30", "L10 P" + "9" * 5000 + "\nM30",
                 "N10 G0 X1\nGOTOB N" + "0" * 30 + "10\nM30", "_" + "A" * 5000 + "\nM30"):
        e = outcome(text)
        assert isinstance(e, NCError) and e.line in (1, 2)


CORNER_BLOCKS = ["G1 X20 Z-5", "G1 X30 Z-10 RND=2", "G1 Z-20 CHF=1.5", "G2 X40 Z-25 CR=5 RND=1",
                 "G3 X30 Z-30 CR=6 CHF=0.5", "G2 X20 Z-40 I-5 K0", "G3 AR=90 I0 K-4 RND=0.8",
                 "G5 X44 Z-50 IX=50 KZ=-45 CHF=1", "G91 G2 X5 Z-5 CR=5 RND=3", "G90",
                 "G2 X20 Z-40 I0 K0 RND=1", "G1 Z-40 RND=50", "G3 X10 Z-10 CR=-8 RND=0.5",
                 "G2 X30 Z-40 I5 K-5", "G1 X30 RND=0.2", "G0 X60", "G1 X0"]


@SETTINGS
@given(st.lists(st.sampled_from(CORNER_BLOCKS), max_size=20))
def test_random_corners_next_to_arcs(blocks):
    """Rounds and chamfers between random lines and arcs: a path or one alarm, never a
    traceback."""
    outcome("\n".join(["G0 X40 Z5", "G1 Z0 F100"] + blocks + ["M30"]))
