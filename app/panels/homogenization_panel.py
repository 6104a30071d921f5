"""Homogenization panel: design an anisotropic material from a periodic two-phase pattern.

The artist picks a pattern family of :data:`gogreen_core.PATTERNS` (widgets are generated from
its :class:`~gogreen_core.PatternParameter` list), the base isotropic phase a (E, ν) and the
stiffness contrast E_b / E_a of phase b (:func:`gogreen_core.bimaterial`). "Compute" runs
:func:`gogreen_core.homogenize_detailed` off the GUI thread through
:class:`app.background.BackgroundRunner` (progress reaches the bar through a queued signal); a
newer request supersedes an older one, which stops at its next progress report. The result,
optionally rotated by Euler angles (:meth:`gogreen_core.Material.rotated`), is shown as its
6×6 Voigt matrix with equal coefficients sharing a colour
(:func:`gogreen_core.describe_symmetry`) and the symmetry class.
"Use this material" emits ``material_ready(Material)``.

Every input widget is bound through :mod:`app.bindings` to the panel's
:class:`HomogenizationInputs`, which never holds an invalid input: a pattern parameter, phase
or contrast the core refuses is marked red with the reason and the computation uses the inputs
in effect.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtGui import QCloseEvent, QColor, QFont
from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QFormLayout,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QProgressBar,
    QPushButton,
    QSlider,
    QVBoxLayout,
    QWidget,
)

from app.background import BackgroundRunner, Task
from app.bindings import bind, bind_check, bind_choice, bind_spin, bind_view
from app.fields import DecimalField, IntegerField
from app.panels.homogenization_inputs import CELL_SIZE, HomogenizationInputs
from app.panels.material_form import rotation_matrix
from app.panels.stiffness_table import StiffnessTable
from app.panels.voxel_preview import PHASE_B_COLOR, SlicePreview, VoxelPreview
from app.panels.widgets import (
    CollapsibleSection,
    EulerAnglesEditor,
    NumberField,
    scrolled_column,
    set_text_role,
)
from gogreen_core import (
    PATTERNS,
    HomogenizationResult,
    Material,
    SymmetryDescription,
    bimaterial,
    describe_symmetry,
    homogenize_detailed,
)
from gogreen_core.interaction.settings import Changes
from gogreen_core.physics.material_words import describe_material

__all__ = ["CELL_SIZE", "HomogenizationInputs", "HomogenizationPanel"]
_VOIGT_LABELS = ("11", "22", "33", "23", "13", "12")
_CONTRAST_RANGE = (1.0, 1.0e4)
_SLIDER_STEPS_PER_DECADE = 100
_AUTO_DELAY_MS = 250


def _slider_position(contrast: float) -> int:
    """The logarithmic contrast slider's position of ``contrast``."""
    position = math.log10(max(contrast, _CONTRAST_RANGE[0]) / _CONTRAST_RANGE[0])
    return round(position * _SLIDER_STEPS_PER_DECADE)


def _slider_contrast(position: int) -> float:
    """The contrast at slider ``position``, to 3 significant digits (a tidy number)."""
    return float(f"{_CONTRAST_RANGE[0] * 10.0 ** (position / _SLIDER_STEPS_PER_DECADE):.3g}")


