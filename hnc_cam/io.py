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
import stat
import sys
import tempfile
from pathlib import Path

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


def _resolve(p: Path) -> Path:
    """Follow a symbolic link (chains too) to the path it names; a dangling link names the
    file to create."""
    if p.is_symlink():
        try:
            return Path(os.path.realpath(p))
        except OSError:
            return p
    return p


def write_atomic(path: str | Path, data: str | bytes) -> None:
    """Write ``data`` to ``path`` whole or not at all; ``-`` writes text to stdout."""
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
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
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
