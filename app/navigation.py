"""Camera navigation of the viewport, Blender's by default.

Blender: middle drag orbits, Shift+middle pans, Ctrl+middle and the wheel zoom; numpad 1, 3
and 7 look from the front, the right and the top (with Ctrl from the opposite side), numpad 5
switches perspective and orthographic, ``.`` frames the model about the point under the cursor;
the wheel zooms towards the point under the cursor (Blender's "Zoom to Mouse Position"; View →
Navigation → Zoom to Mouse Position off: towards the view's centre).
A left drag that starts off the model sculpts as soon as it reaches it (Blender's habit);
preference: it orbits, as in most viewers. "Classic" navigation (the app's first scheme, kept
as a preference): right drag orbits, middle drag pans.

:func:`camera_gesture` is the table of mouse buttons to camera gestures; VTK's trackball style
then does the gesture (orbit: its left button, pan: its middle, zoom: its right).
:class:`CameraViews` is the part of :class:`app.viewport.SculptViewport` that sets the named
views; :class:`NavigationPreferences` keeps the choices in the window's QSettings and offers
them in the View menu.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
from PySide6.QtCore import QKeyCombination, QObject, QPointF, QSettings, Qt
from PySide6.QtGui import QAction, QActionGroup
from PySide6.QtWidgets import QMenu

from gogreen_core.validation import ParameterError

if TYPE_CHECKING:
    from app.mesh_display import MeshDisplay
    from app.viewport import SculptViewport
    from gogreen_core.interaction.settings import ViewSettings

    _Base = MeshDisplay
else:
    _Base = object

__all__ = [
    "CAMERA_VIEWS",
    "LEFT_ON_BACKGROUND",
    "NAVIGATIONS",
    "OPPOSITE_VIEWS",
    "VIEW_TITLES",
    "ZOOM_STEP",
    "CameraViews",
    "NavigationPreferences",
    "ViewAction",
    "camera_gesture",
]

Button = Qt.MouseButton
Mod = Qt.KeyboardModifier

#: Navigation schemes: name → (menu text, {(button, modifier): gesture}).
NAVIGATIONS: dict[str, tuple[str, dict[tuple[Button, Mod], str]]] = {
    "blender": (
        "Blender (middle drag orbits)",
        {
            (Button.MiddleButton, Mod.NoModifier): "orbit",
            (Button.MiddleButton, Mod.ShiftModifier): "pan",
            (Button.MiddleButton, Mod.ControlModifier): "zoom",
        },
    ),
    "classic": (
        "Classic (right drag orbits, middle pans)",
        {
            (Button.RightButton, Mod.NoModifier): "orbit",
            (Button.MiddleButton, Mod.NoModifier): "pan",
            (Button.MiddleButton, Mod.ShiftModifier): "pan",
            (Button.MiddleButton, Mod.ControlModifier): "zoom",
        },
    ),
}
#: What a left drag that starts off the model does: "sculpt" once it reaches the model
#: (Blender), or "orbit".
LEFT_ON_BACKGROUND = ("sculpt", "orbit")
#: The VTK trackball button that does each gesture.
_VTK_BUTTON = {"orbit": Button.LeftButton, "pan": Button.MiddleButton, "zoom": Button.RightButton}
#: Named views (keymap action → direction from the model to the camera, view up), in the
#: model's axes, +y up as OBJ and PLY files have it (the home view looks from +z).
CAMERA_VIEWS = {
    "view_front": ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
    "view_back": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
    "view_right": ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
    "view_left": ((-1.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
    "view_top": ((0.0, 1.0, 0.0), (0.0, 0.0, -1.0)),
    "view_bottom": ((0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),
}

#: Menu text of each named view.
VIEW_TITLES = {
    "view_front": "&Front",
    "view_back": "&Back",
    "view_right": "&Right",
    "view_left": "&Left",
    "view_top": "&Top",
    "view_bottom": "B&ottom",
}
#: How much one wheel notch zooms (VTK's trackball style's step: 1.1 ** 2).
ZOOM_STEP = 1.21
#: The keymap's view keys (numpad 1, 3, 7): the view, and the opposite one with Ctrl.
OPPOSITE_VIEWS = {"view_front": "view_back", "view_right": "view_left", "view_top": "view_bottom"}


def camera_gesture(navigation: str, button: Button, modifiers: Mod) -> str | None:
    """The camera gesture ("orbit", "pan", "zoom") of a drag with ``button`` and
    ``modifiers`` in ``navigation``, or None."""
    mods = modifiers & (Mod.ShiftModifier | Mod.ControlModifier | Mod.AltModifier)
    return NAVIGATIONS[navigation][1].get((button, Mod(mods)))


def vtk_button(gesture: str) -> Button:
    """The button of VTK's trackball style that does ``gesture``."""
    return _VTK_BUTTON[gesture]


