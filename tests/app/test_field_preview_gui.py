"""View → Field Preview (the paper-controls issue, item 7): under the resting cursor the surface
is coloured by how far the current brush would move each vertex, computed off the GUI thread,
gone during a stroke and when switched off; the mask still darkens what it holds."""

from __future__ import annotations

import numpy as np
import pyvista as pv
from gui_helpers import activate, center_of, hover
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtTest import QTest

from app.field_preview import field_arrows, field_colors
from app.mesh_display import COLOR_ARRAY, MODEL_COLOR
from gogreen_core import Material
from gogreen_core.sculpt.preview import FieldPreview

NO_KEYS = Qt.KeyboardModifier.NoModifier
MODEL_RGB = np.array(pv.Color(MODEL_COLOR).int_rgb)


def shown_colors(window) -> np.ndarray | None:
    vp = window.viewport
    if COLOR_ARRAY not in vp.mesh.point_data:
        return None
    colors = np.asarray(vp.mesh.point_data[COLOR_ARRAY]).astype(int)
    return colors[vp.surface.rank] if vp.surface is not None else colors


def rest_over(window, qtbot, pos: QPoint) -> tuple[float, float]:
    """Hover at ``pos`` and wait for the preview drawn there: (largest motion, seconds)."""
    with qtbot.waitSignal(window.field_preview.shown, timeout=20_000) as shown:
        hover(window, pos)
    return tuple(shown.args)


def test_field_colors_ramp_bands_and_fade():
    colors = field_colors(np.array([0.0, 0.005, 0.5, 1.0, 3.0]))
    assert np.array_equal(colors[0], MODEL_RGB) and np.array_equal(colors[1], MODEL_RGB)
    assert np.array_equal(colors[3], [253, 231, 37]) and np.array_equal(colors[4], colors[3])
    bands = field_colors(np.array([0.29, 0.31]))  # tenths alternate light and dark
    assert bands[1].sum() < bands[0].sum() * 0.95
    assert np.array_equal(field_colors(np.array([2.0]), scale=4.0), field_colors(np.array([0.5])))


def test_field_arrows_one_per_cell_where_vertices_move():
    points = np.array([[0.0, 0, 0], [0.01, 0, 0], [1.0, 0, 0], [2.0, 0, 0]])
    velocity = np.array([[1.0, 0, 0], [0.9, 0, 0], [0, 0.5, 0], [0, 0.01, 0]])
    preview = FieldPreview(np.arange(4), velocity, np.linalg.norm(velocity, axis=1))
    feet, vectors = field_arrows(points, None, preview, spacing=0.5, length=0.2)
    assert len(feet) == 2  # one for the two close vertices, none for the still one
    assert np.allclose(np.sort(np.linalg.norm(vectors, axis=1)), [0.1, 0.2])
    assert np.allclose(feet + 0.5 * vectors, points[[0, 2]])  # centred on their vertices
    up = np.tile([0.0, 1.0, 0.0], (4, 1))  # lifted along the normal, more when leaving it
    lifted, _ = field_arrows(points, up, preview, spacing=0.5, length=0.2)
    assert np.allclose(lifted - feet, [[0, 0.01, 0], [0, 0.01 + 0.05, 0]])


