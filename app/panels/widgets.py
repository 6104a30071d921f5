"""Small building blocks shared by the side panels: number fields, Euler angles, colours.

Nothing here computes physics; the rotation matrix of the Euler angles comes from
``scipy.spatial.transform.Rotation`` (gogreen_core has no Euler-angle helper).
"""

from __future__ import annotations

import colorsys
import math
from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import QModelIndex, QPersistentModelIndex, QSize, Qt, Signal
from PySide6.QtGui import QColor, QFontMetrics
from PySide6.QtWidgets import (
    QDoubleSpinBox,
    QFrame,
    QGridLayout,
    QHeaderView,
    QLabel,
    QScrollArea,
    QSizePolicy,
    QSlider,
    QStackedWidget,
    QStyle,
    QStyledItemDelegate,
    QStyleOptionViewItem,
    QTableWidget,
    QTableWidgetItem,
    QToolButton,
    QVBoxLayout,
    QWidget,
)
from scipy.spatial.transform import Rotation

from app.bindings import is_marked_invalid, mark_invalid
from app.fields import DecimalField, NumberField
from app.theme import active_theme
from gogreen_core.validation import ParameterError

__all__ = [
    "CollapsibleSection",
    "CompactNumberDelegate",
    "CompactTable",
    "EulerAnglesEditor",
    "FitStackedWidget",
    "NumberField",
    "PlotColors",
    "compact_number_text",
    "exact_number_text",
    "is_marked_invalid",
    "mark_invalid",
    "pastel_color",
    "plot_colors",
    "set_text_role",
    "zero_cell_colors",
]

#: Text roles of :func:`set_text_role` (their colours come from the theme's style sheet).
TEXT_ROLES = ("muted", "error")

_GOLDEN_RATIO_CONJUGATE = 0.618033988749895


def scrolled_column(panel: QWidget) -> QVBoxLayout:
    """Give ``panel`` a frameless vertically scrolling area; returns the column layout inside."""
    outer = QVBoxLayout(panel)
    outer.setContentsMargins(0, 0, 0, 0)
    scroll = QScrollArea()
    scroll.setWidgetResizable(True)
    scroll.setFrameShape(QFrame.Shape.NoFrame)
    scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
    outer.addWidget(scroll)
    content = QWidget()
    scroll.setWidget(content)
    layout = QVBoxLayout(content)
    layout.setContentsMargins(6, 6, 6, 6)
    layout.setSpacing(6)
    return layout


def set_text_role(label: QLabel, role: str) -> None:
    """Colour ``label``'s text as a ``"muted"`` caption or an ``"error"`` message, in the
    current theme's colours (the application style sheet of :mod:`app.theme` reads the
    ``text_role`` property, so the label follows a later theme switch)."""
    if role not in TEXT_ROLES:
        raise ParameterError("role", f"role: one of {', '.join(TEXT_ROLES)}, got {role!r}")
    label.setProperty("text_role", role)
    label.style().unpolish(label)
    label.style().polish(label)


@dataclass(frozen=True)
class PlotColors:
    """Colours of the panels' hand-drawn plots (falloff curves, modulus glyph, voxel cell)."""

    background: QColor
    frame: QColor
    grid: QColor
    axis: QColor
    text: QColor
    muted: QColor
    legend: QColor
    handle: QColor
    #: Whether curve colours are lightened for a dark background.
    dark: bool


def plot_colors() -> PlotColors:
    """The plot colours of the current theme: white paper on the light theme, the theme's
    field colour (dark) with light text on the dark one."""
    current = active_theme()
    if current.name == "light":
        values = ("#ffffff", "#b0b0b0", "#eeeeee", "#9e9e9e", "#222222", "#888888")
        legend, handle, dark = QColor(255, 255, 255, 225), QColor("#ffffff"), False
    else:
        values = (current.base, current.mid, "#2e3035", "#6c7078", current.text, current.muted_text)
        legend, handle, dark = QColor(current.base), QColor(current.base), True
        legend.setAlpha(225)
    background, frame, grid, axis, text, muted = (QColor(v) for v in values)
    return PlotColors(background, frame, grid, axis, text, muted, legend, handle, dark)


