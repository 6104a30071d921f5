"""Streamlines of a brush's velocity field: RK4 over pseudo-time [0, 1] (paper Sec. 3.2).

    v(x, t) = Σ_M M s(|y - c(t)|) u(y - c(t)),   y = origin + M (x - origin),  c(t) = c₀ + t Δc

u is the expansion of ``_expansion`` with the load contracted into its coefficients (K = 3), s
the C² smooth cutoff (1 up to ``cutoff_inner``, a quintic smoothstep down to 0 over
1 / inv_width), M the mirror reflections about ``origin`` (row 0 is the brush itself).

Two arithmetics of u, chosen by the field's ``single`` flag (see ``_evaluation``):

* evaluation 2 (``single`` false): u as ``_expansion`` evaluates it, in double precision;
* evaluation 3 (``single``): ``_single_field``'s, the parity's lowest degree in double
  precision and the degrees above it in single precision: the higher degrees' arithmetic twice
  as fast, off evaluation 2 by ~1e-8 of the field, and the grabbed point at the brush centre
  still follows the cursor to rounding.

:func:`stream` runs the passes below over blocks of points on the thread pool (``_parallel``):

* fixed steps (``tolerance <= 0``): ``substeps`` classical RK4 steps for every point;
* adaptive: one RK4 step for every point, whose stages also give the ends of two second-order
  rules (midpoint x₀ + k₂, trapezoid x₀ + (k₁ + k₄)/2); the larger distance e of the RK4 end to
  them estimates a second-order error (order h³), and the RK4 error (order h⁵) is predicted as
  e (e / max(m, e))^(2/3), m the point's motion. Points whose prediction exceeds
  ESTIMATE_SAFETY · tolerance · scale (scale = the largest of |Δc| and every motion m) are
  packed into blocks of their own and integrated again with 2, 4, ... RK4 steps until
  Richardson's estimate |x_n - x_(n/2)| / 15 is under that bound (at most MAX_ADAPTIVE_STEPS).

Every point's result depends only on the input (blocks are fixed by the point order, never by
the thread count), and the generic and generated angular kernels compute the same bits, so
replays are bit-identical whatever the threads or the kernels compiled so far.
"""

from __future__ import annotations

import math
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit

from gogreen_core._expansion import _JIT, BLOCK, CUTOFF_END, _angular, _geometry, _radial
from gogreen_core._parallel import run_ranges
from gogreen_core._single_field import _single_velocity

if TYPE_CHECKING:
    #: The velocity field's tuple (see below), the scratch rows of ``_scratch``.
    Field = tuple[Any, ...]
    Scratch = tuple[
        np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
        np.ndarray, np.ndarray, np.ndarray, np.ndarray,
    ]  # fmt: skip
    Rows = tuple[np.ndarray, np.ndarray, np.ndarray]

__all__ = ["CUTOFF_END", "ESTIMATE_SAFETY", "MAX_ADAPTIVE_STEPS", "stream"]

#: SHA-256 (first 16 hex digits) of ``_expansion.py`` and ``_single_field.py``, written by
#: ``scripts/make_kernels.py`` (checked by ``tests/test_unrolled.py``). numba keys the disk cache
#: of this module's compiled code on this file alone, yet compiles their functions and constants
#: into it: a change there must change this file, or a stale machine code (another BLOCK,
#: another arithmetic) would be loaded.
COMPILED_SOURCES = "172a2073fdb8e66b"

#: Largest number of RK4 steps the adaptive streamlines give one vertex in one event.
MAX_ADAPTIVE_STEPS = 256
#: The adaptive streamlines accept a result where its estimated error is at most this fraction
#: of the tolerance. The one-step prediction is a model; calibrated on the ogre (cubic material,
#: l_max 8) with grab, twist, scale and pinch events of 0.1 ε to 0.8 ε against 64 fixed steps:
#: max error / motion scale 2e-6 (grab of 0.2 ε) up to 9.8e-5 (grab of 0.8 ε), affine brushes
#: below 2e-6; 0.1 refined 5x more vertices for no needed gain.
ESTIMATE_SAFETY = 0.25
#: Blocks per range handed to a thread (each a fraction of a millisecond of work).
_MIN_BLOCKS = 8

