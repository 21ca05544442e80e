"""G71 (type I/II), G72, G73: the roughing engine (hnc_cam.geometry.roughing) and the cycle
module (hnc_cam.nc.cycles_rough).

The checks are geometric and independent of the engine's own bookkeeping:

* ``check_region``: a 2-D material simulation with shapely. The stock is the documented
  model (the rectangle between the start point A and the allowance-offset profile, closed by
  the line through the offset end point B″); a feed move removes what lies on the stock side
  of it (its "shadow" away from the part, the way a turning tool's edge clears the layer
  above its tip). Asserted: no move (rapid or feed) enters the part + allowance; no rapid
  crosses material that has not been removed yet; no pass is deeper than Δd; before the
  last pass no material thicker than Δd is left over the offset profile; the last pass is
  exactly the offset profile; the tool ends on A.
* end-to-end tests run the manual's programs through the interpreter (when it exists).
"""
from __future__ import annotations

import math
from typing import Optional

import pytest
from shapely.geometry import LineString, Polygon, box
from shapely.ops import unary_union

from hnc_cam.errors import NCError
from hnc_cam.geometry.primitives import Arc, Line, Point, Segment, same_point
from hnc_cam.geometry.roughing import (Frame, RoughingError, first_non_monotonic,
                                       is_monotonic, pattern_repeat, rough_turn)
from hnc_cam.nc import cycles_rough

from cyclefake import FakeCycleContext

CHORD = 1e-4


# --------------------------------------------------------------------------- builders

def path(start_dia: tuple[float, float], *blocks) -> tuple[list[Segment], list[str]]:
    """A profile from program-like blocks, X in diameter, absolute:
    ('G00', X, Z) | ('G01', X, Z) | ('G02'/'G03', X, Z, R)."""
    cur = (start_dia[0] / 2, start_dia[1])
    segs: list[Segment] = []
    mot: list[str] = []
    for b in blocks:
        g, x, z = b[0], b[1] / 2, b[2]
        end = (x, z)
        if g in ("G00", "G01"):
            segs.append(Line(cur, end))
            mot.append("rapid" if g == "G00" else "feed")
        else:
            segs.append(Arc.from_radius(cur, end, b[3], g == "G02"))
            mot.append("feed")
        cur = end
    return segs, mot


def P3327():
    return path((46, 3), ("G00", 0, 3), ("G01", 10, -2), ("G01", 10, -20),
                ("G02", 20, -25, 5), ("G01", 20, -35), ("G03", 34, -42, 7), ("G01", 34, -52),
                ("G01", 44, -62), ("G01", 44, -82))


def P3328():  # bore, from X6 Z5
    return path((6, 5), ("G00", 44, 5), ("G01", 44, -15), ("G01", 34, -25), ("G01", 34, -35),
                ("G03", 20, -42, 7), ("G01", 20, -52), ("G02", 10, -57, 5), ("G01", 10, -80),
                ("G01", 6, -82))


def P3329():  # type II with grooves, from X42 Z3
    return path((42, 3), ("G00", 10, 3), ("G01", 20, -2), ("G01", 20, -8), ("G02", 28, -12, 4),
                ("G01", 28, -17), ("G01", 18, -22), ("G01", 18, -30),
                ("G01", 26.66, -32.5), ("G01", 26.66, -37.5), ("G02", 30.66, -51.5, 10),
                ("G01", 30.66, -61.5), ("G01", 40, -61.5))


def P3331():  # G72 OD, from X80 Z1
    return path((80, 1), ("G00", 80, -56), ("G01", 54, -40), ("G01", 54, -30),
                ("G02", 46, -26, 4), ("G01", 30, -26), ("G01", 30, -15), ("G01", 14, -15),
                ("G03", 10, -13, 2), ("G01", 10, -2), ("G01", 4, 1))


def P3333():  # G72 ID, from X6 Z3
    return path((6, 3), ("G00", 6, -61), ("G01", 12, -58), ("G01", 12, -48),
                ("G03", 16, -46, 2), ("G01", 30, -46), ("G01", 30, -34), ("G01", 46, -34),
                ("G02", 54, -30, 4), ("G01", 54, -20), ("G01", 74, -10), ("G01", 74, 3))


def P3335():  # G73, from X60 Z5
    return path((60, 5), ("G00", 0, 3), ("G01", 10, -2), ("G01", 10, -20),
                ("G02", 20, -25, 5), ("G01", 20, -35), ("G03", 34, -42, 7), ("G01", 34, -52),
                ("G01", 44, -62), ("G01", 54, -62))


def P3346():  # type II, from X54 Z3
    return path((54, 3), ("G01", 10, 3), ("G01", 19.95, -2), ("G01", 19.95, -33),
                ("G01", 30, -33), ("G01", 30, -43), ("G03", 42, -49, 6), ("G01", 42, -53),
                ("G01", 36, -65), ("G01", 36, -73), ("G02", 40, -75, 2), ("G01", 44, -75),
                ("G01", 46, -76), ("G01", 46, -84), ("G02", 46, -113, 25),
                ("G03", 52, -122, 15), ("G01", 52, -133), ("G01", 54, -133))


def mirror_x(segs):
    """Mirror a profile in X about the line x = 0 (OD -> a 'bore' in the negative half)."""
    return [Frame(False, -1, 1).seg_fwd(s) for s in segs]


# --------------------------------------------------------------------------- the checker

def _pts(seg: Segment) -> list[Point]:
    return seg.sample(CHORD) if isinstance(seg, Arc) else [seg.start, seg.end]


def _to_c(fr: Frame, p: Point) -> tuple[float, float]:
    u, v = fr.fwd(p)
    return (v, u)  # shapely (x=v, y=u)


def check_region(plan, start: Point, offset: list[Segment], fr: Frame, depth: float,
                 L: float = 500.0, approach: Optional[Segment] = None) -> dict:
    """The geometric checks of the module docstring, in the canonical frame ``fr`` of the
    job (u up toward the stock, v back toward the start face). ``approach``: the
    allowance-shifted block ns when it is slanted; the side of it away from the work is air
    (not stock). Returns statistics."""
    oc = [fr.seg_fwd(s) for s in offset]
    pts = [oc[0].start]
    for s in oc:
        pts.extend(_pts(s)[1:])
    vB = pts[-1][1]
    uA, vA = fr.fwd(start)
    # (buffer(0) removes the spike when the profile ends with a face along the closure)
    part = Polygon([(v, u) for u, v in pts] + [(pts[-1][1], -L), (pts[0][1], -L)]).buffer(0)
    assert part.is_valid and part.geom_type == "Polygon"
    # the stock region: rectangle [vB, vA] x [-L, uA] minus the part
    stock = box(vB, -L, vA, uA).difference(part)
    solid = part  # what the passes must stay out of: the part, and the air beyond the approach
    if approach is not None:
        (uc, vc), (ua, va) = fr.fwd(approach.start), fr.fwd(approach.end)
        k = (vc - va) / (uc - ua)  # dv/du along the approach line
        air = Polygon([(va - 2 * k * L, ua - 2 * L), (vc + 2 * k * L, uc + 2 * L),
                       (vc + 2 * L, uc + 2 * L), (vc + 2 * L, ua - 2 * L)])
        stock = stock.difference(air)
        solid = part.union(air)
    part_in = part.buffer(-3 * CHORD)  # chords of concave arcs lie up to CHORD inside
    remaining = stock
    moves = plan.moves
    finish = [m for m in moves if m.role == "finish"]
    for m in moves:
        cs = [_to_c(fr, p) for p in _pts(m.seg)]
        ls = LineString(cs)
        assert not ls.intersects(part_in), f"{m} enters the part + allowance"
        if m.kind == "rapid":
            bad = ls.intersection(remaining.buffer(-3 * CHORD))
            assert bad.length < 1e-6, f"rapid {m} crosses uncut material ({bad.length:g} mm)"
            continue
        us = [c[1] for c in cs]
        if m.role == "cut":
            # nothing left more than Δd above the pass over its length
            col = box(min(c[0] for c in cs), us[0] + depth + 1e-5, max(c[0] for c in cs), L)
            left = col.intersection(remaining).area
            assert left < 1e-6, f"pass {m} deeper than Δd ({left:g} mm² above)"
        if m is finish[0]:
            # before the last pass no material is thicker than Δd over the offset profile
            thick = remaining.difference(_shift_up(solid, depth + 1e-5)).area
            assert thick < 1e-5, f"{thick:g} mm² thicker than Δd before the last pass"
        # a feed clears what lies on the stock side of it (its shadow up to u = +L)
        polys = [q for a, b in zip(cs, cs[1:])
                 if (q := Polygon([a, b, (b[0], L), (a[0], L)])).area > 0]
        if polys:
            remaining = remaining.difference(unary_union(polys).buffer(1e-9))
    assert remaining.area < 1e-4, f"{remaining.area:g} mm² of stock never cut"
    # the last pass is the offset profile
    assert len(finish) >= len(offset)
    for f, o in zip(finish[-len(offset):], offset):
        assert same_point(f.seg.start, o.start, 1e-6) and same_point(f.seg.end, o.end, 1e-6)
        assert type(f.seg) is type(o)
        if isinstance(o, Arc):
            assert same_point(f.seg.center, o.center, 1e-6) and f.seg.cw == o.cw
    assert same_point(moves[-1].seg.end, start, 1e-9)
    for a, b in zip(moves, moves[1:]):
        assert same_point(a.seg.end, b.seg.start, 1e-9)
    assert same_point(moves[0].seg.start, start, 1e-9)
    return {"cut_area": stock.area}


