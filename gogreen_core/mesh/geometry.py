"""Small mesh computations the viewport needs every frame (plain arrays in, arrays out), and
:class:`SurfaceIndex`: normals and picking at a per-event cost proportional to the change."""

from __future__ import annotations

import math
from collections.abc import Callable
from contextlib import AbstractContextManager

import numba
import numpy as np
from numba import njit, prange

from gogreen_core import _compiled
from gogreen_core._jit_options import NogilJitOptions
from gogreen_core.mesh import _geometry_numpy
from gogreen_core.mesh._geometry_numpy import _BLOCK_SHIFT, _MORTON_BITS, LEAF_SIZE
from gogreen_core.mesh.topology import checked_faces
from gogreen_core.threads import threads_at_most

__all__ = ["SurfaceIndex", "mesh_volume", "vertex_normals"]

# No fastmath: an incremental update gives the bits of a new build (sums in face order); nogil: a
# background build.
_JIT: NogilJitOptions = {"cache": True, "boundscheck": False, "nogil": True}


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted unit vertex normals (N, 3) of a triangle mesh (faces (M, 3)); (0, 0, 1)
    for a vertex in no face (or only in degenerate ones)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    face_normals = np.cross(b - a, c - a)  # length = 2 · area: area weighting for free
    corner_normals = np.repeat(face_normals, 3, axis=0)  # faces in order, corners in order
    n, flat = len(vertices), faces.ravel()
    out = np.stack([np.bincount(flat, w, minlength=n) for w in corner_normals.T], axis=1)
    norm: np.ndarray[tuple[int], np.dtype[np.float64]] = np.linalg.norm(out, axis=1)
    out[norm == 0] = (0.0, 0.0, 1.0)
    norm[norm == 0] = 1.0
    return out / norm[:, None]


def mesh_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Signed volume enclosed by a closed, consistently oriented triangle mesh."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


#: Work items per chunk of the per-event kernels, dealt to the threads in turn: all share a region.
_VERTEX_CHUNK = 4096
_LEAF_CHUNK = 128
#: Blocks (of 2**_BLOCK_SHIFT vertices, see ``_geometry_numpy``) per chunk.
_BLOCK_CHUNK = _VERTEX_CHUNK >> _BLOCK_SHIFT


@njit(parallel=True, **_JIT)
def _morton_keys(points: np.ndarray, groups: np.ndarray, low: np.ndarray, scale: np.ndarray,
                 keys: np.ndarray) -> None:  # fmt: skip
    """keys[i] = (Z-order code of points[groups[i]]'s mean) << 31 | i (sorted: ties by index)."""
    k = groups.shape[1]
    for i in prange(groups.shape[0]):
        code = 0
        for axis in range(3):
            s = 0.0
            for j in range(k):
                s += points[groups[i, j], axis]
            cell = int((s / k - low[axis]) * scale[axis])
            cell = min(max(cell, 0), (1 << _MORTON_BITS) - 1)
            for bit in range(_MORTON_BITS):
                code |= ((cell >> bit) & 1) << (3 * bit + axis)
        keys[i] = (code << 31) | np.int64(i)


