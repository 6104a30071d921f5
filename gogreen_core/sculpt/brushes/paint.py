"""The paint family: brushes that act where the cursor passes, weighted like the others' reach.

A paint event is the swept segment (``center`` to ``center + delta``) and ``amount``, the pen
pressure (negative with Ctrl). Each vertex within the influence of the segment (or its mirror
images) gets the brushes' smooth cutoff weight at its distance, so a paint brush covers what a
grab of the same radius and influence moves; an automatic influence is
:data:`PAINT_AUTO_INFLUENCE` (Blender's mask and smooth brushes' reach).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gogreen_core.sculpt.brushes.base import BrushType, StrokeContext, mirror_signs
from gogreen_core.sculpt.brushes.paint_kernels import kernels
from gogreen_core.validation import check_vector

if TYPE_CHECKING:
    from gogreen_core.sculpt.brushes.brush import Brush, BrushEvent

__all__ = ["PAINT_AUTO_INFLUENCE", "PaintBrush"]

#: The influence (in ε) of a paint brush whose influence is automatic.
PAINT_AUTO_INFLUENCE = 2.0


class PaintBrush(BrushType):
    """A brush acting on the region the cursor sweeps (see the module docstring)."""

    family = "paint"
    default_amount = 1.0  # full pen pressure: a script's event without one still paints
    auto_reach = PAINT_AUTO_INFLUENCE

    def check_event(self, brush: Brush, event: BrushEvent, reach: float) -> None:
        check_vector("delta", event.delta, max_norm=reach)

    def region(
        self, ctx: StrokeContext, brush: Brush, event: BrushEvent
    ) -> tuple[np.ndarray, np.ndarray]:
        """The rows (n,) within the brush's influence of the event's segment (or its mirror
        images) and their weights (n,) in [0, 1]."""
        mesh = ctx.mesh
        cutoff = self.cutoff(ctx, brush)
        signs = mirror_signs(brush.symmetry)
        rows = mesh.rows_near(
            event.center, event.delta, None if cutoff is None else cutoff[1], signs
        )
        if cutoff is None:
            return rows, np.ones(len(rows))
        weight = np.empty(len(rows))
        inner, outer = cutoff
        kernels().cutoff_weights(
            mesh.vertices, rows, event.center, event.delta, signs, mesh.origin, inner, outer, weight
        )
        keep = weight > 0
        return rows[keep], weight[keep]
