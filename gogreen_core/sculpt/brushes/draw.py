"""The draw brush (Blender's Draw): each dab moves its vertices along the area normal ``N``
by ``b · f · DRAW_RATE · R ·`` :data:`DAB_SPACING` (:mod:`~gogreen_core.sculpt.brushes.dabs`), so
a stroke raises a smooth ridge; Ctrl carves.
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
        return np.outer(scale * dab.weight, dab.area_normal)
