"""Benchmark of the mesh edits: Loop subdivision, the smooth brush and mask painting.

    python benchmarks/mesh_edits.py [--repeats 5] [--meshes /path/to/meshes] [--no-million]

Prints medians (and minima) of: subdividing the shared ogre (62k vertices) with
:func:`prepare_subdivision` (what the app runs off the GUI thread) and with
:meth:`Sculptor.subdivide` (the same plus the adoption and the undo snapshots, what a replay
does), its undo and redo; the same for the 1M-vertex ogre (the ogre subdivided twice by Loop:
992,608 vertices, to 3,969,272), with the history's memory; one smooth event and one mask event
on the 1M-vertex mesh at radius 0.05 (with the vertices and rows it reached), and the first
smooth event in a fresh process (numba's compile or its disk cache). Roughness and volume of a
noisy sphere before and after ten smooth events. Figures only, no assertions.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.geometry import mesh_volume
from gogreen_core.mesh.mesh_io import load_mesh
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.mesh.subdivision import prepare_subdivision

FIRST_SMOOTH = """
import time
start = time.perf_counter()
import numpy as np
from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.shapes import icosphere
vertices, faces = icosphere(2)
sculptor = Sculptor(vertices, faces)
sculptor.apply_brush(Brush("smooth"), [BrushEvent(vertices[0], amount=1.0)])
print(time.perf_counter() - start)
"""


def timed(function, repeats: int) -> list[float]:
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        samples.append(time.perf_counter() - start)
    return samples


def show(name: str, samples: list[float]) -> None:
    print(f"{name:58s} {1e3 * statistics.median(samples):9.1f} ms (min {1e3 * min(samples):.1f})")


def subdivision(name: str, sculptor: Sculptor, repeats: int) -> None:
    source = sculptor.mesh
    print(f"-- {name}: {len(source.vertices):,} vertices, {len(source.faces):,} faces")
    show("prepare_subdivision (the app's background job)", timed(
        lambda: prepare_subdivision(source), repeats
    ))  # fmt: skip
    whole: list[float] = []
    undo: list[float] = []
    redo: list[float] = []
    for _ in range(repeats):
        start = time.perf_counter()
        sculptor.subdivide()
        whole.append(time.perf_counter() - start)
        start = time.perf_counter()
        sculptor.undo()
        undo.append(time.perf_counter() - start)
        start = time.perf_counter()
        sculptor.redo()
        redo.append(time.perf_counter() - start)
        sculptor.undo()
    show("Sculptor.subdivide (computed, adopted, undo snapshots)", whole)
    show("undo of it", undo)
    show("redo of it", redo)
    prepared = prepare_subdivision(source)
    adopt = timed(lambda: (sculptor.subdivide(prepared=prepared), sculptor.undo()), repeats)
    show("adopting a prepared one on the GUI thread (+ its undo)", adopt)
    sculptor.subdivide(prepared=prepared)
    print(
        f"{'after: vertices, faces, history':58s} {len(sculptor.vertices):,}, "
        f"{len(sculptor.faces):,}, {sculptor.history.memory_bytes / 2**20:.0f} MiB"
    )


def strokes(sculptor: Sculptor, repeats: int) -> None:
    vertices = sculptor.vertices
    center = vertices[int(np.argmax(vertices[:, 1]))]
    delta = np.array([0.002, 0.0, 0.0]) * sculptor.model_size
    for kind in ("smooth", "mask"):
        brush = Brush(kind, radius=0.05)
        rows: list[int] = []

        def event(brush=brush, rows=rows):
            rows.append(len(sculptor.apply_brush(brush, [BrushEvent(center, delta, amount=0.5)])))

        event()  # compiled or loaded from the cache
        show(f"one {kind} event at radius 0.05 ({len(vertices):,} vertices)", timed(event, repeats))
    reached = np.count_nonzero(
        np.linalg.norm(vertices - center, axis=1) < 4 * 0.05 * sculptor.model_size
    )
    print(f"{'vertices within the influence ball':58s} {reached:,}")


def roughness_and_volume() -> None:
    vertices, faces = icosphere(4)
    rng = np.random.default_rng(1)
    noisy = vertices * (1.0 + 0.02 * rng.standard_normal(len(vertices)))[:, None]
    sculptor = Sculptor(noisy, faces)
    brush = Brush("smooth", radius=0.2, influence=np.inf)
    sculptor.apply_brush(brush, [BrushEvent(noisy[0], amount=1.0)] * 10)
    radius = [np.std(np.linalg.norm(v, axis=1)) for v in (noisy, sculptor.vertices)]
    volume = mesh_volume(sculptor.vertices, faces) / mesh_volume(noisy, faces) - 1.0
    print(
        f"-- noisy sphere (2,562 vertices, 2 % noise), 10 smooth events: radius spread "
        f"{radius[0]:.4f} → {radius[1]:.4f}, volume {100 * volume:+.3f} %"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument(
        "--meshes", default=str(Path(__file__).resolve().parents[2] / "shared" / "meshes")
    )
    parser.add_argument("--no-million", action="store_true", help="skip the 1M-vertex mesh")
    args = parser.parse_args()
    roughness_and_volume()
    first = subprocess.run(
        [sys.executable, "-c", FIRST_SMOOTH], capture_output=True, text=True, check=True
    )
    print(f"{'first smooth event in a fresh process (imports included)':58s} "
          f"{1e3 * float(first.stdout.split()[-1]):9.1f} ms")  # fmt: skip
    ogre = Path(args.meshes) / "ogre.obj"
    if not ogre.exists():
        print(f"{ogre} not found: the mesh figures need ../shared/meshes")
        return
    mesh = load_mesh(ogre)
    sculptor = Sculptor(mesh.vertices, mesh.faces)
    subdivision("ogre", sculptor, args.repeats)
    if args.no_million:
        return
    million = Sculptor(sculptor.vertices, sculptor.faces)  # 248k: once more gives 992,608
    million.subdivide()
    million = Sculptor(million.vertices, million.faces)
    strokes(million, args.repeats)
    subdivision("the 1M-vertex ogre", million, max(1, args.repeats // 2))


if __name__ == "__main__":
    main()
