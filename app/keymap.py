"""The keymap as data, and an overlay that shows it (Help menu and ``?``).

:data:`KEYMAP` is the one table of what every key, mouse gesture and pen input does, in
Blender's sculpt-mode habits: F drags the radius and Shift+F the strength on screen, Ctrl inverts
the brush, number keys pick brushes, ``[`` / ``]`` change the radius, Ctrl+Z undoes and
Ctrl+Shift+Z (or Ctrl+Y) redoes, ``?`` shows this keymap; left drag sculpts, right drag orbits,
middle drag pans, the wheel zooms. The main window takes its shortcuts from it
(:func:`shortcuts`), so the overlay and the behaviour cannot drift apart. It is the only source
of key behaviour: the viewport passes no key to VTK or pyvista (their default keys never act).

Each :class:`Binding` is ``(keys, action, description, group)``: ``keys`` holds alternatives,
each either a key sequence in Qt's portable text (``"Shift+F"``, ``"Ctrl+Shift+Z"``, ``"["``) or
a gesture: optional modifiers and one of :data:`GESTURES` (``"Ctrl+Wheel"``, ``"Left drag"``).

:class:`KeymapOverlay` is a translucent widget laid over a parent (the viewport or the central
widget) listing the table by group; Escape, ``?``, F1 or a click closes it.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import NamedTuple

from PySide6.QtCore import QEvent, QObject, QRectF, QSize, Qt, Signal
from PySide6.QtGui import (
    QColor,
    QFont,
    QFontMetricsF,
    QKeyEvent,
    QKeySequence,
    QMouseEvent,
    QPainter,
    QPaintEvent,
    QPen,
    QWheelEvent,
)
from PySide6.QtWidgets import QWidget

from gogreen_core.brushes import BRUSH_KINDS
from gogreen_core.tools import NUMBER_KEYS
from gogreen_core.validation import ParameterError

__all__ = [
    "BRUSH_ACTIONS",
    "GESTURES",
    "GROUPS",
    "KEYMAP",
    "Binding",
    "KeymapOverlay",
    "binding",
    "bindings_by_group",
    "brush_action",
    "display_keys",
    "keymap_markdown",
    "shortcuts",
]

#: Mouse and pen inputs a binding can name (after optional ``Ctrl+``/``Shift+``/``Alt+``).
GESTURES = (
    "Left drag",
    "Right drag",
    "Middle drag",
    "Right click",
    "Wheel",
    "Pen pressure",
)

#: Groups in the order the overlay shows them.
GROUPS = (
    "Sculpt",
    "Brushes",
    "Radius and strength",
    "Pins",
    "Mask and mesh",
    "View",
    "Edit",
    "File",
    "Help",
)


class Binding(NamedTuple):
    """One entry of the keymap.

    keys : alternatives, each a Qt portable key sequence (``"Ctrl+Shift+Z"``) or a gesture
        (``"Ctrl+Wheel"``); all of one kind within a binding.
    action : identifier the window's action or handler uses (``"undo"``, ``"brush_grab"``).
    description : what it does, one short sentence for the overlay and tool tips.
    group : one of :data:`GROUPS`.
    """

    keys: tuple[str, ...]
    action: str
    description: str
    group: str

    @property
    def is_gesture(self) -> bool:
        """True for mouse and pen inputs, False for keyboard shortcuts."""
        return _is_gesture(self.keys[0])


def _is_gesture(keys: str) -> bool:
    return keys.rsplit("+", 1)[-1] in GESTURES or keys in GESTURES


#: Display names of the brushes, in the number-key order of ``BRUSH_KINDS``.
_BRUSH_NAMES = {
    "grab": "Grab brush",
    "grab_biscale": "Bi-scale grab brush (sharper falloff)",
    "grab_triscale": "Tri-scale grab brush (sharpest falloff)",
    "wrinkle": "Wrinkle brush (needs an anisotropic material)",
    "scale": "Scale brush: inflate / deflate",
    "twist": "Twist brush",
    "pinch": "Pinch brush",
    "smooth": "Smooth brush",
    "mask": "Mask brush (Ctrl erases)",
}
#: The letter each brush had before number keys (kept as a second key).
_BRUSH_LETTERS = {
    "grab": "G",
    "grab_biscale": "B",
    "grab_triscale": "T",
    "wrinkle": "R",
    "scale": "S",
    "twist": "W",
    "pinch": "P",
    "smooth": "Shift+S",
    "mask": "M",
}
#: Action identifier of each brush kind (``"brush_grab"`` …).
BRUSH_ACTIONS = {kind: f"brush_{kind}" for kind in BRUSH_KINDS}


def _brush_bindings() -> tuple[Binding, ...]:
    """A number key (in table order, "0" the tenth) and a letter per brush."""
    numbers = [(key,) for key in NUMBER_KEYS] + [()] * max(len(BRUSH_KINDS) - len(NUMBER_KEYS), 0)
    return tuple(
        Binding((*number, _BRUSH_LETTERS[kind]), BRUSH_ACTIONS[kind], _BRUSH_NAMES[kind], "Brushes")
        for number, kind in zip(numbers, BRUSH_KINDS, strict=False)
    )


#: The keymap: every key, mouse gesture and pen input of the application.
KEYMAP: tuple[Binding, ...] = (
    Binding(("Left drag",), "sculpt", "Sculpt with the brush (on the background: orbit)", "Sculpt"),
    Binding(
        ("Ctrl+Left drag",),
        "invert",
        "Sculpt inverted: push instead of pull, deflate, twist the other way",
        "Sculpt",
    ),
    Binding(
        ("Shift+Left drag",),
        "smooth_stroke",
        "Smooth with any brush",
        "Sculpt",
    ),
    Binding(
        ("Pen pressure",),
        "pressure",
        "Pen pressure scales the strength and/or the radius (toggles in the brush bar)",
        "Sculpt",
    ),
    *_brush_bindings(),
    Binding(
        ("F",),
        "radius_drag",
        "Drag the radius on screen; click or Enter sets it, Esc or right click cancels",
        "Radius and strength",
    ),
    Binding(
        ("Shift+F",),
        "strength_drag",
        "Drag the strength on screen; click or Enter sets it, Esc or right click cancels",
        "Radius and strength",
    ),
    Binding(("[",), "radius_smaller", "Radius smaller", "Radius and strength"),
    Binding(("]",), "radius_larger", "Radius larger", "Radius and strength"),
    Binding(("{",), "strength_lower", "Strength lower", "Radius and strength"),
    Binding(("}",), "strength_higher", "Strength higher", "Radius and strength"),
    Binding(("Ctrl+Wheel",), "radius_wheel", "Radius smaller / larger", "Radius and strength"),
    Binding(("Shift+Wheel",), "strength_wheel", "Strength lower / higher", "Radius and strength"),
    Binding(
        ("C",),
        "pin_mode",
        "Pin mode: a click pins a point, dragging a pin moves it while the others hold",
        "Pins",
    ),
    Binding(("Right click",), "remove_pin", "In pin mode: remove the pin under the cursor", "Pins"),
    Binding(("Ctrl+I",), "mask_invert", "Invert the mask", "Mask and mesh"),
    Binding(("Alt+M",), "mask_clear", "Clear the mask", "Mask and mesh"),
    Binding(
        ("Ctrl+D",),
        "subdivide",
        "Subdivide the mesh",
        "Mask and mesh",
    ),
    Binding(
        ("Ctrl+Shift+D",),
        "subdivide_unmasked",
        "Subdivide the unmasked part",
        "Mask and mesh",
    ),
    Binding(("Right drag",), "orbit", "Orbit the camera", "View"),
    Binding(("Middle drag",), "pan", "Pan the camera", "View"),
    Binding(("Wheel",), "zoom", "Zoom", "View"),
    Binding(("Home",), "reset_camera", "Frame the whole model", "View"),
    Binding(("Shift+Z",), "wireframe", "Wireframe on / off", "View"),
    Binding(("Ctrl+Z",), "undo", "Undo", "Edit"),
    Binding(("Ctrl+Shift+Z", "Ctrl+Y"), "redo", "Redo", "Edit"),
    Binding(("Ctrl+N",), "new", "New: the default model", "File"),
    Binding(("Ctrl+O",), "open", "Open a model or a session", "File"),
    Binding(("Ctrl+S",), "save", "Save", "File"),
    Binding(("Ctrl+Shift+S",), "save_as", "Save as", "File"),
    Binding(("F12",), "screenshot", "Screenshot of the viewport", "File"),
    Binding(("Ctrl+Q",), "quit", "Quit", "File"),
    Binding(("?", "F1"), "keymap", "Show this keymap (Esc or a click closes it)", "Help"),
)


def binding(action: str) -> Binding:
    """The keymap entry of ``action``.

    Raises
    ------
    ParameterError
        (parameter ``"action"``) naming an action the keymap does not have.
    """
    for entry in KEYMAP:
        if entry.action == action:
            return entry
    raise ParameterError("action", f"action: no key binding for {action!r} in the keymap")


def shortcuts(action: str) -> list[QKeySequence]:
    """The key sequences of a keyboard ``action``, for ``QAction.setShortcuts``.

    Raises
    ------
    ParameterError
        (parameter ``"action"``) for an unknown action or a mouse / pen gesture.
    """
    entry = binding(action)
    if entry.is_gesture:
        raise ParameterError(
            "action",
            f"action: {action!r} is a mouse or pen gesture ({', '.join(entry.keys)}), "
            "not a keyboard shortcut",
        )
    return [
        QKeySequence.fromString(k, QKeySequence.SequenceFormat.PortableText) for k in entry.keys
    ]


def brush_action(kind: str) -> str:
    """Action identifier of brush ``kind`` (its number key is its place in ``BRUSH_KINDS``)."""
    try:
        return BRUSH_ACTIONS[kind]
    except KeyError:
        raise ParameterError(
            "kind", f"kind: unknown brush {kind!r}; the brushes are {', '.join(BRUSH_KINDS)}"
        ) from None


def bindings_by_group(keymap: Iterable[Binding] = KEYMAP) -> dict[str, tuple[Binding, ...]]:
    """The bindings of each group, groups in :data:`GROUPS` order (empty groups left out)."""
    entries = tuple(keymap)
    result = {g: tuple(b for b in entries if b.group == g) for g in GROUPS}
    return {group: found for group, found in result.items() if found}


def display_keys(keys: str) -> str:
    """How one key alternative is written for the user (native modifier names, e.g. ⌘ on
    macOS); gestures are shown as written."""
    if _is_gesture(keys):
        return keys
    sequence = QKeySequence.fromString(keys, QKeySequence.SequenceFormat.PortableText)
    return sequence.toString(QKeySequence.SequenceFormat.NativeText) or keys


def keymap_markdown(keymap: Iterable[Binding] = KEYMAP) -> str:
    """The keymap as Markdown, one table per group (for the README's Controls section, so
    the documentation is written from the same table as the shortcuts)."""
    parts = []
    for group, entries in bindings_by_group(keymap).items():
        parts.append(f"**{group}**\n\n| Input | Does |\n|---|---|")
        for entry in entries:
            keys = " / ".join(f"`{k}`" for k in entry.keys)
            description = entry.description.replace("|", r"\|")
            parts[-1] += f"\n| {keys} | {description} |"
    return "\n\n".join(parts) + "\n"


# ---------------------------------------------------------------------------------------------
# Overlay
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
    MIN_POINT_SIZE = 5.0  # a small window (640 × 420) still shows every binding
    MIN_DESCRIPTION_CHARS = 16
    PREFERRED_POINT_SIZE = 10.0
    KEY_LINE_GAP = 0.2  # between lines of one row's key caps, in line heights

    def __init__(self, parent: QWidget, keymap: Iterable[Binding] = KEYMAP):
        if not isinstance(parent, QWidget):
            raise ParameterError("parent", "parent: the overlay needs a widget to lie over")
        super().__init__(parent)
        self.setObjectName("keymap_overlay")
        self._groups = bindings_by_group(keymap)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
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
        self.setGeometry(self.parentWidget().rect())
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
        if watched is self.parentWidget() and event.type() == QEvent.Type.Resize:
            if self.isVisible():
                self.setGeometry(self.parentWidget().rect())
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
        """The largest font, then the fewest columns, at which the whole keymap fits; at the
        smallest font, the layout with the most columns that still leaves readable lines."""
        point_size = max(self.font().pointSizeF(), self.PREFERRED_POINT_SIZE)
        while True:
            candidates = [
                layout
                for n_columns in range(1, len(self._groups) + 1)
                if (layout := self._try_layout(point_size, width, n_columns)) is not None
            ]
            for layout in candidates:
                if layout.bottom <= height - self.MARGIN:
                    return layout
            if point_size <= self.MIN_POINT_SIZE:
                if candidates:
                    return min(candidates, key=lambda layout: layout.bottom)
                # not even one readable column: one column as wide as the widget
                return self._try_layout(point_size, width, 1, force=True)
            point_size = max(self.MIN_POINT_SIZE, point_size * 0.9)

    def _try_layout(
        self, point_size: float, width: float, n_columns: int, force: bool = False
    ) -> _Layout | None:
        """Groups packed into ``n_columns`` columns at ``point_size``; None when the lines
        would be too narrow to read (under :attr:`MIN_DESCRIPTION_CHARS` characters)."""
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
        row_gap = metrics.height() * 0.45
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

        heading_height = QFontMetricsF(heading).height() * 1.9
        heights = [heading_height + sum(r.height for r in rows) for _g, rows in blocks]
        target = sum(heights) / n_columns
        columns: list[list] = [[]]
        column_heights = [0.0]
        for block, block_height in zip(blocks, heights, strict=True):
            # a new column when this block would overshoot the even share by more than half
            overshoot = column_heights[-1] + block_height / 2 > target
            if columns[-1] and overshoot and len(columns) < n_columns:
                columns.append([])
                column_heights.append(0.0)
            columns[-1].append(block)
            column_heights[-1] += block_height
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
        )

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
        heading_height = QFontMetricsF(heading).height() * 1.9
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
                    x, y + heading_height - 4, x + layout.column_width, y + heading_height - 4
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


if __name__ == "__main__":  # python -m app.keymap > controls.md: the README's Controls tables
    print(keymap_markdown(), end="")
