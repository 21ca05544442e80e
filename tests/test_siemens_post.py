"""The SINUMERIK 802S/802C post (templates/siemens802): the generated program read as data —
the LCYC95/93/97 transfer parameters against the plan, the contour subprogram's points
against the planned contour, CHF=/RND= in place of exactly the chamfer and round blocks —
and the program files: ``-o FILE`` one file with every program, ``-o DIR/`` one file per
program whose main program finds its subprogram beside it, written whole or not at all."""
from __future__ import annotations

import math
import os
import re
from pathlib import Path

import pytest

from hnc_cam.plan.api import generate
from hnc_cam.plan.export import split_programs

REPO = Path(__file__).resolve().parents[1]
PARTS = REPO / "parts"

pytestmark = pytest.mark.cad

#: a part written the way a user writes one (plain build123d): a shaft with an M16x1.5 thread
#: behind a lead chamfer, a 3 mm groove, a shoulder with an R2 round in its corner, a
#: chamfered step and a chamfered left end
FRESH = '''\
from build123d import (Axis, BuildLine, BuildPart, BuildSketch, Line, Plane, ThreePointArc,
                       make_face, revolve)

from hnc_cam.geometry import Thread

STOCK = "36x72+2"


def THREADS(**_):
    return [Thread(z_start=0.0, z_end=-18.0, diameter=16.0, pitch=1.5, starts=1,
                   internal=False, standard="metric", angle=60.0)]


def part(length: float = 68.0, groove_z: float = 22.0):
    c = 0.70710678
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Line((0, 0), (7.0, 0))
                Line((7.0, 0), (8.0, -1.0))
                Line((8.0, -1.0), (8.0, -groove_z))
                Line((8.0, -groove_z), (6.5, -groove_z))
                Line((6.5, -groove_z), (6.5, -groove_z - 3.0))
                Line((6.5, -groove_z - 3.0), (11.0, -groove_z - 3.0))
                Line((11.0, -groove_z - 3.0), (11.0, -38.0))
                ThreePointArc((11.0, -38.0), (13.0 - 2 * c, -38.0 - 2 * c), (13.0, -40.0))
                Line((13.0, -40.0), (16.0, -40.0))
                Line((16.0, -40.0), (17.0, -41.0))
                Line((17.0, -41.0), (17.0, -length + 1.0))
                Line((17.0, -length + 1.0), (16.0, -length))
                Line((16.0, -length), (0, -length))
                Line((0, -length), (0, 0))
            make_face()
        revolve(axis=Axis.Z)
    return p.part
'''

_WORD = re.compile(r"\b([A-Z]+[0-9]*)=(\"[^\"]*\"|[-+0-9.]+)|\b([A-Z])([-+]?[0-9.]+)")


def words(block: str) -> dict[str, str]:
    """The words of a block (N number and comment left out): ``{"G": "1", "X": "20",
    "CR": "0.4", "R105": "1", "_CNAME": '"NAME"'}`` (the last G word of the block)."""
    body = re.sub(r"^N\d+\s*", "", block.split(";")[0].strip())
    out: dict[str, str] = {}
    for m in re.finditer(r"(_?[A-Z][A-Z0-9_]*)=(\"[^\"]*\"|[-+0-9.]+)|\b([A-Z])([-+]?[0-9.]+)",
                         body):
        if m.group(1):
            out[m.group(1)] = m.group(2)
        else:
            out[m.group(3)] = m.group(4)
    return out


def blocks(text: str) -> list[str]:
    """The blocks of one program's text (header, comment and ;$PATH lines left out)."""
    return [ln for ln in text.splitlines() if ln.strip() and not ln.startswith(("%", ";"))]


def programs(text: str) -> dict[str, str]:
    return dict(split_programs(text))


def cycle_calls(text: str, cycle: str) -> list[dict[str, str]]:
    """The R parameters (and _CNAME) in force at each call of ``cycle`` in the main program:
    every assignment before the call, the later ones replacing the earlier."""
    main = blocks(next(iter(programs(text).values())))
    r: dict[str, str] = {}
    out = []
    for b in main:
        w = words(b)
        if re.search(rf"\b{cycle}\s*$", b):
            out.append(dict(r))
            continue
        r.update({k: v for k, v in w.items() if k.startswith("R") and k[1:].isdigit()
                  or k == "_CNAME"})
    return out


