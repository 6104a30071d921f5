"""The File menu's work: new, open, recent files, save, save as, presets, session, screenshot.

:class:`FileActions` asks and reports through its window (dialogs, status bar) and hands an
opened document to the window (``window.set_document``); every failure is a message that keeps
the model being edited.
"""

from __future__ import annotations

import json
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING

from PySide6.QtCore import QBuffer, QIODevice, QObject
from PySide6.QtGui import QImage
from PySide6.QtWidgets import QFileDialog, QMenu, QMessageBox

from app.document import SAVE_FORMATS, Document
from gogreen_core.files.presets import builtin_presets, load_preset, save_preset
from gogreen_core.mesh.mesh_io import write_bytes_atomic, write_text_atomic
from gogreen_core.physics.material_words import describe_material

if TYPE_CHECKING:
    from app.main_window import MainWindow

__all__ = ["MAX_RECENT", "MESH_FILTER", "SAVE_FILTER", "FileActions"]

MESH_FILTER = "Meshes (*.obj *.ply *.stl *.off);;All files (*)"
SAVE_FILTER = "Wavefront OBJ (*.obj);;Stanford PLY (*.ply);;STL (*.stl)"
MAX_RECENT = 8


def _save_filter(suffix: str) -> str:
    """The entry of :data:`SAVE_FILTER` for a file ending in ``suffix`` (``".ply"``); the
    first (OBJ) for any other."""
    entries = SAVE_FILTER.split(";;")
    return next((e for e in entries if f"*{suffix.lower()})" in e), entries[0])


