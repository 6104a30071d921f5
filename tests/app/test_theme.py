"""Themes (app/theme.py): dark by default, light as an option, the viewport's colours as data."""

from __future__ import annotations

import pytest
from PySide6.QtGui import QColor, QPalette
from PySide6.QtWidgets import QLabel, QToolButton

from app.icons import icon
from app.theme import DEFAULT_THEME, THEMES, apply_theme, current_theme, theme
from gogreen_core.validation import ParameterError

ROLE = QPalette.ColorRole


def _luma(colour: str | QColor) -> float:
    """WCAG relative luminance (linearized sRGB)."""
    c = QColor(colour)

    def linear(v: float) -> float:
        return v / 12.92 if v <= 0.03928 else ((v + 0.055) / 1.055) ** 2.4

    return 0.2126 * linear(c.redF()) + 0.7152 * linear(c.greenF()) + 0.0722 * linear(c.blueF())


def _solid_colours(themed_icon) -> set[str]:
    """Colours of the opaque pixels of an icon at 24 px."""
    image = themed_icon.pixmap(24, 24).toImage()
    return {
        image.pixelColor(x, y).name()
        for y in range(24)
        for x in range(24)
        if image.pixelColor(x, y).alpha() == 255
    }


def test_dark_is_the_default_and_light_an_option():
    assert THEMES == ("dark", "light")
    assert DEFAULT_THEME == "dark"


@pytest.mark.parametrize("name", THEMES)
def test_apply_theme_sets_the_palette(app_look, name):
    app = app_look
    applied = apply_theme(app, name)
    assert applied is theme(name) and current_theme(app) is applied
    palette = app.palette()
    assert palette.color(ROLE.Window).name() == applied.window
    assert palette.color(ROLE.Base).name() == applied.base
    assert palette.color(ROLE.Text).name() == applied.text
    assert palette.color(ROLE.WindowText).name() == applied.window_text
    assert palette.color(ROLE.ButtonText).name() == applied.button_text
    assert palette.color(ROLE.Highlight).name() == applied.highlight
    disabled = palette.color(QPalette.ColorGroup.Disabled, ROLE.Text).name()
    assert disabled == applied.disabled_text
    sheet = app.styleSheet()
    assert "QToolButton:checked" in sheet
    app.setStyleSheet("")  # with a style sheet, app.style() is Qt's style sheet proxy
    assert app.style().name().lower() == "fusion"
    app.setStyleSheet(sheet)
    # a new widget picks the palette up
    label = QLabel("x")
    assert label.palette().color(ROLE.Window).name() == applied.window


def test_default_theme_is_dark(app_look):
    app = app_look
    apply_theme(app)
    assert current_theme(app).name == "dark"
    assert _luma(app.palette().color(ROLE.Window)) < 0.1
    assert _luma(app.palette().color(ROLE.Text)) > 0.6


def test_light_theme_is_light(app_look):
    app = app_look
    apply_theme(app, "light")
    assert _luma(app.palette().color(ROLE.Window)) > 0.6
    assert _luma(app.palette().color(ROLE.Text)) < 0.1


@pytest.mark.parametrize("name", THEMES)
def test_text_contrasts_with_its_background(name):
    t = theme(name)
    pairs = [
        (t.text, t.base),
        (t.window_text, t.window),
        (t.button_text, t.button),
        (t.highlighted_text, t.highlight),
        (t.tooltip_text, t.tooltip_base),
        (t.muted_text, t.window),
        (t.error_text, t.window),
        (t.error_text, t.invalid_base),  # a refused number's text
        (t.text, t.zero_cell),
    ]
    for fg, bg in pairs:
        a, b = sorted((_luma(fg), _luma(bg)))
        # WCAG-style contrast ratio with relative luminance from sRGB channels (approximate)
        assert (b + 0.05) / (a + 0.05) > 2.5, (name, fg, bg)


@pytest.mark.parametrize("name", THEMES)
def test_viewport_background_is_plain_data(name):
    bottom, top = theme(name).viewport_background
    assert QColor(bottom).isValid() and QColor(top).isValid()
    assert _luma(top) > _luma(bottom)  # lit from above


def test_switching_back_and_forth(app_look):
    app = app_look
    apply_theme(app, "light")
    apply_theme(app, "dark")
    assert app.palette().color(ROLE.Window).name() == theme("dark").window


def test_icons_follow_the_theme(app_look):
    app = app_look
    for name in THEMES:
        apply_theme(app, name)
        assert _solid_colours(icon("grab")) == {theme(name).button_text}


def test_checked_tool_button_stands_out(app_look, qtbot):
    apply_theme(app_look, "dark")
    buttons = []
    for checked in (False, True):
        button = QToolButton()
        button.setCheckable(True)
        button.setChecked(checked)
        button.resize(32, 32)
        qtbot.addWidget(button)
        buttons.append(button.grab().toImage().pixelColor(16, 16))
    unchecked, checked = buttons
    # the checked one is tinted with the (green) highlight, the unchecked one is grey
    assert checked.green() - checked.red() > 20, checked.name()
    assert abs(unchecked.green() - unchecked.red()) < 10, unchecked.name()


@pytest.mark.parametrize("bad", ["Dark", "solarized", "", None])
def test_unknown_theme_is_a_named_error(app_look, bad):
    app = app_look
    before = app.palette().color(ROLE.Window).name()
    with pytest.raises(ValueError, match=repr(bad).replace("(", r"\(")) as info:
        apply_theme(app, bad)
    assert isinstance(info.value, ParameterError) and info.value.parameter == "name"
    assert "dark" in str(info.value) and "light" in str(info.value)
    assert app.palette().color(ROLE.Window).name() == before


def test_switching_re_tints_icons_given_by_set_icon(app_look, qtbot):
    from PySide6.QtGui import QAction
    from PySide6.QtWidgets import QToolBar

    from app.icons import set_icon

    app = app_look
    apply_theme(app, "dark")
    bar = QToolBar()
    qtbot.addWidget(bar)
    tracked = QAction("grab", bar)
    set_icon(tracked, "grab")
    untracked = QAction("grab", bar)
    untracked.setIcon(icon("grab"))
    bar.addAction(tracked)
    bar.addAction(untracked)

    assert _solid_colours(tracked.icon()) == {theme("dark").button_text}
    apply_theme(app, "light")
    assert _solid_colours(tracked.icon()) == {theme("light").button_text}
    assert _solid_colours(untracked.icon()) == {theme("dark").button_text}
