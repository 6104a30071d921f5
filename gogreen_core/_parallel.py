"""Serial numba functions run over ranges of work on a small thread pool.

The evaluation functions of ``_expansion`` and ``_integrator`` are serial and release the GIL
(``nogil=True``); :func:`run_ranges` splits their work into ranges and runs them on up to
``numba.get_num_threads()`` threads, the calling thread being one of them. Compared with numba's
``parallel=True`` (which the drivers used before): the functions compile several times faster
(a parfor is lowered through extra passes and outlined into a gufunc per loop), two threads may
evaluate at once (the app's GUI and background threads) whatever numba's threading layer, and
no OpenMP worker spins on cores shared with other programs. Each range is computed
independently of the split, so results do not depend on the thread count.
"""

from __future__ import annotations

import itertools
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import numba

__all__ = ["run_ranges"]

#: Ranges per thread: several, handed out as threads ask for them, so that a thread slowed by
#: other programs on the shared cores does not hold the others up.
RANGES_PER_THREAD = 4

_pool: ThreadPoolExecutor | None = None
_pool_lock = threading.Lock()


def _executor() -> ThreadPoolExecutor:
    global _pool
    with _pool_lock:
        if _pool is None:
            config: Any = numba.config  # its settings are read from the environment: untyped
            _pool = ThreadPoolExecutor(
                max_workers=max(1, config.NUMBA_NUM_THREADS - 1),
                thread_name_prefix="gogreen-eval",
            )
        return _pool


def run_ranges(work: Callable[[int, int], None], n_items: int, min_items: int) -> None:
    """Call ``work(first, last)`` over ranges covering [0, n_items) in order-independent pieces
    of at least ``min_items`` items, on up to ``numba.get_num_threads()`` threads (the caller
    runs ranges too). Exceptions propagate."""
    threads = numba.get_num_threads()
    n_ranges = min(n_items // max(min_items, 1), threads * RANGES_PER_THREAD)
    if threads <= 1 or n_ranges <= 1:
        if n_items > 0:
            work(0, n_items)
        return
    bounds = [n_items * k // n_ranges for k in range(n_ranges + 1)]
    # next() on this iterator is one C call under the GIL: each range goes to one thread
    ranges = itertools.pairwise(bounds)

    def drain() -> None:
        for first, last in ranges:
            work(first, last)

    helpers = [_executor().submit(drain) for _ in range(min(threads, n_ranges) - 1)]
    try:
        drain()
    finally:
        for helper in helpers:
            helper.result()
