"""The kernel warmer's reports cross from the compiling thread to the GUI thread safely, also
when the window that asked is gone by then (the compilation of a new machine outlives it)."""

from __future__ import annotations

import threading

import shiboken6
from PySide6.QtCore import QObject

from app import kernel_warmup
from app.kernel_warmup import KernelWarmer


def _call_on_a_thread(callback) -> list[BaseException]:
    errors: list[BaseException] = []

    def run() -> None:
        try:
            callback([])
        except BaseException as exc:
            errors.append(exc)

    thread = threading.Thread(target=run)
    thread.start()
    thread.join()
    return errors


def test_a_compilation_ending_after_its_warmer_was_deleted_reports_nowhere(qtbot, monkeypatch):
    callbacks = []
    monkeypatch.setattr(kernel_warmup._drivers, "units_for", lambda l_max: (("unit", l_max),))
    monkeypatch.setattr(kernel_warmup._compiled, "request", lambda *units: None)
    monkeypatch.setattr(kernel_warmup._compiled, "when_ready", lambda u, cb: callbacks.append(cb))
    parent = QObject()
    gone = KernelWarmer(parent)
    live = KernelWarmer()
    assert gone.request(6) and live.request(7)
    assert gone.busy and live.busy
    shiboken6.delete(parent)  # the window closed: its warmer went with it
    assert not shiboken6.isValid(gone)
    with qtbot.waitSignal(live.ready, timeout=5_000) as ready:
        assert _call_on_a_thread(callbacks[0]) == []  # the deleted warmer's report
        assert _call_on_a_thread(callbacks[1]) == []
    assert ready.args[0] == 7  # only the live warmer's own report reached it
    assert not live.busy and live.compiled(7)


def test_the_status_bar_names_the_units_compiled_and_the_time_left(window, qtbot):
    """On an empty compile cache (issue 32 item 8): a labelled count, the time left and the
    NumPy path named, from the compile driver's own progress reports (sent from its thread)."""
    window.kernel_warmer.wait(120_000)
    reports = [
        kernel_warmup._compiled.Progress(0, 5, 0.0, ()),
        kernel_warmup._compiled.Progress(2, 5, 16.0, ("geometry", "mesh_io", "brushes")),
    ]
    for progress in reports:
        with qtbot.waitSignal(window.kernel_warmer.progress, timeout=5_000):
            report = kernel_warmup._compiled._tell_progress
            threading.Thread(target=report, args=(progress,)).start()
        text = window.message_label.text()
        assert f"{progress.done} of 5 units" in text and "NumPy path meanwhile" in text
        assert window.status.compile_progress.isVisible()
        assert window.status.compile_progress.value() == progress.done
    assert "about 25 s left" in text  # 8 s a unit, three units left
    assert "Compiling brush kernels (now the surface index): 2 of 5 units" in text
    bar = window.status.compile_progress
    assert bar.text() == "kernels 2/5, about 25 s left" and bar.toolTip() == text
    assert "estimating" not in text
