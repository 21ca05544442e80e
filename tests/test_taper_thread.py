"""Taper threads (NPT/BSPT-like, 1:16 on the diameter): the part declares the taper, every
threading pass follows it (positions from the interpreted toolpath), the part verifies in
every dialect that writes the taper word, and bad tapers are refused."""
from __future__ import annotations

from pathlib import Path

import pytest

from hnc_cam.errors import PartError, PlanError
from hnc_cam.geometry import Thread, TurnedProfile
from hnc_cam.plan.api import generate

from test_plan_shapes import chain

PART = Path(__file__).parent / "data" / "turning_parts" / "taper_thread.py"
#: the part's thread: M20x1.5, 20 mm at its large end Z-14, 1/16 smaller per mm toward Z0
TH = Thread(z_start=0.0, z_end=-14.0, diameter=20.0, pitch=1.5, taper=1 / 16)


def _root(z: float) -> float:
    """The taper root's radius at ``z``: the major radius less the thread depth."""
    return TH.major_at(z) / 2 - TH.depth


def _legs(prog):
    """The threading legs along the thread (the run-in and run-out legs left out)."""
    return [m for m in prog.toolpath.moves if m.kind == "thread" and abs(m.end[1] - m.start[1]) > 5]


def test_major_diameter_follows_the_taper_and_the_minor_is_measured_from_the_small_end():
    assert TH.major_at(-14.0) == pytest.approx(20.0)
    assert TH.major_at(0.0) == pytest.approx(20.0 - 14 / 16)
    # one pitch in from the small end, where the verification measures from
    assert TH.minor_diameter == pytest.approx(TH.major_at(-1.5) - 2 * TH.depth)
    assert Thread(0.0, -14.0, 20.0, 1.5).minor_diameter == pytest.approx(20 - 1.2269 * 1.5,
                                                                         abs=1e-3)
    neg = Thread(0.0, -14.0, 20.0, 1.5, taper=-1 / 16)  # largest at the right end
    assert neg.major_at(0.0) == pytest.approx(20.0) and neg.major_at(-14.0) < 20.0


@pytest.mark.parametrize("dialect,cycle", [("hnc21t", "g76"), ("hnc21t", "g82"),
                                           ("fanuc0it", "g76"), ("fanuc0it", "g82"),
                                           ("haas", "g76"), ("siemens802", "g76")])
@pytest.mark.parametrize("comp", ["cam", "control"])
def test_threading_passes_follow_the_taper_and_the_part_verifies(dialect, cycle, comp):
    prog = generate(PART, dialect=dialect, thread_cycle=cycle, comp=comp)
    assert prog.report.passed, prog.report.summary()
    legs = _legs(prog)
    assert len(legs) >= 5
    for m in legs:  # each pass climbs 1/32 on the radius per mm toward the thread's end
        slope = (m.end[0] - m.start[0]) / (m.end[1] - m.start[1])
        assert slope == pytest.approx(-1 / 32, abs=1.5e-3)
    # the deepest pass lies on the taper root (the flank infeed shifts it along Z by at most
    # the depth x tan 30 deg, 0.017 mm of radius on this taper)
    last = min(legs, key=lambda m: m.end[0] - _root(m.end[1]))
    for x, z in (last.start, last.end):
        if -14.0 <= z <= 0.0:
            assert x == pytest.approx(_root(z), abs=0.02)
    assert last.end[0] == pytest.approx(_root(last.end[1]), abs=0.02)
    # the thread's root diameter, measured on the simulated part, meets the standard at
    # its small end and is 14/16 mm larger at its large end
    th = prog.report.threads[0]
    assert abs(th.achieved_diameter - th.target_diameter) <= 0.05


def test_the_cone_declared_as_a_straight_thread_is_refused():
    # the same cone with the thread declared straight: only its last 0.64 mm stands at the
    # 20 mm major diameter, too short for a thread at full form
    prof = TurnedProfile(chain((0, 0), (8.76, 0), (9.5875, -0.8), (10, -14), (8.9, -15.905),
                               (8.9, -18), (13, -18), (13, -35), (0, -35)),
                         threads=[Thread(0.0, -14.0, 20.0, 1.5)], name="straight")
    with pytest.raises(PlanError, match="too short to reach full depth"):
        generate(prof, stock="30x40+1", verify=False)
    # declared with its taper, the same profile threads
    tapered = TurnedProfile(prof.outside, threads=[TH], name="tapered")
    assert generate(tapered, stock="30x40+1").report.passed


