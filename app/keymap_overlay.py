"""The keymap drawn over the viewport (Help menu, ``?``, F1): :class:`KeymapOverlay`.

A translucent widget laid over a parent (the viewport or the central widget) listing
:data:`app.keymap.KEYMAP` by group; Escape, ``?``, F1 or a click closes it.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from PySide6.QtCore import QEvent, QObject, QPointF, QRectF, QSize, Qt, Signal
from PySide6.QtGui import (
    QColor,
    QFont,
    QFontMetricsF,
    QKeyEvent,
    QMouseEvent,
    QPainter,
    QPaintEvent,
    QPen,
    QWheelEvent,
)
from PySide6.QtWidgets import QWidget

from app.keymap import KEYMAP, Binding, bindings_by_group, display_keys
from gogreen_core.validation import ParameterError

__all__ = ["KeymapOverlay"]

# ---------------------------------------------------------------------------------------------
_BACKDROP = QColor(14, 16, 20, 215)
_TEXT = QColor("#eef0f3")
_MUTED = QColor("#a7adb6")
_ACCENT = QColor("#7fd196")
_KEYCAP_BORDER = QColor("#8a9099")
_KEYCAP_FILL = QColor(255, 255, 255, 22)


@dataclass(frozen=True)
class _Row:
    keys: tuple[tuple[str, ...], ...]  # display text of each alternative, by line
    gesture: bool
    description: str
    height: float


@dataclass(frozen=True)
class _Layout:
    point_size: float
    key_width: float
    description_width: float
    columns: tuple[tuple[tuple[str, tuple[_Row, ...]], ...], ...]
    top: float
    left: float
    column_width: float
    bottom: float
    heading_height: float


class KeymapOverlay(QWidget):
    """Translucent keymap drawn over ``parent``, grouped in columns.

    Hidden when made; :meth:`show_overlay` lays it over the whole parent (following the
    parent's resizes) and takes the keyboard focus; Escape, ``?``, F1 or any click calls
    :meth:`hide_overlay`, which emits :attr:`closed`. It swallows the mouse and wheel events
    it receives so that closing it does not also sculpt or zoom the view under it.
    """

    closed = Signal()

    TITLE = "Keyboard, mouse and pen"
    HINT = "Esc or a click closes this"
    MARGIN = 28.0
    COLUMN_GAP = 36.0
    KEY_GAP = 14.0
    MAX_DESCRIPTION_WIDTH = 330.0
    MIN_POINT_SIZE = 4.5
    MIN_DESCRIPTION_CHARS = 16
    PREFERRED_POINT_SIZE = 10.0
    KEY_LINE_GAP = 0.2  # between lines of one row's key caps, in line heights
    ROW_GAPS = (0.45, 0.12)  # between rows, in line heights: the usual, then tight

    def __init__(self, parent: QWidget, keymap: Iterable[Binding] = KEYMAP):
        if not isinstance(parent, QWidget):
            raise ParameterError("parent", "parent: the overlay needs a widget to lie over")
        super().__init__(parent)
        self._parent = parent
        self.setObjectName("keymap_overlay")
        self._groups = bindings_by_group(keymap)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
        self.setProperty("takes_keys", True)  # keeps the keyboard focus (app.keyboard)
        self.setAttribute(Qt.WidgetAttribute.WA_NoSystemBackground)
        self.setAutoFillBackground(False)
        self.hide()
        parent.installEventFilter(self)

    # -- public ------------------------------------------------------------------------------
    @property
    def groups(self) -> dict[str, tuple[Binding, ...]]:
        """The bindings shown, by group."""
        return dict(self._groups)

    def show_overlay(self) -> None:
        """Lay the overlay over the whole parent, on top, with the keyboard focus."""
        self.setGeometry(self._parent.rect())
        self.raise_()
        self.show()
        self.setFocus(Qt.FocusReason.OtherFocusReason)

    def hide_overlay(self) -> None:
        """Hide the overlay and emit :attr:`closed` (nothing when already hidden)."""
        if self.isHidden():
            return
        self.hide()
        self.closed.emit()

    def toggle_overlay(self) -> None:
        """Show the overlay when hidden, hide it when shown (the ``?`` key and Help menu)."""
        if self.isHidden():
            self.show_overlay()
        else:
            self.hide_overlay()

    def text_lines(self) -> list[str]:
        """The text shown, one line per group title and per binding (``keys — description``);
        for tests and accessibility."""
        lines = []
        for group, entries in self._groups.items():
            lines.append(group)
            for entry in entries:
                keys = " / ".join(display_keys(k) for k in entry.keys)
                lines.append(f"{keys} — {entry.description}")
        return lines

    def sizeHint(self) -> QSize:
        parent = self.parentWidget()
        return parent.size() if parent is not None else QSize(900, 600)

    # -- events ------------------------------------------------------------------------------
    def eventFilter(self, watched: QObject, event: QEvent) -> bool:
        if watched is self._parent and event.type() == QEvent.Type.Resize:
            if self.isVisible():
                self.setGeometry(self._parent.rect())
        return False

    def keyPressEvent(self, event: QKeyEvent) -> None:
        if event.key() in (Qt.Key.Key_Escape, Qt.Key.Key_Question, Qt.Key.Key_F1):
            self.hide_overlay()
            event.accept()
            return
        super().keyPressEvent(event)

    def mousePressEvent(self, event: QMouseEvent) -> None:
        event.accept()
        self.hide_overlay()

    def mouseReleaseEvent(self, event: QMouseEvent) -> None:
        event.accept()

    def mouseMoveEvent(self, event: QMouseEvent) -> None:
        event.accept()

    def wheelEvent(self, event: QWheelEvent) -> None:
        event.accept()

    # -- layout and painting -----------------------------------------------------------------
    def _fonts(self, point_size: float) -> tuple[QFont, QFont, QFont]:
        body = QFont(self.font())
        body.setPointSizeF(point_size)
        heading = QFont(body)
        heading.setBold(True)
        title = QFont(heading)
        title.setPointSizeF(point_size * 1.45)
        return body, heading, title

    def _key_text_width(
        self, metrics: QFontMetricsF, keys: tuple[str, ...], gesture: bool
    ) -> float:
        pad = metrics.height() * 0.5
        cap = metrics.height() * 1.15
        widths = [
            metrics.horizontalAdvance(k)
            if gesture
            else max(metrics.horizontalAdvance(k) + pad, cap)
            for k in keys
        ]
        return sum(widths) + metrics.horizontalAdvance(" / ") * (len(keys) - 1)

    def _key_lines(
        self, metrics: QFontMetricsF, keys: tuple[str, ...], gesture: bool, width: float
    ) -> tuple[tuple[str, ...], ...]:
        """The alternatives packed into lines of at most ``width`` (``"1 / G"`` on one line,
        ``Ctrl+Shift+Z`` over ``Ctrl+Y``): one long pair does not widen the whole key column."""
        lines: list[tuple[str, ...]] = []
        for key in keys:
            if lines and self._key_text_width(metrics, (*lines[-1], key), gesture) <= width:
                lines[-1] = (*lines[-1], key)
            else:
                lines.append((key,))
        return tuple(lines)

    def _layout(self, width: float, height: float) -> _Layout:
        """The largest font, then the fewest columns, at which the whole keymap fits, with
        the usual spacing, else with tight spacing; at the smallest font and tight spacing, the
        layout with the most columns that still leaves readable lines."""
        for gap in self.ROW_GAPS:
            point_size = max(self.font().pointSizeF(), self.PREFERRED_POINT_SIZE)
            while True:
                candidates = self._candidates(point_size, width, gap)
                for layout in candidates:
                    if layout.bottom <= height - self.MARGIN:
                        return layout
                if point_size <= self.MIN_POINT_SIZE:
                    break
                point_size = max(self.MIN_POINT_SIZE, point_size * 0.9)
        if candidates:
            return min(candidates, key=lambda layout: layout.bottom)
        # not even one readable column: one column as wide as the widget
        forced = self._try_layout(self.MIN_POINT_SIZE, width, 1, self.ROW_GAPS[-1], force=True)
        assert forced is not None
        return forced

    def _candidates(self, point_size: float, width: float, gap: float) -> list[_Layout]:
        """The readable layouts at ``point_size`` and row ``gap``, fewest columns first."""
        return [
            layout
            for n_columns in range(1, len(self._groups) + 1)
            if (layout := self._try_layout(point_size, width, n_columns, gap)) is not None
        ]

    def _try_layout(
        self, point_size: float, width: float, n_columns: int, gap: float, force: bool = False
    ) -> _Layout | None:
        """Groups packed into ``n_columns`` columns at ``point_size``, rows ``gap`` line
        heights apart; None when the lines would be too narrow to read (under
        :attr:`MIN_DESCRIPTION_CHARS` characters)."""
        body, heading, title = self._fonts(point_size)
        metrics = QFontMetricsF(body)
        key_width = 0.0
        widest_description = 0.0
        for entries in self._groups.values():
            for entry in entries:
                for key in entry.keys:  # the widest single alternative
                    alone = self._key_text_width(metrics, (display_keys(key),), entry.is_gesture)
                    key_width = max(key_width, alone)
                widest_description = max(
                    widest_description, metrics.horizontalAdvance(entry.description)
                )
        available = width - 2 * self.MARGIN
        column_width = (available - (n_columns - 1) * self.COLUMN_GAP) / n_columns
        description_width = column_width - key_width - self.KEY_GAP
        shortest = metrics.averageCharWidth() * self.MIN_DESCRIPTION_CHARS
        if description_width < shortest:
            if not force:
                return None
            description_width = shortest
        description_width = min(
            description_width,
            widest_description + 1.0,
            self.MAX_DESCRIPTION_WIDTH * point_size / 10.0,
        )
        column_width = key_width + self.KEY_GAP + description_width

        blocks = []
        row_gap = metrics.height() * gap
        key_line_height = metrics.height() * (1.15 + self.KEY_LINE_GAP)
        for group, entries in self._groups.items():
            rows = []
            for entry in entries:
                bounds = metrics.boundingRect(
                    QRectF(0, 0, description_width, 1e6),
                    int(Qt.TextFlag.TextWordWrap),
                    entry.description,
                )
                keys = tuple(display_keys(k) for k in entry.keys)
                lines = self._key_lines(metrics, keys, entry.is_gesture, key_width)
                text_height = max(bounds.height(), metrics.height() * 1.25)
                keys_height = len(lines) * key_line_height
                rows.append(
                    _Row(
                        keys=lines,
                        gesture=entry.is_gesture,
                        description=entry.description,
                        height=max(text_height, keys_height) + row_gap,
                    )
                )
            blocks.append((group, tuple(rows)))

        heading_height = QFontMetricsF(heading).height() * (1.45 + gap)
        columns, column_heights = self._pack(blocks, heading_height, n_columns)
        total_width = len(columns) * column_width + (len(columns) - 1) * self.COLUMN_GAP
        left = max(self.MARGIN, (width - total_width) / 2)
        top = self.MARGIN + QFontMetricsF(title).height() * 2.2
        return _Layout(
            point_size=point_size,
            key_width=key_width,
            description_width=description_width,
            columns=tuple(tuple(c) for c in columns),
            top=top,
            left=left,
            column_width=column_width,
            bottom=top + max(column_heights),
            heading_height=heading_height,
        )

    @staticmethod
    def _pack(
        blocks: list[tuple[str, tuple[_Row, ...]]], heading_height: float, n_columns: int
    ) -> tuple[list[list[tuple[str, tuple[_Row, ...]]]], list[float]]:
        """The groups' rows filled into at most ``n_columns`` columns of about even height, in
        order; a group that does not fit goes on in the next column under "(continued)"."""
        total = sum(heading_height + sum(r.height for r in rows) for _g, rows in blocks)
        target = total / n_columns
        columns: list[list[tuple[str, tuple[_Row, ...]]]] = [[]]
        heights = [0.0]
        for group, rows in blocks:
            title, part = group, list[_Row]()
            for row in rows:
                used = heights[-1] + (heading_height + sum(r.height for r in part) if part else 0)
                extra = row.height + (0.0 if part else heading_height)
                full = used + extra > target + row.height / 2
                if full and (columns[-1] or part) and len(columns) < n_columns:
                    if part:
                        columns[-1].append((title, tuple(part)))
                        heights[-1] = used
                        title = f"{group} (continued)"
                    columns.append([])
                    heights.append(0.0)
                    part = []
                part.append(row)
            columns[-1].append((title, tuple(part)))
            heights[-1] += heading_height + sum(r.height for r in part)
        return columns, heights

    def paintEvent(self, event: QPaintEvent) -> None:
        painter = QPainter(self)
        try:
            painter.setRenderHint(QPainter.RenderHint.Antialiasing)
            painter.setRenderHint(QPainter.RenderHint.TextAntialiasing)
            painter.fillRect(self.rect(), _BACKDROP)
            self._paint_keymap(painter)
        finally:
            painter.end()

    def _paint_keymap(self, painter: QPainter) -> None:
        layout = self._layout(self.width(), self.height())
        body, heading, title = self._fonts(layout.point_size)
        metrics = QFontMetricsF(body)
        title_metrics = QFontMetricsF(title)
        painter.setFont(title)
        painter.setPen(_TEXT)
        painter.drawText(
            QRectF(0, self.MARGIN, self.width(), title_metrics.height()),
            int(Qt.AlignmentFlag.AlignHCenter | Qt.AlignmentFlag.AlignTop),
            self.TITLE,
        )
        painter.setFont(body)
        painter.setPen(_MUTED)
        painter.drawText(
            QRectF(0, self.MARGIN + title_metrics.height() * 1.1, self.width(), metrics.height()),
            int(Qt.AlignmentFlag.AlignHCenter | Qt.AlignmentFlag.AlignTop),
            self.HINT,
        )
        heading_height = layout.heading_height
        for index, column in enumerate(layout.columns):
            x = layout.left + index * (layout.column_width + self.COLUMN_GAP)
            y = layout.top
            for group, rows in column:
                painter.setFont(heading)
                painter.setPen(_ACCENT)
                painter.drawText(
                    QRectF(x, y, layout.column_width, heading_height),
                    int(Qt.AlignmentFlag.AlignLeft | Qt.AlignmentFlag.AlignVCenter),
                    group,
                )
                painter.setPen(QPen(_ACCENT, 1.0))
                painter.drawLine(
                    QPointF(x, y + heading_height - 4),
                    QPointF(x + layout.column_width, y + heading_height - 4),
                )
                y += heading_height
                painter.setFont(body)
                for row in rows:
                    self._paint_keys(painter, metrics, row, x, y, layout.key_width)
                    painter.setPen(_TEXT)
                    painter.drawText(
                        QRectF(
                            x + layout.key_width + self.KEY_GAP,
                            y + 2,
                            layout.description_width,
                            row.height,
                        ),
                        int(Qt.AlignmentFlag.AlignLeft | Qt.TextFlag.TextWordWrap),
                        row.description,
                    )
                    y += row.height

    def _paint_keys(
        self, painter: QPainter, metrics: QFontMetricsF, row: _Row, x: float, y: float, width: float
    ) -> None:
        """Key caps right-aligned in the key column, a line per group of alternatives
        (gestures as plain accent text)."""
        for line, keys in enumerate(row.keys):
            line_y = y + line * metrics.height() * (1.15 + self.KEY_LINE_GAP)
            total = self._key_text_width(metrics, keys, row.gesture)
            self._paint_key_line(painter, metrics, keys, row.gesture, x + width - total, line_y)

    def _paint_key_line(
        self,
        painter: QPainter,
        metrics: QFontMetricsF,
        keys: tuple[str, ...],
        gesture: bool,
        cursor: float,
        y: float,
    ) -> None:
        pad = metrics.height() * 0.5
        cap_height = metrics.height() * 1.15
        separator = " / "
        for index, key in enumerate(keys):
            if index:
                painter.setPen(_MUTED)
                painter.drawText(
                    QRectF(cursor, y, metrics.horizontalAdvance(separator), cap_height),
                    int(Qt.AlignmentFlag.AlignCenter),
                    separator,
                )
                cursor += metrics.horizontalAdvance(separator)
            text_width = metrics.horizontalAdvance(key)
            if gesture:
                painter.setPen(_ACCENT)
                box = QRectF(cursor, y, text_width, cap_height)
            else:
                box = QRectF(cursor, y, max(text_width + pad, cap_height), cap_height)
                painter.setPen(QPen(_KEYCAP_BORDER, 1.0))
                painter.setBrush(_KEYCAP_FILL)
                painter.drawRoundedRect(box.adjusted(0.5, 0.5, -0.5, -0.5), 3, 3)
                painter.setBrush(Qt.BrushStyle.NoBrush)
                painter.setPen(_TEXT)
            painter.drawText(box, int(Qt.AlignmentFlag.AlignCenter), key)
            cursor += box.width()
