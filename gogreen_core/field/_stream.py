"""The streamlines' passes (``_integrator``) run over the thread pool, and the choices between."""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import Any, NamedTuple

import numpy as np

from gogreen_core._parallel import run_ranges
from gogreen_core.field._expansion import BLOCK
from gogreen_core.field._integrator import FIRST, PROBE, REFINE, _pass

__all__ = [
    "ESTIMATE_SAFETY",
    "MIN_PROBES",
    "POINTS_PER_PROBE",
    "THIRD_ORDER_POINTS",
    "StreamField",
    "probe_rows",
    "refinement_bound",
    "stream",
    "third_order_limit",
]

#: The adaptive streamlines accept a result where its estimated error is at most this fraction
#: of the tolerance. The one-step prediction is a model; calibrated on the ogre (cubic material,
#: l_max 8) with grab, twist, scale and pinch events of 0.1 ε to 0.8 ε against 64 fixed steps:
#: max error / motion scale 2e-6 (grab of 0.2 ε) up to 9.8e-5 (grab of 0.8 ε), affine brushes
#: below 2e-6; 0.1 refined 5x more vertices for no needed gain.
ESTIMATE_SAFETY = 0.25
#: Fewest blocks a range handed to a thread (2,048 points: a fraction of a millisecond).
_MIN_BLOCKS = max(1, 2048 // BLOCK)
#: Fewest points an adaptive pass probes for third-order steps (below, RK4 serves them all).
THIRD_ORDER_POINTS = 1024
#: Points a probe stands for (at least MIN_PROBES probes): the probes cost 15 evaluations
#: each, 3 % of the evaluation a point they can save.
POINTS_PER_PROBE = 512
MIN_PROBES = 256


class StreamField(NamedTuple):
    """The streamlines' velocity field (``_integrator``), one record (a named tuple in numba):
    the load moves from ``center0`` by ``center_step``; ``coeffs`` (n_terms, 3) its folded
    expansion of degrees ``l_first`` … ``l_last`` (rows of degree l from ``base[l]``), ``tables``
    the lowest degree's radial table; the degrees above it in float32 (``coeffs32`` over
    ``cscale``, ``beta32``, ``tables32``, ``angular32`` generated if ``unrolled32``); the cutoff
    fades from ``cutoff_inner`` over 1 / ``inv_width``; ``mirrors`` (n_m, 3) signs about
    ``origin``."""

    center0: np.ndarray
    center_step: np.ndarray
    eps: float
    power: int
    l_first: int
    l_last: int
    base: np.ndarray
    coeffs: np.ndarray
    tables: np.ndarray
    cutoff_inner: float
    inv_width: float
    mirrors: np.ndarray
    origin: np.ndarray
    coeffs32: np.ndarray
    beta32: np.ndarray
    tables32: np.ndarray
    cscale: float
    angular32: Any
    unrolled32: bool


def refinement_bound(center_step: np.ndarray, motion: float, tolerance: float) -> float:
    """ESTIMATE_SAFETY · tolerance · scale, scale the larger of |center_step| and the largest
    motion of a first step (the same float wherever it is computed)."""
    s0, s1, s2 = (float(v) for v in center_step)
    return ESTIMATE_SAFETY * tolerance * max(math.sqrt(s0 * s0 + s1 * s1 + s2 * s2), motion)


def _above(rank: np.ndarray, block_rank: np.ndarray, level: float) -> np.ndarray:
    """The points (n,) int64, ascending, whose rank is above ``level``: looked for in the
    blocks whose largest is (``np.flatnonzero(rank > level)`` without a pass over them all)."""
    blocks = np.flatnonzero(block_rank > level)
    if not len(blocks):
        return blocks
    points = (blocks[:, None] * BLOCK + np.arange(BLOCK)).ravel()
    points = points[points < len(rank)]
    above: np.ndarray = points[rank[points] > level]
    return above


def probe_rows(n_points: int) -> np.ndarray:
    """The points (n,) int64 an adaptive third-order pass over ``n_points`` probes first: one
    in :data:`POINTS_PER_PROBE` (at least :data:`MIN_PROBES`), evenly spread; none below
    :data:`THIRD_ORDER_POINTS` points."""
    if n_points < THIRD_ORDER_POINTS:
        return np.zeros(0, dtype=np.int64)
    n_probes = max(MIN_PROBES, n_points // POINTS_PER_PROBE)
    return (2 * np.arange(n_probes, dtype=np.int64) + 1) * n_points // (2 * n_probes)


def third_order_limit(
    center_step: np.ndarray, tolerance: float, error: np.ndarray, spread: np.ndarray,
    motion: np.ndarray,
) -> float:  # fmt: skip
    """The largest squared spread of the third-order steps kept, from the probes' findings
    (``_integrator._pass``), or -1 where the probes showed an error beyond the bound (or none was
    made): no third-order step then."""
    if not len(error):
        return -1.0
    bound = refinement_bound(center_step, math.sqrt(float(motion.max())), tolerance)
    if not (bound > 0.0 and float(error.max()) <= bound):  # NaN: no
        return -1.0
    return float(spread.max())


def _bounded(field: StreamField) -> bool:
    """Whether |v| < 1e300 (no end overflows), float32 sums < 1e36: images × 1/ε^power × tables'
    Σ|c_j| × coefficients × (1 + max β)^l_last (P_l^m = z P_(l-1) - β P_(l-2); |cos mφ| ≤ 1)."""
    with np.errstate(all="ignore"):
        harmonics = (1.0 + float(np.abs(field.beta32).max(initial=0.0))) ** field.l_last
        upper = np.abs(field.tables32.astype(np.float64)) @ [1.0, 2.0, 4.0]  # σ ∈ [0, 2]
        coeffs32 = np.abs(field.coeffs32.astype(np.float64)).sum(axis=0)
        single = harmonics * float(upper.sum(axis=1).max(initial=0.0)) * coeffs32
        low = np.abs(field.tables).sum(axis=-1).max() * np.abs(field.coeffs).sum(axis=0)
        scale = len(field.mirrors) * field.eps ** -float(field.power)
        return bool(single.max() < 1e36 and (scale * (low + field.cscale * single)).max() < 1e300)


def stream(
    points: np.ndarray,
    indices: np.ndarray,
    indexed: bool,
    write_back: bool,
    limit: float,
    field: StreamField,
    substeps: int,
    tolerance: float,
    out: np.ndarray,
    evaluations: np.ndarray,
    run_pass: Callable[..., None],
    rows_checked: bool = False,
) -> int:
    """Move ``points`` (N_all, 3; the rows ``indices`` (N,) if ``indexed``) along the
    streamlines of ``field`` by ``run_pass`` (``_integrator._pass`` or its NumPy twin), as
    ``GreenKernel.streamlines`` (``tolerance <= 0``: fixed steps; ``write_back``: in place).
    Returns 0 when done, 1 if an index is out of range, 2 if an indexed start position is not
    finite or beyond ``limit`` (nothing integrated), 3 if an end position is not finite
    (nothing written back). Vouched rows (``rows_checked``), :func:`_bounded`: written as made."""
    n_points = indices.shape[0] if indexed else points.shape[0]
    if indexed and points.shape[0] == 0:
        return 1
    n_blocks = (n_points + BLOCK - 1) // BLOCK
    adaptive = tolerance > 0.0
    rank = np.empty((1, n_points))
    blocks = np.zeros((2, n_blocks))  # each block's largest motion and rank
    problem = np.zeros(n_blocks, dtype=np.int64)
    bad = np.zeros(n_blocks, dtype=np.bool_)

    def run(
        kind: int,
        picked: np.ndarray,
        found: np.ndarray,
        n_steps: int = 1,
        third: bool = False,
        level: float = 0.0,
    ) -> None:
        work = partial(
            run_pass, kind, points, indices, indexed, in_place and kind != PROBE, limit, field,
            n_steps, adaptive, third, level, picked, out, evaluations, found, blocks, problem, bad,
        )  # fmt: skip
        n = n_blocks if kind == FIRST else (len(picked) + BLOCK - 1) // BLOCK
        run_ranges(work, n, _MIN_BLOCKS if kind == FIRST else 1)

    limit3, in_place = -1.0, False
    if adaptive:
        probes = probe_rows(n_points)
        found = np.empty((3, len(probes)))
        run(PROBE, probes, found)
        limit3 = third_order_limit(field.center_step, tolerance, *found)
    steps = 1 if adaptive else substeps
    in_place = write_back and rows_checked and run_pass is _pass
    in_place = in_place and (limit3 >= 0.0 or not adaptive) and _bounded(field)
    run(FIRST, probe_rows(0), rank, steps, limit3 >= 0.0, max(limit3, 0.0))
    for code in (1, 2):
        if np.any(problem == code):
            return code
    if adaptive:
        bound = refinement_bound(field.center_step, float(blocks[0].max(initial=0.0)), tolerance)
        if bound > 0.0:
            # (a refined block's overflow marks ``bad`` at its own index: only bad.any() is read)
            run(REFINE, _above(rank[0], blocks[1], bound * bound * bound), rank, level=bound)
    if not write_back:
        return 0
    if bad.any():
        return 3
    if not in_place:
        points[indices if indexed else slice(None)] = out[:n_points]
    return 0
