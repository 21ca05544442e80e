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


#: a turning tool's passes, then register 0 (no insert) moving before it cuts threads (a
#: threading tool for all its moves), then the boring bar's register cutting a thread
LATE_THREADS = """%1
T0101
M03 S800
G00 X44 Z2
G00 X38 Z1
G01 Z-30 F0.2
G00 X40 Z1
G00 X36
G01 Z-30
G00 X40 Z1
T0100
G00 X37 Z3
G01 X36.5 Z2 F0.2
G00 X40 Z3
G00 X36 Z3
G32 Z-20 F1.5
G00 X40
G00 Z3
G00 X35.8
G32 Z-20 F1.5
G00 X40
T0303
G00 X37 Z3
G32 Z-20 F1.5
G00 X80 Z80
M30
"""


def test_thread_registers_found_chunk_by_chunk_give_the_one_chunk_result(monkeypatch):
    """A toolpath of several chunks finds its thread moves' registers from the columns each
    run reads (once per chunk); where a register turns out a threading tool after an earlier
    chunk swept its moves, the simulation starts again with the registers known first: the
    same sweeps, removals, findings and thread registers as in one chunk."""
    import importlib
    import numpy as np
    S = importlib.import_module("hnc_cam.sim.simulate")
    machine = load_machine()
    tp = run(LATE_THREADS, machine, start=(50.0, 80.0))
    regs = [m.register for m in tp.moves]
    kinds = [m.kind for m in tp.moves]
    assert regs.index(0) < kinds.index("thread") and machine.register(0).insert is None
    whole = simulate(tp, Stock.parse("40x60"), machine)
    assert whole.thread_regs == {0: 60.0}
    assert [i.kind for i in whole.issues].count("tool") == 1  # the boring bar's
    read = []
    cols = S.columns
    monkeypatch.setattr(S, "columns", lambda ms: read.append(len(ms)) or cols(ms))
    monkeypatch.setattr(S, "CHUNK", 4)
    m = simulate(tp, Stock.parse("40x60"), machine)
    chunks = -(-len(tp.moves) // 4)
    assert len(read) > chunks  # started again once register 0's threads were found
    assert [(str(i), i.at) for i in m.issues] == [(str(i), i.at) for i in whole.issues]
    assert np.array_equal(m.removed_area, whole.removed_area)
    assert m.material.equals_exact(whole.material, 0)
    assert m.thread_regs == whole.thread_regs
    # the threading tool's register instead: each chunk's columns read once
    text = LATE_THREADS.replace("T0100\n", "T0404\n")
    tp = run(text, machine, start=(50.0, 80.0))
    whole = simulate(tp, Stock.parse("40x60"), machine)
    read.clear()
    m = simulate(tp, Stock.parse("40x60"), machine)
    assert len(read) == -(-len(tp.moves) // 4)
    assert [(str(i), i.at) for i in m.issues] == [(str(i), i.at) for i in whole.issues]
    assert np.array_equal(m.removed_area, whole.removed_area)
