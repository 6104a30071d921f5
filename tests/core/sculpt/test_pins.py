"""Pins (constraints): local reach, undo steps for adding/removing, replay, right-click removal."""

import numpy as np
import pytest
from gui_helpers import center_of, send
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent

from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.constraints import CONSTRAINT_INFLUENCE, smooth_cutoff
from gogreen_core.sculpt.sculptor import Sculptor


@pytest.fixture
def sculptor():
    vertices, faces = icosphere(4)
    s = Sculptor(vertices, faces)
    s.change_settings(constraint_radius=0.05)
    return s


def test_dragging_a_pin_moves_only_what_is_within_its_reach(sculptor):
    vertices = sculptor.vertices.copy()
    a, b = int(np.argmax(vertices[:, 2])), int(np.argmax(vertices[:, 0]))
    sculptor.add_constraint(vertices[a])
    sculptor.add_constraint(vertices[b])
    delta = np.array([0.0, 0.0, 0.02])
    sculptor.drag_constraint(0, delta)
    moved = np.linalg.norm(sculptor.vertices - vertices, axis=1)
    reach = sculptor.constraint_reach
    assert reach == pytest.approx(CONSTRAINT_INFLUENCE * 0.05 * sculptor.model_size)
    distance = np.linalg.norm(vertices - vertices[a], axis=1)
    assert np.all(moved[distance >= reach] == 0)  # local: most of the sphere stays
    assert np.count_nonzero(moved) < len(vertices) // 4
    np.testing.assert_allclose(sculptor.vertices[a] - vertices[a], delta, atol=1e-12)
    np.testing.assert_allclose(sculptor.vertices[b], vertices[b], atol=1e-12)  # the other pin


def test_smooth_cutoff_is_the_brushes_quintic():
    r = np.linspace(0.0, 1.0, 11)
    s = smooth_cutoff(r, 0.5, 1.0)
    assert np.all(s[r <= 0.5] == 1.0) and s[-1] == 0.0 and np.all(np.diff(s) <= 0)


def test_adding_and_removing_pins_are_undo_steps_and_replay(sculptor):
    vertices = sculptor.vertices.copy()
    p, q = vertices[0], vertices[50]
    sculptor.add_constraint(p)
    sculptor.add_constraint(q)
    sculptor.remove_constraint(0)
    np.testing.assert_array_equal(sculptor.constraint_points, [q])
    assert sculptor.history.undo_labels[-3:] == ["add pin", "add pin", "remove pin"]
    sculptor.undo()
    np.testing.assert_array_equal(sculptor.constraint_points, [p, q])
    sculptor.undo()
    np.testing.assert_array_equal(sculptor.constraint_points, [p])
    sculptor.redo()
    np.testing.assert_array_equal(sculptor.constraint_points, [p, q])
    sculptor.clear_constraints()
    assert len(sculptor.constraint_points) == 0
    sculptor.undo()
    np.testing.assert_array_equal(sculptor.constraint_points, [p, q])
    sculptor.drag_constraint(1, [0.0, 0.01, 0.0])
    replayed = Sculptor.from_session(sculptor.session(), vertices, sculptor.faces)
    replayed.replay(sculptor.session()["operations"])
    np.testing.assert_array_equal(replayed.vertices, sculptor.vertices)
    np.testing.assert_array_equal(replayed.constraint_points, sculptor.constraint_points)


def click(vp, pos, button=Qt.MouseButton.LeftButton):
    send(vp, QMouseEvent.Type.MouseButtonPress, pos, button)
    send(vp, QMouseEvent.Type.MouseButtonRelease, pos, button, Qt.MouseButton.NoButton)


def test_right_click_removes_a_pin_and_the_rings_follow_undo(window):
    sculptor, vp = window.document.sculptor, window.viewport
    window.brush_bar.constraint_action.setChecked(True)
    center = center_of(window)
    click(vp, center)
    click(vp, center + QPoint(-60, 40))
    assert len(sculptor.constraint_points) == 2
    vp.render_now()
    assert len(vp.pin_overlay.screen_radii) == 2 and min(vp.pin_overlay.screen_radii) > 1
    click(vp, center, Qt.MouseButton.RightButton)  # on the first pin: removed
    assert len(sculptor.constraint_points) == 1
    assert len(vp.pin_overlay.points) == 1
    click(vp, QPointF(3, 3).toPoint(), Qt.MouseButton.RightButton)  # background: nothing
    assert len(sculptor.constraint_points) == 1
    window.undo()  # the removal
    assert len(sculptor.constraint_points) == 2 and len(vp.pin_overlay.points) == 2
    np.testing.assert_array_equal(window.viewport.pin_markers.points, sculptor.constraint_points)
    window.undo()
    window.undo()  # both additions
    assert len(sculptor.constraint_points) == 0 and len(vp.pin_overlay.points) == 0
