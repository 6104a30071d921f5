"""Piecewise polynomial tables of the radial terms, the form the kernel evaluates them in.

Each radial term F(ρ) of a falloff (:mod:`gogreen_core.physics.radial`) is tabulated as F(ρ)(1+ρ)^p
(p = :data:`DECAY` of its kind, so the table stays bounded as ρ → ∞) on t = ρ/(1+ρ) ∈ [0, 1]:
:data:`TABLE_SEGMENTS` segments uniform in t, a polynomial of degree :data:`TABLE_DEGREE` on each,
interpolated at Chebyshev nodes. Tables depend on the falloff's shape alone and are cached by
its :meth:`~gogreen_core.physics.radial.RadialProfile.table_key`.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable
from functools import lru_cache
from typing import TYPE_CHECKING, Any, cast

import numpy as np

if TYPE_CHECKING:
    from gogreen_core.physics.radial import RadialProfile

__all__ = [
    "DECAY",
    "SINGLE_DEGREE",
    "TABLE_DEGREE",
    "TABLE_SEGMENTS",
    "cached_table",
    "radial_table",
    "single_table",
    "single_tables",
]

# Power p of the far-field decay r^-p of each kind; tables store F·(1+ρ)^p.
DECAY = {"R": 1, "dR": 2}

#: Piecewise polynomial tables: segments uniform in t = ρ/(1+ρ), polynomial degree per segment.
TABLE_SEGMENTS = 384
TABLE_DEGREE = 5
#: Polynomial degree of the single precision tables (:func:`single_table`), on the same segments.
SINGLE_DEGREE = 2


@lru_cache(maxsize=2)
def _chebyshev_to_monomial(degree: int = TABLE_DEGREE) -> tuple[np.ndarray, np.ndarray]:
    """Chebyshev nodes s_k on [-1, 1] and the matrix taking values there to the monomial
    coefficients of the interpolant of ``degree`` (via Chebyshev coefficients: well conditioned)."""
    n = degree + 1
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
    """One radial term as (S, D+1) float64: row j, on t ∈ [j/S, (j+1)/S] (S = TABLE_SEGMENTS),
    holds the monomial coefficients in s = 2(tS - j) - 1 ∈ [-1, 1] of F(ρ)(1+ρ)^p."""
    nodes, to_mono = _chebyshev_to_monomial()
    t = (np.arange(TABLE_SEGMENTS)[:, None] + 0.5 * (nodes[None, :] + 1)) / TABLE_SEGMENTS
    rho = t / (1 - t)
    values = profile.dimensionless(kind, l, rho.ravel()).reshape(rho.shape)
    values = values * (1 + rho) ** DECAY[kind]
    if not np.all(np.isfinite(values)):
        raise ValueError(f"falloff {profile!r} gives non-finite values for {kind}{l}")
    return cast(np.ndarray, values @ to_mono.T)


def single_table(table: np.ndarray) -> np.ndarray:
    """The streamlines' float32 table (S, 3) from a :func:`radial_table` of a degree l ≥ 1: on
    each segment the quadratic c₀ + (c₁ + c₂ σ) σ in σ = s + 1 ∈ [0, 2] through its values at
    Chebyshev nodes, except that the first segment's goes through the exact R_l(0) = 0 (c₀ = 0:
    the grabbed point follows the cursor). Off by ~1e-8 of the table's largest value, below
    the float32 rounding of the degrees it serves."""
    nodes, _ = _chebyshev_to_monomial(SINGLE_DEGREE)
    values = table @ (nodes[:, None] ** np.arange(table.shape[1])).T  # each segment at the nodes
    sigma = nodes + 1.0
    coeffs = np.linalg.solve(np.vander(sigma, increasing=True), values.T).T
    low = int(np.argmin(sigma))  # the node nearest σ = 0 moves there
    first, first_values = sigma.copy(), values[0].copy()
    first[low] = first_values[low] = 0.0
    coeffs[0] = np.linalg.solve(np.vander(first, increasing=True), first_values)
    coeffs[0, 0] = 0.0  # exactly
    return np.ascontiguousarray(coeffs, dtype=np.float32)


_TABLE_CACHE: dict[tuple[Any, ...], np.ndarray] = {}
_TABLE_CACHE_LIMIT = 1024
#: Kernels are built on a background thread too: evicting while another thread inserts raises.
_TABLE_CACHE_LOCK = threading.Lock()


def cached_table(key: tuple[Any, ...], kind: str, l: int, profile: RadialProfile) -> np.ndarray:
    """:func:`radial_table` of ``profile`` (whose table key is ``key``), cached (read-only)."""
    return _cached((key, kind, l), lambda: radial_table(profile, kind, l))


def _cached_single(key: tuple[Any, ...], kind: str, l: int, profile: RadialProfile) -> np.ndarray:
    return _cached(
        (key, kind, l, "single"), lambda: single_table(cached_table(key, kind, l, profile))
    )


def single_tables(profile: RadialProfile, kind: str, degrees: Iterable[int]) -> np.ndarray:
    """The streamlines' single precision tables of ``profile`` for ``degrees``, segment by
    segment: (S, n_degrees, SINGLE_DEGREE + 1) float32 (:func:`single_table`, cached)."""
    key = profile.table_key()
    tables = [_cached_single(key, kind, int(l), profile) for l in degrees]
    if not tables:
        return np.zeros((TABLE_SEGMENTS, 0, SINGLE_DEGREE + 1), dtype=np.float32)
    return np.stack(tables, axis=1)


def _cached(full_key: tuple[Any, ...], make: Callable[[], np.ndarray]) -> np.ndarray:
    table = _TABLE_CACHE.get(full_key)
    if table is None:
        table = make()
        table.setflags(write=False)
        with _TABLE_CACHE_LOCK:
            if len(_TABLE_CACHE) >= _TABLE_CACHE_LIMIT:
                _TABLE_CACHE.pop(next(iter(_TABLE_CACHE)))
            _TABLE_CACHE[full_key] = table
    return table
