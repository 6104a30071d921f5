"""Interaction frames from a lighter copy of a big mesh (ParaView's level of detail).

With software OpenGL a full frame of a 2M-triangle mesh takes most of a second; while the
camera moves or a stroke runs the viewport draws a decimated copy instead
(:class:`LightMesh`, about :data:`LIGHT_FACES` faces) and the full mesh again as soon as the
interaction settles (:class:`app.viewport.SculptViewport`).

The copy is a vertex clustering whose vertices are vertices of the mesh (in each cell of a
grid, the one nearest the mean of the cell's vertices), so a stroke frame shows the brush's
effect by copying the moved rows from the mesh: no re-decimation per event. Its normals and
arrays are a :class:`gogreen_core.mesh.geometry.SurfaceIndex` of its own, updated only where
its rows changed. Where dynamic topology changes the mesh (locally) the copy keeps its faces
and follows: its vertices become the same vertices in their new rows, and where one was
collapsed away, a kept neighbour from before the change (:meth:`LightMesh.follow`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

import numpy as np
import pyvista as pv
from PySide6.QtCore import QTimer

from app.background import BackgroundRunner
from gogreen_core.mesh.geometry import SurfaceIndex

if TYPE_CHECKING:
    from app.mesh_display import MeshDisplay
    from gogreen_core.mesh.mesh_state import MeshEdit

__all__ = [
    "LIGHT_FACES",
    "LIGHT_FRAME_MS",
    "LIGHT_MIN_FACES",
    "RESORT_FRACTION",
    "SETTLE_MS",
    "InPlaceRenumbering",
    "LevelOfDetail",
    "LightMesh",
    "Renumbering",
    "cluster_decimation",
    "edit_renumbering",
    "indexed",
    "indexed_polydata",
    "refreshed_polydata",
]

#: How a local change of topology (dynamic topology's) made the mesh of the faces ``before``
#: into the current one: (before, origin (N',), face_origin (M',)), each row's row before, -1
#: for a new one (``gogreen_core.mesh.mesh_state.MeshState.renumbering``).
Renumbering = tuple[np.ndarray, np.ndarray, np.ndarray]
#: Faces of the interaction copy (a tenth of the render cost of 2M faces here).
LIGHT_FACES = 100_000
#: Meshes with fewer faces draw every frame in full (their frames are cheap enough).
LIGHT_MIN_FACES = 400_000
#: A full frame slower than this (ms) makes camera and stroke frames draw the copy.
LIGHT_FRAME_MS = 100.0
#: The full mesh is drawn again this long (ms) after the last wheel zoom (a drag: at its end).
SETTLE_MS = 300
#: Face slots renumberings blanked or wrote (unsorted: their leaves' boxes span the change
#: and picks test more of them) past this fraction of the faces: a sorted build starts in the
#: background while the renumbered index serves (:meth:`LevelOfDetail.attach`).
RESORT_FRACTION = 0.05
#: Multisampling (anti-aliased edges) on hardware OpenGL. Software OpenGL (Mesa's llvmpipe)
#: draws without: there 4 samples tripled a frame of the 1M-vertex mesh and took 340 MB more.
HARDWARE_MULTI_SAMPLES = 4
_SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast", "swiftshader", "software rasterizer")


def indexed_polydata(surface: SurfaceIndex) -> tuple[pv.PolyData, bool]:
    """A PolyData drawing ``surface``'s positions, faces and normals, and whether VTK shares
    their memory (then the index's in-place updates are the PolyData's)."""
    mesh = pv.PolyData.from_regular_faces(surface.positions, surface.faces)  # type: ignore[arg-type]
    mesh.point_data["Normals"] = surface.normals
    mesh.point_data.active_normals_name = "Normals"
    return mesh, _shares(mesh, surface)


def _shares(mesh: pv.PolyData, surface: SurfaceIndex) -> bool:
    """VTK draws ``surface``'s arrays themselves (no copies)."""
    polys = pv.convert_array(mesh.GetPolys().GetConnectivityArray())
    return (
        np.shares_memory(mesh.points, surface.positions)
        and np.shares_memory(mesh.point_data["Normals"], surface.normals)
        and np.shares_memory(polys, surface.faces)
    )