class FileActions(QObject):
    """Documents and files of ``window`` (a :class:`app.main_window.MainWindow`)."""

    def __init__(self, window: MainWindow) -> None:
        super().__init__(window)
        self.window = window
        self.recent_menu: QMenu | None = None
        self.presets_menu: QMenu | None = None

    # -- documents ---------------------------------------------------------------------------
    def open_default(self) -> None:
        """The embedded default model."""
        window = self.window
        document = Document.default(window.model.sculptor_options())
        window.set_document(document)
        window.flash(f"Default model: {len(document.sculptor.vertices)} vertices")

    def new_document(self) -> bool:
        """File → New: the default model, after asking to save unsaved changes (as Open
        does). Returns whether the default model was opened."""
        if not self.maybe_save():
            return False
        self.open_default()
        return True

    def open_file(self, path: str) -> bool:
        """Open a mesh; on failure show why and keep the current model. Returns success."""
        window = self.window
        try:
            document = Document.open(path, window.model.sculptor_options())
        except (ValueError, OSError) as exc:
            window.show_error("Cannot open the file", str(exc))
            return False
        window.set_document(document)
        self._add_recent(str(Path(path).resolve()))
        note = " – preparing it for picking…" if window.viewport.surface_building else ""
        window.flash(f"Opened {document.title}: {len(document.sculptor.vertices)} vertices{note}")
        return True

    def open_dialog(self) -> None:
        if not self.maybe_save():
            return
        path, _ = QFileDialog.getOpenFileName(
            self.window, "Open mesh", self._last_dir(), MESH_FILTER
        )
        if path:
            self.open_file(path)

    def save(self) -> bool:
        document = self.window.document
        if document is None:
            return False
        if not document.path or Path(document.path).suffix.lower() not in SAVE_FORMATS:
            return self.save_as_dialog()
        return self.save_to(document.path)

    def save_to(self, path: str) -> bool:
        window = self.window
        if window.document is None:
            return False
        try:
            saved = window.document.save(path)
        except (ValueError, OSError) as exc:
            window.show_error("Cannot save", str(exc))
            return False
        self._add_recent(str(Path(saved).resolve()))
        window.refresh_title()
        window.flash(f"Saved {Path(saved).name}")
        return True

    def save_as_dialog(self) -> bool:
        if self.window.document is None:
            return False
        suggested = self._save_as_suggestion()
        path, chosen = QFileDialog.getSaveFileName(
            self.window, "Save mesh as", str(suggested), SAVE_FILTER, _save_filter(suggested.suffix)
        )
        if not path:
            return False
        if Path(path).suffix.lower() not in SAVE_FORMATS:
            path += ".ply" if "PLY" in chosen else ".stl" if "STL" in chosen else ".obj"
        return self.save_to(path)

    def _save_as_suggestion(self) -> Path:
        """What Save As proposes: the document's own path (as .obj when its format cannot be
        written, e.g. .off), or untitled.obj in the folder used last for the default model."""
        document = self.window.document
        if document is not None and document.path:
            path = Path(document.path)
            return path if path.suffix.lower() in SAVE_FORMATS else path.with_suffix(".obj")
        return Path(self._last_dir()) / "untitled.obj"

    def maybe_save(self) -> bool:
        """Ask about unsaved changes; True when it is fine to go on."""
        document = self.window.document
        if document is None or not document.dirty:
            return True
        answer = QMessageBox.question(
            self.window,
            "Unsaved changes",
            f"{document.title} has unsaved changes. Save them?",
            QMessageBox.StandardButton.Save
            | QMessageBox.StandardButton.Discard
            | QMessageBox.StandardButton.Cancel,
        )
        if answer == QMessageBox.StandardButton.Save:
            return self.save()
        return answer == QMessageBox.StandardButton.Discard

    # -- recent files ------------------------------------------------------------------------
    def _last_dir(self) -> str:
        recent = self.recent_files()
        return str(Path(recent[0]).parent) if recent else str(Path.home())

    def recent_files(self) -> list[str]:
        value = self.window.settings.value("recent_files", [])
        if isinstance(value, str):
            return [value]
        return [str(v) for v in value] if isinstance(value, (list, tuple)) else []

    def _add_recent(self, path: str) -> None:
        files = [path] + [p for p in self.recent_files() if p != path]
        self.window.settings.setValue("recent_files", files[:MAX_RECENT])
        self.refresh_recent()

    def refresh_recent(self) -> None:
        """The Open Recent menu's entries."""
        menu = self.recent_menu
        if menu is None:
            return
        menu.clear()
        for path in self.recent_files():
            action = menu.addAction(Path(path).name)
            action.setToolTip(path)
            action.triggered.connect(
                lambda _c=False, p=path: self.window.viewport.stroke_worker.after_step(
                    partial(self._open_recent, p), "Opening"
                )
            )
        menu.setEnabled(bool(self.recent_files()))

    def _open_recent(self, path: str) -> None:
        if self.maybe_save():
            self.open_file(path)

    # -- presets, session, screenshot --------------------------------------------------------
    def fill_presets_menu(self, menu: QMenu) -> None:
        """One entry per built-in preset (resources/presets), its description as status tip."""
        self.presets_menu = menu
        try:
            presets = builtin_presets()
        except ValueError as exc:  # a broken installation must not stop the window
            menu.setEnabled(False)
            menu.setToolTip(str(exc))
            return
        for preset in presets:
            action = menu.addAction(preset.name)
            action.setStatusTip(preset.description)
            action.setToolTip(f"{preset.description}\n{describe_material(preset.material)}")
            action.triggered.connect(lambda _c=False, p=preset: self.window.apply_preset(p))
        menu.setToolTipsVisible(True)

    def _json_dialog(self, title: str, save: bool) -> str:
        dialog = QFileDialog.getSaveFileName if save else QFileDialog.getOpenFileName
        path, _ = dialog(self.window, title, self._last_dir(), "JSON (*.json)")
        if path and save and not path.endswith(".json"):
            path += ".json"
        return path

    def load_preset_dialog(self) -> None:
        path = self._json_dialog("Load preset", save=False)
        if path:
            try:
                self.window.apply_preset(load_preset(path))
            except ValueError as exc:
                self.window.show_error("Cannot load the preset", str(exc))

    def save_preset_dialog(self) -> None:
        path = self._json_dialog("Save preset", save=True)
        if path:
            self._write(path, lambda: save_preset(self.window.preset(Path(path).stem), path))

    def export_session_dialog(self) -> None:
        document = self.window.document
        if document is None:
            return
        path = self._json_dialog("Export session (for gogreen replay)", save=True)
        if path:
            text = json.dumps(document.sculptor.session(), indent=1)
            self._write(path, lambda: write_text_atomic(path, text))

    def _write(self, path: str, write) -> None:
        try:
            write()
            self.window.flash(f"Wrote {Path(path).name}")
        except ValueError as exc:  # MeshFileError from the atomic writer
            self.window.show_error("Cannot write", str(exc))

    def screenshot_dialog(self) -> None:
        path, _ = QFileDialog.getSaveFileName(
            self.window, "Export screenshot", self._last_dir(), "PNG (*.png)"
        )
        if path:
            self.save_screenshot(path if path.endswith(".png") else path + ".png")

    def save_screenshot(self, path: str) -> bool:
        """PNG of the viewport only (no panels, menus, overlays or brush cursor), written
        atomically (``write_bytes_atomic``); the status bar names the file. Returns success."""
        target = Path(path)
        try:
            pixels = self.window.viewport.model_image()
            height, width = pixels.shape[:2]
            image = QImage(pixels.data, width, height, 3 * width, QImage.Format.Format_RGB888)
            png = QBuffer()
            png.open(QIODevice.OpenModeFlag.WriteOnly)
            if not image.save(png, "PNG"):  # type: ignore[call-overload]  # stub: bytes; runtime: str
                raise RuntimeError("Qt could not encode the PNG")
            write_bytes_atomic(target, bytes(png.data().data()))
        except (OSError, RuntimeError, ValueError) as exc:
            self.window.show_error("Cannot write the screenshot", f"{target}: {exc}")
            return False
        self.window.flash(f"Screenshot saved: {target} ({width}×{height})")
        return True
