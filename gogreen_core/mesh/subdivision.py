"""Loop subdivision of a triangle mesh (Loop 1987), of all of it or of some of its faces.

Each refined face becomes four; each split edge gets a new vertex numbered after the old ones
(old vertices keep their numbers). Loop's rules: an edge vertex at 3/8 (a + b) + 1/8 (c + d)
inside the refined region, the midpoint on a boundary or the region's rim; an old vertex whose
faces are all refined at (1 − nβ) v + β Σ neighbours, β = (5/8 − (3/8 + cos(2π/n)/4)²)/n, or
3/4 v + 1/8 (b₁ + b₂) on a boundary; others stay. A vertex mask m ∈ [0, 1] holds vertices as a
brush does: an old vertex moves (1 − m) of its step, an edge vertex (1 − max(m_a, m_b)).

A partial refinement stays watertight (red-green): a face next to the region with one split
side becomes two triangles, with two three, with three it is refined. Texture coordinates are
per face corner: a split side gets the midpoint of its own corners' UVs, so seams stay seams.
The result depends on the input arrays alone (numpy's sorts, ordered sums): it replays bit for
bit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import cast

import numpy as np

from gogreen_core.mesh.mesh_state import MeshSnapshot
from gogreen_core.mesh.topology import MeshEdges, mesh_edges

__all__ = [
    "MASK_THRESHOLD",
    "PreparedSubdivision",
    "loop_subdivide",
    "prepare_subdivision",
]

#: A face is "not masked" (refined by a subdivision of the unmasked part) when every corner's
#: mask value is below this.
MASK_THRESHOLD = 0.5


def _gathered_sum(index: np.ndarray, columns: np.ndarray, rows: np.ndarray, n: int) -> np.ndarray:
    """Σ points[rows] (K,) by ``index`` (K,) into (n, 3), summed in order (reproducible);
    ``columns`` (3, N) are the points' coordinates, each contiguous (faster gathers)."""
    out = np.empty((n, 3))
    for axis in range(3):
        out[:, axis] = np.bincount(index, columns[axis][rows], minlength=n)
    return out


def _old_positions(
    vertices: np.ndarray,
    faces: np.ndarray,
    edges: MeshEdges,
    refine: np.ndarray,
    free: np.ndarray,
) -> np.ndarray:
    """Loop's even rule for the vertices whose faces are all refined; the others stay."""
    n = len(vertices)
    both, other = edges.ends.T.ravel(), edges.ends[:, ::-1].T.ravel()  # each edge both ways
    columns = np.ascontiguousarray(vertices.T)
    valence = np.bincount(both, minlength=n)
    around = _gathered_sum(both, columns, other, n)
    rim = np.concatenate([edges.face_count == 1] * 2)
    rim_count = np.bincount(both[rim], minlength=n)
    rim_sum = _gathered_sum(both[rim], columns, other[rim], n)
    odd = np.zeros(n, dtype=bool)
    odd[edges.ends[edges.face_count > 2].ravel()] = True
    odd[faces[~refine].ravel()] = True  # next to an unrefined face: stays
    interior = ~odd & (rim_count == 0) & (valence >= 3)
    boundary = ~odd & (rim_count == 2)
    k = np.maximum(valence, 1).astype(np.float64)  # Loop's β (the module docstring)
    beta = ((0.625 - (0.375 + 0.25 * np.cos(2.0 * np.pi / k)) ** 2) / k)[:, None]
    loop = np.where(
        interior[:, None],
        (1.0 - valence[:, None] * beta) * vertices + beta * around,
        np.where(boundary[:, None], 0.75 * vertices + 0.125 * rim_sum, vertices),
    )
    return cast(np.ndarray, vertices + free[:, None] * (loop - vertices))


