"""QPainter editor of the spline falloff curves of a :class:`gogreen_core.SplineRadial`.

The plot shows F(ρ) against ρ = r/ε on [0, ρ_max]: the smooth curve is sampled with
:meth:`SplineRadial.dimensionless` and the control points of the *active* curve are handles.

Mouse and keys (active curve):

* left drag a handle: move it (it stays between its neighbours; the point at ρ = 0 only moves
  vertically, and not at all for l ≥ 1 where F(0) = 0 is pinned);
* double-click, or Ctrl + left click, on empty space: add a control point there;
* right click a handle, or select it and press Delete / Backspace: remove it;
* left click a handle of another shown curve: make that curve active.

The vertical range fits the shown curves after every edit but stays frozen during a drag.
"""

from __future__ import annotations

import math

import numpy as np
from PySide6.QtCore import QPointF, QRectF, QSize, Qt, Signal
from PySide6.QtGui import (
    QColor,
    QFontMetricsF,
    QKeyEvent,
    QMouseEvent,
    QPainter,
    QPainterPath,
    QPaintEvent,
    QPen,
)
from PySide6.QtWidgets import QSizePolicy, QWidget

from app.panels.plot_axes import draw_plot_axes, plot_font
from app.panels.widgets import plot_colors
from gogreen_core.physics.radial import SplineRadial

__all__ = ["CurveEditor", "curve_color", "curve_label"]

CurveKey = tuple[str, int]

_SUBSCRIPTS = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")
_KEY_COLORS = {
    ("R", 0): QColor("#1565c0"),
    ("R", 2): QColor("#2e7d32"),
    ("dR", 1): QColor("#e65100"),
    ("dR", 3): QColor("#8e24aa"),
}
_OTHER_COLORS = ("#00838f", "#c2185b", "#5d4037", "#546e7a", "#9e9d24", "#3949ab", "#d84315")
_SAMPLES = 240
_MIN_GAP = 0.02  # smallest ρ distance kept between neighbouring control points


def curve_label(key: CurveKey) -> str:
    """Display name: R₀, R₂, … for "R" curves and ℛ₁, ℛ₃, … for "dR" curves."""
    kind, degree = key
    return ("R" if kind == "R" else "ℛ") + str(degree).translate(_SUBSCRIPTS)


def curve_color(key: CurveKey) -> QColor:
    """Line colour of a curve (fixed for the four usual ones; lighter on the dark theme)."""
    if key in _KEY_COLORS:
        color = QColor(_KEY_COLORS[key])
    else:
        kind, degree = key
        color = QColor(_OTHER_COLORS[(degree + (0 if kind == "R" else 3)) % len(_OTHER_COLORS)])
    return color.lighter(165) if plot_colors().dark else color


