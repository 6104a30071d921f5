"""Cost of safe falloffs (issue 13, item 4): what the per-event load normalization adds.

    python benchmarks/falloff_safety.py [--repeats 200]

Prints medians (ms) of
* the one-time sampling of a kernel's field bound (on the first event after a material,
  falloff, l_max or influence change; cached per kernel, whatever the brush radius);
* per event: the bound look-ups a brush's ``load`` adds, the whole ``load`` and the centre
  normalization alone (G(0) solve, or the centre Jacobian), for a Gaussian falloff and for
  edited ones (R₀(0) = 0, ℛ₁ flat near 0), which take the rescaling path.
"""

from __future__ import annotations

import argparse
import statistics
import time
from functools import partial

import numpy as np

from gogreen_core import Brush, BrushEvent, Material, Sculptor
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.physics.radial import GaussianRadial, SplineRadial
from gogreen_core.sculpt.brushes import affine_load_shape
from gogreen_core.sculpt.brushes.affine import centre_jacobian
from gogreen_core.sculpt.falloff_safety import FieldBound

MATERIAL = Material.cubic(3.0, 1.5, 0.4).rotated(
    np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])
)


def median_ms(run, repeats: int) -> float:
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        samples.append(1e3 * (time.perf_counter() - start))
    return statistics.median(samples)


def sample_bound(kernel, affine: bool, load: np.ndarray) -> None:
    """Sample the field bound and build the tables its first look-ups use."""
    bound = FieldBound(kernel, 4.0, affine)
    bound.motion_sup(load, 1.0)
    bound.strain_sup(load, 1.0)


def edited(l_max: int, kind: str, l: int, count: int) -> SplineRadial:
    falloff = SplineRadial.from_profile(GaussianRadial(1.0), l_max)
    rho, value = falloff.curve(kind, l)
    value[:count] = 0.0
    return falloff.with_curves({(kind, l): (rho, value)})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=200)
    args = parser.parse_args()
    vertices, faces = icosphere(3)

    print(f"{'one-time field bound per kernel':<52} {'median ms':>10}")
    for l_max in (8, 16):
        sculptor = Sculptor(vertices, faces, material=MATERIAL, l_max=l_max)
        for kind in ("grab", "twist"):
            brush = Brush(kind)
            kernel = sculptor.kernel(brush)
            kernel.warm_up()
            load = affine_load_shape(kind, None, None) if brush.is_affine else np.ones(3)
            ms = median_ms(partial(sample_bound, kernel, brush.is_affine, load), 5)
            print(f"{f'l_max {l_max}, {kind} (influence 4 ε)':<52} {ms:>10.1f}")

    keep = []  # live splines: radial.py keys its table cache by id()
    print(f"\n{'per event, l_max 8 (ms)':<36} {'checks':>8} {'load':>8} {'centre only':>12}")
    for name, falloff in (
        ("gaussian", GaussianRadial(1.0)),
        ("R0(0) = 0", edited(8, "R", 0, 1)),
        ("dR1 flat near 0", edited(8, "dR", 1, 6)),
    ):
        keep.append(falloff)
        sculptor = Sculptor(vertices, faces, material=MATERIAL, falloff=falloff)
        for kind in ("grab", "grab_biscale", "wrinkle", "twist"):
            if name == "dR1 flat near 0" and kind != "twist":
                continue
            times = event_times(sculptor, Brush(kind), vertices[0], args.repeats)
            print(f"{f'{name}, {kind}':<36} {times[0]:>8.3f} {times[1]:>8.3f} {times[2]:>12.3f}")
    print(
        "checks: the bound look-ups the load adds; load: the brush type's load; centre "
        "only: G(0) solve or centre Jacobian\n(the numba calls inside the last two take ~20 ms "
        "whenever other processes hold the cores: read the minimum of several runs)"
    )


def event_times(
    sculptor: Sculptor, brush: Brush, center: np.ndarray, repeats: int
) -> tuple[float, float, float]:
    """Medians (ms) of the added bound checks, of the whole load, of the centre alone."""
    event = BrushEvent(center, delta=[0.01, 0.02, 0.0], amount=0.1, axis=center)
    kernel = sculptor.kernel(brush)
    behaviour = brush.type
    context = sculptor._strokes.context(sculptor._kernels)  # what the brush sees
    load, _ = behaviour.load(context, brush, kernel, event)  # samples the bound (cached now)
    eps = kernel.eps
    shape = np.eye(3)
    full = sculptor.kernel(Brush("grab", radius=brush.radius)).with_radial(kernel.radial)

    def checks() -> None:
        bound = behaviour.field_bound(context, brush, kernel)
        if brush.is_affine:  # includes the Gaussian reference's centre Jacobian (numba)
            bound.motion_sup(shape, eps)
            bound.strain_sup(shape, eps)
            behaviour.limits(context, brush, shape)
            context.kernels.green_scale  # noqa: B018
        else:
            bound.motion_sup(load, eps)
            bound.strain_sup(load, eps)

    def whole() -> None:
        behaviour.load(context, brush, kernel, event)

    def centre_only() -> None:
        if brush.is_affine:
            centre_jacobian(kernel, center, shape)
        else:
            np.linalg.solve(full.green(np.zeros((1, 3)))[0], event.delta)

    return tuple(median_ms(run, repeats) for run in (checks, whole, centre_only))


if __name__ == "__main__":
    main()
