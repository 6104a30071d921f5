"""Interaction frames from a lighter copy of a big mesh (ParaView's level of detail).

With software OpenGL a full frame of a 2M-triangle mesh takes most of a second; while the
camera moves or a stroke runs the viewport draws a decimated copy instead
(:class:`LightMesh`, about :data:`LIGHT_FACES` faces) and the full mesh again as soon as the
interaction settles (:class:`app.viewport.SculptViewport`).

The copy is a vertex clustering whose vertices are vertices of the mesh (in each cell of a
grid, the one nearest the mean of the cell's vertices), so a stroke frame shows the brush's
effect by copying the moved rows from the mesh: no re-decimation per event. Its normals and
arrays are a :class:`gogreen_core.mesh.geometry.SurfaceIndex` of its own, updated only where
its rows changed.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pyvista as pv

from gogreen_core.mesh.geometry import SurfaceIndex

__all__ = ["LIGHT_FACES", "LIGHT_MIN_FACES", "LightMesh", "cluster_decimation", "indexed_polydata"]

#: Faces of the interaction copy (a tenth of the render cost of 2M faces here).
LIGHT_FACES = 100_000
#: Meshes with fewer faces draw every frame in full (their frames are cheap enough).
LIGHT_MIN_FACES = 400_000


def indexed_polydata(surface: SurfaceIndex) -> tuple[pv.PolyData, bool]:
    """A PolyData drawing ``surface``'s positions, faces and normals, and whether VTK shares
    their memory (then the index's in-place updates are the PolyData's)."""
    mesh = pv.PolyData.from_regular_faces(surface.positions, surface.faces)  # type: ignore[arg-type]
    mesh.point_data["Normals"] = surface.normals
    mesh.point_data.active_normals_name = "Normals"
    shared = np.shares_memory(mesh.points, surface.positions) and np.shares_memory(
        mesh.point_data["Normals"], surface.normals
    )
    return mesh, shared


def _cells(vertices: np.ndarray, low: np.ndarray, size: float) -> np.ndarray:
    """The grid cell (a key, int64) of each vertex, cells of side ``size`` from ``low``."""
    ijk = ((vertices - low) / size).astype(np.int64)
    dims = ijk.max(axis=0) + 1
    return (ijk[:, 0] * dims[1] + ijk[:, 1]) * dims[2] + ijk[:, 2]


def cluster_decimation(
    vertices: np.ndarray, faces: np.ndarray, target_faces: int
) -> tuple[np.ndarray, np.ndarray]:
    """A decimated copy of a mesh by vertex clustering, its vertices chosen among the mesh's.

    Parameters: ``vertices`` (N, 3) float64, ``faces`` (M, 3) int, ``target_faces`` the
    faces wanted (met within a factor of about 1.5: the grid's cell size is set from a first
    count of occupied cells).

    Returns ``rows`` (k,) int64, the mesh vertex each copy vertex is, and ``light_faces``
    (m, 3) int32 into ``rows``: the mesh's faces whose corners fell into three different
    cells, each once, in the mesh's orientation, unless that folds them over.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    low = vertices.min(axis=0)
    diagonal = float(np.linalg.norm(vertices.max(axis=0) - low)) or 1.0
    wanted = max(target_faces // 2, 4)  # a closed mesh has about twice as many faces as vertices
    size = diagonal / np.sqrt(wanted)
    occupied = len(np.unique(_cells(vertices, low, size)))  # a surface: cells ∝ 1 / size²
    size *= np.sqrt(occupied / wanted)
    keys = _cells(vertices, low, size)
    order = np.argsort(keys, kind="stable")
    starts = np.flatnonzero(np.r_[True, np.diff(keys[order]) != 0])
    cluster = np.empty(len(vertices), dtype=np.int64)
    cluster[order] = np.cumsum(np.r_[True, np.diff(keys[order]) != 0]) - 1
    counts = np.diff(np.r_[starts, len(order)])
    means = np.add.reduceat(vertices[order], starts, axis=0) / counts[:, None]
    offset = vertices - means[cluster]
    distance = np.einsum("ij,ij->i", offset, offset)
    nearest = np.lexsort((distance, cluster))
    rows = nearest[np.r_[True, np.diff(cluster[nearest]) != 0]]
    corners = cluster[faces]
    kept = (
        (corners[:, 0] != corners[:, 1])
        & (corners[:, 1] != corners[:, 2])
        & (corners[:, 0] != corners[:, 2])
    )
    source = np.flatnonzero(kept)
    corners = corners[source]
    ordered = np.sort(corners, axis=1)
    k = np.int64(len(rows))
    key = (ordered[:, 0] * k + ordered[:, 1]) * k + ordered[:, 2]
    _, first = np.unique(key, return_index=True)
    first.sort()
    corners, source = corners[first], source[first]
    # a face whose snapped corners fold it over (against the mesh face it comes from) is
    # dropped: drawn, it shows as a dark speck
    facing = np.einsum(
        "ij,ij->i", _face_normals(vertices[rows], corners), _face_normals(vertices, faces[source])
    )
    return rows.astype(np.int64), corners[facing > 0].astype(np.int32)


def _face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    return np.cross(b - a, c - a)


class LightMesh:
    """The interaction copy of a mesh: its vertex rows in the mesh, its own index and actor.

    Parameters: ``vertices`` (N, 3) and ``faces`` (M, 3) of the mesh; ``target_faces``.
    Attributes: ``rows`` (k,) the mesh vertices it copies, ``index`` its
    :class:`SurfaceIndex`, ``polydata`` (drawing the index's arrays), ``actor`` (None until
    :meth:`attach`).
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, target_faces: int = LIGHT_FACES):
        self.rows, light_faces = cluster_decimation(vertices, faces, target_faces)
        self.index = SurfaceIndex(np.asarray(vertices)[self.rows], light_faces)
        self.polydata, self._shared = indexed_polydata(self.index)
        self.actor: Any = None

    @property
    def n_faces(self) -> int:
        return len(self.index.faces)

    def attach(self, plotter: Any, look: Any) -> None:
        """Add the (hidden) actor to ``plotter``, with the property, texture and shader of
        the mesh actor ``look`` (shared: a change of shading shows on both)."""
        self.actor = pv.Actor(mapper=pv.DataSetMapper(self.polydata))
        self.actor.SetProperty(look.GetProperty())
        self.actor.SetShaderProperty(look.GetShaderProperty())
        self.actor.SetPickable(False)
        self.actor.SetVisibility(False)
        plotter.add_actor(self.actor, reset_camera=False, render=False)

    def detach(self, plotter: Any) -> None:
        if self.actor is not None:
            plotter.remove_actor(self.actor, render=False)
            self.actor = None

    def update(self, positions: np.ndarray) -> int:
        """New ``positions`` (k, 3) of the copy's vertices (the mesh's rows :attr:`rows`): the
        rows that changed and the normals around them are written; returns how many rows."""
        light = np.ascontiguousarray(positions, dtype=np.float64)
        changed = self.index.changed_rows(light)
        if len(changed):
            self.index.update(light, changed)
            if not self._shared:
                self.polydata.points = self.index.positions
                self.polydata.point_data["Normals"] = self.index.normals
            self.polydata.GetPoints().Modified()
            self.polydata.GetPointData().GetNormals().Modified()
        return len(changed)

    def show(self, look: Any, colors: np.ndarray | None, mesh_rank: np.ndarray) -> None:
        """Draw the copy in place of the mesh actor ``look``: its texture (a matcap) and its
        direct colours ``colors`` (N, 3) uint8 in the order of the mesh's index, whose
        ``mesh_rank`` places the mesh's vertices (None: the property's colour)."""
        self.actor.SetTexture(look.GetTexture())
        self.set_colors(colors, mesh_rank)
        look.SetVisibility(False)
        self.actor.SetVisibility(True)

    def set_colors(self, colors: np.ndarray | None, mesh_rank: np.ndarray) -> None:
        """The copy's direct colours from the mesh's (see :meth:`show`)."""
        mapper = self.actor.mapper
        if colors is None:
            mapper.ScalarVisibilityOff()
            return
        self.polydata.point_data["Colors"] = colors[mesh_rank[self.rows[self.index.order]]]
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray("Colors")
        mapper.SetColorModeToDirectScalars()
        mapper.ScalarVisibilityOn()

    def hide(self, look: Any) -> None:
        """The mesh actor ``look`` again in place of the copy."""
        self.actor.SetVisibility(False)
        look.SetVisibility(True)
