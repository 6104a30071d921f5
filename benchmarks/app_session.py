"""Scripted stroke in the real main window (run under Xvfb): ms per brush event, screenshot.

    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/app_session.py [--out shot.png]

Goal (issue "Desktop application"): ≤ 33 ms per event on the ogre, excluding render time.
Prints the engine step (what the goal counts) and the whole event including the view update
(positions, normals) and the render. Figures only; nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

from PySide6.QtCore import QPointF, QSettings, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtWidgets import QApplication


def mouse(viewport, kind, pos, button, buttons) -> None:
    event = QMouseEvent(
        kind, pos, viewport.mapToGlobal(pos), button, buttons, Qt.KeyboardModifier.NoModifier
    )
    handler = {
        QMouseEvent.Type.MouseButtonPress: viewport.mousePressEvent,
        QMouseEvent.Type.MouseMove: viewport.mouseMoveEvent,
        QMouseEvent.Type.MouseButtonRelease: viewport.mouseReleaseEvent,
    }[kind]
    handler(event)


def play_stroke(app, window, events: int = 40) -> dict[str, list[float]]:
    """A curved left-button drag across the model; per-event timings in ms."""
    vp = window.viewport
    w, h = vp.width(), vp.height()
    left = Qt.MouseButton.LeftButton
    start = QPointF(0.45 * w, 0.5 * h)
    mouse(vp, QMouseEvent.Type.MouseButtonPress, start, left, left)
    times: dict[str, list[float]] = {"engine": [], "event": []}
    for k in range(1, events + 1):
        pos = QPointF(start.x() + 2.0 * k, start.y() - 1.2 * k + 6 * ((k % 10) / 10))
        t0 = time.perf_counter()
        mouse(vp, QMouseEvent.Type.MouseMove, pos, Qt.MouseButton.NoButton, left)
        total = 1e3 * (time.perf_counter() - t0)
        app.processEvents()
        times["engine"].append(window.last_step_ms)
        times["event"].append(total)
    mouse(vp, QMouseEvent.Type.MouseButtonRelease, pos, left, Qt.MouseButton.NoButton)
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    default_meshes = Path(__file__).resolve().parents[2] / "shared/meshes"
    parser.add_argument("--meshes", default=str(default_meshes))
    parser.add_argument("--out", default="app_session.png")
    args = parser.parse_args()
    app = QApplication.instance() or QApplication(sys.argv[:1])
    from app.main_window import MainWindow

    settings = QSettings(str(Path(tempfile.mkdtemp()) / "s.ini"), QSettings.Format.IniFormat)
    window = MainWindow(settings)
    window.show()
    for _ in range(5):
        app.processEvents()
    print(f"{'mesh':<22} {'vertices':>9} {'engine ms':>10} {'event ms (all)':>15}")
    for name in ("stanford-bunny.obj", "ogre.obj"):
        if not window.open_file(str(Path(args.meshes) / name)):
            continue
        app.processEvents()
        times = play_stroke(app, window)
        med = {k: statistics.median(v[3:]) for k, v in times.items()}
        n = len(window.document.sculptor.vertices)
        print(f"{name:<22} {n:>9} {med['engine']:>10.1f} {med['event']:>15.1f}")
    window.save_screenshot(args.out)
    print(f"screenshot: {args.out}")
    window.document._saved_vertices = window.document.sculptor.vertices.copy()  # no prompt
    window.close()


if __name__ == "__main__":
    main()
