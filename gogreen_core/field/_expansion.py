"""Numba evaluation of one parity of the SH expansion (paper Eqs. 10 and 12), per block of points.

    out[n, k] = Σ_{l ∈ degrees} T_l(t_n) / (r_n + ε)^p  Σ_m Y_lm(x̂_n) coeffs[base_l + l + m, k]

with x = points[n] - center, r = |x|, t = r/(r+ε), T_l the piecewise polynomial radial tables of
``radial.py`` and Y_lm the real harmonics of ``sph.py`` in the rescaled form of ``_unrolled``
(Legendre scales folded into ``coeffs``). G, ∇G, vector and affine loads differ only in ``coeffs``.
The generic ``_angular`` here and ``_unrolled``'s kernels (2-3x faster) perform the same IEEE
operations in the same order (no ``fastmath``): a replay gives the same bits whichever served.

The functions are serial and release the GIL (``_parallel`` runs them over ranges of blocks:
serial ones compile far faster than ``parallel=True``). Points go in blocks of ``BLOCK`` on
contiguous scratch rows so that LLVM vectorizes across points; ``error_model="numpy"`` drops the
zero-division checks that block vectorization; loops touch few arrays each (LLVM gives up when
runtime alias checks grow too many).
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit, types
from numba.np.numpy_support import carray
from numpy.typing import NDArray

if TYPE_CHECKING:
    from gogreen_core._jit_options import NogilJitOptions

# numba's OpenMP layer (``geometry.py``'s parallel functions) lets idle threads spin by default,
# starving the working ones on shared cores (a 1M-vertex grab event: 186-234 ms -> 83-85 ms).
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

#: Points per block (with 256, each block's fixed loop costs made a streamline pass 13 % slower).
BLOCK = 1024
#: Polynomial degree of the radial table segments that ``_radial`` evaluates (radial.py's).
SEGMENT_DEGREE = 5

_JIT: NogilJitOptions = {"cache": True, "boundscheck": False, "error_model": "numpy", "nogil": True}


#: Signature of ``_unrolled``'s kernels: (nb, geo (8, BLOCK), rad (n_deg, BLOCK), coeffs
#: (n_terms, 3), acc (3, BLOCK)) as pointers. First-class functions: the drivers compile once.
_F8P = types.CPointer(types.float64)
ANGULAR_SIGNATURE = types.void(types.int64, _F8P, _F8P, _F8P, _F8P)
#: The same for the single precision kernels of the streamlines (float32 rows).
_F4P = types.CPointer(types.float32)
ANGULAR_SINGLE_SIGNATURE = types.void(types.int64, _F4P, _F4P, _F4P, _F4P)


def generic_marker(nb: int, geo: Any, rad: Any, coeffs: Any, acc: Any) -> None:
    """Passed as ``angular`` with ``unrolled=False`` (``_drivers.generic_marker``): never run."""
    carray(acc, (3, BLOCK))[0, 0] = np.nan  # pragma: no cover


# Exact power-of-two scales for norms of offsets whose squares overflow (see ``_geometry``).
_TINY = 2.0**-600
_HUGE = 2.0**600


#: The cutoff weight is exactly 0 from u = (d - inner) / (outer - inner) ≥ CUTOFF_END on (the
#: smoothstep is below 1e-26 there): a vertex at rounding distance from the influence ball's
#: surface does not move whether the influence test counts it in or out.
CUTOFF_END = 1.0 - 2.0**-30


@njit(**_JIT)
def _geometry(
    eps: float, power: int, n_seg: int, nb: int, geo: NDArray[np.float64], seg: NDArray[np.int64]
) -> None:
    """Rows of ``geo``: x̂, ŷ, ẑ, r, local table variable, 1/(r+ε)^p for l = 0 and for l ≥ 1,
    from the offsets x - c in rows 0-2 (normalized in place); ``seg`` gets each point's segment.
    At r = 0 the direction and the l ≥ 1 scale are 0 (R_l(0) = ℛ_l(0) = 0 for l ≥ 1). Where
    x² + y² + z² would overflow, r comes from the offsets scaled by 2⁻⁶⁰⁰ (exact)."""
    x, y, z, rr, loc, scale0, scale1 = geo[0], geo[1], geo[2], geo[3], geo[4], geo[5], geo[6]
    n_huge = 0
    for i in range(nb):
        r2 = x[i] * x[i] + y[i] * y[i] + z[i] * z[i]
        n_huge += 0 if r2 < 1e300 else 1
        rr[i] = math.sqrt(r2)
    if n_huge > 0:
        # rare: a loop of its own, so that the common one takes one square root per point
        for i in range(nb):
            if not x[i] * x[i] + y[i] * y[i] + z[i] * z[i] < 1e300:
                xs, ys, zs = x[i] * _TINY, y[i] * _TINY, z[i] * _TINY
                rr[i] = math.sqrt(xs * xs + ys * ys + zs * zs) * _HUGE
    for i in range(nb):
        r = rr[i]
        inv = 1.0 / r if r > 0.0 else 0.0
        x[i] *= inv
        y[i] *= inv
        z[i] *= inv
    for i in range(nb):
        r = rr[i]
        inv_re = 1.0 / (r + eps)
        u = min(r * inv_re, 1.0) * n_seg
        fj = min(math.floor(u), n_seg - 1.0)
        seg[i] = int(fj)
        loc[i] = 2.0 * (u - fj) - 1.0
        sc = inv_re if power == 1 else inv_re * inv_re
        scale0[i] = sc
        scale1[i] = sc if r > 0.0 else 0.0


@njit(**_JIT)
def _radial(
    tables: NDArray[np.float64],
    l_first: int,
    nb: int,
    geo: NDArray[np.float64],
    seg: NDArray[np.int64],
    rad: NDArray[np.float64],
) -> None:
    """rad[d, i] = R_l(r_i) (or ℛ_l) for every degree of the parity (d = (l - l_first) / 2):
    the degree-5 segment polynomial by Estrin's scheme, degrees outermost (the loop over the
    points vectorizes with gathers)."""
    loc, scale0, scale1 = geo[4], geo[5], geo[6]
    for d in range(tables.shape[0]):
        c = tables[d]
        row = rad[d]
        # degree 0 keeps its value at r = 0 (G(0) is its l = 0 term); l ≥ 1 vanish there
        scale = scale0 if d == 0 and l_first == 0 else scale1
        for i in range(nb):
            # an unsigned row: no negative-index wrap-around test per load (1.1x faster)
            j = np.uint64(seg[i])
            s = loc[i]
            s2 = s * s
            p01 = c[j, 0] + c[j, 1] * s
            p23 = c[j, 2] + c[j, 3] * s
            p45 = c[j, 4] + c[j, 5] * s
            row[i] = (p01 + (p23 + p45 * s2) * s2) * scale[i]


@njit(**_JIT)
def _angular(
    l_first: int,
    l_last: int,
    base: NDArray[np.int64],
    coeffs: NDArray[np.float64],
    beta: NDArray[np.float64],
    nb: int,
    geo: NDArray[np.float64],
    rad: NDArray[np.float64],
    work: NDArray[np.float64],
    acc: NDArray[np.float64],
) -> None:
    """acc[k, i] = Σ_l rad[l, i] Σ_m Y_lm(x̂_i) coeffs[row(l, m), k] for one block, K outputs:
    the arithmetic of ``_unrolled.angular_source`` (see there), operation for operation, on
    (4 + 2K, BLOCK) scratch rows ``work``."""
    x, y, z = geo[0], geo[1], geo[2]
    cos_m, sin_m, prev, cur = work[0], work[1], work[2], work[3]
    n_out = acc.shape[0]
    part_a = work[4 : 4 + n_out]
    part_b = work[4 + n_out : 4 + 2 * n_out]
    for m in range(l_last + 1):
        if m == 1:
            for i in range(nb):
                cos_m[i] = x[i]
                sin_m[i] = y[i]
        elif m > 1:
            for i in range(nb):
                c_old = cos_m[i]
                cos_m[i] = c_old * x[i] - sin_m[i] * y[i]
                sin_m[i] = c_old * y[i] + sin_m[i] * x[i]
        first = True
        for l in range(m, l_last + 1):
            if l == m + 1:
                for i in range(nb):
                    prev[i] = 1.0
                    cur[i] = z[i]
            elif l > m + 1:
                b = beta[l, m]
                for i in range(nb):
                    p_new = z[i] * cur[i] - b * prev[i]
                    prev[i] = cur[i]
                    cur[i] = p_new
            if (l - l_first) % 2 != 0 or l < l_first:
                continue
            row = rad[(l - l_first) // 2]
            row_c = base[l] + l + m
            row_s = base[l] + l - m
            # the sine part B only for m > 0 (m = 0 has no sine term)
            for k in range(n_out):
                ca = coeffs[row_c, k]
                cs = coeffs[row_s, k]
                a_k = part_a[k]
                b_k = part_b[k]
                if l == m:  # P_m = 1: t = R_l, always the first term of order m
                    for i in range(nb):
                        a_k[i] = row[i] * ca
                    if m > 0:
                        for i in range(nb):
                            b_k[i] = row[i] * cs
                elif first:
                    for i in range(nb):
                        a_k[i] = (row[i] * cur[i]) * ca
                    if m > 0:
                        for i in range(nb):
                            b_k[i] = (row[i] * cur[i]) * cs
                else:
                    for i in range(nb):
                        a_k[i] = a_k[i] + (row[i] * cur[i]) * ca
                    if m > 0:
                        for i in range(nb):
                            b_k[i] = b_k[i] + (row[i] * cur[i]) * cs
            first = False
        for k in range(n_out):
            a_k = part_a[k]
            b_k = part_b[k]
            u_k = acc[k]
            if m == 0:
                for i in range(nb):
                    u_k[i] = a_k[i]
            else:
                for i in range(nb):
                    u_k[i] = (u_k[i] + cos_m[i] * a_k[i]) + sin_m[i] * b_k[i]


@njit(**_JIT)
def expand_blocks(
    points: NDArray[np.float64],  # (N, 3) float64
    center: NDArray[np.float64],  # (3,) float64
    eps: float,
    power: int,  # 1 for R_l (G), 2 for ℛ_l (∇G)
    l_first: int,  # 0 (even degrees) or 1 (odd degrees)
    l_last: int,  # highest degree of the parity
    base: NDArray[np.int64],  # (l_last+1,) int64: coeff row of Y_l,-l for each degree l used
    coeffs: NDArray[np.float64],  # (n_terms, K) float64, Legendre scales folded in (``_unrolled``)
    beta: NDArray[np.float64],  # (L+1, L+1) rescaled recurrence constants β_lm
    tables: NDArray[np.float64],  # (n_deg, S, SEGMENT_DEGREE+1); degree index (l - l_first) // 2
    angular: Any,  # ANGULAR_SIGNATURE function generated for these degrees (K = 3)
    unrolled: bool,  # use ``angular``; else the generic ``_angular``
    out: NDArray[np.float64],  # (N, K) float64: rows of the blocks below overwritten
    first_block: int,
    last_block: int,  # blocks [first_block, last_block) of BLOCK points
) -> None:
    """``out`` rows of blocks first_block … last_block - 1 (see the module docstring)."""
    n_points = points.shape[0]
    n_out = coeffs.shape[1]
    geo = np.empty((8, BLOCK))
    seg = np.empty(BLOCK, dtype=np.int64)
    rad = np.empty((tables.shape[0], BLOCK))
    work = np.empty((4 + 2 * n_out, BLOCK))
    acc = np.empty((n_out, BLOCK))
    for blk in range(first_block, last_block):
        start = blk * BLOCK
        nb = min(BLOCK, n_points - start)
        for i in range(nb):
            geo[0, i] = points[start + i, 0] - center[0]
            geo[1, i] = points[start + i, 1] - center[1]
        for i in range(nb):
            geo[2, i] = points[start + i, 2] - center[2]
        _geometry(eps, power, tables.shape[1], nb, geo, seg)
        _radial(tables, l_first, nb, geo, seg, rad)
        if unrolled:
            angular(nb, geo.ctypes, rad.ctypes, coeffs.ctypes, acc.ctypes)
        else:
            _angular(l_first, l_last, base, coeffs, beta, nb, geo, rad, work, acc)
        for i in range(nb):
            for k in range(n_out):
                out[start + i, k] = acc[k, i]
