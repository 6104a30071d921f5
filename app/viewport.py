"""The 3D viewport: a pyvistaqt QtInteractor where the left mouse button sculpts.

Mouse map (as PyVista and Blender users expect): left drag on the model sculpts (on the
background it orbits), right drag orbits, middle drag pans, the wheel zooms; Ctrl+wheel
changes the brush radius and Shift+wheel the strength. Keys are the window's (app.keymap) and
the tools' (F, number keys): none reaches VTK's interactor, whose default keys (and pyvista's)
would act behind the app's back. The mesh actor is created once; each brush event writes new
positions and normals into its arrays in place.

The viewport knows nothing of elasticity or strokes: it translates Qt mouse events into plain
:class:`gogreen_core.tools.PointerEvent` (the world point under the cursor, picked on press and
hover, on the drag plane through the press point while dragging) for the Qt-free tools, and
draws. It renders on demand only: :meth:`SculptViewport.request_render` coalesces every request
made before control returns to the event loop into one render (pyvistaqt's periodic
``auto_update`` render is off), and hover picking is coalesced the same way, so an idle window
uses no CPU and a burst of mouse moves costs one pick and one render.
"""

from __future__ import annotations

import time

import numpy as np
import pyvista as pv
from PySide6.QtCore import QEvent, QPointF, Qt, QTimer, Signal
from PySide6.QtGui import QKeyEvent, QMouseEvent, QTabletEvent, QWheelEvent
from pyvistaqt import QtInteractor

from app.background import BackgroundRunner
from app.cursor_overlay import CursorOverlay, PinOverlay, to_display
from gogreen_core.geometry import SurfaceIndex
from gogreen_core.tools import CursorState, PointerEvent, SculptTools, ToolUpdate

__all__ = ["SculptViewport"]

MODEL_COLOR = "#c9b79c"  # warm clay
#: How much darker a fully masked vertex is drawn (Blender shows its mask as a dark tint).
MASK_SHADE = 0.6
_MASK_ARRAY = "MaskTint"
#: Meshes with at least this many faces get their SurfaceIndex built in the background
#: (about 25 ms of build below it: not worth a flat-shaded moment).
BACKGROUND_INDEX_FACES = 200_000
#: Direction from the model to the camera in the home view: in front (+z), a little right and above.
HOME_VIEW_DIRECTION = (0.55, 0.4, 1.0)


