"""The deformation gauge of an anchored (affine) stroke: marks set at the press on the circle of
radius ε around the press point and along a few spokes, moving with the surface. Affine brushes
move the surface mostly along itself, which shading hardly shows; the gauge shows it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["GAUGE_POINTS", "GAUGE_SPOKES", "SPOKE_SAMPLES", "DeformationGauge", "tangent_frame"]

#: Marks on the gauge's loop (the circle of radius ε about the press point).
GAUGE_POINTS = 32
#: Spokes from the press point to the loop (evenly spaced).
GAUGE_SPOKES = 4
#: Points along a spoke, the press point and its loop mark included.
SPOKE_SAMPLES = 5
#: Each mark follows this many nearest vertices (blended by inverse distance).
_NEIGHBOURS = 3
#: Vertices farther than this many ε from the press point are not followed.
_SEARCH = 1.6


def tangent_frame(normal: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit ``normal`` (3,) and two unit tangents completing a right-handed frame."""
    n = np.asarray(normal, dtype=float)
    n = n / (np.linalg.norm(n) or 1.0)
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1)
    return n, t1, np.cross(n, t1)


@dataclass(frozen=True)
class DeformationGauge:
    """Marks that move with the surface, each by the blend of its nearest vertices' motion:
    ``rest`` (M, 3) the marks at the press (the press point, the loop's, the spokes' inner
    points), following ``vertices`` (M, k) with ``weights`` (M, k) from their positions
    ``base`` (M, k, 3) at the press on a mesh of ``count`` vertices."""

    rest: np.ndarray
    vertices: np.ndarray
    weights: np.ndarray
    base: np.ndarray
    count: int

    @classmethod
    def at_press(
        cls, vertices: np.ndarray, center: np.ndarray, normal: np.ndarray, eps: float
    ) -> DeformationGauge | None:
        """The gauge around the press point ``center`` (3,) with surface ``normal`` (3,) at
        radius ``eps`` on the mesh's ``vertices`` (N, 3), its marks set onto the surface by
        the height of the vertices they follow; None when no vertex lies within 1.6 ε."""
        vertices = np.asarray(vertices, dtype=float)
        center = np.asarray(center, dtype=float)
        if not (eps > 0 and np.isfinite(eps)) or len(vertices) == 0:
            return None
        near = np.flatnonzero(
            np.einsum("ij,ij->i", vertices - center, vertices - center) <= (_SEARCH * eps) ** 2
        )
        if len(near) == 0:
            return None
        n, t1, t2 = tangent_frame(normal)
        angles = np.linspace(0.0, 2 * np.pi, GAUGE_POINTS, endpoint=False)
        loop = np.cos(angles)[:, None] * t1 + np.sin(angles)[:, None] * t2
        inner = np.linspace(0.0, 1.0, SPOKE_SAMPLES)[1:-1]
        spokes = (inner[None, :, None] * loop[:: GAUGE_POINTS // GAUGE_SPOKES, None]).reshape(-1, 3)
        planar = center + eps * np.concatenate([np.zeros((1, 3)), loop, spokes])
        k = min(_NEIGHBOURS, len(near))
        gaps = np.linalg.norm(planar[:, None, :] - vertices[near][None], axis=2)  # (M, n)
        order = np.argsort(gaps, axis=1)[:, :k]
        followed = near[order]
        distance = np.take_along_axis(gaps, order, axis=1)
        weights = 1.0 / np.maximum(distance, 1e-9 * eps)
        weights /= weights.sum(axis=1, keepdims=True)
        base = vertices[followed]
        # onto the surface: the height (along n) of the vertices the mark follows
        height = np.einsum("mk,mkj->mj", weights, base) - planar
        rest = planar + np.outer(height @ n, n)
        rest[0] = center  # the press point is on the surface already
        return cls(rest, followed, weights, base.copy(), len(vertices))

    def positions(self, vertices: np.ndarray) -> np.ndarray | None:
        """(M, 3) the marks now on the mesh's ``vertices`` (N, 3); None once it was remeshed."""
        if len(vertices) != self.count:
            return None
        moved = np.asarray(vertices, dtype=float)[self.vertices] - self.base
        marks: np.ndarray = self.rest + np.einsum("mk,mkj->mj", self.weights, moved)
        return marks

    @staticmethod
    def loop(positions: np.ndarray) -> np.ndarray:
        """(GAUGE_POINTS, 3) the loop's marks of :meth:`positions`, in order around it."""
        return positions[1 : 1 + GAUGE_POINTS]

    @staticmethod
    def spokes(positions: np.ndarray) -> np.ndarray:
        """(GAUGE_SPOKES, SPOKE_SAMPLES, 3) the spokes of :meth:`positions`, press point out."""
        centre = positions[0]
        ends = positions[1 : 1 + GAUGE_POINTS : GAUGE_POINTS // GAUGE_SPOKES]
        inner = positions[1 + GAUGE_POINTS :].reshape(GAUGE_SPOKES, SPOKE_SAMPLES - 2, 3)
        starts = np.broadcast_to(centre, (GAUGE_SPOKES, 1, 3))
        return np.concatenate([starts, inner, ends[:, None]], axis=1)
