"""Fixes from a new user's walkthrough, driven with real Qt events where possible: Ctrl+Y
redoes, F12 exports the model without the brush cursor, the cursor hides when the pointer
leaves the viewport or a dialog takes the input, VTK's and pyvista's own keys do nothing,
Save As proposes a file name."""

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from tests.test_app import activate, center_of, drag


def test_ctrl_y_redoes_like_ctrl_shift_z(window, qtbot):
    sculptor = window.document.sculptor
    before = sculptor.vertices.copy()
    drag(window, center_of(window))
    after = sculptor.vertices.copy()
    assert not np.array_equal(after, before)
    activate(window, qtbot)
    window.viewport.setFocus()
    for redo_key in (
        (Qt.Key.Key_Y, Qt.KeyboardModifier.ControlModifier),
        (Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier),
    ):
        QTest.keyClick(window.viewport, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
        assert np.array_equal(sculptor.vertices, before)
        QTest.keyClick(window.viewport, *redo_key)
        assert np.array_equal(sculptor.vertices, after), redo_key
        assert np.array_equal(window.viewport.shown_vertices(), after)
    # the keymap overlay and the Redo action's tool tip show both keys
    window.keymap_action.trigger()
    assert any(
        "Ctrl+Y" in line and line.endswith("— Redo") for line in window.keymap_overlay.text_lines()
    )
    assert "Ctrl+Y" in window.redo_action.toolTip()
