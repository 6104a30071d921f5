"""Two-way bindings between Qt widgets and fields of evented models: the one place where a
widget meets a model, and the only place where widget signals are blocked.

A :class:`Binding` writes the model's value into its widget whenever the field changes (the
widget's signals blocked, so it does not echo the value back) and the widget's edits into the
model. A value the model refuses (a ``ValueError``; a
:class:`gogreen_core.validation.ParameterError` names the field it is about) marks the field
red with the message, worded with the field's ``label`` (the name the panel shows), and leaves
the model as it was; the refused text stays on screen until the field loses the focus or
another edit of the same model succeeds, then the widget shows the value in effect again
(:meth:`Binding.refresh`). :func:`refresh` re-shows every widget bound to a model (after undo,
redo, opening a model or a preset). A binding ends when its widget is destroyed.

The models are :class:`gogreen_core.interaction.settings.Settings` (and its ``brush`` and ``pen``
sub-models) for what the engine uses, and small
:class:`~gogreen_core.interaction.settings.EventedModel` subclasses of the panels for what a panel
only shows (the curve being edited, the material's input form), so that every widget of a panel is
bound the same way.

Adding a bound widget to a panel is one call (number fields are :mod:`app.fields`' own,
which never change what was typed; the label is the name refusals use)::

    depth = DecimalField(0.0, 4.0, decimals=2)
    bind_spin(settings, "fold_depth", depth, "Fold depth")     # a number
    bind_check(view, "preview", QCheckBox("Preview"))          # a flag (check box or action)
    bind_choice(settings, "mode", combo)                       # a combo box (item data)
    bind_readout(settings, "error", label, "{:.1%}".format)    # read-only text
    bind(settings, "weights", grid, grid.set_values, grid.edited)   # any other widget
                                                               # (NumberGrid: one field per entry)

and a field the panel alone shows is one ``Field`` on the panel's own model (FalloffView,
MaterialForm, HomogenizationInputs).
"""

from __future__ import annotations

import re
import weakref
from collections.abc import Callable, Iterable, Sequence
from typing import Any

from PySide6.QtCore import QObject, QSignalBlocker, SignalInstance
from PySide6.QtGui import QAction, QColor, QPalette
from PySide6.QtWidgets import (
    QAbstractButton,
    QAbstractSpinBox,
    QComboBox,
    QDoubleSpinBox,
    QLabel,
    QLineEdit,
    QSpinBox,
    QToolTip,
    QWidget,
)
from shiboken6 import invalidate, isValid

from app.theme import active_theme
from gogreen_core.interaction.settings import ChangeEvent, EventedModel

__all__ = [
    "Binding",
    "bind",
    "bind_check",
    "bind_choice",
    "bind_readout",
    "bind_spin",
    "bind_view",
    "bindings_of",
    "is_marked_invalid",
    "line_edit",
    "mark_invalid",
    "panel_words",
    "refresh",
]

_REGISTRY: weakref.WeakKeyDictionary[EventedModel, list[Binding]] = weakref.WeakKeyDictionary()


def _same(value: Any) -> Any:
    return value


def line_edit(box: QAbstractSpinBox) -> QLineEdit:
    """``box.lineEdit()``, past a stale wrapper. Qt deletes a closed viewport's GL surface
    without PySide knowing (a QSurface is no QObject), so PySide keeps that wrapper and hands
    it back for a new object at the same address: a QSurface where a line edit was asked for.
    Invalidating the stale wrapper makes PySide wrap the line edit afresh."""
    line = box.lineEdit()
    if not isinstance(line, QLineEdit):
        invalidate(line)
        line = box.lineEdit()
    return line


def mark_invalid(widget: QWidget, invalid: bool) -> None:
    """Show ``widget`` as holding an invalid value (red text on a red-tinted background: the
    refused text itself reads as refused, not only the field's frame) or restore its normal
    look.

    Uses the palette, not a style sheet, so spin box arrows keep the platform style. Sets the
    dynamic property ``invalid`` too, so tests can query it.
    """
    widget.setProperty("invalid", bool(invalid))
    # a spin box's text is its line edit's, which does not take the box's palette
    line = line_edit(widget) if isinstance(widget, QAbstractSpinBox) else None
    for target in (widget, line):
        if target is None:
            continue
        if invalid:
            current = active_theme()
            palette = target.palette()
            palette.setColor(QPalette.ColorRole.Base, QColor(current.invalid_base))
            palette.setColor(QPalette.ColorRole.Text, QColor(current.error_text))
            target.setPalette(palette)
        else:
            target.setPalette(QPalette())  # back to the inherited palette


def is_marked_invalid(widget: QWidget) -> bool:
    """Whether :func:`mark_invalid` last marked ``widget`` as invalid."""
    return bool(widget.property("invalid"))


