"""Material-removal simulation and verification against the model.

``simulate(toolpath, stock, machine, tools) -> Machined`` removes the swept tool outline of
every move from the stock (2-D half-plane, shapely/GEOS, arcs sampled at 0.0005 mm chord error)
and runs the checks (``material_after(machined, ks)``: the material after the first k moves);
``verify(machined, model, tol=0.01) -> Report`` compares the result with a
:class:`hnc_cam.geometry.TurnedProfile`. This package never imports the planner, the
post-processor, the templates or the CAD front end: it checks the generator independently.
"""
from .region import profile_polygon, stock_region
from .simulate import Issue, Machined, material_after, simulate
from .tool import CHORD, ToolShape, tool_shape
from .verify import Deviation, Report, ThreadResult, verify

__all__ = ["CHORD", "Deviation", "Issue", "Machined", "Report", "ThreadResult", "ToolShape",
           "material_after", "profile_polygon", "simulate", "stock_region", "tool_shape", "verify"]
