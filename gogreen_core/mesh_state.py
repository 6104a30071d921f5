"""The mesh being sculpted: its vertices (edited in place), faces and the sizes tools use.

Brush radii, pins and the reach of every point are relative to the model's size (the
bounding-box diagonal at load), so the same settings act alike on a 0.15-unit bunny and a
30-unit ogre.
"""

from __future__ import annotations

import numpy as np

from gogreen_core._expansion import near_segment
from gogreen_core.limits import MAX_REACH
from gogreen_core.validation import ParameterError, check_vector, vector_norm

__all__ = ["MeshState", "check_mesh"]


def check_mesh(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Copies of ``vertices`` (N, 3) float64 and ``faces`` (M, 3) int64, or ValueError: empty,
    not finite, the wrong shape, a face naming a vertex that does not exist."""
    v = np.array(vertices, dtype=np.float64)
    f = np.array(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
        raise ValueError(f"vertices must be a non-empty (N, 3) array (got shape {v.shape})")
    if not np.all(np.isfinite(v)):
        raise ValueError("vertices contain NaN or infinite coordinates")
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces must be an (M, 3) array (got shape {f.shape})")
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        raise ValueError(f"faces reference vertices outside 0..{len(v) - 1}")
    return v, f


class MeshState:
    """Vertices (N, 3) float64, edited in place by the engine alone, and faces (M, 3) int64
    (copied from the arguments); :attr:`model_size` (bounding-box diagonal at load, model
    units) and :attr:`origin` (its centre: the point of the mirror planes)."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.vertices, self.faces = check_mesh(vertices, faces)
        low, high = self.vertices.min(axis=0), self.vertices.max(axis=0)
        self.model_size = float(np.linalg.norm(high - low))
        if not self.model_size > 0:
            raise ValueError("the mesh has zero size (all vertices coincide)")
        if not np.isfinite(self.model_size):
            raise ValueError("the mesh is too large (its size overflows a float)")
        self.origin = 0.5 * (low + high)

    @property
    def reach(self) -> float:
        """How far (model units) a point, a brush centre or a motion may go from the model's
        centre: :data:`~gogreen_core.limits.MAX_REACH` model sizes."""
        return MAX_REACH * self.model_size

    def check_point(self, name: str, point: object) -> np.ndarray:
        """``point`` (3,) if finite and within :attr:`reach` of the model's centre."""
        p = check_vector(name, point)
        distance = vector_norm(p - self.origin)
        if not distance <= self.reach:
            raise ParameterError(
                name,
                f"{name} is too far from the model: {distance:.4g} from its centre, more than "
                f"{MAX_REACH:g} model sizes ({self.reach:.4g})",
            )
        return p

    def rows_near(
        self, center: np.ndarray, step: np.ndarray, radius: float | None, signs: np.ndarray
    ) -> np.ndarray:
        """Indices (n,) of the vertices within ``radius`` of the segment from ``center`` to
        ``center + step``, or of its mirror images (``signs`` (2^k, 3), see
        :func:`~gogreen_core.brushes.mirror_signs`); every vertex for None."""
        if radius is None:
            return np.arange(len(self.vertices))
        reach = np.empty(len(self.vertices), dtype=bool)
        near_segment(self.vertices, center, step, radius, signs, self.origin, reach)
        return np.flatnonzero(reach)
