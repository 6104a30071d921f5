"""Affine brushes in any direction, strokes that change nothing, and an Edit menu that names
what Undo and Redo will do (issue 21 item 3), with real mouse and key events on the window."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import activate, center_of
from PySide6.QtCore import QPoint, Qt
from PySide6.QtTest import QTest


def real_drag(window, qtbot, offsets, modifiers=Qt.KeyboardModifier.NoModifier) -> None:
    """A left-button drag in the viewport through ``offsets`` from its centre, each move
    applied (as the event loop does between mouse events)."""
    vp = window.viewport
    start = center_of(window)
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, modifiers, start)
    for offset in offsets:
        QTest.mouseMove(vp, start + offset)
        vp.flush_tools()
    QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, modifiers, start + offsets[-1])
    qtbot.wait(5)


@pytest.mark.parametrize("kind", ["scale", "twist", "pinch"])
def test_vertical_drags_drive_the_affine_brushes(window, qtbot, kind):
    activate(window, qtbot)
    window.model.brush.kind = kind
    window.model.brush.radius = 0.2
    sculptor = window.document.sculptor
    results = []
    for sign in (-1, 1):  # up, then down
        before = sculptor.vertices.copy()
        real_drag(window, qtbot, [QPoint(0, sign * 10 * k) for k in range(1, 15)])
        moved = np.linalg.norm(sculptor.vertices - before, axis=1)
        assert moved.max() > 1e-3 * sculptor.model_size, (kind, sign)
        assert sculptor.history.undo_labels[-1] == f"{kind.capitalize()} stroke"
        assert window.undo_action.text() == f"&Undo {kind.capitalize()} stroke"
        assert np.array_equal(window.viewport.shown_vertices(), sculptor.vertices)
        results.append(sculptor.vertices - before)
        window.undo()
        assert np.array_equal(sculptor.vertices, before)
        assert window.message_label.text() == f"Undone: {kind.capitalize()} stroke"
        assert window.redo_action.text() == f"&Redo {kind.capitalize()} stroke"
    # up (+) and down (−) act in opposite senses: inflate / deflate, twist one way / the
    # other, stretch / squeeze along the drag
    up, down = results
    assert np.sum(up * down) < 0


def test_a_click_that_changes_nothing_says_so_and_undo_says_there_is_nothing(window, qtbot):
    activate(window, qtbot)
    window.model.brush.kind = "scale"
    sculptor = window.document.sculptor
    assert window.undo_action.text() == "&Undo (nothing to undo)"
    QTest.keyClick(window.viewport, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    assert window.message_label.text() == "Nothing to undo"
    operations = len(sculptor.operations)
    vp = window.viewport
    QTest.mouseClick(vp, Qt.MouseButton.LeftButton, pos=center_of(window))
    qtbot.wait(5)
    assert window.message_label.text().startswith("Nothing changed: the Scale stroke")
    assert not sculptor.history.can_undo and len(sculptor.operations) == operations
    assert not window.document.dirty
    QTest.keyClick(window.viewport, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    assert window.message_label.text() == "Nothing to undo"
    QTest.keyClick(
        window.viewport,
        Qt.Key.Key_Z,
        Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier,
    )
    assert window.message_label.text() == "Nothing to redo"
