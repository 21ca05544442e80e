"""The interpreter's side of the cycle and compensation contracts, checked with stand-ins
for the cycle and compensation modules (so these tests do not depend on them)."""
from __future__ import annotations

import pytest

from hnc_cam.errors import NCError
from hnc_cam.geometry import Arc, Line
from hnc_cam.nc import cycles, run
from hnc_cam.tooling import Machine, Register


@pytest.fixture
def calls(monkeypatch):
    seen = []

    def fake(code, ctx):
        seen.append((code, ctx))
        if code in (71, 72, 73):
            ctx.profile_result = ctx.profile(int(ctx.word("P")), int(ctx.word("Q")))
            x0, z0 = ctx.pos
            ctx.feed(x0 - 1, z0)
            ctx.rapid(x0, z0)
        else:
            ctx.words = {k: ctx.word(k) for k in "XZIKRF" if ctx.has(k)}
            ctx.start = ctx.pos
            ctx.rapid(ctx.pos[0], ctx.pos[1] - 1)
            ctx.dwell(0.5)
            ctx.thread(ctx.pos[0], ctx.pos[1] - 10, 1.5, 90.0, 60.0)
            ctx.arc(ctx.pos[0] + 1, ctx.pos[1] - 1, (ctx.pos[0] + 1, ctx.pos[1]), True)
    monkeypatch.setattr(cycles, "execute", fake)
    return seen


def test_modal_cycle_words_carry_over(calls):
    run("%1\nG92 X40 Z3\nM03 S300\nG91 G80 X-10 Z-33 I-5.5 F100\nX-13 Z-33\nG00 X50\nG80 X20 Z-5\nM30\n")
    assert [c for c, _ in calls] == [80, 80, 80]
    first, second, third = (ctx for _, ctx in calls)
    assert first.words == {"X": -10, "Z": -33, "I": -5.5, "F": 100}
    assert first.incremental and first.diameter_mode and first.code == 80 and first.line == 4
    assert second.words == {"X": -13, "Z": -33, "I": -5.5, "F": 100}  # I kept from the block before
    assert third.words == {"X": 20, "Z": -5}  # a new cycle after G00: nothing carried


def test_cycle_emitters_and_state(calls):
    tp = run("%1\nG92 X40 Z3\nM03 S400\nG32 Z-20 F1.5\nM30\n")
    kinds = [m.kind for m in tp.moves]
    assert kinds == ["rapid", "dwell", "thread", "arc"]
    th = tp.moves[2]
    assert th.lead == 1.5 and th.angle == 90.0 and th.thread_angle == 60.0
    assert th.feed == pytest.approx(1.5 * 400) and th.duration == pytest.approx(10 / 600 * 60)
    assert all(m.line == 4 and m.op == "G32" for m in tp.moves)


def test_profile_dry_run_resolves_the_contour(calls):
    text = ("%1\nG92 X60 Z5\nG00 X46 Z3\nG71 U1 R1 P5 Q9 X0.4 Z0.1 F100\n"
            "N5 G00 X0\nN6 G01 X10 Z-2 F80\nN7 Z-20 C1\nN8 G91 U10 W-5\nN9 G90 G02 X30 W-5 R5\n"
            "G00 X60 Z5\nM30\n")
    tp = run(text)
    (code, ctx), = calls
    prof = ctx.profile_result
    segs = [(type(s).__name__, s.start, s.end, line, kind) for s, line, kind in prof]
    assert segs[0] == ("Line", (23.0, 3.0), (0.0, 3.0), 5, "rapid")
    assert segs[1][1:] == ((0.0, 3.0), (5.0, -2.0), 6, "feed")
    assert segs[2][2] == pytest.approx((5.0, -19.0))  # chamfer C1 resolved against N8:
    h = 0.5 ** 0.5                                      # 1 mm back along N7, 1 mm on along N8
    assert segs[3][2] == pytest.approx((5.0 + h, -20.0 - h))
    assert segs[4][2] == pytest.approx((10.0, -25.0))
    assert segs[5][0] == "Arc" and segs[5][2] == pytest.approx((15.0, -30.0))
    # the dry run changed nothing: the cycle then ran from A and the contour blocks ran normally
    assert [m for m in tp.moves if m.line == 3][-1].end == pytest.approx((23.0, 3.0))  # at A
    cyc = [m for m in tp.moves if m.line == 4]
    assert cyc[0].start == pytest.approx((23.0, 3.0)) and cyc[0].feed == 100
    after = [m for m in tp.moves if m.line > 4]
    assert after[0].start == pytest.approx((23.0, 3.0))
    assert any(m.kind == "arc" and m.line == 9 for m in after)
    assert not tp.warnings


