"""Slow brush steps off the GUI thread.

With dynamic topology a brush step on a big mesh takes seconds (the 1M-vertex ogre: ~1.5 s an
event); on the GUI thread the window would not answer meanwhile. :class:`StrokeWorker` runs
such a step (the tools' ``press`` or ``flush``: the engine's event, the cursor) on a worker
thread of its own and reports on the GUI thread. The viewport (:mod:`app.viewport`) decides
which steps go there (:meth:`StrokeWorker.slow_steps`), keeps the newest pointer move while one
runs (the next step starts from it), lets the release, and what would touch the mesh (undo,
files, closing), wait for it, and reads the mesh only once the step ended: the sculptor is used
by one thread at a time. A step still running after :data:`BUSY_AFTER_MS` is shown (the
``busy`` signal: a status message and a busy cursor).
"""

from __future__ import annotations

import queue
import threading
import time
from collections.abc import Callable

from PySide6.QtCore import QObject, QTimer, Signal

from gogreen_core.interaction.tools import SculptTools, ToolUpdate

__all__ = ["BIG_MESH_VERTICES", "BUSY_AFTER_MS", "SLOW_STEP_MS", "StrokeWorker"]

#: A step running longer than this is shown as work under way (ms).
BUSY_AFTER_MS = 300
#: On a mesh of at least :data:`BIG_MESH_VERTICES`, a stroke whose last step took this long
#: runs its next ones off the GUI thread (ms). Smaller meshes' steps stay on it (a few ms; the
#: same path as before, and GUI tests stay deterministic on a loaded machine).
SLOW_STEP_MS = 80.0
BIG_MESH_VERTICES = 200_000


class StrokeWorker(QObject):
    """One worker thread for a stroke's slow steps; at most one step at a time.

    Signals
    -------
    finished(ToolUpdate, str, object) : on the GUI thread, a step ended: what it gave back, the
        error title the step was run with, and an exception the tools did not catch (or None).
    busy(bool) : a step has been running for :data:`BUSY_AFTER_MS` (True); the worker is idle
        again after such a step (False).
    """

    finished = Signal(object, str, object)
    busy = Signal(bool)
    _done = Signal(object, object)  # (update, exception), emitted on the worker thread

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self._jobs: queue.SimpleQueue[Callable[[], ToolUpdate] | None] = queue.SimpleQueue()
        self._thread: threading.Thread | None = None
        self._title = ""
        self._started = 0.0
        self._shown_busy = False
        #: A step is running (set on the GUI thread; the worker never changes it).
        self.running = False
        #: Steps of at least this many ms on a mesh of at least this many vertices move the
        #: stroke's next steps off the GUI thread.
        self.slow_step_ms, self.big_mesh_vertices = SLOW_STEP_MS, BIG_MESH_VERTICES
        self._idle = threading.Event()
        self._idle.set()
        self._busy_timer = QTimer(self)
        self._busy_timer.setSingleShot(True)
        self._busy_timer.setInterval(BUSY_AFTER_MS)
        self._busy_timer.timeout.connect(self._show_busy)
        self._done.connect(self._on_done)

    def slow_steps(self, tools: SculptTools, last_step_ms: float) -> bool:
        """Whether ``tools``' next brush step runs here: with dynamic topology (a remesh in
        every event), or on a big mesh when the last step took :attr:`slow_step_ms` or more.
        Pin drags stay on the GUI thread (not strokes: settings may change meanwhile)."""
        sculptor = tools.sculptor
        if sculptor is None or tools.mode != "brush":
            return False
        if sculptor.settings.dynamic_topology:
            return True
        big = len(sculptor.vertices) >= self.big_mesh_vertices
        return big and last_step_ms >= self.slow_step_ms

    def run(self, step: Callable[[], ToolUpdate], error_title: str) -> None:
        """Run ``step`` on the worker thread; ``finished`` reports its end."""
        if self.running:
            raise RuntimeError("a brush step is already running")
        self.running, self._title, self._started = True, error_title, time.perf_counter()
        if self._thread is None:
            self._thread = threading.Thread(target=self._work, name="brush steps", daemon=True)
            self._thread.start()
        self._busy_timer.start()
        self._idle.clear()
        self._jobs.put(step)

    @property
    def seconds(self) -> float:
        """Seconds the running step has taken so far (0 when none runs)."""
        return time.perf_counter() - self._started if self.running else 0.0

    def stop(self) -> None:
        """End the worker thread once its step (if any) is done, waiting for that step (the
        view closes: nothing may report to it afterwards)."""
        self._idle.wait(60.0)
        if self._thread is not None:
            self._jobs.put(None)
            self._thread = None

    def _work(self) -> None:
        while (step := self._jobs.get()) is not None:
            try:
                update, error = step(), None
            except Exception as exc:  # the tools catch the engine's refusals; reported
                update, error = None, exc
            self._idle.set()
            self._done.emit(update, error)

    def _show_busy(self) -> None:
        if self.running and not self._shown_busy:  # once per run of steps
            self._shown_busy = True
            self.busy.emit(True)

    def _on_done(self, update: ToolUpdate | None, error: Exception | None) -> None:
        self.running = False
        self._busy_timer.stop()
        self.finished.emit(update or ToolUpdate(), self._title, error)
        if not self.running and self._shown_busy:  # no next step started from the report
            self._shown_busy = False
            self.busy.emit(False)
