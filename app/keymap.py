"""The keymap as data: one table of every key, mouse gesture and pen input.

:data:`KEYMAP` is the one table of what every key, mouse gesture and pen input does, in
Blender's sculpt-mode habits: F drags the radius and Shift+F the strength on screen, Ctrl inverts
the brush, number keys pick brushes, ``[`` / ``]`` change the radius, Ctrl+Z undoes and
Ctrl+Shift+Z (or Ctrl+Y) redoes, ``?`` shows this keymap; left drag sculpts, middle drag orbits,
Shift+middle pans, Ctrl+middle and the wheel zoom, numpad keys pick the views. The main window
takes its shortcuts from it (:func:`shortcuts`), so the overlay and the behaviour cannot drift
apart. It is the only source of key behaviour: the viewport passes no key to VTK or pyvista
(their default keys never act). A new key is one row here (and its action in the window).

Each :class:`Binding` is ``(keys, action, description, group)``: ``keys`` holds alternatives,
each either a key sequence in Qt's portable text (``"Shift+F"``, ``"Ctrl+Shift+Z"``, ``"["``) or
a gesture: optional modifiers and one of :data:`GESTURES` (``"Ctrl+Wheel"``, ``"Left drag"``).

:class:`app.keymap_overlay.KeymapOverlay` draws the table over the viewport.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import NamedTuple

from PySide6.QtCore import QKeyCombination, Qt
from PySide6.QtGui import (
    QKeySequence,
)

from gogreen_core.sculpt.brushes import BRUSH_KINDS, BRUSH_ROWS
from gogreen_core.validation import ParameterError

__all__ = [
    "BRUSH_ACTIONS",
    "GESTURES",
    "GROUPS",
    "KEYMAP",
    "Binding",
    "binding",
    "bindings_by_group",
    "brush_action",
    "display_keys",
    "keymap_markdown",
    "shortcuts",
]

#: Mouse and pen inputs a binding can name (after optional ``Ctrl+``/``Shift+``/``Alt+``).
GESTURES = (
    "Left drag",
    "Right drag",
    "Middle drag",
    "Right click",
    "Wheel",
    "Pen pressure",
)

#: Groups in the order the overlay shows them.
GROUPS = (
    "Sculpt",
    "Brushes",
    "Radius and strength",
    "Pins",
    "Mask and mesh",
    "View",
    "Edit",
    "File",
    "Help",
)


class Binding(NamedTuple):
    """One entry of the keymap.

    keys : alternatives, each a Qt portable key sequence (``"Ctrl+Shift+Z"``) or a gesture
        (``"Ctrl+Wheel"``); all of one kind within a binding.
    action : identifier the window's action or handler uses (``"undo"``, ``"brush_grab"``).
    description : what it does, one short sentence for the overlay and tool tips.
    group : one of :data:`GROUPS`.
    """

    keys: tuple[str, ...]
    action: str
    description: str
    group: str

    @property
    def is_gesture(self) -> bool:
        """True for mouse and pen inputs, False for keyboard shortcuts."""
        return _is_gesture(self.keys[0])


def _is_gesture(keys: str) -> bool:
    return keys.rsplit("+", 1)[-1] in GESTURES or keys in GESTURES


#: Action identifier of each brush kind (``"brush_grab"`` …).
BRUSH_ACTIONS = {row.kind: f"brush_{row.kind}" for row in BRUSH_ROWS}


def _brush_bindings() -> tuple[Binding, ...]:
    """Each brush row's fixed number key (if it has one) and its letter."""
    return tuple(
        Binding(
            tuple(key for key in (row.number, row.letter) if key),
            BRUSH_ACTIONS[row.kind],
            row.title,
            "Brushes",
        )
        for row in BRUSH_ROWS
    )


