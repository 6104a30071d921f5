"""How the viewport and the window look: theme, shading (matcaps or studio lights), cavity
tint, falloff profile, wireframe, orientation gizmo.

:class:`ViewLook` fills the View menu's look entries. The shading, cavity, profile and zoom
choices live in the settings model (:class:`gogreen_core.interaction.settings.ViewSettings`, the
menu's actions bound to it); :class:`ViewLook` applies them to the viewport and keeps them, with the
theme, in the window's QSettings between runs.
"""

from __future__ import annotations

from typing import Any

import pyvista as pv
from PySide6.QtCore import QObject, QSettings
from PySide6.QtGui import QAction, QActionGroup, QIcon, QImage, QPixmap
from PySide6.QtWidgets import QMenu, QWidget

from app.icons import set_icon
from app.matcaps import MATCAP_RECIPES, matcap_image, use_matcap
from app.theme import DEFAULT_THEME, THEMES, Theme, apply_theme, qt_application, theme
from app.viewport import SculptViewport
from gogreen_core.interaction.settings import ChangeEvent, ViewSettings
from gogreen_core.validation import ParameterError

__all__ = ["SHADINGS", "ViewLook", "load_view_settings"]

#: Shading entries of the View menu: name → (menu text, tool tip), the matcaps (the first is
#: the default) then the studio lights. A matcap's name is ``"matcap:<its name>"``.
SHADINGS = {
    **{
        f"matcap:{name}": (
            f"Matcap: {recipe.title}",
            f"Matcap {recipe.title}: a lit sphere looked up by the surface's angle to the view, "
            "so forms read at any angle",
        )
        for name, recipe in MATCAP_RECIPES.items()
    },
    "studio": ("Studio Lights", "Key, fill and back lights with soft highlights"),
}
#: Material (ambient, diffuse, specular, specular power) of the mesh in each shading.
_SHADING_PROPS = {"studio": (0.12, 0.85, 0.25, 20.0), "matcap": (0.0, 1.0, 0.0, 1.0)}
#: QSettings group of the view settings.
_GROUP = "view"


def load_view_settings(view: ViewSettings, settings: QSettings) -> None:
    """Give ``view`` the choices stored in ``settings`` (a value stored wrongly is skipped)."""
    for name, field in view.fields.items():
        stored = settings.value(f"{_GROUP}/{name}")
        if stored is None:
            continue
        if isinstance(field.default, bool):  # QSettings' INI files give strings back
            stored = stored in (True, "true", "1", 1)
        try:
            view.set(name, stored)
        except ValueError:
            continue


def _matcap_icon(name: str) -> QIcon:
    image = matcap_image(name, 32)
    picture = QImage(image.data, 32, 32, 96, QImage.Format.Format_RGB888).copy()
    return QIcon(QPixmap.fromImage(picture))


def stored_theme(settings: QSettings) -> str:
    """The theme the user chose last (the default one at first)."""
    name = settings.value("theme", DEFAULT_THEME)
    return name if name in THEMES else DEFAULT_THEME


