"""The cost of a stroke's start with a new material frame (issue 35, "Fast").

    python benchmarks/material_frame.py [--repeats 15]

Prints medians (nothing is asserted), for the "Layered sheet wrinkles" material turned
arbitrarily, at l_max 8 and 12:

* turning the kernel by Wigner-D matrices (:meth:`GreenKernel.turned`, what a stroke does) vs a
  new quadrature on the turned material (``GreenKernel(material.rotated(F), l_max)``);
* the first event of a grab, pinch and wrinkle stroke on the default model (40,962 vertices)
  with ``material_frame="world"`` (kernels and field bounds already cached by a previous
  stroke) and ``"surface"`` (a new frame at every stroke: area normal, turned kernel, the
  frame's field bounds), and the difference: what the surface frame adds at a stroke's start;
* a later event of the same surface stroke (nothing left to compute for the frame).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from scipy.spatial.transform import Rotation

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.files.presets import builtin_presets
from gogreen_core.mesh.shapes import default_model
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.brushes.wrinkle import fold_weights
from gogreen_core.sculpt.sculptor import Sculptor


def _median_ms(times: list[float]) -> float:
    return 1e3 * statistics.median(times)


def _events(sculptor: Sculptor, kind: str, k: int) -> tuple[Brush, list[BrushEvent]]:
    """A stroke of ``kind`` at the k-th of a few places (each stroke a new place and frame)."""
    vertices = sculptor.vertices
    rng = np.random.default_rng(k)
    index = int(np.argmax(vertices @ rng.normal(size=3)))
    center = vertices[index].copy()
    normal = center / np.linalg.norm(center)
    tangent = np.cross(normal, rng.normal(size=3))
    tangent /= np.linalg.norm(tangent)
    if kind == "pinch":
        brush = Brush("pinch", radius=0.06)
        return brush, [
            BrushEvent(center, amount=0.02, axis=normal, direction=tangent) for _ in range(2)
        ]
    step = 0.01 * sculptor.model_size * tangent
    return Brush(kind, radius=0.06), [BrushEvent(center + j * step, delta=step) for j in range(2)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=15)
    args = parser.parse_args()
    preset = next(p for p in builtin_presets() if p.name == "Layered sheet wrinkles")
    material = preset.material.rotated(Rotation.from_euler("xyz", (0.4, -0.9, 0.3)).as_matrix())
    frames = Rotation.random(args.repeats, random_state=1).as_matrix()
    vertices, faces = default_model()
    for l_max in (8, 12):
        kernel = GreenKernel(material, l_max)
        kernel.turned(frames[0])  # the Lebedev rule of the Wigner-D matrices, once
        turn, quadrature = [], []
        for frame in frames:
            start = time.perf_counter()
            kernel.turned(frame)
            turn.append(time.perf_counter() - start)
        for frame in frames[:5]:
            start = time.perf_counter()
            GreenKernel(material.rotated(frame), l_max)
            quadrature.append(time.perf_counter() - start)
        print(
            f"l_max {l_max:2d}: turn the kernel (Wigner-D) {_median_ms(turn):7.2f} ms, "
            f"new quadrature {_median_ms(quadrature):7.1f} ms"
        )
        base = preset.engine_settings().replace(
            material=material,
            l_max=l_max,
            brush_weights={"wrinkle": tuple(fold_weights(l_max))},
        )
        for kind in ("grab", "pinch", "wrinkle"):
            firsts: dict[str, list[float]] = {"world": [], "surface": []}
            later: list[float] = []
            for frame_setting in ("world", "surface"):
                sculptor = Sculptor(
                    vertices, faces, settings=base.replace(material_frame=frame_setting)
                )
                brush, events = _events(sculptor, kind, 99)
                sculptor.apply_brush(brush, events)  # compile, cache the world's bounds
                for k in range(args.repeats):
                    brush, events = _events(sculptor, kind, k)
                    sculptor.begin_stroke(brush)
                    start = time.perf_counter()
                    sculptor.stroke_event(events[0])
                    firsts[frame_setting].append(time.perf_counter() - start)
                    start = time.perf_counter()
                    sculptor.stroke_event(events[1])
                    if frame_setting == "surface":
                        later.append(time.perf_counter() - start)
                    sculptor.cancel_stroke()
            world, surface = _median_ms(firsts["world"]), _median_ms(firsts["surface"])
            print(
                f"  {kind:8s} first event: world {world:7.1f} ms, surface {surface:7.1f} ms "
                f"(+{surface - world:6.1f} ms at the stroke's start); "
                f"a later surface event {_median_ms(later):7.1f} ms"
            )


if __name__ == "__main__":
    main()