#: The keymap: every key, mouse gesture and pen input of the application.
KEYMAP: tuple[Binding, ...] = (
    Binding(
        ("Left drag",),
        "sculpt",
        "Sculpt (a drag begun off the model sculpts from where it reaches it)",
        "Sculpt",
    ),
    Binding(
        ("Ctrl+Left drag",),
        "invert",
        "Sculpt inverted: push instead of pull, deflate, twist the other way",
        "Sculpt",
    ),
    Binding(
        ("Shift+Left drag",),
        "smooth_stroke",
        "Smooth with any brush",
        "Sculpt",
    ),
    Binding(
        ("Pen pressure",),
        "pressure",
        "Pen pressure scales the strength and/or the radius (toggles in the brush bar)",
        "Sculpt",
    ),
    *_brush_bindings(),
    Binding(
        ("F",),
        "radius_drag",
        "Drag the radius on screen; click or Enter sets it, Esc or right click cancels",
        "Radius and strength",
    ),
    Binding(
        ("Shift+F",),
        "strength_drag",
        "Drag the strength on screen; click or Enter sets it, Esc or right click cancels",
        "Radius and strength",
    ),
    Binding(("[",), "radius_smaller", "Radius smaller", "Radius and strength"),
    Binding(("]",), "radius_larger", "Radius larger", "Radius and strength"),
    Binding(("{",), "strength_lower", "Strength lower", "Radius and strength"),
    Binding(("}",), "strength_higher", "Strength higher", "Radius and strength"),
    Binding(("Ctrl+Wheel",), "radius_wheel", "Radius smaller / larger", "Radius and strength"),
    Binding(("Shift+Wheel",), "strength_wheel", "Strength lower / higher", "Radius and strength"),
    Binding(
        ("C",),
        "pin_mode",
        "Pin mode: a click pins a point, dragging a pin moves it while the others hold",
        "Pins",
    ),
    Binding(("Right click",), "remove_pin", "In pin mode: remove the pin under the cursor", "Pins"),
    Binding(("Ctrl+I",), "mask_invert", "Invert the mask", "Mask and mesh"),
    Binding(("Alt+M",), "mask_clear", "Clear the mask", "Mask and mesh"),
    Binding(
        ("Ctrl+D",),
        "subdivide",
        "Subdivide the mesh",
        "Mask and mesh",
    ),
    Binding(
        ("Ctrl+Shift+D",),
        "subdivide_unmasked",
        "Subdivide the unmasked part",
        "Mask and mesh",
    ),
    # Blender's dynamic topology key (Ctrl+D) is our Subdivide: Ctrl+Alt+D toggles it here
    Binding(
        ("Ctrl+Alt+D",),
        "dynamic_topology",
        "Dynamic topology on / off (strokes remesh what they move)",
        "Mask and mesh",
    ),
    Binding(("Ctrl+R",), "remesh", "Remesh the mesh to the detail size", "Mask and mesh"),
    Binding(
        ("Middle drag", "Shift+Middle drag", "Ctrl+Middle drag"),
        "orbit",
        "Orbit; with Shift pan, with Ctrl zoom",
        "View",
    ),
    Binding(("Wheel",), "zoom", "Zoom", "View"),
    Binding(
        ("Right drag",),
        "orbit_classic",
        "Orbit, in the classic navigation (View menu)",
        "View",
    ),
    Binding(("Num+1", "Ctrl+Num+1"), "view_front", "Front view (Ctrl: back)", "View"),
    Binding(("Num+3", "Ctrl+Num+3"), "view_right", "Right view (Ctrl: left)", "View"),
    Binding(("Num+7", "Ctrl+Num+7"), "view_top", "Top view (Ctrl: bottom)", "View"),
    Binding(("Num+5",), "projection", "Perspective / orthographic", "View"),
    Binding(
        ("Num+.", "."), "frame_cursor", "Frame the model about the point under the cursor", "View"
    ),
    Binding(("Home",), "reset_camera", "Frame the whole model (the home view)", "View"),
    Binding(("Shift+Z",), "wireframe", "Wireframe on / off", "View"),
    Binding(
        ("Shift+V",),
        "field_preview",
        "Field preview on / off: colour what the brush would move under the resting cursor",
        "View",
    ),
    Binding(("Ctrl+Z",), "undo", "Undo", "Edit"),
    Binding(("Ctrl+Shift+Z", "Ctrl+Y"), "redo", "Redo", "Edit"),
    Binding(("Ctrl+N",), "new", "New: the default model", "File"),
    Binding(("Ctrl+O",), "open", "Open a model or a session", "File"),
    Binding(("Ctrl+S",), "save", "Save", "File"),
    Binding(("Ctrl+Shift+S",), "save_as", "Save as", "File"),
    Binding(("F12",), "screenshot", "Screenshot of the viewport", "File"),
    Binding(("Ctrl+Q",), "quit", "Quit", "File"),
    Binding(("?", "F1"), "keymap", "Show this keymap (Esc or a click closes it)", "Help"),
)


