"""CAD front end: turned-part profiles from build123d, CadQuery, OCP shapes and STEP/BREP
files, and the part-file loader.

``profile`` and ``load_part`` import OpenCascade (OCP) on first use only, so importing this
package stays cheap (``hnc-cam run``/``simulate`` never pay for the CAD kernel).
"""
from __future__ import annotations

from typing import Any

from ..errors import PartError, ProfileError
from .loader import LoadedPart, load_part, parse_set

__all__ = ["LoadedPart", "PartError", "ProfileError", "load_part", "parse_set", "profile"]


def profile(obj: Any, axis: Any = "Z", zero: str | float = "right", envelope: bool = False,
            fit_tol: float = 0.001, name: str | None = None):
    """See :func:`hnc_cam.cad.extract.profile`."""
    from .extract import profile as _profile
    return _profile(obj, axis=axis, zero=zero, envelope=envelope, fit_tol=fit_tol, name=name)
