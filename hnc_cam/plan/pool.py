"""What the fork server of ``hnc-cam family``'s local pool imports once, before it forks the
workers (``multiprocessing``'s fork server preloads this module; a Dask worker started with
``--preload hnc_cam.plan.pool`` imports it too, to have the kernel before its first row).

The CAD kernel (build123d, OpenCascade), the profile extractor, the planner, the templates'
environment, the interpreter, the simulator and the bundled tool library and machine are
loaded here once; every worker is a fork of this process, so it starts with all of them
(their pages shared with the other workers, copy on write) instead of importing the kernel
itself (about 2 s and most of a worker's memory). In the fork server, the objects alive after
the imports are moved out of the cyclic garbage collector's reach (``gc.freeze``): a
collection in a worker then neither walks them nor writes to their pages, which would copy
the shared pages into each worker. The fork server itself leaves without tearing the kernel down (a second or more
of finalisation that nobody waits for) when the family process closes its pipe.

Whatever fails here (the CAD kernel not installed, a broken bundled file) is left for the
worker's initializer and the rows to report: this module never raises.
"""
from __future__ import annotations

import atexit
import gc
import os


def _preload() -> None:
    try:
        import build123d  # noqa: F401
    except Exception:  # noqa: BLE001 - no CAD kernel: the rows say so
        pass
    for name in ("hnc_cam.cad.extract", "hnc_cam.nc", "hnc_cam.sim", "hnc_cam.post",
                 "hnc_cam.plan.api", "hnc_cam.plan.command"):
        try:
            __import__(name)
        except Exception:  # noqa: BLE001 - the worker's own import reports it
            pass
    try:
        from .api import warm
        warm()
    except Exception:  # noqa: BLE001 - the rows report a broken bundled table
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


_preload()
if _in_fork_server():
    gc.collect()
    gc.freeze()
    # the fork server's own exit: no finalisation of the kernel (its workers end with
    # os._exit and never run this)
    atexit.register(os._exit, 0)
