"""Each brush declared once (issue 33 item 4): its row in gogreen_core/sculpt/brushes/table.py is
all the app reads — keymap, brush bar, icons, degree-weight panel and number keys derive from it,
so a new row shows up everywhere and nothing in app/ names a brush."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from gui_helpers import show_widget

from app.brush_bar import BrushBar
from app.icons import icon_names
from app.keymap import binding, brush_action
from app.panels.degree_weights import DegreeWeights
from gogreen_core.interaction.settings import Settings
from gogreen_core.sculpt.brushes import BRUSH_ROWS, DRAGS, brush_for_key

APP = Path(__file__).resolve().parents[2] / "app"


@pytest.mark.parametrize("row", BRUSH_ROWS, ids=lambda row: row.kind)
def test_a_row_shows_up_everywhere(qtbot, row):
    entry = binding(brush_action(row.kind))  # the keymap (and the README's table from it)
    assert entry.keys == tuple(k for k in (row.number, row.letter) if k)
    assert entry.description == row.title
    bar = BrushBar()
    qtbot.addWidget(bar)
    action = bar.kind_actions[row.kind]  # the brush bar
    assert action.text() == row.label and action.toolTip().startswith(row.tooltip)
    assert action.shortcut().toString() == row.letter
    assert row.icon in icon_names()  # its icon is installed
    if row.number:
        assert brush_for_key(row.number) == row.kind  # its own number key
    assert row.drag in DRAGS
    settings = Settings()
    settings.brush.kind = row.kind
    panel = show_widget(qtbot, DegreeWeights(settings), 400, 300)
    assert panel.title() == f"Degree weights: {row.label} brush"
    if row.weights_hint:
        assert row.weights_hint in panel.caption.text()


def test_no_app_module_keeps_a_table_of_brushes():
    """The app's dictionaries come from the rows: no app module keys a dictionary by brush
    kinds (a new brush would otherwise need an edit there). One kind alone is allowed: the
    wrinkle brush's own fold controls."""
    kinds = "|".join(re.escape(row.kind) for row in BRUSH_ROWS)
    pattern = re.compile(rf"[\"']({kinds})[\"']\s*:")
    tables = {}
    for path in sorted(APP.rglob("*.py")):
        keyed = {m.group(1) for m in pattern.finditer(path.read_text(encoding="utf-8"))}
        if len(keyed) > 1:
            tables[path.name] = sorted(keyed)
    assert not tables, tables


def test_the_brush_bar_fits_a_1600_pixel_window_with_room_to_spare(window):
    """Every brush (the five detail brushes too) and the pen fields, Spacing the last, fit a
    1600 px wide window with room for a wider font."""
    bar = window.brush_bar
    spacing = bar.widgetForAction(bar.actions()[-1])
    assert spacing is bar.spacing
    assert bar.sizeHint().width() <= 1500
    window.resize(1600, 900)
    window.show()
    assert spacing.isVisible()
    assert spacing.mapTo(window, spacing.rect().topRight()).x() < 1600
