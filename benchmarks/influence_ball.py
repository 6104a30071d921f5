"""The influence test of a brush event (which vertices it may move) by the vertex blocks
(``gogreen_core.mesh.influence``) and by the plain pass over every vertex, on meshes whose vertex
order has more or less locality (issue 23).

    python benchmarks/influence_ball.py [--repeats 7] [--meshes DIR]

Meshes: the shared ogre subdivided twice (992,608 vertices, files' locality; skipped when
``../shared/meshes/ogre.obj`` is absent), the default model Loop-subdivided twice by the app
(655,362 vertices; the icosphere's order has less locality) and the ogre's vertices shuffled
(none: every block spans the model, the plain pass answers). Per mesh, the blocks' build (the
first query), then per ball radius (model sizes) and symmetry the rows reached and the medians
of both answers (and which answered: the blocks or, where they would not pay, the plain pass).
Figures only.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from peer_event import ogre

from gogreen_core import _compiled
from gogreen_core.mesh.mesh_state import MeshState
from gogreen_core.mesh.shapes import default_model
from gogreen_core.mesh.subdivision import prepare_subdivision
from gogreen_core.sculpt.brushes import mirror_signs

ROOT = Path(__file__).resolve().parents[1]


def median_ms(samples: list[float]) -> float:
    return 1e3 * statistics.median(samples)


def figures(name: str, mesh: MeshState, repeats: int) -> None:
    from gogreen_core.mesh.influence import plain_rows_near

    blocks = mesh._blocks
    vertices = mesh.vertices
    center = vertices[int(np.argmax(vertices @ [0.2, 1.0, 0.3]))].copy()
    step = 0.01 * mesh.model_size * np.array([0.3, 0.8, 0.5])
    start = time.perf_counter()
    mesh.rows_near(center, step, 0.1 * mesh.model_size, mirror_signs(""))
    print(f"{name}: {len(vertices):,} vertices; first query (build): "
          f"{1e3 * (time.perf_counter() - start):.1f} ms")  # fmt: skip
    for radius in (0.01, 0.05, 0.2, 2.0):
        for symmetry in ("", "xyz"):
            args = (center, step, radius * mesh.model_size, mirror_signs(symmetry))
            answered = dict(blocks.answers)
            by_blocks, plain = [], []
            for _ in range(repeats):
                t = time.perf_counter()
                rows = mesh.rows_near(*args)
                by_blocks.append(time.perf_counter() - t)
                t = time.perf_counter()
                plain_rows_near(vertices, *args, mesh.origin, True)
                plain.append(time.perf_counter() - t)
            how = "blocks" if blocks.answers["blocks"] > answered["blocks"] else "plain"
            print(f"  radius {radius:4} symmetry {symmetry or '-':>3}: {len(rows):>9,} rows, "
                  f"{how:>6} {median_ms(by_blocks):6.2f} ms, "
                  f"plain pass {median_ms(plain):6.2f} ms")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--meshes", type=Path, default=ROOT.parent / "shared" / "meshes")
    args = parser.parse_args()
    _compiled.prepare(_compiled.DRIVERS)
    loaded = ogre(args.meshes)
    if loaded is None:
        print(f"ogre: skipped ({args.meshes / 'ogre.obj'} not found)")
    else:
        figures("ogre subdivided twice", MeshState(*loaded), args.repeats)
    model = MeshState(*default_model())
    for _ in range(2):
        model.adopt(prepare_subdivision(model.snapshot(), False).result)
    figures("default model, Loop-subdivided twice", model, args.repeats)
    if loaded is not None:
        order = np.random.default_rng(0).permutation(len(loaded[0]))
        figures("ogre, vertices shuffled", MeshState(loaded[0][order], loaded[1][:0]), args.repeats)


if __name__ == "__main__":
    main()