def refreshed_polydata(mesh: pv.PolyData | None, surface: SurfaceIndex) -> tuple[pv.PolyData, bool]:
    """``mesh`` (of :func:`indexed_polydata`) after ``surface`` was renumbered in place: its
    arrays marked modified where their slots were written in place, wrapped again (no copy)
    where slots were added or the index's room grew; and whether VTK shares them."""
    if mesh is None:
        return indexed_polydata(surface)
    if mesh.n_points != len(surface.positions) or mesh.n_cells != len(surface.faces):
        mesh.points = surface.positions
        mesh.point_data["Normals"] = surface.normals
        mesh.point_data.active_normals_name = "Normals"
        mesh.faces = pv.CellArray.from_regular_cells(surface.faces)
    shared = _shares(mesh, surface)
    if not shared:  # (the index's room grew: new buffers)
        return indexed_polydata(surface)
    mesh.GetPoints().Modified()
    mesh.GetPointData().GetNormals().Modified()
    mesh.GetPolys().Modified()
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
    first_of_cell = np.r_[True, np.diff(keys[order]) != 0]
    starts = np.flatnonzero(first_of_cell)
    cluster = np.empty(len(vertices), dtype=np.int64)
    cluster[order] = np.cumsum(first_of_cell) - 1
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
    :meth:`attach`), ``base`` (the mesh's rows of the copy's vertices where the mesh was
    indexed, before the changes :meth:`follow` took), ``ahead`` (None, or a change's
    ``face_origin`` and the rows :meth:`followed_rows` found for it off the GUI thread).
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, target_faces: int = LIGHT_FACES):
        self.rows, light_faces = cluster_decimation(vertices, faces, target_faces)
        self.base = self.rows
        self.index = SurfaceIndex(np.asarray(vertices)[self.rows], light_faces)
        self.polydata, self._shared = indexed_polydata(self.index)
        self.actor: Any = None
        self.ahead: tuple[np.ndarray, np.ndarray] | None = None

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

    def follow(
        self, vertices: np.ndarray, faces: np.ndarray, change: Renumbering, before: SurfaceIndex
    ) -> None:
        """The mesh became ``vertices`` (N', 3), ``faces`` by ``change`` from the mesh of
        :attr:`base`, indexed by ``before``: the copy's vertices move to :meth:`followed_rows`
        (found ahead, on the stroke's worker thread, if :attr:`ahead` holds them)."""
        if self.ahead is not None and self.ahead[0] is change[2]:  # (the release's: again)
            self.rows = self.ahead[1]
        else:
            self.rows = self.followed_rows(vertices, faces, change, before)
        self.update(vertices[self.rows])

    def followed_rows(
        self, vertices: np.ndarray, faces: np.ndarray, change: Renumbering, before: SurfaceIndex
    ) -> np.ndarray:
        """Where the copy's vertices are after ``change`` (see :meth:`follow`): each the same
        vertex in its new row, or where it was collapsed away, the kept corner of the new faces
        that was nearest to it before (a neighbour on its side of the surface: the corner
        nearest to where it is drawn may be across a fold the stroke made)."""
        from scipy.spatial import cKDTree

        def was_at(mesh_rows: np.ndarray) -> np.ndarray:  # only the rows asked: no (N, 3) copy
            return before.positions[before.rank[mesh_rows]]

        _, origin, face_origin = change
        rows = _new_rows(origin, len(before.rank))[self.base]
        lost = np.flatnonzero(rows < 0)
        if len(lost):
            corners = np.unique(faces[face_origin < 0])
            kept = corners[origin[corners] >= 0]
            if len(kept):
                near = cKDTree(was_at(origin[kept])).query(was_at(self.base[lost]))[1]
                rows[lost] = kept[near]
            else:  # every corner is new: the one nearest to where it is drawn
                drawn = self.index.positions[self.index.rank[lost]]
                rows[lost] = corners[cKDTree(vertices[corners]).query(drawn)[1]]
        return rows

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


