"""The viewport's look and camera (issue 32 items 3-5) in the main window, with real VTK
rendering and picking: matcaps, the cavity tint, the overlay's rules, zoom to the mouse
position and coalesced camera input."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import center_of, hover, send
from PySide6.QtCore import QPoint, QPointF, QSettings, Qt
from PySide6.QtGui import QMouseEvent, QWheelEvent
from PySide6.QtWidgets import QApplication

from app.cursor_overlay import to_display
from app.mesh_display import COLOR_ARRAY

B = Qt.MouseButton
MOVE = QMouseEvent.Type.MouseMove


def model_pixel(window, pos: QPoint) -> np.ndarray:
    """The model's colour (3,) int at widget ``pos``, as rendered (no cursor)."""
    image = window.viewport.model_image()
    ratio = window.viewport.devicePixelRatioF()
    return image[int(pos.y() * ratio), int(pos.x() * ratio)].astype(int)


def test_matcaps_shade_the_model_by_its_angle_to_the_view(window):
    center = center_of(window)
    assert window.viewport.pick(QPointF(center)) is not None
    seen = {}
    for name in ("matcap:clay", "matcap:red_wax", "matcap:glossy", "matcap:basic", "studio"):
        window.look.set_shading(name)
        seen[name] = model_pixel(window, center)
    red, green, _blue = seen["matcap:red_wax"]
    assert red > green + 80  # the wax is red; the clay and basic ones are not
    assert abs(seen["matcap:clay"][0] - seen["matcap:clay"][1]) < 40
    distinct = {tuple(int(c) // 12 for c in rgb) for rgb in seen.values()}
    assert len(distinct) == len(seen)  # five looks, five colours
    # the matcap follows the view: the same surface point looked at from another side
    window.look.set_shading("matcap:clay")
    before = model_pixel(window, center)
    window.viewport.show_view("view_top")
    assert np.abs(model_pixel(window, center) - before).sum() > 10


def test_the_view_settings_live_in_the_settings_model_and_come_back(window, tmp_path):
    from app.main_window import MainWindow

    view = window.model.view
    window.look.cavity_action.trigger()
    window.look.profile_action.trigger()
    window.look.shading_actions["matcap:glossy"].trigger()
    window.navigation.zoom_action.trigger()
    assert (view.cavity, view.falloff_profile, view.matcap, view.zoom_to_mouse) == (
        True,
        True,
        "glossy",
        False,
    )
    assert window.viewport.cavity_on and not window.viewport.zoom_to_mouse
    with pytest.raises(ValueError, match=r"view\.matcap"):
        view.matcap = "chrome"
    window.settings.sync()
    again = MainWindow(QSettings(window.settings.fileName(), QSettings.Format.IniFormat))
    try:
        values = again.model.view.values()
        assert values == view.values()
        assert again.look.cavity_action.isChecked() and again.viewport.cavity_on
        assert not again.navigation.zoom_action.isChecked()
    finally:
        again.close()
        again.deleteLater()


def test_a_bump_of_one_percent_of_the_model_shows_in_the_cavity_tint(window):
    vp = window.viewport
    window.model.view.cavity = True
    colors = lambda: np.asarray(vp.mesh.point_data[COLOR_ARRAY])[vp.surface.rank].astype(int)  # noqa: E731
    before = colors()
    vertices = vp.shown_vertices()
    size = float(np.linalg.norm(np.ptp(vertices, axis=0)))
    hit = vp.pick(QPointF(center_of(window)))
    assert hit is not None
    point, normal = hit
    distance = np.linalg.norm(vertices - point, axis=1)
    width = window.model.brush.radius * size  # the brush's ε
    rows = np.flatnonzero(distance < 3 * width)
    moved = vertices.copy()
    moved[rows] += (0.01 * size * np.exp(-((distance[rows] / width) ** 2)))[:, None] * normal
    vp.update_vertices(moved, rows)  # as a brush event does: its rows only
    after = colors()
    assert np.abs(after - before).max() > 25  # a fifth of the colour range at least
    far = distance > 6 * width
    assert np.array_equal(after[far], before[far])  # untouched rows keep their tint
    window.model.view.cavity = False
    window.model.view.cavity = True  # measured afresh from the whole mesh
    assert np.abs(colors() - after).max() <= 1  # the update equals a full pass (rounding)


def test_the_profile_shows_only_while_f_drags_the_radius_or_when_asked(window):
    vp, overlay = window.viewport, window.viewport.cursor_overlay
    hover(window, center_of(window))
    assert vp.cursor_visible and not overlay.profile_visible
    vp.start_value_drag("radius")
    vp.render_now()
    assert overlay.profile_visible
    vp.finish_value_drag(False)
    vp.render_now()
    assert not overlay.profile_visible
    window.look.profile_action.trigger()  # View → Falloff Profile Over the Brush
    vp.render_now()
    assert overlay.profile_visible


def ring_center(window) -> np.ndarray:
    window.viewport.render_now()
    return np.array(window.viewport.cursor_overlay.screen[0])


def display_of(window, pos: QPoint) -> np.ndarray:
    vp = window.viewport
    ratio = vp.devicePixelRatioF()
    return np.array([pos.x() * ratio, (vp.height() - 1 - pos.y()) * ratio])


@pytest.mark.parametrize("kind", ["grab", "scale"])
def test_after_a_stroke_the_ring_follows_the_pointer_and_an_affine_one_says_where_it_acts(
    window, kind
):
    vp, overlay = window.viewport, window.viewport.cursor_overlay
    window.model.brush.kind = kind
    start = center_of(window)
    send(vp, QMouseEvent.Type.MouseButtonPress, start)
    end = start + QPoint(40, -25)
    for k in range(1, 5):
        send(vp, MOVE, start + (end - start) * k / 4, B.NoButton, B.LeftButton)
        vp.flush_tools()
    center = ring_center(window)
    if kind == "scale":  # at the press point, and says so
        assert np.allclose(center, display_of(window, start), atol=2.0)
        assert overlay.label == "scaling about the press point"
        box = [0.0] * 4  # the whole label inside the view, however wide the ring
        overlay._text.GetBoundingBox(vp.renderer, box)
        view_w, view_h = vp.renderer.GetSize()
        assert 0 <= box[0] and box[1] <= view_w and 0 <= box[2] and box[3] <= view_h
    else:
        assert overlay.label is None
    send(vp, QMouseEvent.Type.MouseButtonRelease, end, buttons=B.NoButton)
    assert not vp.in_stroke
    vp._hover_now()  # the hover the release queued: the surface under the pointer, no move
    hit = vp.pick(QPointF(end))
    assert hit is not None
    expected = to_display(vp.renderer, hit[0])[:2]
    assert np.allclose(ring_center(window), expected, atol=1.0)
    assert overlay.label is None


def test_pin_mode_shows_a_pin_pointer_and_no_brush_ring(window):
    vp = window.viewport
    hover(window, center_of(window))
    assert vp.cursor_visible
    window.brush_bar.constraint_action.trigger()
    assert vp.pin_mode and vp.cursor().shape() == Qt.CursorShape.BitmapCursor
    assert not vp.cursor_visible
    hover(window, center_of(window) + QPoint(10, 5))
    assert not vp.cursor_visible and not vp.cursor_overlay.profile_visible
    window.brush_bar.constraint_action.trigger()
    assert vp.cursor().shape() == Qt.CursorShape.ArrowCursor
    hover(window, center_of(window))
    assert vp.cursor_visible


def wheel(vp, pos: QPoint, notches: int = 1) -> None:
    p = QPointF(pos)
    vp.wheelEvent(
        QWheelEvent(
            p, vp.mapToGlobal(p), QPoint(), QPoint(0, 120 * notches), B.NoButton,
            Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False,
        )
    )  # fmt: skip


def settle(vp) -> None:
    """Let the event loop run until the requested render is done."""
    for _ in range(50):
        QApplication.processEvents()
        if not vp.render_pending and not vp._wheel_timer.isActive():
            break


@pytest.mark.parametrize("orthographic", [False, True])
@pytest.mark.parametrize("notches", [1, -1])
def test_the_point_under_the_cursor_stays_under_it_after_a_wheel_notch(
    window, orthographic, notches
):
    vp = window.viewport
    if orthographic:
        vp.toggle_projection()
    pos = center_of(window) + QPoint(vp.width() // 9, -vp.height() // 10)
    vp.render_now()
    hit = vp.pick(QPointF(pos))
    assert hit is not None
    camera = vp.renderer.GetActiveCamera()
    scale, distance = camera.GetParallelScale(), camera.GetDistance()
    wheel(vp, pos, notches)
    vp.apply_wheel()
    vp.render_now()
    assert np.allclose(to_display(vp.renderer, hit[0])[:2], display_of(window, pos), atol=0.5)
    again = vp.pick(QPointF(pos))
    assert again is not None and np.linalg.norm(again[0] - hit[0]) < 1e-3 * distance
    if orthographic:  # it zoomed
        assert camera.GetParallelScale() == pytest.approx(scale / 1.21**notches)
    else:
        assert camera.GetDistance() == pytest.approx(distance / 1.21**notches)


def test_zoom_to_the_view_centre_is_a_choice(window):
    vp = window.viewport
    window.model.view.zoom_to_mouse = False
    camera = vp.renderer.GetActiveCamera()
    focal, distance = np.array(camera.GetFocalPoint()), camera.GetDistance()
    wheel(vp, QPoint(20, 20))
    vp.apply_wheel()
    assert np.allclose(camera.GetFocalPoint(), focal)
    assert camera.GetDistance() == pytest.approx(distance / 1.21)


def test_a_burst_of_wheel_notches_or_orbit_moves_costs_at_most_two_renders(window):
    vp = window.viewport
    settle(vp)
    distance = vp.renderer.GetActiveCamera().GetDistance()
    frames = vp.frames
    for _ in range(6):  # six notches queued before the loop runs again
        wheel(vp, center_of(window))
    settle(vp)
    assert vp.frames - frames <= 2
    assert vp.renderer.GetActiveCamera().GetDistance() == pytest.approx(distance / 1.21**6)
    direction = np.array(vp.renderer.GetActiveCamera().GetDirectionOfProjection())
    frames = vp.frames
    start = center_of(window)
    send(vp, QMouseEvent.Type.MouseButtonPress, start, B.MiddleButton)
    for k in range(1, 9):  # an orbit: eight moves in one burst
        send(vp, MOVE, start + QPoint(8 * k, 5 * k), B.NoButton, B.MiddleButton)
    send(
        vp, QMouseEvent.Type.MouseButtonRelease, start + QPoint(64, 40), B.MiddleButton, B.NoButton
    )
    settle(vp)
    assert vp.frames - frames <= 2
    turned = np.array(vp.renderer.GetActiveCamera().GetDirectionOfProjection())
    assert turned @ direction < 0.99  # it did orbit
