"""Materials that follow the surface: each stroke turns the material's axes onto the surface
where it starts (``EngineSettings.material_frame == "surface"``).

An artist thinks of fibres and layers relative to the surface they touch, not to the world. With
the "surface" frame a stroke takes a frame F = [t₁ t₂ n] (a proper rotation) at its first event:
n the area normal under the brush (:func:`area_normal`); t₁ the stroke's first motion projected
on the plane ⟂ n (without one: the world axis least aligned with n, projected); t₂ = n × t₁. The
material is turned by F (C' = F·C) once for the whole stroke: re-read per event, the stroke's
own deformation would feed back into the material and the result depend on the event rate.

Mirror symmetry mirrors the frame: a mirrored stroke's field M u(M x) is exactly that of the
reflected turned material, so the result is the mirror image of the stroke.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import numpy as np

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.mesh.mesh_state import MeshState
from gogreen_core.mesh.topology import FaceAdjacency
from gogreen_core.sculpt.kernel_cache import KernelCache

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["FramedKernels", "area_normal", "frame_at", "material_frame_at", "surface_frame"]

#: Below this fraction of its length a motion has no part along the surface.
_TANGENTIAL = 1e-9
_NO_MIRROR = np.ones((1, 3))


def area_normal(mesh: MeshState, center: np.ndarray, radius: float) -> np.ndarray:
    """The unit area normal (3,) of ``mesh`` under a brush of ``radius`` (model units) at
    ``center`` (3,): the sum of the face cross products with a vertex within ``radius`` (else
    around the nearest vertex). ValueError when those faces have no area."""
    vertices, faces = mesh.vertices, mesh.faces
    rows = mesh.rows_near(center, np.zeros(3), radius, _NO_MIRROR)
    if not len(rows):
        gap = vertices - center
        rows = np.array([np.argmin(np.einsum("ij,ij->i", gap, gap))])
    _, around = FaceAdjacency.of(faces, len(vertices)).around(rows)
    chosen = faces[np.unique(around)]
    a, b, c = (vertices[chosen[:, k]] for k in range(3))
    total = np.cross(b - a, c - a).sum(axis=0)
    length = float(np.linalg.norm(total))
    if not length > 0:
        raise ValueError("the surface under the brush has no area: no normal to follow")
    return cast(np.ndarray, total / length)


def surface_frame(normal: np.ndarray, motion: np.ndarray | None) -> np.ndarray:
    """The frame F (3, 3), columns (t₁, t₂, n) (see the module docstring) of the unit
    ``normal`` (3,) and ``motion`` (3,) or None; of equally aligned world axes, the first."""
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    t = None
    if motion is not None:
        m = np.asarray(motion, dtype=np.float64)
        t = m - (m @ n) * n
        if not np.linalg.norm(t) > _TANGENTIAL * np.linalg.norm(m):
            t = None
    if t is None:
        axis = np.eye(3)[int(np.argmin(np.abs(n)))]
        t = axis - (axis @ n) * n
    t1 = t / np.linalg.norm(t)
    t2 = np.cross(n, t1)
    return np.column_stack([t1, t2, n])


def frame_at(
    mesh: MeshState, center: np.ndarray, radius: float, motion: np.ndarray | None
) -> np.ndarray:
    """The surface frame (3, 3) of a stroke at ``center`` with a brush of ``radius`` (model
    units) and first ``motion`` (3,) or None."""
    return surface_frame(area_normal(mesh, center, radius), motion)


def material_frame_at(sculptor: Sculptor, point: np.ndarray, radius: float) -> np.ndarray:
    """The rotation (3, 3) ``sculptor``'s material is turned by for a stroke starting at
    ``point`` (3,) before it moves (:func:`frame_at`; the identity with the "world" frame;
    during a stroke the one it took)."""
    if sculptor.settings.material_frame != "surface":
        return np.eye(3)
    strokes = sculptor._strokes  # the engine's own stroke driver
    current = strokes.current_kernels
    if current is not None and current.frame is not None:
        return current.frame
    return frame_at(strokes.mesh, np.asarray(point, dtype=np.float64), radius, None)


class FramedKernels(KernelCache):
    """The kernels of ``base``'s settings with the material turned by ``frame`` F (3, 3) (once,
    Wigner-D); derived values are the unturned kernels' (:attr:`unturned`), turned where they
    turn, so a new frame computes none of them again."""

    def __init__(self, base: KernelCache, frame: np.ndarray) -> None:
        self.settings = base.settings
        self.base = base
        self.frame = np.array(frame, dtype=np.float64)
        self.frame.setflags(write=False)
        self.full: GreenKernel = base.full.turned(self.frame)
        self._weighted: dict[bytes, GreenKernel] = {}
        self._derived = {}

    @property
    def unturned(self) -> KernelCache:
        return self.base
