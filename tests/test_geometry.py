"""Incremental vertex normals and picking of the SurfaceIndex (gogreen_core.geometry)."""

from __future__ import annotations

import numpy as np
import pytest

from gogreen_core.geometry import FaceAdjacency, SurfaceIndex, vertex_normals
from gogreen_core.shapes import default_model


@pytest.fixture(scope="module")
def pebble():
    return default_model(4)


def brush_move(vertices, center_index, radius, seed=0):
    """Vertices moved randomly within ``radius`` of one vertex, and their indices."""
    rng = np.random.default_rng(seed)
    changed = np.flatnonzero(np.linalg.norm(vertices - vertices[center_index], axis=1) < radius)
    moved = vertices.copy()
    moved[changed] += 0.02 * rng.normal(size=(len(changed), 3))
    return moved, changed


def test_adjacency_lists_each_vertex_faces_in_order(pebble):
    vertices, faces = pebble
    adjacency = FaceAdjacency(faces, len(vertices))
    for v in (0, 17, len(vertices) - 1):
        expected = np.flatnonzero(np.any(faces == v, axis=1))
        got = adjacency.face_ids[adjacency.offsets[v] : adjacency.offsets[v + 1]]
        assert np.array_equal(got, expected)


def test_incremental_normals_equal_full_recompute_bit_for_bit(pebble):
    vertices, faces = pebble
    normals = SurfaceIndex(vertices, faces)
    assert np.array_equal(normals.normals, vertex_normals(vertices, faces))
    moved, changed = brush_move(vertices, 5, 0.6)
    updated = normals.update(moved, changed)
    full = vertex_normals(moved, faces)
    assert np.array_equal(normals.normals, full)  # the rows left alone did not change either
    ring = np.unique(faces[np.any(np.isin(faces, changed), axis=1)])
    assert np.array_equal(updated, ring)
    assert len(updated) > len(changed)
    # a second event elsewhere, from the updated state
    moved2, changed2 = brush_move(moved, 40, 0.5, seed=1)
    normals.update(moved2, changed2)
    assert np.array_equal(normals.normals, vertex_normals(moved2, faces))


def test_isolated_vertex_normal_matches_full():
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5]])
    faces = np.array([[0, 1, 2]])
    normals = SurfaceIndex(np.zeros((4, 3)), faces)
    normals.update(vertices, np.arange(4))
    assert np.array_equal(normals.normals, vertex_normals(vertices, faces))


def test_bad_meshes_and_updates_are_refused(pebble):
    with pytest.raises(ValueError, match="index vertices"):
        FaceAdjacency(np.array([[0, 1, 3]]), 3)
    with pytest.raises(ValueError, match="shape"):
        FaceAdjacency(np.array([0, 1, 2]), 3)
    with pytest.raises(ValueError, match="index vertices"):
        SurfaceIndex(np.zeros((3, 3)), np.array([[0, 1, 3]]))
    vertices, faces = pebble
    index = SurfaceIndex(vertices, faces)
    with pytest.raises(ValueError, match="changed must index"):
        index.update(vertices, np.array([len(vertices)]))
    with pytest.raises(ValueError, match="shape"):
        index.update(vertices[:-1], np.array([0]))


def brute_force_pick(vertices, faces, origin, direction):
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    e1, e2 = b - a, c - a
    p = np.cross(direction, e2)
    det = np.einsum("ij,ij->i", e1, p)
    with np.errstate(all="ignore"):
        inv = 1.0 / det
        s = origin - a
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = (q @ direction) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
    ok = (det != 0) & (u >= 0) & (u <= 1) & (v >= 0) & (u + v <= 1) & (t >= 0)
    if not ok.any():
        return None
    best = np.flatnonzero(ok)[np.argmin(t[ok])]
    return best, origin + t[best] * direction


def test_pick_matches_brute_force_after_the_mesh_moves(pebble):
    vertices, faces = pebble
    index = SurfaceIndex(vertices, faces)
    moved, changed = brush_move(vertices, 5, 0.8)
    moved[changed] += 0.3 * (moved[changed] - vertices[5])  # far beyond the old boxes
    index.update(moved, changed)
    rng = np.random.default_rng(3)
    hits = 0
    for _ in range(100):
        origin = rng.normal(size=3) * 3
        direction = rng.normal(size=3) * 0.3 - origin
        got = index.pick(moved, origin, direction)
        expected = brute_force_pick(moved, faces, origin, direction)
        assert (got is None) == (expected is None)
        if got is not None:
            hits += 1
            assert got[0] == expected[0]
            assert np.allclose(got[1], expected[1], atol=1e-12)
    assert hits > 50


def test_pick_misses_and_bad_rays(pebble):
    vertices, faces = pebble
    index = SurfaceIndex(vertices, faces)
    assert index.pick(vertices, np.array([0.0, 0.0, 10.0]), np.array([0.0, 0.0, 1.0])) is None
    with pytest.raises(ValueError, match="nonzero"):
        index.pick(vertices, np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="finite"):
        index.pick(vertices, np.array([np.nan, 0, 0]), np.ones(3))
