"""Application themes: dark (the default, as in sculpting tools) and light.

A theme is plain data (:class:`Theme`, one per name in :data:`THEMES`): the colours of the Qt
palette, a few colours widgets draw themselves (muted hints, errors, invalid fields, zero cells)
and the viewport's background gradient. :func:`apply_theme` puts one on a
:class:`~PySide6.QtWidgets.QApplication`: the Fusion style (the same look on every platform, and
the one style that follows the palette fully), the palette, and a short style sheet for the few
things the palette does not reach.

The viewport reads its colours with ``theme(name).viewport_background`` (bottom, top), or
``current_theme(app)`` after :func:`apply_theme`. Icons from :func:`app.icons.icon` take the
palette's button text colour, so make them after applying the theme; those given with
:func:`app.icons.set_icon` follow a later switch by themselves.
"""

from __future__ import annotations

from dataclasses import dataclass

from PySide6.QtGui import QColor, QPalette
from PySide6.QtWidgets import QApplication

from app.icons import refresh_icons
from gogreen_core.validation import ParameterError

__all__ = [
    "DEFAULT_THEME",
    "THEMES",
    "Theme",
    "active_theme",
    "apply_theme",
    "current_theme",
    "qt_application",
    "theme",
]

#: Names accepted by :func:`apply_theme`, the default first.
THEMES = ("dark", "light")
DEFAULT_THEME = THEMES[0]
#: Application property holding the applied theme's name.
_PROPERTY = "gogreen_theme"


@dataclass(frozen=True)
class Theme:
    """The colours of one theme, as ``#rrggbb`` strings.

    Palette roles: ``window`` … ``link``. Colours widgets draw themselves: ``muted_text``
    (hints, captions), ``error_text``, ``invalid_base`` (background of a field holding an
    invalid value), ``zero_cell`` (table cells of zero coefficients). Viewport:
    ``viewport_background`` is the (bottom, top) colours of its vertical gradient, the
    arguments of ``pyvista.Plotter.set_background(bottom, top=top)``.
    """

    name: str
    window: str
    window_text: str
    base: str
    alternate_base: str
    text: str
    placeholder_text: str
    button: str
    button_text: str
    bright_text: str
    light: str
    midlight: str
    mid: str
    dark: str
    shadow: str
    highlight: str
    highlighted_text: str
    tooltip_base: str
    tooltip_text: str
    link: str
    disabled_text: str
    muted_text: str
    error_text: str
    invalid_base: str
    zero_cell: str
    viewport_background: tuple[str, str]

    def palette(self) -> QPalette:
        """The :class:`QPalette` of this theme (all colour groups; disabled text dimmed)."""
        role = QPalette.ColorRole
        palette = QPalette()
        colours = {
            role.Window: self.window,
            role.WindowText: self.window_text,
            role.Base: self.base,
            role.AlternateBase: self.alternate_base,
            role.Text: self.text,
            role.PlaceholderText: self.placeholder_text,
            role.Button: self.button,
            role.ButtonText: self.button_text,
            role.BrightText: self.bright_text,
            role.Light: self.light,
            role.Midlight: self.midlight,
            role.Mid: self.mid,
            role.Dark: self.dark,
            role.Shadow: self.shadow,
            role.Highlight: self.highlight,
            role.HighlightedText: self.highlighted_text,
            role.ToolTipBase: self.tooltip_base,
            role.ToolTipText: self.tooltip_text,
            role.Link: self.link,
            role.LinkVisited: self.link,
        }
        for colour_role, value in colours.items():
            palette.setColor(colour_role, QColor(value))
        disabled = QPalette.ColorGroup.Disabled
        for colour_role in (role.WindowText, role.Text, role.ButtonText, role.HighlightedText):
            palette.setColor(disabled, colour_role, QColor(self.disabled_text))
        palette.setColor(disabled, role.Highlight, QColor(self.mid))
        palette.setColor(disabled, role.Base, QColor(self.window))
        return palette

    def style_sheet(self) -> str:
        """What the palette does not cover: checked tool buttons (Fusion draws them barely
        darker than unchecked ones, so the active brush would not stand out), tool tip and menu
        separator contrast, dock titles, and the text colours of labels given a role by
        :func:`app.panels.widgets.set_text_role` (``muted`` captions, ``error`` messages), so
        that they follow a theme switch."""
        return f"""
QToolButton:checked {{
    background-color: {_mix(self.highlight, self.button, 0.45)};
    border: 1px solid {self.highlight};
    border-radius: 3px;
}}
QToolTip {{
    color: {self.tooltip_text};
    background-color: {self.tooltip_base};
    border: 1px solid {self.mid};
    padding: 3px;
}}
QMenu::separator {{
    height: 1px;
    background: {self.mid};
    margin: 4px 8px;
}}
QDockWidget::title {{
    background: {self.button};
    padding: 4px;
}}
QLabel[text_role="muted"] {{
    color: {self.muted_text};
}}
QLabel[text_role="error"] {{
    color: {self.error_text};
}}
"""