# The velocity field travels as one tuple through the functions below:
# (center0, center_step, eps, power, l_first, l_last, base, coeffs, beta, tables, angular,
#  unrolled, cutoff_inner, inv_width, mirrors, origin, single, coeffs32, beta32, tables32,
#  cscale, angular32, unrolled32); see ``stream`` and ``_evaluation.stream``.


@njit(**_JIT)
def _scratch(n_deg: int, n_single: int) -> tuple[Scratch, Rows]:
    """Scratch rows of ``_velocity`` (geometry, segments, radial terms, angular work, the
    angular sum, and their float32 twins for the single precision degrees) and of ``_rk4``
    (position, stage position, velocity)."""
    scratch = (
        np.empty((8, BLOCK)),
        np.empty(BLOCK, dtype=np.int64),
        np.empty((n_deg, BLOCK)),
        np.empty((10, BLOCK)),
        np.empty((3, BLOCK)),
        np.empty((8, BLOCK), dtype=np.float32),
        np.empty((max(n_single, 1), BLOCK), dtype=np.float32),
        np.empty((10, BLOCK), dtype=np.float32),
        np.empty((3, BLOCK), dtype=np.float32),
    )
    rows = (np.empty((3, BLOCK)), np.empty((3, BLOCK)), np.empty((3, BLOCK)))
    return scratch, rows


@njit(**_JIT)
def _velocity(
    pos: np.ndarray, nb: int, t: float, field: Field, scratch: Scratch, vel: np.ndarray
) -> None:
    """vel[:, :nb] = v(pos[:, :nb], t) (rows x, y, z)."""
    (center0, center_step, eps, power, l_first, l_last, base, coeffs, beta, tables, angular,
     unrolled, cutoff_inner, inv_width, mirrors, origin, single) = field[:17]  # fmt: skip
    if single:
        _single_velocity(pos, nb, t, field, scratch, vel)
        return
    geo, seg, rad, work, total = scratch[:5]
    weight = geo[7]
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
        rr = geo[3]
        reached = 0
        for i in range(nb):
            u = min(max((rr[i] - cutoff_inner) * inv_width, 0.0), 1.0)
            w = 1.0 - u * u * u * (10.0 + u * (6.0 * u - 15.0))
            weight[i] = w if u < CUTOFF_END else 0.0
            reached += 1 if u < CUTOFF_END else 0
        if reached == 0:  # the whole block is beyond the cutoff (a far mirror image): v += 0
            if mi == 0:
                for k in range(3):
                    for i in range(nb):
                        vel[k, i] = 0.0
            continue
        _radial(tables, l_first, nb, geo, seg, rad)
        if unrolled:
            angular(nb, geo.ctypes, rad.ctypes, coeffs.ctypes, total.ctypes)
        else:
            _angular(l_first, l_last, base, coeffs, beta, nb, geo, rad, work, total)
        # a zero weight contributes exactly nothing (not ±0 · u): the skip above is then exact
        for k in range(3):
            sgn = mirrors[mi, k]
            v_k = vel[k]
            t_k = total[k]
            if mi == 0:
                for i in range(nb):
                    v_k[i] = weight[i] * t_k[i] if weight[i] != 0.0 else 0.0
            else:
                for i in range(nb):
                    v_k[i] = v_k[i] + (sgn * weight[i]) * t_k[i] if weight[i] != 0.0 else v_k[i]


@njit(**_JIT)
def _norm2(a: np.ndarray, b: np.ndarray, i: int, row: int) -> float:
    """|a[row:row+3, i] - b[0:3, i]|², summed x, y, z in that order."""
    d0: float = a[row, i] - b[0, i]
    d1: float = a[row + 1, i] - b[1, i]
    d2: float = a[row + 2, i] - b[2, i]
    return d0 * d0 + d1 * d1 + d2 * d2


