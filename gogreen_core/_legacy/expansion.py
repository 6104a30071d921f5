"""The evaluation of sessions recorded before version 3 (evaluation 1), kept unchanged.

Frozen: the arithmetic here (operation order, the fused multiply-adds LLVM chose under
``fastmath={"contract"}``, the parallel drivers) is what produced every result of session
files of versions 1 and 2, so that they replay bit for bit (``GreenKernel(...,
evaluation=1)``). Do not edit; the current evaluation is ``gogreen_core._expansion``.

Numba evaluation of one parity of the SH expansion (paper Eqs. 10 and 12).

    out[n, k] = Σ_{l ∈ degrees} T_l(t_n) / (r_n + ε)^p  Σ_m Y_lm(x̂_n) coeffs[base_l + l + m, k]

with x = points[n] - center, r = |x|, t = r/(r+ε), T_l the piecewise polynomial radial tables of
``radial.py`` and Y_lm the real harmonics of ``sph.py``. One compiled function serves every use
(G, ∇G, vector and affine loads): they differ only in ``coeffs`` (n_terms, K).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import cfunc, njit, prange, types
from numba.np.numpy_support import carray

if TYPE_CHECKING:
    from gogreen_core._jit_options import JitOptions

# (OMP_WAIT_POLICY: set by gogreen_core._expansion, imported before this module)

BLOCK = 256
# Parallel tasks per call; each reuses one set of scratch rows for a contiguous run of blocks.
TASKS = 64
#: Polynomial degree of the radial table segments that ``_radial`` evaluates (radial.py's).
SEGMENT_DEGREE = 5

_JIT: JitOptions = {
    "cache": True,
    "fastmath": {"contract"},
    "boundscheck": False,
    "error_model": "numpy",
}

#: Signature of the angular kernels generated per degree by ``_unrolled``:
#: (nb, geo (8, BLOCK), rad (n_deg, BLOCK), coeffs (n_terms, 3), acc (3, BLOCK)), C-contiguous
#: arrays passed as pointers. They reach the drivers below as first-class functions, so the
#: drivers are compiled (and cached on disk) once, whatever the degree.
_F8P = types.CPointer(types.float64)
ANGULAR_SIGNATURE = types.void(types.int64, _F8P, _F8P, _F8P, _F8P)


@cfunc(ANGULAR_SIGNATURE, cache=True)
def generic_marker(  # pragma: no cover - never called
    nb: int, geo: Any, rad: Any, coeffs: Any, acc: Any
) -> None:
    """Passed as ``angular`` with ``unrolled=False``: the drivers then run ``_angular``."""
    carray(acc, (3, BLOCK))[:, :nb] = np.nan


@njit(parallel=True, nogil=True, **_JIT)
def expand(
    points: np.ndarray,  # (N, 3) float64
    center: np.ndarray,  # (3,) float64
    eps: float,
    power: int,  # 1 for R_l (G), 2 for ℛ_l (∇G)
    l_first: int,  # 0 (even degrees) or 1 (odd degrees)
    l_last: int,  # highest degree of the parity
    base: np.ndarray,  # (l_last+1,) int64: coeff row of Y_l,-l for each degree l used
    coeffs: np.ndarray,  # (n_terms, K) float64
    tables: np.ndarray,  # (n_deg, S, SEGMENT_DEGREE+1) float64; degree index (l - l_first) // 2
    qmm: np.ndarray,  # (L+1,) Legendre constants Q_m^m
    rec_a: np.ndarray,  # (L+1, L+1) recurrence a_lm
    rec_b: np.ndarray,  # (L+1, L+1) recurrence b_lm
    angular: Any,  # ANGULAR_SIGNATURE function generated for these degrees (K = 3)
    unrolled: bool,  # use ``angular``; else the generic ``_angular``
    out: np.ndarray,  # (N, K) float64, overwritten
) -> None:
    n_points = points.shape[0]
    n_out = coeffs.shape[1]
    n_deg = tables.shape[0]
    n_blocks = (n_points + BLOCK - 1) // BLOCK
    n_tasks = min(n_blocks, TASKS)
    for task in prange(n_tasks):
        geo = np.empty((8, BLOCK))
        seg = np.empty(BLOCK, dtype=np.int64)
        rad = np.empty((n_deg, BLOCK))
        work = np.empty((6, BLOCK))
        acc = np.empty((n_out, BLOCK))
        for blk in range(task * n_blocks // n_tasks, (task + 1) * n_blocks // n_tasks):
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
                _angular(l_first, l_last, base, coeffs, qmm, rec_a, rec_b, nb, geo, rad, work, acc)
            for i in range(nb):
                for k in range(n_out):
                    out[start + i, k] = acc[k, i]


# Exact power-of-two scales for norms of offsets whose squares overflow (see ``_geometry``).
_TINY = 2.0**-600
_HUGE = 2.0**600


@njit(nogil=True, **_JIT)
def _geometry(
    eps: float, power: int, n_seg: int, nb: int, geo: np.ndarray, seg: np.ndarray
) -> None:
    """Rows of ``geo``: x̂, ŷ, ẑ, r, local table variable, 1/(r+ε)^p for l = 0 and for l ≥ 1,
    from the offsets x - c the caller wrote in rows 0-2 (normalized in place); ``seg`` gets each
    point's table segment.

    At r = 0 the direction is 0 and the l ≥ 1 scale is 0: R_l(0) = ℛ_l(0) = 0 for l ≥ 1, so G(0)
    is its exact degree-0 term and ∇G(0) = 0 with no special case downstream.

    Far points: where x² + y² + z² would overflow (r ≳ 1e154) r is computed from the offsets
    scaled by 2⁻⁶⁰⁰ (exact), so every finite offset up to ~1e300 gives a finite r, direction and
    table variable, and the far field its 1/r (1/r² for ∇G) decay, underflowing to 0 at worst.
    """
    x, y, z, rr, loc, scale0, scale1 = geo[0], geo[1], geo[2], geo[3], geo[4], geo[5], geo[6]
    n_huge = 0
    for i in range(nb):
        r2 = x[i] * x[i] + y[i] * y[i] + z[i] * z[i]
        n_huge += 0 if r2 < 1e300 else 1
        rr[i] = math.sqrt(r2)
    if n_huge > 0:
        # rare: a loop of its own, so that the common one takes one square root per point
        for i in range(nb):
            r2 = x[i] * x[i] + y[i] * y[i] + z[i] * z[i]
            if not r2 < 1e300:
                xs, ys, zs = x[i] * _TINY, y[i] * _TINY, z[i] * _TINY
                rr[i] = math.sqrt(xs * xs + ys * ys + zs * zs) * _HUGE
    for i in range(nb):
        r = rr[i]
        scale1[i] = 1.0 / r if r > 0.0 else 0.0
    for i in range(nb):
        x[i] *= scale1[i]
        y[i] *= scale1[i]
    for i in range(nb):
        z[i] *= scale1[i]
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


@njit(nogil=True, **_JIT)
def _radial(
    tables: np.ndarray, l_first: int, nb: int, geo: np.ndarray, seg: np.ndarray, rad: np.ndarray
) -> None:
    """rad[d, i] = R_l(r_i) (or ℛ_l) for every degree of the parity (d = (l - l_first) / 2).

    The degree-5 segment polynomial by Estrin's scheme (depth 3). Each point reads its own
    segment; degrees outermost, so that the loop over the block's points vectorizes with
    gathers (a segment's six coefficients are contiguous per degree). Measured on 10⁶ points,
    five degrees, one thread: 7.8 ms, where the point-outer loop (scalar, coefficients of all
    degrees contiguous) took 9.5 ms. 384 segments of degree 5 need 6 loads per degree where
    96 of degree 9 needed 10, for the same accuracy.
    """
    loc, scale0, scale1 = geo[4], geo[5], geo[6]
    for d in range(tables.shape[0]):
        c = tables[d]
        row = rad[d]
        # degree 0 keeps its value at r = 0 (G(0) is its l = 0 term); l ≥ 1 vanish there
        scale = scale0 if d == 0 and l_first == 0 else scale1
        for i in range(nb):
            j = seg[i]
            s = loc[i]
            s2 = s * s
            p01 = c[j, 0] + c[j, 1] * s
            p23 = c[j, 2] + c[j, 3] * s
            p45 = c[j, 4] + c[j, 5] * s
            row[i] = (p01 + (p23 + p45 * s2) * s2) * scale[i]


@njit(nogil=True, **_JIT)
def _angular(
    l_first: int,
    l_last: int,
    base: np.ndarray,
    coeffs: np.ndarray,
    qmm: np.ndarray,
    rec_a: np.ndarray,
    rec_b: np.ndarray,
    nb: int,
    geo: np.ndarray,
    rad: np.ndarray,
    work: np.ndarray,
    acc: np.ndarray,
) -> None:
    """acc[k, i] = Σ_l rad[l, i] Σ_m Y_lm(x̂_i) coeffs[row(l, m), k] for one block: for each
    order m, the Legendre recurrence runs up in l two degrees per pass (the other parity is
    never stored) and each pass adds its degree's terms."""
    x, y, z = geo[0], geo[1], geo[2]
    cos_m, sin_m, cur, prev, qc, qs = work[0], work[1], work[2], work[3], work[4], work[5]
    n_out = acc.shape[0]
    acc[:, :nb] = 0.0
    for i in range(nb):
        cos_m[i] = 1.0
        sin_m[i] = 0.0
    for m in range(l_last + 1):
        # lowest degree of the parity with this order: m or m + 1
        l_low = max(m, l_first)
        l_low += (l_low - l_first) % 2
        q0 = qmm[m]  # Q_m^m
        a_low = rec_a[l_low, m] * q0 if l_low > m else q0  # Q_{m+1}^m = a z Q_m^m
        for l in range(l_low, l_last + 1, 2):
            row = rad[(l - l_first) // 2]
            a1, b1 = rec_a[l - 1, m], rec_b[l - 1, m]
            a2, b2 = rec_a[l, m], rec_b[l, m]
            row_c = base[l] + l + m
            row_s = base[l] + l - m
            if n_out == 3:
                # vector and affine loads: one pass per degree (the first of each order also
                # steps cos mφ, sin mφ and starts the recurrence) updates the three outputs
                first = l == l_low
                c0, c1, c2 = coeffs[row_c, 0], coeffs[row_c, 1], coeffs[row_c, 2]
                s0 = coeffs[row_s, 0] if m > 0 else 0.0
                s1 = coeffs[row_s, 1] if m > 0 else 0.0
                s2 = coeffs[row_s, 2] if m > 0 else 0.0
                acc0, acc1, acc2 = acc[0], acc[1], acc[2]
                for i in range(nb):
                    if first:
                        c_m = x[i] * cos_m[i] - y[i] * sin_m[i]
                        s_m = x[i] * sin_m[i] + y[i] * cos_m[i]
                        if m > 0:
                            cos_m[i] = c_m
                            sin_m[i] = s_m
                        else:
                            c_m = 1.0
                            s_m = 0.0
                        q_l = a_low * z[i] if l_low > m else q0
                        prev[i] = q0 if l_low > m else 0.0
                        cur[i] = q_l
                    else:
                        c_m = cos_m[i]
                        s_m = sin_m[i]
                        q_odd = a1 * (z[i] * cur[i] - b1 * prev[i])
                        q_l = a2 * (z[i] * q_odd - b2 * cur[i])
                        prev[i] = q_odd
                        cur[i] = q_l
                    q = row[i] * q_l
                    q_cos = q * c_m
                    q_sin = q * s_m
                    acc0[i] += q_cos * c0 + q_sin * s0
                    acc1[i] += q_cos * c1 + q_sin * s1
                    acc2[i] += q_cos * c2 + q_sin * s2
                continue
            if l == l_low:
                for i in range(nb):
                    if m > 0:
                        c_new = x[i] * cos_m[i] - y[i] * sin_m[i]
                        sin_m[i] = x[i] * sin_m[i] + y[i] * cos_m[i]
                        cos_m[i] = c_new
                    cur[i] = a_low * z[i] if l_low > m else q0
                    prev[i] = q0 if l_low > m else 0.0
            else:
                for i in range(nb):
                    q_odd = a1 * (z[i] * cur[i] - b1 * prev[i])
                    cur[i] = a2 * (z[i] * q_odd - b2 * cur[i])
                    prev[i] = q_odd
            for i in range(nb):
                q = row[i] * cur[i]
                qc[i] = q * cos_m[i]
                qs[i] = q * sin_m[i]
            for k in range(n_out):
                ck = coeffs[row_c, k]
                sk = coeffs[row_s, k] if m > 0 else 0.0
                acc_k = acc[k]
                for i in range(nb):
                    acc_k[i] += qc[i] * ck + qs[i] * sk