def _shift_up(poly, d):
    from shapely.affinity import translate
    return unary_union([translate(poly, 0, d * t / 8) for t in range(9)])


def offset_of(segs, dx, dz):
    return [s.translated(dx, dz) for s in segs[1:] if s.length > 1e-6]


def cuts(plan):
    return [m for m in plan.moves if m.role == "cut"]


# --------------------------------------------------------------------------- engine tests

def test_3327_type_i_od_passes_and_last_pass():
    segs, mot = P3327()
    A = (23.0, 3.0)
    plan = rough_turn(A, segs, mot, depth=1.5, retract=1.0, allowance=(0.2, 0.1))
    c = cuts(plan)
    # levels every 1.5 below A's X, down to the chamfer
    assert [round(m.seg.start[0], 9) for m in c] == [round(23 - 1.5 * k, 9) for k in range(1, 16)]
    # every pass starts on the face Z = A.z and ends on the offset profile
    off = offset_of(segs, 0.2, 0.1)
    for m in c:
        assert m.seg.start[1] == pytest.approx(3.0)
        assert any(s.distance_to(m.seg.end) < 1e-9 for s in off)
    # first pass: X21.5 meets the offset taper (17.2,-51.9)-(22.2,-61.9) at Z-60.5
    assert c[0].seg.end == pytest.approx((21.5, -60.5))
    # retract r in both axes after the first pass, back to the face, then down by 1.5
    i = plan.moves.index(c[0])
    assert plan.moves[i + 1].seg.end == pytest.approx((22.5, -59.5))
    assert plan.moves[i + 1].kind == "rapid"
    assert plan.moves[i + 2].seg.end == pytest.approx((22.5, 3.0))
    assert plan.moves[i + 3].seg.end == pytest.approx((20.0, 3.0))
    check_region(plan, A, off, Frame(False, 1, 1), 1.5)


def test_3328_type_i_bore():
    segs, mot = P3328()
    A = (3.0, 5.0)
    plan = rough_turn(A, segs, mot, depth=1.0, retract=1.0, allowance=(-0.2, 0.1))
    assert plan.warnings == []
    c = cuts(plan)
    assert c[0].seg.start == pytest.approx((4.0, 5.0))  # levels go outward in a bore
    assert all(m.seg.end[1] < m.seg.start[1] for m in c)
    check_region(plan, A, offset_of(segs, -0.2, 0.1), Frame(False, -1, 1), 1.0)


def test_3329_type_ii_grooves_in_turn():
    segs, mot = P3329()
    A = (21.0, 3.0)
    with pytest.raises(RoughingError, match="type I profile is not monotonic in X"):
        rough_turn(A, segs, mot, depth=1.0, retract=1.0, allowance=(0.15, 0.0))
    plan = rough_turn(A, segs, mot, depth=1.0, retract=1.0, allowance=(0.15, 0.0),
                      pockets=True)
    check_region(plan, A, offset_of(segs, 0.15, 0.0), Frame(False, 1, 1), 1.0)
    c = cuts(plan)
    # the pocket order: the region open to the face first, down to its bottom, then the
    # groove at Z-17..-32.5, then the R10 groove
    face_cuts = [m for m in c if m.seg.start[1] == pytest.approx(3.0)]
    first_pocket = next(i for i, m in enumerate(c) if m.seg.start[1] < 2.9)
    assert all(m.seg.start[1] == pytest.approx(3.0) for m in c[:first_pocket])
    assert len(face_cuts) == first_pocket
    pockets = c[first_pocket:]
    zs = [m.seg.start[1] for m in pockets]
    # grooves entered by a feed plunge, never by a rapid
    for m in pockets:
        i = plan.moves.index(m)
        assert plan.moves[i - 1].role == "plunge" and plan.moves[i - 1].kind == "feed"
    # the 18-dia groove (Z -17..-32.5) is finished before the R10 groove (Z -37.5..-51.5)
    in_r10 = [i for i, z in enumerate(zs) if z < -37]
    in_18 = [i for i, z in enumerate(zs) if -33 < z < -17 and pockets[i].seg.end[1] > -33]
    assert in_18 and in_r10 and max(in_18) < min(in_r10)
    # the bottom of the R10 groove is reached: a pass below radius 12.5 exists there
    assert min(m.seg.start[0] for m in pockets if m.seg.start[1] < -37) < 12.5


def test_3346_type_ii():
    segs, mot = P3346()
    A = (27.0, 3.0)
    plan = rough_turn(A, segs, mot, depth=1.0, retract=1.0, allowance=(0.15, 0.0),
                      pockets=True)
    check_region(plan, A, offset_of(segs, 0.15, 0.0), Frame(False, 1, 1), 1.0)


def test_3331_g72_od_face():
    segs, mot = P3331()
    A = (40.0, 1.0)
    plan = rough_turn(A, segs, mot, depth=1.2, retract=1.0, allowance=(0.1, 0.5), face=True)
    c = cuts(plan)
    # passes parallel to X, from the OD (X = A.x) toward the axis, stepping -1.2 in Z
    assert [m.seg.start for m in c[:3]] == [pytest.approx((40.0, 1 - 1.2 * k)) for k in (1, 2, 3)]
    assert all(m.seg.end[0] < m.seg.start[0] for m in c)
    # first pass Z-0.2 meets the offset chamfer (2.1,1.5)-(5.1,-1.5) at X 3.8
    assert c[0].seg.end == pytest.approx((3.8, -0.2))
    check_region(plan, A, offset_of(segs, 0.1, 0.5), Frame(True, 1, 1), 1.2)


def test_3333_g72_bore_face():
    segs, mot = P3333()
    A = (3.0, 3.0)
    plan = rough_turn(A, segs, mot, depth=1.2, retract=1.0, allowance=(-0.1, 0.5), face=True)
    assert plan.warnings == []
    c = cuts(plan)
    assert all(m.seg.end[0] > m.seg.start[0] for m in c)  # outward from the hole
    check_region(plan, A, offset_of(segs, -0.1, 0.5), Frame(True, 1, -1), 1.2)


