"""The project's own icons: single-colour SVG files in ``resources/icons`` tinted by the theme.

Every icon is drawn on a 24×24 grid with one colour, ``currentColor`` (strokes of width 1.75,
round caps and joins), so one file serves both themes: :func:`icon` substitutes the colour and
renders the SVG at the sizes tool bars and menus ask for. The files are found through the
``gogreen_resources`` package (:mod:`importlib.resources`), never by an absolute path, so they
work from a checkout, an editable install and a wheel alike.

Names: one icon per brush kind of :data:`gogreen_core.sculpt.brushes.BRUSH_KINDS`, ``pin``
(constraint mode) and the actions in :data:`ACTION_ICONS`. ``icon_names()`` lists what is installed.
"""

from __future__ import annotations

import functools
from importlib.resources import files

from PySide6.QtCore import QByteArray, QObject, QRectF, Qt
from PySide6.QtGui import QAction, QColor, QGuiApplication, QIcon, QPainter, QPalette, QPixmap
from PySide6.QtSvg import QSvgRenderer
from PySide6.QtWidgets import QAbstractButton, QApplication

from gogreen_core.validation import ParameterError

__all__ = [
    "ACTION_ICONS",
    "DISABLED_OPACITY",
    "ICON_SIZES",
    "icon",
    "icon_names",
    "icon_pixmap",
    "icon_svg",
    "refresh_icons",
    "set_icon",
]

#: Icons of application actions (besides one per brush kind and ``pin``).
ACTION_ICONS = (
    "new",
    "open",
    "save",
    "undo",
    "redo",
    "screenshot",
    "home",
    "wireframe",
    "shading",
    "help",
)
#: Pixel sizes rendered into each :class:`QIcon` (menus, tool bars, 2× screens).
ICON_SIZES = (16, 20, 24, 32, 48, 64)
#: Opacity of the tint in the disabled look.
DISABLED_OPACITY = 0.35
_PACKAGE = "gogreen_resources"
_FOLDER = "icons"
_COLOR_TOKEN = b"currentColor"
#: Dynamic property naming the icon :func:`set_icon` gave an action or button.
_ICON_PROPERTY = "gogreen_icon"


def _icons_folder():
    return files(_PACKAGE).joinpath(_FOLDER)


@functools.cache
def icon_names() -> tuple[str, ...]:
    """Names of the installed icons (the SVG file names without ``.svg``), sorted."""
    folder = _icons_folder()
    return tuple(
        sorted(entry.name[:-4] for entry in folder.iterdir() if entry.name.endswith(".svg"))
    )


@functools.cache
def icon_svg(name: str) -> bytes:
    """The SVG source of icon ``name``, with ``currentColor`` where the tint goes.

    Raises
    ------
    ParameterError
        (parameter ``"name"``) when no icon of that name is installed; the message lists the
        installed names.
    """
    if not isinstance(name, str) or not name or "/" in name or "\\" in name:
        raise ParameterError(
            "name", f"name: icon names are plain strings like 'grab', got {name!r}"
        )
    entry = _icons_folder().joinpath(f"{name}.svg")
    if not entry.is_file():
        raise ParameterError(
            "name",
            f"name: no icon named {name!r} in {_PACKAGE}/{_FOLDER} "
            f"(installed: {', '.join(icon_names())})",
        )
    return entry.read_bytes()


def _tint(color: QColor | str | None) -> QColor:
    """The colour to draw with: ``color``, or the application palette's button text."""
    if color is None:
        if QGuiApplication.instance() is None:
            return QColor("#e6e6e6")
        return QGuiApplication.palette().color(QPalette.ColorRole.ButtonText)
    tint = QColor(color)
    if not tint.isValid():
        raise ParameterError("color", f"color: not a colour Qt knows: {color!r}")
    return tint


@functools.cache
def _renderer(name: str, rgba: str) -> QSvgRenderer:
    svg = icon_svg(name).replace(_COLOR_TOKEN, rgba.encode("ascii"))
    renderer = QSvgRenderer(QByteArray(svg))
    if not renderer.isValid():
        raise ValueError(f"icon {name!r}: {_PACKAGE}/{_FOLDER}/{name}.svg is not a valid SVG file")
    return renderer


