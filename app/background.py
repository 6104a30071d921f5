"""Background work off the GUI thread: one helper for the kernel warm-up and the
homogenization preview.

:class:`BackgroundRunner` runs a function ``fn(task)`` on a worker thread and reports on the GUI
thread through queued signals: ``progress(id, fraction)``, then exactly one of
``finished(id, result)``, ``failed(id, exception)`` or ``cancelled(id)``.

Cancellation is cooperative and documented per job: :meth:`BackgroundRunner.cancel` (or a newer
:meth:`BackgroundRunner.submit` with ``supersede=True``) marks the job cancelled; the job stops
at its next :meth:`Task.progress` call (which raises :class:`Cancelled`), or, for work that
cannot report progress (a numba compilation), runs to its end and its result is dropped: a
cancelled job never reports ``finished``.

All runners share one worker thread (:func:`shared_pool`): numba's default ``workqueue``
threading layer allows one parallel launch at a time, so two background jobs with parallel
kernels (the warm-up's streamlines, the homogenization's FFT solves) must not overlap.
"""

from __future__ import annotations

import itertools
import threading
from collections.abc import Callable
from typing import Any

from PySide6.QtCore import QCoreApplication, QObject, QRunnable, QThreadPool, Signal

__all__ = ["BackgroundRunner", "Cancelled", "Task", "shared_pool"]

_POOL: QThreadPool | None = None


def shared_pool() -> QThreadPool:
    """The one worker thread of the background jobs (see the module docstring)."""
    global _POOL
    if _POOL is None:
        _POOL = QThreadPool()
        _POOL.setMaxThreadCount(1)
    return _POOL


class Cancelled(Exception):
    """Raised by :meth:`Task.progress` in a job that was cancelled."""


class Task:
    """What a job's function receives: its ``id``, :meth:`progress` and :attr:`cancelled`."""

    def __init__(self, job_id: int, report: Callable[[int, float], None]) -> None:
        self.id = job_id
        self._report = report
        self._cancelled = threading.Event()

    @property
    def cancelled(self) -> bool:
        return self._cancelled.is_set()

    def cancel(self) -> None:
        self._cancelled.set()

    def progress(self, fraction: float) -> None:
        """Report ``fraction`` in [0, 1] done; raises :class:`Cancelled` once cancelled."""
        if self.cancelled:
            raise Cancelled
        self._report(self.id, float(fraction))


class _Signals(QObject):
    progress = Signal(int, float)
    done = Signal(int, str, object)  # id, "finished" | "failed" | "cancelled", payload


class _Job(QRunnable):
    def __init__(self, fn: Callable[[Task], Any], task: Task, signals: _Signals) -> None:
        super().__init__()
        self.setAutoDelete(False)  # Python owns the job (kept by the runner until it reports)
        self._fn: Callable[[Task], Any] | None = fn
        self.task, self._signals = task, signals

    def run(self) -> None:
        # the function and what it captured (a mesh's arrays) are let go once it ran: the pool
        # keeps the job's Python object alive (PySide takes it over in ``start``)
        task, fn, self._fn = self.task, self._fn, None
        if task.cancelled or fn is None:
            self._signals.done.emit(task.id, "cancelled", None)
            return
        try:
            result = fn(task)
        except Cancelled:
            self._signals.done.emit(task.id, "cancelled", None)
        except Exception as exc:  # reported on the GUI thread
            self._signals.done.emit(task.id, "failed", exc)
        else:
            self._signals.done.emit(task.id, "cancelled" if task.cancelled else "finished", result)


class BackgroundRunner(QObject):
    """Runs functions on the shared worker thread; reports on the GUI thread.

    Signals
    -------
    progress(int, float) : job id and fraction done (not sent for cancelled jobs).
    finished(int, object) : job id and the function's result.
    failed(int, object) : job id and the exception (its ``parameter`` names the input when it
        is a :class:`gogreen_core.validation.ParameterError`).
    cancelled(int) : job id of a job that stopped or was dropped after :meth:`cancel`.
    busy_changed(bool) : whether a job of this runner is queued or running.
    """

    progress = Signal(int, float)
    finished = Signal(int, object)
    failed = Signal(int, object)
    cancelled = Signal(int)
    busy_changed = Signal(bool)

    def __init__(self, parent: QObject | None = None, pool: QThreadPool | None = None) -> None:
        super().__init__(parent)
        self._pool = pool or shared_pool()
        self._ids = itertools.count(1)
        self._jobs: dict[int, _Job] = {}
        self._signals = _Signals()
        self._signals.progress.connect(self._on_progress)
        self._signals.done.connect(self._on_done)

    def submit(self, fn: Callable[[Task], Any], *, supersede: bool = False) -> int:
        """Queue ``fn(task)``; returns the job id. ``supersede`` cancels this runner's other
        jobs first (a newer request replaces them)."""
        if supersede:
            self.cancel()
        job_id = next(self._ids)
        job = _Job(fn, Task(job_id, self._signals.progress.emit), self._signals)
        was_busy = self.busy
        self._jobs[job_id] = job
        self._pool.start(job)
        if not was_busy:
            self.busy_changed.emit(True)
        return job_id

    def cancel(self, job_id: int | None = None) -> None:
        """Cancel one job, or all of this runner's jobs (see the module docstring)."""
        for jid, job in self._jobs.items():
            if job_id is None or jid == job_id:
                job.task.cancel()

    def is_active(self, job_id: int) -> bool:
        """The job is queued or running and not cancelled."""
        job = self._jobs.get(job_id)
        return job is not None and not job.task.cancelled

    @property
    def busy(self) -> bool:
        return bool(self._jobs)

    def wait(self, msecs: int = -1) -> bool:
        """Block until the shared worker is idle (closing, tests) and deliver the reports of
        the jobs that ended; False on time-out."""
        done = self._pool.waitForDone(msecs)
        QCoreApplication.sendPostedEvents(self)  # the queued progress/done calls
        return done

    def _on_progress(self, job_id: int, fraction: float) -> None:
        if self.is_active(job_id):
            self.progress.emit(job_id, fraction)

    def _on_done(self, job_id: int, outcome: str, payload: object) -> None:
        job = self._jobs.pop(job_id, None)
        if job is None:
            return
        if outcome == "finished" and not job.task.cancelled:
            self.finished.emit(job_id, payload)
        elif outcome == "failed" and not job.task.cancelled:
            self.failed.emit(job_id, payload)
        else:
            self.cancelled.emit(job_id)
        if not self._jobs:
            self.busy_changed.emit(False)