def test_internal_taper_thread_is_refused():
    prof = TurnedProfile(chain((10.2, 0), (19, 0), (19, -30), (10.2, -30)),
                         bore=chain((10.2, 0), (10.2, -30)),
                         threads=[Thread(0.0, -12.0, 22.0, 1.5, internal=True, taper=1 / 16)],
                         name="socket")
    with pytest.raises(PlanError, match="internal taper thread is not supported"):
        generate(prof, stock="40/18x35+1", verify=False)


@pytest.mark.parametrize("spec,taper", [("M20x1.5@0:-14,taper=1:16", 0.0625),
                                        ("M20x1.5@0:-14,taper=0.0625", 0.0625),
                                        ("M20x1.5@0:-14,taper=-1:16", -0.0625)])
def test_thread_option_reads_a_taper(spec, taper):
    from hnc_cam.cad.loader import parse_thread
    assert parse_thread(spec).taper == pytest.approx(taper)


@pytest.mark.parametrize("spec,what", [("M20x1.5@0:-14,taper=1:0", "not understood"),
                                       ("M20x1.5@0:-14,taper=x", "not understood"),
                                       ("M20x1.5@0:-14,taper=1:2", "taper=0.5"),
                                       ("M20x1.5@0:-14,taper=nan", "taper=nan"),
                                       ("M20x1.5@-2:-14,internal,taper=1:16", "internal taper")])
def test_bad_taper_is_one_error_naming_it(spec, what):
    from hnc_cam.cad.loader import parse_thread
    with pytest.raises(PartError, match=what):
        parse_thread(spec)


def test_taper_thread_on_a_cylinder_is_refused_where_the_part_stands_above_it(tmp_path):
    # the taper declared on the straight M20 of the bundled stud: at the right end the part
    # stands 0.875 mm above the taper's major diameter
    from hnc_cam.cli import main
    out = tmp_path / "o.nc"
    rc = main(["generate", "parts/threaded_stud.py", "--thread", "M20x1.5@-1:-15,taper=1:16",
               "-o", str(out)])
    assert rc == 2 and not out.exists()


def test_a_straight_thread_at_the_small_ends_root_fails_the_taper():
    """The program's G76 without its taper (I), at the root the small end needs: the thread is
    right at the small end and 14/16 mm too deep on the diameter at the large end, which the
    root measured against the taper at every Z finds."""
    import re
    from hnc_cam.nc.interp import run
    from hnc_cam.sim import simulate, verify
    from hnc_cam.tooling import Stock, load_machine
    prog = generate(PART)
    assert prog.report.threads[0].ok
    small_root = prog.report.threads[0].target_diameter
    g76 = re.search(r"^(N\d+ G76 .*) X[\d.]+ (Z-?[\d.]+) I-?[\d.]+ ", prog.text, re.M)
    assert g76
    bad = prog.text.replace(g76.group(0), f"{g76.group(1)} X{small_root:.3f} {g76.group(2)} ")
    mach = load_machine(None)
    tp = run(bad, mach)
    legs = [m for m in tp.moves if m.kind == "thread"]
    assert max(abs(m.end[0] - m.start[0]) for m in legs) < 1e-9  # straight passes now
    rep = verify(simulate(tp, Stock.parse(prog.plan.stock.spec), mach), prog.plan.profile)
    (th,) = rep.threads
    assert not th.ok and not rep.passed
    # 1:16 over the length measured: the 14 mm thread less a pitch at its free end and the
    # run-out the collar forces at the other (verify.WALL_RUNOUT pitches): 0.5 mm too deep
    from hnc_cam.sim.verify import WALL_RUNOUT
    measured = 14.0 - 1.5 - WALL_RUNOUT * 1.5
    assert th.achieved_diameter - th.target_diameter == pytest.approx(-measured / 16, abs=0.02)