def zero_cell_colors() -> tuple[QColor, QColor]:
    """(background, text) of zero coefficients in the stiffness tables, from the theme."""
    current = active_theme()
    return QColor(current.zero_cell), QColor(current.muted_text)


def pastel_color(index: int, dark: bool | None = None) -> QColor:
    """A colour for group ``index`` (0, 1, 2, ...): hues spread by the golden ratio so that
    neighbouring indices differ strongly. Light pastels for dark text, or (``dark``, the
    default under the dark theme) deep tones for light text."""
    if dark is None:
        dark = active_theme().name == "dark"
    hue = (0.08 + index * _GOLDEN_RATIO_CONJUGATE) % 1.0
    if dark:
        saturation = 0.55 if index % 2 == 0 else 0.40
        r, g, b = colorsys.hsv_to_rgb(hue, saturation, 0.42)
    else:
        saturation = 0.38 if index % 2 == 0 else 0.26
        r, g, b = colorsys.hsv_to_rgb(hue, saturation, 0.98)
    return QColor.fromRgbF(r, g, b)


class CompactTable(QTableWidget):
    """A small table shown whole: as tall as its header plus rows (no vertical scrolling),
    columns stretched to the width. The height follows the actual font and style."""

    def __init__(
        self, rows: int, columns: int, row_height: int = 24, parent: QWidget | None = None
    ):
        super().__init__(rows, columns, parent)
        self.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeMode.Stretch)
        self.horizontalHeader().setMinimumSectionSize(36)
        self.verticalHeader().setSectionResizeMode(QHeaderView.ResizeMode.Fixed)
        self.verticalHeader().setDefaultSectionSize(row_height)
        self.setVerticalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)

    def cell(self, row: int, column: int) -> QTableWidgetItem:
        """The item at (row, column), which every cell of these tables has."""
        item = self.item(row, column)
        assert item is not None, (row, column)
        return item

    def _height(self) -> int:
        header = self.horizontalHeader()
        header_height = max(header.height(), header.sizeHint().height())
        return header_height + self.verticalHeader().length() + 2 * self.frameWidth()

    def sizeHint(self) -> QSize:
        return QSize(super().sizeHint().width(), self._height())

    def minimumSizeHint(self) -> QSize:
        return QSize(super().minimumSizeHint().width(), self._height())


def exact_number_text(value: float) -> str:
    """The shortest text that reads back as exactly ``value``: ``"0.40601234"``, ``"3"``
    (no ``.0``), ``"1e-07"``; -0.0 is ``"0"``."""
    text = repr(float(value) + 0.0)  # + 0.0 turns -0.0 into 0.0
    return text[:-2] if text.endswith(".0") else text


def compact_number_text(value: float, digits: int = 4) -> str:
    """``value`` rounded to ``digits`` significant digits, short exponents:
    ``compact_number_text(-1.5931234)`` is ``"-1.593"``, ``compact_number_text(2.1e11)`` is
    ``"2.1e11"``, ``compact_number_text(1e-5)`` is ``"1e-5"``."""
    text = f"{float(value) + 0.0:.{digits}g}"
    mantissa, exponent_mark, exponent = text.partition("e")
    return f"{mantissa}e{int(exponent)}" if exponent_mark else text


