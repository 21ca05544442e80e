"""A pin whose part() forwards **kwargs to its sketch: it declares no parameters (only keyword
arguments with defaults do), so --set and DOMAIN naming d1 are refused with the way to
declare them."""
from hnc_cam.cad.sketch import Outline, revolve

DOMAIN = {"d1": (10.0, 14.0)}


def sketch(d1=12.0, l1=20.0):
    s = Outline((0.0, 0.0))
    s.line_to(d1 / 2, 0.0)
    s.line_to(d1 / 2, -l1)
    s.line_to(0.0, -l1)
    return s.segments()


def part(**kw):
    return revolve(sketch(**kw))
