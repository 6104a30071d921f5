"""How much the truncation degree l_max costs in accuracy for one material (paper Fig. 9):
:func:`truncation_errors` measures, for each even l_max, the relative error

    δ(l_max) = max_x ‖G_lmax(x) − G_ref(x)‖_F / max_x ‖G_ref(x)‖_F

over points x within 6 ε of the load, against the same expansion 16 degrees higher (an odd
l_max has the error of l_max − 1; the falloff hardly changes δ: the Gaussian is used). About a
second of work: ``progress(done, total)`` after each degree, ``cancelled()`` stops between them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.integrate import lebedev_rule

from gogreen_core.field.kernel import L_MAX_LIMIT, GreenKernel
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import GaussianRadial
from gogreen_core.validation import check_integer, check_number

__all__ = ["DEFAULT_TOLERANCE", "TruncationCancelled", "TruncationReport", "truncation_errors"]

#: δ below which the truncation is invisible: 0.1 % of the largest displacement, well under a
#: pixel at any zoom an artist sculpts at.
DEFAULT_TOLERANCE = 1e-3
#: How far above the largest l_max asked for the reference expansion goes.
_REFERENCE_MARGIN = 16
#: Sample radii (in ε) of the error, up to 6 ε: dense near the load, where the field bends most.
_RADII = (0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.5, 6.0)
#: Lebedev orders scipy provides above 31 (every 6th).
_ORDERS = (*range(3, 32, 2), *range(35, 132, 6))


class TruncationCancelled(Exception):
    """:func:`truncation_errors` was cancelled by its ``cancelled`` callback."""


@dataclass(frozen=True)
class TruncationReport:
    """δ(l_max) of one material: ``errors`` (n,) at the even l_max ``degrees`` (n,) (0, 2, ...,
    max_degree), against an expansion of ``reference_degree``."""

    degrees: np.ndarray
    errors: np.ndarray
    reference_degree: int

    def error(self, l_max: int) -> float:
        """δ of ``l_max`` (an odd l_max has the error of l_max − 1; beyond the measured
        range, the last measured value, an upper bound)."""
        l_max = check_integer("l_max", l_max, low=0, high=L_MAX_LIMIT)
        index = min(l_max // 2, len(self.errors) - 1)
        return float(self.errors[index])

    def suggested(self, tolerance: float = DEFAULT_TOLERANCE) -> int:
        """The smallest measured even l_max with δ ≤ ``tolerance`` (the largest measured one
        when none reaches it)."""
        tolerance = check_number("tolerance", tolerance, low=0.0, low_open=True)
        within = np.flatnonzero(self.errors <= tolerance)
        return int(self.degrees[within[0]] if len(within) else self.degrees[-1])

    def summary(self, l_max: int, tolerance: float = DEFAULT_TOLERANCE) -> str:
        """One line for the panel or the terminal: the error at ``l_max`` and the suggestion."""
        error, best = self.error(l_max), self.suggested(tolerance)
        text = f"l_max {l_max}: error {100 * error:.2g} % of the displacement"
        if best < l_max - 1:
            return f"{text}; l_max {best} is enough ({100 * self.error(best):.2g} %), and faster"
        if error > tolerance:
            reached = self.error(best) <= tolerance
            return f"{text}; l_max {best} {'brings it under' if reached else 'lowers it to'} " + (
                f"{100 * tolerance:.2g} %" if reached else f"{100 * self.error(best):.2g} %"
            )
        return f"{text} (below {100 * tolerance:.2g} %: exact to the eye)"

    def table(self) -> str:
        """The curve as text: one line per measured l_max."""
        lines = [f"{'l_max':>5}  {'error':>9}"]
        lines += [f"{d:>5}  {e:>9.2e}" for d, e in zip(self.degrees, self.errors, strict=True)]
        return "\n".join(lines)


def _sample_points(reference_degree: int) -> np.ndarray:
    """(n, 3) points (ε = 1): the centre, then on each of :data:`_RADII` a Lebedev rule that
    resolves the reference degree's angular ripples."""
    order = next((o for o in _ORDERS if o >= reference_degree + 3), _ORDERS[-1])
    nodes = lebedev_rule(order)[0].T
    shells = (np.array(_RADII)[:, None, None] * nodes[None]).reshape(-1, 3)
    return np.vstack([np.zeros((1, 3)), shells])


def truncation_errors(
    material: Material,
    max_degree: int = 20,
    *,
    progress: Callable[[int, int], None] | None = None,
    cancelled: Callable[[], bool] | None = None,
) -> TruncationReport:
    """δ(l_max) for even l_max = 0, 2, ..., ``max_degree`` (≤ 44): see the module docstring."""
    top = L_MAX_LIMIT - _REFERENCE_MARGIN
    max_degree = check_integer("max_degree", max_degree, low=0, high=top)
    max_degree -= max_degree % 2
    reference_degree = max_degree + _REFERENCE_MARGIN
    points = _sample_points(reference_degree)
    degrees = np.arange(0, max_degree + 1, 2)
    total = len(degrees) + 1
    reference = GreenKernel(material, reference_degree, GaussianRadial(1.0))
    exact = reference.green(points).reshape(len(points), 9)
    scale = float(np.sqrt(np.einsum("ij,ij->i", exact, exact).max()))
    if progress:
        progress(1, total)
    errors = np.empty(len(degrees))
    for number, degree in enumerate(degrees):
        if cancelled is not None and cancelled():
            raise TruncationCancelled("the truncation error computation was cancelled")
        # the reference with the degrees above `degree` weighted out: exactly the tail left out
        weights = (np.arange(reference_degree + 1) <= degree).astype(np.float64)
        approximate = reference.with_degree_weights(weights).green(points).reshape(-1, 9)
        difference = approximate - exact
        errors[number] = np.sqrt(np.einsum("ij,ij->i", difference, difference).max()) / scale
        if progress:
            progress(number + 2, total)
    errors.setflags(write=False)
    degrees.setflags(write=False)
    return TruncationReport(degrees, errors, reference_degree)
