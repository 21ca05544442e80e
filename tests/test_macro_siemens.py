"""``hnc-cam family PART --macro --dialect siemens802``: the SINUMERIK 802 R-parameter form.

The macro's main program sets the family's parameters as R20... and its contour subprograms
are written with R expressions; run through the 802 reader for fresh parameter sets, its
toolpath is the per-variant ``generate --comp control --dialect siemens802`` program's."""
from __future__ import annotations

import random
import re
from pathlib import Path

import pytest

from hnc_cam.cli import main
from hnc_cam.nc import run

FRESH = Path(__file__).resolve().parent / "data" / "families"


def _moving(tp):
    return [m for m in tp.moves if m.kind != "dwell"
            and (abs(m.end[0] - m.start[0]) > 1e-3 or abs(m.end[1] - m.start[1]) > 1e-3)]


def _folder_text(d: Path) -> str:
    """The written programs as one 802 transfer file: the main program first."""
    mpf = sorted(d.glob("*.MPF"))
    spf = sorted(d.glob("*.SPF"))
    assert len(mpf) == 1 and spf
    return "".join(p.read_text() for p in mpf + spf)


def _with(text: str, values: dict[str, float]) -> str:
    """The macro with the parameter lines ``R20=60 ; LENGTH`` set to ``values``."""
    for k, v in values.items():
        text, n = re.subn(rf"^(R\d+)=[-0-9.]+ ; {k.upper()}$", rf"\g<1>={v:.3f} ; {k.upper()}",
                          text, flags=re.M)
        assert n == 1, k
    return text


def _variant(part: Path, stock: str, values: dict[str, float]) -> str:
    from hnc_cam.plan.api import generate
    return generate(str(part), stock, params={k: f"{v:.3f}" for k, v in values.items()},
                    comp="control", verify=False, dialect="siemens802").text


def _same(got, ref):
    a, b = _moving(got), _moving(ref)
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x.kind == y.kind
        assert abs(x.end[0] - y.end[0]) <= 0.001 and abs(x.end[1] - y.end[1]) <= 0.001


def _derive(tmp_path, part: Path, check: int = 2, extra=()):
    out = tmp_path / "out"
    assert main(["family", str(part), "--macro", "--dialect", "siemens802", "--check",
                 str(check), *extra, "-o", f"{out}/"]) == 0
    return out


def test_pin_macro_follows_every_variant_and_verifies(tmp_path, capsys):
    """The pin family: NAME.MPF with R parameters and the contour subprogram with R words;
    10 fresh sets through the 802 reader equal the per-variant programs within 0.001 mm, and
    the command's own check (10 sets) simulates and verifies each against its model."""
    out = _derive(tmp_path, FRESH / "pin.py", check=10)
    assert "checked 10 parameter set(s): pass" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == ["PIN.MPF", "PIN_C1.SPF"]
    spf = (out / "PIN_C1.SPF").read_text()
    assert spf.startswith("%_N_PIN_C1_SPF")
    # the contour's dimensions are R expressions: the journal X=d, its shoulder Z=-l, the
    # chamfer's own length CHF=
    assert re.search(r"G1 X=R21 Z=\(-R22\)", spf)
    assert spf.count("CHF=") == 2 and "CHF=1" not in spf
    text = _folder_text(out)
    assert re.search(r"^R20=60 ; LENGTH$", text, re.M)
    stock = re.search(r"^; STOCK (\S+)", text, re.M).group(1)
    rnd = random.Random(1802)
    for _ in range(10):
        p = {"length": rnd.uniform(57, 63), "d": rnd.uniform(22.8, 25.2),
             "l": rnd.uniform(28.5, 31.5), "collar": rnd.uniform(32.3, 35.7),
             "chamfer": rnd.uniform(0.95, 1.05)}
        p = {k: round(v, 3) for k, v in p.items()}
        got = run(_with(text, p), file="<macro>", start="reference", dialect="siemens802")
        ref = run(_variant(FRESH / "pin.py", stock, p), file="<variant>", start="reference",
                  dialect="siemens802")
        _same(got, ref)


