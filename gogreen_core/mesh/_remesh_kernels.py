"""The compiled loops of local isotropic remeshing (:mod:`gogreen_core.mesh.remesh`): the
connectivity (counting sorts), the collapses and flips of a pass, strain, per-triangle arithmetic.

Each pass reads the connectivity of its start (compressed rows) and picks operations whose
neighbourhoods do not overlap (each claims every vertex it reads), so every check still holds
when all are applied at once; candidates are visited in the order given (bit for bit)."""

from __future__ import annotations

from typing import cast

import numpy as np
from numba import njit


@njit(cache=True, nogil=True, boundscheck=False)
def strained_corners(
    reference: np.ndarray, vertices: np.ndarray, faces: np.ndarray, marked: np.ndarray, tol2: float
) -> np.ndarray:
    """(N,) bool: the corners of the faces (M, 3) with a ``marked`` (N,) corner one of whose
    sides changed, as a vector, by more than sqrt(``tol2``) times its length from ``reference``
    (N, 3) to ``vertices`` (N, 3) (a grab's faint far field moves most of a big mesh)."""
    out = np.zeros(len(vertices), dtype=np.bool_)
    for f in range(len(faces)):
        if not (marked[faces[f, 0]] or marked[faces[f, 1]] or marked[faces[f, 2]]):
            continue
        for k in range(3):
            a, b = faces[f, k], faces[f, (k + 1) % 3]
            changed = side = 0.0
            for x in range(3):
                c = (vertices[b, x] - reference[b, x]) - (vertices[a, x] - reference[a, x])
                d = reference[b, x] - reference[a, x]
                changed += c * c
                side += d * d
            if changed > tol2 * side:
                out[faces[f, 0]] = out[faces[f, 1]] = out[faces[f, 2]] = True
                break
    return out


