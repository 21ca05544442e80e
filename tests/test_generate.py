"""generate on the parts/ families: interpreter run and verification in both compensation
modes, the CLI's outputs and refusals (nothing written on bad input)."""
from __future__ import annotations

from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.errors import HncError, PartError, PlanError
from hnc_cam.plan.api import generate

REPO = Path(__file__).resolve().parents[1]
PARTS = REPO / "parts"

pytestmark = pytest.mark.cad


FAMILIES = {
    "stepped_shaft.py": [{}, {"length": "90", "d1": "18", "l2": "45"}],
    "grooved_shaft.py": [{}, {"length": "90", "d2": "38"}, {"relief_width": "5", "arc_depth": "1.0"}],
    "flange.py": [{}, {"diameter": "110", "thickness": "12"}, {"hub_diameter": "60", "fillet": "2"}],
    "bushing.py": [{}, {"outer_diameter": "44", "bore_diameter": "24", "length": "34"},
                   {"inner_chamfer": "1.5", "chamfer": "0.5"}],
    "cast_blank.py": [{}, {"waves": "2", "wave_length": "30"}],
    "threaded_stud.py": [{}, {"thread_length": "20", "length": "48"},
                         {"thread_diameter": "16", "relief_diameter": "13.6", "collar_diameter": "26"}],
    "cq_pin.py": [{}, {"length": "44", "groove_z": "10"}, {"diameter": "18", "head_diameter": "26"}],
}
CASES = [(f, p) for f, ps in FAMILIES.items() for p in ps]

#: the operation that shows each family was planned the way its shape asks for
EXPECTED = {"stepped_shaft.py": "G71", "grooved_shaft.py": "G71E", "flange.py": "G72",
            "bushing.py": "bore_rough", "cast_blank.py": "G73", "threaded_stud.py": "G76",
            "cq_pin.py": "groove"}


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("part,params", CASES, ids=[f"{f[:-3]}-{i}" for f, ps in FAMILIES.items()
                                                    for i in range(len(ps))])
def test_family_generates_runs_and_verifies(part, params, comp):
    prog = generate(PARTS / part, params=params, comp=comp, verify=True)
    assert prog.toolpath is not None and prog.toolpath.moves  # ran without alarm
    assert prog.report is not None and prog.report.passed, prog.report.summary()
    assert prog.report.max_overcut_mm <= 0.01
    assert prog.cycle_time_s > 0
    if comp == "cam":
        assert "G41" not in prog.text and "G42" not in prog.text
    else:
        assert "G42" in prog.text or "G41" in prog.text


@pytest.mark.parametrize("part", sorted(EXPECTED))
def test_operation_choice_per_family(part):
    plan = generate(PARTS / part, verify=False).plan
    names = {op.cycle for op in plan.operations} | {op.name for op in plan.operations}
    assert EXPECTED[part] in names, [(op.name, op.cycle, op.reason) for op in plan.operations]
    for op in plan.operations:
        assert op.reason  # every operation says why


def test_cli_generate_writes_program_and_summary(tmp_path, capsys):
    out = tmp_path / "o.nc"
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--set", "length=95",
               "--program-number", "12", "--comp", "control", "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 0
    text = out.read_text()
    assert text.startswith("%0012\n") and "(PARAMETERS " in text and "length=95" in text
    assert "O0012 stepped_shaft:" in err and "cycle time" in err and "verified: pass" in err


