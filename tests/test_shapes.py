"""Procedural meshes: closed, outward, deterministic."""

import numpy as np

from gogreen_core.geometry import mesh_volume, vertex_normals
from gogreen_core.shapes import default_model, icosphere


def edge_use_counts(faces: np.ndarray) -> np.ndarray:
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    return np.unique(edges, axis=0, return_counts=True)[1]


def test_icosphere_is_closed_and_outward():
    vertices, faces = icosphere(4, radius=2.0)
    assert np.all(edge_use_counts(faces) == 2)
    assert np.isclose(mesh_volume(vertices, faces), 4 / 3 * np.pi * 8, rtol=1e-2)
    normals = vertex_normals(vertices, faces)
    assert np.all(np.einsum("ij,ij->i", normals, vertices) > 0)


def test_default_model_is_deterministic_closed_and_centered():
    v1, f1 = default_model(4)
    v2, f2 = default_model(4)
    assert np.array_equal(v1, v2) and np.array_equal(f1, f2)
    assert np.all(edge_use_counts(f1) == 2)
    assert mesh_volume(v1, f1) > 0
    assert np.allclose(v1.min(axis=0), -v1.max(axis=0))