def contour_points(blocks_, start):
    """End points (x radius, z) of the plan's contour blocks, the missing axis carried on."""
    x, z = start
    out = []
    for b in blocks_:
        x = b.x if b.x is not None else x
        z = b.z if b.z is not None else z
        out.append((x, z))
    return out


@pytest.fixture(scope="module")
def stepped():
    return generate(PARTS / "stepped_shaft.py", dialect="siemens802")


def test_program_framing(stepped):
    progs = programs(stepped.text)
    assert list(progs) == ["STEPPED_SHAFT.MPF", "STEPPED_SHAFT_C1.SPF"]
    main, sub = progs.values()
    assert main.splitlines()[:2] == ["%_N_STEPPED_SHAFT_MPF", ";$PATH=/_N_MPF_DIR"]
    assert sub.splitlines()[:2] == ["%_N_STEPPED_SHAFT_C1_SPF", ";$PATH=/_N_SPF_DIR"]
    assert blocks(main)[-1].endswith(" M2") and blocks(sub)[-1].endswith(" RET")
    # every block numbered, in one sequence through both programs
    nums = [int(re.match(r"N(\d+) ", b).group(1)) for b in blocks(main) + blocks(sub)]
    assert nums == list(range(1, len(nums) + 1))
    # T D of every tool the plan uses, G96 with its limit LIMS=
    for op in stepped.plan.operations:
        if op.new_tool:
            assert f"T{op.tool.number} D1" in [re.sub(r"^N\d+ ", "", b) for b in blocks(main)]
    g96 = [words(b) for b in blocks(main) if " G96 " in f" {b} "]
    assert g96 and all(w["LIMS"] == "3000" for w in g96)
    assert stepped.report.passed


def test_lcyc95_parameters_are_the_plans(stepped):
    plan = stepped.plan
    rough = [op for op in plan.operations if op.kind == "rough"]
    calls = cycle_calls(stepped.text, "LCYC95")
    assert len(calls) == len(rough) == 1  # cam mode: the finish calls the contour itself
    r, op = calls[0], rough[0]
    assert r["_CNAME"] == '"STEPPED_SHAFT_C1"'
    assert int(r["R105"]) == 1  # roughing, longitudinal, outside
    assert float(r["R106"]) == pytest.approx(max(op.rough.allowance_x, op.rough.allowance_z),
                                             abs=5e-4)
    assert float(r["R108"]) == pytest.approx(op.rough.depth, abs=5e-4)
    assert float(r["R109"]) == 0.0
    assert float(r["R110"]) == pytest.approx(op.rough.retract, abs=5e-4)
    assert float(r["R111"]) == pytest.approx(op.feed, abs=5e-4)
    # the cycle cut what the parameters say: its passes are the plan's depth apart at most
    cuts = [m for m in stepped.toolpath.moves if m.op == "LCYC95" and m.kind == "line"
            and abs(m.start[0] - m.end[0]) < 1e-9 and m.end[1] < m.start[1] - 1.0]
    levels = sorted({round(m.start[0], 6) for m in cuts}, reverse=True)
    assert len(levels) >= 3
    assert max(a - b for a, b in zip(levels, levels[1:])) <= op.rough.depth + 1e-6


def test_control_mode_finishes_with_lcyc95_and_the_edge_radius():
    prog = generate(PARTS / "stepped_shaft.py", dialect="siemens802", comp="control")
    calls = cycle_calls(prog.text, "LCYC95")
    assert [int(c["R105"]) for c in calls] == [1, 5]  # roughing, then finishing
    fin = [op for op in prog.plan.operations if op.name == "finish"][0]
    assert float(calls[1]["R112"]) == pytest.approx(fin.feed) and float(calls[1]["R106"]) == 0
    assert prog.report.passed and prog.report.max_overcut_mm <= 0.01


