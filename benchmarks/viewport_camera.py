"""Benchmark of the viewport's camera input and look on a 1M-vertex mesh (issue 32 items 3, 5).

    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/viewport_camera.py [--repeats 3]

On the 1M-vertex mesh of ``benchmarks/scale.py`` (the shared ogre subdivided twice, else a
procedural sphere) in a shown 1000 × 800 :class:`app.viewport.SculptViewport`, prints the
medians of:

* a burst of 6 wheel notches posted at once (as a wheel spun during a slow frame queues them):
  renders and seconds until the view is still, through the previous path (each notch handed to
  VTK's trackball style, which zooms and renders at once) and through the viewport's (notches
  summed until the event loop is idle, one zoom about the point under the cursor, one render);
* the same for an orbit drag of 8 moves posted at once;
* one render with the matcap and with studio lights;
* :meth:`SculptViewport.update_vertices` for an event moving the 1k and 100k vertices nearest
  the picked point, with the cavity tint off and on (its curvature for the moved rows and their
  one-ring, and their colours).

Figures only, no assertions.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from PySide6.QtCore import QEvent, QPoint, QPointF, Qt
from PySide6.QtGui import QMouseEvent, QWheelEvent
from PySide6.QtWidgets import QApplication
from pyvistaqt import QtInteractor

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scale import median_ms, million_vertex_mesh

from app.matcaps import use_matcap
from app.viewport import SculptViewport
from gogreen_core import _compiled


def settle(app: QApplication, viewport: SculptViewport) -> None:
    """Run the event loop until nothing is pending (posted input, timers, the render)."""
    for _ in range(1000):
        app.processEvents()
        if not viewport.render_pending and not viewport._wheel_timer.isActive():
            if not viewport._camera_timer.isActive():
                return
        time.sleep(0.001)


def wheel_event(viewport: SculptViewport, pos: QPoint, notches: int) -> QWheelEvent:
    p = QPointF(pos)
    return QWheelEvent(
        p, viewport.mapToGlobal(p), QPoint(), QPoint(0, 120 * notches), Qt.MouseButton.NoButton,
        Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False,
    )  # fmt: skip


def mouse_event(viewport: SculptViewport, kind: QEvent.Type, pos: QPoint, button, buttons):
    p = QPointF(pos)
    return QMouseEvent(
        kind, p, viewport.mapToGlobal(p), button, buttons, Qt.KeyboardModifier.NoModifier
    )


def burst(app, viewport, events, deliver=None) -> tuple[int, float]:
    """Renders and seconds until still after posting ``events`` at once (or handing them to
    ``deliver``)."""
    settle(app, viewport)
    frames, start = viewport.frames, time.perf_counter()
    if deliver is not None:
        deliver(events)
    else:
        for event in events:
            app.postEvent(viewport, event)
    settle(app, viewport)
    return viewport.frames - frames, time.perf_counter() - start


def camera_bursts(app, viewport, repeats: int, label: str, deliver=None) -> None:
    """Renders and seconds of 6 wheel notches and of an 8-move orbit drag posted at once;
    ``deliver(events)``: hand them over another way (the previous path)."""
    center = QPoint(500, 400)
    press, move, release = (
        QEvent.Type.MouseButtonPress, QEvent.Type.MouseMove, QEvent.Type.MouseButtonRelease
    )  # fmt: skip
    middle, none = Qt.MouseButton.MiddleButton, Qt.MouseButton.NoButton
    zoom, orbit = [], []
    for k in range(repeats):
        notches = 1 if k % 2 == 0 else -1
        wheels = [wheel_event(viewport, center, notches) for _ in range(6)]  # Qt owns each
        events = [mouse_event(viewport, press, center, middle, middle)]
        events += [
            mouse_event(viewport, move, center + QPoint(6 * i, 3 * i), none, middle)
            for i in range(1, 9)
        ]
        events.append(mouse_event(viewport, release, center + QPoint(48, 24), middle, none))
        zoom.append(burst(app, viewport, wheels, deliver))
        orbit.append(burst(app, viewport, events, deliver))
    for name, runs in (("6 wheel notches", zoom), ("orbit, 8 moves", orbit)):
        renders = statistics.median(r for r, _ in runs)
        seconds = statistics.median(s for _, s in runs)
        print(f"{label:>9}: {name}: {renders:.0f} renders, {seconds:.2f} s (median of {repeats})")


def previous_path(viewport: SculptViewport):
    """The input as it was handled before: each wheel notch handed to VTK's trackball style
    (it zooms to the view's centre and renders at once), each orbit move too."""

    def deliver(events) -> None:
        for event in events:
            if isinstance(event, QWheelEvent):
                QtInteractor.wheelEvent(viewport, event)
            elif event.type() == QEvent.Type.MouseButtonPress:
                viewport.mousePressEvent(event)  # starts the orbit (no render)
            else:
                vtk_button = viewport._camera[1]
                handler = (
                    QtInteractor.mouseMoveEvent
                    if event.type() == QEvent.Type.MouseMove
                    else QtInteractor.mouseReleaseEvent
                )
                handler(viewport, viewport._as_button(event, vtk_button))
        viewport._camera = None

    return deliver


def main() -> None:
    root = Path(__file__).resolve().parents[1]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--meshes", type=Path, default=root.parent / "shared" / "meshes")
    args = parser.parse_args()
    app = QApplication.instance() or QApplication([])
    _compiled.prepare(_compiled.GEOMETRY)
    vertices, faces, source = million_vertex_mesh(args.meshes)
    print(f"mesh: {source}, {len(vertices):,} vertices, {len(faces):,} faces")
    viewport = SculptViewport()
    viewport.resize(1000, 800)
    viewport.show()
    app.processEvents()
    viewport.set_mesh(vertices, faces)
    viewport.wait_for_surface()
    app.processEvents()
    use_matcap(viewport.mesh_actor, "clay")
    viewport.mesh_actor.prop.ambient, viewport.mesh_actor.prop.diffuse = 0.0, 1.0
    viewport.render_now()
    settle(app, viewport)

    camera_bursts(app, viewport, args.repeats, "viewport")
    camera_bursts(app, viewport, args.repeats, "previous", previous_path(viewport))

    renders = {}
    for name, matcap in (("matcap", "clay"), ("studio", None)):
        use_matcap(viewport.mesh_actor, matcap)
        samples = []
        for _ in range(args.repeats):
            viewport.render_now()
            samples.append(viewport.last_frame_ms / 1e3)
        renders[name] = median_ms(samples)
    print(f"one render: matcap {renders['matcap']}; studio lights {renders['studio']}")

    hit = viewport.pick(QPointF(500, 400))
    center = hit[0] if hit is not None else vertices[0]
    size = float(np.linalg.norm(np.ptp(vertices, axis=0)))
    distance = np.linalg.norm(vertices - center, axis=1)
    nearest = np.argsort(distance, kind="stable")
    current = viewport.shown_vertices()
    for cavity in (False, True):
        viewport.set_cavity(cavity)
        for count in (1_000, 100_000):
            inside = np.sort(nearest[:count])
            reach = distance[nearest[count - 1]]
            samples = []
            for k in range(args.repeats * 3):
                shift = 1e-3 * size * (1 + k % 2) * np.exp(-((distance[inside] / reach) ** 2))
                current[inside, 1] += shift
                start = time.perf_counter()
                viewport.update_vertices(current, inside)
                samples.append(time.perf_counter() - start)
                current[inside, 1] -= shift
            state = "on " if cavity else "off"
            print(f"update_vertices, cavity {state}, {count:>7,} moved: {median_ms(samples)}")
    viewport.close()


if __name__ == "__main__":
    main()
