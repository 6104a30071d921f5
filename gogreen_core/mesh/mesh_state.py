"""The mesh being sculpted: its vertices (edited in place), faces, texture corners, vertex mask
and the sizes tools use. Brush radii, pins and reaches are relative to the model's size (the
bounding-box diagonal at load: settings act alike on a 0.15-unit bunny and a 30-unit ogre),
which a new face array (:meth:`MeshState.adopt`) keeps, so brush sizes do not jump.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property
from typing import NamedTuple

import numpy as np

from gogreen_core.field.limits import MAX_REACH
from gogreen_core.mesh.influence import VertexBlocks
from gogreen_core.mesh.topology import MeshEdges, VertexNeighbours, mesh_edges, vertex_neighbours
from gogreen_core.validation import ParameterError, check_vector, vector_norm

__all__ = [
    "MaskRows",
    "MeshEdit",
    "MeshSnapshot",
    "MeshState",
    "compact_faces",
    "topology_edit",
]


class MaskRows(NamedTuple):
    """Mask values (K,) of the vertices ``rows`` (K,) int64: one side of a mask undo step."""

    rows: np.ndarray
    values: np.ndarray

    @property
    def nbytes(self) -> int:
        return int(self.rows.nbytes + self.values.nbytes)


def compact_faces(faces: np.ndarray) -> np.ndarray:
    """Faces as int32 when the vertex count allows (half the memory of a kept snapshot)."""
    return faces.astype(np.int32) if len(faces) and faces.max() < 2**31 else faces.copy()


@dataclass(frozen=True)
class MeshSnapshot:
    """Copies of all of a mesh's arrays (one side of a subdivision's undo step); faces are kept
    as int32 where they fit and come back as int64, equal."""

    vertices: np.ndarray
    faces: np.ndarray
    mask: np.ndarray
    uv: np.ndarray | None = None
    uv_faces: np.ndarray | None = None

    @property
    def nbytes(self) -> int:
        return sum(int(getattr(getattr(self, k), "nbytes", 0)) for k in self.__dataclass_fields__)

    def frozen(self) -> MeshSnapshot:
        """These arrays themselves, read-only, face arrays compact (a new mesh: the after-side
        of a subdivision's or a remesh's undo step)."""
        corners = None if self.uv_faces is None else compact_faces(self.uv_faces)
        frozen = replace(self, faces=compact_faces(self.faces), uv_faces=corners)
        for array in (frozen.vertices, frozen.faces, frozen.mask, frozen.uv, frozen.uv_faces):
            if array is not None:
                array.setflags(write=False)
        return frozen


@dataclass(frozen=True)
class MeshEdit:
    """One side of a topology edit's undo step (dynamic topology's stroke), holding only what
    changed: applied to the other side's mesh it gives this side's arrays bit for bit. The rows
    of the other mesh not in ``gone`` (vertices, faces) are carried over in order to this
    side's rows not in ``new``, carried faces renumbered; ``rows`` (the new rows and the
    carried rows that moved) take ``vertices``, ``mask_rows`` ``mask``, the ``new_faces`` rows
    ``faces``. Sizes: n_vertices and n_faces, this side's. ``texture``: the same of the texture
    rows (its vertices the (T, 2) uv rows, its faces uv_faces; no mask), or None without."""

    n_vertices: int
    gone: np.ndarray
    new: np.ndarray
    rows: np.ndarray
    vertices: np.ndarray
    mask_rows: np.ndarray
    mask: np.ndarray
    n_faces: int
    gone_faces: np.ndarray
    new_faces: np.ndarray
    faces: np.ndarray
    texture: MeshEdit | None = None

    @property
    def nbytes(self) -> int:
        return sum(int(getattr(getattr(self, k), "nbytes", 0)) for k in self.__dataclass_fields__)

    def applied(self, other: MeshSnapshot | MeshState) -> MeshSnapshot:
        """This side's arrays (new, writable) from ``other``, the other side's mesh."""
        source = _marked(len(other.vertices), self.gone, inverse=True)
        target = _marked(self.n_vertices, self.new, inverse=True)
        vertices = np.empty((self.n_vertices, *other.vertices.shape[1:]))
        mask = np.empty(self.n_vertices)
        vertices[target], mask[target] = other.vertices[source], other.mask[source]
        vertices[self.rows], mask[self.mask_rows] = self.vertices, self.mask
        number = np.full(len(other.vertices) + 1, -1, dtype=np.int64)  # the last: a -1 corner's
        number[source] = target
        faces = np.empty((self.n_faces, 3), dtype=np.int64)
        carried = _marked(len(other.faces), self.gone_faces, inverse=True)
        faces[_marked(self.n_faces, self.new_faces, inverse=True)] = number[other.faces[carried]]
        faces[self.new_faces] = self.faces
        textures = _texture_mesh(other)
        if self.texture is None or textures is None:
            return MeshSnapshot(vertices, faces, mask)
        texture = self.texture.applied(textures)
        return MeshSnapshot(vertices, faces, mask, texture.vertices, texture.faces)


def _texture_mesh(mesh: MeshSnapshot | MeshState) -> MeshSnapshot | None:
    """The texture rows as a mesh (uv_faces its faces, no mask), or None without."""
    if mesh.uv is None or mesh.uv_faces is None:
        return None
    return MeshSnapshot(mesh.uv, mesh.uv_faces, np.broadcast_to(0.0, (len(mesh.uv),)))


def _marked(n: int, *rows: np.ndarray, inverse: bool = False) -> np.ndarray:
    """The rows (ascending) of range(n) in one of ``rows`` (``inverse``: in none); by a mark,
    not np.union1d, which sorts (1.7 s for 1M rows)."""
    mark = np.zeros(n, dtype=bool)
    for some in rows:
        mark[some] = True
    return np.flatnonzero(~mark if inverse else mark)


def topology_edit(
    before: MeshSnapshot,
    after: MeshSnapshot | MeshState,
    origin: np.ndarray,
    face_origin: np.ndarray,
    uv_origin: np.ndarray | None = None,
) -> tuple[MeshEdit, MeshEdit]:
    """The two sides (before, after) of the undo step of an edit that turned ``before`` into
    ``after`` keeping the order of the vertices, faces and texture rows it did not remove and
    appending new ones: ``origin`` (N',), ``face_origin`` (M',) and ``uv_origin`` (T'; None
    without texture rows) int, each row of ``after``'s row in ``before`` (-1 for a new one,
    all after the others)."""
    carried, carried_faces = origin[origin >= 0], face_origin[face_origin >= 0]
    n, m = len(carried), len(carried_faces)
    n_before = len(before.vertices)
    gone = _marked(n_before, carried, inverse=True)
    gone_faces = _marked(len(before.faces), carried_faces, inverse=True)
    bits = before.vertices[carried].view(np.uint64) != after.vertices[:n].view(np.uint64)
    moved = np.flatnonzero(bits.any(axis=1))
    painted = np.flatnonzero(before.mask[carried].view(np.uint64) != after.mask[:n].view(np.uint64))
    added = np.arange(n, len(after.vertices))
    added_faces = np.arange(m, len(after.faces))

    def side(mesh: MeshSnapshot | MeshState, *rows: np.ndarray) -> MeshEdit:
        # the rows int32, as a snapshot's faces
        gone, new, moved, painted, gone_faces, new_faces = map(compact_faces, rows)
        vertices, mask = mesh.vertices[moved], mesh.mask[painted]
        faces = compact_faces(mesh.faces[new_faces])
        n, m = len(mesh.vertices), len(mesh.faces)
        return MeshEdit(
            n, gone, new, moved, vertices, painted, mask, m, gone_faces, new_faces, faces
        )

    back = _marked(n_before, gone, carried[moved])
    back_mask = _marked(n_before, gone, carried[painted])
    forth, forth_mask = np.concatenate([moved, added]), np.concatenate([painted, added])
    sides = (
        side(before, added, gone, back, back_mask, added_faces, gone_faces),
        side(after, gone, added, forth, forth_mask, gone_faces, added_faces),
    )
    textures = _texture_mesh(before), _texture_mesh(after)
    if uv_origin is None or textures[0] is None or textures[1] is None:
        return sides
    inner = topology_edit(textures[0], textures[1], uv_origin, face_origin)
    return replace(sides[0], texture=inner[0]), replace(sides[1], texture=inner[1])


class MeshState:
    """Vertices (N, 3) float64, edited in place by the engine alone, through :meth:`write_rows`
    or with a report of the rows written (:meth:`moved`: :meth:`rows_near`'s blocks of rows
    stay right); faces (M, 3) int64; texture corners ``uv`` (T, 2), ``uv_faces`` (M, 3) (-1:
    untextured) or None; the :attr:`mask` (N,) float64 in [0, 1] (1 does not move);
    :attr:`model_size` (bounding-box diagonal at load, model units) and :attr:`origin` (its
    centre: the point of the mirror planes); :attr:`renumbering` (faces, origin, face_origin)
    if the faces came of those by a local change (as :func:`topology_edit` takes it), else
    None; :attr:`edges` and :attr:`neighbours` are built on first use for the current faces."""

    def __init__(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        uv: np.ndarray | None = None,
        uv_faces: np.ndarray | None = None,
    ) -> None:
        self.vertices = v = np.array(vertices, dtype=np.float64)
        self.faces = f = np.array(faces, dtype=np.int64)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
            raise ValueError(f"vertices must be a non-empty (N, 3) array (got shape {v.shape})")
        if not np.all(np.isfinite(v)):
            raise ValueError("vertices contain NaN or infinite coordinates")
        if f.ndim != 2 or f.shape[1] != 3:
            raise ValueError(f"faces must be an (M, 3) array (got shape {f.shape})")
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise ValueError(f"faces reference vertices outside 0..{len(v) - 1}")
        self.uv = self.uv_faces = None
        if (uv is None) != (uv_faces is None):
            raise ValueError("uv and uv_faces go together")
        if uv is not None:
            self.uv = t = np.array(uv, dtype=np.float64)
            self.uv_faces = c = np.array(uv_faces, dtype=np.int64)
            if t.ndim != 2 or t.shape[1] != 2 or not np.all(np.isfinite(t)):
                raise ValueError(f"uv must be a finite (T, 2) array (got shape {t.shape})")
            if c.shape != (len(f), 3):
                raise ValueError(f"uv_faces must have shape ({len(f)}, 3) (got {c.shape})")
            if c.size and (c.min() < -1 or c.max() >= len(t)):
                raise ValueError(f"uv_faces must hold -1 or rows below {len(t)} of uv")
        low, high = self.vertices.min(axis=0), self.vertices.max(axis=0)
        self.model_size = float(np.linalg.norm(high - low))
        if not self.model_size > 0:
            raise ValueError("the mesh has zero size (all vertices coincide)")
        if not np.isfinite(self.model_size):
            raise ValueError("the mesh is too large (its size overflows a float)")
        self.origin: np.ndarray = 0.5 * (low + high)
        self.mask = np.zeros(len(self.vertices))
        #: Some vertex is masked (mask > 0): brushes' results are blended by the driver.
        self.masked = False
        #: Counts the changes of the mask (a view redraws its tint when it changes).
        self.mask_version = 0
        self.renumbering: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self._blocks = VertexBlocks()

    # -- connectivity ------------------------------------------------------------------------
    @cached_property
    def edges(self) -> MeshEdges:
        """The edges of the current faces (built once per face array)."""
        return mesh_edges(self.faces, len(self.vertices))

    @cached_property
    def neighbours(self) -> VertexNeighbours:
        """Each vertex's neighbours for the current faces (built once per face array)."""
        return vertex_neighbours(self.edges, len(self.vertices))

    # -- mask --------------------------------------------------------------------------------
    def mask_rows(self, rows: np.ndarray) -> MaskRows:
        """The mask values of ``rows`` (copies)."""
        rows = np.asarray(rows, dtype=np.int64)
        return MaskRows(rows, self.mask[rows].copy())

    def set_mask_rows(self, change: MaskRows) -> None:
        """Write mask values (an edit, or one side of an undo step)."""
        self.mask[change.rows] = change.values
        self.masked = bool(np.any(self.mask))
        self.mask_version += 1

    # -- whole arrays ------------------------------------------------------------------------
    def snapshot(self) -> MeshSnapshot:
        """Copies of the arrays (a subdivision's undo step, a replay's rollback)."""
        return MeshSnapshot(
            self.vertices.copy(),
            compact_faces(self.faces),
            self.mask.copy(),
            None if self.uv is None else self.uv.copy(),
            None if self.uv_faces is None else compact_faces(self.uv_faces),
        )

    def adopt(self, mesh: MeshSnapshot | MeshEdit, owned: bool = False) -> None:
        """Take the arrays of ``mesh`` (copies; a new face array, no :attr:`renumbering`), or
        of a :class:`MeshEdit` side applied to these; the model's size and origin stay.
        ``owned``: its arrays are new, writable, float64 and int64, nobody else's (dynamic
        topology's): taken as they are, no copy."""
        if isinstance(mesh, MeshEdit):
            mesh, owned = mesh.applied(self), True
        take = np.asarray if owned else np.array
        faces = take(mesh.faces, dtype=np.int64)
        same = faces.shape == self.faces.shape and np.array_equal(faces, self.faces)
        self.vertices = take(mesh.vertices, dtype=np.float64)
        self.faces = self.faces if same else faces
        self.mask = take(mesh.mask, dtype=np.float64)
        self.masked = bool(np.any(self.mask))
        self.mask_version += 1
        self.uv = None if mesh.uv is None else take(mesh.uv, dtype=np.float64)
        self.uv_faces = None if mesh.uv_faces is None else take(mesh.uv_faces, dtype=np.int64)
        if not same:
            self.renumbering = None  # the caller says how, if it knows
            for built in ("edges", "neighbours"):  # built again on first use
                self.__dict__.pop(built, None)

    # -- places ------------------------------------------------------------------------------
    @property
    def reach(self) -> float:
        """How far (model units) a point, a brush centre or a motion may go from the model's
        centre: :data:`~gogreen_core.field.limits.MAX_REACH` model sizes."""
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
        """Indices (n,) int64, ascending, of the vertices within ``radius`` of the segment from
        ``center`` to ``center + step``, or of its mirror images (``signs`` (2^k, 3), see
        :func:`~gogreen_core.sculpt.brushes.mirror_signs`); every vertex for None. The rows a pass
        over every vertex with ``_evaluation.near_segment`` gives, bit for bit."""
        if radius is None:
            return np.arange(len(self.vertices))
        return self._blocks.rows_near(self.vertices, center, step, radius, signs, self.origin)

    # -- vertex writes -----------------------------------------------------------------------
    def write_rows(self, rows: np.ndarray | None, positions: np.ndarray) -> None:
        """vertices[rows] = positions ((k, 3), or (N, 3) for every row when ``rows`` is None)."""
        try:
            if rows is None:
                self.vertices[:] = positions
            else:
                self.vertices[rows] = positions
        finally:  # a write that failed part-way is reported too
            self.moved(rows)

    def moved(self, rows: np.ndarray | None) -> None:
        """Report vertex rows (k,) written in place by someone else (None: any row may have
        been), after the write: every path that writes :attr:`vertices` in place calls this
        or :meth:`write_rows`, or :meth:`rows_near` may miss moved vertices."""
        self._blocks.changed(self.vertices, rows)