class Binding:
    """Field ``name`` of ``model`` shown in ``widget`` (and edited there when ``edited`` is
    given).

    show : writes a model value into the widget (its signals blocked meanwhile).
    edited : the widget's Qt signal of a user edit, or None for a read-only view.
    read : maps the signal's arguments to the value for the model.
    label : the field's name as the panel shows it ("Young's modulus E"), used in messages.
    dragging : returns whether the edit is a step of a drag (a slider or a curve point held):
        the steps after a drag's first reach the model as ``continued`` (one undo step).
    drag_ended : the widget's signal that a drag ended.
    revert_on_error : a refused edit is replaced at once by the value in effect (a table
        cell, a curve) instead of staying on screen until the focus leaves; or a function of
        the error telling whether to.
    on_error : called with the message of a refused edit (e.g. a panel's message line), and
        with None when the refused value gives way to the one in effect.
    echo : re-show the model's value after the widget's own edit even when it is the value
        the widget holds (default: only when the model changed it).
    block : block the widget's signals while showing a value (off for a view whose widget's
        own signals must run, e.g. a stacked widget resizing to its page).
    """

    def __init__(
        self,
        model: EventedModel,
        name: str,
        widget: QObject,
        show: Callable[[Any], None],
        edited: SignalInstance | None = None,
        read: Callable[..., Any] = _same,
        *,
        label: str = "",
        dragging: Callable[[], bool] | None = None,
        drag_ended: SignalInstance | None = None,
        revert_on_error: bool | Callable[[ValueError], bool] = False,
        on_error: Callable[[str | None], None] | None = None,
        echo: bool = False,
        block: bool = True,
    ) -> None:
        if name not in model.fields:
            raise ValueError(f"{type(model).__name__} has no field {name!r}")
        self.model, self.name, self.widget = model, name, widget
        self.label = label or name
        self._show, self._read = show, read
        self._dragging, self._revert, self._on_error = dragging, revert_on_error, on_error
        self._echo, self._block = echo, block
        self.editable = edited is not None
        self._tooltip = widget.toolTip() if hasattr(widget, "toolTip") else ""
        self._drag_open = False
        self._setting = False
        #: The message of the refused edit on screen, or None.
        self.refused: str | None = None
        model.events[name].connect(self._model_changed)
        if label and isinstance(widget, QWidget) and not widget.accessibleName():
            widget.setAccessibleName(label)  # the field's name in its refusals (app.fields)
        left = getattr(widget, "left", None)
        if isinstance(left, SignalInstance):  # a field that dropped a refused text
            left.connect(self._left)
        if edited is not None:
            edited.connect(self._edited)
        if drag_ended is not None:
            drag_ended.connect(self._drag_ended)
        _REGISTRY.setdefault(model, []).append(self)
        widget.destroyed.connect(self.unbind)
        self.refresh()

    @property
    def value(self) -> Any:
        """The model's value of the field."""
        return getattr(self.model, self.name)

    def refresh(self) -> None:
        """Show the value in effect (dropping a refused edit on screen)."""
        if not isValid(self.widget):  # deleted by Qt before its ``destroyed`` reached us
            self.unbind()
            return
        blocker = QSignalBlocker(self.widget) if self._block else None
        try:
            self._show(self.value)
        finally:
            if blocker is not None:
                blocker.unblock()
        if self.refused is not None and self._on_error is not None:
            self._on_error(None)  # the refusal is gone from the screen: its message too
        self._mark(None)

    def refuse(self, message: str) -> None:
        """Show ``message`` as the reason an edit was refused: the field turns red, its tool
        tip (shown at once) says why; the model is unchanged."""
        self._mark(message)

    def unbind(self, *_args: Any) -> None:
        """End the binding (the widget was destroyed)."""
        self.model.events[self.name].disconnect(self._model_changed)
        bindings = _REGISTRY.get(self.model, [])
        if self in bindings:
            bindings.remove(self)

    # -- internals ---------------------------------------------------------------------------
    def _model_changed(self, _event: ChangeEvent) -> None:
        if not self._setting:
            self.refresh()

    def _left(self) -> None:
        if self.refused is not None:
            self.refresh()

    def _drag_ended(self, *_args: Any) -> None:
        self._drag_open = False

    def _edited(self, *args: Any) -> None:
        in_drag = bool(self._dragging and self._dragging())
        continued = in_drag and self._drag_open
        self._drag_open = in_drag
        try:
            value = self._read(*args)
            self._setting = True
            try:
                self.model.set(self.name, value, continued=continued)
            finally:
                self._setting = False
        except ValueError as exc:
            self._refused(exc)
            return
        for other in bindings_of(self.model):  # the model is consistent again
            if other.refused is not None and other is not self:
                other.refresh()
        field = self.model.fields[self.name]
        if self._echo or not field.equal(self.value, value):
            self.refresh()
        else:
            self._mark(None)

    def _refused(self, exc: ValueError) -> None:
        parameter = getattr(exc, "parameter", None)
        target = self if _names(parameter) & {self.name} else None
        target = target or _binding_for(self.model, parameter) or self
        message = panel_words(str(exc), {parameter or target.name: target.label})
        if self._revert is True or (callable(self._revert) and self._revert(exc)):
            self.refresh()
        target.refuse(message)
        if self._on_error is not None:
            self._on_error(message)

    def _mark(self, message: str | None) -> None:
        if message is None and self.refused is None:
            return  # nothing shown: leave the widget's look and tool tip alone
        self.refused = message
        widget = self.widget
        if isinstance(widget, QWidget):
            mark_invalid(widget, message is not None)
        if hasattr(widget, "setToolTip"):
            widget.setToolTip(message or self._tooltip)
        if message is not None and isinstance(widget, QWidget) and widget.isVisible():
            QToolTip.showText(widget.mapToGlobal(widget.rect().bottomLeft()), message, widget)


