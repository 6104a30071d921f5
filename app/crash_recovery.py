"""Crash recovery in the app: the open document's journal, and the offer of unsaved work at
start.

:class:`CrashRecovery` belongs to the main window. It starts a journal for each document the
window shows (:meth:`Document.start_journal`) and closes the previous one's (a clean close:
removed); when the window is idle after an operation it takes a due checkpoint (the copy of the
vertices is the one cost on the GUI thread), writes a small picture of the model for the
recovery dialog, and shows each journal problem once in the status bar. :meth:`offer` lists the
journals earlier sessions left (:func:`gogreen_core.files.recovery.list_journals`) in a
:class:`~app.recovery_dialog.RecoveryDialog`; :meth:`recover` rebuilds one off the GUI thread,
with progress in the status bar, and shows it: unsaved, titled "(recovered)", with its undo
history.
"""

from __future__ import annotations

import contextlib
import json
import os
import time
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
from PySide6.QtCore import QBuffer, QIODevice, QObject, Qt, QTimer, Signal
from PySide6.QtGui import QImage
from PySide6.QtWidgets import QLabel, QMessageBox, QProgressBar

from app.background import BackgroundRunner, Task
from app.document import Document
from app.recovery_dialog import THUMBNAIL, RecoveryDialog
from app.theme import active_theme
from gogreen_core.files.journal import THUMBNAIL_FILE
from gogreen_core.files.recovery import JournalInfo, Recovery, discard, list_journals, recover
from gogreen_core.sculpt.brushes import Brush

__all__ = ["CrashRecovery"]

#: Milliseconds without an operation before the window counts as idle.
IDLE_MS = 400
#: Seconds between two pictures of the model for the recovery dialog.
THUMBNAIL_SECONDS = 20.0
#: The journal's file of the app's own settings, which the engine's records do not hold: the
#: brush (kind, radius, strength, steps, influence, mirror), the pen, and the Material panel's
#: inputs (its mode, numbers and the rotation angles, not only the rotated 6×6 matrix).
APP_SETTINGS_FILE = "app_settings.json"


def app_settings(window) -> dict[str, Any]:
    """What :data:`APP_SETTINGS_FILE` holds for ``window`` (plain JSON values)."""
    inputs = {
        name: value.tolist() if isinstance(value, np.ndarray) else value
        for name, value in window.material_panel.form.values().items()
    }
    return {
        "brush": asdict(window.model.brush.brush),
        "pen": window.model.pen.values(),
        "material_inputs": inputs,
    }


def restore_app_settings(window, saved: dict[str, Any]) -> None:
    """Give ``window`` the settings :func:`app_settings` wrote (after the engine's own were
    pulled from the recovered sculptor: the material inputs then show the same material, with
    the angles it was made with)."""
    window.model.brush.set_brush(Brush(**saved["brush"]))
    window.model.pen.update(saved["pen"])
    inputs = dict(saved["material_inputs"])
    inputs["voigt"] = np.asarray(inputs["voigt"], dtype=np.float64)
    inputs["angles"] = tuple(inputs["angles"])
    window.material_panel.show_inputs(inputs)


