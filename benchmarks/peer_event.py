"""A grab event against its isotropic peer, and how soon a new machine sculpts (issue 23).

    python benchmarks/peer_event.py [--repeats 15] [--meshes DIR] [--no-cold] [--no-app]

Prints, in one run (figures only, no assertions):

* the grab event on the 1M-vertex ogre (``../shared/meshes/ogre.obj`` subdivided twice, 992,608
  vertices; skipped with the reason when the file is absent) through the Sculptor: cubic
  material, l_max 8, radius 0.05, cursor motion 1% of the model size, compiled code (everything
  the app waits for: kernel, force, influence ball, adaptive streamlines, write-back);
* its peer on the same moved vertices in the same run: Blender's Elastic Deform math, one RK4
  step of the closed-form regularized Kelvinlet (de Goes & James 2017) of the same moving
  load (4 evaluations a vertex), numba, parallel over the vertices, read and written in place
  like the mesh rows of the event; event and peer alternate, so that the load of the shared
  cores falls on both; medians, minima and the ratio of the medians; and the same peer on every
  vertex, as Blender's Elastic Deform runs it (it gathers all nodes: its Kelvinlet has no cutoff);
* the event's influence ball (which vertices it may move): answered by the vertex blocks
  (``gogreen_core.mesh.influence``) against the plain pass over every vertex it replaced, the
  blocks' build (the first query on a new vertex array) and their upkeep after the event (the
  report of its moved rows (the answer itself; the same rows in another array take a pass over
  them), and the refit of their blocks' boxes at the next query);
* where the event's CPU time goes: the streamlines' passes (the probes, the first pass, the
  refinement; a write-back where the ends are not written as made), the influence ball and
  the rest; the moved vertices by distance to the brush centre in ε (the field's far field
  starts beyond the cutoff, at 4 ε) and how many velocity evaluations they took;
* one velocity evaluation's parts on the ball's vertices (one thread, CPU ns a point, each part
  timed with those before it): the geometry (offsets, r, direction, table variable, cutoff),
  the lowest degree's float64 table, the float32 tables of the degrees above it, their angular
  sum (the generated kernel) and the rest of the velocity (the weighted combination);
* the event's accuracy: max vertex error against 64 RK4 substeps over the cursor motion, its
  velocity evaluations a vertex (third-order steps take 3, RK4 steps 4, the probes that choose
  between them 15 each);
* the first grab event in a fresh process with an empty numba cache (NUMBA_CACHE_DIR a new
  temporary directory; numba would also use ``__pycache__`` beside the sources, which this
  overrides): imports, default model (40,962 vertices), one event, and how long the compiled
  code then takes to be ready in the background;
* the app on an empty cache (needs a display, e.g. under xvfb-run): process start → window
  shown, and window shown → first stroke accepted (a press, a move, a release posted to the
  viewport until the mesh changes).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numba
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from gogreen_core import Brush, BrushEvent, Material, Sculptor  # noqa: E402
from gogreen_core.field import _evaluation, _integrator, _stream  # noqa: E402
from gogreen_core.field._evaluation import near_segment  # noqa: E402
from gogreen_core.field._expansion import BLOCK, _radial  # noqa: E402
from gogreen_core.field._stream import probe_rows  # noqa: E402
from gogreen_core.field.kernel import prepare_degree  # noqa: E402
from gogreen_core.mesh.influence import VertexBlocks, plain_rows_near  # noqa: E402
from gogreen_core.sculpt.brushes import mirror_signs  # noqa: E402

MATERIAL = Material.cubic(3.0, 1.5, 0.4)
L_MAX = 8
RADIUS = 0.05
MOTION = 0.01  # of the model size


@numba.njit(parallel=True, cache=True, fastmath={"contract"}, error_model="numpy")
def kelvinlet_rk4(points, rows, center, step, force, eps, a, b):  # pragma: no cover - compiled
    """One classical RK4 step over t ∈ [0, 1] of the regularized Kelvinlet of a load moving
    from ``center`` by ``step``: v = [(a-b)/r_ε + aε²/(2r_ε³)] f + b (r·f)/r_ε³ r, r = x - c(t),
    r_ε = √(r² + ε²) (de Goes & James 2017, Blender's Elastic Deform brush), for the mesh rows
    ``rows`` of ``points``, in place. One vertex per iteration, as Blender's brush loop."""
    e2 = eps * eps
    for n in numba.prange(rows.shape[0]):
        row = rows[n]
        x0, y0, z0 = points[row, 0], points[row, 1], points[row, 2]
        ex, ey, ez = x0, y0, z0
        vx = vy = vz = 0.0
        for stage in range(4):
            h = 0.0 if stage == 0 else (1.0 if stage == 3 else 0.5)
            dx = x0 + h * vx - (center[0] + h * step[0])
            dy = y0 + h * vy - (center[1] + h * step[1])
            dz = z0 + h * vz - (center[2] + h * step[2])
            inv = 1.0 / math.sqrt(dx * dx + dy * dy + dz * dz + e2)
            inv3 = inv * inv * inv
            diagonal = (a - b) * inv + 0.5 * a * e2 * inv3
            along = b * inv3 * (dx * force[0] + dy * force[1] + dz * force[2])
            vx = diagonal * force[0] + along * dx
            vy = diagonal * force[1] + along * dy
            vz = diagonal * force[2] + along * dz
            weight = (1.0 if stage == 0 or stage == 3 else 2.0) / 6.0
            ex += weight * vx
            ey += weight * vy
            ez += weight * vz
        points[row, 0] = ex
        points[row, 1] = ey
        points[row, 2] = ez


@numba.njit(cache=True)
def velocity_parts(part, start, field, repeats):  # pragma: no cover - compiled
    """``_integrator._single_velocity`` on the points ``start`` (3, n), block by block, up to
    its ``part`` (0: the copy alone, 1 + geometry, 2 + lowest degree's table, 3 + float32
    tables, 4 + angular sum, 5 the whole velocity instead)."""
    scratch, _ = _integrator._scratch(field.tables32.shape[1])
    geo, seg, rad, geo32, rad32, _, total32 = scratch
    pos, vel = np.empty((3, BLOCK)), np.empty((3, BLOCK))
    check = 0.0
    for _ in range(repeats):
        for b in range(start.shape[1] // BLOCK):
            pos[:, :] = start[:, b * BLOCK : (b + 1) * BLOCK]
            if part == 5:
                _integrator._single_velocity(pos, BLOCK, 0.5, field, scratch, vel)
                check += vel[0, 0]
                continue
            if part >= 1:
                _integrator._single_geometry(pos, 0, BLOCK, 0.5, field, scratch)
            if part >= 2:
                _radial(field.tables, field.l_first, BLOCK, geo, seg, rad)
            if part >= 3:
                _integrator._single_radial(field.tables32, BLOCK, seg, geo32[4], rad32)
            if part >= 4:
                coeffs32 = field.coeffs32
                field.angular32(BLOCK, geo32.ctypes, rad32.ctypes, coeffs32.ctypes, total32.ctypes)
            check += pos[0, 0] + geo[3, 0] + rad[0, 0] + rad32[0, 0] + total32[0, 0]
    return check


def evaluation_parts(kernel: Any, points: np.ndarray, center: np.ndarray, delta: np.ndarray,
                     load: np.ndarray, cutoff: tuple[float, float]) -> None:  # fmt: skip
    """Print one velocity evaluation's parts (``velocity_parts``), CPU ns a point, minima."""
    parity, tables, single, coeffs = kernel._loaded(load, (3,))
    field, _ = _evaluation.stream_field(
        parity, tables, single, kernel.eps, coeffs, center, delta, cutoff, np.ones((1, 3)),
        np.zeros(3),
    )  # fmt: skip
    if not field.unrolled32:
        print("  (evaluation's parts: the generated angular kernel is not ready; skipped)")
        return
    n = len(points) // BLOCK * BLOCK
    start = np.ascontiguousarray(points[:n].T)
    cumulative = []
    for part in range(6):
        velocity_parts(part, start[:, :BLOCK], field, 1)
        best = math.inf
        for _ in range(5):
            begin = time.process_time()
            velocity_parts(part, start, field, 2)
            best = min(best, time.process_time() - begin)
        cumulative.append(1e9 * best / (2 * n))
    names = ("geometry", "lowest degree's table", "float32 tables", "angular sum")
    parts = [f"{name} {cumulative[k + 1] - cumulative[k]:.2f}" for k, name in enumerate(names)]
    rest = cumulative[5] - cumulative[4]
    print(f"  one evaluation, CPU ns a point (one thread): {cumulative[5] - cumulative[0]:.2f} "
          f"= {', '.join(parts)}, the rest {rest:.2f}")  # fmt: skip


def ogre(meshes: Path) -> tuple[np.ndarray, np.ndarray] | None:
    """The shared ogre subdivided twice (992,608 vertices), or None if it is not there."""
    path = meshes / "ogre.obj"
    if not path.is_file():
        return None
    import trimesh

    mesh = trimesh.load(path, process=False)
    vertices, faces = np.array(mesh.vertices), np.array(mesh.faces)
    for _ in range(2):
        vertices, faces = trimesh.remesh.subdivide(vertices, faces)
    return vertices, faces


def median_ms(samples: list[float]) -> str:
    return f"{1e3 * statistics.median(samples):7.2f} ms (min {1e3 * min(samples):.2f})"


def event_split(sculptor: Sculptor, brush: Brush, event: BrushEvent, repeats: int) -> None:
    """Median CPU time of the event's parts: each pass of the streamlines (timed around
    ``_stream.run_ranges``), the influence ball (``MeshState.rows_near``) and the rest."""
    passes = {0: "probes", 1: "first pass", 2: "refinement"}
    run_ranges, rows_near = _stream.run_ranges, type(sculptor._mesh).rows_near
    times: dict[str, list[float]] = {}

    def timed(name: str, call: Callable[..., Any], *args: Any) -> Any:
        start = time.process_time()
        result = call(*args)
        times.setdefault(name, []).append(time.process_time() - start)
        return result

    def ranges(work: Any, n: int, least: int) -> None:
        name = passes[work.args[0]] if work.func is _stream._pass else "write-back"
        timed(name, run_ranges, work, n, least)

    _stream.run_ranges = ranges
    type(sculptor._mesh).rows_near = lambda *a: timed("influence ball", rows_near, *a)
    try:
        for _ in range(repeats):
            sculptor.begin_stroke(brush)
            timed("event", sculptor.stroke_event, event)
            sculptor.end_stroke()
            sculptor.undo()
    finally:
        _stream.run_ranges, type(sculptor._mesh).rows_near = run_ranges, rows_near
    median = {name: 1e3 * statistics.median(v) * len(v) / repeats for name, v in times.items()}
    rest = 2 * median["event"] - sum(median.values())
    parts = ", ".join(f"{name} {ms:.2f}" for name, ms in median.items() if name != "event")
    print(f"  event's CPU time (ms, medians): {median['event']:.2f} = {parts}, rest {rest:.2f}")


def influence_ball(
    sculptor: Sculptor, center: np.ndarray, delta: np.ndarray, radius: float, repeats: int
) -> None:
    """The event's influence test by the vertex blocks and by the plain pass (medians), the
    blocks' build and their upkeep for the event's moved rows."""
    mesh, signs = sculptor._mesh, mirror_signs("")
    args = (center, delta, radius, signs)
    start = time.perf_counter()
    VertexBlocks().rows_near(mesh.vertices, *args, mesh.origin)  # a build, then the answer
    first = time.perf_counter() - start
    rows = mesh.rows_near(*args)
    blocks, plain, report, report_rows, refit = [], [], [], [], []
    for _ in range(repeats):
        start = time.perf_counter()
        answer = mesh.rows_near(*args)
        blocks.append(time.perf_counter() - start)
        start = time.perf_counter()
        plain_rows_near(mesh.vertices, *args, mesh.origin, True)
        plain.append(time.perf_counter() - start)
        start = time.perf_counter()
        mesh.moved(answer)  # what the event's write reports: the answer itself (its blocks)
        report.append(time.perf_counter() - start)
        start = time.perf_counter()
        mesh.moved(rows)  # another array of the same rows: a pass over them
        report_rows.append(time.perf_counter() - start)
        start = time.perf_counter()
        mesh.rows_near(*args)  # refits the moved rows' blocks first
        refit.append(time.perf_counter() - start - blocks[-1])
    answers = mesh._blocks.answers
    print(f"influence ball, 1M vertices: {statistics.median(blocks) * 1e3:.2f} ms "
          f"(was {statistics.median(plain) * 1e3:.2f} ms brute force)")  # fmt: skip
    print(f"  by the vertex blocks ({len(rows):,} rows; {answers['plain']} plain answers): "
          f"{median_ms(blocks)}")  # fmt: skip
    print(f"  plain pass over every vertex + flatnonzero:  {median_ms(plain)}")
    print(f"  first query on a new vertex array (build):   {1e3 * first:7.2f} ms")
    print(f"  report of the event's {len(rows):,} moved rows:  {median_ms(report)}")
    print(f"  the same rows in another array (a row pass):  {median_ms(report_rows)}")
    print(f"  refit of their blocks at the next query:     {median_ms(refit)}")


def peer_event(vertices: np.ndarray, faces: np.ndarray, repeats: int) -> None:
    prepare_degree(L_MAX)  # the compiled code (a fresh machine gets it in the background)
    sculptor = Sculptor(vertices, faces, material=MATERIAL, l_max=L_MAX)
    center = vertices[int(np.argmax(vertices @ [0.2, 1.0, 0.3]))].copy()
    brush = Brush("grab", radius=RADIUS, influence=4.0)  # the peer's ball (504,347 rows)
    delta = MOTION * sculptor.model_size * np.array([0.3, 0.8, 0.5])
    cutoff = brush.cutoff(sculptor.model_size)
    reach = np.empty(len(vertices), dtype=bool)
    near_segment(vertices, center, delta, cutoff[1], mirror_signs(""), sculptor.origin, reach)
    rows = np.flatnonzero(reach)
    # the peer's load: the Kelvinlet whose centre follows the cursor, G(0) f = Δ with
    # G(0) = (3a/2 - b)/ε I, for an isotropic material of the same scale (μ = 1, ν = 0.3)
    eps = sculptor.kernel(brush).eps
    a = 1.0 / (4.0 * math.pi)
    b = a / (4.0 * (1.0 - 0.3))
    force = delta * eps / (1.5 * a - b)
    work = vertices.copy()
    kelvinlet_rk4(work, rows, center, delta, force, eps, a, b)  # compile / load
    # Blender's Elastic Deform gathers every PBVH node (SCULPT_tool_needs_all_pbvh_nodes: the
    # Kelvinlet has no cutoff), so the brush itself evaluates every vertex: a second figure
    every_row = np.arange(len(vertices))
    events, events_cpu, peers, peers_cpu, blender_cpu = [], [], [], [], []
    after = None
    for _ in range(repeats):
        sculptor.begin_stroke(brush)
        start, start_cpu = time.perf_counter(), time.process_time()
        sculptor.stroke_event(BrushEvent(center, delta))
        events.append(time.perf_counter() - start)
        events_cpu.append(time.process_time() - start_cpu)
        after = sculptor.vertices.copy()
        sculptor.end_stroke()
        sculptor.undo()
        work[rows] = vertices[rows]
        start, start_cpu = time.perf_counter(), time.process_time()
        kelvinlet_rk4(work, rows, center, delta, force, eps, a, b)
        peers.append(time.perf_counter() - start)
        peers_cpu.append(time.process_time() - start_cpu)
        work[:] = vertices
        start_cpu = time.process_time()
        kelvinlet_rk4(work, every_row, center, delta, force, eps, a, b)
        blender_cpu.append(time.process_time() - start_cpu)
    kernel = sculptor.kernel(brush)
    g0 = kernel.green(np.zeros((1, 3)))[0]
    reference = vertices.copy()
    reference[rows] = kernel.streamlines(
        vertices[rows], center, np.linalg.solve(g0, delta), center_step=delta, cutoff=cutoff,
        substeps=64, tolerance=None,
    )  # fmt: skip
    error = np.linalg.norm(after - reference, axis=1).max() / np.linalg.norm(delta)
    evaluations = np.empty(len(rows), dtype=np.int64)
    kernel.streamlines(
        vertices[rows], center, np.linalg.solve(g0, delta), center_step=delta, cutoff=cutoff,
        evaluations=evaluations,
    )  # fmt: skip
    probes = 15 * len(probe_rows(len(rows)))
    # where the event's time goes: one fixed RK4 step on the ball's rows (the influence ball
    # itself: ``influence_ball`` below)
    passes, passes_cpu = [], []
    signs, origin = mirror_signs(""), sculptor.origin
    load = np.linalg.solve(g0, delta)
    for _ in range(repeats):
        start, start_cpu = time.perf_counter(), time.process_time()
        kernel.streamlines(
            vertices, center, load, center_step=delta, cutoff=cutoff, substeps=1, tolerance=None,
            indices=rows, mirror_signs=signs, origin=origin,
        )  # fmt: skip
        passes.append(time.perf_counter() - start)
        passes_cpu.append(time.process_time() - start_cpu)
    ratio = statistics.median(events) / statistics.median(peers)
    ratio_cpu = statistics.median(events_cpu) / statistics.median(peers_cpu)
    print(f"grab event, {len(rows):,} vertices moved ({numba.get_num_threads()} threads):")
    print(f"  event through the Sculptor (wall):           {median_ms(events)}")
    print(f"  event, CPU time of all threads:              {median_ms(events_cpu)}")
    print(f"  Kelvinlet RK4 peer on the same vertices:     {median_ms(peers)}")
    print(f"  peer, CPU time of all threads:               {median_ms(peers_cpu)}")
    print(f"  ratio event / peer (medians, wall):          {ratio:7.2f}x")
    print(f"  ratio event / peer (medians, CPU time):      {ratio_cpu:7.2f}x")
    blender = statistics.median(events_cpu) / statistics.median(blender_cpu)
    print(f"  the peer as Blender's brush runs it, on all {len(vertices):,} vertices (CPU): "
          f"{median_ms(blender_cpu)}; event / that: {blender:.2f}x")  # fmt: skip
    own = float(evaluations.mean())
    print(f"  evaluations a vertex (its own + the probes'): {own:.3f} + {probes / len(rows):.3f}")
    counts = ", ".join(f"{n}: {c:,}" for n, c in enumerate(np.bincount(evaluations)) if c)
    print(f"  vertices by their own evaluations:           {counts}")
    rho = np.linalg.norm(vertices[rows] - center, axis=1) / eps
    counted = np.histogram(rho, bins=[0, 1, 2, 3, 4, np.inf])[0]
    names = ("<1", "1-2", "2-3", "3-4", ">4")
    shells = ", ".join(f"{b}: {c:,}" for b, c in zip(names, counted, strict=True))
    print(f"  vertices by distance to the centre (in ε):   {shells}")
    event_split(sculptor, brush, BrushEvent(center, delta), repeats)
    print(f"  one fixed RK4 step on the ball's rows:       {median_ms(passes)}")
    n_evaluations = 4 * len(rows)
    ns_event = 1e9 * statistics.median(passes_cpu) / n_evaluations
    ns_peer = 1e9 * statistics.median(peers_cpu) / n_evaluations
    print(f"  CPU a field evaluation, expansion / Kelvinlet: {ns_event:5.1f} / {ns_peer:.1f} ns")
    evaluation_parts(kernel, vertices[rows] - center, np.zeros(3), delta, load, cutoff)
    print(f"  max error vs 64 RK4 substeps / cursor motion: {error:.2e}")
    influence_ball(sculptor, center, delta, cutoff[1], repeats)


FIRST_EVENT = r"""
import time
start = time.perf_counter()
import numpy as np
from gogreen_core import Brush, BrushEvent, Material, Sculptor
from gogreen_core import _compiled
from gogreen_core.field import _drivers
from gogreen_core.mesh.shapes import default_model
vertices, faces = default_model()
sculptor = Sculptor(vertices, faces, material=Material.cubic(3.0, 1.5, 0.4))
top = vertices[int(np.argmax(vertices[:, 2]))]
sculptor.apply_brush(Brush("grab"), [BrushEvent(top, [0.0, 0.01, 0.0])])
first = time.perf_counter() - start
_compiled.wait(_drivers.units_for(8))  # the background compilation's end
print(first, time.perf_counter() - start)
"""


def cold_first_event() -> tuple[float, float]:
    """(seconds to the end of the first grab event, seconds until the compiled code was
    ready) in a fresh process with an empty numba cache, imports included."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        result = subprocess.run(
            [sys.executable, "-c", FIRST_EVENT], env=env, capture_output=True, text=True,
            check=True, cwd=ROOT,
        )  # fmt: skip
    first, ready = (float(v) for v in result.stdout.split()[-2:])
    return first, ready


FIRST_STROKE = r"""
import json, sys, tempfile, time
from pathlib import Path
start = time.perf_counter()
from PySide6.QtCore import QEvent, QPointF, QSettings, Qt
from PySide6.QtGui import QMouseEvent
from PySide6.QtWidgets import QApplication
app = QApplication(sys.argv[:1])
from app.main_window import MainWindow
settings = QSettings(str(Path(tempfile.mkdtemp()) / "s.ini"), QSettings.Format.IniFormat)
window = MainWindow(settings)
window.show()
app.processEvents()
shown = time.perf_counter()
window.files.open_default()  # as `gogreen` does, before the event loop runs
vp = window.viewport
left, none = Qt.MouseButton.LeftButton, Qt.MouseButton.NoButton


def post(kind, pos, button, buttons):
    event = QMouseEvent(kind, pos, vp.mapToGlobal(pos), button, buttons,
                        Qt.KeyboardModifier.NoModifier)
    QApplication.postEvent(vp, event)


before = window.document.sculptor.vertices.copy()
accepted = None
while accepted is None and time.perf_counter() - shown < 300:
    app.processEvents()
    pos = QPointF(0.5 * vp.width(), 0.5 * vp.height())
    post(QEvent.Type.MouseButtonPress, pos, left, left)
    post(QEvent.Type.MouseMove, pos + QPointF(12, -9), none, left)
    post(QEvent.Type.MouseButtonRelease, pos + QPointF(12, -9), left, none)
    for _ in range(3):
        app.processEvents()
    if (window.document.sculptor.vertices != before).any():
        accepted = time.perf_counter()
    else:
        time.sleep(0.02)
print(json.dumps(dict(window=shown - start, stroke=(accepted or float("nan")) - shown,
                      message=window.message_label.text())))
window.document._saved_vertices = window.document.sculptor.vertices.copy()
window.close()
"""


def cold_app() -> dict:
    """Process start → window shown and window shown → first accepted stroke, empty cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        result = subprocess.run(
            [sys.executable, "-c", FIRST_STROKE], env=env, capture_output=True, text=True,
            check=True, cwd=ROOT,
        )  # fmt: skip
    return json.loads(result.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=15)
    parser.add_argument("--meshes", type=Path, default=ROOT.parent / "shared" / "meshes")
    parser.add_argument("--no-cold", action="store_true", help="skip the empty-cache runs")
    parser.add_argument("--no-app", action="store_true", help="skip the app's first stroke")
    args = parser.parse_args()
    print(f"load average at start: {os.getloadavg()[0]:.2f} (2 cores, shared)")
    mesh = ogre(args.meshes)
    if mesh is None:
        print(f"grab event on the 1M-vertex ogre: skipped ({args.meshes / 'ogre.obj'} not found)")
    else:
        peer_event(*mesh, args.repeats)
    if not args.no_cold:
        first, ready = cold_first_event()
        print("first grab event, fresh process, empty numba cache, imports included:")
        print(f"  default model, one event:                    {first:7.2f} s")
        print(f"  compiled code ready in the background after: {ready:7.2f} s")
    if not args.no_app and not args.no_cold:
        if not (os.environ.get("DISPLAY") or os.environ.get("QT_QPA_PLATFORM")):
            print("app on an empty cache: skipped (no display: run under xvfb-run)")
        else:
            app = cold_app()
            print("app, empty numba cache:")
            print(f"  process start -> window shown:              {app['window']:7.2f} s")
            print(f"  window shown -> first stroke accepted:      {app['stroke']:7.2f} s")
    print(f"load average at end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
