"""hnc_cam.compensate: tip and centre paths against closed-form values (issue 4)."""
from __future__ import annotations

import math

import pytest

from hnc_cam.compensate import compensate
from hnc_cam.errors import ProfileError, ToolError
from hnc_cam.geometry import Arc, Line, TurnedProfile, chain_is_connected, dist
from hnc_cam.geometry.intersect import horizontal_hits
from hnc_cam.geometry.tip import tip_vector


def chain_of(*pts):
    return [Line(a, b) for a, b in zip(pts, pts[1:])]


def dense(segs, n=200):
    for g in segs:
        for k in range(n + 1):
            yield g.point_at(k / n)


def at_exactly_r(path, contour, r, shift=(0.0, 0.0)):
    for p in dense(path):
        c = (p[0] - shift[0], p[1] - shift[1])
        assert min(g.distance_to(c) for g in contour) == pytest.approx(r, abs=1e-9)


def outside_taper(deg):
    """dia 20 -> taper rising toward -Z at deg to the Z axis -> dia 30 (tool above, G42)."""
    th = math.radians(deg)
    z0 = -5.0
    z1 = z0 - 5.0 / math.tan(th)
    return chain_of((10, 0), (10, z0), (15, z1), (15, z1 - 10)), (z0, z1)


def bore_taper(deg):
    """bore dia 30 -> taper closing toward -Z at deg -> dia 20 (tool below, G41)."""
    th = math.radians(deg)
    z0 = -5.0
    z1 = z0 - 5.0 / math.tan(th)
    return chain_of((15, 0), (15, z0), (10, z1), (10, z1 - 10)), (z0, z1)


def z_at(path, x, zlo, zhi):
    hits = [z for _, z in horizontal_hits(path, x) if zlo <= z <= zhi]
    assert hits, (x, zlo, zhi)
    return hits[0]


# closed forms of the imaginary-tip path on a taper at theta to the Z axis, measured along Z
# at the same X (digest §7: "r(1 - tan(theta/2))-type errors")
TAPER_DZ = {
    3: lambda r, th: -r * (1 - math.tan(th / 2)),  # outside tool, tip (-X,-Z)
    8: lambda r, th: r * math.tan(th / 2),          # tip (-X) only
    2: lambda r, th: -r * (1 - math.tan(th / 2)),  # boring bar on a bore taper, tip (+X,-Z)
}


@pytest.mark.parametrize("r", [0.4, 0.8])
@pytest.mark.parametrize("deg", [45.0, 30.0])
@pytest.mark.parametrize("code", [3, 8, 2])
def test_taper_tip_path_closed_form(code, deg, r):
    th = math.radians(deg)
    if code == 2:
        contour, (z0, z1) = bore_taper(deg)
        res = compensate(contour, r, code, "left")
        x_mid = 12.5
    else:
        contour, (z0, z1) = outside_taper(deg)
        res = compensate(contour, r, code, "right")
        x_mid = 12.5
    assert res.output == "tip" and res.tip_vector == tip_vector(code, r)
    assert chain_is_connected(res.segments, 1e-9)
    z_part = (z0 + z1) / 2
    z_tip = z_at(res.segments, x_mid, z1 - 3, z0 + 3)
    assert z_tip - z_part == pytest.approx(TAPER_DZ[code](r, th), abs=1e-9)
    # and the X shift at the same Z: r(tan(45-theta/2) - 1) for codes 3 and 2
    taper_tip = [g for g, o in zip(res.segments, res.origins) if o.kind == "seg" and o.before == 1][0]
    if code in (3, 2):
        sgn = 1 if code == 3 else -1
        t = (z_part - taper_tip.start[1]) / (taper_tip.end[1] - taper_tip.start[1])
        x_tip = taper_tip.point_at(t)[0]
        assert (x_tip - x_mid) * sgn == pytest.approx(-r * (1 - math.tan(math.pi / 4 - th / 2)), abs=1e-9)
    # the nose-centre form is everywhere at exactly r from the part
    at_exactly_r(res.centre, contour, r)
    at_exactly_r(res.segments, contour, r, shift=res.tip_vector)
    assert not res.unreachable


@pytest.mark.parametrize("r", [0.4, 0.8])
@pytest.mark.parametrize("code", [2, 3, 8])
@pytest.mark.parametrize("convex", [True, False])
def test_arc_tip_path_closed_form(convex, code, r):
    R = 10.0
    if convex:  # dome: G03 R10 from the axis at Z0 down to dia 20 at Z-10 (tool outside, right)
        arc = Arc((0, 0), (R, -R), (0, -R), False)
        contour = [arc, Line((R, -R), (R, -20))]
        R_off = R + r
    else:  # hollow: G02 R10 from dia 40 down to dia 20 and back up (tool outside, right)
        arc = Arc((20, 0), (20, -20), (20, -10), True)
        contour = [Line((20, 5), (20, 0)), arc, Line((20, -20), (20, -25))]
        R_off = R - r
    res = compensate(contour, r, code, "right")
    tv = tip_vector(code, r)
    tip_arcs = [g for g, o in zip(res.segments, res.origins)
                if o.kind == "seg" and contour[o.before] is arc]
    assert len(tip_arcs) == 1
    ta = tip_arcs[0]
    assert ta.kind == "arc" and ta.cw == arc.cw
    assert ta.radius == pytest.approx(R_off, abs=1e-9)
    assert dist(ta.center, (arc.center[0] + tv[0], arc.center[1] + tv[1])) < 1e-12
    # nose-centre ends on the normals at the arc's ends
    ca = [g for g, o in zip(res.centre, res.origins) if o.kind == "seg" and contour[o.before] is arc][0]
    for p, q in ((ca.start, arc.start), (ca.end, arc.end)):
        assert dist(p, q) == pytest.approx(r, abs=1e-12)
        assert dist(p, arc.center) == pytest.approx(R_off, abs=1e-12)
    at_exactly_r(res.centre, contour, r)
    assert not res.unreachable


