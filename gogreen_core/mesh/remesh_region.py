"""Where and how finely :mod:`gogreen_core.mesh.remesh` works: the edge lengths a surface has
(one median, or each vertex's: a sizing field), the vertices a motion strained, a region grown
by rings. Plain arrays in and out; each costs a pass over the faces it is given."""

from __future__ import annotations

from typing import cast

import numpy as np

from gogreen_core.mesh._remesh_kernels import strained_faces
from gogreen_core.mesh.topology import mesh_edges

__all__ = [
    "faces_touching",
    "grow_region",
    "local_edge_lengths",
    "median_edge_length",
    "strained_vertices",
]


def median_edge_length(vertices: np.ndarray, faces: np.ndarray) -> float:
    """The median length of the edges of ``faces`` (M, 3) over ``vertices`` (N, 3) (each
    edge once); 0 without faces."""
    if not len(faces):
        return 0.0
    ends = mesh_edges(np.asarray(faces, dtype=np.int64), len(vertices)).ends
    return float(np.median(np.linalg.norm(vertices[ends[:, 1]] - vertices[ends[:, 0]], axis=1)))


def local_edge_lengths(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(N,) float64: the mean length of each vertex's edges in ``faces`` (M, 3) over
    ``vertices`` (N, 3), model units (a sizing field); a vertex of no face (or only of edges
    of length 0) gets the median of the others (1 without any): every length is positive."""
    faces = np.asarray(faces, dtype=np.int64)
    n = len(vertices)
    total, count = np.zeros(n), np.zeros(n)
    for k in range(3):
        a, b = faces[:, k], faces[:, (k + 1) % 3]
        length = np.linalg.norm(vertices[b] - vertices[a], axis=1)
        total += np.bincount(a, length, minlength=n) + np.bincount(b, length, minlength=n)
        count += np.bincount(a, minlength=n) + np.bincount(b, minlength=n)
    lengths = np.divide(total, count, out=np.zeros(n), where=count > 0)
    alone = ~(lengths > 0)
    if alone.any():
        lengths[alone] = float(np.median(lengths[~alone])) if (~alone).any() else 1.0
    return lengths


def faces_touching(faces: np.ndarray, marked: np.ndarray) -> np.ndarray:
    """(M,) bool: the faces (M, 3) with a corner ``marked`` (N,) bool (column by column: a
    tenth of the time of ``np.any(marked[faces], axis=1)`` on 2M faces)."""
    corners = marked[faces]
    return cast(np.ndarray, corners[:, 0] | corners[:, 1] | corners[:, 2])


def grow_region(faces: np.ndarray, region: np.ndarray, rings: int = 1) -> np.ndarray:
    """(N,) bool: ``region`` (N,) bool and every vertex within ``rings`` edges of it."""
    grown = np.asarray(region, dtype=bool).copy()
    for _ in range(rings):
        grown[faces[np.flatnonzero(faces_touching(faces, grown))].ravel()] = True
    return grown


def strained_vertices(
    reference: np.ndarray, vertices: np.ndarray, faces: np.ndarray, tolerance: float
) -> np.ndarray:
    """(N,) bool: the corners of ``faces`` one of whose sides changed, as a vector, by more than
    ``tolerance`` times its length from ``reference`` (N, 3) to ``vertices`` (N, 3): stretched,
    sheared or turned (a rigid shift strains nothing). It costs a pass over ``faces`` alone."""
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    strained = strained_faces(
        np.ascontiguousarray(reference, dtype=np.float64),
        np.ascontiguousarray(vertices, dtype=np.float64),
        faces,
        float(tolerance) ** 2,
    )
    out = np.zeros(len(vertices), dtype=bool)
    out[faces[strained].ravel()] = True
    return out
