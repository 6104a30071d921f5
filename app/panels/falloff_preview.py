"""The falloff preview: what the selected brush's falloff feels like, computed off the GUI
thread.

:class:`FalloffPreview` plots the felt falloff (:func:`felt_falloff`) of the selected brush
with the settings' material, falloff, l_max and the brush's degree weights;
:class:`PreviewComputer` builds its kernels on the app's background thread
(:mod:`app.background`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import QPointF, QRectF, QSize, Qt, QTimer
from PySide6.QtGui import QColor, QFontMetricsF, QPainter, QPainterPath, QPen
from PySide6.QtWidgets import QWidget

from app.background import BackgroundRunner, Cancelled, Task
from app.panels.curve_editor import curve_color
from app.panels.plot_axes import draw_plot_axes, plot_font
from app.panels.widgets import plot_colors
from gogreen_core.field.kernel import GreenKernel, prepare_degree
from gogreen_core.interaction.settings import Settings
from gogreen_core.interaction.tools import felt_profile
from gogreen_core.sculpt.brushes import brush_row, brush_type
from gogreen_core.sculpt.brushes.base import GreenBrush
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.kernel_cache import KernelCache

__all__ = [
    "PREVIEW_INTERVAL_MS",
    "PREVIEW_SAMPLES",
    "PREVIEW_STALE_MS",
    "FalloffPreview",
    "PreviewComputer",
    "PreviewRequest",
    "felt_falloff",
]

#: Samples of the falloff preview (one kernel evaluation each: a few ms in all).
PREVIEW_SAMPLES = 64
#: Least time between two preview updates (ms): a drag's steps are coalesced.
PREVIEW_INTERVAL_MS = 120
#: A request still running after this long (ms) dims the shown curve: it is out of date (a new
#: material's quadrature, or an l_max whose kernels are still compiling).
PREVIEW_STALE_MS = 400


@dataclass(frozen=True)
class PreviewRequest:
    """What one preview shows: a snapshot taken on the GUI thread (the engine settings, an
    immutable value: material, frozen falloff, l_max, degree weights) and the brush kind."""

    engine: EngineSettings
    kind: str
    rho: np.ndarray

    @classmethod
    def of(cls, settings: Settings, rho: np.ndarray) -> PreviewRequest:
        return cls(settings.engine_settings, settings.brush.kind, np.array(rho, dtype=float))


class PreviewComputer:
    """Builds the kernels of previews off the GUI thread, keeping the one of the latest
    (material, l_max) so that a curve edit only swaps the falloff (new radial tables; a new
    material or l_max needs a new quadrature). Used by one worker at a time (the app's
    background thread runs its jobs in turn), never by two threads at once.

    :meth:`kernel` is the slow part (plain numpy, and the compilation of a new l_max's angular
    code, which runs no parallel code): the worker's. :func:`felt_falloff` evaluates G at the
    64 samples (~0.06 ms) with numba's parallel driver: on the GUI thread, where strokes run,
    because numba's workqueue threading layer aborts the process on two parallel launches
    from two threads at once (measured: "Concurrent access has been detected")."""

    def __init__(self) -> None:
        self._kernels: KernelCache | None = None

    def kernel(self, request: PreviewRequest) -> GreenKernel | None:
        """The kernel of ``request``'s brush (ε = 1: its falloff variant and degree weights,
        :meth:`GreenBrush.unit_kernel`) with its material, l_max and falloff; None for a brush
        without one (smooth, mask)."""
        engine = request.engine
        if self._kernels is None or self._kernels.settings != engine:
            prepare_degree(engine.l_max)  # compiled here, not when the GUI thread evaluates
            self._kernels = KernelCache(engine, self._kernels)  # same quadrature if it can
        brush = brush_type(request.kind)
        return brush.unit_kernel(self._kernels) if isinstance(brush, GreenBrush) else None

    def __call__(self, request: PreviewRequest) -> np.ndarray | None:
        """Both steps on the calling thread (scripts, tests, benchmarks)."""
        return felt_falloff(self.kernel(request), request.rho, request.kind)


def felt_falloff(
    kernel: GreenKernel | None, rho: np.ndarray, kind: str = "grab"
) -> np.ndarray | None:
    """The felt falloff of brush ``kind`` (:func:`felt_profile`) with its ``kernel`` (ε = 1)
    at ``rho`` (n,), normalized to 1 at its peak; None if it is zero or not finite."""
    return felt_profile(kind, kernel, rho)


class FalloffPreview(QWidget):
    """What the artist feels: the selected brush's motion along a radius (:func:`felt_profile`:
    a grab's relative to the cursor's, an affine brush's about its fixed centre, a paint
    brush's weight), normalized to 1 at its peak, for the settings' material, falloff, l_max
    and the brush's degree weights, at ρ = r/ε in [0, ``rho_max``], with tick labels on both
    axes and a title naming the brush.

    Changes are coalesced: at most one request per :data:`PREVIEW_INTERVAL_MS`
    (:meth:`schedule`; :meth:`recompute` requests at once). The kernel is built on the app's
    background thread (:mod:`app.background`; after a curve edit 2-8 ms at l_max 8, 12-28 ms
    at l_max 20, after a material change 40-100 ms, a new l_max's first compilation much
    longer; ``benchmarks/falloff_preview.py``) and evaluated on the GUI thread when it arrives
    (~0.06 ms, see :class:`PreviewComputer`), the latest request winning: a
    request still queued when a newer one is sent is skipped, one already computing is shown
    when it ends (it is newer than the curve on screen) and the newest follows. The shown
    curve stays until a new one arrives (no flicker), dimmed while the latest request is older
    than :data:`PREVIEW_STALE_MS`.
    :attr:`rho` and :attr:`values` are the plotted data (values None if the kernel failed);
    :attr:`pending` tells whether a request is in flight, :meth:`wait` blocks until none is.
    """

    def __init__(self, settings: Settings, parent: QWidget | None = None):
        super().__init__(parent)
        self.settings = settings
        self.rho_max = 4.0
        self.rho = np.linspace(0.0, self.rho_max, PREVIEW_SAMPLES)
        self.values: np.ndarray | None = None
        #: The brush whose curve is shown.
        self.kind = str(settings.brush.kind)
        #: Requests sent and results shown (the rest were skipped as superseded), for tests.
        self.requested = 0
        self.shown = 0
        #: Number of the latest request, read by queued jobs on the worker thread.
        self._latest = [0]
        self._shown_number = 0
        self._computer = PreviewComputer()
        self._runner = BackgroundRunner(self)
        self._runner.finished.connect(self._finished)
        self._runner.failed.connect(self._failed)
        self._runner.cancelled.connect(self._cancelled)
        self._job: int | None = None
        self._stale = False
        self._timer = QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.setInterval(PREVIEW_INTERVAL_MS)
        self._timer.timeout.connect(self.recompute)
        self._stale_timer = QTimer(self)
        self._stale_timer.setSingleShot(True)
        self._stale_timer.setInterval(PREVIEW_STALE_MS)
        self._stale_timer.timeout.connect(self._mark_stale)
        self.setMinimumHeight(130)
        self.setToolTip(
            "Falloff felt by the selected brush: displacement along a radius, in brush radii "
            "(ρ = r/ε), normalized to 1 at its peak, for this material, falloff, l_max and "
            "the brush's degree weights (an affine brush's centre stays: its curve starts at 0)"
        )

    def sizeHint(self) -> QSize:
        return QSize(300, 150)

    @property
    def pending(self) -> bool:
        """A request is scheduled or computing."""
        return self._timer.isActive() or self._job is not None

    @property
    def stale(self) -> bool:
        """The latest request has been computing for longer than :data:`PREVIEW_STALE_MS`:
        the curve on screen is out of date (drawn dimmed, "updating…" in the title)."""
        return self._stale

    def set_rho_max(self, rho_max: float) -> None:
        self.rho_max = float(rho_max)
        self.schedule()

    def schedule(self) -> None:
        """Recompute soon (once for any number of calls within the interval)."""
        if not self._timer.isActive():
            self._timer.start()

    def recompute(self) -> None:
        """Request the preview of the current settings now (see the class docstring for what
        happens to a request in flight)."""
        self._timer.stop()
        request = PreviewRequest.of(self.settings, np.linspace(0.0, self.rho_max, PREVIEW_SAMPLES))
        self.requested += 1
        number, latest, computer = self.requested, self._latest, self._computer
        latest[0] = number

        def compute(_task: Task) -> tuple:
            if latest[0] != number:  # a newer request was sent while this one waited
                raise Cancelled
            return number, request.rho, computer.kernel(request), request.kind

        self._job = self._runner.submit(compute)
        if not self._stale_timer.isActive():
            self._stale_timer.start()

    def wait(self, msecs: int = 30_000) -> bool:
        """Send a scheduled request now and block until its result is shown (tests, scripts);
        False on time-out."""
        if self._timer.isActive():
            self.recompute()
        return self._runner.wait(msecs) and self._job is None

    def _finished(self, job: int, result: tuple) -> None:
        number, rho, kernel, kind = result
        if number > self._shown_number:  # jobs end in order: never older than the shown one
            self.kind = kind
            try:
                values = felt_falloff(kernel, rho, kind)
            except (ValueError, RuntimeError):
                values = None
            self._shown_number = number
            self.rho, self.values = rho, values
            self.shown += 1
        self._ended(job)

    def _failed(self, job: int, _exc: Exception) -> None:
        if job == self._job:
            self.values = None
        self._ended(job)

    def _cancelled(self, job: int) -> None:
        self._ended(job)

    def _ended(self, job: int) -> None:
        if job == self._job:  # the latest request: the preview is up to date
            self._job = None
            self._stale_timer.stop()
            self._stale = False
        self.update()

    def _mark_stale(self) -> None:
        if self._job is not None:
            self._stale = True
            self.update()

    def closeEvent(self, event) -> None:
        self._timer.stop()
        self._latest[0] = -1  # queued requests are skipped
        super().closeEvent(event)

    def title(self) -> str:
        """The plot's title: whose felt falloff it is ("felt falloff of Scale")."""
        return f"felt falloff of {brush_row(self.kind).label}"

    # -- drawing -----------------------------------------------------------------------------
    def plot_rect(self) -> QRectF:
        """The plot area inside the axes' tick labels and titles (widget pixels)."""
        metrics = QFontMetricsF(plot_font(self.font()))
        left = metrics.horizontalAdvance("0.75") + 10 + metrics.height()
        top = metrics.height() + 8
        bottom = 2 * metrics.height() + 10
        return QRectF(self.rect()).adjusted(left, top, -10, -bottom)

    def paintEvent(self, _event) -> None:
        colors = plot_colors()
        painter = QPainter(self)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        painter.fillRect(self.rect(), colors.background)
        painter.setFont(plot_font(self.font()))
        metrics = QFontMetricsF(painter.font())
        rect = self.plot_rect()
        painter.setPen(colors.text)
        painter.drawText(
            QRectF(rect.left(), 2, rect.width(), metrics.height()),
            Qt.AlignmentFlag.AlignHCenter,
            self.title() + ("  (updating…)" if self._stale else ""),
        )
        rho_max = float(self.rho[-1]) if len(self.rho) > 1 and self.rho[-1] > 0 else 1.0
        self._draw_axes(painter, rect, rho_max, colors)
        if self.values is None:
            painter.setPen(colors.muted)
            text = "computing…" if self.pending else "no preview"
            painter.drawText(rect, Qt.AlignmentFlag.AlignCenter, text)
            return
        path = QPainterPath()
        for i, (r, v) in enumerate(zip(self.rho, self.values, strict=True)):
            point = QPointF(
                rect.left() + r / rho_max * rect.width(),
                rect.bottom() - float(v) * rect.height(),
            )
            path.moveTo(point) if i == 0 else path.lineTo(point)
        color = QColor(curve_color(("R", 0)))
        if self._stale:
            color.setAlpha(110)
        painter.setPen(QPen(color, 2.0))
        painter.drawPath(path)

    def _draw_axes(self, painter, rect, rho_max, colors) -> None:
        """Frame, grid, tick labels (ρ below, normalized |u| 0-1 on the left) and titles."""
        y_ticks = (0.0, 0.25, 0.5, 0.75, 1.0) if rect.height() >= 90 else (0.0, 0.5, 1.0)
        titles = ("distance ρ = r/ε (brush radii)", "|u| / peak")
        draw_plot_axes(
            painter, rect, (0.0, rho_max), (0.0, 1.0), titles, colors, y_ticks, (50.0, 40.0)
        )
