"""Real spherical harmonics by the normalized associated-Legendre recurrence.

The real orthonormal basis of the kernel (no Condon–Shortley phase), for a unit (x, y, z):
``Y_l0 = Q_l^0(z)``, ``Y_lm = Q_l^m(z) Re[(x + i y)^m]``, ``Y_l,-m = Q_l^m(z) Im[(x + i y)^m]``
(m > 0), with the stable recurrence

    Q_m^m = sqrt((2m+1)/(2m)) Q_{m-1}^{m-1},    Q_0^0 = 1/sqrt(4π)  (√2 folded in at m = 1)
    Q_l^m = a_lm (z Q_{l-1}^m - b_lm Q_{l-2}^m)  for l > m   (Q_{m-1}^m = 0).

The compiled kernels use the same constants. Y_lm is stored at index ``l*l + l + m``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

__all__ = ["LegendreRecurrence", "legendre_recurrence", "real_sph_harm", "sh_index"]


def sh_index(l: int, m: int) -> int:
    """Column of Y_lm in the full basis returned by :func:`real_sph_harm`."""
    return l * l + l + m


@dataclass(frozen=True)
class LegendreRecurrence:
    """Constants of the normalized Legendre recurrence up to degree ``l_max``: ``qmm`` (L+1,)
    the Q_m^m, ``a``, ``b`` (L+1, L+1) a[l, m], b[l, m] for l > m (zero elsewhere)."""

    l_max: int
    qmm: np.ndarray
    a: np.ndarray
    b: np.ndarray


@lru_cache(maxsize=16)
def legendre_recurrence(l_max: int) -> LegendreRecurrence:
    """Recurrence constants for degrees 0..``l_max`` (cached, read-only arrays)."""
    size = l_max + 1
    steps = [np.sqrt((2.0 * m + 1.0) / (2.0 * m)) for m in range(1, size)]
    qmm = np.cumprod([1.0 / np.sqrt(4.0 * np.pi), *steps])
    qmm[1:] *= np.sqrt(2.0)
    a = np.zeros((size, size))
    b = np.zeros((size, size))
    for m in range(size):
        for l in range(m + 1, size):
            a[l, m] = np.sqrt((4.0 * l * l - 1.0) / (l * l - m * m))
            b[l, m] = np.sqrt(((l - 1.0) ** 2 - m * m) / (4.0 * (l - 1.0) ** 2 - 1.0))
    for arr in (qmm, a, b):
        arr.setflags(write=False)
    return LegendreRecurrence(l_max, qmm, a, b)


def real_sph_harm(directions: np.ndarray, l_max: int) -> np.ndarray:
    """Real orthonormal spherical harmonics (N, (l_max+1)²) of unit ``directions`` (N, 3), Y_lm
    at column ``sh_index(l, m)`` (precompute time; the kernels inline the same recurrence)."""
    d = np.asarray(directions, dtype=np.float64)
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    rec = legendre_recurrence(l_max)
    # filled row by row (contiguous), returned transposed
    out = np.empty(((l_max + 1) ** 2, d.shape[0]))
    cos_m, sin_m = np.ones_like(x), np.zeros_like(x)
    for m in range(l_max + 1):
        if m > 0:
            cos_m, sin_m = x * cos_m - y * sin_m, x * sin_m + y * cos_m
        prev2 = np.zeros_like(x)
        prev1 = np.full_like(x, rec.qmm[m])
        for l in range(m, l_max + 1):
            if l > m:
                prev1, prev2 = rec.a[l, m] * (z * prev1 - rec.b[l, m] * prev2), prev1
            if m == 0:
                out[sh_index(l, 0)] = prev1
            else:
                np.multiply(prev1, cos_m, out=out[sh_index(l, m)])
                np.multiply(prev1, sin_m, out=out[sh_index(l, -m)])
    return out.T
