"""The real Wigner-D matrices of an orthogonal 3×3 map Q (a rotation or a reflection):
Y_l(Q η) = D_l(Q) Y_l(η), D_l (2l+1, 2l+1) orthogonal, in the basis of
:mod:`~gogreen_core.physics.sph`. As that basis is orthonormal, D_l(Q) = ∫ Y_l(Q η) Y_l(η)ᵀ dη,
exact to rounding by a Lebedev rule of degree 2 l: the material term P_lm of a turned material
is a Wigner-D mix of the unturned one's (paper Eq. 10), with no Euler angles or gimbal cases.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from gogreen_core.physics.quadrature import lebedev_points
from gogreen_core.physics.sph import real_sph_harm

__all__ = ["LEBEDEV_ORDERS", "real_wigner_d"]

#: The Lebedev orders SciPy provides (odd up to 31, then every 6th up to 131).
LEBEDEV_ORDERS = (*range(3, 32, 2), *range(35, 132, 6))
#: Nodes per block of the quadrature (bounds the harmonics' memory at high degree).
_CHUNK = 1024


@lru_cache(maxsize=8)
def _rule(l_top: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lebedev nodes (n, 3), weights (n,) exact for degree 2 ``l_top``, and w · Y(η) at them
    ((l_top + 1)², n), read-only."""
    order = next((o for o in LEBEDEV_ORDERS if o >= 2 * l_top + 1), None)
    if order is None:
        raise ValueError(f"degree {l_top} is beyond the Lebedev rules available (65)")
    nodes, weights = lebedev_points(order)
    weighted = np.ascontiguousarray(real_sph_harm(nodes, l_top).T * weights)
    weighted.setflags(write=False)
    return nodes, weights, weighted


def real_wigner_d(transform: np.ndarray, l_top: int) -> list[np.ndarray]:
    """The real Wigner-D matrices D_l(Q) ((2l+1, 2l+1) each, l = 0 … ``l_top``) of the
    orthogonal ``transform`` Q (3, 3): Y_l(Q η) = D_l Y_l(η) for every unit η.

    ValueError when Q is not orthogonal (within 1e-9). Degrees up to 65."""
    q = np.asarray(transform, dtype=np.float64)
    if q.shape != (3, 3) or not np.all(np.isfinite(q)):
        raise ValueError(f"transform must be a finite 3x3 matrix (got shape {q.shape})")
    if np.abs(q @ q.T - np.eye(3)).max() > 1e-9:
        raise ValueError("transform must be orthogonal (a rotation or a reflection)")
    nodes, _, weighted = _rule(l_top)
    blocks = [np.zeros((2 * l + 1, 2 * l + 1)) for l in range(l_top + 1)]
    for start in range(0, len(nodes), _CHUNK):
        turned = real_sph_harm(nodes[start : start + _CHUNK] @ q.T, l_top).T  # ((L+1)², n)
        base = weighted[:, start : start + _CHUNK]
        for l, block in enumerate(blocks):
            rows = slice(l * l, (l + 1) ** 2)
            block += turned[rows] @ base[rows].T
    return blocks