@njit(**_JIT)
def _rk4(
    n_steps: int | np.int64,
    nb: int,
    start: np.ndarray,
    end: np.ndarray,
    mid: np.ndarray,
    field: Field,
    scratch: Scratch,
    rows: Rows,
) -> None:
    """end[:, :nb] = ``n_steps`` classical RK4 steps over t ∈ [0, 1] from start[:, :nb].

    With one step, mid (6, BLOCK) also gets the ends of two second-order rules made of RK4's
    stages, the midpoint rule x₀ + k₂ (rows 0-2) and the trapezoid x₀ + (k₁ + k₄)/2 (rows 3-5):
    the adaptive pass's error estimates.
    """
    pos, stage_pos, vel = rows
    h = 1.0 / n_steps
    # (element loops rather than slice assignments, whose shape checks compile slowly)
    for k in range(3):
        for i in range(nb):
            pos[k, i] = start[k, i]
    for step in range(n_steps):
        t0 = step * h
        for stage in range(4):
            # classical RK4: stage offsets 0, h/2, h/2, h and weights 1, 2, 2, 1
            a = 0.0 if stage == 0 else (h if stage == 3 else 0.5 * h)
            if stage == 0:
                _velocity(pos, nb, t0, field, scratch, vel)
            else:
                for k in range(3):
                    for i in range(nb):
                        stage_pos[k, i] = pos[k, i] + a * vel[k, i]
                _velocity(stage_pos, nb, t0 + a, field, scratch, vel)
            # one loop per stage (a branch on the stage inside the loop kept it from vectorizing)
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
        for k in range(3):
            for i in range(nb):
                pos[k, i] = end[k, i]


@njit(**_JIT)
def _first_pass(
    points: np.ndarray,  # (N_all, 3) float64, start positions (the rows ``indices`` if indexed)
    indices: np.ndarray,  # (N,) int64 rows of ``points`` to move if ``indexed``
    indexed: bool,  # False: move every row of ``points`` (``indices`` is not read)
    limit: float,  # largest coordinate magnitude accepted in an indexed start position
    n_steps: int,  # RK4 steps (1 when adaptive)
    adaptive: bool,  # also estimate the errors (``rank``, ``block_motion``)
    field: Field,
    out: np.ndarray,  # (N, 3) end positions
    steps: np.ndarray,  # (N,) int64 RK4 steps each point took
    rank: np.ndarray,  # (N,) e⁵ / max(m, e)²: the cube of the predicted error (module docstring)
    block_motion: np.ndarray,  # (n_blocks,) the largest motion m in each block
    problem: np.ndarray,  # (n_blocks,) int64: 1 an index out of range, 2 a bad start
    bad: np.ndarray,  # (n_blocks,) bool: an end position not finite
    first_block: int,
    last_block: int,
) -> None:
    """The first pass of ``stream`` over blocks [first_block, last_block)."""
    n_points = indices.shape[0] if indexed else points.shape[0]
    n_rows = points.shape[0]
    scratch, rows = _scratch(field[9].shape[0], field[19].shape[1])
    start_rows = np.empty((3, BLOCK))
    end_rows = np.empty((3, BLOCK))
    mid_rows = np.empty((6, BLOCK))
    motion2 = np.empty(BLOCK)
    for blk in range(first_block, last_block):
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
        _rk4(n_steps, nb, start_rows, end_rows, mid_rows, field, scratch, rows)
        for i in range(nb):
            for k in range(3):
                out[start + i, k] = end_rows[k, i]
            steps[start + i] = n_steps
        for k in range(3):
            for i in range(nb):
                if not math.isfinite(end_rows[k, i]):
                    bad[blk] = True
        if adaptive:
            for i in range(nb):
                m2 = _norm2(end_rows, start_rows, i, 0)
                e_mid = _norm2(mid_rows, end_rows, i, 0)
                e_trap = _norm2(mid_rows, end_rows, i, 3)
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


@njit(**_JIT)
def _refine_pass(
    points: np.ndarray, indices: np.ndarray, indexed: bool, field: Field, bound: float,
    refine: np.ndarray, out: np.ndarray, steps: np.ndarray, bad: np.ndarray, first_block: int,
    last_block: int,
) -> None:  # fmt: skip
    """The points ``refine`` (indices into ``out``), packed BLOCK at a time, again with 2, 4, …
    RK4 steps until Richardson's estimate is under ``bound`` (blocks [first, last) of them)."""
    n_refine = refine.shape[0]
    scratch, rows = _scratch(field[9].shape[0], field[19].shape[1])
    start_rows = np.empty((3, BLOCK))
    end_rows = np.empty((3, BLOCK))
    previous = np.empty((3, BLOCK))
    picked = np.empty(BLOCK, dtype=np.int64)
    for blk in range(first_block, last_block):
        start = blk * BLOCK
        count = min(BLOCK, n_refine - start)
        for j in range(count):
            picked[j] = refine[start + j]
            for k in range(3):
                previous[k, j] = out[picked[j], k]
        n_steps = np.int64(1)
        while count > 0:
            n_steps *= 2
            for j in range(count):
                row = indices[picked[j]] if indexed else picked[j]
                for k in range(3):
                    start_rows[k, j] = points[row, k]
            _rk4(n_steps, count, start_rows, end_rows, end_rows, field, scratch, rows)
            kept = 0
            for j in range(count):
                n = picked[j]
                d2 = _norm2(end_rows, previous, j, 0)
                for k in range(3):
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