def test_r10_arc_r08_tip3_3329():
    """3329's finishing contour (N8-N19) with r=0.8, tip 3: the R10 hollow becomes an R9.2 arc
    about the centre moved by (-0.8, -0.8); the R4 fillet an R3.2 arc."""
    r = 0.8
    a_r4 = Arc.from_radius((10, -8), (14, -12), 4, True)
    a_r10 = Arc.from_radius((13.33, -37.5), (15.33, -51.5), 10, True)
    contour = [Line((5, 3), (10, -2)), Line((10, -2), (10, -8)), a_r4, Line((14, -12), (14, -17)),
               Line((14, -17), (9, -22)), Line((9, -22), (9, -30)), Line((9, -30), (13.33, -32.5)),
               Line((13.33, -32.5), (13.33, -37.5)), a_r10, Line((15.33, -51.5), (15.33, -61.5)),
               Line((15.33, -61.5), (20, -61.5))]
    res = compensate(contour, r, 3, 42)
    by = {o.before: g for g, o in zip(res.segments, res.origins) if o.kind == "seg"}
    assert by[8].radius == pytest.approx(9.2) and dist(by[8].center, (a_r10.center[0] - r, a_r10.center[1] - r)) < 1e-12
    assert by[2].radius == pytest.approx(3.2)
    # the dia 18 groove bottom: tip path at X = 9 + 0.8 - 0.8 = 9 (radius) exactly
    assert by[5].start[0] == pytest.approx(9.0) and by[5].end[0] == pytest.approx(9.0)
    # concave ends of the groove bottom trimmed at the closed-form points
    foot_left = -22 - r * math.tan(math.radians(45) / 2)  # 45 deg taper into the bottom
    # N15 U8.66 W-2.5 rises at 60 deg to the Z axis (30 deg to the face): deviation 60 deg
    foot_right = -30 + r * math.tan(math.atan2(4.33, 2.5) / 2)
    assert by[5].start[1] == pytest.approx(foot_left - r, abs=1e-9)
    assert by[5].end[1] == pytest.approx(foot_right - r, abs=1e-9)
    assert res.ok
    at_exactly_r(res.centre, contour, r)
    cent = compensate(contour, r, 3, 42, output="centre")
    assert cent.segments == res.centre


def test_turned_profile_sides():
    outside = chain_of((0, 0), (9, 0), (10, -1), (10, -30), (20, -30))
    bore = chain_of((6, 0), (5, -1), (5, -30))
    prof = TurnedProfile(outside=outside, bore=bore)
    od = compensate(prof, 0.4, 3)
    assert od.side == "right"
    # face cut with the nose centre at Z+r; the code 3 tip is at centre + (-r, -r)
    assert od.centre[0].start == pytest.approx((0.0, 0.4))
    assert od.segments[0].start == pytest.approx((-0.4, 0.0))
    assert any(o.kind == "seg" and o.before == 3 and g.start[0] == pytest.approx(10.4)
               for g, o in zip(od.centre, od.origins))
    idc = compensate(prof, 0.4, 2, which="bore")
    assert idc.side == "left"
    bore_line = [g for g, o in zip(idc.centre, idc.origins) if o.kind == "seg" and o.before == 1][0]
    assert bore_line.start[0] == pytest.approx(4.6) and bore_line.end == pytest.approx((4.6, -30))
    with pytest.raises(ProfileError):
        compensate(TurnedProfile(outside=outside), 0.4, 2, which="bore")


