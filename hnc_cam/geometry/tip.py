"""Tip direction codes 0-9 (manual fig. 3.3.44, read as in the FANUC/Haas convention).

The code names the direction from the nose centre C to the imaginary tip P in work axes:
1 (+X,+Z), 2 (+X,-Z), 3 (-X,-Z), 4 (-X,+Z), 5 (+Z), 6 (+X), 7 (-Z), 8 (-X); 0 and 9: P = C.
An outside turning tool cutting toward the chuck is code 3, a boring bar code 2.
"""
from __future__ import annotations

from .primitives import Point

_DIRS: dict[int, tuple[int, int]] = {
    0: (0, 0), 1: (1, 1), 2: (1, -1), 3: (-1, -1), 4: (-1, 1),
    5: (0, 1), 6: (1, 0), 7: (0, -1), 8: (-1, 0), 9: (0, 0),
}


def tip_vector(code: int, radius: float) -> Point:
    """Vector (dx radius, dz) from the nose centre to the controlled point P."""
    if code not in _DIRS:
        raise ValueError(f"tip direction code must be 0-9, got {code}")
    sx, sz = _DIRS[code]
    return (sx * radius, sz * radius)


def tip_direction(code: int) -> tuple[int, int]:
    """Signs (sx, sz) of the tip direction (0, 0 for codes 0 and 9)."""
    return _DIRS[code]
