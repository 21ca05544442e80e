"""Every parts/ family: its profile equals its defining sketch segment by segment, for several
parameter sets; default stock fits; threads; the part-file loader's errors."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from hnc_cam.cad import LoadedPart, PartError, ProfileError, load_part, parse_set
from hnc_cam.cad.fit import merge_segments
from hnc_cam.geometry import Arc, Line, reverse_chain
from hnc_cam.tooling import Stock

pytestmark = pytest.mark.cad

PARTS = Path(__file__).resolve().parents[1] / "parts"

FAMILIES = {
    "stepped_shaft": [{}, {"length": "120", "d1": "16", "d2": "30", "d3": "48", "l1": "30",
                           "l2": "62", "taper_length": "20", "dome_radius": "9"},
                      {"chamfer": "0.5", "fillet": "0.8", "dome_radius": "40"}],
    "grooved_shaft": [{}, {"length": "100", "d1": "30", "d2": "44", "l1": "40", "arc_z": "70",
                           "arc_radius": "3", "arc_depth": "3", "relief_angle": "45"},
                      {"relief_width": "3", "relief_depth": "0.6", "relief_radius": "0.4",
                       "relief_angle": "90"}],
    "flange": [{}, {"diameter": "160", "thickness": "20", "hub_diameter": "70",
                    "hub_length": "25", "fillet": "5"},
               {"diameter": "90", "thickness": "10", "hub_diameter": "40", "hub_length": "12",
                "fillet": "1", "chamfer": "0.8"}],
    "bushing": [{}, {"outer_diameter": "60", "bore_diameter": "35", "length": "50"},
                {"outer_diameter": "25", "bore_diameter": "12", "length": "18", "chamfer": "0.5",
                 "inner_chamfer": "0", "back_chamfer": "0.8"}],
    "cast_blank": [{}, {"length": "120", "diameter": "50", "amplitude": "4", "wave_length": "30",
                        "waves": "3"},
                   {"waves": "1", "amplitude": "1.5"}],
    "threaded_stud": [{}, {"thread_diameter": "24", "pitch": "2", "thread_length": "30",
                           "relief_diameter": "21", "collar_diameter": "36", "length": "60"},
                      {"thread_diameter": "16", "pitch": "1", "thread_length": "15",
                       "relief_diameter": "14.2", "collar_diameter": "22", "length": "35"}],
    "cq_pin": [{}, {"length": "60", "diameter": "20", "head_diameter": "30",
                    "head_thickness": "8", "groove_z": "10"},
               {"fillet": "2.5", "head_chamfer": "0.5", "groove_width": "4.5"}],
}

CASES = [(fam, i, params) for fam, sets in FAMILIES.items() for i, params in enumerate(sets)]


def _same(a, b, tol=1e-6) -> bool:
    if type(a) is not type(b):
        return False
    pts = [(a.start, b.start), (a.end, b.end)]
    if isinstance(a, Arc):
        if a.cw != b.cw or abs(a.radius - b.radius) > tol:
            return False
        pts.append((a.center, b.center))
    return all(abs(p[0] - q[0]) <= tol and abs(p[1] - q[1]) <= tol for p, q in pts)


@pytest.fixture(scope="module")
def loaded():
    cache: dict[tuple[str, int], LoadedPart] = {}

    def get(fam: str, i: int) -> LoadedPart:
        if (fam, i) not in cache:
            cache[(fam, i)] = load_part(PARTS / f"{fam}.py", FAMILIES[fam][i])
        return cache[(fam, i)]
    return get


@pytest.mark.parametrize("fam,i,params", CASES, ids=[f"{f}-{i}" for f, i, _ in CASES])
def test_profile_equals_defining_sketch(loaded, fam, i, params):
    lp = loaded(fam, i)
    prof = lp.profile
    expected = merge_segments(lp.module.sketch(**lp.params))
    # the sketch runs from the right face's innermost point around the section (ccw)
    got = prof.outside + (reverse_chain(prof.bore) if prof.bore else [])
    assert len(got) == len(expected), (got, expected)
    for g, e in zip(got, expected):
        assert _same(g, e), (g, e)
    assert prof.z_max == pytest.approx(0.0, abs=1e-9)
    assert prof.notes == []  # nothing fitted, nothing ignored: all exact
    assert prof.name == fam and prof.params == lp.params
    for k, v in params.items():
        assert lp.params[k] == pytest.approx(float(v))


@pytest.mark.parametrize("fam,i,params", CASES, ids=[f"{f}-{i}" for f, i, _ in CASES])
def test_default_stock_fits_with_allowance(loaded, fam, i, params):
    lp = loaded(fam, i)
    assert lp.stock is not None
    st = Stock.parse(lp.stock)
    prof = lp.profile
    if st.kind == "offset":
        assert st.allowance >= 1.0
        return
    assert st.diameter >= prof.max_diameter + 1.0
    assert st.face >= 1.0  # face stock on the right
    assert st.z_left <= prof.z_min - 5.0  # room to grip / part off
    if prof.bore:
        assert st.kind == "tube"
        assert st.bore <= 2 * prof.min_bore_radius - 1.0
    elif st.kind == "tube":
        pytest.fail("tube stock for a part without a bore")


def test_family_shapes(loaded):
    """A few facts that make the families what the issue asks for."""
    shaft = loaded("stepped_shaft", 0).profile
    kinds = [type(s).__name__ for s in shaft.outside]
    assert kinds[0] == "Arc" and shaft.outside[0].start == (0.0, 0.0)  # domed end
    assert any(isinstance(s, Line) and s.start[0] != s.end[0] and s.start[1] != s.end[1]
               and abs(s.start[1] - s.end[1]) > 5 for s in shaft.outside)  # a taper
    grooved = loaded("grooved_shaft", 0).profile
    xs = [s.end[0] for s in grooved.outside]
    assert any(b < a for a, b in zip(xs, xs[1:-1]))  # dips: undercuts
    flange = loaded("flange", 0).profile
    assert flange.max_diameter > 3 * flange.length  # face-dominated
    bush = loaded("bushing", 0).profile
    assert bush.bore is not None and bush.min_bore_radius == pytest.approx(11.0)
    assert bush.bore[0].start == bush.outside[0].start == (12.0, 0.0)
    assert bush.bore[-1].end == bush.outside[-1].end == (11.0, -30.0)
    back = loaded("bushing", 2).profile  # no right inner chamfer, a back chamfer
    assert back.outside[0].start == back.bore[0].start == (6.0, 0.0)
    assert back.bore[-1].end == back.outside[-1].end == (6.8, -18.0)
    cast = loaded("cast_blank", 0).profile
    assert sum(isinstance(s, Arc) for s in cast.outside) == 6
    for a, b in zip(cast.outside[1:6], cast.outside[2:7]):  # tangent arcs
        ta, tb = a.tangent_at_end(), b.tangent_at_start()
        assert ta[0] * tb[0] + ta[1] * tb[1] == pytest.approx(1.0, abs=1e-9)
    pin = loaded("cq_pin", 0)
    assert pin.module.__name__.startswith("hnc_part_cq_pin")
    (fil,) = [s for s in pin.profile.outside if isinstance(s, Arc)]  # CadQuery's threePointArc
    assert fil.radius == pytest.approx(1.0) and fil.center == pytest.approx((9.0, -39.0))


def test_threaded_stud_threads(loaded):
    lp = loaded("threaded_stud", 0)
    (t,) = lp.threads
    assert (t.z_start, t.z_end, t.diameter, t.pitch, t.starts, t.internal) == (0.0, -22.0, 20.0, 1.5, 1, False)
    assert t.standard == "metric" and t.angle == 60.0
    assert lp.profile.threads == lp.threads
    # the major diameter is modelled on the thread length; the relief follows, below the minor
    prof = lp.profile
    on = [s for s in prof.outside if isinstance(s, Line) and s.start[0] == s.end[0] == 10.0]
    assert on and min(s.end[1] for s in on) == pytest.approx(-22.0)
    assert min(s.bbox()[0] for s in prof.outside[1:-1]) < t.minor_diameter / 2
    lp2 = loaded("threaded_stud", 1)
    assert lp2.threads[0].z_end == -30.0 and lp2.threads[0].pitch == 2.0


def test_thread_z_follows_program_zero():
    lp = load_part(PARTS / "threaded_stud.py", zero="left")
    assert lp.profile.z_min == pytest.approx(0.0)
    assert lp.threads[0].z_start == pytest.approx(50.0)
    assert lp.threads[0].z_end == pytest.approx(28.0)


# ---------------------------------------------------------------------------- loader errors
def test_parse_set():
    assert parse_set(["length=120", " d1 = 16.5 "]) == {"length": "120", "d1": "16.5"}
    assert parse_set(None) == {}
    for bad in (["length"], ["=3"], ["length="], ["2x=3"]):
        with pytest.raises(PartError):
            parse_set(bad)


def test_unknown_parameter_lists_known():
    with pytest.raises(PartError) as e:
        load_part(PARTS / "bushing.py", {"lenght": "30"})
    msg = str(e.value)
    assert "unknown parameter lenght" in msg and "outer_diameter" in msg and "length" in msg


def test_kwargs_part_declares_no_parameters():
    """A family whose part() only forwards **kwargs to its sketch has no parameters: --set of
    a sketch argument is refused with the way to declare them; without --set the part loads
    with the sketch's own defaults."""
    f = Path(__file__).parent / "data" / "families" / "kw_pin.py"
    with pytest.raises(PartError) as e:
        load_part(f, {"d1": "13"})
    assert "unknown parameter d1" in str(e.value) and "def part(" in str(e.value)
    lp = load_part(f)
    xs = [max(s.start[0], s.end[0]) for s in lp.profile.outside]
    assert max(xs) == pytest.approx(6.0)


