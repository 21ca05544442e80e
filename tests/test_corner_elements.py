"""CHF= / RND= between a line and an arc, an arc and a line, two arcs
(hnc_cam.geometry.corner.element_corner and the SINUMERIK 802 executor): tangent points,
the trimmed arcs' new ends and centres against values worked out by hand, in G90 and G91,
G2, G3 and G5; tangent elements; corners that do not fit."""
from __future__ import annotations

import math

import pytest

from hnc_cam import dialect, nc
from hnc_cam.errors import NCError
from hnc_cam.geometry.corner import CornerError, CornerFitError, corner, element_corner
from hnc_cam.geometry.primitives import Arc, Line, dist

S802 = dialect.get("siemens802")
R140 = math.sqrt(140.0)  # (R + r)^2 - r^2 with R = 10, r = 2


def run(text):
    return nc.run(text, dialect=S802, start=(50.0, 50.0))


def feeds(tp):
    return [m for m in tp.moves if m.kind != "rapid"]


def approx(p, q, tol=1e-6):
    return p == pytest.approx(q, abs=tol)


# -- the construction ---------------------------------------------------------------------

def test_round_line_then_concave_g2_arc_by_hand():
    # line at radius 20 toward -Z to (20, -10); G2 quarter about (20, -20) to (10, -20).
    # The path turns left; the round's centre lies 2 to the left of the line (x = 18) and
    # 10 + 2 from the arc's centre (the arc's centre is on its right): z = -20 + sqrt(140).
    k = element_corner(Line((20.0, 0.0), (20.0, -10.0)),
                       Arc((20.0, -10.0), (10.0, -20.0), (20.0, -20.0), True), "R", 2.0)
    assert approx(k.segment.center, (18.0, -20.0 + R140))
    assert approx(k.start, (20.0, -20.0 + R140))
    assert approx(k.end, (20.0 - 2.0 * 10 / 12, -20.0 + R140 * 10 / 12))
    assert k.segment.cw is False  # a left turn: G3
    # the arc keeps its centre and end; only its start moved
    assert k.second.center == (20.0, -20.0) and k.second.end == (10.0, -20.0) and k.second.cw
    assert approx(k.second.start, k.end) and k.first.end == k.start


def test_round_arc_then_arc_by_hand():
    # G2 about (20, -20) ending at (10, -20), then G2 about (10, -30) to (0, -30): the round's
    # centre is 12 from both centres, on the bisector of the centres, near the corner
    a1 = Arc((20.0, -10.0), (10.0, -20.0), (20.0, -20.0), True)
    a2 = Arc((10.0, -20.0), (0.0, -30.0), (10.0, -30.0), True)
    k = element_corner(a1, a2, "R", 2.0)
    h = math.sqrt(144.0 - 50.0) / math.sqrt(2.0)
    c = (15.0 - h, -25.0 + h)
    assert approx(k.segment.center, c)
    assert approx(k.first.end, (20.0 + (c[0] - 20.0) * 10 / 12, -20.0 + (c[1] + 20.0) * 10 / 12))
    assert approx(k.second.start, (10.0 + (c[0] - 10.0) * 10 / 12, -30.0 + (c[1] + 30.0) * 10 / 12))
    assert k.first.center == (20.0, -20.0) and k.second.center == (10.0, -30.0)


def test_chamfer_next_to_an_arc_has_equal_chord_legs_and_its_own_length():
    line = Line((20.0, 0.0), (20.0, -10.0))
    arc = Arc((20.0, -10.0), (10.0, -20.0), (20.0, -20.0), True)
    k = element_corner(line, arc, "C", 3.0)
    g = (20.0, -10.0)
    b, e = k.start, k.end
    assert dist(b, e) == pytest.approx(3.0, abs=1e-9)
    assert dist(g, b) == pytest.approx(dist(g, e), abs=1e-9)
    assert b[0] == pytest.approx(20.0) and -10.0 < b[1] < 0.0  # on the line
    assert dist(e, (20.0, -20.0)) == pytest.approx(10.0, abs=1e-9)  # on the arc
    # the leg d by hand: B = (20, -10 + d), E at the angle phi = 2 asin(d / 20) down the arc
    d = dist(g, b)
    phi = 2.0 * math.asin(d / 20.0)
    assert approx(e, (20.0 - 10.0 * math.sin(phi), -20.0 + 10.0 * math.cos(phi)))


