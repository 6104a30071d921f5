"""Slow brush steps off the GUI thread.

With dynamic topology a brush step on a big mesh takes seconds (the 1M-vertex ogre: ~1.5 s an
event); on the GUI thread the window would not answer meanwhile. The viewport hands its stroke's
press, moves and release to :class:`StrokeWorker`, which runs a slow step (the tools' ``press``
or ``flush``: the engine's event, the cursor) on a worker thread of its own
(:meth:`StrokeWorker.slow_steps` decides which) and the rest on the GUI thread as before. While a
step runs, the newest move waits (the next step starts from it), a release waits, a second press
is refused with a message, and what would touch the mesh (undo, files, closing:
:meth:`StrokeWorker.after_step`) waits for the steps to end; the viewport draws each finished
step. The sculptor is used by one thread at a time. A step still running after
:data:`BUSY_AFTER_MS` is shown: a busy cursor and the ``busy`` signal's message.
"""

from __future__ import annotations

import contextlib
import queue
import threading
from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING

from PySide6.QtCore import QObject, QPointF, Qt, QTimer, Signal

from gogreen_core.interaction.tools import PointerEvent, ToolUpdate

if TYPE_CHECKING:
    from app.viewport import SculptViewport

__all__ = ["BIG_MESH_VERTICES", "BUSY_AFTER_MS", "SLOW_STEP_MS", "StrokeWorker"]

#: A step running longer than this is shown as work under way (ms).
BUSY_AFTER_MS = 300
#: On a mesh of at least :data:`BIG_MESH_VERTICES`, a stroke whose last step took this long
#: runs its next ones off the GUI thread (ms). Smaller meshes' steps stay on it: a few ms, and
#: through the worker they cost a render more per release (benchmarks/app_session.py).
SLOW_STEP_MS = 80.0
BIG_MESH_VERTICES = 200_000