def test_value_not_a_number():
    with pytest.raises(PartError, match=r"length='abc' is not a number"):
        load_part(PARTS / "bushing.py", {"length": "abc"})
    with pytest.raises(PartError, match="whole number"):
        load_part(PARTS / "cast_blank.py", {"waves": "2.5"})


def test_int_parameter_parsed_as_int():
    lp = load_part(PARTS / "cast_blank.py", {"waves": "2"})
    assert lp.params["waves"] == 2 and isinstance(lp.params["waves"], int)
    assert sum(isinstance(s, Arc) for s in lp.profile.outside) == 4


def test_missing_and_unimportable_files(tmp_path):
    with pytest.raises(PartError, match="no such part file"):
        load_part(tmp_path / "nope.py")
    bad = tmp_path / "broken.py"
    bad.write_text("def part(:\n")
    with pytest.raises(PartError, match="import failed: SyntaxError"):
        load_part(bad)
    nopart = tmp_path / "nopart.py"
    nopart.write_text("X = 1\n")
    with pytest.raises(PartError, match=r"no function part"):
        load_part(nopart)
    with pytest.raises(PartError, match="no such file"):
        load_part(tmp_path / "missing.step")


def test_part_raising_is_reported(tmp_path):
    with pytest.raises(PartError) as e:
        load_part(PARTS / "stepped_shaft.py", {"d1": "50"})
    msg = str(e.value)
    assert "part(" in msg and "d1=50" in msg and "impossible part: need d1 < d2 < d3" in msg
    # any other exception in a user's part() is reported with its type
    f = tmp_path / "oops.py"
    f.write_text("def part(d=10.0):\n    raise ValueError('boom')\n")
    with pytest.raises(PartError) as e:
        load_part(f, {"d": "12"})
    assert "part(d=12) raised ValueError: boom" in str(e.value)


