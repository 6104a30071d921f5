"""Whether numba's disk cache holds a unit of :mod:`gogreen_core._compiled` (then it is only
loaded). These read numba's cache index (``_cache``, not public API)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

__all__ = ["dispatchers_cached", "modules_cached"]


def dispatchers_cached(calls: Iterable[tuple[Any, tuple[Any, ...]]]) -> bool:
    """Whether numba's disk cache holds every (dispatcher, arguments) call of ``calls``,
    typed as they are (numba's ``_cache.load_overload``, not public API)."""
    from numba import typeof

    for dispatcher, args in calls:
        signature = tuple(typeof(a) for a in args)
        if dispatcher._cache.load_overload(signature, dispatcher.targetctx) is None:
            return False
    return True


def modules_cached(name: str) -> bool:
    """Whether numba's disk cache holds machine code for this machine of every compiled
    function of module ``name`` (of a package: of its modules too), from their cache index. A
    function without any entry is one only compiled code calls."""
    import importlib
    import pkgutil

    from numba.core.dispatcher import Dispatcher

    module = importlib.import_module(name)
    modules = [module]
    for info in pkgutil.iter_modules(getattr(module, "__path__", [])):
        modules.append(importlib.import_module(f"{module.__name__}.{info.name}"))
    found = False
    for dispatcher in (v for m in modules for v in vars(m).values()):
        if isinstance(dispatcher, Dispatcher) and dispatcher.__module__.startswith(module.__name__):
            internals: Any = dispatcher  # numba's cache and code generator carry no types
            magic = internals.targetctx.codegen().magic_tuple()
            index = internals._cache._cache_file._load_index()
            if not index:  # never compiled on its own: called only from compiled code (inlined)
                continue
            if not any(key[1] == magic for key in index):
                return False
            found = True
    return found
