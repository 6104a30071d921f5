"""The flatten brush: levels the surface towards the area plane where the cursor passes
(Blender's Flatten); Ctrl pushes away from it (Blender's contrast).

Each dab (:mod:`~gogreen_core.sculpt.brushes.dabs`) takes the plane through the area centre ``C``
⟂ the area normal ``N`` and moves each vertex ``p`` the fraction
``k = b · f · FLATTEN_RATE ·`` :data:`DAB_SPACING` (at most 1: never past the plane) of its way
to it, ``k ((C − p)·N) N`` (``b`` strength × pressure, ``f`` the falloff): bumps and dents both
go, and at strength 1 one pass leaves about e^−FLATTEN_RATE of a straight stroke's centre
line's height over the plane. Pushing away grows what it pushes (each dab more, the farther a
point is), so a dab's push is also at most ``|b| · f · CONTRAST_RATE · R ·`` :data:`DAB_SPACING`:
a pass moves a point at most ``CONTRAST_RATE · R``, however long the brush stays.
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
        motion: np.ndarray = np.outer(push, dab.area_normal)
        return motion