class CompactNumberDelegate(QStyledItemDelegate):
    """Item delegate for tables of numbers in a narrow panel: the items hold the exact text
    (:func:`exact_number_text`), which the editor opens with and :func:`float` reads back,
    while a cell shows ``digits`` significant digits (:func:`compact_number_text`), fewer
    (down to ``min_digits``) only when the column is too narrow for them, so that no value is
    cut to "0.406…". The editor is widened to its text, over the neighbouring cells if needed.
    Text that is not a number is shown as it is."""

    def __init__(self, digits: int = 4, min_digits: int = 2, parent: QWidget | None = None):
        super().__init__(parent)
        if not 1 <= min_digits <= digits:
            raise ValueError(f"need 1 <= min_digits <= digits (got {min_digits}, {digits})")
        self.digits = digits
        self.min_digits = min_digits

    def fitted_text(self, text: str, width: int, metrics: QFontMetrics) -> str:
        """What a cell ``width`` pixels wide (text area) shows for the item text ``text``."""
        try:
            value = float(text)
        except ValueError:
            return text
        if not math.isfinite(value):
            return text
        shown = text
        for digits in range(self.digits, self.min_digits - 1, -1):
            shown = compact_number_text(value, digits)
            if metrics.horizontalAdvance(shown) <= width:
                break
        return shown  # the view elides it if even min_digits do not fit

    @staticmethod
    def text_width(option: QStyleOptionViewItem) -> int:
        """Width of the text area of a cell drawn with ``option`` (the style's margins, as
        QCommonStyle lays out item text)."""
        style = option.widget.style() if option.widget is not None else None
        margin = 1 + (
            style.pixelMetric(QStyle.PixelMetric.PM_FocusFrameHMargin, None, option.widget)
            if style is not None
            else 2
        )
        return option.rect.width() - 2 * margin

    def initStyleOption(
        self, option: QStyleOptionViewItem, index: QModelIndex | QPersistentModelIndex
    ) -> None:
        super().initStyleOption(option, index)
        if option.features & QStyleOptionViewItem.ViewItemFeature.HasDisplay:
            option.text = self.fitted_text(option.text, self.text_width(option), option.fontMetrics)

    def updateEditorGeometry(
        self,
        editor: QWidget,
        option: QStyleOptionViewItem,
        index: QModelIndex | QPersistentModelIndex,
    ) -> None:
        super().updateEditorGeometry(editor, option, index)
        text = str(index.data(Qt.ItemDataRole.EditRole) or "")
        needed = editor.fontMetrics().horizontalAdvance(text + "00") + 8  # room for the caret
        rect = editor.geometry()
        if needed <= rect.width():
            return
        parent = editor.parentWidget()
        limit = parent.width() if parent is not None else needed
        rect.setWidth(min(needed, limit))
        if rect.right() >= limit:  # keep it inside the table: grow to the left
            rect.moveRight(limit - 1)
        rect.moveLeft(max(rect.left(), 0))
        editor.setGeometry(rect)