class CameraViews(_Base):
    """Named views, projection and framing of the viewport's camera (a part of
    :class:`app.viewport.SculptViewport`)."""

    def show_view(self, name: str) -> None:
        """Look at the model from a named side (:data:`CAMERA_VIEWS`), keeping what the view
        centres on and how far away it is."""
        if name not in CAMERA_VIEWS:
            raise ParameterError(
                "name", f"name: unknown view {name!r}; the views are {', '.join(CAMERA_VIEWS)}"
            )
        direction, up = (np.array(v) for v in CAMERA_VIEWS[name])
        camera = self.renderer.GetActiveCamera()
        focal = np.array(camera.GetFocalPoint())
        distance = float(np.linalg.norm(np.array(camera.GetPosition()) - focal)) or 1.0
        camera.SetPosition(*(focal + distance * direction))
        camera.SetViewUp(*up)
        self.renderer.ResetCameraClippingRange()
        self.request_render()
        self.rehover()

    @property
    def orthographic(self) -> bool:
        """The camera projects in parallel (numpad 5 switches)."""
        return bool(self.renderer.GetActiveCamera().GetParallelProjection())

    def toggle_projection(self) -> None:
        """Perspective ↔ orthographic, the model the same size on screen at the focal point."""
        camera = self.renderer.GetActiveCamera()
        if not camera.GetParallelProjection():
            distance = camera.GetDistance()
            camera.SetParallelScale(distance * np.tan(np.radians(camera.GetViewAngle()) / 2))
        camera.SetParallelProjection(not camera.GetParallelProjection())
        self.renderer.ResetCameraClippingRange()
        self.request_render()
        self.rehover()

    def zoom_at(self, pos: QPointF | None, factor: float) -> None:
        """Zoom in by ``factor`` (> 1; < 1 zooms out) towards the model's point under widget
        position ``pos`` (off the model: the point of the focal plane under it), which stays
        under it; ``pos`` None: towards the view's centre. One render is requested.

        Perspective: the camera (its position and focal point) is scaled about that point by
        1 / ``factor``, so the ray through it keeps its direction and the point its pixel.
        Orthographic: the view's height shrinks by ``factor`` and the camera slides across the
        view so that the point keeps its offset from the centre in pixels."""
        camera = self.renderer.GetActiveCamera()
        focal, position = np.array(camera.GetFocalPoint()), np.array(camera.GetPosition())
        target = focal
        if pos is not None:
            hit = self.pick(pos)
            target = hit[0] if hit is not None else self._unproject(pos, self._depth(focal))
        if camera.GetParallelProjection():
            view = (focal - position) / (np.linalg.norm(focal - position) or 1.0)
            across = (target - focal) - ((target - focal) @ view) * view
            shift = across * (1.0 - 1.0 / factor)
            camera.SetParallelScale(camera.GetParallelScale() / factor)
            camera.SetFocalPoint(*(focal + shift))
            camera.SetPosition(*(position + shift))
        else:
            camera.SetFocalPoint(*(target + (focal - target) / factor))
            camera.SetPosition(*(target + (position - target) / factor))
        self.renderer.ResetCameraClippingRange()
        self.request_render()
        self.rehover()

    def frame_under_cursor(self, pos: QPointF | None = None) -> bool:
        """Frame the whole model about the point under the cursor (``pos``, default where the
        pointer is), from the current direction; about the model's centre when no point of the
        model is under it. Returns whether a point was under the cursor."""
        if self.mesh is None:
            return False
        if pos is None:
            pos = QPointF(self.mapFromGlobal(self.cursor().pos()))
        hit = self.pick(pos)
        points = self.shown_vertices()
        low, high = points.min(axis=0), points.max(axis=0)
        centre = hit[0] if hit is not None else (low + high) / 2
        radius = float(np.max(np.linalg.norm(points - centre, axis=1))) or 1.0
        camera = self.renderer.GetActiveCamera()
        direction = np.array(camera.GetPosition()) - np.array(camera.GetFocalPoint())
        direction /= np.linalg.norm(direction)
        half_angle = np.radians(camera.GetViewAngle()) / 2
        camera.SetFocalPoint(*centre)
        camera.SetPosition(*(centre + direction * radius / np.sin(half_angle)))
        camera.SetParallelScale(radius)
        self.renderer.ResetCameraClippingRange()
        self.request_render()
        self.rehover()
        return hit is not None