class HomogenizationPanel(QWidget):
    """Build an anisotropic Material by homogenizing a two-phase voxel pattern.

    Parameters
    ----------
    parent : QWidget, optional

    Signals
    -------
    material_ready(Material) : "Use this material" was pressed (the rotated result).
    result_ready(Material) : a computation finished (or the rotation of a result changed).
    computation_failed(str) : a computation raised; the message is also shown in the panel.
    busy_changed(bool) : a computation started (True) or the last one ended (False).

    With "Auto" checked (the default) the pattern is homogenized shortly (250 ms) after the
    panel is created and after every change of the inputs; a rotation only re-rotates the last
    result.

    Main widgets (public for scripting and tests): ``pattern_combo``, ``parameter_widgets``
    (name -> QDoubleSpinBox / QSpinBox / QComboBox), ``young_field``, ``poisson_field``,
    ``contrast_field``, ``contrast_slider``, ``rotation``, ``compute_button``,
    ``auto_compute_check``, ``progress_bar``, ``error_label``, ``status_label``,
    ``result_table``, ``symmetry_label``, ``words_label`` (what the result does, in words),
    ``use_button``, ``voxel_view``, ``slice_view``.
    """

    material_ready = Signal(object)
    result_ready = Signal(object)
    computation_failed = Signal(str)
    busy_changed = Signal(bool)

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        #: What the inputs hold (every input widget is bound to it).
        self.inputs = HomogenizationInputs()
        self._phases = self.inputs.phases
        self._detailed: HomogenizationResult | None = None
        self._result_key: tuple | None = None
        self._result: Material | None = None
        self._symmetry: SymmetryDescription | None = None
        self._runner = BackgroundRunner(self)
        self._runner.progress.connect(self._job_progress)
        self._runner.finished.connect(self._job_finished)
        self._runner.failed.connect(self._job_failed)
        self._job: int | None = None  # id of the request whose result is wanted
        self._pending: tuple | None = None  # key of the request in flight
        self._auto_timer = QTimer(self)
        self._auto_timer.setSingleShot(True)
        self._auto_timer.setInterval(_AUTO_DELAY_MS)
        self._auto_timer.timeout.connect(self.compute)
        self.parameter_widgets: dict[str, QWidget] = {}

        layout = scrolled_column(self)
        layout.addWidget(self._pattern_group())
        layout.addWidget(self._phase_group())
        rotation = self._rotation_group()
        layout.addLayout(self._compute_row())
        layout.addWidget(self._result_group())
        # last: unfolding it adds its fields below everything else, so nothing moves under
        # the pointer (above the result it pushed the fields aimed at away)
        layout.addWidget(rotation)
        layout.addStretch(1)

        self._bind()
        self.inputs.events.changed.connect(self._inputs_changed)
        self._show_pattern()
        self._inputs_changed(Changes(frozenset(self.inputs.fields)))

    # -- construction ------------------------------------------------------------------------
    def _pattern_group(self) -> QGroupBox:
        box = QGroupBox("Pattern (periodic cell, 16³ voxels)")
        layout = QVBoxLayout(box)
        layout.setContentsMargins(6, 4, 6, 6)
        self.pattern_combo = QComboBox()
        for name, spec in PATTERNS.items():
            self.pattern_combo.addItem(name.capitalize(), name)
            self.pattern_combo.setItemData(
                self.pattern_combo.count() - 1, spec.description, Qt.ItemDataRole.ToolTipRole
            )
        layout.addWidget(self.pattern_combo)
        self.description_label = QLabel()
        self.description_label.setWordWrap(True)
        set_text_role(self.description_label, "muted")
        layout.addWidget(self.description_label)
        self._parameter_host = QWidget()
        self._parameter_form = QFormLayout(self._parameter_host)
        self._parameter_form.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self._parameter_host)

        preview = QHBoxLayout()
        self.voxel_view = VoxelPreview()
        preview.addWidget(self.voxel_view, 3)
        slices = QVBoxLayout()
        self.slice_view = SlicePreview(vertical=True)
        slices.addWidget(self.slice_view)
        self.slice_slider = QSlider(Qt.Orientation.Horizontal)
        self.slice_slider.setRange(0, CELL_SIZE - 1)
        self.slice_slider.setToolTip("Depth of the three slices (voxel index)")
        slices.addWidget(self.slice_slider)
        preview.addLayout(slices, 2)
        layout.addLayout(preview)
        legend = QLabel(
            f"<span style='color:{PHASE_B_COLOR.name()}'>■</span> phase b (stiff)"
            "&nbsp;&nbsp;<span style='color:#b9c6d6'>■</span> phase a (matrix)"
        )
        set_text_role(legend, "muted")
        layout.addWidget(legend)
        return box

    def _phase_group(self) -> QGroupBox:
        box = QGroupBox("Phases")
        grid = QGridLayout(box)
        grid.setContentsMargins(6, 4, 6, 6)
        grid.setHorizontalSpacing(6)
        self.young_field = NumberField(1.0, 1e-12, 1e300, tooltip="Young's modulus of phase a")
        self.poisson_field = NumberField(
            0.3, -10.0, 10.0, tooltip="Poisson ratio of both phases, -1 < ν < 1/2"
        )
        grid.addWidget(QLabel("E of phase a"), 0, 0)
        grid.addWidget(self.young_field, 0, 1)
        grid.addWidget(QLabel("ν"), 0, 2, alignment=Qt.AlignmentFlag.AlignRight)
        grid.addWidget(self.poisson_field, 0, 3)
        grid.addWidget(QLabel("Contrast E_b/E_a"), 1, 0)
        row = QHBoxLayout()
        self.contrast_slider = QSlider(Qt.Orientation.Horizontal)
        decades = math.log10(_CONTRAST_RANGE[1] / _CONTRAST_RANGE[0])
        self.contrast_slider.setRange(0, round(decades * _SLIDER_STEPS_PER_DECADE))
        self.contrast_slider.setToolTip("Stiffness contrast, logarithmic 1 … 10 000")
        self.contrast_field = NumberField(100.0, *_CONTRAST_RANGE, digits=5)
        self.contrast_field.setToolTip("Stiffness contrast E_b / E_a in [1, 10 000]")
        row.addWidget(self.contrast_slider, 1)
        grid.addLayout(row, 1, 1, 1, 2)
        grid.addWidget(self.contrast_field, 1, 3)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(3, 1)
        return box

    def _rotation_group(self) -> CollapsibleSection:
        self.rotation = EulerAnglesEditor()
        self.rotation.setContentsMargins(12, 0, 0, 0)
        section = CollapsibleSection("Rotate the result", self.rotation, expanded=False)
        section.setToolTip(
            "Euler angles: extrinsic rotations about the fixed x, then y, then z axes, "
            "R = Rz(γ) Ry(β) Rx(α)"
        )
        section.set_summary(self.rotation.summary())
        self.rotation_section = section
        return section

    def _compute_row(self) -> QVBoxLayout:
        column = QVBoxLayout()
        row = QHBoxLayout()
        self.compute_button = QPushButton("Compute")
        self.compute_button.setToolTip("Homogenize the pattern (runs in the background)")
        self.compute_button.clicked.connect(self.compute)
        self.auto_compute_check = QCheckBox("Auto")
        self.auto_compute_check.setToolTip("Recompute shortly after every change")
        self.progress_bar = QProgressBar()
        self.progress_bar.setRange(0, 1000)
        self.progress_bar.setValue(0)
        self.progress_bar.setTextVisible(False)
        self.progress_bar.setMaximumHeight(14)
        # "Use this material" under Compute: in sight at the default window size (below the
        # result table it was under the fold)
        self.use_button = QPushButton("Use this material")
        self.use_button.setToolTip("Send the effective material to the Material panel and brushes")
        self.use_button.setEnabled(False)
        self.use_button.clicked.connect(self.use_material)
        row.addWidget(self.compute_button)
        row.addWidget(self.auto_compute_check)
        row.addWidget(self.progress_bar, 1)
        column.addLayout(row)
        use_row = QHBoxLayout()
        use_row.addWidget(self.use_button)
        use_row.addStretch(1)
        column.addLayout(use_row)
        self.error_label = QLabel()
        self.error_label.setWordWrap(True)
        set_text_role(self.error_label, "error")
        self.error_label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.error_label.hide()
        column.addWidget(self.error_label)
        return column

    def _result_group(self) -> QGroupBox:
        box = QGroupBox("Effective stiffness (Voigt 6×6)")
        layout = QVBoxLayout(box)
        layout.setContentsMargins(6, 4, 6, 6)
        self.symmetry_label = QLabel("Press Compute to homogenize the pattern.")
        self.symmetry_label.setWordWrap(True)
        #: What the result does under a brush, in words (fibres / layers, stiffer along…).
        self.words_label = QLabel()
        self.words_label.setWordWrap(True)
        bold = QFont(self.symmetry_label.font())
        bold.setBold(True)
        self.symmetry_label.setFont(bold)
        layout.addWidget(self.symmetry_label)
        layout.addWidget(self.words_label)
        table = StiffnessTable()
        self.result_table = table
        layout.addWidget(table)
        self.status_label = QLabel()
        self.status_label.setWordWrap(True)
        set_text_role(self.status_label, "muted")
        layout.addWidget(self.status_label)
        return box

    def _bind(self) -> None:
        """Every input widget to its field of :attr:`inputs`."""
        inputs, slider, rotation = self.inputs, self.contrast_slider, self.rotation
        bind_choice(inputs, "pattern", self.pattern_combo, label="Pattern")
        bind_view(inputs, "pattern", self._parameter_host, self._rebuild_parameter_widgets)
        bind_spin(inputs, "young", self.young_field, "E of phase a")
        bind_spin(inputs, "poisson", self.poisson_field, "ν")
        bind_spin(inputs, "contrast", self.contrast_field, "Contrast E_b/E_a")
        bind(
            inputs,
            "contrast",
            slider,
            lambda contrast: slider.setValue(_slider_position(contrast)),
            slider.valueChanged,
            _slider_contrast,
            label="Contrast E_b/E_a",
        )
        bind(
            inputs,
            "angles",
            rotation,
            rotation.set_angles,
            rotation.changed,
            lambda: rotation.angles,
            label="Rotation",
        )
        bind_check(inputs, "auto", self.auto_compute_check)
        slices = self.slice_slider
        bind(inputs, "slice", slices, slices.setValue, slices.valueChanged, label="Slice")
        bind_view(inputs, "slice", self.slice_view, self.slice_view.set_index)
        voxels = self.voxel_view
        bind_view(inputs, "angles", voxels, lambda a: voxels.set_rotation(rotation_matrix(a)))

    def _rebuild_parameter_widgets(self, name: str) -> None:
        """The widgets of pattern ``name``'s parameters, each bound to its entry of
        ``inputs.parameters``."""
        while self._parameter_form.rowCount():
            self._parameter_form.removeRow(0)  # deletes the widgets: their bindings end
        self.parameter_widgets = {}
        for param in PATTERNS[name].parameters:
            widget = self._parameter_widget(param)
            label = QLabel(param.name.capitalize())
            label.setToolTip(param.description)
            widget.setToolTip(param.description)
            self._parameter_form.addRow(label, widget)
            self.parameter_widgets[param.name] = widget

    def _parameter_widget(self, param: Any) -> QWidget:
        inputs, key = self.inputs, param.name

        def entry(value: Any) -> dict[str, Any]:
            return {**inputs.parameters, key: value}

        widget: QComboBox | IntegerField | DecimalField
        if param.kind == "choice":
            widget = combo = QComboBox()
            for choice in param.choices:
                combo.addItem(str(choice), choice)
            bind(
                inputs,
                "parameters",
                combo,
                lambda values: combo.setCurrentIndex(combo.findData(values[key])),
                combo.currentIndexChanged,
                lambda index: entry(combo.itemData(index)),
                label=key.capitalize(),
            )
            return widget
        if param.kind == "int":
            widget = IntegerField(int(param.low), int(param.high))
        else:
            low, high = float(param.low), float(param.high)
            widget = DecimalField(low, high, 3, 0.05 if high - low >= 0.5 else 0.01)
        spin = widget
        bind(
            inputs,
            "parameters",
            spin,
            lambda values: spin.setValue(values[key]),
            spin.valueChanged,
            entry,
            label=key.capitalize(),
        )
        return widget

    # -- public API --------------------------------------------------------------------------
    @property
    def pattern_name(self) -> str:
        """Key of the selected pattern in :data:`gogreen_core.PATTERNS`."""
        return self.inputs.pattern

    def pattern_parameters(self) -> dict[str, Any]:
        """Current values of the selected pattern's parameters."""
        return dict(self.inputs.parameters)

    def set_pattern(self, name: str, **params: Any) -> None:
        """Select pattern ``name`` and set some of its parameters (others keep defaults)."""
        if name not in PATTERNS:
            raise ValueError(f"unknown pattern {name!r}; choose one of {list(PATTERNS)}")
        defaults = {p.name: p.default for p in PATTERNS[name].parameters}
        unknown = set(params) - set(defaults)
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)} for pattern {name!r}")
        self.inputs.update({"pattern": name, "parameters": {**defaults, **params}})

    @property
    def phases(self) -> np.ndarray:
        """The current (16, 16, 16) 0/1 cell (a copy)."""
        return self._phases.copy()

    @property
    def contrast(self) -> float:
        """Stiffness contrast E_b / E_a."""
        return self.inputs.contrast

    def set_contrast(self, contrast: float) -> None:
        """Set the stiffness contrast (clamped to [1, 1e4])."""
        self.inputs.contrast = min(max(float(contrast), _CONTRAST_RANGE[0]), _CONTRAST_RANGE[1])

    @property
    def result(self) -> Material | None:
        """The displayed effective material (rotation applied), or None."""
        return self._result

    @property
    def unrotated_result(self) -> Material | None:
        """The effective material in the axes of the grid, or None."""
        return None if self._detailed is None else self._detailed.material

    @property
    def symmetry(self) -> SymmetryDescription | None:
        """Symmetry description of the displayed matrix, or None."""
        return self._symmetry

    @property
    def is_busy(self) -> bool:
        """Whether a computation is running or queued."""
        return self._pending is not None

    @property
    def is_stale(self) -> bool:
        """Whether the inputs changed since the displayed result was computed."""
        return self._result is None or self._result_key != self._inputs_key()

    def cell_color(self, row: int, col: int) -> QColor:
        """Background colour of result cell (row, col)."""
        return self.result_table.cell_color(row, col)

    def compute(self) -> None:
        """Homogenize the current pattern in the background (supersedes a running request).

        Unchanged inputs reuse the last result (only the rotation is reapplied).
        """
        self._auto_timer.stop()
        inputs = self.inputs
        materials = bimaterial(inputs.young, inputs.poisson, inputs.contrast)  # valid inputs
        key = self._inputs_key()
        if self._detailed is not None and key == self._result_key:
            self._runner.cancel()  # drop any request in flight
            self._job = None
            self._set_pending(None)
            self._display()
            return
        phases = self._phases.copy()

        def solve(task: Task) -> HomogenizationResult:
            # looked up at call time, so tests can substitute the solver
            return homogenize_detailed(phases, materials, task.progress)

        self._job = self._runner.submit(solve, supersede=True)
        self._set_pending(key)
        self.progress_bar.setValue(0)
        self._hide_error()

    def cancel(self) -> None:
        """Abandon any computation in flight (it stops at its next progress report)."""
        self._auto_timer.stop()
        self._runner.cancel()
        self._job = None
        self._set_pending(None)

    def wait_for_idle(self, msecs: int = 30000) -> bool:
        """Block until the worker thread is idle (for shutdown and tests)."""
        return self._runner.wait(msecs)

    def use_material(self) -> None:
        """Emit ``material_ready`` with the displayed result."""
        if self._result is not None:
            self.material_ready.emit(self._result)

    def closeEvent(self, event: QCloseEvent) -> None:
        self.cancel()
        self._runner.wait(5000)
        super().closeEvent(event)

    # -- inputs ------------------------------------------------------------------------------
    def _inputs_key(self) -> tuple:
        inputs = self.inputs
        params = tuple(sorted(inputs.parameters.items()))
        return (inputs.pattern, params, inputs.young, inputs.poisson, inputs.contrast)

    def _inputs_changed(self, changes: Changes) -> None:
        names = changes.names
        if names & {"pattern", "parameters"}:
            self._show_pattern()
        if names & {"pattern", "parameters", "young", "poisson", "contrast", "auto"}:
            self._update_stale_state()
            if self.inputs.auto and self.is_stale:
                self._auto_timer.start()
            elif not self.inputs.auto:
                self._auto_timer.stop()
        if "angles" in names:
            self.rotation_section.set_summary(self.rotation.summary())
            if self._detailed is not None:
                self._display()

    def _show_pattern(self) -> None:
        """The cell of the current pattern in the previews, its description above them."""
        self._phases = self.inputs.phases
        self.description_label.setText(PATTERNS[self.inputs.pattern].description)
        self.voxel_view.set_phases(self._phases)
        self.slice_view.set_phases(self._phases)
        self.slice_view.set_index(self.inputs.slice)

    # -- worker results ----------------------------------------------------------------------
    def _set_pending(self, key: tuple | None) -> None:
        was_busy = self._pending is not None
        self._pending = key
        busy = key is not None
        if busy != was_busy:
            self.busy_changed.emit(busy)

    def _job_progress(self, job: int, fraction: float) -> None:
        if job == self._job:
            self.progress_bar.setValue(round(1000 * fraction))

    def _job_finished(self, job: int, result: HomogenizationResult) -> None:
        if job != self._job or self._pending is None:
            return
        self._job = None
        self._detailed = result
        self._result_key = self._pending
        self._set_pending(None)
        self.progress_bar.setValue(1000)
        self._display()

    def _job_failed(self, job: int, exc: Exception) -> None:
        if job != self._job:
            return
        self._job = None
        message = f"{type(exc).__name__}: {exc}"
        self._set_pending(None)
        self.progress_bar.setValue(0)
        self._show_error(f"Homogenization failed: {message}")
        self.computation_failed.emit(message)

    def refresh_colors(self) -> None:
        """Re-colour the result cells in the current theme (after a theme switch)."""
        self.result_table.refresh_colors()

    # -- display -----------------------------------------------------------------------------
    def _display(self) -> None:
        assert self._detailed is not None
        base = self._detailed.material
        rotated = not self.rotation.is_identity()
        material = base.rotated(self.rotation.rotation_matrix()) if rotated else base
        symmetry = describe_symmetry(material)
        self._result, self._symmetry = material, symmetry
        self.result_table.show_material(material, symmetry)
        text = f"Symmetry: {self._class_text(symmetry)}"
        if rotated:
            text += f"  (pattern axes: {self._class_text(describe_symmetry(base))})"
        self.symmetry_label.setText(text)
        self.words_label.setText(describe_material(material))
        d = self._detailed
        iterations = "1 iteration" if d.iterations == 1 else f"{d.iterations} iterations"
        self.status_label.setText(
            f"{symmetry.group_count} distinct coefficients (colours) · grey = 0\n"
            f"phase b {100 * d.fraction_b:.1f} % · {iterations} · {1000 * d.seconds:.0f} ms"
        )
        self._update_stale_state()
        self.result_ready.emit(material)

    @staticmethod
    def _class_text(symmetry: SymmetryDescription) -> str:
        if symmetry.axis:
            return f"{symmetry.symmetry_class} about {symmetry.axis}"
        return symmetry.symmetry_class

    def _update_stale_state(self) -> None:
        stale = self.is_stale
        self.use_button.setEnabled(not stale)
        self.result_table.setEnabled(not stale)
        if self._result is not None and stale:
            self.use_button.setToolTip("The inputs changed: compute again first")
        else:
            self.use_button.setToolTip(
                "Send the effective material to the Material panel and brushes"
            )

    def _show_error(self, message: str) -> None:
        self.error_label.setText(message)
        self.error_label.show()

    def _hide_error(self) -> None:
        self.error_label.clear()
        self.error_label.hide()
