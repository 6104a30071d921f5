"""Procedural meshes: closed, outward, well shaped, deterministic."""

from __future__ import annotations

import itertools
import time

import numpy as np
import pytest

from gogreen_core.mesh.shapes import default_model, icosphere


def directed_edges(faces: np.ndarray) -> np.ndarray:
    """(3M, 2) edges, each running the way its face turns."""
    return np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])


def assert_closed_and_consistently_oriented(faces: np.ndarray) -> None:
    edges = directed_edges(faces)
    _, undirected = np.unique(np.sort(edges, axis=1), axis=0, return_counts=True)
    assert np.all(undirected == 2)  # every edge shared by exactly two faces: closed, manifold
    _, directed = np.unique(edges, axis=0, return_counts=True)
    assert np.all(directed == 1)  # the two faces run along it in opposite directions


def signed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def corner_angles(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(M, 3) interior angles in degrees."""
    tri = vertices[faces]
    out = []
    for k in range(3):
        u = tri[:, (k + 1) % 3] - tri[:, k]
        w = tri[:, (k + 2) % 3] - tri[:, k]
        cos = np.einsum("ij,ij->i", u, w) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        out.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.stack(out, axis=1)


@pytest.mark.parametrize("subdivisions", [0, 1, 2, 4])
def test_icosphere_is_a_closed_outward_sphere(subdivisions):
    vertices, faces = icosphere(subdivisions)
    assert vertices.dtype == np.float64 and faces.dtype == np.int64
    assert vertices.shape == (10 * 4**subdivisions + 2, 3)
    assert faces.shape == (20 * 4**subdivisions, 3)
    assert np.allclose(np.linalg.norm(vertices, axis=1), 1.0)
    assert len(np.unique(vertices.round(12), axis=0)) == len(vertices)  # no duplicates
    assert_closed_and_consistently_oriented(faces)
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert np.all(np.einsum("ij,ij->i", normals, tri.mean(axis=1)) > 0)  # outward


def test_icosphere_volume_converges_to_the_ball():
    ball = 4 / 3 * np.pi
    errors = [ball - signed_volume(*icosphere(s)) for s in range(1, 6)]
    assert all(e > 0 for e in errors)  # inscribed polyhedron, positive (outward) volume
    assert errors[3] / ball < 3e-3  # 4 subdivisions
    assert all(b < a / 3.5 for a, b in itertools.pairwise(errors))  # ~ h², ×1/4


def test_icosphere_triangles_are_well_shaped():
    angles = corner_angles(*icosphere(5))
    assert angles.min() > 50 and angles.max() < 75


BAD_ARGUMENTS = [
    ((-1,), "subdivisions"),
    ((9,), "subdivisions"),
    ((1.5,), "subdivisions"),
]


@pytest.mark.parametrize(("args", "message"), BAD_ARGUMENTS)
def test_icosphere_rejects_bad_arguments(args, message):
    with pytest.raises(ValueError, match=message):
        icosphere(*args)


@pytest.fixture(scope="module")
def model():
    start = time.perf_counter()
    vertices, faces = default_model()
    return vertices, faces, time.perf_counter() - start


def test_default_model_is_deterministic_and_quick(model):
    vertices, faces, seconds = model
    again_vertices, again_faces = default_model()
    assert np.array_equal(vertices.view(np.uint64), again_vertices.view(np.uint64))
    assert np.array_equal(faces, again_faces)
    assert seconds < 1.0  # it is generated at start-up (about 0.02 s)


def test_default_model_is_a_watertight_well_tessellated_pebble(model):
    vertices, faces, _ = model
    assert vertices.dtype == np.float64 and faces.dtype == np.int64
    assert 20_000 <= len(vertices) <= 42_000
    assert_closed_and_consistently_oriented(faces)
    assert len(vertices) - len(faces) * 3 // 2 + len(faces) == 2  # Euler: a sphere
    assert signed_volume(vertices, faces) > 4.0  # outward, and a solid body
    assert np.allclose(vertices.min(axis=0), -vertices.max(axis=0))  # centred
    extent = vertices.max(axis=0) - vertices.min(axis=0)
    assert np.all((extent > 1.5) & (extent < 3.0))  # unit-ish
    assert corner_angles(vertices, faces).min() > 35  # no slivers
    radii = np.linalg.norm(vertices, axis=1)
    assert radii.min() > 0.8 and radii.max() < 1.5
