"""Two-way bindings between Qt widgets and fields of the evented settings model.

A binding writes the model into the widget when the field changes (signals blocked, so the
widget does not echo the value back) and the widget into the model when the user edits it. A
value the model refuses (:class:`gogreen_core.validation.ParameterError`) marks the widget red
with the message as tooltip and leaves the model unchanged. Bindings end when the widget is
destroyed.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from PySide6.QtCore import QObject, QSignalBlocker
from PySide6.QtWidgets import QAbstractSpinBox, QWidget

from app.panels.widgets import mark_invalid
from gogreen_core.settings import ChangeEvent, EventedModel
from gogreen_core.validation import ParameterError

__all__ = ["bind", "bind_spin"]


def bind(
    model: EventedModel,
    name: str,
    widget: QObject,
    show: Callable[[Any], None],
    edited,
    read: Callable[..., Any],
) -> None:
    """Bind field ``name`` of ``model`` to ``widget``.

    show : writes a model value into the widget.
    edited : the widget's Qt signal of a user edit.
    read : maps the signal's arguments to the value for the model.
    """
    tooltip = widget.toolTip() if hasattr(widget, "toolTip") else ""

    def to_widget(event: ChangeEvent) -> None:
        blocker = QSignalBlocker(widget)
        try:
            show(event.value)
        finally:
            blocker.unblock()
        _mark(widget, None, tooltip)

    def to_model(*args: Any) -> None:
        try:
            model.set(name, read(*args))
        except ParameterError as exc:
            _mark(widget, str(exc), tooltip)
        else:
            _mark(widget, None, tooltip)

    emitter = model.events[name]
    emitter.connect(to_widget)
    edited.connect(to_model)
    widget.destroyed.connect(lambda *_: emitter.disconnect(to_widget))
    show(getattr(model, name))


def _mark(widget: QObject, message: str | None, tooltip: str) -> None:
    if isinstance(widget, QWidget):
        mark_invalid(widget, message is not None)
    if hasattr(widget, "setToolTip"):
        widget.setToolTip(message or tooltip)


def bind_spin(model: EventedModel, name: str, spin: QAbstractSpinBox) -> None:
    """Bind a numeric field to a QSpinBox / QDoubleSpinBox."""
    bind(model, name, spin, spin.setValue, spin.valueChanged, lambda value: value)
