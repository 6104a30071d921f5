"""Keyboard focus rules of the main window.

* The window's shortcuts act wherever the focus is. A number field (spin box) would otherwise
  swallow them: Qt lets a focused line edit claim every printable key and Ctrl+Z. In a number
  field, keys that cannot be part of a number (letters other than the exponent ``e``,
  brackets) and the window's undo/redo keys go to the window's shortcuts instead.
* Enter or Escape in a field commits (Enter) or leaves (Escape) the field and hands the focus
  back to the viewport, so the sculpting keys work again at once.
"""

from __future__ import annotations

from PySide6.QtCore import QEvent, QObject, Qt, QTimer
from PySide6.QtGui import QKeyEvent, QKeySequence
from PySide6.QtWidgets import QAbstractSpinBox, QApplication, QComboBox, QLineEdit, QWidget

__all__ = ["FocusKeys"]

#: Characters a number field accepts (digits, sign, decimal separators, exponent, space).
_NUMBER_CHARS = set("0123456789+-.,eE ")
_RETURN_KEYS = (Qt.Key.Key_Return, Qt.Key.Key_Enter, Qt.Key.Key_Escape)
_EDITING_KEYS = {
    Qt.Key.Key_Home,
    Qt.Key.Key_End,
    Qt.Key.Key_Left,
    Qt.Key.Key_Right,
    Qt.Key.Key_Up,
    Qt.Key.Key_Down,
    Qt.Key.Key_PageUp,
    Qt.Key.Key_PageDown,
    Qt.Key.Key_Backspace,
    Qt.Key.Key_Delete,
}


def _number_field(widget: QWidget | None) -> QAbstractSpinBox | None:
    while widget is not None:
        if isinstance(widget, QAbstractSpinBox):
            return widget
        if not isinstance(widget, QLineEdit):
            return None
        widget = widget.parentWidget()
    return None


def _is_field(widget: QWidget | None) -> bool:
    return isinstance(widget, (QAbstractSpinBox, QLineEdit)) or (
        isinstance(widget, QComboBox) and widget.isEditable()
    )


class FocusKeys(QObject):
    """Application event filter applying the rules above to the widgets of ``window``.

    ``window_keys``: a callable returning the key sequences of the window's actions.
    """

    def __init__(self, window: QWidget, home: QWidget, window_keys) -> None:
        super().__init__(window)
        self._window = window
        self._home = home
        self._window_keys = window_keys
        QApplication.instance().installEventFilter(self)
        window.destroyed.connect(self._detach)

    def _detach(self, *_args) -> None:
        app = QApplication.instance()
        if app is not None:
            app.removeEventFilter(self)

    def _ours(self, obj: QObject) -> bool:
        if not isinstance(obj, QWidget):
            return False
        top = obj.window()  # a floating dock is a window of its own, the main window's child
        return top is self._window or top.parentWidget() is self._window

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:
        kind = event.type()
        if kind == QEvent.Type.ShortcutOverride and self._ours(obj):
            return self._shortcut_wins(obj, event)
        if kind == QEvent.Type.KeyPress and event.key() in _RETURN_KEYS and self._ours(obj):
            field = _number_field(obj) or (obj if _is_field(obj) else None)
            if field is not None:
                # after the field has handled the key (Enter commits the value)
                QTimer.singleShot(0, self._home.setFocus)
        return False

    def _shortcut_wins(self, obj: QObject, event: QKeyEvent) -> bool:
        """True (the field does not claim the key) when a window shortcut should act."""
        if _number_field(obj) is None and not _is_field(obj):
            return False
        modifiers = event.modifiers() & ~Qt.KeyboardModifier.KeypadModifier
        unshifted = modifiers & ~Qt.KeyboardModifier.ShiftModifier
        keys = self._window_keys()
        candidates = (
            QKeySequence(event.keyCombination()),
            QKeySequence(event.key() | unshifted.value),  # "{" is Shift+[ on most layouts
        )
        if not any(candidate in keys for candidate in candidates):
            return False
        if event.key() in _EDITING_KEYS:
            return False  # Home, arrows, Delete...: the field's own
        if unshifted != Qt.KeyboardModifier.NoModifier:
            return True  # Ctrl+Z and the like: the window's undo, not the field's
        text = event.text()
        if not text:
            return True  # F12 and other function keys
        if _number_field(obj) is not None:
            return text not in _NUMBER_CHARS  # a letter cannot be part of a number
        return False  # typing text in a text field
