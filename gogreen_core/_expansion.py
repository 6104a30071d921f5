"""Numba evaluation of one parity of the SH expansion (paper Eqs. 10 and 12).

    out[n, k] = Σ_{l ∈ degrees} T_l(t_n) / (r_n + ε)^p  Σ_m Y_lm(x̂_n) coeffs[base_l + l + m, k]

with x = points[n] - center, r = |x|, t = r/(r+ε), T_l the piecewise polynomial radial tables of
``radial.py`` and Y_lm the real harmonics of ``sph.py``. One compiled function serves every use
(G, ∇G, vector and affine loads): they differ only in ``coeffs`` (n_terms, K).

Speed notes (measured, 2-core AVX-512 machine): points are processed in blocks of ``BLOCK`` on
contiguous scratch rows so that LLVM vectorizes across points; ``error_model="numpy"`` removes
the zero-division checks that otherwise block vectorization; loops touch few arrays each
(LLVM gives up when runtime alias checks grow too many); the Legendre recurrence advances two
degrees per pass and never stores the other parity; for K = 3 (vector and affine loads) one pass
per (l, m) does the recurrence step and updates all three outputs. This generic ``_angular`` is
bound by the loads and stores of its scratch rows; ``_unrolled.py`` generates, per truncation
degree, a straight-line replacement for K = 3 that keeps everything in registers and reuses the
drivers below unchanged.
"""

from __future__ import annotations

import math
import os
from collections import namedtuple

import numpy as np
from numba import carray, cfunc, njit, prange, types

# numba's OpenMP threading layer loads libgomp at the first parallel call (after this import);
# its default lets idle worker threads spin, which on cores shared with other programs starves
# the threads doing the work. Passive waiting, measured on the shared 2-core machine under load
# (wall medians): a grab event on the 1M-vertex ogre 186-234 ms -> 83-85 ms, on a 2,562-vertex
# sphere 72-165 ms -> 0.5 ms; uncontended it costs ~0.1 ms of wake-up per event (small-mesh
# minimum 0.35-0.44 -> 0.50 ms). A user's own setting wins.
os.environ.setdefault("OMP_WAIT_POLICY", "passive")

BLOCK = 256
# Parallel tasks per call; each reuses one set of scratch rows for a contiguous run of blocks.
TASKS = 64
#: Polynomial degree of the radial table segments that ``_radial`` evaluates (radial.py's).
SEGMENT_DEGREE = 5

_JIT = {"cache": True, "fastmath": {"contract"}, "boundscheck": False, "error_model": "numpy"}

#: Signature of the angular kernels generated per degree by ``_unrolled``:
#: (nb, geo (8, BLOCK), rad (n_deg, BLOCK), coeffs (n_terms, 3), acc (3, BLOCK)), C-contiguous
#: arrays passed as pointers. They reach the drivers below as first-class functions, so the
#: drivers are compiled (and cached on disk) once, whatever the degree.
_F8P = types.CPointer(types.float64)
ANGULAR_SIGNATURE = types.void(types.int64, _F8P, _F8P, _F8P, _F8P)


@cfunc(ANGULAR_SIGNATURE, cache=True)
def generic_marker(nb, geo, rad, coeffs, acc):  # pragma: no cover - never called
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
    angular,  # ANGULAR_SIGNATURE function generated for these degrees (K = 3)
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
def _geometry(eps, power, n_seg, nb, geo, seg):
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
def _radial(tables, l_first, nb, geo, seg, rad):
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
def _angular(l_first, l_last, base, coeffs, qmm, rec_a, rec_b, nb, geo, rad, work, acc):
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


#: Largest number of RK4 steps the adaptive streamlines give one vertex in one event.
MAX_ADAPTIVE_STEPS = 256
#: The adaptive streamlines accept a result where its estimated error is at most this fraction
#: of the tolerance. The one-step prediction is a model (see ``stream``); calibrated on the ogre
#: (cubic material, l_max 8) with grab, twist, scale and pinch events of 0.1 ε to 0.8 ε against
#: 64 fixed steps: max error / motion scale 2e-6 (grab of 0.2 ε) up to 9.8e-5 (grab of 0.8 ε),
#: affine brushes below 2e-6; 0.1 refined 5x more vertices for no needed gain.
ESTIMATE_SAFETY = 0.25


