"""The HTML report's data and files (no browser needed; see test_report_browser.py)."""
from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
import shapely

from hnc_cam.cli import main
from hnc_cam.nc.interp import run
from hnc_cam.nc.toolpath import Toolpath
from hnc_cam.report import data as D
from hnc_cam.report import render_page
from hnc_cam.sim import simulate
from hnc_cam.tooling import Stock, load_machine

REPO = Path(__file__).resolve().parents[1]

#: a hand-written program with a subprogram called twice (its lines appear in two passes)
SUB = """%0100
N1 T0101
N2 M03 S1000
N3 G00 X40 Z2
N4 M98 P200 L2
N5 G00 X36 Z2
N6 G01 Z-20 F100
N7 G02 X40 Z-22 R2
N8 G00 X60
N9 Z2
N10 M30
%200
G00 X38 Z2
G01 Z-20 F120
G00 X42
Z2
M99
"""


def page_json(text: str) -> dict:
    m = re.search(r'<script id="hnc-data" type="application/json">(.*?)</script>', text, re.S)
    assert m, "no data block"
    return json.loads(m.group(1))


def undelta(ring: list[int]) -> list[tuple[float, float]]:
    out, z, x = [], 0, 0
    for k in range(0, len(ring), 2):
        z += ring[k]
        x += ring[k + 1]
        out.append((z / 1000.0, x / 1000.0))
    return out


def region(rings: list[list[int]]):
    """The shapely region of a frame's rings (even-odd, as the page fills them)."""
    g = shapely.Polygon()
    for r in rings:
        g = g.symmetric_difference(shapely.Polygon(undelta(r)))
    return g


@pytest.fixture(scope="module")
def sub_machined():
    machine = load_machine()
    tp = run(SUB, machine, file="sub.nc", start="reference")
    return simulate(tp, Stock.parse("40x60+1"), machine)


def test_moves_keep_lines_geometry_and_order(sub_machined):
    tp = sub_machined.toolpath
    cols = D.moves_columns(tp.moves)
    assert len(cols["k"]) == len(tp.moves) == 15
    assert cols["l"] == [m.line for m in tp.moves]
    # the subprogram's G01 (file line 14) ran twice, the main program's G01 once (line 7)
    assert cols["l"].count(14) == 2 and cols["l"].count(7) == 1
    # exact arc: G02 X40 Z-22 R2 from X36 Z-20, centre X40 Z-20 (radius 20, z -20) in um
    i = cols["k"].index(D.KIND_CODES["arc"])
    assert cols["a"] == [i, -20000, 20000, 1]
    assert cols["e"][2 * i:2 * i + 2] == [-22000, 20000]
    # starts are implied by the previous end; only the first is stored
    assert cols["s"] == [] and cols["x0z0"] == [150000, 100000]
    # cumulative clock ends at the cycle time
    assert cols["t"][-1] == round(tp.cycle_time_s * 100)
    assert cols["ops"][cols["g"][0]] == "rapid"
    assert "T01 G01-G03" in cols["ops"]


def test_keyframes_first_stock_last_final_and_bounded(sub_machined):
    frames = D.keyframes(sub_machined)
    assert frames[0]["n"] == 0 and frames[-1]["n"] == len(sub_machined.toolpath.moves)
    first = region(frames[0]["rings"])
    assert first.symmetric_difference(sub_machined.stock).area < 1e-9
    last = region(frames[-1]["rings"])
    # integer micrometres: at most 0.71 um off along the boundary
    assert last.symmetric_difference(sub_machined.material).area < 0.001 * sub_machined.material.length
    assert shapely.hausdorff_distance(last, sub_machined.material) < 0.0015
    assert [f["n"] for f in frames] == sorted(f["n"] for f in frames)


def test_intermediate_keyframe_is_the_material_after_its_moves(sub_machined):
    """A keyframe equals the simulator run on the program cut after that many moves."""
    tp = sub_machined.toolpath
    frames = D.keyframes(sub_machined, target=5)
    for f in frames[1:-1]:
        rings = f["rings"] if not isinstance(f["rings"], int) else frames[f["rings"]]["rings"]
        prefix = Toolpath(moves=tp.moves[:f["n"]], file=tp.file, source_lines=tp.source_lines)
        ref = simulate(prefix, Stock.parse("40x60+1"), sub_machined.machine).material
        got = region(rings)
        assert shapely.hausdorff_distance(got, ref) < D.FRAME_SIMPLIFY + 0.0015, f["n"]


