"""Benchmark of GreenKernel: precompute time, vector/affine throughput, first-call compile time.

Targets (issue "Numerics core"), on the 2-core reference machine, anisotropic material:
precompute ≤ 50 ms at l_max = 8 and ≤ 300 ms at l_max = 20; l_max = 8 vector load on 10⁶ points
≤ 100 ms and at most 3× a numba closed-form isotropic Kelvinlet on the same points in the same run.

The last lines put the ratio in perspective: the floating-point operations per point of the
generated angular sum and of the radial polynomials, timed at the best rate this machine reaches
for them, give the arithmetic floor of the expansion before geometry and memory traffic (which
alone take about the Kelvinlet's time). The current evaluation fuses no multiply-add (its NumPy
twin, which serves until it is compiled, has none); the floor with fused multiply-adds, which
evaluation 1 had, is printed beside it, and evaluation 1's throughput in the same run.

    python benchmarks/kernel.py                 # all sizes, l_max 4, 8, 20
    python benchmarks/kernel.py --sizes 10000 --repeats 3

Prints figures only; nothing here is asserted.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numba
import numpy as np

from gogreen_core import GaussianRadial, GreenKernel, KelvinletRadial, Material
from gogreen_core.field import kernel as kernel_module
from gogreen_core.field._expansion import SEGMENT_DEGREE
from gogreen_core.field._unrolled import UNROLLED_L_MAX, angular_source
from gogreen_core.field.kernel import prepare_degree
from gogreen_core.physics import radial_tables as radial_module


@numba.njit(parallel=True, cache=True, fastmath=True)
def kelvinlet_closed_form(points, center, force, eps, mu, nu):  # pragma: no cover - compiled
    """de Goes & James 2017 regularized Kelvinlet u = [(a-b)/rε I + b/rε³ rrᵀ + aε²/(2rε³) I] f."""
    a = 1.0 / (4.0 * np.pi * mu)
    b = a / (4.0 * (1.0 - nu))
    out = np.empty_like(points)
    for n in numba.prange(points.shape[0]):
        x = points[n, 0] - center[0]
        y = points[n, 1] - center[1]
        z = points[n, 2] - center[2]
        re2 = x * x + y * y + z * z + eps * eps
        inv = 1.0 / np.sqrt(re2)
        inv3 = inv * inv * inv
        rf = x * force[0] + y * force[1] + z * force[2]
        diag = (a - b) * inv + 0.5 * a * eps * eps * inv3
        out[n, 0] = diag * force[0] + b * inv3 * rf * x
        out[n, 1] = diag * force[1] + b * inv3 * rf * y
        out[n, 2] = diag * force[2] + b * inv3 * rf * z
    return out


#: Effective stiffness of round fibres (fraction ~0.3) in a matrix 10⁴ times softer, axis z
#: (homogenize(make_pattern("fibers", 16), bimaterial(contrast=1e4)), rounded).
FIBRES_VOIGT = np.diag([0.0, 0.0, 0.0, 0.747, 0.747, 0.615])
FIBRES_VOIGT[:3, :3] = [[2.357, 0.800, 0.947], [0.800, 2.357, 0.947], [0.947, 0.947, 2970.0]]


def timed(function, repeats: int) -> float:
    """Median wall time of ``function()`` in milliseconds."""
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        samples.append(1e3 * (time.perf_counter() - start))
    return statistics.median(samples)


def clear_caches() -> None:
    """Forget Lebedev nodes and radial tables so the next build is a cold start."""
    kernel_module.lebedev_points.cache_clear()
    radial_module._TABLE_CACHE.clear()


_FIRST_CALL = """
import time, numpy as np
start = time.perf_counter()
from gogreen_core import GreenKernel, Material
from gogreen_core.field.kernel import prepare_degree
k = GreenKernel(Material.cubic(3.0, 1.5, 0.4), l_max=8)
k.displacement(np.ones((4, 3)), np.zeros(3), np.ones(3))
k.affine_displacement(np.ones((4, 3)), np.zeros(3), np.eye(3))
first = 1e3 * (time.perf_counter() - start)
prepare_degree(8)  # the compiled code, brought in the background meanwhile
print(first, 1e3 * (time.perf_counter() - start))
"""


_DEGREE_COMPILE = """
import sys
from gogreen_core.field.kernel import prepare_degree
print(1e3 * prepare_degree(int(sys.argv[1])))
"""


def angular_operations(l_first: int, l_last: int) -> tuple[int, int]:
    """(multiplications, additions and subtractions) per point in the generated angular
    kernel: its arithmetic, each one instruction (with fused multiply-adds every addition would
    fuse into a multiplication)."""
    body = angular_source(l_first, l_last).split("for i in range(nb):")[1]
    return body.count("*"), body.count(" + ") + body.count(" - ")


_CHAINS, _STEPS = 8, 32


def multiply_add_rate(n_points: int = 1_000_000, fused: bool = True) -> float:
    """Multiply-adds per second this machine sustains (all threads) in straight-line code
    vectorized across points, as the generated kernels are: 8 independent chains of 32 steps;
    ``fused``: each one instruction, else a multiplication and an addition."""
    contract = "{'contract'}" if fused else "False"
    lines = [
        f"@numba.njit(parallel=True, fastmath={contract}, error_model='numpy')",
        "def chains(x, out):",
        "    for n in numba.prange(x.shape[0]):",
        "        v = x[n]",
    ]
    lines += [f"        s{c}_0 = v * {c + 1}.0" for c in range(_CHAINS)]
    for step in range(1, _STEPS + 1):
        lines += [f"        s{c}_{step} = s{c}_{step - 1} * v + 0.{c + 1}" for c in range(_CHAINS)]
    lines.append("        out[n] = " + " + ".join(f"s{c}_{_STEPS}" for c in range(_CHAINS)))
    namespace = {"numba": numba}
    exec("\n".join(lines), namespace)  # our own generated code, for this measurement only
    chains = namespace["chains"]
    x = np.random.default_rng(1).uniform(0.0, 0.5, n_points)
    out = np.empty_like(x)
    chains(x, out)
    seconds = timed(lambda: chains(x, out), 9) / 1e3
    return _CHAINS * _STEPS * n_points / seconds


def fresh_process_ms(cache_dir: str, script: str, *args: str) -> float | list[float]:
    """Run ``script`` in a fresh interpreter whose numba cache lives in ``cache_dir``; returns
    the milliseconds it prints (a list when it prints several)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    result = subprocess.run(
        [sys.executable, "-c", script, *args], env=env, capture_output=True, text=True, check=True
    )
    values = [float(v) for v in result.stdout.split()]
    return values[0] if len(values) == 1 else values


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    parser.add_argument("--l-max", type=int, nargs="+", default=[4, 8, 20])
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args()

    material = Material.cubic(3.0, 1.5, 0.4).rotated(
        np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])
    )
    eps = 0.3
    print(f"numba {numba.__version__}, {numba.config.NUMBA_NUM_THREADS} threads")
    print("material: cubic C11=3, C12=1.5, C44=0.4 (Zener ratio 0.53), rotated off-axis")

    with tempfile.TemporaryDirectory() as cache_dir:
        first_ms, compiled_ms = fresh_process_ms(cache_dir, _FIRST_CALL)
        cached_ms, _ = fresh_process_ms(cache_dir, _FIRST_CALL)
    print(
        "first call in a fresh process (import, kernel build, vector + affine evaluation): "
        f"{first_ms:.0f} ms with an empty numba cache (compiled code ready after "
        f"{compiled_ms:.0f} ms), {cached_ms:.0f} ms from the cache"
    )
    per_degree = {}
    for l_max in args.l_max:
        if l_max <= UNROLLED_L_MAX:
            with tempfile.TemporaryDirectory() as cache_dir:
                per_degree[l_max] = fresh_process_ms(cache_dir, _DEGREE_COMPILE, str(l_max))
    if per_degree:
        print(
            "compiled code of a new machine for an l_max (drivers and both parities' angular "
            "kernels, compiled once in a child process while NumPy serves): "
            + ", ".join(f"l{l}: {ms:.0f} ms" for l, ms in per_degree.items())
        )
    rng = np.random.default_rng(0)
    kelvinlet_closed_form(rng.normal(size=(8, 3)), np.zeros(3), np.ones(3), eps, 1.0, 0.3)

    print(
        "\nprecompute (GreenKernel construction), ms: first build of each l_max in this process; "
        "median of cold builds (Lebedev nodes and radial tables cleared), of warm builds, of "
        "new-ε copies"
    )
    print(f"{'l_max':>6} {'first':>9} {'cold':>9} {'warm':>9} {'new eps':>9}")
    for l_max in args.l_max:

        def cold_build(l=l_max):
            clear_caches()
            GreenKernel(material, l_max=l, radial=GaussianRadial(eps))

        first = timed(cold_build, 1)
        cold = timed(cold_build, 5)
        warm = timed(lambda l=l_max: GreenKernel(material, l_max=l, radial=GaussianRadial(eps)), 7)
        kernel = GreenKernel(material, l_max=l_max, radial=GaussianRadial(eps))
        new_eps = timed(lambda k=kernel: k.with_eps(0.7), 7)
        print(f"{l_max:>6} {first:>9.1f} {cold:>9.1f} {warm:>9.1f} {new_eps:>9.2f}")
    # M⁻¹ sharply peaked: the graded product rule instead of Lebedev (see quadrature.material_rule)
    fibres = Material.from_voigt(FIBRES_VOIGT).rotated(
        np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])
    )
    print("fibres at contrast 1e4, cold builds, median ms (nodes of the quadrature rule):")
    for l_max in args.l_max:
        ms = timed(lambda l=l_max: GreenKernel(fibres, l_max=l, radial=GaussianRadial(eps)), 3)
        nodes = len(kernel_module.material_rule(fibres, l_max)[0])
        print(f"{l_max:>6} {ms:>9.1f} ({nodes} nodes)")

    print("\nthroughput, median ms (points in a ball of radius 10 ε)")
    header = f"{'N':>9} {'Kelvinlet':>10}"
    for l_max in args.l_max:
        header += f" {'vec l' + str(l_max):>10} {'aff l' + str(l_max):>10}"
    print(header + "   (ratio vec/Kelvinlet at each l_max)")
    force = np.array([0.3, -0.2, 1.0])
    load = np.array([[0.1, 0.4, 0.0], [-0.4, 0.2, 0.1], [0.0, 0.3, -0.3]])
    kernels = {l: GreenKernel(material, l_max=l, radial=GaussianRadial(eps)) for l in args.l_max}
    for l_max in args.l_max:
        prepare_degree(l_max)  # the compiled code (NumPy serves until then)
    legacy = GreenKernel(material, l_max=8, radial=GaussianRadial(eps), evaluation=1)
    iso = GreenKernel(Material.isotropic(2.6, 0.3), l_max=2, radial=KelvinletRadial(eps))
    center = np.zeros(3)
    for n in args.sizes:
        points = rng.normal(size=(n, 3))
        points *= (10 * eps * rng.uniform(0, 1, n) ** (1 / 3) / np.linalg.norm(points, axis=1))[
            :, None
        ]
        reference = kelvinlet_closed_form(points, center, force, eps, 1.0, 0.3)
        assert np.allclose(iso.displacement(points[:100], center, force), reference[:100])
        kelvin = timed(lambda p=points: kelvinlet_closed_form(p, center, force, eps, 1.0, 0.3), 7)
        row, ratios = f"{n:>9} {kelvin:>10.2f}", []
        for l_max, kernel in kernels.items():
            vec = timed(lambda k=kernel, p=points: k.displacement(p, center, force), args.repeats)
            aff = timed(lambda k=kernel, p=points: k.affine_displacement(p, center, load), 5)
            row += f" {vec:>10.2f} {aff:>10.2f}"
            ratios.append(f"l{l_max}: {vec / kelvin:.1f}x")
        print(row + "   (" + ", ".join(ratios) + ")")
        old = timed(lambda p=points: legacy.displacement(p, center, force), args.repeats)
        print(f"{'':>9} evaluation 1 (fused multiply-adds), vec l8: {old:.2f} ms")

    # What the arithmetic alone costs, at the best rates this machine reaches, for the last N.
    fused_rate, rate = multiply_add_rate(), 2 * multiply_add_rate(fused=False)
    print(
        f"\narithmetic floor, vector load, N = {n}: this machine sustains {rate / 1e9:.1f} G "
        f"multiplications or additions/s ({fused_rate / 1e9:.1f} G fused multiply-adds/s) in "
        "vectorized straight-line code"
    )
    for l_max in args.l_max:
        (_, l_last), _ = kernel_module.parity_ranges(l_max)  # even degrees: G, vector load
        if l_last > UNROLLED_L_MAX:
            continue
        multiplies, additions = angular_operations(0, l_last)
        radial = (l_last // 2 + 1) * (SEGMENT_DEGREE + 1)  # Estrin's products and sums, scale
        floor = 1e3 * (multiplies + additions + 2 * radial) * n / rate
        fused = 1e3 * (multiplies + radial) * n / fused_rate
        print(
            f"  l_max {l_max}: {multiplies} + {additions} angular and {2 * radial} radial "
            f"operations per point = {floor:.2f} ms ({floor / kelvin:.1f}x the Kelvinlet); fused "
            f"multiply-adds would make it {fused:.2f} ms; before any geometry or memory traffic"
        )


if __name__ == "__main__":
    main()
