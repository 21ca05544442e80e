"""The outline a solid made by ``revolve()`` was revolved from is its profile without cutting
the solid, only while the object is that very shape: the profile taken from the outline equals
the one extracted from the solid for every bundled part and test family (several parameter
sets each), and a solid moved, located, copied, mirrored or cut is profiled from its section."""
from __future__ import annotations

import copy
import gc
import math
import pickle
from pathlib import Path

import pytest

from hnc_cam.cad import ProfileError, load_part, profile
from hnc_cam.cad.extract import extract, outline_chain
from hnc_cam.cad.loader import family_parameters, load_module
from hnc_cam.cad.sketch import Outline, SketchError, _REVOLVED, revolve, revolved_outline
from hnc_cam.errors import PartError
from hnc_cam.geometry import Arc, Line

pytestmark = pytest.mark.cad

ROOT = Path(__file__).resolve().parents[1]
FILES = sorted((ROOT / "parts").glob("*.py")) + sorted((ROOT / "tests" / "data" / "families")
                                                       .glob("*.py")) \
    + sorted((ROOT / "tests" / "data" / "turning_parts").glob("*.py"))
FILES = [f for f in FILES if f.name != "__init__.py"]
#: the extractor takes a free-form edge within this of a line or arc as exact (mm)
TOL = 1e-6


def _variants(mod, most: int = 4) -> list[dict]:
    """The defaults and parameter sets with one parameter 7 % smaller or larger, those the
    family accepts, at most ``most``."""
    base = family_parameters(mod)
    sets = [{}]
    for k, v in base.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v == 0:
            continue
        for f in (0.93, 1.07):
            nv = round(v * f) if isinstance(v, int) else v * f
            if nv != v:
                sets.append({k: nv})
    out = []
    for s in sets:
        try:
            mod.part(**{**base, **s})
        except (PartError, SketchError, ValueError):
            continue
        out.append(s)
        if len(out) == most:
            break
    return out


def _same_seg(a, b, tol=TOL) -> bool:
    if type(a) is not type(b):
        return False
    pts = [(a.start, b.start), (a.end, b.end)]
    if isinstance(a, Arc):
        if a.cw != b.cw or abs(a.radius - b.radius) > tol:
            return False
        pts.append((a.center, b.center))
    return all(abs(p[0] - q[0]) <= tol and abs(p[1] - q[1]) <= tol for p, q in pts)


def _same_profile(a, b) -> bool:
    if (a.bore is None) != (b.bore is None) or a.notes != b.notes:
        return False
    for ca, cb in ((a.outside, b.outside), (a.bore or [], b.bore or [])):
        if len(ca) != len(cb) or not all(_same_seg(x, y) for x, y in zip(ca, cb)):
            return False
    return True


@pytest.mark.parametrize("path", FILES, ids=[f"{f.parent.name}/{f.stem}" for f in FILES])
def test_outline_profile_equals_extracted_profile(path):
    mod = load_module(path)
    sets = _variants(mod)
    assert sets, f"{path.name}: no parameter set loads"
    recorded = 0
    for s in sets:
        solid = mod.part(**{**family_parameters(mod), **s})
        segs = revolved_outline(solid)
        if segs is not None:
            recorded += 1
            assert outline_chain(segs) is not None, f"{path.name} {s}: a clean outline refused"
        for zero in ("right", "left", -7.5):
            fast, slow = profile(solid, zero=zero), extract(solid, zero=zero)
            assert _same_profile(fast, slow), (path.name, s, zero, fast.outside, slow.outside)
    src = path.read_text()
    if "return revolve(" in src and "cadquery" not in src:
        assert recorded == len(sets), f"{path.name}: the outline was not used"


