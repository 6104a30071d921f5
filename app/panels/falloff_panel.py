"""Falloff panel: edit the brush falloff curves, the SH truncation degree and wrinkle weights.

A view of the falloff fields of :class:`gogreen_core.settings.Settings` (``falloff``,
``l_max``, ``degree_weights``): the panel owns none of them. The falloff is the settings'
:class:`gogreen_core.SplineRadial` in the dimensionless variable ρ = r/ε (its ε stays 1; the
consumer calls ``with_eps``). Even degrees carry R_l, the falloff of the Green's function G used
by grab brushes; odd degrees carry ℛ_l, used by ∇G and the affine brushes (scale, twist,
pinch). Each edit of the curve editor is a new falloff value, set with
``settings.set("falloff", ..., continued=...)``: the steps of one point drag after the first are
``continued``, so a whole drag can be one undo step in the engine. Curves of degrees above the
current l_max are kept, so lowering and raising l_max restores them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import QPointF, QRectF, QSize, Qt, QTimer, Signal
from PySide6.QtGui import QColor, QFontMetricsF, QPainter, QPainterPath, QPen
from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QPushButton,
    QSpinBox,
    QVBoxLayout,
    QWidget,
)

from app.background import BackgroundRunner, Cancelled, Task
from app.panels.curve_editor import CurveEditor, curve_color, curve_label
from app.panels.plot_axes import draw_plot_axes, plot_font
from app.panels.widgets import plot_colors, scrolled_column, set_text_role
from gogreen_core.brushes import default_wrinkle_weights
from gogreen_core.kernel import GreenKernel, prepare_degree
from gogreen_core.material import Material
from gogreen_core.radial import GaussianRadial, KelvinletRadial, RadialProfile, SplineRadial
from gogreen_core.settings import ChangeEvent, Settings, needed_curves
from gogreen_core.tools import grab_motion

__all__ = [
    "L_MAX_RANGE",
    "QUICK_CURVES",
    "FalloffPanel",
    "FalloffPreview",
    "PreviewComputer",
    "PreviewRequest",
    "felt_falloff",
]

#: Range of the truncation degree spin box.
L_MAX_RANGE = (0, 30)
#: Curves with a "show" check box: R₀ and R₂ (shown by default), ℛ₁ and ℛ₃.
QUICK_CURVES = (("R", 0), ("R", 2), ("dR", 1), ("dR", 3))
_DEFAULT_SHOWN = (("R", 0), ("R", 2))
_WEIGHT_COLUMNS = 3
#: Samples of the falloff preview (one kernel evaluation each: a few ms in all).
PREVIEW_SAMPLES = 64
#: Least time between two preview updates (ms): a drag's steps are coalesced.
PREVIEW_INTERVAL_MS = 120
#: A request still running after this long (ms) dims the shown curve: it is out of date (a new
#: material's quadrature, or an l_max whose kernels are still compiling).
PREVIEW_STALE_MS = 400


@dataclass(frozen=True)
class PreviewRequest:
    """What one preview shows: a snapshot taken on the GUI thread (copies of the control points
    of the settings' falloff)."""

    material: Material
    l_max: int
    curves: dict[tuple[str, int], tuple[np.ndarray, np.ndarray]]
    rho: np.ndarray
    interpolation: str = "monotone"

    @classmethod
    def of(cls, settings: Settings, rho: np.ndarray) -> PreviewRequest:
        falloff = settings.falloff
        curves = {key: falloff.curve(*key) for key in falloff.curve_keys()}  # copies, ~20 µs
        rho = np.array(rho, dtype=float)
        return cls(settings.material, settings.l_max, curves, rho, falloff.interpolation)


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
        self._key: tuple | None = None
        self._kernel: GreenKernel | None = None

    def kernel(self, request: PreviewRequest) -> GreenKernel:
        """The kernel of ``request``'s material, l_max and falloff (ε = 1)."""
        radial = SplineRadial(1.0, request.curves, request.interpolation)
        key = (request.material, request.l_max)
        if self._kernel is None or self._key != key:
            prepare_degree(request.l_max)  # compiled here, not when the GUI thread evaluates
            self._kernel, self._key = GreenKernel(request.material, request.l_max, radial), key
        return self._kernel.with_radial(radial)

    def __call__(self, request: PreviewRequest) -> np.ndarray | None:
        """Both steps on the calling thread (scripts, tests, benchmarks)."""
        return felt_falloff(self.kernel(request), request.rho)


def felt_falloff(kernel: GreenKernel, rho: np.ndarray) -> np.ndarray | None:
    """The felt falloff (:func:`grab_motion`) of ``kernel`` (ε = 1) at ``rho`` (n,), normalized
    to 1 at its peak; None if it is zero or not finite."""
    magnitude = grab_motion(kernel, rho)
    peak = magnitude.max()
    return magnitude / peak if np.isfinite(peak) and peak > 0 else None


class FalloffPreview(QWidget):
    """What the artist feels: a grab's motion along a radius (:func:`grab_motion`, the curve
    the brush cursor draws), normalized to 1 at its peak, for the settings' material, falloff
    and l_max, at ρ = r/ε in [0, ``rho_max``], with tick labels on both axes.

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
            "Falloff felt by a grab brush: displacement along a radius, in brush radii "
            "(ρ = r/ε), normalized to 1 at its peak, for this material, falloff and l_max"
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
            return number, request.rho, computer.kernel(request)

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
        number, rho, kernel = result
        if number > self._shown_number:  # jobs end in order: never older than the shown one
            try:
                values = felt_falloff(kernel, rho)
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
            "felt falloff of a grab" + ("  (updating…)" if self._stale else ""),
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


def _key_id(key: tuple[str, int]) -> str:
    """Combo item data of a curve ("R:0", "dR:1"): plain strings survive QVariant intact."""
    return f"{key[0]}:{key[1]}"


def _key_from_id(text: str) -> tuple[str, int]:
    kind, degree = text.split(":")
    return kind, int(degree)


_needed_keys = needed_curves


class FalloffPanel(QWidget):
    """Edit the falloff (:attr:`radial`), truncation degree (:attr:`l_max`) and per-degree
    weights of the wrinkle brush (:attr:`degree_weights`).

    Parameters
    ----------
    l_max : int, default 8 (the sculptor's default; used when ``settings`` is omitted)
    parent : QWidget, optional
    settings : Settings, optional: the model shown and edited (a private one when omitted)

    Signals
    -------
    falloff_changed() : after every edit made in the panel (each step of a point drag,
        add/remove, reset, l_max, a weight); changes made to the settings elsewhere (a preset,
        an undo) update the panel without it. Read :attr:`radial`, :attr:`l_max`,
        :attr:`degree_weights`.
    editing_finished() : after a discrete edit or at the end of a drag, for consumers that do
        not want every drag step.

    Widgets (public for scripting and tests): ``editor`` (:class:`CurveEditor`),
    ``curve_combo``, ``show_checks`` ((kind, l) -> QCheckBox), ``rho_max_spin``,
    ``reset_gaussian_button``, ``reset_kelvinlet_button``, ``l_max_spin``, ``weight_spins``,
    ``weights_one_button``, ``weights_boost_button``, ``message_label``.
    """

    falloff_changed = Signal()
    editing_finished = Signal()

    def __init__(
        self, l_max: int = 8, parent: QWidget | None = None, settings: Settings | None = None
    ):
        super().__init__(parent)
        self.settings = settings if settings is not None else Settings(l_max=l_max)
        self._check_l_max(self.settings.l_max)
        self._editing = False  # the panel itself is changing the settings
        self._drag_continued = False  # the next drag step continues a drag
        self.weight_spins: list[QDoubleSpinBox] = []

        layout = scrolled_column(self)

        self.editor = CurveEditor(self.radial)
        self.editor.setMinimumHeight(240)
        self.editor.setMaximumHeight(400)
        self.editor.edited.connect(self._curve_edited)
        self.editor.drag_finished.connect(self._drag_finished)
        self.editor.message.connect(self._show_message)
        self.editor.active_curve_changed.connect(self._active_changed_in_editor)
        layout.addWidget(self.editor, 1)
        self.preview = FalloffPreview(self.settings)
        layout.addWidget(self.preview)

        hint = QLabel("Drag points · double-click or Ctrl+click adds · right-click or Del removes")
        hint.setWordWrap(True)
        set_text_role(hint, "muted")
        layout.addWidget(hint)
        self.message_label = QLabel()
        self.message_label.setWordWrap(True)
        set_text_role(self.message_label, "error")
        self.message_label.hide()
        layout.addWidget(self.message_label)

        layout.addWidget(self._curves_group())
        layout.addWidget(self._degrees_group())
        layout.addStretch(0)
        self._refresh_curve_choices()
        self._rebuild_weight_spins(self.settings.degree_weights)
        events = self.settings.events
        callbacks = (
            (events.falloff, self._model_falloff),
            (events.l_max, self._model_l_max),
            (events.degree_weights, self._model_weights),
        )
        callbacks += ((events.changed, self._schedule_preview),)
        for emitter, callback in callbacks:
            emitter.connect(callback)
        self.rho_max_spin.valueChanged.connect(self.preview.set_rho_max)
        self.preview.set_rho_max(self.rho_max_spin.value())
        self.destroyed.connect(lambda *_: [e.disconnect(c) for e, c in callbacks])

    # -- construction ------------------------------------------------------------------------
    def _curves_group(self) -> QGroupBox:
        box = QGroupBox("Curves")
        grid = QGridLayout(box)
        grid.setContentsMargins(6, 4, 6, 6)
        grid.setVerticalSpacing(4)
        grid.addWidget(QLabel("Edit"), 0, 0)
        self.curve_combo = QComboBox()
        self.curve_combo.setToolTip(
            "Curve whose points are editable: R_l (even l) shapes grab brushes, "
            "ℛ_l (odd l) the affine brushes (scale, twist, pinch)"
        )
        self.curve_combo.currentIndexChanged.connect(self._combo_changed)
        grid.addWidget(self.curve_combo, 0, 1, 1, 3)
        grid.addWidget(QLabel("Show"), 1, 0)
        checks = QHBoxLayout()
        self.show_checks: dict[tuple[str, int], QCheckBox] = {}
        for key in QUICK_CURVES:
            check = QCheckBox(curve_label(key))
            check.setStyleSheet(f"QCheckBox {{ color: {curve_color(key).name()}; }}")
            check.setChecked(key in _DEFAULT_SHOWN)
            check.setToolTip("Grab falloff (G)" if key[0] == "R" else "Affine brushes falloff (∇G)")
            check.toggled.connect(self._shown_changed)
            checks.addWidget(check)
            self.show_checks[key] = check
        checks.addStretch(1)
        grid.addLayout(checks, 1, 1, 1, 3)
        grid.addWidget(QLabel("ρ max"), 2, 0)
        self.rho_max_spin = QDoubleSpinBox()
        self.rho_max_spin.setRange(1.0, 50.0)
        self.rho_max_spin.setDecimals(1)
        self.rho_max_spin.setSingleStep(1.0)
        self.rho_max_spin.setValue(self.editor.rho_max)
        self.rho_max_spin.setToolTip("Right end of the plot, in brush radii")
        self.rho_max_spin.valueChanged.connect(self.editor.set_rho_max)
        grid.addWidget(self.rho_max_spin, 2, 1)
        self.reset_gaussian_button = QPushButton("Reset to Gaussian")
        self.reset_gaussian_button.setToolTip("All curves from the Gaussian load (paper Eq. 13)")
        self.reset_gaussian_button.clicked.connect(self.reset_to_gaussian)
        self.reset_kelvinlet_button = QPushButton("Kelvinlet")
        self.reset_kelvinlet_button.setToolTip(
            "All curves from the regularized Kelvinlet load (de Goes & James 2017)"
        )
        self.reset_kelvinlet_button.clicked.connect(self.reset_to_kelvinlet)
        grid.addWidget(self.reset_gaussian_button, 2, 2)
        grid.addWidget(self.reset_kelvinlet_button, 2, 3)
        grid.setColumnStretch(1, 1)
        return box

    def _degrees_group(self) -> QGroupBox:
        box = QGroupBox("Spherical-harmonic degrees")
        layout = QVBoxLayout(box)
        layout.setContentsMargins(6, 4, 6, 6)
        row = QHBoxLayout()
        row.addWidget(QLabel("Truncation l_max"))
        self.l_max_spin = QSpinBox()
        self.l_max_spin.setRange(*L_MAX_RANGE)
        self.l_max_spin.setValue(self.settings.l_max)
        self.l_max_spin.setKeyboardTracking(False)
        self.l_max_spin.setToolTip(
            "G uses even degrees l ≤ l_max, ∇G odd l ≤ l_max + 1; higher follows strong "
            "anisotropy more closely but costs more per brush step"
        )
        self.l_max_spin.valueChanged.connect(self.set_l_max)
        row.addWidget(self.l_max_spin)
        row.addStretch(1)
        layout.addLayout(row)
        caption = QLabel("Wrinkle brush weight of each degree l (0 removes it)")
        caption.setWordWrap(True)
        set_text_role(caption, "muted")
        layout.addWidget(caption)
        self._weights_host = QWidget()
        self._weights_grid = QGridLayout(self._weights_host)
        self._weights_grid.setContentsMargins(0, 0, 0, 0)
        self._weights_grid.setHorizontalSpacing(4)
        self._weights_grid.setVerticalSpacing(2)
        layout.addWidget(self._weights_host)
        buttons = QHBoxLayout()
        self.weights_one_button = QPushButton("All 1")
        self.weights_one_button.setToolTip("Every degree at weight 1: the wrinkle brush = grab")
        self.weights_one_button.clicked.connect(
            lambda: self.set_degree_weights(np.ones(self.l_max + 1), emit=True)
        )
        self.weights_boost_button = QPushButton("Boost high degrees")
        self.weights_boost_button.setToolTip(
            "The default wrinkle weights: degrees 3-8 raised to show their ripples in the brush"
        )
        self.weights_boost_button.clicked.connect(
            lambda: self.set_degree_weights(default_wrinkle_weights(self.l_max), emit=True)
        )
        buttons.addWidget(self.weights_one_button)
        buttons.addWidget(self.weights_boost_button)
        buttons.addStretch(1)
        layout.addLayout(buttons)
        return box

    def _rebuild_weight_spins(self, weights: np.ndarray) -> None:
        while self._weights_grid.count():
            widget = self._weights_grid.takeAt(0).widget()
            if widget is not None:
                widget.hide()  # gone now, not only when the event loop runs the deletion
                widget.deleteLater()
        self.weight_spins = []
        for degree, weight in enumerate(weights):
            row, col = divmod(degree, _WEIGHT_COLUMNS)
            label = QLabel(f"l {degree}")
            label.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
            spin = QDoubleSpinBox()
            spin.setRange(-100.0, 100.0)
            spin.setDecimals(2)
            spin.setSingleStep(0.1)
            spin.setKeyboardTracking(False)
            spin.setValue(float(weight))
            spin.setToolTip(f"Weight of degree {degree} in the wrinkle brush")
            spin.valueChanged.connect(self._weight_changed)
            self._weights_grid.addWidget(label, row, 2 * col)
            self._weights_grid.addWidget(spin, row, 2 * col + 1)
            self.weight_spins.append(spin)
        for col in range(_WEIGHT_COLUMNS):
            self._weights_grid.setColumnStretch(2 * col + 1, 1)

    # -- public API --------------------------------------------------------------------------
    @property
    def radial(self) -> SplineRadial:
        """The edited falloff, the settings' spline (ε = 1; call ``with_eps`` for a radius)."""
        return self.settings.falloff

    @property
    def l_max(self) -> int:
        """Truncation degree of the SH expansion."""
        return self.settings.l_max

    @property
    def degree_weights(self) -> np.ndarray:
        """Per-degree weights of the wrinkle brush, shape (l_max + 1,) (a copy)."""
        return self.settings.degree_weights.copy()

    def set_l_max(self, l_max: int, emit: bool = True) -> None:
        """Change the truncation degree: adds Gaussian curves for new degrees (or restores
        earlier edits of them) and gives new degrees the engine's default wrinkle weights."""
        l_max = self._check_l_max(l_max)
        if l_max != self.l_max:
            self._edit({"l_max": l_max}, emit)

    def set_degree_weights(self, weights: Sequence[float] | None, emit: bool = False) -> None:
        """Set the wrinkle weights (l_max + 1 finite numbers; None: the engine's default,
        :func:`gogreen_core.brushes.default_wrinkle_weights`); ParameterError otherwise."""
        values = default_wrinkle_weights(self.l_max) if weights is None else weights
        self._edit({"degree_weights": values}, emit)

    def set_falloff(
        self,
        falloff: RadialProfile,
        l_max: int | None = None,
        degree_weights: Sequence[float] | None = None,
        emit: bool = False,
    ) -> None:
        """Load a falloff shape (any profile: a spline's curves are copied, a Gaussian,
        Kelvinlet or multi-scale profile is sampled into curves), optionally with ``l_max``
        and wrinkle weights (None: the default ones). Its ε is ignored. Does not emit
        ``falloff_changed`` unless ``emit``."""
        if not isinstance(falloff, RadialProfile):
            raise ValueError(f"falloff must be a RadialProfile (got {type(falloff).__name__})")
        new_l_max = self.l_max if l_max is None else self._check_l_max(l_max)
        weights = default_wrinkle_weights(new_l_max) if degree_weights is None else degree_weights
        self._edit({"l_max": new_l_max, "falloff": falloff, "degree_weights": weights}, emit)

    def reset_to_gaussian(self) -> None:
        """Replace every curve by the Gaussian load's (the default falloff)."""
        self._reset_to(GaussianRadial(1.0))

    def reset_to_kelvinlet(self) -> None:
        """Replace every curve by the regularized Kelvinlet load's."""
        self._reset_to(KelvinletRadial(1.0))

    # -- internals ---------------------------------------------------------------------------
    @staticmethod
    def _check_l_max(l_max: int) -> int:
        if isinstance(l_max, bool) or int(l_max) != l_max:
            raise ValueError(f"l_max must be an integer (got {l_max!r})")
        l_max = int(l_max)
        if not L_MAX_RANGE[0] <= l_max <= L_MAX_RANGE[1]:
            raise ValueError(
                f"l_max must lie in [{L_MAX_RANGE[0]}, {L_MAX_RANGE[1]}] (got {l_max})"
            )
        return l_max

    def _edit(self, values: dict, emit: bool) -> None:
        """Give the settings ``values`` (the panel follows through the model's events)."""
        self.settings.update(values)
        if emit:
            self._emit_changed()

    def _reset_to(self, profile: RadialProfile) -> None:
        samples = SplineRadial.from_profile(profile, self.l_max)
        radial = self.radial.with_curves(samples)
        # Stored curves above l_max are reset too, so raising l_max later stays consistent.
        stale = [k for k in radial.curve_keys() if k not in samples.curve_keys()]
        if stale:
            more = SplineRadial.from_profile(profile, max(degree for _, degree in stale))
            radial = radial.with_curves({key: more.curve(*key) for key in stale})
        self.settings.falloff = radial
        self._emit_changed()

    # -- model -> view -----------------------------------------------------------------------
    def _model_falloff(self, _event: ChangeEvent) -> None:
        if self._editing:  # the editor's own edit: it is already drawn
            return
        self.editor.set_radial(self.radial)
        self._refresh_curve_choices()
        self._hide_message()

    def _schedule_preview(self, changes) -> None:
        if changes.names & {"material", "falloff", "l_max"}:
            self.preview.schedule()

    def _model_l_max(self, _event: ChangeEvent) -> None:
        self._sync_l_max_spin()
        self._rebuild_weight_spins(self.settings.degree_weights)
        self._refresh_curve_choices()

    def _model_weights(self, event: ChangeEvent) -> None:
        if len(event.value) != len(self.weight_spins):
            self._rebuild_weight_spins(event.value)
            return
        for spin, value in zip(self.weight_spins, event.value, strict=True):
            spin.blockSignals(True)
            spin.setValue(float(value))
            spin.blockSignals(False)

    def _sync_l_max_spin(self) -> None:
        self.l_max_spin.blockSignals(True)
        self.l_max_spin.setValue(self.l_max)
        self.l_max_spin.blockSignals(False)

    def _refresh_curve_choices(self) -> None:
        keys = _needed_keys(self.l_max)
        active = self.editor.active_key if self.editor.active_key in keys else ("R", 0)
        self.curve_combo.blockSignals(True)
        self.curve_combo.clear()
        for key in keys:
            role = "grab falloff, G" if key[0] == "R" else "affine brushes, ∇G"
            self.curve_combo.addItem(f"{curve_label(key)}   ({role}, l = {key[1]})", _key_id(key))
        self.curve_combo.setCurrentIndex(keys.index(active))
        self.curve_combo.blockSignals(False)
        for key, check in self.show_checks.items():
            check.setEnabled(key in keys)
        self.editor.set_active_key(active)
        self._shown_changed()

    def _combo_changed(self, index: int) -> None:
        if index >= 0:
            self.editor.set_active_key(_key_from_id(self.curve_combo.itemData(index)))

    def _active_changed_in_editor(self, key: tuple[str, int]) -> None:
        index = self.curve_combo.findData(_key_id(key))
        if index >= 0 and index != self.curve_combo.currentIndex():
            self.curve_combo.blockSignals(True)
            self.curve_combo.setCurrentIndex(index)
            self.curve_combo.blockSignals(False)

    def _shown_changed(self, *_args: object) -> None:
        keys = _needed_keys(self.l_max)
        shown = [k for k, c in self.show_checks.items() if c.isChecked() and k in keys]
        self.editor.set_visible_keys(shown)

    def _curve_edited(self) -> None:
        self._hide_message()
        dragging = self.editor.is_dragging
        self._editing = True
        try:
            continued = dragging and self._drag_continued
            self.settings.set("falloff", self.editor.radial, continued=continued)
        except ValueError as exc:  # e.g. every curve at zero: the settings keep theirs
            self.editor.set_radial(self.radial)
            self._show_message(str(exc))
            return
        finally:
            self._editing = False
        self._drag_continued = dragging
        self.falloff_changed.emit()
        if not dragging:  # add / remove: a discrete edit
            self.editing_finished.emit()

    def _drag_finished(self) -> None:
        self._drag_continued = False
        self.editing_finished.emit()

    def _weight_changed(self, *_args: object) -> None:
        weights = np.array([spin.value() for spin in self.weight_spins], dtype=np.float64)
        self._edit({"degree_weights": weights}, emit=True)

    def _emit_changed(self) -> None:
        self.falloff_changed.emit()
        self.editing_finished.emit()

    def _show_message(self, text: str) -> None:
        self.message_label.setText(text)
        self.message_label.show()

    def _hide_message(self) -> None:
        self.message_label.clear()
        self.message_label.hide()
