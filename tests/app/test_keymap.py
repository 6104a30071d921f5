"""The keymap table and its overlay (app/keymap.py), with pytest-qt."""

from __future__ import annotations

import pytest
from gui_helpers import show_widget
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QColor, QKeySequence, QWheelEvent
from PySide6.QtWidgets import QApplication, QWidget

from app.keymap import (
    BRUSH_ACTIONS,
    GESTURES,
    GROUPS,
    KEYMAP,
    Binding,
    binding,
    bindings_by_group,
    brush_action,
    display_keys,
    shortcuts,
)
from app.keymap_overlay import KeymapOverlay
from gogreen_core.sculpt.brushes import BRUSH_KINDS, BRUSH_ROWS
from gogreen_core.validation import ParameterError

PORTABLE = QKeySequence.SequenceFormat.PortableText


# ---------------------------------------------------------------------------------------------
# The table
# ---------------------------------------------------------------------------------------------
def test_entries_are_well_formed():
    actions = [b.action for b in KEYMAP]
    assert len(actions) == len(set(actions)), "an action bound twice"
    for entry in KEYMAP:
        assert isinstance(entry, Binding)
        assert entry.group in GROUPS, entry
        assert entry.keys and all(isinstance(k, str) and k for k in entry.keys), entry
        assert entry.description and entry.description[0].isupper(), entry
        kinds = {k.rsplit("+", 1)[-1] in GESTURES for k in entry.keys}
        assert len(kinds) == 1, f"{entry.action}: keys and gestures mixed"


def test_key_sequences_parse_and_no_key_does_two_things(qapp):
    seen: dict[str, str] = {}
    for entry in KEYMAP:
        for keys in entry.keys:
            if entry.is_gesture:
                *modifiers, gesture = keys.split("+")
                assert gesture in GESTURES, keys
                assert set(modifiers) <= {"Ctrl", "Shift", "Alt"}, keys
                normal = keys
            else:
                sequence = QKeySequence.fromString(keys, PORTABLE)
                assert sequence.count() == 1, keys
                assert sequence.toString(PORTABLE) == keys, f"{keys!r} is not Qt's spelling"
                normal = sequence.toString(PORTABLE)
            assert normal not in seen, f"{keys} bound to {seen[normal]} and {entry.action}"
            seen[normal] = entry.action


def test_blender_sculpt_habits():
    assert binding("radius_drag").keys == ("F",)
    assert binding("strength_drag").keys == ("Shift+F",)
    assert binding("invert").keys == ("Ctrl+Left drag",)
    assert binding("radius_smaller").keys == ("[",)
    assert binding("radius_larger").keys == ("]",)
    assert binding("undo").keys == ("Ctrl+Z",)
    assert binding("redo").keys == ("Ctrl+Shift+Z", "Ctrl+Y")
    assert "?" in binding("keymap").keys
    assert binding("sculpt").keys == ("Left drag",)
    # Blender's navigation (issue 21 item 4); the first scheme stays as a preference
    assert binding("orbit").keys == ("Middle drag", "Shift+Middle drag", "Ctrl+Middle drag")
    assert binding("zoom").keys == ("Wheel",)
    assert binding("orbit_classic").keys == ("Right drag",)
    for action, key in (("view_front", "1"), ("view_right", "3"), ("view_top", "7")):
        assert binding(action).keys == (f"Num+{key}", f"Ctrl+Num+{key}")  # Ctrl: opposite
    assert binding("projection").keys == ("Num+5",)
    assert binding("frame_cursor").keys == ("Num+.", ".")
    # numpad keys also act with NumLock off, as in Blender
    assert [s.toString() for s in shortcuts("view_top")] == [
        "Num+7",
        "Ctrl+Num+7",
        "Num+Home",
        "Ctrl+Num+Home",
    ]
    assert binding("radius_wheel").keys == ("Ctrl+Wheel",)
    assert binding("strength_wheel").keys == ("Shift+Wheel",)
    assert binding("pressure").keys == ("Pen pressure",)


def test_each_brush_has_its_rows_number_key_and_letter():
    assert set(BRUSH_ACTIONS) == set(BRUSH_KINDS)
    for row in BRUSH_ROWS:
        entry = binding(brush_action(row.kind))
        assert entry.keys == tuple(k for k in (row.number, row.letter) if k)
        assert entry.description == row.title and entry.group == "Brushes"
    # fixed per brush: the local grab on 1 and G, the wide one a key away, mask on 0
    assert binding("brush_grab_local").keys == ("1", "G")
    assert binding("brush_grab").keys == ("2", "Shift+G")
    assert binding("brush_mask").keys == ("0", "M")