def _run_contour(sub_name: str, sub_text: str):
    """The contour subprogram run as a path from a point clear of the part."""
    from hnc_cam import nc
    main = (f"%_N_PROBE_MPF\nN1 G18 G23 G71 G90 G95 G40 T2 D1 S500 M3\nN2 G0 X120 Z10\n"
            f"N3 {sub_name}\nN4 M2\n")
    return nc.run(main + sub_text, dialect="siemens802")


@pytest.mark.parametrize("part", ["stepped_shaft.py", "threaded_stud.py", "fresh"])
def test_contour_subprogram_points_are_the_planned_contour(tmp_path, part):
    if part == "fresh":
        path = tmp_path / "shaft.py"
        path.write_text(FRESH)
    else:
        path = PARTS / part
    prog = generate(path, dialect="siemens802", verify=False)
    plan = prog.plan
    progs = programs(prog.text)
    from hnc_cam.post import contour_subprograms
    owners = contour_subprograms(plan)
    subs = [(n, t) for n, t in progs.items() if n.endswith(".SPF")]
    assert len(subs) == len(owners) >= 1
    for (name, text), owner in zip(subs, owners):
        planned = contour_points(owner.blocks, owner.start)
        if owner.blocks[0].z is None:  # the first block starts the contour at the op's Z
            planned[0] = (planned[0][0], owner.start[1])
        tp = _run_contour(name[:-4], text)
        ends = [m.end for m in tp.moves if m.kind in ("line", "arc", "rapid", "cw", "ccw")][1:]
        # every planned point is a point of the written contour, in order, to 0.001 mm
        j = 0
        for p in planned:
            while j < len(ends) and math.dist(ends[j], p) > 1e-3:
                j += 1
            assert j < len(ends), (name, p)
            j += 1
        written = blocks(text)[:-1]
        corner_words = [b for b in written if "CHF=" in b or "RND=" in b]
        assert len(written) + len(corner_words) == len(owner.blocks)


