"""Vertices that a file split only for its format, joined back (and split again to save).

STL lists three corners per triangle, and Blender's PLY exporter writes one vertex per distinct
(vertex, UV) pair, so such files load in pieces a brush would tear apart. :func:`weld` joins
vertices at exactly the same position (bit for bit), in order of first appearance, with a hash
table in numba code (one pass; sorting took several times longer). :func:`split_at_seams` does
the opposite for a format with one texture coordinate per vertex.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["split_at_seams", "weld"]


def weld(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Join vertices at the same position (bit for bit, -0.0 as 0.0; float32 ``points`` (N, 3)
    compared as float32): the welded vertex of each vertex (N,) int64, and the vertex each
    welded one comes from (W,) int64 (its first appearance, increasing)."""
    if len(points) >= 2**31:
        raise ValueError(f"too many vertices to weld ({len(points)})")
    first = _first_equal_rows(_bits(points))
    new = first == np.arange(len(points))
    return (np.cumsum(new) - 1)[first], np.flatnonzero(new)


def split_at_seams(
    faces: np.ndarray, uv: np.ndarray, uv_faces: np.ndarray, n_vertices: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One texture coordinate per vertex, for a format without per-corner ones (PLY): a vertex
    keeps its number and its first textured corner's; each other (vertex, texture coordinate)
    pair becomes a new vertex after the originals, in order of first appearance. Returns the
    vertex each written vertex copies (V,) (``arange(n_vertices)`` first), its texture
    coordinate (V, 2) ((0, 0) without one) and the faces (M, 3) on the written vertices."""
    corner_vertex = faces.ravel()
    corner_uv = uv_faces.ravel()
    textured = np.flatnonzero(corner_uv >= 0)
    vertex_uv = np.zeros((n_vertices, 2))
    vertices, first_corner = np.unique(corner_vertex[textured], return_index=True)
    vertex_uv[vertices] = uv[corner_uv[textured[first_corner]]]
    value = uv[corner_uv[textured]]
    own = vertex_uv[corner_vertex[textured]]
    other = textured[(_bits(value) != _bits(own)).any(axis=1)]
    written = corner_vertex.copy()
    if len(other):
        keys = np.concatenate(
            [corner_vertex[other, None].astype(np.uint64), _bits(uv[corner_uv[other]])], axis=1
        )
        first = _first_equal_rows(keys)
        new = first == np.arange(len(first))
        number = np.cumsum(new) - 1
        written[other] = n_vertices + number[first]
        extra = other[new]
        source = np.concatenate([np.arange(n_vertices), corner_vertex[extra]])
        vertex_uv = np.concatenate([vertex_uv, uv[corner_uv[extra]]])
    else:
        source = np.arange(n_vertices)
    return source, vertex_uv, written.reshape(faces.shape)


def _bits(values: np.ndarray) -> np.ndarray:
    """(N, A) float values as the bits of their float32 (uint32) or else float64 (uint64)
    value, -0.0 counted as 0.0: equal keys for equal values."""
    if values.dtype == np.float32:
        return np.ascontiguousarray(values + np.float32(0.0)).view(np.uint32)
    return np.ascontiguousarray(np.asarray(values, dtype=np.float64) + 0.0).view(np.uint64)


@numba.njit(cache=True, nogil=True)
def _first_equal_rows(keys: np.ndarray) -> np.ndarray:
    """For each row of ``keys`` (N, W) unsigned ints, the first row equal to it (N,) int64: one
    pass through an open-addressing hash table of 2N slots or more (short probe chains even
    when every row is distinct; a growing table measured 1.4x slower)."""
    n = keys.shape[0]
    size = 16
    while size < 2 * n:
        size *= 2
    mask = np.uint64(size - 1)
    table = np.full(size, -1, dtype=np.int32)  # int32: half the memory to miss in the cache
    first = np.empty(n, dtype=np.int64)
    for i in range(n):
        h = np.uint64(0x9E3779B97F4A7C15)
        for j in range(keys.shape[1]):  # a splitmix64-style mix of each word
            h ^= np.uint64(keys[i, j]) + np.uint64(0x9E3779B97F4A7C15) + (h << np.uint64(6))
            h ^= h >> np.uint64(31)
            h *= np.uint64(0xBF58476D1CE4E5B9)
            h ^= h >> np.uint64(29)
        slot = h & mask
        while True:
            row = table[slot]
            if row < 0:
                table[slot] = i
                first[i] = i
                break
            same = True
            for j in range(keys.shape[1]):
                if keys[row, j] != keys[i, j]:
                    same = False
                    break
            if same:
                first[i] = row
                break
            slot = (slot + np.uint64(1)) & mask
    return first
