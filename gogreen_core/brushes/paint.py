"""The paint family: brushes that act where the cursor passes, weighted like the others' reach.

A paint event is the segment the cursor swept (``center`` to ``center + delta``, nothing for a
dab) and ``amount``: the pen pressure, negative to erase or invert (Ctrl). Each vertex within the
brush's influence ball of the segment (or of its mirror images) gets the weight of the brushes'
smooth cutoff at its distance: 1 up to half the influence radius, a C² fall to 0 at it
(:func:`~gogreen_core.brushes.base.smooth_cutoff`), so a paint brush covers the region a grab
of the same radius and influence moves. Members: the smooth brush
(:mod:`~gogreen_core.brushes.smooth`) and the mask painter (:mod:`~gogreen_core.brushes.mask`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numba import njit, prange

from gogreen_core.brushes.base import BrushType, StrokeContext, mirror_signs
from gogreen_core.limits import MAX_REACH
from gogreen_core.validation import ParameterError, check_vector, vector_norm

if TYPE_CHECKING:
    from gogreen_core.brushes.brush import Brush, BrushEvent

__all__ = ["PaintBrush", "cutoff_weights"]


@njit(parallel=True, cache=True, nogil=True, boundscheck=False)
def cutoff_weights(points, rows, start, step, mirrors, origin, inner, outer, out):
    """out[k] = the brushes' quintic cutoff (:func:`smooth_cutoff`, compiled: a numpy pass over
    half a million rows took 90 ms; 1 up to ``inner``, 0 from ``outer`` on) of the
    distance from points[rows[k]], or its nearest mirror image (``mirrors`` (m, 3) signs about
    ``origin``), to the segment from ``start`` to ``start + step``."""
    length2 = step[0] * step[0] + step[1] * step[1] + step[2] * step[2]
    inv = 1.0 / length2 if length2 > 0.0 else 0.0
    width = outer - inner
    for k in prange(rows.shape[0]):
        n = rows[k]
        nearest = np.inf
        for mi in range(mirrors.shape[0]):
            y0 = origin[0] + mirrors[mi, 0] * (points[n, 0] - origin[0]) - start[0]
            y1 = origin[1] + mirrors[mi, 1] * (points[n, 1] - origin[1]) - start[1]
            y2 = origin[2] + mirrors[mi, 2] * (points[n, 2] - origin[2]) - start[2]
            t = min(max((y0 * step[0] + y1 * step[1] + y2 * step[2]) * inv, 0.0), 1.0)
            d0 = y0 - t * step[0]
            d1 = y1 - t * step[1]
            d2 = y2 - t * step[2]
            nearest = min(nearest, d0 * d0 + d1 * d1 + d2 * d2)
        distance = np.sqrt(nearest)
        if width <= 0.0:
            out[k] = 1.0 if distance < outer else 0.0
        else:
            u = min(max((distance - inner) / width, 0.0), 1.0)
            out[k] = 1.0 - u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)


class PaintBrush(BrushType):
    """A brush acting on the region the cursor sweeps (see the module docstring)."""

    family = "paint"

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
        cutoff = brush.cutoff(ctx.model_size)
        signs = mirror_signs(brush.symmetry)
        rows = mesh.rows_near(
            event.center, event.delta, None if cutoff is None else cutoff[1], signs
        )
        if cutoff is None:
            return rows, np.ones(len(rows))
        weight = np.empty(len(rows))
        inner, outer = cutoff
        cutoff_weights(
            mesh.vertices, rows, event.center, event.delta, signs, mesh.origin, inner, outer, weight
        )
        keep = weight > 0
        return rows[keep], weight[keep]
