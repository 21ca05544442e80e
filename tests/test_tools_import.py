"""``hnc-cam tools import``: Fusion 360 tool library JSON to our TOML."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

from hnc_cam.cli import main
from hnc_cam.tooling import load_tools
from hnc_cam.tools_import import convert, import_file

#: a library as Fusion 360 exports it: a mill, an OD turning tool, a boring bar, a grooving
#: and a threading tool (field names as in its JSON: type, description, unit, geometry
#: SC/RA/TC/SCTY/INSD/S/RE, holder, post-process number, start-values presets v_c/f_n)
LIBRARY = {
    "data": [
        {"type": "flat end mill", "description": "10mm 3FL", "unit": "millimeters",
         "geometry": {"DC": 10, "NOF": 3}, "post-process": {"number": 20}},
        {"type": "turning general", "description": "OD rough CNMG", "unit": "millimeters",
         "product-id": "CNMG 12 04 08-PM",
         "geometry": {"SC": "C", "RA": 0, "TC": "M", "SCTY": "G", "INSD": 12.7, "S": 4.76,
                      "RE": 0.8, "HAND": "R", "EPSR": 80},
         "holder": {"product-id": "PCLNR2525M12", "HAND": "R", "W": 25, "H": 25},
         "post-process": {"number": 1, "diameter-offset": 1, "turret": 0, "comment": "rough"},
         "start-values": {"presets": [
             {"name": "Steel rough", "v_c": 190, "f_n": 0.28, "stepdown": 2.0},
             {"name": "Steel finish", "v_c": 230, "f_n": 0.12}]},
         "coolant": "flood"},
        {"type": "turning boring", "description": "ID bore CCMT", "unit": "millimeters",
         "geometry": {"SC": "C", "RA": 7, "TC": "M", "SCTY": "T", "INSD": 9.525, "S": 3.97,
                      "RE": 0.4},
         "holder": {"product-id": "S16Q-SCLCR09"},
         "post-process": {"number": 3}},
        {"type": "turning grooving", "description": "Groove 3mm", "unit": "millimeters",
         "geometry": {"CW": 3.0, "RE": 0.2}, "post-process": {"number": 7}},
        {"type": "turning threading", "description": "OD thread 1.5", "unit": "millimeters",
         "geometry": {"TP": 1.5}, "post-process": {"number": 4}},
    ],
    "version": 19,
}


def test_turning_tools_map_to_a_library_that_loads(tmp_path):
    src = tmp_path / "lib.json"
    src.write_text(json.dumps(LIBRARY))
    out = tmp_path / "tools.toml"
    assert main(["tools", "import", str(src), "-o", str(out)]) == 0
    lib = load_tools(out)
    by = {t.number: t for t in lib.tools}
    assert sorted(by) == [1, 3, 4, 7]  # the end mill is skipped
    t1 = by[1]
    assert t1.insert.code == "CNMG120408" and t1.insert.nose_radius == 0.8
    assert t1.holder == "PCLNR2525M12" and t1.approach == 95.0  # holder style L
    assert (t1.tip, t1.kind, t1.register) == (3, "turn", 1)
    assert (t1.vc_rough, t1.feed_rough, t1.vc_finish, t1.feed_finish, t1.depth) == \
        (190.0, 0.28, 230.0, 0.12, 2.0)
    t3 = by[3]
    assert t3.insert.code == "CCMT09T304" and t3.insert.clearance == 7
    assert (t3.tip, t3.kind) == (2, "bore")
    assert by[7].insert.kind == "groove" and by[7].insert.width == 3.0
    assert by[4].insert.code == "16ER1.5ISO" and by[4].tip == 8


def test_unmapped_fields_are_reported(tmp_path, capsys):
    src = tmp_path / "lib.json"
    src.write_text(json.dumps(LIBRARY))
    assert main(["tools", "import", str(src)]) == 0
    cap = capsys.readouterr()
    assert cap.out.count("[[tool]]") == 4
    assert "not mapped: coolant" in cap.err
    assert "geometry not mapped: EPSR" in cap.err
    assert "no start-values presets" in cap.err  # the boring bar has none
    assert "skipped (not turning tools): flat end mill x1" in cap.err


def test_inch_library_is_converted():
    lib = {"data": [{"type": "turning general", "description": "inch", "unit": "inches",
                     "geometry": {"SC": "D", "RA": 0, "TC": "M", "SCTY": "G", "INSD": 0.5,
                                  "S": 0.1875, "RE": 0.0156},
                     "post-process": {"number": 2},
                     "start-values": {"presets": [{"v_c": 600, "f_n": 0.01}]}}]}
    e = convert(lib).tools[0]
    assert e["insert"] == "DNMG150404"  # 12.7 IC, 55 deg: 15.5 mm edge; r 0.396 mm
    assert e["radius"] == pytest.approx(0.3962, abs=1e-4)
    assert e["vc_rough"] == pytest.approx(182.88) and e["feed_rough"] == pytest.approx(0.254)


@pytest.mark.parametrize("content,expect", [
    (b"not json at all", "not a Fusion 360 tool library: not JSON"),
    (b'{"tools": []}', 'expected a JSON object with a "data" list of tools'),
    (b"[1, 2]", "no turning tools"),
    (json.dumps({"data": [{"type": "drill", "geometry": {}}]}).encode(),
     "no turning tools (expected types turning general"),
    (b"\xff\xfe\x00garbage", "not UTF-8"),
    (b"[" * 100000 + b"]" * 100000, "not a Fusion 360 tool library"),
    (json.dumps({"data": [{"type": "turning general", "geometry": {"SC": "C"}}]}).encode(),
     "geometry.RE (corner radius)"),
])
def test_bad_files_are_one_line_exit_2(tmp_path, content, expect):
    src = tmp_path / "x.json"
    src.write_bytes(content)
    out = tmp_path / "out.toml"
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "tools", "import", str(src), "-o",
                        str(out)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("error: ") and expect in lines[0], r.stderr
    assert str(src) in lines[0]
    assert not out.exists()


def test_duplicate_turret_position_is_skipped_with_reason():
    lib = json.loads(json.dumps(LIBRARY))
    lib["data"][2]["post-process"]["number"] = 1
    imp = convert(lib)
    assert [t["number"] for t in imp.tools] == [1, 7, 4]
    assert any("T01 is used by an earlier tool" in n for n in imp.notes)


def test_import_file_result_equals_cli(tmp_path):
    src = tmp_path / "lib.json"
    src.write_text(json.dumps(LIBRARY))
    text, imp = import_file(str(src))
    assert len(imp.tools) == 4 and text.startswith("# Tool library imported from lib.json")