def _family_module(fam: str):
    from hnc_cam.cad.loader import load_module
    return load_module(PARTS / f"{fam}.py")


# Parameter sets that make an impossible part: part() itself must refuse them with a
# PartError naming the offending parameters (never an OpenCascade exception, never a
# silently different part). (family, overrides, names the message must contain)
BAD_SETS = [
    ("stepped_shaft", {"d1": 30.0}, ["d1", "d2"]),                       # d1 > d2
    ("stepped_shaft", {"d3": 26.0}, ["d2", "d3"]),
    ("stepped_shaft", {"fillet": 5.0}, ["fillet", "d1", "d2"]),          # fillet > the step
    ("stepped_shaft", {"chamfer": 3.0, "fillet": 1.5}, ["chamfer", "fillet"]),
    ("stepped_shaft", {"chamfer": -1.0}, ["chamfer"]),                   # silently none before
    ("stepped_shaft", {"dome_radius": 8.0}, ["dome_radius", "d1"]),
    ("stepped_shaft", {"l2": 20.0}, ["l1", "l2"]),
    ("stepped_shaft", {"taper_length": 60.0}, ["taper_length", "length"]),
    ("stepped_shaft", {"length": 0.0}, ["length"]),
    ("grooved_shaft", {"d1": 40.0}, ["d1", "d2"]),
    ("grooved_shaft", {"relief_depth": 13.0}, ["relief_depth", "d1"]),
    ("grooved_shaft", {"relief_radius": 1.0}, ["relief_radius", "relief_depth"]),
    ("grooved_shaft", {"relief_width": 1.0}, ["relief_width", "relief_angle"]),
    ("grooved_shaft", {"arc_z": 32.0}, ["arc_z", "l1"]),
    ("grooved_shaft", {"arc_z": 78.0}, ["arc_z", "length"]),
    ("grooved_shaft", {"arc_depth": 6.0}, ["arc_depth", "arc_radius"]),
    ("grooved_shaft", {"relief_angle": 120.0}, ["relief_angle"]),
    ("flange", {"hub_diameter": 130.0}, ["hub_diameter", "diameter"]),
    ("flange", {"fillet": 20.0}, ["fillet", "hub_length"]),
    ("flange", {"chamfer": 8.0}, ["chamfer", "thickness"]),
    ("flange", {"thickness": -2.0}, ["thickness"]),
    ("bushing", {"bore_diameter": 45.0}, ["bore_diameter", "outer_diameter"]),
    ("bushing", {"bore_diameter": 37.5}, ["chamfer", "inner_chamfer"]),  # wall too thin
    ("bushing", {"chamfer": 16.0}, ["chamfer"]),
    ("bushing", {"length": 1.5}, ["chamfer", "length"]),
    ("bushing", {"inner_chamfer": 16.0, "back_chamfer": 15.0}, ["inner_chamfer", "back_chamfer"]),
    ("cast_blank", {"amplitude": 8.0}, ["amplitude", "wave_length"]),
    ("cast_blank", {"waves": 4}, ["waves", "length"]),
    ("cast_blank", {"waves": 0}, ["waves"]),
    ("cast_blank", {"diameter": 8.0}, ["amplitude", "diameter"]),
    ("threaded_stud", {"relief_diameter": 19.0}, ["relief_diameter", "pitch"]),  # above minor
    ("threaded_stud", {"thread_diameter": 30.0}, ["thread_diameter", "collar_diameter"]),
    ("threaded_stud", {"thread_length": 45.0}, ["thread_length", "length"]),
    ("threaded_stud", {"pitch": 0.0}, ["pitch"]),
    ("threaded_stud", {"pitch": 20.0}, ["pitch", "thread_diameter"]),
    ("threaded_stud", {"relief_radius": 3.0}, ["relief_radius", "relief_width"]),
    ("cq_pin", {"groove_width": 0.0}, ["groove_width"]),
    ("cq_pin", {"groove_depth": 9.0}, ["groove_depth", "diameter"]),
    ("cq_pin", {"groove_z": 39.0}, ["groove_z", "length", "fillet"]),
    ("cq_pin", {"groove_z": 1.0}, ["groove_z", "chamfer"]),
    ("cq_pin", {"diameter": 24.0}, ["diameter", "head_diameter"]),
    ("cq_pin", {"head_chamfer": 7.0}, ["head_chamfer", "head_thickness"]),
]


