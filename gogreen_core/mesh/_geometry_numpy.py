"""NumPy twins of ``geometry.py``'s compiled functions, serving until numba has compiled those
(``_compiled``): same arguments (``n_threads`` ignored) and outputs, integer bookkeeping exact,
normals, boxes and hits within 1e-12 relative, so the two may take turns on one index."""

from __future__ import annotations

import numpy as np

from gogreen_core.mesh.topology import concatenated_ranges

__all__ = ["LEAF_SIZE"]

#: Faces per leaf of the surface index (one bounding box each; ``geometry.SurfaceIndex``).
LEAF_SIZE = 32
#: Bits per axis of the Z-order (Morton) codes; a code leaves 31 bits for the item's index.
_MORTON_BITS = 10


def _morton_keys(
    points: np.ndarray, groups: np.ndarray, low: np.ndarray, scale: np.ndarray, keys: np.ndarray
) -> None:
    n, k = groups.shape
    code = np.zeros(n, dtype=np.int64)
    top = (1 << _MORTON_BITS) - 1
    for axis in range(3):
        s = np.zeros(n)
        for j in range(k):
            s = s + points[groups[:, j], axis]
        cell = np.trunc((s / k - low[axis]) * scale[axis])
        cell = np.clip(cell, -(2.0**62), 2.0**62).astype(np.int64)  # int() of a finite float
        cell = np.minimum(np.maximum(cell, 0), top)
        for bit in range(_MORTON_BITS):
            code |= ((cell >> bit) & 1) << (3 * bit + axis)
    keys[:] = (code << 31) | np.arange(n, dtype=np.int64)


