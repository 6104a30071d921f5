"""Number fields that never lie: what is typed stays on screen until it is taken or refused.

A Qt spin box silently changes what was typed: a key that cannot lead to a value in its range
is dropped ("-0.5" in a field of 0.005 … 1 becomes "0.5", "99" in 0 … 30 becomes "9") and a
half-typed value is replaced by the last one when the field loses the focus. The fields here
take every key (so letters never reach the window's hotkeys either) and judge the text when
it is committed (Enter, or the focus leaving): a number in range is taken; anything else is
refused visibly (the field turns red, its tool tip, shown at once, says the allowed range with
the field's name as the panel shows it, its accessible name, and the window's status bar says
it too: the ``note`` of the field's window, when it has one), and the text stays, red,
for the artist to mend, also after the focus has left, until a number in range is entered or
Escape cancels it (the value in effect again).

:class:`DecimalField` (fixed decimals), :class:`IntegerField` and :class:`NumberField` (any
magnitude, ``%g``, scientific input) share that behaviour. ``left`` is emitted when a refused
text is dropped, so a binding can show the model's value (:mod:`app.bindings`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QFocusEvent, QKeyEvent, QValidator
from PySide6.QtWidgets import QAbstractSpinBox, QDoubleSpinBox, QSpinBox, QToolTip, QWidget

from app.bindings import is_marked_invalid, line_edit, mark_invalid

__all__ = ["DecimalField", "IntegerField", "NumberField", "number_text"]

#: Bounds beyond these count as none ("enter a number ≥ 0" rather than "… to 1e+300").
_UNBOUNDED = 1e299


def number_text(value: float) -> str:
    """A bound as the artist reads it: ``0.005``, ``1``, ``10000``, ``1e-12``, minus as ``−``."""
    return f"{value:g}".replace("-", "−")


if TYPE_CHECKING:  # the behaviour of a QSpinBox or a QDoubleSpinBox, whichever follows it
    from typing import Any as _SpinBox
else:
    _SpinBox = object


class _FieldBehaviour(_SpinBox):
    """Shared by the fields (a mixin before the Qt spin box class)."""

    _whole = False

    def _init_field(self) -> None:
        self.setKeyboardTracking(False)
        self.setCorrectionMode(QAbstractSpinBox.CorrectionMode.CorrectToPreviousValue)
        self._tip = ""
        self._said = ""  # what refuse() said in the status bar
        self._line = line_edit(self)
        self._line.textChanged.connect(self._text_changed)

    # -- judging the text --------------------------------------------------------------------
    @property
    def label(self) -> str:
        """The field's name as the panel shows it (its accessible name)."""
        return self.accessibleName() or "This field"

    def range_text(self) -> str:
        """The allowed values in words: "a number from 0.005 to 1", "a whole number from 0 to
        30", "a number ≥ 1e-12"."""
        low, high = self.minimum(), self.maximum()
        kind = "a whole number" if self._whole else "a number"
        if low <= -_UNBOUNDED and high >= _UNBOUNDED:
            text = kind
        elif high >= _UNBOUNDED:
            text = f"{kind} ≥ {number_text(low)}"
        elif low <= -_UNBOUNDED:
            text = f"{kind} ≤ {number_text(high)}"
        else:
            text = f"{kind} from {number_text(low)} to {number_text(high)}"
        special = self.specialValueText()
        return f"{text} (or {special!r})" if special else text

    def _core(self, text: str) -> str:
        """``text`` without the field's prefix and suffix (a unit such as °) and spaces."""
        prefix, suffix = self.prefix(), self.suffix()
        if prefix and text.startswith(prefix):
            text = text[len(prefix) :]
        if suffix and text.endswith(suffix):
            text = text[: -len(suffix)]
        return text.strip()

    def _number(self, text: str) -> float | None:
        """The number ``text`` says (prefix, suffix and spaces aside), else None."""
        core = self._core(text).replace("−", "-")
        try:
            value = float(core)
        except ValueError:
            return None
        if not math.isfinite(value) or (self._whole and value != int(value)):
            return None
        return value

    def refusal(self, text: str) -> str | None:
        """Why ``text`` cannot be taken, in the panel's words; None when it can."""
        if self.specialValueText() and text.strip() == self.specialValueText():
            return None
        value = self._number(text)
        if value is not None and self.minimum() <= value <= self.maximum():
            return None
        shown = self._core(text) or "nothing"
        return f"{self.label}: enter {self.range_text()} (got {shown!r})"

    def validate(self, text: str, pos: int) -> tuple[QValidator.State, str, int]:
        # Never Invalid: what is typed stays on screen (it is judged on Enter).
        state = (
            QValidator.State.Acceptable
            if self.refusal(text) is None
            else QValidator.State.Intermediate
        )
        return state, text, pos

    def fixup(self, text: str) -> str:
        return text  # never change what was typed behind the artist's back

    def _value_of(self, text: str) -> float:
        """The value ``text`` says (the field's minimum for its special text), else the
        current value."""
        if self.specialValueText() and text.strip() == self.specialValueText():
            return float(self.minimum())
        value = self._number(text)
        return float(self.value()) if value is None else value

    # -- showing a refusal -------------------------------------------------------------------
    def refuse(self, message: str) -> None:
        """Red, with ``message`` as tool tip, shown at once, and said in the window's status
        bar (its ``note``, when it has one)."""
        if not is_marked_invalid(self):
            self._tip = self.toolTip()
        mark_invalid(self, True)
        self.setToolTip(message)
        if self.isVisible() and self.hasFocus():
            QToolTip.showText(self.mapToGlobal(self.rect().bottomLeft()), message, self)
        note = getattr(self.window(), "note", None)
        if callable(note):
            self._said = f"Refused: {message}"
            note(self._said)

    def revert(self) -> None:
        """Drop a refused text: the value in effect again (``left`` lets a binding show the
        model's value)."""
        line = self._line
        shown = self.textFromValue(self.value())
        if self.specialValueText() and self.value() == self.minimum():
            shown = self.specialValueText()
        else:
            shown = self.prefix() + shown + self.suffix()
        if line.text() != shown:
            line.setText(shown)
        self._unmark()
        self.left.emit()  # each field class has the signal

    def _unmark(self) -> None:
        if is_marked_invalid(self):
            mark_invalid(self, False)
            self.setToolTip(self._tip)
            QToolTip.hideText()
            # cancelled or mended: the refusal goes from the status bar too (if still shown)
            unsay = getattr(self.window(), "unsay", None)
            if self._said and callable(unsay):
                unsay(self._said)
            self._said = ""

    def _text_changed(self, text: str) -> None:
        """The value in effect is on screen again (set by a binding, the arrows): not red."""
        if is_marked_invalid(self) and self.refusal(text) is None:
            if self._number(text) == self.value() or text == self.specialValueText():
                self._unmark()

    # -- keys and focus ----------------------------------------------------------------------
    def keyPressEvent(self, event: QKeyEvent) -> None:
        key = event.key()
        if key in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
            message = self.refusal(self._line.text())
            if message is not None:
                self.refuse(message)
                event.accept()
                return
            self._unmark()  # mended: taken now
        elif key == Qt.Key.Key_Escape:
            self.revert()
        super().keyPressEvent(event)

    def focusOutEvent(self, event: QFocusEvent) -> None:
        """A text in range is taken (Qt's commit); a refused one stays, red and named (the spin
        box would put the previous value back silently), until mended or cancelled."""
        text = self._line.text()
        message = self.refusal(text)
        super().focusOutEvent(event)
        if message is None:
            self._unmark()  # mended: taken now
        else:
            if self._line.text() != text:
                self._line.setText(text)
            self.refuse(message)


