"""What the viewport draws and picks: the mesh, its surface index, the pins, the brush cursor.

The mesh's colours: the model colour darkened where the vertex mask holds vertices, the field
preview's colours (:mod:`app.field_preview`) over the vertices the brush would move, and with
the cavity tint, darker in hollows and lighter on ridges (:mod:`gogreen_core.mesh.cavity`);
one direct-RGB point array, updated in place for the rows that change.

:class:`MeshDisplay` is a part of :class:`app.viewport.SculptViewport` (a mixin over its
pyvista plotter): the mesh actor is created once; VTK draws the arrays of the mesh's
:class:`gogreen_core.mesh.geometry.SurfaceIndex` (built on the background thread for a big
mesh), which each brush event writes in place; picking is a ray cast on it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import pyvista as pv
from PySide6.QtCore import QPointF
from PySide6.QtWidgets import QApplication

from app.background import BackgroundRunner
from app.cursor_overlay import CursorOverlay, PinOverlay, to_display
from app.level_of_detail import (
    LevelOfDetail,
    LightMesh,
    Renumbering,
    indexed,
    indexed_polydata,
    refreshed_polydata,
)
from gogreen_core.interaction.tools import CursorState
from gogreen_core.mesh.cavity import CavityField
from gogreen_core.mesh.geometry import SurfaceIndex
from gogreen_core.mesh.remesh import closest_points_on_triangles

if TYPE_CHECKING:
    from pyvistaqt import QtInteractor

    from gogreen_core.sculpt.sculptor import Sculptor

    _Base = QtInteractor
else:
    _Base = object

__all__ = [
    "BACKGROUND_INDEX_FACES",
    "CAVITY_CONTRAST",
    "CAVITY_SCALE",
    "COLOR_ARRAY",
    "HOME_VIEW_DIRECTION",
    "MASK_SHADE",
    "MODEL_COLOR",
    "MODEL_RGB",
    "MeshDisplay",
]

MODEL_COLOR = "#c9b79c"  # warm clay
MODEL_RGB = np.array(pv.Color(MODEL_COLOR).int_rgb, dtype=np.float64)
#: How much darker a fully masked vertex is drawn (Blender shows its mask as a dark tint).
MASK_SHADE = 0.6
#: The mesh's point array of direct RGB colours (mask tint and field preview).
COLOR_ARRAY = "SurfaceColors"
#: Meshes of this many faces or more get their index built in the background (~25 ms below).
BACKGROUND_INDEX_FACES = 200_000
#: Direction from the model to the camera in the home view: in front (+z), a little right and above.
HOME_VIEW_DIRECTION = (0.55, 0.4, 1.0)
PIN_COLOR = "#ff3355"
#: The cavity tint: a vertex's colour times 1 − CAVITY_CONTRAST · tanh((κ − κ₀) · size /
#: CAVITY_SCALE), κ its curvature, κ₀ the mesh's median one when the tint was turned on (or
#: the mesh opened), size the model's (its bounding box's diagonal): a bump 1 % of the size
#: high and 8 % wide changes κ · size by about 3 at its top, the colour there by about a
#: fifth (0.04 wide: by 11).
CAVITY_CONTRAST = 0.3
CAVITY_SCALE = 2.5


def _tint(base: np.ndarray, shade: np.ndarray) -> np.ndarray:
    """RGB (n, 3) uint8 of the colour ``base`` (3,) (0-255) times the factors ``shade`` (n,)."""
    return np.rint(np.clip(shade[:, None] * base, 0.0, 255.0)).astype(np.uint8)


class MeshDisplay(_Base):
    """The mesh, pins and cursor of the viewport (see the module docstring).

    Attributes: ``mesh`` (the drawn pv.PolyData), ``mesh_actor``, ``surface`` (its
    :class:`SurfaceIndex`, None while a background build runs), ``cursor_overlay``,
    ``pin_overlay``, ``pin_actor`` (the pins' markers, one actor for all).
    """

    def _init_display(self) -> None:
        self.mesh: pv.PolyData | None = None
        self.mesh_actor: Any = None
        self._faces: np.ndarray | None = None
        #: The mask tinted (the mesh's order; None: nothing masked), its version (-1: none yet).
        self._mask: np.ndarray | None = None
        self._mask_version = -1
        #: The field preview: colours (N, 3) uint8 where ``_field_on`` (N,), the rows it colours.
        self._field_rgb: np.ndarray | None = None
        self._field_on: np.ndarray | None = None
        self._field_rows = np.zeros(0, dtype=np.int64)
        #: The cavity tint: on, the curvature it shows in the index's order (None while off or
        #: until the index is ready), its reference κ₀ and the model size it scales by.
        self.cavity_on = False
        self.cavity: CavityField | None = None
        self._cavity_ref = 0.0
        self._cavity_size = 1.0
        #: The field preview's arrows (one actor, its geometry replaced), None until first shown.
        self.field_arrow_actor: Any = None
        #: Per-mesh index: incremental normals and ray picking (gogreen_core.mesh.geometry).
        self.surface: SurfaceIndex | None = None
        #: The last index made and its faces: a local change renumbers it, no new build.
        self._indexed: tuple[SurfaceIndex, np.ndarray] | None = None
        self._arrays_shared = False
        self.lod = LevelOfDetail(self)  # a big mesh's interaction copy, built with its index
        # the index of a big mesh is built on the background thread (app.background)
        self._index_runner = BackgroundRunner(self)
        self._index_runner.progress.connect(lambda _job, done: self.surface_progress.emit(done))
        self._index_runner.finished.connect(self._index_built)
        self._index_runner.failed.connect(self._index_failed)
        self._index_job: int | None = None
        #: The brush cursor: 2D, drawn over the surface (app.cursor_overlay).
        self.cursor_overlay = CursorOverlay(self.renderer)
        #: The reach of the pins (2D rings) and their markers (one actor, points in place).
        self.pin_overlay = PinOverlay(self.renderer)
        self.pin_actor: Any = None
        self.pin_markers: pv.PolyData | None = None

    # -- mesh --------------------------------------------------------------------------------
    def set_mesh(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        reset_camera: bool = True,
        background: bool | None = None,
        in_stroke: bool = False,
        renumbering: Renumbering | None = None,
    ) -> None:
        """Show a new mesh (one actor, replaced only when the mesh itself changes), without
        pins. Its :class:`SurfaceIndex` (picking, incremental normals) is built at once below
        :data:`BACKGROUND_INDEX_FACES` faces, else (or with ``background``) on the background
        thread (``surface_progress``, then ``surface_ready``): meanwhile the mesh is drawn
        flat, picks find nothing and a left press emits ``surface_pending``. ``in_stroke``:
        new faces during a stroke (dynamic topology; cursor, pins, mask tint kept), a big mesh
        flat until the stroke ends. ``renumbering``: how a local change (a dynamic-topology
        stroke, its undo or redo) made these faces of the indexed ones: a big mesh's index is
        renumbered in place (an undo's, a redo's at once), its copy and actor kept."""
        vertices = np.array(vertices, dtype=np.float64)  # our copy: VTK draws it
        faces = np.asarray(faces)
        if background is None:
            background = len(faces) >= BACKGROUND_INDEX_FACES
        if self._index_job is not None and (taken := self.lod.take_renumbering()) is not None:
            self._index_built(self._index_job, taken)  # the release's renumbering: in first
        base = self._indexed  # renumbered when a local change made these faces
        renumbering = self.lod.chain(renumbering if background else None, base, faces)
        if renumbering is None or base is None:
            base = self._indexed = None  # a new build: the old index is not kept meanwhile
        if self.mesh_actor is not None and not in_stroke and base is None:
            self.remove_actor(self.mesh_actor, render=False)
            self.mesh_actor = None
        if not in_stroke:
            self.show_cursor(None)  # sized for the old mesh; it would also widen the home view
            self.show_pins(np.zeros((0, 3)), 0.0)
            self._mask = None  # the new mesh's tint comes with show_mask
            self._show_arrows(None)
        self._mask_version = -1
        self._field_rgb = self._field_on = None
        self._field_rows = np.zeros(0, dtype=np.int64)
        self.cavity = None  # the new mesh's, once its index is ready
        if base is not None and renumbering is not None:
            self.lod.follow(vertices, faces, renumbering, base[0])
        else:
            self.lod.drop()
        self._index_runner.cancel()
        self._index_job = None
        drawn, self.surface, self._faces = self.surface, None, faces
        old = None if base is None or renumbering is None or in_stroke else base[0]
        if old is not None and old is drawn and renumbering is not None:  # an undo, a redo:
            old.renumber(vertices, faces, renumbering[1], renumbering[2])  # at once, VTK's arrays
            self._use_index(old, self.lod.light, True)
        elif background:  # (a stroke's release: its index, not drawn, renumbered there)
            self._show(pv.PolyData.from_regular_faces(vertices, self._faces))
            if not in_stroke:
                job = self.lod.indexing(vertices, faces, old, renumbering)
                self._index_job = self._index_runner.submit(job, supersede=True)
        else:
            self._use_index(*indexed(vertices, self._faces))
        if reset_camera:
            self.home_view(render=False)
        self.request_render()

    def _show(self, mesh: pv.PolyData) -> None:
        """Draw ``mesh`` with the model's look: a new actor, or the current one's input."""
        self.mesh = mesh
        if self.mesh_actor is not None:
            self.mesh_actor.mapper.SetInputData(mesh)
            self._draw_colors()
            return
        self.mesh_actor = self.add_mesh(
            mesh,
            color=MODEL_COLOR,
            specular=0.25,
            specular_power=20,
            diffuse=0.85,
            ambient=0.12,
            reset_camera=False,
            render=False,
        )
        self.mesh_actor.mapper.SetInputData(mesh)  # our arrays, updated in place
        self.mesh_actor.GetProperty().SetInterpolationToPhong()
        self._draw_colors()

    # -- mask tint ---------------------------------------------------------------------------
    def show_mask_of(self, sculptor: Sculptor, rows: np.ndarray | None = None) -> None:
        """Draw ``sculptor``'s vertex mask as a darker tint if it changed since last drawn
        (``rows``: only these vertices' values may have, a mask stroke's event)."""
        mask = sculptor.mask
        if mask.version == self._mask_version:
            return
        partial = rows if self._mask_version >= 0 else None
        self._mask_version = mask.version
        self.show_mask(mask.values if mask.any else None, partial)

    def show_mask(self, mask: np.ndarray | None, rows: np.ndarray | None = None) -> None:
        """Draw the vertex mask (N,) in [0, 1] (the mesh's order) as a darker tint, a masked
        vertex :data:`MASK_SHADE` darker; None or all zero: no tint. ``rows``: only these
        vertices' values changed."""
        if mask is None or (rows is None and not np.any(mask)):
            if self._mask is not None:
                self._mask = None
                self._draw_colors()
            return
        if self._mask is None or rows is None or len(self._mask) != len(mask):
            self._mask = np.array(mask, dtype=np.float64)
            self._draw_colors()
            return
        rows = np.asarray(rows, dtype=np.int64)
        self._mask[rows] = mask[rows]
        self._draw_colors(rows)

    @property
    def mask_shown(self) -> bool:
        """A mask tint is drawn."""
        return self._mask is not None

    # -- field preview ------------------------------------------------------------------------
    def show_field(
        self,
        rows: np.ndarray | None,
        colors: np.ndarray | None = None,
        arrows: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> None:
        """Colour the vertices ``rows`` (n,) (the mesh's order) with ``colors`` (n, 3) uint8
        RGB over the model (the field preview; the mask still darkens them), with ``arrows``
        (feet (k, 3), vectors (k, 3), model units) drawn over it; None: no preview."""
        n = self.n_vertices
        self._show_arrows(arrows if rows is not None else None)
        if rows is None or colors is None or n == 0:
            if len(self._field_rows):
                gone, self._field_rows = self._field_rows, np.zeros(0, dtype=np.int64)
                if self._field_on is not None:
                    self._field_on[gone] = False
                self._draw_colors(gone)
            return
        rows = np.asarray(rows, dtype=np.int64)
        if self._field_on is None or len(self._field_on) != n:
            self._field_on = np.zeros(n, dtype=bool)
            self._field_rgb = np.zeros((n, 3), dtype=np.uint8)
        assert self._field_rgb is not None
        changed = np.zeros(n, dtype=bool)  # the rows left and the rows coloured now
        changed[self._field_rows] = True
        changed[rows] = True
        self._field_on[self._field_rows] = False
        self._field_on[rows] = True
        self._field_rgb[rows] = colors
        self._field_rows = rows
        self._draw_colors(np.flatnonzero(changed))

    def _show_arrows(self, arrows: tuple[np.ndarray, np.ndarray] | None) -> None:
        """The preview's arrows (one actor, hidden without arrows)."""
        if arrows is None or not len(arrows[0]):
            if self.field_arrow_actor is not None and self.field_arrow_actor.GetVisibility():
                self.field_arrow_actor.SetVisibility(False)
                self.request_render()
            return
        feet, vectors = arrows
        points = pv.PolyData(np.asarray(feet, dtype=np.float64))
        points["vectors"] = np.asarray(vectors, dtype=np.float64)
        glyphs = points.glyph(orient="vectors", scale="vectors", geom=pv.Arrow(), factor=1.0)
        if self.field_arrow_actor is None:
            self.field_arrow_actor = pv.Actor(mapper=pv.DataSetMapper(glyphs))
            self.field_arrow_actor.mapper.ScalarVisibilityOff()
            prop = self.field_arrow_actor.prop
            prop.color, prop.ambient, prop.diffuse = "#1b1f27", 0.35, 0.6
            self.field_arrow_actor.SetPickable(False)
            self.add_actor(self.field_arrow_actor, reset_camera=False, render=False)
        else:
            self.field_arrow_actor.mapper.SetInputData(glyphs)
        self.field_arrow_actor.SetVisibility(True)
        self.request_render()

    # -- cavity tint -------------------------------------------------------------------------
    def set_cavity(self, on: bool) -> None:
        """Tint the surface by its curvature (darker in hollows, lighter on ridges), or not."""
        self.cavity_on = bool(on)
        if not self.cavity_on:
            self.cavity = None  # its neighbour table is the mesh's size: not kept while off
        elif self.surface is not None and self.cavity is None:
            self._measure_cavity()
        self._draw_colors()

    @property
    def cavity_shown(self) -> bool:
        """The cavity tint is drawn (on, and the mesh's curvature known)."""
        return self.cavity_on and self.cavity is not None and self.mesh is not None

    def _measure_cavity(self) -> None:
        """The curvature of every vertex, its median the tint's neutral value, in the surface
        index's order (a brush region's rows near in memory: half the time on the ogre)."""
        surface = self.surface
        assert surface is not None
        positions = surface.positions
        self.cavity = CavityField(surface.faces[surface.face_order >= 0], len(positions))
        self.cavity.update(positions, lambda rows: surface.normals[rows])
        values = self.cavity.values[surface.rank]  # (not the free slots')
        self._cavity_ref = float(np.median(values)) if len(values) else 0.0
        self._cavity_size = float(np.linalg.norm(np.ptp(positions, axis=0))) or 1.0

    @property
    def n_vertices(self) -> int:
        """The mesh's vertices (the points drawn but an index's free slots)."""
        surface, mesh = self.surface, self.mesh
        return len(surface.rank) if surface is not None else mesh.n_points if mesh else 0

    @property
    def field_shown(self) -> bool:
        """A field preview colours some vertices."""
        return len(self._field_rows) > 0

    def _colors(self, rows: np.ndarray | None) -> np.ndarray:
        """The colours (n, 3) uint8 of ``rows`` (None: every vertex), the mesh's order."""
        n = self.n_vertices
        count = n if rows is None else len(rows)
        mask = self._mask if self._mask is not None and len(self._mask) == n else None
        shade = np.ones(count)
        if mask is not None:
            shade -= MASK_SHADE * np.clip(mask if rows is None else mask[rows], 0.0, 1.0)
        if self.cavity_shown:
            assert self.cavity is not None
            assert self.surface is not None  # the curvature is in its order
            rank = self.surface.rank
            kappa = self.cavity.values[rank if rows is None else rank[rows]]
            bend = (kappa - self._cavity_ref) * (self._cavity_size / CAVITY_SCALE)
            shade *= 1.0 - CAVITY_CONTRAST * np.tanh(bend)
        colors = _tint(MODEL_RGB, shade)
        if self.field_shown and self._field_on is not None and self._field_rgb is not None:
            on = self._field_on if rows is None else self._field_on[rows]
            field = self._field_rgb if rows is None else self._field_rgb[rows]
            colors[on] = np.rint(np.clip(shade[on, None] * field[on], 0, 255)).astype(np.uint8)
        return colors

    def _draw_colors(self, rows: np.ndarray | None = None) -> None:
        """Colour the mesh (direct RGB point colours, in the shown order) from the mask, field
        preview and cavity tint, only ``rows`` when given; the plain colour without them."""
        if self.mesh is None or self.mesh_actor is None:
            return
        mapper = self.mesh_actor.mapper
        data = self.mesh.point_data
        masked = self._mask is not None and len(self._mask) == self.n_vertices
        if not masked and not self.field_shown and not self.cavity_shown:
            if COLOR_ARRAY in data:
                data.remove(COLOR_ARRAY)
            mapper.ScalarVisibilityOff()
            self.lod.colors_changed()
            self.request_render()
            return
        rank = self.surface.rank if self.surface is not None else None
        if rows is not None and COLOR_ARRAY in data:
            data[COLOR_ARRAY][rows if rank is None else rank[rows]] = self._colors(rows)
            self.mesh.GetPointData().GetArray(COLOR_ARRAY).Modified()
        else:
            colors = self._colors(None)
            if rank is not None:
                shown = np.zeros((self.mesh.n_points, 3), dtype=np.uint8)  # (free slots too)
                shown[rank] = colors
                colors = shown
            data[COLOR_ARRAY] = colors
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray(COLOR_ARRAY)
        mapper.SetColorModeToDirectScalars()
        mapper.ScalarVisibilityOn()
        self.lod.colors_changed()
        self.request_render()

    def _use_index(
        self, surface: SurfaceIndex, light: LightMesh | None = None, drawn: bool = False
    ) -> None:
        """Draw the mesh from ``surface``'s arrays (VTK wraps them: updates write them in
        place) and pick on it; ``light``: its copy. ``drawn``: drawn already (renumbered)."""
        polydata = refreshed_polydata(self.mesh, surface) if drawn else indexed_polydata(surface)
        mesh, self._arrays_shared = polydata
        self.surface = surface
        assert self._faces is not None
        self._indexed = (surface, self._faces)
        if self.cavity_on:
            self._measure_cavity()
        self._show(mesh)
        self.lod.attach(light)

    def _index_built(self, job: int, built: tuple[SurfaceIndex, LightMesh | None]) -> None:
        if job != self._index_job or self.mesh is None:
            return  # a mesh opened since
        self._index_job = None
        surface, light = built
        # vertices moved while it was built (undo, a script): bring the index up to date
        shown = self.mesh.points
        surface.update(shown, surface.changed_rows(shown))
        self._use_index(surface, light)
        if not QApplication.mouseButtons():  # the copy drawn since a stroke: the mesh now
            self.lod.show_full()
        self.request_render()
        self.surface_ready.emit()

    def _index_failed(self, job: int, error: Exception) -> None:
        if job == self._index_job:
            self._index_job = None
            self.surface_failed.emit(f"{type(error).__name__}: {error}")

    @property
    def surface_building(self) -> bool:
        """A mesh is shown whose :class:`SurfaceIndex` is still being built."""
        return self._index_job is not None

    def wait_for_surface(self, msecs: int = -1) -> bool:
        """Block until a background index build ends and apply it (tests, benchmarks)."""
        done = self._index_runner.wait(msecs)
        return done and self.surface is not None

    def cancel_surface_build(self) -> None:
        """Drop a background index build (closing the window)."""
        self._index_runner.cancel()
        self._index_job = None

    def shown_vertices(self) -> np.ndarray:
        """The positions (N, 3) drawn, in the mesh's vertex order (a copy)."""
        self.lod.catch_up()
        if self.surface is not None:
            return self.surface.vertices
        return np.array(self.mesh.points) if self.mesh is not None else np.zeros((0, 3))

    def home_view(self, render: bool = True) -> None:
        """Front three-quarter view with +y up (the OBJ/PLY convention of Spot, the bunny and
        most exported models), the whole mesh in frame."""
        plotter: Any = self  # pyvista's argument-checking decorator hides these signatures
        plotter.view_vector(HOME_VIEW_DIRECTION, viewup=(0.0, 1.0, 0.0), render=False)
        plotter.reset_camera(render=False)
        if render:
            self.request_render()
            self.rehover()

    def update_vertices(
        self, vertices: np.ndarray, indices: np.ndarray | None = None, now: bool = False
    ) -> None:
        """Write new positions (N, 3, the mesh's order) into the actor's arrays in place:
        ``indices`` moved (None: those that differ from the shown ones), only their rows and
        the normals of their one-ring (:meth:`SurfaceIndex.update`, whose arrays VTK draws).
        While the index builds (flat-shaded) or the interaction copy is drawn (``lod``), that
        is written and the mesh catches up later (``now``: the catching up)."""
        if self.mesh is None:
            return
        vertices = np.asarray(vertices, dtype=np.float64)
        surface = self.surface
        if not now and self.lod.defer(vertices):  # the copy is drawn: the mesh's when it settles
            return
        if indices is None and surface is not None:
            indices = surface.changed_rows(vertices)
        elif indices is None:
            differ = self.mesh.points != vertices  # per column: faster than np.any(axis=1)
            indices = np.flatnonzero(differ[:, 0] | differ[:, 1] | differ[:, 2])
        else:
            indices = np.asarray(indices, dtype=np.int64).ravel()
        if len(indices):
            if surface is None:
                points: np.ndarray = self.mesh.points
                points[indices] = vertices[indices]
            else:
                surface.update(vertices, indices)
                if not self._arrays_shared:
                    self.mesh.points = surface.positions
                    self.mesh.point_data["Normals"] = surface.normals
            self.mesh.GetPoints().Modified()
            normals = self.mesh.GetPointData().GetNormals()
            if normals is not None:
                normals.Modified()
            if self.cavity_shown and surface is not None:
                assert self.cavity is not None
                positions, moved = surface.positions, surface.rank[indices]
                rows = self.cavity.update(positions, lambda rows: surface.normals[rows], moved)
                self._draw_colors(surface.order[rows])

    # -- picking -----------------------------------------------------------------------------
    def _display(self, pos: QPointF) -> tuple[float, float]:
        ratio = self.devicePixelRatioF()
        return pos.x() * ratio, (self.height() - pos.y() - 1) * ratio

    def pick_ray(self, pos: QPointF) -> tuple[np.ndarray, np.ndarray]:
        """Camera ray (origin on the near plane (3,), direction (3,)) through widget ``pos``."""
        near = self._unproject(pos, 0.0)
        return near, self._unproject(pos, 1.0) - near

    def pick(self, pos: QPointF) -> tuple[np.ndarray, np.ndarray] | None:
        """Surface point (3,) and unit normal (3,) under the widget position, or None.

        A ray pick on the :class:`SurfaceIndex` (no locator built over the mesh); the normal is
        the vertex normals interpolated at the hit (as VTK's cell picker gives it)."""
        self.lod.catch_up()
        if self.mesh is None or self.surface is None or self._faces is None:
            return None
        origin, direction = self.pick_ray(pos)
        if not np.any(direction) or not np.all(np.isfinite(direction)):
            return None
        hit = self.surface.pick(origin, direction)
        if hit is None:
            return None
        face, point = hit
        rows = self.surface.rank[self._faces[face]]
        a, b, c = self.surface.positions[rows]
        weights = closest_points_on_triangles(point[None], a[None], b[None], c[None])[1][0]
        normal = weights @ self.surface.normals[rows]
        length = np.linalg.norm(normal)
        return point, (normal / length if length > 0 else np.cross(b - a, c - a))

    def _unproject(self, pos: QPointF, depth: float) -> np.ndarray:
        x, y = self._display(pos)
        self.renderer.SetDisplayPoint(x, y, depth)
        self.renderer.DisplayToWorld()
        w = np.array(self.renderer.GetWorldPoint())
        return w[:3] / w[3]

    def _depth(self, point: np.ndarray) -> float:
        return float(to_display(self.renderer, point)[2])

    def _view_axes(self) -> tuple[np.ndarray, np.ndarray]:
        camera = self.renderer.GetActiveCamera()
        view = np.array(camera.GetFocalPoint()) - np.array(camera.GetPosition())
        view /= np.linalg.norm(view)
        up = np.array(camera.GetViewUp())
        right = np.cross(view, up)
        return view, right / np.linalg.norm(right)

    # -- cursor and pins ---------------------------------------------------------------------
    def show_cursor(self, state: CursorState | None) -> None:
        """Place the brush cursor overlay at ``state`` (drawn at the next render), or hide it
        (None)."""
        self.cursor_overlay.show(state)
        self.request_render()

    @property
    def cursor_visible(self) -> bool:
        return self.cursor_overlay.visible

    def show_pins(self, points: np.ndarray, reach: float) -> None:
        """Show the pins at ``points`` (k, 3): a marker each (one actor, its points replaced
        in place) and the ring of their reach (world radius)."""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        self.pin_overlay.show(points, reach)
        if self.pin_actor is None and len(points):
            # add_actor, not add_points: pyvista's add_* would rebind self.mesh to the markers
            self.pin_markers = pv.PolyData(points)
            self.pin_actor = pv.Actor(mapper=pv.DataSetMapper(self.pin_markers))
            prop = self.pin_actor.prop
            prop.color, prop.point_size, prop.render_points_as_spheres = PIN_COLOR, 14, True
            self.pin_actor.SetPickable(False)
            self.add_actor(self.pin_actor, reset_camera=False, render=False)
        elif self.pin_markers is not None:
            self.pin_markers.points = points if len(points) else np.zeros((0, 3))
            self.pin_markers.verts = np.hstack(
                [np.ones((len(points), 1), int), np.arange(len(points))[:, None]]
            ).ravel()
        self.request_render()

    def model_image(self, light: bool = False) -> np.ndarray:
        """The view as drawn, without the brush cursor: (H, W, 3) uint8 RGB, H and W in device
        pixels (screenshots); ``light``: from the interaction copy when there is one (a
        thumbnail). The cursor is left out of one render read back, drawn again at the next."""
        overlay = self.cursor_overlay
        overlay.suspended = True
        try:
            with self.lod.drawn(light):
                self.render()
                pixels = self.screenshot(return_img=True)
        finally:
            overlay.suspended = False
            overlay.layout()
            self.request_render()
        assert pixels is not None
        return np.ascontiguousarray(pixels[:, :, :3])