@pytest.mark.parametrize("fam,bad,names", BAD_SETS,
                         ids=[f"{f}-{'-'.join(f'{k}{v:g}' for k, v in b.items())}"
                              for f, b, _ in BAD_SETS])
def test_impossible_parameter_sets_raise_part_error_naming_them(fam, bad, names):
    mod = _family_module(fam)
    with pytest.raises(PartError) as e:
        mod.part(**bad)
    msg = str(e.value)
    for n in names:
        assert re.search(rf"\b{n}\b", msg), (n, msg)
    # and through the loader: one line with the file and the full parameter set
    with pytest.raises(PartError) as e2:
        load_part(PARTS / f"{fam}.py", {k: str(v) for k, v in bad.items()})
    assert f"{fam}.py: part(" in str(e2.value) and msg in str(e2.value)


@pytest.mark.parametrize("fam", list(FAMILIES))
def test_random_parameter_sets_refused_or_exact(fam):
    """Random perturbations of the defaults (seeded): every set either raises PartError or
    gives a part whose profile is its sketch, segment by segment (never a wrong part, never
    an OpenCascade exception)."""
    import random
    from hnc_cam.cad import profile
    mod = _family_module(fam)
    from hnc_cam.cad.loader import family_parameters
    defaults = family_parameters(mod)
    rng = random.Random(sum(map(ord, fam)))
    built = refused = 0
    for _ in range(12):
        params = {}
        for k, v in defaults.items():
            if rng.random() < 0.4:
                params[k] = (max(0, v + rng.choice((-1, 1))) if isinstance(v, int)
                             else round(v * rng.uniform(0.3, 1.8), 3))
        try:
            solid = mod.part(**params)
        except PartError:
            refused += 1
            continue
        full = {**defaults, **params}
        prof = profile(solid)
        expected = merge_segments(mod.sketch(**full))
        got = prof.outside + (reverse_chain(prof.bore) if prof.bore else [])
        assert len(got) == len(expected), (params, got, expected)
        assert all(_same(g, x) for g, x in zip(got, expected)), params
        built += 1
    assert built + refused == 12 and built >= 3, (built, refused)


