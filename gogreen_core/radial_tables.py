"""Piecewise polynomial tables of the radial terms, the form the kernel evaluates them in.

Each radial term F(ρ) of a falloff (:mod:`gogreen_core.radial`) is tabulated as F(ρ)(1+ρ)^p
(p = :data:`DECAY` of its kind, so the table stays bounded as ρ → ∞) on t = ρ/(1+ρ) ∈ [0, 1]:
:data:`TABLE_SEGMENTS` segments uniform in t, a polynomial of degree :data:`TABLE_DEGREE` on each,
interpolated at Chebyshev nodes. Tables depend on the falloff's shape alone and are cached by
its :meth:`~gogreen_core.radial.RadialProfile.table_key`.
"""

from __future__ import annotations

import threading
from functools import lru_cache
from typing import TYPE_CHECKING, Any, cast

import numpy as np

if TYPE_CHECKING:
    from gogreen_core.radial import RadialProfile

__all__ = ["DECAY", "TABLE_DEGREE", "TABLE_SEGMENTS", "cached_table", "radial_table"]

# Power p of the far-field decay r^-p of each kind; tables store F·(1+ρ)^p.
DECAY = {"R": 1, "dR": 2}

#: Piecewise polynomial tables: segments uniform in t = ρ/(1+ρ), polynomial degree per segment.
TABLE_SEGMENTS = 384
TABLE_DEGREE = 5


@lru_cache(maxsize=1)
def _chebyshev_to_monomial() -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev nodes s_k on [-1, 1] and the matrix taking values there to monomial
    coefficients of the interpolating polynomial (via Chebyshev coefficients, well conditioned)."""
    n = TABLE_DEGREE + 1
    k = np.arange(n)
    nodes = np.cos((2 * k + 1) * np.pi / (2 * n))
    # values -> Chebyshev coefficients (discrete orthogonality at Chebyshev-Gauss nodes)
    t = np.cos(np.outer(np.arange(n), (2 * k + 1) * np.pi / (2 * n)))  # T_j(s_k)
    to_cheb = (2.0 / n) * t
    to_cheb[0] *= 0.5
    cheb_to_mono = np.zeros((n, n))  # row j: monomial coefficients of T_j
    for j in range(n):
        mono = np.polynomial.chebyshev.cheb2poly(np.eye(n)[j])
        cheb_to_mono[j, : len(mono)] = mono
    return nodes, cheb_to_mono.T @ to_cheb


def radial_table(profile: RadialProfile, kind: str, l: int) -> np.ndarray:
    """Tabulate one radial term as a piecewise polynomial in t = ρ/(1+ρ).

    Segment j covers t ∈ [j/S, (j+1)/S] (S = TABLE_SEGMENTS) with local variable
    s = 2(tS - j) - 1 ∈ [-1, 1]; row j holds monomial coefficients c_0..c_D of
    F(ρ)(1+ρ)^p in s (p = 1 for "R", 2 for "dR"), interpolated at Chebyshev nodes.
    Returns (S, D+1) float64.
    """
    nodes, to_mono = _chebyshev_to_monomial()
    t = (np.arange(TABLE_SEGMENTS)[:, None] + 0.5 * (nodes[None, :] + 1)) / TABLE_SEGMENTS
    rho = t / (1 - t)
    values = profile.dimensionless(kind, l, rho.ravel()).reshape(rho.shape)
    values = values * (1 + rho) ** DECAY[kind]
    if not np.all(np.isfinite(values)):
        raise ValueError(f"falloff {profile!r} gives non-finite values for {kind}{l}")
    return cast(np.ndarray, values @ to_mono.T)


_TABLE_CACHE: dict[tuple[Any, ...], np.ndarray] = {}
_TABLE_CACHE_LIMIT = 1024
#: Kernels are built on the app's background thread too: evicting (iterating the dict) while
#: another thread inserts would raise.
_TABLE_CACHE_LOCK = threading.Lock()


def cached_table(key: tuple[Any, ...], kind: str, l: int, profile: RadialProfile) -> np.ndarray:
    full_key = (key, kind, l)
    table = _TABLE_CACHE.get(full_key)
    if table is None:
        table = radial_table(profile, kind, l)
        table.setflags(write=False)
        with _TABLE_CACHE_LOCK:
            if len(_TABLE_CACHE) >= _TABLE_CACHE_LIMIT:
                _TABLE_CACHE.pop(next(iter(_TABLE_CACHE)))
            _TABLE_CACHE[full_key] = table
    return table
