"""The macro's symbolic trace of a family's sketch: every contour point and arc radius is an
exact expression of the parameters (checked against sketch() on random parameter sets), the
traced checks accept exactly the sets sketch() accepts, and the expressions written as
HNC-21T macro words drive the bundled interpreter along the same contour."""
from __future__ import annotations

import random
from pathlib import Path

import pytest

from hnc_cam.cad.loader import family_parameters, load_module
from hnc_cam.cad.sketch import SketchError
from hnc_cam.geometry.primitives import Arc
from hnc_cam.plan.macro import Lets, _ev, _holds, _node, _trace

PARTS = Path(__file__).resolve().parent.parent / "parts"
FAMILIES = sorted(p.name for p in PARTS.glob("*.py")
                  if "def sketch" in p.read_text(encoding="utf-8"))


def _samples(defaults, n, seed, spread=0.25):
    rnd = random.Random(seed)
    for _ in range(n):
        yield {k: (v * (1 + rnd.uniform(-spread, spread)) if isinstance(v, float) else v)
               for k, v in defaults.items()}


def _free(defaults):
    return [k for k, v in defaults.items() if isinstance(v, float)]


def _traced(name):
    """(module, default parameters, free parameter names, trace) of a bundled family."""
    mod = load_module(PARTS / name)
    d = family_parameters(mod)
    free = _free(d)
    return mod, d, free, _trace(mod, d, free)


@pytest.mark.parametrize("name", FAMILIES)
def test_traced_contour_is_exact(name):
    mod, d, _, tr = _traced(name)
    accepted = refused = 0
    for p in _samples(d, 40, name):
        try:
            segs = mod.sketch(**p)
        except SketchError:
            refused += 1
            assert not all(all(_holds(c, p) for c in ch.conds) for ch in tr.checks), p
            continue
        accepted += 1
        assert all(all(_holds(c, p) for c in ch.conds) for ch in tr.checks), p
        assert len(segs) == len(tr.segments)
        for s, t in zip(segs, tr.segments):
            for a, b in ((s.start, t[1]), (s.end, t[2])):
                assert _ev(_node(b[0]), p) == pytest.approx(a[0], abs=1e-9)
                assert _ev(_node(b[1]), p) == pytest.approx(a[1], abs=1e-9)
            assert isinstance(s, Arc) == (t[0] == "A")
            if t[0] == "A":
                assert _ev(_node(t[4]), p) == pytest.approx(s.radius, abs=1e-9)
                assert s.cw == t[5]
    assert accepted >= 5


def test_a_refused_set_fails_the_check_that_names_its_parameter():
    mod, d, _, tr = _traced("stepped_shaft.py")
    bad = dict(d, d1=30.0)  # d1 > d2
    failing = [ch for ch in tr.checks if not all(_holds(c, bad) for c in ch.conds)]
    assert failing and all("d1" in ch.names for ch in failing)


@pytest.mark.parametrize("name", ["stepped_shaft.py", "grooved_shaft.py", "threaded_stud.py"])
def test_macro_words_drive_the_interpreter_along_the_contour(name):
    from hnc_cam.nc import run
    mod, d, free, tr = _traced(name)
    var = {k: f"#{50 + i}" for i, k in enumerate(free)}
    lines = ["%0001"]
    lines += [f"{var[k]}={v!r}" for k, v in d.items() if k in var]
    lines.append("M98 P1001")
    lines.append("M30")
    lines.append("%1001")
    lets = Lets(var)

    def word(n):
        s = lets.expr(_node(n))
        lines.extend(lets.lines)
        lets.lines.clear()
        return s

    first = tr.segments[0][1]
    x0, z0 = word(first[0] * 2), word(first[1])
    lines.append(f"G00 X[{x0}] Z[{z0}]")
    for t in tr.segments:
        x, z = word(t[2][0] * 2), word(t[2][1])
        if t[0] == "L":
            lines.append(f"G01 X[{x}] Z[{z}] F0.1")
        else:
            r = word(t[4])
            lines.append(f"G0{2 if t[5] else 3} X[{x}] Z[{z}] R[{r}] F0.1")
    lines.append("M99")
    for p in list(_samples(d, 12, name, 0.05)):
        try:
            segs = mod.sketch(**p)
        except SketchError:
            continue
        text = "\n".join(lines).replace("\n".join(f"{var[k]}={d[k]!r}" for k in free),
                                        "\n".join(f"{var[k]}={p[k]!r}" for k in free)) + "\n"
        tp = run(text, start=(0.0, 0.0))
        cuts = [m for m in tp.moves if m.kind in ("line", "arc")]
        assert len(cuts) == len(segs)
        for m, s in zip(cuts, segs):
            assert m.end[0] == pytest.approx(s.end[0], abs=1e-6)
            assert m.end[1] == pytest.approx(s.end[1], abs=1e-6)
            assert (m.kind == "arc") == isinstance(s, Arc)


