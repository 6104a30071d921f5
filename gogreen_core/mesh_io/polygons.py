"""Polygons to triangles: fan triangulation (corners ``0, k, k+1``) in polygon order, and the
index check that names the polygon at fault."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from gogreen_core.mesh_io.data import MeshFileError

__all__ = ["check_polygon_indices", "fan", "fan_corners", "fan_ragged"]


def fan(polygons: np.ndarray) -> np.ndarray:
    """Fan-triangulate polygons of equal size: (P, k) → (P·(k-2), 3), in polygon order."""
    k = polygons.shape[1]
    if k == 3:
        return polygons
    fans = [polygons[:, [0, i, i + 1]] for i in range(1, k - 1)]
    return np.stack(fans, axis=1).reshape(-1, 3)


def fan_ragged(polygons: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Fan-triangulate polygons of any sizes ≥ 3: triangles (T, 3) and their polygon (T,)."""
    triangles: list[np.ndarray] = []
    owner: list[np.ndarray] = []
    for p, corners in enumerate(polygons):
        tri = fan(corners[None, :])
        triangles.append(tri)
        owner.append(np.full(len(tri), p, dtype=np.int64))
    if not triangles:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(triangles), np.concatenate(owner)


def check_polygon_indices(
    triangles: np.ndarray, owner: np.ndarray, n_vertices: int, where: Callable[[int], str]
) -> None:
    """Raise MeshFileError for the first triangle whose index is not in [0, n_vertices)."""
    outside = (triangles < 0) | (triangles >= n_vertices)
    if outside.any():
        row, col = (int(i[0]) for i in np.nonzero(outside))
        polygon = int(owner[row])
        raise MeshFileError(
            f"{where(polygon)}: face {polygon} references vertex {int(triangles[row, col])} "
            f"but the file has {n_vertices} vertices"
        )


def fan_corners(corners: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """Fan triangles (T, 3) of polygons given as consecutive corners (C,) with sizes (P,):
    corners 0, k, k+1 of each polygon, in polygon order."""
    if sizes.min() == sizes.max():
        return fan(corners.reshape(len(sizes), -1))
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    per_polygon = sizes - 2
    owner_first = np.repeat(first, per_polygon)
    k = np.arange(int(per_polygon.sum())) - np.repeat(
        np.concatenate([[0], np.cumsum(per_polygon)[:-1]]), per_polygon
    )
    return np.stack(
        [corners[owner_first], corners[owner_first + k + 1], corners[owner_first + k + 2]], axis=1
    )
