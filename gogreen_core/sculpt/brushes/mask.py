"""The mask painter (Blender's mask brush): one event adds ``strength · amount · w`` to the
mask of each vertex of the swept region (``w`` the paint family's weight), clipped to [0, 1];
no vertex moves (:mod:`gogreen_core.sculpt.mask`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gogreen_core.sculpt.brushes.base import Displacement, StrokeContext
from gogreen_core.sculpt.brushes.paint import PaintBrush

if TYPE_CHECKING:
    from gogreen_core.sculpt.brushes.brush import Brush, BrushEvent

__all__ = ["MaskBrush"]


class MaskBrush(PaintBrush):
    """Paints the vertex mask (see the module docstring)."""

    def displace(self, ctx: StrokeContext, brush: Brush, event: BrushEvent) -> Displacement:
        rows, weight = self.region(ctx, brush, event)
        change = brush.strength * event.acting_amount
        values = np.clip(ctx.mesh.mask[rows] + change * weight, 0.0, 1.0)
        return Displacement(rows, None, mask=values)