class CrashRecovery(QObject):
    """The crash-recovery side of a :class:`~app.main_window.MainWindow` (see the module
    docstring)."""

    _wake = Signal()  # the journal wrote a record or met a problem (from any thread)

    def __init__(self, window) -> None:
        super().__init__(window)
        self.window = window
        self._idle_timer = QTimer(self)
        self._idle_timer.setSingleShot(True)
        self._idle_timer.setInterval(IDLE_MS)
        self._idle_timer.timeout.connect(self.idle)
        self._wake.connect(self._idle_timer.start)
        self._thumbnail_at = (0.0, -1)  # time and journal records of the last picture
        self._settings_written: str | None = None  # the app settings the journal holds
        # a change of the app's own settings is written at the next idle moment
        for events in (window.model.brush.events, window.model.pen.events):
            events.changed.connect(lambda _c: self._idle_timer.start())
        window.material_panel.form.events.changed.connect(lambda _c: self._idle_timer.start())
        self._runner = BackgroundRunner(self)
        self.progress: QProgressBar
        self._runner.progress.connect(lambda _id, done: self.progress.setValue(round(100 * done)))
        self._runner.finished.connect(lambda _id, recovery: self._recovered(recovery))
        self._runner.failed.connect(lambda _id, exc: self._failed(exc))
        self.progress = window.status.add_progress(
            100, "recovering %p%", "Rebuilding the unsaved work from its crash-recovery journal"
        )
        #: Shown while the open document's work is not protected (no journal can be written).
        self.warning = QLabel("⚠ recovery off")
        self.warning.setStyleSheet(f"color: {active_theme().error_text}")
        self.warning.hide()
        window.statusBar().addPermanentWidget(self.warning)

    # -- the open document's journal --------------------------------------------------------
    def document_changed(self, previous: Document | None, document: Document) -> None:
        """The window shows ``document`` now: ``previous`` was saved or discarded (its journal
        goes), ``document`` gets one."""
        if previous is not None and previous is not document:
            previous.close()
        # queued: the journal records a brush step's event on the stroke worker's thread
        document.start_journal(wake=self._wake.emit)
        self._thumbnail_at = (0.0, -1)
        self._settings_written = None
        self.idle()  # says at once when no journal can be written

    def close(self) -> None:
        """The window closes cleanly (its changes saved or discarded)."""
        self._idle_timer.stop()
        self._runner.cancel()
        if self.window.document is not None:
            self.window.document.close()

    def idle(self) -> None:
        """Idle after an operation: a due checkpoint, a picture now and then, and each new
        journal problem in the status bar."""
        document = self.window.document
        journal = None if document is None else document.journal
        if journal is None:
            return
        if self.window.tools.dragging or document.sculptor.in_stroke:
            self._idle_timer.start()
            return
        if journal.maybe_checkpoint():
            self._idle_timer.start()  # then: a checkpoint that could not be written is said
        last, records = self._thumbnail_at
        # none before the first operation: a journal without one is never offered, and the
        # picture (a render, ~0.3 s) would delay the first stroke of a newly opened model
        if journal.active and journal.records != records and journal.records > 0:
            if records < 0 or time.monotonic() - last >= THUMBNAIL_SECONDS:
                self._write_thumbnail(journal)
        self._write_settings(journal)
        for problem in journal.take_problems():
            self.window.flash(problem)
            self.warning.setToolTip(problem)
        self.warning.setVisible(not journal.active)

    def _write_settings(self, journal) -> None:
        """The app's settings into the journal when they changed since last written."""
        if not journal.active:
            return
        text = json.dumps(app_settings(self.window), sort_keys=True)
        if text != self._settings_written:
            self._settings_written = text
            journal.write_file(APP_SETTINGS_FILE, text.encode("utf-8"))

    def _write_thumbnail(self, journal) -> None:
        self._thumbnail_at = (time.monotonic(), journal.records)
        try:
            pixels = self.window.viewport.model_image(light=True)  # a small picture
        except (RuntimeError, ValueError):
            return
        height, width = pixels.shape[:2]
        image = QImage(pixels.data, width, height, 3 * width, QImage.Format.Format_RGB888)
        smooth = Qt.TransformationMode.SmoothTransformation
        small = image.scaled(THUMBNAIL, Qt.AspectRatioMode.KeepAspectRatio, smooth)
        png = QBuffer()
        png.open(QIODevice.OpenModeFlag.WriteOnly)
        if small.save(png, "PNG"):  # type: ignore[call-overload]  # the stub wants bytes, Qt str
            journal.write_file(THUMBNAIL_FILE, png.data().data())

    # -- unsaved work of earlier sessions ---------------------------------------------------
    def journals(self) -> list[JournalInfo]:
        """The journals to offer: not written by a running app; those holding nothing (no
        operation, no damage) are deleted quietly."""
        offered = []
        for info in list_journals():
            if info.in_use:
                continue
            if info.readable and info.operations == 0 and not info.notes:
                with contextlib.suppress(ValueError, OSError):
                    discard(info.directory)
                continue
            offered.append(info)
        return offered

    def offer(self) -> JournalInfo | None:
        """At start: show the unsaved work earlier sessions left (if any) and recover the one
        the artist picks. Returns it (None: nothing, Later, or all discarded)."""
        journals = self.journals()
        if not journals:
            return None
        dialog = RecoveryDialog(journals, self.window)
        dialog.exec()
        if dialog.chosen is not None:
            self.recover(dialog.chosen.directory)
        return dialog.chosen

    def recover(self, directory: str | os.PathLike) -> int | None:
        """Rebuild the document of journal ``directory`` off the GUI thread; the window shows
        it when done. Returns the job id (None when the artist kept the current changes)."""
        if not self.window.files.maybe_save():
            return None
        name = Path(directory).name
        self.window.flash(f"Recovering the unsaved work of journal {name}…")
        self.progress.setValue(0)
        self.progress.show()

        def job(task: Task) -> Recovery:
            def progress(done: int, total: int) -> None:
                task.progress(done / total if total else 1.0)

            return recover(directory, progress=progress)

        return self._runner.submit(job)

    def wait(self, msecs: int = -1) -> bool:
        """Block until a recovery started with :meth:`recover` is shown (tests)."""
        return self._runner.wait(msecs)

    def _recovered(self, recovery: Recovery) -> None:
        self.progress.hide()
        window = self.window
        if not window.files.maybe_save():  # changes made while it was rebuilt: keep them
            recovery.release()
            return
        saved = self._saved_settings(recovery)
        window.set_document(Document.recovered_from(recovery))
        if saved is not None:
            restore_app_settings(window, saved)
        steps, contents = len(recovery.sculptor.history.undo_labels), recovery.contents
        window.flash(
            f"Recovered {contents.title}: {len(contents.operations)} operations, as at the last "
            f"one ({steps} undo steps); not saved yet"
        )
        if recovery.notes:
            QMessageBox.warning(
                window,
                "Recovered with losses",
                "The journal was damaged; everything before the damage was recovered.\n\n"
                + "\n".join(f"• {note}" for note in recovery.notes),
            )

    def _saved_settings(self, recovery: Recovery) -> dict[str, Any] | None:
        """The app settings the recovered journal holds (None: none, e.g. an older journal, or
        unreadable: then the recovered document keeps the current ones, and says so)."""
        path = recovery.contents.directory / APP_SETTINGS_FILE
        try:
            saved = json.loads(path.read_text(encoding="utf-8"))
            Brush(**saved["brush"])  # refused before anything changes
            return dict(saved)
        except FileNotFoundError:
            return None
        except (OSError, ValueError, KeyError, TypeError) as exc:
            self.window.flash(f"The recovered brush and material inputs were not restored: {exc}")
            return None

    def _failed(self, exc: Exception) -> None:
        self.progress.hide()
        self.window.show_error("Cannot recover the unsaved work", str(exc))
