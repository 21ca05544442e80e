"""Parts whose right end the finishing contour itself takes to the centre (a bar not faced
first, a cone to a point, a face narrower than the nose's reach, a ball end), in every
dialect and both compensation modes: a verified program, no cycle block skipped, no
warning of the reader."""
from __future__ import annotations

import pytest

from hnc_cam.geometry import Arc, Line, TurnedProfile
from hnc_cam.plan.api import generate

from test_plan_shapes import chain

SHAPES = {
    "cone_point": chain((0, 0), (10, -10), (10, -40), (0, -40)),
    "tiny_face": chain((0, 0), (0.4, 0), (10, -9.6), (10, -40), (0, -40)),
    "face_1mm": chain((0, 0), (1, 0), (10, -9), (10, -40), (0, -40)),
    "face_chamfer": chain((0, 0), (8, 0), (10, -2), (10, -40), (0, -40)),
    "face_step": chain((0, 0), (5, 0), (5, -10), (10, -10), (10, -40), (0, -40)),
    "ball": [Arc((0, 0), (10, -10), (0, -10), False), Line((10, -10), (10, -40)),
             Line((10, -40), (0, -40))],
}


@pytest.mark.parametrize("dialect", ["hnc21t", "fanuc0it", "haas", "siemens802"])
@pytest.mark.parametrize("comp", ["cam", "control"])
@pytest.mark.parametrize("stock", ["24x45", "24x45+0.3"])
@pytest.mark.parametrize("name", sorted(SHAPES))
def test_right_end_to_the_centre(name, stock, comp, dialect):
    prog = generate(TurnedProfile(SHAPES[name], name=name), stock=stock, comp=comp,
                    dialect=dialect)
    assert prog.report.passed, prog.report.summary()
    assert not prog.toolpath.warnings, prog.toolpath.warnings[:3]
    # the right end is cut to the centre: a feed move reaches X <= 0 at Z 0 (the facing
    # pass, the finisher's face or the contour from the centre)
    cuts = [m for m in prog.toolpath.moves if m.kind != "rapid"]
    assert any(min(m.start[0], m.end[0]) <= 1e-6 and abs(m.end[1]) <= 1e-6 for m in cuts)
