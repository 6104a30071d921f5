"""The clay strips brush (Blender's Clay Strips); Ctrl digs.

Each dab (:mod:`~gogreen_core.sculpt.brushes.dabs`) moves the vertices below the plane ⟂ ``N``
through the area centre raised by ``CLAY_OFFSET · R`` the fraction ``|b| · g · CLAY_RATE ·``
:data:`DAB_SPACING` (at most 1) of their way to it, ``g`` a square footprint aligned with the
stroke (flat up to ``CLAY_PLATEAU · R``): strips with flat tops and straight sides.
"""

from __future__ import annotations

import math

import numpy as np

from gogreen_core.sculpt.brushes.base import smooth_cutoff
from gogreen_core.sculpt.brushes.dabs import DAB_SPACING, Dab, DetailBrush, dot3

__all__ = ["CLAY_OFFSET", "CLAY_PLATEAU", "CLAY_RATE", "ClayStripsBrush", "square_axes"]

#: How far (in R) above the area centre the plane is (Blender: 0.18 of the radius).
CLAY_OFFSET = 0.18
#: How fast a full-strength pass reaches the plane (the height left: about e^−CLAY_RATE).
CLAY_RATE = 1.0
#: Where (in R) the square footprint starts to fall off.
CLAY_PLATEAU = 0.25


def square_axes(normal: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit axes (3,) along and across the stroke in the plane ⟂ unit ``normal``:
    ``direction`` projected on the plane (any direction in it when there is none)."""
    along = direction - dot3(direction, normal) * normal
    size = float(np.linalg.norm(along))
    if not size > 1e-9:
        helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
        along = np.cross(normal, helper)
        size = float(np.linalg.norm(along))
    along = along / size
    return along, np.cross(normal, along)


class ClayStripsBrush(DetailBrush):
    """Builds up towards a raised plane in a square footprint (see the module docstring)."""

    select_factor = math.sqrt(3.0)  # the footprint's corners, R from the plane

    def offsets(self, dab: Dab) -> np.ndarray:
        normal, radius = dab.area_normal, dab.radius
        side = 1.0 if dab.amount > 0 else -1.0
        plane = dab.area_center + side * CLAY_OFFSET * radius * normal
        along, across = square_axes(normal, dab.direction)
        gap = dab.points - dab.center
        square = np.maximum(np.abs(dot3(gap, along)), np.abs(dot3(gap, across)))
        footprint = smooth_cutoff(square, CLAY_PLATEAU * radius, radius)
        height = dot3(plane - dab.points, normal)  # how far the plane is above each point
        footprint[(side * height <= 0) | (np.abs(height) > radius)] = 0.0
        fraction = np.minimum(abs(dab.amount) * CLAY_RATE * DAB_SPACING * footprint, 1.0)
        return np.outer(fraction * height, normal)
