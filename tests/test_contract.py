"""Every command keeps its contract on broken input: one line with a place on stderr, exit 2,
no traceback, no partial or temporary file, no process left behind; user files are checked
key by key."""
from __future__ import annotations

import os
import re
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hnc_cam.errors import HncError, ToolError
from hnc_cam.schema import Key, check_table, key_line, parse_toml
from hnc_cam.tooling import load_tools

REPO = Path(__file__).resolve().parents[1]
TOOLS = (REPO / "hnc_cam" / "data" / "tools.toml").read_text("utf-8")


def _lib(tmp_path: Path, old: str, new: str, name: str = "tools.toml") -> Path:
    assert old in TOOLS
    p = tmp_path / name
    p.write_text(TOOLS.replace(old, new, 1))
    return p


def _line_of(path: Path, needle: str) -> int:
    for n, line in enumerate(path.read_text().splitlines(), 1):
        if needle in line:
            return n
    raise AssertionError(needle)


# --------------------------------------------------------------------------------------------
# the tool library, key by key
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("old,new,needle,expect", [
    ("feed_finish = 0.15", "feed_finsh = 0.05", "feed_finsh",
     "unknown key 'feed_finsh' (did you mean 'feed_finish'?)"),
    ("feed_rough = 0.25", "feed_rough = 25", "feed_rough = 25",
     "feed_rough = 25 is out of range (0.01-2 mm/rev)"),
    ("feed_rough = 0.25", "feed_rough = -0.25", "feed_rough = -0.25",
     "feed_rough = -0.25 is out of range (0.01-2 mm/rev)"),
    ("vc_rough = 180.0", "vc_rough = 18000", "vc_rough = 18000",
     "vc_rough = 18000 is out of range (1-2000 m/min)"),
    ('kind = "turn"', 'kind = "tunr"', "tunr",
     'kind = "tunr" is not one of: turn, bore, thread, groove'),
    ('uses = ["rough", "face"]', 'uses = ["rough","fase"]', "fase",
     '"fase" in uses is not one of: rough, finish, face, profile, thread, thread_id, groove'),
    ("tip = 3", "tip = 12", "tip = 12", "tip = 12 is out of range (0-9)"),
    ("depth = 1.5", 'depth = "deep"', "deep", 'depth = "deep" must be a number'),
    ("feed_rough = 0.25", "feed_rough = nan", "nan", "feed_rough = nan must be a finite number"),
])
def test_tool_library_key_errors_name_file_line_and_range(tmp_path, old, new, needle, expect):
    p = _lib(tmp_path, old, new)
    with pytest.raises(ToolError) as ei:
        load_tools(p)
    msg = str(ei.value)
    assert msg.startswith(f"{p}:{_line_of(p, needle)}: ")
    assert expect in msg


def test_tool_library_error_lines_point_into_the_right_entry(tmp_path):
    # the third [[tool]] gets the bad key; the line is the one in that entry, not the first
    text = TOOLS.split("[[tool]]")
    text[3] = text[3].replace("depth = 0.8", "depht = 0.8")
    p = tmp_path / "t.toml"
    p.write_text("[[tool]]".join(text))
    with pytest.raises(ToolError, match=rf"^{re.escape(str(p))}:{_line_of(p, 'depht')}: "
                                        r"tool\[2\]: unknown key 'depht' \(did you mean 'depth'\?\)"):
        load_tools(p)


def test_tool_library_missing_required_key_and_stray_table(tmp_path):
    p = _lib(tmp_path, 'insert = "GROOVE3.0"\n', "")
    with pytest.raises(ToolError, match=r"tool\[6\]: insert missing"):
        load_tools(p)
    p = tmp_path / "stray.toml"
    p.write_text(TOOLS + "\n[tol]\nx = 1\n")
    with pytest.raises(ToolError, match=rf"{re.escape(str(p))}:{_line_of(p, '[tol]')}: unknown "):
        load_tools(p)