def test_bundled_parts_load_through_the_outline(monkeypatch):
    """load_part of a bundled revolve() family never cuts the solid (the section is not
    asked for), and gives the extractor's profile."""
    from hnc_cam.cad import occ
    part = ROOT / "parts" / "stepped_shaft.py"
    want = extract(load_module(part).part(length=97.0, d1=17.0))
    calls = []
    real = occ.meridian_section
    monkeypatch.setattr(occ, "meridian_section", lambda *a, **k: calls.append(1) or real(*a, **k))
    got = load_part(part, {"length": "97", "d1": "17"}).profile
    assert not calls
    want.params = got.params
    assert _same_profile(got, want)


@pytest.fixture()
def shaft():
    s = Outline((0.0, 0.0))
    s.line_to(10, 0, chamfer=1).line_to(10, -20, fillet=0.5).line_to(15, -20)
    s.arc_to(15, -30, radius=5, cw=True).line_to(15, -40).line_to(0, -40)
    return s.segments()


def test_moved_located_and_mirrored_solids_are_cut(shaft):
    """A numeric program zero shows where the solid is: each changed solid's profile is the
    one of its own position, not of the outline."""
    from build123d import Location, Plane, Pos
    solid = revolve(shaft)
    assert revolved_outline(solid) is not None
    z_max = profile(solid, zero=0.0).z_max
    assert z_max == pytest.approx(0.0, abs=1e-9)

    moved = solid.moved(Location((0, 0, 5)))
    assert revolved_outline(moved) is None
    assert profile(moved, zero=0.0).z_max == pytest.approx(5.0, abs=1e-9)
    assert revolved_outline(solid) is not None  # the original is unchanged

    shifted = Pos(0, 0, -3) * solid
    assert revolved_outline(shifted) is None
    assert profile(shifted, zero=0.0).z_max == pytest.approx(-3.0, abs=1e-9)

    mirrored = solid.mirror(Plane.XY)
    assert revolved_outline(mirrored) is None
    assert profile(mirrored, zero=0.0).z_min == pytest.approx(0.0, abs=1e-9)
    assert profile(mirrored, zero=0.0).z_max == pytest.approx(40.0, abs=1e-9)

    solid.locate(Location((0, 0, 2)))  # in place: the same object, its shape moved
    assert revolved_outline(solid) is None
    assert profile(solid, zero=0.0).z_max == pytest.approx(2.0, abs=1e-9)

    other = revolve(shaft)
    other.move(Location((0, 0, -4)))  # moved in place, relative
    assert revolved_outline(other) is None
    assert profile(other, zero=0.0).z_max == pytest.approx(-4.0, abs=1e-9)


def test_copies_booleans_and_raw_shapes_are_cut(shaft):
    from build123d import Box, Cylinder, Pos
    solid = revolve(shaft)
    for obj in (copy.copy(solid), copy.deepcopy(solid), pickle.loads(pickle.dumps(solid)),
                solid.wrapped):
        assert revolved_outline(obj) is None
        assert _same_profile(profile(obj), extract(solid))
    grooved = solid - Pos(0, 0, -35) * Cylinder(20, 2) + Pos(0, 0, -35) * Cylinder(14, 2)
    assert revolved_outline(grooved) is None
    assert len(profile(grooved).outside) > len(profile(solid).outside)
    keyed = solid - Pos(0, 14, -35) * Box(8, 8, 6)
    assert revolved_outline(keyed) is None
    with pytest.raises(ProfileError, match="not a body of revolution"):
        profile(keyed)


def test_reversed_or_replaced_shape_is_cut(shaft):
    solid = revolve(shaft)
    solid.wrapped.Reverse()  # in place: the same TShape and location, the other orientation
    assert revolved_outline(solid) is None
    other = revolve(shaft)
    other.wrapped = revolve([Line((0, 0), (8, 0)), Line((8, 0), (8, -10)),
                             Line((8, -10), (0, -10))]).wrapped
    assert revolved_outline(other) is None
    assert profile(other).max_radius == pytest.approx(8.0)


def test_the_note_leaves_with_its_solid(shaft):
    gc.collect()
    before = len(_REVOLVED)
    solids = [revolve(shaft) for _ in range(20)]
    assert len(_REVOLVED) == before + 20
    del solids
    gc.collect()
    assert len(_REVOLVED) == before