@njit(cache=True, nogil=True, boundscheck=False)
def edge_length_sums(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(N,) each vertex's sum of its faces' sides' lengths (an inner edge once a face)."""
    total = np.zeros(len(vertices))
    for f in range(len(faces)):
        for k in range(3):
            a, b = faces[f, k], faces[f, (k + 1) % 3]
            length2 = 0.0
            for x in range(3):
                length2 += (vertices[b, x] - vertices[a, x]) ** 2
            length = np.sqrt(length2)
            total[a] += length
            total[b] += length
    return total


@njit(cache=True, nogil=True, boundscheck=False)
def renumber_faces(faces: np.ndarray, skip: np.ndarray, number: np.ndarray, out: np.ndarray) -> int:
    """``out`` (k, 3): the faces (M, 3) not ``skip`` (M,), in order, corners ``number`` (N,)
    (a corner -1 reads its last entry); the smallest number written (0 without)."""
    j, low = 0, 0
    for f in range(len(faces)):
        if not skip[f]:
            for k in range(3):
                out[j, k] = number[faces[f, k]]
                low = min(low, out[j, k])
            j += 1
    return low


@njit(cache=True, nogil=True, boundscheck=False)
def _bucketed(keys: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A counting sort: offsets (n + 1,) and the positions (K,) of ``keys`` (K,) in [0, n)
    grouped by key, in increasing position within each (stable)."""
    offsets = np.zeros(n + 1, dtype=np.int64)
    offsets[1:] = np.cumsum(np.bincount(keys, minlength=n))
    fill, order = offsets[:-1].copy(), np.empty(len(keys), dtype=np.int64)
    for i in range(len(keys)):
        order[fill[keys[i]]] = i
        fill[keys[i]] += 1
    return offsets, order


@njit(cache=True, nogil=True, boundscheck=False)
def patch_connectivity(
    faces: np.ndarray, n: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``topology.mesh_edges`` and ``vertex_neighbours`` of ``faces`` (M, 3) on ``n`` vertices by
    counting sorts (equal; theirs sort 3M keys): ends (E, 2), face_edges (M, 3), face_count (E,),
    each edge's first two faces (E, 2), offsets (n + 1,), neighbours (2E,)."""
    flat = faces.ravel()
    low, high = np.empty(len(flat), np.int64), np.empty(len(flat), np.int64)
    for i in range(len(flat)):
        a, b = flat[i], flat[i - i % 3 + (i + 1) % 3]
        low[i], high[i] = min(a, b), max(a, b)
    starts, order = _bucketed(low, n)
    other = high[order]  # one gather, then the sorts read in sequence
    for v in range(n):  # each vertex's sides by their other end (insertion: a few, stable)
        for j in range(starts[v] + 1, starts[v + 1]):
            h, i, k = other[j], order[j], j
            while k > starts[v] and other[k - 1] > h:
                other[k], order[k] = other[k - 1], order[k - 1]
                k -= 1
            other[k], order[k] = h, i
    face_edges, count = np.empty(len(flat), np.int64), np.zeros(len(flat), np.int64)
    ends, edge_faces = np.empty((len(flat), 2), np.int64), np.full((len(flat), 2), -1, np.int64)
    e = -1
    for v in range(n):
        for j in range(starts[v], starts[v + 1]):
            if j == starts[v] or other[j] != other[j - 1]:
                e += 1
                ends[e, 0], ends[e, 1] = v, other[j]
            face_edges[order[j]] = e
            if count[e] < 2:
                edge_faces[e, count[e]] = order[j] // 3
            count[e] += 1
    ends, count, edge_faces = ends[: e + 1], count[: e + 1], edge_faces[: e + 1]
    offsets, slots = _bucketed(ends.ravel(), n)
    neighbours = ends.ravel()[slots ^ 1]  # the other end of each (edges in order)
    return ends, face_edges.reshape(-1, 3), count, edge_faces, offsets, neighbours


@njit(cache=True, nogil=True, boundscheck=False)
def vertex_faces(faces: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Each vertex's faces, increasing: offsets (n + 1,), faces (3M,) (``FaceAdjacency``'s)."""
    offsets, order = _bucketed(faces.ravel(), n)
    return offsets, order // 3


@njit(cache=True, nogil=True, boundscheck=False)
def _normal(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    return np.cross(q - p, r - p)


@njit(cache=True, nogil=True, boundscheck=False)
def _corner(faces: np.ndarray, f: int, v: int) -> int:
    """The corner (0, 1, 2) of face ``f`` at vertex ``v`` (-1: none)."""
    for k in range(3):
        if faces[f, k] == v:
            return k
    return -1


@njit(cache=True, nogil=True, boundscheck=False)
def _seam(faces: np.ndarray, uv_faces: np.ndarray, f0: int, f1: int, v: int) -> bool:
    """The corners of faces ``f0`` and ``f1`` at vertex ``v`` name different texture rows."""
    return bool(uv_faces[f0, _corner(faces, f0, v)] != uv_faces[f1, _corner(faces, f1, v)])


@njit(cache=True, nogil=True, boundscheck=False)
def _faces_keep_facing(
    points: np.ndarray,
    faces: np.ndarray,
    around: tuple[np.ndarray, np.ndarray],
    a: int,
    b: int,
    position: np.ndarray,
    min_area2: float,
) -> bool:
    """The faces of ``a`` and of ``b`` (``around``: :func:`vertex_faces`) that do not hold both
    still face the way they did and are not degenerate once ``a`` and ``b`` are at ``position``."""
    vf_offsets, vf_faces = around
    for v in (a, b):
        for j in range(vf_offsets[v], vf_offsets[v + 1]):
            f = vf_faces[j]
            if _corner(faces, f, a) >= 0 and _corner(faces, f, b) >= 0:
                continue
            corners = np.empty((3, 3))
            for k in range(3):
                w = faces[f, k]
                corners[k] = position if (w == a or w == b) else points[w]
            before = _normal(points[faces[f, 0]], points[faces[f, 1]], points[faces[f, 2]])
            after = _normal(corners[0], corners[1], corners[2])
            area2 = after[0] ** 2 + after[1] ** 2 + after[2] ** 2
            if area2 <= min_area2:
                return False
            dot = before[0] * after[0] + before[1] * after[1] + before[2] * after[2]
            before2 = before[0] ** 2 + before[1] ** 2 + before[2] ** 2
            if dot <= 0.5 * np.sqrt(area2 * before2):  # turned by more than 60°: refused
                return False
    return True


@njit(cache=True, nogil=True, boundscheck=False)
def pick_collapses(
    candidates: np.ndarray,
    links: tuple[np.ndarray, ...],
    points: np.ndarray,
    faces: np.ndarray,
    uv_faces: np.ndarray,
    around: tuple[np.ndarray, np.ndarray],
    closed: np.ndarray,
    free: np.ndarray,
    high: np.ndarray,
    min_area2: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Short edges to collapse (the conditions of :mod:`gogreen_core.mesh.remesh`, step 2; both
    ends ``closed``, the removed one ``free``; ``high`` (n,): each vertex's longest edge), in
    ``candidates`` (K,) order: rows (k, 3) int64 (removed vertex, kept vertex, edge), the kept
    vertex's new position (k, 3) and whether it is the midpoint (k,) (else it stays). ``links``:
    :func:`patch_connectivity`'s, ``around``: :func:`vertex_faces`'."""
    ends, _, _, edge_faces, offsets, neighbours = links
    n = len(closed)
    claimed = np.zeros(n, dtype=np.bool_)
    mark = np.zeros(n, dtype=np.int64)  # stamp: neighbours of the candidate's first end
    pairs = np.empty((len(candidates), 3), dtype=np.int64)
    positions = np.empty((len(candidates), 3))
    middle = np.empty(len(candidates), dtype=np.bool_)
    count = 0
    stamp = 0
    for e in candidates:
        a, b = ends[e, 0], ends[e, 1]
        if not (closed[a] and closed[b]) or not (free[a] or free[b]):
            continue
        if not free[a]:
            a, b = b, a
        if claimed[a] or claimed[b]:
            continue
        busy = False
        for v in (a, b):
            for j in range(offsets[v], offsets[v + 1]):
                if claimed[neighbours[j]]:
                    busy = True
        if busy:
            continue
        stamp += 1
        for j in range(offsets[a], offsets[a + 1]):
            mark[neighbours[j]] = stamp
        shared = 0
        for j in range(offsets[b], offsets[b + 1]):
            if mark[neighbours[j]] == stamp:
                shared += 1
        if shared != 2:
            continue
        f0, f1 = edge_faces[e, 0], edge_faces[e, 1]
        # the kept end's texture corner must be one row on both sides of the edge
        if _seam(faces, uv_faces, f0, f1, b):
            continue
        both = free[b]
        position = 0.5 * (points[a] + points[b]) if both else points[b].copy()
        high_kept = 0.5 * (high[a] + high[b]) if both else high[b]
        too_long = False
        for v in (a, b):
            for j in range(offsets[v], offsets[v + 1]):
                w = neighbours[j]
                if w == a or w == b:
                    continue
                d = points[w] - position
                limit = 0.5 * (high[w] + high_kept)
                if d[0] ** 2 + d[1] ** 2 + d[2] ** 2 > limit * limit:
                    too_long = True
        if too_long:
            continue
        if not _faces_keep_facing(points, faces, around, a, b, position, min_area2):
            continue
        claimed[a] = claimed[b] = True
        for v in (a, b):
            for j in range(offsets[v], offsets[v + 1]):
                claimed[neighbours[j]] = True
        pairs[count, 0], pairs[count, 1], pairs[count, 2] = a, b, e
        positions[count] = position
        middle[count] = both
        count += 1
    return pairs[:count], positions[:count], middle[:count]


@njit(cache=True, nogil=True, boundscheck=False)
def _min_angle_cos(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> float:
    """The largest cosine of the three angles of triangle p q r (of its smallest angle)."""
    worst = -1.0
    corners = (p, q, r)
    for k in range(3):
        u, v = corners[(k + 1) % 3] - corners[k], corners[(k + 2) % 3] - corners[k]
        nu = np.sqrt(u[0] ** 2 + u[1] ** 2 + u[2] ** 2)
        nv = np.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
        if nu == 0.0 or nv == 0.0:
            return 1.0
        worst = max(worst, (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (nu * nv))
    return worst


@njit(cache=True, nogil=True, boundscheck=False)
def smallest_angles(corners: np.ndarray) -> np.ndarray:
    """The smallest angle (degrees) of each triangle of ``corners`` (K, 3, 3) (0 for a
    degenerate one): what the remeshing keeps away from 0."""
    out = np.empty(len(corners))
    for i in range(len(corners)):
        worst = _min_angle_cos(corners[i, 0], corners[i, 1], corners[i, 2])
        out[i] = np.degrees(np.arccos(min(1.0, worst)))
    return out


@njit(cache=True, nogil=True, boundscheck=False)
def pick_flips(
    candidates: np.ndarray,
    links: tuple[np.ndarray, ...],
    points: np.ndarray,
    faces: np.ndarray,
    uv_faces: np.ndarray,
    closed: np.ndarray,
    valence: np.ndarray,
    target: np.ndarray,
    min_area2: float,
) -> np.ndarray:
    """Edges to flip (:mod:`gogreen_core.mesh.remesh`, step 3: the four valences' squared
    deviations from ``target`` drop, none below 3, the smallest angle not below half of what
    it was nor below 10° when it was above, the faces not turned over, no seam), in
    ``candidates`` (K,) order: rows (k, 4) int64 of the two faces and the edge's ends a, b,
    the first face running a → b (``links``: :func:`patch_connectivity`'s)."""
    ends, _, _, edge_faces, offsets, neighbours = links
    n = len(closed)
    claimed = np.zeros(n, dtype=np.bool_)
    out = np.empty((len(candidates), 4), dtype=np.int64)
    count = 0
    cos10 = np.cos(np.radians(10.0))
    for e in candidates:
        f0, f1 = edge_faces[e, 0], edge_faces[e, 1]
        a, b = ends[e, 0], ends[e, 1]
        # orient: f0 holds the side a → b
        if faces[f0, (_corner(faces, f0, a) + 1) % 3] != b:
            f0, f1 = f1, f0
        c = faces[f0, (_corner(faces, f0, a) + 2) % 3]
        k1 = _corner(faces, f1, b)
        d = faces[f1, (k1 + 2) % 3]
        if faces[f1, (k1 + 1) % 3] != a or c == d:
            continue
        if not (closed[a] and closed[b] and closed[c] and closed[d]):
            continue
        if claimed[a] or claimed[b] or claimed[c] or claimed[d]:
            continue
        if valence[a] <= 3 or valence[b] <= 3:
            continue
        # after - before of the four squared deviations, (x ∓ 1)² - x² = 1 ∓ 2x: drops
        gain = valence[c] - target[c] + valence[d] - target[d]
        if gain - (valence[a] - target[a]) - (valence[b] - target[b]) >= -2:
            continue
        if np.any(neighbours[offsets[c] : offsets[c + 1]] == d):  # the edge c d exists
            continue
        # a texture seam along the edge: the two faces' corners at a (and at b) differ
        if _seam(faces, uv_faces, f0, f1, a) or _seam(faces, uv_faces, f0, f1, b):
            continue
        pa, pb, pc, pd = points[a], points[b], points[c], points[d]
        old = _normal(pa, pb, pc) + _normal(pb, pa, pd)
        n0 = _normal(pa, pd, pc)
        n1 = _normal(pd, pb, pc)
        if (n0[0] ** 2 + n0[1] ** 2 + n0[2] ** 2) <= min_area2 or (
            n1[0] ** 2 + n1[1] ** 2 + n1[2] ** 2
        ) <= min_area2:
            continue
        if (old[0] * n0[0] + old[1] * n0[1] + old[2] * n0[2]) <= 0.0 or (
            old[0] * n1[0] + old[1] * n1[1] + old[2] * n1[2]
        ) <= 0.0:
            continue
        worst_before = max(_min_angle_cos(pa, pb, pc), _min_angle_cos(pb, pa, pd))
        worst_after = max(_min_angle_cos(pa, pd, pc), _min_angle_cos(pd, pb, pc))
        angle_before = np.arccos(min(1.0, worst_before))
        angle_after = np.arccos(min(1.0, worst_after))
        if angle_after < 0.5 * angle_before or (worst_after > cos10 and worst_before <= cos10):
            continue
        claimed[a] = claimed[b] = claimed[c] = claimed[d] = True
        valence[a] -= 1
        valence[b] -= 1
        valence[c] += 1
        valence[d] += 1
        out[count, 0], out[count, 1], out[count, 2], out[count, 3] = f0, f1, a, b
        count += 1
    return out[:count]


def closest_points_on_triangles(
    points: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The point of triangle (a, b, c) nearest to each of ``points``, all (K, 3): the points
    (K, 3) and their barycentric coordinates (K, 3) (Ericson, "Real-Time Collision Detection",
    5.1.5). A degenerate triangle answers with one of its corners or sides."""

    def dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return cast(np.ndarray, np.einsum("ij,ij->i", u, v))

    ab, ac, ap = b - a, c - a, points - a
    bp, cp = points - b, points - c
    d1, d2 = dot(ab, ap), dot(ac, ap)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        total = va + vb + vc
        v_in, w_in = vb / total, vc / total
    zero, one = np.zeros_like(d1), np.ones_like(d1)
    cases = [
        (d1 <= 0) & (d2 <= 0),
        (d3 >= 0) & (d4 <= d3),
        (vc <= 0) & (d1 >= 0) & (d3 <= 0),
        (d6 >= 0) & (d5 <= d6),
        (vb <= 0) & (d2 >= 0) & (d6 <= 0),
        (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0),
    ]
    v = np.select(cases, [zero, one, t_ab, zero, zero, 1.0 - t_bc], v_in)
    w = np.select(cases, [zero, zero, zero, one, t_ac, t_bc], w_in)
    bad = ~np.isfinite(v) | ~np.isfinite(w)  # a degenerate triangle inside: its first corner
    v[bad], w[bad] = 0.0, 0.0
    u = 1.0 - v - w
    weights = np.stack([u, v, w], axis=1)
    return a * u[:, None] + b * v[:, None] + c * w[:, None], weights