@pytest.mark.parametrize("comp", ["control", "cam"])
def test_chf_and_rnd_replace_exactly_the_chamfers_and_rounds(tmp_path, comp):
    path = tmp_path / "shaft.py"
    path.write_text(FRESH)
    prog = generate(path, dialect="siemens802", comp=comp)
    assert prog.report.passed and prog.report.max_overcut_mm <= 0.01
    sub = [t for n, t in programs(prog.text).items() if n.endswith(".SPF")][0]
    ws = [words(b) for b in blocks(sub)]
    owner = [op for op in prog.plan.operations if op.name == "finish"][0]
    arcs = [b for b in owner.blocks if b.arc]
    if comp == "control":
        # the part contour: two 45 degree chamfers (1 mm legs: 1.414 long) and an R2 round
        # between lines, its only arc
        assert [w["CHF"] for w in ws if "CHF" in w] == ["1.414", "1.414"]
        assert [w["RND"] for w in ws if "RND" in w] == ["2"] and len(arcs) == 1
        chf = [w for w in ws if "CHF" in w][0]
        assert (chf["X"], chf["Z"]) == ("16", "0")  # the corner of the two lines
    else:
        # the tip path: each convex corner rounded by the nose radius (the chamfers' ends
        # too), the concave R2 round less the nose radius; every one between two lines
        r = owner.tool.nose_radius
        assert sorted(float(w["RND"]) for w in ws if "RND" in w) == pytest.approx(
            sorted(abs(b.r) for b in arcs))
        assert [float(w["RND"]) for w in ws if "RND" in w].count(pytest.approx(2 - r)) == 1
        assert not [w for w in ws if "CHF" in w]
    # every arc of the plan became a corner word: no G2/G3 is left in this contour
    assert not [w for w in ws if w.get("G") in ("2", "3")]


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_fresh_part_with_groove_thread_and_round(tmp_path, comp):
    path = tmp_path / "shaft.py"
    path.write_text(FRESH)
    prog = generate(path, dialect="siemens802", comp=comp)
    assert prog.report.passed, prog.report.summary()
    assert prog.report.max_overcut_mm <= 0.01
    assert not prog.toolpath.warnings
    # the control-compensated finish runs the contour subprogram under LCYC95 finishing
    finish = "finish LCYC95" if comp == "control" else "finish contour"
    assert prog.operations == ["face G1", "rough LCYC95", finish, "profile contour",
                               "groove LCYC93", "thread LCYC97"]
    if comp == "control":
        assert "R105=5" in prog.text  # LCYC95's finishing type, longitudinal outside
    plan = prog.plan
    groove = [op for op in plan.operations if op.kind == "groove"][0]
    (g,) = cycle_calls(prog.text, "LCYC93")
    w = groove.tool.insert.width
    assert float(g["R101"]) == pytest.approx(min(groove.passes))  # the groove's left edge
    assert float(g["R114"]) == pytest.approx(max(groove.passes) + w - min(groove.passes))
    assert float(g["R107"]) == pytest.approx(w)
    assert float(g["R100"]) / 2 - float(g["R115"]) == pytest.approx(groove.groove.x_bottom,
                                                                     abs=1e-3)
    # the groove's bottom is where the plan puts it: the cycle's deepest point
    gm = [m for m in prog.toolpath.moves if m.op == "LCYC93"]
    assert min(m.end[0] for m in gm) == pytest.approx(groove.groove.x_bottom, abs=1e-6)
    thread = [op for op in plan.operations if op.kind == "thread"][0]
    t = thread.thread
    (th,) = cycle_calls(prog.text, "LCYC97")
    assert float(th["R100"]) / 2 - float(th["R111"]) == pytest.approx(t.x_root, abs=1e-3)
    assert float(th["R103"]) == pytest.approx(t.z_end) and float(th["R104"]) == t.lead
    assert int(th["R114"]) == t.starts and int(th["R105"]) == 1
    tm = [m for m in prog.toolpath.moves if m.op == "LCYC97" and m.kind == "thread"]
    assert min(m.end[0] for m in tm) == pytest.approx(t.x_root, abs=1e-3)
    if comp == "control":
        # roughing, then the finishing pass by the cycle with the edge's nose radius
        assert [int(c["R105"]) for c in cycle_calls(prog.text, "LCYC95")] == [1, 5]
    else:
        assert [int(c["R105"]) for c in cycle_calls(prog.text, "LCYC95")] == [1]


def test_output_one_file_and_a_folder(tmp_path, capsys):
    from hnc_cam.cli import main
    one = tmp_path / "stud.mpf"
    rc = main(["generate", str(PARTS / "threaded_stud.py"), "--dialect", "siemens802",
               "-o", str(one)])
    assert rc == 0, capsys.readouterr().err
    text = one.read_text()
    assert [n for n, _ in split_programs(text)] == ["THREADED_STUD.MPF", "THREADED_STUD_C1.SPF",
                                                    "THREADED_STUD_C2.SPF"]
    out = tmp_path / "nc"
    rc = main(["generate", str(PARTS / "threaded_stud.py"), "--dialect", "siemens802",
               "-o", str(out) + "/"])
    assert rc == 0, capsys.readouterr().err
    assert sorted(os.listdir(out)) == ["THREADED_STUD.MPF", "THREADED_STUD_C1.SPF",
                                       "THREADED_STUD_C2.SPF"]
    # the files are the programs of the one-file output
    assert "".join((out / n).read_text() for n, _ in split_programs(text)) == text
    capsys.readouterr()
    # the main program alone finds its subprograms beside it and runs as the one file does
    from hnc_cam import nc
    rc = main(["run", str(out / "THREADED_STUD.MPF"), "--dialect", "siemens802"])
    assert rc == 0, capsys.readouterr().err
    alone = nc.run_file(str(out / "THREADED_STUD.MPF"), dialect="siemens802")
    whole = nc.run(text, dialect="siemens802")
    assert len(alone.moves) == len(whole.moves)
    assert [c for m in alone.moves for c in m.end] == pytest.approx(
        [c for m in whole.moves for c in m.end])
    # an existing folder without a trailing slash is a folder too
    rc = main(["generate", str(PARTS / "threaded_stud.py"), "--dialect", "siemens802",
               "-o", str(out)])
    assert rc == 0


