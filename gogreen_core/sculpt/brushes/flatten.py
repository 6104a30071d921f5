"""The flatten brush (Blender's Flatten): each dab moves each vertex ``p`` the fraction
``k = b · f · FLATTEN_RATE ·`` :data:`DAB_SPACING` (at most 1) of its way to the plane through the
area centre ``C`` ⟂ ``N``. Ctrl pushes away (Blender's contrast), at most
``|b| · f · CONTRAST_RATE · R ·`` :data:`DAB_SPACING` a dab, since a push grows what it pushes.
"""

from __future__ import annotations

import numpy as np

from gogreen_core.sculpt.brushes.dabs import DAB_SPACING, Dab, DetailBrush, dot3

__all__ = ["CONTRAST_RATE", "FLATTEN_RATE", "FlattenBrush"]

#: How fast one full-strength pass levels (the height left: about e^−FLATTEN_RATE).
FLATTEN_RATE = 2.0
#: The most (in R) one full-strength pass of Ctrl pushes a point from the plane.
CONTRAST_RATE = 0.1


class FlattenBrush(DetailBrush):
    """Moves towards the area plane (see the module docstring)."""

    def offsets(self, dab: Dab) -> np.ndarray:
        fraction = np.minimum(dab.amount * FLATTEN_RATE * DAB_SPACING * dab.weight, 1.0)
        push = fraction * dot3(dab.area_center - dab.points, dab.area_normal)
        if dab.amount < 0:  # contrast: bounded, not a runaway
            most = -dab.amount * CONTRAST_RATE * DAB_SPACING * dab.radius * dab.weight
            push = np.clip(push, -most, most)
        return np.outer(push, dab.area_normal)
