"""Benchmark of sculpting at scale: a million-vertex mesh (issue "Sculpting at scale").

    python benchmarks/scale.py [--repeats 7] [--meshes /path/to/meshes] [--cold-compile]

The mesh is the ogre of ``../shared/meshes`` (relative to the checkout) subdivided twice
(992,608 vertices) when it is there, else a procedural UV sphere of about the same size. Prints
medians of: one grab event (cubic material, l_max 8, cursor motion 1% of the model size) at
radius 0.05 and 0.2 through the Sculptor (everything the app waits for: kernel, force,
influence ball, adaptive streamlines, scatter), its accuracy against 64 fixed RK4 substeps,
loading the 1M-vertex OBJ with ``load_mesh`` and with ``trimesh.load`` (same run), saving it
as OBJ, and the viewport-side core costs: incremental normals for the event's vertices and
picking the surface point under the mouse. The first grab event's time includes loading the
compiled numba code from its cache; ``--cold-compile`` also times it in a fresh process with an
empty cache (the first run on a new machine). Figures only, no assertions.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

from gogreen_core import Brush, BrushEvent, Material, Sculptor, _compiled
from gogreen_core.field._evaluation import near_segment
from gogreen_core.field.kernel import prepare_degree
from gogreen_core.mesh.geometry import SurfaceIndex, vertex_normals
from gogreen_core.mesh.mesh_io import MeshData, load_mesh, save_mesh
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.brushes import mirror_signs
from gogreen_core.threads import threads_at_most

MATERIAL = Material.cubic(3.0, 1.5, 0.4)
L_MAX = 8
#: The influence ball (in ε) the figures are taken with: the 4 ε of every earlier run (the
#: automatic default is measured by benchmarks/influence_cost.py).
INFLUENCE = 4.0
FIRST_EVENT = """
import time
start = time.perf_counter()
import numpy as np
from gogreen_core import Brush, BrushEvent, Material, Sculptor, _compiled
from gogreen_core.mesh.shapes import icosphere
vertices, faces = icosphere(2)
sculptor = Sculptor(vertices, faces, material=Material.cubic(3.0, 1.5, 0.4))
sculptor.apply_brush(Brush("grab"), [BrushEvent(vertices[0], [0.0, 0.01, 0.0])])
print(time.perf_counter() - start)
"""


def cold_first_event() -> float:
    """Seconds of the first grab event (imports included) in a fresh process whose numba
    cache directory is empty, so everything it runs is compiled."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        result = subprocess.run(
            [sys.executable, "-c", FIRST_EVENT], env=env, capture_output=True, text=True, check=True
        )
    return float(result.stdout.split()[-1])


def million_vertex_mesh(meshes: Path) -> tuple[np.ndarray, np.ndarray, str]:
    ogre = meshes / "ogre.obj"
    if ogre.exists():
        mesh = trimesh.load(ogre, process=False)
        vertices, faces = np.array(mesh.vertices), np.array(mesh.faces)
        for _ in range(2):
            vertices, faces = trimesh.remesh.subdivide(vertices, faces)
        return vertices, faces, "ogre subdivided twice"
    sphere = trimesh.creation.uv_sphere(radius=1.0, count=[705, 1408])
    return np.array(sphere.vertices), np.array(sphere.faces), "procedural UV sphere"


def median_ms(samples: list[float]) -> str:
    """Median and min of ``samples`` (seconds) in ms."""
    return f"{1e3 * statistics.median(samples):8.1f} ms (min {1e3 * min(samples):.1f})"


