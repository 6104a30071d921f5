"""Small mesh computations the viewport needs every frame (plain arrays in, arrays out).

Per-event work stays proportional to the change: :class:`FaceAdjacency` (built once per mesh)
lets :func:`update_vertex_normals` recompute only the normals of the moved vertices and their
one-ring, bit for bit what :func:`vertex_normals` gives for them, and :class:`PickIndex`
(built once per mesh, refitted per event for the moved vertices) finds the surface point under
the mouse without a locator over the whole mesh.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = [
    "FaceAdjacency",
    "PickIndex",
    "mesh_volume",
    "update_vertex_normals",
    "vertex_normals",
]

# No fastmath here: the incremental normals must round exactly as numpy's full computation.
_JIT = {"cache": True, "boundscheck": False}


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted unit vertex normals (N, 3) of a triangle mesh (faces (M, 3)).

    A vertex in no face (or only in degenerate ones) gets (0, 0, 1)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    face_normals = np.cross(b - a, c - a)  # length = 2 · area: area weighting for free
    n = len(vertices)
    out = np.empty((n, 3))
    flat = faces.ravel()
    for axis in range(3):
        out[:, axis] = np.bincount(flat, np.repeat(face_normals[:, axis], 3), minlength=n)
    norm = np.linalg.norm(out, axis=1)
    empty = norm == 0
    out[empty] = (0.0, 0.0, 1.0)
    norm[empty] = 1.0
    return out / norm[:, None]


def mesh_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Signed volume enclosed by a closed, consistently oriented triangle mesh."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


class FaceAdjacency:
    """The faces around each vertex, built once per mesh (connectivity only, so it stays valid
    while the vertices move).

    Attributes
    ----------
    offsets : (N + 1,) int64
        The faces of vertex v are ``face_ids[offsets[v]:offsets[v + 1]]``.
    face_ids : (3M,) int64
        In increasing face order (a face listing v twice appears twice), the order in which
        :func:`vertex_normals` sums them, so updates round identically.
    """

    def __init__(self, faces: np.ndarray, n_vertices: int):
        faces = np.ascontiguousarray(faces, dtype=np.int64)
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise ValueError(f"faces must have shape (M, 3) (got {faces.shape})")
        flat = faces.ravel()
        if flat.size and (flat.min() < 0 or flat.max() >= n_vertices):
            raise ValueError(f"faces must index vertices 0 to {n_vertices - 1}")
        order = np.argsort(flat, kind="stable")
        self.face_ids = order // 3
        counts = np.bincount(flat, minlength=n_vertices)
        self.offsets = np.zeros(n_vertices + 1, dtype=np.int64)
        np.cumsum(counts, out=self.offsets[1:])
        self.n_vertices = int(n_vertices)

    def one_ring(self, faces: np.ndarray, vertices: np.ndarray) -> np.ndarray:
        """Sorted indices of ``vertices`` and every vertex sharing a face with one of them."""
        mark = np.zeros(self.n_vertices, dtype=np.bool_)
        _mark_ring(self.offsets, self.face_ids, faces, np.asarray(vertices, np.int64), mark)
        return np.flatnonzero(mark)


@njit(parallel=True, **_JIT)
def _mark_ring(offsets, face_ids, faces, seeds, mark):
    for s in prange(seeds.shape[0]):
        v = seeds[s]
        mark[v] = True
        for j in range(offsets[v], offsets[v + 1]):
            f = face_ids[j]
            for k in range(3):
                mark[faces[f, k]] = True


@njit(parallel=True, **_JIT)
def _normals_of(vertices, faces, offsets, face_ids, targets, normals):
    """normals[v] for v in targets, with the operations and order of ``vertex_normals``."""
    for s in prange(targets.shape[0]):
        v = targets[s]
        n0 = 0.0
        n1 = 0.0
        n2 = 0.0
        for j in range(offsets[v], offsets[v + 1]):
            f = face_ids[j]
            a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
            u0 = vertices[b, 0] - vertices[a, 0]
            u1 = vertices[b, 1] - vertices[a, 1]
            u2 = vertices[b, 2] - vertices[a, 2]
            w0 = vertices[c, 0] - vertices[a, 0]
            w1 = vertices[c, 1] - vertices[a, 1]
            w2 = vertices[c, 2] - vertices[a, 2]
            n0 += u1 * w2 - u2 * w1
            n1 += u2 * w0 - u0 * w2
            n2 += u0 * w1 - u1 * w0
        norm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        if norm == 0.0:
            normals[v, 0] = 0.0
            normals[v, 1] = 0.0
            normals[v, 2] = 1.0
        else:
            normals[v, 0] = n0 / norm
            normals[v, 1] = n1 / norm
            normals[v, 2] = n2 / norm


def update_vertex_normals(
    vertices: np.ndarray,
    faces: np.ndarray,
    adjacency: FaceAdjacency,
    normals: np.ndarray,
    changed: np.ndarray,
) -> np.ndarray:
    """Recompute in place the rows of ``normals`` (N, 3) whose value the move of the vertices
    ``changed`` (indices) can alter: those vertices and their one-ring. Returns the updated
    indices (sorted), whose rows equal :func:`vertex_normals` bit for bit.

    ``vertices`` (N, 3) float64 and ``faces`` (M, 3) int64 C-contiguous, as the Sculptor keeps
    them; ``adjacency`` built once for ``faces``.
    """
    ring = adjacency.one_ring(faces, changed)
    _normals_of(vertices, faces, adjacency.offsets, adjacency.face_ids, ring, normals)
    return ring


# -- picking -----------------------------------------------------------------------------------

#: Faces per leaf of the pick index.
PICK_CHUNK = 32


def _morton_order(points: np.ndarray) -> np.ndarray:
    """Order of ``points`` (n, 3) along a Z-order curve (10 bits per axis)."""
    low, high = points.min(axis=0), points.max(axis=0)
    cells = ((points - low) / np.maximum(high - low, 1e-300) * 1023).astype(np.uint64)
    code = np.zeros(len(points), dtype=np.uint64)
    for bit in range(10):
        for axis in range(3):
            code |= ((cells[:, axis] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit + axis)
    return np.argsort(code, kind="stable")


@njit(parallel=True, **_JIT)
def _refit(vertices, faces, order, chunks, boxes):
    """boxes[c] = (min xyz, max xyz) of the faces order[c·CHUNK:(c+1)·CHUNK], for c in chunks."""
    n_faces = order.shape[0]
    for s in prange(chunks.shape[0]):
        c = chunks[s]
        lo0 = lo1 = lo2 = np.inf
        hi0 = hi1 = hi2 = -np.inf
        for j in range(c * PICK_CHUNK, min((c + 1) * PICK_CHUNK, n_faces)):
            f = order[j]
            for k in range(3):
                v = faces[f, k]
                x, y, z = vertices[v, 0], vertices[v, 1], vertices[v, 2]
                lo0, lo1, lo2 = min(lo0, x), min(lo1, y), min(lo2, z)
                hi0, hi1, hi2 = max(hi0, x), max(hi1, y), max(hi2, z)
        boxes[c, 0], boxes[c, 1], boxes[c, 2] = lo0, lo1, lo2
        boxes[c, 3], boxes[c, 4], boxes[c, 5] = hi0, hi1, hi2


@njit(parallel=True, **_JIT)
def _mark_chunks(offsets, face_ids, rank, seeds, mark):
    for s in prange(seeds.shape[0]):
        v = seeds[s]
        for j in range(offsets[v], offsets[v + 1]):
            mark[rank[face_ids[j]] // PICK_CHUNK] = True


@njit(parallel=True, **_JIT)
def _chunk_hits(boxes, origin, inv_dir, near):
    """near[c] = entry distance of the ray into box c, or inf if it misses."""
    for c in prange(boxes.shape[0]):
        t0 = 0.0
        t1 = np.inf
        for k in range(3):
            a = (boxes[c, k] - origin[k]) * inv_dir[k]
            b = (boxes[c, 3 + k] - origin[k]) * inv_dir[k]
            if a > b:
                a, b = b, a
            if not (a <= b):  # NaN from 0·inf: the ray lies in the slab plane
                a, b = -np.inf, np.inf
            t0 = max(t0, a)
            t1 = min(t1, b)
        near[c] = t0 if t0 <= t1 else np.inf


@njit(**_JIT)
def _closest_hit(vertices, faces, order, candidates, near, origin, direction):
    """(face, t) of the closest ray-triangle hit among the candidate chunks, sorted by entry
    distance (Möller-Trumbore, both sides); (-1, inf) if none."""
    best_t = np.inf
    best_f = -1
    n_faces = order.shape[0]
    for s in range(candidates.shape[0]):
        c = candidates[s]
        if near[c] > best_t:
            break
        for j in range(c * PICK_CHUNK, min((c + 1) * PICK_CHUNK, n_faces)):
            f = order[j]
            a, b, cc = faces[f, 0], faces[f, 1], faces[f, 2]
            e1 = vertices[b] - vertices[a]
            e2 = vertices[cc] - vertices[a]
            p = np.cross(direction, e2)
            det = e1 @ p
            if det == 0.0:
                continue
            inv = 1.0 / det
            s_vec = origin - vertices[a]
            u = (s_vec @ p) * inv
            if u < 0.0 or u > 1.0:
                continue
            q = np.cross(s_vec, e1)
            v = (direction @ q) * inv
            if v < 0.0 or u + v > 1.0:
                continue
            t = (e2 @ q) * inv
            if 0.0 <= t < best_t:
                best_t = t
                best_f = f
    return best_f, best_t


class PickIndex:
    """Finds the surface point under the mouse: a two-level box hierarchy over the faces,
    grouped once per mesh in Z-order into leaves of :data:`PICK_CHUNK` faces.

    The grouping depends only on the mesh at build time; after an event, :meth:`update`
    refits the boxes of the leaves holding a face of a moved vertex (proportional to the
    change). Leaves stay correct however far vertices move (only less tight).

    Parameters
    ----------
    vertices : (N, 3) float64
    faces : (M, 3) int64
    adjacency : FaceAdjacency, optional
        Of ``faces``; built here when omitted.
    """

    def __init__(
        self, vertices: np.ndarray, faces: np.ndarray, adjacency: FaceAdjacency | None = None
    ):
        self._faces = np.ascontiguousarray(faces, dtype=np.int64)
        vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        self._adjacency = adjacency or FaceAdjacency(self._faces, len(vertices))
        centroids = vertices[self._faces].mean(axis=1)
        self._order = _morton_order(centroids) if len(centroids) else np.zeros(0, np.int64)
        self._rank = np.empty_like(self._order)
        self._rank[self._order] = np.arange(len(self._order))
        n_chunks = (len(self._order) + PICK_CHUNK - 1) // PICK_CHUNK
        self._boxes = np.empty((n_chunks, 6))
        _refit(vertices, self._faces, self._order, np.arange(n_chunks), self._boxes)

    def update(self, vertices: np.ndarray, changed: np.ndarray) -> None:
        """Refit after the vertices ``changed`` (indices) moved; ``vertices`` (N, 3) the new
        positions."""
        mark = np.zeros(len(self._boxes), dtype=np.bool_)
        adjacency = self._adjacency
        seeds = np.asarray(changed, dtype=np.int64)
        _mark_chunks(adjacency.offsets, adjacency.face_ids, self._rank, seeds, mark)
        chunks = np.flatnonzero(mark)
        _refit(np.ascontiguousarray(vertices), self._faces, self._order, chunks, self._boxes)

    def pick(
        self, vertices: np.ndarray, origin: np.ndarray, direction: np.ndarray
    ) -> tuple[int, np.ndarray] | None:
        """The first face hit by the ray origin + t·direction (t ≥ 0) and the hit point (3,),
        or None. ``vertices`` (N, 3): the current positions (those of the last update)."""
        o = np.asarray(origin, dtype=np.float64)
        d = np.asarray(direction, dtype=np.float64)
        if o.shape != (3,) or d.shape != (3,) or not np.all(np.isfinite(o) & np.isfinite(d)):
            raise ValueError("pick origin and direction must be 3 finite numbers each")
        if not np.any(d):
            raise ValueError("pick direction must be nonzero")
        with np.errstate(divide="ignore"):
            inv = 1.0 / d
        near = np.empty(len(self._boxes))
        _chunk_hits(self._boxes, o, inv, near)
        hit = np.flatnonzero(near < np.inf)
        candidates = hit[np.argsort(near[hit], kind="stable")]
        face, t = _closest_hit(
            np.ascontiguousarray(vertices), self._faces, self._order, candidates, near, o, d
        )
        if face < 0:
            return None
        return int(face), o + t * d
