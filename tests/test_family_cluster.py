"""hnc-cam family --scheduler: the rows on a Dask distributed cluster (two worker processes on
the loopback interface) give the same programs, summary.csv and error reporting as the local
pool, and each worker initialises once however many rows it runs."""
from __future__ import annotations

import csv
from pathlib import Path

import pytest

from hnc_cam.cli import main

distributed = pytest.importorskip(
    "distributed", reason="the distributed package (extra 'cluster') is not installed")

REPO = Path(__file__).resolve().parents[1]
PART = REPO / "parts" / "stepped_shaft.py"


@pytest.fixture(scope="module")
def cluster():
    from distributed import LocalCluster
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None, worker_dashboard_address=None) as c:
        assert c.scheduler_address.startswith("tcp://127.0.0.1:")
        yield c.scheduler_address


def _table(path: Path) -> None:
    path.write_text("length,d1,program_number\n"
                    "100,20,201\n95,19,202\n90,abc,203\n1,2\n85,18.5,205\n104,21,206\n")


@pytest.mark.cad
def test_cluster_programs_identical_to_local_run(tmp_path, capsys, cluster):
    table = tmp_path / "t.csv"
    _table(table)
    common = ["family", str(PART), "--table", str(table), "--comp", "control"]
    rc_local = main(common + ["--out", str(tmp_path / "local"), "--jobs", "1"])
    err_local = capsys.readouterr().err
    rc_dask = main(common + ["--out", str(tmp_path / "dask"), "--scheduler", cluster])
    err_dask = capsys.readouterr().err
    assert rc_local == rc_dask == 2
    local = sorted(p.name for p in (tmp_path / "local").iterdir())
    assert local == ["O0201.nc", "O0202.nc", "O0205.nc", "O0206.nc", "summary.csv"]
    assert sorted(p.name for p in (tmp_path / "dask").iterdir()) == local
    for name in local:  # programs and summary byte for byte
        assert (tmp_path / "dask" / name).read_bytes() == \
            (tmp_path / "local" / name).read_bytes(), name
    rows = list(csv.DictReader((tmp_path / "dask" / "summary.csv").open()))
    assert [r["row"] for r in rows] == ["1", "2", "3", "4", "5", "6"]
    assert [r["status"] for r in rows] == ["ok", "ok", "error", "error", "ok", "ok"]
    assert all(r["verified"] == "pass" for r in rows if r["status"] == "ok")
    # the same error lines, naming the table and the part file as given
    assert err_dask.replace(str(tmp_path / "dask"), "OUT").splitlines() == \
        err_local.replace(str(tmp_path / "local"), "OUT").splitlines()
    assert "d1='abc' is not a number" in err_dask
    assert "4 of 6 program(s) written" in err_dask


@pytest.mark.cad
def test_cluster_workers_initialise_once(cluster):
    """Every row reports (pid, initialisations) of the worker process that ran it: two worker
    processes at most, each initialised exactly once for all its rows."""
    from hnc_cam.plan.command import _run_jobs
    jobs = [(i, i + 1, str(PART), None, {"nosuch": "1"}, 300 + i, {}) for i in range(1, 9)]
    done: list[int] = []
    res = _run_jobs(jobs, 1, {}, on_done=lambda r: done.append(r["row"]), scheduler=cluster)
    assert sorted(done) == list(range(1, 9)) and len(res) == 8
    assert all(r["status"] == "error" and "nosuch" in r["message"] for r in res)
    pids = {r["worker"][0] for r in res}
    assert 1 <= len(pids) <= 2
    assert all(r["worker"][1] == 1 for r in res)


def test_cluster_relative_paths_and_progress_bar(tmp_path, monkeypatch, capsys, cluster):
    """A part given relative to the current folder reaches the workers, the messages name it
    as given, and the progress bar goes to stderr on a terminal."""
    import sys
    from hnc_cam.plan.command import _run_jobs
    monkeypatch.chdir(REPO)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    jobs = [(i, i + 1, "parts/stepped_shaft.py", None, {"nosuch": "1"}, 400 + i, {})
            for i in range(1, 4)]
    res = _run_jobs(jobs, 1, {}, scheduler=cluster)
    assert "generating" in capsys.readouterr().err
    for r in res:
        assert r["message"].startswith("parts/stepped_shaft.py"), r["message"]
        assert str(REPO) not in r["message"]


