"""Decisions at the control where the planner switches between two laws or two shapes of a
section at its own threshold, on a family written for the purpose (a bolt blank: thread,
relief groove, head): the macro decides where the planner does, proven against per-variant
programs on table rows on both sides of the threshold; where the planner's test combines
several dimensions (no one feature holds it), the derivation refuses and names the cause."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BOLT = ROOT / "tests" / "data" / "families" / "bolt.py"


def _family(tmp_path, capsys, *args):
    from hnc_cam.cli import main
    out = tmp_path / "m"
    rc = main(["family", str(BOLT), "--macro", *args, "-o", str(out) + "/"])
    err = capsys.readouterr().err
    return rc, err, out


def _rows(tmp_path, capsys, family, rows, *args):
    """``family --macro`` of ``family`` with the table ``rows`` (CSV text): (exit code, stderr,
    the program's text or None)."""
    from hnc_cam.cli import main
    table = tmp_path / "rows.csv"
    table.write_text(rows)
    out = tmp_path / "m"
    rc = main(["family", str(family), "--macro", "--table", str(table), *args,
               "-o", str(out) + "/"])
    err = capsys.readouterr().err
    progs = sorted(out.glob("*.nc")) if out.exists() else []
    return rc, err, progs[0].read_text() if len(progs) == 1 else None


def test_802_decides_the_grooves_speed_where_the_planner_does(tmp_path, capsys):
    # the groove's G96 S120 needs 3000 rpm at diameter 12.732: its bottom d - 2.24 is there
    # at d 14.972; below it the planner writes G97 S3000 (the 802's LIMS holds the rest)
    table = tmp_path / "rows.csv"
    table.write_text("d,w,dh\n14.2,3.3,25\n14.97,3.5,26\n14.975,3.5,26\n15.5,3.9,29\n")
    rc, err, out = _family(tmp_path, capsys, "--dialect", "siemens802", "--table", str(table),
                           "--check", "2")
    assert rc == 0, err
    mpf = [p for p in out.iterdir() if p.suffix == ".MPF"]
    assert len(mpf) == 1
    text = mpf[0].read_text()
    m = re.search(r"; D < ([0-9.]+)\?", text)
    assert m and 14.97 < float(m.group(1)) <= 14.975, text
    # the two branches: the groove at the spindle limit, and at its surface speed
    assert "G97 S3000 M3" in text and "G96 S120 LIMS=3000 M3" in text


def test_a_range_the_library_cuts_in_part_is_told(tmp_path, capsys):
    # w down to 3 is declared, but at w 3 the threading insert's flank meets the head: the
    # macro spans w 3.25..4 and says so; a table row below is refused with the reason
    rc, err, out = _family(tmp_path, capsys, "--dialect", "fanuc0it", "--check", "0")
    assert rc == 0, err
    assert "warning: w spans 3.25..4, not to the DOMAIN's 3" in err
    text = next(out.glob("O*.nc")).read_text()
    assert re.search(r"IF \[#\d+ LT 3\.25\]", text), text
    table = tmp_path / "rows.csv"
    table.write_text("d,w\n15,3.2\n")
    rc, err, out2 = _family(tmp_path, capsys, "--dialect", "fanuc0it", "--table", str(table),
                            "--check", "0")
    assert rc == 2 and "row 1 gives w=3.2, outside the macro's w 3.25..4" in err


def test_fanuc_is_one_program_without_decisions(tmp_path, capsys):
    # FANUC's G50 S clamps G96 and its G76 keeps the thread's end: nothing to decide
    rc, err, out = _family(tmp_path, capsys, "--dialect", "fanuc0it", "--check", "3")
    assert rc == 0, err
    (prog,) = out.glob("O*.nc")
    body = [ln for ln in prog.read_text().splitlines() if ln.startswith("IF")]
    assert all("#3000" in ln for ln in body)  # only the parameter checks' alarms


def test_hnc_single_passes_make_one_program(tmp_path, capsys):
    rc, err, out = _family(tmp_path, capsys, "--thread-cycle", "g82", "--check", "3")
    assert rc == 0, err
    (prog,) = out.glob("O*.nc")
    text = prog.read_text()
    assert "G82 X[" in text and "G76" not in text


@pytest.mark.slow
def test_hnc_thread_cycle_switch_is_refused_with_its_cause(tmp_path, capsys):
    # G76 or G82 passes by a test of d, w and dh together: no threshold on one feature holds
    # it; the refusal names the thread's cycle and the option that makes it one program
    rc, err, out = _family(tmp_path, capsys, "--check", "3")
    assert rc == 2 and not out.exists()
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1
    assert "G76" in lines[0] and "G82" in lines[0] and "--thread-cycle g82" in lines[0]


def test_round_written_breaks_a_half_up_whatever_the_binary_value():
    from hnc_cam.units import round_written
    # -0.1605 and 0.1605 are not exact in binary; the rule does not depend on which side
    assert round_written(-0.1605) == -0.16 and round_written(0.1605) == 0.161
    assert round_written(-160.5 / 1000) == -0.16 and round_written(2.0004999) == 2.0
    assert round_written(-0.16049) == -0.16 and round_written(-0.16051) == -0.161


def test_a_word_that_fits_nothing_after_a_kinked_one_decides_the_kink_first():
    """Two regimes of the planner's switch fitted as the larger of two laws (the G71's split
    at X19.1, or at d1 + 1.22 above it), and a later word that fits nothing over the same
    variants (the split's Z on a taper below, on the face above): the kinked word is what
    changes, with the set where its other law holds, its nominal's law first."""
    from hnc_cam.plan.macro_program import Slot, _kinked, blocks, core
    nb = core(blocks("%0001\nN27 G00 X19.22\nN28 G01 Z-12.7\nM30\n"))
    law_d1 = ("+", ("p", "d1"), ("c", 1.22))
    slots = [Slot(1, 1, "fit", ("max", ("c", 19.1), law_d1))]
    sets = [{"d1": 18.0}, {"d1": 18.3}, {"d1": 17.2}, {"d1": 17.5}]
    t = _kinked(slots, nb, sets)
    other, what, (bi, wi, first, second) = t.p, t.diff, t.split
    assert other == {"d1": 17.2} and (bi, wi) == (1, 1)
    assert first == law_d1 and second == ("c", 19.1)  # the nominal (d1 18) follows d1 + 1.22
    assert "X19.22" in what
    # a word fitted as one law is no kink
    assert _kinked([Slot(1, 1, "fit", law_d1)], nb, sets) is None


PIN = ROOT / "tests" / "data" / "families" / "pin.py"


def test_pin_decides_its_g71_split_on_the_chamfers_end(tmp_path, capsys):
    # the HNC-21T planner splits the G71 where the chamfer's end, d - 2 chamfer, is at most
    # 21.496 (the spindle limit); the macro decides there, not on d (equal to it at chamfer
    # 1 only): rows where the two disagree (d - 2 chamfer 21.519 at d 23.473, 21.494 at
    # d 23.514) each follow their per-variant program
    rc, err, text = _rows(tmp_path, capsys, PIN, "d,chamfer\n23.473,0.977\n23.514,1.01\n"
                          "23.45,1.0\n23.55,1.0\n", "--check", "20")
    assert rc == 0, err
    # one decision, on the chamfer's end (the first segment's end diameter) at the written
    # 21.496, which takes the split (half the chamfer end's step at 0.001 mm above it)
    conds = re.findall(r"\(([A-Z0-9 ]+) ([<>]=?) ([0-9.]+)\?\)", text)
    assert [(c[0], float(c[2])) for c in conds] == [("SEGMENT 1 END X", 21.4965)], conds


GROOVED_PIN = ROOT / "tests" / "data" / "families" / "grooved_pin.py"


@pytest.mark.parametrize("family, rows, decision", [
    # the groove comes from length 52 on (the family's `length > 52`): a row of length 52
    # is a plain pin, 52.001 grooved
    (GROOVED_PIN, "length\n52\n51.999\n52.001\n", ("LENGTH", "<=", 52.0)),
    # the split at the written diameter 21.496 (the planner's `<=`): d - 2 chamfer = 21.496
    # exactly, and one step either side of it
    (PIN, "d,chamfer\n23.496,1\n23.495,1\n23.497,1\n23.498,1.001\n",
     ("SEGMENT 1 END X", "<", 21.4965)),
])
def test_a_set_at_the_threshold_takes_the_planners_side(family, rows, decision, tmp_path,
                                                        capsys):
    rc, err, text = _rows(tmp_path, capsys, family, rows, "--check", "2")
    assert rc == 0, err
    conds = {(c[0], c[1], float(c[2])) for c in
             re.findall(r"\(([A-Z0-9 ]+) ([<>]=?) ([0-9.]+)\?\)", text)}
    assert decision in conds, conds


TAPER_PIN = ROOT / "tests" / "data" / "families" / "taper_pin.py"


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "siemens802"])
def test_a_shallow_taper_roughs_to_the_per_variant_passes(dialect, tmp_path, capsys):
    # the roughing cycle's passes end on the 7 deg taper: its contour's words, exact in the
    # macro, moved the passes' ends 0.001 mm along Z from the per-variant program's, which
    # writes them to 0.001; the macro writes the cycle's contour rounded as the program
    # does, and the row that showed it follows its per-variant program
    rc, err, _ = _rows(tmp_path, capsys, TAPER_PIN, "length,d1,d2,lt,chamfer\n"
                       "58.253,21.364,28.624,29.724,1.033\n", "--dialect", dialect,
                       "--check", "12")
    assert rc == 0, err
    assert "checked 13 parameter set(s): pass" in err


