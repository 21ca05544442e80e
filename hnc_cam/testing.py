"""Round-trip checks for pytest: generate a program for a part, then verify it independently.

    from hnc_cam.testing import assert_roundtrip

    def test_shaft():
        assert_roundtrip("parts/stepped_shaft.py", stock="45x110+2", tol=0.01, d1=22)

``assert_roundtrip`` plans and renders the program with :func:`hnc_cam.generate` (its own
verification switched off), then checks the *text* the way a user's CI would: the model comes
from the CAD front end (not from the planner), the program is re-run by the interpreter, the cut
is simulated from the stock and compared with the model (:func:`hnc_cam.sim.verify`). It raises
``AssertionError`` with the report when the program fails, and returns ``(program, report)``.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

#: keyword arguments of hnc_cam.generate that are options, not part parameters
GENERATE_OPTIONS = ("tools", "machine", "comp", "templates", "program_number", "number_format",
                    "block_numbers", "thread_cycle", "face_cycle")


def assert_roundtrip(part: Any, stock: str | None = None, tol: float = 0.01, *,
                     strict: bool = False, plot: str | Path | None = None, **params: Any):
    """Generate a program for ``part`` (a part file path, a loaded part or a TurnedProfile)
    from ``stock`` (default: the part's STOCK) and assert that it verifies within ``tol`` mm.

    ``params``: part parameters (``d1=22``); generate options (``comp="control"``,
    ``tools=...``, ``machine=...``, ...) are passed to :func:`hnc_cam.generate` and used for
    the simulation too. ``plot``: also write the verification plot there. Returns
    ``(program, report)``.
    """
    import hnc_cam
    from .geometry import TurnedProfile
    from .nc.interp import run
    from .sim import simulate, verify
    from .tooling import Machine, Stock, ToolLibrary, load_machine, load_tools

    options = {k: params.pop(k) for k in list(params) if k in GENERATE_OPTIONS}
    part_params = {k: str(v) for k, v in params.items()}
    prog = hnc_cam.generate(part, stock=stock, verify=False,
                            params=part_params or None, **options)

    # the model, independently of the planner
    threads = None
    if isinstance(part, TurnedProfile):
        model, default_stock = part, None
    elif isinstance(part, (str, Path)):
        from .cad import load_part
        loaded = load_part(str(part), part_params)
        model, default_stock, threads = loaded.profile, loaded.stock, loaded.threads
    else:
        model, default_stock = part.profile, getattr(part, "stock", None)
        threads = getattr(part, "threads", None)
    spec = stock if stock is not None else default_stock
    if spec is None:
        raise AssertionError("no stock given and the part declares none")
    st = spec if isinstance(spec, Stock) else Stock.parse(str(spec))

    tools = options.get("tools")
    lib = tools if isinstance(tools, ToolLibrary) else load_tools(tools)
    mach = options.get("machine")
    machine = mach if isinstance(mach, Machine) else load_machine(mach, tools=lib)

    tp = run(prog.text, machine, file=f"<{getattr(model, 'name', 'part')} roundtrip>",
             start="reference")
    machined = simulate(tp, st, machine, model=model)
    report = verify(machined, model, tol=tol, threads=threads, strict=strict)
    if plot is not None:
        from .sim.plot import plot as _plot
        _plot(machined, plot, report=report, model=model)
    if not report.passed:
        head = "\n".join(prog.text.splitlines()[:12])
        raise AssertionError(f"round trip of {getattr(model, 'name', part)} from {st.spec} "
                             f"fails at {tol:g} mm:\n{report.summary()}\n"
                             f"program (first lines):\n{head}\n...")
    return prog, report
