"""Background compilation of the evaluation kernels of a truncation degree.

The angular kernels are generated and compiled per l_max on first use (``prepare_degree``:
seconds once per machine, milliseconds from numba's disk cache afterwards). The window asks for
the current l_max at start and whenever it changes, so that the next stroke does not wait;
a stroke that comes first simply waits for the same compilation (results do not depend on
which thread compiled).
"""

from __future__ import annotations

from PySide6.QtCore import QObject, QRunnable, QThreadPool, Signal

from gogreen_core.kernel import prepare_degree

__all__ = ["KernelWarmer"]


class _Signals(QObject):
    ready = Signal(int, float)  # l_max, seconds
    failed = Signal(int, str)


class _WarmUpJob(QRunnable):
    def __init__(self, l_max: int, signals: _Signals):
        super().__init__()
        self.setAutoDelete(False)  # Python owns the job (kept by the warmer)
        self.l_max = l_max
        self._signals = signals

    def run(self) -> None:
        try:
            seconds = prepare_degree(self.l_max)
        except Exception as exc:  # reported in the status bar; strokes will raise it again
            self._signals.failed.emit(self.l_max, f"{type(exc).__name__}: {exc}")
        else:
            self._signals.ready.emit(self.l_max, seconds)


class KernelWarmer(QObject):
    """Compiles the kernels of each requested l_max once, on a private one-thread pool.

    Signals
    -------
    ready(int, float) : l_max and the seconds its warm-up took.
    failed(int, str) : l_max and the error.
    """

    def __init__(self, parent: QObject | None = None):
        super().__init__(parent)
        self._signals = _Signals()
        self.ready = self._signals.ready
        self.failed = self._signals.failed
        self._pool = QThreadPool()
        self._pool.setMaxThreadCount(1)
        self._jobs: dict[int, _WarmUpJob] = {}

    def request(self, l_max: int) -> bool:
        """Queue the warm-up of ``l_max`` unless already asked for; True if queued now."""
        if l_max in self._jobs:
            return False
        job = self._jobs[l_max] = _WarmUpJob(l_max, self._signals)
        self._pool.start(job)
        return True

    def wait(self, msecs: int = -1) -> bool:
        """Block until queued warm-ups end (tests, closing the window); False on time-out."""
        return self._pool.waitForDone(msecs)
