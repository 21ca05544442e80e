"""pytest plugin (entry point ``pytest11``, loaded when hnc_cam is installed): the
``hnc_roundtrip`` fixture.

    def test_shaft(hnc_roundtrip):
        hnc_roundtrip("parts/shaft.py", stock="45x90+2", length=80)

``hnc_roundtrip(part, stock=None, tol=0.01, *, strict=False, report=None, **params)`` runs
:func:`hnc_cam.testing.assert_roundtrip` (generate, then verify the program text independently)
and returns ``(program, report)``. When the round trip fails it writes the HTML report of the
program (backplot, program, step-through, setup sheet) and the failure names its path:
``HTML report: /.../test_shaft.html``. Reports go to ``--hnc-reports DIR`` (default: a
``hnc_reports`` folder in pytest's base temporary directory); ``report="FILE.html"`` writes
the page whether the round trip passes or not. A relative part path is looked up from the
current directory, then from the rootdir.

Nothing heavy is imported until a test uses the fixture.
"""
from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("hnc_cam", "hnc_cam round trips")
    group.addoption("--hnc-reports", metavar="DIR", default=None,
                    help="where hnc_roundtrip writes the HTML report of a failing round trip "
                         "(default: hnc_reports in pytest's base temporary directory)")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "hnc_cam: a round trip of a turned part (hnc_roundtrip)")


def _resolve(part: Any, rootpath: Path) -> Any:
    if isinstance(part, (str, Path)):
        p = Path(part)
        if not p.is_absolute() and not p.exists() and (rootpath / p).exists():
            return str(rootpath / p)
        return str(p)
    return part


def roundtrip_report(path: str | Path, part: Any, stock: str | None, tol: float, *,
                     strict: bool = False, **params: Any):
    """Write the HTML report of ``part``'s round trip (as :func:`assert_roundtrip` runs it:
    the program generated without its own verification, the model loaded independently) and
    return the verification report."""
    import hnc_cam
    from .geometry import TurnedProfile
    from .nc.interp import run
    from .report import write_report
    from .sim import simulate, verify
    from .testing import GENERATE_OPTIONS
    from .tooling import Machine, Stock, ToolLibrary, load_machine, load_tools

    options = {k: params.pop(k) for k in list(params) if k in GENERATE_OPTIONS}
    part_params = {k: str(v) for k, v in params.items()}
    prog = hnc_cam.generate(part, stock=stock, verify=False, params=part_params or None,
                            **options)
    threads = None
    if isinstance(part, TurnedProfile):
        model = part
    elif isinstance(part, (str, Path)):
        from .cad import load_part
        loaded = load_part(str(part), part_params)
        model, threads = loaded.profile, loaded.threads
    else:
        model, threads = part.profile, getattr(part, "threads", None)
    st = prog.plan.stock if stock is None else (stock if isinstance(stock, Stock)
                                                else Stock.parse(str(stock)))
    tools = options.get("tools")
    lib = tools if isinstance(tools, ToolLibrary) else load_tools(tools)
    mach = options.get("machine")
    machine = mach if isinstance(mach, Machine) else load_machine(mach, tools=lib)
    tp = run(prog.text, machine, file=f"O{prog.plan.program_number:04d}.nc", start="reference")
    machined = simulate(tp, st, machine, model=model)
    rep = verify(machined, model, tol=tol, threads=threads, strict=strict)
    write_report(path, machined, rep, model, title=f"round trip of {prog.plan.name}",
                 plan=prog.plan, library=lib, stock=st.spec, labels=getattr(prog, "labels", None))
    return rep


@pytest.fixture
def hnc_roundtrip(request: pytest.FixtureRequest):
    """``hnc_roundtrip(part, stock=None, tol=0.01, *, strict=False, report=None, **params)``:
    generate and verify; on failure the HTML report is written and its path is in the
    failure message."""
    config = request.config
    rootpath = Path(str(config.rootpath))
    calls = [0]

    def report_path() -> Path:
        calls[0] += 1
        opt = config.getoption("--hnc-reports")
        if opt:
            base = Path(opt)
            if not base.is_absolute():
                base = Path(str(config.invocation_params.dir)) / base
        else:
            base = request.getfixturevalue("tmp_path_factory").getbasetemp() / "hnc_reports"
        name = re.sub(r"[^A-Za-z0-9_.-]+", "_", request.node.name).strip("_") or "roundtrip"
        if calls[0] > 1:
            name += f"_{calls[0]}"
        return base / f"{name}.html"

    def roundtrip(part: Any, stock: str | None = None, tol: float = 0.01, *,
                  strict: bool = False, report: str | Path | None = None, **params: Any):
        from .testing import assert_roundtrip
        part = _resolve(part, rootpath)
        try:
            result = assert_roundtrip(part, stock, tol, strict=strict, **dict(params))
        except AssertionError as e:
            path = Path(report) if report else report_path()
            try:
                roundtrip_report(path, part, stock, tol, strict=strict, **dict(params))
                where = f"HTML report: {path}"
            except Exception as err:  # the failure itself matters more than its report
                where = f"HTML report not written: {type(err).__name__}: {err}"
            raise AssertionError(f"{e}\n{where}") from None
        if report:
            roundtrip_report(report, part, stock, tol, strict=strict, **dict(params))
        return result

    return roundtrip