class StrokeWorker(QObject):
    """The stroke steps of ``view`` (a :class:`~app.viewport.SculptViewport`): slow ones on a
    worker thread, one at a time.

    Signals
    -------
    busy(str) : what a step running for :data:`BUSY_AFTER_MS` does; "" once the steps ended.
    """

    busy = Signal(str)
    _done = Signal(object, str, object)  # (update, error title, exception): from the thread

    def __init__(self, view: SculptViewport) -> None:
        super().__init__(view)
        self.view = view
        self._jobs: queue.SimpleQueue[Callable[[], ToolUpdate] | None] = queue.SimpleQueue()
        self._thread: threading.Thread | None = None
        self._idle = threading.Event()
        self._idle.set()
        #: A step runs on the worker thread (set and cleared on the GUI thread).
        self.running = False
        self._title, self._shown_busy = "", False
        self._message = "Applying the brush to the mesh"  # said once a step runs a while
        #: The newest move that came during a step and how many came; where the button was
        #: released during a step (the release waits); what waits for the steps to end.
        self.waiting_move: tuple[PointerEvent, int] | None = None
        self.release_pos: QPointF | None = None
        self._after: list[Callable[[], object]] = []
        #: Steps of at least this many ms on a mesh of at least this many vertices move the
        #: stroke's next steps off the GUI thread.
        self.slow_step_ms, self.big_mesh_vertices = SLOW_STEP_MS, BIG_MESH_VERTICES
        self.last_step_ms = 0.0
        view.step_timed.connect(lambda ms: setattr(self, "last_step_ms", ms))
        self._busy_timer = QTimer(self)
        self._busy_timer.setSingleShot(True)
        self._busy_timer.setInterval(BUSY_AFTER_MS)
        self._busy_timer.timeout.connect(self._show_busy)
        self._done.connect(self._step_done)

    def slow_steps(self) -> bool:
        """Whether the tools' next brush step runs on the worker: with dynamic topology (a
        remesh in every event), or on a big mesh when the last step took :attr:`slow_step_ms`
        or more. Pin drags stay on the GUI thread (not strokes: settings may change meanwhile)."""
        tools = self.view.tools
        sculptor = tools.sculptor if tools is not None else None
        if tools is None or sculptor is None or tools.mode != "brush":
            return False
        if sculptor.settings.dynamic_topology:
            return True
        big = len(sculptor.vertices) >= self.big_mesh_vertices
        return big and self.last_step_ms >= self.slow_step_ms

    # -- the stroke's events, from the viewport ----------------------------------------------
    def refuse_press(self) -> bool:
        """A press while a step runs (the last stroke's release waits for it) starts nothing:
        True, and the status bar says why."""
        if self.running:
            self.view.tool_message.emit(
                "Cannot sculpt yet: the last stroke's brush step is still being applied "
                "(see the status bar); press again when it ends"
            )
        return self.running

    def press(self, event: PointerEvent) -> None:
        """Start a stroke (or a pin) at ``event``."""
        tools = self.view.tools
        assert tools is not None
        if self.slow_steps() and not tools.ready():  # (refused at once, else on the worker)
            self._run(partial(tools.press, event), "Cannot sculpt")
        else:
            self.view.draw(tools.press(event), "Cannot sculpt")

    def move(self, event: PointerEvent) -> bool:
        """Keep ``event`` for after the running step (True; latest wins), or False: no step
        runs, the tools take it."""
        if not self.running:
            return False
        count = self.waiting_move[1] if self.waiting_move is not None else 0
        self.waiting_move = (event, count + 1)
        return True

    def flush(self) -> None:
        """Apply the tools' newest move (or hover) and draw it; a slow step on the worker,
        drawn when it ends. Nothing while a step runs (its end takes the newest move)."""
        tools = self.view.tools
        if tools is None or self.running:
            return
        if tools.dragging and tools.has_pending and self.slow_steps():
            self._run(tools.flush, "Brush stopped")
        else:
            self.view.draw(tools.flush(), "Brush stopped")

    def release(self, pos: QPointF) -> None:
        """The button was released at ``pos``: the last move applied, then the stroke ends
        (:meth:`_finish_release`), at once or after the running step."""
        self.release_pos = pos
        tools = self.view.tools
        if tools is not None and tools.has_pending and not self.running:
            self.flush()  # the last move: on the worker when slow
        if not self.running:
            self._finish_release()

    def _finish_release(self) -> None:
        """End the stroke whose button was released (its last move applied)."""
        view, pos, self.release_pos = self.view, self.release_pos, None
        if view.tools is not None:
            view.draw(view.tools.release(), "Brush stopped")
        if view._faces_in_stroke:  # the whole new mesh shown and indexed, once
            view._faces_in_stroke = False
            view.faces_replaced.emit()
        if not view.surface_building:  # else the mesh is drawn once indexed (no flat frame)
            view.lod.show_full()
        view.stroke_ended.emit()
        # the ring leaves where the stroke acted for the surface under the pointer now, in
        # the same frame as the settled mesh (a frame of a big mesh is slow)
        view._hover_pos = pos
        view._hover_now()

    def after_step(self, action: Callable[[], object], what: str = "") -> None:
        """Call ``action`` now, or once the running step and a release waiting for it are
        done (``what`` says so in the status bar): what touches the mesh (undo, files,
        closing) never meets a half-applied step."""
        if not self.running:
            action()
            return
        self._after.append(action)
        if what:
            self.view.tool_message.emit(f"{what} once the brush step being applied ends")

    def stop(self) -> None:
        """End the worker thread once its step (if any) is done, waiting for that step (the
        view closes: nothing may report to it afterwards)."""
        self._idle.wait(60.0)
        if self._thread is not None:
            self._jobs.put(None)
            self._thread = None

    # -- the worker thread -------------------------------------------------------------------
    def _run(self, step: Callable[[], ToolUpdate], error_title: str) -> None:
        self.running = True
        self._title = error_title
        tools = self.view.tools  # what the busy message says, read before the step runs
        sculptor = tools.sculptor if tools is not None else None
        if sculptor is not None:
            remesh = " (dynamic topology remeshes it)" if sculptor.settings.dynamic_topology else ""
            self._message = (
                f"Applying the brush to the mesh of {len(sculptor.vertices):,} vertices{remesh}: "
                "the newest pointer position follows"
            )
        if self._thread is None:
            self._thread = threading.Thread(target=self._work, name="brush steps", daemon=True)
            self._thread.start()
        self._busy_timer.start()
        self._idle.clear()
        self._jobs.put(step)

    def _work(self) -> None:
        while (step := self._jobs.get()) is not None:
            try:
                update, error = step(), None
            except Exception as exc:  # the tools catch the engine's refusals; reported
                update, error = None, exc
            if error is None:  # (failing, the GUI thread finds the rows: not the step's error)
                with contextlib.suppress(Exception):
                    self._follow_ahead()
            self._idle.set()
            self._done.emit(update, self._title, error)

    def _follow_ahead(self) -> None:
        """(On the worker thread) A step that gave the mesh new faces (dynamic topology): where
        the interaction copy's vertices go (:meth:`LightMesh.followed_rows`: 30-70 ms at 1M
        vertices) is found here, with the step, not when the GUI thread draws it."""
        view, tools = self.view, self.view.tools
        sculptor = tools.sculptor if tools is not None else None
        light, indexed = view.lod.light, view._indexed
        if sculptor is None or light is None or indexed is None or sculptor.faces is view._faces:
            return
        change = sculptor.remesher.mesh.renumbering
        if change is not None and change[0] is indexed[1]:
            rows = light.followed_rows(sculptor.vertices, sculptor.faces, change, indexed[0])
            light.ahead = change[2], rows

    def _step_done(self, update: ToolUpdate | None, title: str, error: Exception | None) -> None:
        """A step ended: draw it, then a step from the newest move, or the waiting release,
        and what waited for the steps."""
        self.running = False
        self._busy_timer.stop()
        view, tools = self.view, self.view.tools
        view.draw(update or ToolUpdate(), title)
        if error is not None and tools is not None:  # restores the mesh: no half step
            tools.cancel()
            view.draw(ToolUpdate(all_moved=True))
            view.tool_error.emit(title, f"{type(error).__name__}: {error}")
        if self.waiting_move is not None and tools is not None:
            (move, count), self.waiting_move = self.waiting_move, None
            tools.move(move)
            tools.received += count - 1 if tools.dragging else 0
        self.flush()
        if self.running:
            return
        if self.release_pos is not None:
            self._finish_release()
        waiting, self._after = self._after, []
        for action in waiting:
            action()
        if self._shown_busy and not self.running:
            self._shown_busy = False
            if not view.pin_mode:  # (a pin mode that waited for the steps set its cursor)
                view.unsetCursor()
            self.busy.emit("")

    def _show_busy(self) -> None:
        """A step has run for a while: a busy cursor and a message, once per run of steps."""
        if not self.running or self._shown_busy:
            return
        self._shown_busy = True
        self.view.setCursor(Qt.CursorShape.BusyCursor)
        self.busy.emit(self._message)
