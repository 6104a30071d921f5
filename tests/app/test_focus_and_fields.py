"""Focus and keys, fields that never lie (issue 21, items 1, 2 and 4), with real Qt key and
mouse events sent where the keyboard focus is: the sculpting keys act on the viewport after any
panel button, menu or dialog; letters typed into a number field stay there and are refused
visibly, as is a value out of range, named as the panel names it and in the status bar; a
refused value stays, red, after the focus leaves, until mended or cancelled (Esc); every panel
shows the settings in effect after undo, redo, opening a model or a preset."""

from __future__ import annotations

import numpy as np
import pytest
from gui_helpers import activate
from PySide6.QtCore import QPoint, Qt, QTimer
from PySide6.QtGui import QColor, QPalette
from PySide6.QtTest import QTest
from PySide6.QtWidgets import (
    QAbstractButton,
    QAbstractSpinBox,
    QApplication,
    QMessageBox,
    QWidget,
)

from app.bindings import is_marked_invalid
from app.fields import DecimalField, IntegerField, NumberField
from app.panels.material_form import MODES
from app.theme import active_theme
from gogreen_core import Material


def focused() -> QWidget | None:
    return QApplication.focusWidget()


def press_key(key, text_modifiers=Qt.KeyboardModifier.NoModifier) -> None:
    """A key pressed on the keyboard: it goes where the focus is."""
    QTest.keyClick(focused(), key, text_modifiers)


def type_text(text: str) -> None:
    QTest.keyClicks(focused(), text)


def click(qtbot, widget: QWidget) -> None:
    """A left click in the middle of ``widget``, then the event loop turns."""
    qtbot.mouseClick(widget, Qt.MouseButton.LeftButton, pos=widget.rect().center())
    qtbot.wait(10)


def settings_in_effect(window) -> tuple:
    model = window.model
    return (
        model.material,
        model.l_max,
        model.falloff,
        tuple(model.brush_weights.items()),
        tuple(model.brush.values().items()),
        tuple(model.pen.values().items()),
        window.homogenization_panel.inputs.values().__repr__(),
    )


# -- focus -------------------------------------------------------------------------------------
def _panel_buttons(window) -> list[QAbstractButton]:
    buttons = []
    for panel in (window.material_panel, window.homogenization_panel, window.falloff_panel):
        buttons += [b for b in panel.findChildren(QAbstractButton) if b.isEnabled()]
    return buttons


def test_the_keys_go_back_to_the_viewport_after_each_panel_button(window, qtbot):
    activate(window, qtbot)
    window.homogenization_panel.inputs.auto = False
    clicked, names = 0, []
    for tab in range(window.panel_tabs.count()):
        window.panel_tabs.setCurrentIndex(tab)
        panel = window.panel_tabs.widget(tab)
        buttons = [b for b in panel.findChildren(QAbstractButton) if b.isEnabled()]
        for button in buttons:
            if not button.isVisible():
                continue
            field = window.brush_bar.radius  # the focus sits in a field before the click
            click(qtbot, field.lineEdit())
            assert field.hasFocus()
            click(qtbot, button)
            qtbot.waitUntil(window.viewport.hasFocus, timeout=2000)
            clicked += 1
            names.append(button.text())
        window.homogenization_panel.cancel()
    # every enabled button of the three panels: radio buttons, check boxes, push buttons
    assert clicked >= 12, names
    window.model.brush.kind = "grab"
    press_key(Qt.Key.Key_3)  # the tri-scale brush, not a 3 typed somewhere
    assert window.model.brush.kind == "grab_triscale"


def test_use_a_wrinkle_material_leaves_the_keys_to_the_viewport(window, qtbot):
    """The walkthrough's case: the button hides itself once used, and Qt moved the focus to
    the next field (Lazy); pressing 3 typed into it."""
    activate(window, qtbot)
    window.model.brush.kind = "wrinkle"
    button = window.wrinkle_fix_button
    qtbot.waitUntil(button.isVisible)
    click(qtbot, button)
    assert button.isHidden()
    qtbot.waitUntil(window.viewport.hasFocus, timeout=2000)
    lazy = window.model.pen.lazy_radius
    press_key(Qt.Key.Key_3)
    assert window.model.brush.kind == "grab_triscale" and window.model.pen.lazy_radius == lazy


