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


# ---------------------------------------------------------------- written contours are clean

def _hausdorff(a, b, chord=1e-5):
    from hnc_cam.geometry import sample_chain
    pa, pb = sample_chain(a, chord), sample_chain(b, chord)
    d1 = max(min(s.distance_to(p) for s in b) for p in pa)
    d2 = max(min(s.distance_to(p) for s in a) for p in pb)
    return max(d1, d2)


def test_merge_and_absorb_fragments_within_half_the_resolution():
    """Collinear pieces, co-circular pieces and moves under 0.001 mm become one segment each;
    the written path stays within 0.0005 mm of the exact one (the stated bound)."""
    from hnc_cam.geometry.chain import absorb_short, merge_segments
    from hnc_cam.plan.contour import clean
    c = (5.0, -10.0)
    a = Arc((9.0, -10.0), (5.0, -14.0), c, False)
    assert abs(a.sweep) < 1.6
    mid = a.point_at(0.4)
    segs = [Line((0.0, 0.0), (3.0, 0.0)), Line((3.0, 0.0), (5.0, 0.0)),  # collinear
            Line((5.0, 0.0), (5.0006, -0.0004)),  # a 0.0007 mm corner fragment
            Line((5.0006, -0.0004), (9.0, -6.0)),
            Line((9.0, -6.0), (9.0, -10.0)),
            Arc((9.0, -10.0), mid, c, False), Arc(mid, (5.0, -14.0), c, False),  # co-circular
            Line((5.0, -14.0), (5.0, -14.0003)),  # a 0.0003 mm tail after an arc
            Line((5.0, -14.0003), (5.0, -20.0))]
    out = clean(segs)
    assert [s.kind for s in out] == ["line", "line", "line", "arc", "line"]
    assert out[0].start == (0.0, 0.0) and out[-1].end == (5.0, -20.0)
    assert all(s.length >= 0.001 for s in out)
    assert all(x.end == y.start for x, y in zip(out, out[1:]))
    assert _hausdorff(segs, out) < 0.0005
    # the merge's bound holds over all absorbed joints, not joint by joint: a slow bend of
    # many pieces, each within tol of its neighbours' line, is not merged into one line
    bend = [Line((0.0, -i * 1.0), (1e-6 * (i + 1) ** 2, -(i + 1) * 1.0)) for i in range(30)]
    bend = [Line(bend[i - 1].end if i else (0.0, 0.0), s.end) for i, s in enumerate(bend)]
    merged = merge_segments(bend, 1e-5)
    assert len(merged) > 1 and _hausdorff(bend, merged) <= 1e-5
    # a piece that runs backwards is never merged; a short piece between two arcs is kept
    assert len(merge_segments([Line((0, 0), (5, 0)), Line((5, 0), (4, 0))])) == 2
    a1 = Arc.from_radius((0.0, 0.0), (1.0, -1.0), 1.0, True)
    a2 = Arc.from_radius((1.0, -1.0004), (0.0, -2.0004), 1.0, True)
    k = [a1, Line((1.0, -1.0), (1.0, -1.0004)), a2]
    assert absorb_short(k, 0.001) == k


@pytest.mark.parametrize("shape,stock", [("shaft", "50x90+2"), ("undercut", "40x70"),
                                         ("wavy", "offset:2"), ("bushing", "42/16x45+2"),
                                         ("stud", "30x60+1"), ("flange", "104x30+2")])
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_written_contours_have_no_fragments(shape, stock, comp):
    """In every finishing contour: no two consecutive G01 blocks on one line, no two
    consecutive arcs on one circle, no move shorter than the 0.001 mm resolution."""
    import math

    from hnc_cam.plan import Options, make_plan
    from hnc_cam.tooling import Stock, load_machine, load_tools
    lib = load_tools(None)
    prof = globals()[shape]()
    p = make_plan(prof, Stock.parse(stock), lib, load_machine(None, tools=lib),
                  Options(comp=comp), name=shape)
    for op in p.operations:
        if not op.blocks:
            continue
        cur = None
        prev = None
        for b in op.blocks:
            x = b.x if b.x is not None else (cur[0] if cur else None)
            z = b.z if b.z is not None else (cur[1] if cur else None)
            end = (round(2 * x, 3), round(z, 3)) if x is not None and z is not None else None
            if cur is not None and end is not None and b.kind != "rapid":
                d = (end[0] - cur[0], end[1] - cur[1])
                assert math.hypot(d[0] / 2, d[1]) >= 0.0005, (op.name, b)
                if b.kind == "line" and prev is not None and prev[0] == "line":
                    pd = prev[1]
                    crs = abs(pd[0] * d[1] - pd[1] * d[0]) / (math.hypot(*pd) * math.hypot(*d))
                    assert crs > 1e-4 or pd[0] * d[0] + pd[1] * d[1] < 0, (op.name, b)
                if b.arc and prev is not None and prev[0] == b.kind:
                    assert not (b.r is not None and prev[2] == b.r), (op.name, b)
                prev = (b.kind, d, b.r)
            if end is not None:
                cur = end
