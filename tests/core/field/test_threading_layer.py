"""numba's parallel layer must accept launches from two threads at once.

The app runs compiled parallel code on its background worker (kernel warm-up, homogenization,
falloff preview tables) while the GUI thread runs a stroke. numba's OpenMP and TBB layers allow
that; its fallback "workqueue" layer aborts the whole process ("Concurrent access has been
detected"). scripts/setup_env.sh installs GNU OpenMP (libgomp1) for this reason.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import njit, prange


@njit(parallel=True)
def _total(values):
    out = 0.0
    for i in prange(values.shape[0]):
        out += values[i]
    return out


def test_parallel_layer_is_thread_safe():
    assert _total(np.ones(1000)) == 1000.0
    layer = numba.threading_layer()
    assert layer in ("omp", "tbb"), (
        f"numba uses its {layer!r} threading layer, which aborts the app when the worker and "
        "the GUI thread run parallel code at once; install GNU OpenMP (Debian: libgomp1, done "
        "by scripts/setup_env.sh) or the tbb package"
    )


def test_run_ranges_covers_the_items_in_few_shrinking_ranges():
    """The thread pool's ranges (``_parallel.run_ranges``): every item once, at least
    ``min_items`` a range, a guided schedule (each range a share of what is left, the last
    ones small) rather than 32 equal ranges a thread: each call unboxes its arguments anew."""
    import itertools
    import threading

    import pytest

    from gogreen_core import _parallel

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("needs two threads")
    threads = numba.get_num_threads()
    numba.set_num_threads(2)
    lock, ranges = threading.Lock(), []

    def work(first: int, last: int) -> None:
        with lock:
            ranges.append((first, last))

    try:
        _parallel.run_ranges(work, 493, 2)  # a 1M-vertex event's first pass, in blocks
    finally:
        numba.set_num_threads(threads)
    ranges.sort()
    assert ranges[0][0] == 0 and ranges[-1][1] == 493
    assert all(a[1] == b[0] for a, b in itertools.pairwise(ranges))
    sizes = [last - first for first, last in ranges]
    assert min(sizes) >= 2 and sizes == sorted(sizes, reverse=True)
    assert len(ranges) <= 16  # guided: few calls, each unboxes its arguments
    assert sizes[-1] <= 493 // 64 + 1  # the last as small as 64 equal ones
