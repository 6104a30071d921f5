"""The clay strips brush: lays strips of clay where the cursor passes (Blender's Clay Strips);
Ctrl digs them.

Each dab (:mod:`~gogreen_core.sculpt.brushes.dabs`) takes the plane ⟂ the area normal ``N``
through the area centre ``C`` raised by ``CLAY_OFFSET · R`` (lowered with Ctrl), and moves the
vertices below it (above it with Ctrl) the fraction ``k = |b| · g · CLAY_RATE ·``
:data:`DAB_SPACING` (at most 1: a vertex reaches the plane, never passes it) of their way to
it. ``g`` is a square footprint aligned with the stroke: the falloff of max(|u|, |v|), the
coordinates along and across the stroke direction in the plane, flat up to
``CLAY_PLATEAU · R`` (and nothing farther than R from the plane), so strokes leave flat-topped
strips with straight sides that build up as they cross.
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
        motion: np.ndarray = np.outer(fraction * height, normal)
        return motion
