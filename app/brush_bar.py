"""Brush toolbar: brush kind, radius, strength, RK4 substeps, mirror symmetry, constraint mode."""

from __future__ import annotations

import math

from PySide6.QtCore import Signal
from PySide6.QtGui import QAction, QActionGroup, QKeySequence
from PySide6.QtWidgets import QDoubleSpinBox, QLabel, QSpinBox, QToolBar, QWidget

from gogreen_core.brushes import BRUSH_KINDS, Brush

__all__ = ["BRUSH_LABELS", "BrushBar"]

#: Toolbar text, shortcut and tooltip of each brush.
BRUSH_LABELS = {
    "grab": ("Grab", "G", "Grab: the point under the cursor follows the cursor"),
    "grab_biscale": ("Bi-scale", "B", "Bi-scale grab: sharper falloff (two radii)"),
    "grab_triscale": ("Tri-scale", "T", "Tri-scale grab: sharpest falloff (three radii)"),
    "scale": ("Scale", "S", "Scale: inflate (drag right) or deflate (drag left)"),
    "twist": ("Twist", "W", "Twist about the view axis: drag right or left"),
    "pinch": ("Pinch", "P", "Pinch: stretch along the drag, squeeze across"),
    "wrinkle": ("Wrinkle", "R", "Wrinkle: grab with reweighted SH degrees (Falloff panel)"),
}


class BrushBar(QToolBar):
    """Toolbar editing a :class:`gogreen_core.Brush`; ``changed`` fires on every edit."""

    changed = Signal()
    constraint_mode_changed = Signal(bool)

    def __init__(self, parent: QWidget | None = None):
        super().__init__("Brush", parent)
        self.setObjectName("brush_bar")
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
        self.kind_actions["grab"].setChecked(True)
        self._group.triggered.connect(lambda _a: self._edited())
        self.addSeparator()

        self.radius = self._spin(
            "Radius",
            0.005,
            1.0,
            0.08,
            3,
            0.01,
            "ε as a fraction of the model size  [ ] / Ctrl+wheel",
        )
        self.strength = self._spin(
            "Strength", 0.01, 10.0, 1.0, 2, 0.1, "Brush strength  { } / Shift+wheel"
        )
        self.addWidget(QLabel(" Substeps "))
        self.substeps = QSpinBox()
        self.substeps.setRange(1, 32)
        self.substeps.setValue(4)
        self.substeps.setToolTip("RK4 steps per mouse event")
        self.substeps.valueChanged.connect(self._edited)
        self.addWidget(self.substeps)
        self.addSeparator()

        self.symmetry_actions: dict[str, QAction] = {}
        for axis in "xyz":
            action = QAction(axis.upper(), self, checkable=True)
            action.setToolTip(f"Mirror the brush across the {axis.upper()} plane of the model")
            action.toggled.connect(self._edited)
            self.addAction(action)
            self.symmetry_actions[axis] = action
        self.addSeparator()
        self.constraint_action = QAction("Pin", self, checkable=True)
        self.constraint_action.setShortcut(QKeySequence("C"))
        self.constraint_action.setToolTip(
            "Constraint mode: click pins a point, dragging a pin moves it while the others stay [C]"
        )
        self.constraint_action.toggled.connect(self.constraint_mode_changed)
        self.addAction(self.constraint_action)

    def _spin(self, label, low, high, value, decimals, step, tip) -> QDoubleSpinBox:
        self.addWidget(QLabel(f" {label} "))
        spin = QDoubleSpinBox()
        spin.setRange(low, high)
        spin.setDecimals(decimals)
        spin.setSingleStep(step)
        spin.setValue(value)
        spin.setToolTip(tip)
        spin.valueChanged.connect(self._edited)
        self.addWidget(spin)
        return spin

    def _edited(self, *_args) -> None:
        self.changed.emit()

    @property
    def constraint_mode(self) -> bool:
        return self.constraint_action.isChecked()

    @property
    def brush(self) -> Brush:
        """The brush the bar shows."""
        kind = self._group.checkedAction().data()
        symmetry = "".join(a for a, act in self.symmetry_actions.items() if act.isChecked())
        return Brush(
            kind=kind,
            radius=self.radius.value(),
            strength=self.strength.value(),
            substeps=self.substeps.value(),
            symmetry=symmetry,
        )

    def set_brush(self, brush: Brush) -> None:
        """Show ``brush`` (e.g. from a preset)."""
        self.kind_actions[brush.kind].setChecked(True)
        self.radius.setValue(brush.radius)
        self.strength.setValue(brush.strength)
        self.substeps.setValue(brush.substeps)
        for axis, action in self.symmetry_actions.items():
            action.setChecked(axis in brush.symmetry)
        self.changed.emit()

    def scale_radius(self, notches: int) -> None:
        self.radius.setValue(self.radius.value() * math.pow(1.1, notches))

    def scale_strength(self, notches: int) -> None:
        self.strength.setValue(self.strength.value() * math.pow(1.1, notches))