def test_the_outline_is_kept_as_given(shaft):
    segs = list(shaft)
    solid = revolve(segs)
    segs.clear()
    assert revolved_outline(solid) == shaft
    assert revolved_outline(revolve(iter(shaft))) == shaft


def _lines(*pts):
    return [Line(a, b) for a, b in zip(pts, pts[1:])]


@pytest.mark.parametrize("segs", [
    # crosses itself (a bow tie between two radii)
    _lines((0, 0), (10, 0), (5, -10), (10, -20), (5, -20), (10, -10), (5, 0.5), (0, 0.5)),
    # folds back on itself
    _lines((0, 0), (10, 0), (10, -20), (10, -10), (0, -10)),
    # touches the axis between its ends
    _lines((0, 0), (10, 0), (0, -10), (10, -20), (0, -20)),
    # crosses the axis
    _lines((0, 0), (10, 0), (-2, -10), (0, -20)),
    # an arc leaving the axis not about it (a self-intersecting torus)
    [Arc((0.0, 0.0), (10.0, -10.0), (10.0, 0.0), False)] + _lines((10, -10), (10, -20), (0, -20)),
    # not contiguous
    [Line((0, 0), (10, 0)), Line((10, -1), (10, -20)), Line((10, -20), (0, -20))],
    # a loop touching the axis
    _lines((5, 0), (10, 0), (10, -10), (0, -5), (5, 0)),
    # neighbours the kernel unifies: collinear lines, co-circular arcs (also across the start)
    _lines((0, 0), (10, 0), (10, -5), (10, -20), (0, -20)),
    [Line((0.0, 0.0), (3.0, 0.0)), Arc((3.0, 0.0), (8.0, -5.0), (3.0, -5.0), True),
     Arc((8.0, -5.0), (3.0, -10.0), (3.0, -5.0), True)] + _lines((3, -10), (0, -10)),
    _lines((5, -5), (5, 0), (10, 0), (10, -20), (5, -20), (5, -5)),
    # no volume
    _lines((0, 0), (10, 0), (0, 0)),
])
def test_doubtful_outlines_are_not_trusted(segs):
    assert outline_chain(segs) is None


def test_unified_neighbours_profile_as_extracted():
    segs = _lines((0, 0), (10, 0), (10, -5), (10, -20), (0, -20))
    solid = revolve(segs)
    assert revolved_outline(solid) is not None and outline_chain(segs) is None
    got = profile(solid)
    assert _same_profile(got, extract(solid))
    assert got.outside[1] == Line((10.0, 0.0), (10.0, -20.0))


def test_outlines_the_solid_is_made_of_are_trusted():
    sphere = [Arc((0.0, 5.0), (0.0, -5.0), (0.0, 0.0), False)]
    assert outline_chain(sphere) is not None
    assert outline_chain([Arc((0.0, 5.0), (0.0, -5.0), (0.0, 0.0), True)]) is None  # r < 0
    torus = [Arc((10.0, 0.0), (20.0, 0.0), (15.0, 0.0), True),
             Arc((20.0, 0.0), (10.0, 0.0), (15.0, 0.0), True)]
    assert outline_chain(torus) is not None
    for get in (profile, extract):  # no end faces: refused alike, in one line
        with pytest.raises(ProfileError, match="cannot find the outside contour"):
            get(revolve(torus))
    ring = [Line((10.0, 0.0), (16.0, 0.0)), Arc((16.0, 0.0), (20.0, -4.0), (16.0, -4.0), True),
            Line((20.0, -4.0), (20.0, -12.0)), Line((20.0, -12.0), (10.0, -12.0)),
            Line((10.0, -12.0), (10.0, 0.0))]  # a tube with a rounded outer edge
    assert outline_chain(ring) is not None
    closed_on_axis = _lines((0, 0), (10, 0), (10, -20), (0, -20), (0, 0))
    ch = outline_chain(closed_on_axis)
    assert ch is not None and len(ch.segs) == 3
    axis_inside = _lines((10, 0), (10, -20), (0, -20), (0, 0), (10, 0))  # axis run mid-list
    ch = outline_chain(axis_inside)
    assert ch is not None and ch.segs[0].start == (0.0, 0.0) and ch.segs[-1].end == (0.0, -20.0)
    tube = _lines((5, 0), (10, 0), (10, -20), (5, -20), (5, 0))
    assert outline_chain(tube) is not None
    for segs in (sphere, ring, closed_on_axis, axis_inside, tube):
        solid = revolve(segs)
        assert revolved_outline(solid) is not None
        for zero in ("right", "left"):
            assert _same_profile(profile(solid, zero=zero), extract(solid, zero=zero))