def test_cli_formatting_and_cycle_options(tmp_path, capsys):
    """--number-format, --block-numbers, --thread-cycle and --face-cycle reach the program
    (through plan.command._options), and the program still verifies."""
    out = tmp_path / "o.nc"
    rc = main(["generate", str(PARTS / "threaded_stud.py"), "--number-format", "zero",
               "--block-numbers", "pq", "--thread-cycle", "g82", "--face-cycle", "g01",
               "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 0 and "verified: pass" in err, err
    text = out.read_text()
    lines = text.splitlines()
    assert "G82 " in text and "G76 " not in text and "G81 " not in text
    assert "G00 G40 Z80.0" in lines and "G00 X100.0" in lines
    refs = sorted({int(w[1:]) for ln in lines if ln.startswith(("G71", "G72", "G73"))
                   for w in ln.split() if w[0] in "PQ"})
    assert [int(ln.split()[0][1:]) for ln in lines if ln.startswith("N")] == refs
    assert any(ln.startswith("G71 ") and " P1 Q2 " in ln for ln in lines)
    g82 = [ln for ln in lines if ln.startswith("G82 ")]
    assert len(g82) >= 4 and g82[-1] == g82[-2]  # passes to depth, the last one repeated
    assert all(ln.endswith(" F1.5") for ln in g82)


@pytest.mark.parametrize("argv,msg", [
    (["--set", "nosuch=1"], "nosuch"),
    (["--stock", "30x120+2"], "smaller than the part's largest diameter"),
    (["--stock", "45x60"], "too short"),
])
def test_cli_bad_input_exit_2_and_nothing_written(tmp_path, capsys, argv, msg):
    out = tmp_path / "o.nc"
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), *argv, "-o", str(out), "--no-verify"])
    err = capsys.readouterr().err
    assert rc == 2
    assert msg in err and err.startswith("error:")
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_cli_tool_missing_from_the_library(tmp_path, capsys):
    """A --tools library without a finishing tool: exit 2, the message names what is missing,
    nothing written."""
    lib = (REPO / "hnc_cam" / "data" / "tools.toml").read_text()
    first = lib.split("[[tool]]")[:2]  # the header comments and tool 1 (roughing) only
    tools = tmp_path / "lib" / "tools.toml"
    tools.parent.mkdir()
    tools.write_text("[[tool]]".join(first))
    out = tmp_path / "o.nc"
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--tools", str(tools), "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("error:")
    assert "no OD finishing tool" in err
    assert not out.exists()


