"""Polygons to triangles by their shape, and the index check that names the polygon at fault.

Polygons come as consecutive corners with their sizes (as files list them) and go back as
triangles of *corner positions*, so vertex and texture indices map through the same triangles.
A quad keeps the file's diagonal (0-2) unless a triangle of it folds over against the quad's
normal and the other diagonal folds less (all quads at once). A larger polygon keeps the fan
from its first corner when every fan triangle lies on the polygon's side of its best-fit plane;
else the fan from another corner that does, else ear clipping (``mapbox_earcut``). A polygon of
k corners always gives k-2 triangles using all its corners and edges, so neighbours stay joined.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import mapbox_earcut
import numba
import numpy as np

from gogreen_core.mesh.mesh_io.data import MeshFileError
from gogreen_core.mesh.topology import concatenated_ranges

__all__ = ["check_corner_indices", "triangulate"]

#: A fan triangle whose turn against the polygon's normal is below -this (the sine of the
#: angle between the triangle's and the polygon's sides) folds over: the polygon is concave
#: there. The tolerance lets nearly straight corners (three points in a row) keep the fan.
_FOLD_TOLERANCE = 1e-9
#: Polygons of up to this many corners try the fan from each of their corners (k² work each)
#: before ear clipping.
_MAX_FAN_STARTS = 32


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
    """Triangles (T = Σ(k-2), 3) int64 of polygons by their shape (see the module's
    description), as positions in ``corners`` (C,) (each polygon's vertex indices into
    ``points`` (N, 3), polygon after polygon; ``sizes`` (P,) ≥ 3 corners each)."""
    sizes = np.ascontiguousarray(sizes, dtype=np.int64)
    if len(sizes) == 0 or sizes.max() == 3:
        return np.arange(3 * len(sizes), dtype=np.int64).reshape(-1, 3)
    corners = np.ascontiguousarray(corners, dtype=np.int64)
    points = np.ascontiguousarray(points, dtype=np.float64)
    corner_starts, triangle_starts = np.cumsum(sizes) - sizes, np.cumsum(sizes - 2) - (sizes - 2)
    # Every polygon's fan from its first corner, then the quads' and larger polygons' choices.
    polygon = np.repeat(np.arange(len(sizes)), sizes - 2)
    first = corner_starts[polygon]
    step = np.arange(len(polygon)) - triangle_starts[polygon]
    triangles = np.stack([first, first + step + 1, first + step + 2], axis=1)
    quads = np.flatnonzero(sizes == 4)
    if len(quads):
        _split_quads(points, corners, corner_starts[quads], triangle_starts[quads], triangles)
    larger = np.flatnonzero(sizes > 4)
    if len(larger):
        own = concatenated_ranges(corner_starts[larger], sizes[larger])
        rows = concatenated_ranges(triangle_starts[larger], sizes[larger] - 2)
        their_sizes = np.ascontiguousarray(sizes[larger])
        their_corners = np.ascontiguousarray(corners[own])
        found, uncovered = _fans(
            points, their_corners, their_sizes, _FOLD_TOLERANCE, _MAX_FAN_STARTS
        )
        starts, firsts = np.cumsum(their_sizes) - their_sizes, np.cumsum(their_sizes - 2)
        for p in np.flatnonzero(uncovered).tolist():  # ear clipping (a twisted one keeps its fan)
            k, c = int(their_sizes[p]), int(starts[p])
            clipped = _ear_clip(points[their_corners[c : c + k]])
            if clipped is not None:
                found[int(firsts[p]) - k + 2 : int(firsts[p])] = c + clipped
        triangles[rows] = own[found]
    return triangles


@np.errstate(all="ignore")  # huge coordinates overflow: such a quad keeps its split
def _split_quads(
    points: np.ndarray,
    corners: np.ndarray,
    starts: np.ndarray,
    rows: np.ndarray,
    triangles: np.ndarray,
) -> None:
    """Choose each quad's diagonal, all quads at once: the file's (corners 0-2, the fan kept in
    ``triangles[rows]``, ``triangles[rows + 1]``) unless one of its triangles folds over against
    the quad's normal while the other diagonal (1-3) folds less; then (1, 2, 3), (1, 3, 0).
    Convex quads keep the file's split bit for bit, as Blender and the file's writer made it."""
    at = corners[starts + np.arange(4)[:, None]]  # (4, Q) vertex of each corner
    x, y, z = np.take(np.ascontiguousarray(points.T), at, axis=1)  # (4, Q) each
    one, two, three = ((x[k] - x[0], y[k] - y[0], z[k] - z[0]) for k in (1, 2, 3))
    # Newell's normal of a quad: the cross product of its diagonals (2 - 0) x (3 - 1).
    n = _cross(two, _minus(three, one))
    # The fan's triangles (0, 1, 2), (0, 2, 3) turn with the normal where these are >= 0.
    first, second = _dot(_cross(one, two), n), _dot(_cross(two, three), n)
    maybe = np.flatnonzero((first < 0) | (second < 0))  # only these can fold
    if len(maybe) == 0:  # every quad keeps the file's split
        return
    one, two, three, n = ((a[maybe], b[maybe], c[maybe]) for a, b, c in (one, two, three, n))
    nn = _dot(n, n)
    kept = np.maximum(_fold(one, two, n, nn), _fold(two, three, n, nn))
    other = np.maximum(
        _fold(_minus(two, one), _minus(three, one), n, nn),
        _fold(_minus(three, one), _minus((0.0, 0.0, 0.0), one), n, nn),
    )
    flip = maybe[(kept > _FOLD_TOLERANCE) & (other < kept)]
    start, row = starts[flip], rows[flip]
    triangles[row] = np.stack([start + 1, start + 2, start + 3], axis=1)
    triangles[row + 1] = np.stack([start + 1, start + 3, start], axis=1)


#: A vector of Q points or directions, as its three (Q,) coordinate arrays (no stacked copies).
_Vectors = tuple[np.ndarray, np.ndarray, np.ndarray]


def _minus(u: _Vectors | tuple[float, float, float], v: _Vectors) -> _Vectors:
    return u[0] - v[0], u[1] - v[1], u[2] - v[2]


def _cross(u: _Vectors, v: _Vectors) -> _Vectors:
    return u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]


def _dot(u: _Vectors, v: _Vectors) -> np.ndarray:
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]  # type: ignore[no-any-return]


def _fold(u: _Vectors, v: _Vectors, n: _Vectors, nn: np.ndarray) -> np.ndarray:
    """(Q,) minus the sine of the side of the triangle with edges ``u``, ``v`` against the
    quads' normals ``n`` (``nn`` their squared lengths): above 0 when it folds."""
    side = _dot(_cross(u, v), n)
    scale = np.sqrt(_dot(u, u) * _dot(v, v) * nn)
    return np.where(scale > 0, -side / np.where(scale > 0, scale, 1.0), 0.0)


