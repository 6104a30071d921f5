"""Keyboard focus rules of the main window: the sculpting keys act on the viewport unless the
artist is typing in a field.

* Typing widgets (number and text fields, the curve editor, the keymap overlay) keep the keys
  they are given: a letter typed in a number field stays there (and is refused visibly,
  :mod:`app.fields`), it never reaches the hotkeys. Only the window's shortcuts with Ctrl or
  Alt (undo, save, …) and the function keys (F1, F12) act from inside a field.
* Enter in a field commits and hands the focus back to the viewport, unless the field refused
  the text (it stays red, with the focus, to be mended); Escape drops what was typed and hands
  the focus back.
* The focus never rests on anything else: after a click on a panel's button, check box,
  slider, tab or combo box, after a menu, a dialog or another window, and when a focused
  widget disappears, the viewport has the keys again.
* Numpad keys are told from the digits above the letters (numpad 1 is a view, 1 a brush):
  Qt's shortcut map drops the keypad flag of X11 key events, so the window's actions with a
  numpad shortcut are triggered here, outside fields, from the key event itself.
"""

from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import QEvent, QObject, Qt, QTimer
from PySide6.QtGui import QAction, QKeyEvent, QKeySequence
from PySide6.QtWidgets import (
    QAbstractItemView,
    QAbstractSpinBox,
    QApplication,
    QComboBox,
    QLineEdit,
    QMenu,
    QWidget,
)

from app.bindings import is_marked_invalid

__all__ = ["FocusKeys", "typing_widget"]

_RETURN_KEYS = (Qt.Key.Key_Return, Qt.Key.Key_Enter)
#: Focus reasons of the artist choosing a widget (Tab: keyboard navigation is kept).
_CHOSEN = (
    Qt.FocusReason.MouseFocusReason,
    Qt.FocusReason.TabFocusReason,
    Qt.FocusReason.BacktabFocusReason,
    Qt.FocusReason.ShortcutFocusReason,
)
#: Focus given back when a popup, menu or dialog closes or the window is activated again.
_RETURNED = (Qt.FocusReason.PopupFocusReason, Qt.FocusReason.ActiveWindowFocusReason)


def _editable(widget: QWidget | None) -> bool:
    return isinstance(widget, QAbstractSpinBox) or (
        isinstance(widget, QComboBox) and widget.isEditable()
    )


def _field(widget: QWidget | None) -> QWidget | None:
    """The number or text field ``widget`` is (or is the line edit of), else None; a line
    edit of its own (a table cell's editor) is a field."""
    if isinstance(widget, QLineEdit):
        parent = widget.parentWidget()
        return parent if _editable(parent) else widget
    return widget if _editable(widget) else None


def typing_widget(widget: QWidget | None) -> bool:
    """Whether ``widget`` takes typed keys itself: a field, a table being edited, or a
    widget that handles keys of its own (``takes_keys`` property: the curve editor)."""
    if widget is None:
        return False
    if _field(widget) is not None or isinstance(widget, QAbstractItemView):
        return True
    return bool(widget.property("takes_keys"))


class FocusKeys(QObject):
    """Application event filter applying the rules above to the widgets of ``window``, with
    ``home`` (the viewport) as the place the keys go back to.

    ``window_keys``: a callable returning the key sequences of the window's actions;
    ``actions``: one returning those actions (for their numpad shortcuts).
    """

    def __init__(
        self,
        window: QWidget,
        home: QWidget,
        window_keys: Callable[[], list[QKeySequence]],
        actions: Callable[[], list[QAction]] = list,
    ) -> None:
        super().__init__(window)
        self._window = window
        self._home = home
        self._window_keys = window_keys
        self._actions = actions
        app = QApplication.instance()
        assert app is not None
        app.installEventFilter(self)
        window.destroyed.connect(self._detach)

    def _detach(self, *_args: object) -> None:
        app = QApplication.instance()
        if app is not None:
            app.removeEventFilter(self)

    def _ours(self, obj: QObject) -> bool:
        if not isinstance(obj, QWidget) or isinstance(obj, QMenu):
            return False
        top = obj.window()  # a floating dock is a window of its own, the main window's child
        return top is self._window or top.parentWidget() is self._window

    def go_home(self) -> None:
        """Give the keys to the viewport (when the window is the active one)."""
        if self._home.isVisible() and not self._home.hasFocus():
            self._home.setFocus(Qt.FocusReason.OtherFocusReason)

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:
        kind = event.type()
        if kind not in (
            QEvent.Type.ShortcutOverride,
            QEvent.Type.KeyPress,
            QEvent.Type.MouseButtonRelease,
            QEvent.Type.FocusIn,
        ) or not self._ours(obj):
            return False
        assert isinstance(obj, QWidget)
        if kind in (QEvent.Type.ShortcutOverride, QEvent.Type.KeyPress) and self._numpad(
            obj, event, kind == QEvent.Type.KeyPress
        ):
            return True
        if kind == QEvent.Type.ShortcutOverride:
            assert isinstance(event, QKeyEvent)
            return self._shortcut_wins(obj, event)
        if kind == QEvent.Type.KeyPress:
            assert isinstance(event, QKeyEvent)
            self._key_pressed(obj, event)
        elif kind == QEvent.Type.MouseButtonRelease:
            # a click on a control (button, check box, slider, tab…): the keys go home after
            # the control has handled it; a click into a field or on the viewport keeps them
            if obj is not self._home and not typing_widget(obj):
                QTimer.singleShot(0, self.go_home)
        elif kind == QEvent.Type.FocusIn and obj is not self._home:
            reason = event.reason()  # type: ignore[attr-defined]
            typing = typing_widget(obj)
            if (typing and reason in _RETURNED) or (not typing and reason not in _CHOSEN):
                QTimer.singleShot(0, self.go_home)
        return False

    def _numpad(self, obj: QWidget, event: QEvent, press: bool) -> bool:
        """A numpad key of one of the window's actions, outside a field: claimed from Qt's
        shortcut map (which would take numpad 1 for the brush key 1) and, on the key press,
        the action triggered (told which key: Ctrl+numpad 1 is the back view)."""
        assert isinstance(event, QKeyEvent)
        if not event.modifiers() & Qt.KeyboardModifier.KeypadModifier or typing_widget(obj):
            return False
        pressed = QKeySequence(event.keyCombination())
        action = next(
            (a for a in self._actions() if a.isEnabled() and pressed in a.shortcuts()), None
        )
        if action is None:
            return False
        event.accept()
        if press:
            trigger = getattr(action, "trigger_for_key", None)
            trigger(event.keyCombination()) if trigger is not None else action.trigger()
        return True

    def _key_pressed(self, obj: QWidget, event: QKeyEvent) -> None:
        field = _field(obj)
        if field is None or event.key() not in (Qt.Key.Key_Escape, *_RETURN_KEYS):
            return

        def after() -> None:
            # once the field has handled the key (Enter commits, Escape drops the text):
            # home, unless the field refused the text or the artist went to another widget
            if field.hasFocus() and not is_marked_invalid(field):
                self.go_home()

        QTimer.singleShot(0, after)

    def _shortcut_wins(self, obj: QWidget, event: QKeyEvent) -> bool:
        """True (the widget does not claim the key) when a window shortcut should act."""
        if not typing_widget(obj):
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
        if unshifted & (Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.AltModifier):
            return True  # Ctrl+Z and the like: the window's undo, not the field's
        return not event.text()  # F1, F12: the window's; printable keys: the field's