@pytest.mark.parametrize("raw,expect", [
    (b"\xff\xfe[\x00[\x00t\x00", "UTF-16 text"),
    (b"[[tool]]\nname = \"\xe9t\xe9\"\n", ":2:9: not UTF-8 text (byte 0xe9)"),
    (b"[[tool]]\nnumber = 1\x00\n", ":2:11: NUL byte"),
    (b"[[tool]]\nnumber = \n", ":2:10: not valid TOML"),
    (bytes(range(256)) * 4, "not UTF-8"),
])
def test_tool_library_bad_bytes_are_one_line(tmp_path, raw, expect):
    p = tmp_path / "bin.toml"
    p.write_bytes(raw)
    with pytest.raises(ToolError) as ei:
        load_tools(p)
    assert str(ei.value).startswith(str(p))
    assert expect in str(ei.value)
    assert "\n" not in str(ei.value)


def test_tool_library_not_a_file(tmp_path):
    with pytest.raises(ToolError, match="is a directory"):
        load_tools(tmp_path)
    with pytest.raises(ToolError, match="cannot read"):
        load_tools(tmp_path / "absent.toml")
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)
    with pytest.raises(ToolError, match="not a regular file"):
        load_tools(fifo)


def test_bundled_library_passes_its_own_schema():
    lib = load_tools(None)
    assert [t.number for t in lib.tools] == [1, 2, 3, 4, 5, 6, 7]
    assert lib.by_number(1).feed_finish == 0.15


def test_schema_reports_line_and_range():
    schema = {"a": Key("int", 1, 5), "b": Key("float", 0, 1, "mm", lo_open=True),
              "c": Key("str", choices=("x", "y"), fold=True), "d": Key("bool")}
    text = "# c\n[s]\na = 2\nb = 0\nc = \"X\"\nd = true\n"
    data = parse_toml(text, "f.toml")
    with pytest.raises(HncError, match=r"^f.toml:4: b = 0 is out of range \(above 0-1 mm\)$"):
        check_table(data["s"], schema, "f.toml", text=text, table="s")
    good = dict(data["s"], b=0.5)
    check_table(good, schema, "f.toml", text=text, table="s")  # "X" matches "x" folded
    with pytest.raises(HncError, match=r"^f.toml:6: d = 1 must be true or false$"):
        check_table(dict(good, d=1), schema, "f.toml", text=text, table="s")
    assert key_line(text, "s", "c") == 5
    assert key_line(text, "t", "c") is None
    assert key_line(text, "s", "zz") == 2  # the header, when the key is not written


# --------------------------------------------------------------------------------------------
# one cycle-time format
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("t,expect", [
    (300.0, "300.0 s (5:00.0)"), (299.97, "300.0 s (5:00.0)"), (59.97, "60.0 s (1:00.0)"),
    (59.94, "59.9 s (0:59.9)"), (0.0, "0.0 s (0:00.0)"), (3725.5, "3725.5 s (1:02:05.5)"),
])
def test_cycle_time_never_shows_60_seconds(t, expect):
    from hnc_cam.units import fmt_cycle_time
    assert fmt_cycle_time(t) == expect


def test_cycle_time_in_summaries_rolls_over():
    from hnc_cam.nc.interp import run
    from hnc_cam.tooling import Machine
    # G04 dwells (P in seconds): 299.97 s
    tp = run("%1\nG04 P299.97\nM30\n", Machine(), start=(0, 0))
    assert "(5:00.0)" in tp.summary() and ":60.0" not in tp.summary()


# --------------------------------------------------------------------------------------------
# outputs: whole or absent; never replace what is not a regular file
# --------------------------------------------------------------------------------------------

