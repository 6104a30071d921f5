"""Streamlines of a brush's velocity field: RK4 over pseudo-time [0, 1] (paper Sec. 3.2).

    v(x, t) = Σ_M M s(|y - c(t)|) u(y - c(t)),   y = origin + M (x - origin),  c(t) = c₀ + t Δc

u is the expansion of ``_expansion`` with the load contracted into its coefficients (K = 3), s
the C² cutoff (1 up to ``cutoff_inner``, a quintic smoothstep to 0 over 1 / inv_width), M the
mirror reflections about ``origin`` (row 0: the brush itself).

The parity's lowest degree (l = 0 for G, 1 for ∇G: most of the field, all of it at the centre)
is evaluated in double precision, so the grabbed point follows the cursor to rounding; the
degrees above it (a correction of a few to tens of percent) in float32, at twice the arithmetic
rate (``StreamField``'s float32 members, ``radial_tables.single_table``), summed in double: ~1e-8
of the field, 1e-4 below the tolerance. No fastmath: ``_numpy_eval`` repeats the operations.

``_stream.stream`` runs the passes of ``_pass`` over blocks of points on the thread pool:

* fixed steps (``tolerance <= 0``): ``substeps`` RK4 steps for every point;
* adaptive: one RK4 step, its error predicted from the larger distance e of its end to the
  midpoint (x₀ + k₂) and trapezoid (x₀ + (k₁ + k₄)/2) ends as e (e / max(m, e))^(2/3), m the
  point's motion. Points predicted beyond ``_stream.ESTIMATE_SAFETY`` · tolerance · scale (the
  largest of |Δc| and every m) are integrated again, BLOCK at a time, with 2, 4, ... RK4 steps
  until Richardson's |x_n - x_(n/2)| / 15 is under that bound, and 16 times the one before (at
  most MAX_ADAPTIVE_STEPS);
* adaptive on ``_stream.THIRD_ORDER_POINTS`` points or more: probes (``_stream.probe_rows``)
  first compare one SSPRK3 step with one and two RK4 steps; where the third-order error is
  within the bound at every probe, every point takes the SSPRK3 step and keeps it if its spread
  (to the Heun end of the same stages) is within the probes' range; the others are refined.

A point's result depends only on the input (blocks follow the point order, not the threads),
and both angular kernels give the same bits: replays are bit-identical.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from gogreen_core.field._expansion import _HUGE, _JIT, _TINY, BLOCK, CUTOFF_END, _angular, _radial

if TYPE_CHECKING:
    from gogreen_core.field._stream import StreamField as Field

    #: The scratch rows of ``_scratch``.
    Scratch = tuple[np.ndarray, ...]
    Rows = tuple[np.ndarray, np.ndarray, np.ndarray]

__all__ = ["CUTOFF_END", "MAX_ADAPTIVE_STEPS"]

#: SHA-256 (first 16 hex digits) of ``_expansion.py``, written by ``scripts/make_kernels.py``.
#: numba keys the disk cache of this module's compiled code on this file alone, yet compiles
#: that module's functions into it: a change there must change this file.
COMPILED_SOURCES = "8d3d7833f022b0fc"

#: Largest number of RK4 steps the adaptive streamlines give one vertex in one event.
MAX_ADAPTIVE_STEPS = 256
_SIXTH = 1.0 / 6.0
_THIRD = 1.0 / 3.0


@njit(**_JIT)
def _single_geometry(
    pos: np.ndarray, mi: int, nb: int, t: float, field: Field, scratch: Scratch
) -> int:
    """``_expansion._geometry`` of mirror image ``mi`` of the points ``pos`` (fewer passes), the
    direction and table variable also as float32 (geo32 rows 0-2 and 4), the cutoff weight (geo
    row 7). Returns how many points it reaches."""
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
    """rad32[d, i] = the float32 table ``tables32`` (S, n_deg - 1, 3) of degree d above the
    lowest at point i, c₀ + (c₁ + c₂ σ) σ, σ = loc + 1, unscaled; four degrees a loop, then two
    (side by side: one index serves them; 1.15x faster than two, two 1.3x faster than one)."""
    n_deg = tables32.shape[1]
    n_four = n_deg - n_deg % 4
    for d0 in range(0, n_four, 4):
        for i in range(nb):
            s = sigma[i]
            coeffs = tables32[np.uint64(seg[i])]
            for d in range(d0, d0 + 4):
                rad32[d, i] = coeffs[d, 0] + (coeffs[d, 1] + coeffs[d, 2] * s) * s
    for d in range(n_four, n_deg, 2):
        e = min(d + 1, n_deg - 1)  # (an odd count: the last degree twice, the same value)
        row, nxt = rad32[d], rad32[e]
        for i in range(nb):
            j = np.uint64(seg[i])
            s = sigma[i]
            row[i] = tables32[j, d, 0] + (tables32[j, d, 1] + tables32[j, d, 2] * s) * s
            nxt[i] = tables32[j, e, 0] + (tables32[j, e, 1] + tables32[j, e, 2] * s) * s


@njit(**_JIT)
def _single_velocity(
    pos: np.ndarray, nb: int, t: float, field: Field, scratch: Scratch, vel: np.ndarray
) -> None:
    """vel[:, :nb] = v(pos[:, :nb], t) (rows x, y, z; module docstring)."""
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
        # the lowest degree: R₀ Y₀₀ C, or R₁ Σ_m Y_1m C_1m in the rescaled form of
        # ``_expansion._angular`` (P_1^0 = z, P_1^1 = 1, cos φ = x̂, sin φ = ŷ); then the weighted
        # sum (a zero weight adds exactly nothing); x, y, z in one loop: each row read once
        t0, row1, row2 = rad[0], (1 if l_first else 0), (2 if l_first else 0)
        for i in range(nb):
            a, s, w = t0[i], scale1[i] * cscale, weight[i]
            for k in range(3):
                c0, c1, c2 = coeffs[0, k], coeffs[row1, k], coeffs[row2, k]
                if l_first == 0:
                    u = a * c0 + s * total32[k, i]
                else:
                    u = ((a * z[i]) * c1 + x[i] * (a * c2)) + y[i] * (a * c0)
                    u = u + s * total32[k, i]
                if mi == 0:
                    vel[k, i] = w * u if w != 0.0 else 0.0
                else:
                    vel[k, i] = vel[k, i] + (mirrors[mi, k] * w) * u if w != 0.0 else vel[k, i]


@njit(**_JIT)
def _scratch(n_single: int) -> tuple[Scratch, Rows]:
    """Scratch rows of the velocity and of ``_steps`` (position, stage position, velocity)."""
    scratch = (
        np.empty((8, BLOCK)),
        np.empty(BLOCK, dtype=np.int64),
        np.empty((1, BLOCK)),
        np.empty((8, BLOCK), dtype=np.float32),
        np.empty((max(n_single, 1), BLOCK), dtype=np.float32),
        np.empty((10, BLOCK), dtype=np.float32),
        np.empty((3, BLOCK), dtype=np.float32),
    )
    rows = (np.empty((3, BLOCK)), np.empty((3, BLOCK)), np.empty((3, BLOCK)))
    return scratch, rows


@njit(**_JIT)
def _norm2(a: np.ndarray, b: np.ndarray, i: int, row: int) -> float:
    """|a[row:row+3, i] - b[0:3, i]|², summed x, y, z in that order."""
    d0: float = a[row, i] - b[0, i]
    d1: float = a[row + 1, i] - b[1, i]
    d2: float = a[row + 2, i] - b[2, i]
    return d0 * d0 + d1 * d1 + d2 * d2


@njit(**_JIT)
def _steps(
    third_order: bool,
    n_steps: int | np.int64,
    nb: int,
    start: np.ndarray,
    end: np.ndarray,
    mid: np.ndarray,
    spread: np.ndarray,
    field: Field,
    scratch: Scratch,
    rows: Rows,
) -> None:
    """end[:, :nb] = ``n_steps`` RK4 steps over t ∈ [0, 1] from start[:, :nb]; one step also
    writes the midpoint end x₀ + k₂ (mid rows 0-2) and the trapezoid end (rows 3-5). Or
    (``third_order``) Shu and Osher's SSPRK3: k₁ at (x₀, 0), k₂ at (x₀ + k₁, 1), k₃ at
    (x₀ + (k₁ + k₂)/4, ½), end x₀ + (k₁ + k₂ + 4 k₃)/6, spread[i] = |(2 k₃ - k₁ - k₂)/3|² (to
    the Heun end; mid rows 3-5 hold k₁ + k₂). One velocity call site: fewer inlined copies."""
    pos, stage_pos, vel = rows
    h = 1.0 / n_steps
    if third_order or n_steps == 1:  # one step: it starts from ``start`` itself
        pos = start
    else:  # (element loops rather than slice assignments, whose shape checks compile slowly)
        for k in range(3):
            for i in range(nb):
                pos[k, i] = start[k, i]
    ksum = mid[3:6]
    for step in range(n_steps):
        t0 = step * h
        for stage in range(3 if third_order else 4):
            if third_order:
                t = 0.0 if stage == 0 else (1.0 if stage == 1 else 0.5)
            else:  # classical RK4: stage offsets 0, h/2, h/2, h and weights 1, 2, 2, 1
                t = t0 + (0.0 if stage == 0 else (h if stage == 3 else 0.5 * h))
            _single_velocity(pos if stage == 0 else stage_pos, nb, t, field, scratch, vel)
            # one loop per stage (a branch on the stage inside the loop kept it from
            # vectorizing); each makes the next stage's position
            if third_order and stage == 0:
                for k in range(3):
                    for i in range(nb):
                        ksum[k, i] = vel[k, i]
                        stage_pos[k, i] = pos[k, i] + vel[k, i]
            elif third_order and stage == 1:
                for k in range(3):
                    for i in range(nb):
                        ksum[k, i] = ksum[k, i] + vel[k, i]
                        stage_pos[k, i] = pos[k, i] + 0.25 * ksum[k, i]
            elif third_order:
                for k in range(3):
                    for i in range(nb):
                        end[k, i] = pos[k, i] + (ksum[k, i] + 4.0 * vel[k, i]) * _SIXTH
                for i in range(nb):
                    d0 = (2.0 * vel[0, i] - ksum[0, i]) * _THIRD
                    d1 = (2.0 * vel[1, i] - ksum[1, i]) * _THIRD
                    d2 = (2.0 * vel[2, i] - ksum[2, i]) * _THIRD
                    spread[i] = d0 * d0 + d1 * d1 + d2 * d2
            else:
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
                            mid[3 + k, i] = mid[3 + k, i] + 0.5 * vel[k, i]
                weight = h / 6.0 if stage == 0 or stage == 3 else h / 3.0
                for k in range(3):
                    for i in range(nb):
                        end[k, i] = (end[k, i] if stage > 0 else pos[k, i]) + weight * vel[k, i]
                if stage < 3:
                    a = h if stage == 2 else 0.5 * h
                    for k in range(3):
                        for i in range(nb):
                            stage_pos[k, i] = pos[k, i] + a * vel[k, i]
        if not third_order and step + 1 < n_steps:
            for k in range(3):
                for i in range(nb):
                    pos[k, i] = end[k, i]


@njit(**_JIT)
def _predicted_error(end: np.ndarray, start: np.ndarray, mid: np.ndarray, i: int) -> float:
    """The cube of one RK4 step's predicted error at point i, e⁵ / max(m, e)² (module
    docstring)."""
    m2 = _norm2(end, start, i, 0)
    e = math.sqrt(max(_norm2(mid, end, i, 0), _norm2(mid, end, i, 3)))
    reach2 = max(m2, e * e)
    return e * e * e * e * e / reach2 if reach2 > 0.0 else 0.0


#: What ``_pass`` does with its blocks: the probes, the first pass, the refinement.
PROBE, FIRST, REFINE = 0, 1, 2


@njit(**_JIT)
def _pass(
    kind: int,  # PROBE, FIRST or REFINE (module docstring)
    points: np.ndarray,  # (N_all, 3) float64, start positions (the rows ``indices`` if indexed)
    indices: np.ndarray,  # (N,) int64 rows of ``points`` to move if ``indexed``
    indexed: bool,  # False: move every row of ``points`` (``indices`` is not read)
    in_place: bool,  # FIRST, REFINE: final ends into ``points`` (see below)
    limit: float,  # largest coordinate magnitude accepted in an indexed start position
    field: Field,
    n_steps: int,  # FIRST: RK4 steps (1 when adaptive)
    adaptive: bool,  # FIRST: also estimate the errors (``found``, ``block_found``)
    third_order: bool,  # FIRST: one SSPRK3 step, kept where its spread is within ``level``
    level: float,  # FIRST: the largest squared spread the probes spoke for; REFINE: the bound
    picked_rows: np.ndarray,  # (P,) int64: PROBE the points probed, REFINE those refined
    out: np.ndarray,  # (N, 3) end positions
    evaluations: np.ndarray,  # (N,) int64 velocity evaluations each point took (empty: none)
    found: np.ndarray,  # PROBE (3, P) float64, FIRST (1, N): see below
    block_found: np.ndarray,  # FIRST (2, n_blocks): each block's largest motion and rank
    problem: np.ndarray,  # (n_blocks,) int64: 1 an index out of range, 2 a bad start
    bad: np.ndarray,  # (n_blocks,) bool: an end position not finite
    first_block: int,
    last_block: int,
) -> None:
    """Blocks [first_block, last_block) of one pass of ``_stream.stream``. PROBE: found[0] =
    |x₃ - x₄| + |x₄ - x₄'| / 15 (SSPRK3 against two RK4 steps, plus their Richardson estimate;
    infinite for a bad start), found[1] the spread, found[2] |x₄ - x₀|². FIRST: found[0] the
    rank (the cube of the predicted error). REFINE: ``picked_rows`` (rows of ``out``), BLOCK at
    a time (module docstring). One function for the three: each one holding the velocity
    compiles for seconds. ``in_place``: final ends into ``points``, others into ``out``."""
    n_points = indices.shape[0] if indexed else points.shape[0]
    if kind != FIRST:
        n_points = picked_rows.shape[0]
    n_rows = points.shape[0]
    scratch, rows = _scratch(field.tables32.shape[1])
    start_rows = np.empty((3, BLOCK))
    ends = np.empty((3, 3, BLOCK))  # PROBE: third-order, one and two RK4 steps
    end_rows, previous = ends[0], ends[1]  # REFINE: the last two ends
    mid_rows = np.empty((6, BLOCK))
    motion2 = np.empty(BLOCK)
    spreads = np.empty(BLOCK)
    changes = np.empty(BLOCK)  # REFINE: each point's last |x_n - x_(n/2)| (none before)
    picked = np.empty(BLOCK, dtype=np.int64)
    for blk in range(first_block, last_block):
        start = blk * BLOCK
        nb = min(BLOCK, n_points - start)
        if kind == REFINE:
            for j in range(nb):
                picked[j] = picked_rows[start + j]
                changes[j] = 0.0
                for k in range(3):
                    previous[k, j] = out[picked[j], k]
        else:  # the gather, then the checks counted in loops that vectorize (no store in a branch)
            n_outside = 0
            for i in range(nb):
                row = start + i if kind == FIRST else picked_rows[start + i]
                if indexed:
                    row = indices[row]
                    inside = 0 <= row < n_rows
                    n_outside += 0 if inside else 1
                    row = row if inside else 0
                for k in range(3):
                    start_rows[k, i] = points[row, k]
            n_bad_starts = 0
            if indexed:
                for k in range(3):
                    for i in range(nb):
                        n_bad_starts += 0 if abs(start_rows[k, i]) <= limit else 1  # or NaN
            if (n_outside or n_bad_starts) and kind == PROBE:
                for j in range(nb):
                    found[0, start + j] = np.inf
                continue
            if n_outside or n_bad_starts:
                problem[blk] = 1 if n_outside else 2
        count = nb
        call = 0
        while count > 0 and (kind == REFINE or call < (3 if kind == PROBE else 1)):
            steps = n_steps if kind == FIRST else max(call, 1)
            if kind == REFINE:
                steps = 2 << call
                for j in range(count):
                    row = indices[picked[j]] if indexed else picked[j]
                    for k in range(3):
                        start_rows[k, j] = points[row, k]
            third = third_order if kind == FIRST else (kind == PROBE and call == 0)
            end = ends[call if kind == PROBE else 0]
            _steps(third, steps, count, start_rows, end, mid_rows, spreads, field, scratch, rows)
            call += 1
            if kind != REFINE:
                continue
            kept = 0
            for j in range(count):
                n = picked[j]
                change = math.sqrt(_norm2(end, previous, j, 0))
                for k in range(3):
                    out[n, k] = end[k, j]
                if evaluations.shape[0]:
                    evaluations[n] += 4 * steps
                # Richardson: the n-step result's error is about |x_n - x_(n/2)| / (2⁴ - 1); the
                # change before within 16 times that too (RK4's rate, not a chance agreement)
                again = change > 15.0 * level or changes[j] > 240.0 * level
                if again and steps < MAX_ADAPTIVE_STEPS:
                    picked[kept] = n
                    changes[kept] = change
                    for k in range(3):
                        previous[k, kept] = end[k, j]
                    kept += 1
                else:  # its final end position
                    row = indices[n] if indexed else n
                    for k in range(3):
                        if in_place:
                            points[row, k] = end[k, j]
                        if not math.isfinite(end[k, j]):
                            bad[blk] = True
            count = kept
        if kind == PROBE:
            third_end, coarse, fourth = ends[0], ends[1], ends[2]
            for j in range(nb):
                richardson = math.sqrt(_norm2(fourth, coarse, j, 0)) / 15.0
                found[0, start + j] = math.sqrt(_norm2(third_end, fourth, j, 0)) + richardson
                found[1, start + j] = spreads[j]
                found[2, start + j] = _norm2(fourth, start_rows, j, 0)
        if kind != FIRST:
            continue
        for i in range(nb):  # (a block with a problem: its rows may be out of range)
            final = in_place and problem[blk] == 0 and (not adaptive or spreads[i] <= level)
            row = indices[start + i] if indexed and final else start + i
            for k in range(3):
                if final:
                    points[row, k] = end_rows[k, i]
                else:
                    out[start + i, k] = end_rows[k, i]
        if evaluations.shape[0]:  # (an empty array: not counted)
            for i in range(nb):
                evaluations[start + i] = 3 if third_order else 4 * n_steps
        n_bad = 0  # (a count, not a flag set in the loop: it vectorizes)
        for k in range(3):
            for i in range(nb):
                n_bad += 0 if math.isfinite(end_rows[k, i]) else 1
        if n_bad:
            bad[blk] = True
        if not adaptive:
            continue
        rank = found[0]
        for i in range(nb):
            motion2[i] = _norm2(end_rows, start_rows, i, 0)
        if third_order:  # kept (rank 0), or refined (its spread is beyond the probes')
            kept = 0
            for i in range(nb):
                kept += 1 if spreads[i] <= level else 0
            block_found[1, blk] = 0.0 if kept == nb else np.inf
            if kept < nb:  # only such blocks' ranks are read (``_above``)
                for i in range(nb):
                    rank[start + i] = 0.0 if spreads[i] <= level else np.inf
        else:
            for i in range(nb):
                # prediction e (e/reach)^(2/3) > bound  ⇔  e⁵ / reach² > bound³
                rank[start + i] = _predicted_error(end_rows, start_rows, mid_rows, i)
            largest = 0.0
            for i in range(nb):
                largest = max(largest, rank[start + i])
            block_found[1, blk] = largest
        # the block's largest motion in a loop of its own: a max reduction inside the loops
        # above kept them (square roots and divisions) from vectorizing
        most = 0.0
        for i in range(nb):
            most = max(most, motion2[i])
        block_found[0, blk] = math.sqrt(most)
