"""Background compilation of everything a stroke evaluates with, per truncation degree.

The angular kernels are generated and compiled per l_max on first use
(:func:`gogreen_core.kernel.prepare_degree`), and the parallel drivers (streamlines,
displacements) once per machine (:meth:`gogreen_core.kernel.GreenKernel.warm_up`): seconds to
tens of seconds from an empty numba cache, milliseconds from the disk cache afterwards. The
window asks for the current l_max at start and whenever it changes and refuses strokes of an
l_max that is not ready yet (with a message), so no stroke ever waits on a compiler.

A warm-up cannot be interrupted (a numba compilation reports no progress); cancelling one only
drops its result (see :mod:`app.background`).
"""

from __future__ import annotations

import time

import numpy as np
from PySide6.QtCore import QObject, Signal

from app.background import BackgroundRunner, Task
from gogreen_core import mesh_io
from gogreen_core.brushes import Brush, BrushEvent
from gogreen_core.kernel import GreenKernel, prepare_degree
from gogreen_core.material import Material
from gogreen_core.radial import GaussianRadial, SplineRadial
from gogreen_core.sculptor import Sculptor
from gogreen_core.shapes import icosphere

__all__ = ["KernelWarmer", "warm_up_degree"]


def warm_up_degree(l_max: int, task: Task | None = None) -> float:
    """Compile (or load from the cache) what strokes of ``l_max`` run; returns seconds.

    The compiled code does not depend on the material or the falloff's values (those are
    tables), so a fixed isotropic material and a spline Gaussian (the app's default falloff
    type) compile all of it.
    """
    start = time.perf_counter()
    mesh_io.warm_up()  # the mesh readers' compiled loops: opening a file then never compiles
    prepare_degree(l_max)
    if task is not None:
        task.progress(0.3)
    falloff = SplineRadial.from_profile(GaussianRadial(1.0), l_max)
    GreenKernel(Material.isotropic(1.0, 0.3), l_max, falloff).warm_up()
    if task is not None:
        task.progress(0.6)
    # A stroke also runs helpers outside the kernel (the active-vertex search, G(0) for the
    # grab force, the pins' solve): one tiny stroke of each kind compiles them all.
    vertices, faces = icosphere(1)
    sculptor = Sculptor(vertices, faces, l_max=l_max, falloff=falloff)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    grab = BrushEvent(center=top, delta=np.array([0.0, 0.0, 0.01]))
    sculptor.apply_brush(Brush("grab", radius=0.3, symmetry="x"), [grab])
    sculptor.apply_brush(Brush("wrinkle", radius=0.3), [grab])
    twist = BrushEvent(center=top, amount=0.01, axis=np.array([0.0, 0.0, 1.0]))
    sculptor.apply_brush(Brush("twist", radius=0.3), [twist])
    paint = BrushEvent(center=top, delta=np.array([0.0, 0.0, 0.01]), amount=0.5)
    sculptor.apply_brush(Brush("mask", radius=0.1), [paint])  # the blend of masked rows
    sculptor.apply_brush(Brush("smooth", radius=0.3, symmetry="x"), [paint])
    pin = sculptor.add_constraint(top)
    sculptor.add_constraint(-top)
    sculptor.drag_constraint(pin, np.array([0.0, 0.0, 0.01]))
    return time.perf_counter() - start


class KernelWarmer(QObject):
    """Warms the kernels of each requested l_max once, on the shared background thread.

    Signals
    -------
    ready(int, float) : l_max and the seconds its warm-up took.
    failed(int, str) : l_max and the error.
    busy_changed(bool) : a warm-up is queued or running.
    """

    ready = Signal(int, float)
    failed = Signal(int, str)
    busy_changed = Signal(bool)

    def __init__(self, parent: QObject | None = None):
        super().__init__(parent)
        self._runner = BackgroundRunner(self)
        self._runner.finished.connect(self._finished)
        self._runner.failed.connect(self._failed)
        self._runner.busy_changed.connect(self.busy_changed)
        self._jobs: dict[int, int] = {}  # job id -> l_max
        self._requested: set[int] = set()
        self._ready: set[int] = set()
        self._errors: dict[int, str] = {}

    def request(self, l_max: int) -> bool:
        """Queue the warm-up of ``l_max`` unless already asked for; True if queued now."""
        if l_max in self._requested:
            return False
        self._requested.add(l_max)
        job = self._runner.submit(lambda task, l=l_max: warm_up_degree(l, task))
        self._jobs[job] = l_max
        return True

    def is_ready(self, l_max: int) -> bool:
        """The warm-up of ``l_max`` ended (a failed one counts: strokes then show the error)."""
        return l_max in self._ready or l_max in self._errors

    @property
    def busy(self) -> bool:
        return self._runner.busy

    def wait(self, msecs: int = -1) -> bool:
        """Block until queued warm-ups end (tests, closing the window); False on time-out."""
        return self._runner.wait(msecs)

    def _finished(self, job: int, seconds: float) -> None:
        l_max = self._jobs.pop(job)
        self._ready.add(l_max)
        self.ready.emit(l_max, seconds)

    def _failed(self, job: int, exc: Exception) -> None:
        l_max = self._jobs.pop(job)
        self._errors[l_max] = f"{type(exc).__name__}: {exc}"
        self.failed.emit(l_max, self._errors[l_max])