class ViewLook(QObject):
    """Theme, shading, cavity tint, falloff profile, wireframe and gizmo of ``viewport`` (and
    the theme of the app); ``view`` the settings model's view part (its stored values are
    loaded here, and every change stored).

    ``refresh_colors`` : called after a theme switch for widgets that colour themselves.
    """

    def __init__(
        self,
        parent: QWidget,
        viewport: SculptViewport,
        settings: QSettings,
        current: Theme,
        view: ViewSettings | None = None,
    ) -> None:
        super().__init__(parent)
        self.viewport, self.settings, self.theme = viewport, settings, current
        self.view = view if view is not None else ViewSettings()
        load_view_settings(self.view, settings)
        for name in self.view.fields:
            self.view.events[name].connect(self._view_changed)
        self.refresh_colors: list = []
        self.theme_actions: dict[str, QAction] = {}
        self.shading_actions: dict[str, QAction] = {}
        self.gizmo_action = QAction("Orientation &Gizmo", self, checkable=True, checked=True)
        self.gizmo_action.setToolTip("Axes in the corner of the view: x red, y green, z blue")
        self.gizmo_action.triggered.connect(self.show_gizmo)
        self.wireframe_action = QAction("&Wireframe", self, checkable=True)
        self.wireframe_action.triggered.connect(self._wireframe_toggled)
        set_icon(self.wireframe_action, "wireframe")
        self.cavity_action = QAction("&Cavity", self, checkable=True)
        self.cavity_action.setToolTip(
            "Tint the surface by its curvature: darker in hollows, lighter on ridges, so small "
            "changes of shape show"
        )
        self.cavity_action.setChecked(self.view.cavity)
        self.cavity_action.triggered.connect(lambda on: self.view.set("cavity", bool(on)))
        self.profile_action = QAction("Falloff &Profile Over the Brush", self, checkable=True)
        self.profile_action.setToolTip(
            "Draw the brush's falloff curve over its ring at all times (else only while F "
            "drags the radius)"
        )
        self.profile_action.setChecked(self.view.falloff_profile)
        self.profile_action.triggered.connect(lambda on: self.view.set("falloff_profile", bool(on)))
        viewport.cursor_overlay.profile_always = self.view.falloff_profile
        viewport.set_cavity(self.view.cavity)

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
            if name == "studio":
                shading_menu.addSeparator()
            action = QAction(title, self, checkable=True)
            action.setToolTip(tip)
            action.setStatusTip(tip)
            if name.startswith("matcap:"):
                action.setIcon(_matcap_icon(name.split(":", 1)[1]))
            action.triggered.connect(lambda _c=False, n=name: self.set_shading(n))
            shading_group.addAction(action)
            shading_menu.addAction(action)
            self.shading_actions[name] = action
        self.shading_actions[self.shading].setChecked(True)
        view_menu.addAction(self.cavity_action)
        view_menu.addAction(self.profile_action)
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

    @property
    def shading(self) -> str:
        """The shading: ``"studio"`` or ``"matcap:<name>"`` (a key of :data:`SHADINGS`)."""
        view = self.view
        return "studio" if view.shading == "studio" else f"matcap:{view.matcap}"

    def set_shading(self, name: str) -> None:
        """Shade the model ``name`` (a key of :data:`SHADINGS`): the settings model takes it,
        the view follows and it is remembered."""
        if name not in SHADINGS:
            raise ParameterError(
                "name", f"name: unknown shading {name!r}; the shadings are {', '.join(SHADINGS)}"
            )
        if name == "studio":
            self.view.shading = "studio"
        else:
            self.view.update({"shading": "matcap", "matcap": name.split(":", 1)[1]})

    def _view_changed(self, event: ChangeEvent) -> None:
        """A view setting changed (menu, preset, script): store it and show it."""
        self.settings.setValue(f"{_GROUP}/{event.name}", event.value)
        if event.name in ("shading", "matcap"):
            if self.shading in self.shading_actions:
                self.shading_actions[self.shading].setChecked(True)
            self._apply_lights()
            self.apply_mesh_look()
        elif event.name == "cavity":
            self.cavity_action.setChecked(event.value)
            self.viewport.set_cavity(event.value)
        elif event.name == "falloff_profile":
            self.profile_action.setChecked(event.value)
            self.viewport.cursor_overlay.profile_always = event.value
            self.viewport.request_render()

    def _apply_lights(self) -> None:
        self.viewport.remove_all_lights()
        if self.view.shading == "studio":
            self.viewport.enable_lightkit()
        else:  # the matcap is the lighting; a headlight keeps the other actors (pins) lit
            self.viewport.add_light(pv.Light(light_type="headlight", intensity=1.0))
        self.viewport.request_render()

    def apply_mesh_look(self) -> None:
        """Shading and wireframe of the mesh actor (made anew by each ``set_mesh``)."""
        actor = self.viewport.mesh_actor
        if actor is None:
            return
        prop = actor.prop
        mode = self.view.shading
        prop.ambient, prop.diffuse, prop.specular, prop.specular_power = _SHADING_PROPS[mode]
        use_matcap(actor, self.view.matcap if mode == "matcap" else None)
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