class CurveEditor(QWidget):
    """Interactive plot of the falloff curves of one :class:`SplineRadial`.

    Parameters
    ----------
    radial : SplineRadial
        The spline shown; each edit replaces it by an edited value (``with_point_moved``,
        ``with_point_added``, ``without_point``), read back from :attr:`radial`.
    parent : QWidget, optional

    Signals
    -------
    edited() : after every change of the spline (each drag step, add, remove): :attr:`radial`
        is the new value.
    drag_finished() : the left button was released after dragging a point.
    selection_changed(int) : the selected control point of the active curve (-1: none).
    active_curve_changed(object) : the (kind, l) key of the new active curve.
    message(str) : a refused edit, explained (e.g. the point at ρ = 0 cannot be removed).
    """

    edited = Signal()
    drag_finished = Signal()
    selection_changed = Signal(int)
    active_curve_changed = Signal(object)
    message = Signal(str)

    HANDLE_RADIUS = 4.5
    PICK_RADIUS = 9.0
    MARGINS = (48.0, 12.0, 12.0, 38.0)  # left, top, right, bottom

    def __init__(self, radial: SplineRadial, parent: QWidget | None = None):
        super().__init__(parent)
        self._radial = radial
        self._active: CurveKey = ("R", 0)
        self._visible: list[CurveKey] = [("R", 0), ("R", 2)]
        self._rho_max = 6.0
        self._range = (0.0, 1.0)
        self._selected = -1
        self._hover = -1
        self._dragging = False
        self.setMinimumSize(240, 200)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Expanding)
        self.setMouseTracking(True)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setProperty("takes_keys", True)  # keeps the keyboard focus (app.keyboard)
        self.setToolTip(
            "Drag a point to move it · double-click or Ctrl+click to add · "
            "right-click or Delete to remove"
        )
        self._clamp_keys()
        self.refit()

    def sizeHint(self) -> QSize:
        return QSize(380, 260)

    # -- state -------------------------------------------------------------------------------
    @property
    def radial(self) -> SplineRadial:
        """The spline being edited."""
        return self._radial

    def set_radial(self, radial: SplineRadial) -> None:
        """Edit another spline (keeps the active curve when it has one)."""
        self._radial = radial
        self._clamp_keys()
        self._select(-1)
        self.refit()

    @property
    def active_key(self) -> CurveKey:
        """(kind, l) of the curve whose points are editable."""
        return self._active

    def set_active_key(self, key: CurveKey) -> None:
        """Make curve ``key`` editable (it is always shown)."""
        key = (str(key[0]), int(key[1]))
        if key not in self._radial.curve_keys():
            raise ValueError(f"the falloff has no curve {curve_label(key)}")
        if key == self._active:
            return
        self._active = key
        self._select(-1)
        self.refit()
        self.active_curve_changed.emit(key)

    @property
    def visible_keys(self) -> list[CurveKey]:
        """Curves drawn, the active one last (on top)."""
        keys = [k for k in self._visible if k != self._active and k in self._radial.curve_keys()]
        return [*keys, self._active]

    def set_visible_keys(self, keys: list[CurveKey]) -> None:
        """Curves drawn besides the active one."""
        self._visible = [(str(k), int(d)) for k, d in keys]
        self.refit()

    @property
    def rho_max(self) -> float:
        """Right end of the plotted ρ range."""
        return self._rho_max

    def set_rho_max(self, rho_max: float) -> None:
        """Plot ρ on [0, rho_max] (rho_max > 0)."""
        if not rho_max > 0:
            raise ValueError(f"rho_max must be > 0 (got {rho_max})")
        self._rho_max = float(rho_max)
        self.refit()

    @property
    def value_range(self) -> tuple[float, float]:
        """Plotted vertical range (low, high)."""
        return self._range

    @property
    def is_dragging(self) -> bool:
        """Whether a control point is being dragged."""
        return self._dragging

    @property
    def selected_index(self) -> int:
        """Selected control point of the active curve, or -1."""
        return self._selected

    def control_points(self) -> tuple[np.ndarray, np.ndarray]:
        """(ρ, value) of the active curve's control points (copies)."""
        return self._radial.curve(*self._active)

    def _clamp_keys(self) -> None:
        keys = self._radial.curve_keys()
        if self._active not in keys:
            self._active = ("R", 0) if ("R", 0) in keys else keys[0]

    # -- geometry ----------------------------------------------------------------------------
    def plot_rect(self) -> QRectF:
        """Widget rectangle of the plotting area."""
        left, top, right, bottom = self.MARGINS
        return QRectF(left, top, self.width() - left - right, self.height() - top - bottom)

    def to_screen(self, rho: float, value: float) -> QPointF:
        """Widget position of the data point (ρ, value)."""
        rect = self.plot_rect()
        low, high = self._range
        return QPointF(
            rect.left() + rect.width() * rho / self._rho_max,
            rect.bottom() - rect.height() * (value - low) / (high - low),
        )

    def to_data(self, point: QPointF) -> tuple[float, float]:
        """Data coordinates (ρ, value) of a widget position."""
        rect = self.plot_rect()
        low, high = self._range
        rho = (point.x() - rect.left()) / rect.width() * self._rho_max
        value = low + (rect.bottom() - point.y()) / rect.height() * (high - low)
        return rho, value

    def point_position(self, index: int) -> QPointF:
        """Widget position of control point ``index`` of the active curve."""
        rho, value = self.control_points()
        return self.to_screen(float(rho[index]), float(value[index]))

    def refit(self) -> None:
        """Fit the vertical range to the shown curves and repaint."""
        rho = np.linspace(0.0, self._rho_max, _SAMPLES)
        values = [np.zeros(1)]
        for key in self.visible_keys:
            values.append(self._radial.dimensionless(*key, rho))
            xs, ys = self._radial.curve(*key)
            values.append(ys[xs <= self._rho_max])
        allv = np.concatenate(values)
        low, high = float(min(allv.min(), 0.0)), float(allv.max())
        span = high - low if high - low > 1e-9 else 1.0
        self._range = (low - 0.08 * span, high + 0.08 * span)
        self.update()

    def _pick(self, pos: QPointF, key: CurveKey | None = None) -> int:
        """Index of the control point of curve ``key`` (default active) near ``pos``, or -1."""
        xs, ys = self._radial.curve(*(key or self._active))
        best, best_dist = -1, self.PICK_RADIUS
        for i, (x, y) in enumerate(zip(xs, ys, strict=True)):
            if x > self._rho_max * 1.0001:
                break
            p = self.to_screen(float(x), float(y))
            dist = math.hypot(p.x() - pos.x(), p.y() - pos.y())
            if dist <= best_dist:
                best, best_dist = i, dist
        return best

    def _select(self, index: int) -> None:
        if index != self._selected:
            self._selected = index
            self.selection_changed.emit(index)
        self.update()

    # -- edits -------------------------------------------------------------------------------
    def move_selected(self, rho: float, value: float) -> None:
        """Move the selected point to (ρ, value), respecting its constraints, and emit
        ``edited``."""
        index = self._selected
        if index < 0:
            return
        kind, degree = self._active
        xs, ys = self._radial.curve(kind, degree)
        if index == 0:
            rho = 0.0
            if degree >= 1:
                value = 0.0
        else:
            low = xs[index - 1] + _MIN_GAP
            high = xs[index + 1] - _MIN_GAP if index + 1 < len(xs) else max(self._rho_max, low)
            rho = float(np.clip(rho, low, high))
        if rho == xs[index] and value == ys[index]:
            return
        self._radial = self._radial.with_point_moved(kind, degree, index, rho, value)
        self.update()
        self.edited.emit()

    def add_point_at(self, rho: float, value: float) -> int:
        """Insert a control point at (ρ, value) on the active curve; returns its index, or -1
        (with a ``message``) when ρ is too close to an existing point or outside (0, ρ_max]."""
        xs, _ = self._radial.curve(*self._active)
        if not 0.0 < rho <= self._rho_max:
            self.message.emit(
                f"cannot add a point at ρ = {rho:.3g}: outside (0, {self._rho_max:g}]"
            )
            return -1
        if np.min(np.abs(xs - rho)) < _MIN_GAP:
            self.message.emit(f"cannot add a point at ρ = {rho:.3g}: too close to another point")
            return -1
        self._radial, index = self._radial.with_point_added(*self._active, rho, value)
        self._select(index)
        self.refit()
        self.edited.emit()
        return index

    def remove_point(self, index: int) -> bool:
        """Remove control point ``index`` of the active curve; False (with a ``message``) when
        the spline refuses (the point at ρ = 0, or fewer than 3 points would remain)."""
        try:
            self._radial = self._radial.without_point(*self._active, index)
        except ValueError as exc:
            self.message.emit(f"cannot remove this point: {exc}")
            return False
        self._selected = -1
        self.selection_changed.emit(-1)
        self.refit()
        self.edited.emit()
        return True

    # -- events ------------------------------------------------------------------------------
    def mousePressEvent(self, event: QMouseEvent) -> None:
        pos = event.position()
        index = self._pick(pos)
        if event.button() == Qt.MouseButton.RightButton:
            if index >= 0:
                self.remove_point(index)
            return
        if event.button() != Qt.MouseButton.LeftButton:
            return
        if index < 0 and not event.modifiers() & Qt.KeyboardModifier.ControlModifier:
            for key in reversed(self.visible_keys[:-1]):  # a handle of another shown curve
                other = self._pick(pos, key)
                if other >= 0:
                    self.set_active_key(key)
                    index = other
                    break
        if index >= 0:
            self._select(index)
            self._dragging = True
            self.setCursor(Qt.CursorShape.ClosedHandCursor)
        elif event.modifiers() & Qt.KeyboardModifier.ControlModifier:
            self.add_point_at(*self.to_data(pos))
        else:
            self._select(-1)

    def mouseMoveEvent(self, event: QMouseEvent) -> None:
        pos = event.position()
        if self._dragging:
            rho, value = self.to_data(pos)
            low, high = self._range
            self.move_selected(rho, float(np.clip(value, low, high)))
            return
        hover = self._pick(pos)
        if hover != self._hover:
            self._hover = hover
            self.setCursor(
                Qt.CursorShape.OpenHandCursor if hover >= 0 else Qt.CursorShape.CrossCursor
            )
            self.update()

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:
        if self._dragging and event.button() == Qt.MouseButton.LeftButton:
            self._dragging = False
            self.setCursor(Qt.CursorShape.OpenHandCursor)
            self.refit()
            self.drag_finished.emit()

    def mouseDoubleClickEvent(self, event: QMouseEvent) -> None:
        if event.button() != Qt.MouseButton.LeftButton:
            return
        pos = event.position()
        if self._pick(pos) < 0 and self.plot_rect().contains(pos):
            self.add_point_at(*self.to_data(pos))

    def keyPressEvent(self, event: QKeyEvent) -> None:
        if event.key() in (Qt.Key.Key_Delete, Qt.Key.Key_Backspace) and self._selected >= 0:
            self.remove_point(self._selected)
            return
        super().keyPressEvent(event)

    def leaveEvent(self, event) -> None:
        self._hover = -1
        self.update()
        super().leaveEvent(event)

    # -- drawing -----------------------------------------------------------------------------
    def paintEvent(self, event: QPaintEvent) -> None:
        painter = QPainter(self)
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        self._colors = plot_colors()
        painter.fillRect(self.rect(), self._colors.background)
        rect = self.plot_rect()
        painter.setFont(plot_font(painter.font()))
        self._draw_grid(painter, rect)
        painter.save()
        painter.setClipRect(rect.adjusted(-6, -6, 6, 6))
        for key in self.visible_keys:
            self._draw_curve(painter, key, active=key == self._active)
        self._draw_handles(painter)
        painter.restore()
        self._draw_legend(painter, rect)
        self._draw_readout(painter, rect)
        if self.hasFocus():
            painter.setPen(QPen(QColor("#90caf9"), 1.0))
            painter.setBrush(Qt.BrushStyle.NoBrush)
            painter.drawRect(QRectF(self.rect()).adjusted(0.5, 0.5, -0.5, -0.5))
        painter.end()

    def _draw_grid(self, painter: QPainter, rect: QRectF) -> None:
        draw_plot_axes(
            painter,
            rect,
            (0.0, self._rho_max),
            self._range,
            ("ρ = r / ε", "F(ρ)  (dimensionless)"),
            self._colors,
        )

    def _draw_curve(self, painter: QPainter, key: CurveKey, active: bool) -> None:
        rho = np.linspace(0.0, self._rho_max, _SAMPLES)
        values = self._radial.dimensionless(*key, rho)
        path = QPainterPath()
        for i, (x, y) in enumerate(zip(rho, values, strict=True)):
            p = self.to_screen(float(x), float(y))
            if i == 0:
                path.moveTo(p)
            else:
                path.lineTo(p)
        color = curve_color(key)
        if not active:
            color.setAlpha(150)
        pen = QPen(color, 2.4 if active else 1.4)
        if not active:
            pen.setStyle(Qt.PenStyle.DashLine)
        painter.setPen(pen)
        painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.drawPath(path)
        if not active:  # small dots show where the other curves' points are
            painter.setPen(Qt.PenStyle.NoPen)
            painter.setBrush(color)
            xs, ys = self._radial.curve(*key)
            for x, y in zip(xs, ys, strict=True):
                if x <= self._rho_max:
                    painter.drawEllipse(self.to_screen(float(x), float(y)), 2.2, 2.2)

    def _draw_handles(self, painter: QPainter) -> None:
        kind, degree = self._active
        color = curve_color(self._active)
        xs, ys = self._radial.curve(kind, degree)
        for i, (x, y) in enumerate(zip(xs, ys, strict=True)):
            if x > self._rho_max * 1.0001:
                break
            p = self.to_screen(float(x), float(y))
            r = self.HANDLE_RADIUS + (1.5 if i in (self._hover, self._selected) else 0.0)
            if i == 0 and degree >= 1:  # pinned at F(0) = 0
                painter.setPen(QPen(QColor("#757575"), 1.2))
                painter.setBrush(QColor("#e0e0e0"))
                painter.drawRect(QRectF(p.x() - r, p.y() - r, 2 * r, 2 * r))
                continue
            painter.setPen(QPen(color.darker(130), 1.5))
            painter.setBrush(color if i == self._selected else self._colors.handle)
            painter.drawEllipse(p, r, r)

    def _draw_legend(self, painter: QPainter, rect: QRectF) -> None:
        metrics = QFontMetricsF(painter.font())
        keys = self.visible_keys
        line = metrics.height() + 2
        width = max(metrics.horizontalAdvance(curve_label(k) + " (edit)") for k in keys) + 30
        box = QRectF(rect.right() - width - 6, rect.top() + 6, width, line * len(keys) + 6)
        painter.setPen(QPen(self._colors.frame, 1.0))
        painter.setBrush(self._colors.legend)
        painter.drawRoundedRect(box, 3, 3)
        for row, key in enumerate(reversed(keys)):
            y = box.top() + 3 + row * line + line / 2
            active = key == self._active
            pen = QPen(curve_color(key), 2.4 if active else 1.4)
            if not active:
                pen.setStyle(Qt.PenStyle.DashLine)
            painter.setPen(pen)
            painter.drawLine(QPointF(box.left() + 5, y), QPointF(box.left() + 21, y))
            painter.setPen(self._colors.text)
            painter.drawText(
                QRectF(box.left() + 25, y - line / 2, width - 26, line),
                Qt.AlignmentFlag.AlignVCenter,
                curve_label(key) + (" (edit)" if active else ""),
            )

    def _draw_readout(self, painter: QPainter, rect: QRectF) -> None:
        index = self._selected if self._selected >= 0 else self._hover
        if index < 0:
            return
        xs, ys = self.control_points()
        if index >= len(xs):
            return
        text = f"{curve_label(self._active)}   ρ = {xs[index]:.3g}   F = {ys[index]:.4g}"
        painter.setPen(self._colors.text)
        painter.drawText(
            QRectF(rect.left() + 6, rect.top() + 4, rect.width() - 12, 18),
            Qt.AlignmentFlag.AlignLeft | Qt.AlignmentFlag.AlignVCenter,
            text,
        )
