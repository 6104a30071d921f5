"""Long computations off Blender's main thread, one at a time (no bpy).

Compiling the numba kernels the first time (tens of seconds) and homogenizing a pattern
(seconds) must not freeze Blender's window silently: they run on a worker thread while a timer
on the main thread polls :meth:`JobRunner.poll` to redraw the progress and, when a job ends,
hands its result to the job's ``done`` callback there (Blender data may only be changed on the
main thread).

Every computation with the engine holds :data:`ENGINE_LOCK`: numba's fallback threading layer
aborts the process when two threads launch parallel code at once, so a stroke never runs while
a job does (the modal tool refuses to start, with a message; ``gogreen.apply_stroke`` waits).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

__all__ = ["ENGINE_LOCK", "RUNNER", "Job", "JobRunner"]

#: Held by whatever runs the engine (a job's thread, a stroke on the main thread).
ENGINE_LOCK = threading.RLock()


class Job:
    """One background computation.

    label : what the status line says ("Compiling brush kernels").
    work : ``work(progress) -> result``; ``progress(fraction)`` may be called from the worker.
    done : called on the main thread with the finished job (result or error), by
        :meth:`JobRunner.poll`.
    """

    def __init__(
        self,
        label: str,
        work: Callable[[Callable[[float], None]], Any],
        done: Callable[[Job], None] | None = None,
    ) -> None:
        self.label = label
        self.work = work
        self.done = done
        self.progress: float | None = None
        self.result: Any = None
        self.error: BaseException | None = None
        self.started = time.monotonic()
        self.ended: float | None = None
        self._thread: threading.Thread | None = None

    @property
    def finished(self) -> bool:
        return self.ended is not None

    @property
    def elapsed(self) -> float:
        """Seconds since the job started (until it ended)."""
        return (self.ended or time.monotonic()) - self.started

    def _report(self, fraction: float) -> None:
        self.progress = min(max(float(fraction), 0.0), 1.0)

    def run(self) -> None:
        """Run the work here (the worker thread, or the caller in background mode)."""
        with ENGINE_LOCK:
            try:
                self.result = self.work(self._report)
            except Exception as exc:  # handed to `done` and shown; the thread must not die
                self.error = exc
            finally:
                self.ended = time.monotonic()

    def status(self) -> str:
        """'Compiling brush kernels: 12 s' or 'Homogenizing: 40 %'."""
        if self.progress is not None:
            return f"{self.label}: {100 * self.progress:.0f} %"
        return f"{self.label}: {self.elapsed:.0f} s"

    def wait(self, timeout: float | None = None) -> bool:
        """Block until the worker ends; True if it has."""
        if self._thread is not None:
            self._thread.join(timeout)
        return self.finished


class JobRunner:
    """Runs one :class:`Job` at a time on a daemon thread; the main thread polls it."""

    def __init__(self) -> None:
        self.current: Job | None = None

    @property
    def busy(self) -> Job | None:
        """The job still running, or None."""
        job = self.current
        return job if job is not None and not job.finished else None

    def submit(self, job: Job, threaded: bool = True) -> bool:
        """Start ``job`` (False: another one is still running, nothing started). With
        ``threaded`` False it runs here and now (Blender in background mode, scripts)."""
        if self.busy is not None:
            return False
        self.current = job
        if threaded:
            job._thread = threading.Thread(target=job.run, name=f"gogreen: {job.label}")
            job._thread.daemon = True
            job._thread.start()
        else:
            job.run()
        return True

    def poll(self) -> Job | None:
        """On the main thread: the job that has just ended (its ``done`` called), else None."""
        job = self.current
        if job is None or not job.finished:
            return None
        self.current = None
        if job.done is not None:
            job.done(job)
        return job

    def wait(self) -> Job | None:
        """Block until the running job ends and deliver it (:meth:`poll`)."""
        job = self.current
        if job is None:
            return None
        job.wait()
        return self.poll()


#: The add-on's runner.
RUNNER = JobRunner()
