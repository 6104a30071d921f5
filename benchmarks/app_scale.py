"""The app's cost around the engine: memory, compile start-up, one compilation per cache.

    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/app_scale.py [--meshes DIR]

Prints (figures only; nothing is asserted; issue 36, items 2, 3 and 4):

* RSS of the app (the real main window, in a process of its own) idle on the default model
  after a fresh start (median of ``--launches``), beside the floor its dependencies set (child
  processes: a bare main window of the app's size with one pyvistaqt view drawing a
  40,962-point sphere with the viewport's render settings; with numba, scipy.spatial and
  trimesh imported too; and the same loaded as the app loads them, ``app.memory.start_lean``):
  the app above that last floor is what the app's own code costs. Then, in one process: idle,
  after opening the ~1M-vertex mesh (the ogre of ``../shared/meshes``
  Loop-subdivided twice: 992,608 vertices; skipped with the reason when the meshes are absent);
  and idle again after Ctrl+N (a key event posted to the window) back to the default model;
* on that mesh, with real events posted to the viewport (medians, ms): the brush step in the
  app (the engine's event, the tools and the viewport's arrays, without the render) beside the
  engine's event alone; a full frame; the frames of a left-button stroke, a middle-button
  orbit and wheel zooms (from the interaction copy, :mod:`app.level_of_detail`, where full
  frames take over 100 ms); from each release (and the last notch) to a settled screen and
  that frame, at full resolution; the idle CPU after it all;
* on that mesh with dynamic topology (issue 34): a left-button grab (radius 0.03), a move posted
  every 40 ms for 10 s, then the release: the GUI thread's longest stall (the longest gap
  between ticks of a 10 ms timer) and the longest without the time spent rendering, the
  engine's events (count, median), and from the release until a next stroke can start (the
  new faces indexed), and what ran after the release, when and for how long; then the
  stroke's undo and its redo, each until a next stroke can start, and what ran meanwhile.
  ``--stall-only`` runs only this (``--default-model``: on the default model);
  ``--on-gui-thread`` runs every step on the GUI thread, as before :mod:`app.stroke_worker`;
* on an empty numba cache (a temporary ``NUMBA_CACHE_DIR``): seconds from the app's first
  request of its kernels until the field's compiled drivers serve (the first stroke runs
  compiled), and until every unit of the request is in;
* three short scripts (one brush event each) started one after another on an empty cache: how
  many compiling child processes they started (one: the lock beside the cache).

Measured 2026-11-29 (the dynamic-topology stroke; 2 cores shared, load average ~5):
* every step on the GUI thread (``--on-gui-thread``, as before the stroke worker): longest
  stall 2.70 s, 2.26 s not counting renders (frames 0.51 s); 8 events, median 0.95 s;
  release -> next stroke possible 5.4 s.
* slow steps on the stroke worker (three runs): longest stall 0.87-1.11 s, 0.22-0.56 s not
  counting renders (frames 0.30-0.45 s: a full-resolution frame per finished event is now the
  longest stall); 10 events, median 1.09-1.25 s; release -> next stroke possible 3.8 s, or
  ~24 s in the two runs whose last step took 18-20 s: the last move was a small one, and the
  brush's core was measured against that event's fastest, so the whole path was remeshed.
* with the core measured against the fastest the stroke went (quiet machine, 2 runs): longest
  stall 0.60-0.95 s; 9 events, median 1.2-1.3 s, none over 2.5 s; release -> next stroke 4.7-5.5
  s (6 runs before it: 3.7-31 s, the last step 18-28 s in 4 of them).

* the index renumbered at the release (issue 34: given orders, now ``carried=``, no sort; the
  interaction copy kept, following the new vertices, so stroke frames stay light), three runs
  each interleaved with main's, load average 5-5.5: release -> next stroke possible 2.4-2.7 s
  (median 2.57 s; main 4.7-5.4 s, median 5.19 s), of which ~1.3 s the steps still running at
  the release, ~0.1 s the tools' release, ~0.5 s renumbering, ~0.4-0.75 s the first full frame
  (main: ~1.8 s index and copy built anew); frames during the stroke 59-67 ms (copy; main
  312-358 ms, full flat mesh); longest stall 0.49-0.89 s (main 0.75-0.78 s: the last full
  frame either way), 0.27-0.30 s not counting renders (main 0.19-0.25 s: the copy follows the
  new vertices on the GUI thread, 30-70 ms a step). ``--default-model`` (2 runs each): release
  -> next stroke 0.42-0.69 s (main 0.76-0.94 s), the same code path (small meshes index at
  once).
* undo and redo of that stroke renumbered too (the step's MeshEdit read as the change; the
  copy drawn meanwhile, its rows found on the stroke worker), three runs each interleaved with
  main's (7aac3d2, same script), load average 5.5-6.4: undo -> next stroke possible 2.0-2.3
  s (median 2.32 s; main 3.0-5.6 s, median 5.53 s: index and copy built anew, 2.0-4.2 s,
  beside a flat full frame of 0.5-1.3 s), redo 1.5-2.8 s (median 1.93 s; main 3.5-9.4 s,
  median 6.98 s); the renumbering itself 0.6-1.2 s, then the first full frame 0.5-1.0 s.
  Stall not counting renders 251-362 ms (median 318; main 324-577, median 433: the copy's
  follow no longer on the GUI thread). Release -> next stroke 3.1-5.1 s (main 3.4-5.6 s: the
  steps still running at the release vary most); its renumbering 0.8-1.0 s (main 0.7-1.2 s):
  at this load the fresh pages of the new arrays (~200 MB, the app gives each its own) and
  the serial face-connect pass outweigh the normals now carried over (measured alone: a
  build in given orders 250-560 ms, carried 220-480 ms).
* round 8 (index8: an undo pressed before the release's index is in chains the two changes; a
  sorted build in the background past 5 % of appended faces; the copy tinted during an undo):
  three runs each interleaved with m7 (b7950e6, same script), load 3.5-6: release -> next
  stroke median 2.86 s (m7 2.41 s), undo 1.71 s (m7 1.32 s), redo 2.32 s (m7 1.43 s): the
  same path (the undo waits for the index here; no sorted build: ~0.1 % of faces appended), the
  spread is the load's (run 3: 1.51 / 1.01 / 1.25 s vs m7's 2.09 / 0.83 / 1.22 s). Renumbering by
  stage (9 renumberings): orders kept 58-346 ms (vertices and faces), the face-connect pass
  73-333 ms (median 81), the arrays carried over 65-561 ms (median 203): fresh pages and
  memory traffic, not the normals; what is left for a change-proportional renumbering.
* round 9 (index9: SurfaceIndex.renumber in place: slots, removed faces blanked, only the
  changed face lists and normals rewritten, the old buffers reused; an undo's or redo's on the
  GUI thread with VTK's arrays marked modified, a release's on the background thread): three
  runs each interleaved with main (f5efe7a, same script), load 1.2-1.7. The renumbering itself:
  release 167-193 ms (main 298-379, background), undo 94-144 ms (main 265-378), redo 125-130
  ms (main 305-451); by stage (undo): slot maps of vertices and faces ~30 ms, face lists ~11
  ms, moved rows found ~14 ms, normals ~35 ms (of them the ~860k rows the elastic grab moved;
  main: orders 83, face-connect pass 73, arrays carried 45-142 ms). From the change shown to
  the first full frame of the renumbered index: release median 540 ms (main 634), undo 447
  (742), redo 453 (986); undo -> next stroke 797 ms (main 916), redo 662 (1158); release ->
  next stroke 1986 ms (main 1600: the steps still running at the release vary; here the
  recovery thumbnail's copy frame and a full frame again, ~300 ms, fall after the index is
  in). Longest stall 374 ms (main 306), 142 not counting renders (main 125). VTK given a new
  PolyData instead of the same arrays marked modified (--fresh-arrays, 4 runs each): the next
  frame the same within the spread (medians 271-277 vs 258-330 ms: VTK uploads whole buffers
  either way). The index alone on three recorded 1M changes (topology only, quiet machine,
  median of 5): 67k, 88k and 169k new faces 60/66/102 ms (main's carried build 168/160/177 ms).

Goals: brush step ≤ the engine's event + 20 ms; stroke and camera frames ≥ 3× faster than
a full frame; idle ≤ 500 MB; after Ctrl+N within 10 % of the fresh start; drivers ≤ 20 s after the
request; one compilation. On a busy machine the compile figures grow with the load (printed).
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

HERE = Path(__file__).resolve()


def rss_mb(pid: int | str = "self") -> float:
    """Resident set size of process ``pid`` in MB (/proc/<pid>/status VmRSS)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS")


