"""The affine family: an affine load H = k B at a fixed centre (scale, twist, pinch, stretch).

Each member has a pattern B (3, 3), the velocity gradient that ``amount`` 1 asks for at the
brush centre: I (scale), [a]_× (twist about the view axis a), d dᵀ − e eᵀ (pinch along the
stroke direction d, e = a × d), d dᵀ (stretch, the sides left to the material). k is set so
that the velocity gradient J at the centre has component (J : B)/(B : B) = ``strength ·
amount`` along B, whatever the material; the centre's deformation gradient is then exp(J): per
unit amount a log strain of 1 or a rotation of 1 radian, which add up over events. The load is
held to the safe-falloff bounds (:data:`~gogreen_core.sculpt.falloff_safety.AFFINE_MARGIN`).
A new member is a pattern function (axis, direction) → B and a table row.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, cast

import numpy as np

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.field.limits import MAX_AMOUNT
from gogreen_core.physics.radial import GaussianRadial, MultiscaleRadial, RadialProfile
from gogreen_core.sculpt.brushes.base import ZERO_FIELD, GreenBrush, StrokeContext
from gogreen_core.sculpt.falloff_safety import AFFINE_FALLBACK, AFFINE_MARGIN, FieldBound
from gogreen_core.validation import ParameterError

if TYPE_CHECKING:
    from gogreen_core.sculpt.brushes.brush import Brush, BrushEvent

__all__ = [
    "AffineBrush",
    "centre_jacobian",
    "local_affine",
    "pinch_pattern",
    "scale_pattern",
    "stretch_pattern",
    "stroke_direction",
    "twist_pattern",
]

#: Step (in ε) of the central differences that measure the velocity gradient an affine load
#: makes at its centre (:func:`centre_jacobian`), which sets what ``amount`` means.
JACOBIAN_STEP = 1e-3

#: A pattern: (unit view axis a (3,), stroke direction (3,) or None) → B (3, 3).
Pattern = Callable[[np.ndarray, "np.ndarray | None"], np.ndarray]


def _tame(vector: np.ndarray) -> np.ndarray:
    """``vector`` (3,), rescaled by its largest component when its length would overflow or
    underflow (a direction is all that is used)."""
    v = np.asarray(vector, dtype=np.float64)
    peak = np.abs(v).max()
    return v / peak if peak > 1e150 or 0 < peak < 1e-150 else v


def stroke_direction(axis: np.ndarray, direction: np.ndarray | None) -> np.ndarray:
    """The unit stroke direction d (3,): ``direction`` projected ⟂ the unit ``axis`` (any
    vector ⟂ axis when None or along the axis)."""
    d = np.cross(axis, [1.0, 0.0, 0.0]) if direction is None else _tame(direction)
    d = d - axis * (d @ axis)
    if np.linalg.norm(d) < 1e-12:
        d = np.cross(axis, [0.0, 1.0, 0.0])
    return cast(np.ndarray, d / np.linalg.norm(d))


def scale_pattern(axis: np.ndarray, direction: np.ndarray | None) -> np.ndarray:
    """B = I: every direction stretches (inflate; deflate with a negative amount)."""
    return np.eye(3)


def twist_pattern(axis: np.ndarray, direction: np.ndarray | None) -> np.ndarray:
    """B = [a]_× (B x = a × x): a rotation about the view axis a, one radian per unit."""
    a = axis
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def pinch_pattern(axis: np.ndarray, direction: np.ndarray | None) -> np.ndarray:
    """B = d dᵀ − e eᵀ: stretch along the stroke direction d, squeeze along e = a × d."""
    d = stroke_direction(axis, direction)
    e = np.cross(axis, d)
    return cast(np.ndarray, np.outer(d, d) - np.outer(e, e))


def stretch_pattern(axis: np.ndarray, direction: np.ndarray | None) -> np.ndarray:
    """B = d dᵀ: a uniaxial load along the stroke direction d (paper Fig. 11); the sides move
    as the material's Poisson ratios say."""
    d = stroke_direction(axis, direction)
    return np.outer(d, d)


def local_affine(base: RadialProfile) -> MultiscaleRadial:
    """The affine brushes' falloff: tri-scale at ε, 2 ε, 4 ε (Blender's Elastic Deform radii;
    de Goes & James 2017, Sec. 5): the far field cancels (a tenth of the motion at 2.8 ε, not
    5 ε) while the strain stays spread over the brush circle."""
    return MultiscaleRadial.triscale(base, 2.0, 1.0)


def centre_jacobian(kernel: GreenKernel, center: np.ndarray, load: np.ndarray) -> np.ndarray:
    """∂u_i/∂x_p (3, 3) at the centre of the affine load ``load``: central differences at
    h = JACOBIAN_STEP · ε and h/2, Richardson-extrapolated (~1e-12 relative)."""
    h = JACOBIAN_STEP * kernel.eps
    steps = np.array([h, h, h, 0.5 * h, 0.5 * h, 0.5 * h])[:, None]
    offsets = steps * np.vstack([np.eye(3), np.eye(3)])
    u = kernel.affine_displacement(
        center + np.vstack([offsets, -offsets]), center, load
    )  # (12, 3): +h, +h/2, −h, −h/2
    coarse = (u[0:3] - u[6:9]) / (2 * h)
    fine = (u[3:6] - u[9:12]) / h
    return cast(np.ndarray, ((4 * fine - coarse) / 3).T)  # [i, p] = ∂u_i/∂x_p


