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
    assert [t.number for t in lib.tools] == list(range(1, 17))
    assert lib.by_number(16).kind == "groove_face" and lib.by_number(16).max_diameter == 80.0
    assert lib.by_number(1).feed_finish == 0.15
    assert lib.by_number(8).kind == "part" and lib.by_number(8).max_depth == 26.0


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


def _sigint_after_mkstemp(monkeypatch):
    """tempfile.mkstemp that sends this process Ctrl-C the moment the temporary exists."""
    import signal
    import tempfile
    real = tempfile.mkstemp

    def mkstemp(*a, **k):
        got = real(*a, **k)
        os.kill(os.getpid(), signal.SIGINT)
        return got
    monkeypatch.setattr(tempfile, "mkstemp", mkstemp)


def test_write_atomic_under_ctrl_c_writes_whole_then_stops(tmp_path, monkeypatch):
    # Ctrl-C arriving between the temporary's creation and its rename: the file is written
    # whole, no temporary is left, and the interrupt is raised after
    from hnc_cam.io import write_atomic
    target = tmp_path / "O0001.nc"
    target.write_text("old\n")
    _sigint_after_mkstemp(monkeypatch)
    with pytest.raises(KeyboardInterrupt):
        write_atomic(target, "new\n")
    assert target.read_text() == "new\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["O0001.nc"]


def test_write_files_under_ctrl_c_writes_all_then_stops(tmp_path, monkeypatch):
    # another thread runs meanwhile (the kernel may hand it the process's signal)
    import threading

    from hnc_cam.plan.export import write_files
    _sigint_after_mkstemp(monkeypatch)
    stop = threading.Event()
    other = threading.Thread(target=stop.wait, args=(10,))
    other.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            write_files(str(tmp_path / "o"), [("O0001.nc", "%1\nM30\n"),
                                              ("O0002.nc", "%2\nM30\n")])
    finally:
        stop.set()
        other.join()
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == ["O0001.nc", "O0002.nc"]
    assert (tmp_path / "o" / "O0002.nc").read_text() == "%2\nM30\n"


