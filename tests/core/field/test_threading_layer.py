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
