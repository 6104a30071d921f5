"""The cavity tint's curvature (gogreen_core.mesh.cavity): exact on spheres whatever the sampling,
independent of the resolution, and an event's update equal to a full recomputation."""

from __future__ import annotations

import numpy as np
import pytest

from gogreen_core.mesh.cavity import CavityField
from gogreen_core.mesh.geometry import vertex_normals
from gogreen_core.mesh.shapes import default_model, icosphere
from gogreen_core.mesh.subdivision import loop_subdivide


def field_of(vertices: np.ndarray, faces: np.ndarray) -> CavityField:
    field = CavityField(faces, len(vertices))
    normals = vertex_normals(vertices, faces)
    field.update(vertices, lambda rows: normals[rows])
    return field


@pytest.mark.parametrize("radius", [0.5, 3.0])
def test_a_sphere_bends_by_minus_one_over_its_radius(radius):
    vertices, faces = icosphere(3)
    vertices = radius * vertices / np.linalg.norm(vertices, axis=1, keepdims=True)
    # the chords' normal curvatures: -1/R for every edge, so whatever the vertex normal's error
    values = field_of(vertices, faces).values
    assert values == pytest.approx(-1.0 / radius, rel=2e-2)


def test_a_bump_tints_the_same_on_a_finer_mesh_and_a_hollow_is_positive():
    vertices, faces = icosphere(3)
    fine = loop_subdivide(vertices, faces)
    fine_vertices, fine_faces = fine.vertices, fine.faces

    def bumped(v):
        v = v / np.linalg.norm(v, axis=1, keepdims=True)
        height = -0.1 * np.exp(-((np.linalg.norm(v - [0, 0, 1], axis=1) / 0.3) ** 2))
        return v * (1 + height)[:, None]  # a dent on the top

    coarse_values = field_of(bumped(vertices), faces).values
    fine_values = field_of(bumped(fine_vertices), fine_faces).values
    top = np.argmax(vertices[:, 2])
    fine_top = np.argmax(fine_vertices[:, 2])
    # a hollow bends the other way than a sphere; the same figure at four times the faces
    assert coarse_values[top] > 0 and fine_values[fine_top] > 0
    assert fine_values[fine_top] == pytest.approx(coarse_values[top], rel=0.25)


def test_an_event_recomputes_its_rows_and_their_ring_only_and_equals_a_full_pass():
    vertices, faces = default_model(4)
    field = field_of(vertices, faces)
    moved = np.flatnonzero(vertices[:, 1] > np.percentile(vertices[:, 1], 97))
    after = vertices.copy()
    after[moved] += 0.01 * np.array([0.3, 1.0, 0.2])
    normals = vertex_normals(after, faces)
    rows = field.update(after, lambda r: normals[r], moved)
    assert set(moved) <= set(rows) and len(rows) < 2 * len(moved) + 200
    ring = [
        field.neighbours.neighbours[field.neighbours.offsets[v] : field.neighbours.offsets[v + 1]]
        for v in moved
    ]
    assert np.array_equal(rows, np.unique(np.concatenate([moved, *ring])))
    assert np.allclose(field.values, field_of(after, faces).values, rtol=0, atol=1e-12)
