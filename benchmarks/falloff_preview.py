"""Cost of the falloff panel's live preview (issue 13): what runs on the GUI thread now, and
what ran there before it moved to the background thread.

    python benchmarks/falloff_preview.py [--repeats 31]

Prints medians and minima (wall ms) and the median CPU ms of one preview update
* after a curve edit (a control point of R₀ moved: new tables, same kernel), and
* after a material change (a new kernel: the SH quadrature of P_lm),
at l_max 8 and 20, for the whole computation (what the GUI thread did before, ``before``:
the spline copy, the kernel swap, G along a radius) and, now, the GUI thread's part (``GUI
now``: the snapshot of the settings, then G at the 64 samples when the kernel arrives) and the
worker's (``worker``: the kernel).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from app.panels.falloff_preview import (
    PREVIEW_SAMPLES,
    PreviewComputer,
    PreviewRequest,
    felt_falloff,
)
from gogreen_core.field.kernel import GreenKernel
from gogreen_core.interaction.settings import Settings
from gogreen_core.interaction.tools import grab_motion
from gogreen_core.physics.material import Material

MATERIALS = [Material.isotropic(1.0, 0.3), Material.cubic(3.0, 1.5, 0.4)]


def measure(run, repeats: int) -> tuple[float, float, float]:
    """(median wall ms, min wall ms, median CPU ms) of ``run()`` (its setup excluded)."""
    wall, cpu = [], []
    for _ in range(repeats):
        step = run()
        t, c = time.perf_counter(), time.process_time()
        step()
        wall.append(1e3 * (time.perf_counter() - t))
        cpu.append(1e3 * (time.process_time() - c))
    return statistics.median(wall), min(wall), statistics.median(cpu)


def edit(settings: Settings, k: int) -> None:
    """Move R₀'s second control point a little (as one step of a drag does)."""
    rho, value = settings.falloff.curve("R", 0)
    value[1] *= 1.0 + 1e-6 * (1 + k)  # a new value every time: no table is cached yet
    settings.falloff = settings.falloff.with_curves({("R", 0): (rho, value)})


def old_update(settings: Settings, kernel: GreenKernel | None, rho: np.ndarray):
    """The GUI-thread update of before: copy the spline, swap (or build) the kernel, G."""
    radial = settings.falloff.with_eps(1.0)
    if kernel is None:
        kernel = GreenKernel(settings.material, settings.l_max, radial)
    magnitude = grab_motion(kernel.with_radial(radial), rho)
    return magnitude / magnitude.max()


def bench(l_max: int, material: Material, rho: np.ndarray, repeats: int) -> None:
    settings = Settings(l_max=l_max, material=material)
    name = f"l_max {l_max}, {'isotropic' if material == MATERIALS[0] else 'cubic'}"
    kernel = GreenKernel(material, l_max, settings.falloff.with_eps(1.0))
    computer = PreviewComputer()
    computer(PreviewRequest.of(settings, rho))  # compiled, its kernel kept
    edits = iter(range(10**9))

    def after_edit(step):
        def setup():
            edit(settings, next(edits))
            return step

        return setup

    def worker_after_edit():
        edit(settings, next(edits))
        request = PreviewRequest.of(settings, rho)
        return lambda: computer.kernel(request)

    def gui_after_edit():
        edit(settings, next(edits))
        kernel = computer.kernel(PreviewRequest.of(settings, rho))
        return lambda: (PreviewRequest.of(settings, rho), felt_falloff(kernel, rho))

    def worker_new_material():
        fresh = PreviewComputer()  # no kernel kept: the quadrature of a new material
        request = PreviewRequest.of(settings, rho)
        return lambda: fresh.kernel(request)

    cases = {
        "curve edit, before (all on the GUI thread)": after_edit(
            lambda: old_update(settings, kernel, rho)
        ),
        "curve edit, GUI now (snapshot, 64 samples)": gui_after_edit,
        "curve edit, worker": worker_after_edit,
        "material change, before (GUI thread)": lambda: lambda: old_update(settings, None, rho),
        "material change, worker": worker_new_material,
    }
    for label, setup in cases.items():
        print(ROW.format(f"{name}: {label}", *measure(setup, repeats)))


ROW = "{:<58} {:>8.2f} {:>8.2f} {:>8.2f}"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=31)
    repeats = parser.parse_args().repeats
    rho = np.linspace(0.0, 4.0, PREVIEW_SAMPLES)
    print(f"{'falloff preview update (ms)':<58} {'median':>8} {'min':>8} {'cpu':>8}")
    for l_max in (8, 20):
        for material in MATERIALS:
            bench(l_max, material, rho, repeats)


if __name__ == "__main__":
    main()
