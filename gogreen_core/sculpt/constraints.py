"""Point constraints with prescribed displacements (paper Sec. 2.5, Fig. 1).

k constraint points p_i carry forces f_j such that u(x) = Σ_j G(x − p_j) f_j takes the prescribed
values d_i there: Σ_j G(p_i − p_j) f_j = d_i, a dense symmetric positive definite 3k × 3k system
K f = d. K⁻¹ is updated when one constraint is added (block bordering with the 3 × 3 Schur
complement) or removed, O(k²) each; one refinement step with K lands the points to ~1e-14.

Pins act locally: each term carries the brushes' smooth cutoff s over
:data:`CONSTRAINT_INFLUENCE` ε, u(x) = Σ_j s(|x − p_j|) G(x − p_j) f_j, and K uses the same
blocks, so the pins still get exactly their displacements (G alone decays only as 1/r).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import cast

import numpy as np

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.sculpt.brushes import CUTOFF_START, DEFAULT_INFLUENCE, smooth_cutoff

__all__ = ["CONSTRAINT_INFLUENCE", "ConstraintSet", "smooth_cutoff"]

#: Reach of a pin's displacement in multiples of its ε (the brushes' default influence).
CONSTRAINT_INFLUENCE = DEFAULT_INFLUENCE


class ConstraintSet:
    """Constraint points for one ``kernel`` (material, falloff and ε: the pins' reach is
    :data:`CONSTRAINT_INFLUENCE` ε; two closer than 1e-6 ε are refused as coincident).

    State: ``points`` (k, 3), ``matrix`` K (3k, 3k), ``inverse`` K⁻¹ (3k, 3k).
    """

    def __init__(self, kernel: GreenKernel):
        self.kernel = kernel
        outer = CONSTRAINT_INFLUENCE * kernel.eps
        self._cutoff = (CUTOFF_START * outer, outer)
        self._min_sep = 1e-6 * kernel.eps
        self._points = np.zeros((0, 3))
        self.matrix = np.zeros((0, 0))
        self.inverse = np.zeros((0, 0))

    @classmethod
    def restored(
        cls, kernel: GreenKernel, points: np.ndarray, matrix: np.ndarray, inverse: np.ndarray
    ) -> ConstraintSet:
        """A set in exactly the state another one had: its ``points`` (k, 3), ``matrix`` and
        ``inverse`` (3k, 3k) bit for bit (adding the points again would round differently)."""
        constraints = cls(kernel)
        constraints._points, constraints.matrix, constraints.inverse = points, matrix, inverse
        return constraints

    @property
    def points(self) -> np.ndarray:
        """(k, 3) constraint positions (a copy)."""
        return self._points.copy()

    def __len__(self) -> int:
        return len(self._points)

    def _blocks(self, p: np.ndarray, others: np.ndarray) -> np.ndarray:
        """s G(others − p) as a (3k, 3) column block."""
        offsets = others - p
        weights = smooth_cutoff(np.linalg.norm(offsets, axis=1), *self._cutoff)
        blocks = self.kernel.green(offsets) * weights[:, None, None]
        return cast(np.ndarray, blocks.reshape(-1, 3))

    def add(self, point: np.ndarray) -> int:
        """Add a constraint at ``point`` (3,) (finite: checked by the caller); returns its
        index. O(k²)."""
        p = np.asarray(point, dtype=np.float64)
        k = len(self._points)
        if k:
            dist = np.linalg.norm(self._points - p, axis=1)
            j = int(np.argmin(dist))
            if dist[j] < self._min_sep:
                raise ValueError(
                    f"constraint point {p.tolist()} coincides with constraint {j} "
                    f"(distance {dist[j]:.3g} < {self._min_sep:.3g})"
                )
        b = self._blocks(p, self._points)  # (3k, 3)
        d = self.kernel.green(np.zeros((1, 3)))[0]
        a_inv_b = self.inverse @ b
        schur = d - b.T @ a_inv_b
        try:
            eig = np.linalg.eigvalsh(0.5 * (schur + schur.T))
        except np.linalg.LinAlgError:  # NaN or overflow in the blocks
            eig = np.array([np.nan])
        if not np.all(np.isfinite(eig)):
            raise ValueError(
                f"constraint point {p.tolist()} overflows the constraint system (is it too far "
                "from the model?)"
            )
        if eig[0] <= 1e-10 * eig[-1]:
            raise ValueError(
                f"constraint point {p.tolist()} is too close to the others for the brush radius "
                "(the constraint system would be singular)"
            )
        s_inv = np.linalg.inv(schur)
        top = self.inverse + a_inv_b @ s_inv @ a_inv_b.T
        side = -a_inv_b @ s_inv
        self.inverse = np.block([[top, side], [side.T, s_inv]])
        self.matrix = np.block([[self.matrix, b], [b.T, d]])
        self._points = np.vstack([self._points, p])
        return k

    def remove(self, index: int) -> None:
        """Remove constraint ``index`` (an existing one: checked by the caller). O(k²)."""
        k = len(self._points)
        keep = np.concatenate([np.arange(3 * index), np.arange(3 * index + 3, 3 * k)])
        drop = np.arange(3 * index, 3 * index + 3)
        p = self.inverse[np.ix_(keep, keep)]
        q = self.inverse[np.ix_(keep, drop)]
        r = self.inverse[np.ix_(drop, drop)]
        self.inverse = p - q @ np.linalg.solve(r, q.T)
        self.matrix = self.matrix[np.ix_(keep, keep)]
        self._points = np.delete(self._points, index, axis=0)

    def move(self, index: int, point: np.ndarray) -> None:
        """Move constraint ``index`` to ``point`` (keeps its index): a removal and an addition."""
        saved = (self._points, self.matrix, self.inverse)
        self.remove(index)
        try:
            new = self.add(point)
        except ValueError:
            self._points, self.matrix, self.inverse = saved
            raise
        order = list(range(new))
        order.insert(index, new)  # the moved point back at its index
        idx = np.concatenate([np.arange(3 * i, 3 * i + 3) for i in order])
        self._points = self._points[order]
        self.matrix = self.matrix[np.ix_(idx, idx)]
        self.inverse = self.inverse[np.ix_(idx, idx)]

    def solve(self, displacements: np.ndarray) -> np.ndarray:
        """Forces (k, 3) whose field has the prescribed ``displacements`` (k, 3) at the points."""
        d = np.asarray(displacements, dtype=np.float64).reshape(-1)
        f = self.inverse @ d
        f += self.inverse @ (d - self.matrix @ f)  # one refinement step
        return f.reshape(-1, 3)

    def displacement_rows(
        self,
        points: np.ndarray,
        forces: np.ndarray,
        near: Callable[[np.ndarray, float], np.ndarray],
    ) -> tuple[np.ndarray, np.ndarray]:
        """The rows (K,) int64, sorted, of ``points`` (N, 3) within :attr:`reach` of a pin
        whose force is not zero, and u(x) = Σ_j s G(x − p_j) f_j (K, 3) there (zero elsewhere).
        ``near(point (3,), radius)``: the rows (k,) int64, ascending, of ``points`` within
        ``radius`` of ``point`` or a superset of them (``MeshState.rows_near``)."""
        points = np.asarray(points, dtype=np.float64)
        pins: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []
        for p, f in zip(self._points, forces, strict=True):
            if not np.any(f):
                continue
            # candidates a hair wider (rounding never drops one), then the exact test on them
            candidates = near(p, self._cutoff[1] * (1.0 + 1e-9))
            distance = np.linalg.norm(points[candidates] - p, axis=1)
            inside = distance < self._cutoff[1]
            pins.append((p, f, candidates[inside], smooth_cutoff(distance[inside], *self._cutoff)))
        reached = np.zeros(len(points), dtype=np.bool_)
        for pin in pins:
            reached[pin[2]] = True
        rows = np.flatnonzero(reached)
        slot = np.cumsum(reached) - 1  # row r is u[slot[r]]
        u = np.zeros((len(rows), 3))
        for p, f, pin_rows, weights in pins:
            if len(pin_rows):
                displacement = self.kernel.displacement(points[pin_rows], p, f)
                u[slot[pin_rows]] += displacement * weights[:, None]
        return rows, u
