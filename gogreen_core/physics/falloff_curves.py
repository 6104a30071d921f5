"""How a spline falloff's curve passes through its control points (the artist's falloff
curves, :class:`gogreen_core.physics.radial.SplineRadial`).
"""

from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicHermiteSpline, CubicSpline, PPoly

__all__ = ["INTERPOLATIONS", "interpolant", "local_slopes", "monotone_hermite"]

#: How a spline falloff passes through its control points: ``"monotone"`` (new curves,
#: :func:`monotone_hermite`), or ``"cubic"``, the not-a-knot C² spline of files saved before
#: (no ``"interpolation"`` key), kept for them; it overshoots and rings, which a stroke shows
#: as lines along its rim (``benchmarks/falloff_striations.py``).
INTERPOLATIONS = ("monotone", "cubic")

#: Points on each side whose polynomial gives a point's slope (4th-order slopes).
_STENCIL = 2


def local_slopes(rho: np.ndarray, value: np.ndarray) -> np.ndarray:
    """At each point (n ≥ 3), the slope of the polynomial through it and its
    :data:`_STENCIL` neighbours on each side (shifted inwards at the ends): 4th-order accurate.
    Lagrange's formula for all points at once (a falloff reset rebuilds 30 curves on the GUI
    thread)."""
    rho = np.asarray(rho, dtype=np.float64)
    value = np.asarray(value, dtype=np.float64)
    n = len(rho)
    width = min(2 * _STENCIL + 1, n)
    point = np.arange(n)
    start = np.clip(point - _STENCIL, 0, n - width)
    window = start[:, None] + np.arange(width)  # (n, width) indices of each point's stencil
    x, y = rho[window], value[window]
    at = point - start  # the point's place in its stencil
    own = np.arange(width)[None, :] == at[:, None]  # (n, width)
    x_at = rho[:, None, None]
    # (x_i − x_k) / (x_j − x_k) over k ∉ {i, j}: the derivative at x_i of the j-th Lagrange
    # basis polynomial, ℓ_j′(x_i) = Π_k≠i,j (x_i − x_k) / Π_k≠j (x_j − x_k)
    skip = np.eye(width, dtype=bool)[None] | own[:, None, :]  # (n, j, k)
    gap_jk = np.where(skip, 1.0, x[:, :, None] - x[:, None, :])
    ratio = np.where(skip, 1.0, (x_at - x[:, None, :]) / gap_jk)
    gap_ji = np.where(own, 1.0, x - rho[:, None])
    weight = np.prod(ratio, axis=2) / gap_ji
    # ℓ_i′(x_i) = Σ_k≠i 1 / (x_i − x_k)
    weight[own] = np.sum(np.where(own, 0.0, 1.0 / np.where(own, 1.0, rho[:, None] - x)), axis=1)
    return np.asarray(np.sum(weight * y, axis=1))


def monotone_hermite(rho: np.ndarray, value: np.ndarray) -> CubicHermiteSpline:
    """The C¹ piecewise cubic through (ρ_i, value_i) (n ≥ 3), monotone on every interval: the
    :func:`local_slopes` limited as Fritsch & Carlson (1980) do (0 at a local extremum, else at
    most 3× the smaller neighbouring secant). Moving a point changes the curve near it alone.

    Not SciPy's PCHIP (2nd-order slopes): its curvature jumps at every control point (max
    |F″ − G″| on R₀ 1.41 against 0.05 here), which shows in a stroke's shading, and a tri-scale
    grab on it strains past the safety bound (2.03 against 1.61)."""
    rho = np.asarray(rho, dtype=np.float64)
    value = np.asarray(value, dtype=np.float64)
    secant = np.diff(value) / np.diff(rho)
    left = np.concatenate([secant[:1], secant])
    right = np.concatenate([secant, secant[-1:]])
    sign = np.sign(right)
    bound = 3.0 * np.minimum(np.abs(left), np.abs(right))
    limited = sign * np.minimum(np.maximum(sign * local_slopes(rho, value), 0.0), bound)
    return CubicHermiteSpline(rho, value, np.where(left * right > 0, limited, 0.0))


def interpolant(interpolation: str, rho: np.ndarray, value: np.ndarray) -> PPoly:
    """The curve through the control points (ρ (n,) increasing, value (n,)) by
    ``interpolation`` (one of :data:`INTERPOLATIONS`)."""
    if interpolation == "monotone":
        return monotone_hermite(rho, value)
    if interpolation == "cubic":
        return CubicSpline(rho, value, bc_type="not-a-knot")
    raise ValueError(
        f"spline interpolation must be one of {', '.join(INTERPOLATIONS)} (got {interpolation!r})"
    )