def test_verify_reads_the_stock_and_parameters_from_the_802_header(tmp_path, capsys):
    """``; STOCK`` and ``; PARAMETERS`` after ``%_N_..._MPF`` and ``;$PATH`` are the header
    verify reads, as ``(STOCK ...)`` is in the HNC and FANUC programs."""
    from hnc_cam.check import program_header
    from hnc_cam.cli import main
    one = tmp_path / "shaft.mpf"
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--dialect", "siemens802",
               "--set", "d1=18", "-o", str(one)])
    assert rc == 0, capsys.readouterr().err
    params, stock = program_header(str(one))
    assert params["d1"] == "18.0" and stock == "45x117+2"
    capsys.readouterr()
    rc = main(["verify", str(one), "--model", str(PARTS / "stepped_shaft.py"), "--dialect",
               "siemens802"])
    out = capsys.readouterr().out
    assert rc == 0 and "PASS" in out


def test_folder_output_never_replaces_a_link_and_writes_nothing(tmp_path, capsys):
    from hnc_cam.cli import main
    out = tmp_path / "nc"
    out.mkdir()
    victim = tmp_path / "precious.txt"
    victim.write_text("keep me\n")
    os.symlink(victim, out / "STEPPED_SHAFT_C1.SPF")
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--dialect", "siemens802",
               "-o", str(out) + "/"])
    err = capsys.readouterr().err
    assert rc == 2
    msgs = [ln for ln in err.splitlines() if ln.startswith("error")]
    assert len(msgs) == 1 and "STEPPED_SHAFT_C1.SPF" in msgs[0] and "link" in msgs[0]
    assert victim.read_text() == "keep me\n"
    assert sorted(os.listdir(out)) == ["STEPPED_SHAFT_C1.SPF"]  # no MPF, no temporaries
    assert os.path.islink(out / "STEPPED_SHAFT_C1.SPF")


def test_json_names_the_802_cycles(tmp_path, capsys):
    import json
    from hnc_cam.cli import main
    path = tmp_path / "shaft.py"
    path.write_text(FRESH)
    js = tmp_path / "plan.json"
    rc = main(["generate", str(path), "--dialect", "siemens802", "-o", str(tmp_path / "s.mpf"),
               "--json", str(js), "--explain"])
    err = capsys.readouterr().err
    assert rc == 0, err
    doc = json.loads(js.read_text())
    assert doc["dialect"] == "siemens802"
    assert [o["cycle"] for o in doc["operations"]] == ["G1", "LCYC95", "contour", "contour",
                                                      "LCYC93", "LCYC97"]
    assert "ROUGH OD LCYC95" in err and "LCYC97" not in doc["operations"][0]["summary"]


def test_family_writes_one_file_per_row(tmp_path, capsys):
    from hnc_cam.cli import main
    table = tmp_path / "t.csv"
    table.write_text("length,program_number\n100,7\n95,8\n")
    out = tmp_path / "out"
    rc = main(["family", str(PARTS / "stepped_shaft.py"), "--table", str(table), "--out",
               str(out), "--jobs", "1", "--dialect", "siemens802"])
    assert rc == 0, capsys.readouterr().err
    files = sorted(p.name for p in out.iterdir() if p.name != "summary.csv")
    assert len(files) == 2
    for f in files:
        text = (out / f).read_text()
        names = [n for n, _ in split_programs(text)]
        assert names == ["STEPPED_SHAFT.MPF", "STEPPED_SHAFT_C1.SPF"]
    summary = (out / "summary.csv").read_text()
    assert "LCYC95" in summary


def test_program_names():
    from hnc_cam.post.filters import program_name
    assert program_name("stepped_shaft") == "STEPPED_SHAFT"
    assert program_name("2-shaft v3") == "PN2_SHAFT_V3"
    assert program_name("") == "PART"
    assert len(program_name("a" * 80)) == 24