def _assert_profiles_as_extracted(solid, segs) -> None:
    """``profile(solid)`` is what the extractor gives, or refuses it with the same line."""
    try:
        want = extract(solid)
    except ProfileError as e:
        with pytest.raises(ProfileError) as got:
            profile(solid)
        assert str(got.value) == str(e)
    else:
        assert _same_profile(profile(solid), want), segs


def test_refused_outline_reports_as_before():
    """An outline whose solid is not a valid turned body: the extractor's verdict."""
    bow = _lines((0, 0), (10, 0), (5, -10), (10, -20), (5, -20), (10, -10), (5, 0.5), (0, 0.5))
    try:
        solid = revolve(bow)
    except Exception:  # noqa: BLE001 - the kernel refused it outright: nothing to profile
        return
    _assert_profiles_as_extracted(solid, bow)


def test_other_axes_are_cut(shaft):
    solid = revolve(shaft)
    with pytest.raises(ProfileError):
        profile(solid, axis="X")
    p = profile(solid, axis="-Z")
    assert p.outside[0].start == pytest.approx((0.0, 0.0))
    assert p.length == pytest.approx(40.0)
    assert math.isclose(p.max_radius, 15.0)


def _random_outline(rng):
    """A turned part as a user might sketch it: steps up and down, tapers, chamfers and
    fillets at random corners, an arc here and there, sometimes a through bore."""
    n = rng.randint(2, 6)
    zs = sorted({round(rng.uniform(-80.0, -2.0), 3) for _ in range(n)}, reverse=True)
    bore = rng.random() < 0.3
    r_in = rng.uniform(3.0, 6.0) if bore else 0.0
    s = Outline((r_in, 0.0))
    r_prev = None
    for z in zs + [-90.0]:
        r = round(rng.uniform(r_in + 4.0, 30.0), 3)
        while r_prev is not None and abs(r - r_prev) < 0.5:
            r = round(rng.uniform(r_in + 4.0, 30.0), 3)
        corner = rng.choice(["", "C", "R"])
        size = rng.uniform(0.2, 0.8)
        kw = {"chamfer": size} if corner == "C" else {"fillet": size} if corner == "R" else {}
        pos = s.pos
        if rng.random() < 0.2 and pos[1] - z > 6.0:  # an arc down to the next step
            s.line_to(r, pos[1])
            mid = (pos[1] + z) / 2
            s.arc_to(r, mid, radius=(pos[1] - mid) * rng.uniform(0.6, 3.0),
                     cw=rng.random() < 0.5)
            s.line_to(r, z, **kw)
        else:
            s.line_to(r, pos[1], **kw)
            s.line_to(r, z)
        r_prev = r
    s.line_to(r_in, -90.0)
    if bore:
        s.close()
    return s.segments()


def test_random_outlines_profile_as_extracted():
    """Outlines made at random the way part files make them: the profile taken from the
    outline is the extracted one (or both refuse the part alike)."""
    import random
    rng = random.Random(1507)
    used = done = 0
    while done < 40:
        try:
            segs = _random_outline(rng)
            solid = revolve(segs)
        except (SketchError, ValueError):
            continue
        done += 1
        used += outline_chain(segs) is not None
        _assert_profiles_as_extracted(solid, segs)
    assert used >= 30