@njit(**_JIT)
def _write_back(
    points: np.ndarray, indices: np.ndarray, indexed: bool, out: np.ndarray, first: int, last: int
) -> None:
    """points[indices[n]] (or points[n]) = out[n] for n in [first, last)."""
    for n in range(first, last):
        row = indices[n] if indexed else n
        for k in range(3):
            points[row, k] = out[n, k]


def refinement_bound(center_step: np.ndarray, motion: float, tolerance: float) -> float:
    """ESTIMATE_SAFETY · tolerance · scale, scale the larger of |center_step| and the largest
    motion of a first step (the same float wherever it is computed)."""
    s0, s1, s2 = (float(v) for v in center_step)
    return ESTIMATE_SAFETY * tolerance * max(math.sqrt(s0 * s0 + s1 * s1 + s2 * s2), motion)


def stream(
    points: np.ndarray,
    indices: np.ndarray,
    indexed: bool,
    write_back: bool,
    limit: float,
    field: tuple[Any, ...],
    substeps: int,
    tolerance: float,
    out: np.ndarray,
    steps: np.ndarray,
) -> int:
    """Move points along the streamlines of ``field`` (see the module docstring).

    ``points`` (N_all, 3): start positions, the rows ``indices`` (N,) int64 if ``indexed``
    (read in place, no gathered copy), written back in place with ``write_back`` and only if
    every end position is finite. ``field``: the velocity (see ``_velocity``). ``substeps``
    fixed RK4 steps if ``tolerance <= 0``, else adaptive steps within ``tolerance`` times the
    motion scale. ``out`` (N, 3) gets the end positions, ``steps`` (N,) int64 the RK4 steps of
    each point. Returns 0 when done, 1 if an index is out of range, 2 if an indexed start
    position is not finite or beyond ``limit`` (nothing integrated), 3 if an end position is not
    finite (nothing written back).
    """
    n_points = indices.shape[0] if indexed else points.shape[0]
    if indexed and points.shape[0] == 0:
        return 1
    n_blocks = (n_points + BLOCK - 1) // BLOCK
    adaptive = tolerance > 0.0
    rank = np.empty(n_points)
    block_motion = np.zeros(n_blocks)
    problem = np.zeros(n_blocks, dtype=np.int64)
    bad = np.zeros(n_blocks, dtype=np.bool_)
    first_pass = partial(
        _first_pass, points, indices, indexed, limit, 1 if adaptive else substeps, adaptive,
        field, out, steps, rank, block_motion, problem, bad,
    )  # fmt: skip
    run_ranges(first_pass, n_blocks, _MIN_BLOCKS)
    for code in (1, 2):
        if np.any(problem == code):
            return code
    if adaptive:
        bound = refinement_bound(field[1], float(block_motion.max(initial=0.0)), tolerance)
        if bound > 0.0:
            refine = np.flatnonzero(rank > bound * bound * bound)
            n_packed = (len(refine) + BLOCK - 1) // BLOCK
            refined_bad = np.zeros(n_packed, dtype=np.bool_)
            refine_pass = partial(
                _refine_pass, points, indices, indexed, field, bound, refine, out, steps,
                refined_bad,
            )  # fmt: skip
            run_ranges(refine_pass, n_packed, 1)
            # a first step that overflowed fails the event even where refinement might not
            if write_back and (refined_bad.any() or bad.any()):
                return 3
    if not write_back:
        return 0
    if bad.any():
        return 3
    run_ranges(partial(_write_back, points, indices, indexed, out), n_points, 1 << 16)
    return 0
