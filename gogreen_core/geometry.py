"""Small mesh computations the viewport needs every frame (plain arrays in, arrays out)."""

from __future__ import annotations

import numpy as np

__all__ = ["mesh_volume", "vertex_normals"]


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted unit vertex normals (N, 3) of a triangle mesh (faces (M, 3)).

    A vertex in no face (or only in degenerate ones) gets (0, 0, 1)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    face_normals = np.cross(b - a, c - a)  # length = 2 · area: area weighting for free
    n = len(vertices)
    out = np.empty((n, 3))
    flat = faces.ravel()
    for axis in range(3):
        out[:, axis] = np.bincount(flat, np.repeat(face_normals[:, axis], 3), minlength=n)
    norm = np.linalg.norm(out, axis=1)
    empty = norm == 0
    out[empty] = (0.0, 0.0, 1.0)
    norm[empty] = 1.0
    return out / norm[:, None]


def mesh_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Signed volume enclosed by a closed, consistently oriented triangle mesh."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)