def test_write_atomic_follows_a_symlink(tmp_path):
    from hnc_cam.io import write_atomic
    target = tmp_path / "real.nc"
    target.write_text("old\n")
    link = tmp_path / "link.nc"
    link.symlink_to(target)
    write_atomic(link, "new\n")
    assert link.is_symlink() and target.read_text() == "new\n"
    dangling = tmp_path / "dangling.nc"
    dangling.symlink_to(tmp_path / "made.nc")
    write_atomic(dangling, "x\n")
    assert dangling.is_symlink() and (tmp_path / "made.nc").read_text() == "x\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dangling.nc", "link.nc", "made.nc",
                                                           "real.nc"]


def test_write_atomic_writes_a_fifo_in_place(tmp_path):
    import threading

    from hnc_cam.io import write_atomic
    fifo = tmp_path / "out.fifo"
    os.mkfifo(fifo)
    got = []
    fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)  # a reader is there
    try:
        t = threading.Thread(target=write_atomic, args=(fifo, "G00 X1\n"))
        t.start()
        t.join(10)
        os.set_blocking(fd, True)
        got.append(os.read(fd, 100))
    finally:
        os.close(fd)
    assert got == [b"G00 X1\n"]
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.fifo"]


def test_write_atomic_fifo_without_reader_is_an_error_not_a_hang(tmp_path):
    from hnc_cam.io import write_atomic
    fifo = tmp_path / "out.fifo"
    os.mkfifo(fifo)
    with pytest.raises(HncError, match="no process reads it"):
        write_atomic(fifo, "x")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


@pytest.mark.skipif(os.geteuid() != 0, reason="making a device node needs root")
def test_write_atomic_keeps_a_character_device(tmp_path):
    from hnc_cam.io import write_atomic
    dev = tmp_path / "null"
    os.mknod(dev, 0o666 | stat.S_IFCHR, os.makedev(1, 3))  # the null device
    write_atomic(dev, "x" * 100_000)
    assert stat.S_ISCHR(os.lstat(dev).st_mode)
    r = subprocess.run([sys.executable, "-m", "hnc_cam.cli", "run", str(_good(tmp_path)),
                        "--json", str(dev)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert stat.S_ISCHR(os.lstat(dev).st_mode)


def test_stale_temporaries_of_dead_writers_are_removed(tmp_path):
    from hnc_cam.io import write_atomic
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True).stdout.strip()
    stale = tmp_path / f".O0001.nc.{dead}.abc123.tmp"
    stale.write_text("half")
    live = tmp_path / f".O0002.nc.{os.getpid()}.abc123.tmp"  # a writer still running
    live.write_text("half")
    other = tmp_path / ".notes.tmp"
    other.write_text("mine")
    write_atomic(tmp_path / "O0003.nc", "%3\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        live.name, ".notes.tmp", "O0003.nc"]


def test_killed_writer_leaves_no_temporary_behind_after_the_next_run(tmp_path):
    # a writer killed mid-write: its temporary is there; the next write cleans it
    code = ("import sys, os, signal; from hnc_cam.io import write_atomic\n"
            "class Big(bytes):\n    pass\n"
            "import hnc_cam.io as io; real = os.fdopen\n"
            "def slow(fd, mode):\n    os.kill(os.getpid(), signal.SIGKILL)\n"
            "io.os.fdopen = slow\n"
            f"write_atomic({str(tmp_path / 'p.nc')!r}, 'x')\n")
    r = subprocess.run([sys.executable, "-c", code], timeout=60)
    assert r.returncode == -signal.SIGKILL
    assert any(p.name.endswith(".tmp") for p in tmp_path.iterdir())
    from hnc_cam.io import write_atomic
    write_atomic(tmp_path / "q.nc", "y")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["q.nc"]


def _good(tmp_path: Path) -> Path:
    p = tmp_path / "good.nc"
    p.write_text("%1\nT0101\nM03 S800\nG00 X42 Z2\nG01 Z-30 F200\nX44\nG00 X80 Z80\nM30\n")
    return p