# -- the app's RSS (run in a process of its own: --probe-rss) ------------------------------------
def big_mesh(meshes: Path) -> Path | str:
    """The ogre subdivided twice, as a PLY file in the temporary directory (made once), or why
    not."""
    ogre = meshes / "ogre.obj"
    if not ogre.is_file():
        return f"no {ogre} (../shared/meshes beside the checkout)"
    out = Path(tempfile.gettempdir()) / f"gogreen-ogre-1m-{int(ogre.stat().st_mtime)}.ply"
    if not out.is_file():
        from gogreen_core.mesh.mesh_io import MeshData, load_mesh, save_mesh
        from gogreen_core.mesh.subdivision import loop_subdivide

        mesh = load_mesh(str(ogre))
        vertices, faces = mesh.vertices, mesh.faces
        for _ in range(2):
            step = loop_subdivide(vertices, faces)
            vertices, faces = step.vertices, step.faces
        save_mesh(MeshData(vertices, faces), str(out))
    return out


def anonymous_mb() -> float:
    """This process's anonymous memory in MB (its heaps and stacks: RSS without the pages of
    mapped files, which depend on what other processes keep in the page cache)."""
    for line in Path("/proc/self/smaps_rollup").read_text().splitlines():
        if line.startswith("Anonymous:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("no Anonymous")


FLOOR = """
import json, sys, time
if "--lean" in sys.argv:  # the dependencies loaded as the app loads them (app.memory)
    from app.memory import start_lean
    start_lean()
if "--all" in sys.argv:  # the rest of the app's dependencies, imported first as the app does
    import numba, scipy.spatial, trimesh
from PySide6.QtWidgets import QApplication, QMainWindow
import pyvista as pv
from pyvistaqt import QtInteractor
sys.path.insert(0, sys.argv[1])
from app_scale import anonymous_mb, rss_mb
app = QApplication(sys.argv[:1])
window = QMainWindow()
free = window.screen().availableGeometry()  # the app's size: app.main_window.fit_to_screen
window.resize(round(free.width() * 0.94), round(free.height() * 0.94))
plotter = QtInteractor(window, auto_update=False, multi_samples=0)  # as app.viewport's
window.setCentralWidget(plotter.interactor)
plotter.add_mesh(pv.Icosphere(nsub=6), smooth_shading=True)  # 40,962 points: the default model's
window.show()
end = time.perf_counter() + 3.0
while time.perf_counter() < end:
    app.processEvents()
    time.sleep(0.01)
plotter.render()
print(json.dumps({"rss": rss_mb(), "anonymous": anonymous_mb()}))
"""


def child_json(*args: str) -> dict:
    """What a child Python process run with ``args`` prints last, as JSON (its error's end
    raised when it fails)."""
    run = subprocess.run([sys.executable, *args], capture_output=True, text=True)
    if run.returncode:
        raise RuntimeError(run.stderr[-3000:])
    return json.loads(run.stdout.strip().splitlines()[-1])


def floor(*options: str) -> dict[str, float]:
    """RSS and anonymous MB of the floor the dependencies set: a bare Qt main window of the
    app's size with one pyvistaqt view of a 40,962-point smooth-shaded sphere, rendered
    (options ``--all``: with numba, scipy.spatial and trimesh imported as well; ``--lean``: the
    dependencies loaded as the app loads them, :func:`app.memory.start_lean`)."""
    return child_json("-c", FLOOR, str(HERE.parent), *options)


def probe_idle() -> dict[str, float]:
    """RSS and anonymous MB of the app idle on the default model after a fresh start."""
    window, _settle = start_app()
    result = {"rss": rss_mb(), "anonymous": anonymous_mb()}
    window.close()
    return result


def start_app():
    """The main window, started as ``app.cli.main`` does, idle on the default model; and a
    function that runs its events for some seconds."""
    from PySide6.QtCore import QSettings
    from PySide6.QtWidgets import QApplication

    from app import memory

    # as app.cli.main does (older code: only the first)
    getattr(memory, "start_lean", memory.use_own_pages_for_big_blocks)()
    app = QApplication.instance() or QApplication(sys.argv[:1])
    from app.main_window import MainWindow

    def settle(seconds: float) -> None:
        end = time.perf_counter() + seconds
        while time.perf_counter() < end or window.viewport.surface_building:
            app.processEvents()
            time.sleep(0.01)

    settings = QSettings(str(Path(tempfile.mkdtemp()) / "s.ini"), QSettings.Format.IniFormat)
    window = MainWindow(settings)
    window.show()
    window.files.open_default()
    window.kernel_warmer.wait()
    while window.homogenization_panel.is_busy:
        settle(0.1)
    settle(3.0)
    return window, settle


def probe_rss(
    meshes: Path, stall_only: bool = False, gui: bool = False, default: bool = False
) -> dict[str, object]:
    from PySide6.QtCore import Qt
    from PySide6.QtTest import QTest
    from PySide6.QtWidgets import QApplication

    window, settle = start_app()
    app = QApplication.instance()
    result: dict[str, object] = {"idle": rss_mb(), "idle_anonymous": anonymous_mb()}
    if default:  # the stall on the default model instead
        result.update(dynamic_stroke_stall(app, window, on_gui_thread=gui))
        window.document._saved_vertices = window.document.sculptor.vertices.copy()
        window.document._saved_faces = window.document.sculptor.faces
        window.close()
        return result
    path = big_mesh(meshes)
    if isinstance(path, str):
        result["skipped"] = path
        return result
    if not window.files.open_file(str(path)):
        result["skipped"] = f"could not open {path}"
        return result
    settle(3.0)
    result["vertices"] = len(window.document.sculptor.vertices)
    result["big"] = rss_mb()
    if stall_only:
        result.update(dynamic_stroke_stall(app, window, on_gui_thread=gui))
        window.document._saved_vertices = window.document.sculptor.vertices.copy()
        window.document._saved_faces = window.document.sculptor.faces
        window.close()
        return result
    result.update(interaction_figures(app, window))
    result.update(dynamic_stroke_stall(app, window))
    window.document._saved_vertices = window.document.sculptor.vertices.copy()  # no prompt
    assert not window.document.dirty  # Ctrl+N then asks nothing
    window.activateWindow()  # the shortcut fires in the active window
    QTest.qWaitForWindowActive(window, 5000)
    QTest.keyClick(window.viewport, Qt.Key.Key_N, Qt.KeyboardModifier.ControlModifier)
    settle(3.0)
    result["back"] = rss_mb()
    result["back_anonymous"] = anonymous_mb()
    result["back_vertices"] = len(window.document.sculptor.vertices)
    window.close()
    return result


def interaction_figures(app, window) -> dict[str, object]:
    """Brush steps, stroke, camera and settled frames on the open mesh, from real events
    posted to the viewport (milliseconds, medians)."""
    from statistics import median

    from PySide6.QtCore import QEvent, QPoint, QPointF, Qt
    from PySide6.QtGui import QMouseEvent, QWheelEvent
    from PySide6.QtWidgets import QApplication

    vp = window.viewport
    # the brush step on the GUI thread: a slow one on a big mesh would go to the stroke
    # worker (app.stroke_worker), and this figure is the app's cost around the engine
    vp.stroke_worker.slow_step_ms = float("inf")
    frames: list[tuple[float, bool]] = []  # (ms, drawn from the interaction copy)
    vp.frame_rendered.connect(lambda ms: frames.append((ms, vp.lod.shown)))
    app_steps: list[float] = []
    engine_steps: list[float] = []
    tools_flush = window.tools.flush

    def engine_timed():
        update = tools_flush()
        if update.step_seconds:
            engine_steps.append(1e3 * update.step_seconds)
        return update

    window.tools.flush = engine_timed
    viewport_flush = vp.flush_tools

    def app_timed() -> None:  # engine + tools + the viewport's arrays, without the render
        start = time.perf_counter()
        viewport_flush()
        app_steps.append(1e3 * (time.perf_counter() - start))

    vp.flush_tools = app_timed
    vp._flush_timer.timeout.disconnect()
    vp._flush_timer.timeout.connect(app_timed)

    def post(kind, pos, button, buttons) -> None:
        event = QMouseEvent(
            kind, pos, vp.mapToGlobal(pos), button, buttons, Qt.KeyboardModifier.NoModifier
        )
        QApplication.postEvent(vp, event)

    def until_quiet() -> None:
        app.processEvents()  # the posted events first
        timers = (vp._flush_timer, vp._camera_timer, vp._wheel_timer, vp._hover_timer)
        while vp.render_pending or any(timer.isActive() for timer in timers):
            app.processEvents()
        app.processEvents()

    def full_frames(count: int) -> list[float]:
        out = []
        for _ in range(count):
            vp.render_now()
            out.append(vp.last_frame_ms)
            until_quiet()
        return out

    w, h = vp.width(), vp.height()
    start = QPointF(0.45 * w, 0.5 * h)
    if vp.pick(start) is None:
        return {"interaction_skipped": "no model under the view's middle"}
    until_quiet()
    full = median(full_frames(3))

    def drag(button, moves: int, step: tuple[float, float]) -> tuple[list[float], float, float]:
        """Frames during a drag (one move at a time, drawn before the next), then the
        release: ms to a settled screen and the settled frame's ms."""
        post(QEvent.Type.MouseButtonPress, start, button, button)
        until_quiet()
        frames.clear()
        pos = start
        for k in range(1, moves + 1):
            pos = QPointF(start.x() + step[0] * k, start.y() + step[1] * k)
            post(QEvent.Type.MouseMove, pos, Qt.MouseButton.NoButton, button)
            until_quiet()
        during = [ms for ms, light in frames]
        frames.clear()
        released = time.perf_counter()
        post(QEvent.Type.MouseButtonRelease, pos, button, Qt.MouseButton.NoButton)
        until_quiet()
        settled = 1e3 * (time.perf_counter() - released)
        after = [ms for ms, light in frames if not light]
        return during, settled, after[-1] if after else float("nan")

    left, middle = Qt.MouseButton.LeftButton, Qt.MouseButton.MiddleButton
    stroke, stroke_settled, stroke_full = drag(left, 20, (2.0, -1.2))
    figures: dict[str, object] = {
        "full_frame": full,
        "light_faces": vp.lod.light.n_faces if vp.lod.light is not None else 0,
        "app_step": median(app_steps[1:]) if len(app_steps) > 1 else float("nan"),
        "engine_step": median(engine_steps[1:]) if len(engine_steps) > 1 else float("nan"),
        "stroke_frame": median(stroke),
        "stroke_settled": stroke_settled,
        "stroke_full": stroke_full,
    }
    camera, camera_settled, camera_full = drag(middle, 12, (6.0, 2.0))
    figures.update(camera_frame=median(camera), camera_settled=camera_settled)
    figures["camera_full"] = camera_full
    frames.clear()
    for _ in range(3):  # wheel notches, each drawn
        wheel = QWheelEvent(
            start, vp.mapToGlobal(start), QPoint(0, 0), QPoint(0, 120), Qt.MouseButton.NoButton,
            Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False,
        )  # fmt: skip
        QApplication.postEvent(vp, wheel)
        until_quiet()
    zoom = [ms for ms, light in frames if light]
    waited = time.perf_counter()
    while vp.lod.shown or vp.render_pending:  # the settle timer draws the full mesh
        app.processEvents()
        time.sleep(0.005)
    figures["wheel_frame"] = median(zoom) if zoom else float("nan")
    figures["wheel_settled"] = 1e3 * (time.perf_counter() - waited)
    figures["wheel_full"] = frames[-1][0] if frames and not frames[-1][1] else float("nan")
    cpu = time.process_time()
    idle_start = time.perf_counter()
    while time.perf_counter() - idle_start < 3.0:
        app.processEvents()
        time.sleep(0.05)
    figures["idle_cpu"] = 100 * (time.process_time() - cpu) / 3.0
    return figures


def _timed_release_stages(window) -> list[tuple[str, float, float]]:
    """Wrap what a dynamic-topology stroke's end runs (the tools' release: undo step and
    journal; showing the new mesh; the index build or renumbering, on the background thread;
    taking the built index) to record (name, start, end) of each call, perf_counter seconds."""
    import app.level_of_detail

    spans: list[tuple[str, float, float]] = []

    def timed(name, function):
        def run(*args, **kwargs):
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                spans.append((name, start, time.perf_counter()))

        return run

    vp, tools = window.viewport, window.tools
    tools.release = timed("tools.release (undo step, journal)", tools.release)
    vp.set_mesh = timed("viewport.set_mesh", vp.set_mesh)
    vp._use_index = timed("viewport takes the index", vp._use_index)
    tools.flush = timed("brush step", tools.flush)
    built = app.level_of_detail.indexed
    app.level_of_detail.indexed = timed("index and copy built anew (background)", built)
    import app.mesh_display

    refreshed = app.level_of_detail.refreshed_polydata
    if os.environ.get("GOGREEN_BENCH_FRESH_ARRAYS"):  # the other way: a new PolyData each time
        fresh = app.level_of_detail.indexed_polydata
        app.mesh_display.refreshed_polydata = timed(
            "  VTK given a new PolyData", lambda _mesh, surface: fresh(surface)
        )
    else:
        app.mesh_display.refreshed_polydata = timed("  VTK arrays refreshed in place", refreshed)
    _time_renumbering_stages(timed)
    return spans


def _time_renumbering_stages(timed) -> None:
    """Wrap SurfaceIndex.renumber (in place: an undo's or a redo's on the GUI thread, a
    release's on the background thread) and its stages (the slot maps
    of vertices and faces, the face lists rewritten, the rows that moved found, the
    normals and face normals of what changed) with ``timed``."""
    from gogreen_core.mesh import geometry

    index = geometry.SurfaceIndex
    inside = [False]

    def renumber(self, *args):
        inside[0] = True
        try:
            return timed("index renumbered in place", plain)(self, *args)
        finally:
            inside[0] = False

    def stage(name, function):
        wrapped = timed(name, function)
        return lambda *a, **k: (wrapped if inside[0] else function)(*a, **k)

    plain = index.renumber
    index.renumber = renumber
    geometry._carried_slots = timed("  renumbering: slot maps", geometry._carried_slots)
    index._relist = timed("  renumbering: face lists", index._relist)
    index.changed_rows = stage("  renumbering: moved rows found", index.changed_rows)
    index.update = stage("  renumbering: normals of what changed", index.update)


def dynamic_stroke_stall(
    app, window, seconds: float = 10.0, on_gui_thread: bool = False
) -> dict[str, object]:
    """A left-button grab (radius 0.03) with dynamic topology on the open mesh, moves posted
    every 40 ms for ``seconds``, then the release: the longest gap between ticks of a 10 ms
    timer of the GUI thread from the press to the stroke's end (the window's longest stall),
    the events applied and seconds from the release to the stroke's end (issue 34).
    ``on_gui_thread``: every step on the GUI thread, as before issue 34's worker."""
    from PySide6.QtCore import QEvent, QPointF, Qt, QTimer
    from PySide6.QtGui import QMouseEvent
    from PySide6.QtWidgets import QApplication

    from app.stroke_worker import SLOW_STEP_MS

    vp = window.viewport
    vp.stroke_worker.slow_step_ms = SLOW_STEP_MS
    if on_gui_thread:
        vp.stroke_worker.slow_steps = lambda *_args: False
    result_before = len(window.document.sculptor.vertices)
    window.model.dynamic_topology = True
    window.model.brush.update({"kind": "grab", "radius": 0.03})
    w, h = vp.width(), vp.height()
    start = QPointF(0.45 * w, 0.5 * h)
    ticks: list[float] = []
    beat = QTimer()
    beat.setInterval(10)
    beat.timeout.connect(lambda: ticks.append(time.perf_counter()))

    def post(kind, pos, button, buttons) -> None:
        event = QMouseEvent(
            kind, pos, vp.mapToGlobal(pos), button, buttons, Qt.KeyboardModifier.NoModifier
        )
        QApplication.postEvent(vp, event)

    def stroke_going() -> bool:
        return window.tools.dragging or vp.stroke_worker.running or vp.render_pending

    left, none = Qt.MouseButton.LeftButton, Qt.MouseButton.NoButton

    def until_ended() -> None:  # and the new faces indexed (strokes wait for it)
        while stroke_going() or vp.surface_building:
            app.processEvents()
            time.sleep(0.002)

    # a first stroke, not measured: the remesh kernels load (or compile) on first use
    post(QEvent.Type.MouseButtonPress, start, left, left)
    for k in range(1, 4):
        post(QEvent.Type.MouseMove, QPointF(start.x() - 12 * k, start.y() + 5 * k), none, left)
        app.processEvents()
        while vp.stroke_worker.running or vp._flush_timer.isActive():
            app.processEvents()
    post(QEvent.Type.MouseButtonRelease, QPointF(start.x() - 36, start.y() + 15), left, none)
    app.processEvents()
    until_ended()
    steps: list[float] = []
    vp.step_timed.connect(steps.append)
    renders: list[tuple[float, float]] = []  # (start, end) of each frame
    drew: list[str] = []  # what each frame drew

    def rendered(ms: float) -> None:
        renders.append((time.perf_counter() - ms / 1e3, time.perf_counter()))
        drew.append("frame (copy)" if vp.lod.shown else "frame (full mesh)")

    vp.frame_rendered.connect(rendered)
    stages = _timed_release_stages(window)
    beat.start()
    began = time.perf_counter()
    post(QEvent.Type.MouseButtonPress, start, left, left)
    count = round(seconds / 0.04)
    released = [0.0]
    to_global = vp.mapToGlobal(QPointF(0.0, 0.0))

    def pointer() -> None:  # as the window system does: on time, however busy the window
        def send(kind, pos, button, buttons) -> None:
            modifiers = Qt.KeyboardModifier.NoModifier
            event = QMouseEvent(kind, pos, pos + to_global, button, buttons, modifiers)
            QApplication.postEvent(vp, event)  # (thread-safe)

        for k in range(1, count + 1):
            time.sleep(max(0.0, began + 0.04 * k - time.perf_counter()))
            pos = QPointF(start.x() + 0.25 * k, start.y() - 0.15 * k)
            send(QEvent.Type.MouseMove, pos, none, left)
        released[0] = time.perf_counter()
        send(QEvent.Type.MouseButtonRelease, pos, left, none)

    thread = threading.Thread(target=pointer)
    thread.start()
    while thread.is_alive():
        app.processEvents()
        time.sleep(0.002)
    thread.join()
    moves = count
    app.processEvents()
    until_ended()
    ended = time.perf_counter()
    release_time = released[0]
    beat.stop()
    stages.extend((what, s, e) for what, (s, e) in zip(drew, renders, strict=True))
    stages.sort(key=lambda stage: stage[1])
    stall_stages = [
        (name, round(1e3 * (a - release_time)), round(1e3 * (b - a)))
        for name, a, b in stages
        if b >= release_time
    ]
    history: dict[str, object] = {}  # (before the setting's change, an undo step of its own)
    for name in ("undo", "redo"):  # of the stroke: until a next stroke can start
        spans_before, frames_before = len(stages), len(renders)
        begun = time.perf_counter()
        getattr(window, name)()  # what Ctrl+Z / Ctrl+Shift+Z run
        until_ended()
        history[f"{name}_ms"] = 1e3 * (time.perf_counter() - begun)
        spans = [*stages[spans_before:], *(("frame", a, b) for a, b in renders[frames_before:])]
        history[f"{name}_stages"] = [
            (what, round(1e3 * (a - begun)), round(1e3 * (b - a)))
            for what, a, b in sorted(spans, key=lambda span: span[1])
        ]
    window.model.dynamic_topology = False
    spans = list(zip([began, *ticks], [*ticks, ended], strict=True))
    gaps = [b - a for a, b in spans]

    def outside_renders(a: float, b: float) -> float:
        return b - a - sum(max(0.0, min(b, e) - max(a, s)) for s, e in renders)

    return {
        "stall_max": 1e3 * max(gaps),
        "stall_no_render": 1e3 * max(outside_renders(a, b) for a, b in spans),
        "frame": statistics.median(e - s for s, e in renders) * 1e3 if renders else float("nan"),
        "stall_moves": moves,
        "stall_events": window.tools.processed,
        "stall_release": 1e3 * (ended - release_time),
        "stall_vertices": len(window.document.sculptor.vertices),
        "vertices_before": result_before,
        "stall_step": statistics.median(steps) if steps else float("nan"),
        "stall_steps": [round(ms) for ms in steps],
        # what ran after the release: (stage, ms from the release to its start, its ms)
        "stall_stages": stall_stages,
        **history,
    }


# -- compile figures -----------------------------------------------------------------------------
FIRST_REQUEST = """
import json, time
from gogreen_core import _compiled
from gogreen_core.field import _drivers
try:
    from gogreen_core.interaction.compile_kernels import UNIT_MODULES, units_for_app
    for module in UNIT_MODULES:  # importing them registers their units
        __import__(module)
    units = units_for_app(8)
except ImportError:  # before the install step compiled them: the app's request of then
    import gogreen_core.mesh.geometry, gogreen_core.sculpt.brushes.paint_kernels
    import gogreen_core.mesh.mesh_io.formats
    units = (*_drivers.units_for(8), _compiled.GEOMETRY, _compiled.MESH_IO, _compiled.BRUSHES)
import os
from pathlib import Path

def compile_cpu():
    # CPU seconds of this process's compiling children: running, and ended (reaped)
    ticks = 0
    for entry in Path("/proc").iterdir():
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):
            continue
        if entry.name.isdigit() and int(fields[1]) == os.getpid():
            ticks += int(fields[11]) + int(fields[12])
    ended = os.times()
    return ticks / os.sysconf("SC_CLK_TCK") + ended.children_user + ended.children_system

start = time.perf_counter()
_compiled.request(*units)
_compiled.wait([_compiled.DRIVERS])
drivers, drivers_cpu = time.perf_counter() - start, compile_cpu()
_compiled.wait(units)
print(json.dumps({"drivers": drivers, "drivers_cpu": drivers_cpu,
                  "all": time.perf_counter() - start, "all_cpu": compile_cpu()}))
"""

ONE_EVENT = """
import sys, time
import numpy as np
from gogreen_core import Brush, BrushEvent, Material, Sculptor
from gogreen_core.mesh.shapes import default_model
vertices, faces = default_model(4)
sculptor = Sculptor(vertices, faces, material=Material.cubic(3.0, 1.5, 0.4), l_max=6)
top = vertices[int(np.argmax(vertices[:, 2]))]
sculptor.apply_brush(Brush("grab", radius=0.2), [BrushEvent(top, [0.02, 0.05, 0.0])])
time.sleep(8)  # the rest of a script: long enough for a compile to be started
"""


def compiling_children(cache: Path) -> set[int]:
    """Pids of the compiling children (``_compiled._main``) working for the cache ``cache``."""
    pids = set()
    needle = f"NUMBA_CACHE_DIR={cache}".encode()
    for entry in Path("/proc").iterdir():
        try:
            if (
                entry.name.isdigit()
                and b"_compiled import _main" in (entry / "cmdline").read_bytes()
            ):
                if needle in (entry / "environ").read_bytes().split(b"\0"):
                    pids.add(int(entry.name))
        except OSError:
            continue
    return pids


def compile_ready() -> dict[str, float]:
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, GOGREEN_COMPILE="child")
        run = subprocess.run(
            [sys.executable, "-c", FIRST_REQUEST], env=env, capture_output=True, text=True
        )
        if run.returncode:
            raise RuntimeError(run.stderr)
        return json.loads(run.stdout.strip().splitlines()[-1])


