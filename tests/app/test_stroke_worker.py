"""Slow brush steps off the GUI thread (issue 34): the newest move waits for the running step,
the release, undo, closing and a second press wait for it or are refused, and the window says
that work is under way. A step is made slow by a gate the test opens (no big mesh, no sleep)."""

import threading

import numpy as np
import pytest
from gui_helpers import center_of, send, steps_done
from PySide6.QtCore import QPoint, Qt
from PySide6.QtGui import QMouseEvent

from gogreen_core import Material

LEFT, NONE = Qt.MouseButton.LeftButton, Qt.MouseButton.NoButton
MOVE, PRESS = QMouseEvent.Type.MouseMove, QMouseEvent.Type.MouseButtonPress
RELEASE = QMouseEvent.Type.MouseButtonRelease


class Gate:
    """The sculptor's events wait until the test opens the gate; each event's centre kept."""

    def __init__(self, sculptor, monkeypatch, error: Exception | None = None) -> None:
        self.opened = threading.Event()
        self.centers: list[np.ndarray] = []
        event = sculptor.stroke_event

        def slow_event(brush_event):
            self.centers.append(np.array(brush_event.center))
            assert self.opened.wait(30), "the test never opened the gate"
            moved = event(brush_event)
            if error is not None:  # after the engine moved vertices: the cancel restores them
                raise error
            return moved

        monkeypatch.setattr(sculptor, "stroke_event", slow_event)

    def open(self) -> None:
        self.opened.set()


@pytest.fixture
def slow(window, monkeypatch):
    """Every brush step of the window runs off the GUI thread, behind a closed gate."""
    window.model.brush.kind = "grab"
    worker = window.viewport.stroke_worker
    worker.slow_step_ms = worker.big_mesh_vertices = 0  # the policy: every step is slow
    return Gate(window.document.sculptor, monkeypatch)


def press_and_move(window, moves: int) -> QPoint:
    """A left press at the view's centre and ``moves`` moves, each flushed; the position."""
    vp = window.viewport
    pos = center_of(window)
    send(vp, PRESS, pos)
    steps_done(vp)  # a grab's press runs no event
    for _ in range(moves):
        pos = pos + QPoint(5, -3)
        send(vp, MOVE, pos, NONE, LEFT)
        vp.flush_tools()
    return pos


def test_moves_during_a_slow_step_are_coalesced_and_the_newest_follows(window, slow, qtbot):
    vp, sculptor = window.viewport, window.document.sculptor
    before = sculptor.vertices.copy()
    pos = press_and_move(window, 5)
    assert vp.stroke_worker.running
    qtbot.waitUntil(lambda: len(slow.centers) == 1)  # the first move's step runs, held
    assert np.array_equal(sculptor.vertices, before)  # nothing drawn before the step ends
    # the window answers meanwhile: after ~0.3 s it says that work is under way
    qtbot.waitUntil(lambda: "Applying the brush" in window.message_label.text(), timeout=5000)
    assert vp.cursor().shape() == Qt.CursorShape.BusyCursor
    slow.open()
    steps_done(vp)
    assert len(slow.centers) == 2  # the running step, then one from the newest move
    assert window.tools.received == 5 and window.tools.processed == 2
    send(vp, RELEASE, pos, buttons=NONE)
    assert not vp.stroke_worker.running and not window.tools.dragging
    assert not np.array_equal(sculptor.vertices, before)
    assert np.array_equal(vp.shown_vertices(), sculptor.vertices)  # each step drawn
    assert "Applying the brush" not in window.message_label.text()
    assert vp.cursor().shape() != Qt.CursorShape.BusyCursor
    assert sculptor.history.undo_labels[-1].endswith("stroke")


def test_the_release_and_an_undo_wait_for_the_running_step(window, slow, qtbot):
    vp, sculptor = window.viewport, window.document.sculptor
    before, steps = sculptor.vertices.copy(), len(sculptor.history.undo_labels)
    pos = press_and_move(window, 2)
    send(vp, RELEASE, pos, buttons=NONE)
    assert vp.stroke_worker.running and vp.in_stroke and window.tools.dragging  # the release waits
    window.undo_action.trigger()  # Ctrl+Z right after the release: queued behind the stroke
    assert "Undo once the brush step being applied ends" in window.message_label.text()
    assert np.array_equal(sculptor.vertices, before)
    slow.open()
    steps_done(vp)
    assert not vp.in_stroke and not window.tools.dragging
    assert len(slow.centers) == 2  # the newest move was applied before the release
    # the stroke was recorded, then undone: no undo step lost
    assert np.array_equal(sculptor.vertices, before)
    assert len(sculptor.history.undo_labels) == steps
    assert sculptor.history.redo_labels[0].endswith("stroke")
    assert "Undone: " in window.message_label.text()
    window.redo()
    assert not np.array_equal(sculptor.vertices, before)
    assert np.array_equal(vp.shown_vertices(), sculptor.vertices)


