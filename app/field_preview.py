"""View → Field Preview: the current brush's field drawn on the surface under the resting cursor.

With a grab, an isotropic and a fibre composite differ by a few percent of the motion: invisible
until the stroke is done. While the preview is on, each time the pointer rests over the model
(and after each stroke) the brush's velocity field for a unit drag is evaluated once at the
vertices it would move (:func:`gogreen_core.sculpt.preview.field_preview`) and those vertices are
coloured by how far they would go: from the model's colour where nothing moves, through blue to
yellow where a vertex follows the cursor entirely (grab brushes; affine brushes are scaled to
their largest motion), in bands of a tenth, so the shape of the region (stretched along fibres,
flattened across layers) reads like a contour map; arrows, about one per ε/2 where a vertex
moves at least a tenth as far, show which way (an anisotropic material turns them away from the
drag). The drag direction is the one the pointer last moved in over the model (the view's up at
first).

The evaluation, its colours and arrows run on the background thread (8 ms on the default model,
0.1 to 0.9 s on a 1M-vertex mesh, ``benchmarks/field_preview.py``); the GUI thread only writes
the colours of the rows that change (about 90 ms for a 1M-vertex preview). A newer rest
supersedes it; a stroke or a moved mesh drops it.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import numpy as np
import pyvista as pv
from PySide6.QtCore import QObject, QSettings, QTimer, Signal
from PySide6.QtGui import QAction

from app.background import BackgroundRunner, Task
from app.mesh_display import MODEL_COLOR
from gogreen_core.interaction.settings import Settings
from gogreen_core.sculpt.preview import FieldPreview, field_preview

if TYPE_CHECKING:
    from app.viewport import SculptViewport

__all__ = ["REST_MS", "FieldPreviewer", "field_colors"]

#: How long the pointer rests before the field is evaluated (ms): moving on costs nothing.
REST_MS = 60
#: Motion (fraction of the cursor's, or of the largest) below which a vertex keeps its colour.
VISIBLE_MOTION = 0.01
#: The colour ramp over the motion in [0, 1]: blue (a little) to yellow (follows the cursor).
_RAMP_AT = np.array([0.0, 0.15, 0.4, 0.7, 1.0])
_RAMP = np.array(
    [[44, 90, 160], [33, 145, 190], [31, 161, 135], [144, 200, 60], [253, 231, 37]],
    dtype=np.float64,
)
#: Alternate tenths of the motion are this much darker (contour bands).
_BAND_SHADE = 0.12


def field_colors(motion: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """RGB (n, 3) uint8 of the motions (n,) ≥ 0 divided by ``scale``: the ramp, banded by
    tenths, faded into the model's colour below :data:`VISIBLE_MOTION`."""
    t = np.clip(np.asarray(motion, dtype=np.float64) / scale, 0.0, 1.0)
    rgb = np.stack([np.interp(t, _RAMP_AT, _RAMP[:, c]) for c in range(3)], axis=1)
    band = np.floor(t * 10).astype(np.int64)  # 10 at t = 1: the full motion is bright
    rgb *= np.where(band % 2 == 1, 1.0 - _BAND_SHADE, 1.0)[:, None]
    base = np.array(pv.Color(MODEL_COLOR).int_rgb, dtype=np.float64)
    fade = np.clip(t / VISIBLE_MOTION - 1.0, 0.0, 1.0)[:, None]  # 0 up to 1 %, 1 from 2 %
    return np.rint(base + fade * (rgb - base)).astype(np.uint8)