#: What the streamline velocity is made of, passed as one value through ``stream``, ``_refine``,
#: ``_rk4`` and ``_velocity``: the load path (centre at pseudo-time t = center0 + t ·
#: center_step), the expansion (``expand``'s arrays, ``coeffs`` with the load contracted in),
#: the smooth cutoff (1 for d <= cutoff_inner, falling over 1 / inv_width; inv_width 0: none)
#: and the mirrors (±1 rows about ``origin``).
_Field = namedtuple(
    "_Field",
    "center0 center_step eps power l_first l_last base coeffs tables qmm rec_a rec_b angular "
    "unrolled cutoff_inner inv_width mirrors origin",
)


@njit(nogil=True, **_JIT)
def _velocity(
    pos,
    nb,
    t,
    field,
    scratch,
    vel,
):
    """vel[:, :nb] = v(pos[:, :nb], t), the streamline velocity of ``stream`` (rows x, y, z)."""
    (center0, center_step, eps, power, l_first, l_last, base, coeffs, tables, qmm, rec_a, rec_b,
     angular, unrolled, cutoff_inner, inv_width, mirrors, origin) = field  # fmt: skip
    geo, seg, rad, work, total = scratch
    for k in range(3):
        for i in range(nb):
            vel[k, i] = 0.0
    for mi in range(mirrors.shape[0]):
        for k in range(3):
            sgn = mirrors[mi, k]
            o = origin[k]
            c = center0[k] + t * center_step[k]
            offset = geo[k]
            for i in range(nb):
                # the brush itself (sgn = 1) sees exactly its own positions
                offset[i] = (pos[k, i] if sgn > 0 else o - (pos[k, i] - o)) - c
        _geometry(eps, power, tables.shape[1], nb, geo, seg)
        _radial(tables, l_first, nb, geo, seg, rad)
        if unrolled:
            angular(nb, geo.ctypes, rad.ctypes, coeffs.ctypes, total.ctypes)
        else:
            _angular(l_first, l_last, base, coeffs, qmm, rec_a, rec_b, nb, geo, rad, work, total)
        rr = geo[3]
        for i in range(nb):
            u = min(max((rr[i] - cutoff_inner) * inv_width, 0.0), 1.0)
            geo[7, i] = 1.0 - u * u * u * (10.0 + u * (6.0 * u - 15.0))
        for k in range(3):
            sgn = mirrors[mi, k]
            for i in range(nb):
                vel[k, i] += sgn * geo[7, i] * total[k, i]


@njit(nogil=True, **_JIT)
def _rk4(
    n_steps,
    nb,
    start,
    end,
    mid,
    field,
    scratch,
    rows,
):
    """end[:, :nb] = ``n_steps`` classical RK4 steps over t ∈ [0, 1] from start[:, :nb].

    With one step, mid (6, BLOCK) also gets the ends of two second-order rules made of RK4's
    stages, the midpoint rule x₀ + k₂ (rows 0-2) and the trapezoid x₀ + (k₁ + k₄)/2 (rows 3-5):
    the adaptive driver's error estimates.
    """
    pos, stage_pos, vel = rows
    h = 1.0 / n_steps
    for k in range(3):
        for i in range(nb):
            pos[k, i] = start[k, i]
    for step in range(n_steps):
        for stage in range(4):
            # classical RK4: stage offsets 0, h/2, h/2, h and weights 1, 2, 2, 1
            a = 0.0 if stage == 0 else (h if stage == 3 else 0.5 * h)
            for k in range(3):
                for i in range(nb):
                    stage_pos[k, i] = pos[k, i] + (a * vel[k, i] if stage > 0 else 0.0)
            _velocity(
                stage_pos,
                nb,
                step * h + a,
                field,
                scratch,
                vel,
            )
            # mid[0:3] = x₀ + k₂ (midpoint rule), mid[3:6] = x₀ + (k₁ + k₄)/2 (trapezoid); one
            # loop per stage (a branch on the stage inside the loop kept it from vectorizing)
            if n_steps == 1 and stage == 0:
                for k in range(3):
                    for i in range(nb):
                        mid[3 + k, i] = pos[k, i] + 0.5 * vel[k, i]
            elif n_steps == 1 and stage == 1:
                for k in range(3):
                    for i in range(nb):
                        mid[k, i] = pos[k, i] + vel[k, i]
            elif n_steps == 1 and stage == 3:
                for k in range(3):
                    for i in range(nb):
                        mid[3 + k, i] += 0.5 * vel[k, i]
            weight = h / 6.0 if stage == 0 or stage == 3 else h / 3.0
            for k in range(3):
                for i in range(nb):
                    end[k, i] = (end[k, i] if stage > 0 else pos[k, i]) + weight * vel[k, i]
        for k in range(3):
            for i in range(nb):
                pos[k, i] = end[k, i]


