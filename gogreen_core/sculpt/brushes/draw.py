"""The draw brush: raises the surface along the area normal where the cursor passes (Blender's
Draw); Ctrl carves.

Each dab (:mod:`~gogreen_core.sculpt.brushes.dabs`) moves its vertices along the area normal
``N`` (the weighted mean normal under the brush) by ``b · f · DRAW_RATE · R ·`` :data:`DAB_SPACING`
(``b`` strength × pressure, ``f`` the falloff, ``R`` the radius): at strength 1 a straight
stroke raises its centre line by about ``DRAW_RATE · R``. All vertices of a dab move the same
way, so a stroke raises a smooth ridge rather than swelling each bump.
"""

from __future__ import annotations

import numpy as np

from gogreen_core.sculpt.brushes.dabs import DAB_SPACING, Dab, DetailBrush

__all__ = ["DRAW_RATE", "DrawBrush"]

#: Height (in R) one full-strength pass raises a straight stroke's centre line.
DRAW_RATE = 0.25


class DrawBrush(DetailBrush):
    """Moves along the area normal (see the module docstring)."""

    def offsets(self, dab: Dab) -> np.ndarray:
        scale = dab.amount * DRAW_RATE * DAB_SPACING * dab.radius
        motion: np.ndarray = np.outer(scale * dab.weight, dab.area_normal)
        return motion
