"""The code a :class:`~gogreen_core.field.kernel.GreenKernel` evaluates with: the compiled
drivers (``_expansion``, ``_integrator``, with ``_unrolled``'s angular kernels) on the thread
pool, bit for bit whatever the number of threads, or until they are ready (``_compiled``) the
NumPy reference ``_numpy_eval``; each parity chooses once they are (:meth:`Parity.backend`).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from gogreen_core import _compiled
from gogreen_core._parallel import run_ranges
from gogreen_core.field import _drivers, _expansion, _integrator, _numpy_eval, _stream, _unrolled
from gogreen_core.field._expansion import BLOCK
from gogreen_core.field._influence_compiled import near_segment_rows

__all__ = ["Backend", "Parity", "expand", "near_segment", "stream_field"]
#: Blocks per range handed to a thread by ``expand``.
_MIN_BLOCKS = 32


class Backend(NamedTuple):
    """The compiled drivers (``compiled``) with the angular kernel of the parity's degrees
    (``angular``: generated if ``unrolled``, else the generic marker; ``angular32`` the
    streamlines' float32 one), or the NumPy reference (``compiled`` false)."""

    compiled: bool
    angular: Any = None
    unrolled: bool = False
    angular32: Any = None
    unrolled32: bool = False


#: The NumPy reference's backend.
NUMPY = Backend(False)


class Parity:
    """Packed material coefficients of one parity (even: G, odd: ∇G): ``matrices`` (n_terms, 3,
    3) or (n_terms, 3, 3, 3), rows of degree l from ``base[l]``."""

    def __init__(self, l_first: int, l_last: int, matrices: np.ndarray, base: np.ndarray):
        self.l_first = l_first
        self.l_last = l_last
        self.degrees = list(range(l_first, l_last + 1, 2))
        self.matrices = matrices
        self.base = base  # (l_last+1,) int64, row of Y_l,-l
        self.scales = _unrolled.row_scales(l_first, l_last)
        self.beta = np.array(_unrolled.angular_constants(l_last)[0])  # writable: one type
        #: the streamlines' single precision recurrence constants
        self.beta_single = self.beta.astype(np.float32)
        self._backend: Backend | None = None

    @property
    def power(self) -> int:
        """1 for G (R_l ~ 1/r), 2 for ∇G (ℛ_l ~ 1/r²)."""
        return 1 if self.l_first == 0 else 2

    def backend(self) -> Backend:
        """The code this parity evaluates with: NumPy until the compiled drivers are ready (they
        and the generated kernels are requested), then the generic angular kernel until the
        generated ones are too (kept once final; chosen at every call within
        ``_compiled.forced``)."""
        if self._backend is not None and _compiled.forced_code() is None:
            return self._backend
        generated = self.l_last <= _unrolled.UNROLLED_L_MAX
        if generated and _compiled.forced_code() is None:  # both parities' kernels: one batch
            _compiled.request(*_drivers.units_for(self.l_last - self.l_first))
        if not _compiled.drivers():
            return NUMPY
        kernel = _drivers.angular(self.l_first, self.l_last) if generated else None
        upper = generated and self.l_last > self.l_first
        kernel32 = _drivers.angular(self.l_first, self.l_last, single=True) if upper else None
        angular = kernel if kernel is not None else _drivers.generic_marker()
        angular32 = kernel32 if kernel32 is not None else _drivers.generic_marker(single=True)
        backend = Backend(True, angular, kernel is not None, angular32, kernel32 is not None)
        if not generated or (kernel is not None and (kernel32 is not None or not upper)):
            self._backend = backend
        return backend

    def folded(self, coeffs: np.ndarray) -> np.ndarray:
        """``coeffs`` (n_terms, K) with the Legendre scales folded in."""
        return np.ascontiguousarray(coeffs * self.scales[:, None])


def expand(
    parity: Parity,
    tables: np.ndarray,
    eps: float,
    points: np.ndarray,
    center: np.ndarray,
    coeffs: np.ndarray,
) -> np.ndarray:
    """out[n, k] = the expansion of ``parity`` with ``coeffs`` (n_terms, K) at points - center
    → (N, K)."""
    out = np.empty((points.shape[0], coeffs.shape[1]))
    if points.shape[0] == 0:
        return out
    folded = parity.folded(coeffs)
    backend = parity.backend()
    if not backend.compiled:
        args = (points, center, eps, parity.power, parity.l_first, parity.l_last, parity.base)
        out[:] = _numpy_eval.expand(*args, folded, parity.beta, tables)
        return out
    unrolled = backend.unrolled and coeffs.shape[1] == 3  # generated for three outputs
    angular = backend.angular if unrolled else _drivers.generic_marker()
    work = partial(
        _expansion.expand_blocks, points, center, eps, parity.power, parity.l_first,
        parity.l_last, parity.base, folded, parity.beta, tables, angular, unrolled, out,
    )  # fmt: skip
    run_ranges(work, (points.shape[0] + BLOCK - 1) // BLOCK, _MIN_BLOCKS)
    return out


def stream_field(
    parity: Parity,
    tables: np.ndarray,
    single_tables: np.ndarray,
    eps: float,
    coeffs: np.ndarray,
    center: np.ndarray,
    center_step: np.ndarray,
    cutoff: tuple[float, float],
    mirrors: np.ndarray,
    origin: np.ndarray,
) -> tuple[_stream.StreamField, Callable[..., None]]:
    """The velocity field of the load ``coeffs`` (n_terms, 3) of ``parity`` moving from
    ``center`` by ``center_step``, faded between the ``cutoff`` radii, mirrored by ``mirrors``
    about ``origin`` (``tables``: the parity's radial tables; ``single_tables``: the float32
    ones of the degrees above the lowest), and the pass that integrates it (``run_pass`` of
    ``_stream.stream``: compiled or NumPy's)."""
    inner, outer = cutoff
    width = outer - inner
    backend = parity.backend()
    folded = parity.folded(coeffs)
    # float32 coefficients over the largest magnitude of the rows above the lowest degree
    cscale = float(np.abs(folded[2 * parity.l_first + 1 :]).max(initial=0.0))
    coeffs32 = np.zeros(folded.shape, dtype=np.float32)
    if cscale != 0.0:
        with np.errstate(invalid="ignore"):
            coeffs32 = np.ascontiguousarray(folded / cscale, dtype=np.float32)
    field = _stream.StreamField(
        center0=center, center_step=center_step, eps=float(eps), power=parity.power,
        l_first=parity.l_first, l_last=parity.l_last, base=parity.base, coeffs=folded,
        tables=tables[:1], cutoff_inner=float(inner),
        inv_width=1.0 / width if outer > 0.0 and width > 0.0 else 0.0, mirrors=mirrors,
        origin=origin, coeffs32=coeffs32, beta32=parity.beta_single, tables32=single_tables,
        cscale=cscale, angular32=backend.angular32, unrolled32=backend.unrolled32,
    )  # fmt: skip
    return field, _integrator._pass if backend.compiled else _numpy_eval.stream_pass


def near_segment(
    points: NDArray[np.float64],  # (N, 3) float64
    start: NDArray[np.float64],  # (3,) segment start
    step: NDArray[np.float64],  # (3,) segment end - start
    radius: float,
    mirrors: NDArray[np.float64],  # (n_m, 3) ±1 signs
    origin: NDArray[np.float64],  # (3,)
    out: NDArray[np.bool_],  # (N,): some mirror image of the point is within radius of the segment
    compiled: bool | None = None,  # the compiled pass or NumPy's; None: compiled once ready
) -> None:
    """Which points some mirror image of which lies within ``radius`` of the segment (the
    vertices a brush event can reach), on the thread pool; in NumPy until compiled."""
    if not (_compiled.drivers() if compiled is None else compiled):
        # without the compiled test's contractions: rows at rounding distance from the ball's
        # surface may differ, which moves nothing (``_integrator``'s CUTOFF_END)
        distance2 = _numpy_eval.segment_distance2(points, start, step, mirrors, origin)
        out[:] = distance2 < radius * radius
        return
    work = partial(near_segment_rows, points, start, step, float(radius), mirrors, origin, out)
    run_ranges(work, points.shape[0], 1 << 16)