def _b(kind, x=None, z=None, r=None, feed=None, label=""):
    from hnc_cam.plan.model import Block
    return Block(kind, x=x, z=z, r=r, feed=feed, label=label)


def test_corner_words_only_where_the_control_rebuilds_the_points():
    from hnc_cam.post.corners import corner_blocks
    # a 45 degree chamfer of 1 mm legs between a face and a diameter: CHF= its length
    chamfer = [_b("line", 7.0, 0.0), _b("line", 8.0, -1.0), _b("line", 8.0, -20.0)]
    out = corner_blocks(chamfer, (0.0, 0.0))
    assert [(w, round(v, 3)) for _, w, v in out] == [("CHF", 1.414), ("", 0.0)]
    assert (out[0][0].x, out[0][0].z) == pytest.approx((8.0, 0.0))
    # a line that is not symmetric about the corner is no chamfer: kept as it is
    skew = [_b("line", 7.0, 0.0), _b("line", 8.0, -2.0), _b("line", 8.0, -20.0)]
    assert [w for _, w, _ in corner_blocks(skew, (0.0, 0.0))] == ["", "", ""]
    # the written chamfer is rebuilt from numbers rounded to 0.001 mm: a 1 mm chamfer at a
    # corner 0.3 mm off the written grid still lands on the planned points
    off = [_b("line", 7.0003, 0.0), _b("line", 8.0003, -1.0), _b("line", 8.0003, -20.0)]
    out = corner_blocks(off, (0.0, 0.0))
    assert [w for _, w, _ in out] == ["CHF", ""]
    # a round tangent to both lines: RND= its radius; an arc that is not tangent stays an arc
    rnd = [_b("line", 10.0, -23.0), _b("cw", 12.0, -25.0, r=2.0), _b("line", 20.0, -25.0)]
    out = corner_blocks(rnd, (10.0, 0.0))
    assert [(w, v) for _, w, v in out] == [("RND", 2.0), ("", 0.0)]
    assert (out[0][0].x, out[0][0].z) == pytest.approx((10.0, -25.0))
    not_tangent = [_b("line", 10.0, -23.0), _b("cw", 12.0, -25.0, r=2.5), _b("line", 20.0, -25.0)]
    assert [w for _, w, _ in corner_blocks(not_tangent, (10.0, 0.0))] == ["", "", ""]
    # a labelled or fed corner block is kept (a cycle's reference or a feed change)
    fed = [_b("line", 7.0, 0.0), _b("line", 8.0, -1.0, feed=0.1), _b("line", 8.0, -20.0)]
    assert [w for _, w, _ in corner_blocks(fed, (0.0, 0.0))] == ["", "", ""]


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_part_off_in_802(comp):
    """Held in the chuck, the part is parted off last: the blade's G97 speed, its T D, the
    left end's corner and the plunge to the centre as G1 blocks; the piece that falls off
    verifies."""
    prog = generate(PARTS / "stepped_shaft.py", "45x140+2", dialect="siemens802", comp=comp,
                    grip=20)
    assert prog.report.passed and prog.report.max_overcut_mm <= 0.01
    assert prog.operations[-1] == "partoff G1"
    op = prog.plan.operations[-1]
    main = [re.sub(r"^N\d+ ", "", b) for b in blocks(next(iter(programs(prog.text).values())))]
    i = main.index(f"T{op.tool.number} D1")
    assert f"G97 S{round(op.speed)} M3" in main[i:]
    assert min(m.end[0] for m in prog.toolpath.moves if m.kind == "line") < 0  # past the axis


