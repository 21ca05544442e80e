"""family at scale: the local pool's workers are forked from a fork server that imported the
CAD kernel and loaded the bundled tables once; each worker loads nothing again per row,
takes the family process's environment, and dies with the family process."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hnc_cam.cli import main

REPO = Path(__file__).resolve().parents[1]
PART = REPO / "parts" / "stepped_shaft.py"
SHAFT_STEP = REPO / "tests" / "data" / "stepped_shaft.step"
LINUX = sys.platform.startswith("linux")


def _jobs(n: int, first: int = 600) -> list[tuple]:
    opts = {"verify": False}
    return [(i, i + 1, str(PART), None, {"length": str(90 + i), "d1": f"{18 + i % 3}"},
             first + i, opts) for i in range(1, n + 1)]


@pytest.mark.cad
def test_workers_load_nothing_again_per_row():
    """Eight rows on two workers: every row reports its worker's counters. Each worker ran
    its initializer once, found the CAD kernel already imported (a fork of the fork server)
    and has parsed one tool library and one machine file and built the same template
    environments at its last row as at its first: nothing is loaded per row. The programs
    are those of a run in this process."""
    from hnc_cam.plan.command import _run_jobs
    res = sorted(_run_jobs(_jobs(8), 2, {"verify": False}), key=lambda r: r["row"])
    assert [r["status"] for r in res] == ["ok"] * 8, [r.get("message") for r in res]
    by_pid: dict[int, list[dict]] = {}
    for r in res:
        assert r["counts"]["pid"] == r["worker"][0] != os.getpid()
        by_pid.setdefault(r["counts"]["pid"], []).append(r["counts"])
    assert 1 <= len(by_pid) <= 2
    for counts in by_pid.values():
        first, last = counts[0], counts[-1]
        assert all(c["inits"] == 1 for c in counts)
        if LINUX:
            assert all(c["kernel_inherited"] for c in counts)
            assert all(c["warmed"] for c in counts)
        assert first["tools"] == last["tools"] == 1
        assert first["machines"] == last["machines"] == 1
        assert first["environments"] == last["environments"] >= 1
    here = sorted(_run_jobs(_jobs(8), 1, {"verify": False}), key=lambda r: r["row"])
    assert [r["text"] for r in here] == [r["text"] for r in res]
    assert all(set(r["stages"]) >= {"load", "plan", "render", "interpret"} for r in res)


@pytest.mark.cad
def test_verified_rows_report_every_stage(tmp_path):
    from hnc_cam.plan import command
    table = tmp_path / "t.csv"
    table.write_text("length,d1\n95,19\n100,20\n97,18.5\n")
    t0 = time.perf_counter()
    rc = main(["family", str(PART), "--table", str(table), "--out", str(tmp_path / "o"),
               "--jobs", "2"])
    wall = time.perf_counter() - t0
    assert rc == 0
    last = command.LAST_RUN
    assert 0 < last["first_row_s"] < wall
    assert last["rows"] == 3
    assert set(last["stages"]) == {"load", "plan", "render", "interpret", "simulate", "verify",
                                   "write"}
    assert all(v > 0 for v in last["stages"].values())
    assert 1 <= len(last["workers"]) <= 2 and os.getpid() not in last["workers"]
    for w in last["workers"].values():
        assert w["peak_rss_mb"] > 0


@pytest.mark.cad
def test_workers_take_the_family_process_environment(tmp_path, monkeypatch):
    """The fork server keeps the environment it started with; the workers take the family
    process's at their start: a profile cache named after the server started is used."""
    from hnc_cam.cad.loader import CACHE_ENV
    from hnc_cam.plan.command import start_pool_server
    monkeypatch.delenv(CACHE_ENV, raising=False)
    start_pool_server()
    cache = tmp_path / "cache"
    monkeypatch.setenv(CACHE_ENV, str(cache))
    table = tmp_path / "t.csv"
    table.write_text("stock\n45x120+2\n45x125+2\n")
    rc = main(["family", str(SHAFT_STEP), "--table", str(table), "--out",
               str(tmp_path / "o"), "--jobs", "2", "--no-verify"])
    assert rc == 0
    assert len(list(cache.glob("*.profile"))) == 1
    assert sorted(p.name for p in (tmp_path / "o").glob("O*.nc")) == ["O0001.nc", "O0002.nc"]