def _connect(
    faces: np.ndarray, rank: np.ndarray, face_order: np.ndarray, face_rank: np.ndarray,
    index_faces: np.ndarray, offsets: np.ndarray, leaf_ids: np.ndarray,
) -> None:  # fmt: skip
    corners = rank[faces].astype(np.int64)  # (M, 3) index vertex of each corner
    index_faces[:] = corners[face_order]
    flat = corners.ravel()  # faces in original order, corners in order: the summation order
    offsets[0] = 0
    np.cumsum(np.bincount(flat, minlength=offsets.shape[0] - 1), out=offsets[1:])
    leaf_ids[: flat.size] = face_rank[np.argsort(flat, kind="stable") // 3]


def _ranges(starts: np.ndarray, ends: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """Every index in [starts[r], ends[r]) for r in ``rows``, in order."""
    return concatenated_ranges(starts[rows], ends[rows] - starts[rows])


def _update(
    vertices: np.ndarray, seeds: np.ndarray, rank: np.ndarray, starts: np.ndarray,
    ends: np.ndarray, leaf_ids: np.ndarray, faces: np.ndarray, positions: np.ndarray,
    moved: np.ndarray, ring: np.ndarray, leaf_mark: np.ndarray, leaf_dirty: np.ndarray,
    face_normals: np.ndarray, normals: np.ndarray, n_threads: int,
) -> int:  # fmt: skip
    rows = rank[seeds].astype(np.int64)
    positions[rows] = vertices[seeds]
    moved[rows] = True
    leaf_mark[leaf_ids[_ranges(starts, ends, rows)] // LEAF_SIZE] = True
    leaves = np.flatnonzero(leaf_mark)
    leaf_mark[leaves] = False
    leaf_dirty[leaves] = True
    n_faces = faces.shape[0]
    face = (leaves[:, None] * LEAF_SIZE + np.arange(LEAF_SIZE)).ravel()
    face = face[face < n_faces]
    a, b, c = (faces[face, k] for k in range(3))
    face = face[moved[a] | moved[b] | moved[c]]
    a, b, c = (faces[face, k] for k in range(3))
    face_normals[face] = np.cross(positions[b] - positions[a], positions[c] - positions[a])
    ring[a] = ring[b] = ring[c] = True
    vertex = np.flatnonzero(moved[: positions.shape[0]] | ring[: positions.shape[0]])
    moved[vertex] = False
    ring[vertex] = False
    entries = _ranges(starts, ends, vertex)
    owner = np.repeat(np.arange(len(vertex)), ends[vertex] - starts[vertex])
    sums = np.zeros((len(vertex), 3))
    np.add.at(sums, owner, face_normals[leaf_ids[entries]])  # in face order, as compiled
    norm = np.sqrt(np.sum(sums * sums, axis=1))
    zero = norm == 0.0
    sums[zero] = (0.0, 0.0, 1.0)
    normals[vertex] = sums * (1.0 / np.where(zero, 1.0, norm))[:, None]
    return len(vertex)


def _differ(
    vertices: np.ndarray, rank: np.ndarray, positions: np.ndarray, mask: np.ndarray, n_threads: int
) -> None:
    mask[:] = np.any(positions[rank] != vertices, axis=1)


def _refit(
    positions: np.ndarray,
    index_faces: np.ndarray,
    leaf_dirty: np.ndarray,
    boxes: np.ndarray,
    n_threads: int,
) -> None:
    leaves = np.flatnonzero(leaf_dirty)
    if not leaves.size:
        return
    leaf_dirty[leaves] = False
    n_faces = index_faces.shape[0]
    starts = leaves * LEAF_SIZE
    counts = np.minimum(starts + LEAF_SIZE, n_faces) - starts
    face = concatenated_ranges(starts, counts)
    f = index_faces[face]
    corners = positions[f]  # (f, 3, 3): the faces' corners of the leaves
    blank = ((f[:, 0] == f[:, 1]) & (f[:, 1] == f[:, 2]))[:, None]  # widens no box
    bounds = np.concatenate([[0], np.cumsum(counts)[:-1]])
    low, high = np.where(blank, np.inf, corners.min(axis=1)), corners.max(axis=1)
    boxes[leaves, :3] = np.minimum.reduceat(low, bounds, axis=0)
    boxes[leaves, 3:] = np.maximum.reduceat(np.where(blank, -np.inf, high), bounds, axis=0)


def _leaf_hits(
    boxes: np.ndarray, origin: np.ndarray, inv_dir: np.ndarray, near: np.ndarray
) -> None:
    t0 = np.zeros(boxes.shape[0])
    t1 = np.full(boxes.shape[0], np.inf)
    with np.errstate(invalid="ignore"):
        for k in range(3):
            a = (boxes[:, k] - origin[k]) * inv_dir[k]
            b = (boxes[:, 3 + k] - origin[k]) * inv_dir[k]
            a, b = np.where(a > b, b, a), np.where(a > b, a, b)
            flat = ~(a <= b)  # NaN from 0·inf: the ray lies in the slab plane
            t0 = np.maximum(t0, np.where(flat, -np.inf, a))
            t1 = np.minimum(t1, np.where(flat, np.inf, b))
    near[:] = np.where((t0 <= t1) & (boxes[:, 0] <= boxes[:, 3]), t0, np.inf)


def _closest_hit(
    vertices: np.ndarray,
    leaf_faces: np.ndarray,
    order: np.ndarray,
    candidates: np.ndarray,
    near: np.ndarray,
    origin: np.ndarray,
    direction: np.ndarray,
) -> tuple[int, float]:
    n_faces = order.shape[0]
    ox, oy, oz = origin
    dx, dy, dz = direction
    best_t, best_f = np.inf, -1
    for c in candidates:
        if near[c] > best_t:
            break
        j = np.arange(c * LEAF_SIZE, min((c + 1) * LEAF_SIZE, n_faces))
        a, b, cc = (leaf_faces[j, k] for k in range(3))
        ax, ay, az = vertices[a, 0], vertices[a, 1], vertices[a, 2]
        e1x, e1y, e1z = vertices[b, 0] - ax, vertices[b, 1] - ay, vertices[b, 2] - az
        e2x, e2y, e2z = vertices[cc, 0] - ax, vertices[cc, 1] - ay, vertices[cc, 2] - az
        px = dy * e2z - dz * e2y
        py = dz * e2x - dx * e2z
        pz = dx * e2y - dy * e2x
        det = e1x * px + e1y * py + e1z * pz
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            sx, sy, sz = ox - ax, oy - ay, oz - az
            u = (sx * px + sy * py + sz * pz) * inv
            qx = sy * e1z - sz * e1y
            qy = sz * e1x - sx * e1z
            qz = sx * e1y - sy * e1x
            v = (dx * qx + dy * qy + dz * qz) * inv
            t = (e2x * qx + e2y * qy + e2z * qz) * inv
        hit = (det != 0.0) & (u >= 0.0) & (u <= 1.0) & (v >= 0.0) & (u + v <= 1.0) & (t >= 0.0)
        if hit.any():
            t = np.where(hit, t, np.inf)
            first = int(np.argmin(t))  # the first of equal values, as the loop's strict <
            if t[first] < best_t:
                best_t, best_f = float(t[first]), int(order[j[first]])
    return best_f, best_t
