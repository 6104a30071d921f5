"""The inflate brush (Blender's Inflate): each dab (:mod:`~gogreen_core.sculpt.brushes.dabs`)
moves vertex ``i`` along its own normal ``nᵢ`` by ``b · f · INFLATE_RATE · R ·``
:data:`DAB_SPACING`: unlike draw, a finger grows thicker; Ctrl deflates.
"""

from __future__ import annotations

import numpy as np

from gogreen_core.sculpt.brushes.dabs import DAB_SPACING, Dab, DetailBrush

__all__ = ["INFLATE_RATE", "InflateBrush"]

#: Distance (in R) one full-strength pass moves a straight stroke's centre line.
INFLATE_RATE = 0.25


class InflateBrush(DetailBrush):
    """Moves along each vertex normal (see the module docstring)."""

    def offsets(self, dab: Dab) -> np.ndarray:
        scale = dab.amount * INFLATE_RATE * DAB_SPACING * dab.radius
        motion: np.ndarray = (scale * dab.weight)[:, None] * dab.normals
        return motion