def _descendants(pid: int) -> list[int]:
    kids: dict[int, list[int]] = {}
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                ppid = int(Path(f"/proc/{d}/stat").read_text().rsplit(")", 1)[1].split()[1])
            except (OSError, IndexError, ValueError):
                continue
            kids.setdefault(ppid, []).append(int(d))
    out, todo = [], [pid]
    while todo:
        for k in kids.get(todo.pop(), []):
            out.append(k)
            todo.append(k)
    return out


def _running(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.cad
@pytest.mark.skipif(not LINUX, reason="reads /proc")
def test_family_killed_takes_the_fork_server_and_its_workers_along(tmp_path):
    table = tmp_path / "t.csv"
    table.write_text("length\n" + "".join(f"{90 + i % 10}\n" for i in range(200)))
    p = subprocess.Popen([sys.executable, "-m", "hnc_cam.cli", "family", str(PART), "--table",
                          str(table), "--out", str(tmp_path / "o"), "--jobs", "2"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        t0 = time.monotonic()
        while time.monotonic() - t0 < 120 and not list((tmp_path / "o").glob("O*.nc")):
            time.sleep(0.2)
        tree = _descendants(p.pid)
        # the resource tracker, the fork server and its two workers
        assert len(tree) >= 3, tree
        p.kill()
        p.wait(30)
        t0 = time.monotonic()
        while any(_running(k) for k in tree) and time.monotonic() - t0 < 15:
            time.sleep(0.1)
        alive = [k for k in tree if _running(k)]
    finally:
        if p.poll() is None:
            p.kill()
    for k in alive:
        os.kill(k, signal.SIGKILL)
    assert alive == []



TURNABLE = '''
from hnc_cam.cad.sketch import Outline, revolve


def part(length=40.0, d=20.0, turned=0):
    s = Outline((0.0, 0.0))
    s.line_to(d / 2, 0.0, chamfer=1.0).line_to(d / 2, -length).line_to(0.0, -length)
    solid = revolve(s.segments())
    if turned:  # a row that uses its solid: made, and profiled from its section
        from build123d import Location
        return solid.moved(Location((0, 0, 0), (1, 0, 0), 180))
    return solid
'''

RUN_ROWS = '''
import json, sys
from hnc_cam.plan.command import _run_jobs
part = sys.argv[1]
jobs = [(i, i + 1, part, "25x60+2", {"length": str(38 + i), "turned": str(int(i % 3 == 0))},
         700 + i, {"verify": False}) for i in range(1, 9)]
res = sorted(_run_jobs(jobs, int(sys.argv[2]), {"verify": False}), key=lambda r: r["row"])
print(json.dumps([[r["status"], r.get("text") or r.get("message"), r["counts"]]
                  for r in res]))
'''


def _rows(part: Path, jobs: int) -> list:
    import json
    out = subprocess.run([sys.executable, "-c", RUN_ROWS, str(part), str(jobs)],
                         capture_output=True, text=True, timeout=600, cwd=REPO)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout)


@pytest.mark.cad
@pytest.mark.skipif(not LINUX, reason="the fork server")
def test_a_revolve_family_runs_without_the_cad_kernel(tmp_path):
    """The fork server loads the family's part with its defaults: a part that returns
    revolve(outline) needs no CAD kernel, and the workers' rows run without importing it
    (a fresh family process); a row whose part() uses its solid (turned end for end)
    imports it in its worker, and is profiled from the solid. The programs are those of a
    run in one process."""
    part = tmp_path / "turnable.py"
    part.write_text(TURNABLE)
    pool, here = _rows(part, 2), _rows(part, 1)
    assert [r[0] for r in pool] == ["ok"] * 8, [r[1] for r in pool]
    assert [r[1] for r in pool] == [r[1] for r in here]
    turned = [i % 3 == 0 for i in range(1, 9)]
    for (_, _, c), t in zip(pool, turned):
        assert c["pid"] != os.getpid()
        assert c["kernel"] in ("not needed", "imported")
        if t:
            assert c["kernel"] == "imported"
        assert c["kernel_inherited"] is (c["kernel"] != "imported")
    assert [r[2]["kernel"] for r in pool[:2]] == ["not needed"] * 2  # before any turned row
    assert pool[2][1] != _unturned_row_3(tmp_path)


def _unturned_row_3(tmp_path: Path) -> str:
    """Row 3's program had its part not been turned (same length)."""
    from hnc_cam.plan.api import generate
    return generate(tmp_path / "turnable.py", "25x60+2", params={"length": "41"},
                    program_number=703, file="O0703.nc", verify=False).text
