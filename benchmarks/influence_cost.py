"""What the automatic influence costs (the paper-controls issue, item 3): one brush event with
the old 4 ε ball and with ``influence="auto"`` on the 1M-vertex mesh of ``benchmarks/scale.py``.

    python benchmarks/influence_cost.py [--repeats 5]

Prints, per brush: the influence in ε, the vertices the event can reach and the median time of
one event (cubic material, l_max 8, cursor motion 1 % of the model size or an amount of 0.02).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scale import L_MAX, MATERIAL, median_ms, million_vertex_mesh

from gogreen_core import Brush, BrushEvent, Sculptor

SHARED = Path(__file__).resolve().parents[2] / "shared" / "meshes"


def event_times(sculptor: Sculptor, brush: Brush, event: BrushEvent, repeats: int) -> list[float]:
    samples = []
    for _ in range(repeats):
        sculptor.begin_stroke(brush)
        start = time.perf_counter()
        sculptor.stroke_event(event)
        samples.append(time.perf_counter() - start)
        sculptor.end_stroke()
        sculptor.undo()
    return samples


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--radius", type=float, default=0.05)
    args = parser.parse_args()
    vertices, faces, name = million_vertex_mesh(SHARED)
    sculptor = Sculptor(vertices, faces, material=MATERIAL, l_max=L_MAX)
    center = vertices[int(np.argmax(vertices[:, 1]))]
    print(f"{name}: {len(vertices):,} vertices, brush radius {args.radius}")
    delta = 0.01 * sculptor.model_size * np.array([0.3, 0.8, 0.5])
    for kind in ("grab", "pinch", "grab_triscale"):
        brush = Brush(kind, radius=args.radius)
        affine = brush.is_affine
        event = (
            BrushEvent(center, amount=0.02, axis=[0, 0, 1], direction=[1, 0, 0])
            if affine
            else BrushEvent(center, delta)
        )
        for influence in (4.0, "auto"):
            b = Brush(kind, radius=args.radius, influence=influence)
            reach = sculptor.influence(b)
            event_times(sculptor, b, event, 1)  # warm: field bounds, reach, compiled code
            moved = len(
                sculptor._mesh.rows_near(
                    center, np.zeros(3), reach * b.eps(sculptor.model_size), np.ones((1, 3))
                )
            )
            samples = event_times(sculptor, b, event, args.repeats)
            print(
                f"  {kind:<14} influence {influence!s:>4} = {reach:5.1f} ε: {moved:>9,} "
                f"vertices reachable, event {median_ms(samples)}"
            )


if __name__ == "__main__":
    main()