class ViewAction(QAction):
    """The action of a named view whose shortcuts with Ctrl show the ``opposite`` view
    (numpad 1, Ctrl+numpad 1); from the menu, the view itself."""

    def __init__(
        self, text: str, parent: QObject, view: str, opposite: str, show: Callable[[str], None]
    ) -> None:
        super().__init__(text, parent)
        self._view, self._opposite, self._show = view, opposite, show
        self.triggered.connect(lambda _checked=False: show(view))

    def trigger_for_key(self, combination: QKeyCombination) -> None:
        """The view of the key pressed (app.keyboard calls this for numpad keys)."""
        ctrl = bool(combination.keyboardModifiers() & Mod.ControlModifier)
        self._show(self._opposite if ctrl else self._view)


class NavigationPreferences(QObject):
    """The navigation scheme and what a left drag off the model does, remembered in
    ``settings`` and applied to ``viewport``, and the zoom's centre (the settings model's
    ``view.zoom_to_mouse``, :class:`gogreen_core.interaction.settings.ViewSettings`);
    :meth:`fill_menu` offers them in a menu."""

    def __init__(
        self,
        parent: QObject,
        viewport: SculptViewport,
        settings: QSettings,
        view: ViewSettings | None = None,
    ) -> None:
        super().__init__(parent)
        self.viewport, self.settings = viewport, settings
        scheme = settings.value("navigation", "blender")
        left = settings.value("left_on_background", "sculpt")
        self.actions: dict[str, QAction] = {}
        self.orbit_action = QAction("Left Drag off the Model &Orbits", self, checkable=True)
        self.orbit_action.setToolTip(
            "Off: a left drag that starts off the model sculpts once it reaches it (Blender)"
        )
        self.orbit_action.triggered.connect(
            lambda on: self.set_left_on_background("orbit" if on else "sculpt")
        )
        self.view = view
        self.zoom_action = QAction("&Zoom to Mouse Position", self, checkable=True)
        self.zoom_action.setToolTip(
            "On: the wheel zooms towards the point under the cursor (Blender's choice); "
            "off: towards the view's centre"
        )
        if view is not None:
            self.zoom_action.triggered.connect(lambda on: view.set("zoom_to_mouse", bool(on)))
            view.events.zoom_to_mouse.connect(lambda e: self._zoom_to_mouse(e.value))
            self._zoom_to_mouse(view.zoom_to_mouse)
        self.set_navigation(scheme if scheme in NAVIGATIONS else "blender")
        self.set_left_on_background(left if left in LEFT_ON_BACKGROUND else "sculpt")

    def fill_menu(self, menu: QMenu) -> None:
        """A Navigation submenu: the schemes, then the left-drag preference."""
        submenu = menu.addMenu("&Navigation")
        group = QActionGroup(self)
        for name, (text, _table) in NAVIGATIONS.items():
            action = QAction(text, self, checkable=True)
            action.setChecked(name == self.viewport.navigation)
            action.triggered.connect(lambda _c=False, n=name: self.set_navigation(n))
            group.addAction(action)
            submenu.addAction(action)
            self.actions[name] = action
        submenu.addSeparator()
        submenu.addAction(self.orbit_action)
        if self.view is not None:
            submenu.addAction(self.zoom_action)

    def _zoom_to_mouse(self, on: bool) -> None:
        self.viewport.zoom_to_mouse = on
        self.zoom_action.setChecked(on)

    def set_navigation(self, name: str) -> None:
        """Use navigation scheme ``name`` (a key of :data:`NAVIGATIONS`) and remember it."""
        if name not in NAVIGATIONS:
            schemes = ", ".join(NAVIGATIONS)
            raise ParameterError(
                "name", f"name: unknown navigation {name!r}; the schemes are {schemes}"
            )
        self.viewport.navigation = name
        self.settings.setValue("navigation", name)
        if name in self.actions:
            self.actions[name].setChecked(True)

    def set_left_on_background(self, what: str) -> None:
        """What a left drag that starts off the model does: "sculpt" or "orbit"."""
        if what not in LEFT_ON_BACKGROUND:
            choices = ", ".join(LEFT_ON_BACKGROUND)
            raise ParameterError("what", f"what: one of {choices}, got {what!r}")
        self.viewport.left_on_background = what
        self.settings.setValue("left_on_background", what)
        self.orbit_action.setChecked(what == "orbit")
