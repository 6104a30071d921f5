"""What the viewport's field preview costs (View → Field preview): one evaluation of the current
brush's field at the vertices it reaches, against one brush event of the same brush.

    python benchmarks/field_preview.py [--repeats 5]

Prints, per mesh (the default model; the 1M-vertex mesh of ``benchmarks/scale.py``) and brush
(grab, pinch, wrinkle; automatic influence, cubic material, l_max 8): the vertices the preview
colours, the median time of the field alone, of the field with the app's colours and arrows
(what the app's background job does after the pointer rests), and of one brush event.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from scale import L_MAX, MATERIAL, million_vertex_mesh

from app.field_preview import field_arrows, field_colors  # numpy only (Qt is not shown)
from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.shapes import default_model
from gogreen_core.sculpt.preview import field_preview

SHARED = Path(__file__).resolve().parents[2] / "shared" / "meshes"


def median_ms(samples: list[float]) -> float:
    return 1e3 * statistics.median(samples)


def measure(sculptor: Sculptor, name: str, repeats: int) -> None:
    vertices = sculptor.vertices
    center = vertices[int(np.argmax(vertices[:, 1]))].copy()
    axis = np.array([0.0, 0.0, -1.0])
    direction = np.array([1.0, 0.0, 0.0])
    for kind in ("grab", "pinch", "wrinkle"):
        brush = Brush(kind, radius=0.05)
        event = (
            BrushEvent(center, amount=0.02, axis=axis, direction=direction)
            if brush.is_affine
            else BrushEvent(center, 0.01 * sculptor.model_size * direction)
        )
        preview = field_preview(sculptor, brush, center, axis, direction)  # warm
        previews, drawn, events = [], [], []
        eps = brush.eps(sculptor.model_size)
        for _ in range(repeats):
            start = time.perf_counter()
            field = field_preview(sculptor, brush, center, axis, direction)
            previews.append(time.perf_counter() - start)
            assert field is not None
            field_arrows(sculptor.vertices, None, field, 0.5 * eps, 0.45 * eps)
            field_colors(field.motion)
            drawn.append(time.perf_counter() - start)
            sculptor.begin_stroke(brush)
            start = time.perf_counter()
            sculptor.stroke_event(event)
            events.append(time.perf_counter() - start)
            sculptor.end_stroke()
            sculptor.undo()
        rows = 0 if preview is None else len(preview.rows)
        print(
            f"{name:>28} {kind:>8}: {rows:>9,} vertices  field {median_ms(previews):7.1f} ms"
            f"  with colours and arrows {median_ms(drawn):7.1f} ms"
            f"  event {median_ms(events):7.1f} ms"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    vertices, faces = default_model()
    measure(
        Sculptor(vertices, faces, material=MATERIAL, l_max=L_MAX), "default model", args.repeats
    )
    vertices, faces, name = million_vertex_mesh(SHARED)
    measure(Sculptor(vertices, faces, material=MATERIAL, l_max=L_MAX), name, args.repeats)


if __name__ == "__main__":
    main()
