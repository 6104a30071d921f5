"""The crease brush (Blender's Crease): each dab draws inwards along the area normal ``N`` by
``b · f · CREASE_DEPTH · R ·`` :data:`DAB_SPACING` and pinches each vertex the fraction
``|b| · f · CREASE_PINCH ·`` :data:`DAB_SPACING` of its way to the stroke line, so the groove stays
sharp. Ctrl raises a ridge: it inverts the drawing, never the pinch (as Blender).
"""

from __future__ import annotations

import numpy as np

from gogreen_core.sculpt.brushes.dabs import DAB_SPACING, Dab, DetailBrush, dot3

__all__ = ["CREASE_DEPTH", "CREASE_PINCH", "CreaseBrush"]

#: Depth (in R) one full-strength pass cuts along a straight stroke's centre line.
CREASE_DEPTH = 0.2
#: How fast a full-strength pass pinches to the line (distances left: about e^−CREASE_PINCH).
CREASE_PINCH = 1.0


class CreaseBrush(DetailBrush):
    """Draws inwards and pinches towards the stroke line (see the module docstring)."""

    def offsets(self, dab: Dab) -> np.ndarray:
        normal = dab.area_normal
        lateral = dab.center - dab.points
        lateral -= np.outer(dot3(lateral, normal), normal)
        along = dab.direction - dot3(dab.direction, normal) * normal
        size = float(np.linalg.norm(along))
        if size > 1e-9:
            along = along / size
            lateral -= np.outer(dot3(lateral, along), along)
        pinch = np.minimum(abs(dab.amount) * CREASE_PINCH * DAB_SPACING * dab.weight, 1.0)
        depth = -dab.amount * CREASE_DEPTH * DAB_SPACING * dab.radius
        motion: np.ndarray = pinch[:, None] * lateral + np.outer(depth * dab.weight, normal)
        return motion