def test_smooth_mask_and_subdivide_keys():
    assert binding("smooth_stroke").keys == ("Shift+Left drag",)  # Blender: Shift smooths
    assert binding("brush_mask").keys[-1] == "M"  # Blender's mask brush key
    assert binding("mask_invert").keys == ("Ctrl+I",)
    assert binding("mask_clear").keys == ("Alt+M",)
    assert binding("subdivide").keys == ("Ctrl+D",)  # ZBrush's divide


def test_shortcuts_the_window_had_are_kept():
    # what app/main_window.py and app/brush_bar.py bound before the keymap existed
    kept = {
        "radius_smaller": "[",
        "radius_larger": "]",
        "strength_lower": "{",
        "strength_higher": "}",
        "reset_camera": "Home",
        "screenshot": "F12",
        "save_as": "Ctrl+Shift+S",
        "pin_mode": "C",
        "brush_grab_local": "G",
        "brush_twist": "W",
    }
    for action, keys in kept.items():
        assert keys in binding(action).keys, action


def test_shortcuts_returns_key_sequences(qapp):
    assert shortcuts("undo") == [QKeySequence("Ctrl+Z")]
    assert shortcuts("brush_grab_local") == [QKeySequence("1"), QKeySequence("G")]
    assert shortcuts("keymap") == [QKeySequence("?"), QKeySequence("F1")]


def test_gestures_and_unknown_actions_are_named_errors(qapp):
    with pytest.raises(ParameterError, match="'orbit' is a mouse or pen gesture") as info:
        shortcuts("orbit")
    assert info.value.parameter == "action"
    with pytest.raises(ParameterError, match="'fly'") as info:
        binding("fly")
    assert info.value.parameter == "action"
    with pytest.raises(ParameterError, match="'smudge'") as info:
        brush_action("smudge")
    assert info.value.parameter == "kind"


def test_groups_in_order_and_complete():
    grouped = bindings_by_group()
    assert list(grouped) == [g for g in GROUPS if g in grouped]
    assert sum(len(v) for v in grouped.values()) == len(KEYMAP)
    assert set(grouped) == set(GROUPS)


def test_display_keys(qapp):
    assert display_keys("Ctrl+Wheel") == "Ctrl+Wheel"
    assert display_keys("Ctrl+Shift+Z") == QKeySequence("Ctrl+Shift+Z").toString(
        QKeySequence.SequenceFormat.NativeText
    )


# ---------------------------------------------------------------------------------------------
# The overlay
# ---------------------------------------------------------------------------------------------
class _Parent(QWidget):
    """A stand-in for the viewport that counts the input it receives."""

    def __init__(self):
        super().__init__()
        self.presses = 0
        self.wheels = 0
        self.setStyleSheet("background: #808080;")
        self.setAutoFillBackground(True)

    def mousePressEvent(self, event):
        self.presses += 1

    def wheelEvent(self, event):
        self.wheels += 1


@pytest.fixture
def parent(qtbot):
    return show_widget(qtbot, _Parent(), 1000, 700)


@pytest.fixture
def overlay(parent):
    return KeymapOverlay(parent)


def test_hidden_until_shown_then_covers_the_parent(qtbot, parent, overlay):
    assert overlay.isHidden()
    overlay.show_overlay()
    assert overlay.isVisible()
    assert overlay.geometry() == parent.rect()
    # the keyboard goes to the overlay once the window is active (no window manager here)
    assert parent.focusWidget() is overlay
    parent.resize(800, 500)
    qtbot.waitUntil(lambda: overlay.geometry() == parent.rect())


def test_escape_closes(qtbot, overlay):
    overlay.show_overlay()
    with qtbot.waitSignal(overlay.closed, timeout=1000):
        qtbot.keyClick(overlay, Qt.Key.Key_Escape)
    assert overlay.isHidden()


def test_question_mark_closes(qtbot, overlay):
    overlay.show_overlay()
    with qtbot.waitSignal(overlay.closed, timeout=1000):
        qtbot.keyClick(overlay, Qt.Key.Key_Question, Qt.KeyboardModifier.ShiftModifier)
    assert overlay.isHidden()


