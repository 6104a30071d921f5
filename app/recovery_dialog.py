"""The dialog that offers the work a crash left unsaved: one row per recovery journal (its
picture, file name, time of the last change, number of operations and what they were, and any
damage), with Recover, Discard and Later.

A thin view over :func:`gogreen_core.files.recovery.list_journals`: Discard deletes the journal at
once (after a confirmation), Recover closes the dialog with :attr:`RecoveryDialog.chosen` set
(the window then rebuilds the document off the GUI thread), Later keeps every journal for the
next start.
"""

from __future__ import annotations

import html
import time
from datetime import datetime

from PySide6.QtCore import QSize, Qt
from PySide6.QtGui import QIcon, QPixmap
from PySide6.QtWidgets import (
    QDialog,
    QDialogButtonBox,
    QLabel,
    QListWidget,
    QListWidgetItem,
    QMessageBox,
    QPushButton,
    QVBoxLayout,
)

from app.icons import icon
from app.theme import active_theme
from gogreen_core.files.recovery import JournalError, JournalInfo, discard

__all__ = ["RecoveryDialog", "describe", "when"]

#: Size of the pictures in the list.
THUMBNAIL = QSize(160, 100)


def when(seconds: float, now: float | None = None) -> str:
    """``"today 14:32 (5 minutes ago)"``-style time of a last change."""
    now = time.time() if now is None else now
    moment = datetime.fromtimestamp(seconds)
    day = moment.date()
    today = datetime.fromtimestamp(now).date()
    date = "today" if day == today else moment.strftime("%a %d %b %Y")
    ago = now - seconds
    if ago < 90:
        span = "just now"
    elif ago < 5400:
        span = f"{round(ago / 60)} minutes ago"
    elif ago < 2 * 86400:
        span = f"{round(ago / 3600)} hours ago"
    else:
        span = f"{round(ago / 86400)} days ago"
    return f"{date} {moment:%H:%M} ({span})"


def describe(info: JournalInfo) -> str:
    """The rich text of one journal's row."""
    muted = active_theme().muted_text
    place = html.escape(info.document) if info.document else "not saved to a file yet"
    lines = [
        f"<b>{html.escape(info.title)}</b> <span style='color:{muted}'>— {place}</span>",
        f"Last change {when(info.modified)} · {info.operations} operations: "
        f"{html.escape(info.summary())}",
        f"<span style='color:{muted}'>{info.vertices:,} vertices · journal {info.id}</span>",
    ]
    if info.notes:
        error = active_theme().error_text
        notes = html.escape("; ".join(info.notes))
        lines.append(f"<span style='color:{error}'>Damaged: {notes}</span>")
    return "<br>".join(lines)


