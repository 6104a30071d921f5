"""Crash recovery in the app: a window sculpts in another process and is killed; a new window
offers the unsaved work, recovers the same vertices (unsaved, titled "recovered", with its undo
history), Discard removes a journal, and a clean quit leaves none."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from PySide6.QtCore import Qt, QTimer
from PySide6.QtWidgets import QApplication

from gogreen_core.files.recovery import list_journals
from gogreen_core.interaction.settings import Settings
from gogreen_core.physics.radial import KelvinletRadial

#: The start of a window script: the window, a mesh opened, kernels and surface ready.
_WINDOW_READY = """
import sys, time
import numpy as np
sys.path.insert(0, {tests!r})
from PySide6.QtCore import QSettings, QPoint
from PySide6.QtWidgets import QApplication
from gui_helpers import center_of, drag
from app.main_window import MainWindow
from gogreen_core.physics.radial import KelvinletRadial

app = QApplication(sys.argv[:1])
window = MainWindow(QSettings({settings!r}, QSettings.Format.IniFormat))
window.show()
assert window.files.open_file({mesh!r})
assert window.kernel_warmer.wait(120_000)
while window.viewport.surface_building:
    app.processEvents()
window.viewport.render()
"""

#: A window that opens a mesh, sculpts (drags, a pin, an undo), saves its vertices, then waits.
SCULPTING_WINDOW = (
    _WINDOW_READY
    + """
for k in range(3):
    drag(window, center_of(window) + QPoint(20 * k - 20, 10 * k))
window.undo()
window.model.constraint_radius = 0.07
drag(window, center_of(window) + QPoint(-30, 25))
np.save({vertices!r}, window.document.sculptor.vertices)
end = time.monotonic() + 1.5
while time.monotonic() < end:  # idle: the window draws the journal's thumbnail
    app.processEvents()
    time.sleep(0.01)
assert window.document.journal.flush()
print("SCULPTED", len(window.document.sculptor.operations), flush=True)
time.sleep(120)
"""
)


def sculpt_and_kill(
    tmp_path: Path, mesh: Path, name: str, script: str | None = None
) -> tuple[int, np.ndarray | None]:
    """Run a sculpting window (``script``, default :data:`SCULPTING_WINDOW`) in a process and
    SIGKILL it; its operations and last vertices (None when the script saves none)."""
    files = {"vertices": str(tmp_path / f"{name}-vertices.npy")}
    code = (script or SCULPTING_WINDOW).format(
        tests=str(Path(__file__).resolve().parents[1] / "helpers"),
        settings=str(tmp_path / f"{name}.ini"),
        mesh=str(mesh),
        **files,
    )
    child = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(code)], stdout=subprocess.PIPE, text=True
    )
    try:
        line = child.stdout.readline()
        assert line.startswith("SCULPTED"), line
        os.kill(child.pid, signal.SIGKILL)
    finally:
        child.kill()
        child.wait(30)
    saved = Path(files["vertices"])
    return int(line.split()[1]), np.load(saved) if saved.exists() else None


def answer_the_dialog(qtbot, button: str) -> None:
    """When the recovery dialog is up, click ``button`` ("recover", "discard", "later")."""

    def click() -> None:
        dialog = QApplication.activeModalWidget()
        if dialog is None or not hasattr(dialog, "recover_button"):
            QTimer.singleShot(50, click)
            return
        qtbot.mouseClick(getattr(dialog, f"{button}_button"), Qt.MouseButton.LeftButton)

    QTimer.singleShot(50, click)


@pytest.fixture
def made_file(made_textured, tmp_path) -> Path:
    path = tmp_path / "made.obj"
    path.write_bytes(made_textured.path.read_bytes())
    return path


def test_a_killed_window_is_recovered_by_the_next_one(window, qtbot, tmp_path, made_file):
    operations, vertices = sculpt_and_kill(tmp_path, made_file, "first")
    # the new window's own journal is in use: not offered
    (offered,) = window.crash_recovery.journals()
    assert offered.operations == operations == 6 and offered.title == "made.obj"
    assert offered.thumbnail is not None  # the killed window drew one
    answer_the_dialog(qtbot, "recover")
    chosen = window.crash_recovery.offer()
    assert chosen is not None and chosen.directory == offered.directory
    assert window.crash_recovery.wait(60_000)
    qtbot.waitUntil(lambda: window.document.recovered, timeout=60_000)
    document = window.document
    assert np.array_equal(document.sculptor.vertices, vertices)
    assert document.path == str(made_file) and document.dirty
    assert window.windowTitle() == "made.obj (recovered) • — GoGreen Sculpt"
    assert window.model.constraint_radius == 0.07  # its settings show in the panels
    assert "Recovered made.obj: 6 operations" in window.message_label.text()
    # its undo history: the last drag, the pins' radius, the second drag (the third was undone)
    window.undo()
    window.undo()
    assert window.model.constraint_radius != 0.07
    window.undo()
    window.redo()
    window.redo()
    window.redo()
    assert np.array_equal(document.sculptor.vertices, vertices)
    # the recovered journal is replaced by the document's own, which holds the state now
    journal = document.journal
    assert journal.flush() and not offered.directory.exists()
    (info,) = list_journals()
    assert info.directory == journal.directory and info.in_use
    # saving: no longer "recovered", and the journal starts afresh
    assert window.files.save_to(str(tmp_path / "saved.obj"))
    assert window.windowTitle() == "saved.obj — GoGreen Sculpt"
    assert journal.records == 0
    window.close()
    assert list_journals() == []  # a clean quit leaves none


def test_discard_removes_the_journal_and_later_keeps_it(window, qtbot, tmp_path, made_file):
    sculpt_and_kill(tmp_path, made_file, "first")
    answer_the_dialog(qtbot, "later")
    assert window.crash_recovery.offer() is None
    (info,) = window.crash_recovery.journals()  # kept for the next start
    original = window.document
    answer_the_dialog(qtbot, "discard")  # the window fixture confirms with Discard
    assert window.crash_recovery.offer() is None
    assert not info.directory.exists() and window.crash_recovery.journals() == []
    assert window.document is original
    window.close()
    assert list_journals() == []


def test_a_clean_quit_leaves_no_journal(window):
    from gui_helpers import center_of, drag

    (info,) = list_journals()
    assert info.in_use and info.title == "textured.obj"
    drag(window, center_of(window))
    assert window.document.journal.records == 1
    window.close()  # unsaved changes discarded (the fixture answers Discard)
    assert list_journals() == []


def test_a_journal_that_cannot_be_written_is_said_once_and_sculpting_goes_on(window, monkeypatch):
    import errno

    from gui_helpers import center_of, drag

    import gogreen_core.files.journal as journal_module

    def full_disk(*_args) -> None:
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(journal_module, "write_all", full_disk)
    drag(window, center_of(window))
    window.crash_recovery.idle()  # what the idle timer does
    assert "journal stopped: No space left on device" in window.message_label.text()
    assert not window.crash_recovery.warning.isHidden()
    window.flash("something else")
    drag(window, center_of(window))
    window.crash_recovery.idle()
    assert window.message_label.text() == "something else"  # said once
    assert len(window.document.sculptor.operations) == 2  # sculpting went on


def test_the_recovery_picture_waits_for_the_first_operation(window):
    """A journal without an operation is never offered: no picture of it (a render that would
    delay the first stroke of a newly opened model); the first idle after an operation takes
    one."""
    from gui_helpers import center_of, drag

    from gogreen_core.files.journal import THUMBNAIL_FILE

    journal = window.document.journal
    picture = journal.directory / THUMBNAIL_FILE
    window.crash_recovery.idle()  # what the idle timer does
    assert journal.flush() and journal.records == 0 and not picture.exists()
    drag(window, center_of(window))
    window.crash_recovery.idle()
    assert journal.flush() and journal.records == 1 and picture.exists()


#: A window that sculpts, then changes every setting an artist tunes, then waits to be killed.
TUNING_WINDOW = (
    _WINDOW_READY
    + """
