"""The NumPy twins of :mod:`~gogreen_core.sculpt.brushes.paint_kernels`, held to them within 1e-12
relative; they serve only until numba has compiled the loops."""

from __future__ import annotations

import numpy as np

from gogreen_core.field._numpy_eval import segment_distance2
from gogreen_core.mesh.topology import BOUNDARY, FIXED
from gogreen_core.sculpt.brushes.base import smooth_cutoff

__all__ = ["cutoff_weights", "relax"]


def cutoff_weights(
    points: np.ndarray,
    rows: np.ndarray,
    start: np.ndarray,
    step: np.ndarray,
    mirrors: np.ndarray,
    origin: np.ndarray,
    inner: float,
    outer: float,
    out: np.ndarray,
) -> None:
    """See :func:`gogreen_core.sculpt.brushes.paint_kernels.cutoff_weights`."""
    distance = np.sqrt(segment_distance2(points[rows], start, step, mirrors, origin))
    out[:] = smooth_cutoff(distance, inner, outer)


def relax(
    vertices: np.ndarray,
    rows: np.ndarray,
    slot: np.ndarray,
    current: np.ndarray,
    factor: np.ndarray,
    offsets: np.ndarray,
    neighbours: np.ndarray,
    on_boundary: np.ndarray,
    mode: np.ndarray,
    out: np.ndarray,
) -> None:
    """See :func:`gogreen_core.sculpt.brushes.paint_kernels.relax`."""
    n = len(rows)
    kind = mode[rows]
    begin = offsets[rows]
    degree = np.where((kind != FIXED) & (factor != 0.0), offsets[rows + 1] - begin, 0)
    owner = np.repeat(np.arange(n), degree)  # each row's edges in turn
    edge = np.repeat(begin - np.cumsum(degree) + degree, degree) + np.arange(owner.size)
    keep = (kind[owner] != BOUNDARY) | on_boundary[edge]  # the rim: its rim neighbours only
    owner, neighbour = owner[keep], neighbours[edge[keep]]
    s = slot[neighbour]
    point = np.where((s >= 0)[:, None], current[np.maximum(s, 0)], vertices[neighbour])
    count = np.bincount(owner, minlength=n)
    total = np.zeros((n, 3))
    np.add.at(total, owner, point)
    first = np.zeros((n, 3))
    some = np.flatnonzero(count)
    first[some] = point[np.searchsorted(owner, some)]
    u, v = first - current, total - first - current
    turn = np.sum(u * v, axis=1) > -0.5 * np.sqrt(np.sum(u * u, axis=1) * np.sum(v * v, axis=1))
    count[(kind == BOUNDARY) & (count == 2) & turn] = 0  # a corner of the rim stays
    mean = total / np.maximum(count, 1)[:, None]
    out[:] = np.where((count > 0)[:, None], current + factor[:, None] * (mean - current), current)
