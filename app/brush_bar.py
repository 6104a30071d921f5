"""Brush toolbar: a view of the brush settings (kind, radius, strength, RK4 substeps,
influence, mirror symmetry) plus the constraint (pin) mode of the pointer tools.

The bar holds no brush of its own: every widget is bound to a field of
:class:`gogreen_core.interaction.settings.BrushSettings` (see :mod:`app.bindings`), so presets, the
wheel shortcuts and scripts that change the model show here, and edits here reach the model.
"""

from __future__ import annotations

import math
from functools import partial

from PySide6.QtCore import Signal
from PySide6.QtGui import QAction, QActionGroup, QKeySequence
from PySide6.QtWidgets import (
    QAbstractSpinBox,
    QDoubleSpinBox,
    QLabel,
    QSpinBox,
    QToolBar,
    QWidget,
)

from app.bindings import bind, bind_spin
from app.fields import DecimalField, IntegerField
from gogreen_core.interaction.settings import BrushSettings, PenSettings
from gogreen_core.sculpt.brushes import AUTO_INFLUENCE, BRUSH_KINDS, BRUSH_ROWS, Brush

__all__ = ["BRUSH_LABELS", "BrushBar"]

#: Toolbar text, shortcut and tooltip of each brush (from its row, :data:`BRUSH_ROWS`).
BRUSH_LABELS = {row.kind: (row.label, row.letter, row.tooltip) for row in BRUSH_ROWS}