def _mix(first: str, second: str, weight: float) -> str:
    """``weight`` of colour ``first`` and ``1 - weight`` of ``second``, as ``#rrggbb``."""
    a, b = QColor(first), QColor(second)
    channels = [
        round(weight * x + (1.0 - weight) * y)
        for x, y in zip((a.red(), a.green(), a.blue()), (b.red(), b.green(), b.blue()), strict=True)
    ]
    return QColor(*channels).name()


_THEMES = {
    "dark": Theme(
        name="dark",
        window="#2b2d31",
        window_text="#e3e5e8",
        base="#1e1f22",
        alternate_base="#26282c",
        text="#e3e5e8",
        placeholder_text="#868b93",
        button="#393b40",
        button_text="#e3e5e8",
        bright_text="#ff6b6b",
        light="#4d5056",
        midlight="#43464c",
        mid="#55585f",
        dark="#1a1b1e",
        shadow="#0e0f11",
        highlight="#3f9a5a",
        highlighted_text="#ffffff",
        tooltip_base="#1e1f22",
        tooltip_text="#e3e5e8",
        link="#6cc787",
        disabled_text="#6c7078",
        muted_text="#a0a5ad",
        error_text="#ff7a70",
        invalid_base="#5a2a2a",
        zero_cell="#34363b",
        viewport_background=("#202328", "#444b57"),
    ),
    "light": Theme(
        name="light",
        window="#eceef1",
        window_text="#1f2328",
        base="#ffffff",
        alternate_base="#f4f5f7",
        text="#1f2328",
        placeholder_text="#8a9099",
        button="#e1e4e8",
        button_text="#1f2328",
        bright_text="#c62828",
        light="#ffffff",
        midlight="#f3f4f6",
        mid="#b4b9c1",
        dark="#9aa0a8",
        shadow="#5a5f66",
        highlight="#2e8b4f",
        highlighted_text="#ffffff",
        tooltip_base="#ffffff",
        tooltip_text="#1f2328",
        link="#1f7a3f",
        disabled_text="#9aa0a8",
        muted_text="#555a61",
        error_text="#c62828",
        invalid_base="#ffd0d0",
        zero_cell="#e4e4e4",
        viewport_background=("#8e959f", "#dde1e6"),
    ),
}


def theme(name: str = DEFAULT_THEME) -> Theme:
    """The colours of theme ``name`` (one of :data:`THEMES`).

    Raises
    ------
    ParameterError
        (a :class:`ValueError`, parameter ``"name"``) for an unknown name, naming it.
    """
    try:
        return _THEMES[name]
    except (KeyError, TypeError):
        raise ParameterError(
            "name", f"name: unknown theme {name!r}; the themes are {', '.join(THEMES)}"
        ) from None


def qt_application() -> QApplication:
    """The running QApplication (the app's widgets need one)."""
    app = QApplication.instance()
    if not isinstance(app, QApplication):
        raise RuntimeError("no QApplication is running")
    return app


def apply_theme(app: QApplication, name: str = DEFAULT_THEME) -> Theme:
    """Give ``app`` the Fusion style, the palette and the style sheet of theme ``name``.

    Can be called again to switch themes: widgets already shown repaint with the new palette,
    and icons given by :func:`app.icons.set_icon` are re-tinted (icons set otherwise keep
    their colour). Returns the applied theme.

    Raises
    ------
    ParameterError
        (a :class:`ValueError`) naming an unknown theme; ``app`` is then left unchanged.
    """
    chosen = theme(name)
    app.setStyle("Fusion")
    app.setPalette(chosen.palette())
    app.setStyleSheet(chosen.style_sheet())
    app.setProperty(_PROPERTY, chosen.name)
    refresh_icons()
    return chosen


def current_theme(app: QApplication) -> Theme | None:
    """The theme last applied to ``app`` by :func:`apply_theme`, or None."""
    name = app.property(_PROPERTY)
    return _THEMES.get(name) if isinstance(name, str) else None


def active_theme() -> Theme:
    """The theme widgets should draw with now: the one applied to the running application,
    else (no theme applied, e.g. a panel made alone in a test) the built-in theme matching the
    application palette's lightness."""
    app = QApplication.instance()
    if not isinstance(app, QApplication):
        return theme()
    applied = current_theme(app)
    if applied is not None:
        return applied
    window = app.palette().color(QPalette.ColorRole.Window)
    return theme("dark" if window.lightnessF() < 0.5 else "light")