def test_the_keys_go_back_to_the_viewport_after_a_menu_and_a_dialog(window, qtbot, monkeypatch):
    activate(window, qtbot)
    field = window.brush_bar.strength
    click(qtbot, field.lineEdit())
    assert field.hasFocus()
    # a menu opened from the keyboard and closed again
    menu = window.menuBar().actions()[1].menu()  # Edit
    QTimer.singleShot(100, menu.close)
    menu.exec(window.mapToGlobal(QPoint(40, 40)))
    qtbot.waitUntil(window.viewport.hasFocus, timeout=2000)
    # a real dialog (a message box) shown and closed
    click(qtbot, field.lineEdit())
    assert field.hasFocus()
    box = QMessageBox(QMessageBox.Icon.Information, "Note", "A dialog", parent=window)
    QTimer.singleShot(200, box.accept)
    box.exec()
    # (no window manager here to activate the window again: the focus it will give back)
    qtbot.waitUntil(lambda: window.focusWidget() is window.viewport, timeout=2000)
    activate(window, qtbot)
    assert window.viewport.hasFocus()
    press_key(Qt.Key.Key_2)
    assert window.model.brush.kind == "grab"  # key 2: the wide grab


# -- number fields -----------------------------------------------------------------------------
def _visible_fields(window) -> list[QAbstractSpinBox]:
    return [
        f
        for f in window.findChildren(QAbstractSpinBox)
        if f.isVisible() and f.isEnabled() and f.window() is window
    ]


def _show_every_field(window):
    """Yield once per arrangement of the panels that shows another set of fields."""
    material, homogenize = window.material_panel, window.homogenization_panel
    window.panel_tabs.setCurrentWidget(material)
    for mode in MODES:
        material.set_mode(mode)
        yield
        if mode == "isotropic":
            material.lame_radio.setChecked(True)
            yield
            material.lame_radio.setChecked(False)
    material.set_mode("isotropic")
    window.panel_tabs.setCurrentWidget(homogenize)
    homogenize.rotation_section.set_expanded(True)
    for pattern in ("layered", "fibers", "random"):
        homogenize.set_pattern(pattern)
        yield
    window.panel_tabs.setCurrentWidget(window.falloff_panel)
    yield


def _out_of_range(field: QAbstractSpinBox) -> str:
    if field.maximum() < 1e299:
        return f"{field.maximum() * 10 + 7:g}"
    return "1e400"  # no finite number is out of range: infinity is


def _refuses(window, qtbot, field, text: str) -> None:
    """Type ``text`` into ``field`` and press Enter: refused visibly, nothing changes."""
    before = settings_in_effect(window)
    value = field.value()
    click(qtbot, field.lineEdit())
    field.selectAll()
    type_text(text)
    press_key(Qt.Key.Key_Return)
    qtbot.wait(5)
    name = field.accessibleName()
    assert name, f"a field without a name: {field!r}"
    assert is_marked_invalid(field), (name, text)
    # what was typed is on screen, not replaced (a unit such as ° stays after it)
    assert field.lineEdit().text().removesuffix(field.suffix()) == text
    assert field.toolTip().startswith(f"{name}: enter"), field.toolTip()
    assert field.hasFocus()  # to be mended
    assert field.value() == value and settings_in_effect(window) == before, (name, text)


def test_letters_and_values_out_of_range_are_refused_in_every_number_field(window, qtbot):
    activate(window, qtbot)
    window.homogenization_panel.inputs.auto = False
    window.model.brush.kind = "grab"
    seen = set()
    for _ in _show_every_field(window):
        for field in _visible_fields(window):
            if id(field) in seen:
                continue
            seen.add(id(field))
            assert isinstance(field, (DecimalField, IntegerField, NumberField)), field
            for text in ("abc", _out_of_range(field)):
                _refuses(window, qtbot, field, text)
                # the letters did not reach the hotkeys: b is bi-scale, c is pin mode
                assert window.model.brush.kind == "grab"
                assert not window.brush_bar.constraint_action.isChecked()
                assert window.message_label.text() == f"Refused: {field.toolTip()}"
                press_key(Qt.Key.Key_Escape)  # cancelled: the value in effect again
                qtbot.wait(10)  # (and the keys go home)
                assert not is_marked_invalid(field)
                assert "Refused" not in window.message_label.text()  # said no more
                assert field.lineEdit().text() == field.textFromValue(field.value()) or (
                    field.lineEdit().text() in (field.specialValueText(), field.text())
                )
    assert len(seen) >= 40  # brush bar, every material page, homogenize, falloff


