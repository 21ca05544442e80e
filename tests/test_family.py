"""hnc-cam family: one program per CSV row, summary.csv, bad rows reported, others done."""
from __future__ import annotations

import csv
from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.errors import PartError
from hnc_cam.plan.command import read_table

REPO = Path(__file__).resolve().parents[1]


def test_read_table_reports_malformed_rows(tmp_path):
    p = tmp_path / "t.csv"
    p.write_text("length,d1\n100,20\n1,2,3\n\n90,18\n")
    header, rows = read_table(str(p))
    assert header == ["length", "d1"]
    assert rows[0][2] == {"length": "100", "d1": "20"}
    assert rows[1][2] == f"{p}:3: row has 3 field(s), the header has 2"
    assert rows[2][1] == 5
    (tmp_path / "e.csv").write_text("")
    with pytest.raises(PartError, match="empty"):
        read_table(str(tmp_path / "e.csv"))


@pytest.mark.cad
def test_family_writes_programs_and_summary(tmp_path, capsys):
    table = tmp_path / "t.csv"
    table.write_text("length,d1,program_number\n100,20,101\n90,18,102\n80,abc,103\n1,2\n")
    out = tmp_path / "out"
    rc = main(["family", str(REPO / "parts" / "stepped_shaft.py"), "--table", str(table),
               "--out", str(out), "--jobs", "2", "--comp", "control"])
    err = capsys.readouterr().err
    assert rc == 2
    assert sorted(p.name for p in out.iterdir()) == ["O0101.nc", "O0102.nc", "summary.csv"]
    assert (out / "O0101.nc").read_text().startswith("%0101\n")
    rows = list(csv.DictReader((out / "summary.csv").open()))
    assert [r["status"] for r in rows] == ["ok", "ok", "error", "error"]
    assert rows[0]["verified"] == "pass" and float(rows[0]["cycle_time_s"]) > 0
    assert "d1='abc' is not a number" in rows[2]["message"]
    assert "row has 2 field(s), the header has 3" in rows[3]["message"]
    assert "2 of 4 program(s) written" in err
