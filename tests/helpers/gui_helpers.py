"""Helpers shared by the GUI tests: synthetic mouse events sent to the viewport, a drag, a hover,
showing a widget and activating a window. Imported as ``from gui_helpers import ...`` (pytest
puts ``tests/`` on the path, as for ``green_reference``); Qt only, the app is imported lazily."""

from __future__ import annotations

import faulthandler
import sys
import time

from PySide6.QtCore import QCoreApplication, QEventLoop, QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent


def send(viewport, kind, pos, button=Qt.MouseButton.LeftButton, buttons=None) -> None:
    """A mouse event of type ``kind`` at widget ``pos`` given straight to the viewport's
    handler (``buttons``: the buttons held; default ``button``)."""
    buttons = button if buttons is None else buttons
    p = QPointF(pos)
    event = QMouseEvent(
        kind, p, viewport.mapToGlobal(p), button, buttons, Qt.KeyboardModifier.NoModifier
    )
    {
        QMouseEvent.Type.MouseButtonPress: viewport.mousePressEvent,
        QMouseEvent.Type.MouseMove: viewport.mouseMoveEvent,
        QMouseEvent.Type.MouseButtonRelease: viewport.mouseReleaseEvent,
    }[kind](event)


def steps_done(viewport, timeout: float = 120.0) -> None:
    """Deliver events until no brush step runs off the GUI thread (a slow step's end is drawn,
    a release waiting for it done); fails after ``timeout`` seconds."""
    end = time.monotonic() + timeout
    while viewport.stroke_worker.running:
        if time.monotonic() > end:
            faulthandler.dump_traceback(sys.stderr)  # where the step hangs
            raise AssertionError("a brush step did not end")
        QCoreApplication.processEvents(QEventLoop.ProcessEventsFlag.AllEvents, 20)


def drag(window, start: QPoint, steps: int = 6) -> None:
    """A left-button drag in the window's viewport from ``start``, ``steps`` moves of (8, -6)."""
    vp = window.viewport
    offset = QPoint(8, -6)
    send(vp, QMouseEvent.Type.MouseButtonPress, start)
    pos = start
    for _ in range(steps):
        pos = pos + offset
        send(
            vp, QMouseEvent.Type.MouseMove, pos, Qt.MouseButton.NoButton, Qt.MouseButton.LeftButton
        )
    send(vp, QMouseEvent.Type.MouseButtonRelease, pos, buttons=Qt.MouseButton.NoButton)


def center_of(window) -> QPoint:
    """The centre of the window's viewport (widget coordinates)."""
    return QPoint(window.viewport.width() // 2, window.viewport.height() // 2)


def hover(window, pos) -> None:
    """A button-less move to ``pos``, the hover delivered to the tools and rendered at once."""
    send(
        window.viewport,
        QMouseEvent.Type.MouseMove,
        pos,
        Qt.MouseButton.NoButton,
        Qt.MouseButton.NoButton,
    )
    window.viewport._hover_now()  # the hover's pick, handed to the tools and drawn
    window.viewport.render_now()


def activate(window, qtbot) -> None:
    """Make ``window`` the active window (shortcuts act only in the active window)."""
    with qtbot.waitActive(window, timeout=10_000):
        window.activateWindow()
        window.windowHandle().requestActivate()


def show_widget(qtbot, widget, width: int, height: int):
    """``widget`` closed after the test, resized to ``width`` × ``height``, shown and exposed."""
    qtbot.addWidget(widget)
    widget.resize(width, height)
    widget.show()
    qtbot.waitExposed(widget)
    return widget


def shown_viewport(qtbot):
    """A bare :class:`~app.viewport.SculptViewport` (no main window), 500 × 400, shown."""
    from app.viewport import SculptViewport

    return show_widget(qtbot, SculptViewport(), 500, 400)
