"""Benchmark of dynamic topology and Mesh → Remesh (issue 34).

    .venv/bin/python benchmarks/dynamic_topology.py [--repeats 3] [--meshes DIR] [--no-million]

Prints medians of:
* the pull of the done-when tests on the default model (grab radius 0.03, 20 events of 0.02
  model sizes along the normal from the top vertex, cubic material) with fixed and with
  dynamic topology (``detail_size=None``): the whole stroke, its events, and what the mesh
  looks like after it (longest edge over the model's median edge, the spike's faces with all
  angles >= 20°, vertices);
* Mesh → Remesh of the default model to its surface's own edge lengths (no detail size: each
  vertex's mean edge), to its median edge length (a uniform remesh) and to twice it;
* with ``../shared/meshes/ogre.obj`` (relative to the checkout): the ogre subdivided twice
  (992,608 vertices): the split of one dynamic-topology step of a belly pull into its stages
  (:data:`STAGES`: selection, split, collapse, flip, relaxation, compaction, adoption, the
  stroke's bookkeeping, the brush); a long pull on its belly (the same brush, 10 events) with
  and without dynamic topology in events per second and the memory of its undo step, and a
  Remesh of it to its own edge lengths (two rounds). Skipped, with the reason, when the mesh is
  absent or with ``--no-million``; ``--million-events``, ``--no-million-remesh`` and
  ``--million-only`` shorten it.

Measured 2026-11-29 (2 cores shared with other jobs, load average 4-6; CPU times, medians;
"before" is main 7aac3d2, run interleaved with "after" in the same session):
* default model: the pull 3 ms an event fixed; dynamic 55-56 ms before, 34-35 ms after (stroke
  1.41-1.44 s -> 0.92 s), the same mesh (longest edge 1.73 x the median, spike faces >= 20 deg
  100 %, 41,512 vertices). Remesh to its own edges 1.94-1.97 s -> 1.30-1.34 s (40,950
  vertices, edges 0.85-1.23 x the median), to its median 2.74-2.78 s -> 1.56-1.67 s, to twice
  it 1.91-2.05 s -> 1.24 s.
* 1M-vertex ogre, 8 events: fixed 22-23.5 events/s (47-50 ms an event), undo step 48 MiB (the
  grab's far field moves every vertex); dynamic 0.70-0.76 events/s (1.30-1.40 s an event)
  before, 1.30-1.31 events/s (749-758 ms) after, 992,608 -> 1,000,297 vertices either way,
  undo step 55 MiB. One step (each remeshes a region of ~78k vertices, 156k faces: the
  strained faces and the brush's core), before -> after: selection 42 ms (strain 34: every
  face with a moved corner, and the grab moves every row; growing 8) -> the same; setup (the
  patch's rows and connectivity) 117-119 -> 56-59; split 203-215 -> 144-148; collapse 289-304
  -> 124-127; flip 195-203 -> 71-73; relaxation 237-257 -> 183-189; compaction of the arrays
  35-148 (page faults of two 2M-face temporaries) -> 26-28; the stroke's bookkeeping (marks,
  reference positions, origins) 93-96 -> 69-71; the whole step 1268-1285 -> 737-757; the brush
  50 either way. A stroke's first dynamic event also measures each vertex's edges: 0.62 s ->
  0.07 s.
* Remesh of the 1M-vertex ogre to its own edges (2 rounds): 48.8 s -> 29.0 s CPU, 1,042,626
  vertices either way. To its median edge (one length for edges spanning 0.005-0.097): 510 s
  before, 4,636,878 vertices, ~8 GB (not measured again).

``--textured-only``: dynamic-topology pulls (20 events, ``--million-events`` on the ogre, of
0.01 model sizes along the normal, grab radius 0.03) without and with texture corners: the
default model and the 1M-vertex ogre with :func:`two_charts` (two charts, a seam), Spot
subdivided twice (its own UVs and seams).
Measured 2026-11-29, load 3.8-5.6, two runs of each interleaved with main b7950e6, and the
final tree once more (load 2-3), event medians and the stroke's undo step (the final run's
bytes count an edit's new rows too, which main's count left out: +5 % on untextured steps):
* default model, textured: 57-60 ms an event before, 30-35 ms after (untextured 27-50 ms);
  undo step 9.42 MiB (whole snapshots) -> 3.86 MiB (untextured 2.87 MiB).
* Spot subdivided twice (46,850 vertices, 51,514 uv rows): 107 ms -> 80-97 ms (untextured
  75-84 ms); undo step 11.06 -> 6.42 MiB (3.96).
* the ogre subdivided twice (992,608 vertices, 1,001,040 uv rows), 5 events: 1,965-2,572 ms ->
  850-1,039 ms an event (untextured 733-785 ms: the rest is mostly the new uv and uv_faces
  arrays of each step, 16 + 48 MB); undo step 227.65 MiB -> 64.93 MiB (untextured 55.29 MiB:
  the grab's far field moves every vertex).

Times are CPU seconds of this process (``time.process_time``: the machine is shared, and the
engine's threads count too), medians. Figures only, no assertions.
"""