def _svg_color(tint: QColor) -> str:
    # SVG colours have no alpha channel in QtSvg's parser: opacity is applied when painting.
    return tint.name(QColor.NameFormat.HexRgb)


def icon_pixmap(name: str, size: int, color: QColor | str | None = None) -> QPixmap:
    """Icon ``name`` rendered into a transparent ``size``×``size`` pixmap (device pixels).

    ``color`` defaults to the application palette's button text colour (light on the dark
    theme, dark on the light one).
    """
    if not isinstance(size, int) or size < 1:
        raise ParameterError("size", f"size: a pixel size ≥ 1 is needed, got {size!r}")
    tint = _tint(color)
    renderer = _renderer(name, _svg_color(tint))
    pixmap = QPixmap(size, size)
    pixmap.fill(Qt.GlobalColor.transparent)
    painter = QPainter(pixmap)
    try:
        painter.setRenderHint(QPainter.RenderHint.Antialiasing)
        renderer.render(painter, QRectF(0, 0, size, size))
    finally:
        painter.end()
    if tint.alpha() == 255:
        return pixmap
    # Translucent tint: fade the finished glyph as a whole (fading each path would darken the
    # places where strokes overlap).
    faded = QPixmap(size, size)
    faded.fill(Qt.GlobalColor.transparent)
    painter = QPainter(faded)
    try:
        painter.setOpacity(tint.alphaF())
        painter.drawPixmap(0, 0, pixmap)
    finally:
        painter.end()
    return faded


@functools.cache
def _cached_icon(name: str, rgba: str) -> QIcon:
    result = QIcon()
    tint = QColor.fromString(rgba)
    # The style's generated disabled look darkens pixmaps, which leaves a light icon on a dark
    # theme as bright as an enabled one; a faded tint reads as disabled on both themes.
    faded = QColor(tint)
    faded.setAlphaF(tint.alphaF() * DISABLED_OPACITY)
    for size in ICON_SIZES:
        result.addPixmap(icon_pixmap(name, size, tint), QIcon.Mode.Normal)
        result.addPixmap(icon_pixmap(name, size, faded), QIcon.Mode.Disabled)
    return result


def icon(name: str, color: QColor | str | None = None) -> QIcon:
    """The project's icon ``name`` as a :class:`QIcon`, tinted ``color``.

    ``color`` defaults to the current application palette's button text colour, so call it
    after :func:`app.theme.apply_theme`. Icons are cached per (name, colour); the disabled look
    is the tint at :data:`DISABLED_OPACITY`.

    Raises
    ------
    ParameterError
        (parameter ``"name"``) naming the missing icon and listing the installed ones.
    """
    tint = _tint(color)
    icon_svg(name)  # the clear error for a missing icon, before any rendering
    return _cached_icon(name, tint.name(QColor.NameFormat.HexArgb))


def set_icon(target: QAction | QAbstractButton, name: str) -> None:
    """Give ``target`` icon ``name`` in the current palette's colour, and remember the name so
    that :func:`refresh_icons` (called by :func:`app.theme.apply_theme`) re-tints it after a
    theme switch."""
    target.setIcon(icon(name))
    target.setProperty(_ICON_PROPERTY, name)


def refresh_icons(root: QObject | None = None) -> int:
    """Re-make, in the current palette's colour, the icons :func:`set_icon` gave to ``root``
    and its descendants (default: every top-level widget). Returns how many were re-made."""
    roots: list[QObject]
    if root is not None:
        roots = [root]
    elif QApplication.instance() is not None:
        roots = list(QApplication.topLevelWidgets())
    else:
        return 0
    count = 0
    for top in roots:
        for item in (top, *top.findChildren(QObject)):
            name = item.property(_ICON_PROPERTY)
            if isinstance(name, str) and isinstance(item, QAction | QAbstractButton):
                item.setIcon(icon(name))
                count += 1
    return count
