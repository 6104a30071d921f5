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
from gogreen_core.mesh._geometry_numpy import _MORTON_BITS, LEAF_SIZE
from gogreen_core.mesh.topology import checked_faces, concatenated_ranges
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
def _connect(faces: np.ndarray, rank: np.ndarray, face_order: np.ndarray, face_rank: np.ndarray,
             index_faces: np.ndarray, offsets: np.ndarray,
             leaf_ids: np.ndarray) -> None:  # fmt: skip
    """Fill index_faces (index order and numbering); leaf_ids by offsets: each vertex's faces
    in mesh face order."""
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


@njit(parallel=True, **_JIT)
def _update(
    vertices: np.ndarray, seeds: np.ndarray, rank: np.ndarray, starts: np.ndarray,
    ends: np.ndarray, leaf_ids: np.ndarray, faces: np.ndarray, positions: np.ndarray,
    moved: np.ndarray, ring: np.ndarray, leaf_mark: np.ndarray, leaf_dirty: np.ndarray,
    face_normals: np.ndarray, normals: np.ndarray, n_threads: int,
) -> np.int64:  # fmt: skip
    """One :meth:`SurfaceIndex.update`: copy the seeds, redo their leaves' face normals
    (float32) and their corners' normals (summed in face order)."""
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
    for t in prange(n_threads):  # their faces' leaves, in slot order (no random reads)
        for s in range(t * _VERTEX_CHUNK, n, n_threads * _VERTEX_CHUNK):
            for i in range(s, min(s + _VERTEX_CHUNK, n)):
                if moved[i]:
                    for e in range(starts[i], ends[i]):
                        leaf_mark[leaf_ids[e] // LEAF_SIZE] = True
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
    counts = np.zeros(16 * n_threads, dtype=np.int64)  # a cache line per thread
    for t in prange(n_threads):
        count = 0
        for s in range(t * _VERTEX_CHUNK, n, n_threads * _VERTEX_CHUNK):
            for i in range(s, min(s + _VERTEX_CHUNK, n)):
                if not moved[i] and not ring[i]:
                    continue
                moved[i] = False
                ring[i] = False
                count += 1
                n0 = 0.0
                n1 = 0.0
                n2 = 0.0
                for j in range(starts[i], ends[i]):
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
                    if index_faces[f, 0] == index_faces[f, 1] == index_faces[f, 2]:
                        continue  # blanked (a removed face's slot): widens no box
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
        near[c] = t0 if t0 <= t1 and boxes[c, 0] <= boxes[c, 3] else np.inf  # (empty leaf)


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
    for bit a new build's; :func:`vertex_normals`' within float32 rounding), :meth:`pick`
    refits the stale boxes and tests those the ray hits, nearest first; :meth:`renumber` takes
    a local change of topology in place. Parameters: vertices (N, 3) float64; faces (M, 3)
    int; progress: called with the fraction done (0, 1] (raising from it cancels the build).

    Attributes (a renderer draws them directly): positions (S, 3), normals (S, 3) float64 by
    slot (order (S,) int32: each slot's vertex, -1: free; rank (N,): each vertex's slot);
    faces (F, 3) int32 in leaf order, of slots (face_order (F,): each one's mesh face, -1: a
    blanked slot, one corner thrice: drawn as nothing, never picked). S = N, F = M until
    :meth:`renumber`; ``unsorted``: the face slots it blanked or wrote since the build.
    """

    def __init__(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        progress: Callable[[float], None] | None = None,
    ):
        report = progress if progress is not None else (lambda _fraction: None)
        vertices = self._checked(vertices, None)
        n = len(vertices)
        faces = checked_faces(faces, n)
        if n >= 2**31 or 3 * len(faces) >= 2**31:  # int32 rows and face-corner offsets
            raise ValueError("meshes of 2**31 vertices or 2**31 / 3 faces or more are unsupported")
        faces = faces.astype(np.int32)
        self._n_vertices, self.unsorted, m = n, 0, len(faces)
        self._slots, self._face_slots = n, m
        self._order = _curve_order(vertices, np.arange(n, dtype=np.int32).reshape(n, 1))
        self._face_order = _curve_order(vertices, faces)
        self.rank, self._face_rank = np.empty(n, np.int32), np.empty(m, np.int32)
        self.rank[self._order] = np.arange(n, dtype=np.int32)
        self._face_rank[self._face_order] = np.arange(m, dtype=np.int32)
        report(0.4)
        self._faces = np.empty((m, 3), dtype=np.int32)
        offsets, self._leaf_ids = np.empty(n + 1, np.int32), np.empty(3 * m, dtype=np.int32)
        _kernels()._connect(faces, self.rank, self._face_order, self._face_rank, self._faces,
                            offsets, self._leaf_ids)  # fmt: skip
        # each slot's faces: [start, end) of a pool (a renumber writes new lists at its end)
        self._starts, self._ends, self._pool = offsets[:-1].copy(), offsets[1:].copy(), 3 * m
        report(0.7)
        self._positions, self._normals = np.empty((n, 3)), np.empty((n, 3))
        self._moved, self._ring = np.zeros(n, dtype=np.bool_), np.zeros(n, dtype=np.bool_)
        n_leaves = -(-m // LEAF_SIZE)  # (rounded up)
        self._leaf_mark = np.zeros(n_leaves, dtype=np.bool_)
        self._leaf_dirty = np.ones(n_leaves, dtype=np.bool_)  # every box is fit at the end
        # float32: half the memory the normals' sums read; each (b - a) × (c - a) rounded once
        self._face_normals = np.empty((m, 3), dtype=np.float32)
        self._boxes = np.empty((n_leaves, 6))
        self._stale_boxes = n  # vertices moved since the boxes were last refit (all)
        self.update(vertices, np.arange(n, dtype=np.int64))  # every vertex "moved"
        report(0.95)
        self._refit()
        self._grow(1.125)  # room for new rows: a renumber writes in place
        report(1.0)

    positions = property(lambda self: self._positions[: self._slots])
    normals = property(lambda self: self._normals[: self._slots])
    order = property(lambda self: self._order[: self._slots])
    faces = property(lambda self: self._faces[: self._face_slots])
    face_order = property(lambda self: self._face_order[: self._face_slots])

    def renumber(self, vertices: np.ndarray, faces: np.ndarray, origin: np.ndarray,
                 face_origin: np.ndarray) -> int:  # fmt: skip
        """Become, in place, the index of ``vertices`` (N', 3), ``faces`` (M', 3) that a local
        change made of this mesh (``origin`` (N',), ``face_origin`` (M',): each row's row before,
        -1: new; kept faces in order): removed rows' slots freed or blanked, new rows in free
        slots or after; only what changed recomputed (a new build's normals, picks and faces).
        Returns the normals and face slots written."""
        vertices, faces = self._checked(vertices, None), np.asarray(faces)
        origin, face_origin = np.asarray(origin), np.asarray(face_origin)
        if origin.shape != (len(vertices),) or face_origin.shape != (len(faces),):
            raise ValueError("origin and face_origin must give each vertex's and face's row")
        rank, _ = _carried_slots(self.rank, self._order, origin)
        face_rank, gone = _carried_slots(self._face_rank, self._face_order, face_origin)
        lost = self._faces[gone].ravel()  # the slots that lost a face
        self._faces[gone] = self._faces[gone, :1]  # blanked: one corner thrice
        new, new_faces = np.flatnonzero(origin < 0), np.flatnonzero(face_origin < 0)
        rank[new] = self._free_slots(new, "_order", "_slots")
        face_rank[new_faces] = slots = self._free_slots(new_faces, "_face_order", "_face_slots")
        self._faces[slots] = corners = rank[checked_faces(faces[new_faces], len(vertices))]
        self.rank, self._face_rank, self._n_vertices = rank, face_rank, len(vertices)
        self._relist(lost, corners, slots, gone)
        self.unsorted += len(gone) + len(slots)
        self._leaf_dirty[np.concatenate([gone, slots]) // LEAF_SIZE] = True  # (refit by seeds)
        live = self._order[lost]
        seeds = [new, faces[new_faces].ravel(), live[live >= 0], self.changed_rows(vertices)]
        return self.update(vertices, np.concatenate(seeds)) + len(gone) + len(slots)

    def _free_slots(self, rows: np.ndarray, owner: str, used: str) -> np.ndarray:
        """Slots for ``rows``: free ones (``owner`` -1) below the ``used`` count, then after."""
        count = getattr(self, used)
        free = np.flatnonzero(getattr(self, owner)[:count] < 0)[: len(rows)]
        extra = len(rows) - len(free)
        setattr(self, used, count + extra)
        self._grow(1.0)
        slots = np.concatenate([free, np.arange(count, count + extra)]).astype(np.int32)
        getattr(self, owner)[slots] = rows
        return slots

    def _grow(self, room: float) -> None:
        """Room for ``room`` times the slots in use (vertices and faces; a quarter more)."""
        n, m = int(room * self._slots), int(room * self._face_slots)
        for names, size in (
            ("_positions _normals _order _moved _ring _starts _ends", n),
            ("_faces _face_order _face_normals", m),
            ("_leaf_mark _leaf_dirty _boxes", -(-m // LEAF_SIZE)),
        ):
            for name in names.split():
                setattr(self, name, _room(getattr(self, name), size))

    def _relist(self, lost: np.ndarray, corners: np.ndarray, slots: np.ndarray,
                gone: np.ndarray) -> None:  # fmt: skip
        """The face lists of the slots that lost faces (``gone``) or got faces (``corners`` of
        ``slots``) rewritten at the pool's end, in mesh face order (a new build's sums)."""
        mark = np.zeros(self._slots, dtype=bool)
        mark[lost] = mark[corners] = True
        touched = np.flatnonzero(mark)
        counts = self._ends[touched] - self._starts[touched]
        ids = self._leaf_ids[concatenated_ranges(self._starts[touched], counts)]
        keep = ~np.isin(ids, gone, kind="table")
        owner = np.concatenate([np.repeat(touched, counts)[keep], corners.ravel()])
        ids = np.concatenate([ids[keep], np.repeat(slots, 3)])
        ids = ids[np.lexsort((self._face_order[ids], owner))]
        counts = np.bincount(owner, minlength=self._slots)[touched]
        self._leaf_ids = _room(self._leaf_ids, self._pool + len(ids))
        self._leaf_ids[self._pool : self._pool + len(ids)] = ids
        self._starts[touched] = self._pool + np.cumsum(counts) - counts
        self._pool += len(ids)
        self._ends[touched] = self._starts[touched] + counts

    @property
    def vertices(self) -> np.ndarray:
        """The positions (N, 3) as of the last :meth:`update`, in the mesh's order (a copy)."""
        return np.take(self._positions, self.rank, axis=0)

    def update(self, vertices: np.ndarray, changed: np.ndarray) -> int:
        """The vertices ``changed`` (indices) moved to ``vertices`` (N, 3, the mesh's order;
        only those rows are read): update :attr:`positions` and :attr:`normals`, mark their
        boxes stale. Returns how many normals were recomputed (theirs and their one-ring's)."""
        vertices = self._checked(vertices, self._n_vertices)
        seeds = np.ascontiguousarray(changed, dtype=np.int64).ravel()
        if not seeds.size:
            return 0
        if seeds.min() < 0 or seeds.max() >= self._n_vertices:
            raise ValueError(f"changed must index vertices 0 to {self._n_vertices - 1}")
        self._stale_boxes += len(seeds)
        with _threads_for(len(seeds)) as threads:
            return int(
                _kernels()._update(
                    vertices, seeds, self.rank, self._starts, self._ends, self._leaf_ids,
                    self.faces, self.positions, self._moved, self._ring, self._leaf_mark,
                    self._leaf_dirty, self._face_normals, self.normals, threads,
                )
            )  # fmt: skip

    @staticmethod
    def _checked(vertices: np.ndarray, n: int | None) -> np.ndarray:
        vertices = np.ascontiguousarray(vertices, dtype=np.float64)
        if vertices.ndim != 2 or vertices.shape[1] != 3 or n not in (None, len(vertices)):
            expected = "N" if n is None else n
            raise ValueError(f"vertices must have shape ({expected}, 3) (got {vertices.shape})")
        return vertices

    def changed_rows(self, vertices: np.ndarray) -> np.ndarray:
        """The rows (sorted) of ``vertices`` (N, 3, the mesh's order) unlike the last update's."""
        vertices = self._checked(vertices, self._n_vertices)
        mask = np.empty(self._n_vertices, dtype=np.bool_)
        with _threads_for(self._n_vertices) as threads:
            _kernels()._differ(vertices, self.rank, self._positions, mask, threads)
        return np.flatnonzero(mask)

    def _refit(self) -> None:
        """Refit the boxes of the leaves marked stale since the last pick."""
        if self._stale_boxes:  # (the leaves past the faces: none marked, no faces)
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
        boxes = self._boxes[: -(-self._face_slots // LEAF_SIZE)]
        near = np.empty(len(boxes))
        kernels = _kernels()
        kernels._leaf_hits(boxes, o, inv, near)
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


def _carried_slots(rank: np.ndarray, order: np.ndarray, origin: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Each kept row's slot (``origin``: rows before, -1: new), the gone rows' slots (-1 in
    ``order``, each slot's row, renumbered); a new row's slot is a placeholder."""
    new_rank = rank[origin]
    alive = np.zeros(len(rank) + 1, dtype=bool)
    alive[origin] = True  # (-1: the last, spare entry)
    gone = rank[~alive[:-1]]
    kept = np.flatnonzero(origin >= 0)
    order[new_rank[kept]] = kept
    order[gone] = -1
    return new_rank, gone


def _room(array: np.ndarray, size: int) -> np.ndarray:
    """``array``, or a copy with room for a quarter more than ``size`` rows (zeros after)."""
    if len(array) >= size:
        return array
    out = np.zeros((size + size // 4, *array.shape[1:]), dtype=array.dtype)
    out[: len(array)] = array
    return out


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