def three_scripts() -> int:
    with tempfile.TemporaryDirectory() as folder:
        cache = Path(folder)
        env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), GOGREEN_COMPILE="child")
        seen: set[int] = set()
        try:
            for _ in range(3):
                script = subprocess.Popen(
                    [sys.executable, "-c", ONE_EVENT], env=env, stderr=subprocess.DEVNULL
                )
                while script.poll() is None:
                    seen |= compiling_children(cache)
                    time.sleep(0.2)
            seen |= compiling_children(cache)
        finally:
            for pid in compiling_children(cache):
                os.kill(pid, signal.SIGKILL)
        return len(seen)


def print_interaction(r: dict[str, object]) -> None:
    if "interaction_skipped" in r:
        print(f"interaction figures: skipped ({r['interaction_skipped']})")
        return
    f = {k: v for k, v in r.items() if isinstance(v, float)}
    print(
        f"brush step in the app at {r['vertices']:,} vertices (median of 19 events): "
        f"{f['app_step']:.0f} ms, the engine's event {f['engine_step']:.0f} ms "
        f"(+{f['app_step'] - f['engine_step']:.0f} ms; goal <= +20)"
    )
    print(
        f"full frame {f['full_frame']:.0f} ms; interaction copy {r['light_faces']:,} faces: "
        f"stroke frames {f['stroke_frame']:.0f} ms ({f['full_frame'] / f['stroke_frame']:.1f}x), "
        f"orbit frames {f['camera_frame']:.0f} ms ({f['full_frame'] / f['camera_frame']:.1f}x), "
        f"wheel frames {f['wheel_frame']:.0f} ms (goal >= 3x)"
    )
    print(
        f"settled at full resolution: stroke release -> {f['stroke_settled']:.0f} ms "
        f"(full frame {f['stroke_full']:.0f} ms), orbit release -> {f['camera_settled']:.0f} ms "
        f"(frame {f['camera_full']:.0f} ms), "
        f"last wheel notch's frame -> {f['wheel_settled']:.0f} ms "
        f"(frame {f['wheel_full']:.0f} ms); idle CPU after it {f['idle_cpu']:.1f} % of a core"
    )