def _edge_positions(
    vertices: np.ndarray,
    faces: np.ndarray,
    edges: MeshEdges,
    refine: np.ndarray,
    split: np.ndarray,
    free: np.ndarray,
) -> np.ndarray:
    """Loop's odd rule for the split edges inside the refined region; midpoints elsewhere."""
    count = len(edges)
    opposite = faces[:, [2, 0, 1]].ravel()  # the corner facing side k (corner k to k + 1)
    columns = np.ascontiguousarray(vertices.T)
    opposite_sum = _gathered_sum(edges.face_edges.ravel(), columns, opposite, count)
    refined_sides = np.bincount(edges.face_edges[refine].ravel(), minlength=count)
    inside = (edges.face_count == 2) & (refined_sides == 2)
    chosen = np.flatnonzero(split)
    a, b = edges.ends[chosen, 0], edges.ends[chosen, 1]
    middle = 0.5 * (vertices[a] + vertices[b])
    loop = 0.375 * (vertices[a] + vertices[b]) + 0.125 * opposite_sum[chosen]
    weight = np.where(inside[chosen], np.minimum(free[a], free[b]), 0.0)
    return cast(np.ndarray, middle + weight[:, None] * (loop - middle))


def _split_faces(
    corners: np.ndarray, middles: np.ndarray, refine: np.ndarray, splits: np.ndarray
) -> np.ndarray:
    """Child triangles of each face (``corners`` (M, 3): vertices or UV rows), grouped by
    parent: 4 for a refined face, 1 + its split sides for the others; ``middles`` (M, 3): the
    new point of side k (corner k to k + 1) where it is split."""
    count = np.where(refine, 4, splits + 1)
    start = np.cumsum(count) - count
    out = np.empty((int(count.sum()), 3), dtype=np.int64)
    whole = ~refine & (splits == 0)
    out[start[whole]] = corners[whole]
    r = np.flatnonzero(refine)
    (c0, c1, c2), (m0, m1, m2) = corners[r].T, middles[r].T
    for child, triangle in enumerate(((c0, m0, m2), (c1, m1, m0), (c2, m2, m1), (m0, m1, m2))):
        out[start[r] + child] = np.stack(triangle, axis=1)
    for n_split in (1, 2):
        f = np.flatnonzero(~refine & (splits == n_split))
        split_sides = middles[f] >= 0
        # rotate each face so that side 0 is its split side (one) or its whole side (two)
        first = np.argmax(split_sides if n_split == 1 else ~split_sides, axis=1)
        turn = (first[:, None] + np.arange(3)) % 3
        (c0, c1, c2) = np.take_along_axis(corners[f], turn, axis=1).T
        (m0, m1, m2) = np.take_along_axis(middles[f], turn, axis=1).T
        children: tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]
        if n_split == 1:
            children = ((c0, m0, c2), (m0, c1, c2))
        else:
            children = ((c0, c1, m1), (c0, m1, m2), (m1, c2, m2))
        for child, triangle in enumerate(children):
            out[start[f] + child] = np.stack(triangle, axis=1)
    return out