@pytest.mark.parametrize("sx,sz", [(1, 1), (-1, 1), (1, -1), (-1, -1)])
def test_g71_every_quadrant_is_the_mirror_of_the_od(sx, sz):
    segs, mot = P3327()
    A = (23.0, 3.0)
    fr = Frame(False, sx, sz)
    ms = [fr.seg_fwd(s) for s in segs]
    Am = fr.fwd(A)
    plan0 = rough_turn(A, segs, mot, depth=1.5, retract=1.0, allowance=(0.2, 0.1))
    plan = rough_turn(Am, ms, mot, depth=1.5, retract=1.0, allowance=(sx * 0.2, sz * 0.1))
    assert plan.warnings == []
    assert len(plan.moves) == len(plan0.moves)
    for a, b in zip(plan.moves, plan0.moves):
        assert a.kind == b.kind and a.role == b.role
        assert a.seg.end == pytest.approx(fr.fwd(b.seg.end), abs=1e-9)
        if isinstance(b.seg, Arc):
            assert a.seg.cw == (b.seg.cw if sx * sz > 0 else not b.seg.cw)
    check_region(plan, Am, offset_of(ms, sx * 0.2, sz * 0.1), fr, 1.5)


@pytest.mark.parametrize("sx,sz", [(1, 1), (-1, 1), (1, -1), (-1, -1)])
def test_g72_every_quadrant(sx, sz):
    segs, mot = P3331()
    A = (40.0, 1.0)
    mirror = Frame(False, sx, sz)
    ms = [mirror.seg_fwd(s) for s in segs]
    Am = mirror.fwd(A)
    plan = rough_turn(Am, ms, mot, depth=1.2, retract=1.0, allowance=(sx * 0.1, sz * 0.5),
                      face=True)
    assert plan.warnings == []
    check_region(plan, Am, offset_of(ms, sx * 0.1, sz * 0.5), Frame(True, sz, sx), 1.2)


def test_g72_is_g71_with_axes_swapped():
    segs, mot = P3327()
    A = (23.0, 3.0)
    swap = Frame(True, 1, 1)  # (x, z) -> (z, x)
    ss = [swap.seg_fwd(s) for s in segs]
    p71 = rough_turn(A, segs, mot, depth=1.5, retract=1.0, allowance=(0.2, 0.1))
    p72 = rough_turn(swap.fwd(A), ss, mot, depth=1.5, retract=1.0, allowance=(0.1, 0.2),
                     face=True)
    assert [m.seg.end for m in p72.moves] == [pytest.approx(swap.fwd(m.seg.end)) for m in p71.moves]


def test_retract_is_clipped_in_short_passes_and_levels_hit_flats():
    # a profile with a flat exactly on a level: the pass at that level stops where the flat
    # starts (it does not rub along the offset profile)
    segs, mot = path((20, 0), ("G00", 10, 0), ("G01", 10, -10), ("G01", 16, -10),
                     ("G01", 16, -30))
    plan = rough_turn((10.0, 0.0), segs, mot, depth=1.0, retract=2.0, allowance=(0.0, 0.0))
    c = cuts(plan)
    assert [m.seg.start[0] for m in c] == [9.0, 8.0, 7.0, 6.0]
    assert c[0].seg.end == pytest.approx((9.0, -30.0))
    assert c[1].seg.end == pytest.approx((8.0, -10.0))
    check_region(plan, (10.0, 0.0), segs[1:], Frame(False, 1, 1), 1.0)


def test_monotonic_helpers():
    a = Arc.from_radius((5.0, -20.0), (10.0, -25.0), 5, True)
    assert is_monotonic(a, 0, +1) and is_monotonic(a, 1, -1)
    half = Arc((5.0, 0.0), (5.0, -10.0), (5.0, -5.0), False)  # bulges below x = 5
    assert not is_monotonic(half, 0, +1)
    assert is_monotonic(half, 1, -1)
    assert first_non_monotonic([Line((0, 0), (1, -1)), half], 0, +1) == 1


def test_engine_errors():
    segs, mot = P3327()
    A = (23.0, 3.0)
    with pytest.raises(RoughingError, match="depth of cut must be > 0"):
        rough_turn(A, segs, mot, depth=0, retract=1, allowance=(0, 0))
    # A->A' without X motion
    bad = [Line(A, (23.0, 0.0))] + [Line((23.0, 0.0), (30.0, -10.0))]
    with pytest.raises(RoughingError, match="does not move in X") as e:
        rough_turn(A, bad, ["rapid", "feed"], depth=1, retract=1, allowance=(0, 0))
    assert e.value.index == 0
    # profile that turns back toward the start face
    back, m2 = path((46, 3), ("G00", 10, 3), ("G01", 10, -10), ("G01", 20, -5),
                    ("G01", 20, -20))
    with pytest.raises(RoughingError, match="turns back") as e:
        rough_turn(A, back, m2, depth=1, retract=1, allowance=(0, 0))
    assert e.value.index == 2
    # a profile going deeper than its start: does not reach the start side
    deep, m3 = path((46, 3), ("G00", 30, 3), ("G01", 30, -10), ("G01", 20, -20))
    with pytest.raises(RoughingError, match="does not reach the start side"):
        rough_turn(A, deep, m3, depth=1, retract=1, allowance=(0, 0), pockets=True)
    # wrong-sign allowance: planned, with a warning
    plan = rough_turn(A, segs, mot, depth=1.5, retract=1, allowance=(-0.2, 0.1))
    assert plan.warnings and "opposite" in plan.warnings[0]


def test_g73_3335_passes():
    segs, mot = P3335()
    A = (30.0, 5.0)
    plan = pattern_repeat(A, segs, mot, stock=(3.0, 0.9), allowance=(0.3, 0.1), count=3)
    # pass k is the profile shifted by (0.3 + 3(3-k)/3, 0.1 + 0.9(3-k)/3)
    for k in (1, 2, 3):
        du, dz = 0.3 + 3.0 * (3 - k) / 3, 0.1 + 0.9 * (3 - k) / 3
        mv = [m for m in plan.moves if m.role == "cut" and m.level == k]
        assert len(mv) == len(segs)
        for m, s in zip(mv, segs):
            t = s.translated(du, dz)
            assert m.seg.end == pytest.approx(t.end)
            if isinstance(s, Arc):
                assert m.seg.center == pytest.approx(t.center) and m.seg.cw == s.cw
    # the last pass is the allowance-offset profile; the tool ends on A
    last = [m for m in plan.moves if m.role == "cut" and m.level == 3]
    for m, o in zip(last[1:], offset_of(segs, 0.3, 0.1)):
        assert same_point(m.seg.end, o.end)
    assert plan.moves[-1].seg.end == A
    # no move comes into the part + allowance
    fr = Frame(False, 1, 1)
    pts = []
    for s in offset_of(segs, 0.3, 0.1):
        pts.extend(_pts(s))
    part = Polygon([(p[1], p[0]) for p in pts] + [(pts[-1][1], -50), (pts[0][1] + 50, -50)])
    part_in = part.buffer(-3 * CHORD)  # chords of concave arcs lie up to CHORD inside
    for m in plan.moves:
        assert not LineString([_to_c(fr, p) for p in _pts(m.seg)]).intersects(part_in)
    # no rapid between passes enters the material left after the last pass (the profile
    # shifted by that pass's offset), nor the blank (shifted by the whole stock) before pass 1
    def below(k):
        f = (3 - k) / 3
        segs_k = [s.translated(0.3 + 3.0 * f, 0.1 + 0.9 * f) for s in segs[1:]]
        q = [p for s in segs_k for p in _pts(s)]
        return Polygon([(p[1], p[0]) for p in q] + [(q[-1][1], -50), (q[0][1], -50)]) \
            .buffer(0).buffer(-3 * CHORD)
    done = 0
    for m in plan.moves:
        if m.role == "cut":
            done = m.level
        elif m.kind == "rapid":
            ls = LineString([_to_c(fr, p) for p in _pts(m.seg)])
            assert not ls.intersects(below(done)), (m, done)
    # links between passes go out in X first, then along Z (never across the blank)
    links = [m for m in plan.moves if m.role == "link"]
    first = links[0].seg
    assert first.end[0] > first.start[0] and first.end[1] == first.start[1]


