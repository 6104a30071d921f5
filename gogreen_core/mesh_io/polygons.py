"""Polygons to triangles by their shape, and the index check that names the polygon at fault.

Polygons are given as consecutive corners with their sizes (the way files list them) and come
back as triangles of *corner positions*, so that a caller maps vertex and texture indices
through the same triangles. A polygon whose fan from its first corner (``0, j, j+1``) covers it
exactly (every fan triangle on the polygon's side of its best-fit plane: triangles, convex
polygons, and many concave ones) keeps that fan, as the file order has it. The others (a
concave n-gon, where the fan would cover the notch) are triangulated on their best-fit plane:
by the fan from another corner when one covers the polygon, else by ear clipping
(``mapbox_earcut``). Each polygon of k corners always gives k-2 triangles that use each of its
corners and edges, so neighbouring faces stay connected, and the polygon's area is kept.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import mapbox_earcut
import numba
import numpy as np

from gogreen_core.mesh_io.data import MeshFileError

__all__ = ["check_corner_indices", "concatenated_ranges", "triangulate"]

#: A fan triangle whose turn against the polygon's normal is below -this (the sine of the
#: angle between the triangle's and the polygon's sides) folds over: the polygon is concave
#: there. The tolerance lets nearly straight corners (three points in a row) keep the fan.
_FOLD_TOLERANCE = 1e-9
#: Polygons of up to this many corners try the fan from each of their corners (k² work each)
#: before ear clipping.
_MAX_FAN_STARTS = 32


def concatenated_ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The ranges ``starts[i] : starts[i] + counts[i]`` (int64), concatenated."""
    return np.repeat(starts - _starts(counts), counts) + np.arange(int(counts.sum()))


def check_corner_indices(
    corners: np.ndarray, sizes: np.ndarray, n_vertices: int, where: Callable[[int], str]
) -> None:
    """Raise MeshFileError for the first corner (in file order) whose vertex index is not in
    [0, n_vertices); ``where(polygon)`` starts the message (the file, and its line if known)."""
    outside = (corners < 0) | (corners >= n_vertices)
    if outside.any():
        corner = int(np.argmax(outside))
        polygon = int(np.searchsorted(np.cumsum(sizes), corner, side="right"))
        raise MeshFileError(
            f"{where(polygon)}: face {polygon} references vertex {int(corners[corner])} "
            f"but the file has {n_vertices} vertices"
        )


def triangulate(points: np.ndarray, corners: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """Triangles of polygons by their shape (see the module's description).

    Parameters
    ----------
    points : (N, 3) float64
        Vertex positions.
    corners : (C,) int
        Vertex index of each corner (all in [0, N)), polygon after polygon.
    sizes : (P,) int
        Corners of each polygon (≥ 3), summing to C.

    Returns
    -------
    (T, 3) int64
        Positions in ``corners`` of each triangle's corners, T = Σ(k-2), polygon after polygon.
    """
    sizes = np.asarray(sizes, dtype=np.int64)
    if len(sizes) == 0 or sizes.max() == 3:
        return np.arange(3 * len(sizes), dtype=np.int64).reshape(-1, 3)
    corners = np.ascontiguousarray(corners, dtype=np.int64)
    points = np.ascontiguousarray(points, dtype=np.float64)
    triangles, folded = _fans(points, corners, sizes, _FOLD_TOLERANCE)
    if folded.any():
        _retriangulate(points, corners, sizes, triangles, np.flatnonzero(folded))
    return triangles


def _starts(sizes: np.ndarray) -> np.ndarray:
    """Offset of each run of ``sizes`` items in their concatenation."""
    return np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)


@numba.njit(cache=True, nogil=True)
def _fans(points, corners, sizes, tolerance):
    """The fan of each polygon from its first corner (T, 3) (positions in ``corners``), and
    whether it folds over (P,): a fan triangle turns against the polygon's Newell normal (its
    best-fit plane), which is the sum of the fan triangles' cross products."""
    n_triangles = 0
    for p in range(len(sizes)):
        n_triangles += sizes[p] - 2
    triangles = np.empty((n_triangles, 3), dtype=np.int64)
    folded = np.zeros(len(sizes), dtype=np.bool_)
    cross = np.empty((np.max(sizes), 4))  # per fan triangle: its cross product and scale
    c = 0
    t = 0
    for p in range(len(sizes)):
        k = sizes[p]
        for j in range(k - 2):
            triangles[t + j, 0] = c
            triangles[t + j, 1] = c + j + 1
            triangles[t + j, 2] = c + j + 2
        if k > 3:
            o = corners[c]
            nx = ny = nz = 0.0
            for j in range(k - 2):
                b = corners[c + j + 1]
                d = corners[c + j + 2]
                ax = points[b, 0] - points[o, 0]
                ay = points[b, 1] - points[o, 1]
                az = points[b, 2] - points[o, 2]
                bx = points[d, 0] - points[o, 0]
                by = points[d, 1] - points[o, 1]
                bz = points[d, 2] - points[o, 2]
                cross[j, 0] = ay * bz - az * by
                cross[j, 1] = az * bx - ax * bz
                cross[j, 2] = ax * by - ay * bx
                cross[j, 3] = np.sqrt((ax * ax + ay * ay + az * az) * (bx * bx + by * by + bz * bz))
                nx += cross[j, 0]
                ny += cross[j, 1]
                nz += cross[j, 2]
            length = np.sqrt(nx * nx + ny * ny + nz * nz)
            for j in range(k - 2):
                side = cross[j, 0] * nx + cross[j, 1] * ny + cross[j, 2] * nz
                if side < -tolerance * cross[j, 3] * length:
                    folded[p] = True
                    break
        c += k
        t += k - 2
    return triangles, folded


