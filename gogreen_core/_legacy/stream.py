"""The streamlines of sessions recorded before version 3 (evaluation 1), kept unchanged.

Frozen, as ``_legacy.expansion`` (whose drivers' arithmetic it shares): adaptive RK4 steps with
the one-step error prediction, the packed refinement pass and the fixed-step reference, exactly
as they produced the results of session files of versions 1 and 2. Do not edit.
"""

from __future__ import annotations

import math
from collections import namedtuple
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit, prange

from gogreen_core._legacy.expansion import _JIT, BLOCK, TASKS, _angular, _geometry, _radial

if TYPE_CHECKING:
    Scratch = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    Rows = tuple[np.ndarray, np.ndarray, np.ndarray]

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
    pos: np.ndarray,
    nb: int,
    t: float,
    field: _Field,
    scratch: Scratch,
    vel: np.ndarray,
) -> None:
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
    n_steps: int,
    nb: int,
    start: np.ndarray,
    end: np.ndarray,
    mid: np.ndarray,
    field: _Field,
    scratch: Scratch,
    rows: Rows,
) -> None:
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
def _scratch(n_deg: int) -> tuple[Scratch, Rows]:
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
    angular: Any,  # as in ``expand``
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
    points: np.ndarray,
    indices: np.ndarray,
    indexed: bool,
    field: _Field,
    tolerance: float,
    out: np.ndarray,
    steps: np.ndarray,
    rank: np.ndarray,
    block_motion: np.ndarray,
) -> bool:
    """The adaptive pass of ``stream``: the points whose predicted error is too large, again
    with 2, 4, ... RK4 steps (see ``stream``). Returns True if an end position it wrote is not
    finite."""
    n_points = out.shape[0]
    n_deg = field.tables.shape[0]
    n_blocks: int = block_motion.shape[0]
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
    n_refine: int = offsets[n_blocks]
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