def test_the_line_line_case_agrees_with_the_two_line_corner():
    a, g, e = (20.0, 0.0), (20.0, -10.0), (5.0, -25.0)
    k = element_corner(Line(a, g), Line(g, e), "R", 3.0)
    c = corner(a, g, e, "R", 3.0)
    assert approx(k.start, c.start, 1e-12) and approx(k.end, c.end, 1e-12)
    assert approx(k.segment.center, c.center, 1e-12)
    ch = element_corner(Line(a, g), Line(g, e), "C", 3.0)
    turn = math.radians(45.0)
    assert dist(g, ch.start) == pytest.approx(3.0 / (2.0 * math.cos(turn / 2.0)), abs=1e-12)


def test_tangent_and_reversing_elements_and_rounds_that_do_not_fit():
    line = Line((20.0, 0.0), (20.0, -10.0))
    tangent = Arc((20.0, -10.0), (10.0, -20.0), (10.0, -10.0), False)  # starts along -Z
    with pytest.raises(CornerError) as e:
        element_corner(line, tangent, "R", 1.0)
    assert e.value.reason == "straight"
    with pytest.raises(CornerError) as e:
        element_corner(line, Arc((20.0, -10.0), (10.0, -20.0), (10.0, -10.0), True), "R", 1.0)
    assert e.value.reason == "reverse"
    arc = Arc((20.0, -10.0), (10.0, -20.0), (20.0, -20.0), True)
    with pytest.raises(CornerFitError) as e:
        element_corner(line, arc, "R", 30.0)
    assert e.value.element == "first"
    with pytest.raises(CornerFitError) as e:
        element_corner(Line((20.0, 0.0), (20.0, -10.0)), Line((20.0, -10.0), (19.0, -10.0)), "R", 5.0)
    assert e.value.element == "second"
    # a round on the inside of a convex arc larger than the arc itself
    # a round on the inside (the centre's side) of a G3 arc of radius 5 that turns left
    inner = Arc((20.0, -10.0), (15.0, -5.0), (20.0, -5.0), False)
    k = element_corner(line, inner, "R", 2.0)  # centre 2 left of the line, 5 - 2 from (20, -5)
    assert approx(k.segment.center, (18.0, -5.0 - math.sqrt(5.0)))
    assert approx(k.end, (20.0 - 2.0 * 5 / 3, -5.0 - math.sqrt(5.0) * 5 / 3))
    with pytest.raises(CornerFitError):  # no circle of 4 touches both inside
        element_corner(line, inner, "R", 4.0)
    with pytest.raises(CornerFitError) as e:
        element_corner(line, inner, "R", 6.0)
    assert e.value.element == "second"


# -- the 802 executor ------------------------------------------------------------------------

def _line_g2_g1(tp):
    m = feeds(tp)
    assert [x.kind for x in m] == ["line", "arc", "arc", "arc", "line"]
    return m


@pytest.mark.parametrize("text", [
    "G0 X40 Z0\nG1 Z-10 RND=2 F100\nG2 X20 Z-20 CR=10 RND=2\nG1 X0\nM30\n",
    "G0 X40 Z0\nG1 Z-10 RND=2 F100\nG2 X20 Z-20 I0 K-10 RND=2\nG1 X0\nM30\n",
    "G0 X40 Z0\nG91 G1 Z-10 RND=2 F100\nG2 X-10 Z-10 I0 K-10 RND=2\nG1 X-10\nM30\n",
    "G0 X40 Z0\nG1 Z-10 RND=2 F100\nG2 AR=90 I0 K-10 RND=2\nG1 X0\nM30\n",
], ids=["G90-CR", "G90-IK", "G91-IK", "AR-IK"])
def test_802_line_g2_line_with_rounds_at_both_ends(text):
    tp = run(text)
    line, r1, arc, r2, last = _line_g2_g1(tp)
    assert approx(line.end, (20.0, -20.0 + R140))
    assert approx(r1.center, (18.0, -20.0 + R140)) and r1.cw is False
    assert approx(arc.start, (20.0 - 20.0 / 12, -20.0 + R140 * 10 / 12))
    assert approx(arc.center, (20.0, -20.0)) and arc.cw is True
    # the round after the arc: centre at z = -18 (2 left of the face line), x = 20 - sqrt(140)
    assert approx(arc.end, (20.0 - R140 * 10 / 12, -20.0 + 20.0 / 12))
    assert approx(r2.center, (20.0 - R140, -18.0)) and r2.cw is False
    assert approx(last.start, (20.0 - R140, -20.0)) and approx(last.end, (0.0, -20.0))
    assert not tp.warnings


