"""The manual's G71/G72/G73 examples, simulated from a stock that fits them with a sharp tool
(registers of radius 0), end exactly on their finishing contour; and G71 with a negative
allowance is caught as an overcut on the right line.

The models are built from the programs' own finishing contours with the kernel's Line/Arc
(no CAD); "exactly" is within 0.001 mm (the arcs' chord error is 0.0005). The default sharp tool is an 80 deg rhombic insert on a 95 deg holder (end cutting
edge angle 5 deg); where a contour descends more steeply than that behind the tool (3329's 45
deg groove flank) the test's machine file names a 35 deg insert (VNMG, 52 deg end angle), as a
real shop would: the 80 deg insert would gouge that flank, and the simulator says so."""
from __future__ import annotations

import pytest

from hnc_cam.geometry import Arc, Line, TurnedProfile, reverse_chain
from hnc_cam.nc.interp import run, run_file
from shapely.geometry import box

from hnc_cam.sim import simulate, stock_region, verify
from hnc_cam.tooling import Stock, load_machine

SHARP = "use_tool_library = false\n[machine]\nname = \"sharp\"\n"
SHARP_V = SHARP + "".join(
    f"[[register]]\nnumber = {n}\nradius = 0.0\ntip = 3\ninsert = \"VNMG160400\"\napproach = 93.0\n"
    for n in (1, 2))


def L(*pts):
    return [Line(a, b) for a, b in zip(pts[:-1], pts[1:])]


def A(a, b, r, cw):
    return Arc.from_radius(a, b, r, cw)


def machine(tmp_path, text):
    p = tmp_path / "m.toml"
    p.write_text(text)
    return load_machine(p)


def check(path, stock, model, mach, tol=0.001):
    tp = run_file(str(path), mach, start=mach.reference)
    m = simulate(tp, Stock.parse(stock) if isinstance(stock, str) else stock, mach, model=model)
    r = verify(m, model, tol=tol)
    assert not m.issues, m.summary()
    assert r.max_overcut_mm < tol and r.max_undercut_mm < tol, r.summary()
    assert r.passed, r.summary()
    return m, r


# 3327 / 3335 share the part: chamfer to dia 10, R5 fillet, dia 20, R7 round, dia 34, taper
P3327 = ([*L((0, 0), (3, 0), (5, -2), (5, -20)), A((5, -20), (10, -25), 5, True),
          *L((10, -25), (10, -35)), A((10, -35), (17, -42), 7, False),
          *L((17, -42), (17, -52), (22, -62))])


def test_3327_g71(manual, tmp_path):
    model = TurnedProfile(outside=[*P3327, *L((22, -62), (22, -82))])
    m, r = check(manual("3327.nc"), "46x100", model, machine(tmp_path, SHARP))
    assert r.air_cut_fraction < 0.9 and m.removed_volume_mm3 > 0


def test_3335_g73_from_offset_stock(manual, tmp_path):
    # a near-net blank 0.9 mm over the part all round, its right face already at Z0 (the
    # program's contour starts on the chamfer's extension and does not face the part)
    model = TurnedProfile(outside=[*P3327, *L((22, -62), (0, -62))])
    blank = stock_region(Stock.parse("offset:0.9"), model).intersection(box(-100, 0, 0, 100))
    m, r = check(manual("3335.nc"), blank, model, machine(tmp_path, SHARP))
    assert m.stock.bounds == pytest.approx((-62.9, 0, 0, 22.9))


def test_3329_g71_type2_grooves(manual, tmp_path):
    model = TurnedProfile(outside=[
        *L((0, 0), (8, 0), (10, -2), (10, -8)), A((10, -8), (14, -12), 4, True),
        *L((14, -12), (14, -17), (9, -22), (9, -30), (13.33, -32.5), (13.33, -37.5)),
        A((13.33, -37.5), (15.33, -51.5), 10, True), *L((15.33, -51.5), (15.33, -61.5))])
    check(manual("3329.nc"), "40x80", model, machine(tmp_path, SHARP_V))


def test_3329_with_80_deg_insert_gouges_the_groove_flank(manual, tmp_path):
    model = TurnedProfile(outside=[
        *L((0, 0), (8, 0), (10, -2), (10, -8)), A((10, -8), (14, -12), 4, True),
        *L((14, -12), (14, -17), (9, -22), (9, -30), (13.33, -32.5), (13.33, -37.5)),
        A((13.33, -37.5), (15.33, -51.5), 10, True), *L((15.33, -51.5), (15.33, -61.5))])
    mach = machine(tmp_path, SHARP)
    tp = run_file(str(manual("3329.nc")), mach, start=mach.reference)
    r = verify(simulate(tp, Stock.parse("40x80"), mach), model)
    assert not r.passed and r.max_overcut_mm > 0.5
    # the insert's trailing edge (5 deg) carves the dia 28 land behind the 45 deg down-cut
    # taper: blamed on the finishing block N13 (or the G71 roughing that follows the contour)
    text = manual("3329.nc").read_text().splitlines()
    lines = {i for i, l in enumerate(text, 1) if l.startswith(("N13 ", "N4G71"))}
    assert r.overcut_at.line in lines and -17.5 < r.overcut_at.z < -11.5


def test_3331fix_g72(manual, tmp_path):
    # program order: from the chuck side toward the face (G72), taper cut off at the stock dia 74
    z74 = -40 - 16 * 10 / 13
    prog = [*L((37, z74), (27, -40), (27, -30)), A((27, -30), (23, -26), 4, True),
            *L((23, -26), (15, -26), (15, -15), (7, -15)), A((7, -15), (5, -13), 2, False),
            *L((5, -13), (5, -2), (3, 0))]
    model = TurnedProfile(outside=[*L((0, 0), (3, 0)), *reverse_chain(prog)])
    check(manual("3331fix.nc"), "74x70", model, machine(tmp_path, SHARP))


G71_NEG = """%1
T0101
M03 S600
G00 X46 Z3
G71 U1.5 R1 P10 Q40 X-0.4 Z0.1 F150
G00 X80 Z80
M30
N10 G00 X20
N20 G01 Z-30 F100
N30 X40 Z-40
N40 Z-60
"""


def test_g71_negative_allowance_overcut(tmp_path):
    # the roughing runs 0.2 mm (radial) inside the finishing contour: overcut 0.2 on the
    # dia 20 and dia 40 portions, blamed on the G71 block
    mach = machine(tmp_path, SHARP)
    text = G71_NEG.replace("M30\n", "M30\n")
    tp = run(text, mach, file="neg.nc", start=mach.reference)
    model = TurnedProfile(outside=L((0, 0), (10, 0), (10, -30), (20, -40), (20, -60)))
    m = simulate(tp, Stock.parse("44x80"), mach)
    r = verify(m, model)
    assert not r.passed
    assert r.max_overcut_mm == pytest.approx(0.2, abs=0.002)
    g71_line = text.splitlines().index("G71 U1.5 R1 P10 Q40 X-0.4 Z0.1 F150") + 1
    assert r.overcut_at.line == g71_line