class BrushBar(QToolBar):
    """Toolbar bound to a :class:`BrushSettings`; ``changed`` fires after each brush change.

    Parameters
    ----------
    settings : BrushSettings, optional (a private one when omitted, for standalone use)
    parent : QWidget, optional
    """

    changed = Signal()
    constraint_mode_changed = Signal(bool)

    def __init__(self, settings: BrushSettings | None = None, parent: QWidget | None = None):
        super().__init__("Brush", parent)
        self.setObjectName("brush_bar")
        self.settings = settings if settings is not None else BrushSettings()
        self._group = QActionGroup(self)
        self._group.setExclusive(True)
        self.kind_actions: dict[str, QAction] = {}
        for kind in BRUSH_KINDS:
            text, key, tip = BRUSH_LABELS[kind]
            action = QAction(text, self, checkable=True)
            action.setShortcut(QKeySequence(key))
            action.setToolTip(f"{tip}  [{key}]")
            action.setData(kind)
            self._group.addAction(action)
            self.addAction(action)
            self.kind_actions[kind] = action
        bind(
            self.settings,
            "kind",
            self._group,
            lambda kind: self.kind_actions[kind].setChecked(True),
            self._group.triggered,
            lambda action: action.data(),
        )
        self.addSeparator()

        self.radius = self._spin(
            "Radius", 0.005, 1.0, 3, 0.01, "ε as a fraction of the model size  [ ] / Ctrl+wheel"
        )
        bind_spin(self.settings, "radius", self.radius, "Radius")
        self.strength = self._spin(
            "Strength", 0.01, 10.0, 2, 0.1, "Brush strength  { } / Shift+wheel"
        )
        bind_spin(self.settings, "strength", self.strength, "Strength")
        self._label("Steps")
        self.substeps = IntegerField(0, 32)
        self.substeps.setSpecialValueText("auto")  # 0: adaptive, within 1e-4 of the cursor motion
        self.substeps.setToolTip(
            "RK4 steps per mouse event; auto: adaptive, within 1e-4 of the cursor motion"
        )
        self.addWidget(_compact(self.substeps))
        bind_spin(self.settings, "substeps", self.substeps, "Steps")
        self.influence = self._spin(
            "Influence",
            0.0,
            50.0,
            1,
            0.5,
            "Radius of the moved region in brush radii ε (vertices farther stay put; a smooth "
            "cutoff starts at half of it). auto: where the brush's own field has faded to a "
            "tenth, shown by the cursor's outer ring",
        )
        self.influence.setSpecialValueText("auto")  # 0: the field's own reach
        _compact(self.influence)
        bind(
            self.settings,
            "influence",
            self.influence,
            lambda value: self.influence.setValue(0.0 if value == AUTO_INFLUENCE else value),
            self.influence.valueChanged,
            lambda value: AUTO_INFLUENCE if value == 0.0 else value,
            label="Influence",
        )
        self.addSeparator()

        self.symmetry_actions: dict[str, QAction] = {}
        for axis in "xyz":
            action = QAction(axis.upper(), self, checkable=True)
            action.setToolTip(f"Mirror the brush across the {axis.upper()} plane of the model")
            self.addAction(action)
            self.symmetry_actions[axis] = action
            bind(
                self.settings,
                "symmetry",
                action,
                partial(self._show_axis, axis),
                action.toggled,
                lambda _on: "".join(
                    a for a, act in self.symmetry_actions.items() if act.isChecked()
                ),
            )
        self.addSeparator()
        self.constraint_action = QAction("Pin", self, checkable=True)
        self.constraint_action.setShortcut(QKeySequence("C"))
        self.constraint_action.setToolTip(
            "Constraint mode: click pins a point, dragging a pin moves it while the others stay [C]"
        )
        self.constraint_action.toggled.connect(self.constraint_mode_changed)
        self.addAction(self.constraint_action)
        self.pen: PenSettings | None = None
        emitter, callback = self.settings.events.changed, self._model_changed
        emitter.connect(callback)
        self.destroyed.connect(lambda *_: emitter.disconnect(callback))

    def _show_axis(self, axis: str, axes: str) -> None:
        self.symmetry_actions[axis].setChecked(axis in axes)

    def bind_pen(self, pen: PenSettings) -> None:
        """Add the pen controls bound to ``pen``: pressure → strength and pressure → radius
        toggles (as in Blender), the stabilizer's lazy radius (pixels) and event spacing (ε)."""
        self.pen = pen
        self.addSeparator()
        self.pressure_actions: dict[str, QAction] = {}
        for name, text, tip in (
            ("pressure_strength", "P→S", "Pen pressure scales the strength"),
            ("pressure_radius", "P→R", "Pen pressure scales the radius along the stroke"),
        ):
            action = QAction(text, self, checkable=True)
            action.setToolTip(tip)
            self.addAction(action)
            self.pressure_actions[name] = action
            bind(pen, name, action, action.setChecked, action.toggled, bool)
        self.lazy_radius = self._spin(
            "Lazy",
            0.0,
            500.0,
            0,
            5.0,
            "Stroke stabilizer: the brush trails the pen by this many pixels (0: off)",
        )
        bind_spin(pen, "lazy_radius", self.lazy_radius, "Lazy")
        self.spacing = self._spin(
            "Spacing",
            0.0,
            10.0,
            2,
            0.05,
            "Minimum brush motion between applied events, in brush radii ε (0: every event)",
        )
        bind_spin(pen, "spacing", self.spacing, "Spacing")

    def _label(self, text: str) -> None:
        label = QLabel(text)
        label.setContentsMargins(6, 0, 3, 0)  # the bar fits a 1600 px window with every brush
        self.addWidget(label)

    def _spin(self, label, low, high, decimals, step, tip) -> DecimalField:
        self._label(label)
        spin = DecimalField(low, high, decimals, step, tip)
        self.addWidget(_compact(spin))
        return spin

    def _model_changed(self, _changes) -> None:
        self.changed.emit()

    @property
    def constraint_mode(self) -> bool:
        return self.constraint_action.isChecked()

    @property
    def brush(self) -> Brush:
        """The brush of the settings the bar shows."""
        return self.settings.brush

    def set_brush(self, brush: Brush) -> None:
        """Give the settings ``brush`` (e.g. from a preset); the bar follows."""
        self.settings.set_brush(brush)

    def scale_radius(self, notches: int) -> None:
        self.settings.radius = _scaled(self.settings.radius, notches, self.radius)

    def scale_strength(self, notches: int) -> None:
        self.settings.strength = _scaled(self.settings.strength, notches, self.strength)


def _compact(spin: QAbstractSpinBox) -> QAbstractSpinBox:
    """``spin`` no wider than its longest text and its arrows need (Qt's own size hint adds
    room for a wider text than the field can hold)."""
    metrics = spin.fontMetrics()
    texts = [spin.specialValueText(), spin.text()]
    if isinstance(spin, QDoubleSpinBox):
        texts += [spin.textFromValue(spin.minimum()), spin.textFromValue(spin.maximum())]
    elif isinstance(spin, QSpinBox):
        texts += [str(spin.minimum()), str(spin.maximum())]
    widest = max(metrics.horizontalAdvance(text) for text in texts)
    spin.setMaximumWidth(widest + 34)  # the arrows, the frame and the text's margins
    return spin


def _scaled(value: float, notches: int, spin: QDoubleSpinBox) -> float:
    """``value`` times 1.1 per notch, within the spin box's range."""
    return min(max(value * math.pow(1.1, notches), spin.minimum()), spin.maximum())