@njit(**_JIT)
def _connect(
    faces: np.ndarray, rank: np.ndarray, face_order: np.ndarray, face_rank: np.ndarray,
    index_faces: np.ndarray, offsets: np.ndarray, leaf_ids: np.ndarray, block_offsets: np.ndarray,
    block_leaves: np.ndarray) -> int:  # fmt: skip
    """Fill index_faces (index order and numbering); leaf_ids by offsets: each vertex's faces
    in mesh face order; block_leaves by block_offsets: each block's leaves (returns their count)."""
    n_faces = faces.shape[0]
    for p in range(n_faces):
        f = face_order[p]
        for k in range(3):
            index_faces[p, k] = rank[faces[f, k]]
    offsets[:] = 0
    for f in range(n_faces):
        for k in range(3):
            offsets[rank[faces[f, k]] + 1] += 1
    for i in range(1, offsets.shape[0]):
        offsets[i] += offsets[i - 1]
    cursor = offsets[:-1].copy()
    for f in range(n_faces):
        for k in range(3):
            i = rank[faces[f, k]]
            leaf_ids[cursor[i]] = face_rank[f]
            cursor[i] += 1
    n = offsets.shape[0] - 1
    seen_by = np.full((n_faces + LEAF_SIZE - 1) // LEAF_SIZE, -1, dtype=np.int32)
    used = 0
    block_offsets[0] = 0
    for b in range(block_offsets.shape[0] - 1):
        for j in range(offsets[b << _BLOCK_SHIFT], offsets[min((b + 1) << _BLOCK_SHIFT, n)]):
            leaf = leaf_ids[j] // LEAF_SIZE
            if seen_by[leaf] != b:
                seen_by[leaf] = b
                block_leaves[used] = leaf
                used += 1
        block_offsets[b + 1] = used
    return used


@njit(parallel=True, **_JIT)
def _update(
    vertices: np.ndarray, seeds: np.ndarray, rank: np.ndarray, offsets: np.ndarray,
    leaf_ids: np.ndarray, block_offsets: np.ndarray, block_leaves: np.ndarray, faces: np.ndarray,
    positions: np.ndarray, moved: np.ndarray, ring: np.ndarray, block_moved: np.ndarray,
    block_ring: np.ndarray, leaf_mark: np.ndarray, leaf_dirty: np.ndarray, face_normals: np.ndarray,
    normals: np.ndarray, n_threads: int) -> np.int64:  # fmt: skip
    """One :meth:`SurfaceIndex.update`: copy the seeds, redo their blocks' leaves' face normals
    (float32) and their corners' normals (summed in face order); block flags spare scans."""
    n = positions.shape[0]
    n_seeds = seeds.shape[0]
    for t in prange(n_threads):
        for s in range(t * _VERTEX_CHUNK, n_seeds, n_threads * _VERTEX_CHUNK):
            for j in range(s, min(s + _VERTEX_CHUNK, n_seeds)):
                v = seeds[j]
                i = rank[v]
                positions[i, 0] = vertices[v, 0]
                positions[i, 1] = vertices[v, 1]
                positions[i, 2] = vertices[v, 2]
                moved[i] = True
                block_moved[i >> _BLOCK_SHIFT] = True
    n_blocks = block_moved.shape[0]
    for t in prange(n_threads):
        for s in range(t * _BLOCK_CHUNK, n_blocks, n_threads * _BLOCK_CHUNK):
            for b in range(s, min(s + _BLOCK_CHUNK, n_blocks)):
                if block_moved[b]:
                    block_moved[b] = False
                    block_ring[b] = True
                    for j in range(block_offsets[b], block_offsets[b + 1]):
                        leaf_mark[block_leaves[j]] = True
    n_leaves = leaf_mark.shape[0]
    n_faces = faces.shape[0]
    for t in prange(n_threads):
        for s in range(t * _LEAF_CHUNK, n_leaves, n_threads * _LEAF_CHUNK):
            for lf in range(s, min(s + _LEAF_CHUNK, n_leaves)):
                if not leaf_mark[lf]:
                    continue
                leaf_mark[lf] = False
                leaf_dirty[lf] = True
                for f in range(lf * LEAF_SIZE, min((lf + 1) * LEAF_SIZE, n_faces)):
                    a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
                    if not moved[a] and not moved[b] and not moved[c]:
                        continue
                    u0 = positions[b, 0] - positions[a, 0]
                    u1 = positions[b, 1] - positions[a, 1]
                    u2 = positions[b, 2] - positions[a, 2]
                    w0 = positions[c, 0] - positions[a, 0]
                    w1 = positions[c, 1] - positions[a, 1]
                    w2 = positions[c, 2] - positions[a, 2]
                    face_normals[f, 0] = u1 * w2 - u2 * w1
                    face_normals[f, 1] = u2 * w0 - u0 * w2
                    face_normals[f, 2] = u0 * w1 - u1 * w0
                    ring[a] = True
                    ring[b] = True
                    ring[c] = True
                    block_ring[a >> _BLOCK_SHIFT] = True
                    block_ring[b >> _BLOCK_SHIFT] = True
                    block_ring[c >> _BLOCK_SHIFT] = True
    counts = np.zeros(16 * n_threads, dtype=np.int64)  # a cache line per thread
    for t in prange(n_threads):
        count = 0
        for s in range(t * _BLOCK_CHUNK, n_blocks, n_threads * _BLOCK_CHUNK):
            for b in range(s, min(s + _BLOCK_CHUNK, n_blocks)):
                if not block_ring[b]:
                    continue
                block_ring[b] = False
                for i in range(b << _BLOCK_SHIFT, min((b + 1) << _BLOCK_SHIFT, n)):
                    if not moved[i] and not ring[i]:
                        continue
                    moved[i] = False
                    ring[i] = False
                    count += 1
                    n0 = 0.0
                    n1 = 0.0
                    n2 = 0.0
                    for j in range(offsets[i], offsets[i + 1]):
                        f = leaf_ids[j]
                        n0 += face_normals[f, 0]
                        n1 += face_normals[f, 1]
                        n2 += face_normals[f, 2]
                    norm = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
                    if norm == 0.0:  # in no face, or only in degenerate ones
                        n0, n1, n2, norm = 0.0, 0.0, 1.0, 1.0
                    inverse = 1.0 / norm
                    normals[i, 0] = n0 * inverse
                    normals[i, 1] = n1 * inverse
                    normals[i, 2] = n2 * inverse
        counts[16 * t] = count
    total: np.int64 = counts.sum()
    return total


@njit(parallel=True, **_JIT)
def _differ(vertices: np.ndarray, rank: np.ndarray, positions: np.ndarray, mask: np.ndarray,
            n_threads: int) -> None:  # fmt: skip
    """mask[v]: row v of ``vertices`` differs from the index's positions (any coordinate)."""
    n = mask.shape[0]
    for t in prange(n_threads):
        for s in range(t * _VERTEX_CHUNK, n, n_threads * _VERTEX_CHUNK):
            for v in range(s, min(s + _VERTEX_CHUNK, n)):
                i = rank[v]
                mask[v] = (
                    positions[i, 0] != vertices[v, 0]
                    or positions[i, 1] != vertices[v, 1]
                    or positions[i, 2] != vertices[v, 2]
                )


@njit(parallel=True, **_JIT)
def _refit(positions: np.ndarray, index_faces: np.ndarray, leaf_dirty: np.ndarray,
           boxes: np.ndarray, n_threads: int) -> None:  # fmt: skip
    """The bounding box of each leaf marked in ``leaf_dirty`` (cleared)."""
    n_leaves = leaf_dirty.shape[0]
    n_faces = index_faces.shape[0]
    for t in prange(n_threads):
        for s in range(t * _LEAF_CHUNK, n_leaves, n_threads * _LEAF_CHUNK):
            for leaf in range(s, min(s + _LEAF_CHUNK, n_leaves)):
                if not leaf_dirty[leaf]:
                    continue
                leaf_dirty[leaf] = False
                lo0 = lo1 = lo2 = np.inf
                hi0 = hi1 = hi2 = -np.inf
                for f in range(leaf * LEAF_SIZE, min((leaf + 1) * LEAF_SIZE, n_faces)):
                    for k in range(3):
                        v = index_faces[f, k]
                        x, y, z = positions[v, 0], positions[v, 1], positions[v, 2]
                        lo0, lo1, lo2 = min(lo0, x), min(lo1, y), min(lo2, z)
                        hi0, hi1, hi2 = max(hi0, x), max(hi1, y), max(hi2, z)
                boxes[leaf, 0], boxes[leaf, 1], boxes[leaf, 2] = lo0, lo1, lo2
                boxes[leaf, 3], boxes[leaf, 4], boxes[leaf, 5] = hi0, hi1, hi2


@njit(**_JIT)
def _leaf_hits(boxes: np.ndarray, origin: np.ndarray, inv_dir: np.ndarray,
               near: np.ndarray) -> None:  # fmt: skip
    """near[c] = entry distance of the ray into box c, or inf if it misses (serial: ~1 ms)."""
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
def _closest_hit(vertices: np.ndarray, leaf_faces: np.ndarray, order: np.ndarray,
                 candidates: np.ndarray, near: np.ndarray, origin: np.ndarray,
                 direction: np.ndarray) -> tuple[int, float]:  # fmt: skip
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
    """What the viewport needs per event, at a cost proportional to the change: vertices in
    Z-order (:attr:`order`), faces by their centroids' in leaves of :data:`LEAF_SIZE` faces
    (:attr:`face_order`) with bounding boxes, so a brush region reads neighbouring memory.
    :meth:`update` redoes the faces around the moved vertices and their one-ring's normals (bit
    for bit a new build's; :func:`vertex_normals`' within float32 rounding) and marks their
    boxes stale; :meth:`pick` refits those, then tests the boxes the ray hits, nearest first.

    Parameters: vertices (N, 3) float64; faces (M, 3) int; progress: called with the fraction
    done (0, 1] between the build's stages (raising from it cancels the build); carried:
    (index, origin, face_origin) if these came of ``index``'s mesh by a local change (each
    row's row there, -1: new; the carried in order): no sort, the kept rows in their order
    and with their normals, the new ones after them, updated where anything changed.

    Attributes (a renderer draws them directly): positions (N, 3), normals (N, 3) float64 in
    index order (order (N,) int32: the vertex of each row, rank (N,) its inverse); faces (M, 3)
    int32 in leaf order, as rows of positions (face_order (M,) int32: the mesh face of each).
    """

    def __init__(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        progress: Callable[[float], None] | None = None,
        carried: tuple[SurfaceIndex, np.ndarray, np.ndarray] | None = None,
    ):
        report = progress if progress is not None else (lambda _fraction: None)
        vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        if vertices.ndim != 2 or vertices.shape[1] != 3:
            raise ValueError(f"vertices must have shape (N, 3) (got {vertices.shape})")
        n = len(vertices)
        faces = checked_faces(faces, n)
        if n >= 2**31 or 3 * len(faces) >= 2**31:  # int32 rows and face-corner offsets
            raise ValueError("meshes of 2**31 vertices or 2**31 / 3 faces or more are unsupported")
        faces = np.ascontiguousarray(faces, dtype=np.int32)
        self._n_vertices = n
        if carried is None:  # the vertices along the curve, then the faces by their centroids
            self.order = _curve_order(vertices, np.arange(n, dtype=np.int32).reshape(n, 1))
            self.face_order = _curve_order(vertices, faces)
        else:  # the kept rows in the order they had, the new ones after them
            before, origin, face_origin = carried
            self.order, rows = _kept_order(before.order, origin)
            self.face_order, face_rows = _kept_order(before.face_order, face_origin)
        self.rank = np.empty(n, dtype=np.int32)
        self.rank[self.order] = np.arange(n, dtype=np.int32)
        face_rank = np.empty(len(faces), dtype=np.int32)
        face_rank[self.face_order] = np.arange(len(faces), dtype=np.int32)
        report(0.4)
        self.faces = np.empty((len(faces), 3), dtype=np.int32)
        n_blocks = (n + (1 << _BLOCK_SHIFT) - 1) >> _BLOCK_SHIFT
        self._offsets = np.empty(n + 1, dtype=np.int32)
        self._leaf_ids = np.empty(3 * len(faces), dtype=np.int32)
        self._block_offsets = np.empty(n_blocks + 1, dtype=np.int32)
        block_leaves = np.empty(3 * len(faces), dtype=np.int32)
        used = _kernels()._connect(
            faces, self.rank, self.face_order, face_rank, self.faces, self._offsets,
            self._leaf_ids, self._block_offsets, block_leaves,
        )  # fmt: skip
        self._block_leaves = block_leaves[:used].copy()
        report(0.7)
        n_leaves = (len(faces) + LEAF_SIZE - 1) // LEAF_SIZE
        self.positions = np.empty((n, 3))
        self.normals = np.empty((n, 3))
        self._moved = np.zeros(n, dtype=np.bool_)
        self._ring = np.zeros(n, dtype=np.bool_)
        self._block_moved = np.zeros(n_blocks, dtype=np.bool_)
        self._block_ring = np.zeros(n_blocks, dtype=np.bool_)
        self._leaf_mark = np.zeros(n_leaves, dtype=np.bool_)
        self._leaf_dirty = np.ones(n_leaves, dtype=np.bool_)  # every box is fit at the end
        # float32: half the memory the normals' sums read; each (b - a) × (c - a) rounded once
        self._face_normals = np.empty((len(faces), 3), dtype=np.float32)
        self._boxes = np.empty((n_leaves, 6))
        self._stale_boxes = n  # vertices moved since the boxes were last refit (all)
        if carried is None:  # every vertex "moved": every face normal and vertex normal
            self.update(vertices, np.arange(n, dtype=np.int64))
        else:  # only what changed
            self.update(vertices, self._carried(vertices, faces, before, rows, face_rows))
        report(0.95)
        self._refit()
        report(1.0)

    def _carried(self, vertices: np.ndarray, faces: np.ndarray, before: SurfaceIndex,
                 rows: np.ndarray, face_rows: np.ndarray) -> np.ndarray:  # fmt: skip
        """Take ``before``'s normals of the rows carried over (``rows``, ``face_rows``: its rows'
        new rows, -1: gone); the vertices to update: new, moved, corners of new or gone faces."""
        kept, kept_faces = np.flatnonzero(rows >= 0), np.flatnonzero(face_rows >= 0)
        n, m = len(kept), len(kept_faces)  # ascending rows of ``before``: no random reads
        np.take(before.positions, kept, axis=0, out=self.positions[:n], mode="clip")
        np.take(before.normals, kept, axis=0, out=self.normals[:n], mode="clip")  # clip: no buffer
        np.take(before._face_normals, kept_faces, 0, self._face_normals[:m], mode="clip")
        gone = rows[before.faces[face_rows < 0]].ravel()
        new = (self.order[n:], faces[self.face_order[m:]].ravel(), gone[gone >= 0])
        return np.concatenate([*new, self.changed_rows(vertices)])

    @property
    def vertices(self) -> np.ndarray:
        """The positions (N, 3) as of the last :meth:`update`, in the mesh's order (a copy)."""
        return self.positions[self.rank]

    def update(self, vertices: np.ndarray, changed: np.ndarray) -> int:
        """The vertices ``changed`` (indices) moved to ``vertices`` (N, 3, the mesh's order;
        only those rows are read): update :attr:`positions` and :attr:`normals`, mark their
        boxes stale. Returns how many normals were recomputed (theirs and their one-ring's)."""
        vertices = self._checked(vertices)
        seeds = np.ascontiguousarray(changed, dtype=np.int64).ravel()
        if not seeds.size:
            return 0
        if seeds.min() < 0 or seeds.max() >= self._n_vertices:
            raise ValueError(f"changed must index vertices 0 to {self._n_vertices - 1}")
        self._stale_boxes += len(seeds)
        with _threads_for(len(seeds)) as threads:
            return int(
                _kernels()._update(
                    vertices, seeds, self.rank, self._offsets, self._leaf_ids,
                    self._block_offsets, self._block_leaves, self.faces, self.positions,
                    self._moved, self._ring, self._block_moved, self._block_ring,
                    self._leaf_mark, self._leaf_dirty, self._face_normals, self.normals,
                    threads,
                )
            )  # fmt: skip

    def _checked(self, vertices: np.ndarray) -> np.ndarray:
        vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        if vertices.shape != (self._n_vertices, 3):
            raise ValueError(
                f"vertices must have shape ({self._n_vertices}, 3) (got {vertices.shape})"
            )
        return vertices

    def changed_rows(self, vertices: np.ndarray) -> np.ndarray:
        """The rows (sorted) of ``vertices`` (N, 3, the mesh's order) unlike the last update's."""
        vertices = self._checked(vertices)
        mask = np.empty(self._n_vertices, dtype=np.bool_)
        with _threads_for(self._n_vertices) as threads:
            _kernels()._differ(vertices, self.rank, self.positions, mask, threads)
        return np.flatnonzero(mask)

    def _refit(self) -> None:
        """Refit the boxes of the leaves marked stale since the last pick."""
        if self._stale_boxes:
            with _threads_for(self._stale_boxes) as threads:
                _kernels()._refit(
                    self.positions, self.faces, self._leaf_dirty, self._boxes, threads
                )
            self._stale_boxes = 0

    def pick(self, origin: np.ndarray, direction: np.ndarray) -> tuple[int, np.ndarray] | None:
        """The first face (the mesh's face number) hit by the ray origin + t·direction (t ≥ 0)
        at the positions of the last :meth:`update`, and the hit point (3,); or None."""
        o, d = (np.asarray(v, dtype=np.float64) for v in (origin, direction))
        if o.shape != (3,) or d.shape != (3,) or not np.all(np.isfinite(o) & np.isfinite(d)):
            raise ValueError("pick origin and direction must be 3 finite numbers each")
        if not np.any(d):
            raise ValueError("pick direction must be nonzero")
        self._refit()
        with np.errstate(divide="ignore"):
            inv = 1.0 / d
        near = np.empty(len(self._boxes))
        kernels = _kernels()
        kernels._leaf_hits(self._boxes, o, inv, near)
        hit = np.flatnonzero(near < np.inf)
        candidates = hit[np.argsort(near[hit], kind="stable")]
        face, t = kernels._closest_hit(
            self.positions, self.faces, self.face_order, candidates, near, o, d
        )
        return None if face < 0 else (int(face), o + t * d)


#: Below this many moved vertices an update runs on the calling thread alone (cheaper).
PARALLEL_VERTICES = 20_000


def _threads_for(work: int) -> AbstractContextManager[int]:
    """numba's thread count for ``work`` vertices: 1 below :data:`PARALLEL_VERTICES`."""
    return threads_at_most(1 if work < PARALLEL_VERTICES else numba.get_num_threads())


def _kept_order(old_order: np.ndarray, origin: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The order (int32) of rows carried over (``origin``: each one's old row, -1: new) in
    ``old_order``, then the new rows; and each row of ``old_order``'s new row (-1: gone)."""
    new_row = np.full(len(old_order), -1, dtype=np.int32)
    new_row[origin[origin >= 0]] = np.flatnonzero(origin >= 0)
    rows = new_row[old_order]
    return np.concatenate([rows[rows >= 0], np.flatnonzero(origin < 0)]).astype(np.int32), rows


def _curve_order(points: np.ndarray, groups: np.ndarray) -> np.ndarray:
    """Indices (int32) of the groups (k, g) of ``points`` (N, 3) sorted along the Z-order curve
    (of the points' bounding box) of their mean points, ties in index order."""
    low = points.min(axis=0) if len(points) else np.zeros(3)
    extent = (points.max(axis=0) - low) if len(points) else np.ones(3)
    scale = ((1 << _MORTON_BITS) - 1) / np.maximum(extent, 1e-300)
    keys = np.empty(len(groups), dtype=np.int64)
    _kernels()._morton_keys(points, np.ascontiguousarray(groups, dtype=np.int32), low, scale, keys)
    keys.sort()  # unique keys: any sort gives the stable order; numpy's default is fastest
    return (keys & np.int64(2**31 - 1)).astype(np.int32)


def _exercise() -> None:
    """Call every compiled function of this module once, on a small surface index."""
    vertices = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    index = SurfaceIndex(vertices, np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))
    index.update(1.5 * vertices, np.array([3]))
    index.changed_rows(vertices)
    index.pick(np.array([0.2, 0.2, 3.0]), np.array([0.0, 0.0, -1.0]))


#: This module's compiled functions once numba has them (``gogreen_core._compiled``), else
#: their NumPy twins (``_geometry_numpy``): a new machine picks and shades at once.
_COMPILED = _compiled.CompiledModule(_compiled.GEOMETRY, __name__, _geometry_numpy, _exercise)
_kernels = _COMPILED.kernels
