"""Render the paper's artistic effects with the engine, off-screen, to PNG (the paper-controls
issue, item 8): what an artist gets from the brushes and presets we ship.

    .venv/bin/python benchmarks/paper_figures.py [-o docs/figures]

(under ``xvfb-run -a`` without a display). Writes, and prints the measured figures behind:

* ``fig10_wrinkle.png``: a flat sheet pulled 2 ε along its normal (top) and dragged 2 ε along
  it (bottom) with the "Layered sheet wrinkles" preset: grab, then the wrinkle brush with fold
  degree 6, 8, 10 (Fig. 10), coloured by the normal displacement (blue down, red up);
* ``fig07_pinch.png``: a pinch on a long tube, ℛ₁ weighted 0.25 (global) and 16 (local)
  (Fig. 7), coloured by the displacement's size;
* ``fig11_stretch.png``: a cube stretched along x at its centre (Fig. 11): Poisson ratios +0.45
  (x–y) / −0.45 (x–z) against an isotropic ν = 0.45, seen along x (the mid-section's outline)
  and from above;
* ``fig09_truncation.png``: δ(l_max), the truncation error of each anisotropic preset (Fig. 9);
* ``dynamic_topology.png``: the default model pulled 0.4 model sizes along its normal (grab
  radius 0.03, 20 events, cubic material) with fixed topology and with dynamic topology (issue
  34), in wireframe, the smallest angle of each triangle in colour;
* ``field_preview.png``: the app's field preview (View → Field Preview) of a grab on the default
  model, soft clay against the fibre composite, dragged along and across the fibres: what
  would move and which way, before the stroke, in the app's colours and arrows.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pyvista as pv
import trimesh

from gogreen_core import (
    Brush,
    BrushEvent,
    Material,
    Sculptor,
    bimaterial,
    builtin_presets,
    homogenize,
    make_pattern,
)
from gogreen_core.field.truncation import truncation_errors
from gogreen_core.mesh.remesh import smallest_angles
from gogreen_core.mesh.shapes import default_model, flat_sheet, open_tube
from gogreen_core.sculpt.brushes import fold_weights
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.preview import field_preview

HERE = Path(__file__).resolve().parent
PANEL = (520, 460)


def _polydata(vertices: np.ndarray, faces: np.ndarray) -> pv.PolyData:
    return pv.PolyData(vertices, np.hstack([np.full((len(faces), 1), 3), faces]).ravel())


def _plotter(columns: int, rows: int = 1) -> pv.Plotter:
    plotter = pv.Plotter(
        off_screen=True, shape=(rows, columns), window_size=(PANEL[0] * columns, PANEL[1] * rows)
    )
    plotter.set_background("white")
    return plotter


def wrinkle_figure(out: Path) -> None:
    preset = next(p for p in builtin_presets() if p.name == "Layered sheet wrinkles")
    vertices, faces = flat_sheet()
    panels = [("grab", None)] + [("wrinkle", degree) for degree in (6, 8, 10)]
    rows = [
        ("pulled 2 eps along the normal", (0.0, 0.0, 1.0)),
        ("dragged 2 eps along y", (0.0, 1.0, 0.0)),
    ]
    plotter = _plotter(len(panels), len(rows))
    for row, (how, direction) in enumerate(rows):
        for column, (kind, degree) in enumerate(panels):
            settings = preset.engine_settings().replace(material_frame="world")  # as measured
            if degree is not None:
                settings = settings.with_brush_weights("wrinkle", fold_weights(10, degree))
            sculptor = Sculptor(vertices, faces, settings=settings)
            eps = 0.05 * sculptor.model_size
            step = 0.2 * eps * np.array(direction)
            start = time.perf_counter()
            sculptor.apply_brush(
                Brush(kind, radius=0.05), [BrushEvent(k * step, step) for k in range(10)]
            )
            seconds = time.perf_counter() - start
            lifted = (sculptor.vertices[:, 2] - vertices[:, 2]) / (2 * eps)
            title = "grab" if degree is None else f"wrinkle, fold degree {degree}"
            print(
                f"fig 10 {title}, {how}: deepest fold {lifted.min():+.2f}, highest "
                f"{lifted.max():+.2f} of the motion ({seconds:.2f} s)"
            )
            mesh = _polydata(sculptor.vertices, faces)
            mesh["normal displacement / motion"] = lifted
            window = mesh.clip_box([-0.85, 0.85, -0.85, 0.85, -1.0, 1.0], invert=False)
            plotter.subplot(row, column)
            plotter.add_mesh(
                window,
                scalars="normal displacement / motion",
                cmap="coolwarm",
                clim=(-0.6, 0.6),
                smooth_shading=True,
                specular=0.4,
                show_scalar_bar=(row, column) == (len(rows) - 1, len(panels) - 1),
                scalar_bar_args={"title": "normal displacement / motion", "n_labels": 3},
            )
            plotter.add_text(f"{title}\n{how}", font_size=10, color="black")
            plotter.camera_position = [(1.7, -2.3, 1.5), (0.0, 0.0, 0.05), (0.0, 0.0, 1.0)]
    plotter.screenshot(str(out / "fig10_wrinkle.png"))
    plotter.close()


def pinch_figure(out: Path) -> None:
    laminate = homogenize(make_pattern("layered", 8), bimaterial(contrast=100.0))
    vertices, faces = open_tube()
    plotter = _plotter(2)
    for column, omega_1 in enumerate((0.25, 16.0)):
        sculptor = Sculptor(vertices, faces, material=laminate)
        omega = sculptor.settings.weights_for("pinch")
        omega[1] = omega_1
        sculptor.apply_settings(sculptor.settings.with_brush_weights("pinch", omega))
        brush = Brush("pinch", radius=0.02)
        top = np.array([1.0, 0.0, 0.0])
        event = BrushEvent(top, amount=0.08, axis=top, direction=[0.0, 0.0, 1.0])
        sculptor.apply_brush(brush, [event] * 4)
        motion = np.linalg.norm(sculptor.vertices - vertices, axis=1)
        eps = brush.eps(sculptor.model_size)
        far = np.linalg.norm(vertices - top, axis=1) > 6 * eps
        ratio = motion[far].max() / motion.max()
        print(
            f"fig 7 ℛ₁ × {omega_1:g}: far (> 6 ε) / peak displacement {ratio:.3f}, influence "
            f"{sculptor.influence(brush):.1f} ε"
        )
        mesh = _polydata(sculptor.vertices, faces)
        mesh["displacement / peak"] = motion / motion.max()
        plotter.subplot(0, column)
        plotter.add_mesh(
            mesh,
            scalars="displacement / peak",
            cmap="magma",
            clim=(0.0, 1.0),
            smooth_shading=True,
            show_scalar_bar=column == 1,
            scalar_bar_args={"title": "displacement / peak", "n_labels": 3},
        )
        label = "global" if omega_1 < 1 else "local"
        plotter.add_text(
            f"pinch, R1 x {omega_1:g} ({label})\nfar / peak {ratio:.2f}",
            font_size=11,
            color="black",
        )
        plotter.camera_position = [(14.0, -4.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
    plotter.screenshot(str(out / "fig07_pinch.png"))
    plotter.close()


def stretch_figure(out: Path) -> None:
    box = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    for _ in range(5):
        box = box.subdivide()
    vertices, faces = np.array(box.vertices), np.array(box.faces)
    materials = {
        "Poisson +0.45 (x-y), -0.45 (x-z)": Material.orthotropic(
            young=(1.0, 1.0, 1.0), shear=(0.4, 0.4, 0.4), poisson=(0.45, -0.45, 0.0)
        ),
        "isotropic, Poisson 0.45": Material.isotropic(1.0, 0.45),
    }
    plotter = _plotter(len(materials), 2)
    for column, (name, material) in enumerate(materials.items()):
        sculptor = Sculptor(vertices, faces, material=material)
        event = BrushEvent(np.zeros(3), amount=0.06, axis=[0, 0, 1], direction=[1, 0, 0])
        sculptor.apply_brush(Brush("stretch", radius=0.3), [event] * 5)
        moved = sculptor.vertices
        mid = np.abs(vertices[:, 0]) < 1e-9
        length = np.ptp(moved[:, 0]) - 1
        width_y, width_z = np.ptp(moved[mid, 1]) - 1, np.ptp(moved[mid, 2]) - 1
        print(
            f"fig 11 {name}: length along x {100 * length:+.1f} %, mid-section along y "
            f"{100 * width_y:+.1f} %, along z {100 * width_z:+.1f} %"
        )
        mesh = _polydata(moved, faces)
        rest = _polydata(vertices, faces)
        # top: the mid-section (x = 0) before (black) and after (red), seen along x
        plotter.subplot(0, column)
        plotter.add_mesh(rest.slice(normal="x"), color="black", line_width=3)
        plotter.add_mesh(mesh.slice(normal="x"), color="#d62728", line_width=5)
        plotter.add_text(
            f"{name}\nmid-section along x: y {width_y:+.1%}, z {width_z:+.1%}",
            font_size=10,
            color="black",
        )
        plotter.camera_position = [(6.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)]
        plotter.enable_parallel_projection()
        plotter.camera.parallel_scale = 0.62
        # bottom: the cube seen from above, the cube before in black
        plotter.subplot(1, column)
        plotter.add_mesh(mesh, color="#c9b49a", smooth_shading=False, specular=0.2)
        plotter.add_mesh(rest.extract_feature_edges(feature_angle=60), color="black", line_width=2)
        plotter.add_text(f"from above: x {length:+.1%}", font_size=10, color="black")
        plotter.camera_position = [(0.0, 0.0, 6.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)]
        plotter.enable_parallel_projection()
        plotter.camera.parallel_scale = 0.75
    plotter.screenshot(str(out / "fig11_stretch.png"))
    plotter.close()


def truncation_figure(out: Path) -> None:
    chart = pv.Chart2D(x_label="l_max", y_label="log10 of the relative error")
    colors = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]
    presets = [
        p
        for p in builtin_presets()
        if p.name not in ("Soft clay", "Rubber (volume preserving)", "Elastic Deform (Kelvinlets)")
    ]
    for color, preset in zip(colors, presets, strict=False):
        report = truncation_errors(preset.material, 20)
        print(
            f"fig 9 {preset.name}: δ(8) {report.error(8):.2e}, δ(12) {report.error(12):.2e}, "
            f"suggested l_max {report.suggested()}"
        )
        x, y = report.degrees.astype(float), np.log10(np.maximum(report.errors, 1e-16))
        chart.line(x, y, color=color, width=3, label=preset.name)
        chart.scatter(x, y, color=color, size=8)
    plotter = pv.Plotter(off_screen=True, window_size=(900, 520))
    plotter.add_chart(chart)
    plotter.screenshot(str(out / "fig09_truncation.png"))
    plotter.close()


def preview_figure(out: Path) -> None:
    from app.field_preview import field_arrows, field_colors  # the app's (Qt is not shown)

    vertices, faces = default_model()
    names = ("Soft clay", "Fibre composite")
    drags = (("along the fibres (z)", (0.0, 0.0, 1.0)), ("across them (y)", (0.0, 1.0, 0.0)))
    plotter = _plotter(len(names), len(drags))
    view = np.array([-1.0, 0.0, 0.0])  # seen from +x: the fibres (z) lie in the picture
    center = vertices[int(np.argmax(vertices[:, 0]))]
    for row, (how, drag) in enumerate(drags):
        for column, name in enumerate(names):
            preset = next(p for p in builtin_presets() if p.name == name)
            sculptor = Sculptor(
                vertices, faces, settings=preset.engine_settings().replace(material_frame="world")
            )
            brush = Brush("grab", radius=0.08)
            eps = brush.eps(sculptor.model_size)
            start = time.perf_counter()
            preview = field_preview(sculptor, brush, center, view, drag)
            seconds = time.perf_counter() - start
            colors = field_colors(np.zeros(len(vertices)))
            colors[preview.rows] = field_colors(preview.motion)
            offsets = vertices[preview.rows] - center
            half = np.linalg.norm(offsets[preview.motion >= 0.5], axis=1).max() / eps
            sideways = np.abs(preview.velocity @ np.cross(view, drag)).max()
            print(
                f"field preview, {name}, a grab {how}: {len(preview.rows):,} vertices in "
                f"{1e3 * seconds:.1f} ms; half the cursor's motion up to {half:.2f} eps; "
                f"sideways motion up to {sideways:.2f} of it"
            )
            mesh = _polydata(vertices, faces)
            mesh["colors"] = colors
            plotter.subplot(row, column)
            plotter.add_mesh(mesh, scalars="colors", rgb=True, smooth_shading=True, specular=0.3)
            shaded = mesh.compute_normals(cell_normals=False, split_vertices=False)
            normals = np.asarray(shaded.point_data["Normals"])
            feet, vectors = field_arrows(vertices, normals, preview, 0.5 * eps, 0.45 * eps)
            arrows = pv.PolyData(feet)
            arrows["v"] = vectors
            plotter.add_mesh(
                arrows.glyph(orient="v", scale="v", geom=pv.Arrow(), factor=1.0),
                color="#1b1f27",
            )
            plotter.add_text(f"{name}: a grab {how}", font_size=10, color="black")
            plotter.camera_position = [
                tuple(center + 6 * eps * np.array([1.0, 0.0, 0.0])),
                tuple(center),
                (0.0, 1.0, 0.0),
            ]
    plotter.screenshot(str(out / "field_preview.png"))
    plotter.close()


def dynamic_topology_figure(out: Path) -> None:
    vertices, faces = default_model()
    top = int(np.argmax(vertices[:, 2]))
    ends = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    median = float(np.median(np.linalg.norm(vertices[ends[:, 0]] - vertices[ends[:, 1]], axis=1)))
    plotter = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(1100, 1000))
    plotter.set_background("white")
    for column, dynamic in enumerate((False, True)):
        settings = EngineSettings(material=Material.cubic(3.0, 1.5, 0.4), dynamic_topology=dynamic)
        sculptor = Sculptor(vertices, faces, settings=settings)
        step = np.array([0.0, 0.0, 0.02 * sculptor.model_size])
        start = time.perf_counter()
        sculptor.apply_brush(
            Brush("grab", radius=0.03),
            [BrushEvent(vertices[top] + k * step, step) for k in range(20)],
        )
        seconds = time.perf_counter() - start
        pulled, cells = sculptor.vertices, sculptor.faces
        smallest = smallest_angles(pulled[cells])
        ends = np.concatenate([cells[:, [0, 1]], cells[:, [1, 2]], cells[:, [2, 0]]])
        longest = np.linalg.norm(pulled[ends[:, 0]] - pulled[ends[:, 1]], axis=1).max()
        title = "dynamic topology" if dynamic else "fixed topology"
        print(
            f"dynamic topology figure, {title}: {len(pulled):,} vertices, longest edge "
            f"{longest / median:.1f} x the model's median, smallest angle {smallest.min():.1f} deg "
            f"({seconds:.1f} s)"
        )
        mesh = _polydata(pulled, cells)
        mesh.cell_data["smallest angle (deg)"] = smallest
        window = mesh.clip_box([-0.4, 0.4, -0.4, 0.4, 0.7, 3.0], invert=False)
        plotter.subplot(0, column)
        plotter.add_mesh(
            window,
            scalars="smallest angle (deg)",
            cmap="viridis",
            clim=(0.0, 60.0),
            show_edges=True,
            edge_color="black",
            line_width=0.6,
            show_scalar_bar=column == 1,
            scalar_bar_args={
                "title": "smallest angle (deg)",
                "n_labels": 4,
                "vertical": False,  # top right, clear of the spike in the middle
                "position_x": 0.58,
                "position_y": 0.86,
                "width": 0.38,
                "height": 0.08,
            },
        )
        plotter.add_text(title, font_size=11, color="black")
        plotter.camera_position = [(0.0, -3.3, 1.72), (0.0, 0.0, 1.72), (0.0, 0.0, 1.0)]
    plotter.screenshot(str(out / "dynamic_topology.png"))
    plotter.close()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("-o", "--output", default=str(HERE.parent / "docs" / "figures"))
    parser.add_argument("--only", help="one figure's function name, e.g. dynamic_topology_figure")
    args = parser.parse_args(argv)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    figures = (
        wrinkle_figure,
        pinch_figure,
        stretch_figure,
        truncation_figure,
        preview_figure,
        dynamic_topology_figure,
    )
    for make in figures:
        if args.only in (None, make.__name__):
            make(out)
    print(f"wrote the figures to {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
