"""A new or opened document frees the previous one (issue 36, item 4): nothing of the app keeps
the old mesh's arrays or its sculptor alive (weak references to them die; no RSS figures here,
benchmarks/app_scale.py prints those)."""

from __future__ import annotations

import gc
import weakref

import numpy as np

from app.background import BackgroundRunner


def test_a_background_job_lets_go_of_what_its_function_captured(qtbot):
    runner = BackgroundRunner()
    big = np.ones(1000)
    held = weakref.ref(big)
    job = runner.submit(lambda task, big=big: float(big.sum()))
    del big
    with qtbot.waitSignal(runner.finished, timeout=10_000) as finished:
        pass
    assert finished.args == [job, 1000.0]
    gc.collect()
    assert held() is None  # the pool keeps the job object; not its function's arrays


def _dead_after_new(window, qtbot) -> list[str]:
    old = window.document
    refs = {
        "document": weakref.ref(old),
        "sculptor": weakref.ref(old.sculptor),
        "vertices": weakref.ref(old.sculptor.vertices),
        "faces": weakref.ref(old.sculptor.faces),
    }
    del old
    assert window.files.new_document()
    qtbot.wait(50)  # the queued reports of the old mesh's jobs
    gc.collect()
    return [name for name, ref in refs.items() if ref() is not None]


def test_ctrl_n_frees_a_mesh_indexed_in_the_background(window, qtbot):
    sculptor = window.document.sculptor
    # as a big mesh is: its surface index built on the background thread
    window.viewport.set_mesh(sculptor.vertices, sculptor.faces, background=True)
    qtbot.waitUntil(lambda: not window.viewport.surface_building, timeout=60_000)
    del sculptor
    assert _dead_after_new(window, qtbot) == []