#: a part with a cove (an R5 arc) between a diameter and a shoulder: an R1 round between the
#: diameter and the cove, a 1 mm chamfer between the cove and the next diameter (points worked
#: out by hand: the round's centre 1 mm inside the line and 5 - 1 from the cove's centre)
COVE = '''\
from build123d import (Axis, BuildLine, BuildPart, BuildSketch, Line, Plane, ThreePointArc,
                       make_face, revolve)

STOCK = "32x34+2"


def part():
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Line((0, 0), (8.0, 0))
                Line((8.0, 0), (8.0, -9.464101615))
                ThreePointArc((8.0, -9.464101615), (8.133974596, -9.964101615), (8.5, -10.330127019))
                ThreePointArc((8.5, -10.330127019), (9.378544109, -10.729786549),
                              (10.317508043, -10.953201463))
                Line((10.317508043, -10.953201463), (11.0, -11.684094566))
                Line((11.0, -11.684094566), (11.0, -20.0))
                Line((11.0, -20.0), (15.0, -20.0))
                Line((15.0, -20.0), (15.0, -32.0))
                Line((15.0, -32.0), (0, -32.0))
                Line((0, -32.0), (0, 0))
            make_face()
        revolve(axis=Axis.Z)
    return p.part
'''


def test_chf_and_rnd_next_to_an_arc_in_the_written_contour(tmp_path):
    path = tmp_path / "cove.py"
    path.write_text(COVE)
    prog = generate(path, dialect="siemens802", comp="control")
    assert prog.report.passed and prog.report.max_overcut_mm <= 0.01
    sub = [t for n, t in programs(prog.text).items() if n.endswith(".SPF")][0]
    ws = [words(b) for b in blocks(sub)]
    # the diameter runs to the corner of the line and the cove (X16 Z-10) with RND=1, the
    # cove (G2, CR=5) to its corner with the next diameter (X22 Z-11) with CHF=1
    rnd = [w for w in ws if "RND" in w]
    chf = [w for w in ws if "CHF" in w]
    assert [(w["G"], w["X"], w["Z"], w["RND"]) for w in rnd] == [("1", "16", "-10", "1")]
    assert [(w["G"], w["X"], w["Z"], w["CR"], w["CHF"]) for w in chf] == [("2", "22", "-11", "5", "1")]
    # the contour as the control builds it from those words: the planned points, to 0.001 mm
    owner = [op for op in prog.plan.operations if op.name == "finish"][0]
    name = [n for n in programs(prog.text) if n.endswith(".SPF")][0]
    planned = contour_points(owner.blocks, owner.start)[1:]
    ends = [m.end for m in _run_contour(name[:-4], sub).moves][-len(planned):]
    assert max(math.dist(p, q) for p, q in zip(ends, planned)) <= 1e-3


def test_corner_words_next_to_arcs_in_cr_and_ik_form():
    from hnc_cam.plan.model import Block
    from hnc_cam.post.corners import corner_blocks
    r140 = math.sqrt(140.0)
    # a line, an R2 round, a G2 R10 about (20, -20), an R2 round, a face line (the corners
    # worked out by hand: the rounds' centres 12 from (20, -20), 2 inside the lines)
    t1, t2 = (20.0, -20.0 + r140), (20.0 - 20.0 / 12, -20.0 + r140 * 10 / 12)
    t3, t4 = (20.0 - r140 * 10 / 12, -20.0 + 20.0 / 12), (20.0 - r140, -20.0)
    cr = [Block("line", *t1), Block("ccw", *t2, r=2.0), Block("cw", *t3, r=10.0),
          Block("ccw", *t4, r=2.0), Block("line", 0.0, -20.0)]
    out = corner_blocks(cr, (20.0, 0.0))
    assert [(b.kind, w, v) for b, w, v in out] == [("line", "RND", 2.0), ("cw", "RND", 2.0), ("line", "", 0.0)]
    assert (out[0][0].x, out[0][0].z) == pytest.approx((20.0, -10.0))
    assert (out[1][0].x, out[1][0].z, out[1][0].r) == pytest.approx((10.0, -20.0, 10.0))
    # the arc in I K form (from its start): after the corner its I K are taken from the corner
    ik = list(cr)
    ik[2] = Block("cw", *t3, i=20.0 - t2[0], k=-20.0 - t2[1])
    out = corner_blocks(ik, (20.0, 0.0))
    assert [w for _, w, _ in out] == ["RND", "RND", ""]
    assert (out[1][0].i, out[1][0].k) == pytest.approx((0.0, -10.0))
    # a round of another radius than the corner's is not a corner: everything kept
    wrong = list(cr)
    wrong[1] = Block("ccw", *t2, r=2.5)
    assert [w for _, w, _ in corner_blocks(wrong, (20.0, 0.0))][:2] == ["", ""]