def test_user_part_file_with_constants(tmp_path):
    f = tmp_path / "collar.py"
    f.write_text(
        '"""Collar. Parameters: d (mm), length (mm)."""\n'
        "from hnc_cam.cad.sketch import Outline, revolve\n"
        "from hnc_cam.geometry import Thread\n"
        "STOCK = '50x40+1'\n"
        "THREADS = [Thread(0.0, -10.0, 30.0, 2.0)]\n"
        "def part(d=30.0, length=20.0):\n"
        "    s = Outline((0.0, 0.0)).line_to(d / 2, 0.0).line_to(d / 2, -length).line_to(0.0, -length)\n"
        "    return revolve(s.segments())\n")
    lp = load_part(f, {"length": "25"})
    assert lp.stock == "50x40+1" and lp.params == {"d": 30.0, "length": 25.0}
    assert lp.profile.length == pytest.approx(25.0) and lp.threads[0].pitch == 2.0
    assert [type(s) for s in lp.profile.outside] == [Line, Line, Line]
    f2 = tmp_path / "badstock.py"
    f2.write_text(f.read_text().replace("'50x40+1'", "'50y40'"))
    with pytest.raises(PartError, match="STOCK"):
        load_part(f2)
    f3 = tmp_path / "badthread.py"
    f3.write_text(f.read_text().replace("Thread(0.0, -10.0, 30.0, 2.0)", "Thread(0.0, -80.0, 30.0, 2.0)"))
    with pytest.raises(PartError, match="outside the part"):
        load_part(f3)
    f4 = tmp_path / "keyed.py"
    f4.write_text(
        "from build123d import Box, Cylinder, Pos\n"
        "def part(d=30.0):\n"
        "    return Cylinder(d / 2, 40) - Pos(0, d / 2, 0) * Box(8, 8, 20)\n")
    with pytest.raises(ProfileError, match=r"keyed\.py.*planar face parallel to the axis"):
        load_part(f4)
    assert load_part(f4, envelope=True).profile.max_diameter == pytest.approx(30.0)


def test_step_file_loads_without_parameters():
    step = Path(__file__).parent / "data" / "stepped_shaft.step"
    lp = load_part(step)
    assert lp.stock is None and lp.params == {} and lp.threads == [] and lp.name == "stepped_shaft"
    with pytest.raises(PartError, match="no parameters"):
        load_part(step, {"length": "3"})


def test_loaded_part_pickles(loaded):
    import pickle
    lp = loaded("threaded_stud", 0)
    back = pickle.loads(pickle.dumps(lp))
    assert back.module is None and back.profile.outside == lp.profile.outside
    assert back.threads == lp.threads and back.stock == lp.stock and back.params == lp.params


# ---------------------------------------------------------------------------- thread checks
_NUT = (
    '"""Threaded sleeve: OD 40, bore {bore} (modelled at the minor diameter) to Z-{depth}."""\n'
    "from hnc_cam.cad.sketch import Outline, revolve\n"
    "from hnc_cam.geometry import Thread\n"
    "THREADS = [{threads}]\n"
    "def part(length=40.0):\n"
    "    s = Outline(({rb}, 0.0)).line_to(20.0, 0.0).line_to(20.0, -length)\n"
    "    s.line_to(0.0, -length).line_to(0.0, -{depth}).line_to({rb}, -{depth})\n"
    "    return revolve(s.close().segments())\n")


def _nut(tmp_path, threads: str, bore: float = 22.0, depth: float = 25.0) -> Path:
    f = tmp_path / "nut.py"
    f.write_text(_NUT.format(threads=threads, bore=bore, rb=bore / 2, depth=depth))
    return f


def test_internal_thread_in_the_bore_accepted(tmp_path):
    # M24x2 internal: minor diameter 24 - 1.0825*2 = 21.835; bore modelled at 22; and an
    # external M40x2 on the 40 mm outside at the same time
    lp = load_part(_nut(tmp_path, "Thread(0.0, -20.0, 24.0, 2.0, internal=True), "
                                  "Thread(0.0, -15.0, 40.0, 2.0)"))
    t, ext = lp.threads
    assert t.internal and not ext.internal and lp.profile.bore is not None
    assert lp.profile.bore[0] == Line((11.0, 0.0), (11.0, -25.0))


