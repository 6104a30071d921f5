"""A grid of labelled number fields editing one array, e.g. a weight per SH degree."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import QGridLayout, QLabel, QWidget

from app.fields import DecimalField

__all__ = ["NumberGrid"]


class NumberGrid(QWidget):
    """One spin box per entry of a 1-D array, ``columns`` per row, each labelled by
    ``label(index)``; as many as the array shown has entries (:meth:`set_values` adds or
    removes fields when the length changes). ``edited(np.ndarray)`` carries the whole array
    after the user changes one entry. Bind it to an array field with :func:`app.bindings.bind`::

        grid = NumberGrid(lambda l: f"l {l}", (-100.0, 100.0), decimals=2)
        bind(model, "weights", grid, grid.set_values, grid.edited)
    """

    edited = Signal(object)

    def __init__(
        self,
        label: Callable[[int], str],
        value_range: tuple[float, float],
        decimals: int = 2,
        step: float = 0.1,
        columns: int = 3,
        tooltip: Callable[[int], str] | None = None,
        name: str = "",
        parent: QWidget | None = None,
    ):
        super().__init__(parent)
        self._name = name
        self._label, self._range, self._decimals, self._step = label, value_range, decimals, step
        self._columns, self._tooltip = columns, tooltip
        self._grid = QGridLayout(self)
        self._grid.setContentsMargins(0, 0, 0, 0)
        self._grid.setHorizontalSpacing(4)
        self._grid.setVerticalSpacing(2)
        self.spins: list[DecimalField] = []
        #: The label of each field, in order.
        self.labels: list[QLabel] = []

    @property
    def values(self) -> np.ndarray:
        """The entries shown (n,)."""
        return np.array([spin.value() for spin in self.spins], dtype=np.float64)

    def set_values(self, values: Sequence[float] | np.ndarray) -> None:
        """Show ``values`` (n,), with n fields."""
        values = np.asarray(values, dtype=np.float64).ravel()
        if len(values) != len(self.spins):
            self._rebuild(len(values))
        for index, (spin, value) in enumerate(zip(self.spins, values, strict=True)):
            # the labels follow what is shown (another brush's degrees: as many, others)
            self.labels[index].setText(self._label(index))
            spin.setAccessibleName(f"{self._name} {self._label(index)}".strip())
            if self._tooltip is not None:
                spin.setToolTip(self._tooltip(index))
            spin.setValue(float(value))

    def _rebuild(self, count: int) -> None:
        while self._grid.count():
            taken = self._grid.takeAt(0)
            widget = taken.widget() if taken is not None else None
            if widget is not None:
                widget.hide()  # gone now, not only when the event loop runs the deletion
                widget.deleteLater()
        self.spins, self.labels = [], []
        for index in range(count):
            row, col = divmod(index, self._columns)
            label = QLabel()
            label.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
            spin = DecimalField(*self._range, decimals=self._decimals, step=self._step)
            spin.valueChanged.connect(self._spin_changed)
            self._grid.addWidget(label, row, 2 * col)
            self._grid.addWidget(spin, row, 2 * col + 1)
            self.spins.append(spin)
            self.labels.append(label)
        for col in range(self._columns):
            self._grid.setColumnStretch(2 * col + 1, 1)

    def _spin_changed(self, _value: float) -> None:
        self.edited.emit(self.values)
