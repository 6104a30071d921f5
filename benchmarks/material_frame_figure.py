"""docs/figures/material_frame.png: the wrinkle brush on a sphere at three places, with the
material's axes fixed in the world and following the surface (issue 35).

    xvfb-run -a -s "-screen 0 1600x1000x24" python benchmarks/material_frame_figure.py [--out DIR]

The "Layered sheet wrinkles" material (1:100 laminate, layers tilted 45°, fold degree 8) and
one stroke per place: 6 events pulling 0.4 ε along the normal and dragging 0.15 ε along the
local east. Each panel looks straight down the normal at its place, north up, coloured by the
normal displacement over the pull. With the world frame the layers meet each place at another
angle, so the folds differ from place to place; with the surface frame every stroke turns the
material onto the surface where it starts and the folds are alike everywhere. Prints, per
row, the largest difference between the three places' normal displacements sampled on the same
local grid (relative to the deepest fold): what the eye compares.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pyvista as pv
from scipy.interpolate import LinearNDInterpolator

from gogreen_core.files.presets import builtin_presets
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.sculptor import Sculptor

PANEL = (420, 400)
#: Where the strokes start (unit directions on the sphere).
PLACES = ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (-0.6, -0.6, -0.53))  # 90-127° apart


def _local(direction: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(normal, east, north) at a point of the unit sphere (north toward +z; at a pole, +y)."""
    n = direction / np.linalg.norm(direction)
    up = np.array([0.0, 0.0, 1.0]) if abs(n[2]) < 0.99 else np.array([0.0, 1.0, 0.0])
    east = np.cross(up, n)
    east /= np.linalg.norm(east)
    return n, east, np.cross(n, east)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(Path(__file__).parent.parent / "docs" / "figures"))
    args = parser.parse_args()
    preset = next(p for p in builtin_presets() if p.name == "Layered sheet wrinkles")
    vertices, faces = icosphere(6)
    rows = (("world", "axes fixed in the world"), ("surface", "axes follow the surface"))
    plotter = pv.Plotter(
        off_screen=True, shape=(2, 3), window_size=(PANEL[0] * 3, PANEL[1] * 2), border=False
    )
    plotter.set_background("white")
    grid = np.stack(np.meshgrid(np.linspace(-4, 4, 41), np.linspace(-4, 4, 41)), -1).reshape(-1, 2)
    for row, (frame, title) in enumerate(rows):
        sculptor = Sculptor(
            vertices, faces, settings=preset.engine_settings().replace(material_frame=frame)
        )
        brush = Brush("wrinkle", radius=0.03)
        eps = brush.eps(sculptor.model_size)
        samples = []
        pull = 6 * 0.4 * eps
        for place in PLACES:
            n, east, north = _local(np.asarray(place))
            step = eps * (0.4 * n + 0.15 * east)
            center = vertices[int(np.argmax(vertices @ n))]
            before = sculptor.vertices.copy()
            sculptor.apply_brush(brush, [BrushEvent(center + k * step, step) for k in range(6)])
            # this stroke's normal displacement (unit sphere: the normal is the position) on a
            # grid of the place's own (east, north) coordinates, in ε
            own = np.einsum("ij,ij->i", sculptor.vertices - before, vertices) / pull
            near = np.flatnonzero(vertices @ n > np.cos(5 * eps))
            local = np.column_stack([vertices[near] @ east, vertices[near] @ north]) / eps
            samples.append(LinearNDInterpolator(local, own[near])(grid))
        lifted = np.einsum("ij,ij->i", sculptor.vertices - vertices, vertices) / pull
        mesh = pv.PolyData(sculptor.vertices, np.hstack([np.full((len(faces), 1), 3), faces]))
        mesh["normal displacement / pull"] = lifted
        for column, place in enumerate(PLACES):
            n, _, north = _local(np.asarray(place))
            plotter.subplot(row, column)
            plotter.add_mesh(
                mesh,
                scalars="normal displacement / pull",
                cmap="coolwarm",
                clim=(-0.4, 0.4),
                smooth_shading=True,
                specular=0.3,
                show_scalar_bar=(row, column) == (1, 2),
                scalar_bar_args={"title": "normal displacement / pull", "n_labels": 3},
            )
            plotter.add_text(f"{title}\nplace {column + 1}", font_size=10, color="black")
            focus = n * 1.0
            plotter.camera_position = [tuple(focus + 12 * eps * n), tuple(focus), tuple(north)]
            plotter.camera.parallel_projection = True
            plotter.camera.parallel_scale = 4.5 * eps
        values = np.array(samples)
        depth = np.nanmax(np.abs(values))
        gaps = [np.nanmax(np.abs(values[k] - values[0])) / depth for k in (1, 2)]
        print(
            f"{frame:7s}: places 2 and 3 differ from place 1 by {gaps[0]:.3f} and {gaps[1]:.3f} "
            "of the highest normal displacement"
        )
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    plotter.screenshot(str(out / "material_frame.png"))
    plotter.close()
    print(f"wrote {out / 'material_frame.png'}")


if __name__ == "__main__":
    main()
