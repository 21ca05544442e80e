"""Output files are written whole or not at all.

A regular file (or a new one) is written to a temporary file beside the target, then renamed
over it. A symbolic link is resolved first, so the file it points to is replaced and the link
stays. A character device, FIFO or socket (``/dev/null``, a pipe) is written directly: it is
not a file that could be left half-written, and replacing it would destroy it.

The temporary file is ``.NAME.PID.RANDOM.tmp``. One left behind by a process that was killed
mid-write is removed by the next write into that folder, when its pid is no longer running.
"""
from __future__ import annotations

import os
import re
import signal
import stat
import sys
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator

from .errors import HncError

_TMP_RE = re.compile(r"^\..+\.(\d+)\.[A-Za-z0-9_]+\.tmp$")


def _pid_alive(pid: int) -> bool:
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def clean_stale_temporaries(folder: str | Path) -> list[str]:
    """Remove the ``.NAME.PID.*.tmp`` files of :func:`write_atomic` in ``folder`` whose
    writing process is gone; returns their names. Never raises."""
    removed = []
    try:
        names = os.listdir(folder)
    except OSError:
        return removed
    for name in names:
        m = _TMP_RE.match(name)
        if not m or _pid_alive(int(m.group(1))):
            continue
        try:
            st = os.lstat(os.path.join(folder, name))
            if stat.S_ISREG(st.st_mode) and st.st_uid == os.getuid():
                os.unlink(os.path.join(folder, name))
                removed.append(name)
        except OSError:
            pass
    return removed


@contextmanager
def signals_held() -> Iterator[None]:
    """Ctrl-C (SIGINT) and SIGTERM wait until the block ends: a file being written is written
    whole, and what records it is updated with it, before the signal's handler runs. Their
    handlers are replaced for the block by one that notes the signal (a mask would not do:
    the kernel may hand a process's signal to any thread that does not block it), then
    restored and run. Only in the main thread (elsewhere the block runs as it is)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    got: list[int] = []

    def note(signum: int, _frame: object) -> None:
        got.append(signum)
    old = {s: signal.signal(s, note) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)
        for s in dict.fromkeys(got):
            h = old[s]
            if callable(h):
                h(s, None)
            elif h == signal.SIG_DFL:
                signal.raise_signal(s)


def _resolve(p: Path) -> Path:
    """Follow a symbolic link (chains too) to the path it names; a dangling link names the
    file to create."""
    if p.is_symlink():
        try:
            return Path(os.path.realpath(p))
        except OSError:
            return p
    return p


def write_atomic(path: str | Path, data: str | bytes, *, clean_folder: bool = True) -> None:
    """Write ``data`` to ``path`` whole or not at all; ``-`` writes text to stdout. The stale
    temporaries of dead writers in its folder are removed first, unless ``clean_folder`` is
    false (a caller writing many files into a folder it has just cleaned: the scan of the
    folder grows with every file written)."""
    if str(path) == "-":
        sys.stdout.write(data if isinstance(data, str) else data.decode())
        sys.stdout.flush()
        return
    raw = data.encode("utf-8") if isinstance(data, str) else data
    p = _resolve(Path(path))
    try:
        st = os.stat(p)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise HncError(f"{path}: cannot write: {e.strerror or e}") from None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise HncError(f"{path}: cannot write: is a directory")
    if st is not None and not stat.S_ISREG(st.st_mode):
        _write_special(path, p, raw)
        return
    with signals_held():  # no temporary left behind by a Ctrl-C between its creation and rename
        _write_replacing(path, p, raw, st, clean_folder)


def _write_replacing(path: str | Path, p: Path, raw: bytes, st: os.stat_result | None,
                     clean_folder: bool) -> None:
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        if clean_folder:
            clean_stale_temporaries(p.parent)
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.{os.getpid()}.", suffix=".tmp",
                                   dir=str(p.parent))
    except OSError as e:
        raise HncError(f"{path}: cannot write: {e.strerror or e}") from None
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(raw)
        if st is not None:  # keep the mode of the file we replace
            os.chmod(tmp, stat.S_IMODE(st.st_mode))
        else:  # mkstemp creates the file 0600: give it the mode a plain open() would have
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, p)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise HncError(f"{path}: cannot write: {e.strerror or e}") from None
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def _write_special(path: str | Path, p: Path, raw: bytes) -> None:
    """A device, FIFO or socket: written in place (a FIFO without a reader is an error, not
    a hang)."""
    flags = os.O_WRONLY | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(p, flags)
    except OSError as e:
        why = "no process reads it" if e.errno == 6 else (e.strerror or str(e))  # ENXIO
        raise HncError(f"{path}: cannot write: {why}") from None
    try:
        os.set_blocking(fd, True)
        view = memoryview(raw)
        while view:
            n = os.write(fd, view)
            view = view[n:]
    except OSError as e:
        raise HncError(f"{path}: cannot write: {e.strerror or e}") from None
    finally:
        os.close(fd)


def read_bytes(path: str | Path, kind: str, error: Callable[[str], Exception] = HncError,
               max_bytes: int = 16 * 1024 * 1024) -> bytes:
    """The bytes of a user's input file, ``kind`` naming what it should be ("a TOML file").

    Only a regular file is read: it is opened without blocking, so a FIFO with no writer or a
    device is refused, not waited on or read without end. A directory, a file over
    ``max_bytes`` or one that cannot be read raises ``error`` with one line naming the path.
    """
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as e:
        raise error(f"{path}: cannot read: {e.strerror or e}") from None
    try:
        st = os.fstat(fd)
        if stat.S_ISDIR(st.st_mode):
            raise error(f"{path}: is a directory, not {kind}")
        if not stat.S_ISREG(st.st_mode):
            raise error(f"{path}: not a regular file")
        if st.st_size > max_bytes:
            raise error(f"{path}: {st.st_size} bytes, more than the {max_bytes} {kind} may have")
        with os.fdopen(os.dup(fd), "rb") as f:
            return f.read(max_bytes + 1)
    except OSError as e:
        raise error(f"{path}: cannot read: {e.strerror or e}") from None
    finally:
        os.close(fd)


def decode_text(raw: bytes, where: str, kind: str,
                error: Callable[[str], Exception] = HncError) -> str:
    """UTF-8 text of a user's file (a byte-order mark dropped). UTF-16, a byte that is not
    UTF-8 and a NUL character raise ``error`` with one line and the place (``FILE:LINE:COL``)."""
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise error(f"{where}: UTF-16 text; save {kind} as UTF-8")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        line = raw[:e.start].count(b"\n") + 1
        col = e.start - (raw.rfind(b"\n", 0, e.start) + 1) + 1
        raise error(f"{where}:{line}:{col}: not UTF-8 text (byte 0x{raw[e.start]:02x})") from None
    if text.startswith("\ufeff"):
        text = text[1:]
    if "\0" in text:
        i = text.index("\0")
        line = text.count("\n", 0, i) + 1
        raise error(f"{where}:{line}:{i - text.rfind(chr(10), 0, i)}: NUL byte: not {kind}")
    return text


def read_text(path: str | Path, kind: str, error: Callable[[str], Exception] = HncError,
              max_bytes: int = 16 * 1024 * 1024) -> str:
    """``read_bytes`` then ``decode_text``: a user's text file, or one line saying why not."""
    return decode_text(read_bytes(path, kind, error, max_bytes), str(path), kind, error)
