# A spacer as a plain CadQuery script: the solid is left in `result`, as CQ-editor expects.
import cadquery as cq

result = (cq.Workplane("XZ")
          .polyline([(0, 0), (8, 0), (9, -1), (9, -12), (12, -12), (12, -25), (0, -25)])
          .close()
          .revolve(360, (0, 0, 0), (0, 1, 0)))