@pytest.mark.parametrize("bad", [{"d": 36.0}, {"length": 70.0}, {"chamfer": 20.0}])
def test_a_failing_check_stops_before_any_motion(tmp_path, bad):
    """A set the family refuses (d above the collar, outside the domain, a chamfer that does
    not fit) jumps to its stop: M30 with the parameters named, nothing moves."""
    out = tmp_path / "out"
    assert main(["family", str(FRESH / "pin.py"), "--macro", "--dialect", "siemens802",
                 "--check", "0", "-o", f"{out}/"]) == 0
    text = _folder_text(out)
    tp = run(_with(text, bad), file="<macro>", start="reference", dialect="siemens802")
    assert not _moving(tp)
    # the stop the check jumps to names the parameter
    k = next(iter(bad)).upper()
    lines = text.splitlines()
    stops = [lines[i + 1] for i, ln in enumerate(lines) if re.fullmatch(r"ER\d+:", ln)]
    assert any(k in s for s in stops)


def test_a_decision_at_the_control_is_if_gotof(tmp_path):
    """grooved_pin's groove appears above length 52: one 802 program, the control jumps over
    the alternative it does not cut (IF ... GOTOF), either side's toolpath the variant's."""
    out = _derive(tmp_path, FRESH / "grooved_pin.py", check=2)
    text = _folder_text(out)
    assert re.search(r"^IF R\d+>52 GOTOF MD\d+$", text, re.M)
    stock = re.search(r"^; STOCK (\S+)", text, re.M).group(1)
    for length in (48.5, 51.9, 52.0, 52.1, 52.4):
        got = run(_with(text, {"length": length}), file="<macro>", start="reference",
                  dialect="siemens802")
        ref = run(_variant(FRESH / "grooved_pin.py", stock, {"length": length}),
                  file="<variant>", start="reference", dialect="siemens802")
        _same(got, ref)


def test_table_rows_are_selected_by_number(tmp_path):
    table = tmp_path / "t.csv"
    table.write_text("length,collar\n58,33\n62.5,35.5\n")
    out = _derive(tmp_path, FRESH / "pin.py", check=1, extra=("--table", str(table)))
    text = _folder_text(out)
    assert re.search(r"^R20=1 ; ROW", text, re.M) and "IF R20<>2 GOTOF RW2" in text
    stock = re.search(r"^; STOCK (\S+)", text, re.M).group(1)
    for row, over in ((1, {"length": 58.0, "collar": 33.0}),
                      (2, {"length": 62.5, "collar": 35.5})):
        t = text.replace("R20=1 ; ROW", f"R20={row} ; ROW")
        got = run(t, file="<macro>", start="reference", dialect="siemens802")
        ref = run(_variant(FRESH / "pin.py", stock, over), file="<variant>",
                  start="reference", dialect="siemens802")
        _same(got, ref)
    bad = text.replace("R20=1 ; ROW", "R20=3 ; ROW")
    assert not _moving(run(bad, file="<macro>", start="reference", dialect="siemens802"))


def test_one_file_holds_the_main_program_and_its_subprograms(tmp_path, capsys):
    """-o FILE: the 802 transfer form, every program in one file, as the reader runs it."""
    f = tmp_path / "pin.txt"
    assert main(["family", str(FRESH / "pin.py"), "--macro", "--dialect", "siemens802",
                 "--check", "1", "-o", str(f)]) == 0
    text = f.read_text()
    assert text.startswith("%_N_PIN_MPF") and "\n%_N_PIN_C1_SPF\n" in text
    assert _moving(run(text, file="<macro>", start="reference", dialect="siemens802"))


def test_a_bundled_family_in_the_802_form(tmp_path, capsys):
    """cq_pin (parts/): one 802 program deciding its left-end chamfer passes at the control
    (head_chamfer <= 1); the command checks 10 sets through the 802 reader, the simulator and
    verify; fresh sets on both sides of the decision follow their variants."""
    part = Path(__file__).resolve().parent.parent / "parts" / "cq_pin.py"
    out = _derive(tmp_path, part, check=10)
    assert "checked 10 parameter set(s): pass" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == ["CQ_PIN.MPF", "CQ_PIN_C1.SPF"]
    text = _folder_text(out)
    assert re.search(r"^IF R28>1 GOTOF MD\d+$", text, re.M)
    stock = re.search(r"^; STOCK (\S+)", text, re.M).group(1)
    rnd = random.Random(21)
    nominal = {"length": 40, "diameter": 16, "chamfer": 1.5, "groove_z": 8,
               "groove_depth": 1, "head_diameter": 24, "head_thickness": 6, "fillet": 1}
    for hc in (0.97, 1.03):
        p = {k: v * (1 + rnd.uniform(-0.02, 0.02)) for k, v in nominal.items()}
        p["head_chamfer"] = hc
        got = run(_with(text, p), file="<macro>", start="reference", dialect="siemens802")
        ref = run(_variant(part, stock, p), file="<variant>", start="reference",
                  dialect="siemens802")
        _same(got, ref)