def _barycentric(a: np.ndarray, b: np.ndarray, c: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Barycentric weights (3,) of point ``p`` in triangle ``a b c`` (clipped to [0, 1])."""
    v0, v1, v2 = b - a, c - a, p - a
    d00, d01, d11 = v0 @ v0, v0 @ v1, v1 @ v1
    d20, d21 = v2 @ v0, v2 @ v1
    det = d00 * d11 - d01 * d01
    if det == 0:
        return np.full(3, 1.0 / 3.0)
    v = (d11 * d20 - d01 * d21) / det
    w = (d00 * d21 - d01 * d20) / det
    weights = np.clip(np.array([1.0 - v - w, v, w]), 0.0, 1.0)
    return weights / weights.sum()


class SculptViewport(QtInteractor):
    """Viewport with pointer events for the tools, a brush cursor ring, in-place mesh updates
    and on-demand rendering.

    Signals
    -------
    pointer_pressed(PointerEvent) : left press on the model (``point``, ``normal`` picked).
    pointer_moved(PointerEvent) : drag move after such a press (``point`` on the drag plane).
    pointer_released(PointerEvent) : the end of that drag.
    hovered(PointerEvent) : the newest hover position (coalesced), ``point`` None off the model.
    radius_wheel(int), strength_wheel(int) : +1 / -1 per wheel notch with Ctrl / Shift.
    tool_update(ToolUpdate) : what a key or click handled here changed (a pin removed by a
        right click), for the window to draw.
    frame_rendered(float) : milliseconds of a render just done.
    surface_progress(float) : fraction done of a background :class:`SurfaceIndex` build.
    surface_ready() : that build ended; picking and smooth shading work from now on.
    surface_failed(str) : that build failed (the error).
    surface_pending() : a left press while that build runs (no stroke started).
    """

    pointer_pressed = Signal(object)
    pointer_moved = Signal(object)
    pointer_released = Signal(object)
    hovered = Signal(object)
    radius_wheel = Signal(int)
    strength_wheel = Signal(int)
    frame_rendered = Signal(float)
    tool_update = Signal(object)
    surface_progress = Signal(float)
    surface_ready = Signal()
    surface_failed = Signal(str)
    surface_pending = Signal()

    def __init__(self, parent=None):
        # auto_update=False: no periodic render (pyvistaqt's default re-renders 5 times a
        # second, which alone kept a core busy with software OpenGL)
        super().__init__(parent, auto_update=False)
        self.set_background("#2b2f36", top="#4a5260")
        self.enable_trackball_style()
        self._mute_vtk_keys()
        self.mesh: pv.PolyData | None = None
        self.mesh_actor = None
        self._faces: np.ndarray | None = None
        #: The vertex mask drawn as a tint (the mesh's order), None when nothing is masked.
        self._mask: np.ndarray | None = None
        #: Per-mesh index: incremental normals and ray picking (gogreen_core.geometry).
        self.surface: SurfaceIndex | None = None
        self._arrays_shared = False
        # the index of a big mesh is built on the background thread (app.background)
        self._index_runner = BackgroundRunner(self)
        self._index_runner.progress.connect(lambda _job, done: self.surface_progress.emit(done))
        self._index_runner.finished.connect(self._index_built)
        self._index_runner.failed.connect(self._index_failed)
        self._index_job: int | None = None
        #: The brush cursor: 2D, drawn over the surface (app.cursor_overlay).
        self.cursor_overlay = CursorOverlay(self.renderer)
        #: The reach of the pins (2D rings).
        self.pin_overlay = PinOverlay(self.renderer)
        #: The Qt-free tools the keys act on (F / Shift+F drags, number keys); set by the
        #: window. The viewport only translates key and mouse events for them.
        self.tools: SculptTools | None = None
        #: Depth (display z) of the drag plane while the left button drags on the model.
        self._drag_depth: float | None = None
        self._orbit_button: Qt.MouseButton | None = None
        self._hover_pos: QPointF | None = None
        #: Pen pressure of the latest tablet event (1 for a mouse), given to the tools.
        self._pressure = 1.0
        self._hover_timer = self._zero_timer(self._emit_hover)
        #: Renders done and the duration of the last one (ms), measured by VTK's own events.
        self.frames = 0
        self.last_frame_ms = 0.0
        self._render_pending = False
        self._frame_start = 0.0
        self.ren_win.AddObserver("StartEvent", self._frame_started)
        self.ren_win.AddObserver("EndEvent", self._frame_ended)
        self.setMouseTracking(True)
        # takes the keyboard focus when clicked, and back from fields (app.keyboard)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)

    def _mute_vtk_keys(self) -> None:
        """No VTK or pyvista key binding may act (app.keymap is the app's only keymap): keys
        are not passed to the interactor (:meth:`keyPressEvent`), and should one arrive by
        another path, pyvista's key callbacks (q, b, v, Shift+C, Up, Down, plus, minus) are gone
        and the style's default key actions (p outline, s / w, r, e / q, f, 3, j / t / c / a)
        are replaced by observers that do nothing."""
        self.iren.clear_key_event_callbacks()
        style = self.iren.interactor.GetInteractorStyle()
        for event in ("CharEvent", "KeyPressEvent", "KeyReleaseEvent"):
            style.AddObserver(event, lambda *_args: None)

    def _zero_timer(self, slot) -> QTimer:
        timer = QTimer(self)
        timer.setSingleShot(True)
        timer.setInterval(0)
        timer.timeout.connect(slot)
        return timer

    # -- rendering ---------------------------------------------------------------------------
    def request_render(self) -> None:
        """Render once when control returns to the event loop.

        A Qt ``update()``: requests made before the next paint merge into one paint, and the
        widget's paint is where pyvistaqt renders. (``render()`` renders at once and then
        schedules that paint, which renders again: two renders per frame.)
        """
        self._render_pending = True
        self.update()

    def render_now(self) -> None:
        """Render at once (tests, screenshots); a paint (one more render) follows."""
        self.render()

    def _frame_started(self, *_args) -> None:
        self._frame_start = time.perf_counter()

    def _frame_ended(self, *_args) -> None:
        self.last_frame_ms = 1e3 * (time.perf_counter() - self._frame_start)
        self.frames += 1
        self._render_pending = False
        self.frame_rendered.emit(self.last_frame_ms)

    @property
    def render_pending(self) -> bool:
        """A requested render has not happened yet."""
        return self._render_pending

    # -- mesh --------------------------------------------------------------------------------
    def set_mesh(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        reset_camera: bool = True,
        background: bool | None = None,
    ) -> None:
        """Show a new mesh (one actor, replaced only when the mesh itself changes).

        Its :class:`SurfaceIndex` (picking, incremental normals) is built at once for a mesh
        of fewer than :data:`BACKGROUND_INDEX_FACES` faces, else (or with ``background``) on
        the background thread (about 0.5 s at 2M faces): meanwhile the mesh is shown
        flat-shaded in its own order, vertex updates are drawn, picks find nothing and a left
        press emits :attr:`surface_pending` instead of starting a stroke.
        :attr:`surface_progress` and then :attr:`surface_ready` report the build.
        """
        if self.mesh_actor is not None:
            self.remove_actor(self.mesh_actor, render=False)
            self.mesh_actor = None
        self.show_cursor(None)  # sized for the old mesh; it would also widen the home view
        self._mask = None  # the new mesh's tint comes with show_mask
        self._index_runner.cancel()
        self._index_job = None
        self.surface = None
        vertices = np.array(vertices, dtype=np.float64)  # our copy: VTK draws it
        self._faces = np.asarray(faces)
        if background is None:
            background = len(self._faces) >= BACKGROUND_INDEX_FACES
        if background:
            self._show(pv.PolyData.from_regular_faces(vertices, self._faces))
            built_from = vertices.copy()  # the build reads this; the view's copy may move
            faces = self._faces
            self._index_job = self._index_runner.submit(
                lambda task: SurfaceIndex(built_from, faces, task.progress), supersede=True
            )
        else:
            self._use_index(SurfaceIndex(vertices, self._faces))
        if reset_camera:
            self.home_view(render=False)
        self.request_render()

    def _show(self, mesh: pv.PolyData) -> None:
        """Draw ``mesh`` with the model's look: a new actor, or the current one's input."""
        self.mesh = mesh
        if self.mesh_actor is not None:
            self.mesh_actor.mapper.SetInputData(mesh)
            self._draw_mask()
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
        self._draw_mask()

    # -- mask tint ---------------------------------------------------------------------------
    def show_mask(self, mask: np.ndarray | None, rows: np.ndarray | None = None) -> None:
        """Draw the vertex mask (N,) in [0, 1] (the mesh's order) as a darker tint, a masked
        vertex :data:`MASK_SHADE` darker; None or all zero: no tint. ``rows``: only these
        vertices' values changed (a mask stroke's event)."""
        if mask is None or (rows is None and not np.any(mask)):
            if self._mask is not None:
                self._mask = None
                self._draw_mask()
            return
        if self._mask is None or rows is None or len(self._mask) != len(mask):
            self._mask = np.array(mask, dtype=np.float64)
            self._draw_mask()
            return
        rows = np.asarray(rows, dtype=np.int64)
        self._mask[rows] = mask[rows]
        self._draw_mask(rows)

    @property
    def mask_shown(self) -> bool:
        """A mask tint is drawn."""
        return self._mask is not None

    def _tint(self, mask: np.ndarray) -> np.ndarray:
        base = np.array(pv.Color(MODEL_COLOR).int_rgb, dtype=np.float64)
        shade = 1.0 - MASK_SHADE * np.clip(mask, 0.0, 1.0)
        return np.rint(shade[:, None] * base).astype(np.uint8)

    def _draw_mask(self, rows: np.ndarray | None = None) -> None:
        """Colour the mesh from :attr:`_mask` (in the shown order: the surface index's when it
        draws), or back to the plain colour without one; ``rows``: only these changed."""
        if self.mesh is None or self.mesh_actor is None:
            return
        mapper = self.mesh_actor.mapper
        data = self.mesh.point_data
        if self._mask is None or len(self._mask) != self.mesh.n_points:
            if _MASK_ARRAY in data:
                data.remove(_MASK_ARRAY)
            mapper.ScalarVisibilityOff()
            self.request_render()
            return
        rank = self.surface.rank if self.surface is not None else None
        if rows is not None and _MASK_ARRAY in data:
            colors = data[_MASK_ARRAY]
            colors[rows if rank is None else rank[rows]] = self._tint(self._mask[rows])
            self.mesh.GetPointData().GetArray(_MASK_ARRAY).Modified()
        else:
            colors = self._tint(self._mask)
            if rank is not None:
                shown = np.empty_like(colors)
                shown[rank] = colors
                colors = shown
            data[_MASK_ARRAY] = colors
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray(_MASK_ARRAY)
        mapper.SetColorModeToDirectScalars()
        mapper.ScalarVisibilityOn()
        self.request_render()

    def _use_index(self, surface: SurfaceIndex) -> None:
        """Draw the mesh from ``surface``'s arrays (shared, in its order: the per-event
        updates write them in place) and pick on it."""
        mesh = pv.PolyData.from_regular_faces(surface.positions, surface.faces)
        mesh.point_data["Normals"] = surface.normals
        mesh.point_data.active_normals_name = "Normals"
        # VTK wraps the index's arrays without a copy: its updates are the actor's
        self._arrays_shared = np.shares_memory(mesh.points, surface.positions) and (
            np.shares_memory(mesh.point_data["Normals"], surface.normals)
        )
        self.surface = surface
        self._show(mesh)

    def _index_built(self, job: int, surface: SurfaceIndex) -> None:
        if job != self._index_job or self.mesh is None:
            return  # a mesh opened since
        self._index_job = None
        # vertices moved while it was built (undo, a script): bring the index up to date
        shown = self.mesh.points
        surface.update(shown, surface.changed_rows(shown))
        self._use_index(surface)
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
        if self.surface is not None:
            return self.surface.vertices
        return np.array(self.mesh.points) if self.mesh is not None else np.zeros((0, 3))

    def home_view(self, render: bool = True) -> None:
        """Front three-quarter view with +y up (the OBJ/PLY convention of Spot, the bunny and
        most exported models), the whole mesh in frame."""
        self.view_vector(HOME_VIEW_DIRECTION, viewup=(0.0, 1.0, 0.0), render=False)
        self.reset_camera(render=False)
        if render:
            self.request_render()

    def update_vertices(self, vertices: np.ndarray, indices: np.ndarray | None = None) -> None:
        """Write new positions (N, 3, the mesh's order) into the actor's arrays in place.

        ``indices``: the vertices that moved; None compares every vertex with the shown one
        (undo, a pin drag) and updates those that differ. Only the moved rows and the normals
        of them and their one-ring are written (:meth:`SurfaceIndex.update`, whose arrays VTK
        draws); the arrays are marked modified, nothing is rebuilt. While the index builds in
        the background the moved rows are written (flat-shaded view) and the index catches up
        when it is ready.
        """
        if self.mesh is None:
            return
        vertices = np.asarray(vertices, dtype=np.float64)
        surface = self.surface
        if indices is None and surface is not None:
            indices = surface.changed_rows(vertices)
        elif indices is None:
            differ = self.mesh.points != vertices  # per column: faster than np.any(axis=1)
            indices = np.flatnonzero(differ[:, 0] | differ[:, 1] | differ[:, 2])
        else:
            indices = np.asarray(indices, dtype=np.int64).ravel()
        if len(indices):
            if surface is None:
                self.mesh.points[indices] = vertices[indices]
            else:
                surface.update(vertices, indices)
                if not self._arrays_shared:
                    self.mesh.points = surface.positions
                    self.mesh.point_data["Normals"] = surface.normals
            self.mesh.GetPoints().Modified()
            normals = self.mesh.GetPointData().GetNormals()
            if normals is not None:
                normals.Modified()

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
        if self.mesh is None or self.surface is None:
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
        weights = _barycentric(a, b, c, point)
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

    # -- cursor ------------------------------------------------------------------------------
    def show_cursor(self, state: CursorState | None) -> None:
        """Place the brush cursor overlay at ``state`` (drawn at the next render), or hide it
        (None)."""
        self.cursor_overlay.show(state)
        self.request_render()

    @property
    def cursor_visible(self) -> bool:
        return self.cursor_overlay.visible

    def model_image(self) -> np.ndarray:
        """The view as drawn, without the brush cursor: (H, W, 3) uint8 RGB, H and W in device
        pixels (screenshots).

        The cursor is left out of one render, which is read back; it is then drawn again as it
        was (its state is kept) at the next render, requested here: one frame without it on
        screen at most.
        """
        overlay = self.cursor_overlay
        overlay.suspended = True
        try:
            self.render()
            pixels = self.screenshot(return_img=True)
        finally:
            overlay.suspended = False
            overlay.layout()
            self.request_render()
        return np.ascontiguousarray(pixels[:, :, :3])

    # -- mouse -------------------------------------------------------------------------------
    def _as_left(self, ev: QMouseEvent) -> QMouseEvent:
        buttons = Qt.MouseButton.LeftButton if ev.buttons() else Qt.MouseButton.NoButton
        return QMouseEvent(
            ev.type(),
            ev.position(),
            ev.globalPosition(),
            Qt.MouseButton.LeftButton,
            buttons,
            Qt.KeyboardModifier.NoModifier,
        )

    def pointer_event(
        self,
        pos: QPointF,
        point: np.ndarray | None,
        normal: np.ndarray | None = None,
        modifiers: Qt.KeyboardModifier = Qt.KeyboardModifier.NoModifier,
        pressure: float | None = None,
    ) -> PointerEvent:
        """A plain :class:`PointerEvent` for widget position ``pos`` (pressure: the pen's)."""
        pressure = self._pressure if pressure is None else pressure
        view, right = self._view_axes()
        names = frozenset(
            name
            for name, flag in (
                ("shift", Qt.KeyboardModifier.ShiftModifier),
                ("ctrl", Qt.KeyboardModifier.ControlModifier),
                ("alt", Qt.KeyboardModifier.AltModifier),
            )
            if modifiers & flag
        )
        return PointerEvent((pos.x(), pos.y()), point, normal, view, right, float(pressure), names)

    def tabletEvent(self, ev: QTabletEvent) -> None:
        """Keep the pen's pressure; Qt then sends the mouse event made from this one."""
        touching = ev.type() != QTabletEvent.Type.TabletRelease and bool(ev.buttons())
        self._pressure = float(ev.pressure()) if touching else 1.0  # hover: a mouse's 1
        ev.ignore()

    # -- keys and value drags (F / Shift+F) ---------------------------------------------------
    @property
    def value_dragging(self) -> bool:
        return self.tools is not None and self.tools.value_drag is not None

    def _show_tool_update(self, update: ToolUpdate) -> None:
        if update.cursor is not None:
            self.show_cursor(update.cursor)

    def start_value_drag(self, name: str, pos: QPointF | None = None) -> None:
        """Begin dragging the brush ``"radius"`` (F) or ``"strength"`` (Shift+F) with the
        pointer at ``pos`` (default: where it is now): moving sets it live, a click or Enter
        confirms, Escape or a right click restores it."""
        if self.tools is None or self.in_stroke:
            return
        if pos is None:
            pos = QPointF(self.mapFromGlobal(self.cursor().pos()))
        center, ring = None, None
        if self.cursor_overlay.screen is not None:
            (x, y), ring, _ = self.cursor_overlay.screen
            ratio = self.devicePixelRatioF() or 1.0
            center, ring = (x / ratio, self.height() - 1 - y / ratio), ring / ratio
        self._hover_timer.stop()
        self._show_tool_update(self.tools.start_value_drag(name, (pos.x(), pos.y()), center, ring))

    def finish_value_drag(self, confirm: bool) -> None:
        if self.value_dragging:
            self._show_tool_update(self.tools.finish_value_drag(confirm))

    def keyPressEvent(self, ev: QKeyEvent) -> None:
        key, mods = ev.key(), ev.modifiers()
        if self.value_dragging:
            if key in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
                self.finish_value_drag(True)
            elif key == Qt.Key.Key_Escape:
                self.finish_value_drag(False)
            ev.accept()  # nothing else while dragging a value
            return
        plain = not mods & ~Qt.KeyboardModifier.ShiftModifier & ~Qt.KeyboardModifier.KeypadModifier
        if key == Qt.Key.Key_F and plain and self.tools is not None:
            shift = bool(mods & Qt.KeyboardModifier.ShiftModifier)
            self.start_value_drag("strength" if shift else "radius")
            ev.accept()
            return
        if plain and self.tools is not None and self.tools.pick_brush(ev.text()):
            ev.accept()
            return
        # not to VTK (its and pyvista's default keys would act): Qt gives it to the parent
        ev.ignore()

    def keyReleaseEvent(self, ev: QKeyEvent) -> None:
        ev.ignore()  # not to VTK either

    def mousePressEvent(self, ev: QMouseEvent) -> None:
        self.setFocus(Qt.FocusReason.MouseFocusReason)
        if self.value_dragging:
            self.finish_value_drag(ev.button() != Qt.MouseButton.RightButton)
            return
        if ev.button() == Qt.MouseButton.LeftButton and self.surface_building:
            self.surface_pending.emit()  # nothing to pick on yet: no stroke, no orbit
            return
        if ev.button() == Qt.MouseButton.LeftButton and self._drag_depth is None:
            hit = self.pick(ev.position())
            if hit is not None:
                point, normal = hit
                self._drag_depth = self._depth(point)
                self._hover_timer.stop()
                self.pointer_pressed.emit(
                    self.pointer_event(ev.position(), point, normal, ev.modifiers())
                )
                return
            self._orbit_button = Qt.MouseButton.LeftButton
            super().mousePressEvent(ev)
        elif ev.button() == Qt.MouseButton.RightButton and self._remove_pin(ev.position()):
            return
        elif ev.button() == Qt.MouseButton.RightButton:
            self._orbit_button = Qt.MouseButton.RightButton
            super().mousePressEvent(self._as_left(ev))  # right drag orbits
        else:
            super().mousePressEvent(ev)

    def _remove_pin(self, pos: QPointF) -> bool:
        """In pin mode, a right click on a pin removes it (True); elsewhere it orbits."""
        if self.tools is None or self.tools.mode != "pin" or self.in_stroke:
            return False
        hit = self.pick(pos)
        if hit is None:
            return False
        update = self.tools.remove_pin(self.pointer_event(pos, hit[0], hit[1]))
        if not update.changed:
            return False
        self.tool_update.emit(update)
        return True

    def show_pins(self, points: np.ndarray, reach: float) -> None:
        """Show the reach (world radius) of the pins at ``points`` (k, 3)."""
        self.pin_overlay.show(points, reach)
        self.request_render()

    def mouseMoveEvent(self, ev: QMouseEvent) -> None:
        if self.value_dragging:
            pos = ev.position()
            self._show_tool_update(self.tools.move_value_drag((pos.x(), pos.y())))
            return
        if self._drag_depth is not None:
            point = self._unproject(ev.position(), self._drag_depth)
            self.pointer_moved.emit(self.pointer_event(ev.position(), point, None, ev.modifiers()))
            return
        if self._orbit_button == Qt.MouseButton.RightButton:
            super().mouseMoveEvent(self._as_left(ev))
            return
        super().mouseMoveEvent(ev)
        if not ev.buttons():  # hover: pick once for the newest position
            self._hover_pos = ev.position()
            if not self._hover_timer.isActive():
                self._hover_timer.start()

    def _emit_hover(self) -> None:
        if self._hover_pos is None or self._drag_depth is not None:
            return
        pos, self._hover_pos = self._hover_pos, None
        hit = self.pick(pos)
        point, normal = hit if hit is not None else (None, None)
        self.hovered.emit(self.pointer_event(pos, point, normal))

    def leaveEvent(self, ev: QEvent) -> None:
        super().leaveEvent(ev)
        self._pointer_gone()

    def event(self, ev: QEvent) -> bool:
        if ev.type() == QEvent.Type.WindowDeactivate:  # a dialog or another window has the input
            self._pointer_gone()
        return super().event(ev)

    def _pointer_gone(self) -> None:
        """The pointer left the view (in any jump) or the window lost the input: hide the brush
        cursor until the next hover over the model. A miss is reported as the newest hover, so
        the tools forget the cursor too and a hover still queued cannot bring it back. Not
        during a stroke or an F / Shift+F drag, which keep their cursor."""
        if self.in_stroke or self.value_dragging:
            return
        self._hover_timer.stop()
        self._hover_pos = None
        if not self.cursor_visible and (self.tools is None or self.tools.cursor.state is None):
            return  # nothing shown: no event, no render
        self.show_cursor(None)
        pos = QPointF(self.mapFromGlobal(self.cursor().pos()))
        self.hovered.emit(self.pointer_event(pos, None))

    def mouseReleaseEvent(self, ev: QMouseEvent) -> None:
        if self._drag_depth is not None and ev.button() == Qt.MouseButton.LeftButton:
            point = self._unproject(ev.position(), self._drag_depth)
            self._drag_depth = None
            self.pointer_released.emit(
                self.pointer_event(ev.position(), point, None, ev.modifiers())
            )
            return
        if self._orbit_button == Qt.MouseButton.RightButton and ev.button() == self._orbit_button:
            self._orbit_button = None
            super().mouseReleaseEvent(self._as_left(ev))
            return
        self._orbit_button = None
        super().mouseReleaseEvent(ev)

    def wheelEvent(self, ev: QWheelEvent) -> None:
        notches = 1 if ev.angleDelta().y() > 0 else -1
        if ev.modifiers() & Qt.KeyboardModifier.ControlModifier:
            self.radius_wheel.emit(notches)
        elif ev.modifiers() & Qt.KeyboardModifier.ShiftModifier:
            self.strength_wheel.emit(notches)
        else:
            super().wheelEvent(ev)

    @property
    def in_stroke(self) -> bool:
        """The left button is dragging on the model."""
        return self._drag_depth is not None
