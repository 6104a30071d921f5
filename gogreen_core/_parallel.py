"""Serial numba functions run over ranges of work on a small thread pool.

:func:`run_ranges` splits the work of the serial, GIL-releasing evaluation functions into
ranges run on up to ``numba.get_num_threads()`` threads, the caller among them. Unlike numba's
``parallel=True`` they compile several times faster, two threads (GUI and background) may
evaluate at once, and no OpenMP worker spins on shared cores; each range is computed
independently, so results do not depend on the thread count. Each range calls the compiled
entry point directly (found once per call from a key of the argument types): typing a
23-element tuple argument in Python costs ~0.2 ms a call, this ~15 µs a range.
"""

from __future__ import annotations

import itertools
import threading
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from typing import Any

import numba
import numpy as np
from numba.core.ccallback import CFunc

__all__ = ["run_ranges"]

#: Ranges per thread at most, handed out as threads ask, each 1 / (2 threads) of what is left
#: (guided): the last small, so a thread slowed by other programs does not hold the others up,
#: and few calls (each unboxes its arguments: 9 µs for a streamline pass).
RANGES_PER_THREAD = 32

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


#: numba's argument types of the calls :func:`run_ranges` made, by dispatcher and type key.
_signatures: dict[tuple[Any, ...], tuple[Any, ...]] = {}


def _type_key(value: Any) -> Any:
    """What numba's type of an argument depends on, for the values the drivers take (arrays,
    tuples of them, bools, ints, floats, C callbacks); None for any other (then typed anew)."""
    if isinstance(value, np.ndarray):
        flags = value.flags
        layout = "C" if flags.c_contiguous else ("F" if flags.f_contiguous else "A")
        return (value.dtype.str, value.ndim, layout, flags.writeable, flags.aligned)
    if isinstance(value, tuple):  # (a named tuple's type is part of numba's)
        keys = tuple(_type_key(v) for v in value)
        return None if None in keys else (type(value), keys)
    if isinstance(value, (bool, float)):
        return type(value)
    if isinstance(value, int):
        return (int, value.bit_length() > 63)
    if isinstance(value, CFunc):
        callback: Any = value  # (numba's signature attribute carries no type)
        return callback._sig
    return None


def _entry_point(work: Callable[[int, int], None]) -> Callable[[int, int], None]:
    """``work``, a ``partial`` of a numba dispatcher, as a ``partial`` of the compiled entry
    point it would choose (no typing of the arguments); ``work`` itself when there is none yet
    or it cannot be told (numba's ``overloads`` is not public API)."""
    if not isinstance(work, partial) or work.keywords:
        return work
    overloads = getattr(work.func, "overloads", None)
    if not isinstance(overloads, dict):
        return work
    args = (*work.args, 0, 0)
    try:
        key = _type_key(args)
        signature = None if key is None else _signatures.get((work.func, key))
        if signature is None:
            signature = tuple(numba.typeof(a) for a in args)
            if key is not None:
                _signatures[work.func, key] = signature
        entry = overloads[signature].entry_point
    except Exception:
        return work
    return partial(entry, *work.args)


def run_ranges(work: Callable[[int, int], None], n_items: int, min_items: int) -> None:
    """Call ``work(first, last)`` over ranges covering [0, n_items) in order-independent pieces
    of at least ``min_items`` items, on up to ``numba.get_num_threads()`` threads (the caller
    runs ranges too). Exceptions propagate."""
    if n_items <= 0:
        return
    threads = numba.get_num_threads()
    n_ranges = min(n_items // max(min_items, 1), threads * RANGES_PER_THREAD)
    work = _entry_point(work)
    if threads <= 1 or n_ranges <= 1:
        work(0, n_items)
        return
    bounds, least = [0], max(n_items // n_ranges, 1)
    while bounds[-1] < n_items:
        share = max((n_items - bounds[-1]) // (2 * threads), least)
        bounds.append(min(bounds[-1] + share, n_items))
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