def test_keyframes_stay_bounded_for_long_programs():
    lines = ["%1", "T0101", "M03 S1000", "G00 X42 Z1"]
    # 3,000 short feed moves in one operation
    z = 1.0
    for k in range(3000):
        z -= 0.01
        lines.append(f"G01 X{39.9 if k % 2 else 39.8} Z{z:.3f} F200")
    lines += ["G00 X60", "M30"]
    machine = load_machine()
    tp = run("\n".join(lines) + "\n", machine, file="long.nc", start="reference")
    ends = D.keyframe_ends(tp.moves)
    assert len(tp.moves) > 3000
    assert len(ends) <= D.KEYFRAMES + 4  # evenly spaced + operation boundaries
    assert ends[-1] == len(tp.moves)


def test_page_is_self_contained_and_carries_the_program(sub_machined):
    text = render_page(sub_machined, title="sub.nc")
    assert text.startswith("<!DOCTYPE html>")
    # nothing fetched at view time: no external scripts, styles, images or fonts
    assert not re.search(r"<(script|link|img|iframe)[^>]+(src|href)=", text)
    assert "http://" not in text.replace("http://www.w3.org/2000/svg", "")
    assert "https://" not in text
    d = page_json(text)
    assert d["program"]["lines"] == SUB.splitlines()
    assert len(d["moves"]["k"]) == 15
    assert d["chuck"] is None  # the jaws are drawn once the simulator models them


def test_page_draws_the_jaws_the_simulator_models():
    """With a grip the simulator models the jaws; the page carries them as its chuck rings
    and the setup sheet says they are drawn."""
    from hnc_cam.tooling import with_grip
    machine = with_grip(load_machine(), 15.0)
    tp = run(SUB, machine, file="sub.nc", start="reference")
    m = simulate(tp, Stock.parse("40x60+1"), machine)
    assert m.jaws is not None
    text = render_page(m, title="sub.nc")
    d = page_json(text)
    jaws = region(d["chuck"])
    assert jaws.symmetric_difference(m.jaws).area < 1e-3
    z0, x0, z1, x1 = jaws.bounds
    # front face 15 mm in from the stock's left end (Z-59: 60 mm long, 1 mm face stock), on the 20 mm radius
    assert z1 == pytest.approx(-59 + 15, abs=1e-3) and x0 == pytest.approx(20.0, abs=1e-3)
    assert "chuck jaws as drawn" in text


def test_script_end_tag_in_a_comment_cannot_break_the_page():
    machine = load_machine()
    prog = "%1\nT0101 (</script><b>x)\nM03 S500\nG00 X30 Z2\nG01 Z-5 F100\nM30\n"
    tp = run(prog, machine, file="c.nc", start="reference")
    text = render_page(simulate(tp, Stock.parse("40x20"), machine), title="c")
    assert text.count("</script>") == 2  # the data block and the script
    assert page_json(text)["program"]["lines"][1] == "T0101 (</script><b>x)"


def test_operations_and_tools_from_the_toolpath(sub_machined):
    ops = D.operations_run(sub_machined.toolpath.moves)
    assert [o["tool"] for o in ops] == ["T0101"]
    assert ops[0]["moves"] == 15
    assert ops[0]["feed"] == "100-120 mm/min"
    assert ops[0]["time_s"] == pytest.approx(sub_machined.toolpath.cycle_time_s, abs=0.06)
    tools = D.tools_table(sub_machined.toolpath.moves, sub_machined.machine)
    assert tools[0]["t"] == "T0101" and tools[0]["insert"] == "CNMG120408"
    assert tools[0]["nose_radius"] == 0.8 and tools[0]["tip"] == 3


# ---- the commands -------------------------------------------------------------------------

@pytest.fixture(scope="module")
def shaft(tmp_path_factory):
    """A generated stepped_shaft program with its report (the planner's data on the sheet)."""
    d = tmp_path_factory.mktemp("shaft")
    rc = main(["generate", str(REPO / "parts/stepped_shaft.py"), "-o", str(d / "O1.nc"),
               "--report", str(d / "O1.html")])
    assert rc == 0
    return d


@pytest.mark.cad
def test_generate_report_has_the_setup_sheet(shaft):
    text = (shaft / "O1.html").read_text()
    d = page_json(text)
    nc = (shaft / "O1.nc").read_text().splitlines()
    assert d["program"]["lines"] == nc
    # tools table: T0101 CNMG120408 r0.8 tip 3 with its holder from the library
    row = re.search(r"<tr><td>T0101</td><td>([^<]*)</td><td>([^<]*)</td><td>([^<]*)</td>"
                    r"<td class=\"num\">([^<]*)</td><td class=\"num\">([^<]*)</td>", text)
    assert row and row.group(2) == "CNMG120408" and row.group(3) == "PCLNR2525M12"
    assert float(row.group(4)) == 0.8 and row.group(5) == "3"
    assert 'id="plan-ops"' in text and "G71" in text
    assert 'class="badge pass"' in text
    assert d["model"], "the model outline is on the page"
    assert "<svg id=\"part-picture\"" in text


