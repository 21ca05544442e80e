"""The one geometry kernel: exact lines and arcs in the (x = radius, z) half-plane.

Everything that intersects, offsets or samples geometry (profiling, compensation, the
interpreter's cycles and G41/G42, the planner, the simulator) goes through this package.
"""
from .primitives import (EPS, TOL, Arc, Line, Point, Segment, chain_is_connected, cross, dist,
                         iter_points, left_normal, point_at_angle, polar_angle, reverse_chain,
                         same_point, sample_chain)

__all__ = ["EPS", "TOL", "Arc", "Line", "Point", "Segment", "chain_is_connected", "cross", "dist",
           "iter_points", "left_normal", "point_at_angle", "polar_angle", "reverse_chain",
           "same_point", "sample_chain"]
from .profile import Thread, TurnedProfile  # noqa: E402

__all__ += ["Thread", "TurnedProfile"]
