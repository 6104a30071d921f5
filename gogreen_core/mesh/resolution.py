"""How finely things are sampled for a mesh: its edge length, and the falloff editor's control
points (paper Sec. 5: the spline falloffs are sampled by the mesh resolution, so the smallest
scale the mesh can show can be edited)."""

from __future__ import annotations

import weakref
from typing import TYPE_CHECKING

import numpy as np

from gogreen_core.physics.radial import DEFAULT_SPLINE_RHO
from gogreen_core.validation import check_number

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

#: Mean edge length of each sculptor's mesh as it was first asked for (the edge lengths barely
#: change under a brush; a subdivision makes a new mesh state but the same sculptor: a rough
#: figure is all the falloff editor needs).
_EDGES: weakref.WeakKeyDictionary[Sculptor, tuple[int, float]] = weakref.WeakKeyDictionary()

__all__ = ["edges_per_eps", "mean_edge_length", "spline_abscissae"]


def spline_abscissae(edges_per_eps: float | None = None) -> np.ndarray:
    """Control abscissae ρ (increasing, from 0) of a spline falloff for a mesh whose edges are
    ε / ``edges_per_eps`` long: one control point every two edges up to ρ = 4 (the finest
    scale the mesh can show, paper Sec. 5), at least :data:`DEFAULT_SPLINE_RHO`'s density
    (every 0.25) and at most every 1/16, then the tail 5, 6, 8, 10. None: the default 17."""
    if edges_per_eps is None:
        return DEFAULT_SPLINE_RHO.copy()
    value = check_number("edges_per_eps", edges_per_eps, low=0.0, low_open=True)
    step = min(0.25, max(1.0 / 16.0, 2.0 / value))  # finer (over 69 points): not editable by hand
    return np.concatenate([np.linspace(0.0, 4.0, round(4.0 / step) + 1), (5.0, 6.0, 8.0, 10.0)])


def mean_edge_length(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Mean length (model units) of the triangles' edges, each interior edge counted twice
    (a resolution measure: the falloff editor samples its curves by it)."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    if not len(f):
        return 0.0
    lengths = [np.linalg.norm(v[f[:, (k + 1) % 3]] - v[f[:, k]], axis=1) for k in range(3)]
    return float(np.mean(np.concatenate(lengths)))


def edges_per_eps(sculptor: Sculptor, radius: float) -> float | None:
    """How many mesh edges a brush of ``radius`` (a fraction of the model size) spans: ε over
    the mean edge length of the sculptor's mesh (measured once per face count), None for a mesh
    without edges."""
    faces = len(sculptor.faces)
    cached = _EDGES.get(sculptor)
    if cached is None or cached[0] != faces:
        cached = (faces, mean_edge_length(sculptor.vertices, sculptor.faces))
        _EDGES[sculptor] = cached
    edge = cached[1]
    return radius * sculptor.model_size / edge if edge > 0 else None
