"""numba's thread count for a block of work, restored afterwards."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import numba

__all__ = ["threads_at_most"]


@contextmanager
def threads_at_most(limit: int) -> Iterator[int]:
    """Run the block with at most ``limit`` numba threads (this thread's setting); yields the
    count in force. For small work a second thread only adds its wake-up."""
    threads = numba.get_num_threads()
    if limit >= threads:
        yield threads
        return
    numba.set_num_threads(limit)
    try:
        yield limit
    finally:
        numba.set_num_threads(threads)
