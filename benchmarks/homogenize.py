"""Benchmark of gogreen_core.physics.homogenization: median wall time per pattern, grid size and
contrast.

Targets (issue "Bimaterial homogenization"): 16^3 <= 300 ms so the contrast slider feels live,
32^3 <= 5 s, on a 2-core machine, up to contrast 1e4. Prints figures, never asserts.

    python3 benchmarks/homogenize.py                 # 16^3 and 32^3, contrasts 10, 100, 1e4
    python3 benchmarks/homogenize.py --sizes 16 --repeats 9
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np

from gogreen_core.physics.homogenization import bimaterial, homogenize_detailed
from gogreen_core.physics.patterns import make_pattern
from gogreen_core.physics.symmetry import describe_symmetry

CASES: list[tuple[str, dict]] = [
    ("layered", {"normal": "z", "fraction": 0.5}),
    ("fibers", {"axis": "z", "fraction": 0.3}),
    ("checkerboard", {}),
    ("spheres", {"fraction": 0.3}),
    ("lattice", {"fraction": 0.3}),
    ("random", {"fraction": 0.5, "seed": 0}),
    ("random", {"fraction": 0.3, "seed": 0, "correlation": 0.08}),
]


def label(name: str, params: dict) -> str:
    extra = ",".join(f"{k}={v}" for k, v in params.items() if k not in ("seed",))
    return f"{name}({extra})" if extra else name


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[16, 32])
    parser.add_argument("--contrasts", type=float, nargs="+", default=[10.0, 100.0, 1e4])
    parser.add_argument("--repeats", type=int, default=0, help="0: 7 for n <= 16, else 3")
    args = parser.parse_args()

    print(f"cpus: {os.cpu_count()}  (numba threads: {__import__('numba').get_num_threads()})")
    t0 = time.perf_counter()
    homogenize_detailed(make_pattern("random", 4), bimaterial())  # JIT compile / cache load
    print(f"first call (numba compile or cache load): {time.perf_counter() - t0:.2f} s\n")

    worst: dict[int, float] = {}
    header = f"{'n':>3} {'pattern':<40} {'contrast':>8} {'iters':>5} {'median':>9}  {'class'}"
    print(header)
    print("-" * len(header))
    for n in args.sizes:
        repeats = args.repeats or (7 if n <= 16 else 3)
        for name, params in CASES:
            ph = make_pattern(name, n, **params)
            for contrast in args.contrasts:
                mats = bimaterial(1.0, 0.3, contrast)
                times, res = [], None
                for _ in range(repeats):
                    res = homogenize_detailed(ph, mats)
                    times.append(res.seconds)
                med = statistics.median(times)
                worst[n] = max(worst.get(n, 0.0), med)
                sym = describe_symmetry(res.material).symmetry_class
                print(
                    f"{n:>3} {label(name, params):<40} {contrast:>8.0e} {res.iterations:>5} "
                    f"{med * 1e3:>7.1f}ms  {sym}"
                )
        print()
    targets = {16: 0.3, 32: 5.0}
    for n, t in worst.items():
        target = f" (target {targets[n] * 1e3:.0f} ms)" if n in targets else ""
        print(f"worst median at {n}^3: {t * 1e3:.1f} ms{target}")
    arr = np.array(list(worst.values()))
    print(f"overall worst median: {arr.max() * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
