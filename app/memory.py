"""Keeping the app's memory to what it uses, and giving it back when a document is replaced.

A mesh of a million vertices takes hundreds of MB (its arrays, the viewport's copies, the
surface index, the renderer's buffers). When another document replaces it, those objects die,
some only at Python's next full garbage collection (reference cycles through the sculptor's
callbacks), and glibc's allocator keeps the freed pages: arrays of up to 32 MB (glibc's
dynamic mmap threshold grows to the size of the biggest mapped block freed) come from its heap,
which it returns to the system only from the top. So the app fixes the threshold (each
array above 1 MB gets pages of its own, returned when freed) at start, and after a document
change, and once the start-up work is done, collects the cycles and trims the allocator's free
pages (``malloc_trim``). Both are glibc's (Linux); elsewhere they do nothing.

PySide6 reads the source of every module imported after it (``inspect.getsource``, to see
whether it names PySide6: its ``__feature__`` switches), and :mod:`linecache` keeps each
source: about 70 MB for the app's 1,160 modules. :func:`read_sources_uncached` asks PySide6's
question of the file's bytes instead, kept nowhere; :func:`release_freed_memory` drops the
sources cached anyway (tracebacks read them again when needed). And pyvista loads its mypy
plugin whenever mypy is installed (the test tools of the project's environment): 27 MB the
app never uses. :func:`start_lean` does all of this at start.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import gc
import linecache
import os
import sys
from types import ModuleType

__all__ = [
    "MMAP_THRESHOLD",
    "read_sources_uncached",
    "release_freed_memory",
    "start_lean",
    "use_own_pages_for_big_blocks",
]

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


def read_sources_uncached() -> bool:
    """Import PySide6 and let its import hook read the sources of the modules imported after
    it without keeping them (call before the app's imports); True if the hook was found (a
    PySide6 without it keeps nothing)."""
    import PySide6.QtCore  # noqa: F401  (loads the hook's module)

    feature = sys.modules.get("shibokensupport.feature")
    uses_pyside = getattr(feature, "_mod_uses_pyside", None)
    if uses_pyside is None or getattr(uses_pyside, "reads_uncached", False):
        return uses_pyside is not None

    def reads_pyside(module: ModuleType) -> bool:  # the hook's question, of the file's bytes
        path = getattr(module, "__file__", None)
        if not (isinstance(path, str) and path.endswith(".py")):
            return bool(uses_pyside(module))  # no source: the hook answers without caching
        try:
            with open(path, "rb") as source:
                return b"PySide6" in source.read()
        except OSError:
            return False

    reads_pyside.reads_uncached = True  # type: ignore[attr-defined]
    feature._mod_uses_pyside = reads_pyside  # type: ignore[union-attr]
    return True


def start_lean() -> None:
    """Call first at start, before pyvista and the app's modules are imported: big blocks get
    pages of their own, PySide6 keeps no module sources, and pyvista finds no mypy to load its
    plugin from (a None in ``sys.modules`` stops that import in this process only)."""
    use_own_pages_for_big_blocks()
    read_sources_uncached()
    sys.modules.setdefault("mypy", None)  # type: ignore[arg-type]


def release_freed_memory(collect: bool = True) -> None:
    """Collect reference cycles now (unless ``collect`` is False), drop the module sources
    :mod:`linecache` keeps of files on disk, and return the allocator's free pages to the
    system."""
    if collect:
        gc.collect()
    for path in list(linecache.cache):
        if os.path.isfile(path):  # not the sources registered for code without a file
            linecache.cache.pop(path, None)
    libc = _libc()
    if libc is not None:
        libc.malloc_trim(0)