def _retriangulate(
    points: np.ndarray,
    corners: np.ndarray,
    sizes: np.ndarray,
    triangles: np.ndarray,
    polygons: np.ndarray,
) -> None:
    """Replace, in ``triangles``, the fans of ``polygons`` by triangulations that cover them:
    the fan from another corner when one does, else ear clipping."""
    corner_starts, triangle_starts = _starts(sizes), _starts(sizes - 2)
    for k in np.unique(sizes[polygons]).tolist():
        group = polygons[sizes[polygons] == k]
        positions = points[corners[corner_starts[group][:, None] + np.arange(k)]]  # (G, k, 3)
        local = np.arange(k - 2)
        normal = np.cross(
            positions[:, 1:-1] - positions[:, :1], positions[:, 2:] - positions[:, :1]
        ).sum(axis=1)
        left = np.ones(len(group), dtype=bool)
        for start in range(1, k if k <= _MAX_FAN_STARTS else 1):
            ring = (start + np.arange(k)) % k
            covers = left & _fan_covers(positions[:, ring], normal)
            if covers.any():
                fan_rows = np.stack([np.zeros(k - 2, int), local + 1, local + 2], axis=1)
                rows = triangle_starts[group[covers]][:, None] + local
                triangles[rows] = corner_starts[group[covers]][:, None, None] + ring[fan_rows]
                left &= ~covers
            if not left.any():
                break
        for g in np.flatnonzero(left).tolist():
            clipped = _ear_clip(positions[g], normal[g])
            if clipped is not None:  # else the fan stays: a degenerate or twisted polygon
                rows = triangle_starts[group[g]] + local
                triangles[rows] = corner_starts[group[g]] + clipped


def _fan_covers(positions: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Whether the fan from the first corner of each polygon (G, k, 3) stays on the side of
    its ``normal`` (G, 3)."""
    a = positions[:, 1:-1] - positions[:, :1]
    b = positions[:, 2:] - positions[:, :1]
    side = np.einsum("gtj,gj->gt", np.cross(a, b), normal)
    scale = np.sqrt(
        np.einsum("gtj,gtj->gt", a, a)
        * np.einsum("gtj,gtj->gt", b, b)
        * np.einsum("gj,gj->g", normal, normal)[:, None]
    )
    return (side >= -_FOLD_TOLERANCE * scale).all(axis=1)


def _ear_clip(positions: np.ndarray, normal: np.ndarray) -> np.ndarray | None:
    """Triangles (k-2, 3) of corner numbers covering one polygon (k, 3) with Newell ``normal``,
    by ear clipping on its best-fit plane; None when that fails (a twisted polygon)."""
    k = len(positions)
    length = np.linalg.norm(normal)
    if not length > 0:
        return None
    w = normal / length
    u = np.cross(w, [1.0, 0.0, 0.0] if abs(w[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(w, u)  # (u, v, w) right-handed: the polygon runs counter-clockwise in (u, v)
    flat = np.ascontiguousarray((positions - positions[0]) @ np.stack([u, v], axis=1))
    found = mapbox_earcut.triangulate_float64(flat, np.array([k], dtype=np.uint32))
    tri = np.asarray(found, dtype=np.int64).reshape(-1, 3)
    if len(tri) == 0:
        return None
    a, b = flat[tri[:, 1]] - flat[tri[:, 0]], flat[tri[:, 2]] - flat[tri[:, 0]]
    area = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    if area.sum() < 0:
        tri = tri[:, ::-1]
    if len(tri) < k - 2:
        tri = _put_back_dropped_corners(tri, k)
    if tri is None or len(tri) != k - 2 or len(np.unique(tri)) != k:
        return None
    return tri


def _put_back_dropped_corners(tri: np.ndarray, k: int) -> np.ndarray | None:
    """Ear clipping drops corners that lie on a straight line between their neighbours (or
    repeat one); a neighbouring face may still use such a corner, so split the triangle on the
    edge that skips them into a fan through them. None when no such triangle is found."""
    kept = np.flatnonzero(np.isin(np.arange(k), tri))
    rows = [list(t) for t in tri.tolist()]
    for a, b in zip(kept.tolist(), np.roll(kept, -1).tolist(), strict=True):
        dropped = [(a + i) % k for i in range(1, (b - a) % k)]
        if not dropped:
            continue
        for r, t in enumerate(rows):
            if (a, b) in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
                c = t[(t.index(b) + 1) % 3]
                chain = [a, *dropped, b]
                rows[r : r + 1] = [[p, q, c] for p, q in itertools.pairwise(chain)]
                break
        else:
            return None
    return np.array(rows, dtype=np.int64)