def test_summary_names_the_802_program_and_its_lcyc95_finish():
    ctrl = generate(PARTS / "stepped_shaft.py", dialect="siemens802", comp="control", verify=False)
    cam = generate(PARTS / "stepped_shaft.py", dialect="siemens802", comp="cam", verify=False)
    assert ctrl.summary().startswith("%_N_STEPPED_SHAFT_MPF: face G1, rough LCYC95, finish LCYC95,")
    # the tip path (CAM compensation) calls the contour subprogram: no LCYC95 finishing
    assert cam.summary().startswith("%_N_STEPPED_SHAFT_MPF: face G1, rough LCYC95, finish contour,")
    assert "R105=5" in ctrl.text and "R105=5" not in cam.text
    # HNC and FANUC: their program number and their own names, as before
    hnc = generate(PARTS / "stepped_shaft.py", comp="control", verify=False)
    fanuc = generate(PARTS / "stepped_shaft.py", dialect="fanuc0it", comp="control", verify=False)
    assert hnc.summary().startswith("O0001 stepped_shaft: face G01, rough G71, finish contour,")
    assert fanuc.summary().startswith("O0001 stepped_shaft: face G01, rough G71, finish G70,")
    # the JSON plan and the report's operation table name the same cycles as the summary
    from hnc_cam.plan.export import plan_json
    from hnc_cam.report.data import plan_operations
    for prog in (ctrl, cam, hnc, fanuc):
        names = [o.split(" ", 1)[1] for o in prog.operations]
        assert [o["cycle"] for o in plan_json(prog)["operations"]] == names
        assert [o["cycle"] for o in plan_operations(prog.plan, prog.labels)] == names
    assert [o["cycle"] for o in plan_json(ctrl)["operations"]][:3] == ["G1", "LCYC95", "LCYC95"]


#: a tool library written by a user whose offsets sit in other registers than the turret
#: positions: the roughing tool at position 1 keeps its offsets in register 3, the finishing
#: tool at 2 in register 4, the parting blade at 8 in register 5
SHIFTED_TOOLS = '''\
[[tool]]
number = 1
register = 3
name = "OD roughing 80 deg"
insert = "CNMG120408"
holder = "PCLNR2525M12"
tip = 3
kind = "turn"
uses = ["rough", "face"]
depth = 1.5

[[tool]]
number = 2
register = 4
name = "OD finishing 35 deg"
insert = "VNMG160404"
holder = "SVJBR2525M16"
tip = 3
kind = "turn"
uses = ["finish", "rough", "profile"]
depth = 1.0

[[tool]]
number = 8
register = 5
name = "Parting blade 3 mm"
insert = "GROOVE3.0"
radius = 0.2
tip = 4
kind = "part"
uses = ["part"]
max_depth = 26.0
feed_finish = 0.06
vc_finish = 100.0
max_rpm = 1500.0
'''


def test_t_d_names_the_library_register_of_each_tool(tmp_path):
    lib = tmp_path / "tools.toml"
    lib.write_text(SHIFTED_TOOLS)
    prog = generate(PARTS / "stepped_shaft.py", "45x140+2", dialect="siemens802", comp="control",
                    tools=lib, grip=20)
    main = [re.sub(r"^N\d+ ", "", b) for b in blocks(next(iter(programs(prog.text).values())))]
    assert [b for b in main if re.fullmatch(r"T\d+ D\d+", b)] == ["T1 D3", "T2 D4", "T8 D5"]
    # the 802 reader takes each D as the tool's register: the moves of T2 carry register 4,
    # whose 0.4 mm nose the control's compensation used; the part verifies
    regs = {(m.tool, m.register) for m in prog.toolpath.moves if m.kind != "dwell"}
    assert {(1, 3), (2, 4), (8, 5)} <= regs and not any(t and r == t for t, r in regs)
    assert prog.report.passed and prog.report.max_overcut_mm <= 0.01
