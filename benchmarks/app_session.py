"""The real main window under Xvfb: start-up, idle CPU, a scripted 100-event drag, screenshot.

    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/app_session.py [--cold] [--out PNG]

Prints (figures only; nothing is asserted):

* start-up: seconds until the brush kernels are ready (``--cold``: from an empty numba cache and
  kernel directory, as on a fresh install), and the longest time the event loop did not answer
  meanwhile (a 20 ms heartbeat timer; a frozen window shows as a long gap);
* idle CPU: the process's CPU time over 5 s of the event loop with nothing to do, in % of a core;
* per mesh, a 100-event left-button drag posted to the viewport's event queue at 120 Hz (as a
  pen or a fast mouse delivers them): events received vs brush steps processed (moves arriving
  during a step or a render are coalesced; the last position is always applied), median brush
  step and render times, renders and milliseconds from the button release to a settled screen
  (no render pending), and the first stroke after start-up;
* 12 undos queued at once (a held Ctrl+Z): milliseconds until the screen settles, renders;
* a screenshot of the window.

Issue goals: idle ≤ 2 % of a core; release → settled in ≤ one render; first stroke after the
kernels are ready ≤ 1 s.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path


def _cold_cache() -> None:
    """Fresh numba cache and generated-kernel directories (before numba is imported)."""
    root = Path(tempfile.mkdtemp(prefix="gogreen-cold-"))
    os.environ["NUMBA_CACHE_DIR"] = str(root / "numba")
    os.environ["GOGREEN_KERNEL_DIR"] = str(root / "kernels")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    default_meshes = Path(__file__).resolve().parents[2] / "shared/meshes"
    parser.add_argument("--meshes", default=str(default_meshes))
    parser.add_argument("--cold", action="store_true", help="start from an empty kernel cache")
    parser.add_argument("--events", type=int, default=100)
    parser.add_argument("--out", default="app_session.png")
    args = parser.parse_args()
    if args.cold:
        _cold_cache()

    from PySide6.QtCore import QEvent, QPointF, QSettings, Qt, QTimer
    from PySide6.QtGui import QMouseEvent
    from PySide6.QtWidgets import QApplication

    app = QApplication.instance() or QApplication(sys.argv[:1])
    from app.main_window import MainWindow

    def spin(seconds: float) -> None:
        end = time.perf_counter() + seconds
        while time.perf_counter() < end:
            app.processEvents()
            time.sleep(0.002)

    # -- start-up ----------------------------------------------------------------------------
    gaps: list[float] = []
    last = [time.perf_counter()]

    def beat() -> None:
        now = time.perf_counter()
        gaps.append(now - last[0])
        last[0] = now

    heartbeat = QTimer()
    heartbeat.setInterval(20)
    heartbeat.timeout.connect(beat)
    t0 = time.perf_counter()
    settings = QSettings(str(Path(tempfile.mkdtemp()) / "s.ini"), QSettings.Format.IniFormat)
    window = MainWindow(settings)
    window.show()
    window.files.open_default()
    construct = time.perf_counter() - t0
    last[0] = time.perf_counter()
    heartbeat.start()
    while window.kernel_warmer.busy or not window.kernel_warmer.is_ready(window.model.l_max):
        app.processEvents()
        time.sleep(0.005)
    ready = time.perf_counter() - t0
    spin(0.3)
    heartbeat.stop()
    state = "cold (empty cache)" if args.cold else "warm cache"
    print(f"start-up, {state}: window {construct:.2f} s, kernels ready after {ready:.1f} s")
    print(f"  longest event-loop gap while compiling: {1e3 * max(gaps, default=0):.0f} ms")
    # let a homogenization preview started with the window finish before measuring
    while window.homogenization_panel.is_busy:
        spin(0.1)

    # -- idle --------------------------------------------------------------------------------
    spin(1.0)
    cpu0, wall0 = time.process_time(), time.perf_counter()
    idle_end = wall0 + 5.0
    while time.perf_counter() < idle_end:
        app.processEvents()
        time.sleep(0.05)  # Qt's own loop would block in poll(); this adds < 0.1 %
    cpu = time.process_time() - cpu0
    wall = time.perf_counter() - wall0
    print(f"idle CPU over {wall:.1f} s: {100 * cpu / wall:.1f} % of a core")

    # -- drags -------------------------------------------------------------------------------
    vp = window.viewport
    left = Qt.MouseButton.LeftButton
    # every render of the view (requested or from a paint event), timed by VTK's own events
    renders: list[float] = []
    vp.frame_rendered.connect(renders.append)
    steps: list[float] = []
    flush = window.tools.flush

    def timed_flush():
        update = flush()
        if update.step_seconds:
            steps.append(1e3 * update.step_seconds)
        return update

    window.tools.flush = timed_flush

    def post(kind, pos, button, buttons) -> None:
        event = QMouseEvent(
            kind, pos, vp.mapToGlobal(pos), button, buttons, Qt.KeyboardModifier.NoModifier
        )
        QApplication.postEvent(vp, event)

    def on_model() -> QPointF:
        """A widget point over the model, near the middle of the view."""
        w, h = vp.width(), vp.height()
        for fx, fy in ((0.45, 0.5), (0.5, 0.5), (0.5, 0.45), (0.55, 0.5), (0.5, 0.55)):
            point = QPointF(fx * w, fy * h)
            if vp.pick(point) is not None:
                return point
        return QPointF(0.5 * w, 0.5 * h)

    def drag(n_events: int) -> dict:
        start = on_model()
        steps.clear()
        renders.clear()
        t_press = time.perf_counter()
        post(QEvent.Type.MouseButtonPress, start, left, left)
        spin(0.05)
        if not window.tools.dragging:  # the press orbited instead (or was refused)
            post(QEvent.Type.MouseButtonRelease, start, left, Qt.MouseButton.NoButton)
            spin(0.5)
            return None
        pos = start
        # Move k is due at k/120 s: whatever fell due while the window was busy (a step, a
        # render) is posted at once, as the X server queues a real mouse's events.
        t_moves, k = time.perf_counter(), 0
        while k < n_events:
            due = min(n_events, int((time.perf_counter() - t_moves) * 120) + 1)
            while k < due:
                k += 1
                pos = QPointF(start.x() + 1.5 * k, start.y() - 0.9 * k + 6 * ((k % 10) / 10))
                post(QEvent.Type.MouseMove, pos, Qt.MouseButton.NoButton, left)
            app.processEvents()
            time.sleep(0.001)
        drag_renders = len(renders)
        post(QEvent.Type.MouseButtonRelease, pos, left, Qt.MouseButton.NoButton)
        t_release = time.perf_counter()
        app.processEvents()  # the release itself
        while vp.render_pending or window.tools.dragging:
            app.processEvents()
        settled = time.perf_counter() - t_release
        return {
            "received": window.tools.received,
            "processed": window.tools.processed,
            "step": statistics.median(steps) if steps else float("nan"),
            "render": statistics.median(renders) if renders else float("nan"),
            "after": len(renders) - drag_renders,
            "settled": 1e3 * settled,
            "total": time.perf_counter() - t_press,
        }

    # the first stroke after start-up: press, one move, release
    first = drag(1)
    if first is None:
        sys.exit(f"the first press did not start a stroke: {window.message_label.text()}")
    print(
        f"first stroke after ready: {first['total']:.2f} s (press, 1 move, release; "
        f"step {first['step']:.0f} ms, render {first['render']:.0f} ms)"
    )
    header = (
        f"{'mesh':<16} {'vertices':>8} {'recv':>5} {'proc':>5} {'step ms':>8} "
        f"{'render ms':>9} {'renders after release':>22} {'release→settled ms':>19}"
    )
    print(header)
    meshes = [("default", None)] + [
        (name, Path(args.meshes) / name) for name in ("stanford-bunny.obj", "ogre.obj")
    ]
    for name, path in meshes:
        if path is not None:
            if not path.exists():
                print(f"{name:<16} skipped: {path} not found")
                continue
            if not window.files.open_file(str(path)):
                continue
            spin(0.5)
        r = drag(args.events)
        n = len(window.document.sculptor.vertices)
        if r is None:
            note = window.message_label.text()
            print(f"{name:<16} {n:>8} the press did not start a stroke: {note}")
            continue
        print(
            f"{name:<16} {n:>8} {r['received']:>5} {r['processed']:>5} {r['step']:>8.1f} "
            f"{r['render']:>9.0f} {r['after']:>22} {r['settled']:>19.0f}"
        )
        window.document._saved_vertices = window.document.sculptor.vertices.copy()  # no prompt
    # 12 undos queued at once (a held Ctrl+Z): one render for all of them, not twelve
    for _ in range(12):
        r = drag(5)
    renders.clear()
    t_undo = time.perf_counter()
    for _ in range(12):
        QTimer.singleShot(0, window.undo)
    app.processEvents()
    while vp.render_pending:
        app.processEvents()
    print(
        f"12 queued undos: settled after {1e3 * (time.perf_counter() - t_undo):.0f} ms, "
        f"{len(renders)} render(s)"
    )
    window.files.save_screenshot(args.out)
    print(f"screenshot: {args.out}")
    # the drags above left unsaved edits: without this, closing asks to save and waits forever
    window.document._saved_vertices = window.document.sculptor.vertices.copy()
    window.close()


if __name__ == "__main__":
    main()