def _names(parameter: str | None) -> set[str]:
    """A parameter's name and its last dotted part (``"brush.radius"``: also ``"radius"``)."""
    return {parameter, parameter.rsplit(".", 1)[-1]} if parameter else set()


def _binding_for(model: EventedModel, parameter: str | None) -> Binding | None:
    """The editable binding of ``model``'s field ``parameter`` (or its last dotted part)."""
    names = _names(parameter)
    return next((b for b in bindings_of(model) if b.editable and b.name in names), None)


def panel_words(message: str, labels: dict[str, str]) -> str:
    """``message`` with the internal names (keys of ``labels``, also as their last dotted
    part) replaced by the names the panel shows: ``"poisson must lie in (-1, 1/2)"`` becomes
    ``"Poisson ratio ν must lie in (-1, 1/2)"``."""
    for name, label in labels.items():
        if not name or not label or name == label:
            continue
        for word in dict.fromkeys((name, name.rsplit(".", 1)[-1])):
            message = re.sub(rf"(?<![\w.]){re.escape(word)}(?![\w])", label, message)
    return message


def bindings_of(model: EventedModel) -> list[Binding]:
    """The live bindings of ``model``'s fields."""
    return list(_REGISTRY.get(model, []))


def refresh(models: EventedModel | Iterable[EventedModel] | None = None) -> None:
    """Show the values in effect in every widget bound to ``models`` (default: every bound
    model), dropping refused edits still on screen: after undo, redo, opening a model or a
    preset."""
    if models is None:
        models = list(_REGISTRY.keys())
    for model in [models] if isinstance(models, EventedModel) else models:
        for binding in bindings_of(model):
            binding.refresh()


# -- one call per kind of widget -------------------------------------------------------------
def bind(
    model: EventedModel,
    name: str,
    widget: QObject,
    show: Callable[[Any], None],
    edited: SignalInstance | None = None,
    read: Callable[..., Any] = _same,
    **options: Any,
) -> Binding:
    """Bind field ``name`` of ``model`` to ``widget`` (see :class:`Binding`)."""
    return Binding(model, name, widget, show, edited, read, **options)


def bind_view(
    model: EventedModel,
    name: str,
    owner: QObject,
    show: Callable[[Any], None],
    block: bool = False,
) -> Binding:
    """Call ``show(value)`` with the field's value now and after each change, while ``owner``
    lives: a read-only view of a field (``block``: with ``owner``'s signals blocked, e.g. a
    combo box whose items are rebuilt)."""
    return Binding(model, name, owner, show, block=block)


def bind_spin(
    model: EventedModel, name: str, spin: QAbstractSpinBox, label: str = "", **options: Any
) -> Binding:
    """A number field (QSpinBox, QDoubleSpinBox, NumberField) bound to a numeric field; the
    value reaches the model when editing finishes (Enter, focus out) or an arrow steps."""
    if not isinstance(spin, (QSpinBox, QDoubleSpinBox)):
        raise TypeError(f"bind_spin needs a spin box (got {type(spin).__name__})")
    spin.setKeyboardTracking(False)
    return Binding(model, name, spin, spin.setValue, spin.valueChanged, label=label, **options)


def bind_check(
    model: EventedModel, name: str, checkable: QAbstractButton | QAction, label: str = ""
) -> Binding:
    """A check box, checkable button or checkable action bound to a boolean field."""
    checkable.setCheckable(True)
    return Binding(
        model, name, checkable, checkable.setChecked, checkable.toggled, bool, label=label
    )


def bind_choice(
    model: EventedModel,
    name: str,
    combo: QComboBox,
    values: Callable[[], Sequence[Any]] | None = None,
    label: str = "",
) -> Binding:
    """A combo box bound to a field whose value is the current item's data, or with
    ``values`` (returning one value per item, in order) for values a QVariant would not carry
    intact (tuples)."""

    def show(value: Any) -> None:
        index = list(values()).index(value) if values is not None else combo.findData(value)
        combo.setCurrentIndex(index)

    def read(index: int) -> Any:
        if index < 0:
            raise ValueError(f"{label or name}: nothing chosen")
        return values()[index] if values is not None else combo.itemData(index)

    return Binding(model, name, combo, show, combo.currentIndexChanged, read, label=label)


def bind_readout(
    model: EventedModel, name: str, label: QLabel, format: Callable[[Any], str] = str
) -> Binding:
    """A label showing the field's value as ``format(value)`` (read-only)."""
    return Binding(model, name, label, lambda value: label.setText(format(value)), block=False)