def indexed(
    vertices: np.ndarray, faces: np.ndarray, progress: Callable[[float], None] | None = None
) -> tuple[SurfaceIndex, LightMesh | None]:
    """A mesh's :class:`SurfaceIndex` (``progress`` as it takes) and its interaction copy if
    it has at least :data:`LIGHT_MIN_FACES` faces."""
    light = LightMesh(vertices, faces) if len(faces) >= LIGHT_MIN_FACES else None
    return SurfaceIndex(vertices, faces, progress), light


class InPlaceRenumbering:
    """The background job renumbering ``base`` in place to ``vertices`` (N, 3; a copy is read),
    ``faces`` by ``change``, with the copy ``light`` (which followed the change). Nothing else
    may touch ``base`` meanwhile. :meth:`take` (the GUI thread) ends it at once."""

    def __init__(
        self,
        base: SurfaceIndex,
        vertices: np.ndarray,
        faces: np.ndarray,
        change: Renumbering,
        light: LightMesh | None,
    ) -> None:
        self.base, self.light = base, light
        self._args = (vertices.copy(), faces, change[1], change[2])
        self._lock = threading.Lock()
        self._started = False  # (under the lock: it ran, or take dropped it)

    def __call__(self, _task: Any) -> tuple[SurfaceIndex, LightMesh | None]:
        with self._lock:
            if not self._started:
                self._started = True
                self.base.renumber(*self._args)
        return self.base, self.light

    def take(self) -> tuple[SurfaceIndex, LightMesh | None] | None:
        """Its result, waiting while it runs (a fraction of a second); None if it has not
        started (other work ahead of it on the one background thread: a homogenization, the
        kernels' warm-up): it is dropped then, ``base`` untouched, rather than waited for."""
        with self._lock:
            ran, self._started = self._started, True
        return (self.base, self.light) if ran else None


def _sorted_build(
    vertices: np.ndarray, faces: np.ndarray
) -> Callable[[Any], tuple[SurfaceIndex, np.ndarray]]:
    """The background job of a new (sorted) index of a mesh, and the faces it was made for."""
    return lambda task: (SurfaceIndex(vertices, faces, task.progress), faces)


def edit_renumbering(edit: MeshEdit, faces: np.ndarray) -> Renumbering | None:
    """How an undo or redo step of a dynamic-topology stroke, ``edit`` (the side applied),
    renumbered the mesh of ``faces``: the stroke's change inverted (each row's row before,
    -1 for one the stroke had removed), or again; the carried rows keep their order. None
    if ``edit`` was not applied to a mesh of that many faces."""

    def origin(n: int, new: np.ndarray, gone: np.ndarray) -> np.ndarray:
        kept, carried = np.ones(n, dtype=bool), np.ones(n - len(new) + len(gone), dtype=bool)
        kept[new] = carried[gone] = False
        rows = np.full(n, -1)
        rows[kept] = np.flatnonzero(carried)
        return rows

    if len(faces) != edit.n_faces - len(edit.new_faces) + len(edit.gone_faces):
        return None
    vertex_origin = origin(edit.n_vertices, edit.new, edit.gone)
    return faces, vertex_origin, origin(edit.n_faces, edit.new_faces, edit.gone_faces)


def _new_rows(origin: np.ndarray, n: int) -> np.ndarray:
    """Each of ``n`` old rows' new row (-1: gone), from ``origin`` (see :data:`Renumbering`)."""
    new = np.full(n, -1)
    kept = np.flatnonzero(origin >= 0)
    new[origin[kept]] = kept
    return new


def _software_renderer(window: Any) -> bool:
    """The render ``window``'s OpenGL renderer is a software one (after its first frame)."""
    report = window.ReportCapabilities().lower()
    renderer = next((line for line in report.splitlines() if "renderer string" in line), "")
    return any(name in renderer for name in _SOFTWARE_RENDERERS)


