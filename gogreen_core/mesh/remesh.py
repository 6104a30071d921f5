"""Local isotropic remeshing (Botsch & Kobbelt 2004, "A remeshing approach to multiresolution
modeling", Sec. 4), of a region of a triangle mesh or of all of it.

Given a target edge length L (one, or each vertex's: a sizing field, an edge measured against
the mean of its ends'), each iteration
1. splits the edges longer than 4/3 L at their midpoints (all at once, red-green as in
   :mod:`gogreen_core.mesh.subdivision`), until none is left;
2. collapses the edges shorter than 4/5 L (into their midpoint, or into the end that may not
   move), unless that makes an edge longer than 4/3 L, turns a face over or degenerates it,
   breaks the link condition (manifold), removes a held vertex, or crosses a texture seam;
3. flips edges where that brings the four valences nearer to 6 (4 on an open rim) without
   worsening the pair's smallest angle much;
4. moves each free vertex towards the area-weighted centroid of its one-ring in its tangent
   plane, back onto the nearest point of its one-ring's triangles as they were, whose mask and
   texture coordinates it interpolates;
then a last split pass splits what the relaxation stretched beyond 4/3 L.

Only the faces touching ``region`` change: the other vertices keep their positions bit for bit
(their indices shift down past removed vertices; new ones come after the old); open rims and
non-manifold edges are never split, collapsed or flipped nor their vertices moved; a closed
surface stays closed, of the same Euler characteristic, consistently oriented. Held vertices
(``locked``: pins, masked vertices) never move nor go. Texture coordinates are per face corner:
a split gives each face its own midpoint (seams stay seams), nothing crosses a seam, seam
vertices do not move. Every step is a numpy pass or a compiled loop over candidates in a fixed
order (:mod:`gogreen_core.mesh._remesh_kernels`): a remesh replays bit for bit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gogreen_core.mesh._remesh_kernels import (
    closest_points_on_triangles,
    edge_length_sums,
    patch_connectivity,
    pick_collapses,
    pick_flips,
    renumber_faces,
    smallest_angles,
    strained_corners,
    vertex_faces,
)
from gogreen_core.mesh.subdivision import (
    MASK_THRESHOLD,
    _gathered_sum,
    _split_faces,
    _subdivided_uv,
)
from gogreen_core.mesh.topology import (
    BOUNDARY,
    INTERIOR,
    FaceAdjacency,
    MeshEdges,
    mesh_edges,
    vertex_neighbours,
)

__all__ = [
    "COLLAPSE_BELOW",
    "SPLIT_ABOVE",
    "RemeshedMesh",
    "closest_points_on_triangles",
    "grow_region",
    "local_edge_lengths",
    "median_edge_length",
    "remesh",
    "smallest_angles",
    "strained_corners",
]

#: Edges longer than this many target lengths are split (Botsch & Kobbelt's 4/3).
SPLIT_ABOVE = 4.0 / 3.0
#: Edges shorter than this many target lengths are collapsed (their 4/5).
COLLAPSE_BELOW = 4.0 / 5.0
#: Split passes per iteration at most (each halves the long edges: 2^8 × L is plenty).
_SPLIT_ROUNDS = 8
#: Vertex-triangle pairs per block of the relaxation's nearest points (bounds its memory).
_BLOCK = 1 << 17
#: A face is degenerate below this area, in target lengths squared.
_MIN_AREA = 1e-4
_NO_ROWS = np.zeros(0, dtype=np.int64)


@dataclass(frozen=True)
class RemeshedMesh:
    """The result of :func:`remesh`: the new arrays (mask, uv and sizes None without; sizes
    (N',): each vertex's target length); kept (N,) int64: each old vertex's new index, -1 when
    collapsed away; changed (N',) bool: the region's vertices and the new ones (the others are
    bit for bit as they were); kept_faces (M,) bool: the old faces kept, in order, first;
    uv_kept (T,) int64 (None without uv): each old texture row's new index, -1 when dropped
    (the region's rows no face uses any more; new rows come after the kept ones)."""

    vertices: np.ndarray
    faces: np.ndarray
    mask: np.ndarray | None
    uv: np.ndarray | None
    uv_faces: np.ndarray | None
    kept: np.ndarray
    changed: np.ndarray
    kept_faces: np.ndarray
    sizes: np.ndarray | None = None
    uv_kept: np.ndarray | None = None


@dataclass
class _Patch:
    """The faces being remeshed with their own vertex numbering (the patch's vertices first,
    ascending by their mesh index, then new ones), mask and texture corners."""

    points: np.ndarray
    faces: np.ndarray
    closed: np.ndarray  # all the vertex's faces are here (it may change)
    locked: np.ndarray  # never moves, never removed
    mask: np.ndarray
    sizes: np.ndarray  # each vertex's target edge length L
    uv: np.ndarray | None
    uv_faces: np.ndarray  # -1 rows: untextured

    def __post_init__(self) -> None:
        # how each vertex may move (topology.INTERIOR, ...): right for the closed vertices, kept
        # through the passes (only edges of two faces change; new vertices are interior)
        n = len(self.points)
        self.mode = vertex_neighbours(MeshEdges(*patch_connectivity(self.faces, n)[:3]), n).mode

    def free(self) -> np.ndarray:
        """Vertices that may move or be collapsed away (not on a seam: their corners name one
        texture row, or all none)."""
        free: np.ndarray = self.closed & ~self.locked & (self.mode == INTERIOR)
        if self.uv is not None:
            corners, rows = self.faces.ravel(), self.uv_faces.ravel()
            row = np.empty(len(free), dtype=np.int64)
            row[corners] = rows  # one of each vertex's rows: a seam's differs from another
            free[corners[rows != row[corners]]] = False
        return free

    # -- 1. split ------------------------------------------------------------------------------
    def split(self) -> bool:
        ends, face_edges, count = patch_connectivity(self.faces, len(self.points))[:3]
        a, b = ends[:, 0], ends[:, 1]
        side = self.points[b] - self.points[a]
        length2 = np.einsum("ij,ij->i", side, side)
        high = SPLIT_ABOVE * 0.5 * (self.sizes[a] + self.sizes[b])
        split = (count == 2) & (self.closed[a] | self.closed[b]) & (length2 > high * high)
        if not split.any():
            return False
        split_sides = split[face_edges]
        refine = split_sides.all(axis=1)
        number = np.cumsum(split) - 1 + len(self.points)
        middles = np.where(split_sides, number[face_edges], -1)
        counts = split_sides.sum(axis=1)
        ends = ends[split]
        for name in ("points", "mask", "sizes"):  # the midpoints'
            old = getattr(self, name)
            setattr(self, name, np.concatenate([old, 0.5 * (old[ends[:, 0]] + old[ends[:, 1]])]))
        for name, value in (("closed", True), ("locked", False), ("mode", INTERIOR)):
            old = getattr(self, name)
            setattr(self, name, np.concatenate([old, np.full(len(ends), value, old.dtype)]))
        if self.uv is not None:
            self.uv, self.uv_faces = _subdivided_uv(self.uv, self.uv_faces, split_sides, refine)
        else:
            self.uv_faces = np.full((int((np.where(refine, 4, counts + 1)).sum()), 3), -1, np.int64)
        self.faces = _split_faces(self.faces, middles, refine, counts)
        return True

    # -- 2. collapse ---------------------------------------------------------------------------
    def collapse(self, min_area2: float) -> bool:
        links = patch_connectivity(self.faces, len(self.points))
        ends, _, count, edge_faces = links[:4]
        a, b = ends[:, 0], ends[:, 1]
        length = np.linalg.norm(self.points[b] - self.points[a], axis=1)
        free = self.free()
        short = (count == 2) & self.closed[a] & self.closed[b] & (free[a] | free[b])
        short &= length < COLLAPSE_BELOW * 0.5 * (self.sizes[a] + self.sizes[b])
        candidates = np.flatnonzero(short)
        if not len(candidates):
            return False
        candidates = candidates[np.argsort(length[candidates], kind="stable")]
        pairs, positions, middle = pick_collapses(
            candidates,
            links,
            self.points,
            self.faces,
            self.uv_faces,
            vertex_faces(self.faces, len(self.points)),
            self.closed,
            free,
            SPLIT_ABOVE * self.sizes,
            min_area2,
        )
        if not len(pairs):
            return False
        gone, kept = pairs[:, 0], pairs[:, 1]
        if self.uv is not None:
            # the kept end's row (one on both sides of the edge) replaces the removed end's
            face = edge_faces[pairs[:, 2], 0]
            kept_row = self.uv_faces[face, np.argmax(self.faces[face] == kept[:, None], axis=1)]
            gone_row = self.uv_faces[face, np.argmax(self.faces[face] == gone[:, None], axis=1)]
            both = middle & (kept_row >= 0)  # a face's corners are all textured or none
            self.uv[kept_row[both]] = 0.5 * (self.uv[gone_row[both]] + self.uv[kept_row[both]])
            row_of = np.full(len(self.points), -1, dtype=np.int64)
            row_of[gone] = kept_row  # a removed end's corners all had its one row, or none
            rows = row_of[self.faces]
            self.uv_faces = np.where(rows >= 0, rows, self.uv_faces)
        self.mask[kept[middle]] = 0.5 * (self.mask[gone[middle]] + self.mask[kept[middle]])
        self.sizes[kept[middle]] = 0.5 * (self.sizes[gone[middle]] + self.sizes[kept[middle]])
        self.points[kept] = positions
        target = np.arange(len(self.points))
        target[gone] = kept
        faces = target[self.faces]
        alive = np.all(faces != np.roll(faces, 1, axis=1), axis=1)
        self.faces, self.uv_faces = faces[alive], self.uv_faces[alive]
        self.closed[gone] = False
        return True

    # -- 3. flip -------------------------------------------------------------------------------
    def flip(self, min_area2: float) -> bool:
        links = patch_connectivity(self.faces, len(self.points))
        ends, count, offsets = links[0], links[2], links[4]
        a, b = ends[:, 0], ends[:, 1]
        candidates = np.flatnonzero((count == 2) & self.closed[a] & self.closed[b])
        if not len(candidates):
            return False
        valence = np.diff(offsets)
        target = np.where(self.mode == BOUNDARY, 4, 6).astype(np.int64)
        flips = pick_flips(
            candidates,
            links,
            self.points,
            self.faces,
            self.uv_faces,
            self.closed,
            valence.astype(np.int64),
            target,
            min_area2,
        )
        if not len(flips):
            return False
        f0, f1, va, vb = flips.T
        k0 = np.argmax(self.faces[f0] == va[:, None], axis=1)
        k1 = np.argmax(self.faces[f1] == vb[:, None], axis=1)
        for table in (self.faces, self.uv_faces):  # a b c, b a d -> a d c, d b c
            a, c = table[f0, k0], table[f0, (k0 + 2) % 3]
            b, d = table[f1, k1], table[f1, (k1 + 2) % 3]
            table[f0] = np.stack([a, d, c], axis=1)
            table[f1] = np.stack([d, b, c], axis=1)
        return True

    # -- 4. tangential relaxation --------------------------------------------------------------
    def relax(self, min_area2: float) -> None:
        free = self.free()
        points, faces = self.points, self.faces
        n = len(points)
        p0, p1, p2 = points[faces[:, 0]], points[faces[:, 1]], points[faces[:, 2]]
        normal = np.cross(p1 - p0, p2 - p0)  # twice the area times the unit normal
        area = np.linalg.norm(normal, axis=1)
        centroid = (p0 + p1 + p2) / 3.0
        corners = faces.ravel()
        face_of = np.repeat(np.arange(len(faces)), 3)
        weight = np.bincount(corners, area[face_of], minlength=n)
        vertex_normal = _gathered_sum(corners, np.ascontiguousarray(normal.T), face_of, n)
        length = np.linalg.norm(vertex_normal, axis=1)
        moving = free & (length > 0)  # no tangent plane (a fold's normals cancel): stays
        if not moving.any():
            return
        columns = np.ascontiguousarray((area[:, None] * centroid).T)
        centre = _gathered_sum(corners, columns, face_of, n)
        rows = np.flatnonzero(moving)
        centre = centre[rows] / weight[rows, None]
        unit = vertex_normal[rows] / length[rows, None]
        step = centre - points[rows]
        step -= np.einsum("ij,ij->i", step, unit)[:, None] * unit
        goal = points[rows] + step
        slot = np.full(n, -1, dtype=np.int64)
        slot[rows] = np.arange(len(rows))
        # back onto the surface: the first nearest point of the one-ring's triangles (as they were)
        who, face = FaceAdjacency(faces, n).around(rows)  # faces increasing
        near, bary = np.empty((len(who), 3)), np.empty((len(who), 3))
        for at in range(0, len(who), _BLOCK):  # in blocks: a dozen (K, 3) temporaries each
            s, w, f = slice(at, at + _BLOCK), who[at : at + _BLOCK], face[at : at + _BLOCK]
            near[s], bary[s] = closest_points_on_triangles(goal[w], p0[f], p1[f], p2[f])
        gap = np.einsum("ij,ij->i", near - goal[who], near - goal[who])
        starts = np.searchsorted(who, np.arange(len(rows)))
        nearest = np.flatnonzero(gap == np.minimum.reduceat(gap, starts)[who])
        first = nearest[np.r_[True, who[nearest][1:] != who[nearest][:-1]]]
        near, chosen_face, chosen_bary = near[first], face[first], bary[first]
        # a vertex whose move would turn a face of its by more than 60° or degenerate it
        # (the centroid beyond its one-ring) stays where it is
        moved = points.copy()
        moved[rows] = near
        stays = np.zeros(len(rows), dtype=bool)
        for _ in range(4):
            moved[rows[stays]] = points[rows[stays]]
            q0, q1, q2 = moved[faces[:, 0]], moved[faces[:, 1]], moved[faces[:, 2]]
            after = np.cross(q1 - q0, q2 - q0)
            area2 = np.einsum("ij,ij->i", after, after)
            facing = np.einsum("ij,ij->i", normal, after)
            bad = (area2 <= min_area2) | (facing <= 0.5 * np.sqrt(area2) * area)
            culprits = slot[faces[bad].ravel()]
            culprits = culprits[culprits >= 0]
            if not len(culprits) or stays[culprits].all():
                break
            stays[culprits] = True
        go = ~stays
        rows, chosen_face, chosen_bary = rows[go], chosen_face[go], chosen_bary[go]
        self.mask[rows] = np.einsum("ij,ij->i", self.mask[faces[chosen_face]], chosen_bary)
        if self.uv is not None:
            corner_rows = self.uv_faces[chosen_face]
            textured = corner_rows[:, 0] >= 0
            own_row = np.empty(n, dtype=np.int64)  # a free vertex's one texture row
            own_row[corners] = self.uv_faces.ravel()
            new_uv = np.einsum("ijk,ij->ik", self.uv[corner_rows[textured]], chosen_bary[textured])
            self.uv[own_row[rows][textured]] = new_uv
        self.points[rows] = moved[rows]


def remesh(
    vertices: np.ndarray,
    faces: np.ndarray,
    region: np.ndarray,
    target_length: float | np.ndarray,
    *,
    mask: np.ndarray | None = None,
    uv: np.ndarray | None = None,
    uv_faces: np.ndarray | None = None,
    locked: np.ndarray | None = None,
    iterations: int = 3,
    progress: Callable[[float], None] | None = None,
) -> RemeshedMesh:
    """Isotropic remeshing of the faces around ``region`` (see the module docstring).

    Parameters
    ----------
    vertices : (N, 3) float64, model units; faces : (M, 3) int64.
    region : (N,) bool, the vertices whose faces may change (e.g. what a stroke moved, grown
        by a ring: :func:`grow_region`); every vertex for the whole mesh.
    target_length : L, model units (> 0): edges end between 4/5 L and 4/3 L where they can;
        or (N,) float64, each vertex's L (a sizing field: an edge against the mean of its
        ends'; new vertices interpolate it, returned as ``sizes``).
    mask : (N,) float64 in [0, 1], optional: carried onto new vertices (interpolated); a
        vertex held at :data:`~gogreen_core.mesh.subdivision.MASK_THRESHOLD` or more is locked.
    uv : (T, 2) float64 and uv_faces : (M, 3) int64 (-1 rows: untextured faces), optional.
    locked : (N,) bool, optional: vertices that never move and are never removed (pins).
    iterations : rounds of split, collapse, flip and relaxation.
    progress : called with the fraction done after each round, optional; may raise to cancel.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    n = len(vertices)
    sizing = np.ndim(target_length) > 0
    target = np.asarray(target_length, dtype=np.float64)
    if sizing and target.shape != (n,):
        raise ValueError(f"target_length must be one length or ({n},) (got {target.shape})")
    if not sizing and not (np.isfinite(target) and target > 0):
        raise ValueError(f"target_length must be a positive length (got {target_length!r})")
    region = np.asarray(region, dtype=bool)
    if region.shape != (n,):
        raise ValueError(f"region must have shape ({n},) (got {region.shape})")
    in_patch = region[faces[:, 0]] | region[faces[:, 1]] | region[faces[:, 2]]
    inside = np.flatnonzero(in_patch)
    local, cells = _localized(faces[inside], n)
    mask_local = np.zeros(len(local)) if mask is None else np.asarray(mask, np.float64)[local]
    sizes = target[local] if sizing else np.full(len(local), float(target))  # the patch's own
    if sizing and not (np.isfinite(sizes).all() and (sizes > 0).all()):
        raise ValueError("target_length must be positive lengths around the region")
    held = mask_local >= MASK_THRESHOLD
    if locked is not None:
        held |= np.asarray(locked, dtype=bool)[local]
    uv_local, uv_rows, corners = _NO_ROWS, None, np.full((len(inside), 3), -1)
    if uv is not None and uv_faces is not None:  # the patch's texture rows numbered alike
        uv_local, corners = _localized(np.asarray(uv_faces, np.int64)[inside], len(uv))
        uv_rows = np.asarray(uv, dtype=np.float64)[uv_local]
    L = float(sizes.min()) if len(local) else 1.0
    patch = _Patch(vertices[local], cells, region[local], held, mask_local, sizes, uv_rows, corners)
    min_area2 = (2.0 * _MIN_AREA * L * L) ** 2
    report = progress or (lambda _fraction: None)
    for done in range(iterations):
        report(done / (iterations + 1))
        _repeat(patch.split, _SPLIT_ROUNDS)
        _repeat(lambda: patch.collapse(min_area2), 2)
        _repeat(lambda: patch.flip(min_area2), 2)
        patch.relax(min_area2)
    report(iterations / (iterations + 1))
    _repeat(patch.split, _SPLIT_ROUNDS)  # what the relaxation stretched past 4/3 L
    # the whole mesh again: the kept rows in order, then new ones; outside faces, then the patch's
    used = np.bincount(patch.faces.ravel(), minlength=len(patch.points)) > 0
    numbering = kept, number, n_kept = _numbering(len(vertices), local, used)
    out_vertices = _carried(vertices, patch.points, numbering)
    out_faces = np.empty((len(faces) - int(in_patch.sum()) + len(patch.faces), 3), np.int64)
    renumber_faces(faces, in_patch, kept, out_faces)
    n_carried = len(out_faces) - len(patch.faces)
    out_faces[n_carried:] = number[patch.faces]
    out_mask = None if mask is None else _carried(np.asarray(mask), patch.mask, numbering)
    out_sizes = _carried(target, patch.sizes, numbering) if sizing else None
    out_uv = out_uv_faces = uv_kept = None
    if uv is not None and uv_faces is not None and patch.uv is not None:
        used_uv = np.bincount(patch.uv_faces.ravel() + 1, minlength=len(patch.uv) + 1)[1:] > 0
        out_uv_faces = np.empty_like(out_faces)
        for _ in range(2):
            uv_numbering = uv_kept, uv_number, _ = _numbering(len(uv), uv_local, used_uv)
            # -1 corners read the last entry; a row the patch no longer uses but a face outside
            # it does (one row for far corners: deduplicated UVs) reads -2: then all are kept
            table = np.append(uv_kept, -1)
            table[uv_local[~used_uv[: len(uv_local)]]] = -2
            if renumber_faces(uv_faces, in_patch, table, out_uv_faces) >= -1:
                break
            used_uv[: len(uv_local)] = True
        out_uv = _carried(np.asarray(uv), patch.uv, uv_numbering)
        out_uv_faces[n_carried:] = np.where(patch.uv_faces >= 0, uv_number[patch.uv_faces], -1)
    changed = np.zeros(len(out_vertices), dtype=bool)
    changed[kept[local[patch.closed[: len(local)] & (kept[local] >= 0)]]] = True
    changed[n_kept:] = True
    arrays = (out_vertices, out_faces, out_mask, out_uv, out_uv_faces)
    return RemeshedMesh(*arrays, kept, changed, ~in_patch, out_sizes, uv_kept)


def _repeat(step: Callable[[], bool], rounds: int) -> None:
    """``step`` until it changes nothing (returns False), ``rounds`` times at most."""
    for _ in range(rounds):
        if not step():
            break


def _localized(corners: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The rows (ascending) of range(n) that ``corners`` (K, 3) name, and the corners numbered
    by them (-1 stays -1): by a count, no sort."""
    local = np.flatnonzero(np.bincount(corners.ravel() + 1, minlength=n + 1)[1:])
    number = np.full(n + 1, -1, dtype=np.int64)  # the last: a -1 corner's
    number[local] = np.arange(len(local))
    return local, number[corners]


def _numbering(n: int, local: np.ndarray, used: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """A patch's rows in the whole mesh's: ``local`` (n_local,) the patch's first rows' in the
    mesh's n, ``used`` (n_patch,) bool the patch's rows its faces use. Returns kept (n,): each
    row's new one (-1: gone, the patch's unused old rows); number (n_patch,): each patch row's
    new one (the new rows after the kept, in order; -1: unused); how many rows are kept."""
    n_local = len(local)
    keep = np.ones(n, dtype=bool)
    keep[local[~used[:n_local]]] = False
    kept = np.cumsum(keep) - 1
    n_kept = int(kept[-1]) + 1 if n else 0
    kept[~keep] = -1
    number = np.full(len(used), -1, dtype=np.int64)
    number[:n_local] = kept[local]
    added = np.flatnonzero(used[n_local:]) + n_local
    number[added] = n_kept + np.arange(len(added))
    return kept, number, n_kept


def _carried(
    old: np.ndarray, new: np.ndarray, numbering: tuple[np.ndarray, np.ndarray, int]
) -> np.ndarray:
    """``old``'s rows kept, the patch's rows ``new`` written where they go (``numbering``: by
    :func:`_numbering`); np.compress: a quarter of boolean indexing's time at 1M rows."""
    kept, number, n_kept = numbering
    rows = np.flatnonzero(number >= 0)
    out = np.empty((max(n_kept, int(number.max(initial=-1)) + 1), *old.shape[1:]))
    out[:n_kept] = np.compress(kept >= 0, old, axis=0) if n_kept < len(old) else old
    out[number[rows]] = new[rows]
    return out


def median_edge_length(vertices: np.ndarray, faces: np.ndarray) -> float:
    """The median length of the edges (each once) of ``faces`` (M, 3); 0 without faces."""
    if not len(faces):
        return 0.0
    ends = mesh_edges(np.asarray(faces, dtype=np.int64), len(vertices)).ends
    return float(np.median(np.linalg.norm(vertices[ends[:, 1]] - vertices[ends[:, 0]], axis=1)))


def local_edge_lengths(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(N,) float64: the mean length of each vertex's edges in ``faces`` (M, 3) over
    ``vertices`` (N, 3), model units (a sizing field); a vertex of no face (or only of edges
    of length 0) gets the median of the others (1 without any): every length is positive."""
    n = len(vertices)
    faces = np.asarray(faces, dtype=np.int64)
    total = edge_length_sums(np.asarray(vertices, np.float64), faces)
    count = 2.0 * np.bincount(faces.ravel(), minlength=n)  # each corner is on two sides
    lengths: np.ndarray = np.divide(total, count, out=np.zeros(n), where=count > 0)
    alone = ~(lengths > 0)
    if alone.any():
        lengths[alone] = float(np.median(lengths[~alone])) if (~alone).any() else 1.0
    return lengths


def grow_region(faces: np.ndarray, region: np.ndarray) -> np.ndarray:
    """(N,) bool: ``region`` (N,) bool and every vertex one edge from it."""
    grown = np.asarray(region, dtype=bool).copy()
    touching = grown[faces[:, 0]] | grown[faces[:, 1]] | grown[faces[:, 2]]
    grown[faces[np.flatnonzero(touching)].ravel()] = True
    return grown