def _response(jacobian: np.ndarray, shape: np.ndarray) -> float:
    """The component of the velocity gradient ``jacobian`` along the pattern ``shape``."""
    return float(np.sum(jacobian * shape) / np.sum(shape * shape))


class AffineBrush(GreenBrush):
    """An affine load of pattern ``pattern`` at the press point (see the module docstring)."""

    family = "affine"
    default_amount = None  # a log strain or angle: no default

    def __init__(
        self,
        kind: str,
        pattern: Pattern,
        multiscale: Callable[[RadialProfile], RadialProfile] | None = None,
        weights_of: str | None = None,
    ) -> None:
        super().__init__(kind, multiscale, weights_of)
        self._pattern = pattern

    def wide(self) -> AffineBrush:
        """This brush with the settings' falloff itself (no multi-scale combination), under
        the kind ``<kind>_wide``, reading this brush's degree weights."""
        return AffineBrush(f"{self.kind}_wide", self._pattern, None, self.kind)

    def shape(self, axis: np.ndarray | None, direction: np.ndarray | None) -> np.ndarray:
        """Pattern B (3, 3) for a view ``axis`` (any nonzero length; +z when None) and a stroke
        ``direction`` (3,) or None."""
        a = np.array([0.0, 0.0, 1.0]) if axis is None else _tame(axis)
        return self._pattern(a / np.linalg.norm(a), direction)

    def check_event(self, brush: Brush, event: BrushEvent, reach: float) -> None:
        load = abs(brush.strength * event.acting_amount)
        if not load <= MAX_AMOUNT:
            raise ParameterError(
                "amount",
                f"amount × brush strength must be ≤ {MAX_AMOUNT:g} in magnitude "
                f"(got {event.acting_amount:g} × {brush.strength:g})",
            )

    def load(
        self, ctx: StrokeContext, brush: Brush, kernel: GreenKernel, event: BrushEvent
    ) -> tuple[np.ndarray, np.ndarray]:
        """(H, 0): the affine load (3, 3); the centre stays."""
        shape = self.shape(event.axis, event.direction)
        jacobian = centre_jacobian(kernel, event.center, shape)
        # Its component along the pattern B (the sign depends on the material: Kelvinlets'
        # scale load contracts for ν < 1/2) is divided out, so that the velocity gradient at
        # the centre has component strength · amount along B: `amount` is a log strain or
        # an angle at the centre whatever the material.
        response = _response(jacobian, shape)
        amount = brush.strength * event.acting_amount
        eps = kernel.eps
        # The largest displacement and velocity gradient of the load B anywhere: the centre's
        # response must be large enough that B · amount / response stays within the limits.
        bound = self.field_bound(ctx, brush, kernel)
        peak, at, moved = bound.motion_sup(shape, eps)
        if not peak * eps**2 > ZERO_FIELD * ctx.kernels.green_scale:
            raise ParameterError(
                "falloff",
                f"the {brush.kind} brush's falloff has no gradient within its influence "
                f"({self.reach(ctx, brush):g} ε): its odd-degree curves (dR) are zero",
            )
        motion_limit, strain_limit = self.limits(ctx, brush, shape)
        needed = max(peak / (motion_limit * eps), bound.strain_sup(shape, eps) / strain_limit)
        if np.linalg.norm(jacobian) >= needed:  # the centre moves: the usual rule
            if not abs(response) * np.linalg.norm(shape) > 1e-3 * np.linalg.norm(jacobian):
                raise ValueError(
                    f"the {brush.kind} brush has no effect with this material and falloff "
                    f"(response {response:.3g})"
                )
            if abs(response) >= needed:
                return shape * (amount / response), np.zeros(3)
        # A weak centre: scale B to the limits, with the sign of the centre's response, or
        # where that is lost in rounding, the sign that makes the most moved point follow the
        # pattern (outwards for scale).
        if abs(response) * eps > 1e-6 * peak:
            sign = np.sign(response)
        else:
            sign = -1.0 if moved @ (shape @ at) < 0 else 1.0
        return shape * (sign * amount / needed), np.zeros(3)

    def limits(self, ctx: StrokeContext, brush: Brush, shape: np.ndarray) -> tuple[float, float]:
        """(motion in |amount| ε, velocity gradient in |amount|) an event of pattern ``shape``
        may reach: AFFINE_MARGIN × what the Gaussian falloff reaches with the same material,
        l_max, weights, influence and pattern (its field bound is cached per settings)."""
        weights = self.degree_weights(ctx.settings)
        frame = ctx.kernels.frame  # a turned material: the unturned one with the pattern turned
        if frame is not None:
            shape = frame.T @ shape @ frame
        kernels = ctx.kernels.unturned
        base = kernels.weighted(weights)
        reach = self.reach(ctx, brush)

        def reference() -> tuple[GreenKernel, FieldBound]:
            gaussian = base.with_radial(GaussianRadial(1.0))
            return gaussian, FieldBound(gaussian, reach, True)

        key = ("gaussian", None if weights is None else weights.tobytes(), reach)
        gaussian, bound = kernels.derived(key, reference)
        jacobian = centre_jacobian(gaussian, np.zeros(3), shape)
        response = _response(jacobian, shape)
        if not abs(response) * np.linalg.norm(shape) > 1e-3 * np.linalg.norm(jacobian):
            return AFFINE_FALLBACK  # no effect with a Gaussian (an incompressible scale)
        load = shape / response
        motion, strain = bound.motion_sup(load, 1.0)[0], bound.strain_sup(load, 1.0)
        return AFFINE_MARGIN * motion, AFFINE_MARGIN * strain