def binding(action: str) -> Binding:
    """The keymap entry of ``action``.

    Raises
    ------
    ParameterError
        (parameter ``"action"``) naming an action the keymap does not have.
    """
    for entry in KEYMAP:
        if entry.action == action:
            return entry
    raise ParameterError("action", f"action: no key binding for {action!r} in the keymap")


def shortcuts(action: str) -> list[QKeySequence]:
    """The key sequences of a keyboard ``action``, for ``QAction.setShortcuts``.

    Raises
    ------
    ParameterError
        (parameter ``"action"``) for an unknown action or a mouse / pen gesture.
    """
    entry = binding(action)
    if entry.is_gesture:
        raise ParameterError(
            "action",
            f"action: {action!r} is a mouse or pen gesture ({', '.join(entry.keys)}), "
            "not a keyboard shortcut",
        )
    sequences = [
        QKeySequence.fromString(k, QKeySequence.SequenceFormat.PortableText) for k in entry.keys
    ]
    return sequences + [s for s in map(_numlock_off, sequences) if s is not None]


#: What a numpad key sends with NumLock off (Blender takes both alike).
_NUMLOCK_OFF = {
    Qt.Key.Key_1: Qt.Key.Key_End,
    Qt.Key.Key_3: Qt.Key.Key_PageDown,
    Qt.Key.Key_5: Qt.Key.Key_Clear,
    Qt.Key.Key_7: Qt.Key.Key_Home,
    Qt.Key.Key_Period: Qt.Key.Key_Delete,
}


def _numlock_off(sequence: QKeySequence) -> QKeySequence | None:
    """The sequence a numpad shortcut arrives as with NumLock off, None for other keys."""
    combination = sequence[0] if sequence.count() == 1 else None  # type: ignore[index]
    if (
        combination is None
        or not combination.keyboardModifiers() & Qt.KeyboardModifier.KeypadModifier
    ):
        return None
    other = _NUMLOCK_OFF.get(combination.key())
    return (
        None
        if other is None
        else QKeySequence(QKeyCombination(combination.keyboardModifiers(), other))
    )


def brush_action(kind: str) -> str:
    """Action identifier of brush ``kind`` (its keys are its row's, :data:`BRUSH_ROWS`)."""
    try:
        return BRUSH_ACTIONS[kind]
    except KeyError:
        raise ParameterError(
            "kind", f"kind: unknown brush {kind!r}; the brushes are {', '.join(BRUSH_KINDS)}"
        ) from None


def bindings_by_group(keymap: Iterable[Binding] = KEYMAP) -> dict[str, tuple[Binding, ...]]:
    """The bindings of each group, groups in :data:`GROUPS` order (empty groups left out)."""
    entries = tuple(keymap)
    result = {g: tuple(b for b in entries if b.group == g) for g in GROUPS}
    return {group: found for group, found in result.items() if found}


def display_keys(keys: str) -> str:
    """How one key alternative is written for the user (native modifier names, e.g. ⌘ on
    macOS); gestures are shown as written."""
    if _is_gesture(keys):
        return keys
    sequence = QKeySequence.fromString(keys, QKeySequence.SequenceFormat.PortableText)
    return sequence.toString(QKeySequence.SequenceFormat.NativeText) or keys


def keymap_markdown(keymap: Iterable[Binding] = KEYMAP) -> str:
    """The keymap as Markdown, one table per group (for the README's Controls section, so
    the documentation is written from the same table as the shortcuts)."""
    parts = []
    for group, entries in bindings_by_group(keymap).items():
        parts.append(f"**{group}**\n\n| Input | Does |\n|---|---|")
        for entry in entries:
            keys = " / ".join(f"`{k}`" for k in entry.keys)
            description = entry.description.replace("|", r"\|")
            parts[-1] += f"\n| {keys} | {description} |"
    return "\n\n".join(parts) + "\n"


if __name__ == "__main__":  # python -m app.keymap > controls.md: the README's Controls tables
    print(keymap_markdown(), end="")
