"""The remeshing's compiled connectivity gives what the sorting builders of
:mod:`gogreen_core.mesh.topology` give, equal (the remesh's choices follow their orders)."""

import numpy as np
import pytest

from gogreen_core.mesh._remesh_kernels import patch_connectivity
from gogreen_core.mesh.shapes import icosphere, open_tube
from gogreen_core.mesh.topology import mesh_edges, vertex_neighbours


def _meshes() -> list[tuple[np.ndarray, int]]:
    sphere = icosphere(2)[1]
    tube = open_tube(rings=6, around=10)[1]
    # a fin: three faces on one edge, a face of its own, a vertex of no face
    odd = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4], [5, 6, 7]])
    return [(sphere, int(sphere.max()) + 1), (tube, int(tube.max()) + 1), (odd, 9)]


@pytest.mark.parametrize(("faces", "n"), _meshes())
def test_patch_connectivity_equals_the_sorting_builders(faces, n):
    faces = np.ascontiguousarray(np.random.default_rng(3).permutation(faces), dtype=np.int64)
    edges = mesh_edges(faces, n)
    neighbours = vertex_neighbours(edges, n)
    ends, face_edges, count, edge_faces, offsets, around = patch_connectivity(faces, n)
    assert np.array_equal(ends, edges.ends) and np.array_equal(face_edges, edges.face_edges)
    assert np.array_equal(count, edges.face_count)
    assert np.array_equal(offsets, neighbours.offsets)
    assert np.array_equal(around, neighbours.neighbours)
    for e in np.flatnonzero(count == 2):  # the two faces of an inner edge, in face order
        assert list(edge_faces[e]) == list(np.flatnonzero((face_edges == e).any(axis=1)))