SLEEVE = ROOT / "tests" / "data" / "families" / "sleeve.py"


def test_a_g97_cycle_runs_at_its_tools_own_speed_floored(tmp_path, capsys):
    # the boring cycle's G97 S is floor(150 m/min at the diameter it starts from), 1829 at
    # bore 20.465 + 2 x 0.82 + 4 = 26.105 mm; a speed fitted to the sampled variants' whole
    # rpm (149.955 rounded to nearest) gave 1828 there
    rc, err, text = _rows(tmp_path, capsys, SLEEVE, "d,bore,lb,df,lf,c,ci\n"
                          "34.997,20.465,21.322,50.357,7.624,0.952,0.82\n", "--check", "12")
    assert rc == 0, err
    m = re.search(r"G97 S\[INT\[([0-9.]+)/ABS\[.*\]\]\] M03", text)
    assert m and float(m.group(1)) == pytest.approx(150000 / 3.141592653589793, abs=1e-5)


def test_a_sketch_that_loses_an_expression_is_told_where(tmp_path, capsys):
    # math imported inside sketch() is the real one: the journal's diameter, a root of the
    # parameters, becomes a plain number there and no law fits its words; the refusal names
    # the sketch's line
    from hnc_cam.cli import main
    src = PIN.read_text().replace(
        "    s = Outline((0.0, 0.0))\n",
        "    import math\n    k = math.sqrt(d * d - 40)\n    s = Outline((0.0, 0.0))\n", 1)
    src = src.replace("s.line_to(d / 2, 0.0, chamfer=chamfer)",
                      "s.line_to(k / 2, 0.0, chamfer=chamfer)")
    fam = tmp_path / "pin_local_math.py"
    fam.write_text(src)
    line = next(i for i, ln in enumerate(src.splitlines(), 1) if "math.sqrt" in ln)
    out = tmp_path / "m"
    rc = main(["family", str(fam), "--macro", "--check", "2", "-o", str(out) + "/"])
    err = capsys.readouterr().err
    assert rc == 2 and not out.exists()
    assert f"pin_local_math.py:{line}" in err, err


ROLLER = ROOT / "tests" / "data" / "families" / "roller.py"


def test_a_domed_grooved_roller_is_proven_in_the_802_form(tmp_path, capsys):
    # a dome (an arc about the axis whose end is a root of the parameters), a square groove
    # and a fillet, over d 28-34 and the groove at 18-24: every piece's program through the
    # 802 reader, compared with its per-variant program and verified on 10 sets
    from hnc_cam.cli import main
    out = tmp_path / "m"
    rc = main(["family", str(ROLLER), "--macro", "--dialect", "siemens802", "--check", "10",
               "-o", str(out) + "/"])
    err = capsys.readouterr().err
    assert rc == 0, err
    assert "checked 10 parameter set(s): pass" in err
    # each piece's program with its contour subprogram, the dome an arc in it
    names = sorted(p.name for p in out.iterdir())
    mpf = [n for n in names if n.endswith(".MPF")]
    assert mpf and all(n[:-4] + "_C1.SPF" in names for n in mpf), names
    for n in mpf:
        assert re.search(r"^N\d+ G[23] ", (out / (n[:-4] + "_C1.SPF")).read_text(), re.M)
