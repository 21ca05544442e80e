"""hnc-cam family: one program per CSV row, summary.csv, bad rows reported, others done."""
from __future__ import annotations

import csv
import re
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


def test_workers_are_reused_and_initialised_once(tmp_path):
    """Two worker processes for six rows: each row reports the pid of the worker that ran it
    and how many times that worker ran the initializer (imports, tables, templates): once."""
    from hnc_cam.plan.command import _run_jobs
    part = str(REPO / "parts" / "stepped_shaft.py")
    jobs = [(i, i + 1, part, None, {"nosuch": "1"}, 100 + i, {}) for i in range(1, 7)]
    res = _run_jobs(jobs, 2, {})
    assert len(res) == 6 and all(r["status"] == "error" and "nosuch" in r["message"]
                                 for r in res)
    pids = {r["worker"][0] for r in res}
    assert 1 <= len(pids) <= 2
    assert all(r["worker"][1] == 1 for r in res)


def test_progress_bar_on_a_terminal_only(tmp_path, monkeypatch, capsys):
    """The rich progress bar goes to stderr when stderr is a terminal, and not otherwise."""
    import sys
    from hnc_cam.plan.command import _run_jobs
    part = str(REPO / "parts" / "stepped_shaft.py")
    jobs = [(i, i + 1, part, None, {"nosuch": "1"}, 100 + i, {}) for i in range(1, 3)]
    _run_jobs(jobs, 1, {})
    assert "generating" not in capsys.readouterr().err
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    _run_jobs(jobs, 1, {})
    cap = capsys.readouterr()
    assert "generating" in cap.err and "generating" not in cap.out


@pytest.mark.cad
def test_family_stock_column_and_options(tmp_path, capsys):
    """A stock column per row, the program number from the base number, options passed to
    every row (number format, block numbering, comp)."""
    table = tmp_path / "t.csv"
    table.write_text("length,stock\n95,45x100+1\n90,\n")
    out = tmp_path / "out"
    rc = main(["family", str(REPO / "parts" / "stepped_shaft.py"), "--table", str(table),
               "--out", str(out), "--jobs", "1", "--program-number", "500",
               "--number-format", "point", "--block-numbers", "pq", "--no-verify"])
    assert rc == 0, capsys.readouterr().err
    a, b = (out / "O0500.nc").read_text(), (out / "O0501.nc").read_text()
    assert "(STOCK 45x100+1)" in a
    assert "(STOCK 45x100+1)" not in b and "(STOCK 45x" in b  # the part's STOCK(length=90)
    assert "(PARAMETERS " in a and "length=95" in a
    for t in (a, b):
        assert "G00 G40 Z80." in t
        numbered = [ln.split()[0] for ln in t.splitlines() if ln.startswith("N")]
        # only the blocks a P or Q word refers to are numbered (ns and nf of each cycle)
        refs = {f"N{n}" for n in re.findall(r"\b[PQ](\d+)\b", t)}
        assert numbered == [f"N{i}" for i in range(1, len(numbered) + 1)]
        assert set(numbered) == refs and len(numbered) >= 2
    rows = list(csv.DictReader((out / "summary.csv").open()))
    assert [r["file"] for r in rows] == ["O0500.nc", "O0501.nc"]
    assert [r["verified"] for r in rows] == ["skipped", "skipped"]
