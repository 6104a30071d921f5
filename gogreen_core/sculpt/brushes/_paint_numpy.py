"""The NumPy twins of :mod:`~gogreen_core.sculpt.brushes.paint_kernels`: the same arithmetic in the
same order, so the same results bit for bit (a stroke made before the compiled loops were in
replays exactly after). Slower: they serve only until numba has compiled the loops."""

from __future__ import annotations

import numpy as np

from gogreen_core.mesh.topology import BOUNDARY, FIXED

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
    length2 = step[0] * step[0] + step[1] * step[1] + step[2] * step[2]
    inv = 1.0 / length2 if length2 > 0.0 else 0.0
    width = outer - inner
    p = points[rows]
    nearest = np.full(len(rows), np.inf)
    for m in mirrors:
        y0 = origin[0] + m[0] * (p[:, 0] - origin[0]) - start[0]
        y1 = origin[1] + m[1] * (p[:, 1] - origin[1]) - start[1]
        y2 = origin[2] + m[2] * (p[:, 2] - origin[2]) - start[2]
        t = np.minimum(np.maximum((y0 * step[0] + y1 * step[1] + y2 * step[2]) * inv, 0.0), 1.0)
        d0 = y0 - t * step[0]
        d1 = y1 - t * step[1]
        d2 = y2 - t * step[2]
        nearest = np.minimum(nearest, d0 * d0 + d1 * d1 + d2 * d2)
    distance = np.sqrt(nearest)
    if width <= 0.0:
        out[:] = np.where(distance < outer, 1.0, 0.0)
    else:
        u = np.minimum(np.maximum((distance - inner) / width, 0.0), 1.0)
        out[:] = 1.0 - u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)


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
    """See :func:`gogreen_core.sculpt.brushes.paint_kernels.relax`: the neighbour sums run over the
    neighbours' places in turn (the compiled loop's order)."""
    n = len(rows)
    kind = mode[rows]
    first_edge = offsets[rows]
    degree = offsets[rows + 1] - first_edge
    active = (kind != FIXED) & (factor != 0.0)
    total = np.zeros((3, n))
    first = np.zeros((3, n))
    count = np.zeros(n, dtype=np.int64)
    for j in range(int(degree.max(initial=0))):
        sel = np.flatnonzero(active & (j < degree))
        edge = first_edge[sel] + j
        keep = ~((kind[sel] == BOUNDARY) & ~on_boundary[edge])
        sel, edge = sel[keep], edge[keep]
        neighbour = neighbours[edge]
        s = slot[neighbour]
        inside = s >= 0
        point = np.where(inside[:, None], current[np.where(inside, s, 0)], vertices[neighbour])
        new = count[sel] == 0
        first[:, sel[new]] = point[new].T
        total[:, sel] += point.T
        count[sel] += 1
    sx, sy, sz = total
    cx, cy, cz = current[:, 0], current[:, 1], current[:, 2]
    corner = (kind == BOUNDARY) & (count == 2)
    if np.any(corner):
        fx, fy, fz = first
        ux, uy, uz = fx - cx, fy - cy, fz - cz
        vx, vy, vz = sx - fx - cx, sy - fy - cy, sz - fz - cz
        dot = ux * vx + uy * vy + uz * vz
        turn = dot > -0.5 * np.sqrt((ux * ux + uy * uy + uz * uz) * (vx * vx + vy * vy + vz * vz))
        count[corner & turn] = 0  # a corner of the rim stays
    moving = count > 0
    safe = np.where(moving, count, 1)
    for axis, s_axis, c_axis in ((0, sx, cx), (1, sy, cy), (2, sz, cz)):
        out[:, axis] = np.where(moving, c_axis + factor * (s_axis / safe - c_axis), c_axis)
