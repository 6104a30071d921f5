"""Small mesh computations the viewport needs every frame (plain arrays in, arrays out).

Per-event work stays proportional to the change: a :class:`SurfaceIndex`, built once per mesh,
recomputes after each event only the faces around the moved vertices and the normals of those
vertices and their one-ring (bit for bit what :func:`vertex_normals` gives), refits the boxes
of the face groups they touch, and finds the surface point under the mouse without a locator
built over the whole mesh.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

__all__ = ["FaceAdjacency", "SurfaceIndex", "mesh_volume", "vertex_normals"]

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


#: Faces per leaf of the surface index (one bounding box each).
LEAF_SIZE = 32


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
def _mark(offsets, leaf_ids, seeds, face_mark, leaf_mark):
    """Mark the faces (leaf positions) around the seed vertices and their leaves."""
    for s in prange(seeds.shape[0]):
        v = seeds[s]
        for j in range(offsets[v], offsets[v + 1]):
            f = leaf_ids[j]
            face_mark[f] = True
            leaf_mark[f // LEAF_SIZE] = True


@njit(parallel=True, **_JIT)
def _refresh(vertices, leaf_faces, leaves, face_mark, face_normals, boxes, vertex_mark):
    """For each leaf in ``leaves``: its box, and for its marked faces the normal
    (b - a) × (c - a) with numpy.cross's operations (no fused multiply-add; see _JIT) and
    their corners marked in vertex_mark. Face arrays are in leaf order."""
    n_faces = leaf_faces.shape[0]
    for s in prange(leaves.shape[0]):
        leaf = leaves[s]
        lo0 = lo1 = lo2 = np.inf
        hi0 = hi1 = hi2 = -np.inf
        for f in range(leaf * LEAF_SIZE, min((leaf + 1) * LEAF_SIZE, n_faces)):
            a, b, c = leaf_faces[f, 0], leaf_faces[f, 1], leaf_faces[f, 2]
            for v in (a, b, c):
                x, y, z = vertices[v, 0], vertices[v, 1], vertices[v, 2]
                lo0, lo1, lo2 = min(lo0, x), min(lo1, y), min(lo2, z)
                hi0, hi1, hi2 = max(hi0, x), max(hi1, y), max(hi2, z)
            if not face_mark[f]:
                continue
            u0 = vertices[b, 0] - vertices[a, 0]
            u1 = vertices[b, 1] - vertices[a, 1]
            u2 = vertices[b, 2] - vertices[a, 2]
            w0 = vertices[c, 0] - vertices[a, 0]
            w1 = vertices[c, 1] - vertices[a, 1]
            w2 = vertices[c, 2] - vertices[a, 2]
            face_normals[f, 0] = u1 * w2 - u2 * w1
            face_normals[f, 1] = u2 * w0 - u0 * w2
            face_normals[f, 2] = u0 * w1 - u1 * w0
            vertex_mark[a] = True
            vertex_mark[b] = True
            vertex_mark[c] = True
        boxes[leaf, 0], boxes[leaf, 1], boxes[leaf, 2] = lo0, lo1, lo2
        boxes[leaf, 3], boxes[leaf, 4], boxes[leaf, 5] = hi0, hi1, hi2


@njit(parallel=True, **_JIT)
def _sum_normals(offsets, leaf_ids, face_normals, targets, normals):
    """normals[v] for v in targets: its faces' normals summed in face order (as np.bincount
    does), then divided by their norm (as np.linalg.norm computes it); (0, 0, 1) if zero."""
    for s in prange(targets.shape[0]):
        v = targets[s]
        n0 = 0.0
        n1 = 0.0
        n2 = 0.0
        for j in range(offsets[v], offsets[v + 1]):
            f = leaf_ids[j]
            n0 += face_normals[f, 0]
            n1 += face_normals[f, 1]
            n2 += face_normals[f, 2]
        norm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        if norm == 0.0:
            normals[v, 0] = 0.0
            normals[v, 1] = 0.0
            normals[v, 2] = 1.0
        else:
            normals[v, 0] = n0 / norm
            normals[v, 1] = n1 / norm
            normals[v, 2] = n2 / norm


@njit(**_JIT)
def _leaf_hits(boxes, origin, inv_dir, near):
    """near[c] = entry distance of the ray into box c, or inf if it misses. Serial: a
    parallel launch costs more than this millisecond of work when the cores are busy."""
    for c in range(boxes.shape[0]):
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
def _closest_hit(vertices, leaf_faces, order, candidates, near, origin, direction):
    """(face, t) of the closest ray-triangle hit among the candidate chunks, sorted by entry
    distance (Möller-Trumbore, both sides); (-1, inf) if none."""
    best_t = np.inf
    best_f = -1
    n_faces = order.shape[0]
    ox, oy, oz = origin[0], origin[1], origin[2]
    dx, dy, dz = direction[0], direction[1], direction[2]
    for s in range(candidates.shape[0]):
        c = candidates[s]
        if near[c] > best_t:
            break
        for j in range(c * LEAF_SIZE, min((c + 1) * LEAF_SIZE, n_faces)):
            a, b, cc = leaf_faces[j, 0], leaf_faces[j, 1], leaf_faces[j, 2]
            ax, ay, az = vertices[a, 0], vertices[a, 1], vertices[a, 2]
            e1x, e1y, e1z = vertices[b, 0] - ax, vertices[b, 1] - ay, vertices[b, 2] - az
            e2x, e2y, e2z = vertices[cc, 0] - ax, vertices[cc, 1] - ay, vertices[cc, 2] - az
            px = dy * e2z - dz * e2y
            py = dz * e2x - dx * e2z
            pz = dx * e2y - dy * e2x
            det = e1x * px + e1y * py + e1z * pz
            if det == 0.0:
                continue
            inv = 1.0 / det
            sx, sy, sz = ox - ax, oy - ay, oz - az
            u = (sx * px + sy * py + sz * pz) * inv
            if u < 0.0 or u > 1.0:
                continue
            qx = sy * e1z - sz * e1y
            qy = sz * e1x - sx * e1z
            qz = sx * e1y - sy * e1x
            v = (dx * qx + dy * qy + dz * qz) * inv
            if v < 0.0 or u + v > 1.0:
                continue
            t = (e2x * qx + e2y * qy + e2z * qz) * inv
            if 0.0 <= t < best_t:
                best_t = t
                best_f = order[j]
    return best_f, best_t


class SurfaceIndex:
    """What the viewport needs per event, at a cost proportional to the change.

    Built once per mesh: the face adjacency, the faces grouped in Z-order of their centroids
    into leaves of :data:`LEAF_SIZE` faces with a bounding box each, every face normal and the
    vertex normals. After an event, :meth:`update` recomputes the faces around the moved
    vertices, the normals of those vertices and their one-ring (bit for bit what
    :func:`vertex_normals` gives on the whole mesh) and the boxes of the leaves they touch.
    :meth:`pick` tests a ray against every box, then the faces of the boxes hit, nearest box
    first, until no box can hold a nearer hit. The leaves depend only on the mesh at build
    time; they stay correct however far vertices move (only less tight).

    Parameters
    ----------
    vertices : (N, 3) float64
    faces : (M, 3) int64, indices into ``vertices``

    Attributes
    ----------
    normals : (N, 3) float64
        The current unit vertex normals (updated in place by :meth:`update`).
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray):
        vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        if vertices.ndim != 2 or vertices.shape[1] != 3:
            raise ValueError(f"vertices must have shape (N, 3) (got {vertices.shape})")
        faces = np.ascontiguousarray(faces, dtype=np.int64)
        adjacency = FaceAdjacency(faces, len(vertices))
        self._n_vertices = len(vertices)
        centroids = vertices[faces].mean(axis=1)
        self._order = _morton_order(centroids) if len(faces) else np.zeros(0, np.int64)
        rank = np.empty_like(self._order)
        rank[self._order] = np.arange(len(self._order))
        self._leaf_faces = np.ascontiguousarray(faces[self._order])
        self._offsets = adjacency.offsets
        # each vertex's faces in face order (the summation order), as leaf positions
        self._leaf_ids = rank[adjacency.face_ids]
        a, b, c = (vertices[self._leaf_faces[:, k]] for k in range(3))
        self._face_normals = np.cross(b - a, c - a)
        self.normals = vertex_normals(vertices, faces)
        n_leaves = (len(faces) + LEAF_SIZE - 1) // LEAF_SIZE
        self._boxes = np.empty((n_leaves, 6))
        face_mark = np.zeros(len(faces), dtype=np.bool_)  # normals are already right
        vertex_mark = np.zeros(len(vertices), dtype=np.bool_)
        _refresh(
            vertices,
            self._leaf_faces,
            np.arange(n_leaves),
            face_mark,
            self._face_normals,
            self._boxes,
            vertex_mark,
        )

    def update(self, vertices: np.ndarray, changed: np.ndarray) -> np.ndarray:
        """The vertices ``changed`` (indices) moved to ``vertices`` (N, 3): update
        :attr:`normals` and the boxes; returns the sorted indices of the normals recomputed
        (the moved vertices and their one-ring), the rows the viewport must upload."""
        vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        if vertices.shape != (self._n_vertices, 3):
            raise ValueError(
                f"vertices must have shape ({self._n_vertices}, 3) (got {vertices.shape})"
            )
        seeds = np.asarray(changed, dtype=np.int64).ravel()
        if seeds.size and (seeds.min() < 0 or seeds.max() >= self._n_vertices):
            raise ValueError(f"changed must index vertices 0 to {self._n_vertices - 1}")
        face_mark = np.zeros(len(self._leaf_faces), dtype=np.bool_)
        leaf_mark = np.zeros(len(self._boxes), dtype=np.bool_)
        _mark(self._offsets, self._leaf_ids, seeds, face_mark, leaf_mark)
        vertex_mark = np.zeros(self._n_vertices, dtype=np.bool_)
        vertex_mark[seeds] = True  # a vertex in no face still gets its (0, 0, 1)
        _refresh(
            vertices,
            self._leaf_faces,
            np.flatnonzero(leaf_mark),
            face_mark,
            self._face_normals,
            self._boxes,
            vertex_mark,
        )
        ring = np.flatnonzero(vertex_mark)
        _sum_normals(self._offsets, self._leaf_ids, self._face_normals, ring, self.normals)
        return ring

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
        _leaf_hits(self._boxes, o, inv, near)
        hit = np.flatnonzero(near < np.inf)
        candidates = hit[np.argsort(near[hit], kind="stable")]
        face, t = _closest_hit(
            np.ascontiguousarray(vertices), self._leaf_faces, self._order, candidates, near, o, d
        )
        if face < 0:
            return None
        return int(face), o + t * d
