"""Main window: viewport, brush bar, side panels, menus, status bar.

The window wires menus and documents. It owns the open :class:`app.document.Document` and one
:class:`gogreen_core.interaction.settings.Settings` (brush, material, falloff, constraints) that the
brush bar and the panels are bound to; an :class:`gogreen_core.interaction.settings.EngineLink`
feeds the settings to the engine. Pointer events never pass through it: the viewport hands them to
the Qt-free :class:`gogreen_core.interaction.tools.SculptTools` and draws what they give back
(:mod:`app.viewport`); the window hears only what it reports (a message, an error, a stroke's
end). The File menu's work is :class:`app.files.FileActions`, the View menu's look
:class:`app.look.ViewLook`; every failure is a message that leaves the model as it was.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

from PySide6.QtCore import QPoint, QSettings, QSize, Qt, QTimer
from PySide6.QtGui import QAction, QCloseEvent, QKeySequence
from PySide6.QtWidgets import (
    QApplication,
    QDockWidget,
    QMainWindow,
    QMenu,
    QMessageBox,
    QTabWidget,
    QToolBar,
)

from app.background import shared_pool
from app.bindings import panel_words, refresh
from app.brush_bar import BrushBar
from app.crash_recovery import CrashRecovery
from app.document import Document
from app.field_preview import FieldPreviewer
from app.files import FileActions
from app.icons import set_icon
from app.kernel_warmup import KernelWarmer
from app.keyboard import FocusKeys
from app.keymap import binding, brush_action, display_keys, shortcuts
from app.keymap_overlay import KeymapOverlay
from app.look import SHADINGS, ViewLook, stored_theme
from app.memory import release_freed_memory
from app.mesh_edits import MeshEdits
from app.navigation import OPPOSITE_VIEWS, VIEW_TITLES, NavigationPreferences, ViewAction
from app.panels.falloff_panel import FalloffPanel
from app.panels.homogenization_panel import HomogenizationPanel
from app.panels.material_panel import MaterialPanel
from app.status import StatusArea, active_material_name
from app.theme import apply_theme, qt_application
from app.viewport import SculptViewport
from app.wrinkle_hint import WrinkleHint, material_anisotropy, wrinkle_preset
from gogreen_core.files.presets import Preset
from gogreen_core.interaction.settings import ChangeEvent, EngineLink, Settings
from gogreen_core.interaction.tools import SculptTools
from gogreen_core.mesh.resolution import edges_per_eps
from gogreen_core.physics.material import Material
from gogreen_core.sculpt.brushes import brush_row
from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["FIRST_RUN_HINT", "SHADINGS", "MainWindow", "material_anisotropy", "wrinkle_preset"]

#: Share of the screen's free width and height the window opens with.
WINDOW_SHARE = 0.94
#: The settings' fields as the panels name them (in messages).
SETTING_NAMES = {
    "material": "Material",
    "falloff": "Falloff",
    "l_max": "Truncation l_max",
    "brush_weights": "Degree weights",
    "constraint_radius": "Pin radius",
}
FIRST_RUN_HINT = (
    "Welcome! Press ? (or F1, or Help → Keyboard & Mouse) to see every key, mouse and pen control"
)


def fit_to_screen(window: QMainWindow) -> None:
    """Open ``window`` centred over :data:`WINDOW_SHARE` of its screen's free area."""
    screen = window.screen() or QApplication.primaryScreen()
    free = screen.availableGeometry()
    size = QSize(round(free.width() * WINDOW_SHARE), round(free.height() * WINDOW_SHARE))
    window.resize(size)
    window.move(free.center() - QPoint(size.width() // 2, size.height() // 2))


class MainWindow(QMainWindow):
    """GoGreen Sculpt's main window.

    Parameters
    ----------
    settings : QSettings, optional
        Where recent files, the theme and the first-run hint live (tests pass a temporary one).

    Parts (public for scripting and tests): ``viewport``, ``brush_bar``, ``material_panel``,
    ``homogenization_panel``, ``falloff_panel``, ``files`` (:class:`FileActions`), ``look``
    (:class:`ViewLook`), ``status`` (:class:`StatusArea`), ``tools``, ``model``.
    """

    def __init__(self, settings: QSettings | None = None):
        super().__init__()
        self.settings = settings or QSettings("GoGreen", "GoGreen Sculpt")
        # Before any widget is made: icons take the theme's colour when they are made.
        theme = apply_theme(qt_application(), stored_theme(self.settings))
        fit_to_screen(self)
        #: The one source of truth of what the artist tunes; widgets and the engine follow it.
        self.model = Settings()
        self.engine_link = EngineLink(self.model, None, on_error=self._setting_refused)
        self.document: Document | None = None
        self.viewport = SculptViewport(self)
        self.setCentralWidget(self.viewport)
        self.look = ViewLook(self, self.viewport, self.settings, theme, self.model.view)
        #: View → Field Preview: what the brush would move, coloured under the resting cursor.
        self.field_preview = FieldPreviewer(self, self.viewport, self.model, self.settings)
        self.files = FileActions(self)
        self.brush_bar = BrushBar(self.model.brush, self)
        self.addToolBar(Qt.ToolBarArea.TopToolBarArea, self.brush_bar)
        self.brush_bar.bind_pen(self.model.pen)  # pressure toggles, stabilizer, spacing
        self.material_panel = MaterialPanel(settings=self.model)
        self.homogenization_panel = HomogenizationPanel()
        self.falloff_panel = FalloffPanel(settings=self.model)
        # curves made from a Gaussian get a control point every two edges of the mesh
        self.falloff_panel.resolution = lambda: (
            None if self.sculptor is None else edges_per_eps(self.sculptor, self.model.brush.radius)
        )
        self.look.refresh_colors += [
            self.material_panel.refresh_colors,
            self.homogenization_panel.refresh_colors,
        ]
        self._build_docks()
        self.status = StatusArea(self.statusBar())
        self.message_label = self.status.message_label
        self.surface_progress = self.status.surface_progress
        self.wrinkle_fix_button = self.status.wrinkle_fix_button
        self._build_menus()

        def first_pin_radius() -> None:  # the first pin takes the brush radius
            self.model.constraint_radius = self.model.brush.radius

        self.tools = SculptTools(
            None,
            brush=lambda: self.model.brush.brush,
            first_pin_radius=first_pin_radius,
            ready=self._stroke_refusal,
            settings=self.model.brush,
            pen=lambda: self.model.pen,
        )
        self.viewport.set_tools(self.tools)
        self.last_step_ms = 0.0
        self.kernel_warmer = KernelWarmer(self)
        self._announced_warmups: set[int] = set()
        #: The documents' crash-recovery journals and the offer of unsaved work at start.
        self.crash_recovery = CrashRecovery(self)
        self._connect()
        self.focus_keys = FocusKeys(
            self, self.viewport, self._shortcut_keys, lambda: self.findChildren(QAction)
        )
        #: The keymap drawn over the viewport (Help menu, ``?``, F1).
        self.keymap_overlay = KeymapOverlay(self.viewport)
        self.keymap_overlay.closed.connect(self.viewport.setFocus)
        self.look.apply()
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
        self,
        menu: QMenu,
        text: str,
        slot: Callable,
        key: str | None = None,
        icon_name: str | None = None,
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
        """Checkable View-menu entry that shows or hides a dock or tool bar (not
        ``toggleViewAction()``: PySide6 once gave a stale wrapper of that C++-made action)."""
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
        bar, files = self.menuBar(), self.files

        def later(slot: Callable[[], object], what: str = "") -> Callable[[], None]:
            # what reads or replaces the mesh waits for a brush step off the GUI thread
            return lambda *_args: self.viewport.stroke_worker.after_step(slot, what)

        file_menu = bar.addMenu("&File")
        new = later(files.new_document, "New")
        self.new_action = self._action(file_menu, "&New", new, "new", "new")
        self._action(file_menu, "&Open…", later(files.open_dialog, "Opening"), "open", "open")
        files.recent_menu = file_menu.addMenu("Open &Recent")
        self._action(file_menu, "&Save", later(files.save, "Saving"), "save", "save")
        self._action(file_menu, "Save &As…", later(files.save_as_dialog, "Saving"), "save_as")
        file_menu.addSeparator()
        files.fill_presets_menu(file_menu.addMenu("&Presets"))
        self._action(file_menu, "Load &Preset File…", files.load_preset_dialog)
        self._action(file_menu, "Save Pr&eset…", files.save_preset_dialog)
        self._action(file_menu, "Export Se&ssion…", later(files.export_session_dialog, "Export"))
        self.screenshot_action = self._action(
            file_menu, "Export Scree&nshot…", files.screenshot_dialog, "screenshot", "screenshot"
        )
        file_menu.addSeparator()
        self._action(file_menu, "&Quit", self.close, "quit")
        edit_menu = bar.addMenu("&Edit")
        self.undo_action = self._action(edit_menu, "&Undo", self.undo, "undo", "undo")
        self.redo_action = self._action(edit_menu, "&Redo", self.redo, "redo", "redo")
        edit_menu.addSeparator()
        self._action(edit_menu, "Clear &Constraints", later(self.clear_constraints))
        brush = self.brush_bar
        self._action(edit_menu, "Radius Smaller", lambda: brush.scale_radius(-1), "radius_smaller")
        self._action(edit_menu, "Radius Larger", lambda: brush.scale_radius(1), "radius_larger")
        self._action(
            edit_menu, "Strength Lower", lambda: brush.scale_strength(-1), "strength_lower"
        )
        self._action(
            edit_menu, "Strength Higher", lambda: brush.scale_strength(1), "strength_higher"
        )
        #: The Mesh menu (subdivide, mask) and what keeps the view in step with the mesh.
        self.mesh_edits = MeshEdits(self)
        self.mesh_menu = self.mesh_edits.build_menu(bar)
        view_menu = bar.addMenu("&View")
        self._action(view_menu, "Reset &Camera", self.viewport.home_view, "reset_camera", "home")
        views, viewport = view_menu.addMenu("Camera &Views"), self.viewport
        for key, opposite in OPPOSITE_VIEWS.items():
            # numpad 1, 3, 7: one side, and with Ctrl the opposite one (Blender's keys)
            view_action = ViewAction(VIEW_TITLES[key], self, key, opposite, viewport.show_view)
            self._bind_keys(view_action, key)
            views.addAction(view_action)
            self._action(views, VIEW_TITLES[opposite], partial(viewport.show_view, opposite))
        self._action(views, "Perspective / &Orthographic", viewport.toggle_projection, "projection")
        self._action(
            views, "&Frame About the Cursor", lambda: viewport.frame_under_cursor(), "frame_cursor"
        )
        self.navigation = NavigationPreferences(self, viewport, self.settings, self.model.view)
        self.navigation.fill_menu(view_menu)
        self.view_actions = [self._visibility_action(w) for w in (self.panels_dock, self.brush_bar)]
        view_menu.addActions(self.view_actions)
        view_menu.addSeparator()
        self.look.fill_menu(view_menu)
        self._bind_keys(self.look.wireframe_action, "wireframe")
        view_menu.addAction(self.field_preview.action)
        self._bind_keys(self.field_preview.action, "field_preview")
        help_menu = bar.addMenu("&Help")
        self.keymap_action = self._action(  # (the overlay is made after the menus)
            help_menu, "&Keyboard && Mouse", lambda: self.keymap_overlay.toggle_overlay(), "keymap"
        )
        set_icon(self.keymap_action, "help")
        # The brush bar's actions take their keys from the keymap too, and the project's icons.
        for kind, action in self.brush_bar.kind_actions.items():
            tip = action.toolTip().rsplit("  [", 1)[0]
            self._bind_keys(action, brush_action(kind), tip)
            set_icon(action, brush_row(kind).icon)
        pin = self.brush_bar.constraint_action
        self._bind_keys(pin, "pin_mode", pin.toolTip().rsplit(" [", 1)[0])
        set_icon(pin, "pin")
        files.refresh_recent()

    def _connect(self) -> None:
        viewport, status = self.viewport, self.status
        viewport.stroke_worker.busy.connect(status.show_busy)  # a slow brush step runs
        viewport.tool_message.connect(self.flash)
        viewport.tool_error.connect(self.show_error)
        viewport.step_timed.connect(self._step_timed)
        viewport.faces_replaced.connect(lambda: self.mesh_edits.sync())
        viewport.stroke_ended.connect(self._stroke_ended)
        viewport.frame_rendered.connect(status.show_frame_time)
        viewport.radius_wheel.connect(self.brush_bar.scale_radius)
        viewport.strength_wheel.connect(self.brush_bar.scale_strength)
        viewport.surface_progress.connect(status.show_surface_progress)
        viewport.surface_ready.connect(self._surface_ready)
        viewport.surface_failed.connect(self._surface_failed)
        viewport.surface_pending.connect(self._surface_pending)

        def release_if_settled() -> None:  # asked again when it runs: a new mesh may build
            if not (self.kernel_warmer.busy or viewport.surface_building):
                release_freed_memory(collect=False)

        def release_when_settled(*_args: object) -> None:  # start-up or opening work done
            QTimer.singleShot(0, release_if_settled)

        for settled in (viewport.surface_ready, self.kernel_warmer.busy_changed):
            settled.connect(release_when_settled)
        self.brush_bar.constraint_mode_changed.connect(
            lambda on: viewport.stroke_worker.after_step(partial(self._constraint_mode_changed, on))
        )
        self.model.brush.events.changed.connect(lambda _c: viewport.refresh_cursor())
        self.model.events.material.connect(self._material_changed)
        self.material_panel.form.events.angles.connect(
            lambda _e: status.show_material(active_material_name(self))
        )
        status.show_material(active_material_name(self))
        self.wrinkle_hint = WrinkleHint(
            self.model, self.brush_bar.kind_actions["wrinkle"], self.wrinkle_fix_button, self.note
        )
        # after the engine link (connected first): a settings step enables Undo at once
        self.model.events.changed.connect(lambda _c: self.refresh_title())
        self.model.events.l_max.connect(self._l_max_changed)
        self.homogenization_panel.material_ready.connect(self._use_homogenized)
        self.kernel_warmer.ready.connect(self._kernels_ready)
        self.kernel_warmer.busy_changed.connect(self._compiling)
        self.kernel_warmer.progress.connect(self._compile_progress)
        self.kernel_warmer.failed.connect(
            lambda l_max, error: self.flash(f"Kernels for l_max = {l_max} failed: {error}")
        )

    # -- help --------------------------------------------------------------------------------
    def show_first_run_hint(self) -> bool:
        """Once per user (remembered in the settings): say that ``?`` shows the controls.
        Returns whether the hint was shown."""
        if self.settings.value("keymap_hint_shown", False, type=bool):
            return False
        self.settings.setValue("keymap_hint_shown", True)
        self.statusBar().showMessage(FIRST_RUN_HINT, 30_000)
        return True

    # -- documents ---------------------------------------------------------------------------
    @property
    def sculptor(self) -> Sculptor | None:
        """The open document's engine (None before a document is open)."""
        return self.document.sculptor if self.document is not None else None

    def set_document(self, document: Document) -> None:
        """Edit ``document`` from now on: the tools, the engine link and the view follow, and
        every panel shows the settings in effect."""
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
        self.look.apply_mesh_look()
        self.viewport.show_sculptor()  # its pins: none, or a recovered document's
        refresh()  # every panel shows the settings in effect, refused inputs dropped
        self.refresh_title()
        self._refresh_status()
        self.crash_recovery.document_changed(previous, document)
        if previous is not None:  # once its last queued reports are delivered
            del previous
            QTimer.singleShot(0, release_freed_memory)

    def _surface_ready(self) -> None:
        """The background build of the mesh's surface index ended: strokes can start."""
        self.surface_progress.hide()
        self.look.apply_mesh_look()  # the actor now draws the index's arrays
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

    def closeEvent(self, event: QCloseEvent) -> None:
        if self.viewport.stroke_worker.running:  # closes once the brush step ends
            event.ignore()
            self.viewport.stroke_worker.after_step(self.close, "Closing")
        elif self.files.maybe_save():
            self.mesh_edits.cancel()
            self.crash_recovery.close()  # saved or discarded: the journal goes
            self.viewport.cancel_surface_build()  # it stops at its next progress report
            # background jobs stop at their next progress report (a compilation goes on in
            # its own process and needs no waiting for)
            self.falloff_panel.truncation.runner.cancel()
            self.field_preview.runner.cancel()
            shared_pool().waitForDone(10_000)
            self.viewport.close()
            event.accept()
        else:
            event.ignore()

    # -- settings ----------------------------------------------------------------------------
    def apply_material(self, material: Material) -> None:
        """Use ``material`` (through the settings: the panel and the engine follow)."""
        self.model.material = material

    def _material_changed(self, event: ChangeEvent) -> None:
        self.status.show_material(active_material_name(self))
        sculptor = self.sculptor
        if (
            event.source != "engine"
            and sculptor is not None
            and sculptor.settings.material == event.value
        ):
            self.flash("Material applied")

    def _use_homogenized(self, material: Material) -> None:
        self.apply_material(material)
        self.panel_tabs.setCurrentWidget(self.material_panel)

    def _l_max_changed(self, event: ChangeEvent) -> None:
        if self.kernel_warmer.request(event.value):
            self._announced_warmups.add(event.value)
            self.flash(f"Preparing the l_max = {event.value} kernels…")

    def _setting_refused(self, parameter: str, exc: Exception) -> None:
        """The engine refused a setting: the settings were restored from it; say why, in
        the panels' words."""
        name = SETTING_NAMES.get(parameter.rsplit(".", 1)[-1], parameter)
        self.show_error(f"{name} not applied", panel_words(str(exc), SETTING_NAMES))

    def _compiling(self, busy: bool) -> None:
        self.status.compile_progress.setVisible(busy)
        if busy:  # a busy bar until the driver counts units missing from the cache
            self.status.compile_progress.setRange(0, 0)
            self.flash(
                "Preparing the brush kernels (compiled on the first start only): strokes run on "
                "the NumPy path meanwhile"
            )

    def _compile_progress(self, done: int, total: int, seconds_left: float, now: str) -> None:
        """Units missing from the compile cache are compiling: say what (``now``), which count
        and about how long is left (``seconds_left`` < 0: not known yet)."""
        self.status.compile_progress.setVisible(done < total)
        left = None if seconds_left < 0 else seconds_left
        self.flash(self.status.show_compile_progress(done, total, left, now))

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

    def _kernels_ready(self, l_max: int, seconds: float, compiled: bool) -> None:
        if l_max in self._announced_warmups:
            # say what happened: compiled (once per machine) or only loaded from the cache
            note = (
                f" (compiled in {seconds:.1f} s, kept for next time)"
                if compiled
                else f" (loaded in {seconds:.1f} s)"
            )
            self.flash(f"l_max = {l_max} kernels ready{note}")

    def _constraint_mode_changed(self, on: bool) -> None:
        self.tools.cancel()
        self.tools.mode = "pin" if on else "brush"
        self.viewport.set_pin_mode(on)

    # -- edit --------------------------------------------------------------------------------
    def undo(self) -> None:
        self._history_step("undo")

    def redo(self) -> None:
        self._history_step("redo")

    def _history_step(self, name: str) -> None:
        sculptor, worker = self.sculptor, self.viewport.stroke_worker
        if worker.running:  # after the brush step (and the release waiting for it)
            worker.after_step(partial(self._history_step, name), name.title())
            return
        if self.tools.dragging:
            self.flash(f"Cannot {name} during a stroke")
            return
        if self.mesh_edits.busy:
            self.flash(f"Cannot {name}: {self.mesh_edits.refusal()}")
            return
        label = getattr(sculptor, name)() if sculptor is not None else None
        if label is None or sculptor is None:
            self.flash(f"Nothing to {name}")
            return
        self.engine_link.pull()  # an undone setting shows in the panels again
        refresh()
        # a subdivision undone or redone shows its whole mesh
        self.mesh_edits.sync(sculptor.history.restored_indices, stepped=True)
        self.refresh_title()
        self._refresh_status()  # a dynamic-topology stroke undone: another vertex count
        # past tense: "Undo: Scale stroke" read as what the next undo would do, and stayed
        # on while later strokes were made
        self.flash(f"{'Undone' if name == 'undo' else 'Redone'}: {label}")

    def clear_constraints(self) -> None:
        if self.sculptor is not None:
            self.sculptor.clear_constraints()
            self.viewport.show_sculptor()

    # -- presets -----------------------------------------------------------------------------
    def preset(self, name: str = "") -> Preset:
        """The current material + falloff + brush as a :class:`Preset`."""
        return self.model.preset(name)

    def apply_preset(self, preset: Preset) -> None:
        """Give the settings ``preset``'s values (panels, brush bar and engine follow)."""
        self.model.apply_preset(preset)
        refresh()
        self.flash(f"Preset: {preset.name}" if preset.name else "Preset loaded")

    # -- feedback ----------------------------------------------------------------------------
    def flash(self, text: str) -> None:
        """Say ``text`` in the status bar (until the next message)."""
        self.message_label.setText(text)

    def unsay(self, text: str) -> None:
        """Take ``text`` from the status bar if it still says it (a refusal mended or
        cancelled)."""
        if self.message_label.text() == text:
            self.message_label.clear()

    def note(self, text: str) -> None:
        """Say ``text`` in the status bar now, over a temporary hint shown there."""
        self.statusBar().clearMessage()
        self.flash(text)

    def show_error(self, title: str, message: str) -> None:
        self.flash(f"{title}: {message}")
        QMessageBox.warning(self, title, message)

    def _step_timed(self, ms: float) -> None:
        self.last_step_ms = ms
        self._refresh_status()

    def _stroke_ended(self) -> None:
        self.refresh_title()
        self._refresh_status()

    def refresh_title(self) -> None:
        """The title (document, unsaved mark) and the Undo / Redo entries."""
        sculptor = self.sculptor
        if self.document is not None:
            mark = " •" if self.document.dirty else ""
            self.setWindowTitle(f"{self.document.title}{mark} — GoGreen Sculpt")
        history = sculptor.history if sculptor is not None else None
        for action, name, labels in (
            (self.undo_action, "Undo", history.undo_labels[-1:] if history else []),
            (self.redo_action, "Redo", history.redo_labels[:1] if history else []),
        ):
            # named after what it will do; kept enabled so that the key says "Nothing to …"
            what = labels[0].replace("_", " ") if labels else ""
            action.setText(f"&{name} {what}" if what else f"&{name} (nothing to {name.lower()})")

    def _refresh_status(self) -> None:
        sculptor = self.sculptor
        self.status.show_counts(len(sculptor.vertices) if sculptor else None, self.last_step_ms)
