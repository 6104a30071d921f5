"""Connectivity of a triangle mesh: its edges, each vertex's neighbours and faces (plain arrays),
built once per face array. Their orders are fixed by the face array alone, so everything
computed from them is reproducible bit for bit.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

__all__ = [
    "FaceAdjacency",
    "MeshEdges",
    "VertexNeighbours",
    "checked_faces",
    "concatenated_ranges",
    "mesh_edges",
    "vertex_neighbours",
]

#: :attr:`VertexNeighbours.mode` values: relax towards all neighbours, along the boundary
#: (its two boundary neighbours), or not at all (a vertex where the surface is not a manifold).
INTERIOR, BOUNDARY, FIXED = 0, 1, 2


def checked_faces(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """``faces`` as a contiguous (M, 3) int64 array; ValueError unless it indexes vertices."""
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise ValueError(f"faces must have shape (M, 3) (got {faces.shape})")
    if faces.size and (faces.min() < 0 or faces.max() >= n_vertices):
        raise ValueError(f"faces must index vertices 0 to {n_vertices - 1}")
    return faces


def concatenated_ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The ranges ``starts[i] : starts[i] + counts[i]`` (int64), concatenated."""
    starts, counts = np.asarray(starts, dtype=np.int64), np.asarray(counts, dtype=np.int64)
    return np.repeat(starts - (np.cumsum(counts) - counts), counts) + np.arange(int(counts.sum()))


@dataclass(frozen=True)
class MeshEdges:
    """The undirected edges of a triangle mesh: ``ends`` (E, 2) int64, the two vertices of each
    (smaller first, edges sorted by them); ``face_edges`` (M, 3) int64, the edge of each face's
    side k (corner k to k + 1); ``face_count`` (E,) int64, the faces sharing each edge."""

    ends: np.ndarray
    face_edges: np.ndarray
    face_count: np.ndarray

    def __len__(self) -> int:
        return len(self.ends)


def mesh_edges(faces: np.ndarray, n_vertices: int) -> MeshEdges:
    """The edges of ``faces`` (M, 3) int64 on ``n_vertices`` vertices (see :class:`MeshEdges`)."""
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    nxt = np.roll(faces, -1, axis=1)
    low = np.minimum(faces, nxt).ravel()
    high = np.maximum(faces, nxt).ravel()
    key = low * np.int64(max(n_vertices, 1)) + high
    order = np.argsort(key, kind="stable")
    ordered = key[order]
    first = np.empty(len(ordered), dtype=bool)
    first[:1] = True
    np.not_equal(ordered[1:], ordered[:-1], out=first[1:])
    edge = np.cumsum(first) - 1
    face_edges = np.empty(len(key), dtype=np.int64)
    face_edges[order] = edge
    starts = np.flatnonzero(first)
    ends = np.stack([low[order[starts]], high[order[starts]]], axis=1)
    face_count = np.diff(np.append(starts, len(ordered)))
    return MeshEdges(ends, face_edges.reshape(-1, 3), face_count)


@dataclass(frozen=True)
class VertexNeighbours:
    """Each vertex's neighbours, in compressed rows: those of vertex v are
    ``neighbours[offsets[v]:offsets[v + 1]]`` (increasing; ``offsets`` (N + 1,), ``neighbours``
    (2E,) int64), ``on_boundary`` (2E,) bool when their edge has one face. ``mode`` (N,) int8:
    how a relaxation moves the vertex, :data:`INTERIOR` (towards its neighbours' mean),
    :data:`BOUNDARY` (towards its two boundary neighbours', so an open rim does not shrink) or
    :data:`FIXED` (on a non-manifold edge, other than two boundary edges, or in no face).
    """

    offsets: np.ndarray
    neighbours: np.ndarray
    on_boundary: np.ndarray
    mode: np.ndarray


def vertex_neighbours(edges: MeshEdges, n_vertices: int) -> VertexNeighbours:
    """The neighbours of every vertex (see :class:`VertexNeighbours`) from ``edges``."""
    source, target = edges.ends.T.ravel(), edges.ends[:, ::-1].T.ravel()  # each edge both ways
    boundary = np.concatenate([edges.face_count == 1] * 2)
    order = np.lexsort((target, source))
    counts = np.bincount(source, minlength=n_vertices)
    offsets = np.zeros(n_vertices + 1, dtype=np.int64)
    np.cumsum(counts, out=offsets[1:])
    on_boundary = boundary[order]
    boundary_count = np.bincount(source[order][on_boundary], minlength=n_vertices)
    odd = np.zeros(n_vertices, dtype=bool)
    odd[edges.ends[edges.face_count > 2].ravel()] = True
    mode = np.full(n_vertices, INTERIOR, dtype=np.int8)
    mode[boundary_count == 2] = BOUNDARY
    mode[(boundary_count != 0) & (boundary_count != 2)] = FIXED
    mode[odd | (counts == 0)] = FIXED
    return VertexNeighbours(offsets, target[order], on_boundary, mode)


class FaceAdjacency:
    """The faces around each vertex (connectivity only: valid while the vertices move): those
    of vertex v are ``face_ids[offsets[v]:offsets[v + 1]]`` (``offsets`` (N + 1,), ``face_ids``
    (3M,) int64), in increasing face order, the order in which
    :func:`~gogreen_core.mesh.geometry.vertex_normals` sums them."""

    def __init__(self, faces: np.ndarray, n_vertices: int):
        flat = checked_faces(faces, n_vertices).ravel()
        order = np.argsort(flat, kind="stable")
        self.face_ids = order // 3
        counts = np.bincount(flat, minlength=n_vertices)
        self.offsets = np.zeros(n_vertices + 1, dtype=np.int64)
        np.cumsum(counts, out=self.offsets[1:])
        self.n_vertices = int(n_vertices)

    @classmethod
    def of(cls, faces: np.ndarray, n_vertices: int) -> FaceAdjacency:
        """The adjacency of the face array ``faces`` (that array object), built once and shared
        (a 1.3M-face mesh takes 50-300 ms), held by a weak reference so a replaced mesh is
        freed."""
        if _LAST_ADJACENCY:
            held, adjacency = _LAST_ADJACENCY[0]
            if held() is faces and adjacency.n_vertices == n_vertices:
                return adjacency
        adjacency = cls(faces, n_vertices)
        _LAST_ADJACENCY[:] = [(weakref.ref(faces), adjacency)]
        return adjacency

    def around(self, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(owner (K,), face numbers (K,)): the faces around each vertex of ``rows`` (k,), in
        this adjacency's order; ``owner`` is the vertex's position in ``rows``."""
        start = self.offsets[rows]
        count = self.offsets[rows + 1] - start
        owner = np.repeat(np.arange(len(rows)), count)
        return owner, self.face_ids[concatenated_ranges(start, count)]


#: The last :meth:`FaceAdjacency.of`: (a weak reference to its face array, the adjacency).
_LAST_ADJACENCY: list[tuple[weakref.ref[np.ndarray], FaceAdjacency]] = []
