"""A step the finishing nose cannot enter is refused in one line in both compensation modes:
with ``--comp control`` the control's G41/G42 would alarm on the program, so the planner
refuses it before writing, exactly as it does when it computes the tip path itself."""
from __future__ import annotations

from hnc_cam.cli import main

# a journal of 30.9 mm, a 0.38 mm shoulder and a 1 mm chamfer up to a 33.66 mm collar: the
# shoulder is narrower than the 0.4 mm nose's 0.8 mm
NARROW_OD = '''
from build123d import BuildLine, BuildPart, BuildSketch, Plane, Polyline, Axis, make_face, revolve

STOCK = "36x70+1"


def part():
    pts = [(0, 0), (14.45, 0), (15.45, -1), (15.45, -30), (15.83, -30), (16.83, -31),
           (16.83, -60), (0, -60)]
    with BuildPart() as p:
        with BuildSketch(Plane.XZ):
            with BuildLine():
                Polyline(*pts, close=True)
            make_face()
        revolve(axis=Axis.Z)
    return p.part
'''

def test_narrow_concave_step_refused_in_both_modes(tmp_path, capsys):
    part = tmp_path / "part.py"
    part.write_text(NARROW_OD)
    errors = {}
    for comp in ("cam", "control"):
        out = tmp_path / f"{comp}.nc"
        rc = main(["generate", str(part), "--comp", comp, "-o", str(out)])
        err = capsys.readouterr().err.strip().splitlines()
        assert rc == 2, (comp, err)
        assert not out.exists()
        assert len(err) == 1 and err[0].startswith("error:"), err
        assert "internal error" not in err[0]
        errors[comp] = err[0]
    # the same feature, the same words, whichever side computes the offset
    assert errors["cam"] == errors["control"]
    assert "too narrow for the nose radius" in errors["cam"]
