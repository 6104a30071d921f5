"""Quadrature rules on the unit sphere for the material matrices of the Green's function.

P_lm = ∫_S² M(ξ̂)⁻¹ Y_lm(ξ̂) dS (paper Eq. 10) and 𝒫_lm,p (Eq. 12) are integrated once per
material: by the paper's Lebedev rule where M⁻¹ is smooth, and by a product rule graded toward
the material's axis where it is sharply peaked (:func:`material_rule`).
"""

from __future__ import annotations

from functools import lru_cache
from typing import cast

import numpy as np
from scipy.integrate import lebedev_rule

from gogreen_core.physics.material import Material

__all__ = ["CHECK_ORDER", "QUADRATURE_ORDER", "QUADRATURE_RTOL", "lebedev_points", "material_rule"]

#: The paper's Lebedev rule (5,810 nodes, exact to degree 131), when M(ξ̂)⁻¹ is smooth enough.
QUADRATURE_ORDER = 131
#: Lower rule whose disagreement on the low moments of M⁻¹ measures M⁻¹'s content between
#: degrees ~70 and 131, which would alias into the coefficients of degree ≤ 61.
CHECK_ORDER = 71
#: Relative accuracy asked of the material matrices (against their largest entry).
QUADRATURE_RTOL = 1e-11


@lru_cache(maxsize=4)
def lebedev_points(order: int = QUADRATURE_ORDER) -> tuple[np.ndarray, np.ndarray]:
    """Lebedev nodes (n, 3) on the unit sphere and weights (n,) summing to 4π (read-only)."""
    nodes, weights = lebedev_rule(order)
    nodes = np.ascontiguousarray(nodes.T)
    nodes.setflags(write=False)
    weights.setflags(write=False)
    return nodes, weights


def _low_moments(material: Material, nodes: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """∫ M⁻¹ ξ̂^α dS for the monomials of degree ≤ 2 (10, 3, 3): the error indicator."""
    m_inv = np.linalg.inv(material.acoustic_tensor(nodes))
    x, y, z = nodes.T
    mono = np.stack([np.ones_like(x), x, y, z, x * x, y * y, z * z, x * y, x * z, y * z])
    return cast(np.ndarray, ((mono * weights) @ m_inv.reshape(len(nodes), 9)).reshape(10, 3, 3))


def _material_frame(material: Material) -> np.ndarray:
    """Rotation (3, 3) whose last column is the eigenvector of A_ij = C_ikjk farthest (in ratio)
    from the others: M⁻¹'s ridge or peaks then lie where the product rule grades its nodes."""
    values, vectors = np.linalg.eigh(np.einsum("ikjk->ij", material.tensor))
    logs = np.log(np.maximum(values, values[-1] * 1e-300))
    axis = 0 if logs[1] - logs[0] > logs[2] - logs[1] else 2
    others = [k for k in range(3) if k != axis]
    frame = vectors[:, [*others, axis]]
    return frame if np.linalg.det(frame) > 0 else frame * np.array([-1.0, 1.0, 1.0])


def _product_rule(
    l_max: int, level: int, frame: np.ndarray, finest: float
) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre in θ × trapezoid in φ, in ``frame``: nodes (n, 3), weights (n,). θ panels
    resolve Y_lm to l_max + 1, graded toward the equator and poles (M⁻¹'s ridges and peaks)
    down to width ``finest``; ``level`` raises the points per panel and in φ."""
    coarse_points, fine_points = 16 + 4 * level, 8 + 4 * level
    n_uniform = int(np.ceil(np.pi * (l_max + 2) / (4 * (coarse_points - 8))))
    uniform_width = np.pi / (2 * n_uniform)
    edge_set = set(np.linspace(0.0, np.pi, 2 * n_uniform + 1).tolist())
    width = finest
    while width < uniform_width / 2:
        edge_set.update((width, np.pi / 2 - width, np.pi / 2 + width, np.pi - width))
        width *= 2.0
    edges = np.array(sorted(edge_set))
    thetas, theta_weights = [], []
    for points in (coarse_points, fine_points):
        lo, hi = edges[:-1], edges[1:]
        pick = ((hi - lo) > 0.75 * uniform_width) == (points == coarse_points)
        lo, hi = lo[pick, None], hi[pick, None]
        gx, gw = np.polynomial.legendre.leggauss(points)
        thetas.append((lo + 0.5 * (hi - lo) * (gx + 1)).ravel())
        theta_weights.append((0.5 * (hi - lo) * gw).ravel())
    theta = np.concatenate(thetas)
    w_theta = np.concatenate(theta_weights) * np.sin(theta)
    n_phi = 2 * (l_max + 2) + 24 * (level + 1)
    phi = 2 * np.pi * np.arange(n_phi) / n_phi
    sin_t = np.sin(theta)[:, None]
    local = np.stack(
        [sin_t * np.cos(phi), sin_t * np.sin(phi), np.cos(theta)[:, None] + 0 * phi], axis=-1
    ).reshape(-1, 3)
    weights = np.repeat(w_theta, n_phi) * (2 * np.pi / n_phi)
    return local @ frame.T, weights


def material_rule(
    material: Material, l_max: int, rtol: float = QUADRATURE_RTOL
) -> tuple[np.ndarray, np.ndarray]:
    """Quadrature nodes (n, 3) and weights (n,) on the unit sphere for the material matrices
    P_lm = ∫ M(ξ̂)⁻¹ Y_lm dS of truncation ``l_max``, accurate to ``rtol`` (relative).

    The paper's Lebedev rule (order 131) when the order-71 rule agrees with it on the moments
    of M⁻¹ up to degree 2 (nothing to alias); for strong anisotropy M⁻¹ is sharply peaked
    (fibres at contrast 10⁴: Lebedev's l = 0 term off by 1.5e-3), and a product rule graded
    toward the material's axis is refined until two levels agree (at most four)."""
    nodes, weights = lebedev_points()
    reference = _low_moments(material, nodes, weights)
    scale = np.abs(reference).max()
    check = _low_moments(material, *lebedev_points(CHECK_ORDER))
    if np.abs(check - reference).max() <= rtol * scale:
        return nodes, weights
    frame = _material_frame(material)
    stiffness = np.linalg.eigvalsh(material.voigt)
    finest = min(0.05, 0.1 * np.sqrt(stiffness[0] / stiffness[-1]))
    coarse = _product_rule(l_max, 0, frame, finest)
    coarse_moments = _low_moments(material, *coarse)
    for level in range(1, 4):
        fine = _product_rule(l_max, level, frame, finest)
        fine_moments = _low_moments(material, *fine)
        if np.abs(fine_moments - coarse_moments).max() <= rtol * scale:
            return coarse  # two levels agree: the cheaper one is accurate
        coarse, coarse_moments = fine, fine_moments
    return coarse