class FitStackedWidget(QStackedWidget):
    """A stacked widget as tall as its *current* page (QStackedWidget takes the largest)."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setSizePolicy(QSizePolicy.Policy.Preferred, QSizePolicy.Policy.Maximum)
        self.currentChanged.connect(lambda _index: self.updateGeometry())

    def sizeHint(self) -> QSize:
        page = self.currentWidget()
        return page.sizeHint() if page is not None else super().sizeHint()

    def minimumSizeHint(self) -> QSize:
        page = self.currentWidget()
        return page.minimumSizeHint() if page is not None else super().minimumSizeHint()


class CollapsibleSection(QWidget):
    """A titled section whose body folds away under an arrow button; the header can show a
    one-line summary of the body (e.g. the current angles) while folded."""

    def __init__(
        self, title: str, body: QWidget, expanded: bool = True, parent: QWidget | None = None
    ):
        super().__init__(parent)
        self._title = title
        self._summary = ""
        self.body = body
        self.toggle = QToolButton()
        self.toggle.setCheckable(True)
        self.toggle.setToolButtonStyle(Qt.ToolButtonStyle.ToolButtonTextBesideIcon)
        self.toggle.setAutoRaise(True)
        self.toggle.setStyleSheet("QToolButton { border: none; font-weight: bold; }")
        self.toggle.toggled.connect(self.set_expanded)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(2)
        layout.addWidget(self.toggle)
        layout.addWidget(body)
        self.toggle.setChecked(expanded)
        self.set_expanded(expanded)

    @property
    def expanded(self) -> bool:
        """Whether the body is shown."""
        return self.toggle.isChecked()

    def set_expanded(self, expanded: bool) -> None:
        """Show or fold the body."""
        if self.toggle.isChecked() != expanded:
            self.toggle.setChecked(expanded)  # re-enters through toggled
            return
        self.toggle.setArrowType(Qt.ArrowType.DownArrow if expanded else Qt.ArrowType.RightArrow)
        self.body.setVisible(expanded)
        self._update_text()

    def set_summary(self, summary: str) -> None:
        """Text shown after the title while the section is folded."""
        self._summary = summary
        self._update_text()

    def _update_text(self) -> None:
        folded = not self.toggle.isChecked() and self._summary
        self.toggle.setText(f"{self._title}   ({self._summary})" if folded else self._title)


class EulerAnglesEditor(QWidget):
    """Three Euler angles in degrees, each a slider plus a spin box.

    Convention: extrinsic rotations about the fixed x, y and z axes, in that order, so the
    rotation matrix is ``R = Rz(γ) · Ry(β) · Rx(α)`` (``Rotation.from_euler("xyz", ...)``).
    ``changed`` fires on every edit, live while a slider moves, once for :meth:`set_angles`;
    ``drag_finished`` when a slider is let go (:meth:`is_dragging` tells a drag's steps).
    """

    changed = Signal()
    drag_finished = Signal()

    AXES = ("x", "y", "z")
    SYMBOLS = ("α", "β", "γ")

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        layout = QGridLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setHorizontalSpacing(6)
        layout.setVerticalSpacing(2)
        self._setting = False  # set_angles is writing the spins: one `changed` at the end
        self.sliders: list[QSlider] = []
        self.spins: list[QDoubleSpinBox] = []
        for row, (axis, symbol) in enumerate(zip(self.AXES, self.SYMBOLS, strict=True)):
            label = QLabel(f"{symbol} about {axis}")
            slider = QSlider(Qt.Orientation.Horizontal)
            slider.setRange(-180, 180)
            slider.setPageStep(15)
            spin = DecimalField(-180.0, 180.0, 1, 5.0)
            spin.setSuffix("°")
            spin.setWrapping(True)
            spin.setMinimumWidth(72)
            spin.setAccessibleName(f"{symbol} about {axis}")
            tip = f"Rotation of the material axes about the fixed {axis} axis, degrees"
            for widget in (label, slider, spin):
                widget.setToolTip(tip)
            # each follows the other; comparing the values ends the round trip
            slider.valueChanged.connect(lambda v, s=spin: self._slider_moved(s, v))
            spin.valueChanged.connect(lambda v, s=slider: self._spin_changed(s, v))
            slider.sliderReleased.connect(self.drag_finished)
            layout.addWidget(label, row, 0)
            layout.addWidget(slider, row, 1)
            layout.addWidget(spin, row, 2)
            self.sliders.append(slider)
            self.spins.append(spin)
        layout.setColumnStretch(1, 1)

    def _slider_moved(self, spin: QDoubleSpinBox, value: int) -> None:
        if round(spin.value()) != value:
            spin.setValue(float(value))  # emits through _spin_changed

    def _spin_changed(self, slider: QSlider, value: float) -> None:
        if slider.value() != round(value):
            slider.setValue(round(value))  # its change finds the spin at the value already
        if not self._setting:
            self.changed.emit()

    def is_dragging(self) -> bool:
        """A slider is held (its edits are the steps of one drag)."""
        return any(slider.isSliderDown() for slider in self.sliders)

    @property
    def angles(self) -> tuple[float, float, float]:
        """(α, β, γ) in degrees."""
        a, b, c = (spin.value() for spin in self.spins)
        return a, b, c

    def set_angles(self, angles: tuple[float, float, float], emit: bool = True) -> None:
        """Set the three angles (degrees); emits ``changed`` once if ``emit`` and they
        changed."""
        before = self.angles
        self._setting = True
        try:
            for spin, value in zip(self.spins, angles, strict=True):
                spin.setValue(float(value))
        finally:
            self._setting = False
        if emit and self.angles != before:
            self.changed.emit()

    def summary(self) -> str:
        """The angles as short text, e.g. "α 0°, β 30°, γ 0°"."""
        return ", ".join(
            f"{symbol} {angle:g}°" for symbol, angle in zip(self.SYMBOLS, self.angles, strict=True)
        )

    def is_identity(self) -> bool:
        """True when all three angles are zero."""
        return all(math.isclose(a, 0.0, abs_tol=1e-12) for a in self.angles)

    def rotation_matrix(self) -> np.ndarray:
        """The (3, 3) proper rotation ``Rz(γ) Ry(β) Rx(α)``."""
        return Rotation.from_euler("xyz", self.angles, degrees=True).as_matrix()
