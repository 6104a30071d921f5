"""The kernel's material coefficients: the quadrature sums of paper Eq. 10 and 12
(:func:`material_sums`, the expensive part, independent of the degree weights) and their packing
with signs, 1/(2π²), weights and output maps (:func:`pack_terms`, microseconds: a kernel repacks
for other weights with the arithmetic it was built with).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from gogreen_core.field._evaluation import Parity
from gogreen_core.physics.material import Material
from gogreen_core.physics.quadrature import material_rule
from gogreen_core.physics.sph import real_sph_harm
from gogreen_core.validation import check_finite

__all__ = ["checked_weights", "degree_norms", "material_sums", "pack_terms", "parity_ranges"]


def parity_ranges(l_max: int) -> tuple[tuple[int, int], tuple[int, int]]:
    """(first, last) degree of each parity for truncation ``l_max``: even l ≤ l_max for G,
    odd l ≤ l_max + 1 for ∇G."""
    return (0, l_max - l_max % 2), (1, l_max + 1 - l_max % 2)


def checked_weights(degree_weights: Sequence[float] | np.ndarray | None, l_max: int) -> np.ndarray:
    """Degree weights (l_max + 1,), read-only: all ones for None; ValueError for the wrong
    count or a value that is not finite."""
    weights = np.ones(l_max + 1) if degree_weights is None else np.array(degree_weights, float)
    if weights.shape != (l_max + 1,):
        count = f"l_max + 1 = {l_max + 1}"
        raise ValueError(f"degree_weights must have {count} values (got shape {weights.shape})")
    check_finite("degree_weights", weights)
    weights.setflags(write=False)
    return weights


def material_sums(material: Material, l_max: int) -> tuple[np.ndarray, np.ndarray]:
    """Σ_q w_q Y_lm(ξ_q) M⁻¹(ξ_q) for even l ≤ l_max ((n_even, 9)) and Σ_q w_q Y_lm(ξ_q)
    M⁻¹(ξ_q) ξ_q,p for odd l ≤ l_max + 1 ((n_odd, 27)): paper Eq. 10 and 12 before signs,
    normalization and weights."""
    nodes, qw = material_rule(material, l_max)
    (_, even_last), (_, odd_last) = parity_ranges(l_max)
    even_rows = [c for l in range(0, even_last + 1, 2) for c in range(l * l, (l + 1) ** 2)]
    odd_rows = [c for l in range(1, odd_last + 1, 2) for c in range(l * l, (l + 1) ** 2)]
    # in chunks of nodes that bound the harmonics to ~64 MB
    even_sum: np.ndarray | float = 0.0
    odd_sum: np.ndarray | float = 0.0
    chunk = max(256, 8_000_000 // (l_max + 2) ** 2)
    for start in range(0, len(nodes), chunk):
        part = nodes[start : start + chunk]
        m_inv = np.linalg.inv(material.acoustic_tensor(part))
        m_inv *= qw[start : start + chunk, None, None]
        flat = m_inv.reshape(len(part), 9)
        grad_flat = (m_inv[:, :, :, None] * part[:, None, None, :]).reshape(len(part), 27)
        rows = real_sph_harm(part, l_max + 1).T  # ((L+1)², n), C-contiguous
        even_sum = even_sum + rows[even_rows] @ flat
        odd_sum = odd_sum + rows[odd_rows] @ grad_flat
    return np.asarray(even_sum), np.asarray(odd_sum)


def pack_terms(
    sums: tuple[np.ndarray, np.ndarray],
    l_max: int,
    weights: np.ndarray,
    output_maps: np.ndarray | None = None,
) -> tuple[Parity, Parity]:
    """The even and odd packed coefficients: the sums times i^l (even l) or i^(l+1) (odd l),
    both real, the 1/(2π²) and the degree weight (the odd degree l takes ``weights[l − 1]``),
    then each degree's output map (``output_maps[l]``, l_max's for ∇G's top degree)."""
    if output_maps is not None:
        output_maps = check_finite("output_maps", output_maps, (l_max + 1, 3, 3))

    def pack(l_first: int, l_last: int, sums: np.ndarray, shape: tuple[int, ...]) -> Parity:
        base = np.full(l_last + 1 if l_last >= 0 else 1, -1, dtype=np.int64)
        factors: list[float] = []
        offset = 0
        for l in range(l_first, l_last + 1, 2):
            base[l] = offset
            offset += 2 * l + 1
            sign = (-1.0) ** ((l + (l % 2)) // 2)
            weight = weights[l] if l % 2 == 0 else weights[l - 1]
            factors.extend([sign * weight / (2 * np.pi**2)] * (2 * l + 1))
        mats = (sums * np.asarray(factors)[:, None]).reshape((offset, *shape))
        if output_maps is not None:
            for l in range(l_first, l_last + 1, 2):
                rows = slice(base[l], base[l] + 2 * l + 1)
                mats[rows] = np.einsum("ik,tk...->ti...", output_maps[min(l, l_max)], mats[rows])
        return Parity(l_first, l_last, mats, base)

    (_, even_last), (_, odd_last) = parity_ranges(l_max)
    return pack(0, even_last, sums[0], (3, 3)), pack(1, odd_last, sums[1], (3, 3, 3))


def degree_norms(sums: tuple[np.ndarray, np.ndarray], l_max: int) -> np.ndarray:
    """(l_max + 2,) the Frobenius norm of each degree's quadrature sums (Σ_m P_lm for even l,
    𝒫_lm for odd l), comparable between degrees of one parity."""
    norms = np.zeros(l_max + 2)
    for (first, last), parity_sums in zip(parity_ranges(l_max), sums, strict=True):
        for l in range(first, last + 1, 2):
            rows = parity_sums[l * (l - 1) // 2 : (l + 1) * (l + 2) // 2]
            norms[l] = float(np.sqrt(np.sum(rows * rows)))
    return norms
