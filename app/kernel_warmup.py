"""The compiled brush kernels, brought in while the artist already sculpts.

Strokes never wait for a compiler: until the compiled code of an l_max is ready the engine runs
the same arithmetic in NumPy, with the same results bit for bit (``gogreen_core._compiled``),
and so do the viewport's surface index (picking, normals). The window asks for the current
l_max at start and whenever it changes; on a new machine a child process compiles it, with the
surface index, the mesh readers' and the paint brushes' loops (seconds to tens of seconds, once
per machine: numba keeps them on disk; the install step, ``scripts/setup_env.sh``, compiles
them already), elsewhere they load from the disk cache in milliseconds.
:class:`KernelWarmer` reports when the kernels are in, to say so in the status bar and stop its
progress indicator; it runs nothing on the app's background thread, which stays free for mesh
indexing and homogenization.
"""

from __future__ import annotations

import itertools
import time

from PySide6.QtCore import QObject, Qt, Signal

from gogreen_core import _compiled
from gogreen_core.field import _drivers
from gogreen_core.interaction.compile_kernels import units_for_app

__all__ = ["KernelWarmer"]


class _Relay(QObject):
    """Carries a compilation's end from the compiling thread to the GUI thread.

    One for the process, never deleted: the compiling thread calls back long after the window
    that asked may be gone (on a new machine the compilation takes tens of seconds), and a
    signal emitted on a deleted warmer from another thread is a use after free (a crash seen in
    CI). Each warmer listens with a connection Qt drops when the warmer is deleted."""

    settled = Signal(int, int, float, str)  # warmer token, l_max, seconds, error
    # units compiled, units to compile, about how many seconds are left (-1: not known yet),
    # what is compiling now
    progressed = Signal(int, int, float, str)


_relay: _Relay | None = None
_tokens = itertools.count(1)


def _the_relay() -> _Relay:
    """The process's relay, made on the GUI thread by the first warmer."""
    global _relay
    if _relay is None:
        relay = _relay = _Relay()

        def progressed(progress: _compiled.Progress) -> None:
            left = progress.seconds_left
            seconds = -1.0 if left is None else left
            relay.progressed.emit(progress.done, progress.total, seconds, progress.compiling)

        _compiled.add_progress_listener(progressed)
    return _relay


class KernelWarmer(QObject):
    """Brings in the compiled kernels of each requested l_max once.

    Signals (emitted on the GUI thread, after the call that requested them returned)
    -------
    ready(int, float, bool) : l_max, the seconds it took, and whether it was compiled (False:
        only loaded from the disk cache).
    failed(int, str) : l_max and the error (its strokes keep running in NumPy).
    busy_changed(bool) : some requested l_max is not ready yet.
    progress(int, int, float, str) : units compiled, units to compile (missing from the disk
        cache), about how many seconds are left (-1: not known) and what is compiling now.
    """

    ready = Signal(int, float, bool)
    progress = Signal(int, int, float, str)
    failed = Signal(int, str)
    busy_changed = Signal(bool)

    def __init__(self, parent: QObject | None = None):
        super().__init__(parent)
        self._token = next(_tokens)
        self._relay = _the_relay()
        self._relay.settled.connect(self._settled, Qt.ConnectionType.QueuedConnection)
        self._relay.progressed.connect(self.progress, Qt.ConnectionType.QueuedConnection)
        self._requested: dict[int, tuple] = {}  # l_max -> its compiled units
        self._waiting: set[int] = set()

    def request(self, l_max: int) -> bool:
        """Ask for the compiled kernels of ``l_max`` unless already asked for; True if asked
        now. Returns at once; :attr:`ready` follows."""
        if l_max in self._requested:
            return False
        units = _drivers.units_for(l_max)
        if not self._requested:  # with the kernels, in one child process on a new machine,
            _compiled.request(*units_for_app(l_max))  # in the order the first stroke needs
        self._requested[l_max] = units
        self._waiting.add(l_max)
        if len(self._waiting) == 1:
            self.busy_changed.emit(True)
        start = time.perf_counter()
        relay, token = self._relay, self._token  # never self: it may be gone by then

        def settled(failures: list) -> None:
            error = "; ".join(f"{type(e).__name__}: {e}" for e in failures)
            relay.settled.emit(token, l_max, time.perf_counter() - start, error)

        _compiled.when_ready(units, settled)
        return True

    def is_ready(self, l_max: int) -> bool:
        """Strokes of ``l_max`` may start: always (the NumPy evaluation serves until the
        compiled code is ready, with the same results)."""
        return True

    def compiled(self, l_max: int) -> bool:
        """The compiled kernels of ``l_max`` are in use (or failed: NumPy serves)."""
        return l_max in self._requested and l_max not in self._waiting

    @property
    def busy(self) -> bool:
        return bool(self._waiting)

    def wait(self, msecs: int = -1) -> bool:
        """Block until the requested kernels are compiled or loaded (tests, benchmarks);
        False on time-out. Closing the app need not wait: a compiling child process finishes
        on its own and leaves its work in the disk cache."""
        units = {u for units in self._requested.values() for u in units}
        return _compiled.wait(units, None if msecs < 0 else msecs / 1000)

    def _settled(self, token: int, l_max: int, seconds: float, error: str) -> None:
        if token == self._token:
            self._report(l_max, seconds, error)

    def _report(self, l_max: int, seconds: float, error: str) -> None:
        self._waiting.discard(l_max)
        if error:
            self.failed.emit(l_max, error)
        else:
            self.ready.emit(l_max, seconds, _compiled.compiled_here(self._requested[l_max]))
        if not self._waiting:
            self.busy_changed.emit(False)