def test_a_second_press_and_a_setting_during_the_step_are_refused_with_a_message(
    window, slow, qtbot
):
    vp, sculptor = window.viewport, window.document.sculptor
    history = sculptor.history
    material, steps = sculptor.settings.material, len(history.undo_labels)
    pos = press_and_move(window, 1)
    send(vp, RELEASE, pos, buttons=NONE)
    send(vp, PRESS, pos)  # a second stroke while the first one's step runs
    assert "Cannot sculpt yet" in window.message_label.text()
    send(vp, MOVE, pos + QPoint(20, 0), NONE, LEFT)
    send(vp, RELEASE, pos + QPoint(20, 0), buttons=NONE)
    window.apply_material(Material.cubic(3.0, 1.5, 0.4))  # the engine is in a stroke
    assert "not applied" in window.message_label.text()
    assert sculptor.settings.material == material and window.model.material == material
    slow.open()
    steps_done(vp)
    assert len(slow.centers) == 1 and not window.tools.dragging
    assert len(history.undo_labels) == steps + 1  # one stroke only
    assert history.undo_labels[-1].endswith("stroke")


def test_closing_during_a_step_closes_once_it_ended(window, slow, qtbot):
    vp = window.viewport
    press_and_move(window, 1)
    assert not window.close()  # refused for now: the step is using the mesh
    assert window.isVisible() and "Closing once" in window.message_label.text()
    slow.open()
    qtbot.waitUntil(lambda: not window.isVisible(), timeout=30_000)
    assert not vp.stroke_worker.running


def test_new_document_during_a_step_waits_for_it(window, slow, qtbot):
    vp, old = window.viewport, window.document
    pos = press_and_move(window, 1)
    send(vp, RELEASE, pos, buttons=NONE)
    window.new_action.trigger()
    assert window.document is old  # not replaced under the running step
    slow.open()
    qtbot.waitUntil(lambda: window.document is not old, timeout=30_000)
    assert not vp.stroke_worker.running and not window.tools.dragging
    assert window.tools.sculptor is window.document.sculptor


def test_an_error_in_a_step_off_the_gui_thread_restores_the_mesh(window, monkeypatch, qtbot):
    vp, sculptor = window.viewport, window.document.sculptor
    window.model.brush.kind = "grab"
    vp.stroke_worker.slow_step_ms = vp.stroke_worker.big_mesh_vertices = 0
    gate = Gate(sculptor, monkeypatch, error=ZeroDivisionError("broken kernel"))
    before, steps = sculptor.vertices.copy(), len(sculptor.history.undo_labels)
    pos = press_and_move(window, 1)
    gate.open()
    steps_done(vp)
    assert "broken kernel" in window.message_label.text()
    assert not window.tools.dragging
    assert np.array_equal(sculptor.vertices, before)  # no half-applied step
    assert np.array_equal(vp.shown_vertices(), before)
    send(vp, RELEASE, pos, buttons=NONE)
    assert len(sculptor.history.undo_labels) == steps


def test_fast_steps_stay_on_the_gui_thread_and_dynamic_topology_goes_off_it(window):
    vp, sculptor = window.viewport, window.document.sculptor
    window.model.brush.kind = "grab"
    before = sculptor.vertices.copy()
    press_and_move(window, 1)
    assert not vp.stroke_worker.running  # done at once, on the GUI thread
    assert not np.array_equal(sculptor.vertices, before)
    send(vp, RELEASE, center_of(window) + QPoint(5, -3), buttons=NONE)
    assert not vp.in_stroke
    window.model.dynamic_topology = True
    window.model.detail_size = 0.004  # finer than the model's edges: the step splits them
    count = len(sculptor.vertices)
    pos = press_and_move(window, 1)
    assert vp.stroke_worker.running  # the remeshing step runs off the GUI thread
    send(vp, RELEASE, pos, buttons=NONE)
    steps_done(vp)
    assert not vp.in_stroke and sculptor.history.undo_labels[-1].endswith("stroke")
    assert np.array_equal(vp.shown_vertices(), sculptor.vertices)
    assert len(sculptor.vertices) > count
    window.undo()  # the count of the mesh the undo gave back is shown
    assert window.status.vertex_label.text() == f"{count:,} vertices"
