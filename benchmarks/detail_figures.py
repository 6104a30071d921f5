"""Render each detail brush (issue 34 item 3) stroked on the default model, off-screen, to PNG.

    xvfb-run -a .venv/bin/python benchmarks/detail_figures.py [-o docs/figures]

Writes ``detail_<brush>.png`` for Draw, Clay Strips, Crease, Flatten and Inflate: the default
model seen from the front, with two wavy strokes across it as the app's tools make them (a dab
at the press, then one event per 0.01 model sizes of cursor travel, each starting where the
surface under the cursor is now): the upper one plain, the lower one with Ctrl (inverted). The
left panel is shaded as the app shows it, the right one coloured by how far each point moved
along the model's original normal (red out, blue in). Prints each stroke's time per event and
the largest motion out and in.
"""

from __future__ import annotations

import argparse
import itertools
import sys
import time
from pathlib import Path

import numpy as np
import pyvista as pv

from gogreen_core import Brush, BrushEvent, Sculptor
from gogreen_core.mesh.geometry import vertex_normals
from gogreen_core.mesh.shapes import default_model

HERE = Path(__file__).resolve().parent
PANEL = (640, 560)
#: (kind, title, what Ctrl does, strength, ε in model sizes: the brush reaches 2 ε)
BRUSHES = (
    ("draw", "Draw", "carves", 1.0, 0.025),
    ("clay_strips", "Clay Strips", "digs", 1.5, 0.025),
    ("crease", "Crease", "a sharp ridge", 2.0, 0.025),
    ("flatten", "Flatten", "contrast", 3.0, 0.05),
    ("inflate", "Inflate", "deflates", 1.0, 0.025),
)
STEP = 0.01  # cursor travel per event, model sizes


def stroke_path(vertices: np.ndarray, height: float, step: float) -> np.ndarray:
    """Vertex ids (k,) under a wavy line across the model's front (−y side) at ``height``,
    one every ``step`` model units: where the cursor passes."""
    x = np.arange(-0.75, 0.75, step)
    z = height + 0.12 * np.sin(2.5 * x)
    front = np.flatnonzero(vertices[:, 1] < 0)
    ids = []
    for px, pz in zip(x, z, strict=True):
        gap = (vertices[front, 0] - px) ** 2 + (vertices[front, 2] - pz) ** 2
        ids.append(front[int(np.argmin(gap))])
    return np.array(ids)


def sculpt(sculptor: Sculptor, brush: Brush, path: np.ndarray, amount: float) -> int:
    """One stroke along ``path``: each event from where its vertex is now to where the next
    one is (the cursor on the current surface). Returns the number of events."""
    sculptor.begin_stroke(brush)
    sculptor.stroke_event(BrushEvent(sculptor.vertices[path[0]], amount=amount))
    for a, b in itertools.pairwise(path):
        center = sculptor.vertices[a].copy()
        delta = sculptor.vertices[b] - center
        if np.any(delta):
            sculptor.stroke_event(BrushEvent(center, delta, amount=amount))
    sculptor.end_stroke()
    return len(path)


def figure(out: Path, kind: str, title: str, inverted: str, strength: float, radius: float) -> None:
    vertices, faces = default_model()
    normals = vertex_normals(vertices, faces)
    sculptor = Sculptor(vertices, faces)
    brush = Brush(kind, radius=radius, strength=strength)
    step = STEP * sculptor.model_size
    start = time.perf_counter()
    events = 0
    for height, amount in ((0.3, 1.0), (-0.3, -1.0)):
        events += sculpt(sculptor, brush, stroke_path(vertices, height, step), amount)
    per_event = (time.perf_counter() - start) / events
    motion = np.einsum("ij,ij->i", sculptor.vertices - vertices, normals)
    scale = 2 * radius * sculptor.model_size
    print(
        f"{kind}: {events} events, {1e3 * per_event:.1f} ms each; motion along the normal "
        f"{motion.max() / scale:+.3f} … {motion.min() / scale:+.3f} of the brush radius"
    )
    mesh = pv.PolyData(sculptor.vertices, np.hstack([np.full((len(faces), 1), 3), faces]).ravel())
    mesh["motion along the normal"] = motion
    plotter = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(2 * PANEL[0], PANEL[1]))
    plotter.set_background("white")
    limit = max(abs(motion).max(), 1e-12)
    for column in range(2):
        plotter.subplot(0, column)
        if column == 0:
            plotter.add_mesh(mesh, color="#c8b89a", smooth_shading=True, specular=0.3)
            label = f"{title}: upper stroke plain, lower with Ctrl ({inverted})"
        else:
            plotter.add_mesh(
                mesh,
                scalars="motion along the normal",
                cmap="coolwarm",
                clim=(-limit, limit),
                smooth_shading=True,
                scalar_bar_args={"title": "motion along the normal", "n_labels": 3},
            )
            label = "red: moved out, blue: moved in"
        plotter.add_text(label, font_size=10, color="black")
        plotter.camera_position = [(0.0, -5.2, 0.6), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    plotter.screenshot(str(out / f"detail_{kind}.png"))
    plotter.close()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("-o", "--output", default=str(HERE.parent / "docs" / "figures"))
    parser.add_argument("--only", help="one brush kind, e.g. draw")
    args = parser.parse_args(argv)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    for kind, title, inverted, strength, radius in BRUSHES:
        if args.only in (None, kind):
            figure(out, kind, title, inverted, strength, radius)
    return 0


if __name__ == "__main__":
    sys.exit(main())