@pytest.mark.cad
def test_verify_report_and_unwritable_path(shaft, tmp_path, capsys):
    nc = shaft / "O1.nc"
    out = tmp_path / "v.html"
    js = tmp_path / "v.json"
    rc = main(["verify", str(nc), "--model", str(REPO / "parts/stepped_shaft.py"),
               "--stock", "45x117+2", "--report", str(out), "--json", str(js)])
    assert rc == 0 and out.exists()
    d = page_json(out.read_text())
    rep = json.loads(js.read_text())
    js.unlink()
    # within tolerance: no overcut/undercut mark; the unreachable leftover with its size
    marks = d["findings"]["marks"]
    assert {m["kind"] for m in marks} <= {"unreachable"}
    assert [(m["z"] / 1000, 2 * m["x"] / 1000, m["size"]) for m in marks] == \
        [pytest.approx((u["z"], u["x"], u["size_mm"]), abs=1e-3) for u in rep["unreachable"]]
    # a report path that cannot be written: one line, exit 2, nothing left behind
    blocker = tmp_path / "file"
    blocker.write_text("x")
    capsys.readouterr()
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "verify", str(nc), "--model",
                        str(REPO / "parts/stepped_shaft.py"), "--stock", "45x117+2",
                        "--report", str(blocker / "r.html")], capture_output=True, text=True)
    assert r.returncode == 2
    err = [ln for ln in r.stderr.splitlines() if ln.strip() and not ln.startswith("note: ")]
    assert len(err) == 1 and err[0].startswith("error: --report ") and "Traceback" not in r.stderr
    assert "cannot write" in err[0]
    assert sorted(tmp_path.iterdir()) == sorted([blocker, out])


@pytest.mark.cad
def test_verify_report_marks_deviations_with_values(shaft, tmp_path):
    """The program (d1 = 20) against a model with d1 = 22: the overcut is marked with its value."""
    out = tmp_path / "fail.html"
    rc = main(["verify", str(shaft / "O1.nc"), "--model", str(REPO / "parts/stepped_shaft.py"),
               "--set", "d1=22", "--stock", "45x117+2", "--report", str(out)])
    assert rc == 1
    text = out.read_text()
    d = page_json(text)
    kinds = {m["kind"] for m in d["findings"]["marks"]}
    assert "undercut" in kinds or "overcut" in kinds
    assert all(m["size"] > 0.01 for m in d["findings"]["marks"] if m["kind"] != "unreachable")
    assert 'class="badge fail"' in text


@pytest.mark.cad
def test_generate_refused_by_verification_still_writes_its_report(tmp_path):
    """0.1 um is below the simulator's own chord error: the program is refused (exit 1, not
    written) and the page shows why, with the overcut marked at its value."""
    nc, page = tmp_path / "F.nc", tmp_path / "F.html"
    rc = main(["generate", str(REPO / "parts/stepped_shaft.py"), "-o", str(nc),
               "--report", str(page), "--tol", "0.0001"])
    assert rc == 1 and not nc.exists() and page.exists()
    text = page.read_text()
    assert 'class="badge fail"' in text and "FAIL at tolerance 0.0001 mm" in text
    marks = page_json(text)["findings"]["marks"]
    assert any(m["kind"] == "overcut" and m["size"] > 0.0001 for m in marks)


@pytest.mark.cad
def test_setup_sheet_names_the_cycles_of_the_programs_dialect():
    from hnc_cam.plan.api import generate

    part = REPO / "parts" / "stepped_shaft.py"
    fanuc = generate(str(part), dialect="fanuc0it", verify=False)
    hnc = generate(str(part), verify=False)
    f_ops = D.plan_operations(fanuc.plan, fanuc.labels)
    h_ops = D.plan_operations(hnc.plan, hnc.labels)
    assert [o["name"] for o in f_ops] == [o["name"] for o in h_ops]
    f_cycles = {o["name"]: o["cycle"] for o in f_ops}
    h_cycles = {o["name"]: o["cycle"] for o in h_ops}
    assert f_cycles["finish"].startswith("G70") and not h_cycles["finish"].startswith("G70")
    # the same cycle names as the program's own summary line
    assert [f"{o['name']} {o['cycle']}" for o in f_ops] == fanuc.operations
