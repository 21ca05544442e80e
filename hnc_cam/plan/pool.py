"""What the fork server of ``hnc-cam family``'s local pool imports once, before it forks the
workers (``multiprocessing``'s fork server preloads this module; a Dask worker started with
``--preload hnc_cam.plan.pool`` imports it too, to have the kernel before its first row).

The profile extractor, the planner, the templates' environment, the interpreter, the
simulator and the bundled tool library and machine are loaded here once, and the family's
part file (named by the family process as it starts the server) is loaded with its defaults,
its nominal row: what that imports (the part module and its helpers, the CAD kernel when the
part file imports it or its ``part()`` uses a solid) is loaded here once too. A family whose
``part()`` returns ``revolve(outline)`` needs no CAD kernel (the loader defers the solid and
profiles the outline), and none is imported: a few tens of MB per worker instead of the
kernel's hundreds, and no 2 to 3 s import before the first row. Without a part named (a Dask
worker, a pool started for no family), the CAD kernel (build123d, OpenCascade) is imported.
Every worker is a fork of this process, so it starts with all of it (their pages shared with
the other workers, copy on write) instead of importing it itself. One small program is
generated here too,
so that what a first row does once (modules imported on first use, templates compiled) is
done once for all the workers. The cyclic collector is off while all this is imported (a
tenth of the import's CPU). In the fork server, the objects alive after
the imports are moved out of the cyclic garbage collector's reach (``gc.freeze``): a
collection in a worker then neither walks them nor writes to their pages, which would copy
the shared pages into each worker. The fork server itself leaves without tearing the kernel down (a second or more
of finalisation that nobody waits for) when the family process closes its pipe.

Whatever fails here (the CAD kernel not installed, a broken bundled file, a part that does not
load) is left for the worker's initializer and the rows to report: this module never raises.
"""
from __future__ import annotations

import atexit
import gc
import os


#: whether this process generated the warm-up program (:func:`_first_program`): true in the
#: fork server and in every worker forked from it
WARMED: list[bool] = [False]

#: the part file this process loaded before forking (its nominal row), or None: then the
#: CAD kernel was imported whether the rows need it or not
PART: list[str | None] = [None]


def _preload() -> None:
    try:
        from .command import POOL_PART_ENV
        part = os.environ.get(POOL_PART_ENV) or None
    except Exception:  # noqa: BLE001 - the worker's own import reports it
        part = None
    if part is None:
        try:
            import build123d  # noqa: F401
        except Exception:  # noqa: BLE001 - no CAD kernel: the rows say so
            pass
    for name in ("hnc_cam.cad.extract", "hnc_cam.cad.sketch", "hnc_cam.nc", "hnc_cam.sim",
                 "hnc_cam.post", "hnc_cam.plan.api", "hnc_cam.plan.command"):
        try:
            __import__(name)
        except Exception:  # noqa: BLE001 - the worker's own import reports it
            pass
    if part is not None:
        _nominal_row(part)
    try:
        from .api import warm
        warm()
        _first_program()
        WARMED[0] = True
    except Exception:  # noqa: BLE001 - the rows report a broken bundled table
        pass


def _nominal_row(part: str) -> None:
    """The family's part loaded once with its defaults (the nominal row), as a row loads it:
    what that imports (the part module, the helpers it imports, the CAD kernel when the part
    file imports it or its ``part()`` uses a solid) is then shared by every worker. A part
    whose ``part()`` only returns ``revolve(outline)`` needs no CAD kernel at all
    (:func:`hnc_cam.cad.loader._deferred_part`), and none is imported: a row that does
    need it imports it in its worker."""
    PART[0] = part
    try:
        from ..cad import load_part
        load_part(part)
    except BaseException:  # noqa: BLE001 - the rows report the part's errors
        pass


def _first_program() -> None:
    """A small shaft's program generated and read back once here (not verified), so that
    what a worker's first row would otherwise do once each, in every worker (the modules the
    generator and the interpreter import on first use, the templates compiled), is done once
    and shared."""
    from ..geometry import Line, TurnedProfile
    from .api import generate
    pts = [(0.0, 0.0), (8.0, 0.0), (8.0, -12.0), (11.0, -12.0), (11.0, -25.0), (0.0, -25.0)]
    prof = TurnedProfile(outside=[Line(a, b) for a, b in zip(pts, pts[1:])], bore=None,
                         name="warm-up")
    generate(prof, verify=False)


def _release_free_memory() -> None:
    """Give the heap's free pages back to the system (glibc's ``malloc_trim``), so that the
    workers forked from here do not start with them counted in their resident memory."""
    import sys
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes
        ctypes.CDLL(None).malloc_trim(0)
    except (OSError, AttributeError):  # another C library: nothing to release this way
        pass


def _in_fork_server() -> bool:
    """True when this import runs inside ``multiprocessing.forkserver.main`` (its preload)."""
    import sys
    f = sys._getframe()
    while f is not None:
        if f.f_code.co_name == "main" and \
                f.f_globals.get("__name__") == "multiprocessing.forkserver":
            return True
        f = f.f_back
    return False


# the cyclic collector is off while the kernel is imported: the imports make millions of
# objects and almost no cyclic garbage, and its passes over them cost about a tenth of the
# import's time (collected once below, or by the collector when it is on again)
_collecting = gc.isenabled()
gc.disable()
try:
    _preload()
finally:
    if _collecting:
        gc.enable()
if _in_fork_server():
    gc.collect()
    gc.freeze()
    _release_free_memory()
    # the fork server's own exit: no finalisation of the kernel (its workers end with
    # os._exit and never run this)
    atexit.register(os._exit, 0)
