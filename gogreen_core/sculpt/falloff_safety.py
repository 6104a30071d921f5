"""Safe falloffs: bounds on how far one brush event can move a vertex, whatever the falloff.

A brush event moves vertices along the load's field over pseudo-time [0, 1], so no vertex moves
farther than sup_x |u(x)| over the influence ball. A load normalized by the field at the centre
(grab: f = G(0)⁻¹ Δ) is safe where the field peaks there; for an edited falloff weak at its
centre the brushes scale the load down to the bounds below.

:class:`FieldBound` samples one kernel's field once (in units of ε, so for every brush radius)
and answers sup_k |D_k h| for a load h per event, visiting the samples in decreasing order of
their norm until none can beat the best so far.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import cast

import numpy as np

from gogreen_core.field.kernel import GreenKernel, lebedev_points
from gogreen_core.physics.material import Material
from gogreen_core.physics.sph_rotation import LEBEDEV_ORDERS

__all__ = [
    "AFFINE_FALLBACK",
    "AFFINE_MARGIN",
    "AUTO_LEVEL",
    "MAX_GRAB_RATIO",
    "MAX_GRAB_STRAIN",
    "FieldBound",
    "TurnedFieldBound",
    "field_reach",
    "mean_green_direction",
]

#: Largest motion of any vertex in one grab event, in multiples of the cursor motion |Δ|
#: (closed-form falloffs: 1, the fibre preset's tri-scale grab 1.08).
MAX_GRAB_RATIO = 1.5
#: Affine brushes have no natural scale (their reach depends on the material), so their load
#: may move and shear vertices at most this many times what the Gaussian falloff's does with
#: the same material and pattern.
AFFINE_MARGIN = 1.5
#: Fallback bounds (motion in |amount| ε, velocity gradient in |amount|) where no pattern of
#: the Gaussian reference has an effect (an incompressible material's scale brush).
AFFINE_FALLBACK = (4.0, 8.0)
#: Largest velocity gradient ‖∇u‖_F of one grab event, in multiples of |Δ|/ε (the flow of a
#: field with ‖∇v‖ ≤ L turns no face over while e^L − 1 < 1; closed-form falloffs: 0.4-1.77).
MAX_GRAB_STRAIN = 2.0
#: Finite-difference step (in ε) of the sampled velocity gradient.
_GRADIENT_STEP = 1e-4
#: Radial samples per ε (uniform in ρ = r/ε up to the influence radius, capped below).
_SAMPLES_PER_EPS = 16
#: Beyond this radius (in ε) the field is sampled geometrically (unbounded influence).
_DENSE_RHO = 10.0


def _directions(l_max: int) -> tuple[np.ndarray, np.ndarray]:
    """Lebedev nodes (n, 3) and weights (n,) of order ≥ 2 (l_max + 1) + 1 (at most 41)."""
    return lebedev_points(next(o for o in LEBEDEV_ORDERS if o >= min(2 * l_max + 3, 41)))


def _radii(influence: float) -> np.ndarray:
    """Sample radii ρ = r/ε (increasing, starting at 0) covering the influence ball."""
    reach = min(influence, _DENSE_RHO)
    dense = np.linspace(0.0, reach, max(2, math.ceil(reach * _SAMPLES_PER_EPS) + 1))
    if influence <= _DENSE_RHO:
        return dense
    # the far field decays like 1/ρ (G) or 1/ρ² (∇G): a geometric tail catches late bumps
    far = min(influence, 1e4)
    return np.concatenate([dense, np.geomspace(reach, far, 40)[1:]])


#: An automatic influence (:func:`field_reach`) keeps the field at full strength out to where
#: its envelope falls below this fraction of its peak.
AUTO_LEVEL = 0.1
#: Bounds (in ε) of an automatic influence (a 1/r far field never fades: capped).
AUTO_INFLUENCE_RANGE = (4.0, 32.0)


def field_reach(kernel: GreenKernel, affine: bool) -> float:
    """Automatic influence radius (in ε) of a kernel's field: twice the radius beyond which
    the envelope max_|x|=ρ ‖G(x)‖ (‖∇G(x)‖ for affine loads) stays below :data:`AUTO_LEVEL` of
    its peak, within :data:`AUTO_INFLUENCE_RANGE` (the cutoff, from half the influence, then
    fades only what is faint)."""
    unit = kernel.with_eps(1.0)
    nodes, _ = _directions(kernel.l_max)
    rho = np.geomspace(0.05, 2 * AUTO_INFLUENCE_RANGE[1], 160)
    points = (rho[:, None, None] * nodes[None]).reshape(-1, 3)
    values = unit.green_gradient(points) if affine else unit.green(points)
    size = np.linalg.norm(values.reshape(len(rho), len(nodes), -1), axis=2).max(axis=1)
    above = np.flatnonzero(size > AUTO_LEVEL * size.max())
    if not len(above):
        return AUTO_INFLUENCE_RANGE[0]
    last = above[-1]
    if last + 1 >= len(rho):
        return AUTO_INFLUENCE_RANGE[1]
    # where the envelope crosses the level between the last sample above it and the next
    a, b = np.log(size[last]), np.log(size[last + 1])
    t = (a - np.log(AUTO_LEVEL * size.max())) / (a - b) if a > b else 0.0
    crossing = float(np.exp(np.log(rho[last]) + t * (np.log(rho[last + 1]) - np.log(rho[last]))))
    low, high = AUTO_INFLUENCE_RANGE
    return float(np.clip(2.0 * crossing, low, high))


@lru_cache(maxsize=16)
def mean_green_direction(material: Material) -> np.ndarray:
    """A (3, 3), the material part of G(0): G(0) = c R₀(0) A with A = ∫_S² M(ξ̂)⁻¹ dS / 4π for
    every falloff (only the l = 0 term of paper Eq. 10 survives at x = 0), so A⁻¹ Δ is the
    direction of the grab force even where R₀(0) vanishes (read-only, positive definite)."""
    nodes, weights = lebedev_points()  # the kernel's own rule: exact for its P_00
    m_inv = np.linalg.inv(material.acoustic_tensor(nodes))
    mean = np.einsum("q,qij->ij", weights, m_inv) / (4 * np.pi)
    mean = 0.5 * (mean + mean.T)
    mean.setflags(write=False)
    return cast(np.ndarray, mean)


class _SupTable:
    """sup_k |D_k h| over sampled linear maps D_k (K, m, n), visited in decreasing order of
    ‖D_k‖₂ and stopping as soon as no unvisited sample can beat the best so far."""

    def __init__(self, points: np.ndarray, operators: np.ndarray):
        if not np.all(np.isfinite(operators)):
            raise ValueError("the falloff's field is not finite")
        # ‖D‖₂² is the largest eigenvalue of the smaller Gram matrix, D Dᵀ or Dᵀ D
        if operators.shape[1] <= operators.shape[2]:
            gram = operators @ operators.transpose(0, 2, 1)
        else:
            gram = operators.transpose(0, 2, 1) @ operators
        largest = np.linalg.eigvalsh(gram)[:, -1]
        norms = np.sqrt(np.maximum(largest, 0.0)) * (1 + 1e-9)  # margin for rounding
        order = np.argsort(-norms, kind="stable")
        self.points = points[order]  # (K, 3)
        self.operators = np.ascontiguousarray(operators[order])  # (K, m, n)
        self.norms = np.append(norms[order], 0.0)  # (K + 1,) decreasing, then a sentinel

    def sup(self, h: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """(sup_k |D_k h|, x_k (3,), D_k h (m,)) at the best sample."""
        size = float(np.linalg.norm(h))
        count, total = 64, len(self.points)
        while True:
            values = self.operators[:count] @ h  # (count, m)
            lengths = np.einsum("ki,ki->k", values, values)
            best = int(np.argmax(lengths))
            top = math.sqrt(lengths[best])
            if count >= total or top >= self.norms[count] * size:
                return top, self.points[best], values[best]
            count = min(4 * count, total)


class FieldBound:
    """Sampled sup of a load's field and of its gradient over the influence ball of one
    kernel shape: ``kernel`` at any radius (sampled at ε = 1), ``influence`` in ε (``inf``:
    none), ``affine``: sample ∇G (loads H (3, 3)) instead of G (loads h (3,)). Gradients by
    forward differences of what moves the vertices (a spline's R_l and ℛ_l are separate curves).
    """

    def __init__(self, kernel: GreenKernel, influence: float, affine: bool):
        unit = kernel.with_eps(1.0)
        nodes, _ = _directions(kernel.l_max)
        rho = _radii(influence)
        points = (rho[1:, None, None] * nodes[None]).reshape(-1, 3)
        points = np.concatenate([np.zeros((1, 3)), points])  # the centre itself
        self.affine = bool(affine)
        h = _GRADIENT_STEP
        shifted = (points[:, None, :] + h * np.eye(3)[None]).reshape(-1, 3)  # x_k + h e_p
        if self.affine:
            # [k, i, (j, q)] = ∂_q G_ij: u_i = Σ_jq ∂_q G_ij H_jq = (D_k h)_i, h = H.ravel()
            values = unit.green_gradient(points).reshape(-1, 3, 9)
            ahead = unit.green_gradient(shifted).reshape(len(points), 3, 3, 9)
        else:
            values = unit.green(points)  # [k, i, j]
            ahead = unit.green(shifted).reshape(len(points), 3, 3, 3)  # [k, p, i, j]
        # forward differences (error O(h) ~ 1e-4): [k, p, i, n] = ∂_p of the map at x_k
        gradient = (ahead - values[:, None]) / h
        # [k, (i, p), n]: (∇u)_ip = Σ_n ∂_p D_in h_n
        n = values.shape[2]
        self._points = points
        self._maps = (values, gradient.transpose(0, 2, 1, 3).reshape(-1, 9, n))
        self._tables: dict[str, tuple[np.ndarray | None, _SupTable, _SupTable]] = {}

    def _table(self, load: np.ndarray) -> tuple[np.ndarray, _SupTable, _SupTable]:
        """(coefficients of ``load`` in the pattern subspace it lies in, motion table, strain
        table): tables restricted to the subspace (built on first use) prune far better."""
        h = np.asarray(load, dtype=np.float64)
        name = "vector" if h.shape == (3,) else _subspace(h)
        basis = _BASES[name] if name in _BASES else None
        if name not in self._tables:
            maps = self._maps if basis is None else tuple(m @ basis for m in self._maps)
            self._tables[name] = (
                basis,
                _SupTable(self._points, maps[0]),
                _SupTable(self._points, maps[1]),
            )
        basis, motion, strain = self._tables[name]
        return (h.ravel() if basis is None else basis.T @ h.ravel()), motion, strain

    def motion_sup(self, load: np.ndarray, eps: float) -> tuple[float, np.ndarray, np.ndarray]:
        """(sup |u|, the point (3,) relative to the centre, u there (3,)) for ``load`` (3,) or
        (3, 3) on the kernel of radius ``eps`` (model units)."""
        coefficients, motion, _ = self._table(load)
        top, point, value = motion.sup(coefficients)
        scale = eps ** -(2 if self.affine else 1)
        return top * scale, point * eps, value * scale

    def strain_sup(self, load: np.ndarray, eps: float) -> float:
        """sup ‖∇u‖_F (dimensionless) of the load's field u (force (3,) or affine (3, 3)) on
        the kernel of radius ``eps``."""
        coefficients, _, strain = self._table(load)
        return strain.sup(coefficients)[0] / eps ** (3 if self.affine else 2)


class TurnedFieldBound(FieldBound):
    """The field bound of a kernel whose material is turned by the rotation F (3, 3), from the
    unturned kernel's ``bound`` without new samples: G'(x) = F G(Fᵀx) Fᵀ."""

    def __init__(self, bound: FieldBound, frame: np.ndarray) -> None:  # no sampling
        self.affine = bound.affine
        self._bound = bound
        self._frame = np.asarray(frame, dtype=np.float64)

    def _local(self, load: np.ndarray) -> np.ndarray:
        f, h = self._frame, np.asarray(load, dtype=np.float64)
        return cast(np.ndarray, f.T @ h @ f if h.shape == (3, 3) else f.T @ h)

    def motion_sup(self, load: np.ndarray, eps: float) -> tuple[float, np.ndarray, np.ndarray]:
        top, point, value = self._bound.motion_sup(self._local(load), eps)
        return top, self._frame @ point, self._frame @ value

    def strain_sup(self, load: np.ndarray, eps: float) -> float:
        return self._bound.strain_sup(self._local(load), eps)


def _orthonormal(matrices: list[np.ndarray]) -> np.ndarray:
    """(9, r) orthonormal basis (columns) of the span of 3×3 ``matrices``."""
    q, _ = np.linalg.qr(np.array([m.ravel() for m in matrices]).T)
    return q


_E = np.eye(9).reshape(9, 3, 3)  # _E[3 i + j]: the unit matrix of entry (i, j)
_SYMMETRIC = [_E[3 * i + j] + _E[3 * j + i] for i, j in ((1, 2), (0, 2), (0, 1))]
_BASES = {
    "scale": _orthonormal([np.eye(3)]),
    "twist": _orthonormal([_E[3 * i + j] - _E[3 * j + i] for i, j in ((1, 2), (0, 2), (0, 1))]),
    "pinch": _orthonormal([_E[0] - _E[4], _E[4] - _E[8], *_SYMMETRIC]),
    "symmetric": _orthonormal([_E[0], _E[4], _E[8], *_SYMMETRIC]),
}


def _subspace(load: np.ndarray) -> str:
    """The pattern subspace of :data:`_BASES` a (3, 3) load lies in, else "general"."""
    size = np.abs(load).max()
    tol = 1e-12 * size
    if np.abs(load - load[0, 0] * np.eye(3)).max() <= tol:
        return "scale"
    if np.abs(load + load.T).max() <= tol:
        return "twist"
    if np.abs(load - load.T).max() <= tol:
        return "pinch" if abs(np.trace(load)) <= 3 * tol else "symmetric"
    return "general"
