"""The wrinkle brush (paper Fig. 10): a pull that folds the surface around the cursor.

Only an anisotropic material has SH degrees above 2, and their angular ripples are the folds:
degree l of a layered material ripples around the brush with about l sign changes, along the
layers. With the falloff's own radial terms they stay invisible inside a brush (R₆/R₀ = 0.056,
R₁₀/R₀ = 0.004 at 2.5 ε for a Gaussian), so this brush builds its field from two parts:

* the pull: degrees 0 and 2 of the falloff at ε / :data:`MOUND_SCALE` (a tighter mound than a
  grab's, so the folds around it show), weighted ω₀, ω₂;
* the folds: each degree l ≥ 4 with the radial window W_l(ρ) = t^l exp(l (1 − t²) / 2),
  t = ρ / :data:`FOLD_RING` (one band peaking at the fold ring, smooth at the centre as r^l
  must be), its material term brought to the size of degree 0's (‖P₀‖ / ‖P_l‖, so the folds
  do not depend on how anisotropic the material is, only where it is), weighted ω_l; of it only
  the component along the surface normal n is kept (n nᵀ per degree, via
  :meth:`GreenKernel.with_degree_weights`): folds lift and lower the surface, while the
  in-plane part of these degrees only compressed faces until they folded over.

Per event the load sits on the surface under the cursor (projected along n onto the plane of
the previous event's load, so the folds stay in place while they grow) and moves along the
surface; the folds are scaled to a normal depth of max_l ω_l × |Δ| on the tangent disk around
the load (at most :data:`FOLD_SLOPE` steep), and the whole field, sampled on that disk, is held
to the safe-falloff bounds (:mod:`~gogreen_core.sculpt.falloff_safety`). Measured on a flat
sheet of a 1:100 laminate: see ``tests/core/sculpt/test_wrinkle_brush.py``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.physics.radial import RadialProfile
from gogreen_core.sculpt.brushes.base import EventField, StrokeContext, mirror_signs, smooth_cutoff
from gogreen_core.sculpt.brushes.grab import GrabBrush
from gogreen_core.sculpt.falloff_safety import MAX_GRAB_RATIO, MAX_GRAB_STRAIN

if TYPE_CHECKING:
    from gogreen_core.sculpt.brushes.brush import Brush, BrushEvent
    from gogreen_core.sculpt.engine_settings import EngineSettings
    from gogreen_core.sculpt.kernel_cache import KernelCache

__all__ = [
    "FOLD_DEGREES",
    "FOLD_DEPTH",
    "FOLD_RING",
    "MOUND_SCALE",
    "FoldRadial",
    "WrinkleBrush",
    "fold_weights",
]

#: Radius (in ε) where the folds are deepest.
FOLD_RING = 3.0
#: The pull's falloff is the settings' at ε / MOUND_SCALE.
MOUND_SCALE = 1.5
#: The fold depth of a new wrinkle brush: its folds' largest normal displacement per event, in
#: units of the cursor motion.
FOLD_DEPTH = 0.8
#: Steepest slope the folds may add in one event, in units of |Δ| / ε: the events of a pull
#: stack the same folds, and steeper ones turned faces over (degree 10 on the test sheet).
FOLD_SLOPE = 0.9
#: The fold degrees the app offers (more folds around the brush for a higher degree).
FOLD_DEGREES = (6, 8, 10)
#: The default fold degree.
DEFAULT_FOLD_DEGREE = 8
#: A degree whose material term is below this fraction of degree 0's has none (an isotropic
#: material's l > 2, rounding only).
_NO_TERM = 1e-8
#: The tangent disk the folds and the safety bounds are sampled on: radii (in ε, up to the
#: influence or 8), angles, and the step (in ε) of the tangential derivatives.
_DISK_RADII, _DISK_ANGLES, _DISK_STEP = 16, 64, 1e-3
#: Vertices within this many ε of the load give the surface normal (principal axes).
_NORMAL_RADIUS = 1.0
#: The normal is measured again when the load has moved this far (in ε) along the surface.
_NORMAL_REFRESH = 1.0


def fold_weights(
    l_max: int, degree: int = DEFAULT_FOLD_DEGREE, depth: float = FOLD_DEPTH
) -> np.ndarray:
    """The wrinkle brush's ω_l (l_max + 2,): ω₀ = ω₂ = 1 (the pull), ω_degree = ``depth`` (the
    folds; a ``degree`` above l_max: the highest even one ≥ 4 there is), the rest 0."""
    omega = np.zeros(l_max + 2)
    omega[0] = 1.0
    if l_max >= 2:
        omega[2] = 1.0
    top = l_max - l_max % 2
    degree = min(int(degree), top)
    if degree >= 4:
        omega[degree - degree % 2] = depth
    return omega


class FoldRadial(RadialProfile):
    """The wrinkle brush's radial terms: degrees ≤ 3 from ``base`` at ε / :data:`MOUND_SCALE`,
    degrees ≥ 4 the window W_l (see the module docstring). Its ε is the brush's."""

    kind_name = "folds"

    def __init__(self, eps: float, base: RadialProfile) -> None:
        super().__init__(eps)
        self._base = base.with_eps(1.0)

    def dimensionless(self, kind: str, l: int, rho: np.ndarray) -> np.ndarray:
        rho = np.asarray(rho, dtype=np.float64)
        if l <= 3:
            # the base at ε/k: F(kρ)·k for R (∝ 1/ε), F'(kρ)·k² for ℛ (∝ 1/ε²)
            power = 1 if kind == "R" else 2
            return self._base.dimensionless(kind, l, MOUND_SCALE * rho) * MOUND_SCALE**power
        t = rho / FOLD_RING
        return t**l * np.exp(0.5 * l * (1.0 - t * t))

    def table_key(self) -> tuple[Any, ...]:
        return ("folds", FOLD_RING, MOUND_SCALE, self._base.table_key())

    def to_dict(self) -> dict[str, Any]:
        return {"type": self.kind_name, "base": self._base.to_dict()}