def test_unreachable_scheduler_is_one_line(tmp_path, capsys, monkeypatch):
    """Nothing listens on the port: one line naming the address, exit 2, no program."""
    import socket
    monkeypatch.setattr("hnc_cam.plan.command.CONNECT_TIMEOUT_S", 1.0)
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    table = tmp_path / "t.csv"
    _table(table)
    rc = main(["family", str(PART), "--table", str(table), "--out", str(tmp_path / "o"),
               "--scheduler", f"tcp://127.0.0.1:{port}"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2
    assert len(err) == 1 and f"tcp://127.0.0.1:{port}" in err[0] and "Traceback" not in err[0]
    assert not list((tmp_path / "o").glob("*.nc"))


@pytest.mark.parametrize("addr", ["127.0.0.1:8786", "tcp://127.0.0.1", "tcp://h:0",
                                  "tcp://h:99999", "http://h:80", "tcp://a b:1"])
def test_bad_scheduler_address_is_an_option_error(tmp_path, capsys, addr):
    rc = main(["family", str(PART), "--table", str(tmp_path / "t.csv"), "--out",
               str(tmp_path / "o"), "--scheduler", addr])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and "tcp://HOST:PORT" in err[0]
    assert not (tmp_path / "o").exists()


def test_cluster_interrupt_keeps_finished_rows(cluster):
    """Ctrl-C while the rows run on the cluster: the rows finished so far come back with the
    signal, the others are cancelled on the cluster, and the cluster takes new work after."""
    import signal
    from distributed import Client
    from hnc_cam.plan.command import _Interrupted, _run_jobs
    jobs = [(i, i + 1, str(PART), None, {"nosuch": "1"}, 500 + i, {}) for i in range(1, 7)]
    seen: list[int] = []

    def on_done(r):
        seen.append(r["row"])
        if len(seen) == 2:
            raise KeyboardInterrupt

    with pytest.raises(_Interrupted) as ei:
        _run_jobs(jobs, 1, {}, on_done=on_done, scheduler=cluster)
    assert ei.value.signum == signal.SIGINT
    assert [r["row"] for r in ei.value.done] == seen[:1]  # the row being handed over is lost
    with Client(cluster, set_as_default=False) as c:
        import time
        t0 = time.monotonic()
        while any(str(k).startswith("hnc-family-") for k in c.who_has()) and \
                time.monotonic() - t0 < 10:
            time.sleep(0.1)
        assert not any(str(k).startswith("hnc-family-") for k in c.who_has())
    res = _run_jobs(jobs[:2], 1, {}, scheduler=cluster)
    assert sorted(r["row"] for r in res) == [1, 2]


@pytest.mark.cad
def test_cluster_workers_run_a_revolve_family_without_the_cad_kernel(cluster):
    """A family whose part() returns revolve(outline) needs no CAD kernel: the cluster's
    workers run its rows without importing it (each row reports where its worker's kernel
    came from), and the programs are those of a run in this process."""
    from hnc_cam.plan.command import _run_jobs
    jobs = [(i, i + 1, str(PART), None, {"length": str(94 + i)}, 400 + i, {"verify": False})
            for i in range(1, 5)]
    res = sorted(_run_jobs(jobs, 1, {"verify": False}, scheduler=cluster),
                 key=lambda r: r["row"])
    assert [r["status"] for r in res] == ["ok"] * 4, [r.get("message") for r in res]
    assert all(r["counts"]["kernel"] == "not needed" for r in res)
    here = sorted(_run_jobs(jobs, 1, {"verify": False}), key=lambda r: r["row"])
    assert [r["text"] for r in res] == [r["text"] for r in here]
