"""The field's compile units, registered with :mod:`gogreen_core._compiled` on import: the
drivers (``_expansion``, ``_integrator``, ``_influence_compiled``) and the generated angular
kernel of each parity and highest degree (``(l_first, l_last)``).
"""

from __future__ import annotations

from functools import cache
from typing import TYPE_CHECKING, Any

import numpy as np

from gogreen_core import _compiled
from gogreen_core.field import _expansion, _influence_compiled, _integrator, _stream, _unrolled

if TYPE_CHECKING:
    from numba.core.ccallback import CFunc

__all__ = ["angular", "generic_marker", "units_for"]


@cache
def generic_marker(single: bool = False) -> CFunc[Any]:
    """The C callback passed as ``angular`` (``single``: ``angular32``) with ``unrolled=False``
    (never called: the drivers run the generic ``_expansion._angular``)."""
    from numba import cfunc

    signature = _expansion.ANGULAR_SINGLE_SIGNATURE if single else _expansion.ANGULAR_SIGNATURE
    return cfunc(signature, cache=True)(_expansion.generic_marker)


def angular(l_first: int, l_last: int, single: bool = False) -> CFunc[Any] | None:
    """The generated angular kernel (``single``: its single precision one) if it is ready,
    else None (its unit is requested)."""
    code = _compiled.forced_code()
    if code == "generic":
        return None
    if code == "unrolled":
        _compiled.prepare((l_first, l_last))
    kernel = _unrolled._KERNELS.get((l_first, l_last, single))
    if kernel is None:
        _compiled.request((l_first, l_last))
    return kernel


def units_for(l_max: int) -> tuple[_compiled.Unit, ...]:
    """The units vector and affine loads of truncation degree ``l_max`` evaluate with: the
    drivers and the generated angular kernel of each parity (when one is generated)."""
    parities = ((0, l_max - l_max % 2), (1, l_max + 1 - l_max % 2))
    return (_compiled.DRIVERS, *(p for p in parities if p[1] <= _unrolled.UNROLLED_L_MAX))


def _angular_kernels(unit: _compiled.Unit) -> list[tuple[int, int, bool]]:
    """(l_first, l_last, single) of the kernels of an angular unit (single precision too where
    the parity has more than one degree)."""
    first, last = int(unit[0]), int(unit[1])
    return [(first, last, single) for single in ((False, True) if last > first else (False,))]


def _driver_calls() -> list[tuple[Any, tuple[Any, ...]]]:
    """(dispatcher, arguments) of every driver, typed as the real calls are, with empty ranges:
    calling them compiles and returns."""
    f3, f33 = np.zeros(3), np.zeros((1, 3))
    rows, base = np.zeros(1, dtype=np.int64), np.zeros(2, dtype=np.int64)
    tables = np.zeros((1, 2, _expansion.SEGMENT_DEGREE + 1))
    beta, flags = np.zeros((2, 2)), np.zeros(1, dtype=np.bool_)
    marker = generic_marker()
    field = _stream.StreamField(
        center0=f3, center_step=f3, eps=1.0, power=1, l_first=0, l_last=0, base=base,
        coeffs=f33, tables=tables, cutoff_inner=0.0, inv_width=0.0, mirrors=f33, origin=f3,
        coeffs32=f33.astype(np.float32), beta32=beta.astype(np.float32),
        tables32=np.zeros((2, 0, 3), np.float32), cscale=0.0,
        angular32=generic_marker(single=True), unrolled32=False,
    )  # fmt: skip
    return [
        (_integrator._pass,
         (0, f33, rows, True, True, 1.0, field, 1, True, True, 0.0, rows, f33, rows, f33, f33,
          rows, flags, 0, 0)),
        # the rest: see HELPER
        (_expansion.expand_blocks,
         (f33, f3, 1.0, 1, 0, 0, base, f33, beta, tables, marker, False, f33, 0, 0)),
        *_influence_compiled.compile_calls(),
    ]  # fmt: skip


def _register_drivers(unit: str, first: int, helps: _compiled.Unit | None = None) -> None:
    """Register the drivers ``_driver_calls()[first:]`` as ``unit`` (compiled by calling them)."""
    _compiled.register(
        unit,
        __name__,
        lambda _: [dispatcher(*args) for dispatcher, args in _driver_calls()[first:]],
        lambda _: _compiled.dispatchers_cached(_driver_calls()[first:]),
        helps,
    )


_register_drivers(_compiled.DRIVERS, 0)
_compiled.register(
    _compiled.ANGULAR,
    __name__,
    lambda unit: [_unrolled.unrolled_angular(*kernel) for kernel in _angular_kernels(unit)],
    lambda unit: all(_unrolled.angular_cached(*kernel) for kernel in _angular_kernels(unit)),
)
#: The drivers after the streamlines' two (the expansion, the influence loops), which a second
#: compiling child compiles first, while the first compiles the streamlines' (the costliest):
#: it then finds these in the disk cache.
HELPER = "drivers_rest"
_register_drivers(HELPER, 2, helps=_compiled.DRIVERS)