def _surface_normal(vertices: np.ndarray, rows: np.ndarray) -> np.ndarray | None:
    """The unit normal (3,) of the least-squares plane of ``vertices[rows]`` (None: < 3)."""
    if len(rows) < 3:
        return None
    points = vertices[rows]
    centred = points - points.mean(axis=0)
    _, vectors = np.linalg.eigh(centred.T @ centred)
    return vectors[:, 0]


def _disk(
    normal: np.ndarray, reach: float, frame: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Offsets (n, 3) in ε on the disk ⟂ ``normal`` (the centre first), their radii (n,), and
    the two tangent directions (2, 3), turning with the stroke's surface ``frame`` if any."""
    t1 = None
    if frame is not None:
        normal = normal if normal @ frame[:, 2] >= 0 else -normal
        t1 = frame[:, 0] - (frame[:, 0] @ normal) * normal
        t1 = t1 if np.linalg.norm(t1) > 1e-6 else None
    if t1 is None:
        t1 = np.cross(normal, np.eye(3)[np.argmin(np.abs(normal))])
    t1 = t1 / np.linalg.norm(t1)
    t2 = np.cross(normal, t1)
    radii = np.linspace(0.0, min(reach, 8.0), _DISK_RADII + 1)[1:]
    angles = np.linspace(0.0, 2 * np.pi, _DISK_ANGLES, endpoint=False)
    r, a = (grid.ravel() for grid in np.meshgrid(radii, angles))
    offsets = np.outer(r * np.cos(a), t1) + np.outer(r * np.sin(a), t2)
    return np.vstack([np.zeros((1, 3)), offsets]), np.concatenate([[0.0], r]), np.array([t1, t2])


class WrinkleBrush(GrabBrush):
    """The folding wrinkle brush (see the module docstring); its ω_l are the settings'
    (:meth:`EngineSettings.weights_for`), default :func:`fold_weights`."""

    def default_weights(self, l_max: int) -> np.ndarray:
        return fold_weights(l_max)

    def _parts(self, settings: EngineSettings) -> tuple[np.ndarray, np.ndarray]:
        """The kernel weights (l_max + 1,) of the pull and of the folds."""
        omega = settings.weights_for(self.kind)[: settings.l_max + 1].copy()
        omega[1::2] = 0.0
        low = np.arange(len(omega)) < 4
        return np.where(low, omega, 0.0), np.where(low, 0.0, omega)

    def _fold_kernels(self, kernels: KernelCache, eps: float) -> tuple[GreenKernel, np.ndarray]:
        """The kernel of the brush's radial terms at ``eps`` (unit weights) and the degrees'
        material scale factors ‖P₀‖/‖P_l‖ (l_max + 1,; 0: no term; the same in every frame)."""
        base = kernels.unturned

        def scales() -> np.ndarray:
            norms = base.full.degree_norms()[: base.settings.l_max + 1]
            has = norms > _NO_TERM * norms[0]
            return np.where(has, norms[0] / np.where(has, norms, 1.0), 0.0)

        factors = base.derived(("fold scales",), scales)
        radial = FoldRadial(eps, kernels.settings.falloff)
        return kernels.full.with_radial(radial), factors

    def unit_kernel(self, kernels: KernelCache, eps: float = 1.0) -> GreenKernel:
        """The pull part at ``eps`` (the folds depend on the surface under the cursor)."""
        unit, _ = self._fold_kernels(kernels, eps)
        return unit.with_degree_weights(self._parts(kernels.settings)[0])

    def reach_kernel(self, kernels: KernelCache) -> GreenKernel:
        """The pull and unit folds (an automatic influence of about 9 ε)."""
        unit, factors = self._fold_kernels(kernels, 1.0)
        pull, folds = self._parts(kernels.settings)
        depth = folds.max() if folds.max() > 0 else 1.0
        return unit.with_degree_weights(pull + folds * factors / depth)

    def field(self, ctx: StrokeContext, brush: Brush, event: BrushEvent) -> EventField:
        eps = brush.eps(ctx.model_size)
        delta = brush.strength * event.delta
        size = float(np.linalg.norm(delta))
        reach = self.reach(ctx, brush)
        memo: dict[str, Any] = ctx.stroke if ctx.stroke is not None else {}
        center, normal = self._surface_frame(ctx, memo, event.center, eps)
        unit, factors = self._fold_kernels(ctx.kernels, eps)
        pull, folds = self._parts(ctx.settings)
        pull_kernel = unit.with_degree_weights(pull)
        g0 = pull_kernel.green(np.zeros((1, 3)))[0]
        force = np.linalg.solve(g0, delta) if size > 0 else np.zeros(3)
        step, maps, weights = delta, None, pull
        if normal is not None:
            step = delta - (delta @ normal) * normal  # the load moves along the surface only
            maps = np.array(
                [np.eye(3) if l < 4 else np.outer(normal, normal) for l in range(len(pull))]
            )
            if size > 0:
                fold_kernel = unit.with_degree_weights(folds * factors, maps)
                alpha, scale = self._balance(
                    ctx,
                    pull_kernel,
                    fold_kernel,
                    force,
                    center,
                    normal,
                    reach,
                    size,
                    float(folds.max()),
                )
                weights = pull + alpha * (folds * factors)
                force = force * min(scale, self._pull_scale(ctx, pull_kernel, force, reach, size))
        kernel = unit.with_degree_weights(weights, maps)
        memo["anchor"] = center + step
        return EventField(kernel, center, force, step, reach)

    def _surface_frame(
        self, ctx: StrokeContext, memo: dict[str, Any], cursor: np.ndarray, eps: float
    ) -> tuple[np.ndarray, np.ndarray | None]:
        """(the load's centre, the surface normal there or None); the normal is measured again
        when the load has moved :data:`_NORMAL_REFRESH` ε."""
        anchor = memo.get("anchor")
        normal = memo.get("normal")
        center = (
            cursor
            if anchor is None or normal is None
            else cursor - ((cursor - anchor) @ normal) * normal
        )
        measured_at = memo.get("normal_at")
        if (
            normal is None
            or measured_at is None
            or np.linalg.norm(center - measured_at) > _NORMAL_REFRESH * eps
        ):
            rows = ctx.mesh.rows_near(center, np.zeros(3), _NORMAL_RADIUS * eps, mirror_signs(""))
            found = _surface_normal(ctx.mesh.vertices, rows)
            if found is not None:
                normal, memo["normal"], memo["normal_at"] = found, found, center
        return center, normal

    def _pull_scale(
        self, ctx: StrokeContext, pull: GreenKernel, force: np.ndarray, reach: float, size: float
    ) -> float:
        """The force scale that keeps the pull alone within the safe-falloff bounds anywhere in
        the influence ball (an edited falloff weak at the centre), as a grab's."""
        key = ("wrinkle pull bound", pull.degree_weights.tobytes(), reach)
        bound = self.cached_bound(ctx, key, pull, reach)
        eps = pull.eps
        strain = bound.strain_sup(force, eps) * eps
        return _bounded(size, bound.motion_sup(force, eps)[0], strain)

    @staticmethod
    def _balance(
        ctx: StrokeContext,
        pull_kernel: GreenKernel,
        fold_kernel: GreenKernel,
        force: np.ndarray,
        center: np.ndarray,
        normal: np.ndarray,
        reach: float,
        size: float,
        depth: float,
    ) -> tuple[float, float]:
        """(the folds' weight α, force scale) of one event: the folds at their ``depth`` on the
        tangent disk, the whole held to the safe-falloff bounds there."""
        eps = pull_kernel.eps
        offsets, radii, tangents = _disk(normal, reach, ctx.kernels.frame)
        points = center + eps * np.vstack(
            [offsets, offsets + _DISK_STEP * tangents[0], offsets + _DISK_STEP * tangents[1]]
        )
        n = len(offsets)
        u_pull = pull_kernel.displacement(points, center, force).reshape(3, n, 3)
        u_fold = fold_kernel.displacement(points, center, force).reshape(3, n, 3)
        cut = (
            smooth_cutoff(radii, 0.5 * reach, reach) if np.isfinite(reach) else np.ones_like(radii)
        )
        fold_size = float((np.linalg.norm(u_fold[0], axis=1) * cut).max())
        pull_size = float((np.linalg.norm(u_pull[0], axis=1) * cut).max())
        alpha = depth * size / fold_size if depth > 0 and fold_size > _NO_TERM * pull_size else 0.0
        if alpha > 0:  # steep folds (the high degrees') are held to a slope
            steepest = _steepest(u_fold, eps)
            if steepest > 0:
                alpha = min(alpha, FOLD_SLOPE * size / (eps * steepest))
        u = u_pull + alpha * u_fold
        motion = float((np.linalg.norm(u[0], axis=1) * cut).max())
        return alpha, _bounded(size, motion, eps * _steepest(u, eps))


def _steepest(u: np.ndarray, eps: float) -> float:
    """Largest ‖∂u/∂t1, ∂u/∂t2‖ of the disk's samples ``u`` (3, n, 3) (centre, t1, t2 steps)."""
    gradient = (u[1:] - u[0]) / (_DISK_STEP * eps)
    return float(np.sqrt((gradient**2).sum(axis=(0, 2))).max())


def _bounded(size: float, motion: float, strain: float) -> float:
    """The force scale ≤ 1 that keeps an event's largest motion and (dimensionless) velocity
    gradient within a grab's bounds for a cursor motion of ``size``."""
    scale = 1.0
    if motion > 0:
        scale = min(scale, MAX_GRAB_RATIO * size / motion)
    if strain > 0:
        scale = min(scale, MAX_GRAB_STRAIN * size / strain)
    return scale