def test_g73_bore_and_every_quadrant():
    segs, mot = P3328()
    A = (3.0, 5.0)
    plan = pattern_repeat(A, segs, mot, stock=(-2.0, 0.5), allowance=(-0.2, 0.1), count=4)
    assert plan.warnings == []
    last = [m for m in plan.moves if m.level == 4 and m.role == "cut"]
    for m, o in zip(last[1:], offset_of(segs, -0.2, 0.1)):
        assert same_point(m.seg.end, o.end)
    first = [m for m in plan.moves if m.level == 1 and m.role == "cut"]
    assert first[-1].seg.end == pytest.approx((3.0 - 0.2 - 1.5, -82 + 0.1 + 0.375))


# --------------------------------------------------------------------------- cycle module

class FakeCtx(FakeCycleContext):
    """The cycle context over a fixed profile ``(segments, motions)``; records each leg with
    its start: ``(kind, start, end[, centre, cw])``."""

    def __init__(self, code: int, words: dict, pos: Point, profile=None, *,
                 diameter_mode: bool = True):
        def items(ns, nf):
            if profile is None:
                raise NCError(f"block N{ns} not found", line=4)
            segs, mot = profile
            return [(s, 10 + i, m) for i, (s, m) in enumerate(zip(segs, mot))]
        super().__init__(code, words, pos, profile=items, diameter_mode=diameter_mode, line=4)

    def _leg(self, kind, x, z, *extra):
        self.moves.append((kind, self._pos, (x, z), *extra))
        self._pos = (x, z)

    def arc(self, x, z, center, cw, feed=None):
        self._leg("arc", x, z, center, cw)


def test_execute_g71_3327_words():
    ctx = FakeCtx(71, {"U": 1.5, "R": 1, "P": 5, "Q": 13, "X": 0.4, "Z": 0.1}, (23.0, 3.0),
                  P3327())
    cycles_rough.execute(71, ctx)
    segs, mot = P3327()
    plan = rough_turn((23.0, 3.0), segs, mot, depth=1.5, retract=1, allowance=(0.2, 0.1))
    assert len(ctx.moves) == len(plan.moves)
    assert ctx.moves[-1][2] == (23.0, 3.0)
    arcs = [m for m in ctx.moves if m[0] == "arc"]
    assert len(arcs) == 2 and arcs[0][3] == pytest.approx((10.2, -19.9)) and arcs[0][4] is True
    # radius mode: X is a radius allowance
    ctx2 = FakeCtx(71, {"U": 1.5, "R": 1, "P": 5, "Q": 13, "X": 0.2, "Z": 0.1}, (23.0, 3.0),
                   P3327(), diameter_mode=False)
    cycles_rough.execute(71, ctx2)
    assert ctx2.moves == ctx.moves


def test_execute_type_ii_e_word_and_g72_g73():
    ctx = FakeCtx(71, {"U": 1, "R": 1, "P": 8, "Q": 19, "E": 0.3}, (21.0, 3.0), P3329())
    p = cycles_rough.plan_cycle(71, ctx)
    assert p.offset_profile[0].start == pytest.approx((5.15, 3.0))
    ctx = FakeCtx(72, {"W": 1.2, "R": 1, "P": 8, "Q": 17, "X": 0.2, "Z": 0.5}, (40.0, 1.0),
                  P3331())
    p = cycles_rough.plan_cycle(72, ctx)
    assert p.offset_profile[-1].end == pytest.approx((2.1, 1.5))
    ctx = FakeCtx(73, {"U": 3, "W": 0.9, "R": 3, "P": 5, "Q": 13, "X": 0.6, "Z": 0.1},
                  (30.0, 5.0), P3335())
    cycles_rough.execute(73, ctx)
    assert ctx.moves[-1][2] == (30.0, 5.0)


ALARMS = [
    (71, {"R": 1, "P": 5, "Q": 13, "X": 0.4, "Z": 0.1}, "needs U"),
    (71, {"U": 0, "R": 1, "P": 5, "Q": 13, "X": 0.4, "Z": 0.1}, "must be > 0"),
    (71, {"U": -1.5, "R": 1, "P": 5, "Q": 13, "X": 0.4, "Z": 0.1}, "must be > 0"),
    (71, {"U": 1.5, "P": 5, "Q": 13, "X": 0.4, "Z": 0.1}, "needs R"),
    (71, {"U": 1.5, "R": 1, "Q": 13, "X": 0.4, "Z": 0.1}, "needs P"),
    (71, {"U": 1.5, "R": 1, "P": 5, "X": 0.4, "Z": 0.1}, "needs Q"),
    (71, {"U": 1.5, "W": 1, "R": 1, "P": 5, "Q": 13, "X": 0.4, "Z": 0.1}, "W is not a word"),
    (71, {"U": 1.5, "R": 1, "P": 5, "Q": 13, "X": 0.4, "E": 0.3}, "takes no X/Z"),
    (72, {"U": 1.2, "W": 1.2, "R": 1, "P": 8, "Q": 17, "X": 0.2, "Z": 0.5}, "U is not a word"),
    (72, {"W": 0, "R": 1, "P": 8, "Q": 17, "X": 0.2, "Z": 0.5}, "must be > 0"),
    (73, {"U": 3, "W": 0.9, "R": 2.5, "P": 5, "Q": 13, "X": 0.6, "Z": 0.1}, "whole number"),
    (73, {"U": 3, "W": 0.9, "R": 0, "P": 5, "Q": 13, "X": 0.6, "Z": 0.1}, "must be > 0"),
    (73, {"R": 3, "P": 5, "Q": 13, "X": 0.6, "Z": 0.1}, "needs U and/or W"),
]


@pytest.mark.parametrize("code,words,msg", ALARMS)
def test_alarms_on_words(code, words, msg):
    prof = {71: P3327(), 72: P3331(), 73: P3335()}[code]
    pos = {71: (23.0, 3.0), 72: (40.0, 1.0), 73: (30.0, 5.0)}[code]
    with pytest.raises(NCError, match=msg):
        cycles_rough.execute(code, FakeCtx(code, words, pos, prof))


def test_alarms_on_profiles():
    # type I on a grooved profile
    ctx = FakeCtx(71, {"U": 1, "R": 1, "P": 8, "Q": 19, "X": 0.3, "Z": 0}, (21.0, 3.0), P3329())
    with pytest.raises(NCError, match=r"type I profile is not monotonic in X .*line 15"):
        cycles_rough.execute(71, ctx)
    # G72 with an X move in block ns
    segs, mot = path((80, 1), ("G00", 78, -56), ("G01", 54, -40), ("G01", 54, 1))
    ctx = FakeCtx(72, {"W": 1, "R": 1, "P": 8, "Q": 10, "X": 0.2, "Z": 0.5}, (40.0, 1.0),
                  (segs, mot))
    with pytest.raises(NCError, match="moves in X"):
        cycles_rough.execute(72, ctx)
    # the profile does not reach the start side
    deep = path((46, 3), ("G00", 30, 3), ("G01", 30, -10), ("G01", 20, -20))
    ctx = FakeCtx(71, {"U": 1, "R": 1, "P": 1, "Q": 3, "E": 0.2}, (23.0, 3.0), deep)
    with pytest.raises(NCError, match="does not reach the start side"):
        cycles_rough.execute(71, ctx)
    # P/Q not found: raised by the interpreter's profile()
    ctx = FakeCtx(71, {"U": 1, "R": 1, "P": 99, "Q": 100, "X": 0.3, "Z": 0}, (21.0, 3.0), None)
    with pytest.raises(NCError, match="not found"):
        cycles_rough.execute(71, ctx)


def test_missing_allowance_warns():
    ctx = FakeCtx(71, {"U": 1.5, "R": 1, "P": 5, "Q": 13}, (23.0, 3.0), P3327())
    cycles_rough.execute(71, ctx)
    assert any("allowance" in w for w in ctx.warnings)


