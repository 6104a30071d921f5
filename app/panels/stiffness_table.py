"""A read-only 6×6 Voigt stiffness table whose equal coefficients share a colour."""

from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtGui import QBrush, QColor
from PySide6.QtWidgets import QTableWidget, QTableWidgetItem, QWidget

from app.panels.plot_axes import plot_font
from app.panels.widgets import CompactTable, pastel_color, zero_cell_colors
from app.theme import active_theme
from gogreen_core import Material, SymmetryDescription

__all__ = ["VOIGT_LABELS", "StiffnessTable"]

VOIGT_LABELS = ("11", "22", "33", "23", "13", "12")


class StiffnessTable(CompactTable):
    """Shows a material's Voigt stiffness (4 significant digits, the exact value as tool tip)
    with the coefficient groups of its :class:`gogreen_core.SymmetryDescription` as colours:
    equal coefficients share a pastel, zeros are grey."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(6, 6, parent=parent)
        self.setHorizontalHeaderLabels(VOIGT_LABELS)
        self.setVerticalHeaderLabels(VOIGT_LABELS)
        self.setEditTriggers(QTableWidget.EditTrigger.NoEditTriggers)
        self.setSelectionMode(QTableWidget.SelectionMode.NoSelection)
        self.setFocusPolicy(Qt.FocusPolicy.NoFocus)
        self.setToolTip("Equal coefficients share a colour; grey cells are zero")
        self._symmetry: SymmetryDescription | None = None
        small = plot_font(self.font())
        for i in range(6):
            for j in range(6):
                item = QTableWidgetItem("")
                item.setTextAlignment(Qt.AlignmentFlag.AlignCenter)
                item.setFont(small)
                self.setItem(i, j, item)

    def show_material(self, material: Material, symmetry: SymmetryDescription) -> None:
        """The entries of ``material``, coloured by ``symmetry``'s groups."""
        self._symmetry = symmetry
        voigt = material.voigt
        for i in range(6):
            for j in range(6):
                group = int(symmetry.groups[i, j])
                item = self.cell(i, j)
                item.setText("0" if group < 0 else f"{voigt[i, j]:.4g}")
                item.setToolTip(f"C{VOIGT_LABELS[i]},{VOIGT_LABELS[j]} = {voigt[i, j]:.10g}")
        self.refresh_colors()

    def refresh_colors(self) -> None:
        """Colour the cells in the current theme (after a theme switch)."""
        if self._symmetry is None:
            return
        for i in range(6):
            for j in range(6):
                group = int(self._symmetry.groups[i, j])
                item = self.cell(i, j)
                item.setBackground(QBrush(self.group_color(group)))
                item.setForeground(QBrush(self.group_text_color(group)))

    def cell_color(self, row: int, col: int) -> QColor:
        """Background colour of cell (row, col)."""
        return self.cell(row, col).background().color()

    @staticmethod
    def group_color(group: int) -> QColor:
        """Cell colour of coefficient group ``group`` (-1, the zeros, is grey)."""
        return zero_cell_colors()[0] if group < 0 else pastel_color(group)

    @staticmethod
    def group_text_color(group: int) -> QColor:
        """Text colour on a cell of group ``group``: muted for the zeros; on the group
        colours, the theme's text colour under the dark theme (deep tones), near-black on the
        light theme's pastels."""
        if group < 0:
            return zero_cell_colors()[1]
        current = active_theme()
        return QColor(current.text if current.name == "dark" else "#1a1a1a")
