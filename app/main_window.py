"""Main window: viewport, brush bar, side panels, menus, status bar.

A thin view over :class:`app.document.Document` (which owns a :class:`gogreen_core.Sculptor`)
and one :class:`gogreen_core.settings.Settings` (brush, material, falloff, constraints) that the
brush bar and the panels are bound to; an :class:`gogreen_core.settings.EngineLink` feeds the
settings to the engine. Pointer events from the viewport go to the Qt-free
:class:`gogreen_core.tools.SculptTools`; every failure is shown as a message that leaves the
model as it was.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyvista as pv
from PySide6.QtCore import QBuffer, QIODevice, QSettings, Qt, QTimer
from PySide6.QtGui import QAction, QActionGroup, QCloseEvent, QImage, QKeySequence
from PySide6.QtWidgets import (
    QApplication,
    QDockWidget,
    QFileDialog,
    QLabel,
    QMainWindow,
    QMessageBox,
    QProgressBar,
    QPushButton,
    QTabWidget,
    QToolBar,
)

from app.brush_bar import BrushBar
from app.crash_recovery import CrashRecovery
from app.document import SAVE_FORMATS, Document
from app.icons import set_icon
from app.kernel_warmup import KernelWarmer
from app.keyboard import FocusKeys
from app.keymap import KeymapOverlay, binding, brush_action, display_keys, shortcuts
from app.mesh_edits import MeshEdits
from app.panels.falloff_panel import FalloffPanel
from app.panels.homogenization_panel import HomogenizationPanel
from app.panels.material_panel import MaterialPanel
from app.theme import DEFAULT_THEME, THEMES, Theme, apply_theme, theme
from app.viewport import SculptViewport
from gogreen_core.brushes import default_wrinkle_weights
from gogreen_core.material import Material
from gogreen_core.mesh_io import write_bytes_atomic, write_text_atomic
from gogreen_core.presets import Preset, builtin_presets, load_preset, save_preset
from gogreen_core.settings import ChangeEvent, EngineLink, Settings
from gogreen_core.tools import PointerEvent, SculptTools, ToolUpdate
from gogreen_core.validation import ParameterError

__all__ = ["MainWindow"]

MESH_FILTER = "Meshes (*.obj *.ply *.stl *.off);;All files (*)"
SAVE_FILTER = "Wavefront OBJ (*.obj);;Stanford PLY (*.ply);;STL (*.stl)"
MAX_RECENT = 8
FIRST_RUN_HINT = (
    "Welcome! Press ? (or F1, or Help → Keyboard & Mouse) to see every key, mouse and pen control"
)
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
#: Below this :func:`material_anisotropy` the wrinkle brush moves the surface like grab (its
#: reweighted degrees l > 2 carry next to nothing): the cubic c11=1, c12=.5, c44=.4 is 0.13,
#: the built-in layered / wood / fibre presets 0.65 to 0.83.
WRINKLE_MIN_ANISOTROPY = 0.25
WRINKLE_NEEDS = (
    "needs a layered or fibred (anisotropic) material: on this uniform one it moves the "
    "surface like Grab"
)
#: Tool tip of the wrinkle brush: what it does and what it needs, in an artist's words.
WRINKLE_TIP = (
    "Wrinkle: pulls like Grab and ripples the surface around the pull, along the "
    "material's layers or fibres; needs a layered material such as the “Layered sheet "
    "wrinkles” preset (ripple strength per degree: Falloff panel)"
)


def _save_filter(suffix: str) -> str:
    """The entry of :data:`SAVE_FILTER` for a file ending in ``suffix`` (``".ply"``); the
    first (OBJ) for any other."""
    entries = SAVE_FILTER.split(";;")
    return next((e for e in entries if f"*{suffix.lower()})" in e), entries[0])


def material_anisotropy(material: Material) -> float:
    """‖C − C_iso‖ / ‖C‖ (Frobenius, on the 3×3×3×3 tensor): 0 for an isotropic material,
    where C_iso, the closest isotropic tensor, has the same C_iijj and C_ijij."""
    c = material.tensor
    eye = np.eye(3)
    trace, shear = np.einsum("iijj", c), np.einsum("ijij", c)  # 9λ + 6μ, 3λ + 12μ
    mu = (3.0 * shear - trace) / 30.0
    lam = (trace - 6.0 * mu) / 9.0
    iso = lam * np.einsum("ij,kl", eye, eye) + mu * (
        np.einsum("ik,jl", eye, eye) + np.einsum("il,jk", eye, eye)
    )
    norm = np.linalg.norm(c)
    return float(np.linalg.norm(c - iso) / norm) if norm > 0 else 0.0


def wrinkle_preset() -> Preset:
    """The built-in preset made for the wrinkle brush ("Layered sheet wrinkles")."""
    return next(p for p in builtin_presets() if p.brush.kind == "wrinkle")


class MainWindow(QMainWindow):
    """GoGreen Sculpt's main window.

    Parameters
    ----------
    settings : QSettings, optional
        Where recent files, the theme and the first-run hint live (tests pass a temporary one).
    """

    def __init__(self, settings: QSettings | None = None):
        super().__init__()
        self.settings = settings or QSettings("GoGreen", "GoGreen Sculpt")
        # Before any widget is made: icons take the theme's colour when they are made.
        self.theme: Theme = apply_theme(QApplication.instance(), self._stored_theme())
        self.resize(1500, 920)
        #: The one source of truth of what the artist tunes; widgets and the engine follow it.
        self.model = Settings()
        self.engine_link = EngineLink(self.model, None, on_error=self._setting_refused)
        self.viewport = SculptViewport(self)
        self.setCentralWidget(self.viewport)
        self._viewport_colors()
        self.brush_bar = BrushBar(self.model.brush, self)
        self.addToolBar(Qt.ToolBarArea.TopToolBarArea, self.brush_bar)
        self.material_panel = MaterialPanel(settings=self.model)
        self.homogenization_panel = HomogenizationPanel()
        self.falloff_panel = FalloffPanel(settings=self.model)
        self._build_docks()
        self._build_menus()
        self._build_status_bar()
        self.document: Document | None = None
        self._constraint_actor = None
        self.tools = SculptTools(
            None,
            brush=lambda: self.model.brush.brush,
            first_pin_radius=self._first_pin_radius,
            ready=self._stroke_refusal,
            settings=self.model.brush,
            pen=lambda: self.model.pen,
        )
        self.brush_bar.bind_pen(self.model.pen)  # pressure toggles, stabilizer, spacing
        self.viewport.tools = self.tools  # F / Shift+F drags and number keys
        # Drag moves are applied once per event-loop turn, the newest position winning.
        self._tool_timer = QTimer(self)
        self._tool_timer.setSingleShot(True)
        self._tool_timer.setInterval(0)
        self._tool_timer.timeout.connect(self._process_tools)
        self.last_step_ms = 0.0
        self.kernel_warmer = KernelWarmer(self)
        self._announced_warmups: set[int] = set()
        #: The documents' crash-recovery journals and the offer of unsaved work at start.
        self.crash_recovery = CrashRecovery(self)
        self._connect()
        self.focus_keys = FocusKeys(self, self.viewport, self._shortcut_keys)
        #: The keymap drawn over the viewport (Help menu, ``?``, F1).
        self.keymap_overlay = KeymapOverlay(self.viewport)
        self.keymap_overlay.closed.connect(self.viewport.setFocus)
        self.shading = self._stored_shading()
        self.shading_actions[self.shading].setChecked(True)
        self._apply_lights()
        self._show_gizmo()
        self.show_first_run_hint()
        self.kernel_warmer.request(self.model.l_max)
        self._announced_warmups.add(self.model.l_max)

    # -- construction ------------------------------------------------------------------------
    def _build_docks(self) -> None:
        tabs = QTabWidget()
        tabs.addTab(self.material_panel, "Material")
        tabs.addTab(self.homogenization_panel, "Homogenize")
        tabs.addTab(self.falloff_panel, "Falloff")
        self.panel_tabs = tabs
        dock = QDockWidget("Panels", self)
        dock.setObjectName("panels")
        dock.setWidget(tabs)
        dock.setMinimumWidth(400)
        self.addDockWidget(Qt.DockWidgetArea.RightDockWidgetArea, dock)
        self.panels_dock = dock

    def _action(
        self, menu, text: str, slot, key: str | None = None, icon_name: str | None = None
    ) -> QAction:
        """A menu action; ``key``: its entry in :data:`app.keymap.KEYMAP`, which gives its
        shortcuts (the one table the keymap overlay and the README show)."""
        action = QAction(text, self)
        if key is not None:
            self._bind_keys(action, key)
        if icon_name is not None:
            set_icon(action, icon_name)
        action.triggered.connect(slot)
        menu.addAction(action)
        return action

    def _bind_keys(self, action: QAction, key: str, tip: str | None = None) -> None:
        """Give ``action`` the shortcuts of keymap entry ``key`` and a tool tip naming them
        (``tip`` or the keymap's description, then the keys)."""
        entry = binding(key)
        action.setShortcuts(shortcuts(key))
        action.setShortcutContext(Qt.ShortcutContext.WindowShortcut)
        keys = " / ".join(display_keys(k) for k in entry.keys)
        action.setToolTip(f"{tip or entry.description}  [{keys}]")
        self.keymap_actions[key] = action

    def _visibility_action(self, widget: QDockWidget | QToolBar) -> QAction:
        """Checkable View-menu entry that shows or hides a dock or tool bar.

        Made here instead of taken from ``toggleViewAction()``: for that C++-created action
        PySide6 6.12 once returned a stale wrapper of another class (a TypeError at start-up in
        CI); actions created from Python always have their own wrapper.
        """
        action = QAction(widget.windowTitle(), self, checkable=True, checked=True)
        # triggered (the user's choice), not toggled: echoes of visibilityChanged must not hide
        action.triggered.connect(lambda: widget.setVisible(action.isChecked()))
        widget.visibilityChanged.connect(action.setChecked)
        return action

    def _shortcut_keys(self) -> list[QKeySequence]:
        """The key sequences of the window's actions (menus and brush bar)."""
        return [
            key for a in self.findChildren(QAction) for key in a.shortcuts() if not key.isEmpty()
        ]

    def _build_menus(self) -> None:
        #: The window's actions by keymap entry (``"undo"``, ``"brush_grab"``, …).
        self.keymap_actions: dict[str, QAction] = {}
        bar = self.menuBar()
        file_menu = bar.addMenu("&File")
        self.new_action = self._action(file_menu, "&New", self.new_document, "new", "new")
        self._action(file_menu, "&Open…", self.open_dialog, "open", "open")
        self.recent_menu = file_menu.addMenu("Open &Recent")
        self._action(file_menu, "&Save", self.save, "save", "save")
        self._action(file_menu, "Save &As…", self.save_as_dialog, "save_as")
        file_menu.addSeparator()
        self.presets_menu = file_menu.addMenu("&Presets")
        self._fill_presets_menu()
        self._action(file_menu, "Load &Preset File…", self.load_preset_dialog)
        self._action(file_menu, "Save Pr&eset…", self.save_preset_dialog)
        self._action(file_menu, "Export Se&ssion…", self.export_session_dialog)
        self.screenshot_action = self._action(
            file_menu, "Export Scree&nshot…", self.screenshot_dialog, "screenshot", "screenshot"
        )
        file_menu.addSeparator()
        self._action(file_menu, "&Quit", self.close, "quit")
        edit_menu = bar.addMenu("&Edit")
        self.undo_action = self._action(edit_menu, "&Undo", self.undo, "undo", "undo")
        self.redo_action = self._action(edit_menu, "&Redo", self.redo, "redo", "redo")
        edit_menu.addSeparator()
        self._action(edit_menu, "Clear &Constraints", self.clear_constraints)
        bar_ = self.brush_bar
        self._action(edit_menu, "Radius Smaller", lambda: bar_.scale_radius(-1), "radius_smaller")
        self._action(edit_menu, "Radius Larger", lambda: bar_.scale_radius(1), "radius_larger")
        self._action(edit_menu, "Strength Lower", lambda: bar_.scale_strength(-1), "strength_lower")
        self._action(
            edit_menu, "Strength Higher", lambda: bar_.scale_strength(1), "strength_higher"
        )
        #: The Mesh menu (subdivide, mask) and what keeps the view in step with the mesh.
        self.mesh_edits = MeshEdits(self)
        self.mesh_menu = self.mesh_edits.build_menu(bar)
        view_menu = bar.addMenu("&View")
        self._action(view_menu, "Reset &Camera", self.reset_camera, "reset_camera", "home")
        self.view_actions = [self._visibility_action(w) for w in (self.panels_dock, self.brush_bar)]
        view_menu.addActions(self.view_actions)
        view_menu.addSeparator()
        theme_menu = view_menu.addMenu("&Theme")
        self.theme_actions: dict[str, QAction] = {}
        theme_group = QActionGroup(self)
        for name in THEMES:
            action = QAction(name.capitalize(), self, checkable=True)
            action.setChecked(name == self.theme.name)
            action.triggered.connect(lambda _c=False, n=name: self.set_theme(n))
            theme_group.addAction(action)
            theme_menu.addAction(action)
            self.theme_actions[name] = action
        shading_menu = view_menu.addMenu("&Shading")
        set_icon(shading_menu.menuAction(), "shading")
        self.shading_actions: dict[str, QAction] = {}
        shading_group = QActionGroup(self)
        for name, (title, tip) in SHADINGS.items():
            action = QAction(title, self, checkable=True)
            action.setToolTip(tip)
            action.setStatusTip(tip)
            action.triggered.connect(lambda _c=False, n=name: self.set_shading(n))
            shading_group.addAction(action)
            shading_menu.addAction(action)
            self.shading_actions[name] = action
        self.wireframe_action = self._action(
            view_menu, "&Wireframe", self._wireframe_toggled, "wireframe", "wireframe"
        )
        self.wireframe_action.setCheckable(True)
        self.gizmo_action = QAction("Orientation &Gizmo", self, checkable=True, checked=True)
        self.gizmo_action.setToolTip("Axes in the corner of the view: x red, y green, z blue")
        self.gizmo_action.triggered.connect(self._show_gizmo)
        view_menu.addAction(self.gizmo_action)
        help_menu = bar.addMenu("&Help")
        self.keymap_action = self._action(
            help_menu, "&Keyboard && Mouse", self.toggle_keymap, "keymap", "help"
        )
        # The brush bar's actions take their keys from the keymap too, and the project's icons.
        for kind, action in self.brush_bar.kind_actions.items():
            tip = action.toolTip().rsplit("  [", 1)[0]
            self._bind_keys(action, brush_action(kind), tip)
            set_icon(action, kind)
        pin = self.brush_bar.constraint_action
        self._bind_keys(pin, "pin_mode", pin.toolTip().rsplit(" [", 1)[0])
        set_icon(pin, "pin")
        self._refresh_recent()

    def _fill_presets_menu(self) -> None:
        """One entry per built-in preset (resources/presets), its description as status tip."""
        try:
            presets = builtin_presets()
        except ValueError as exc:  # a broken installation must not stop the window
            self.presets_menu.setEnabled(False)
            self.presets_menu.setToolTip(str(exc))
            return
        for preset in presets:
            action = self.presets_menu.addAction(preset.name)
            action.setStatusTip(preset.description)
            action.setToolTip(preset.description)
            action.triggered.connect(lambda _c=False, p=preset: self.apply_preset(p))
        self.presets_menu.setToolTipsVisible(True)

    def _build_status_bar(self) -> None:
        self.vertex_label = QLabel()
        self.step_label = QLabel("brush step: –")
        self.frame_label = QLabel("render: –")
        self.message_label = QLabel()
        # Busy indicator while kernels compile (first start, a new l_max): never a silent wait.
        self.compile_progress = self._status_progress(
            0,
            "",
            "Compiling the brush kernels (once per machine and l_max); strokes start after it",
        )
        # Progress of the background build of a big mesh's surface index (picking, shading)
        self.surface_progress = self._status_progress(
            100,
            "preparing %p%",
            "Preparing the opened mesh for picking and smooth shading; strokes start after it",
        )
        for label in (self.vertex_label, self.step_label, self.frame_label):
            label.setMinimumWidth(150)
            self.statusBar().addPermanentWidget(label)
        self.statusBar().addWidget(self.message_label, 1)
        # one click to a material the wrinkle brush needs (shown only when it lacks one)
        self.wrinkle_fix_button = QPushButton("Use a wrinkle material")
        self.wrinkle_fix_button.setToolTip(
            "Apply the “Layered sheet wrinkles” material and wrinkle weights (one undo step)"
        )
        self.wrinkle_fix_button.clicked.connect(self.use_wrinkle_material)
        self.wrinkle_fix_button.hide()
        self.statusBar().addWidget(self.wrinkle_fix_button)
        # a temporary message (the first-run hint) is drawn where the label is: not both
        self.statusBar().messageChanged.connect(
            lambda text: self.message_label.setHidden(bool(text))
        )

    def _connect(self) -> None:
        self.viewport.pointer_pressed.connect(self._pointer_pressed)
        self.viewport.pointer_moved.connect(self._pointer_moved)
        self.viewport.pointer_released.connect(self._pointer_released)
        self.viewport.hovered.connect(self._hovered)
        self.viewport.frame_rendered.connect(self._frame_rendered)
        self.viewport.tool_update.connect(lambda u: self._show_update(u, "Pin"))
        self.brush_bar.constraint_mode_changed.connect(self._constraint_mode_changed)
        self.viewport.radius_wheel.connect(self.brush_bar.scale_radius)
        self.viewport.strength_wheel.connect(self.brush_bar.scale_strength)
        self.model.brush.events.changed.connect(lambda _c: self._brush_changed())
        self.model.events.material.connect(self._material_changed)
        self.model.brush.events.kind.connect(lambda _e: self._check_wrinkle_material())
        shortcut = self.brush_bar.kind_actions["wrinkle"].toolTip().rpartition("  [")
        self._wrinkle_tip = WRINKLE_TIP + (shortcut[1] + shortcut[2] if shortcut[1] else "")
        self._check_wrinkle_material()
        # after the engine link (connected first): a settings step enables Undo at once
        self.model.events.changed.connect(lambda _c: self._refresh_title())
        self.model.events.l_max.connect(self._l_max_changed)
        self.homogenization_panel.material_ready.connect(self._use_homogenized)
        self.viewport.surface_progress.connect(
            lambda done: self.surface_progress.setValue(round(100 * done))
        )
        self.viewport.surface_ready.connect(self._surface_ready)
        self.viewport.surface_failed.connect(self._surface_failed)
        self.viewport.surface_pending.connect(self._surface_pending)
        self.kernel_warmer.ready.connect(self._kernels_ready)
        self.kernel_warmer.busy_changed.connect(self._compiling)
        self.kernel_warmer.failed.connect(
            lambda l_max, error: self.flash(f"Kernels for l_max = {l_max} failed: {error}")
        )

    # -- look --------------------------------------------------------------------------------
    def _stored_theme(self) -> str:
        name = self.settings.value("theme", DEFAULT_THEME)
        return name if name in THEMES else DEFAULT_THEME

    def set_theme(self, name: str) -> None:
        """Switch to theme ``name`` (one of :data:`app.theme.THEMES`) and remember it."""
        self.theme = apply_theme(QApplication.instance(), theme(name).name)
        self.settings.setValue("theme", self.theme.name)
        self.theme_actions[self.theme.name].setChecked(True)
        self.material_panel.refresh_colors()
        self.homogenization_panel.refresh_colors()
        self._viewport_colors()
        self.viewport.request_render()

    def _viewport_colors(self) -> None:
        bottom, top = self.theme.viewport_background
        self.viewport.set_background(bottom, top=top)
        if getattr(self, "gizmo_action", None) is not None:
            self._show_gizmo()  # its labels in the theme's text colour

    def _stored_shading(self) -> str:
        name = self.settings.value("shading", next(iter(SHADINGS)))
        return name if name in SHADINGS else next(iter(SHADINGS))

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
        self._apply_mesh_look()
        self.viewport.request_render()

    def _apply_lights(self) -> None:
        self.viewport.remove_all_lights()
        if self.shading == "clay":
            self.viewport.add_light(pv.Light(light_type="headlight", intensity=1.0))
        else:
            self.viewport.enable_lightkit()

    def _apply_mesh_look(self) -> None:
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

    @property
    def wireframe(self) -> bool:
        """The triangle edges are drawn over the surface (View → Wireframe, Shift+Z)."""
        return self.wireframe_action.isChecked()

    def _wireframe_toggled(self) -> None:
        self._apply_mesh_look()
        self.viewport.request_render()

    def _show_gizmo(self) -> None:
        """The orientation gizmo (pyvista's axes widget) when View → Orientation Gizmo is on."""
        self.viewport.hide_axes()
        if self.gizmo_action.isChecked():
            self.viewport.add_axes(interactive=False, line_width=2, color=self.theme.window_text)
        self.viewport.request_render()

    @property
    def gizmo_visible(self) -> bool:
        widget = getattr(self.viewport.renderer, "axes_widget", None)
        return bool(widget is not None and widget.GetEnabled())

    # -- help --------------------------------------------------------------------------------
    def toggle_keymap(self) -> None:
        """Show the keymap over the viewport, or hide it (Help menu, ``?``, F1)."""
        self.keymap_overlay.toggle_overlay()

    def show_first_run_hint(self) -> bool:
        """Once per user (remembered in the settings): say that ``?`` shows the controls.
        Returns whether the hint was shown."""
        if self.settings.value("keymap_hint_shown", False, type=bool):
            return False
        self.settings.setValue("keymap_hint_shown", True)
        self.statusBar().showMessage(FIRST_RUN_HINT, 30_000)
        return True

    # -- documents ---------------------------------------------------------------------------
    def _sculptor_options(self) -> dict:
        return self.model.sculptor_options()

    def set_document(self, document: Document) -> None:
        self.tools.cancel()
        previous, self.document = self.document, document
        self.tools.set_sculptor(document.sculptor)
        self.tools.cursor.hide()  # until the mouse moves over the new model
        if document.recovered:  # its settings are the ones to show
            self.engine_link.sculptor = document.sculptor
            self.engine_link.pull()
        else:
            self.engine_link.attach(document.sculptor)
        self.viewport.set_mesh(document.sculptor.vertices, document.sculptor.faces)
        self.mesh_edits.attach()
        self.surface_progress.setValue(0)
        self.surface_progress.setVisible(self.viewport.surface_building)
        self._apply_mesh_look()
        if self._constraint_actor is not None:
            self.viewport.remove_actor(self._constraint_actor, render=False)
        self._constraint_actor = None
        self._show_constraints()  # none, or a recovered document's
        self._brush_changed()
        self._refresh_title()
        self._refresh_status()
        self.crash_recovery.document_changed(previous, document)

    def open_default(self) -> None:
        self.set_document(Document.default(self._sculptor_options()))
        self.flash(f"Default model: {len(self.document.sculptor.vertices)} vertices")

    def new_document(self) -> bool:
        """File → New: the default model, after asking to save unsaved changes (as Open
        does). Returns whether the default model was opened."""
        if not self.maybe_save():
            return False
        self.open_default()
        return True

    def open_file(self, path: str) -> bool:
        """Open a mesh; on failure show why and keep the current model. Returns success."""
        try:
            document = Document.open(path, self._sculptor_options())
        except (ValueError, OSError) as exc:
            self.show_error("Cannot open the file", str(exc))
            return False
        self.set_document(document)
        self._add_recent(str(Path(path).resolve()))
        note = " – preparing it for picking…" if self.viewport.surface_building else ""
        self.flash(f"Opened {document.title}: {len(document.sculptor.vertices)} vertices{note}")
        return True

    def _surface_ready(self) -> None:
        """The background build of the mesh's surface index ended: strokes can start."""
        self.surface_progress.hide()
        self._apply_mesh_look()  # the actor now draws the index's arrays
        if self.document is not None:
            self.flash(f"{self.document.title} is ready to sculpt")

    def _surface_failed(self, error: str) -> None:
        self.surface_progress.hide()
        self.show_error("Cannot prepare the mesh for picking", error)

    def _surface_pending(self) -> None:
        """A left press while the surface index builds: say why nothing happens."""
        self.flash(
            f"Cannot sculpt yet: the mesh is being prepared for picking "
            f"({self.surface_progress.value()} %, see the status bar); "
            "strokes start as soon as it is ready"
        )

    def open_dialog(self) -> None:
        if not self.maybe_save():
            return
        path, _ = QFileDialog.getOpenFileName(self, "Open mesh", self._last_dir(), MESH_FILTER)
        if path:
            self.open_file(path)

    def save(self) -> bool:
        if self.document is None:
            return False
        if not self.document.path or Path(self.document.path).suffix.lower() not in SAVE_FORMATS:
            return self.save_as_dialog()
        return self.save_to(self.document.path)

    def save_to(self, path: str) -> bool:
        try:
            saved = self.document.save(path)
        except (ValueError, OSError) as exc:
            self.show_error("Cannot save", str(exc))
            return False
        self._add_recent(str(Path(saved).resolve()))
        self._refresh_title()
        self.flash(f"Saved {Path(saved).name}")
        return True

    def save_as_dialog(self) -> bool:
        if self.document is None:
            return False
        suggested = self._save_as_suggestion()
        path, chosen = QFileDialog.getSaveFileName(
            self, "Save mesh as", str(suggested), SAVE_FILTER, _save_filter(suggested.suffix)
        )
        if not path:
            return False
        if Path(path).suffix.lower() not in SAVE_FORMATS:
            path += ".ply" if "PLY" in chosen else ".stl" if "STL" in chosen else ".obj"
        return self.save_to(path)

    def _save_as_suggestion(self) -> Path:
        """What Save As proposes: the document's own path (as .obj when its format cannot be
        written, e.g. .off), or untitled.obj in the folder used last for the default model."""
        if self.document.path:
            path = Path(self.document.path)
            return path if path.suffix.lower() in SAVE_FORMATS else path.with_suffix(".obj")
        return Path(self._last_dir()) / "untitled.obj"

    def maybe_save(self) -> bool:
        """Ask about unsaved changes; True when it is fine to go on."""
        if self.document is None or not self.document.dirty:
            return True
        answer = QMessageBox.question(
            self,
            "Unsaved changes",
            f"{self.document.title} has unsaved changes. Save them?",
            QMessageBox.StandardButton.Save
            | QMessageBox.StandardButton.Discard
            | QMessageBox.StandardButton.Cancel,
        )
        if answer == QMessageBox.StandardButton.Save:
            return self.save()
        return answer == QMessageBox.StandardButton.Discard

    def closeEvent(self, event: QCloseEvent) -> None:
        if self.maybe_save():
            self.mesh_edits.cancel()
            self.crash_recovery.close()  # saved or discarded: the journal goes
            self.viewport.cancel_surface_build()  # it stops at its next progress report
            self.kernel_warmer.wait(60_000)  # a compilation cannot be interrupted
            self.viewport.close()
            event.accept()
        else:
            event.ignore()

    def _last_dir(self) -> str:
        recent = self.recent_files()
        return str(Path(recent[0]).parent) if recent else str(Path.home())

    def recent_files(self) -> list[str]:
        value = self.settings.value("recent_files", [])
        return [value] if isinstance(value, str) else list(value or [])

    def _add_recent(self, path: str) -> None:
        files = [path] + [p for p in self.recent_files() if p != path]
        self.settings.setValue("recent_files", files[:MAX_RECENT])
        self._refresh_recent()

    def _refresh_recent(self) -> None:
        self.recent_menu.clear()
        for path in self.recent_files():
            action = self.recent_menu.addAction(Path(path).name)
            action.setToolTip(path)
            action.triggered.connect(
                lambda _c=False, p=path: self.maybe_save() and self.open_file(p)
            )
        self.recent_menu.setEnabled(bool(self.recent_files()))

    # -- settings --------------------------------------------------------------------------
    def apply_material(self, material: Material) -> None:
        """Use ``material`` (through the settings: the panel and the engine follow)."""
        self.model.material = material

    def _material_changed(self, event: ChangeEvent) -> None:
        if event.source != "engine" and self.document is not None:
            if self.document.sculptor.material == event.value:
                self.flash("Material applied")
        self._check_wrinkle_material()

    @property
    def wrinkle_lacks_material(self) -> bool:
        """The wrinkle brush is picked and the material is (nearly) isotropic."""
        return (
            self.model.brush.kind == "wrinkle"
            and material_anisotropy(self.model.material) < WRINKLE_MIN_ANISOTROPY
        )

    def _check_wrinkle_material(self) -> None:
        """Say what the wrinkle brush needs (status bar, its tool tip) and offer the fix."""
        lacking = self.wrinkle_lacks_material
        action = self.brush_bar.kind_actions["wrinkle"]
        note = f"\n{WRINKLE_NEEDS[0].upper()}{WRINKLE_NEEDS[1:]}."
        action.setToolTip(self._wrinkle_tip + (note if lacking else ""))
        if lacking and self.wrinkle_fix_button.isHidden():
            self.statusBar().clearMessage()  # a temporary hint would hide the message
            self.flash(f"Wrinkle {WRINKLE_NEEDS}.")
        self.wrinkle_fix_button.setVisible(lacking)

    def use_wrinkle_material(self) -> None:
        """Apply the wrinkle preset's material and weights: one undo step."""
        preset = wrinkle_preset()
        l_max = self.model.l_max
        weights = preset.weights
        if len(weights) != l_max + 1:
            weights = default_wrinkle_weights(l_max)
        changed = self.model.update({"material": preset.material})
        # continued: the weights join the material's undo step
        self.model.update({"degree_weights": weights}, continued=bool(changed))
        self.flash(f"Wrinkle material: {preset.name} (Ctrl+Z undoes it)")

    def _use_homogenized(self, material: Material) -> None:
        self.apply_material(material)
        self.panel_tabs.setCurrentWidget(self.material_panel)

    def _l_max_changed(self, event: ChangeEvent) -> None:
        if self.kernel_warmer.request(event.value):
            self._announced_warmups.add(event.value)
            self.flash(f"Preparing the l_max = {event.value} kernels…")

    def _setting_refused(self, parameter: str, exc: Exception) -> None:
        """The engine refused a setting: the settings were restored from it; say why."""
        self.show_error(f"{parameter} not applied", str(exc))

    def _compiling(self, busy: bool) -> None:
        self.compile_progress.setVisible(busy)
        if busy:
            self.flash("Compiling the brush kernels (first start only)…")

    def _stroke_refusal(self) -> str | None:
        """Why a stroke may not start now (kernels still compiling, a subdivision running), or
        None."""
        if self.mesh_edits.busy:
            return self.mesh_edits.refusal()
        l_max = self.model.l_max
        if self.kernel_warmer.is_ready(l_max):
            return None
        self.kernel_warmer.request(l_max)
        return (
            f"the brush kernels for l_max = {l_max} are still compiling (see the status bar); "
            "strokes start as soon as they are ready"
        )

    def _kernels_ready(self, l_max: int, seconds: float) -> None:
        if l_max in self._announced_warmups:
            # more than a load from the disk cache: say that it compiled, once
            note = f" (compiled in {seconds:.1f} s, kept for next time)" if seconds > 0.5 else ""
            self.flash(f"l_max = {l_max} kernels ready{note}")

    def _brush_changed(self) -> None:
        """The ring shows the new radius at once."""
        state = self.tools.cursor.state
        if state is not None and self.document is not None:
            self.viewport.show_cursor(self.tools.cursor.refresh())  # requests the render

    # -- pointer tools -----------------------------------------------------------------------
    def _constraint_mode_changed(self, on: bool) -> None:
        self.tools.cancel()
        self.tools.mode = "pin" if on else "brush"

    def _first_pin_radius(self) -> None:
        """The first pin takes the brush radius."""
        self.model.constraint_radius = self.model.brush.radius

    def _pointer_pressed(self, event: PointerEvent) -> None:
        if self.document is not None:
            self._show_update(self.tools.press(event), "Cannot sculpt")

    def _pointer_moved(self, event: PointerEvent) -> None:
        self.tools.move(event)
        if not self._tool_timer.isActive():
            self._tool_timer.start()

    def _hovered(self, event: PointerEvent) -> None:
        self.tools.hover(event)
        if not self._tool_timer.isActive():
            self._tool_timer.start()

    def _pointer_released(self, _event: PointerEvent) -> None:
        self._tool_timer.stop()
        self._show_update(self.tools.release(), "Brush stopped")
        self._refresh_title()
        self._refresh_status()

    def _process_tools(self) -> None:
        """One engine step for the newest pointer position (older ones were coalesced)."""
        self._show_update(self.tools.flush(), "Brush stopped")

    def _show_update(self, update: ToolUpdate, error_title: str) -> None:
        """Draw what the tools changed; one render is requested for all of it."""
        if self.document is not None and update.all_moved:
            self.viewport.update_vertices(self.document.sculptor.vertices)
        elif self.document is not None and update.moved is not None:
            self.viewport.update_vertices(self.document.sculptor.vertices, update.moved)
        if self.document is not None and update.changed:
            self.mesh_edits.sync(update.moved)  # a mask stroke's tint
        if update.refused:  # not an error: e.g. kernels still compiling
            self.flash(f"{error_title}: {update.error}")
        elif update.error:
            self.show_error(error_title, update.error)
        if self.document is None or not update.changed:
            return
        if update.step_seconds:
            self.last_step_ms = 1e3 * update.step_seconds
            self._refresh_status()
        if update.pins_changed:
            self._show_constraints()
        if update.cursor is not None:
            self.viewport.show_cursor(update.cursor)
        elif update.hide_cursor:
            self.viewport.show_cursor(None)
        self.viewport.request_render()

    def _frame_rendered(self, ms: float) -> None:
        self.frame_label.setText(f"render: {ms:.0f} ms")

    def _show_constraints(self) -> None:
        """One marker actor for all pins, its points replaced in place."""
        points = self.document.sculptor.constraint_points
        self.viewport.show_pins(points, self.document.sculptor.constraint_reach)
        if self._constraint_actor is None and len(points):
            # add_actor, not add_points: pyvista's add_* would rebind viewport.mesh to the markers
            self._constraint_markers = pv.PolyData(points)
            self._constraint_actor = pv.Actor(mapper=pv.DataSetMapper(self._constraint_markers))
            prop = self._constraint_actor.prop
            prop.color, prop.point_size, prop.render_points_as_spheres = "#ff3355", 14, True
            self._constraint_actor.SetPickable(False)
            self.viewport.add_actor(self._constraint_actor, reset_camera=False, render=False)
        elif self._constraint_actor is not None:
            self._constraint_markers.points = points if len(points) else np.zeros((0, 3))
            self._constraint_markers.verts = np.hstack(
                [np.ones((len(points), 1), int), np.arange(len(points))[:, None]]
            ).ravel()
        self.viewport.request_render()

    # -- edit --------------------------------------------------------------------------------
    def undo(self) -> None:
        self._history_step(self.document.sculptor.undo if self.document else None, "Undo")

    def redo(self) -> None:
        self._history_step(self.document.sculptor.redo if self.document else None, "Redo")

    def _history_step(self, step, name: str) -> None:
        if step is None or self.tools.dragging:
            return
        if self.mesh_edits.busy:
            self.flash(f"Cannot {name.lower()}: {self.mesh_edits.refusal()}")
            return
        label = step()
        if label is None:
            self.flash(f"Nothing to {name.lower()}")
            return
        self.engine_link.pull()  # an undone setting shows in the panels again
        self.tools.cursor.hide()  # the surface under it moved: hidden until the mouse moves
        self.viewport.show_cursor(None)
        sculptor = self.document.sculptor
        if not self.mesh_edits.sync():  # a subdivision undone or redone shows its whole mesh
            self.viewport.update_vertices(sculptor.vertices, sculptor.history.restored_indices)
        self._show_constraints()  # the pins follow undo/redo
        self._refresh_title()
        self.flash(f"{name}: {label}")

    def clear_constraints(self) -> None:
        if self.document is not None:
            self.document.sculptor.clear_constraints()
            self._show_constraints()

    def reset_camera(self) -> None:
        self.viewport.home_view()

    # -- presets, session, screenshot --------------------------------------------------------
    def preset(self, name: str = "") -> Preset:
        """The current material + falloff + brush as a :class:`Preset`."""
        return self.model.preset(name)

    def apply_preset(self, preset: Preset) -> None:
        """Give the settings ``preset``'s values (panels, brush bar and engine follow)."""
        self.model.apply_preset(preset)
        self.flash(f"Preset: {preset.name}" if preset.name else "Preset loaded")

    def _json_dialog(self, title: str, save: bool) -> str:
        dialog = QFileDialog.getSaveFileName if save else QFileDialog.getOpenFileName
        path, _ = dialog(self, title, self._last_dir(), "JSON (*.json)")
        if path and save and not path.endswith(".json"):
            path += ".json"
        return path

    def load_preset_dialog(self) -> None:
        path = self._json_dialog("Load preset", save=False)
        if path:
            try:
                self.apply_preset(load_preset(path))
            except ValueError as exc:
                self.show_error("Cannot load the preset", str(exc))

    def save_preset_dialog(self) -> None:
        path = self._json_dialog("Save preset", save=True)
        if path:
            self._write(path, lambda: save_preset(self.preset(Path(path).stem), path))

    def export_session_dialog(self) -> None:
        if self.document is None:
            return
        path = self._json_dialog("Export session (for gogreen replay)", save=True)
        if path:
            text = json.dumps(self.document.sculptor.session(), indent=1)
            self._write(path, lambda: write_text_atomic(path, text))

    def _write(self, path: str, write) -> None:
        try:
            write()
            self.flash(f"Wrote {Path(path).name}")
        except ValueError as exc:  # MeshFileError from the atomic writer
            self.show_error("Cannot write", str(exc))

    def screenshot_dialog(self) -> None:
        path, _ = QFileDialog.getSaveFileName(
            self, "Export screenshot", self._last_dir(), "PNG (*.png)"
        )
        if path:
            self.save_screenshot(path if path.endswith(".png") else path + ".png")

    def save_screenshot(self, path: str) -> bool:
        """PNG of the viewport only (no panels, menus, overlays or brush cursor), written
        atomically (``write_bytes_atomic``); the status bar names the file. Returns success."""
        target = Path(path)
        try:
            pixels = self.viewport.model_image()
            height, width = pixels.shape[:2]
            image = QImage(pixels.data, width, height, 3 * width, QImage.Format.Format_RGB888)
            png = QBuffer()
            png.open(QIODevice.OpenModeFlag.WriteOnly)
            if not image.save(png, "PNG"):
                raise RuntimeError("Qt could not encode the PNG")
            write_bytes_atomic(target, png.data().data())
        except (OSError, RuntimeError, ValueError) as exc:
            self.show_error("Cannot write the screenshot", f"{target}: {exc}")
            return False
        self.flash(f"Screenshot saved: {target} ({width}×{height})")
        return True

    # -- feedback ----------------------------------------------------------------------------
    def show_error(self, title: str, message: str) -> None:
        self.flash(f"{title}: {message}")
        QMessageBox.warning(self, title, message)

    def _status_progress(self, maximum: int, text: str, tip: str) -> QProgressBar:
        """A hidden progress bar at the right of the status bar (``maximum`` 0: busy, no
        fraction)."""
        bar = QProgressBar()
        bar.setRange(0, maximum)
        bar.setMaximumWidth(160)
        bar.setFormat(text)
        bar.setToolTip(tip)
        bar.hide()
        self.statusBar().addPermanentWidget(bar)
        return bar

    def flash(self, text: str) -> None:
        self.message_label.setText(text)

    def _refresh_title(self) -> None:
        if self.document is not None:
            mark = " •" if self.document.dirty else ""
            self.setWindowTitle(f"{self.document.title}{mark} — GoGreen Sculpt")
        self.undo_action.setEnabled(bool(self.document and self.document.sculptor.history.can_undo))
        self.redo_action.setEnabled(bool(self.document and self.document.sculptor.history.can_redo))

    def _refresh_status(self) -> None:
        if self.document is not None:
            self.vertex_label.setText(f"{len(self.document.sculptor.vertices):,} vertices")
        self.step_label.setText(f"brush step: {self.last_step_ms:.1f} ms")