def print_idle_and_floor(launches: int) -> None:
    """Idle RSS of the app beside the floor of its dependencies, medians of fresh launches
    taking turns (the page cache then serves them alike)."""
    from statistics import median

    runs: dict[str, list[dict[str, float]]] = {"app": [], "gui": [], "all": [], "lean": []}
    for _ in range(launches):
        runs["gui"].append(floor())
        runs["all"].append(floor("--all"))
        runs["lean"].append(floor("--all", "--lean"))
        runs["app"].append(child_json(str(HERE), "--probe-idle"))
    rss = {k: median(r["rss"] for r in v) for k, v in runs.items()}
    anon = {k: median(r["anonymous"] for r in v) for k, v in runs.items()}
    each = ", ".join(f"{r['rss']:.0f}" for r in runs["app"])
    print(
        f"RSS idle, default model, fresh start (median of {launches} launches: {each}): "
        f"{rss['app']:.0f} MB (anonymous {anon['app']:.0f} MB; goal <= 500)"
    )
    print(
        f"floor of the dependencies (a bare window of the app's size, one pyvistaqt view of a "
        f"40,962-point sphere, no multisampling as the viewport): {rss['gui']:.0f} MB "
        f"(anonymous {anon['gui']:.0f}); with numba, "
        f"scipy.spatial and trimesh imported too: {rss['all']:.0f} MB (anonymous "
        f"{anon['all']:.0f}); the app above it: {rss['app'] - rss['all']:+.0f} MB "
        f"(anonymous {anon['app'] - anon['all']:+.0f})"
    )
    print(
        f"the same floor with the dependencies loaded as the app loads them (app.memory."
        f"start_lean: PySide6 keeps no module sources, pyvista no mypy plugin): "
        f"{rss['lean']:.0f} MB (anonymous {anon['lean']:.0f}); the app above it (ours): "
        f"{rss['app'] - rss['lean']:+.0f} MB (anonymous {anon['app'] - anon['lean']:+.0f})"
    )


