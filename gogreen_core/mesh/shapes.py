"""Procedural meshes as plain arrays: icospheres, the model the app opens on start (generated
in 0.02 s rather than shipped), and the flat sheet and long tube of the paper's figures. The
icosphere is built here, not by trimesh, so that the default model (whose SHA-256 a recorded
session stores) cannot change with a trimesh release.
"""

from __future__ import annotations

import itertools

import numpy as np

from gogreen_core.mesh.subdivision import _split_faces
from gogreen_core.mesh.topology import mesh_edges
from gogreen_core.validation import check_integer

__all__ = ["default_model", "flat_sheet", "icosphere", "open_tube"]


def _icosahedron() -> tuple[np.ndarray, np.ndarray]:
    """Unit icosahedron: vertices (12, 3) on the unit sphere, outward faces (20, 3)."""
    phi = (1.0 + np.sqrt(5.0)) / 2.0
    corners = []
    for s, t in itertools.product((-1.0, 1.0), repeat=2):  # cyclic permutations of (0, ±1, ±φ)
        corners += [(0.0, s, t * phi), (s, t * phi, 0.0), (t * phi, 0.0, s)]
    vertices = np.array(corners)
    # The faces are the triples of mutual nearest neighbours (edge length 2 before scaling).
    faces = []
    for a, b, c in itertools.combinations(range(12), 3):
        sides = [np.linalg.norm(vertices[i] - vertices[j]) for i, j in ((a, b), (b, c), (c, a))]
        if np.allclose(sides, 2.0):
            normal = np.cross(vertices[b] - vertices[a], vertices[c] - vertices[a])
            faces.append((a, b, c) if normal @ vertices[a] > 0 else (a, c, b))
    return vertices / np.linalg.norm(vertices, axis=1, keepdims=True), np.array(faces)


def _subdivide(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Split each triangle in four at its edge midpoints, projected onto the unit sphere (old
    vertices keep their indices, orientation is kept)."""
    edges = mesh_edges(faces, len(vertices))
    midpoints = vertices[edges.ends[:, 0]] + vertices[edges.ends[:, 1]]
    midpoints /= np.linalg.norm(midpoints, axis=1, keepdims=True)
    every = np.ones(len(faces), dtype=bool)
    children = _split_faces(faces, len(vertices) + edges.face_edges, every, 3 * every)
    return np.concatenate([vertices, midpoints]), children


def icosphere(subdivisions: int = 4) -> tuple[np.ndarray, np.ndarray]:
    """A closed unit sphere of near-equilateral triangles: an icosahedron whose triangles are
    split in four ``subdivisions`` times (0 to 8). Returns vertices (10·4^s + 2, 3) float64 and
    faces (20·4^s, 3) int64, counter-clockwise seen from outside."""
    vertices, faces = _icosahedron()
    for _ in range(check_integer("subdivisions", subdivisions, low=0, high=8)):
        vertices, faces = _subdivide(vertices, faces)
    return vertices, faces.astype(np.int64)


# (direction, relative amplitude, angular width in radians) of the default model's bumps
_BUMPS = (
    ((0.0, 0.0, 1.0), 0.22, 0.55),
    ((0.8, 0.3, 0.5), 0.12, 0.45),
    ((-0.7, 0.5, 0.2), 0.10, 0.50),
    ((0.1, -0.9, 0.3), 0.08, 0.40),
    ((-0.3, -0.4, -0.85), -0.10, 0.70),
)
_STRETCH = (1.15, 1.0, 0.9)


def default_model(subdivisions: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """The smooth pebble the app opens on start: an icosphere's vertices moved along their radii
    by smooth Gaussian bumps around a few fixed directions (the radius stays above 0.9: no
    self-intersection), stretched by (1.15, 1, 0.9), its bounding box centred at the origin.
    Returns vertices (N, 3) float64, about 2.4 × 2.1 × 1.9 units across, and closed, outward
    faces (M, 3) int64; 6 subdivisions (the default) give 40,962 vertices and 81,920 faces."""
    sphere, faces = icosphere(subdivisions)
    radius = np.ones(len(sphere))
    for direction, amplitude, width in _BUMPS:
        d = np.asarray(direction) / np.linalg.norm(direction)
        radius += amplitude * np.exp((sphere @ d - 1.0) / width**2)
    shaped = sphere * radius[:, None] * np.asarray(_STRETCH)
    return shaped - 0.5 * (shaped.min(axis=0) + shaped.max(axis=0)), faces


def _quads_as_triangles(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Triangles (2k, 3) of the quads a b c d (each (k,)), split along a c."""
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def flat_sheet(n: int = 201) -> tuple[np.ndarray, np.ndarray]:
    """A flat n × n grid over [-1, 1]² in z = 0: vertices (n², 3) float64 and faces
    (2 (n − 1)², 3) int64 (the wrinkle brush's measuring sheet, paper Fig. 10)."""
    x = np.linspace(-1.0, 1.0, n)
    grid_x, grid_y = np.meshgrid(x, x, indexing="ij")
    vertices = np.stack([grid_x.ravel(), grid_y.ravel(), np.zeros(n * n)], axis=1)
    index = np.arange(n * n).reshape(n, n)
    return vertices, _quads_as_triangles(
        index[:-1, :-1].ravel(), index[1:, :-1].ravel(), index[1:, 1:].ravel(),
        index[:-1, 1:].ravel(),
    )  # fmt: skip


def open_tube(
    rings: int = 480, around: int = 64, length: float = 24.0
) -> tuple[np.ndarray, np.ndarray]:
    """A long open tube of radius 1 along z, ``length`` long: vertices (rings · around, 3)
    float64 and faces (2 (rings − 1) around, 3) int64 (the long shape of paper Fig. 7)."""
    angle = np.linspace(0.0, 2 * np.pi, around, endpoint=False)
    z = np.linspace(-length / 2, length / 2, rings)
    zz, aa = np.meshgrid(z, angle, indexing="ij")
    vertices = np.stack([np.cos(aa.ravel()), np.sin(aa.ravel()), zz.ravel()], axis=1)
    index = np.arange(rings * around).reshape(rings, around)
    j0, j1 = np.arange(around), np.roll(np.arange(around), -1)
    return vertices, _quads_as_triangles(
        index[:-1][:, j0].ravel(), index[1:][:, j0].ravel(), index[1:][:, j1].ravel(),
        index[:-1][:, j1].ravel(),
    )  # fmt: skip
