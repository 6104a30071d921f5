"""Per-vertex curvature for the viewport's cavity tint (darker in hollows, lighter on ridges).

κ_i = 2 n_i · Σ_j (x_j − x_i) / Σ_j |x_j − x_i|² over the one-ring j (n_i the unit vertex
normal): the edges' normal curvatures 2 n·d / |d|² (exact for a sphere's chords) weighted by
their squared lengths. So κ = −1/R on a sphere whatever the sampling: a dent tints the same on a
coarse and on a subdivided mesh. An event updates the moved vertices and their one-ring only.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from gogreen_core.mesh.topology import (
    VertexNeighbours,
    concatenated_ranges,
    mesh_edges,
    vertex_neighbours,
)

__all__ = ["CavityField", "curvature"]


def _gather(
    neighbours: VertexNeighbours, rows: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The one-rings of ``rows`` (n,) one after another: their vertices (K,), each row's count
    (n,) and where each row's ring starts (n,)."""
    starts = neighbours.offsets[rows]
    counts = neighbours.offsets[rows + 1] - starts
    ring = neighbours.neighbours[concatenated_ranges(starts, counts)]
    return ring, counts, np.cumsum(counts) - counts


def curvature(
    vertices: np.ndarray, normals: np.ndarray, neighbours: VertexNeighbours, rows: np.ndarray
) -> np.ndarray:
    """κ (n,) (1 / model units) at ``rows`` (n,) of ``vertices`` (N, 3), whose unit normals
    are ``normals`` (n, 3) (see the module docstring); 0 at a vertex without neighbours."""
    rows = np.asarray(rows, dtype=np.int64)
    out = np.zeros(len(rows))
    ring, counts, begins = _gather(neighbours, rows)
    if not len(ring):
        return out
    edges = vertices[ring] - np.repeat(vertices[rows], counts, axis=0)  # d_ij (K, 3)
    # sums per row (reduceat gives an empty row the next row's first term: masked out below);
    # n_i · Σ_j d_ij: one dot product a row
    at = np.minimum(begins, len(ring) - 1)
    sums = np.add.reduceat(edges, at, axis=0)
    length = np.add.reduceat(np.einsum("ij,ij->i", edges, edges), at)
    bend = np.einsum("ij,ij->i", sums, np.asarray(normals, dtype=np.float64))
    np.divide(2.0 * bend, length, out=out, where=(counts > 0) & (length > 0))
    return out


class CavityField:
    """The curvature ``values`` (N,) float64 of the vertices of a mesh of triangles ``faces``
    (M, 3), kept up to date event by event by :meth:`update` (zeros before)."""

    def __init__(self, faces: np.ndarray, n_vertices: int) -> None:
        faces = np.asarray(faces, dtype=np.int64)
        self.neighbours = vertex_neighbours(mesh_edges(faces, n_vertices), n_vertices)
        self.n_vertices = int(n_vertices)
        self.values = np.zeros(self.n_vertices)

    def update(
        self,
        vertices: np.ndarray,
        normals: Callable[[np.ndarray], np.ndarray],
        moved: np.ndarray | None = None,
    ) -> np.ndarray:
        """Recompute κ where ``moved`` (indices; None: every vertex) changed it, from
        ``vertices`` (N, 3); ``normals(rows)`` gives the unit normals (n, 3) of vertices
        ``rows`` (n,). Returns the rows recomputed, sorted: the moved vertices and their
        one-ring (a vertex's κ reads its normal, which reads its one-ring, and its neighbours)."""
        if moved is None:
            rows = np.arange(self.n_vertices)
        else:
            moved = np.asarray(moved, dtype=np.int64).ravel()
            mark = np.zeros(self.n_vertices, dtype=bool)
            mark[moved] = True
            mark[_gather(self.neighbours, moved)[0]] = True
            rows = np.flatnonzero(mark)
        self.values[rows] = curvature(vertices, normals(rows), self.neighbours, rows)
        return rows