@pytest.mark.parametrize("depth,retract", [(0.7, 2.5), (1.3, 0.4), (2.0, 2.0)])
def test_type_ii_any_depth_and_retract(depth, retract):
    """Large retracts over short groove passes stay over the pass just cut (clipped in Z)."""
    for prof, A in ((P3329, (21.0, 3.0)), (P3346, (27.0, 3.0))):
        segs, mot = prof()
        plan = rough_turn(A, segs, mot, depth=depth, retract=retract, allowance=(0.15, 0.0),
                          pockets=True)
        check_region(plan, A, offset_of(segs, 0.15, 0.0), Frame(False, 1, 1), depth)


def test_short_pass_at_the_bottom_of_a_v_groove_retracts_over_itself():
    # V groove 45 deg down to radius 5: the deepest pass (radius 5.35) is 0.7 long, shorter
    # than the retract 0.9; a full 45 deg retract would rapid into the groove wall's stair
    segs, mot = path((24.7, 0), ("G00", 16, 0), ("G01", 20, -2), ("G01", 20, -10),
                     ("G01", 10, -15), ("G01", 20, -20), ("G01", 20, -30), ("G01", 24.7, -30))
    A = (12.35, 0.0)
    plan = rough_turn(A, segs, mot, depth=1.0, retract=0.9, allowance=(0.0, 0.0), pockets=True)
    bottom = min(cuts(plan), key=lambda m: m.seg.start[0])
    assert bottom.seg.start == pytest.approx((5.35, -14.65))
    assert bottom.seg.end == pytest.approx((5.35, -15.35))
    i = plan.moves.index(bottom)
    assert plan.moves[i + 1].seg.end == pytest.approx((6.25, -14.65))
    check_region(plan, A, segs[1:], Frame(False, 1, 1), 1.0)


# --------------------------------------------------------------------------- end to end

interp = pytest.importorskip("hnc_cam.nc.interp")


def _machine(sharp: bool):
    from hnc_cam.tooling import Register, load_machine
    m = load_machine()
    if sharp:  # zero nose radius: G41/G42 leave the finishing path on the profile
        numbers = set(m.registers) | set(range(1, 10))
        m = m.with_registers({n: Register(number=n) for n in numbers})
    return m


def cycle_moves(tp, op: str, start: Point, offset: list[Segment], fr: Frame):
    """The cycle's moves of a Toolpath as RoughMoves with roles read from the geometry:
    the last pass is the run that ends on the offset profile's end (its first move is the
    approach to A″), feeds at constant level are cuts, the other feeds plunges."""
    from hnc_cam.geometry.roughing import RoughMove
    ms = [m for m in tp.moves if m.op == op]
    assert ms and same_point(ms[0].start, start, 1e-9)
    segs = [m.segment() for m in ms]
    j = max(i for i, s in enumerate(segs) if same_point(s.end, offset[0].start, 1e-9))
    out = []
    for i, (m, s) in enumerate(zip(ms, segs)):
        kind = "rapid" if m.kind == "rapid" else "feed"
        if j <= i <= j + len(offset):
            role = "finish"
        elif kind == "feed":
            u0, u1 = fr.fwd(s.start)[0], fr.fwd(s.end)[0]
            role = "cut" if abs(u0 - u1) < 1e-9 else "plunge"
        else:
            role = "link"
        out.append(RoughMove(kind, s, role))

    class _Plan:
        moves = out
    return _Plan(), ms


def ends_on_profile(tp, profile: list[Segment], lines: set[int], tol=1e-6):
    """Every finishing move (the profile blocks run after the cycle) lies on the programmed
    profile, and the last of them ends on its end point B."""
    fin = [m for m in tp.moves if m.line in lines and not m.op.startswith("G7")
           and m.kind != "rapid"]
    assert fin
    for m in fin:
        for p in _pts(m.segment()):
            assert min(s.distance_to(p) for s in profile) < tol, (m, p)
    assert same_point(fin[-1].end, profile[-1].end, tol)


E2E = [
    # file, cycle, A, profile, allowance (radius), frame, depth, profile lines
    ("3327.nc", "G71", (23.0, 3.0), P3327, (0.2, 0.1), Frame(False, 1, 1), 1.5),
    ("3328.nc", "G71", (3.0, 5.0), P3328, (-0.2, 0.1), Frame(False, -1, 1), 1.0),
    ("3329.nc", "G71", (21.0, 3.0), P3329, (0.15, 0.0), Frame(False, 1, 1), 1.0),
    ("3331fix.nc", "G72", (40.0, 1.0), P3331, (0.1, 0.5), Frame(True, 1, 1), 1.2),
    ("3333.nc", "G72", (3.0, 3.0), P3333, (-0.1, 0.5), Frame(True, 1, -1), 1.2),
    ("3346.nc", "G71", (27.0, 3.0), P3346, (0.15, 0.0), Frame(False, 1, 1), 1.0),
]


@pytest.mark.parametrize("name,op,A,prof,allow,fr,depth", E2E, ids=[e[0] for e in E2E])
def test_manual_examples_end_to_end(manual, name, op, A, prof, allow, fr, depth):
    from hnc_cam.nc import run_file
    tp = run_file(str(manual(name)), _machine(False))
    segs, _ = prof()
    offset = offset_of(segs, *allow)
    plan, ms = cycle_moves(tp, op, A, offset, fr)
    check_region(plan, A, offset, fr, depth)
    assert all(m.feed == pytest.approx(100.0) for m in ms if m.kind != "rapid")
    # after the cycle the program runs ns..nf as the finishing pass, ending on the profile
    tp0 = run_file(str(manual(name)), _machine(True))
    ends_on_profile(tp0, segs[1:], profile_lines(manual(name).read_text()))


def profile_lines(text: str) -> set[int]:
    """1-based source lines of the blocks N(ns)..N(nf) named by the program's G71/G72/G73
    block (P, Q), excluding the block ns itself (A→A′ is an approach, not the profile)."""
    import re
    lines = text.splitlines()
    cyc = next(ln for ln in lines if re.search(r"G7[123]", ln.split("(")[0]))
    ns = int(re.search(r"P(\d+)", cyc).group(1))
    nf = int(re.search(r"Q(\d+)", cyc).group(1))
    out, inside = set(), False
    for i, ln in enumerate(lines, 1):
        m = re.match(r"\s*N\s*(\d+)", ln)
        n = int(m.group(1)) if m else None
        if n == ns:
            inside = True
            continue
        if inside:
            out.add(i)
        if n == nf:
            break
    return out


def test_3331_as_printed_alarms_on_the_erratum(manual):
    from hnc_cam.nc import run_file
    with pytest.raises(NCError, match="G03 needs R or I/K") as e:
        run_file(str(manual("3331.nc")))
    # N16 Z-2 after N15 G03: G01 missing (see 3331fix.nc); the alarm is raised while the
    # G72 reads its profile
    text = manual("3331.nc").read_text().splitlines()
    assert text[e.value.line - 1].startswith("N16 Z-2")


def test_3335_g73_end_to_end(manual):
    from hnc_cam.nc import run_file
    tp = run_file(str(manual("3335.nc")), _machine(True))
    segs, _ = P3335()
    ms = [m for m in tp.moves if m.op == "G73"]
    assert same_point(ms[0].start, (30.0, 5.0)) and same_point(ms[-1].end, (30.0, 5.0))
    # each pass ends on B shifted by the remaining stock + allowance
    for k in (1, 2, 3):
        du, dz = 0.3 + (3 - k), 0.1 + 0.3 * (3 - k)
        b = (27.0 + du, -62.0 + dz)
        assert any(same_point(m.end, b, 1e-9) and m.kind == "line" for m in ms), k
    # the last pass is the allowance-offset profile, exactly
    off = offset_of(segs, 0.3, 0.1)
    segs_tp = [m.segment() for m in ms if m.kind != "rapid"]
    tail = segs_tp[-len(off):]
    for a, b in zip(tail, off):
        assert same_point(a.start, b.start, 1e-9) and same_point(a.end, b.end, 1e-9)
    # no move comes into the part + allowance
    pts = []
    for s in off:
        pts.extend(_pts(s))
    part = Polygon([(p[1], p[0]) for p in pts] + [(pts[-1][1], -50), (pts[0][1], -50)]).buffer(0)
    part_in = part.buffer(-3 * CHORD)
    for m in ms:
        assert not LineString([(p[1], p[0]) for p in _pts(m.segment())]).intersects(part_in), m
    ends_on_profile(tp, segs[1:], profile_lines(manual("3335.nc").read_text()))


