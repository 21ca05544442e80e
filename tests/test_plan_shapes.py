"""Synthetic turned profiles for the planner tests (no CAD kernel needed), and checks of the
profile analysis on them."""
from __future__ import annotations

import pytest

from hnc_cam.geometry import Arc, Line, Thread, TurnedProfile
from hnc_cam.plan import analysis as an


def chain(*pts_or_arcs):
    """Polyline through points; an item ("arc", end, radius, cw) makes an arc."""
    segs = []
    cur = pts_or_arcs[0]
    for it in pts_or_arcs[1:]:
        if isinstance(it, tuple) and it and it[0] == "arc":
            _, end, r, cw = it
            segs.append(Arc.from_radius(cur, end, r, cw))
            cur = end
        else:
            segs.append(Line(cur, it))
            cur = it
    return segs


def shaft() -> TurnedProfile:
    """Monotonic stepped shaft (3327-like): chamfer, R5 fillet, R7 round, taper."""
    return TurnedProfile(chain((0, 0), (4, 0), (5, -1), (5, -20), ("arc", (10, -25), 5, True),
                               (10, -35), ("arc", (17, -42), 7, False), (17, -52), (22, -62),
                               (22, -82), (0, -82)), name="shaft")


def undercut() -> TurnedProfile:
    """3329-like: a 45 deg down taper into a groove and a 30 deg way out (needs type II)."""
    return TurnedProfile(chain((0, 0), (8, 0), (10, -2), (10, -8), ("arc", (14, -12), 4, True),
                               (14, -17), (9, -22), (9, -30), (13.33, -32.5), (13.33, -37.5),
                               (15.33, -37.5), (15.33, -61.5), (0, -61.5)), name="undercut")


def grooved(width=4.0) -> TurnedProfile:
    """Shaft with a square groove."""
    return TurnedProfile(chain((0, 0), (9, 0), (10, -1), (10, -20), (8, -20), (8, -20 - width),
                               (10, -20 - width), (10, -40), (14, -40), (14, -60), (0, -60)),
                         name="grooved")


def flange() -> TurnedProfile:
    return TurnedProfile(chain((0, 0), (15, 0), (15, -10), (50, -10), (50, -25), (0, -25)),
                         name="flange")


def bushing() -> TurnedProfile:
    return TurnedProfile(chain((12, 0), (19, 0), (20, -1), (20, -40), (11, -40)),
                         bore=chain((12, 0), (11, -1), (11, -40)), name="bushing")


def stud(thread_len=22.0) -> TurnedProfile:
    return TurnedProfile(chain((0, 0), (9, 0), (10, -1), (10, -25), (8.9, -25), (8.9, -29),
                               (13, -29), (13, -45), (0, -45)),
                         threads=[Thread(0.0, -thread_len, 20.0, 1.5)], name="stud")


def wavy() -> TurnedProfile:
    return TurnedProfile(chain((0, 0), (15, 0), (15, -10), ("arc", (15, -30), 14, False),
                               (15, -50), (0, -50)), name="wavy")


def test_monotonic_shaft_has_no_pockets():
    hull, pockets = an.pockets(shaft().outside[:-1])
    assert pockets == []
    assert an.is_monotonic(shaft().outside[:-1])


def test_undercut_pocket_found_with_its_walls():
    _hull, pockets = an.pockets(undercut().outside[:-1])
    assert len(pockets) == 1
    p = pockets[0]
    assert p.level == pytest.approx(14)
    assert p.bottom == pytest.approx(9)
    assert p.max_descent == pytest.approx(45.0)
    assert p.exit == pytest.approx((14.0, -37.5))  # leaves on the wall up to the 15.33 step
    assert p.z_right == pytest.approx(-17)


def test_square_groove_recognised():
    _hull, pockets = an.pockets(grooved().outside[:-1])
    assert len(pockets) == 1
    assert an.square_groove(pockets[0]) == pytest.approx((-24.0, -20.0, 8.0))
