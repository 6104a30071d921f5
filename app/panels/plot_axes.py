"""Axes of the small 2D plots (falloff curve editor, felt-falloff preview): frame, grid, tick
marks with labels and axis titles, drawn with QPainter in the theme's plot colours."""

from __future__ import annotations

import math
from collections.abc import Sequence

from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QFont, QFontMetricsF, QPainter, QPen

__all__ = ["draw_plot_axes", "nice_ticks", "plot_font", "tick_text"]

#: Length of a tick mark outside the frame (pixels).
TICK_LENGTH = 4.0


def plot_font(font: QFont) -> QFont:
    """The plots' label font (also the small print of the panels' tables): ``font`` one point
    smaller (at least 7 pt)."""
    small = QFont(font)
    small.setPointSizeF(max(7.0, font.pointSizeF() - 1.0))
    return small


def _nice_step(span: float, target_ticks: int) -> float:
    raw = span / max(target_ticks, 1)
    magnitude = 10.0 ** math.floor(math.log10(raw))
    for factor in (1.0, 2.0, 2.5, 5.0, 10.0):
        if raw <= factor * magnitude:
            return factor * magnitude
    return 10.0 * magnitude


def nice_ticks(low: float, high: float, target_ticks: int) -> list[float]:
    """About ``target_ticks`` round values (steps 1, 2, 2.5 or 5 × 10^k) in [low, high]."""
    step = _nice_step(high - low, target_ticks)
    first = math.ceil(low / step - 1e-9) * step
    count = math.floor((high - first) / step + 1e-9) + 1
    return [first + i * step for i in range(max(count, 0))]


def tick_text(value: float, step: float) -> str:
    """Tick label with as many decimals as the tick step needs."""
    decimals = 0
    while decimals < 6 and abs(round(step * 10**decimals) - step * 10**decimals) > 1e-6:
        decimals += 1
    text = f"{value:.{decimals}f}"
    return "0" if float(text) == 0 else text


def _step(ticks: Sequence[float]) -> float:
    return ticks[1] - ticks[0] if len(ticks) > 1 else 1.0


def draw_plot_axes(
    painter: QPainter,
    rect: QRectF,
    x_range: tuple[float, float],
    y_range: tuple[float, float],
    titles: tuple[str, str],
    colors,
    y_ticks: Sequence[float] | None = None,
    spacing: tuple[float, float] = (60.0, 40.0),
) -> None:
    """Frame ``rect`` (the data area, mapped linearly to ``x_range`` × ``y_range``), its grid
    and labelled ticks (x below, y on the left; the y = 0 line in the axis colour) and the
    titles (x below the labels, y rotated along the left edge). ``colors``: the theme's
    ``plot_colors()``; ``y_ticks`` default to round values about ``spacing[1]`` pixels apart,
    x ticks are about ``spacing[0]`` pixels apart."""
    metrics = QFontMetricsF(painter.font())
    (x0, x1), (y0, y1) = x_range, y_range
    painter.setPen(QPen(colors.frame, 1.0))
    painter.drawRect(rect)
    x_ticks = nice_ticks(x0, x1, max(2, int(rect.width() / spacing[0])))
    for tick in x_ticks:
        x = rect.left() + (tick - x0) / (x1 - x0) * rect.width()
        painter.setPen(QPen(colors.grid, 1.0))
        painter.drawLine(QPointF(x, rect.top()), QPointF(x, rect.bottom()))
        painter.setPen(colors.text)
        painter.drawLine(QPointF(x, rect.bottom()), QPointF(x, rect.bottom() + TICK_LENGTH))
        painter.drawText(
            QRectF(x - 30, rect.bottom() + TICK_LENGTH + 1, 60, metrics.height()),
            Qt.AlignmentFlag.AlignHCenter | Qt.AlignmentFlag.AlignTop,
            tick_text(tick, _step(x_ticks)),
        )
    if y_ticks is None:
        y_ticks = nice_ticks(y0, y1, max(2, int(rect.height() / spacing[1])))
    for tick in y_ticks:
        y = rect.bottom() - (tick - y0) / (y1 - y0) * rect.height()
        zero = abs(tick) < 1e-9 * _step(y_ticks)
        painter.setPen(QPen(colors.axis if zero else colors.grid, 1.0))
        painter.drawLine(QPointF(rect.left(), y), QPointF(rect.right(), y))
        painter.setPen(colors.text)
        painter.drawLine(QPointF(rect.left() - TICK_LENGTH, y), QPointF(rect.left(), y))
        painter.drawText(
            QRectF(0, y - metrics.height() / 2, rect.left() - TICK_LENGTH - 3, metrics.height()),
            Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter,
            tick_text(tick, _step(y_ticks)),
        )
    x_title, y_title = titles
    painter.setPen(colors.text)
    below = rect.bottom() + TICK_LENGTH + 1 + metrics.height()
    painter.drawText(
        QRectF(rect.left(), below, rect.width(), metrics.height()),
        Qt.AlignmentFlag.AlignHCenter,
        x_title,
    )
    painter.save()
    painter.translate(metrics.height() / 2 + 2, rect.center().y())
    painter.rotate(-90)
    height = metrics.height()
    painter.drawText(
        QRectF(-rect.height() / 2 - 20, -height / 2, rect.height() + 40, height),
        Qt.AlignmentFlag.AlignCenter,
        y_title,
    )
    painter.restore()