def test_a_split_family_names_each_programs_files(tmp_path, capsys):
    """bushing (parts/) is two programs (split at outer_diameter 44): the second is
    BUSHING2.MPF with its own BUSHING2_C1.SPF ..., so one folder holds both; each program
    cuts its side of the boundary as the per-variant program does."""
    part = Path(__file__).resolve().parent.parent / "parts" / "bushing.py"
    out = _derive(tmp_path, part, check=2)
    names = sorted(p.name for p in out.iterdir())
    assert names == ["BUSHING.MPF", "BUSHING2.MPF", "BUSHING2_C1.SPF", "BUSHING2_C2.SPF",
                     "BUSHING_C1.SPF", "BUSHING_C2.SPF"]
    for mpf, od in (("BUSHING", 40.5), ("BUSHING2", 45.5)):
        text = "".join((out / n).read_text() for n in names if n.startswith(mpf + ".")
                       or n.startswith(mpf + "_"))
        assert f'_CNAME="{mpf}_C1"' in text
        stock = re.search(r"^; STOCK (\S+)", text, re.M).group(1)
        got = run(_with(text, {"outer_diameter": od}), file="<macro>", start="reference",
                  dialect="siemens802")
        ref = run(_variant(part, stock, {"outer_diameter": od}), file="<variant>",
                  start="reference", dialect="siemens802")
        _same(got, ref)


@pytest.mark.parametrize("node", [
    ("f", "sin", ("p", "a")), ("f", "cos", ("*", ("p", "a"), ("p", "b"))),
    ("f", "tan", ("p", "a")), ("f", "atan", ("p", "b")), ("atan2", ("p", "a"), ("p", "b")),
    ("atan2", ("neg", ("p", "a")), ("p", "b")), ("f", "sqrt", ("+", ("p", "a"), ("c", 2.0))),
    ("min", ("p", "a"), ("p", "b")), ("max", ("p", "a"), ("neg", ("p", "b"))),
    ("-", ("c", -3.5), ("/", ("p", "a"), ("p", "b")))])
def test_expressions_keep_their_value_through_the_802_reader(node):
    """An expression as the 802 form writes it (degrees, ATAN2, ( ) brackets, R variables)
    has, read by our 802 reader, the value of the traced expression (radians)."""
    from hnc_cam.plan.macro import Lets, _ev
    env = {"a": 0.7, "b": -1.3}
    lets = Lets({"a": "R20", "b": "R21"}, "siemens802", first=30, last=99, inline=12)
    e = lets.expr(node)
    text = "\n".join(["%_N_T_MPF", "R20=0.7 R21=-1.3", *lets.lines, "G18 G23 G90",
                      f"G0 X=({e})*10+100 Z0", "M30"]) + "\n"
    tp = run(text, file="<t>", start="reference", dialect="siemens802")
    x = tp.moves[-1].end[0] * 2  # G23: X is a diameter
    assert (x - 100) / 10 == pytest.approx(_ev(node, env), abs=1e-9)


def test_temporaries_beyond_r99_are_refused():
    """The temporaries stay below the cycles' R100: more than the range holds is refused."""
    from hnc_cam.errors import PlanError
    from hnc_cam.plan.macro import Lets
    lets = Lets({"a": "R20"}, "siemens802", first=98, last=99, inline=4)
    node = ("p", "a")
    for k in range(1, 5):
        node = ("+", ("*", node, ("c", float(k))), ("f", "sqrt", node))
    with pytest.raises(PlanError, match="R99"):
        lets.expr(node)
