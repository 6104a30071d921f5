"""The Mesh menu and the new tools in the window, with real key and mouse events: the mask
brush and its tint, Ctrl+I / Alt+M, Shift-drag smoothing, Ctrl+D subdivision (in the
background for big meshes), undo of each."""

from __future__ import annotations

import numpy as np
from gui_helpers import activate, center_of, steps_done
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QInputDialog

import app.mesh_edits as mesh_edits
from app.mesh_display import COLOR_ARRAY
from gogreen_core.mesh.remesh import median_edge_length

CTRL = Qt.KeyboardModifier.ControlModifier
ALT = Qt.KeyboardModifier.AltModifier
SHIFT = Qt.KeyboardModifier.ShiftModifier


def drag_with(window, start: QPoint, modifiers=Qt.KeyboardModifier.NoModifier, steps=6):
    """A left drag in the viewport with ``modifiers`` held, the tools flushed after each move."""
    vp = window.viewport

    def event(kind, pos, button, buttons):
        p = QPointF(pos)
        return QMouseEvent(kind, p, vp.mapToGlobal(p), button, buttons, modifiers)

    left, none = Qt.MouseButton.LeftButton, Qt.MouseButton.NoButton
    vp.mousePressEvent(event(QMouseEvent.Type.MouseButtonPress, start, left, left))
    steps_done(vp)
    pos = start
    for _ in range(steps):
        pos = pos + QPoint(6, -4)
        vp.mouseMoveEvent(event(QMouseEvent.Type.MouseMove, pos, none, left))
        window.viewport.flush_tools()
        steps_done(vp)  # a dynamic-topology step runs off the GUI thread
    vp.mouseReleaseEvent(event(QMouseEvent.Type.MouseButtonRelease, pos, left, none))
    steps_done(vp)


def shown_colors(window):
    """The tint colours (N, 3) in the mesh's vertex order, None without a tint."""
    vp = window.viewport
    if COLOR_ARRAY not in vp.mesh.point_data:
        return None
    colors = np.asarray(vp.mesh.point_data[COLOR_ARRAY])
    return colors[vp.surface.rank] if vp.surface is not None else colors


def test_mask_brush_tint_and_the_mask_keys(window, qtbot):
    activate(window, qtbot)
    window.viewport.setFocus()
    sculptor = window.document.sculptor
    start = sculptor.vertices.copy()
    QTest.keyClick(window.viewport, Qt.Key.Key_M)
    assert window.model.brush.kind == "mask"
    drag_with(window, center_of(window))
    mask = sculptor.mask.values.copy()
    assert mask.max() == 1.0 and np.array_equal(sculptor.vertices, start)
    colors = shown_colors(window)
    assert window.viewport.mask_shown and colors is not None
    held, free = mask == 1.0, mask == 0.0
    assert colors[held].sum(axis=1).max() < colors[free].sum(axis=1).min()  # darker
    QTest.keyClick(window.viewport, Qt.Key.Key_I, CTRL)  # invert
    assert np.array_equal(sculptor.mask.values, 1.0 - mask)
    assert (
        shown_colors(window)[held].sum(axis=1).min() > shown_colors(window)[free].sum(axis=1).max()
    )
    QTest.keyClick(window.viewport, Qt.Key.Key_M, ALT)  # clear
    assert not sculptor.mask.any and not window.viewport.mask_shown
    assert shown_colors(window) is None
    QTest.keyClick(window.viewport, Qt.Key.Key_Z, CTRL)  # undo the clear
    assert np.array_equal(sculptor.mask.values, 1.0 - mask) and window.viewport.mask_shown
    assert sculptor.history.undo_labels[-2:] == ["Mask stroke", "invert mask"]
    # a grab over the held region moves the free vertices only
    QTest.keyClick(window.viewport, Qt.Key.Key_1)
    drag_with(window, center_of(window))
    held = sculptor.mask.values == 1.0
    assert np.array_equal(sculptor.vertices[held], start[held])
    window.viewport.render_now()