def grab_event(sculptor: Sculptor, radius: float, center: np.ndarray, repeats: int):
    """Seconds of each grab event (wall, CPU of all threads, and the streamlines alone, also
    on one thread), how many vertices it could reach, its max error against 64 fixed RK4
    substeps relative to the cursor motion, and the vertices after it."""
    brush = Brush("grab", radius=radius, influence=INFLUENCE)
    delta = 0.01 * sculptor.model_size * np.array([0.3, 0.8, 0.5])
    before = sculptor.vertices.copy()
    samples, cpu, after = [], [], None
    for _ in range(repeats):
        sculptor.begin_stroke(brush)
        start, start_cpu = time.perf_counter(), time.process_time()
        sculptor.stroke_event(BrushEvent(center, delta))
        samples.append(time.perf_counter() - start)
        cpu.append(time.process_time() - start_cpu)
        after = sculptor.vertices.copy()
        sculptor.end_stroke()
        sculptor.undo()
    # the reference: the same event with 64 fixed RK4 substeps for every vertex it can reach
    kernel = sculptor.kernel(brush)
    force = np.linalg.solve(kernel.green(np.zeros((1, 3)))[0], delta)
    cutoff = brush.cutoff(sculptor.model_size)
    if cutoff is None:
        active = np.arange(len(before))
    else:
        reach = np.empty(len(before), dtype=bool)
        near_segment(before, center, delta, cutoff[1], mirror_signs(""), sculptor.origin, reach)
        active = np.flatnonzero(reach)
    points = before[active]
    stream, stream_cpu, fixed, fixed_cpu = [], [], [], []
    for _ in range(repeats):
        # the adaptive streamlines and, interleaved, the former 4 fixed RK4 substeps
        for tolerance, wall, cpu_ in ((1e-4, stream, stream_cpu), (None, fixed, fixed_cpu)):
            start, start_cpu = time.perf_counter(), time.process_time()
            kernel.streamlines(
                points, center, force, center_step=delta, cutoff=cutoff, tolerance=tolerance
            )
            wall.append(time.perf_counter() - start)
            cpu_.append(time.process_time() - start_cpu)
    # the same adaptive streamlines on one thread: CPU time that the other developers' load on
    # the shared cores disturbs least
    single = []
    with threads_at_most(1):
        for _ in range(repeats):
            start_cpu = time.process_time()
            kernel.streamlines(points, center, force, center_step=delta, cutoff=cutoff)
            single.append(time.process_time() - start_cpu)
    reference = before.copy()
    reference[active] = kernel.streamlines(
        before[active], center, force, center_step=delta, cutoff=cutoff, substeps=64,
        tolerance=None,
    )  # fmt: skip
    error = np.linalg.norm(after - reference, axis=1).max() / np.linalg.norm(delta)
    times = (samples, cpu, stream, stream_cpu, single, fixed, fixed_cpu)
    return times, len(active), error, after


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--cold-compile", action="store_true", help="also time a cold compile")
    parser.add_argument(
        "--meshes", default=str(Path(__file__).resolve().parents[2] / "shared/meshes")
    )
    args = parser.parse_args()

    start = time.perf_counter()
    sphere = trimesh.creation.icosphere(subdivisions=2)
    probe = Sculptor(np.array(sphere.vertices), np.array(sphere.faces), material=MATERIAL)
    probe.apply_brush(Brush("grab"), [BrushEvent(sphere.vertices[0], [0.0, 0.01, 0.0])])
    first = time.perf_counter() - start
    print(f"first grab event incl. numba cache load:        {1e3 * first:8.0f} ms")
    # the compiled code (on a new machine the first events run in NumPy while a child process
    # compiles it; peer_event.py times that)
    prepare_degree(L_MAX)
    _compiled.prepare(_compiled.GEOMETRY)
    if args.cold_compile:
        cold = cold_first_event()
        print(f"first grab event, empty numba cache (compile):  {1e3 * cold:8.0f} ms")

    vertices, faces, name = million_vertex_mesh(Path(args.meshes))
    print(f"mesh: {name}, {len(vertices):,} vertices, {len(faces):,} faces\n")

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "big.obj"
        saves, ours, theirs = [], [], []
        for _ in range(max(3, args.repeats // 2)):
            t0 = time.perf_counter()
            save_mesh(MeshData(vertices, faces), path)
            saves.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            loaded = load_mesh(path)
            ours.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            trimesh.load(path, process=False)
            theirs.append(time.perf_counter() - t0)
        same = np.array_equal(loaded.vertices, vertices)
        print(f"save OBJ (save_mesh):                           {median_ms(saves)}")
        print(f"load OBJ (load_mesh):                           {median_ms(ours)}")
        print(f"load OBJ (trimesh.load, same run):              {median_ms(theirs)}")
        ratio = statistics.median(ours) / statistics.median(theirs)
        print(f"load_mesh / trimesh.load:                       {ratio:8.2f}x "
              f"(vertices bit-identical: {same})")  # fmt: skip

    sculptor = Sculptor(vertices, faces, material=MATERIAL, l_max=L_MAX)
    center = vertices[int(np.argmax(vertices @ [0.2, 1.0, 0.3]))].copy()
    print()
    events = {}
    for radius in (0.05, 0.2):
        times, affected, error, after = grab_event(sculptor, radius, center, args.repeats)
        events[radius] = after
        samples, cpu, stream, stream_cpu, single, fixed, fixed_cpu = times
        print(f"grab event r={radius:<4} ({affected:>9,} vertices in ball): {median_ms(samples)}")
        print(f"  CPU time of all threads (the 2 cores are shared): {median_ms(cpu)}")
        print(f"  adaptive streamlines alone, wall:                 {median_ms(stream)}")
        print(f"  adaptive streamlines alone, CPU:                  {median_ms(stream_cpu)}")
        print(f"  adaptive streamlines alone, one thread, CPU:      {median_ms(single)}")
        print(f"  4 fixed RK4 substeps (former default), wall:      {median_ms(fixed)}")
        print(f"  4 fixed RK4 substeps (former default), CPU:       {median_ms(fixed_cpu)}")
        print(f"  max vertex error vs 64 RK4 substeps / cursor motion: {error:.2e}")

    # viewport-side core costs for the radius-0.05 event: normals of the moved vertices and
    # their one-ring (adjacency built once per mesh), and the pick under the mouse
    after = events[0.05]
    changed = np.flatnonzero(np.any(after != vertices, axis=1))
    small, small_faces = icosphere(2)  # load the compiled code first: not part of the build
    warm = SurfaceIndex(small, small_faces)
    warm.update(small, np.arange(3))
    warm.pick(np.array([0.0, 0.0, 3.0]), np.array([0.0, 0.0, -1.0]))
    builds = []
    for _ in range(3):
        t0 = time.perf_counter()
        index = SurfaceIndex(vertices, faces)
        builds.append(time.perf_counter() - t0)
    t0 = time.perf_counter()
    full = vertex_normals(after, faces)
    full_time = time.perf_counter() - t0
    updates, updates_cpu, refits = [], [], []
    low, high = after.min(axis=0), after.max(axis=0)
    ray = (high + 0.1 * (high - low), low - high)
    for _ in range(args.repeats):
        # the event, then its undo: every timed update moves the same 504k vertices
        for state in (after, vertices):
            t0, c0 = time.perf_counter(), time.process_time()
            updated = index.update(state, changed)
            if state is after:
                updates.append(time.perf_counter() - t0)
                updates_cpu.append(time.process_time() - c0)
        t0 = time.perf_counter()
        index.pick(*ray)  # refits the boxes the two updates left stale
        refits.append(time.perf_counter() - t0)
    index.update(after, changed)
    shown = index.normals[index.rank]
    fresh = SurfaceIndex(after, faces)  # the same code over the whole moved mesh
    exact = np.array_equal(shown, fresh.normals[fresh.rank])
    off = np.abs(shown - full).max()  # float32 face normals
    print(f"\nsurface index build (once per mesh):            {median_ms(builds)}")
    print(f"all vertex normals (full recompute, numpy):     {1e3 * full_time:8.1f} ms")
    print(
        f"per-event update: normals of {len(changed):,} moved vertices + one-ring "
        f"({updated:,}): {median_ms(updates)}"
    )
    print(f"  bit-equal to a new index of the moved mesh: {exact}; max |Δ| vs numpy: {off:.1e}")
    print(f"  CPU time of all threads:                      {median_ms(updates_cpu)}")
    print(f"first pick after an event and its undo (refits their leaf boxes): {median_ms(refits)}")
    rng = np.random.default_rng(1)
    picks, hits = [], 0
    for _ in range(max(args.repeats, 20)):
        target = low + rng.random(3) * (high - low)
        origin = target + np.array([0.1, 0.2, 1.0]) * 2 * np.linalg.norm(high - low)
        t0 = time.perf_counter()
        hits += index.pick(origin, target - origin) is not None
        picks.append(time.perf_counter() - t0)
    print(f"pick (ray under the mouse, {hits}/{len(picks)} hit):            {median_ms(picks)}")


if __name__ == "__main__":
    main()
