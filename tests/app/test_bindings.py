"""Widgets bound to evented models (app.bindings): both ways, refusals in the panel's words,
refresh after undo, drags as continued edits, and no signal blocking anywhere else."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shiboken6
from PySide6.QtGui import QColor, QPalette, QSurface
from PySide6.QtWidgets import QComboBox, QDoubleSpinBox, QLabel, QLineEdit, QSlider, QSpinBox

from app.bindings import (
    bind,
    bind_check,
    bind_choice,
    bind_readout,
    bind_spin,
    bindings_of,
    line_edit,
    mark_invalid,
    panel_words,
    refresh,
)
from app.panels.number_grid import NumberGrid
from app.panels.widgets import is_marked_invalid
from app.theme import active_theme
from gogreen_core.interaction.settings import (
    BrushSettings,
    EventedModel,
    Field,
    PenSettings,
    Settings,
)

ROOT = Path(__file__).resolve().parents[2]


class Weights(EventedModel):
    """A model with an array field."""

    values = Field(lambda: np.ones(9), lambda model, name, value: np.array(value, dtype=float))


def test_a_spin_box_follows_the_model_and_edits_it(qtbot):
    brush = BrushSettings()
    spin = QDoubleSpinBox()
    qtbot.addWidget(spin)
    spin.setRange(0.001, 5.0)
    spin.setDecimals(3)
    bind_spin(brush, "radius", spin, "Radius")
    assert spin.value() == pytest.approx(brush.radius)
    brush.radius = 0.25
    assert spin.value() == 0.25
    events = []
    brush.events.radius.connect(events.append)
    spin.setValue(0.5)
    assert brush.radius == 0.5 and len(events) == 1  # one change, no echo back


def test_a_refused_value_is_named_as_the_panel_names_it_and_reverts(qtbot):
    brush = BrushSettings()
    spin = QDoubleSpinBox()
    qtbot.addWidget(spin)
    spin.setRange(-5.0, 5.0)
    binding = bind_spin(brush, "radius", spin, "Radius")
    before = brush.radius
    spin.setValue(-0.5)  # the brush refuses a negative radius
    assert brush.radius == before
    assert is_marked_invalid(spin) and spin.value() == -0.5  # shown until the focus leaves
    assert binding.refused is not None and binding.refused.startswith("Radius")
    assert "brush.radius" not in spin.toolTip() and "Radius" in spin.toolTip()
    refresh(brush)  # e.g. after undo: the value in effect, the mark gone
    assert spin.value() == before and not is_marked_invalid(spin)
    spin.setValue(-1.0)
    other = QDoubleSpinBox()
    qtbot.addWidget(other)
    other.setRange(0.0, 100.0)
    bind_spin(brush, "strength", other, "Strength")
    other.setValue(2.0)  # another edit of the model succeeds: the refused one reverts
    assert spin.value() == before and not is_marked_invalid(spin)


def test_check_choice_readout_and_a_grid(qtbot):
    pen = PenSettings()
    from PySide6.QtWidgets import QCheckBox

    check = QCheckBox()
    combo = QComboBox()
    label = QLabel()
    grid = NumberGrid(lambda l: f"l {l}", (-100.0, 100.0))
    for widget in (check, combo, label, grid):
        qtbot.addWidget(widget)
    bind_check(pen, "pressure_radius", check)
    pen.pressure_radius = True
    assert check.isChecked()
    check.setChecked(False)
    assert pen.pressure_radius is False
    values = [0.0, 10.0, 25.0]
    for value in values:
        combo.addItem(f"{value:g} px")
    bind_choice(pen, "lazy_radius", combo, lambda: values, "Lazy")
    combo.setCurrentIndex(2)
    assert pen.lazy_radius == 25.0
    pen.lazy_radius = 10.0
    assert combo.currentIndex() == 1
    bind_readout(pen, "spacing", label, "{:.2f} ε".format)
    pen.spacing = 0.5
    assert label.text() == "0.50 ε"
    weights = Weights()
    bind(weights, "values", grid, grid.set_values, grid.edited)
    assert len(grid.spins) == 9
    grid.spins[2].setValue(3.5)
    assert weights.values[2] == 3.5
    weights.values = np.ones(5)  # fewer entries: fewer fields
    assert len(grid.spins) == 5
    np.testing.assert_array_equal(grid.values, weights.values)


def test_a_drag_is_one_first_step_then_continued_ones(qtbot):
    settings = Settings()
    slider = QSlider()
    qtbot.addWidget(slider)
    slider.setRange(0, 20)
    bind(
        settings,
        "l_max",
        slider,
        slider.setValue,
        slider.valueChanged,
        dragging=slider.isSliderDown,
        drag_ended=slider.sliderReleased,
    )
    changes = []
    settings.events.changed.connect(changes.append)
    for _ in range(2):  # two drags
        slider.setSliderDown(True)
        for value in (3, 4, 5):
            slider.setValue(value if not changes else value + 6)
        slider.setSliderDown(False)
    assert [c.continued for c in changes] == [False, True, True] * 2


def test_a_binding_ends_with_its_widget(qtbot):
    brush = BrushSettings()
    spin = QSpinBox()
    bind_spin(brush, "substeps", spin, "Steps")
    listeners = len(brush.events.substeps)
    assert len(bindings_of(brush)) == 1
    spin.deleteLater()
    qtbot.waitUntil(lambda: not bindings_of(brush))
    assert len(brush.events.substeps) == listeners - 1


def test_panel_words():
    assert (
        panel_words("poisson must lie in (-1, 1/2) (got 0.6)", {"poisson": "Poisson ratio ν"})
        == "Poisson ratio ν must lie in (-1, 1/2) (got 0.6)"
    )
    # the last dotted part too, whole words only
    assert (
        panel_words("brush.radius must be > 0", {"brush.radius": "Radius"}) == "Radius must be > 0"
    )
    assert panel_words("radiuses", {"radius": "Radius"}) == "radiuses"


def test_no_signal_is_blocked_by_hand_outside_the_bindings():
    offenders = []
    for path in sorted((ROOT / "app").rglob("*.py")):
        if path.name == "bindings.py":
            continue
        text = path.read_text(encoding="utf-8")
        if "blockSignals" in text or "QSignalBlocker" in text:
            offenders.append(path.relative_to(ROOT).as_posix())
    assert not offenders, f"signals blocked by hand (bind the widget instead): {offenders}"


def _stale_surface_over_line_edit(box: QDoubleSpinBox) -> None:
    """What a closed viewport leaves behind: PySide's wrapper of a deleted QSurface registered at
    the address of the box's line edit (Qt reused the memory)."""
    ptr = shiboken6.getCppPointer(box.lineEdit())[0]
    shiboken6.invalidate(box.lineEdit())
    stale = shiboken6.wrapInstance(ptr, QSurface)
    assert type(box.lineEdit()) is QSurface  # the state a new field would meet
    box._stale = stale  # kept alive as pyvistaqt keeps its surface


def test_line_edit_gets_past_a_stale_surface_wrapper(qtbot) -> None:
    box = QDoubleSpinBox()
    qtbot.addWidget(box)
    box.setValue(0.25)
    _stale_surface_over_line_edit(box)
    line = line_edit(box)
    assert isinstance(line, QLineEdit)
    assert line.text() == box.text()
    mark_invalid(box, True)  # reaches the line edit's palette, not the stale QSurface
    assert is_marked_invalid(box)
    assert line.palette().color(QPalette.ColorRole.Text) == QColor(active_theme().error_text)
