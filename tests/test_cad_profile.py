"""Profile extraction: inputs, exactness, STEP round trip, spline fitting, conventions,
validation errors and the turned envelope."""
from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import pytest

from hnc_cam.cad import ProfileError, profile
from hnc_cam.geometry import Arc, Line, chain_is_connected, sample_chain

pytestmark = pytest.mark.cad

b3d = pytest.importorskip("build123d")
ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data"


def _family(name: str):
    spec = importlib.util.spec_from_file_location(f"fam_{name}", ROOT / "parts" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def shaft():
    return _family("stepped_shaft")


@pytest.fixture(scope="module")
def shaft_solid(shaft):
    return shaft.part()


def _same_chain(a, b, tol=1e-6):
    assert len(a) == len(b), (a, b)
    for s, t in zip(a, b):
        assert type(s) is type(t), (s, t)
        assert s.start == pytest.approx(t.start, abs=tol) and s.end == pytest.approx(t.end, abs=tol)
        if isinstance(s, Arc):
            assert s.cw == t.cw and s.center == pytest.approx(t.center, abs=tol)
            assert s.radius == pytest.approx(t.radius, abs=tol)


SPLINE_PTS = [(12, 0, 0), (14, 0, -10), (11, 0, -25), (15, 0, -40), (13, 0, -55)]


def _spline_part():
    from build123d import Axis, Edge, Face, Wire, revolve
    sp = Edge.make_spline(SPLINE_PTS)
    w = Wire([Edge.make_line((0, 0, 0), (12, 0, 0)), sp, Edge.make_line((13, 0, -55), (0, 0, -55)),
              Edge.make_line((0, 0, -55), (0, 0, 0))])
    return sp, revolve(Face(w), Axis.Z)


def _check_spline_fit(segs, spline, tol):
    """Arcs of the profile between z=0 and z=-55 stay within tol of the spline, both ways,
    measured at 2000 points of the spline and every 0.001 mm chord point of the arcs."""
    from build123d import Vector
    body = [s for s in segs if not (s.start[1] == s.end[1])]  # drop the end faces
    assert all(isinstance(s, (Line, Arc)) for s in body) and len(body) > 3
    assert chain_is_connected(body)
    # arcs, not a polyline in disguise: at most two lines, pieces of a useful length
    assert sum(isinstance(s, Line) for s in body) <= 2
    assert len(body) <= 60 * (0.001 / tol) ** 0.5 and min(s.length for s in body) > 0.2
    for a, b in zip(body, body[1:]):  # the spline is smooth: the chain has no real corner
        ta, tb = a.tangent_at_end(), b.tangent_at_start()  # (single-arc pieces keep only the
        assert ta[0] * tb[0] + ta[1] * tb[1] > math.cos(math.radians(1.0))  # start tangent)
    worst = 0.0
    for i in range(2001):
        q = spline.position_at(i / 2000)
        worst = max(worst, min(s.distance_to((q.X, q.Z)) for s in body))
    assert worst <= tol
    pts = sample_chain(body, 1e-3)
    worst2 = max(spline.distance_to(Vector(r, 0, z)) for r, z in pts[:: max(1, len(pts) // 400)])
    assert worst2 <= tol
    return worst, worst2


# ---------------------------------------------------------------------------- exactness
def test_profile_of_step_export_equals_source(shaft, shaft_solid):
    src = profile(shaft_solid)
    stp = profile(DATA / "stepped_shaft.step")
    _same_chain(stp.outside, src.outside)
    assert stp.bore is None and stp.notes == []
    # and the committed STEP file is family (1) with its defaults
    from hnc_cam.cad.fit import merge_segments
    _same_chain(stp.outside, merge_segments(shaft.sketch()))


def test_export_roundtrip_step_and_brep(tmp_path):
    from build123d import export_brep, export_step
    bush = _family("bushing")
    solid = bush.part(outer_diameter=52, bore_diameter=30, length=44)
    src = profile(solid)
    export_step(solid, tmp_path / "b.stp")
    export_brep(solid, tmp_path / "b.brep")
    for f in (tmp_path / "b.stp", str(tmp_path / "b.brep")):
        p = profile(f)
        _same_chain(p.outside, src.outside)
        _same_chain(p.bore, src.bore)


def test_all_bspline_model_still_exact(shaft, shaft_solid):
    """A model whose every face and edge is B-spline (as some CAD systems write STEP) still
    gives the exact lines and arcs (within 1e-6)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
    from hnc_cam.cad.fit import merge_segments
    nurbs = BRepBuilderAPI_NurbsConvert(shaft_solid.wrapped, True).Shape()
    p = profile(nurbs)
    _same_chain(p.outside, merge_segments(shaft.sketch()))
    assert any("free-form" in n and "sampling" in n for n in p.notes)


@pytest.mark.parametrize("tol", [0.0001, 0.001, 0.01])
def test_revolved_spline_fitted_with_arcs_within_tolerance(tol):
    spline, solid = _spline_part()
    p = profile(solid, fit_tol=tol)
    assert any("BSplineCurve" in n and f"within {tol:g} mm" in n for n in p.notes)
    _check_spline_fit(p.outside, spline, tol)
    assert p.outside[0] == Line((0.0, 0.0), (12.0, 0.0))
    assert p.outside[-1] == Line((13.0, -55.0), (0.0, -55.0))


def test_spline_step_from_elsewhere_fitted_within_tolerance():
    spline, _ = _spline_part()
    p = profile(DATA / "spline_knob.step")  # every face B-spline
    _check_spline_fit(p.outside, spline, 0.001)
    assert any("fitted" in n for n in p.notes)


# ---------------------------------------------------------------------------- inputs/options
def test_inputs_of_every_kind(shaft_solid):
    import cadquery as cq
    from build123d import BuildPart, Compound, Cylinder
    ref = profile(shaft_solid).outside
    _same_chain(profile(shaft_solid.wrapped).outside, ref)          # OCP TopoDS_Shape
    _same_chain(profile(Compound([shaft_solid])).outside, ref)      # build123d Compound
    _same_chain(profile(cq.Shape.cast(shaft_solid.wrapped)).outside, ref)  # CadQuery Shape
    _same_chain(profile(cq.Workplane().add(cq.Shape.cast(shaft_solid.wrapped))).outside, ref)
    with BuildPart() as bp:
        Cylinder(10, 30)
    p = profile(bp)
    assert [type(s) for s in p.outside] == [Line, Line, Line]
    assert p.outside[1] == Line((10.0, 0.0), (10.0, -30.0))
    with pytest.raises(ProfileError, match="cannot profile a int"):
        profile(42)


def test_axis_option_and_program_zero(shaft_solid):
    from build123d import Pos, Rot
    ref = profile(shaft_solid)
    along_x = Rot(0, 90, 0) * shaft_solid  # model axis now +X
    _same_chain(profile(along_x, axis="X").outside, ref.outside)
    off = Pos(5, -3, 20) * shaft_solid
    _same_chain(profile(off, axis=((5, -3, 0), (0, 0, 1))).outside, ref.outside)
    with pytest.raises(ProfileError, match=r"not a body of revolution about the Z axis: .*every "
                                           r"round face is about the axis through \(5, -3, 0\) "
                                           r"along \(0, 0, 1\): axis=\(\(5, -3, 0\), \(0, 0, 1\)\)\?"):
        profile(off)
    with pytest.raises(ProfileError, match=r"about the model's X axis: axis=\"X\" or \"-X\"\?"):
        profile(along_x)
    left = profile(shaft_solid, zero="left")
    assert left.z_min == pytest.approx(0.0) and left.z_max == pytest.approx(100.0)
    assert left.outside[0].start == (0.0, 100.0)
    num = profile(shaft_solid, zero=-50.0)  # model Z=-50 becomes Z0
    assert num.z_max == pytest.approx(50.0) and num.z_min == pytest.approx(-50.0)
    assert ref.length == pytest.approx(100.0) and ref.max_diameter == pytest.approx(40.0)
    assert ref.bbox() == pytest.approx((0.0, -100.0, 20.0, 0.0))
    for bad in ({"axis": "W"}, {"axis": ((0, 0, 0),)}, {"zero": "middle"}, {"fit_tol": 0}):
        with pytest.raises(ProfileError):
            profile(shaft_solid, **bad)


def test_blind_bore_and_left_centre_hole_conventions():
    """Bore opening on the right: outside starts at the bore edge of the right face, bore runs
    into the hole and ends on the axis. A hole opening only on the left is in neither chain."""
    from build123d import Axis, Edge, Face, Wire, revolve
    from hnc_cam.cad.sketch import Outline
    s = (Outline((6.0, 0.0)).line_to(15.0, 0.0).line_to(15.0, -40.0).line_to(2.0, -40.0)
         .line_to(2.0, -35.0).line_to(0.0, -35.0))
    # the loop continues along the axis to (0, -20), then the blind bore back to (6, 0)
    segs = s.segments() + [Line((0.0, -35.0), (0.0, -20.0)), Line((0.0, -20.0), (6.0, -20.0)),
                           Line((6.0, -20.0), (6.0, 0.0))]
    edges = [Edge.make_line((a.start[0], 0, a.start[1]), (a.end[0], 0, a.end[1])) for a in segs]
    solid = revolve(Face(Wire(edges)), Axis.Z)
    p = profile(solid)
    assert p.outside == [Line((6.0, 0.0), (15.0, 0.0)), Line((15.0, 0.0), (15.0, -40.0)),
                         Line((15.0, -40.0), (2.0, -40.0))]
    assert p.bore == [Line((6.0, 0.0), (6.0, -20.0)), Line((6.0, -20.0), (0.0, -20.0))]
    assert any("cavity opening on the left face" in n for n in p.notes)


# ---------------------------------------------------------------------------- validation
def test_keyway_named(shaft_solid):
    from build123d import Box, Pos
    keyed = shaft_solid - Pos(0, 14, -38) * Box(8, 8, 20)  # 4 mm deep on the d28 journal
    with pytest.raises(ProfileError) as e:
        profile(keyed)
    msg = str(e.value)
    assert "not a body of revolution about the Z axis" in msg
    assert "planar face parallel to the axis (a wall of a keyway or slot 8.000 wide)" in msg
    assert "z=-" in msg and "envelope=True" in msg
    env = profile(keyed, envelope=True)
    _same_chain(env.outside, profile(shaft_solid).outside)
    ignored = [n for n in env.notes if n.startswith("ignored (envelope)")]
    assert len(ignored) == 3 and all("planar face parallel to the axis" in n for n in ignored)


def test_cross_hole_named(shaft_solid):
    from build123d import Cylinder, Pos, Rot
    holed = shaft_solid - Pos(0, 0, -80) * Rot(0, 90, 0) * Cylinder(3, 60)
    with pytest.raises(ProfileError, match=r"cross hole or cross pin of diameter 6\.000.*z=-80\.000"):
        profile(holed)
    env = profile(holed, envelope=True)
    _same_chain(env.outside, profile(shaft_solid).outside)
    assert any("cross hole" in n for n in env.notes)
    assert not any("fitted" in n for n in env.notes)  # the hole's ellipse is not in the outline


def test_flat_double_d_square_and_radial_hole_named(shaft_solid):
    from build123d import Box, Cylinder, Pos, Rot
    flat = shaft_solid - Pos(0, 22, -38) * Box(40, 20, 20)  # a flat 12 mm from the axis
    with pytest.raises(ProfileError, match=r"\(a flat 12\.000 from the axis\).*z=-38\.000"):
        profile(flat)
    double_d = flat - Pos(0, -22, -38) * Box(40, 20, 20)
    with pytest.raises(ProfileError, match=r"two parallel flats 24\.000 apart"):
        profile(double_d)
    with pytest.raises(ProfileError, match=r"a square, 20\.000 across flats"):
        profile(Box(20, 20, 40))
    radial = shaft_solid - Pos(0, 17, -80) * Rot(90, 0, 0) * Cylinder(2, 10)
    with pytest.raises(ProfileError, match=r"radial hole .* diameter 4\.000\) at .*z=-80\.000"):
        profile(radial)


def test_off_axis_hole_named(shaft_solid):
    from build123d import Cylinder, Pos
    holed = shaft_solid - Pos(8, 0, -100) * Cylinder(2, 30)
    with pytest.raises(ProfileError, match=r"eccentric.*diameter 4\.000, axis 8\.000 mm off centre"):
        profile(holed)


def test_hex_named_and_its_envelope_is_the_circumscribed_cylinder():
    from build123d import RegularPolygon, extrude
    hexbar = extrude(RegularPolygon(15, 6), 40)
    with pytest.raises(ProfileError, match=r"planar face parallel to the axis \(a hex, 25\.981 across flats\) "
                                          r"at x=.* z=20\.000"):
        profile(hexbar)
    env = profile(hexbar, envelope=True)  # every half-plane touches a flat: through a corner
    assert env.outside == [Line((0.0, 0.0), (15.0, 0.0)), Line((15.0, 0.0), (15.0, -40.0)),
                           Line((15.0, -40.0), (0.0, -40.0))]
    assert sum(n.startswith("ignored (envelope)") and "a hex" in n for n in env.notes) == 6
    assert any("through a corner of the non-turned faces" in n for n in env.notes)


def test_chamfered_hex_nut_envelope_is_the_turned_blank():
    """A hex nut AF24 with 30 deg turned chamfers and a bore: the envelope is the turned blank
    it was cut from (circumscribed diameter, the chamfer cones, the bore), exactly."""
    from build123d import Pos, RegularPolygon, extrude
    from hnc_cam.cad.sketch import Outline, revolve
    R = 24 / math.sqrt(3)
    k = (R - 12) * math.tan(math.radians(60))
    turned = revolve(Outline((8.5, 0.0)).line_to(12.0, 0.0).line_to(R, -k).line_to(R, -20 + k)
                     .line_to(12.0, -20.0).line_to(8.5, -20.0).close().segments())
    nut = turned & (Pos(0, 0, -20) * extrude(RegularPolygon(R, 6), 20))
    with pytest.raises(ProfileError, match=r"a hex, 24\.000 across flats"):
        profile(nut)
    env, ref = profile(nut, envelope=True), profile(turned)
    _same_chain(env.outside, ref.outside)
    _same_chain(env.bore, ref.bore)
    assert env.max_diameter == pytest.approx(2 * R, abs=1e-9)


def test_envelope_not_one_section_is_a_stated_limit():
    """A square whose corners are not at the hex's corners: no single meridian section holds
    the envelope; the error says so instead of returning a section that cuts a corner."""
    from build123d import Align, Box, Pos, RegularPolygon, Rot, extrude
    sq = (Pos(0, 0, -10) * Rot(0, 0, 30) * Box(20, 20, 10, align=(Align.CENTER, Align.CENTER, Align.MIN))
          + Pos(0, 0, -30) * extrude(RegularPolygon(12, 6), 20))
    with pytest.raises(ProfileError, match="no single section through a corner of those faces "
                                           "contains the others"):
        profile(sq, envelope=True)


def test_partial_revolution_rejected():
    from build123d import Axis, Plane, Rectangle, revolve
    sector = revolve(Plane.XZ * Rectangle(10, 20, align=None).translate((5, 0, 0)), Axis.Z, 180)
    with pytest.raises(ProfileError, match="planar face parallel to the axis"):
        profile(sector)


def test_not_a_solid_several_solids_empty():
    from build123d import Compound, Cylinder, Face, Pos, Rectangle
    with pytest.raises(ProfileError, match="not a solid"):
        profile(Face(Rectangle(10, 10).wire()))
    with pytest.raises(ProfileError, match="not a solid"):
        profile(Cylinder(10, 20).shell())
    two = Compound([Cylinder(10, 20), Pos(0, 0, 40) * Cylinder(8, 10)])
    with pytest.raises(ProfileError, match=r"several disconnected solids \(2\)"):
        profile(two)
    with pytest.raises(ProfileError, match="empty geometry"):
        profile(Compound([]))


def test_internal_void_rejected():
    from build123d import Cylinder, Sphere
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    cut = BRepAlgoAPI_Cut(Cylinder(10, 30).wrapped, Sphere(4).wrapped).Shape()
    with pytest.raises(ProfileError, match="internal void"):
        profile(cut)


def test_bad_files(tmp_path):
    with pytest.raises(ProfileError, match="no such file"):
        profile(tmp_path / "x.step")
    bad = tmp_path / "x.step"
    bad.write_text("not a step file\n")
    with pytest.raises(ProfileError, match="not a readable STEP file"):
        profile(bad)
    igs = tmp_path / "x.igs"
    igs.write_text("")
    with pytest.raises(ProfileError, match="unknown CAD file type"):
        profile(igs)


def test_revolved_volume_closed_form():
    from hnc_cam.cad.extract import revolved_volume
    cyl = [Line((0.0, 0.0), (10.0, 0.0)), Line((10.0, 0.0), (10.0, -30.0)),
           Line((10.0, -30.0), (0.0, -30.0))]
    assert revolved_volume(cyl) == pytest.approx(math.pi * 100 * 30, rel=1e-12)
    ball = [Arc((0.0, 5.0), (0.0, -5.0), (0.0, 0.0), True)]  # half circle, r=5
    assert revolved_volume(ball) == pytest.approx(4 / 3 * math.pi * 125, rel=1e-12)
    cone = [Line((0.0, 0.0), (6.0, -9.0)), Line((6.0, -9.0), (0.0, -9.0))]
    assert revolved_volume(cone) == pytest.approx(math.pi * 36 * 9 / 3, rel=1e-12)


def test_volume_check_is_a_safety_net(shaft_solid, monkeypatch):
    """Should the face classification miss a milled feature, the volume comparison of the
    solid with the revolution of its section still refuses the part."""
    from build123d import Box, Pos
    from hnc_cam.cad import occ
    keyed = shaft_solid - Pos(0, 14, -38) * Box(8, 8, 20)
    monkeypatch.setattr(occ, "classify_faces", lambda shape: ([], []))
    with pytest.raises(ProfileError, match="differs from the revolution of its section"):
        profile(keyed)


def test_ellipsoidal_dome_fitted_and_rest_exact():
    """A revolved quarter ellipse (semi-axes 20 radial, 8 axial) on a cylinder: the dome is
    arcs within tolerance of the true ellipse, the program zero is its apex, and the lines
    after it stay exact (OpenCascade's approximate cut is projected back onto the surface)."""
    from build123d import Axis, Edge, Face, Plane, Wire, revolve
    el = Edge.make_ellipse(20, 8, Plane.XZ, start_angle=0, end_angle=90)
    w = Wire([el, Edge.make_line((0, 0, 8), (0, 0, -30)), Edge.make_line((0, 0, -30), (20, 0, -30)),
              Edge.make_line((20, 0, -30), (20, 0, 0))])
    p = profile(revolve(Face(w), Axis.Z), fit_tol=0.001)
    assert p.outside[0].start == (0.0, 0.0)
    assert p.outside[-2:] == [Line((20.0, -8.0), (20.0, -38.0)), Line((20.0, -38.0), (0.0, -38.0))]
    dome = p.outside[:-2]
    assert all(isinstance(s, Arc) for s in dome) and chain_is_connected(dome)
    worst = max(min(s.distance_to((20 * math.cos(t), 8 * math.sin(t) - 8)) for s in dome)
                for t in (math.pi / 2 * i / 3000 for i in range(3001)))
    assert worst <= 0.001
    assert any("fitted with" in n for n in p.notes)


# ---------------------------------------------------------------------------- split pieces
def _raw_section(shape, theta=0.3):
    from hnc_cam.cad import occ
    return occ.meridian_section(shape, theta, occ.bbox(shape))


def _revolve_unmerged(edges):
    """OCP revolve of a wire of build123d edges, without any unification (each edge gives
    its own face)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeRevol
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt
    mw = BRepBuilderAPI_MakeWire()
    for e in edges:
        mw.Add(e.wrapped)
    face = BRepBuilderAPI_MakeFace(mw.Wire(), True).Face()
    return BRepPrimAPI_MakeRevol(face, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 2 * math.pi).Shape()


def test_pieces_split_by_faces_are_merged():
    """A dome arc modelled as two arcs (two spherical faces), the cylinder as two lines (two
    faces) and the end face as two lines: the section has 7 pieces, the profile 3 exact
    segments (end points, centre and radius to 1e-9)."""
    from build123d import Edge
    R = 10.0

    def pa(a):  # point of the dome at a degrees from the apex, in the XZ plane
        return (R * math.sin(math.radians(a)), 0, -R + R * math.cos(math.radians(a)))
    edges = [Edge.make_three_point_arc(pa(0), pa(22.5), pa(45)),
             Edge.make_three_point_arc(pa(45), pa(67.5), pa(90)),
             Edge.make_line((R, 0, -R), (R, 0, -25)), Edge.make_line((R, 0, -25), (R, 0, -40)),
             Edge.make_line((R, 0, -40), (5, 0, -40)), Edge.make_line((5, 0, -40), (0, 0, -40)),
             Edge.make_line((0, 0, -40), (0, 0, 0))]
    solid = _revolve_unmerged(edges)
    raw = _raw_section(solid)
    assert len(raw) == 6 and sum(e.kind == "circle" for e in raw) == 2  # really split
    p = profile(solid)
    assert p.outside == [Arc((0.0, 0.0), (10.0, -10.0), (0.0, -10.0), False),
                         Line((10.0, -10.0), (10.0, -40.0)), Line((10.0, -40.0), (0.0, -40.0))]


def test_face_split_by_an_imprinted_edge_is_merged():
    """Two cylinders fused without unification: the cylindrical face is split by the circle
    where they meet; and a ball fused on a cylinder whose own pole axis is X, turned so that
    the ball's seam lies in the default meridian half-plane."""
    from build123d import Align, Cylinder, Pos, Rot, Solid, Sphere
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
    mn = (Align.CENTER, Align.CENTER, Align.MIN)

    def fuse(a, b):
        f = BRepAlgoAPI_Fuse(a.wrapped, b.wrapped)
        f.Build()
        return f.Shape()
    two = fuse(Cylinder(10, 20, align=mn), Pos(0, 0, 20) * Cylinder(10, 20, align=mn))
    raw = _raw_section(two)
    assert sum(e.kind == "line" and abs(e.rz(e.first)[0] - 10) < 1e-9 for e in raw) == 2
    assert profile(two).outside == [Line((0.0, 0.0), (10.0, 0.0)), Line((10.0, 0.0), (10.0, -40.0)),
                                    Line((10.0, -40.0), (0.0, -40.0))]
    ball = fuse(Cylinder(10, 30, align=(Align.CENTER, Align.CENTER, Align.MAX)),
                Rot(0, -90, 0) * Sphere(10))  # the sphere's seam meridian is in y = 0
    turned = (Rot(0, 0, math.degrees(0.3)) * Solid(ball)).wrapped  # ... now at 0.3 rad
    assert profile(turned).outside == [Arc((0.0, 0.0), (10.0, -10.0), (0.0, -10.0), False),
                                       Line((10.0, -10.0), (10.0, -40.0)),
                                       Line((10.0, -40.0), (0.0, -40.0))]


@pytest.mark.parametrize("rad", [0.3, 1.1, 2.3])
def test_revolve_seam_in_the_section_half_plane(shaft, shaft_solid, rad):
    """The seam every revolve leaves at angle 0, turned into each half-plane the section
    uses: the profile is the same, exactly."""
    from build123d import Rot
    from hnc_cam.cad.fit import merge_segments
    assert profile(Rot(0, 0, math.degrees(rad)) * shaft_solid).outside == profile(shaft_solid).outside
    _same_chain(profile(Rot(0, 0, math.degrees(rad)) * shaft_solid).outside,
                merge_segments(shaft.sketch()), tol=1e-9)


# ---------------------------------------------------------------------------- more inputs
def test_more_input_kinds(tmp_path, shaft_solid):
    """build123d Part (algebra result), a CadQuery Workplane built in CadQuery (with a
    chamfer and a fillet), a CadQuery Solid, an OCP TopoDS_Solid, str and Path file names,
    upper-case suffixes."""
    import cadquery as cq
    from build123d import Cylinder, Part, Pos, export_brep, export_step
    part = Cylinder(20, 50) - Pos(0, 0, 20) * Cylinder(8, 10)  # a blind bore on the right face
    assert isinstance(part, Part)
    p = profile(part)
    assert p.outside == [Line((8.0, 0.0), (20.0, 0.0)), Line((20.0, 0.0), (20.0, -50.0)),
                         Line((20.0, -50.0), (0.0, -50.0))]
    assert p.bore == [Line((8.0, 0.0), (8.0, -10.0)), Line((8.0, -10.0), (0.0, -10.0))]
    wp = cq.Workplane("XY").circle(12).extrude(30).faces(">Z").chamfer(2).faces("<Z").fillet(3)
    q = profile(wp)
    assert q.outside == [Line((0.0, 0.0), (10.0, 0.0)), Line((10.0, 0.0), (12.0, -2.0)),
                         Line((12.0, -2.0), (12.0, -27.0)),
                         Arc((12.0, -27.0), (9.0, -30.0), (9.0, -27.0), False),  # G03
                         Line((9.0, -30.0), (0.0, -30.0))]
    _same_chain(profile(wp.val()).outside, q.outside)              # cq.Solid
    _same_chain(profile(wp.faces(">Z").workplane()).outside, q.outside)  # chain, no solid on top
    with pytest.raises(ProfileError, match="the CadQuery Workplane holds no shape"):
        profile(cq.Workplane("XY"))
    _same_chain(profile(wp.val().wrapped).outside, q.outside)      # OCP TopoDS_Solid
    export_step(shaft_solid, tmp_path / "S.STP")
    export_brep(shaft_solid, tmp_path / "S.BREP")
    ref = profile(shaft_solid).outside
    for f in (tmp_path / "S.STP", str(tmp_path / "S.BREP")):
        _same_chain(profile(f).outside, ref)


def test_part_modelled_along_x_and_reversed_axes(shaft_solid):
    """A shaft modelled along +X (revolved about the X axis in build123d), profiled with
    axis="X"; the same shaft along -X with axis="-X"; along Y; and a direction given as a
    non-unit vector through a point off the origin. zero="left" and an explicit offset with
    a non-Z axis."""
    from build123d import Axis, Edge, Face, Plane, Pos, Rot, Wire, mirror, revolve
    pts = [(0, 0), (0, 8), (-30, 8), (-30, 12), (-60, 12), (-60, 0)]  # (x, radius in y)
    w = Wire([Edge.make_line((a[0], a[1], 0), (b[0], b[1], 0)) for a, b in zip(pts, pts[1:] + pts[:1])])
    along_x = revolve(Face(w), Axis.X)
    p = profile(along_x, axis="X")
    assert p.outside == [Line((0.0, 0.0), (8.0, 0.0)), Line((8.0, 0.0), (8.0, -30.0)),
                         Line((8.0, -30.0), (12.0, -30.0)), Line((12.0, -30.0), (12.0, -60.0)),
                         Line((12.0, -60.0), (0.0, -60.0))]
    flipped = mirror(along_x, Plane.YZ)  # now from x=0 to x=+60, the small end at x=0
    _same_chain(profile(flipped, axis="-X").outside, p.outside)
    _same_chain(profile(Rot(0, 0, 90) * along_x, axis="Y").outside, p.outside)
    moved = Pos(3, 4, 5) * along_x
    _same_chain(profile(moved, axis=((0, 4, 5), (2.5, 0, 0))).outside,
                p.outside)
    left = profile(along_x, axis="X", zero="left")
    assert left.z_min == pytest.approx(0.0) and left.z_max == pytest.approx(60.0)
    assert left.outside[0] == Line((0.0, 60.0), (8.0, 60.0))
    off = profile(along_x, axis="X", zero=-30.0)  # model x = -30 (the step) becomes Z0
    assert off.z_max == pytest.approx(30.0) and off.outside[2] == Line((8.0, 0.0), (12.0, 0.0))
    with pytest.raises(ProfileError, match="not a body of revolution about the Z axis"):
        profile(along_x)  # wrong axis: the cylinder faces are not about Z


def test_face_location_in_model_coordinates_with_another_axis():
    """With axis="X" the offending face is still located in the user's model coordinates."""
    from build123d import Cylinder, Pos, Rot
    shaft = Rot(0, 90, 0) * (Cylinder(10, 40) - Pos(0, 0, 5) * Rot(90, 0, 0) * Cylinder(2, 30))
    with pytest.raises(ProfileError, match=r"about the X axis: .*cross hole or cross pin of "
                                           r"diameter 4\.000\) at x=5\.000 y=-?0\.000 z=-?0\.000 \(model\)"):
        profile(shaft, axis="X")


def test_null_and_edge_only_shapes_are_empty():
    from build123d import Edge, Wire
    from OCP.TopoDS import TopoDS_Shape
    with pytest.raises(ProfileError, match="empty geometry: the shape is null"):
        profile(TopoDS_Shape())
    with pytest.raises(ProfileError, match="empty geometry: the shape holds no solid and no face"):
        profile(Wire([Edge.make_line((0, 0, 0), (10, 0, 0))]))


def test_eccentric_boss_and_oblique_cut_named_with_envelopes(shaft_solid):
    """An eccentric pin on the left end (its turned envelope: radius offset + pin radius) and
    a corner cut off at 45 deg (an oblique plane)."""
    from build123d import Align, Box, Cylinder, Pos, Rot
    boss = shaft_solid + Pos(3, 0, -100) * Cylinder(5, 10, align=(Align.CENTER, Align.CENTER, Align.MAX))
    with pytest.raises(ProfileError, match=r"eccentric\) cylinder or axial hole of diameter 10\.000, "
                                           r"axis 3\.000 mm off centre\) at x=3\.000 .*z=-105\.000"):
        profile(boss)
    env = profile(boss, envelope=True)
    assert env.outside[-2:] == [Line((8.0, -100.0), (8.0, -110.0)), Line((8.0, -110.0), (0.0, -110.0))]
    assert any("at 0.0 deg (through a corner" in n for n in env.notes)
    cut = shaft_solid - Pos(0, 20, -100) * Rot(45, 0, 0) * Box(50, 10, 10)
    with pytest.raises(ProfileError, match=r"planar face oblique to the axis \(a bevel or cut not "
                                           r"turned about the axis\) at x=0\.000 y=15\.828 z=-97\.101"):
        profile(cut)
    assert profile(cut, envelope=True).outside == profile(shaft_solid).outside


def test_revolved_degree1_bspline_polyline_gives_exact_lines():
    """Some exporters write a polyline as a degree-1 B-spline: its revolution is one free-form
    face with creases. The profile is its lines within 1e-6 (nothing fitted), and the volume
    check (OpenCascade integrates such a face poorly) does not refuse it."""
    from build123d import Axis, Edge, Face, Wire, revolve
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.Geom import Geom_BSplineCurve
    from OCP.gp import gp_Pnt
    from OCP.TColgp import TColgp_Array1OfPnt
    from OCP.TColStd import TColStd_Array1OfInteger, TColStd_Array1OfReal
    rz = [(12, 0), (12, -10), (15, -15), (15, -30), (10, -40)]
    n = len(rz)
    P, K, M = TColgp_Array1OfPnt(1, n), TColStd_Array1OfReal(1, n), TColStd_Array1OfInteger(1, n)
    for i, (r, z) in enumerate(rz):
        P.SetValue(i + 1, gp_Pnt(r, 0, z))
        K.SetValue(i + 1, float(i))
        M.SetValue(i + 1, 2 if i in (0, n - 1) else 1)
    poly = Edge(BRepBuilderAPI_MakeEdge(Geom_BSplineCurve(P, K, M, 1)).Edge())
    w = Wire([Edge.make_line((0, 0, 0), (12, 0, 0)), poly, Edge.make_line((10, 0, -40), (0, 0, -40)),
              Edge.make_line((0, 0, -40), (0, 0, 0))])
    p = profile(revolve(Face(w), Axis.Z))
    pts = [(0, 0)] + rz + [(0, -40)]
    _same_chain(p.outside, [Line(a, b) for a, b in zip(pts, pts[1:])], tol=1e-6)
    assert not any("fitted" in note for note in p.notes)


def test_square_bar_and_double_d_envelopes(shaft_solid):
    """A square bar's envelope is its circumscribed cylinder; a double-D shaft's is the round
    shaft (a half-plane between the flats is clean)."""
    from build123d import Box, Pos
    sq = profile(Pos(0, 0, -20) * Box(20, 20, 40), envelope=True)
    r = math.hypot(10, 10)
    _same_chain(sq.outside, [Line((0.0, 0.0), (r, 0.0)), Line((r, 0.0), (r, -40.0)),
                             Line((r, -40.0), (0.0, -40.0))], tol=1e-9)
    double_d = (shaft_solid - Pos(0, 22, -38) * Box(40, 20, 20)) - Pos(0, -22, -38) * Box(40, 20, 20)
    env = profile(double_d, envelope=True)
    assert env.outside == profile(shaft_solid).outside
    assert sum(n.startswith("ignored (envelope)") for n in env.notes) == 2