def print_stall(r: dict[str, object]) -> None:
    if "stall_max" not in r:
        return
    print(
        f"dynamic-topology grab (radius 0.03) for 10 s on the {r['vertices_before']:,}-vertex "
        f"mesh: longest GUI-thread stall "
        f"{r['stall_max']:.0f} ms (10 ms heartbeat), {r['stall_no_render']:.0f} ms not counting "
        f"renders (frames {r['frame']:.0f} ms); {r['stall_moves']} moves -> "
        f"{r['stall_events']} events (median {r['stall_step']:.0f} ms), release -> next stroke "
        f"possible {r['stall_release']:.0f} ms, "
        f"{r['stall_vertices']:,} vertices after"
    )
    for name, start, ms in r.get("stall_stages", []):
        print(f"    after the release: {name} at {start} ms, for {ms} ms")
    for step in ("undo", "redo"):
        if f"{step}_ms" in r:
            print(f"{step} of that stroke -> next stroke possible {r[f'{step}_ms']:.0f} ms")
            for name, start, ms in r[f"{step}_stages"]:
                print(f"    after the {step}: {name} at {start} ms, for {ms} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--meshes", default=str(HERE.parents[2] / "shared/meshes"))
    parser.add_argument("--probe-rss", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--probe-idle", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument(
        "--launches", type=int, default=3, help="fresh launches for the idle medians (default 3)"
    )
    parser.add_argument("--skip-compile", action="store_true", help="RSS figures only")
    parser.add_argument(
        "--stall-only", action="store_true", help="only the dynamic-topology stroke's stall"
    )
    parser.add_argument(
        "--on-gui-thread", action="store_true", help="(--stall-only) steps on the GUI thread"
    )
    parser.add_argument(
        "--default-model", action="store_true", help="(--stall-only) on the default model"
    )
    parser.add_argument(
        "--fresh-arrays",
        action="store_true",
        help="(--stall-only) VTK gets a new PolyData after each renumbering (not Modified())",
    )
    parser.add_argument("--skip-rss", action="store_true", help="compile figures only")
    args = parser.parse_args()
    if args.fresh_arrays:  # (read by the probe's process)
        os.environ["GOGREEN_BENCH_FRESH_ARRAYS"] = "1"
    if args.probe_rss:
        options = (args.stall_only, args.on_gui_thread, args.default_model)
        print(json.dumps(probe_rss(Path(args.meshes), *options)))
        return
    if args.probe_idle:
        print(json.dumps(probe_idle()))
        return
    import gogreen_core

    print(f"code: {Path(gogreen_core.__file__).parent.parent}")
    if not args.skip_rss:
        if not args.stall_only:
            print_idle_and_floor(args.launches)
        options = ["--stall-only"] * args.stall_only + ["--on-gui-thread"] * args.on_gui_thread
        options += ["--default-model"] * args.default_model
        rss = child_json(str(HERE), "--probe-rss", "--meshes", args.meshes, *options)
        print(f"RSS idle, default model, fresh start (the process below): {rss['idle']:.0f} MB")
        if "skipped" in rss:
            print(f"1M-vertex mesh: skipped ({rss['skipped']})")
        elif args.stall_only:
            print_stall(rss)
        else:
            print(f"RSS with the {rss['vertices']:,}-vertex mesh open: {rss['big']:.0f} MB")
            change = 100 * (rss["back"] / rss["idle"] - 1)
            print(
                f"RSS after Ctrl+N back to the default model: {rss['back']:.0f} MB "
                f"({change:+.0f} % of the fresh start; anonymous {rss['back_anonymous']:.0f} MB, "
                f"{rss['idle_anonymous']:.0f} MB at the fresh start)"
            )
            print_interaction(rss)
            print_stall(rss)
    if args.skip_compile or args.stall_only:
        return
    load = os.getloadavg()[0]
    ready = compile_ready()
    print(
        f"empty cache: compiled drivers serve {ready['drivers']:.1f} s after the first request "
        f"({ready['drivers_cpu']:.1f} s of compiling CPU by then), every unit in after "
        f"{ready['all']:.1f} s ({ready['all_cpu']:.1f} s CPU); load average {load:.1f} on "
        f"{os.cpu_count()} cores (the CPU seconds are the wall time of a quiet machine)"
    )
    print(f"three one-event scripts in a row, empty cache: {three_scripts()} compilation(s)")


if __name__ == "__main__":
    main()