def test_shift_drag_smooths_with_any_brush(window, qtbot):
    sculptor = window.document.sculptor
    window.model.brush.kind = "grab"
    start = sculptor.vertices.copy()
    drag_with(window, center_of(window), SHIFT)
    assert sculptor.operations[-1].brush.kind == "smooth"
    assert sculptor.operations[-1].brush.radius == window.model.brush.radius
    assert sculptor.history.undo_labels[-1] == "Smooth stroke"
    assert np.any(sculptor.vertices != start)
    window.undo()
    assert np.array_equal(sculptor.vertices, start)


def test_ctrl_d_subdivides_and_undo_gives_the_mesh_back(window, qtbot):
    activate(window, qtbot)
    window.viewport.setFocus()
    sculptor = window.document.sculptor
    faces, vertices = sculptor.faces.copy(), sculptor.vertices.copy()
    QTest.keyClick(window.viewport, Qt.Key.Key_D, CTRL)
    assert len(sculptor.faces) == 4 * len(faces)
    assert window.viewport.mesh.n_cells == 4 * len(faces)
    assert window.viewport.mesh.n_points == len(sculptor.vertices)
    assert window.document.dirty and "•" in window.windowTitle()
    assert "Subdivided" in window.message_label.text()
    assert window.viewport.pick(QPointF(center_of(window))) is not None  # picking on it
    drag_with(window, center_of(window))  # and sculpting
    assert sculptor.history.undo_labels[-2:] == ["subdivide", "Grab stroke"]
    window.undo()
    window.undo()
    assert np.array_equal(sculptor.faces, faces) and np.array_equal(sculptor.vertices, vertices)
    assert window.viewport.mesh.n_cells == len(faces)
    assert np.array_equal(window.viewport.shown_vertices(), vertices)
    assert not window.document.dirty
    window.redo()
    assert window.viewport.mesh.n_cells == 4 * len(faces)


def test_a_big_subdivision_runs_in_the_background(window, qtbot, monkeypatch):
    monkeypatch.setattr(mesh_edits, "BACKGROUND_SUBDIVISION_FACES", 1)
    edits = window.mesh_edits
    sculptor = window.document.sculptor
    faces = len(sculptor.faces)
    window.model.brush.kind = "mask"
    drag_with(window, center_of(window))  # a mask to carry and a part to subdivide
    edits.subdivide_unmasked_action.trigger()
    assert edits.busy and not edits.subdivide_action.isEnabled()
    assert "refine" not in window.message_label.text()
    # meanwhile nothing changes the mesh: strokes, undo and mask edits wait
    update = window.tools.press(
        window.viewport.pointer_event(QPointF(center_of(window)), sculptor.vertices[0])
    )
    assert update.refused and "subdivided" in update.error
    window.undo()
    assert "Cannot undo" in window.message_label.text()
    assert edits.wait(120_000)
    qtbot.waitUntil(lambda: not edits.busy, timeout=10_000)
    assert faces < len(sculptor.faces) < 4 * faces  # the unmasked part alone
    assert sculptor.history.undo_labels[-1] == "subdivide"
    assert window.viewport.mask_shown and len(shown_colors(window)) == len(sculptor.vertices)
    assert edits.subdivide_action.isEnabled() and edits.last_seconds > 0
    window.undo()
    assert len(sculptor.faces) == faces and window.viewport.mesh.n_cells == faces


