"""FANUC macro B calls: M, S and T of a G65/G66 block are arguments (#13, #19, #20) and take
their decimal point as every argument does (the FANUC custom macro manual: "it is good
practice to use decimal points in macro call arguments"); outside a call they stay whole-number
code words (PS0007). Read through the FANUC reader (``hnc_cam.nc.run(..., dialect="fanuc0it")``)."""
from __future__ import annotations

import pytest

from hnc_cam import nc
from hnc_cam.errors import NCError


def ends(text: str) -> list[tuple[float, float]]:
    """Where each programmed block ends (X on diameter, Z): a rapid's dog-leg pieces aside."""
    tp = nc.run(text, dialect="fanuc0it", start=(0.0, 0.0))
    out: dict[int, tuple[float, float]] = {}
    for m in tp.moves:
        if m.kind in ("rapid", "line"):
            out[m.line] = (round(2 * m.end[0], 6), round(m.end[1], 6))
    return list(out.values())


def alarm(text: str) -> NCError:
    with pytest.raises(NCError) as e:
        nc.run(text, dialect="fanuc0it", start=(0.0, 0.0))
    return e.value


def test_m_s_t_arguments_keep_their_decimals():
    # X = M + S, Z = -(T + A): the decimals arrive whole, not rounded to codes
    got = ends("O0001\nG65 P1001 A1.5 M2.25 S30.125 T-4.75\nM30\n"
               "O1001\nG00 X[#13+#19] Z[-[#20+#1]]\nM99\n")
    assert got == [(32.375, 3.25)]


def test_m_s_t_arguments_without_a_point_are_whole_units():
    got = ends("O0001\nG65 P1001 M3 S12 T5\nM30\nO1001\nG00 X[#13+#19] Z[-#20]\nM99\n")
    assert got == [(15.0, -5.0)]


def test_an_argument_m_neither_runs_nor_stops_the_program():
    # M30.5 as argument #13 is a number, not the end of the program
    got = ends("O0001\nG65 P1001 M30.5\nG00 X1. Z1.\nM30\nO1001\nG00 X#13 Z0\nM99\n")
    assert got == [(30.5, 0.0), (1.0, 1.0)]


def test_g66_modal_call_takes_decimal_arguments_too():
    got = ends("O0001\nG66 P1001 S0.5\nG00 X10. Z0\nG67\nM30\nO1001\nG01 W-#19 F0.1\nM99\n")
    assert got == [(10.0, 0.0), (10.0, -0.5)]


@pytest.mark.parametrize("text, line, col, what", [
    ("O0001\nM3.5\nM30\n", 2, 1, "PS0007"),          # a code word, not an argument
    ("O0001\nS1000.5 M03\nM30\n", 2, 1, "PS0007"),
    ("O0001\nG65 P1001 M2.5 L2.5\nM30\nO1001\nM99\n", 2, 16, "PS0007"),  # L: the repeat count
    ("O0001\nG65 P1001 S123456789\nM30\nO1001\nM99\n", 2, 11, "more than 8 digits"),
    ("O0001\nG65 P1001 M98\nM30\nO1001\nM99\n", 2, 11, "G65/G66 and M98"),
])
def test_call_argument_alarms(text, line, col, what):
    e = alarm(text)
    assert (e.line, e.col) == (line, col)
    assert what in str(e)
