"""The 3D viewport: a pyvistaqt QtInteractor where the left mouse button sculpts.

Mouse map (as PyVista and Blender users expect): left drag on the model sculpts (on the
background it orbits), right drag orbits, middle drag pans, the wheel zooms; Ctrl+wheel
changes the brush radius and Shift+wheel the strength. The mesh actor is created once; each
brush event writes new positions and normals into its arrays in place.

The viewport knows nothing of elasticity: it reports strokes as world-space cursor positions
(:class:`CursorSample`) and the window turns them into engine calls.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pyvista as pv
import vtk
from PySide6.QtCore import QPointF, Qt, Signal
from PySide6.QtGui import QMouseEvent, QWheelEvent
from pyvistaqt import QtInteractor

from gogreen_core.geometry import vertex_normals

__all__ = ["CursorSample", "SculptViewport"]

MODEL_COLOR = "#c9b79c"  # warm clay
#: Direction from the model to the camera in the home view: in front (+z), a little right and above.
HOME_VIEW_DIRECTION = (0.55, 0.4, 1.0)
CURSOR_COLOR = "#ff8c1a"


@dataclass(frozen=True)
class CursorSample:
    """One mouse sample of a stroke, in world (model) units.

    point : (3,) the cursor on the drag plane (at stroke start: the picked surface point).
    normal : (3,) surface normal at the stroke start.
    view_dir : (3,) unit direction from the camera into the screen.
    screen_x : (3,) world direction of the screen's x axis.
    pixels : (dx, dy) mouse motion since the previous sample, in pixels (y up).
    """

    point: np.ndarray
    normal: np.ndarray
    view_dir: np.ndarray
    screen_x: np.ndarray
    pixels: tuple[float, float]


def _ring(segments: int = 96) -> pv.PolyData:
    """Unit circle in the xy plane, as a closed polyline."""
    t = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    points = np.column_stack([np.cos(t), np.sin(t), np.zeros_like(t)])
    lines = np.concatenate([[segments + 1], np.arange(segments), [0]])
    return pv.PolyData(points, lines=lines)


class SculptViewport(QtInteractor):
    """Viewport with sculpting strokes, a brush cursor ring and in-place mesh updates."""

    stroke_started = Signal(object)  # CursorSample
    stroke_moved = Signal(object)  # CursorSample
    stroke_ended = Signal()
    radius_wheel = Signal(int)  # +1 / -1 per wheel notch with Ctrl
    strength_wheel = Signal(int)  # +1 / -1 per wheel notch with Shift

    def __init__(self, parent=None):
        super().__init__(parent)
        self.set_background("#2b2f36", top="#4a5260")
        self.enable_trackball_style()
        self.mesh: pv.PolyData | None = None
        self.mesh_actor = None
        self._faces: np.ndarray | None = None
        self._picker = vtk.vtkCellPicker()
        self._picker.SetTolerance(1e-4)
        self._cursor = self.add_mesh(
            _ring(),
            color=CURSOR_COLOR,
            line_width=2.5,
            pickable=False,
            reset_camera=False,
            render_lines_as_tubes=False,
        )
        self._cursor.SetVisibility(False)
        self.cursor_radius = 0.1
        self._stroke: dict | None = None
        self._orbit_button: Qt.MouseButton | None = None
        self.setMouseTracking(True)

    # -- mesh --------------------------------------------------------------------------------
    def set_mesh(self, vertices: np.ndarray, faces: np.ndarray, reset_camera: bool = True) -> None:
        """Show a new mesh (one actor, replaced only when the mesh itself changes)."""
        if self.mesh_actor is not None:
            self.remove_actor(self.mesh_actor, render=False)
        cells = np.hstack([np.full((len(faces), 1), 3), faces]).ravel()
        self.mesh = pv.PolyData(np.array(vertices, dtype=np.float64), cells)
        self.mesh.point_data["Normals"] = vertex_normals(vertices, faces)
        self.mesh.point_data.active_normals_name = "Normals"
        self._faces = np.asarray(faces)
        self.mesh_actor = self.add_mesh(
            self.mesh,
            color=MODEL_COLOR,
            specular=0.25,
            specular_power=20,
            diffuse=0.85,
            ambient=0.12,
            reset_camera=False,
            render=False,
        )
        self.mesh_actor.mapper.SetInputData(self.mesh)  # our arrays, updated in place
        self.mesh_actor.GetProperty().SetInterpolationToPhong()
        self._picker.InitializePickList()
        self._picker.AddPickList(self.mesh_actor)
        self._picker.PickFromListOn()
        if reset_camera:
            self.home_view(render=False)
        self.render()

    def home_view(self, render: bool = True) -> None:
        """Front three-quarter view with +y up (the OBJ/PLY convention of Spot, the bunny and
        most exported models), the whole mesh in frame."""
        self.view_vector(HOME_VIEW_DIRECTION, viewup=(0.0, 1.0, 0.0), render=False)
        self.reset_camera(render=render)

    def update_vertices(self, vertices: np.ndarray, indices: np.ndarray | None = None) -> None:
        """Write new positions (N, 3) and recompute normals, in place (no new actor)."""
        if self.mesh is None:
            return
        points = self.mesh.points
        if indices is None:
            points[:] = vertices
        else:
            points[indices] = vertices[indices]
        self.mesh.point_data["Normals"][:] = vertex_normals(points, self._faces)
        self.mesh.GetPoints().Modified()
        self.mesh.GetPointData().GetNormals().Modified()
        self.mesh.Modified()

    # -- picking -----------------------------------------------------------------------------
    def _display(self, pos: QPointF) -> tuple[float, float]:
        ratio = self.devicePixelRatioF()
        return pos.x() * ratio, (self.height() - pos.y() - 1) * ratio

    def pick(self, pos: QPointF) -> tuple[np.ndarray, np.ndarray] | None:
        """Surface point and normal under the widget position, or None."""
        if self.mesh_actor is None:
            return None
        x, y = self._display(pos)
        if not self._picker.Pick(x, y, 0, self.renderer):
            return None
        return np.array(self._picker.GetPickPosition()), np.array(self._picker.GetPickNormal())

    def _unproject(self, pos: QPointF, depth: float) -> np.ndarray:
        x, y = self._display(pos)
        self.renderer.SetDisplayPoint(x, y, depth)
        self.renderer.DisplayToWorld()
        w = np.array(self.renderer.GetWorldPoint())
        return w[:3] / w[3]

    def _depth(self, point: np.ndarray) -> float:
        self.renderer.SetWorldPoint(*point, 1.0)
        self.renderer.WorldToDisplay()
        return self.renderer.GetDisplayPoint()[2]

    def _view_axes(self) -> tuple[np.ndarray, np.ndarray]:
        camera = self.renderer.GetActiveCamera()
        view = np.array(camera.GetFocalPoint()) - np.array(camera.GetPosition())
        view /= np.linalg.norm(view)
        up = np.array(camera.GetViewUp())
        right = np.cross(view, up)
        return view, right / np.linalg.norm(right)

    # -- cursor ------------------------------------------------------------------------------
    def show_cursor(self, point: np.ndarray | None, normal: np.ndarray | None = None) -> None:
        """Place the brush ring (radius :attr:`cursor_radius`) on the surface, or hide it."""
        if point is None:
            self._cursor.SetVisibility(False)
            return
        n = np.asarray(normal, dtype=float) if normal is not None else self._view_axes()[0]
        n = n / (np.linalg.norm(n) or 1.0)
        helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        t1 = np.cross(n, helper)
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        matrix = np.eye(4)
        matrix[:3, 0], matrix[:3, 1], matrix[:3, 2] = (
            t1 * self.cursor_radius,
            t2 * self.cursor_radius,
            n * self.cursor_radius,
        )
        matrix[:3, 3] = point + 1e-3 * self.cursor_radius * n
        self._cursor.SetUserMatrix(pv.vtkmatrix_from_array(matrix))
        self._cursor.SetVisibility(True)

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

    def _sample(self, pos: QPointF, point: np.ndarray, normal: np.ndarray) -> CursorSample:
        view, right = self._view_axes()
        last = self._stroke["pos"] if self._stroke and self._stroke["pos"] is not None else pos
        pixels = (pos.x() - last.x(), last.y() - pos.y())
        return CursorSample(point, normal, view, right, pixels)

    def mousePressEvent(self, ev: QMouseEvent) -> None:
        if ev.button() == Qt.MouseButton.LeftButton and self._stroke is None:
            hit = self.pick(ev.position())
            if hit is not None:
                point, normal = hit
                self._stroke = {"depth": self._depth(point), "normal": normal, "pos": None}
                sample = self._sample(ev.position(), point, normal)
                self._stroke["pos"] = ev.position()
                self.stroke_started.emit(sample)
                return
            self._orbit_button = Qt.MouseButton.LeftButton
            super().mousePressEvent(ev)
        elif ev.button() == Qt.MouseButton.RightButton:
            self._orbit_button = Qt.MouseButton.RightButton
            super().mousePressEvent(self._as_left(ev))  # right drag orbits
        else:
            super().mousePressEvent(ev)

    def mouseMoveEvent(self, ev: QMouseEvent) -> None:
        if self._stroke is not None:
            point = self._unproject(ev.position(), self._stroke["depth"])
            sample = self._sample(ev.position(), point, self._stroke["normal"])
            self._stroke["pos"] = ev.position()
            self.stroke_moved.emit(sample)
            return
        if self._orbit_button == Qt.MouseButton.RightButton:
            super().mouseMoveEvent(self._as_left(ev))
            return
        super().mouseMoveEvent(ev)
        if not ev.buttons():
            hit = self.pick(ev.position())
            self.show_cursor(*(hit if hit else (None, None)))
            self.render()

    def mouseReleaseEvent(self, ev: QMouseEvent) -> None:
        if self._stroke is not None and ev.button() == Qt.MouseButton.LeftButton:
            self._stroke = None
            self.stroke_ended.emit()
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
        return self._stroke is not None