def test_the_preview_colours_what_the_brush_would_move_and_goes_during_a_stroke(window, qtbot):
    activate(window, qtbot)
    vp = window.viewport
    sculptor = window.document.sculptor
    # the wide grab (key 1's is sharper: its vertex nearest the cursor moves 0.9 of it)
    window.model.brush.kind = "grab"
    window.model.brush.influence = 4.0  # a ball smaller than the model: some vertices stay
    assert not window.field_preview.enabled and shown_colors(window) is None
    QTest.keyClick(vp, Qt.Key.Key_V, Qt.KeyboardModifier.ShiftModifier)
    assert window.field_preview.enabled and window.settings.value("field_preview") in (True, "true")
    before = sculptor.vertices.copy()
    largest, seconds = rest_over(window, qtbot, center_of(window))
    assert 0.99 < largest <= 1.0 + 1e-9 and seconds < 5.0  # a grab: the cursor's vertex follows
    colors = shown_colors(window)
    state = vp.tools.cursor.state
    distance = np.linalg.norm(sculptor.vertices - state.center, axis=1)
    near = distance < 0.5 * state.radius
    far = distance > 1.1 * state.influence * state.radius
    assert near.any() and far.any()
    assert np.abs(colors[near] - MODEL_RGB).sum(axis=1).min() > 60  # coloured where it moves
    assert (colors[far] == MODEL_RGB).all()  # untouched where it cannot reach
    assert np.array_equal(sculptor.vertices, before)  # a preview, not a stroke
    arrows = vp.field_arrow_actor
    assert arrows.GetVisibility() and arrows.mapper.GetInput().GetNumberOfPoints() > 0
    # a stroke hides it; resting again after the stroke shows it again
    left, none = Qt.MouseButton.LeftButton, Qt.MouseButton.NoButton

    def mouse(kind, pos, button, buttons):
        return QMouseEvent(kind, pos, vp.mapToGlobal(pos), button, buttons, NO_KEYS)

    start = QPointF(center_of(window))
    vp.mousePressEvent(mouse(QMouseEvent.Type.MouseButtonPress, start, left, left))
    assert not vp.field_shown and shown_colors(window) is None
    assert not arrows.GetVisibility()
    end = start + QPointF(8, -5)
    vp.mouseMoveEvent(mouse(QMouseEvent.Type.MouseMove, end, none, left))
    vp.flush_tools()
    with qtbot.waitSignal(window.field_preview.shown, timeout=20_000):
        vp.mouseReleaseEvent(mouse(QMouseEvent.Type.MouseButtonRelease, end, left, none))
    assert not np.array_equal(sculptor.vertices, before) and vp.field_shown
    # the material shows: the same rest with a fibre composite colours the vertices otherwise
    first = shown_colors(window)
    with qtbot.waitSignal(window.field_preview.shown, timeout=20_000):
        window.model.material = Material.transversely_isotropic(40.0, 1.0, 0.25, 0.3, 0.5)
    assert (np.abs(shown_colors(window) - first).sum(axis=1) > 30).sum() > 50
    # off: the plain model again, remembered
    QTest.keyClick(vp, Qt.Key.Key_V, Qt.KeyboardModifier.ShiftModifier)
    assert not vp.field_shown and shown_colors(window) is None
    assert window.settings.value("field_preview") in (False, "false")


def test_the_preview_leaves_out_what_the_mask_holds_and_the_tint_stays(window, qtbot):
    activate(window, qtbot)
    vp = window.viewport
    sculptor = window.document.sculptor
    window.model.brush.influence = 4.0
    window.field_preview.action.setChecked(True)
    rest_over(window, qtbot, center_of(window))
    free = shown_colors(window)
    state = vp.tools.cursor.state
    side = (sculptor.vertices - state.center) @ np.cross(state.normal, [0.0, 1.0, 0.0]) > 0
    values = np.where(side, 1.0, 0.0)
    sculptor.mask._change("mask stroke", np.arange(len(values)), values)  # half held
    vp.show_sculptor()
    rest_over(window, qtbot, center_of(window) + QPoint(1, 0))
    colors = shown_colors(window)
    tint = np.rint((1.0 - 0.6) * MODEL_RGB)
    assert np.array_equal(colors[side], np.broadcast_to(tint, colors[side].shape))  # held: tint
    moving = ~side & (np.abs(free - MODEL_RGB).sum(axis=1) > 60)
    assert moving.sum() > 5 and np.abs(colors[moving] - MODEL_RGB).sum(axis=1).min() > 30
    window.field_preview.action.setChecked(False)
    colors = shown_colors(window)
    assert np.array_equal(colors[side], np.broadcast_to(tint, colors[side].shape))
    assert (colors[~side] == MODEL_RGB).all()