def test_unreachable_features_are_reported_not_gouged():
    r = 0.8
    # an R0.5 inside fillet and a 1 mm groove: both too small for r = 0.8
    contour = [Line((10, 0), (10, -9.5)), Arc((10, -9.5), (10.5, -10), (10.5, -9.5), True),
               Line((10.5, -10), (15, -10)), Line((15, -10), (15, -20)), Line((15, -20), (13, -20)),
               Line((13, -20), (13, -21)), Line((13, -21), (15, -21)), Line((15, -21), (15, -30))]
    res = compensate(contour, r, 3, "right")
    kinds = sorted(d.kind for d in res.unreachable)
    assert kinds == ["groove", "radius"]
    rad = [d for d in res.unreachable if d.kind == "radius"][0]
    assert rad.segments == (0, 1, 2)  # the fillet and the trimmed ends of its neighbours
    assert rad.departure == pytest.approx(0.3 * math.sqrt(2) + 0.5 - r, abs=1e-6)
    gr = [d for d in res.unreachable if d.kind == "groove"][0]
    assert gr.segments == (4, 5, 6)
    h = math.sqrt(r * r - 0.25)
    assert gr.departure == pytest.approx(math.hypot(15 + h - 13, 0.5) - r, abs=1e-6)
    assert not res.ok
    at_exactly_r(res.centre, contour, r)
    js = res.to_json()
    assert len(js["unreachable"]) == 2 and js["unreachable"][0]["start"][0] > 0


def test_errors():
    contour = chain_of((10, 0), (10, -5))
    with pytest.raises(ToolError):
        compensate(contour, -0.1, 3, "right")
    with pytest.raises(ToolError):
        compensate(contour, 0.4, 12, "right")
    with pytest.raises(ValueError):
        compensate(contour, 0.4, 3, None)
    with pytest.raises(ValueError):
        compensate(contour, 0.4, 3, "right", output="edge")
    with pytest.raises(ProfileError):
        compensate([Line((0, 0), (1, 0)), Line((2, 0), (3, 0))], 0.4, 3, "right")


@pytest.mark.parametrize("code", [0, 9])
def test_codes_0_and_9_program_the_centre(code):
    contour = chain_of((10, 0), (10, -5))
    res = compensate(contour, 0.4, code, "right")
    assert res.segments == res.centre


def test_insert_edges_by_tip_code():
    from hnc_cam.geometry.offset import insert_edges
    assert insert_edges(3, 95, 80) == (85.0, 5.0)
    assert insert_edges(2, 95, 55) == (-85.0, -30.0)   # boring bar: mirrored in X
    assert insert_edges(4, 93, 35) == (93.0, 128.0)    # left-hand OD tool feeding +Z
    assert insert_edges(1, 90, 80) == (-90.0, -170.0)
    with pytest.raises(ValueError):
        insert_edges(8, 95, 80)
    with pytest.raises(ToolError):
        compensate(chain_of((10, 0), (10, -5)), 0.4, 8, "right", insert=(95, 80))


def _shadow_case():
    # dia 20, 45 deg plunge down to dia 14, dia 14 on toward the chuck
    return chain_of((10, 0), (10, -5), (7, -8), (7, -50))


def test_insert_flank_on_a_plunge_closed_form():
    r = 0.4
    contour = _shadow_case()
    # 35 deg insert in a 93 deg holder follows a 45 deg plunge (trailing edge at 52 deg)
    ok = compensate(contour, r, 3, "right", insert=(93, 35))
    assert not [d for d in ok.departures if d.kind == "insert"]
    # an 80 deg insert in a 95 deg holder drags its trailing edge (5 deg) over the plunge
    bad = compensate(contour, r, 3, "right", insert=(95, 80))
    (d,) = [d for d in bad.departures if d.kind == "insert"]
    assert d.unreachable and not bad.ok
    a = math.radians(95)  # nose centre where the path's normal leaves the allowed range
    A = (10 + r * math.sin(a), -5 + r * math.cos(a))
    u = (-math.sin(math.radians(5)), -math.cos(math.radians(5)))  # along the trailing edge
    w = (7 - A[0], -8 - A[1])
    expected = abs(w[0] * u[1] - w[1] * u[0]) - r  # the plunge's foot, seen from the shadow
    assert d.departure == pytest.approx(expected, abs=1e-6)
    assert dist(d.at, (7, -8)) < 1e-6
    # the shadow meets dia 14 + 2r where the trailing edge comes down to it
    assert d.end[0] == pytest.approx(7.0) and d.end[1] == pytest.approx(A[1] + (7.4 - A[0]) / u[0] * u[1], abs=1e-6)


def test_insert_flank_on_a_face_leaning_over_the_tool():
    r = 0.4
    contour = chain_of((10, 0), (10, -5), (14, -4.3), (14, -20))  # shoulder leaning 10 deg back
    assert not [d for d in compensate(contour, r, 3, "right", insert=(107.5, 35)).departures
                if d.kind == "insert"]
    res = compensate(contour, r, 3, "right", insert=(95, 80))
    (d,) = [d for d in res.departures if d.kind == "insert"]
    # the main edge (85 deg) comes down from the top corner of the shoulder to dia 20 + 2r
    b = math.radians(-5)
    B = (14 + r * math.sin(b), -4.3 + r * math.cos(b))
    v = (-math.sin(math.radians(85)), -math.cos(math.radians(85)))
    zc = B[1] + (10.4 - B[0]) / v[0] * v[1]
    env = [Line((10.4, 0), (10.4, zc)), Line((10.4, zc), B)]
    assert d.departure == pytest.approx(min(g.distance_to((10, -5)) for g in env) - r, abs=1e-6)
    assert d.start[1] == pytest.approx(zc, abs=1e-6)