@pytest.mark.parametrize("threads,bore,match", [
    ("Thread(0.0, -30.0, 24.0, 2.0, internal=True)", 22.0,
     r"internal thread D24x2 Z0..Z-30 lies outside the bore: no bore at Z-2[0-9.]+"),
    ("Thread(0.0, -20.0, 20.0, 1.5, internal=True)", 22.0,
     r"internal thread D20x1.5 .*the bore is 22\.000 in diameter there, not under the major"),
    ("Thread(0.0, -20.0, 36.0, 2.0, internal=True)", 22.0,
     r"internal thread D36x2 .*far under the minor diameter"),
    ("Thread(0.0, -20.0, 36.0, 2.0)", 22.0,
     r"external thread D36x2 Z0..Z-20: the part is 40\.000 in diameter on the thread, larger "
     r"than the major diameter 36"),
    ("Thread(0.0, -20.0, 48.0, 2.0)", 22.0,
     r"external thread D48x2 .*only 40\.000 in diameter there, under the minor diameter"),
    ("Thread(5.0, -20.0, 40.0, 2.0)", 22.0, r"lies outside the part \(Z0..Z-40\)"),
    ("Thread(0.0, -50.0, 40.0, 2.0)", 22.0, r"lies outside the part"),
    ("Thread(0.0, -20.0, 40.0, 0.0)", 22.0, r"THREADS: .*pitch=0\.0 must be positive"),
    ("Thread(0.0, -20.0, 40.0, -1.5)", 22.0, r"pitch=-1\.5 must be positive"),
    ("Thread(-20.0, 0.0, 40.0, 1.5)", 22.0, r"z_start=-20\.0 must be greater than z_end=0\.0"),
    ("Thread(0.0, -20.0, 40.0, 1.5, starts=0)", 22.0, r"starts=0 must be a whole number >= 1"),
    ("Thread(0.0, -20.0, 0.0, 1.5)", 22.0, r"diameter=0\.0 must be positive"),
])
def test_thread_declarations_checked(tmp_path, threads, bore, match):
    with pytest.raises(PartError, match=match):
        load_part(_nut(tmp_path, threads, bore))


def test_internal_thread_on_a_part_without_bore(tmp_path):
    f = tmp_path / "pin.py"
    f.write_text("from hnc_cam.cad.sketch import Outline, revolve\n"
                 "from hnc_cam.geometry import Thread\n"
                 "THREADS = [Thread(0.0, -10.0, 20.0, 1.5, internal=True)]\n"
                 "def part(d=20.0):\n"
                 "    return revolve(Outline((0.0, 0.0)).line_to(d / 2, 0.0).line_to(d / 2, -30.0)"
                 ".line_to(0.0, -30.0).segments())\n")
    with pytest.raises(PartError, match=r"internal thread D20x1.5 Z0..Z-10 lies outside the bore: "
                                        r"the part has no bore"):
        load_part(f)


def test_every_family_default_thread_fits(loaded):
    """The threaded stud's declared thread passes the checks for each parameter set (the
    model's major diameter under the thread)."""
    for i in range(len(FAMILIES["threaded_stud"])):
        lp = loaded("threaded_stud", i)
        (t,) = lp.threads
        on = [s for s in lp.profile.outside if isinstance(s, Line) and s.start[0] == s.end[0]]
        assert max(s.start[0] for s in on if s.start[1] > t.z_end - 1e-9) == pytest.approx(t.diameter / 2)


@pytest.mark.parametrize("fam", list(FAMILIES))
def test_step_export_of_every_family_profiles_the_same(tmp_path, fam):
    """Each family (defaults) written to STEP and read back gives the same profile, exactly
    (1e-6), with nothing fitted."""
    from build123d import Solid, export_step
    from hnc_cam.cad import profile
    mod = _family_module(fam)
    solid = mod.part()
    shape = solid if hasattr(solid, "wrapped") and not hasattr(solid, "vals") else Solid(solid.val().wrapped)
    export_step(shape, tmp_path / f"{fam}.step")
    src, back = profile(solid), profile(tmp_path / f"{fam}.step")
    for a, b in ((src.outside, back.outside), (src.bore or [], back.bore or [])):
        assert len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b)), (a, b)
    assert back.notes == []