def test_radius_minus_half_and_l_max_99_say_the_allowed_range(window, qtbot):
    """The walkthrough's cases: −0.5 became 0.500, 99 became 9."""
    activate(window, qtbot)
    radius = window.brush_bar.radius
    _refuses(window, qtbot, radius, "-0.5")
    assert radius.toolTip() == "Radius: enter a number from 0.005 to 1 (got '-0.5')"
    # the refused text itself is red (the theme's error colour), not only the field's tint
    red = QColor(active_theme().error_text)
    assert radius.lineEdit().palette().color(QPalette.ColorRole.Text) == red
    window.panel_tabs.setCurrentWidget(window.falloff_panel)
    l_max = window.falloff_panel.l_max_spin
    _refuses(window, qtbot, l_max, "99")
    assert l_max.toolTip() == "Truncation l_max: enter a whole number from 0 to 30 (got '99')"
    # the radius refused before is still red, its text shown, after the focus went to l_max
    assert is_marked_invalid(radius) and radius.lineEdit().text() == "-0.5"
    assert window.message_label.text() == f"Refused: {l_max.toolTip()}"  # the status bar too
    press_key(Qt.Key.Key_Escape)  # drops it at once, and the keys go home
    assert l_max.lineEdit().text() == "8" and not is_marked_invalid(l_max)
    assert l_max.lineEdit().palette().color(QPalette.ColorRole.Text) != red  # black again
    assert "Refused" not in window.message_label.text()  # nor says it any more
    qtbot.waitUntil(window.viewport.hasFocus, timeout=2000)
    click(qtbot, window.viewport)  # a click elsewhere: the refused radius stays, named
    assert is_marked_invalid(radius) and radius.lineEdit().text() == "-0.5"
    assert window.model.brush.radius == 0.08
    # a good value is taken and hands the keys back
    click(qtbot, radius.lineEdit())
    radius.selectAll()
    _refuses(window, qtbot, radius, "500")  # said again, then mended
    assert window.message_label.text() == f"Refused: {radius.toolTip()}"
    radius.selectAll()
    type_text("0.25")
    press_key(Qt.Key.Key_Return)
    assert window.model.brush.radius == 0.25
    assert "Refused" not in window.message_label.text()
    qtbot.waitUntil(window.viewport.hasFocus, timeout=2000)


def test_ctrl_z_and_f1_still_act_from_a_field(window, qtbot):
    from gui_helpers import center_of, drag

    activate(window, qtbot)
    drag(window, center_of(window))
    assert window.document.dirty
    field = window.material_panel.fields["young"]
    click(qtbot, field.lineEdit())
    press_key(Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)  # the window's undo
    assert not window.document.dirty
    assert field.hasFocus()
    press_key(Qt.Key.Key_F1)
    assert window.keymap_overlay.isVisible()
    press_key(Qt.Key.Key_Escape)


def test_refused_material_values_never_stay_on_screen(window, qtbot, made_textured):
    """E = −5 and ν = 0.6 are refused in the panel's words; after opening another model the
    panel shows the material in effect, not them."""
    activate(window, qtbot)
    panel = window.material_panel
    young, poisson = panel.fields["young"], panel.fields["poisson"]
    for field, text, words in ((young, "-5", "Young's modulus E"), (poisson, "0.6", "Poisson")):
        click(qtbot, field.lineEdit())
        field.selectAll()
        type_text(text)
        press_key(Qt.Key.Key_Return)
        assert field.lineEdit().text() == text and is_marked_invalid(field)
        assert panel.error.startswith(f"Not applied: {words}")
        assert "young" not in panel.error and "poisson" not in panel.error
    assert window.document.sculptor.settings.material == Material.isotropic(1.0, 0.3)
    assert window.files.open_file(str(made_textured.path))
    assert young.lineEdit().text() == "1" and poisson.lineEdit().text() == "0.3"
    assert not is_marked_invalid(poisson) and panel.error == ""


def test_every_panel_shows_the_settings_in_effect_after_undo_and_a_preset(window, qtbot):
    panel = window.material_panel
    panel.set_mode("orthotropic")
    panel.set_field("E3", 5.0)
    orthotropic = window.model.material
    window.apply_material(Material.isotropic(2.0, 0.2))
    assert panel.mode == "isotropic"
    window.undo()  # back to the orthotropic material: shown as such, with its constants
    assert window.model.material == orthotropic and panel.mode == "orthotropic"
    assert panel.fields["E3"].value() == 5.0
    window.redo()
    assert panel.mode == "isotropic" and panel.fields["young"].value() == pytest.approx(2.0)
    preset = window.preset("mine")
    window.falloff_panel.l_max_spin.setValue(6)
    window.brush_bar.radius.setValue(0.3)
    window.apply_preset(preset)
    assert window.falloff_panel.l_max_spin.value() == preset.l_max
    assert window.brush_bar.radius.value() == pytest.approx(preset.brush.radius)
    kind = window.model.brush.kind
    shown = window.falloff_panel.degree_weights.degrees
    np.testing.assert_array_equal(
        window.falloff_panel.weight_grid.values, preset.engine_settings().weights_for(kind)[shown]
    )