drag(window, center_of(window))
model = window.model
model.brush.update(dict(kind="pinch", radius=0.06, strength=1.7, influence=5.0, symmetry="xz"))
model.pen.update(dict(pressure_radius=True, pressure_strength=False, lazy_radius=12.0,
                      spacing=0.3))
window.material_panel.set_mode("transversely_isotropic")
window.material_panel.rotation.set_angles((30.0, 0.0, 15.0))
model.falloff = KelvinletRadial(1.0)
model.set_brush_weights("pinch", [1.0, 16.0, 1.0, 1.0, 1.0, 0.5, 1.0, 1.0, 1.0, 1.0])
end = time.monotonic() + 1.5
while time.monotonic() < end:  # idle: the window writes its settings into the journal
    app.processEvents()
    time.sleep(0.01)
assert window.document.journal.flush()
print("SCULPTED", len(window.document.sculptor.operations), flush=True)
time.sleep(120)
"""
)


def test_recovery_brings_back_every_setting(window, qtbot, tmp_path, made_file):
    """Brush (kind, radius, strength, influence, mirror), pen, material with its rotation
    angles (not folded into the 6×6 matrix), falloff and degree weights: as before the crash
    (the radius came back 0.080 instead of 0.060, the angles 0°)."""
    sculpt_and_kill(tmp_path, made_file, "tuned", TUNING_WINDOW)
    answer_the_dialog(qtbot, "recover")
    assert window.crash_recovery.offer() is not None
    assert window.crash_recovery.wait(60_000)
    qtbot.waitUntil(lambda: window.document.recovered, timeout=60_000)
    model = window.model
    brush = model.brush
    assert (brush.kind, brush.radius, brush.strength) == ("pinch", 0.06, 1.7)
    assert (brush.influence, brush.symmetry) == (5.0, "xz")
    assert window.brush_bar.radius.value() == 0.06
    pen = model.pen
    assert (pen.pressure_radius, pen.pressure_strength) == (True, False)
    assert (pen.lazy_radius, pen.spacing) == (12.0, 0.3)
    panel = window.material_panel
    assert panel.mode == "transversely_isotropic"
    assert panel.form.angles == (30.0, 0.0, 15.0)
    assert panel.rotation.angles == (30.0, 0.0, 15.0)
    assert panel.form.material == model.material == window.document.sculptor.settings.material
    expected = Settings()
    expected.falloff = KelvinletRadial(1.0)
    assert model.falloff == expected.falloff
    weights = model.weights_for("pinch")
    assert weights[1] == 16.0 and weights[5] == 0.5
    assert "axes turned 30°, 0°, 15°" in window.status.material_label.text()