def test_domain_box_covers_the_table_and_whole_numbers_stay_fixed():
    from hnc_cam.errors import PartError
    from hnc_cam.plan.macro import load_family
    f = load_family(str(PARTS / "stepped_shaft.py"), {"d1": "21"}, [{"length": "130"}],
                    spread=0.1)
    assert f.params["d1"] == 21.0
    assert f.lo["d1"] == pytest.approx(18.9) and f.hi["d1"] == pytest.approx(23.1)
    assert f.lo["length"] == pytest.approx(90.0) and f.hi["length"] == 130.0
    g = load_family(str(PARTS / "cast_blank.py"), {})
    assert "waves" not in g.free and g.params["waves"] == 3
    with pytest.raises(PartError, match="waves"):
        load_family(str(PARTS / "cast_blank.py"), {}, [{"waves": "4"}])
    with pytest.raises(PartError, match="not a number"):
        load_family(str(PARTS / "stepped_shaft.py"), {"d1": "abc"})


def test_hnc_checks_end_the_program_before_any_motion():
    from hnc_cam.nc import run
    from hnc_cam.plan.macro import hnc_checks
    mod, d, free, tr = _traced("stepped_shaft.py")
    var = {k: f"#{50 + i}" for i, k in enumerate(free)}
    body = hnc_checks(tr, Lets(var))

    def prog(p):
        return "\n".join(["%0001"] + [f"{var[k]}={p[k]!r}" for k in free]
                         + ["M98 P1001", "M30", "%1001"] + body
                         + ["G00 X50 Z5", "G01 X40 Z0 F0.1", "M99"]) + "\n"

    seen = set()
    for p in _samples(d, 30, "checks"):
        try:
            mod.sketch(**p)
            ok = True
        except SketchError:
            ok = False
        moves = run(prog(p), start=(0.0, 0.0)).moves
        assert bool(moves) == ok, p
        seen.add(ok)
    assert seen == {True, False}
    assert not run(prog(dict(d, d1=30.0)), start=(0.0, 0.0)).moves


@pytest.mark.parametrize("name", ["grooved_shaft.py", "stepped_shaft.py", "cq_pin.py"])
def test_fanuc_macro_words_follow_the_contour(name):
    """FANUC: trigonometry in degrees, brackets at most 5 deep (PS0118), temporaries #500+."""
    from hnc_cam.nc import run
    mod, d, free, tr = _traced(name)
    var = {k: f"#{100 + i}" for i, k in enumerate(free)}
    for p in list(_samples(d, 8, name, 0.05)):
        try:
            segs = mod.sketch(**p)
        except SketchError:
            continue
        lets = Lets(var, "fanuc0it", first=500, last=999)
        lines = ["%", "O0001"] + [f"{var[k]}={p[k]!r}" for k in free]

        def word(n):
            s = lets.expr(_node(n))
            lines.extend(lets.lines)
            lets.lines.clear()
            return s

        first = tr.segments[0][1]
        lines.append(f"G00 X[{word(first[0] * 2)}] Z[{word(first[1])}]")
        for t in tr.segments:
            x, z = word(t[2][0] * 2), word(t[2][1])
            lines.append(f"G01 X[{x}] Z[{z}] F0.1" if t[0] == "L" else
                         f"G0{2 if t[5] else 3} X[{x}] Z[{z}] R[{word(t[4])}] F0.1")
        lines += ["M30", "%"]
        tp = run("\n".join(lines) + "\n", start=(0.0, 0.0), dialect="fanuc0it")
        cuts = [m for m in tp.moves if m.kind in ("line", "arc")]
        assert len(cuts) == len(segs)
        for m, s in zip(cuts, segs):
            assert m.end[0] == pytest.approx(s.end[0], abs=1e-6)
            assert m.end[1] == pytest.approx(s.end[1], abs=1e-6)