@pytest.mark.parametrize("text", [
    "G0 X20 Z0\nG1 Z-10 RND=2 F100\nG3 X40 Z-20 CR=10\nM30\n",
    "G0 X20 Z0\nG91 G1 Z-10 RND=2 F100\nG3 X10 Z-10 CR=10\nM30\n",
    "G0 X20 Z0\nG1 Z-10 RND=2 F100\nG5 X40 Z-20 IX=34.142136 KZ=-12.928932\nM30\n",
], ids=["G90-G3", "G91-G3", "G5"])
def test_802_line_then_convex_g3_arc(text):
    # G3 about (10, -20) from (10, -10) up to (20, -20): the path turns right, the round lies
    # on the right (x = 12), 12 from the arc's centre: z = -20 + sqrt(140)
    line, rnd, arc = feeds(run(text))
    assert approx(line.end, (10.0, -20.0 + R140))
    assert approx(rnd.center, (12.0, -20.0 + R140), 2e-6) and rnd.cw is True
    assert approx(arc.start, (10.0 + 20.0 / 12, -20.0 + R140 * 10 / 12), 2e-6)
    assert approx(arc.center, (10.0, -20.0), 2e-6) and arc.end == pytest.approx((20.0, -20.0))
    assert arc.cw is False


def test_802_chamfer_after_an_arc_and_before_one():
    tp = run("G0 X40 Z0\nG1 Z-10 CHF=3 F100\nG2 X20 Z-20 CR=10 CHF=1\nG1 X0\nM30\n")
    line, ch1, arc, ch2, last = feeds(tp)
    assert ch1.kind == ch2.kind == "line"
    assert dist(ch1.start, ch1.end) == pytest.approx(3.0, abs=1e-9)
    assert dist(ch2.start, ch2.end) == pytest.approx(1.0, abs=1e-9)
    g = (10.0, -20.0)  # the arc's programmed end: equal chord legs from it
    assert dist(g, ch2.start) == pytest.approx(dist(g, ch2.end), abs=1e-9)
    assert ch2.end[1] == pytest.approx(-20.0) and last.start == ch2.end
    assert dist(arc.end, (20.0, -20.0)) == pytest.approx(10.0, abs=1e-9)


def test_802_tangent_elements_cut_nothing_and_warn():
    tp = run("G0 X40 Z0\nG1 Z-10 RND=2 F100\nG2 X30 Z-15 I0 K-5 RND=1\nG1 Z-30\nM30\n")
    m = feeds(tp)
    # RND=2 between the line and the G2 (turning) is cut; RND=1 between the G2 ending
    # along -Z and the line along -Z is tangent: nothing cut, a warning on its line
    assert [x.kind for x in m] == ["line", "arc", "arc", "line"]
    assert m[2].end == pytest.approx((15.0, -15.0)) and m[3].start == pytest.approx((15.0, -15.0))
    assert [w.line for w in tp.warnings] == [3]
    tp = run("G0 X20 Z0\nG1 Z-10 RND=2 F100\nG1 Z-20\nM30\n")
    # two lines in one direction: both run whole
    assert [(x.start, x.end) for x in feeds(tp)] == [((10.0, 0.0), (10.0, -10.0)),
                                                    ((10.0, -10.0), (10.0, -20.0))]
    assert len(tp.warnings) == 1


def test_802_arc_round_that_does_not_fit_is_an_alarm_with_its_place(tmp_path):
    p = tmp_path / "R.MPF"
    p.write_text("G0 X40 Z0\nG1 Z-10 F100\nG2 X20 Z-20 CR=10 RND=16\nG1 X0\nM30\n")
    with pytest.raises(NCError) as e:
        nc.run_file(str(p), dialect=S802)
    assert (e.value.line, e.value.col) == (3, 19)
    assert "RND=16 does not fit the next element (line 4)" in e.value.one_line() and e.value.one_line().startswith(str(p))
