"""The HTML report in a real browser: headless Chromium driven over its DevTools protocol.

Skips, naming what is missing, where no Chromium is installed (``.ci/run`` installs Debian's
``chromium`` when it runs as root)."""
from __future__ import annotations

import pytest
import shapely

from hnc_cam.nc.interp import run
from hnc_cam.report import render_page
from hnc_cam.report.browser import Chromium, find_chromium
from hnc_cam.sim import simulate
from hnc_cam.tooling import Stock, load_machine

from test_report import SUB, region

pytestmark = pytest.mark.skipif(find_chromium() is None,
                                reason="no Chromium installed (apt-get install chromium; "
                                       "or HNC_CHROMIUM=/path/to/chrome)")

#: a second program: G71 roughing plus a finishing contour with arcs (cycle moves, many passes)
G71 = """%0200
T0101
M03 S800
G00 X46 Z2
G71 U1.5 R0.5 P10 Q20 X0.4 Z0.1 F150
N10 G00 X16
G01 Z0 F80
G03 X24 Z-4 R4
G01 Z-20
X30
G02 X36 Z-23 R3
G01 Z-40
N20 X46
G00 X80 Z60
M30
"""


@pytest.fixture(scope="module")
def browser():
    with Chromium() as b:
        yield b


def _page(tmp_path, program: str, stock: str, name: str):
    machine = load_machine()
    tp = run(program, machine, file=name, start="reference")
    m = simulate(tp, Stock.parse(stock), machine)
    p = tmp_path / f"{name}.html"
    p.write_text(render_page(m, title=name))
    return p, m


@pytest.mark.parametrize("program,stock,name", [(SUB, "40x60+1", "sub.nc"),
                                                (G71, "45x60+1", "g71.nc"),
                                                ("%1\nM30\n", "20x10", "empty.nc"),
                                                ("%1\nT0101\nG04 P2\nM30\n", "20x10", "dwell.nc")])
def test_page_loads_draws_every_move_and_steps_to_the_final_outline(browser, tmp_path, program,
                                                                     stock, name):
    page, m = _page(tmp_path, program, stock, name)
    browser.events.clear()
    browser.open(page)
    assert browser.errors() == []
    n = len(m.toolpath.moves)
    assert browser.eval("window.hncReport.moves") == n
    assert browser.eval("window.hncReport.drawnMoves()") == n
    # step to the start: the material is the stock; to the end: the simulator's final outline
    browser.eval("window.hncReport.setStep(0)")
    f0 = browser.eval("window.hncReport.frame()")
    assert f0["n"] == 0
    assert region_abs(f0["rings"]).symmetric_difference(m.stock).area < 1e-6
    browser.eval(f"window.hncReport.setStep({n})")
    last = browser.eval("window.hncReport.frame()")
    assert last["n"] == n
    got = region_abs(last["rings"])
    assert shapely.hausdorff_distance(got, m.material) < 0.0015
    assert got.symmetric_difference(m.material).area < 0.001 * m.material.length
    # the clock at the end is the cycle time
    clock = browser.eval("document.getElementById('clock').textContent")
    t = m.toolpath.cycle_time_s
    assert clock.startswith(f"{int(t // 60)}:{t % 60:04.1f}")
    assert browser.errors() == []


def region_abs(rings):
    """A frame's rings as the page holds them (absolute um after decoding)."""
    g = shapely.Polygon()
    for r in rings:
        pts = [(r[k] / 1000.0, r[k + 1] / 1000.0) for k in range(0, len(r), 2)]
        g = g.symmetric_difference(shapely.Polygon(pts))
    return g


def test_clicking_a_block_selects_its_moves_also_in_a_subprogram(browser, tmp_path):
    page, m = _page(tmp_path, SUB, "40x60+1", "sub.nc")
    browser.open(page)
    # file line 14 is the subprogram's G01, run twice (M98 P200 L2)
    want = [i for i, mv in enumerate(m.toolpath.moves) if mv.line == 14]
    assert len(want) == 2
    rect = browser.eval("(function(){var r=window.hncReport.lineElement(14).getBoundingClientRect();"
                        "return [r.left + 80, r.top + r.height / 2];})()")
    browser.click(*rect)
    assert browser.eval("window.hncReport.selectedMoves()") == want
    # the main program's arc on line 8: one move
    rect = browser.eval("(function(){var r=window.hncReport.lineElement(8).getBoundingClientRect();"
                        "return [r.left + 80, r.top + r.height / 2];})()")
    browser.click(*rect)
    arc = [i for i, mv in enumerate(m.toolpath.moves) if mv.line == 8]
    assert browser.eval("window.hncReport.selectedMoves()") == arc
    assert browser.eval("document.querySelector('.pl.sel').getAttribute('data-line')") == "8"
    assert browser.errors() == []


def test_hovering_a_move_highlights_its_block(browser, tmp_path):
    page, m = _page(tmp_path, SUB, "40x60+1", "sub.nc")
    browser.open(page)
    # the middle of the finishing G01 X36 Z2 -> Z-20 (line 7): radius 18, z -9
    k = next(i for i, mv in enumerate(m.toolpath.moves) if mv.line == 7)
    x, y = browser.eval("window.hncReport.toScreen(-9.0, 18.0)")
    browser.move_mouse(x, y)
    browser.eval("new Promise(function(r){requestAnimationFrame(function(){requestAnimationFrame(r);});})")
    assert browser.eval("window.hncReport.hoverLine()") == m.toolpath.moves[k].line == 7
    assert browser.eval("document.querySelector('.pl.hov').getAttribute('data-line')") == "7"
    assert browser.errors() == []


def test_a_long_program_draws_every_move_and_keeps_few_lines_in_the_page(browser, tmp_path):
    lines = ["%1", "T0101", "M03 S1000", "G00 X42 Z1"]
    z = 1.0
    for k in range(3000):
        z -= 0.01
        lines.append(f"G01 X{39.9 if k % 2 else 39.8} Z{z:.3f} F200")
    lines += ["G00 X60", "M30"]
    page, m = _page(tmp_path, "\n".join(lines) + "\n", "40x40+1", "long.nc")
    browser.events.clear()
    browser.open(page)
    n = len(m.toolpath.moves)
    assert n > 3000
    assert browser.eval("window.hncReport.drawnMoves()") == n
    # the program pane is a virtual list: only the visible lines are elements
    assert browser.eval("document.querySelectorAll('#prog-inner .pl').length") < 200
    # the block of the last feed move is rendered when scrolled to
    k = max(i for i, mv in enumerate(m.toolpath.moves) if mv.kind == "line")
    assert browser.eval(f"window.hncReport.lineElement({m.toolpath.moves[k].line}) !== null")
    assert browser.errors() == []
