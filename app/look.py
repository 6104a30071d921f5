"""How the viewport and the window look: theme, shading, wireframe, orientation gizmo.

:class:`ViewLook` fills the View menu's look entries and remembers the choices in the window's
QSettings.
"""

from __future__ import annotations

from typing import Any

import pyvista as pv
from PySide6.QtCore import QObject, QSettings
from PySide6.QtGui import QAction, QActionGroup
from PySide6.QtWidgets import QMenu, QWidget

from app.icons import set_icon
from app.theme import DEFAULT_THEME, THEMES, Theme, apply_theme, qt_application, theme
from app.viewport import SculptViewport
from gogreen_core.validation import ParameterError

__all__ = ["SHADINGS", "ViewLook"]

#: Shading modes of the View menu: (menu text, tool tip); the first is the default.
SHADINGS = {
    "studio": ("Studio", "Key, fill and back lights with soft highlights"),
    "clay": (
        "Clay",
        "Matte clay lit from the camera, like a matcap: forms read at any angle",
    ),
}
#: Material (ambient, diffuse, specular, specular power) of the mesh in each shading mode.
_SHADING_PROPS = {"studio": (0.12, 0.85, 0.25, 20.0), "clay": (0.22, 0.9, 0.0, 1.0)}


def stored_theme(settings: QSettings) -> str:
    """The theme the user chose last (the default one at first)."""
    name = settings.value("theme", DEFAULT_THEME)
    return name if name in THEMES else DEFAULT_THEME


class ViewLook(QObject):
    """Theme, shading, wireframe and gizmo of ``viewport`` (and the theme of the app).

    ``refresh_colors`` : called after a theme switch for widgets that colour themselves.
    """

    def __init__(
        self, parent: QWidget, viewport: SculptViewport, settings: QSettings, current: Theme
    ) -> None:
        super().__init__(parent)
        self.viewport, self.settings, self.theme = viewport, settings, current
        self.refresh_colors: list = []
        name = settings.value("shading", next(iter(SHADINGS)))
        self.shading = name if name in SHADINGS else next(iter(SHADINGS))
        self.theme_actions: dict[str, QAction] = {}
        self.shading_actions: dict[str, QAction] = {}
        self.gizmo_action = QAction("Orientation &Gizmo", self, checkable=True, checked=True)
        self.gizmo_action.setToolTip("Axes in the corner of the view: x red, y green, z blue")
        self.gizmo_action.triggered.connect(self.show_gizmo)
        self.wireframe_action = QAction("&Wireframe", self, checkable=True)
        self.wireframe_action.triggered.connect(self._wireframe_toggled)
        set_icon(self.wireframe_action, "wireframe")

    def fill_menu(self, view_menu: QMenu) -> None:
        """The Theme and Shading submenus, Wireframe and Orientation Gizmo."""
        theme_menu = view_menu.addMenu("&Theme")
        group = QActionGroup(self)
        for name in THEMES:
            action = QAction(name.capitalize(), self, checkable=True)
            action.setChecked(name == self.theme.name)
            action.triggered.connect(lambda _c=False, n=name: self.set_theme(n))
            group.addAction(action)
            theme_menu.addAction(action)
            self.theme_actions[name] = action
        shading_menu = view_menu.addMenu("&Shading")
        set_icon(shading_menu.menuAction(), "shading")
        shading_group = QActionGroup(self)
        for name, (title, tip) in SHADINGS.items():
            action = QAction(title, self, checkable=True)
            action.setToolTip(tip)
            action.setStatusTip(tip)
            action.triggered.connect(lambda _c=False, n=name: self.set_shading(n))
            shading_group.addAction(action)
            shading_menu.addAction(action)
            self.shading_actions[name] = action
        self.shading_actions[self.shading].setChecked(True)
        view_menu.addAction(self.wireframe_action)
        view_menu.addAction(self.gizmo_action)

    def apply(self) -> None:
        """Lights, colours and gizmo as chosen (at start-up)."""
        self.viewport_colors()
        self._apply_lights()

    def set_theme(self, name: str) -> None:
        """Switch to theme ``name`` (one of :data:`app.theme.THEMES`) and remember it."""
        self.theme = apply_theme(qt_application(), theme(name).name)
        self.settings.setValue("theme", self.theme.name)
        self.theme_actions[self.theme.name].setChecked(True)
        for refresh in self.refresh_colors:
            refresh()
        self.viewport_colors()

    def viewport_colors(self) -> None:
        """The viewport's background gradient and the gizmo's labels in the theme's colours."""
        bottom, top = self.theme.viewport_background
        plotter: Any = self.viewport  # pyvista's decorator hides set_background's signature
        plotter.set_background(bottom, top=top)
        self.show_gizmo()

    def set_shading(self, name: str) -> None:
        """Shade the model ``name`` (a key of :data:`SHADINGS`) and remember it."""
        if name not in SHADINGS:
            raise ParameterError(
                "name", f"name: unknown shading {name!r}; the shadings are {', '.join(SHADINGS)}"
            )
        self.shading = name
        self.settings.setValue("shading", name)
        self.shading_actions[name].setChecked(True)
        self._apply_lights()
        self.apply_mesh_look()

    def _apply_lights(self) -> None:
        self.viewport.remove_all_lights()
        if self.shading == "clay":
            self.viewport.add_light(pv.Light(light_type="headlight", intensity=1.0))
        else:
            self.viewport.enable_lightkit()
        self.viewport.request_render()

    def apply_mesh_look(self) -> None:
        """Shading and wireframe of the mesh actor (made anew by each ``set_mesh``)."""
        actor = self.viewport.mesh_actor
        if actor is None:
            return
        prop = actor.prop
        prop.ambient, prop.diffuse, prop.specular, prop.specular_power = _SHADING_PROPS[
            self.shading
        ]
        prop.show_edges = self.wireframe_action.isChecked()
        prop.edge_color = "#1c1f24"
        prop.line_width = 1.0
        self.viewport.request_render()

    @property
    def wireframe(self) -> bool:
        """The triangle edges are drawn over the surface (View → Wireframe, Shift+Z)."""
        return self.wireframe_action.isChecked()

    def _wireframe_toggled(self) -> None:
        self.apply_mesh_look()

    def show_gizmo(self) -> None:
        """The orientation gizmo (pyvista's axes widget) when View → Orientation Gizmo is on."""
        plotter: Any = self.viewport  # pyvista's decorator hides these signatures
        plotter.hide_axes()
        if self.gizmo_action.isChecked():
            plotter.add_axes(interactive=False, line_width=2, color=self.theme.window_text)
        self.viewport.request_render()

    @property
    def gizmo_visible(self) -> bool:
        widget = getattr(self.viewport.renderer, "axes_widget", None)
        return bool(widget is not None and widget.GetEnabled())