@njit(nogil=True, **_JIT)
def _scratch(n_deg):
    """Per-task scratch rows of ``_velocity`` and ``_rk4``."""
    scratch = (
        np.empty((8, BLOCK)),
        np.empty(BLOCK, dtype=np.int64),
        np.empty((n_deg, BLOCK)),
        np.empty((6, BLOCK)),
        np.empty((3, BLOCK)),
    )
    rows = (np.empty((3, BLOCK)), np.empty((3, BLOCK)), np.empty((3, BLOCK)))
    return scratch, rows


@njit(parallel=True, nogil=True, **_JIT)
def stream(
    points: np.ndarray,  # (N_all, 3) float64, start positions (the rows ``indices`` if indexed)
    indices: np.ndarray,  # (N,) int64 rows of ``points`` to move if ``indexed``
    indexed: bool,  # False: move every row of ``points`` (``indices`` is not read)
    write_back: bool,  # write the end positions into points[indices] if all are finite
    limit: float,  # largest coordinate magnitude accepted in an indexed start position
    center0: np.ndarray,  # (3,) load center at pseudo-time 0
    center_step: np.ndarray,  # (3,) center(t) = center0 + t * center_step
    eps: float,
    power: int,
    l_first: int,
    l_last: int,
    base: np.ndarray,
    coeffs: np.ndarray,  # (n_terms, 3): the load already contracted in
    tables: np.ndarray,
    qmm: np.ndarray,
    rec_a: np.ndarray,
    rec_b: np.ndarray,
    angular,  # as in ``expand``
    unrolled: bool,
    cutoff_inner: float,  # smooth cutoff: 1 for d <= inner, 0 for d >= outer (outer <= 0: none)
    cutoff_outer: float,
    mirrors: np.ndarray,  # (n_m, 3) ±1 signs; row 0 is (1, 1, 1), the brush itself
    origin: np.ndarray,  # (3,) a point of the mirror planes
    substeps: int,  # fixed RK4 steps (tolerance <= 0)
    tolerance: float,  # > 0: adaptive, relative to the motion scale; <= 0: fixed steps
    out: np.ndarray,  # (N, 3) float64, end positions
    steps: np.ndarray,  # (N,) int64: RK4 steps each point took
) -> int:
    """RK4 streamlines of the velocity v(x, t) = Σ_M M s(|y - c(t)|) u(y - c(t)), y = M x.

    u is the expansion with ``coeffs`` (K = 3), s the C² smooth cutoff, M the mirror
    reflections about ``origin``. Each block of points is integrated over t ∈ [0, 1] while it
    stays in cache (paper Sec. 3.2):

    * ``tolerance <= 0``: ``substeps`` classical RK4 steps for every point;
    * ``tolerance > 0``: one RK4 step for every point, whose stages also give the ends of two
      second-order rules (midpoint x₀ + k₂, trapezoid x₀ + (k₁ + k₄)/2); the larger distance
      e of the RK4 end to them estimates a second-order error (order h³), and the RK4 error
      (order h⁵) is predicted as e (e / max(m, e))^(2/3), m the point's motion. Points whose
      prediction exceeds ESTIMATE_SAFETY · tolerance · scale (scale = the largest of
      |center_step| and every motion m) are packed into blocks of their own and integrated
      again with 2, 4, ... RK4 steps until Richardson's estimate |x_n - x_(n/2)| / 15 is
      under that bound (at most MAX_ADAPTIVE_STEPS). Each point's result depends only on the
      input (the blocks are fixed by the point order, never by the thread count), so replays
      are bit-identical.

    Indexed (``indexed``), point n is the row indices[n] of ``points``, read in place (no
    gathered copy); with ``write_back`` the end positions are scattered back into those rows,
    and only if every one of them is finite. Returns 0 when done, 1 if an index is out of
    range, 2 if an indexed start position is not finite or beyond ``limit`` (nothing
    integrated), 3 if an end position is not finite (nothing written back).
    """
    n_points = indices.shape[0] if indexed else points.shape[0]
    n_rows = points.shape[0]
    n_deg = tables.shape[0]
    n_blocks = (n_points + BLOCK - 1) // BLOCK
    n_tasks = min(n_blocks, TASKS)
    width = cutoff_outer - cutoff_inner
    inv_width = 1.0 / width if cutoff_outer > 0.0 and width > 0.0 else 0.0
    field = _Field(
        center0,
        center_step,
        eps,
        power,
        l_first,
        l_last,
        base,
        coeffs,
        tables,
        qmm,
        rec_a,
        rec_b,
        angular,
        unrolled,
        cutoff_inner,
        inv_width,
        mirrors,
        origin,
    )
    adaptive = tolerance > 0.0
    first_steps = 1 if adaptive else substeps
    block_motion = np.zeros(n_blocks)  # largest motion m in each block
    if indexed and n_rows == 0:
        return 1
    # per block: 1 an index out of range (row 0 read instead), 2 a start position not finite
    # or beyond ``limit``; checked while the rows are read, acted on after the first pass
    rank = np.empty(n_points)  # e⁵ / max(m, e)², see below
    problem = np.zeros(n_blocks, dtype=np.int64)
    # per block: an end position not finite, checked as the rows are written (no pass of its
    # own): a first step that overflowed fails the event even where refinement might not)
    bad = np.zeros(n_blocks, dtype=np.bool_)
    for task in prange(n_tasks):
        scratch, rows = _scratch(n_deg)
        start_rows = np.empty((3, BLOCK))
        end_rows = np.empty((3, BLOCK))
        mid_rows = np.empty((6, BLOCK))
        motion2 = np.empty(BLOCK)
        for blk in range(task * n_blocks // n_tasks, (task + 1) * n_blocks // n_tasks):
            start = blk * BLOCK
            nb = min(BLOCK, n_points - start)
            for i in range(nb):
                row = start + i
                if indexed:
                    row = indices[start + i]
                    if row < 0 or row >= n_rows:
                        problem[blk] = 1
                        row = 0
                    for k in range(3):
                        if not abs(points[row, k]) <= limit and problem[blk] == 0:  # or NaN
                            problem[blk] = 2
                for k in range(3):
                    start_rows[k, i] = points[row, k]
            _rk4(
                first_steps,
                nb,
                start_rows,
                end_rows,
                mid_rows,
                field,
                scratch,
                rows,
            )
            for i in range(nb):
                for k in range(3):
                    out[start + i, k] = end_rows[k, i]
                steps[start + i] = first_steps
            if write_back:
                for k in range(3):
                    for i in range(nb):
                        if not math.isfinite(end_rows[k, i]):
                            bad[blk] = True
            if adaptive:
                for i in range(nb):
                    m2 = 0.0
                    e_mid = 0.0
                    e_trap = 0.0
                    for k in range(3):
                        d = end_rows[k, i] - start_rows[k, i]
                        m2 += d * d
                        d = mid_rows[k, i] - end_rows[k, i]
                        e_mid += d * d
                        d = mid_rows[3 + k, i] - end_rows[k, i]
                        e_trap += d * d
                    # prediction e (e/reach)^(2/3) > bound  ⇔  e⁵ / reach² > bound³
                    e = math.sqrt(max(e_mid, e_trap))
                    reach2 = max(m2, e * e)
                    motion2[i] = m2
                    rank[start + i] = e * e * e * e * e / reach2 if reach2 > 0.0 else 0.0
                # the block's largest motion in a loop of its own: a max reduction inside the
                # loop above kept it (its square roots and divisions) from vectorizing
                most = 0.0
                for i in range(nb):
                    most = max(most, motion2[i])
                block_motion[blk] = math.sqrt(most)
    for code in (1, 2):
        for blk in range(n_blocks):
            if problem[blk] == code:
                return code
    if adaptive:
        refined_bad = _refine(
            points,
            indices,
            indexed,
            field,
            tolerance,
            out,
            steps,
            rank,
            block_motion,
        )
        if refined_bad and write_back:
            return 3
    if not write_back:
        return 0
    for blk in range(n_blocks):
        if bad[blk]:
            return 3
    for blk in prange(n_blocks):
        for n in range(blk * BLOCK, min((blk + 1) * BLOCK, n_points)):
            row = indices[n] if indexed else n
            for k in range(3):
                points[row, k] = out[n, k]
    return 0


@njit(parallel=True, nogil=True, **_JIT)
def _refine(
    points,
    indices,
    indexed,
    field,
    tolerance,
    out,
    steps,
    rank,
    block_motion,
):
    """The adaptive pass of ``stream``: the points whose predicted error is too large, again
    with 2, 4, ... RK4 steps (see ``stream``). Returns True if an end position it wrote is not
    finite."""
    n_points = out.shape[0]
    n_deg = field.tables.shape[0]
    n_blocks = block_motion.shape[0]
    step = field.center_step
    scale = math.sqrt(step[0] ** 2 + step[1] ** 2 + step[2] ** 2)
    for blk in range(n_blocks):
        scale = max(scale, block_motion[blk])
    bound = ESTIMATE_SAFETY * tolerance * scale
    if bound <= 0.0:
        return False
    # the points to refine, packed in index order into full blocks spread evenly over the
    # tasks (they cluster in space, so in the mesh's order too)
    bound3 = bound * bound * bound
    offsets = np.zeros(n_blocks + 1, dtype=np.int64)
    for blk in prange(n_blocks):
        count = 0
        for n in range(blk * BLOCK, min((blk + 1) * BLOCK, n_points)):
            count += 1 if rank[n] > bound3 else 0
        offsets[blk + 1] = count
    for blk in range(n_blocks):
        offsets[blk + 1] += offsets[blk]
    n_refine = offsets[n_blocks]
    refine = np.empty(n_refine, dtype=np.int64)
    for blk in prange(n_blocks):
        j = offsets[blk]
        for n in range(blk * BLOCK, min((blk + 1) * BLOCK, n_points)):
            if rank[n] > bound3:
                refine[j] = n
                j += 1
    n_packed = (n_refine + BLOCK - 1) // BLOCK
    n_tasks = min(n_packed, TASKS)
    bad = np.zeros(n_packed, dtype=np.bool_)
    for task in prange(n_tasks):
        scratch, rows = _scratch(n_deg)
        start_rows = np.empty((3, BLOCK))
        end_rows = np.empty((3, BLOCK))
        previous = np.empty((3, BLOCK))
        picked = np.empty(BLOCK, dtype=np.int64)
        for blk in range(task * n_packed // n_tasks, (task + 1) * n_packed // n_tasks):
            start = blk * BLOCK
            count = min(BLOCK, n_refine - start)
            for j in range(count):
                picked[j] = refine[start + j]
                for k in range(3):
                    previous[k, j] = out[picked[j], k]
            n_steps = 2
            while count > 0:
                for j in range(count):
                    row = indices[picked[j]] if indexed else picked[j]
                    for k in range(3):
                        start_rows[k, j] = points[row, k]
                _rk4(
                    n_steps,
                    count,
                    start_rows,
                    end_rows,
                    end_rows,
                    field,
                    scratch,
                    rows,
                )
                kept = 0
                for j in range(count):
                    n = picked[j]
                    d2 = 0.0
                    for k in range(3):
                        d = end_rows[k, j] - previous[k, j]
                        d2 += d * d
                        out[n, k] = end_rows[k, j]
                    steps[n] = n_steps
                    # Richardson: the n-step result's error is about |x_n - x_(n/2)| / (2⁴ - 1)
                    if math.sqrt(d2) > 15.0 * bound and n_steps < MAX_ADAPTIVE_STEPS:
                        picked[kept] = n
                        for k in range(3):
                            previous[k, kept] = end_rows[k, j]
                        kept += 1
                    else:  # its final end position
                        for k in range(3):
                            if not math.isfinite(end_rows[k, j]):
                                bad[blk] = True
                count = kept
                n_steps *= 2
    for blk in range(n_packed):
        if bad[blk]:
            return True
    return False


@njit(parallel=True, nogil=True, **_JIT)
def near_segment(
    points: np.ndarray,  # (N, 3)
    start: np.ndarray,  # (3,) segment start
    step: np.ndarray,  # (3,) segment end - start
    radius: float,
    mirrors: np.ndarray,  # (n_m, 3) ±1 signs
    origin: np.ndarray,  # (3,)
    out: np.ndarray,  # (N,) bool: some mirror image of the point is within radius of the segment
) -> None:
    length2 = step[0] * step[0] + step[1] * step[1] + step[2] * step[2]
    inv = 1.0 / length2 if length2 > 0.0 else 0.0
    r2 = radius * radius
    for n in prange(points.shape[0]):
        hit = False
        for mi in range(mirrors.shape[0]):
            y0 = origin[0] + mirrors[mi, 0] * (points[n, 0] - origin[0]) - start[0]
            y1 = origin[1] + mirrors[mi, 1] * (points[n, 1] - origin[1]) - start[1]
            y2 = origin[2] + mirrors[mi, 2] * (points[n, 2] - origin[2]) - start[2]
            t = min(max((y0 * step[0] + y1 * step[1] + y2 * step[2]) * inv, 0.0), 1.0)
            d0 = y0 - t * step[0]
            d1 = y1 - t * step[1]
            d2 = y2 - t * step[2]
            hit = hit or d0 * d0 + d1 * d1 + d2 * d2 < r2
        out[n] = hit
