"""The mask painter: paints how much each vertex is held (Blender's mask brush).

The mask is a value per vertex in [0, 1] (:attr:`gogreen_core.mesh.mesh_state.MeshState.mask`):
every brush and pin drag moves a vertex by (1 − mask) of what it would (the stroke driver
blends, :mod:`gogreen_core.sculpt.stroke`), so a vertex at 1 does not move at all. One event adds
``strength · amount · w`` to the mask of each vertex of the swept region (``w`` the paint
family's cutoff weight, :mod:`~gogreen_core.sculpt.brushes.paint`), clipped to [0, 1]: ``amount`` is
the pen pressure, negative to erase (Ctrl). No vertex moves.
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