# --- own programs: every quadrant of G71/G72/G73, written as program text

B3327 = [("G00", 0, 3), ("G01", 10, -2), ("G01", 10, -20), ("G02", 20, -25, 5), ("G01", 20, -35),
         ("G03", 34, -42, 7), ("G01", 34, -52), ("G01", 44, -62), ("G01", 44, -82)]
B3328 = [("G00", 44, 5), ("G01", 44, -15), ("G01", 34, -25), ("G01", 34, -35), ("G03", 20, -42, 7),
         ("G01", 20, -52), ("G02", 10, -57, 5), ("G01", 10, -80), ("G01", 6, -82)]
B3331 = [("G00", 80, -56), ("G01", 54, -40), ("G01", 54, -30), ("G02", 46, -26, 4),
         ("G01", 30, -26), ("G01", 30, -15), ("G01", 14, -15), ("G03", 10, -13, 2),
         ("G01", 10, -2), ("G01", 4, 1)]
B3333 = [("G00", 6, -61), ("G01", 12, -58), ("G01", 12, -48), ("G03", 16, -46, 2),
         ("G01", 30, -46), ("G01", 30, -34), ("G01", 46, -34), ("G02", 54, -30, 4),
         ("G01", 54, -20), ("G01", 74, -10), ("G01", 74, 3)]


def _mz(blocks):
    """Mirror in Z (a part cut toward +Z): Z negated, G02 <-> G03."""
    sw = {"G02": "G03", "G03": "G02"}
    return [(sw.get(b[0], b[0]), b[1], -b[2]) + tuple(b[3:]) for b in blocks]


def program(start_dia, cycle: str, blocks) -> str:
    out = ["%1234", "N1 T0101", "N2 M03 S500", f"N3 G00 X{start_dia[0]:g} Z{start_dia[1]:g}",
           f"N4 {cycle} P10 Q{9 + len(blocks)} F120" if " P" not in cycle and " Q" not in cycle
           else f"N4 {cycle} F120"]
    for i, b in enumerate(blocks):
        w = f"N{10 + i} {b[0]} X{b[1]:g} Z{b[2]:g}" + (f" R{b[3]:g}" if len(b) > 3 else "")
        out.append(w)
    out += ["N90 G00 X100 Z100", "N91 M30"]
    return "\n".join(out) + "\n"


OWN = [
    # name, cycle words, start (dia, z), blocks, allowance (radius, z), frame, depth
    ("G71 OD -Z", "G71 U1.5 R1 X0.4 Z0.1", (46, 3), B3327, (0.2, 0.1), Frame(False, 1, 1), 1.5),
    ("G71 ID -Z", "G71 U1 R0.5 X-0.4 Z0.1", (6, 5), B3328, (-0.2, 0.1), Frame(False, -1, 1), 1.0),
    ("G71 OD +Z", "G71 U1.5 R1 X0.4 Z-0.1", (46, -3), _mz(B3327), (0.2, -0.1),
     Frame(False, 1, -1), 1.5),
    ("G71 ID +Z", "G71 U1 R0.5 X-0.4 Z-0.1", (6, -5), _mz(B3328), (-0.2, -0.1),
     Frame(False, -1, -1), 1.0),
    ("G72 OD -Z", "G72 W1.2 R1 X0.2 Z0.5", (80, 1), B3331, (0.1, 0.5), Frame(True, 1, 1), 1.2),
    ("G72 ID -Z", "G72 W1.2 R1 X-0.2 Z0.5", (6, 3), B3333, (-0.1, 0.5), Frame(True, 1, -1), 1.2),
    ("G72 OD +Z", "G72 W1.2 R1 X0.2 Z-0.5", (80, -1), _mz(B3331), (0.1, -0.5),
     Frame(True, -1, 1), 1.2),
    ("G72 ID +Z", "G72 W0.8 R0.3 X-0.2 Z-0.5", (6, -3), _mz(B3333), (-0.1, -0.5),
     Frame(True, -1, -1), 0.8),
    ("G71 II ID", "G71 U0.7 R0.4 E-0.3", (6, 5), B3328, (-0.15, 0.0), Frame(False, -1, 1), 0.7),
]


@pytest.mark.parametrize("name,words,start,blocks,allow,fr,depth", OWN, ids=[o[0] for o in OWN])
def test_own_programs_every_quadrant(name, words, start, blocks, allow, fr, depth):
    from hnc_cam.nc import run
    text = program(start, words, blocks)
    tp = run(text, _machine(True))
    segs, _ = path(start, *blocks)
    A = (start[0] / 2, float(start[1]))
    offset = offset_of(segs, *allow)
    plan, ms = cycle_moves(tp, words.split()[0], A, offset, fr)
    assert not [w for w in tp.warnings if "opposite" in str(w)]
    check_region(plan, A, offset, fr, depth)
    assert all(m.feed == pytest.approx(120.0) for m in ms if m.kind != "rapid")
    ends_on_profile(tp, segs[1:], profile_lines(text))


@pytest.mark.parametrize("mirror", [False, True])
def test_own_g73_bore_program(mirror):
    from hnc_cam.nc import run
    blocks = _mz(B3328) if mirror else B3328
    z0 = -5 if mirror else 5
    sz = -1 if mirror else 1
    text = program((6, z0), f"G73 U-2 W{0.6 * sz:g} R4 X-0.4 Z{0.1 * sz:g}", blocks)
    tp = run(text, _machine(True))
    segs, _ = path((6, z0), *blocks)
    A = (3.0, float(z0))
    ms = [m for m in tp.moves if m.op == "G73"]
    cut = [m for m in ms if m.kind != "rapid"]
    # 4 passes, each the profile (less the rapid approach) shifted by the remaining stock
    n = len(segs) - 1
    assert len(cut) == 4 * n
    for k in range(1, 5):
        f = (4 - k) / 4
        d = (-0.2 - 2 * f, sz * (0.1 + 0.6 * f))
        for m, s in zip(cut[(k - 1) * n:k * n], segs[1:]):
            t = s.translated(*d)
            assert same_point(m.start, t.start, 1e-9) and same_point(m.end, t.end, 1e-9)
    assert same_point(ms[-1].end, A)
    ends_on_profile(tp, segs[1:], profile_lines(text))


# --- alarms through the interpreter

