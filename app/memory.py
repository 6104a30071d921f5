"""Giving memory back to the system when a document is replaced.

A mesh of a million vertices takes hundreds of MB (its arrays, the viewport's copies, the
surface index, the renderer's buffers). When another document replaces it, those objects die,
some only at Python's next full garbage collection (reference cycles through the sculptor's
callbacks), and glibc's allocator keeps the freed pages: arrays of up to 32 MB (glibc's
dynamic mmap threshold grows to the size of the biggest mapped block freed) come from its heap,
which it returns to the system only from the top. So the app fixes the threshold (each
array above 1 MB gets pages of its own, returned when freed) at start, and after a document
change collects the cycles and trims the allocator's free pages (``malloc_trim``). Both are
glibc's (Linux); elsewhere they do nothing.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import sys

__all__ = ["MMAP_THRESHOLD", "release_freed_memory", "use_own_pages_for_big_blocks"]

#: Blocks of at least this many bytes get pages of their own (glibc's ``M_MMAP_THRESHOLD``).
MMAP_THRESHOLD = 1 << 20
_M_MMAP_THRESHOLD = -3  # glibc's malloc.h


def _libc() -> ctypes.CDLL | None:
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
    except OSError:
        return None
    return libc if hasattr(libc, "malloc_trim") and hasattr(libc, "mallopt") else None


def use_own_pages_for_big_blocks() -> bool:
    """Fix glibc's mmap threshold at :data:`MMAP_THRESHOLD` (call at start); True if set."""
    libc = _libc()
    return bool(libc is not None and libc.mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD))


def release_freed_memory() -> None:
    """Collect reference cycles now and return the allocator's free pages to the system."""
    gc.collect()
    libc = _libc()
    if libc is not None:
        libc.malloc_trim(0)
