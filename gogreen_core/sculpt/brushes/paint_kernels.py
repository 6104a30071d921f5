"""The compiled loops of the paint family: these once numba has them (compiled in the
background with the kernels, unit ``"brushes"``), else their NumPy twins (``_paint_numpy``, the
same arithmetic in the same order), so that a stroke never waits for the compiler.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from gogreen_core import _compiled
from gogreen_core.mesh.topology import BOUNDARY, FIXED
from gogreen_core.sculpt.brushes import _paint_numpy

__all__ = ["compile_now", "cutoff_weights", "kernels", "relax"]


def _exercise() -> None:
    """Call both loops once, typed as the brushes call them."""
    points = np.zeros((2, 3))
    rows = np.arange(2, dtype=np.int64)
    out = np.empty(2)
    f3 = np.zeros(3)
    cutoff_weights(points, rows, f3, f3, np.ones((1, 3)), f3, 0.5, 1.0, out)
    offsets = np.array([0, 1, 2], dtype=np.int64)
    neighbours = np.array([1, 0], dtype=np.int64)
    flags = np.zeros(2, dtype=np.bool_)
    mode = np.zeros(2, dtype=np.int8)
    relax(points, rows, rows, points, out, offsets, neighbours, flags, mode, np.empty((2, 3)))


_COMPILED = _compiled.CompiledModule(_compiled.BRUSHES, __name__, _paint_numpy, _exercise)
kernels = _COMPILED.kernels
compile_now = _COMPILED.compile_now


@njit(parallel=True, cache=True, nogil=True, boundscheck=False)
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
    """out[k] = the brushes' cutoff (:func:`~gogreen_core.sculpt.brushes.base.smooth_cutoff`)
    of the distance from points[rows[k]], or its nearest mirror image (``mirrors`` (m, 3) signs
    about ``origin``), to the segment from ``start`` to ``start + step``."""
    length2 = step[0] * step[0] + step[1] * step[1] + step[2] * step[2]
    inv = 1.0 / length2 if length2 > 0.0 else 0.0
    width = outer - inner
    for k in prange(rows.shape[0]):
        n = rows[k]
        nearest = np.inf
        for mi in range(mirrors.shape[0]):
            y0 = origin[0] + mirrors[mi, 0] * (points[n, 0] - origin[0]) - start[0]
            y1 = origin[1] + mirrors[mi, 1] * (points[n, 1] - origin[1]) - start[1]
            y2 = origin[2] + mirrors[mi, 2] * (points[n, 2] - origin[2]) - start[2]
            t = min(max((y0 * step[0] + y1 * step[1] + y2 * step[2]) * inv, 0.0), 1.0)
            d0 = y0 - t * step[0]
            d1 = y1 - t * step[1]
            d2 = y2 - t * step[2]
            nearest = min(nearest, d0 * d0 + d1 * d1 + d2 * d2)
        distance = np.sqrt(nearest)
        if width <= 0.0:
            out[k] = 1.0 if distance < outer else 0.0
        else:
            u = min(max((distance - inner) / width, 0.0), 1.0)
            out[k] = 1.0 - u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)


@njit(parallel=True, cache=True, nogil=True, boundscheck=False)
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
    """out[k] = current[k] + factor[k] (mean of the neighbours of vertex rows[k] − current[k]),
    neighbours read from ``current`` where they are rows (``slot`` ≥ 0) and ``vertices``
    elsewhere; boundary vertices take their boundary neighbours only, fixed ones stay."""
    for k in prange(rows.shape[0]):
        i = rows[k]
        kind = mode[i]
        sx = 0.0
        sy = 0.0
        sz = 0.0
        count = 0
        fx = fy = fz = 0.0
        if kind != FIXED and factor[k] != 0.0:
            for e in range(offsets[i], offsets[i + 1]):
                if kind == BOUNDARY and not on_boundary[e]:
                    continue
                j = neighbours[e]
                s = slot[j]
                if s >= 0:
                    px, py, pz = current[s, 0], current[s, 1], current[s, 2]
                else:
                    px, py, pz = vertices[j, 0], vertices[j, 1], vertices[j, 2]
                if count == 0:
                    fx, fy, fz = px, py, pz
                sx += px
                sy += py
                sz += pz
                count += 1
        if kind == BOUNDARY and count == 2:
            # a corner of the rim (a turn over 60° between its rim neighbours) stays
            ux, uy, uz = fx - current[k, 0], fy - current[k, 1], fz - current[k, 2]
            vx, vy, vz = sx - fx - current[k, 0], sy - fy - current[k, 1], sz - fz - current[k, 2]
            dot = ux * vx + uy * vy + uz * vz
            if dot > -0.5 * np.sqrt((ux * ux + uy * uy + uz * uz) * (vx * vx + vy * vy + vz * vz)):
                count = 0
        if count == 0:
            out[k, 0] = current[k, 0]
            out[k, 1] = current[k, 1]
            out[k, 2] = current[k, 2]
        else:
            f = factor[k]
            out[k, 0] = current[k, 0] + f * (sx / count - current[k, 0])
            out[k, 1] = current[k, 1] + f * (sy / count - current[k, 1])
            out[k, 2] = current[k, 2] + f * (sz / count - current[k, 2])
