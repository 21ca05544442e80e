"""A program that threads with a register whose tool is not a threading tool (a shop program
read with a tool library whose numbers are not the shop's): one ``tool`` finding at the first
thread move of that register, before the collisions its outline then makes."""
from __future__ import annotations

from hnc_cam.nc.interp import run
from hnc_cam.sim import simulate
from hnc_cam.tooling import Stock, load_machine

#: FANUC two-block G76, M20x1.5 to Z-18 on a 20 mm diameter, tool T``n``
SHOP = """O1234
G21 G99 G40
T{n}0{n}
G97 S800 M03
G00 X24.0 Z5.0
G76 P020060 Q50 R0.05
G76 X18.376 Z-18.0 P812 Q400 F1.5
G00 X100.0 Z100.0
M30
"""


def _sim(n: int):
    machine = load_machine()  # the default tool library: T03 a boring bar, T04 a threading tool
    text = SHOP.format(n=n)
    tp = run(text, machine, file="shop.nc", dialect="fanuc0it")
    return simulate(tp, Stock.parse("20x40+1"), machine)


def test_threading_with_the_boring_bar_register_is_one_tool_finding():
    m = _sim(3)
    tool = [i for i in m.issues if i.kind == "tool"]
    assert len(tool) == 1
    assert tool[0].line == 7  # the G76 block that moves
    assert m.issues[0] is tool[0]
    # its outline then cuts the bar where no thread tool goes: collisions follow
    assert any(i.kind == "collision" for i in m.issues)


def test_threading_with_the_threading_register_has_no_tool_finding():
    m = _sim(4)
    assert not [i for i in m.issues if i.kind in ("tool", "collision")]