def _subdivided_uv(
    uv: np.ndarray, uv_faces: np.ndarray, split_sides: np.ndarray, refine: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """New UV rows (one midpoint per distinct pair of a split side's corner UVs) and the
    children's UV corners."""
    rows = len(uv)
    textured = uv_faces[:, 0] >= 0
    following = np.roll(uv_faces, -1, axis=1)
    need = split_sides & textured[:, None]
    key = np.minimum(uv_faces, following) * np.int64(max(rows, 1)) + np.maximum(uv_faces, following)
    pairs, slot = np.unique(key[need], return_inverse=True)
    middles = np.full(uv_faces.shape, -1, dtype=np.int64)
    middles[need] = rows + slot.ravel()
    a, b = pairs // max(rows, 1), pairs % max(rows, 1)
    new_uv = np.concatenate([uv, 0.5 * (uv[a] + uv[b])])
    splits = split_sides.sum(axis=1)
    return new_uv, _split_faces(uv_faces, middles, refine, splits)


def loop_subdivide(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    refine: np.ndarray | None = None,
    mask: np.ndarray | None = None,
    uv: np.ndarray | None = None,
    uv_faces: np.ndarray | None = None,
    edges: MeshEdges | None = None,
    progress: Callable[[float], None] | None = None,
) -> MeshSnapshot:
    """One step of Loop subdivision (see the module docstring) of ``vertices`` (N, 3) float64,
    ``faces`` (M, 3) int64: the faces ``refine`` (M,) bool (default all), ``mask`` (N,) in
    [0, 1] (default 0; an edge vertex gets the mean of its ends'), ``uv`` (T, 2) with
    ``uv_faces`` (M, 3) (-1 rows: untextured), ``edges`` (their
    :func:`~gogreen_core.mesh.topology.mesh_edges` when known); ``progress`` is called with the
    fraction done (it may raise to cancel). Returns the new arrays (uv None without)."""
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    n = len(vertices)
    report = progress or (lambda _fraction: None)
    report(0.0)
    if edges is None:
        edges = mesh_edges(faces, n)
    report(0.35)
    refine = np.ones(len(faces), dtype=bool) if refine is None else np.array(refine, dtype=bool)
    split = np.zeros(len(edges), dtype=bool)
    split[edges.face_edges[refine].ravel()] = True
    split_sides = split[edges.face_edges]
    refine |= split_sides.all(axis=1)  # all three sides split: refined with the region
    m = np.zeros(n) if mask is None else np.asarray(mask, dtype=np.float64)
    free = 1.0 - m
    old = _old_positions(vertices, faces, edges, refine, free)
    report(0.55)
    new = _edge_positions(vertices, faces, edges, refine, split, free)
    report(0.75)
    number = np.cumsum(split) - 1 + n  # the new vertex of each split edge
    middles = np.where(split_sides, number[edges.face_edges], -1)
    new_faces = _split_faces(faces, middles, refine, split_sides.sum(axis=1))
    report(0.85)
    ends = edges.ends[split]
    new_mask = np.concatenate([m, 0.5 * (m[ends[:, 0]] + m[ends[:, 1]])])
    new_uv = new_uv_faces = None
    if uv is not None and uv_faces is not None:
        new_uv, new_uv_faces = _subdivided_uv(
            np.asarray(uv, dtype=np.float64),
            np.asarray(uv_faces, dtype=np.int64),
            split_sides,
            refine,
        )
    report(1.0)
    return MeshSnapshot(np.concatenate([old, new]), new_faces, new_mask, new_uv, new_uv_faces)


def _same_bits(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    if a is None or b is None or a.dtype != b.dtype or a.shape != b.shape:
        return a is b
    return np.array_equal(
        np.ascontiguousarray(a).view(np.uint8), np.ascontiguousarray(b).view(np.uint8)
    )


@dataclass(frozen=True)
class PreparedSubdivision:
    """A subdivision computed ahead (off the GUI thread) of the mesh ``source``, for
    :meth:`Sculptor.subdivide` to adopt if the mesh is still ``source``."""

    source: MeshSnapshot
    unmasked_only: bool
    result: MeshSnapshot

    def made_from(self, mesh: MeshSnapshot) -> bool:
        """``mesh`` holds the arrays this was made from, bit for bit."""
        names = ("vertices", "faces", "mask", "uv", "uv_faces")
        return all(_same_bits(getattr(self.source, k), getattr(mesh, k)) for k in names)


def prepare_subdivision(
    source: MeshSnapshot,
    unmasked_only: bool = False,
    progress: Callable[[float], None] | None = None,
    edges: MeshEdges | None = None,
) -> PreparedSubdivision:
    """Loop subdivision of the mesh ``source``, or of its unmasked faces, mask and UVs carried
    along; the result is read-only and compact (the sculptor keeps it for undo)."""
    faces = np.asarray(source.faces, dtype=np.int64)
    uv_faces = None if source.uv_faces is None else np.asarray(source.uv_faces, dtype=np.int64)
    refine = np.all(source.mask[faces] < MASK_THRESHOLD, axis=1) if unmasked_only else None
    done = loop_subdivide(
        source.vertices,
        faces,
        refine=refine,
        mask=source.mask,
        uv=source.uv,
        uv_faces=uv_faces,
        edges=edges,
        progress=progress,
    )
    result = done.frozen()
    return PreparedSubdivision(source, bool(unmasked_only), result)