@pytest.mark.parametrize("prof,msg", [
    ("N5 G00 X0\nN6 G01 Z-5", "N7 (Q) not found"),
    ("N6 G01 X0\nN7 G01 Z-5", "N5 (P) not found"),
    ("N5 G02 X10 Z-5 R20\nN7 G01 Z-5", "must be G00 or G01"),
    ("N5 G00 X0\nM98 P2\nN7 G01 Z-5", "M98"),
    ("N5 G00 X0\n#1=2\nN7 G01 Z-5", "assignments inside the profile"),
])
def test_profile_alarms(calls, prof, msg):
    text = f"%1\nG92 X60 Z5\nG71 U1 R1 P5 Q7 F100\n{prof}\nM30\n%2\nM99\n"
    with pytest.raises(NCError) as ei:
        run(text)
    assert msg in ei.value.message


def test_missing_cycle_module_alarm(monkeypatch):
    import hnc_cam.nc.interp as I
    monkeypatch.setattr(I, "_missing", lambda mod: True)

    def boom(code, ctx):
        raise ImportError("no module", name="hnc_cam.nc.cycles_rough")
    monkeypatch.setattr(cycles, "execute", boom)
    with pytest.raises(NCError, match="G71 not yet supported"):
        run("%1\nG71 U1 R1 P5 Q7\nN5 G00 X0\nN7 G01 Z-1\nM30\n")


def test_bug_in_a_cycle_is_an_alarm_not_a_traceback(monkeypatch):
    monkeypatch.setattr(cycles, "execute", lambda code, ctx: 1 / 0)
    with pytest.raises(NCError, match="internal error in the G80 cycle: ZeroDivisionError"):
        run("%1\nG80 X10 Z-5 F100\nM30\n")


# --- compensation ---------------------------------------------------------------------------

@pytest.fixture
def comp(monkeypatch):
    import hnc_cam.nc.compensation as C
    batches = []

    def fake(items, radius, tip, side):
        batches.append(([(it.mode, it.kind, it.line, type(it.seg).__name__) for it in items],
                        radius, tip, side))
        out = []
        for it in items:  # shift everything up by the radius, like a trivial offset
            s = it.seg
            if isinstance(s, Arc):
                out.append((Arc((s.start[0] + radius, s.start[1]), (s.end[0] + radius, s.end[1]),
                                (s.center[0] + radius, s.center[1]), s.cw), it))
            else:
                out.append((Line((s.start[0] + radius, s.start[1]), (s.end[0] + radius, s.end[1])), it))
        return out
    monkeypatch.setattr(C, "compensate_moves", fake)
    return batches


MACH = Machine(registers={1: Register(number=1, radius=0.4, tip=3)})


def test_compensation_run_from_g42_to_g40(comp):
    text = ("%1\nT0101\nG00 X40 Z5\nG00 X0\nG01 G42 Z0 F60\nG03 U24 W-24 R15\nG01 Z-40\n"
            "G00 X30\nG40 X40 Z5\nM30\n")
    tp = run(text, MACH)
    (modes, radius, tip, side), = comp
    assert [m[0] for m in modes] == ["start", "normal", "normal", "normal", "cancel"]
    assert [m[1] for m in modes] == ["feed", "feed", "feed", "rapid", "rapid"]
    assert modes[1][3] == "Arc"
    assert (radius, tip, side) == (0.4, 3, 42)
    lines = [m.line for m in tp.moves]
    assert lines == sorted(lines)  # emitted in program order after the flush
    arc = next(m for m in tp.moves if m.kind == "arc")
    assert arc.comp == 42 and arc.feed == 60
    assert [m.kind for m in tp.moves if m.line == 9] == ["rapid", "rapid"]  # the dog-leg kept


def test_compensation_flushes_at_program_end_and_calls(comp):
    text = "%1\nT0101\nG42 G01 X10 Z0 F60\nZ-10\nM98 P2\nZ-20\nM30\n%2\nG01 X12\nM99\n"
    run(text, MACH)
    assert [[m[0] for m in b[0]] for b in comp] == [["start", "normal"], ["normal"], ["normal"]]


def test_compensation_radius_zero_passes_through(comp):
    tp = run("%1\nT0202\nG42 G01 X10 Z0 F60\nZ-10\nG40 G00 X20\nM30\n",
             Machine(registers={2: Register(number=2, radius=0.0)}))
    assert comp == [] and tp.moves[-1].end == (10.0, -10.0)


def test_g40_on_an_arc_alarms(comp):
    with pytest.raises(NCError, match="G40"):
        run("%1\nT0101\nG42 G01 X10 Z0 F60\nG40 G02 X20 Z-5 R5\nM30\n", MACH)
