"""The brush cursor overlay in the main window: where it sits, when it updates and hides."""

import pytest
from PySide6.QtCore import QPoint, QPointF, QSettings, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtWidgets import QMessageBox

from app.main_window import MainWindow
from tests.test_app import center_of, drag, send


@pytest.fixture
def window(qtbot, tmp_path, monkeypatch, made_textured):
    monkeypatch.setattr(QMessageBox, "warning", lambda *a, **k: QMessageBox.StandardButton.Ok)
    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: QMessageBox.StandardButton.Discard)
    win = MainWindow(QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat))
    qtbot.addWidget(win)
    win.show()
    qtbot.waitExposed(win)
    assert win.open_file(str(made_textured.path))
    assert win.kernel_warmer.wait(120_000)
    win.viewport.render()
    return win


def hover(window, pos):
    send(
        window.viewport,
        QMouseEvent.Type.MouseMove,
        pos,
        Qt.MouseButton.NoButton,
        Qt.MouseButton.NoButton,
    )
    window.viewport._emit_hover()
    window._process_tools()
    window.viewport.render_now()


def test_cursor_shows_radius_and_influence_and_updates_without_a_move(window):
    vp = window.viewport
    hover(window, center_of(window))
    assert vp.cursor_visible
    (_, eps_px, outer_px) = vp.cursor_overlay.screen
    assert outer_px == pytest.approx(window.model.brush.influence * eps_px)
    window.model.brush.radius = 2 * window.model.brush.radius  # no mouse move
    vp.render_now()
    assert vp.cursor_overlay.screen[1] == pytest.approx(2 * eps_px, rel=0.05)
    window.model.brush.influence = 2.0
    vp.render_now()
    assert vp.cursor_overlay.screen[2] == pytest.approx(2.0 * vp.cursor_overlay.screen[1])


def test_cursor_hides_after_undo_and_open_until_the_mouse_moves(window, made_textured):
    vp = window.viewport
    drag(window, center_of(window))
    hover(window, center_of(window))
    assert vp.cursor_visible
    window.undo()
    assert not vp.cursor_visible
    window.model.brush.radius = 0.5 * window.model.brush.radius  # must not bring it back
    assert not vp.cursor_visible
    hover(window, center_of(window))
    assert vp.cursor_visible
    assert window.open_file(str(made_textured.path))
    window.model.brush.radius = 0.5 * window.model.brush.radius
    assert not vp.cursor_visible
    assert vp.pick(QPointF(center_of(window))) is not None


def key(window, key, modifiers=Qt.KeyboardModifier.NoModifier, text=""):
    from PySide6.QtGui import QKeyEvent

    window.viewport.keyPressEvent(QKeyEvent(QKeyEvent.Type.KeyPress, key, modifiers, text))


def test_f_drags_the_radius_on_screen_and_escape_restores_it(window):
    vp = window.viewport
    center = center_of(window)
    hover(window, center)
    (x, y), eps_px, _ = vp.cursor_overlay.screen
    start = window.model.brush.radius
    edge = QPointF(x + eps_px, vp.height() - 1 - y)
    vp.start_value_drag("radius", edge)
    assert vp.value_dragging
    moved = QPointF(x + 2 * eps_px, vp.height() - 1 - y)
    send(vp, QMouseEvent.Type.MouseMove, moved, Qt.MouseButton.NoButton, Qt.MouseButton.NoButton)
    assert window.model.brush.radius == pytest.approx(2 * start, rel=0.02)
    vp.render_now()
    assert vp.cursor_overlay.screen[1] == pytest.approx(2 * eps_px, rel=0.05)  # live ring
    assert vp.cursor_overlay.state.label.startswith("Radius")
    key(window, Qt.Key.Key_Escape)
    assert window.model.brush.radius == start and not vp.value_dragging
    # Shift+F then a left click keeps the new strength; F via the key
    key(window, Qt.Key.Key_F, Qt.KeyboardModifier.ShiftModifier, "F")
    assert vp.value_dragging and vp.tools.value_drag.name == "strength"
    key(window, Qt.Key.Key_Return)
    assert not vp.value_dragging


def test_number_keys_and_a_click_confirming_a_radius_drag(window):
    vp = window.viewport
    key(window, Qt.Key.Key_5, text="5")
    assert window.model.brush.kind == "scale"
    key(window, Qt.Key.Key_1, text="1")
    assert window.model.brush.kind == "grab"
    hover(window, center_of(window))
    before = window.document.sculptor.vertices.copy()
    vp.start_value_drag("radius", QPointF(center_of(window)) + QPointF(30, 0))
    send(
        vp,
        QMouseEvent.Type.MouseMove,
        center_of(window) + QPoint(60, 0),
        Qt.MouseButton.NoButton,
        Qt.MouseButton.NoButton,
    )
    send(vp, QMouseEvent.Type.MouseButtonPress, center_of(window) + QPoint(60, 0))
    assert not vp.value_dragging
    import numpy as np

    assert np.array_equal(window.document.sculptor.vertices, before)  # the click did not sculpt