class LevelOfDetail:
    """Which of a viewport's mesh and its interaction copy is drawn, and the vertices moved
    while the copy was (``display``: the :class:`app.mesh_display.MeshDisplay`).

    Attributes: ``light`` (the copy, None for a small mesh or until the index is built),
    ``shown`` (the copy is drawn), ``full_frame_ms`` (the last frame that drew the full mesh),
    ``software_gl`` (the renderer is a software one; None until the first frame).
    """

    def __init__(self, display: MeshDisplay) -> None:
        self.display = display
        self.light: LightMesh | None = None
        self.shown = False
        self.full_frame_ms = 0.0
        self.software_gl: bool | None = None
        #: The newest positions (N, 3) given while the copy was drawn; the mesh's index and
        #: arrays catch up with them when it is drawn again or picked on.
        self._deferred: np.ndarray | None = None
        self.settle_timer = QTimer(display)
        self.settle_timer.setSingleShot(True)
        self.settle_timer.setInterval(SETTLE_MS)
        self.settle_timer.timeout.connect(self.show_full)
        self._resort = BackgroundRunner(display)
        self._resort.finished.connect(self._resorted)
        self._renumbering: InPlaceRenumbering | None = None

    def indexing(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        base: SurfaceIndex | None,
        change: Renumbering | None,
    ) -> Callable[[Any], tuple[SurfaceIndex, LightMesh | None]]:
        """The background job indexing a mesh (it reads a copy of ``vertices``: the view's may
        move): ``base`` renumbered in place by ``change`` with the copy (kept for
        :meth:`take_renumbering`), or a new index and copy."""
        if base is None or change is None:
            self._renumbering, vertices = None, vertices.copy()
            return lambda task: indexed(vertices, faces, task.progress)
        self._renumbering = InPlaceRenumbering(base, vertices, faces, change, self.light)
        return self._renumbering

    def take_renumbering(self) -> tuple[SurfaceIndex, LightMesh | None] | None:
        """The result of the in-place renumbering last submitted, if any and it ran
        (:meth:`InPlaceRenumbering.take`: else it is dropped)."""
        pending, self._renumbering = self._renumbering, None
        return None if pending is None else pending.take()

    def chain(
        self,
        change: Renumbering | None,
        indexed: tuple[SurfaceIndex, np.ndarray] | None,
        faces: np.ndarray,
    ) -> Renumbering | None:
        """``change`` if it made ``faces`` of the faces ``indexed`` (index, faces), else None
        (a sorted build running for the faces before is dropped either way)."""
        if change is None or indexed is None:
            return None
        self._resort.cancel()  # the faces it sorts are gone
        return change if change[0] is indexed[1] else None

    def attach(self, light: LightMesh | None) -> None:
        """Use ``light`` as the copy of the mesh just shown (None: none; the copy in use: it
        followed the mesh to its new topology, indexed now). An index renumbered past
        :data:`RESORT_FRACTION` of unsorted faces: a sorted build starts."""
        self._renumbering = None  # (done: what it holds goes)
        surface, faces = self.display.surface, self.display._faces
        if surface is not None and faces is not None and surface.unsorted:
            if surface.unsorted > RESORT_FRACTION * len(faces):
                self._resort.submit(_sorted_build(surface.vertices, faces), supersede=True)
        if light is not None and light is self.light:
            light.base, light.ahead = light.rows, None  # its change is in: the rows found go
            return
        self.light = light
        if light is not None:
            light.attach(self.display, self.display.mesh_actor)

    def _resorted(self, _job: int, built: tuple[SurfaceIndex, np.ndarray]) -> None:
        """A sorted build of the renumbered mesh ended: it serves from now on, brought up to
        the vertices moved meanwhile; dropped if the faces changed or a stroke runs (the next
        renumbering starts another)."""
        surface, faces = built
        display: Any = self.display
        if faces is not display._faces or display.surface is None or display.in_stroke:
            return
        shown = display.shown_vertices()
        surface.update(shown, surface.changed_rows(shown))
        display._use_index(surface, self.light)
        display.request_render()

    def drop(self) -> None:
        """No copy (a new mesh: the moved vertices of the old one are dropped)."""
        self._resort.cancel()
        self._deferred = None
        self.settle_timer.stop()
        if self.light is not None:
            self.light.detach(self.display)
            self.light = None
        if self.shown and self.display.mesh_actor is not None:
            self.display.mesh_actor.SetVisibility(True)
        self.shown = False

    def frame_ended(self, ms: float) -> None:
        """A frame took ``ms``; after the first, multisampling unless OpenGL is software."""
        if not self.shown:
            self.full_frame_ms = ms
        if self.software_gl is None:
            window: Any = self.display.ren_win
            self.software_gl = _software_renderer(window)
            if not self.software_gl:
                window.SetMultiSamples(HARDWARE_MULTI_SAMPLES)
                self.display.request_render()

    def follow(
        self, vertices: np.ndarray, faces: np.ndarray, change: Renumbering, base: SurfaceIndex
    ) -> None:
        """The mesh became ``vertices``, ``faces`` by a local ``change`` of the topology ``base``
        indexed (before it is renumbered): the copy follows it (:meth:`LightMesh.follow`), still
        drawn if it was; the vertices moved meanwhile are dropped (the change has them)."""
        self._deferred = None
        if self.light is not None:
            self.light.follow(vertices, faces, change, base)

    def interaction_frames(self) -> None:
        """The camera moves or a stroke runs: its frames from the copy when full frames are
        slow (over :data:`LIGHT_FRAME_MS`), until :meth:`show_full`."""
        self.settle_timer.stop()
        if self.full_frame_ms > LIGHT_FRAME_MS:
            self.show_light()

    def show_light(self) -> None:
        """Draw the copy instead of the mesh (brought up to date with it); nothing without
        one."""
        surface, light = self.display.surface, self.light
        if light is None or self.shown or surface is None:
            return
        light.update(surface.positions[surface.rank[light.rows]])
        light.show(self.display.mesh_actor, self._colors(), surface.rank)
        self.shown = True
        self.display.request_render()

    def show_full(self) -> None:
        """The mesh again in place of the copy, with the vertices moved meanwhile."""
        if not self.shown:
            return
        self.shown = False
        self.catch_up()
        if self.light is not None:
            self.light.hide(self.display.mesh_actor)
        self.display.request_render()

    def defer(self, vertices: np.ndarray) -> bool:
        """New positions (N, 3): while the copy is drawn, only its rows are written (True);
        False: the mesh's arrays are to be written now."""
        if not self.shown or self.light is None:
            return False
        self.light.update(vertices[self.light.rows])
        self._deferred = vertices
        return True

    def catch_up(self) -> None:
        """Write the vertices moved while the copy was drawn into the mesh's index and arrays
        (only the rows that changed)."""
        if self._deferred is not None:
            vertices, self._deferred = self._deferred, None
            self.display.update_vertices(vertices, now=True)

    def colors_changed(self) -> None:
        """The mesh's direct colours changed: the drawn copy's follow (also during a
        dynamic-topology stroke, the mesh without an index: the colours in the mesh's order)."""
        surface, mesh = self.display.surface, self.display.mesh
        if self.shown and self.light is not None and mesh is not None:
            rank = surface.rank if surface is not None else np.arange(mesh.n_points)
            self.light.set_colors(self._colors(), rank)

    def _colors(self) -> np.ndarray | None:
        """The mesh's direct colours (N, 3) uint8 as drawn (its index's order), or None."""
        mesh, mapper = self.display.mesh, self.display.mesh_actor.mapper
        name = mapper.GetArrayName()
        if mesh is None or not mapper.GetScalarVisibility() or name not in mesh.point_data:
            return None
        return np.asarray(mesh.point_data[name])

    @contextmanager
    def drawn(self, light: bool) -> Iterator[None]:
        """Within: the copy drawn if ``light`` and there is one (a thumbnail), else as is."""
        copy = light and not self.shown and self.light is not None
        if copy:
            self.show_light()
        try:
            yield
        finally:
            if copy:
                self.show_full()
