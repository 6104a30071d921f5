"""Procedural meshes (plain arrays out): spheres for tests and the app's default model.

The default model is generated, not shipped: a subdivided icosahedron pushed along its normals
by a few smooth low-frequency bumps into an organic pebble, then stretched. It takes ~0.2 s,
is deterministic, closed and outward oriented, with well-shaped triangles everywhere.
"""

from __future__ import annotations

import numpy as np
import trimesh

__all__ = ["default_model", "icosphere"]


def icosphere(subdivisions: int = 4, radius: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Closed, outward-oriented sphere: vertices (10·4^s + 2, 3) float64, faces (20·4^s, 3)."""
    if not 0 <= int(subdivisions) <= 8:
        raise ValueError(f"subdivisions must lie in [0, 8] (got {subdivisions})")
    if not (np.isfinite(radius) and radius > 0):
        raise ValueError(f"radius must be finite and > 0 (got {radius})")
    mesh = trimesh.creation.icosphere(subdivisions=int(subdivisions), radius=float(radius))
    return np.array(mesh.vertices, dtype=np.float64), np.array(mesh.faces, dtype=np.int64)


# (direction, amplitude, angular width) of the bumps of the default model
_BUMPS = (
    ((0.0, 0.0, 1.0), 0.22, 0.55),
    ((0.8, 0.3, 0.5), 0.12, 0.45),
    ((-0.7, 0.5, 0.2), 0.10, 0.50),
    ((0.1, -0.9, 0.3), 0.08, 0.40),
    ((-0.3, -0.4, -0.85), -0.10, 0.70),
)


def default_model(subdivisions: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """The app's start-up model (40,962 vertices at the default 6 subdivisions), centered at
    the origin, about 2 units across: vertices (N, 3), faces (M, 3)."""
    vertices, faces = icosphere(subdivisions)
    radius = np.ones(len(vertices))
    for direction, amplitude, width in _BUMPS:
        d = np.asarray(direction) / np.linalg.norm(direction)
        cos_angle = vertices @ d
        radius += amplitude * np.exp((cos_angle - 1.0) / width**2)
    shaped = vertices * radius[:, None] * np.array([1.15, 1.0, 0.9])
    return shaped - 0.5 * (shaped.min(axis=0) + shaped.max(axis=0)), faces