def test_family_row_written_is_a_row_recorded_under_ctrl_c(tmp_path, monkeypatch):
    # a row whose program is written while Ctrl-C arrives is in the finished rows the
    # interrupted family lists in summary.csv
    from hnc_cam.io import write_atomic
    from hnc_cam.plan.command import _Finished
    _sigint_after_mkstemp(monkeypatch)
    out: list = []
    fin = _Finished(1, lambda r: (write_atomic(tmp_path / "O0001.nc", r["text"]),
                                  r.__setitem__("file", "O0001.nc")), out)
    with pytest.raises(KeyboardInterrupt):
        fin.add({"row": 1, "status": "ok", "text": "%1\nM30\n"})
    assert [r["file"] for r in out] == ["O0001.nc"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["O0001.nc"]


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
    write_atomic(tmp_path / "O0004.nc", "%4\n", clean_folder=False)  # its caller cleaned
    assert stale.exists()
    write_atomic(tmp_path / "O0003.nc", "%3\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        live.name, ".notes.tmp", "O0003.nc", "O0004.nc"]


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


# --------------------------------------------------------------------------------------------
# every command x every broken-input class, as a user runs them (subprocesses, timeouts)
# --------------------------------------------------------------------------------------------

CLI = [sys.executable, "-m", "hnc_cam.cli"]
PART = '''from hnc_cam.cad.sketch import Outline, revolve
STOCK = "45x60+1"
def part(d: float = 30.0, length: float = 30.0):
    s = Outline((0.0, 0.0))
    s.line_to(d / 2, 0.0)
    s.line_to(d / 2, -length)
    s.line_to(20.0, -length)
    s.line_to(20.0, -50.0)
    s.line_to(0.0, -50.0)
    return revolve(s.segments())
'''
PROGRAM = "%1\nT0101\nM03 S800\nG00 X42 Z2\nG01 Z-30 F200\nX44\nG00 X80 Z80\nM30\n"
TABLE = "d,length\n30,30\n28,25\n"
PLACE = re.compile(r"^(error: )?\S.*?(:\d+(:\d+)?)?: ")
# the run's exit code and stderr, from a fresh process
TIMEOUT = 240


def _cli(args: list[str], cwd: Path, timeout: float = TIMEOUT) -> subprocess.CompletedProcess:
    return subprocess.run(CLI + args, cwd=cwd, capture_output=True, text=True, timeout=timeout,
                          stdin=subprocess.DEVNULL)


def _assert_one_line_error(r: subprocess.CompletedProcess, where: str) -> None:
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert r.returncode == 2, (r.returncode, r.stderr[-2000:])
    assert "Traceback" not in r.stderr
    assert len(lines) == 1, r.stderr
    assert where in lines[0] and PLACE.match(lines[0]), lines[0]


def _make_input(kind: str, d: Path, name: str) -> Path:
    p = d / name
    if kind == "missing":
        return p
    if kind == "directory":
        p.mkdir()
    elif kind == "empty":
        p.write_bytes(b"")
    elif kind == "binary":
        p.write_bytes(bytes(range(256)) * 64)
    elif kind == "nul":
        p.write_bytes(b"%1\nG00 X1\x00 Z2\nM30\n")
    elif kind == "utf16":
        p.write_bytes("%1\nG00 X1 Z2\nM30\n".encode("utf-16"))
    elif kind == "huge_line":
        p.write_bytes(b"%1\n(" + b"A" * 3_000_000 + b")\nM30\n")
    elif kind == "fifo":
        os.mkfifo(p)  # nobody writes it: a reader that blocks would hang
    return p


INPUTS = ["missing", "directory", "empty", "binary", "nul", "utf16", "huge_line", "fifo"]


def _workspace(tmp_path: Path) -> Path:
    (tmp_path / "part.py").write_text(PART)
    (tmp_path / "t.csv").write_text(TABLE)
    (tmp_path / "good.nc").write_text(PROGRAM)
    return tmp_path


def _command(cmd: str, role: str, bad: str, tmp: Path) -> list[str]:
    """The command line with the broken file in ``role`` (program, model, part, table,
    tools)."""
    prog = bad if role == "program" else "good.nc"
    model = bad if role == "model" else "part.py"
    part = bad if role == "part" else "part.py"
    table = bad if role == "table" else "t.csv"
    extra = ["--tools", bad] if role == "tools" else []
    if cmd == "run":
        return ["run", prog] + (["--machine", bad] if role == "machine" else [])
    if cmd == "simulate":
        return ["simulate", prog, "--stock", "45x60"] + extra
    if cmd == "verify":
        return ["verify", prog, "--model", model, "--stock", "45x60"] + extra
    if cmd == "generate":
        return ["generate", part, "--stock", "45x60+1", "--no-verify", "-o", "out.nc"] + extra
    if cmd == "family":
        return ["family", part, "--table", table, "--out", "fam", "--no-verify",
                "--jobs", "1"] + extra
    raise AssertionError(cmd)


CASES = [("run", "program"), ("run", "machine"), ("simulate", "program"),
         ("simulate", "tools"), ("verify", "program"), ("verify", "model"),
         ("generate", "part"), ("generate", "tools"), ("family", "part"),
         ("family", "table"), ("family", "tools")]


@pytest.mark.parametrize("kind", INPUTS)
@pytest.mark.parametrize("cmd,role", CASES, ids=[f"{c}-{r}" for c, r in CASES])
def test_broken_input_is_one_line_exit_2(tmp_path, cmd, role, kind):
    tmp = _workspace(tmp_path)
    if kind == "empty" and role in ("program", "machine"):
        pytest.skip("an empty program or machine file is valid (nothing to run, defaults)")
    suffix = {"program": ".nc", "machine": ".toml", "tools": ".toml", "model": ".py",
              "part": ".py", "table": ".csv"}[role]
    bad = _make_input(kind, tmp, "bad" + suffix)
    before = set(os.listdir(tmp))
    t0 = time.monotonic()
    r = _cli(_command(cmd, role, bad.name, tmp), tmp)
    assert time.monotonic() - t0 < TIMEOUT
    _assert_one_line_error(r, bad.name)
    assert r.stdout == ""
    # nothing written, no temporary left
    assert set(os.listdir(tmp)) == before, set(os.listdir(tmp)) ^ before


@pytest.mark.parametrize("cmd", ["run", "simulate", "verify", "generate", "family"])
@pytest.mark.parametrize("out", ["parent_is_file", "unwritable_dir"])
def test_unwritable_output_is_one_line_exit_2(tmp_path, cmd, out):
    tmp = _workspace(tmp_path)
    (tmp / "blocker").write_text("a file, not a folder")
    if out == "parent_is_file":
        target = "blocker/out"
    else:
        if os.geteuid() == 0:
            pytest.skip("root writes into a read-only folder")
        ro = tmp / "ro"
        ro.mkdir()
        ro.chmod(0o500)
        target = "ro/out"
    args = {"run": ["run", "good.nc", "--json", target],
            "simulate": ["simulate", "good.nc", "--stock", "45x60", "--json", target],
            "verify": ["verify", "good.nc", "--model", "part.py", "--stock", "45x60",
                       "--json", target],
            "generate": ["generate", "part.py", "--no-verify", "-o", target],
            "family": ["family", "part.py", "--table", "t.csv", "--no-verify", "--out",
                       target]}[cmd]
    r = _cli(args, tmp)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    errs = [ln for ln in r.stderr.splitlines() if "error" in ln]
    assert len(errs) == 1 and target in errs[0], r.stderr
    assert (tmp / "blocker").read_text() == "a file, not a folder"


def test_family_out_is_a_file(tmp_path):
    tmp = _workspace(tmp_path)
    (tmp / "blocker").write_text("x")
    r = _cli(["family", "part.py", "--table", "t.csv", "--no-verify", "--out", "blocker"], tmp)
    _assert_one_line_error(r, "--out blocker")
    assert (tmp / "blocker").read_text() == "x"


def test_family_rows_given_o_instead_of_out_are_told_which_to_use(tmp_path):
    # the generate habit (-o) in the per-row mode: the line names -o and --out, nothing written
    tmp = _workspace(tmp_path)
    r = _cli(["family", "part.py", "--table", "t.csv", "--no-verify", "-o", "fam/"], tmp)
    _assert_one_line_error(r, "--out DIR")
    assert "-o/--output" in r.stderr and not (tmp / "fam").exists()


@pytest.mark.parametrize("cmd", ["generate", "verify", "family"])
@pytest.mark.parametrize("value", ["nan", "-1", "inf", "0", "x"])
def test_tol_must_be_a_positive_number(tmp_path, cmd, value):
    tmp = _workspace(tmp_path)
    args = {"generate": ["generate", "part.py"],
            "verify": ["verify", "good.nc", "--model", "part.py", "--stock", "45x60"],
            "family": ["family", "part.py", "--table", "t.csv", "--out", "fam"]}[cmd]
    r = _cli(args + ["--tol", value], tmp, timeout=60)
    _assert_one_line_error(r, "--tol")
    assert not (tmp / "fam").exists()


def test_bad_part_file_is_one_error_for_the_whole_family(tmp_path):
    tmp = _workspace(tmp_path)
    (tmp / "broken.py").write_text("def part(d: float = 1.0):\n    return (\n")
    r = _cli(["family", "broken.py", "--table", "t.csv", "--out", "fam", "--jobs", "2"], tmp)
    _assert_one_line_error(r, "broken.py:")
    assert not (tmp / "fam").exists()
    # a part file whose part() fails at run time: one line for all the rows
    (tmp / "raises.py").write_text("def part(d: float = 1.0, length: float = 2.0):\n"
                                   "    raise RuntimeError('no geometry')\n")
    r = _cli(["family", "raises.py", "--table", "t.csv", "--out", "fam2", "--jobs", "1",
              "--no-verify"], tmp)
    errs = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    # each row's error names its parameters: one line per row, no count line
    assert len(errs) == 2 and all("no geometry" in e for e in errs), r.stderr
    assert "row 1 (line 2)" in errs[0] and "d=30, length=30" in errs[0]
    assert "row 2 (line 3)" in errs[1] and "d=28, length=25" in errs[1]


def test_part_returning_a_string_says_so(tmp_path):
    tmp = _workspace(tmp_path)
    (tmp / "s.py").write_text("def part(d: float = 1.0):\n    return 'hello'\n")
    r = _cli(["generate", "s.py", "--stock", "40x50"], tmp, timeout=120)
    _assert_one_line_error(r, "s.py")
    assert "returned a str ('hello'), not a solid" in r.stderr


def test_table_in_utf16_or_with_a_huge_field(tmp_path):
    tmp = _workspace(tmp_path)
    (tmp / "u.csv").write_bytes(TABLE.encode("utf-16"))
    r = _cli(["family", "part.py", "--table", "u.csv", "--out", "fam"], tmp, timeout=60)
    _assert_one_line_error(r, "u.csv: UTF-16")
    (tmp / "h.csv").write_text("d,length\n" + "3" * 200_000 + ",1\n")
    r = _cli(["family", "part.py", "--table", "h.csv", "--out", "fam"], tmp, timeout=60)
    _assert_one_line_error(r, "h.csv:2: not a CSV table")
    assert not (tmp / "fam").exists()


def test_templates_folder_that_does_not_exist(tmp_path):
    tmp = _workspace(tmp_path)
    r = _cli(["generate", "part.py", "--templates", "nope", "-o", "o.nc"], tmp, timeout=120)
    _assert_one_line_error(r, "nope")
    assert not (tmp / "o.nc").exists()


def test_corrupt_step_keeps_stdout_clean_and_names_the_line(tmp_path):
    tmp = _workspace(tmp_path)
    (tmp / "bad.step").write_text(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nENDSEC;\nDATA;\n"
        "#1=CARTESIAN_POINT('',(0.,0.,0.);\n#2 = garbage here;\nENDSEC;\nEND-ISO-10303-21;\n")
    r = _cli(["generate", "bad.step", "--stock", "40x50"], tmp, timeout=120)
    assert r.stdout == ""
    _assert_one_line_error(r, "bad.step:7: not a readable STEP file")
    assert "\x1b[" not in r.stderr and "****" not in r.stderr


# --------------------------------------------------------------------------------------------
# family: interrupted and killed runs
# --------------------------------------------------------------------------------------------

def _children(pid: int) -> list[int]:
    out = []
    for d in os.listdir("/proc"):
        if d.isdigit():
            try:
                stat_ = Path(f"/proc/{d}/stat").read_text()
            except OSError:
                continue
            if int(stat_.rsplit(")", 1)[1].split()[1]) == pid:
                out.append(int(d))
    return out


def _running(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _family_in_background(tmp: Path, rows: int) -> subprocess.Popen:
    (tmp / "many.csv").write_text("d,length\n" + "".join(
        f"{26 + (i % 6)},{10 + i % 20}\n" for i in range(rows)))
    return subprocess.Popen(CLI + ["family", "part.py", "--table", "many.csv", "--out", "fam",
                                   "--jobs", "2"], cwd=tmp, stderr=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True)


def _wait_for_workers(p: subprocess.Popen, n: int = 2, timeout: float = 120) -> list[int]:
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        kids = _children(p.pid)
        if len(kids) >= n:
            return kids
        time.sleep(0.1)
    p.kill()
    raise AssertionError("no workers started")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_family_killed_leaves_no_worker_running(tmp_path):
    tmp = _workspace(tmp_path)
    p = _family_in_background(tmp, 40)
    kids = _wait_for_workers(p)
    time.sleep(1.0)
    p.kill()
    p.wait(30)
    t0 = time.monotonic()
    while any(_running(k) for k in kids) and time.monotonic() - t0 < 10:
        time.sleep(0.1)
    alive = [k for k in kids if _running(k)]
    for k in alive:
        os.kill(k, signal.SIGKILL)
    assert alive == []


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_family_interrupted_writes_what_finished(tmp_path, sig):
    tmp = _workspace(tmp_path)
    p = _family_in_background(tmp, 30)
    kids = _wait_for_workers(p)
    fam = tmp / "fam"
    t0 = time.monotonic()  # wait for a finished row (or give up waiting and interrupt anyway)
    while time.monotonic() - t0 < 120 and not any(fam.glob("O*.nc")):
        time.sleep(0.2)
    p.send_signal(sig)
    _out, err = p.communicate(timeout=60)
    assert p.returncode == 128 + sig, err
    assert "Traceback" not in err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("interrupted"), err
    import csv
    rows = list(csv.DictReader((fam / "summary.csv").open()))
    assert len(rows) == 30
    done = [r for r in rows if r["status"] == "ok"]
    assert all(r["status"] in ("ok", "interrupted") for r in rows)
    assert sorted(f.name for f in fam.glob("O*.nc")) == sorted(r["file"] for r in done)
    assert not [f for f in fam.iterdir() if f.name.endswith(".tmp")]
    time.sleep(0.5)
    assert not [k for k in kids if _running(k)]


# --------------------------------------------------------------------------------------------
# user templates: errors name the template file and line
# --------------------------------------------------------------------------------------------

FOOTER_OK = "G00 X{{ plan.tool_change[0]|dia }}\nG00 G40 Z{{ plan.tool_change[1]|num }}\n"


@pytest.mark.parametrize("footer,line,expect", [
    (FOOTER_OK + "G12 X5\nM30\n", 3, "raises an alarm at its line"),
    ("{{ plan.nothing }}\nM30\n", 1, "has no attribute 'nothing'"),
    ("M30\n{{ 1/0 }}\n", 2, "ZeroDivisionError: division by zero"),
    ("{% if %}\nM30\n", 1, "template syntax:"),
])
def test_user_template_errors_name_file_and_line(tmp_path, footer, line, expect):
    tmp = _workspace(tmp_path)
    (tmp / "tpl").mkdir()
    (tmp / "tpl" / "footer.j2").write_text(footer)
    r = _cli(["generate", "part.py", "--templates", "tpl", "--no-verify", "-o", "o.nc"], tmp)
    _assert_one_line_error(r, f"tpl/footer.j2:{line}: ")
    assert expect in r.stderr and "generator bug" not in r.stderr
    assert not (tmp / "o.nc").exists()


def test_generate_from_a_build123d_solid():
    build123d = pytest.importorskip("build123d")
    import hnc_cam
    prog = hnc_cam.generate(build123d.Cylinder(15, 40), stock="32x45+1", verify=False)
    assert "G71" in prog.text and prog.plan.profile.max_radius == pytest.approx(15.0)


def test_generate_cli_profile_options(tmp_path):
    # a cylinder modelled along X: refused about Z with a hint in CLI words, accepted with
    # --axis X; a flat on it needs --envelope
    tmp = _workspace(tmp_path)
    (tmp / "x.py").write_text(
        "import build123d as bd\n"
        "def part(d: float = 30.0):\n"
        "    return bd.Cylinder(d / 2, 40, rotation=(0, 90, 0))\n")
    r = _cli(["generate", "x.py", "--stock", "32x45+1", "--no-verify"], tmp)
    _assert_one_line_error(r, "x.py")
    assert "--axis X" in r.stderr
    r = _cli(["generate", "x.py", "--stock", "32x45+1", "--no-verify", "--axis", "X"], tmp)
    assert r.returncode == 0, r.stderr
    assert "G71" in r.stdout
    (tmp / "flat.py").write_text(
        "import build123d as bd\n"
        "def part(d: float = 30.0):\n"
        "    return bd.Cylinder(d / 2, 40) - bd.Pos(d / 2, 0, 0) * bd.Box(4, 40, 10)\n")
    r = _cli(["generate", "flat.py", "--stock", "32x45+1", "--no-verify"], tmp)
    _assert_one_line_error(r, "flat.py")
    assert "--envelope" in r.stderr
    r = _cli(["generate", "flat.py", "--stock", "32x45+1", "--no-verify", "--envelope",
              "--fit-tol", "0.002", "--zero", "right"], tmp)
    assert r.returncode == 0, r.stderr


def test_verify_takes_parameters_and_stock_from_the_program(tmp_path):
    tmp = _workspace(tmp_path)
    r = _cli(["generate", "part.py", "--set", "d=26", "-o", "p.nc"], tmp)
    assert r.returncode == 0, r.stderr
    head = (tmp / "p.nc").read_text().splitlines()[:4]
    assert "(PARAMETERS d=26.0 length=30.0)" in head and "(STOCK 45x60+1)" in head
    r = _cli(["verify", "p.nc", "--model", "part.py"], tmp)
    assert r.returncode == 0, r.stdout + r.stderr
    notes = [ln for ln in r.stderr.splitlines() if ln.startswith("note:")]
    assert len(notes) == 1 and "d=26.0" in notes[0] and "45x60+1" in notes[0]
    # an explicit --set wins (and the program then fails against the d=30 model)
    r = _cli(["verify", "p.nc", "--model", "part.py", "--set", "d=30"], tmp)
    assert r.returncode == 1, r.stdout + r.stderr
    r = _cli(["simulate", "p.nc"], tmp)
    assert r.returncode == 0 and "stock 45x60+1" in r.stderr
    # no STOCK line and no --stock: one line
    (tmp / "bare.nc").write_text(PROGRAM)
    r = _cli(["simulate", "bare.nc"], tmp)
    _assert_one_line_error(r, "bare.nc")
    assert "--stock" in r.stderr