ALARM_PROGRAMS = [
    ("P missing", "G71 U1 R1 Q12 X0.4 Z0.1", [("G00", 0, 3), ("G01", 10, -2), ("G01", 10, -20)],
     "needs P"),
    ("Q not found", "G71 U1 R1 P10 Q55 X0.4 Z0.1",
     [("G00", 0, 3), ("G01", 10, -2), ("G01", 10, -20)], "N55 .*not found"),
    ("ns is an arc", "G71 U1 R1 P10 Q12 X0.4 Z0.1",
     [("G02", 0, 3, 20), ("G01", 10, -2), ("G01", 10, -20)], "must be G00 or G01"),
    ("G72 ns with X", "G72 W1 R1 P10 Q12 X0.4 Z0.1",
     [("G00", 40, -20), ("G01", 10, -10), ("G01", 10, 1)], "moves in X"),
    ("type I with a groove", "G71 U1 R1 P10 Q14 X0.4 Z0.1",
     [("G00", 0, 3), ("G01", 20, -2), ("G01", 20, -10), ("G01", 12, -15), ("G01", 30, -30)],
     "type I profile is not monotonic"),
    ("not reaching the start side", "G71 U1 R1 P10 Q12 E0.4",
     [("G00", 30, 3), ("G01", 30, -10), ("G01", 20, -20)], "does not reach the start side"),
    ("depth 0", "G71 U0 R1 P10 Q12 X0.4 Z0.1", [("G00", 0, 3), ("G01", 10, -2), ("G01", 10, -20)],
     "must be > 0"),
    ("W on G71", "G71 U1 W1 R1 P10 Q12 X0.4 Z0.1",
     [("G00", 0, 3), ("G01", 10, -2), ("G01", 10, -20)], "W is not a word of G71"),
    ("U on G72", "G72 U1 W1 R1 P10 Q12 X0.4 Z0.1",
     [("G00", 46, -20), ("G01", 10, -10), ("G01", 10, 1)], "U is not a word of G72"),
    ("G72 P not found", "G72 W1 R1 P77 Q12 X0.4 Z0.1",
     [("G00", 46, -20), ("G01", 10, -10), ("G01", 10, 1)], "N77 .*not found"),
    ("G72 ns is an arc", "G72 W1 R1 P10 Q12 X0.4 Z0.1",
     [("G03", 46, -20, 30), ("G01", 10, -10), ("G01", 10, 1)], "must be G00 or G01"),
    ("G72 depth 0", "G72 W0 R1 P10 Q12 X0.4 Z0.1",
     [("G00", 46, -20), ("G01", 10, -10), ("G01", 10, 1)], "must be > 0"),
    ("G73 Q missing", "G73 U3 W0.9 R3 P10 X0.6 Z0.1",
     [("G00", 0, 3), ("G01", 10, -2), ("G01", 10, -20)], "needs Q"),
    ("G73 ns is an arc", "G73 U3 W0.9 R3 P10 Q12 X0.6 Z0.1",
     [("G02", 0, 3, 30), ("G01", 10, -2), ("G01", 10, -20)], "must be G00 or G01"),
]


@pytest.mark.parametrize("name,words,blocks,msg", ALARM_PROGRAMS,
                         ids=[a[0] for a in ALARM_PROGRAMS])
def test_alarms_through_the_interpreter(name, words, blocks, msg):
    from hnc_cam.nc import run
    text = program((46, 3), words, blocks)
    with pytest.raises(NCError, match=msg) as e:
        run(text, _machine(True))
    assert e.value.line >= 5


def test_m98_inside_the_profile_alarms():
    from hnc_cam.nc import run
    text = ("%1\nN1 G00 X46 Z3\nN2 G71 U1 R1 P10 Q12 X0.4 Z0.1 F100\nN10 G00 X0\n"
            "N11 M98 P2\nN12 G01 X40 Z-20\nN13 M30\n%2\nG01 X10\nM99\n")
    with pytest.raises(NCError, match="M98/M99 inside the profile"):
        run(text, _machine(True))


# --- random profiles (hypothesis): the invariants hold for any groove pattern

from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@st.composite
def grooved_profiles(draw):
    """OD profiles monotonic in Z with random lines, faces and arcs (type II)."""
    n = draw(st.integers(2, 9))
    z, x = -draw(st.sampled_from([0.0, 0.0, 0.5, 2.0])), draw(st.floats(1.0, 8.0))
    blocks = [("G00", 2 * x, z)]  # z < 0: a slanted approach A->A'

    kind = "face"  # no face right after the approach or after a face (it would fold back)
    for _ in range(n):
        kind = draw(st.sampled_from(["line", "line", "arc"] + ([] if kind == "face" else ["face"])))
        nx = draw(st.floats(0.5, 14.0))
        if kind == "face":
            blocks.append(("G01", 2 * nx, z))
        else:
            nz = z - draw(st.floats(0.3, 8.0))
            if kind == "arc" and abs(nx - x) > 1e-3:
                # quarter-ish arc: monotonic in Z when its sweep stays within one quadrant
                c = math.hypot(nx - x, nz - z)
                blocks.append(("G02" if draw(st.booleans()) else "G03", 2 * nx, nz,
                               c * draw(st.floats(0.75, 3.0))))
            else:
                blocks.append(("G01", 2 * nx, nz))
            z = nz
        x = nx
    blocks.append(("G01", 2 * draw(st.floats(x, 16.0)), z - draw(st.floats(0.5, 3.0))))
    return blocks


@settings(max_examples=60, deadline=None)
@given(grooved_profiles(), st.floats(0.3, 2.0), st.floats(0.1, 2.5), st.floats(0.0, 0.4),
       st.sampled_from([(1, 1), (-1, 1), (1, -1), (-1, -1)]))
def test_random_grooved_profiles(blocks, depth, retract, e, quadrant):
    sx, sz = quadrant
    segs, mot = path((34.0, 0.0), *blocks)
    if first_non_monotonic(segs[1:], 1, -1) is not None:
        return  # an arc that turns back in Z: not a type II profile
    fr = Frame(False, sx, sz)
    ms = [fr.seg_fwd(s) for s in segs]
    A = fr.fwd((17.0, 0.0))
    try:
        plan = rough_turn(A, ms, mot, depth=depth, retract=retract, allowance=(sx * e, 0.0),
                          pockets=True)
    except RoughingError as err:
        assert "does not reach the start side" in err.message
        return
    ns = ms[0].translated(sx * e, 0.0)
    check_region(plan, A, offset_of(ms, sx * e, 0.0), fr, depth,
                 approach=ns if abs(ms[0].start[1] - ms[0].end[1]) > 1e-9 else None)


def test_slanted_approach_block():
    """A→A′ with a Z component (G00 X0 Z3 from Z6): the side of the approach line away
    from the work is air; passes start on that line, entered by a feed (the stair in
    front of each pass is cut on the way down) and never by a rapid through material."""
    segs, mot = path((46, 6), *B3327)
    A = (23.0, 6.0)
    plan = rough_turn(A, segs, mot, depth=1.5, retract=1.0, allowance=(0.2, 0.1))
    c = cuts(plan)
    ns = segs[0].translated(0.2, 0.1)
    for m in c:  # every pass starts on the shifted approach line
        assert ns.distance_to(m.seg.start) < 1e-9
    check_region(plan, A, offset_of(segs, 0.2, 0.1), Frame(False, 1, 1), 1.5, approach=ns)


# --------------------------------------------------------------------------- rounding (0.001 mm)

def test_arc_past_its_extreme_within_the_rounding_tolerance():
    """An arc may run back past an X/Z extreme by up to ROUND_TOL (0.001 mm) and still count
    as monotonic; more than that is a profile that turns back."""
    from hnc_cam.geometry.roughing import ROUND_TOL
    assert ROUND_TOL == pytest.approx(1e-3)
    R = 10.0
    # polar angle t: x = R sin t, z = R cos t; ccw (G03) increases t; x is extreme at t = pi/2
    for back, ok in ((0.0009, True), (0.002, False)):
        d = math.acos(1 - back / R)  # R (1 - cos d) = back
        t0, t1 = 0.5, math.pi / 2 + d
        a = Arc((R * math.sin(t0), R * math.cos(t0)), (R * math.sin(t1), R * math.cos(t1)),
                (0.0, 0.0), False)
        assert is_monotonic(a, 0, +1) is ok
        assert is_monotonic(a, 1, -1)
        # ... and the same arc reversed, the extreme passed right after the start
        r = Arc(a.end, a.start, a.center, True)
        assert is_monotonic(r, 0, -1) is ok