@pytest.mark.parametrize("pitch,needs", [("1.0", "16ER1ISO"), ("2.0", "16ER2ISO")])
def test_threaded_stud_pitch_without_an_insert_is_refused(tmp_path, capsys, pitch, needs):
    """The thread's pitch comes from the part (THREADS); the bundled 16ER1.5ISO cuts 1.5 only,
    so pitch 1 and 2 are refused naming the thread and the insert it needs; nothing written."""
    out = tmp_path / "o.nc"
    # pitch 2 needs a deeper relief than the default (the part itself checks that)
    rc = main(["generate", str(PARTS / "threaded_stud.py"), "--set", f"pitch={pitch}",
               "--set", "relief_diameter=17.2", "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("error:")
    assert f"external thread M20x{float(pitch):g} from Z0 to Z-22" in err
    assert f"cuts pitch {float(pitch):g} mm" in err and needs in err
    assert list(tmp_path.iterdir()) == []


def test_threaded_stud_pitch_1_with_a_partial_profile_insert(tmp_path):
    """With an A60 partial-profile insert (0.5-1.5 mm) pitch 1.0 is cut at F1 and verifies;
    pitch 2.0 is still refused (needs AG60/G60 or 16ER2ISO)."""
    lib = (REPO / "hnc_cam" / "data" / "tools.toml").read_text()
    assert 'insert = "16ER1.5ISO"' in lib
    tools = tmp_path / "tools.toml"
    tools.write_text(lib.replace('insert = "16ER1.5ISO"', 'insert = "16ERA60"'))
    prog = generate(PARTS / "threaded_stud.py", params={"pitch": "1.0"}, tools=str(tools))
    assert prog.report.passed, prog.report.summary()
    g76 = [ln for ln in prog.text.splitlines() if " G76 " in ln]
    assert len(g76) == 1 and g76[0].endswith(" F1") and " K0.613 " in g76[0]
    with pytest.raises(PlanError, match=r"pitch 2 mm.*16ERA60 \(pitch 0.5-1.5.*16ERAG60"):
        generate(PARTS / "threaded_stud.py", params={"pitch": "2.0", "relief_diameter": "17.2"},
                 tools=str(tools),
                 verify=False)


@pytest.mark.parametrize("step,stock", [("stepped_shaft.step", "45x120+2"),
                                        ("spline_knob.step", "45x120+2")])
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_step_files_generate_and_verify(step, stock, comp):
    prog = generate(REPO / "tests" / "data" / step, stock, comp=comp)
    assert prog.report.passed, prog.report.summary()


GOLDEN_PARTS = REPO / "tests" / "data" / "golden" / "parts"


@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("part", sorted(FAMILIES))
def test_bundled_part_program_golden(part, comp):
    """The HNC-21T program of each bundled part (default parameters and stock) stays byte for
    byte (regenerate with HNC_CAM_UPDATE_GOLDEN=1 after a deliberate change, and review the
    diff)."""
    import os
    text = generate(PARTS / part, comp=comp, verify=False).text
    path = GOLDEN_PARTS / f"{part[:-3]}_{comp}.nc"
    if os.environ.get("HNC_CAM_UPDATE_GOLDEN"):
        path.parent.mkdir(exist_ok=True)
        path.write_text(text)
    assert text == path.read_text()


# ---------------------------------------------------------------- the plan as JSON

@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it"])
def test_json_plan_has_each_operation_as_explain_says_it(tmp_path, capsys, dialect):
    import json
    out, js = tmp_path / "o.nc", tmp_path / "plan.json"
    rc = main(["generate", str(PARTS / "threaded_stud.py"), "--explain", "--dialect", dialect,
               "--json", str(js), "-o", str(out)])
    err = capsys.readouterr().err
    assert rc == 0 and out.exists()
    doc = json.loads(js.read_text())
    ops = doc["operations"]
    explain = [ln for ln in err.splitlines() if ln.startswith("  ") and ". " in ln
               and not ln.startswith("  note:")]
    # every operation of --explain, in order, with its label line and reason
    assert [f"  {o['index']}. {o['summary']}: {o['reason']}" for o in ops] == explain
    prog = generate(PARTS / "threaded_stud.py", dialect=dialect)
    assert [o["name"] for o in ops] == [op.name for op in prog.plan.operations]
    assert [o["cycle"] for o in ops] == [c.split(" ", 1)[1] for c in prog.operations]
    for o, op in zip(ops, prog.plan.operations):
        assert o["reason"] and o["spindle"]["cap_rpm"] == pytest.approx(op.max_rpm)
        assert o["spindle"]["cap_rpm"] <= doc["machine_max_rpm"]
        assert o["tool"]["number"] == op.tool.number and o["feed_mm_rev"] == pytest.approx(op.feed)
        z = o["zone"]
        assert z["diameter_min"] <= z["diameter_max"] and z["z_min"] <= z["z_max"]
    # the thread's zone reaches its root and its end
    th = [o for o in ops if o["kind"] == "thread"][0]
    top = [op for op in prog.plan.operations if op.kind == "thread"][0].thread
    assert th["zone"]["diameter_min"] == pytest.approx(2 * top.x_root, abs=1e-4)
    assert th["zone"]["z_min"] <= top.z_end + 1e-4
    v = doc["verification"]
    assert v["pass"] is True and v["max_overcut_mm"] <= 0.01
    # the HNC-21T roughing cycle of this stud is capped: the JSON says at what speed
    rough = [o for o in ops if o["name"] == "rough"][0]
    assert (rough["spindle"]["unclamped_rpm"] is not None) == \
        ([op for op in prog.plan.operations if op.name == "rough"][0].unclamped is not None)


def test_json_to_stdout_and_unverified(tmp_path, capsys):
    import json
    out = tmp_path / "o.nc"
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--no-verify", "--json", "-",
               "-o", str(out)])
    doc = json.loads(capsys.readouterr().out)
    assert rc == 0 and doc["verification"] is None and doc["operations"]


def test_json_to_stdout_with_the_program_on_stdout_is_refused(tmp_path, capsys):
    rc = main(["generate", str(PARTS / "stepped_shaft.py"), "--json", "-"])
    cap = capsys.readouterr()
    err = cap.err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "--json -" in err[0] and cap.out == ""


def test_json_is_absent_when_the_plan_is_refused(tmp_path, capsys):
    js = tmp_path / "plan.json"
    rc = main(["generate", str(PARTS / "threaded_stud.py"), "--set", "thread_length=2.2",
               "--json", str(js), "-o", str(tmp_path / "o.nc")])
    assert rc == 2 and not js.exists()
