"""Blender navigation (issue 21 item 4) with real mouse and key events on the window: middle
drag orbits, Shift+middle pans, Ctrl+middle and the wheel zoom, numpad 1 / 3 / 7 (Ctrl: the
opposite side) pick views, numpad 5 switches the projection, ``.`` frames the model about the
point under the cursor; a left drag begun off the model sculpts from where it reaches it. The
first scheme (right drag orbits, middle pans) and a left drag off the model that orbits stay as
preferences."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import activate, center_of
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QCursor
from PySide6.QtTest import QTest

B = Qt.MouseButton
M = Qt.KeyboardModifier


def camera(window) -> dict[str, np.ndarray]:
    cam = window.viewport.renderer.GetActiveCamera()
    position, focal = np.array(cam.GetPosition()), np.array(cam.GetFocalPoint())
    return {
        "position": position,
        "focal": focal,
        "distance": np.linalg.norm(position - focal),
        "direction": (position - focal) / np.linalg.norm(position - focal),
        "up": np.array(cam.GetViewUp()),
    }


def mouse_drag(window, button, modifiers=M.NoModifier, start=None, offset=None):
    """A drag with ``button`` (and ``modifiers``) in the viewport, in eight moves."""
    vp = window.viewport
    start = center_of(window) if start is None else start
    offset = QPoint(60, 40) if offset is None else offset
    QTest.mousePress(vp, button, modifiers, start)
    for k in range(1, 9):
        QTest.mouseMove(vp, start + offset * k / 8)
        vp.flush_tools()
    QTest.mouseRelease(vp, button, modifiers, start + offset)


def test_blender_mouse_navigation(window, qtbot):
    activate(window, qtbot)
    sculptor = window.document.sculptor
    vertices = sculptor.vertices.copy()
    before = camera(window)
    mouse_drag(window, B.MiddleButton)  # orbit: the camera turns about the same centre
    orbited = camera(window)
    assert np.allclose(orbited["focal"], before["focal"])
    assert np.isclose(orbited["distance"], before["distance"])
    assert orbited["direction"] @ before["direction"] < 0.99
    mouse_drag(window, B.MiddleButton, M.ShiftModifier)  # pan: centre and camera move along
    panned = camera(window)
    assert np.linalg.norm(panned["focal"] - orbited["focal"]) > 1e-3 * before["distance"]
    assert np.allclose(panned["direction"], orbited["direction"], atol=1e-6)
    mouse_drag(window, B.MiddleButton, M.ControlModifier, offset=QPoint(0, -80))  # zoom
    zoomed = camera(window)
    assert abs(zoomed["distance"] - panned["distance"]) > 1e-3 * panned["distance"]
    assert np.allclose(zoomed["direction"], panned["direction"], atol=1e-6)
    QTest.mouseClick(window.viewport, B.RightButton, pos=center_of(window))  # no gesture
    mouse_drag(window, B.RightButton)
    assert np.allclose(camera(window)["position"], zoomed["position"])
    # the sculpture never moved
    assert np.array_equal(sculptor.vertices, vertices) and not sculptor.history.can_undo


def test_numpad_views_projection_and_framing(window, qtbot):
    activate(window, qtbot)
    vp = window.viewport
    vp.setFocus()
    keypad = M.KeypadModifier
    for key, modifiers, direction, up in (
        (Qt.Key.Key_1, keypad, (0, 0, 1), (0, 1, 0)),
        (Qt.Key.Key_1, keypad | M.ControlModifier, (0, 0, -1), (0, 1, 0)),
        (Qt.Key.Key_3, keypad, (1, 0, 0), (0, 1, 0)),
        (Qt.Key.Key_3, keypad | M.ControlModifier, (-1, 0, 0), (0, 1, 0)),
        (Qt.Key.Key_7, keypad, (0, 1, 0), (0, 0, -1)),
        (Qt.Key.Key_7, keypad | M.ControlModifier, (0, -1, 0), (0, 0, 1)),
        (Qt.Key.Key_End, keypad, (0, 0, 1), (0, 1, 0)),  # numpad 1 with NumLock off
    ):
        kind = window.model.brush.kind
        QTest.keyClick(vp, key, modifiers)
        now = camera(window)
        np.testing.assert_allclose(now["direction"], direction, atol=1e-9, err_msg=str(key))
        np.testing.assert_allclose(now["up"], up, atol=1e-9)
        assert window.model.brush.kind == kind  # numpad 1 and 3 are views, not brushes
    QTest.keyClick(vp, Qt.Key.Key_3)  # the top row's 3 still picks the tri-scale brush
    assert window.model.brush.kind == "grab_triscale"
    assert not vp.orthographic
    QTest.keyClick(vp, Qt.Key.Key_5, keypad)
    assert vp.orthographic
    QTest.keyClick(vp, Qt.Key.Key_5, keypad)
    assert not vp.orthographic
    # "." frames the model about the point under the cursor
    QTest.keyClick(vp, Qt.Key.Key_1, keypad)
    target = center_of(window) + QPoint(40, -30)
    hit = vp.pick(QPointF(target))
    assert hit is not None
    QCursor.setPos(vp.mapToGlobal(target))
    qtbot.waitUntil(lambda: vp.mapFromGlobal(QCursor.pos()) == target, timeout=2000)
    QTest.keyClick(vp, Qt.Key.Key_Period)
    np.testing.assert_allclose(camera(window)["focal"], hit[0], atol=1e-9)
    vp.render_now()
    assert vp.pick(QPointF(vp.width() / 2, vp.height() / 2)) is not None  # centred on it


def test_a_left_drag_begun_off_the_model_sculpts_from_where_it_reaches_it(window, qtbot):
    activate(window, qtbot)
    sculptor = window.document.sculptor
    vertices = sculptor.vertices.copy()
    before = camera(window)
    corner = QPoint(15, 15)
    assert window.viewport.pick(QPointF(corner)) is None  # off the model
    mouse_drag(window, B.LeftButton, start=corner, offset=center_of(window) - corner)
    assert not np.array_equal(sculptor.vertices, vertices)
    assert sculptor.history.undo_labels == ["Grab stroke"]
    assert np.allclose(camera(window)["position"], before["position"])  # no orbit
    window.undo()
    # the preference: it orbits, and sculpts nothing
    window.navigation.set_left_on_background("orbit")
    mouse_drag(window, B.LeftButton, start=corner, offset=center_of(window) - corner)
    assert np.array_equal(sculptor.vertices, vertices)
    assert not np.allclose(camera(window)["position"], before["position"])


@pytest.mark.parametrize("scheme", ["classic"])
def test_the_first_scheme_stays_as_a_preference(window, qtbot, scheme):
    activate(window, qtbot)
    window.navigation.actions[scheme].trigger()
    assert window.settings.value("navigation") == scheme
    before = camera(window)
    mouse_drag(window, B.RightButton)  # orbit
    orbited = camera(window)
    assert np.allclose(orbited["focal"], before["focal"])
    assert orbited["direction"] @ before["direction"] < 0.99
    mouse_drag(window, B.MiddleButton)  # pan
    assert np.linalg.norm(camera(window)["focal"] - orbited["focal"]) > 0
    window.navigation.actions["blender"].trigger()
    assert window.viewport.navigation == "blender"
