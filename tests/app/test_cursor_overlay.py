"""The brush cursor overlay in the main window: where it sits, when it updates and hides."""

import numpy as np
import pytest
from gui_helpers import activate, center_of, drag, hover, send
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QApplication


def test_cursor_shows_radius_and_influence_and_updates_without_a_move(window):
    vp = window.viewport
    hover(window, center_of(window))
    assert vp.cursor_visible
    (_, eps_px, outer_px) = vp.cursor_overlay.screen
    influence = window.document.sculptor.influence(window.model.brush.brush)  # "auto": resolved
    assert outer_px == pytest.approx(influence * eps_px)
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
    assert window.files.open_file(str(made_textured.path))
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
    assert window.model.brush.kind == "grab_local"
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


def tablet(vp, kind, pos, pressure, buttons=Qt.MouseButton.LeftButton):
    from PySide6.QtGui import QInputDevice, QPointingDevice, QTabletEvent

    device = QPointingDevice(
        "test pen",
        7,
        QInputDevice.DeviceType.Stylus,
        QPointingDevice.PointerType.Pen,
        QInputDevice.Capability.Position | QInputDevice.Capability.Pressure,
        1,
        3,
    )
    p = QPointF(pos)
    event = QTabletEvent(
        kind,
        device,
        p,
        vp.mapToGlobal(p),
        pressure,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        Qt.KeyboardModifier.NoModifier,
        Qt.MouseButton.LeftButton,
        buttons,
    )
    vp.tabletEvent(event)


def pen_drag(window, pressure):
    vp = window.viewport
    start = center_of(window)
    end = start + QPoint(0, -12)
    tablet(vp, QMouseEvent.Type.TabletPress, start, pressure)
    send(vp, QMouseEvent.Type.MouseButtonPress, start)
    tablet(vp, QMouseEvent.Type.TabletMove, end, pressure)
    send(vp, QMouseEvent.Type.MouseMove, end, Qt.MouseButton.NoButton, Qt.MouseButton.LeftButton)
    window.viewport.flush_tools()
    send(vp, QMouseEvent.Type.MouseButtonRelease, end, buttons=Qt.MouseButton.NoButton)
    tablet(vp, QMouseEvent.Type.TabletRelease, end, 0.0, Qt.MouseButton.NoButton)


def test_pen_pressure_scales_the_strength_and_the_toggles_are_in_the_brush_bar(window):
    import numpy as np

    sculptor = window.document.sculptor
    before = sculptor.vertices.copy()
    pen_drag(window, 1.0)
    full = np.linalg.norm(sculptor.vertices - before, axis=1).max()
    window.undo()
    pen_drag(window, 0.5)
    half = np.linalg.norm(sculptor.vertices - before, axis=1).max()
    window.undo()
    assert full > 0 and half == pytest.approx(0.5 * full, rel=0.05)
    assert window.viewport._pressure == 1.0  # back to a mouse's after the pen lifted
    # the brush bar's toggle turns it off: a light pen then moves as much as a firm one
    window.brush_bar.pressure_actions["pressure_strength"].trigger()
    assert window.model.pen.pressure_strength is False
    pen_drag(window, 0.5)
    same = np.linalg.norm(sculptor.vertices - before, axis=1).max()
    assert same == pytest.approx(full, rel=0.05)
    window.model.pen.pressure_radius = True
    assert window.brush_bar.pressure_actions["pressure_radius"].isChecked()
    window.brush_bar.lazy_radius.setValue(15)
    assert window.model.pen.lazy_radius == 15.0


def test_pen_pressure_drives_the_radius_along_one_stroke_and_the_cursor_shows_it(window):
    """Synthetic tablet events with pressure going 1.0 → 0.3 within one stroke: each engine
    event's radius factor follows the pen, the moved region shrinks, and the cursor's ε ring
    shows the pressure-scaled radius while the pen draws."""
    import numpy as np

    vp = window.viewport
    sculptor = window.document.sculptor
    window.model.pen.pressure_radius = True
    window.model.pen.pressure_strength = False
    window.model.brush.influence = 4.0  # a ball smaller than the model, so it can shrink
    pressures = [1.0, 0.8, 0.55, 0.3]
    start = center_of(window)
    tablet(vp, QMouseEvent.Type.TabletPress, start, pressures[0])
    send(vp, QMouseEvent.Type.MouseButtonPress, start)
    vp.render_now()
    ring_px, full_px, moved = [], [], []
    pos = start
    for pressure in pressures:
        pos = pos + QPoint(0, -4)
        tablet(vp, QMouseEvent.Type.TabletMove, pos, pressure)
        send(
            vp, QMouseEvent.Type.MouseMove, pos, Qt.MouseButton.NoButton, Qt.MouseButton.LeftButton
        )
        before = sculptor.vertices.copy()
        window.viewport.flush_tools()
        vp.render_now()
        moved.append(int(np.count_nonzero(np.any(sculptor.vertices != before, axis=1))))
        ring_px.append(vp.cursor_overlay.screen[1])
        full_px.append(vp.cursor_overlay.full_pixels)
    send(vp, QMouseEvent.Type.MouseButtonRelease, pos, buttons=Qt.MouseButton.NoButton)
    tablet(vp, QMouseEvent.Type.TabletRelease, pos, 0.0, Qt.MouseButton.NoButton)
    events = sculptor.operations[-1].events
    assert [e.radius_factor for e in events] == pytest.approx(pressures)
    assert moved == sorted(moved, reverse=True) and 0 < moved[-1] < 0.5 * moved[0]
    # the ring follows the pressure (the depth of the point under the pen barely changes)
    assert np.array(ring_px) / ring_px[0] == pytest.approx(pressures, rel=0.1)
    # a faint ring keeps the full radius while the pressure shrinks it (none at full pressure)
    assert full_px[0] is None
    assert full_px[1:] == pytest.approx([ring_px[0]] * 3, rel=0.1)
    # after the pen lifts, the cursor is back at the brush's own radius, alone
    hover(window, start)
    assert vp.cursor_overlay.screen[1] == pytest.approx(ring_px[0], rel=0.1)
    assert vp.cursor_overlay.full_pixels is None


