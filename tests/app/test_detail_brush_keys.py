"""The detail brushes in the app (issue 34 item 3): their keys pick them, the brush bar shows
them, and a drag with Draw raises the surface under the cursor."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import activate, center_of, drag
from PySide6.QtCore import Qt
from PySide6.QtGui import QKeySequence
from PySide6.QtTest import QTest

from gogreen_core.mesh.geometry import vertex_normals

DETAIL_KEYS = {
    "draw": "X",
    "clay_strips": "L",
    "crease": "Shift+C",
    "flatten": "Shift+T",
    "inflate": "I",
}


@pytest.mark.parametrize("kind", DETAIL_KEYS)
def test_a_key_picks_the_detail_brush_the_bar_shows(window, qtbot, kind):
    activate(window, qtbot)
    window.viewport.setFocus()
    combination = QKeySequence(DETAIL_KEYS[kind])[0]
    QTest.keyClick(window.viewport, combination.key(), combination.keyboardModifiers())
    assert window.model.brush.kind == kind
    action = window.brush_bar.kind_actions[kind]
    assert action.isChecked() and action.isVisible() and not action.icon().isNull()
    assert [k.toString() for k in action.shortcuts()] == [DETAIL_KEYS[kind]]


def test_the_bar_shows_the_detail_brushes_after_smooth_and_mask(window):
    labels = [action.text() for action in window.brush_bar.kind_actions.values()]
    assert labels[-5:] == ["Draw", "Clay Strips", "Crease", "Flatten", "Inflate"]


def test_a_draw_drag_raises_the_surface_under_the_cursor(window, qtbot):
    activate(window, qtbot)
    window.viewport.setFocus()
    QTest.keyClick(window.viewport, Qt.Key.Key_X)
    sculptor = window.document.sculptor
    before = sculptor.vertices.copy()
    drag(window, center_of(window))
    motion = sculptor.vertices - before
    moved = np.linalg.norm(motion, axis=1) > 0
    assert moved.sum() > 10
    outward = np.einsum("ij,ij->i", motion, vertex_normals(before, sculptor.faces))
    # out along the surface's normal where it moved most (the rim follows the area normal)
    most = np.argsort(np.linalg.norm(motion, axis=1))[-10:]
    assert np.all(outward[most] > 0.9 * np.linalg.norm(motion[most], axis=1))
    assert np.mean(outward[moved] > 0) > 0.9
    assert sculptor.history.undo_labels[-1] == "Draw stroke"


def test_a_paint_stroke_follows_the_surface_under_the_cursor(window, qtbot, monkeypatch):
    """A sweep's moves are picked on the surface (as Blender casts each dab onto it), not on
    the drag plane through the press point, which leaves a curved model behind it."""
    from gui_helpers import send
    from PySide6.QtCore import QPoint
    from PySide6.QtGui import QMouseEvent

    activate(window, qtbot)
    window.viewport.setFocus()
    QTest.keyClick(window.viewport, Qt.Key.Key_M)  # the mask: it paints, nothing moves
    tools = window.viewport.tools
    points = []
    move = tools.move
    monkeypatch.setattr(tools, "move", lambda event: (points.append(event.point), move(event)))
    vp, start = window.viewport, center_of(window) - QPoint(150, 0)
    send(vp, QMouseEvent.Type.MouseButtonPress, start)
    for k in range(1, 16):
        pos = start + QPoint(20 * k, 0)
        send(
            vp, QMouseEvent.Type.MouseMove, pos, Qt.MouseButton.NoButton, Qt.MouseButton.LeftButton
        )
    send(vp, QMouseEvent.Type.MouseButtonRelease, pos, buttons=Qt.MouseButton.NoButton)
    sculptor = window.document.sculptor
    gap = [surface_gap(sculptor.vertices, sculptor.faces, point) for point in points]
    assert len(points) >= 10 and max(gap) < 1e-6 * sculptor.model_size
    assert window.model.brush.kind == "mask" and sculptor.mask.any


def surface_gap(vertices: np.ndarray, faces: np.ndarray, point: np.ndarray) -> float:
    """How far ``point`` is from the faces it projects into (inf when it projects into none)."""
    a, b, c = (vertices[faces[:, k]] for k in range(3))
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    height = np.einsum("ij,ij->i", point - a, normal)
    foot = point - height[:, None] * normal
    inside = np.ones(len(faces), dtype=bool)
    for p, q in ((a, b), (b, c), (c, a)):
        turn = np.einsum("ij,ij->i", np.cross(q - p, foot - p), normal)
        inside &= turn >= -1e-9
    return float(np.abs(height[inside]).min()) if inside.any() else np.inf
