"""Benchmark of one brush step (a mouse event) of the sculpting engine.

Targets (issue "Sculpting engine"), 2 cores, anisotropic material, l_max = 8: one brush step on
the 62k-vertex ogre ≤ 20 ms, and on 100k affected vertices ≤ 33 ms. Streamlines are adaptive
(GreenKernel.streamlines' default tolerance; Brush.substeps no longer changes them).

    python benchmarks/brush.py [--repeats 15] [--meshes /path/to/meshes]

Each step is a grab event of 1% of the model size at a surface vertex; the time includes
everything the app waits for (kernel for the brush radius, force solve, influence-ball
selection, fused adaptive RK4 integration, scatter back). Prints figures only.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
import trimesh

from gogreen_core import Brush, BrushEvent, Material, Sculptor

MATERIAL = Material.cubic(3.0, 1.5, 0.4).rotated(
    np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])
)


def time_steps(sculptor: Sculptor, brush: Brush, center_index: int, repeats: int):
    """Median and best ms of one event, and how many vertices it evaluated.

    Each event is a one-event stroke that is undone afterwards (outside the timing), so every
    sample deforms the same mesh and moves the same vertices.
    """
    delta = 0.01 * sculptor.model_size * np.array([0.3, 0.8, 0.5])
    center = sculptor.vertices[center_index].copy()
    samples, affected = [], 0
    for _ in range(repeats):
        sculptor.begin_stroke(brush)
        start = time.perf_counter()
        affected = len(sculptor.stroke_event(BrushEvent(center, delta)))
        samples.append(1e3 * (time.perf_counter() - start))
        sculptor.end_stroke()
        sculptor.undo()
    return statistics.median(samples), min(samples), affected


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=15)
    parser.add_argument(
        "--meshes", default=str(Path(__file__).resolve().parents[2] / "shared/meshes")
    )
    args = parser.parse_args()

    start = time.perf_counter()
    sphere = trimesh.creation.icosphere(subdivisions=2)
    probe = Sculptor(np.array(sphere.vertices), np.array(sphere.faces), material=MATERIAL)
    probe.apply_brush(Brush("grab"), [BrushEvent(sphere.vertices[0], [0.0, 0.01, 0.0])])
    print(
        f"first brush step incl. numba load/compile: {1e3 * (time.perf_counter() - start):.0f} ms"
    )

    print(f"\n{'case':<44} {'affected':>9} {'median ms':>10} {'min ms':>8}")
    for name in ("stanford-bunny.obj", "spot.obj", "ogre.obj"):
        mesh = trimesh.load(Path(args.meshes) / name, process=False)
        sculptor = Sculptor(np.array(mesh.vertices), np.array(mesh.faces), material=MATERIAL)
        center = int(np.argmax(np.array(mesh.vertices) @ [0.2, 1.0, 0.3]))
        for brush in (Brush("grab", radius=0.05), Brush("grab", radius=0.1), Brush("twist")):
            median, best, affected = time_steps(sculptor, brush, center, args.repeats)
            case = f"{name} ({len(mesh.vertices)} v) {brush.kind} r={brush.radius}"
            print(f"{case:<44} {affected:>9} {median:>10.1f} {best:>8.1f}")

    # 100k affected vertices: a finely tessellated sphere, influence ball sized to hold 100k.
    sphere = trimesh.creation.icosphere(subdivisions=7)
    vertices = np.array(sphere.vertices)
    sculptor = Sculptor(vertices, np.array(sphere.faces), material=MATERIAL)
    center = int(np.argmax(vertices[:, 2]))
    dist = np.sort(np.linalg.norm(vertices - vertices[center], axis=1))
    brush = Brush("grab", radius=0.1)
    # the influence ball around the event's short segment then holds just over 100k vertices
    influence = dist[100_000] / brush.eps(sculptor.model_size)
    for symmetry in ("", "x"):
        brush_s = Brush("grab", radius=0.1, influence=influence, symmetry=symmetry)
        median, best, affected = time_steps(sculptor, brush_s, center, args.repeats)
        case = f"sphere ({len(vertices)} v), 100k affected" + (" mirror x" if symmetry else "")
        print(f"{case:<44} {affected:>9} {median:>10.1f} {best:>8.1f}")


if __name__ == "__main__":
    main()
