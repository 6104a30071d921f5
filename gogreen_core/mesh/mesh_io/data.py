"""The mesh as plain arrays, the error every reader and writer raises, and the mesh's checks."""

from __future__ import annotations

import copy
from dataclasses import dataclass

import numpy as np

__all__ = ["MAX_INDEX", "MeshData", "MeshFileError", "first_non_finite", "validate_mesh"]

#: Larger 1-based indices cannot be real (and would overflow int64 arrays).
MAX_INDEX = 2**53


class MeshFileError(ValueError):
    """A mesh file could not be read or written; the message names the file and the problem."""


@dataclass
class MeshData:
    """A triangle mesh as plain arrays: ``vertices`` (N, 3) float64 in the file's units and
    order; ``faces`` (M, 3) int64, vertex indices from 0, counter-clockwise seen from outside;
    ``uv`` (T, 2) float64 texture coordinates (OBJ ``vt``, a PLY's ``s, t``) with ``uv_faces``
    (M, 3) int64, each corner's row of ``uv`` (a row of -1: a face without), or both None;
    ``source``: the path it was loaded from, or None."""

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray | None = None
    uv_faces: np.ndarray | None = None
    source: str | None = None

    def __post_init__(self) -> None:
        self.vertices = np.asarray(self.vertices, dtype=np.float64)
        self.faces = np.asarray(self.faces, dtype=np.int64)
        if self.vertices.ndim != 2 or self.vertices.shape[1] != 3:
            raise ValueError(f"vertices must have shape (N, 3), got {self.vertices.shape}")
        if self.faces.ndim != 2 or self.faces.shape[1] != 3:
            raise ValueError(f"faces must have shape (M, 3), got {self.faces.shape}")
        if (self.uv is None) != (self.uv_faces is None):
            raise ValueError("uv and uv_faces must be given together")
        if self.uv is not None:
            self.uv = np.asarray(self.uv, dtype=np.float64)
            self.uv_faces = np.asarray(self.uv_faces, dtype=np.int64)

    def copy(self) -> MeshData:
        """A deep copy."""
        return copy.deepcopy(self)


def first_non_finite(rows: np.ndarray) -> int | None:
    """The first row of ``rows`` (N, k) with a non-finite value, or None."""
    finite = np.isfinite(rows).all(axis=1)
    return None if finite.all() else int(np.argmin(finite))


def validate_mesh(mesh: MeshData, name: str) -> None:
    """Raise MeshFileError unless ``mesh`` is a usable triangle mesh."""
    v, f = mesh.vertices, mesh.faces
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
        raise MeshFileError(f"{name}: no vertices")
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise MeshFileError(f"{name}: no faces")
    if (bad := first_non_finite(v)) is not None:
        raise MeshFileError(f"{name}: vertex {bad} has a non-finite coordinate {v[bad].tolist()}")
    outside = (f < 0) | (f >= len(v))
    if outside.any():
        row, col = (int(i[0]) for i in np.nonzero(outside))
        raise MeshFileError(
            f"{name}: face {row} references vertex {int(f[row, col])} "
            f"but the mesh has {len(v)} vertices"
        )
    if mesh.uv is None:
        return
    uv, uvf = mesh.uv, mesh.uv_faces
    assert uvf is not None  # set together with uv (__post_init__)
    if uv.ndim != 2 or uv.shape[1] != 2 or not np.isfinite(uv).all():
        raise MeshFileError(f"{name}: texture coordinates must be finite (T, 2) values")
    if uvf.shape != f.shape:
        raise MeshFileError(f"{name}: uv_faces has shape {uvf.shape} but there are {len(f)} faces")
    partial = (uvf < 0).any(axis=1) & (uvf >= 0).any(axis=1)
    if partial.any() or (uvf < -1).any() or (uvf >= len(uv)).any():
        raise MeshFileError(
            f"{name}: uv_faces must hold rows of -1 or indices below {len(uv)} (texture "
            "coordinates)"
        )
