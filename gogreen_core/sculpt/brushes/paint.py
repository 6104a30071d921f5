"""The paint family: brushes that act where the cursor passes, weighted like the others' reach.

A paint event is the segment the cursor swept (``center`` to ``center + delta``, nothing for a
dab) and ``amount``: the pen pressure, negative to erase or invert (Ctrl). Each vertex within the
brush's influence ball of the segment (or of its mirror images) gets the weight of the brushes'
smooth cutoff at its distance: 1 up to half the influence radius, a C² fall to 0 at it
(:func:`~gogreen_core.sculpt.brushes.base.smooth_cutoff`), so a paint brush covers the region a grab
of the same radius and influence moves. An automatic influence is
:data:`PAINT_AUTO_INFLUENCE`: full strength within the brush circle (ε), none beyond 2ε, where
Blender's mask and smooth brushes act. Members: the smooth brush
(:mod:`~gogreen_core.sculpt.brushes.smooth`), the mask painter
(:mod:`~gogreen_core.sculpt.brushes.mask`) and the detail brushes, which act in dabs along the
segment (:mod:`~gogreen_core.sculpt.brushes.dabs`): draw, clay strips, crease, flatten, inflate.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gogreen_core.field.limits import MAX_REACH
from gogreen_core.sculpt.brushes.base import BrushType, StrokeContext, mirror_signs
from gogreen_core.sculpt.brushes.paint_kernels import kernels
from gogreen_core.validation import ParameterError, check_vector, vector_norm

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
        if not vector_norm(event.delta) <= reach:
            raise ParameterError(
                "delta", f"delta must be ≤ {MAX_REACH:g} model sizes ({reach:.4g}) long"
            )

    def region(
        self, ctx: StrokeContext, brush: Brush, event: BrushEvent
    ) -> tuple[np.ndarray, np.ndarray]:
        """The rows (n,) within the brush's influence of the event's segment (or its mirror
        images) and their weights (n,) in [0, 1]: the smooth cutoff at their distance (1 for
        every vertex with an infinite influence)."""
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