def test_other_keys_do_not_close(qtbot, overlay):
    overlay.show_overlay()
    qtbot.keyClick(overlay, Qt.Key.Key_A)
    assert overlay.isVisible()


def test_click_closes_and_does_not_reach_the_view(qtbot, parent, overlay):
    overlay.show_overlay()
    with qtbot.waitSignal(overlay.closed, timeout=1000):
        qtbot.mouseClick(overlay, Qt.MouseButton.LeftButton, pos=QPoint(500, 350))
    assert overlay.isHidden()
    assert parent.presses == 0


def test_wheel_does_not_reach_the_view(qtbot, parent, overlay):
    overlay.show_overlay()
    event = QWheelEvent(
        QPointF(500, 350),
        QPointF(overlay.mapToGlobal(QPoint(500, 350))),
        QPoint(0, 0),
        QPoint(0, 120),
        Qt.MouseButton.NoButton,
        Qt.KeyboardModifier.NoModifier,
        Qt.ScrollPhase.NoScrollPhase,
        False,
    )
    QApplication.sendEvent(overlay, event)
    assert parent.wheels == 0
    assert overlay.isVisible()


def test_toggle_and_hide_emit_closed_once(qtbot, overlay):
    received = []
    overlay.closed.connect(lambda: received.append(1))
    overlay.toggle_overlay()
    assert overlay.isVisible()
    overlay.toggle_overlay()
    assert overlay.isHidden()
    overlay.hide_overlay()  # already hidden: no second signal
    assert received == [1]


def test_lists_every_binding_by_group(overlay):
    lines = overlay.text_lines()
    text = "\n".join(lines)
    for group in GROUPS:
        assert group in lines
    for entry in KEYMAP:
        assert entry.description in text
        for keys in entry.keys:
            assert display_keys(keys) in text
    assert lines.index("Sculpt") < lines.index("Help")


def _ink_rows(image, threshold=170):
    """Rows holding light (text) pixels."""
    rows = []
    for y in range(image.height()):
        for x in range(0, image.width(), 2):
            if QColor(image.pixel(x, y)).lightness() > threshold:
                rows.append(y)
                break
    return rows


@pytest.mark.parametrize("size", [(1200, 760), (900, 600), (640, 420)])
def test_paints_a_dark_veil_and_fits_the_text(qtbot, parent, overlay, size):
    parent.resize(*size)
    overlay.show_overlay()
    qtbot.waitUntil(lambda: overlay.geometry() == parent.rect())
    image = parent.grab().toImage()
    # the grey parent shows through darkened, not hidden and not untouched
    corner = QColor(image.pixel(3, image.height() - 3))
    assert 10 < corner.lightness() < 0x80 * 0.45, corner.name()
    rows = _ink_rows(image)
    assert rows, "no text drawn"
    # all text inside the margins: nothing cut off at the bottom
    assert max(rows) < image.height() - KeymapOverlay.MARGIN / 2, (max(rows), image.height())
    # and it uses the height: more than a few lines
    assert max(rows) - min(rows) > image.height() / 2


def test_closed_overlay_leaves_the_view_untouched(qtbot, parent, overlay):
    overlay.show_overlay()
    overlay.hide_overlay()
    image = parent.grab().toImage()
    assert QColor(image.pixel(500, 350)).name() == "#808080"


def test_needs_a_parent():
    with pytest.raises(ParameterError, match="parent"):
        KeymapOverlay(None)


def test_markdown_lists_every_binding():
    from app.keymap import keymap_markdown

    text = keymap_markdown()
    for group in GROUPS:
        assert f"**{group}**" in text
    for entry in KEYMAP:
        assert entry.description in text
        for keys in entry.keys:
            assert f"`{keys}`" in text
    table_rows = [line for line in text.splitlines() if line.startswith("| `")]
    assert len(table_rows) == len(KEYMAP)


def test_readme_controls_section_is_the_keymap():
    """README.md's Controls tables are keymap_markdown() verbatim (regenerate them with
    ``python -m app.keymap``), so the documentation cannot drift from the shortcuts."""
    from pathlib import Path

    from app.keymap import keymap_markdown

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    assert "## Controls" in readme
    begin = readme.index("<!-- controls:begin")
    begin = readme.index("-->\n", begin) + len("-->\n")
    end = readme.index("<!-- controls:end -->")
    assert readme[begin:end] == keymap_markdown()
    assert readme.index("## Controls") < begin