class DecimalField(_FieldBehaviour, QDoubleSpinBox):
    """A number with ``decimals`` decimals in [``minimum``, ``maximum``]."""

    left = Signal()

    def __init__(
        self,
        minimum: float,
        maximum: float,
        decimals: int = 2,
        step: float = 0.1,
        tooltip: str = "",
        parent: QWidget | None = None,
    ):
        super().__init__(parent)
        self.setRange(minimum, maximum)
        self.setDecimals(decimals)
        self.setSingleStep(step)
        if tooltip:
            self.setToolTip(tooltip)
        self._init_field()

    def valueFromText(self, text: str) -> float:
        return self._value_of(text)


class IntegerField(_FieldBehaviour, QSpinBox):
    """A whole number in [``minimum``, ``maximum``]."""

    left = Signal()
    _whole = True

    def __init__(
        self, minimum: int, maximum: int, tooltip: str = "", parent: QWidget | None = None
    ):
        super().__init__(parent)
        self.setRange(minimum, maximum)
        if tooltip:
            self.setToolTip(tooltip)
        self._init_field()

    def valueFromText(self, text: str) -> int:
        return int(self._value_of(text))


class NumberField(_FieldBehaviour, QDoubleSpinBox):
    """A number of any magnitude (material constants): up to ``digits`` significant digits
    shown (``%g``: 200, 0.3, 1.5e+09), scientific notation accepted, steps of about a tenth of
    the value's magnitude."""

    left = Signal()

    def __init__(
        self,
        value: float = 0.0,
        minimum: float = -1e300,
        maximum: float = 1e300,
        digits: int = 6,
        tooltip: str = "",
        parent: QWidget | None = None,
    ):
        super().__init__(parent)
        self._digits = digits
        self.setDecimals(15)
        self.setRange(minimum, maximum)
        self.setStepType(QAbstractSpinBox.StepType.AdaptiveDecimalStepType)
        self.setAccelerated(True)
        self.setMinimumWidth(70)
        self.setValue(value)
        if tooltip:
            self.setToolTip(tooltip)
        self._init_field()

    def textFromValue(self, value: float) -> str:
        return f"{value:.{self._digits}g}"

    def valueFromText(self, text: str) -> float:
        return self._value_of(text)
