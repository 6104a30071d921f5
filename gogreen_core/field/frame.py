"""A kernel turned with its material: the material term P_lm of paper Eq. 10 and 12 rotated by
Wigner-D matrices instead of a new quadrature. For C' = F·C, M'(ξ) = F M(Fᵀξ) Fᵀ, so with
Y_l(F η) = D_l(F) Y_l(η) (:func:`~gogreen_core.physics.sph_rotation.real_wigner_d`):

    P'_lm = F [Σ_m' D_l(F)_mm' P_lm'] Fᵀ                          (G's terms, even l)
    𝒫'_lm,ijp = Σ_m' D_l(F)_mm' F_ia F_jb F_pc 𝒫_lm',abc        (∇G's terms, odd l)

and G'(x) = F G(Fᵀx) Fᵀ follows term by term: exact, and a fraction of a millisecond where a new
quadrature costs tens to hundreds (``benchmarks/material_frame.py``).
"""

from __future__ import annotations

import numpy as np

from gogreen_core.field.coefficients import parity_ranges
from gogreen_core.physics.sph_rotation import real_wigner_d

__all__ = ["turned_sums"]


def turned_sums(
    sums: tuple[np.ndarray, np.ndarray], l_max: int, rotation: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The quadrature sums (:func:`~gogreen_core.field.coefficients.material_sums`: (n_even, 9)
    and (n_odd, 27)) of the material turned by ``rotation`` F (3, 3, orthogonal), from those of
    the material itself (see the module docstring)."""
    f = np.asarray(rotation, dtype=np.float64)
    (_, even_last), (_, odd_last) = parity_ranges(l_max)
    wigner = real_wigner_d(f, max(even_last, odd_last, 0))
    even, odd = sums
    out_even, out_odd = np.empty_like(even), np.empty_like(odd)
    for l in range(0, even_last + 1, 2):
        rows = slice(l * (l - 1) // 2, (l + 1) * (l + 2) // 2)  # the 2l + 1 rows of degree l
        mixed = (wigner[l] @ even[rows]).reshape(-1, 3, 3)
        out_even[rows] = np.einsum("ia,tab,jb->tij", f, mixed, f).reshape(-1, 9)
    for l in range(1, odd_last + 1, 2):
        rows = slice(l * (l - 1) // 2, (l + 1) * (l + 2) // 2)
        mixed = (wigner[l] @ odd[rows]).reshape(-1, 3, 3, 3)
        out_odd[rows] = np.einsum("ia,jb,pc,tabc->tijp", f, f, f, mixed).reshape(-1, 27)
    return out_even, out_odd