def field_arrows(
    points: np.ndarray,
    normals: np.ndarray | None,
    preview: FieldPreview,
    spacing: float,
    length: float,
    scale: float = 1.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Arrows of the preview's field: their feet (k, 3) and vectors (k, 3), at most one per
    cube of side ``spacing`` (model units) among the vertices moving at least a tenth of
    ``scale``; a vertex that moves ``scale`` gets an arrow ``length`` long, centred on it and
    lifted along its unit normal (``normals`` (N, 3), or None) so that an arrow leaving the
    surface's tangent plane is not hidden inside it. ``points``: the vertices (N, 3)."""
    strong = np.flatnonzero(preview.motion >= 0.1 * scale)
    if not len(strong) or not spacing > 0:
        return np.zeros((0, 3)), np.zeros((0, 3))
    rows = preview.rows[strong]
    cells = np.floor(points[rows] / spacing).astype(np.int64)
    cells -= cells.min(axis=0)
    span = cells.max(axis=0) + 1
    keys = (cells[:, 0] * span[1] + cells[:, 1]) * span[2] + cells[:, 2]  # one int a cell
    _, first = np.unique(keys, return_index=True)
    rows, vectors = rows[first], preview.velocity[strong[first]] * (length / scale)
    feet = points[rows] - 0.5 * vectors
    if normals is not None:
        n = normals[rows]
        lift = 0.5 * np.abs(np.einsum("ij,ij->i", vectors, n)) + 0.05 * length
        feet += lift[:, None] * n
    return feet, vectors


class FieldPreviewer(QObject):
    """The field preview of one window's viewport (see the module docstring).

    ``action`` toggles it (remembered in the app's settings as ``field_preview``).

    Signals
    -------
    shown(float, float) : a preview was drawn: its largest motion (fraction of the cursor's for
        grab brushes, ε per unit amount for affine ones) and the seconds it took.
    """

    shown = Signal(float, float)

    def __init__(
        self,
        parent: QObject,
        viewport: SculptViewport,
        model: Settings,
        app_settings: QSettings,
    ) -> None:
        super().__init__(parent)
        self.viewport, self.model, self._app_settings = viewport, model, app_settings
        self.action = QAction("Field &Preview", self, checkable=True)
        self.action.setStatusTip(
            "Colour what the brush would move under the resting cursor: blue a little, yellow "
            "as far as the cursor, in bands of a tenth"
        )
        self.action.setChecked(bool(app_settings.value("field_preview", False, type=bool)))
        self.action.toggled.connect(self._toggled)
        self._rest = QTimer(self, singleShot=True, interval=REST_MS)
        self._rest.timeout.connect(self._evaluate)
        # not this object's child: a job ending after the window is gone reports to a live
        # runner (Qt drops its connections to the deleted previewer)
        self.runner = BackgroundRunner()
        self.runner.finished.connect(self._computed)
        self.destroyed.connect(self.runner.cancel)
        self._job: int | None = None
        self._key: tuple | None = None  # what the shown preview was evaluated for
        self._last_center: np.ndarray | None = None
        self._direction: np.ndarray | None = None  # world, the pointer's last motion
        viewport.hovered.connect(self._hovered)
        viewport.pointer_pressed.connect(lambda _event: self.clear())
        viewport.stroke_ended.connect(self._hovered)
        model.events.changed.connect(lambda _change: self._hovered())
        model.brush.events.changed.connect(lambda _change: self._hovered())

    @property
    def enabled(self) -> bool:
        return self.action.isChecked()

    def _toggled(self, on: bool) -> None:
        self._app_settings.setValue("field_preview", on)
        if on:
            self._hovered()
        else:
            self.clear()

    def clear(self) -> None:
        """No preview: drop the one shown and any on its way."""
        self._rest.stop()
        if self._job is not None:
            self.runner.cancel(self._job)
            self._job = None
        self._key = None
        self.viewport.show_field(None)

    def _hovered(self) -> None:
        """The pointer moved or rests somewhere new, or what the brush does changed."""
        if not self.enabled:
            return
        tools = self.viewport.tools
        state = tools.cursor.state if tools is not None else None
        if state is None or self.viewport.in_stroke or self.viewport.value_dragging:
            self.clear()
            return
        center = np.asarray(state.center, dtype=np.float64)
        if self._last_center is not None:
            moved = center - self._last_center
            if np.linalg.norm(moved) > 0.05 * state.radius:
                self._direction = moved
        self._last_center = center
        self._rest.start()

    def _evaluate(self) -> None:
        """The pointer rested: evaluate the field for it on the background thread."""
        tools = self.viewport.tools
        state = tools.cursor.state if tools is not None else None
        if tools is None or tools.sculptor is None or state is None or self.viewport.in_stroke:
            return
        sculptor, brush = tools.sculptor, tools.stroke_brush()
        axis, right = self.viewport._view_axes()
        direction = self._direction if self._direction is not None else np.cross(right, axis)
        center = np.array(state.center, dtype=np.float64)
        key = (id(sculptor), sculptor.history.done, sculptor.settings, brush, tuple(center))
        if key == self._key and self.viewport.field_shown:
            return  # showing it already
        start = time.perf_counter()
        surface = self.viewport.surface  # the normals the arrows are lifted along

        def evaluate(task: Task) -> tuple | None:
            # everything but drawing here: on a 1M-vertex mesh the colours and arrows take
            # tenths of a second too
            preview = field_preview(sculptor, brush, center, axis, direction)
            task.progress(0.5)  # dropped here if a stroke began meanwhile
            if preview is None:
                return None
            largest = float(preview.motion.max()) if len(preview.motion) else 0.0
            scale = largest if brush.is_affine and largest > 0 else 1.0
            normals = None if surface is None else surface.normals[surface.rank]
            eps = brush.eps(sculptor.model_size)
            arrows = field_arrows(sculptor.vertices, normals, preview, 0.5 * eps, 0.45 * eps, scale)
            colors = field_colors(preview.motion, scale)
            task.progress(1.0)
            return key, preview.rows, colors, arrows, largest, time.perf_counter() - start

        self._job = self.runner.submit(evaluate, supersede=True)

    def _computed(self, job: int, result: tuple | None) -> None:
        if job != self._job:
            return
        self._job = None
        tools = self.viewport.tools
        if result is None or tools is None or tools.sculptor is None or not self.enabled:
            self.viewport.show_field(None)
            return
        key, rows, colors, arrows, largest, seconds = result
        sculptor = tools.sculptor
        if self.viewport.in_stroke or key[:2] != (id(sculptor), sculptor.history.done):
            return  # the mesh moved since: the next rest evaluates again
        self._key = key
        self.viewport.show_field(rows, colors, arrows)
        self.shown.emit(largest, seconds)
