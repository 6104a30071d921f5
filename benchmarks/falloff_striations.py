"""The striations along a stroke's rim after a falloff edit (issue 21 item 8), measured.

    python benchmarks/falloff_striations.py [--grid 401]

The edit of the issue: the default falloff (the Gaussian sampled at the default control
points), its R₀ raised by 0.3 at ρ = 2. Prints, for the interpolating cubic spline (what the
falloffs saved before use), the monotone curve (new falloffs) and, for reference, SciPy's
PCHIP:

1. the curve: where the edited R₀ turns (new extrema are dips and bumps the artist did not
   make), how far its curvature changes away from the edit, and how close the unedited curves
   are to the Gaussian they sample (value and curvature);
2. one event's field: where a grab's motion profile turns (each turn is a ring of the field);
3. a stroke: a 40-event raising grab along x on a flat grid (--grid² vertices), and the mean
   |second difference| of the surface normal across the stroke (what the shading shows) in
   bands of distance ρ from its path, against the unedited stroke: the rings of (2) swept along
   the path are the striations.
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.interpolate import PchipInterpolator

from gogreen_core import Brush, BrushEvent, Material, Sculptor
from gogreen_core.field.kernel import GreenKernel
from gogreen_core.interaction.tools import grab_motion
from gogreen_core.mesh.geometry import vertex_normals
from gogreen_core.physics.radial import GaussianRadial, SplineRadial

L_MAX = 8
RAISE = 0.3
BANDS = ((0.3, 1.5), (1.5, 2.6), (2.6, 3.2), (3.2, 4.5))


def turns(values: np.ndarray, x: np.ndarray) -> np.ndarray:
    step = np.diff(values)
    return x[np.flatnonzero(np.sign(step[1:]) * np.sign(step[:-1]) < 0) + 1]


def falloffs(interpolation: str) -> tuple[SplineRadial, SplineRadial]:
    """The default falloff and the issue's edit of it, or PCHIP curves through the same
    points ("pchip": SciPy's interpolant swapped in, for comparison only)."""
    spline = SplineRadial.from_profile(
        GaussianRadial(1.0),
        L_MAX,
        interpolation="cubic" if interpolation == "cubic" else "monotone",
    ).as_value()
    rho, value = spline.curve("R", 0)
    index = int(np.flatnonzero(rho == 2.0)[0])
    edited = spline.with_point_moved("R", 0, index, 2.0, value[index] + RAISE)
    if interpolation == "pchip":
        for curve in (spline, edited):
            curve._splines = {
                key: PchipInterpolator(*points) for key, points in curve._curves.items()
            }
            curve._digest = f"pchip {id(curve)}"  # its own radial tables
    return spline, edited


def curves() -> None:
    print("1. the curve R₀ (edit: +0.3 at ρ = 2)")
    x = np.linspace(0.0, 6.0, 60001)
    exact = GaussianRadial(1.0).dimensionless("R", 0, x)
    exact2 = np.gradient(np.gradient(exact, x), x)
    inner = (x > 0.05) & (x < 5.0)
    for interpolation in ("cubic", "monotone", "pchip"):
        before, after = falloffs(interpolation)
        b, a = before.dimensionless("R", 0, x), after.dimensionless("R", 0, x)
        b2 = np.gradient(np.gradient(b, x), x)
        change2 = np.abs(np.gradient(np.gradient(a - b, x), x))
        print(
            f"   {interpolation:8s} edited turns at ρ = {np.round(turns(a, x), 2)}; "
            f"|ΔF″| on [2.6, 3]: {change2[(x > 2.6) & (x < 3)].max():.3f}, on [3, 4]: "
            f"{change2[(x > 3) & (x < 4)].max():.3f}; unedited vs Gaussian: "
            f"|F − G| ≤ {np.abs(b - exact).max():.1e}, "
            f"|F″ − G″| ≤ {np.abs(b2 - exact2)[inner].max():.3f}"
        )


def fields() -> None:
    print("2. one grab event's motion profile (isotropic, l_max 8): where it turns")
    material = Material.isotropic(1.0, 0.3)
    r = np.linspace(0.0, 4.0, 8001)
    for interpolation in ("cubic", "monotone", "pchip"):
        for name, falloff in zip(("unedited", "edited"), falloffs(interpolation), strict=True):
            motion = grab_motion(GreenKernel(material, L_MAX, falloff), r)
            print(f"   {interpolation:8s} {name:8s} rings at ρ = {np.round(turns(motion, r), 3)}")


def stroke(n: int) -> None:
    print(f"3. a 40-event stroke on a {n}×{n} grid: shading curvature across it, by band of ρ")
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n), indexing="ij")
    vertices = np.stack([x.ravel(), y.ravel(), np.zeros(n * n)], axis=1)
    index = np.arange(n * n).reshape(n, n)
    quads = np.stack(
        [index[:-1, :-1], index[1:, :-1], index[1:, 1:], index[:-1, 1:]], axis=-1
    ).reshape(-1, 4)
    faces = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    path = np.linspace(-0.5, 0.5, 41)
    events = [
        BrushEvent([path[k], 0.0, 0.004 * k], [path[1] - path[0], 0.0, 0.004]) for k in range(40)
    ]
    eps = 0.05 * np.sqrt(8.0)
    rho = np.abs(np.linspace(-1, 1, n))[1:-1] / eps
    rows = slice(n // 2 - n // 10, n // 2 + n // 10)  # the middle of the stroke
    cases = [("Gaussian", GaussianRadial(1.0))]
    for interpolation in ("cubic", "monotone", "pchip"):
        before, after = falloffs(interpolation)
        cases += [(f"{interpolation} unedited", before), (f"{interpolation} edited", after)]
    print("   " + " " * 18 + "  ".join(f"[{a}, {b}]".rjust(10) for a, b in BANDS))
    for name, falloff in cases:
        sculptor = Sculptor(vertices, faces, falloff=falloff, l_max=L_MAX)
        sculptor.apply_brush(Brush("grab", radius=0.05), events)
        normals = vertex_normals(sculptor.vertices, faces).reshape(n, n, 3)
        curvature = np.abs(np.diff(normals[rows, :, 1], 2, axis=1)).mean(axis=0)
        bands = [curvature[(rho > a) & (rho < b)].mean() for a, b in BANDS]
        print(f"   {name:18s}" + "  ".join(f"{v:10.2e}" for v in bands))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grid", type=int, default=401)
    args = parser.parse_args()
    curves()
    fields()
    stroke(args.grid)


if __name__ == "__main__":
    main()