class RecoveryDialog(QDialog):
    """Offer ``journals`` (recoverable ones: not in use). After ``exec()``, :attr:`chosen` is
    the journal to recover, or None (Later, or every journal discarded)."""

    def __init__(self, journals: list[JournalInfo], parent=None) -> None:
        super().__init__(parent)
        self.setWindowTitle("Recover unsaved work")
        self.setMinimumSize(760, 380)
        self.chosen: JournalInfo | None = None
        self._journals = list(journals)
        intro = QLabel(
            "GoGreen Sculpt did not close properly, and this work was not saved. "
            "Recover it to go on where you stopped (with its undo history), or discard it."
        )
        intro.setWordWrap(True)
        self.list = QListWidget()
        colors = active_theme()
        # a framed row rather than a filled one: the muted and red lines stay readable
        self.list.setStyleSheet(
            f"QListWidget::item:selected {{ background: {colors.alternate_base}; "
            f"border: 2px solid {colors.highlight}; border-radius: 4px; }}"
        )
        self.list.setIconSize(THUMBNAIL)
        self.list.setSpacing(4)
        self.list.setWordWrap(True)
        self.list.itemDoubleClicked.connect(lambda _item: self.recover_selected())
        self.list.currentRowChanged.connect(lambda _row: self._update_buttons())
        self._labels: list[QLabel] = []
        for info in self._journals:
            self._add_row(info)
        buttons = QDialogButtonBox()
        self.recover_button = QPushButton("&Recover")
        self.recover_button.setDefault(True)
        self.recover_button.setToolTip(
            "Open this work as it was at its last operation, unsaved, with its undo history"
        )
        self.discard_button = QPushButton("&Discard…")
        self.discard_button.setToolTip("Delete this unsaved work for good")
        self.later_button = QPushButton("&Later")
        self.later_button.setToolTip("Keep all of it; it is offered again at the next start")
        buttons.addButton(self.recover_button, QDialogButtonBox.ButtonRole.AcceptRole)
        buttons.addButton(self.discard_button, QDialogButtonBox.ButtonRole.DestructiveRole)
        buttons.addButton(self.later_button, QDialogButtonBox.ButtonRole.RejectRole)
        self.recover_button.clicked.connect(self.recover_selected)
        self.discard_button.clicked.connect(lambda: self.discard_selected())
        self.later_button.clicked.connect(self.reject)
        layout = QVBoxLayout(self)
        layout.addWidget(intro)
        layout.addWidget(self.list, 1)
        layout.addWidget(buttons)
        self.list.setCurrentRow(0)
        self._update_buttons()

    def _add_row(self, info: JournalInfo) -> None:
        item = QListWidgetItem()
        picture = QPixmap(str(info.thumbnail)) if info.thumbnail else QPixmap()
        if picture.isNull():
            picture = icon("grab").pixmap(64, 64)
        picture_icon = QIcon(picture)
        picture_icon.addPixmap(picture, QIcon.Mode.Selected)  # not tinted when selected
        item.setIcon(picture_icon)
        label = QLabel(describe(info))
        label.setTextFormat(Qt.TextFormat.RichText)
        label.setWordWrap(True)
        label.setContentsMargins(8, 4, 8, 4)
        item.setSizeHint(QSize(600, max(THUMBNAIL.height() + 8, label.sizeHint().height())))
        self.list.addItem(item)
        self.list.setItemWidget(item, label)
        self._labels.append(label)

    @property
    def journals(self) -> list[JournalInfo]:
        """The journals still listed."""
        return list(self._journals)

    @property
    def selected(self) -> JournalInfo | None:
        row = self.list.currentRow()
        return self._journals[row] if 0 <= row < len(self._journals) else None

    def _update_buttons(self) -> None:
        readable = self.selected is not None and self.selected.readable
        self.recover_button.setEnabled(readable)
        self.discard_button.setEnabled(self.selected is not None)

    def recover_selected(self) -> None:
        """Close the dialog, choosing the selected journal."""
        if self.selected is not None and self.selected.readable:
            self.chosen = self.selected
            self.accept()

    def discard_selected(self, confirm: bool = True) -> bool:
        """Delete the selected journal (after asking, unless ``confirm`` is False); the dialog
        closes when none is left. Returns whether it was deleted."""
        info = self.selected
        if info is None:
            return False
        if confirm:
            answer = QMessageBox.question(
                self,
                "Discard unsaved work",
                f"Delete the unsaved work on {info.title}: {info.operations} operations, last "
                f"changed {when(info.modified)}? This cannot be undone.",
                QMessageBox.StandardButton.Discard | QMessageBox.StandardButton.Cancel,
                QMessageBox.StandardButton.Cancel,
            )
            if answer != QMessageBox.StandardButton.Discard:
                return False
        try:
            discard(info.directory)
        except (JournalError, OSError) as exc:
            QMessageBox.warning(self, "Cannot discard", str(exc))
            return False
        row = self.list.currentRow()
        self.list.takeItem(row)
        del self._journals[row]
        del self._labels[row]
        if not self._journals:
            self.reject()
        self._update_buttons()
        return True