def test_cursor_shows_the_material_axes_only_for_an_anisotropic_material(window):
    """Isotropic: no axes. The layered preset with the surface frame: three lines through the
    centre, the third (the material's z) along the surface normal under the cursor."""
    import numpy as np

    from gogreen_core.files.presets import builtin_presets
    from gogreen_core.sculpt.material_frame import material_frame_at

    vp = window.viewport
    hover(window, center_of(window))
    assert vp.cursor_overlay.state.axes is None and vp.cursor_overlay.axes_screen is None
    layered = next(p for p in builtin_presets() if p.name == "Layered sheet wrinkles")
    window.model.apply_preset(layered)
    assert window.document.sculptor.settings.material_frame == "surface"
    hover(window, center_of(window))
    vp.render_now()
    state = vp.cursor_overlay.state
    assert state.axes is not None and vp.cursor_overlay.axes_screen is not None
    # the material's axes turned onto the surface: the frame's normal is the surface's
    frame = material_frame_at(window.document.sculptor, state.center, state.radius)
    assert abs(frame[:, 2] @ state.normal) > 0.9
    assert np.allclose(np.linalg.det(frame), 1.0)
    # the material panel's combo shows (and sets) the frame
    combo = window.material_panel.frame_combo
    assert combo.currentData() == "surface"
    combo.setCurrentIndex(combo.findData("world"))
    assert window.document.sculptor.settings.material_frame == "world"
    hover(window, center_of(window))
    assert np.allclose(material_frame_at(window.document.sculptor, state.center, 1.0), np.eye(3))


def test_cursor_draws_the_detail_size_while_dynamic_topology_is_on(window):
    vp = window.viewport
    hover(window, center_of(window))
    vp.render_now()
    assert vp.cursor_visible and vp.cursor_overlay.detail_pixels is None
    window.model.detail_size = 0.02
    window.model.dynamic_topology = True  # no mouse move: the cursor follows
    QApplication.processEvents()
    vp.render_now()
    eps_px = vp.cursor_overlay.screen[1]
    radius = window.model.brush.brush.radius  # ε in model sizes
    # a circle as wide as the edges dynamic topology makes (0.02 model sizes)
    assert vp.cursor_overlay.detail_pixels == pytest.approx(0.5 * eps_px * 0.02 / radius, rel=0.1)
    window.model.dynamic_topology = False
    QApplication.processEvents()
    vp.render_now()
    assert vp.cursor_overlay.detail_pixels is None


@pytest.mark.parametrize("kind", ["twist", "grab"])
def test_the_gauge_is_drawn_while_an_affine_stroke_acts_only(window, qtbot, kind):
    """A twist's gauge: the loop of marks around the press point, turning as the drag goes on,
    gone after the release; a grab draws none."""
    activate(window, qtbot)
    window.model.brush.kind = kind
    vp = window.viewport
    start = center_of(window)
    QTest.mousePress(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
    vp.render_now()
    overlay = vp.cursor_overlay
    if kind == "grab":
        assert overlay.gauge_screen is None
        for k in range(1, 6):
            QTest.mouseMove(vp, start + QPoint(6 * k, 0))
            vp.flush_tools()
        vp.render_now()
        assert overlay.visible and overlay.gauge_screen is None
        QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start)
        return
    pressed = overlay.gauge_screen.copy()
    (cx, cy), eps_px, _ = overlay.screen
    radii = np.hypot(pressed[:, 0] - cx, pressed[:, 1] - cy)
    assert pressed.shape == (32, 2) and np.median(radii) == pytest.approx(eps_px, rel=0.25)
    for k in range(1, 11):
        QTest.mouseMove(vp, start + QPoint(10 * k, 0))
        vp.flush_tools()
    vp.render_now()
    now = overlay.gauge_screen
    a, b = pressed - (cx, cy), now - (cx, cy)
    turn = np.degrees(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.sum(a * b, axis=1)))
    assert abs(np.median(turn)) >= 15.0  # the spokes and marks turn on screen
    QTest.mouseRelease(
        vp, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier, start + QPoint(100, 0)
    )
    qtbot.wait(5)
    vp.render_now()
    assert overlay.gauge_screen is None
