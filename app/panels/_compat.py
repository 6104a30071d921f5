"""Work around a reference-count bug of PySide6 6.12.0 on CPython < 3.12.

Measured here (PySide6 / shiboken6 6.12.0, CPython 3.11): every call of a Qt method returning
``void`` (``QPainter.setPen``, ``QObject.setObjectName``, ``QPointF.setX``, ...) *drops one
reference to None* instead of returning a new one. From CPython 3.12 on None is immortal and
nothing happens; on 3.11 None's count (about 28 000 in a process with numpy, scipy, VTK and Qt
loaded) reaches zero after that many calls and the interpreter aborts with
"Fatal Python error: none_dealloc: deallocating None" — a few repaints of a QPainter widget
are enough. The workaround adds 2**40 references to None once (what 2**40 ``Py_INCREF(None)``
calls would do), which makes None effectively immortal as on 3.12. It is applied only when a
probe shows the leak, so a fixed PySide6 or a newer Python leaves None untouched.
"""

from __future__ import annotations

import ctypes
import sys

__all__ = ["apply_none_refcount_workaround", "void_calls_leak_none"]

_PROBE_CALLS = 64
_EXTRA_REFERENCES = 1 << 40
_applied = False


def void_calls_leak_none() -> bool:
    """Whether calling a void PySide6 method decrements None's reference count."""
    if sys.version_info >= (3, 12):  # None is immortal: its count never reaches zero
        return False
    from PySide6.QtCore import QPointF

    point = QPointF(0.0, 0.0)
    before = sys.getrefcount(None)
    for _ in range(_PROBE_CALLS):
        point.setX(1.0)
    return sys.getrefcount(None) - before <= -_PROBE_CALLS // 2


def apply_none_refcount_workaround() -> bool:
    """Give None 2**40 extra references if void PySide6 calls leak them (once per process).

    Returns True when the workaround is (or was already) in effect.
    """
    global _applied
    if _applied:
        return True
    if not void_calls_leak_none():
        return False
    # CPython < 3.12: ob_refcnt (Py_ssize_t) is the first field of every object.
    ctypes.c_ssize_t.from_address(id(None)).value += _EXTRA_REFERENCES
    _applied = True
    return True