from __future__ import annotations

import argparse
import contextlib
import resource
import statistics
import time
from collections import defaultdict
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from gogreen_core import Brush, BrushEvent, Material, Sculptor
from gogreen_core.mesh import remesh as remesh_module
from gogreen_core.mesh.geometry import vertex_normals
from gogreen_core.mesh.mesh_io import load_mesh
from gogreen_core.mesh.mesh_state import MeshState
from gogreen_core.mesh.remesh import median_edge_length, smallest_angles
from gogreen_core.mesh.shapes import default_model
from gogreen_core.mesh.topology import mesh_edges
from gogreen_core.sculpt import stroke as stroke_module
from gogreen_core.sculpt.engine_settings import EngineSettings

CUBIC = Material.cubic(3.0, 1.5, 0.4)


def pull(
    sculptor: Sculptor, row: int, direction: np.ndarray, events: int, step: float
) -> list[float]:
    """A grab (radius 0.03) pulling vertex ``row`` along ``direction``; each event's seconds."""
    center = sculptor.vertices[row].copy()
    delta = step * sculptor.model_size * direction / np.linalg.norm(direction)
    times = []
    sculptor.begin_stroke(Brush("grab", radius=0.03))
    for _ in range(events):
        start = time.process_time()
        sculptor.stroke_event(BrushEvent(center=center, delta=delta))
        times.append(time.process_time() - start)
        center = center + delta
    sculptor.end_stroke()
    return times


def default_pull(repeats: int) -> None:
    vertices, faces = default_model()
    median = median_edge_length(vertices, faces)
    top = int(np.argmax(vertices[:, 2]))
    print(f"-- default model ({len(vertices):,} vertices), pull 0.4 model sizes in 20 events")
    for dynamic in (False, True):
        totals, events = [], []
        for _ in range(repeats):
            settings = EngineSettings(material=CUBIC, dynamic_topology=dynamic)
            sculptor = Sculptor(vertices, faces, settings=settings)
            times = pull(sculptor, top, np.array([0.0, 0.0, 1.0]), 20, 0.02)
            totals.append(sum(times))
            events.extend(times[1:])  # the first: kernels and compiled code loading
        pulled, cells = sculptor.vertices, sculptor.faces
        ends = mesh_edges(cells, len(pulled)).ends
        longest = np.linalg.norm(pulled[ends[:, 1]] - pulled[ends[:, 0]], axis=1).max()
        spike = pulled[cells].mean(axis=1)[:, 2] > vertices[:, 2].max() + 0.04 * sculptor.model_size
        good = np.mean(smallest_angles(pulled[cells[spike]]) >= 20.0)
        name = "dynamic" if dynamic else "fixed"
        print(
            f"{name:8s} stroke {statistics.median(totals):6.2f} s, event median "
            f"{1e3 * statistics.median(events):6.0f} ms (max {1e3 * max(events):5.0f}); "
            f"longest edge {longest / median:5.2f} x median, spike faces >= 20 deg "
            f"{100 * good:5.1f} %, {len(pulled):,} vertices"
        )


