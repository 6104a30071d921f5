"""The velocity field of the streamlines (``_integrator``): the parity's lowest degree in double
precision, the degrees above it in single precision.

The lowest degree (l = 0 for G, 1 for ∇G) carries most of the field and all of it at the brush
centre; it is evaluated in double precision, so the grabbed point follows the cursor to
rounding. The others, a correction of a few to a few tens of percent, are summed in float32:
float32 directions and table variables, the tables of ``radial_tables.single_table``,
coefficients scaled by their largest magnitude (``cscale``), and the generated
``angular_single`` kernels or the generic ``_expansion._angular`` on float32 rows, whose float32
arithmetic is twice as fast (8 lanes a vector instead of 4). The sum is scaled and added in
double precision. Off double precision by ~1e-8 of the field, 1e-4 below the integrator's
tolerance.

The NumPy reference (``_numpy_eval``) performs the float32 operations in the same order (within
1e-12 of the field: float32 rounding differences would be ~1e-9), so no fastmath here.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from gogreen_core.field._expansion import _HUGE, _JIT, _TINY, CUTOFF_END, _angular, _radial

if TYPE_CHECKING:
    #: The velocity field's record and the scratch rows (see ``_integrator``).
    from gogreen_core.field._stream import StreamField as Field

    Scratch = tuple[
        np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray
    ]

__all__ = ["_single_velocity"]


@njit(**_JIT)
def _single_geometry(
    pos: np.ndarray, mi: int, nb: int, t: float, field: Field, scratch: Scratch
) -> int:
    """The geometry of mirror image ``mi`` of the points ``pos``: the offsets and
    ``_expansion._geometry`` (the same r, direction, segment, table variable and
    scales, in fewer passes), the direction (in double precision only for an odd parity, whose
    lowest degree needs it) and the table variable also as float32 (geo32 rows 0-2 and 4), and
    the cutoff weight (geo row 7). Returns how many points it reaches."""
    center0, center_step, eps, power, l_first, tables = (
        field.center0, field.center_step, field.eps, field.power, field.l_first, field.tables
    )  # fmt: skip
    cutoff_inner, inv_width = field.cutoff_inner, field.inv_width
    mirrors, origin = field.mirrors, field.origin
    n_seg = tables.shape[1]
    geo, seg, geo32 = scratch[0], scratch[1], scratch[3]
    x, y, z, rr, loc, scale0, scale1, weight = (
        geo[0], geo[1], geo[2], geo[3], geo[4], geo[5], geo[6], geo[7]
    )  # fmt: skip
    x32, y32, z32, loc32 = geo32[0], geo32[1], geo32[2], geo32[4]
    cx = center0[0] + t * center_step[0]
    cy = center0[1] + t * center_step[1]
    cz = center0[2] + t * center_step[2]
    n_huge = 0
    if mi == 0:  # the brush itself sees exactly its own positions
        for i in range(nb):
            a = pos[0, i] - cx
            b = pos[1, i] - cy
            c = pos[2, i] - cz
            x[i] = a
            y[i] = b
            z[i] = c
            r2 = a * a + b * b + c * c
            n_huge += 0 if r2 < 1e300 else 1
            rr[i] = math.sqrt(r2)
    else:
        for k in range(3):
            sgn = mirrors[mi, k]
            o = origin[k]
            c = center0[k] + t * center_step[k]
            offset = geo[k]
            for i in range(nb):
                offset[i] = (pos[k, i] if sgn > 0 else o - (pos[k, i] - o)) - c
        for i in range(nb):
            r2 = x[i] * x[i] + y[i] * y[i] + z[i] * z[i]
            n_huge += 0 if r2 < 1e300 else 1
            rr[i] = math.sqrt(r2)
    if n_huge > 0:  # rare: see ``_geometry``
        for i in range(nb):
            if not x[i] * x[i] + y[i] * y[i] + z[i] * z[i] < 1e300:
                xs, ys, zs = x[i] * _TINY, y[i] * _TINY, z[i] * _TINY
                rr[i] = math.sqrt(xs * xs + ys * ys + zs * zs) * _HUGE
    if l_first:
        for i in range(nb):
            r = rr[i]
            inv = 1.0 / r if r > 0.0 else 0.0
            x[i] *= inv
            y[i] *= inv
            z[i] *= inv
            x32[i] = x[i]
            y32[i] = y[i]
            z32[i] = z[i]
    else:
        for i in range(nb):
            r = rr[i]
            inv = 1.0 / r if r > 0.0 else 0.0
            x32[i] = x[i] * inv
            y32[i] = y[i] * inv
            z32[i] = z[i] * inv
    reached = 0
    for i in range(nb):
        r = rr[i]
        inv_re = 1.0 / (r + eps)
        u = min(r * inv_re, 1.0) * n_seg
        fj = min(math.floor(u), n_seg - 1.0)
        seg[i] = int(fj)
        sigma = 2.0 * (u - fj)
        loc[i] = sigma - 1.0
        loc32[i] = sigma
        sc = inv_re if power == 1 else inv_re * inv_re
        scale0[i] = sc
        scale1[i] = sc if r > 0.0 else 0.0
        c = min(max((r - cutoff_inner) * inv_width, 0.0), 1.0)
        w = 1.0 - c * c * c * (10.0 + c * (6.0 * c - 15.0))
        weight[i] = w if c < CUTOFF_END else 0.0
        reached += 1 if c < CUTOFF_END else 0
    return reached


@njit(**_JIT)
def _single_radial(
    tables32: np.ndarray, nb: int, seg: np.ndarray, sigma: np.ndarray, rad32: np.ndarray
) -> None:
    """rad32[d, i] = the single precision table (``tables32`` (S, n_deg - 1, 3) float32) of
    degree d above the lowest at point i, c₀ + (c₁ + c₂ σ) σ in float32 with σ = loc + 1,
    unscaled (the velocity scales it).

    Two degrees a loop over the points: their six coefficients sit side by side in a segment's
    row, so one index serves both (1.3x faster than a loop per degree, the same bits)."""
    n_deg = tables32.shape[1]
    for d in range(0, n_deg - 1, 2):
        row, nxt = rad32[d], rad32[d + 1]
        for i in range(nb):
            j = np.uint64(seg[i])
            s = sigma[i]
            row[i] = tables32[j, d, 0] + (tables32[j, d, 1] + tables32[j, d, 2] * s) * s
            nxt[i] = tables32[j, d + 1, 0] + (tables32[j, d + 1, 1] + tables32[j, d + 1, 2] * s) * s
    if n_deg % 2:
        d = n_deg - 1
        row = rad32[d]
        for i in range(nb):
            j = np.uint64(seg[i])
            s = sigma[i]
            row[i] = tables32[j, d, 0] + (tables32[j, d, 1] + tables32[j, d, 2] * s) * s


@njit(**_JIT)
def _single_velocity(
    pos: np.ndarray, nb: int, t: float, field: Field, scratch: Scratch, vel: np.ndarray
) -> None:
    """vel[:, :nb] = v(pos[:, :nb], t) (rows x, y, z; ``_integrator``): the parity's lowest
    degree in double precision (its table alone in ``tables``), the degrees above it in single
    precision (float32 directions, table variables, ``tables32``, coefficients ``coeffs32`` over
    their scale ``cscale``; the generated ``angular32`` or the generic ``_angular`` on float32
    rows), weighted by the cutoff and summed over the mirror images."""
    l_first, l_last, base, coeffs, tables = (
        field.l_first, field.l_last, field.base, field.coeffs, field.tables
    )  # fmt: skip
    mirrors = field.mirrors
    coeffs32, beta32, tables32, cscale = field.coeffs32, field.beta32, field.tables32, field.cscale
    angular32, unrolled32 = field.angular32, field.unrolled32
    geo, seg, rad, geo32, rad32, work32, total32 = scratch
    x, y, z, scale1, weight = geo[0], geo[1], geo[2], geo[6], geo[7]
    upper = l_last > l_first
    for mi in range(mirrors.shape[0]):
        if _single_geometry(pos, mi, nb, t, field, scratch) == 0:  # beyond the cutoff: v += 0
            if mi == 0:
                for k in range(3):
                    for i in range(nb):
                        vel[k, i] = 0.0
            continue
        _radial(tables, l_first, nb, geo, seg, rad)  # the lowest degree's, alone in ``tables``
        _single_radial(tables32, nb, seg, geo32[4], rad32)
        if upper:
            if unrolled32:
                angular32(nb, geo32.ctypes, rad32.ctypes, coeffs32.ctypes, total32.ctypes)
            else:
                _angular(
                    l_first + 2, l_last, base, coeffs32, beta32, nb, geo32, rad32, work32, total32
                )
        else:
            for k in range(3):
                for i in range(nb):
                    total32[k, i] = 0.0
        t0 = rad[0]
        for k in range(3):
            sgn = mirrors[mi, k]
            v_k, t_k = vel[k], total32[k]
            c0, c1, c2 = (
                coeffs[0, k],
                coeffs[1 if l_first else 0, k],
                coeffs[2 if l_first else 0, k],
            )
            # the lowest degree: R₀ Y₀₀ C, or R₁ Σ_m Y_1m C_1m in the rescaled form of
            # ``_expansion._angular`` (P_1^0 = z, P_1^1 = 1, cos φ = x̂, sin φ = ŷ); then the
            # weighted sum (a zero weight adds exactly nothing; one loop per case: a branch
            # inside kept it from vectorizing)
            if l_first == 0 and mi == 0:
                for i in range(nb):
                    u = t0[i] * c0 + (scale1[i] * cscale) * t_k[i]
                    v_k[i] = weight[i] * u if weight[i] != 0.0 else 0.0
            elif l_first == 0:
                for i in range(nb):
                    u = t0[i] * c0 + (scale1[i] * cscale) * t_k[i]
                    v_k[i] = v_k[i] + (sgn * weight[i]) * u if weight[i] != 0.0 else v_k[i]
            elif mi == 0:
                for i in range(nb):
                    a = t0[i]
                    u = ((a * z[i]) * c1 + x[i] * (a * c2)) + y[i] * (a * c0)
                    u = u + (scale1[i] * cscale) * t_k[i]
                    v_k[i] = weight[i] * u if weight[i] != 0.0 else 0.0
            else:
                for i in range(nb):
                    a = t0[i]
                    u = ((a * z[i]) * c1 + x[i] * (a * c2)) + y[i] * (a * c0)
                    u = u + (scale1[i] * cscale) * t_k[i]
                    v_k[i] = v_k[i] + (sgn * weight[i]) * u if weight[i] != 0.0 else v_k[i]
