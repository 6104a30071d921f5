"""The NumPy twins of ``_influence_compiled``'s loops: the boxes and the box tests (the same
tests, with the same margins), and the rows of the chosen blocks with the per-point test of
``_numpy_eval.near_segment``. They serve until the compiled code is ready."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from gogreen_core.field import _numpy_eval
from gogreen_core.field._influence_compiled import BLOCK, BLOCK_SHIFT, MAX_SCALE, SLACK


def mark(rows: NDArray[np.int64], n: int, dirty: NDArray[np.bool_]) -> None:
    """``_influence_compiled._mark``."""
    rows = rows[(rows >= -n) & (rows < n)] % n
    dirty[rows >> BLOCK_SHIFT] = True


def refit(
    vertices: NDArray[np.float64],
    blocks: NDArray[np.int64],
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
) -> None:
    """``_influence_compiled._refit`` (a few thousand blocks at a time)."""
    n = len(vertices)
    for part in np.array_split(blocks, max(1, len(blocks) // 4096)):
        rows = np.minimum((part[:, None] << BLOCK_SHIFT) + np.arange(BLOCK), n - 1)
        points = vertices[rows]  # (k, BLOCK, 3); a short last block repeats its last row
        lo[part] = np.fmin.reduce(points, axis=1, initial=np.inf)
        hi[part] = np.fmax.reduce(points, axis=1, initial=-np.inf)


def classify(
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    start: NDArray[np.float64],
    step: NDArray[np.float64],
    radius: float,
    mirrors: NDArray[np.float64],
    origin: NDArray[np.float64],
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]] | None:
    """``_influence_compiled._classify``: (blocks (n_blocks,) a capsule may meet, those inside one),
    or None where the margin argument does not hold."""
    valid = np.all(lo <= hi, axis=1)
    r = abs(radius)
    scale = max(r, *np.abs(origin), *np.abs(start), *np.abs(step), *np.abs(start + step))
    if valid.any():
        scale = max(scale, float(np.abs(lo[valid]).max()), float(np.abs(hi[valid]).max()))
    if not scale <= MAX_SCALE:
        return None
    slack = SLACK * scale
    inner = r - slack
    inner2 = inner * inner if inner > 0.0 else -1.0
    reached = np.zeros(len(lo), dtype=np.bool_)
    inside = np.zeros(len(lo), dtype=np.bool_)
    for signs in mirrors:
        a = origin + signs * (start - origin)
        d = signs * step
        length2 = float(d @ d)
        inv = 1.0 / length2 if length2 > 0.0 else 0.0
        near = valid & np.all(hi >= np.minimum(a, a + d) - (r + slack), axis=1)
        near &= np.all(lo <= np.maximum(a, a + d) + (r + slack), axis=1)
        mid = a + 0.5 * d
        gap = np.minimum(np.maximum(mid, lo), hi) - mid
        near &= np.einsum("ij,ij->i", gap, gap) <= (r + 0.5 * np.sqrt(length2) + slack) ** 2
        reached |= near
        if inner2 < 0.0:
            continue
        whole = near.copy()
        for corner in range(8):
            y = np.where([corner & 1, corner & 2, corner & 4], hi, lo) - a
            t = np.clip((y @ d) * inv, 0.0, 1.0)
            e = y - t[:, None] * d
            whole &= np.einsum("ij,ij->i", e, e) < inner2
        inside |= whole
    return reached, inside


def rows_near(
    points: NDArray[np.float64],
    start: NDArray[np.float64],
    step: NDArray[np.float64],
    radius: float,
    mirrors: NDArray[np.float64],
    origin: NDArray[np.float64],
    blocks: NDArray[np.int64],
    inside: NDArray[np.bool_],
) -> NDArray[np.int64]:
    """The reached rows of ``blocks`` (ascending; ``inside``: each is taken whole), the others'
    rows tested by ``_numpy_eval.near_segment``."""
    begin = blocks << BLOCK_SHIFT
    lengths = np.minimum(begin + BLOCK, len(points)) - begin
    ends = np.cumsum(lengths)
    total = int(ends[-1]) if len(ends) else 0
    rows = np.arange(total) + np.repeat(begin - (ends - lengths), lengths)
    keep = np.repeat(inside, lengths)
    tested = rows[~keep]
    near = np.empty(len(tested), dtype=np.bool_)
    _numpy_eval.near_segment(points[tested], start, step, radius, mirrors, origin, near)
    keep[~keep] = near
    reached: NDArray[np.int64] = rows[keep]
    return reached