def two_charts(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Texture corners the benchmark makes (uv (T, 2), uv_faces (M, 3)): the faces whose centre
    lies beyond the median x take the chart (y, z), the others (y, z) shifted by 10 model sizes
    (a seam where they meet); each row used."""
    east = vertices[faces].mean(axis=1)[:, 0] > np.median(vertices[:, 0])
    rows, corners = np.unique(
        np.where(east[:, None], faces, faces + len(vertices)), return_inverse=True
    )
    size = float(np.linalg.norm(vertices.max(axis=0) - vertices.min(axis=0)))
    charts = np.concatenate([vertices[:, 1:], vertices[:, 1:] + [10.0 * size, 0.0]])
    return charts[rows], corners.reshape(-1, 3)


def textured_pulls(
    vertices: np.ndarray,
    faces: np.ndarray,
    corners: tuple[np.ndarray, np.ndarray],
    row: int,
    events: int,
    repeats: int,
) -> None:
    """A dynamic-topology pull from ``row`` along its normal (:func:`pull`, steps of 0.01 model
    sizes) on the mesh without and with the texture ``corners`` (uv, uv_faces): event medians
    (the first left out) and the bytes of its undo step."""
    direction = vertex_normals(vertices, faces)[row]
    for uv, uv_faces in ((None, None), corners):
        events_s, sizes = [], []
        for _ in range(repeats):
            settings = EngineSettings(material=CUBIC, dynamic_topology=True)
            sculptor = Sculptor(vertices, faces, uv=uv, uv_faces=uv_faces, settings=settings)
            events_s.extend(pull(sculptor, row, direction, events, 0.01)[1:])
            sizes.append(sculptor.history.memory_bytes)
        rows = sculptor.mesh.uv
        print(
            f"dynamic, {'plain' if uv is None else 'textured':8s} event median "
            f"{1e3 * statistics.median(events_s):7.1f} ms, undo step "
            f"{statistics.median(sizes) / 2**20:7.2f} MiB, {len(sculptor.vertices):,} vertices, "
            f"{0 if rows is None else len(rows):,} uv rows"
        )


def remesh_default(repeats: int) -> None:
    vertices, faces = default_model()
    for factor in (None, 1.0, 2.0):
        seconds = []
        for _ in range(repeats):
            sculptor = Sculptor(vertices, faces)
            size = None if factor is None else factor * median_edge_length(vertices, faces)
            start = time.process_time()
            sculptor.remesher.remesh(None if size is None else size / sculptor.model_size)
            seconds.append(time.process_time() - start)
        lengths = sculptor.vertices[mesh_edges(sculptor.faces, len(sculptor.vertices)).ends]
        ratio = np.linalg.norm(lengths[:, 1] - lengths[:, 0], axis=1) / (
            size or median_edge_length(vertices, faces)
        )
        angles = smallest_angles(sculptor.vertices[sculptor.faces])
        name = "its own edges" if factor is None else f"{factor:g} x its median edge"
        print(
            f"Remesh of the default model to {name}: "
            f"{statistics.median(seconds):5.2f} s, {len(sculptor.vertices):,} vertices, "
            f"edges {np.percentile(ratio, 5):.2f}-{np.percentile(ratio, 95):.2f} x the target "
            f"(5-95 %), faces with all angles >= 30 deg {100 * np.mean(angles >= 30):.1f} %"
        )


#: The stages of one dynamic-topology step, as (owner, attribute) timed by :func:`timed_stages`.
STAGES = {
    "select: strain": (stroke_module, "strained_corners"),
    "select: pins": (stroke_module.StrokeDriver, "pinned_vertices"),
    "select: grow": (stroke_module, "grow_region"),
    "remesh: total": (stroke_module, "remesh"),
    "remesh: split": (remesh_module._Patch, "split"),
    "remesh: collapse": (remesh_module._Patch, "collapse"),
    "remesh: flip": (remesh_module._Patch, "flip"),
    "remesh: relax": (remesh_module._Patch, "relax"),
    "remesh: compact (numbering)": (remesh_module, "_numbering"),
    "remesh: compact (copies)": (remesh_module, "_carried"),
    "remesh: compact (renumbering)": (remesh_module, "renumber_faces"),
    "mesh adopt": (MeshState, "adopt"),
    "step: total": (stroke_module.StrokeDriver, "_remesh"),
}


@contextlib.contextmanager
def timed_stages(seconds: dict[str, list[float]]) -> Iterator[None]:
    """While open, each :data:`STAGES` function adds its CPU seconds of each call to
    ``seconds[name]`` (one entry per step: calls within a step add up)."""
    saved = [(owner, name, getattr(owner, name)) for owner, name in STAGES.values()]

    def timer(stage: str, function: Callable[..., Any]) -> Callable[..., Any]:
        def timed(*args: Any, **kwargs: Any) -> Any:
            start = time.process_time()
            try:
                return function(*args, **kwargs)
            finally:
                seconds[stage][-1] += time.process_time() - start

        return timed

    for stage, (owner, name) in STAGES.items():
        setattr(owner, name, timer(stage, getattr(owner, name)))
    try:
        yield
    finally:
        for owner, name, function in saved:
            setattr(owner, name, function)


def step_stages(vertices: np.ndarray, faces: np.ndarray, row: int, events: int) -> None:
    """The split of dynamic-topology steps (a belly pull of ``events`` events from ``row``)
    into :data:`STAGES`: medians of the steps after the first, ms; "other" is the step less its
    stages (strain marks, bookkeeping of the stroke: reference, origins)."""
    normals = vertex_normals(vertices, faces)
    sculptor = Sculptor(
        vertices, faces, settings=EngineSettings(material=CUBIC, dynamic_topology=True)
    )
    seconds: dict[str, list[float]] = defaultdict(list)
    center = sculptor.vertices[row].copy()
    delta = 0.01 * sculptor.model_size * normals[row]
    sculptor.begin_stroke(Brush("grab", radius=0.03))
    sizes = []
    with timed_stages(seconds):
        for _ in range(events):
            for stage in STAGES:
                seconds[stage].append(0.0)
            before = len(sculptor.faces)
            start = time.process_time()
            sculptor.stroke_event(BrushEvent(center=center, delta=delta))
            seconds["event: total"].append(time.process_time() - start)
            sizes.append(len(sculptor.faces) - before)
            center = center + delta
    sculptor.end_stroke()
    inner: tuple[str, ...] = ("remesh: split", "remesh: collapse", "remesh: flip", "remesh: relax")
    inner += tuple(stage for stage in STAGES if stage.startswith("remesh: compact"))
    derived = {
        "remesh: setup (patch, region rows)": [
            t - sum(seconds[s][i] for s in inner) for i, t in enumerate(seconds["remesh: total"])
        ],
        "other (marks, stroke bookkeeping)": [
            t - sum(seconds[s][i] for s in STAGES if s.startswith(("select", "remesh: t", "mesh")))
            for i, t in enumerate(seconds["step: total"])
        ],
        "brush (event less step)": [
            e - t for e, t in zip(seconds["event: total"], seconds["step: total"], strict=True)
        ],
    }
    print(f"-- one dynamic-topology step at {len(vertices):,} vertices (median of {events - 1})")
    for stage, values in {**seconds, **derived}.items():
        print(f"{stage:38s} {1e3 * statistics.median(values[1:]):7.1f} ms")


def subdivided_twice(path: Path) -> Sculptor:
    """A sculptor on the mesh of ``path`` (its UVs too) subdivided twice."""
    mesh = load_mesh(path)
    base = Sculptor(mesh.vertices, mesh.faces, uv=mesh.uv, uv_faces=mesh.uv_faces)
    base.subdivide()
    base.subdivide()
    return base


def million(meshes: Path, events: int, remesh_too: bool) -> None:
    ogre = meshes / "ogre.obj"
    if not ogre.exists():
        print(f"{ogre} not found: the 1M-vertex figures need ../shared/meshes")
        return
    base = subdivided_twice(ogre)
    vertices, faces = base.vertices.copy(), base.faces.copy()
    normals = vertex_normals(vertices, faces)
    belly = int(np.argmin(vertices[:, 1]))  # the front of the belly (-y)
    step_stages(vertices, faces, belly, events)
    print(f"-- the ogre subdivided twice ({len(vertices):,} vertices), {events}-event belly pull")
    for dynamic in (False, True):
        settings = EngineSettings(material=CUBIC, dynamic_topology=dynamic)
        sculptor = Sculptor(vertices, faces, settings=settings)
        times = pull(sculptor, belly, normals[belly], events, 0.01)
        name = "dynamic" if dynamic else "fixed"
        steady = times[1:]
        print(
            f"{name:8s} {len(steady) / sum(steady):5.2f} events/s (event median "
            f"{1e3 * statistics.median(steady):6.0f} ms), {len(sculptor.vertices):,} vertices, "
            f"undo step {sculptor.history.memory_bytes / 2**20:.0f} MiB"
        )
    if not remesh_too:
        return
    sculptor = Sculptor(vertices, faces)
    start = time.process_time()
    sculptor.remesher.remesh(None, iterations=2)
    print(
        f"Remesh of it to its own edges (2 rounds): {time.process_time() - start:.1f} s, "
        f"{len(sculptor.vertices):,} vertices, peak memory of the process "
        f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20:.1f} GiB"
    )


def textured(meshes: Path, repeats: int, million_too: bool, events: int) -> None:
    """Dynamic-topology pulls with and without texture corners: the default model
    (:func:`two_charts`), Spot subdivided twice (its own UVs and seams) and the ogre subdivided
    twice (1M vertices, :func:`two_charts`)."""
    vertices, faces = default_model()
    print(f"-- the default model ({len(vertices):,} vertices), 20 events from the top")
    top = int(np.argmax(vertices[:, 2]))
    textured_pulls(vertices, faces, two_charts(vertices, faces), top, 20, repeats)
    spot = meshes / "spot.obj"
    if spot.exists():
        base = subdivided_twice(spot)
        v, uv, uv_faces = base.vertices, base.mesh.uv, base.mesh.uv_faces
        assert uv is not None and uv_faces is not None
        print(f"-- Spot subdivided twice ({len(v):,} vertices), 20 events from the top")
        textured_pulls(v, base.faces, (uv, uv_faces), int(np.argmax(v[:, 2])), 20, repeats)
    else:
        print(f"{spot} not found: Spot's figures need ../shared/meshes")
    ogre = meshes / "ogre.obj"
    if not million_too or not ogre.exists():
        print("the 1M-vertex textured figures skipped (--no-million or no ogre.obj)")
        return
    base = subdivided_twice(ogre)
    v, f = base.vertices.copy(), base.faces.copy()
    print(f"-- the ogre subdivided twice ({len(v):,} vertices), {events} events on its belly")
    textured_pulls(v, f, two_charts(v, f), int(np.argmin(v[:, 1])), events, 1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument(
        "--meshes", default=str(Path(__file__).resolve().parents[2] / "shared" / "meshes")
    )
    parser.add_argument("--no-million", action="store_true", help="skip the 1M-vertex mesh")
    parser.add_argument("--million-events", type=int, default=10, help="events of its pull")
    parser.add_argument("--no-million-remesh", action="store_true", help="skip its Remesh")
    parser.add_argument("--million-only", action="store_true", help="only the 1M-vertex mesh")
    parser.add_argument("--textured-only", action="store_true", help="only textured pulls")
    args = parser.parse_args()
    if args.textured_only:
        textured(Path(args.meshes), args.repeats, not args.no_million, args.million_events)
        return
    if not args.million_only:
        default_pull(args.repeats)
        remesh_default(args.repeats)
    if args.no_million:
        print("the 1M-vertex figures skipped (--no-million)")
    else:
        million(Path(args.meshes), args.million_events, not args.no_million_remesh)


if __name__ == "__main__":
    main()
