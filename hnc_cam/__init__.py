"""hnc_cam: turned parts from CAD to Huazhong HNC-21/22T lathe programs, verified.

Heavy packages (OCP, build123d, cadquery, matplotlib) are imported lazily, only by the
stages that need them, so that ``hnc-cam run``/``simulate`` start fast.
"""
__version__ = "0.1.0"


def generate(part, stock=None, **options):
    """Generate a program for a part; see :func:`hnc_cam.plan.api.generate`."""
    from .plan.api import generate as _generate
    return _generate(part, stock=stock, **options)