@numba.njit(cache=True, nogil=True)
def _fans(
    points: np.ndarray, corners: np.ndarray, sizes: np.ndarray, tolerance: float, max_starts: int
) -> tuple[np.ndarray, np.ndarray]:
    """Fan triangles of each polygon (T, 3): from the first of its corners (up to
    ``max_starts``) whose fan covers it; and which polygons no fan covers (P,)."""
    triangles = np.empty(((sizes - 2).sum(), 3), dtype=np.int64)
    uncovered = np.zeros(len(sizes), dtype=np.bool_)
    c = 0
    t = 0
    for p in range(len(sizes)):
        k = sizes[p]
        fan = 0  # the first corner whose fan covers the polygon (else the first)
        if k > 3:
            # The Newell normal: the sum of the cross products of any fan's triangles.
            nx = ny = nz = 0.0
            o = corners[c]
            for j in range(1, k - 1):
                ax, ay, az = _edge(points, o, corners[c + j])
                bx, by, bz = _edge(points, o, corners[c + j + 1])
                nx += ay * bz - az * by
                ny += az * bx - ax * bz
                nz += ax * by - ay * bx
            length = np.sqrt(nx * nx + ny * ny + nz * nz)
            uncovered[p] = True
            for start in range(k if k <= max_starts else 1):
                if _fan_covers(points, corners, c, k, start, nx, ny, nz, length, tolerance):
                    fan, uncovered[p] = start, False
                    break
        for j in range(k - 2):
            triangles[t + j, 0] = c + fan
            triangles[t + j, 1] = c + (fan + j + 1) % k
            triangles[t + j, 2] = c + (fan + j + 2) % k
        c += k
        t += k - 2
    return triangles, uncovered


@numba.njit(cache=True, nogil=True, inline="always")
def _edge(points: np.ndarray, a: int, b: int) -> tuple[float, float, float]:
    return points[b, 0] - points[a, 0], points[b, 1] - points[a, 1], points[b, 2] - points[a, 2]


@numba.njit(cache=True, nogil=True)
def _fan_covers(
    points: np.ndarray,
    corners: np.ndarray,
    c: int,
    k: int,
    start: int,
    nx: float,
    ny: float,
    nz: float,
    length: float,
    tolerance: float,
) -> bool:
    """Whether every triangle of the fan from corner ``start`` of the polygon at ``c`` turns
    with the normal (within ``tolerance``, a sine)."""
    o = corners[c + start]
    for j in range(1, k - 1):
        ax, ay, az = _edge(points, o, corners[c + (start + j) % k])
        bx, by, bz = _edge(points, o, corners[c + (start + j + 1) % k])
        side = (ay * bz - az * by) * nx + (az * bx - ax * bz) * ny + (ax * by - ay * bx) * nz
        scale = np.sqrt((ax * ax + ay * ay + az * az) * (bx * bx + by * by + bz * bz))
        if side < -tolerance * scale * length:
            return False
    return True


def _ear_clip(positions: np.ndarray) -> np.ndarray | None:
    """Triangles (k-2, 3) of corner numbers covering one polygon (k, 3), by ear clipping on its
    best-fit plane; None when that fails."""
    k = len(positions)
    edges = positions[1:] - positions[0]
    normal = np.cross(edges[:-1], edges[1:]).sum(axis=0)  # Newell's
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
    whole = tri if len(tri) == k - 2 else _put_back_dropped_corners(tri, k)
    if whole is None or len(whole) != k - 2 or len(np.unique(whole)) != k:
        return None
    return whole


def _put_back_dropped_corners(tri: np.ndarray, k: int) -> np.ndarray | None:
    """Ear clipping drops corners on a straight line between their neighbours (or repeated);
    a neighbouring face may use one, so the triangle on the edge skipping them is split into
    a fan through them. None when no such triangle is found."""
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