def test_dynamic_topology_toggle_a_remeshing_drag_and_remesh(window, qtbot, monkeypatch):
    activate(window, qtbot)
    window.viewport.setFocus()
    sculptor = window.document.sculptor
    faces, vertices = sculptor.faces.copy(), sculptor.vertices.copy()
    QTest.keyClick(window.viewport, Qt.Key.Key_D, CTRL | ALT)  # Ctrl+Alt+D (Ctrl+D subdivides)
    assert sculptor.settings.dynamic_topology and window.model.dynamic_topology
    assert window.mesh_edits.dynamic_topology_action.isChecked()
    assert len(sculptor.faces) == len(faces)  # not subdivided
    window.model.detail_size = 0.004  # finer than the model's edges: the drag splits them
    drag_with(window, center_of(window), steps=4)
    assert len(sculptor.faces) > len(faces)
    assert window.viewport.mesh.n_cells == len(sculptor.faces)  # the new faces are shown
    assert window.viewport.mesh.n_points == len(sculptor.vertices)
    assert np.array_equal(window.viewport.shown_vertices(), sculptor.vertices)
    window.undo()
    assert np.array_equal(sculptor.faces, faces) and np.array_equal(sculptor.vertices, vertices)
    assert window.viewport.mesh.n_cells == len(faces)
    monkeypatch.setattr(
        QInputDialog, "getDouble", staticmethod(lambda *args, **kwargs: (1.0, True))
    )
    window.mesh_edits.ask_detail_size()
    assert window.model.detail_size == 0.01 and sculptor.settings.detail_size == 0.01
    QTest.keyClick(window.viewport, Qt.Key.Key_R, CTRL)  # Ctrl+R: Remesh (Blender's key)
    window.mesh_edits.wait()
    qtbot.waitUntil(lambda: "Remeshed" in window.message_label.text())
    median = median_edge_length(sculptor.vertices, sculptor.faces)
    assert 0.8 < median / (0.01 * sculptor.model_size) < 4.0 / 3.0
    assert window.viewport.mesh.n_cells == len(sculptor.faces)
    assert sculptor.history.undo_labels[-1] == "remesh"
    window.undo()
    assert np.array_equal(sculptor.faces, faces)


def test_a_dynamic_topology_drag_draws_new_faces_without_rebuilding_the_view(
    window, qtbot, monkeypatch
):
    """Each event's new faces go into the same actor (no new mesh shown, camera and pins
    kept); the whole mesh is shown and indexed anew once, when the stroke ends."""
    activate(window, qtbot)
    window.viewport.setFocus()
    sculptor = window.document.sculptor
    window.model.dynamic_topology = True
    window.model.detail_size = 0.004
    viewport = window.viewport
    rebuilt, drawn = [], []
    set_mesh = viewport.set_mesh

    def spy(vertices, faces, *args, in_stroke=False, **kwargs):
        set_mesh(vertices, faces, *args, in_stroke=in_stroke, **kwargs)
        if in_stroke:
            drawn.append(viewport.mesh.n_cells == len(faces))
            assert not rebuilt  # nothing rebuilt during the stroke
        else:
            rebuilt.append(1)

    monkeypatch.setattr(viewport, "set_mesh", spy)
    drag_with(window, center_of(window), steps=4)
    assert drawn and all(drawn)  # each event's faces drawn as they came
    assert len(rebuilt) == 1  # once, at the end
    assert viewport.mesh.n_cells == len(sculptor.faces)
    assert np.array_equal(viewport.shown_vertices(), sculptor.vertices)


def test_remesh_runs_in_the_background_and_ctrl_r_again_cancels_it(window, qtbot):
    activate(window, qtbot)
    window.viewport.setFocus()
    sculptor = window.document.sculptor
    faces, steps = sculptor.faces.copy(), len(sculptor.history.undo_labels)
    edits = window.mesh_edits
    QTest.keyClick(window.viewport, Qt.Key.Key_R, CTRL)
    assert edits.busy and "remeshed" in edits.refusal()  # strokes and edits wait for it
    QTest.keyClick(window.viewport, Qt.Key.Key_R, CTRL)  # again: cancelled
    assert not edits.busy and "cancelled" in window.message_label.text()
    edits.wait()
    qtbot.wait(50)
    assert np.array_equal(sculptor.faces, faces)  # the mesh untouched, no undo step
    assert len(sculptor.history.undo_labels) == steps


def test_remesh_without_a_detail_size_keeps_the_surfaces_own_edges(window, qtbot):
    """No detail size: each vertex keeps its own edge length (issue 34), so the vertex count
    stays near the model's, and the status bar says so."""
    activate(window, qtbot)
    window.viewport.setFocus()
    sculptor = window.document.sculptor
    window.model.detail_size = None
    count = len(sculptor.vertices)
    QTest.keyClick(window.viewport, Qt.Key.Key_R, CTRL)
    window.mesh_edits.wait()
    qtbot.waitUntil(lambda: "Remeshed" in window.message_label.text())
    assert "own edge lengths" in window.message_label.text()
    assert 0.8 * count <= len(sculptor.vertices) <= 1.2 * count
    assert sculptor.history.undo_labels[-1] == "remesh"
