"""The project's SVG icons (app/icons.py): complete, valid, tinted, found through the package."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from importlib.resources import files

import pytest
from PySide6.QtCore import QByteArray
from PySide6.QtGui import QColor, QImage
from PySide6.QtSvg import QSvgRenderer

from app.icons import ACTION_ICONS, icon, icon_names, icon_pixmap, icon_svg
from gogreen_core.sculpt.brushes import BRUSH_KINDS
from gogreen_core.validation import ParameterError

REQUIRED = (*BRUSH_KINDS, "pin", *ACTION_ICONS)


def _ink(image: QImage) -> list[tuple[int, int, QColor]]:
    """Pixels with any opacity, as (x, y, colour)."""
    return [
        (x, y, image.pixelColor(x, y))
        for y in range(image.height())
        for x in range(image.width())
        if image.pixelColor(x, y).alpha() > 0
    ]


def test_every_brush_kind_and_action_has_an_icon():
    missing = sorted(set(REQUIRED) - set(icon_names()))
    assert not missing, f"icons missing from resources/icons: {missing}"


def test_icons_are_found_through_the_package_not_a_path():
    folder = files("gogreen_resources").joinpath("icons")
    assert folder.joinpath("grab.svg").is_file()
    assert icon_svg("grab") == folder.joinpath("grab.svg").read_bytes()


@pytest.mark.parametrize("name", REQUIRED)
def test_svg_is_well_formed_single_colour_24px(name):
    svg = icon_svg(name)
    root = ET.fromstring(svg)
    assert root.tag.endswith("svg")
    assert root.get("viewBox") == "0 0 24 24"
    # one colour, the tint: no hard-coded colours that would not follow the theme
    for element in root.iter():
        for attribute in ("stroke", "fill", "color", "stop-color"):
            value = element.get(attribute)
            assert value in (None, "none", "currentColor"), (name, element.tag, attribute, value)
        assert element.get("style") is None, (name, element.tag)


@pytest.mark.parametrize("name", REQUIRED)
def test_svg_renders_non_empty(qapp, name):
    renderer = QSvgRenderer(QByteArray(icon_svg(name).replace(b"currentColor", b"#ffffff")))
    assert renderer.isValid()
    image = icon_pixmap(name, 24, "#ffffff").toImage()
    ink = _ink(image)
    # a legible glyph covers a real part of the cell, not a dot and not a filled square
    assert 0.08 * 24 * 24 < len(ink) < 0.6 * 24 * 24, (name, len(ink))


def test_icons_are_distinct(qapp):
    images = {name: icon_pixmap(name, 24, "#ffffff").toImage() for name in REQUIRED}
    seen = {}
    for name, image in images.items():
        key = bytes(image.constBits())
        assert key not in seen, f"icons {name!r} and {seen[key]!r} render the same"
        seen[key] = name


def test_tint_colours_the_strokes(qapp):
    for colour in ("#ff0000", "#0000ff"):
        ink = _ink(icon_pixmap("twist", 32, colour).toImage())
        solid = [c for _x, _y, c in ink if c.alpha() == 255]
        assert solid, "no opaque pixel"
        assert all(c.name() == colour for c in solid)


def test_default_tint_follows_the_palette(app_look):
    from PySide6.QtGui import QPalette

    palette = QPalette(app_look.palette())
    palette.setColor(QPalette.ColorRole.ButtonText, QColor("#00ff00"))
    app_look.setPalette(palette)
    image = icon("save").pixmap(24, 24).toImage()
    solid = [c for _x, _y, c in _ink(image) if c.alpha() == 255]
    assert solid and all(c.name() == "#00ff00" for c in solid)


def test_icon_is_cached_and_has_sizes(qapp):
    first = icon("grab", "#ffffff")
    assert first.cacheKey() == icon("grab", QColor("#ffffff")).cacheKey()
    assert not first.isNull()
    sizes = {(s.width(), s.height()) for s in first.availableSizes()}
    assert {(16, 16), (24, 24), (48, 48)} <= sizes


@pytest.mark.parametrize("bad", ["no_such_icon", "", "../pyproject", "icons/grab"])
def test_missing_icon_is_a_named_error(qapp, bad):
    with pytest.raises(ParameterError) as info:
        icon(bad)
    assert info.value.parameter == "name"
    assert repr(bad) in str(info.value)


def test_missing_icon_lists_the_installed_ones(qapp):
    with pytest.raises(ParameterError, match=r"installed: .*grab"):
        icon("grabb")


def test_bad_colour_is_a_named_error(qapp):
    with pytest.raises(ParameterError, match="not-a-colour"):
        icon("grab", "not-a-colour")


def test_disabled_look_is_faded(qapp):
    from PySide6.QtGui import QIcon

    themed = icon("redo", "#ffffff")
    normal = _ink(themed.pixmap(24, 24, QIcon.Mode.Normal).toImage())
    disabled = _ink(themed.pixmap(24, 24, QIcon.Mode.Disabled).toImage())
    assert max(c.alpha() for _x, _y, c in normal) == 255
    assert max(c.alpha() for _x, _y, c in disabled) < 128