ROUNDED = [
    # name, cycle words, start (dia, z), blocks written to 3 decimals, allowance, frame, depth
    # a dome from the axis: the R16 arc starts on its Z extreme, its end rounded to 0.001
    ("G71 dome", "G71 U1 R0.5 X0.4 Z0.1", (42, 2),
     [("G00", 0, 2), ("G01", 0, 0), ("G03", 20, -3.509, 16), ("G01", 20, -20),
      ("G01", 42, -20)], (0.2, 0.1), Frame(False, 1, 1), 1.0),
    # a quarter round from the face to a cylinder: starts on its Z and ends on its X extreme
    ("G71 quarter", "G71 U1 R0.5 X0.4 Z0.1", (42, 2),
     [("G00", 10, 2), ("G01", 10, 0), ("G03", 30.001, -10, 10), ("G01", 30.001, -20),
      ("G01", 42, -20)], (0.2, 0.1), Frame(False, 1, 1), 1.0),
    # G72: a quarter round from a face to the front cylinder
    ("G72 quarter", "G72 W1 R0.5 X0.4 Z0.1", (42, 2),
     [("G00", 42, -20), ("G01", 30, -20), ("G01", 30, -10.001), ("G02", 10, 0, 10),
      ("G01", 10, 2)], (0.2, 0.1), Frame(True, 1, 1), 1.0),
]


@pytest.mark.parametrize("name,words,start,blocks,allow,fr,depth", ROUNDED,
                         ids=[o[0] for o in ROUNDED])
def test_profiles_rounded_to_3_decimals_with_arcs_on_their_extremes(name, words, start, blocks,
                                                                     allow, fr, depth):
    """Regression: with coordinates rounded to 0.001 mm these arcs pass their extreme by a
    hair (< 1e-6 mm); the 1e-6 check used to raise 'the profile turns back'."""
    from hnc_cam.nc import run
    segs, _ = path(start, *blocks)
    arc = fr.seg_fwd(next(s for s in segs if isinstance(s, Arc)))
    # the programmed arc really does pass an extreme by a hair (in the job's canonical frame:
    # levels along u rising, cut toward -v)
    assert (not is_monotonic(arc, 1, -1, overshoot=0.0)
            or not is_monotonic(arc, 0, +1, overshoot=0.0))
    assert is_monotonic(arc, 1, -1) and is_monotonic(arc, 0, +1)
    text = program(start, words, blocks)
    tp = run(text, _machine(True))
    A = (start[0] / 2, float(start[1]))
    offset = offset_of(segs, *allow)
    plan, ms = cycle_moves(tp, words.split()[0], A, offset, fr)
    check_region(plan, A, offset, fr, depth)
    ends_on_profile(tp, segs[1:], profile_lines(text))


# --------------------------------------------------------------------------- audit additions

PROFILE_WORDS = """%1
N1 T0101
N2 M03 S500
N3 G00 X46 Z3
N4 G71 U1.5 R1 P10 Q15 X0.4 Z0.1 F120 S600
N10 G00 G42 X10 S900
N11 G01 X20 Z-2 F60
N12 Z-20
N13 G02 X30 Z-25 R5
N14 G01 Z-35
N15 G40 G00 X46
N16 G00 X100 Z100
N17 M30
"""


def test_g41_g42_g40_and_f_s_inside_the_profile():
    """G41/G42/G40 words inside ns..nf are allowed; F/S inside it apply to the finishing run
    after the cycle, the cycle's F/S to roughing; the roughing is not compensated, the
    finishing run is (register 1: r 0.8, tip 3), its nose centre at exactly r from the
    profile."""
    from hnc_cam.nc import run
    from hnc_cam.tooling import load_machine
    m = load_machine()
    r = m.registers[1].radius
    assert (r, m.registers[1].tip) == (0.8, 3)
    tp = run(PROFILE_WORDS, m)
    rough = [mv for mv in tp.moves if mv.op == "G71"]
    assert rough and all(mv.comp == 40 for mv in rough)
    assert {mv.feed for mv in rough if mv.kind != "rapid"} == {120.0}
    assert {mv.spindle for mv in rough} == {600.0}
    fin = [mv for mv in tp.moves if 7 <= mv.line <= 10 and mv.kind in ("line", "arc")]
    assert fin and all(mv.comp == 42 and mv.feed == 60.0 and mv.spindle == 900.0 for mv in fin)
    prof, _ = path((10, 3), ("G01", 20, -2), ("G01", 20, -20), ("G02", 30, -25, 5),
                   ("G01", 30, -35))
    for mv in fin:
        g = mv.segment()
        for k in range(21):
            p = g.point_at(k / 20)
            c = (p[0] + r, p[1] + r)  # controlled point -> nose centre (tip 3: (-r, -r))
            assert min(s.distance_to(c) for s in prof) == pytest.approx(r, abs=1e-9), (mv, p)


def test_m99_inside_the_profile_alarms():
    from hnc_cam.nc import run
    text = ("%1\nN1 G00 X46 Z3\nN2 G71 U1 R1 P10 Q12 X0.4 Z0.1 F100\nN10 G00 X0\n"
            "N11 M99\nN12 G01 X40 Z-20\nN13 M30\n")
    with pytest.raises(NCError, match="M98/M99 inside the profile") as e:
        run(text, _machine(True))
    assert e.value.line == 5


def test_3328_finishing_contour_is_compensated(manual):
    """3328: the bore's finishing contour after the G71 runs under G42 (the manual's erratum:
    a bore cut toward -Z takes G41; the interpreter runs it as written, so the offset lands
    on the other side) with the nose centre at exactly r from the programmed contour."""
    from hnc_cam.nc import run_file
    from hnc_cam.tooling import load_machine
    m = load_machine()
    r = m.registers[2].radius
    tp = run_file(str(manual("3328.nc")), m)
    lines = profile_lines(manual("3328.nc").read_text())
    fin = [mv for mv in tp.moves if mv.line in lines and mv.comp == 42 and mv.op != "G71"
           and mv.kind in ("line", "arc")]
    assert len(fin) >= 5
    segs, _ = P3328()
    tip = m.registers[2].tip
    from hnc_cam.geometry.tip import tip_vector
    tv = tip_vector(tip, r)
    for mv in fin:
        g = mv.segment()
        for k in range(21):
            p = g.point_at(k / 20)
            c = (p[0] - tv[0], p[1] - tv[1])
            assert min(s.distance_to(c) for s in segs[1:]) == pytest.approx(r, abs=1e-7), (mv, p)
    # ... on the right of the motion (+X for a cut toward -Z), i.e. inside the bore wall of
    # dia 44: the erratum is reproduced, not corrected
    mid = [mv for mv in fin if mv.kind == "line" and mv.start[1] > -14 and mv.end[1] < -1][0]
    assert mid.start[0] - tv[0] == pytest.approx(22.0 + r)


@pytest.mark.parametrize("end", [(29.999, -10), (30.001, -10), (30, -9.999), (30, -10.001)])
def test_ik_arc_ending_off_its_circle_at_an_extreme(end):
    """A quarter round written with I/K whose end, rounded to 0.001 mm, misses the circle
    (inside or outside, in X or in Z) at its X extreme: planned, and the passes respect the
    offset profile."""
    from hnc_cam.nc import run
    X, Z = end
    text = ("%1\nN1 T0101\nN3 G00 X42 Z2\nN4 G71 U1 R0.5 P10 Q14 X0.4 Z0.1 F120\n"
            "N10 G00 X10\nN11 G01 Z0\n"
            f"N12 G03 X{X:g} Z{Z:g} I0 K-10\nN13 G01 Z-20\nN14 G01 X42\nN90 G00 X100 Z100\n"
            "N91 M30\n")
    tp = run(text, _machine(True))
    xe = X / 2
    segs = [Line((21.0, 2.0), (5.0, 2.0)), Line((5.0, 2.0), (5.0, 0.0)),
            Arc((5.0, 0.0), (xe, Z), (5.0, -10.0), False), Line((xe, Z), (xe, -20.0)),
            Line((xe, -20.0), (21.0, -20.0))]
    A = (21.0, 2.0)
    offset = offset_of(segs, 0.2, 0.1)
    plan, _ = cycle_moves(tp, "G71", A, offset, Frame(False, 1, 1))
    check_region(plan, A, offset, Frame(False, 1, 1), 1.0)
    ends_on_profile(tp, segs[1:], profile_lines(text), tol=1e-3)
