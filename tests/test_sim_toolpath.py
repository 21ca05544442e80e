"""The interpreter's Move as the simulator reads it: the constructor's 18 arguments (by position
or name), every field readable and writable, equality, pickling, values that do not fit the
compact storage, and the memory a move takes."""
from __future__ import annotations

import copy
import pickle
import threading
import tracemalloc

import pytest

from hnc_cam.nc.toolpath import MOVE_FIELDS, Move, Toolpath

ARGS = ("arc", (12.5, -3.25), (14.0, -6.0), 1234, 150.0, (14.0, -3.25), True, 3, 4, 812.5, 4,
        True, 1.75, 2.0, 90.0, 60.0, "G71", 42)


def test_positional_and_keyword_construction_keep_every_value():
    m = Move(*ARGS)
    assert tuple(getattr(m, f) for f in MOVE_FIELDS) == ARGS
    k = Move(**dict(zip(MOVE_FIELDS, ARGS)))
    assert k == m
    d = Move("dwell", (1.0, 2.0), (1.0, 2.0), 9)
    assert (d.feed, d.center, d.cw, d.tool, d.register, d.spindle, d.spindle_dir, d.coolant,
            d.duration, d.lead, d.angle, d.thread_angle, d.op, d.comp) == \
        (None, None, None, 0, 0, 0.0, 5, False, 0.0, 0.0, 0.0, 0.0, "", 40)
    assert isinstance(d.start, tuple) and isinstance(d.line, int)
    assert Move("line", (0.0, 0.0), (1.0, 0.0), 1, cw=False).cw is False


def test_fields_are_writable_and_other_moves_keep_theirs():
    a, b = Move(*ARGS), Move(*ARGS)
    a.duration = 9.5
    a.end = (1.0, 2.0)
    a.feed = None
    a.op = "G01"
    a.line = 77
    assert (a.duration, a.end, a.feed, a.op, a.line) == (9.5, (1.0, 2.0), None, "G01", 77)
    assert b == Move(*ARGS) and a != b
    a.tool = 10 ** 12  # beyond a C int: kept as given
    assert a.tool == 10 ** 12 and a.duration == 9.5 and a.end == (1.0, 2.0)


def test_values_that_do_not_fit_are_kept_as_given():
    m = Move("line", [1.0, 2.0], (3.0, 4.0), 2 ** 40, feed=100, spindle="fast")
    assert m.start == [1.0, 2.0] and m.line == 2 ** 40 and m.spindle == "fast"
    assert Move("slide", (0.0, 0.0), (1.0, 1.0), 1).kind == "slide"
    assert Move("line", (0.0, 0.0), (1.0, 1.0), True).line is True


def test_equality_repr_pickle_copy_and_json():
    m = Move(*ARGS)
    assert pickle.loads(pickle.dumps(m)) == m
    assert copy.copy(m) == m and copy.deepcopy(m) == m and copy.copy(m) is not m
    assert repr(m).startswith("Move(kind='arc', start=(12.5, -3.25)")
    js = m.to_json()
    assert js["center"] == [28.0, -3.25] and js["cw"] is True and js["feed"] == 150.0
    assert js["line"] == 1234 and js["op"] == "G71"
    with pytest.raises(TypeError):
        hash(m)
    tp = Toolpath(moves=[m, Move("rapid", (0.0, 0.0), (1.0, 0.0), 1, duration=2.0)])
    assert tp.cycle_time_s == pytest.approx(3.75)


def test_moves_made_by_threads_at_once_keep_their_values():
    out: dict[int, list[Move]] = {}

    def make(t: int) -> None:
        out[t] = [Move("line", (float(t), float(i)), (float(i), float(t)), i + 1,
                       feed=float(t * 1000 + i)) for i in range(5000)]

    ths = [threading.Thread(target=make, args=(t,)) for t in range(4)]
    for th in ths:
        th.start()
    for th in ths:
        th.join()
    for t, ms in out.items():
        for i, m in enumerate(ms):
            assert m.start == (float(t), float(i)) and m.line == i + 1
            assert m.feed == float(t * 1000 + i)


def test_a_move_takes_under_200_bytes():
    tracemalloc.start()
    before = tracemalloc.get_traced_memory()[0]
    moves = [Move("line", (15.0 + i * 1e-6, -i * 0.05), (15.0, -(i + 1) * 0.05), 1000 + i // 3,
                  300.0 + i % 7, None, None, 1, 1, 800.0 + i, 3, False, 0.01 * i, 0.0, 0.0, 0.0,
                  "G01", 40) for i in range(50_000)]
    used = tracemalloc.get_traced_memory()[0] - before
    tracemalloc.stop()
    assert len(moves) == 50_000
    assert used / 50_000 < 200


def test_columns_read_the_same_values_as_the_attributes():
    import random

    import numpy as np

    from hnc_cam.nc.toolpath import MOVE_KINDS, columns
    moves = [Move(*ARGS)]
    for i in range(3000):
        moves.append(Move(MOVE_KINDS[i % 5], (1.0 + i, -0.5 * i), (2.0 + i, 0.25 * i), 10 + i,
                          None if i % 4 == 0 else 50.0 + i,
                          (3.0, 4.0) if i % 5 == 2 else None, None if i % 5 != 2 else bool(i % 2),
                          i % 7, i % 3, 100.0 * (i % 2), 3 + i % 3, bool(i % 2), 0.01 * i,
                          0.0, 0.0, 60.0 * (i % 5 == 3), "G0%d" % (i % 4), 40 + i % 3))
    moves.append(Move("slide", [0, 1], (2.0, 3.0), 2 ** 40, feed=7))  # kept as given
    random.Random(1).shuffle(moves)  # moves of many blocks, out of order
    c = columns(moves)
    for i, m in enumerate(moves):
        assert c["kind"][i] == (MOVE_KINDS.index(m.kind) if m.kind in MOVE_KINDS else -1)
        assert tuple(c["start"][i]) == tuple(float(v) for v in m.start)
        assert tuple(c["end"][i]) == m.end
        assert (np.isnan(c["feed"][i]) if m.feed is None else c["feed"][i] == m.feed)
        assert (np.isnan(c["center"][i]).all() if m.center is None
                else tuple(c["center"][i]) == m.center)
        assert c["cw"][i] == (-1 if m.cw is None else int(m.cw))
        for f in ("line", "tool", "register", "spindle_dir", "comp", "spindle", "duration",
                  "thread_angle", "coolant"):
            assert c[f][i] == getattr(m, f), f
