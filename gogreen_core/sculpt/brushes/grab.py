"""The grab family: a vector load at the cursor that the grabbed point follows exactly.

The centre moves with the cursor during an event, c(t) = c₀ + tΔ, and f solves G(0) f = Δ, so
the point under the cursor lands on the cursor. ``grab_biscale``, ``grab_triscale``: the same
with Kelvinlets' faster-decaying multi-scale falloff (radii ε, 1.25ε, 1.25²ε). An edited falloff
weak at its centre gets the force scaled to the safe-falloff bounds
(:mod:`~gogreen_core.sculpt.falloff_safety`); a field zero everywhere is refused.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.field.limits import MAX_REACH
from gogreen_core.sculpt.brushes.base import ZERO_FIELD, GreenBrush, StrokeContext
from gogreen_core.sculpt.falloff_safety import MAX_GRAB_RATIO, MAX_GRAB_STRAIN, mean_green_direction
from gogreen_core.validation import ParameterError, check_vector, vector_norm

if TYPE_CHECKING:
    from gogreen_core.sculpt.brushes.brush import Brush, BrushEvent

__all__ = ["GrabBrush"]


class GrabBrush(GreenBrush):
    """A vector load normalized so that the grabbed point follows the cursor (only degree 0
    is nonzero at the centre: its weight ω_0 divides out)."""

    family = "vector"

    def check_event(self, brush: Brush, event: BrushEvent, reach: float) -> None:
        check_vector("delta", event.delta, max_norm=reach)
        if not vector_norm(brush.strength * event.delta) <= reach:
            raise ParameterError(
                "delta",
                f"delta × brush strength must be ≤ {MAX_REACH:g} model sizes "
                f"({reach:.4g}) long (got |delta| = {vector_norm(event.delta):.4g}, "
                f"strength {brush.strength:g})",
            )

    def load(
        self, ctx: StrokeContext, brush: Brush, kernel: GreenKernel, event: BrushEvent
    ) -> tuple[np.ndarray, np.ndarray]:
        """(f, Δ): the force (3,) and the cursor motion, along which the load travels."""
        delta = brush.strength * event.delta
        g0 = kernel.green(np.zeros((1, 3)))[0]
        with np.errstate(all="ignore"):
            try:
                force = np.linalg.solve(g0, delta)
            except np.linalg.LinAlgError:  # G(0) = 0: R₀(0) pulled to 0
                force = np.full(3, np.nan)
        size = vector_norm(delta)
        finite = bool(np.all(np.isfinite(force)))
        if size == 0:
            return (force if finite else np.zeros(3)), delta
        bound = self.field_bound(ctx, brush, kernel)
        eps = kernel.eps
        if (
            finite
            and bound.motion_sup(force, eps)[0] <= MAX_GRAB_RATIO * size
            and bound.strain_sup(force, eps) * eps <= MAX_GRAB_STRAIN * size
        ):
            return force, delta
        # A weak centre: G(0) = c R₀(0) A whatever the falloff, so A⁻¹ Δ is the direction of
        # G(0)⁻¹ Δ even where R₀(0) = 0; scale it to the bounds.
        mean = mean_green_direction(ctx.settings.material)
        frame = ctx.kernels.frame  # the material turned onto a stroke's surface frame
        if frame is not None:
            mean = frame @ mean @ frame.T
        direction = np.linalg.solve(mean, delta)
        peak, _, moved = bound.motion_sup(direction, eps)
        if not peak * eps > ZERO_FIELD * vector_norm(direction) * ctx.kernels.green_scale:
            raise ParameterError(
                "falloff",
                f"the {brush.kind} brush's falloff is zero everywhere within its influence "
                f"({self.reach(ctx, brush):g} ε): raise R0 somewhere in the falloff editor",
            )
        strain = bound.strain_sup(direction, eps) * eps
        scale = min(MAX_GRAB_RATIO / peak, MAX_GRAB_STRAIN / strain if strain else np.inf) * size
        sign = -1.0 if moved @ delta < 0 else 1.0  # the most moved point goes with the cursor
        return direction * (sign * scale), delta
