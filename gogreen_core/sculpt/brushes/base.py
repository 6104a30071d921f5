"""The brush interface: one :class:`BrushType` per row of the brush table.

:meth:`BrushType.displace` turns one mouse event into the rows it moves and their new positions
(a :class:`Displacement`); the stroke driver (:mod:`gogreen_core.sculpt.stroke`) writes them and
records the undo step. :class:`GreenBrush` is the family of the paper: a load at the cursor whose
regularized Green's function field is taken as a velocity over pseudo-time [0, 1] (paper
Sec. 3.2); members give its kernel and how its load is normalized and bounded.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from gogreen_core.field.kernel import STREAMLINE_TOLERANCE, GreenKernel, StreamlineOverflow
from gogreen_core.physics.radial import RadialProfile
from gogreen_core.sculpt.falloff_safety import FieldBound, TurnedFieldBound, field_reach
from gogreen_core.validation import ParameterError

if TYPE_CHECKING:
    from gogreen_core.mesh.mesh_state import MeshState
    from gogreen_core.sculpt.brushes.brush import Brush, BrushEvent
    from gogreen_core.sculpt.engine_settings import EngineSettings
    from gogreen_core.sculpt.kernel_cache import KernelCache

__all__ = [
    "AUTO_INFLUENCE",
    "CUTOFF_START",
    "DEFAULT_INFLUENCE",
    "BrushType",
    "Displacement",
    "EventField",
    "GreenBrush",
    "StrokeContext",
    "mirror_signs",
    "smooth_cutoff",
]

#: Where the smooth cutoff starts, as a fraction of the influence radius.
CUTOFF_START = 0.5
#: Influence in ε of a brush without a field of its own (also the pins' reach and the least an
#: automatic influence is).
DEFAULT_INFLUENCE = 4.0
#: The default ``influence``: follows the field's own decay (:meth:`GreenBrush.reach`).
AUTO_INFLUENCE = "auto"
#: A field smaller than this fraction of the material's G scale (‖A‖/ε) is zero everywhere.
ZERO_FIELD = 1e-9


def smooth_cutoff(distance: np.ndarray, inner: float, outer: float) -> np.ndarray:
    """The brushes' C² cutoff (quintic smoothstep) of ``distance`` (any shape): 1 up to
    ``inner``, 0 from ``outer`` on."""
    distance = np.asarray(distance, dtype=float)
    width = outer - inner
    if width <= 0:
        return (distance < outer).astype(float)
    u = np.clip((distance - inner) / width, 0.0, 1.0)
    return 1.0 - u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)  # the compiled loops' order


def mirror_signs(symmetry: str) -> np.ndarray:
    """Sign rows (2^k, 3) of the mirror group of ``symmetry`` ("", "x", "xz", ...); row 0 is the
    identity."""
    rows = [np.ones(3)]
    for axis in symmetry:
        flip = np.ones(3)
        flip["xyz".index(axis)] = -1.0
        rows += [r * flip for r in rows]
    return np.array(rows)


@dataclass(frozen=True)
class StrokeContext:
    """What a brush sees of the engine during one event: the mesh, the kernels of the current
    settings, and ``rows``: n → a writable (n, 3) float64 buffer for the new positions.

    write_through : a brush may write the new positions into ``mesh.vertices`` itself (all or
        none, only if all are finite; not with a mask, which the driver blends by).
    stroke : a dict the brush may keep state in between the events of a stroke; None outside.
    """

    mesh: MeshState
    kernels: KernelCache
    rows: Callable[[int], np.ndarray]
    write_through: bool = False
    stroke: dict[str, Any] | None = None

    @property
    def settings(self) -> EngineSettings:
        return self.kernels.settings

    @property
    def model_size(self) -> float:
        return self.mesh.model_size


@dataclass(frozen=True)
class EventField:
    """The velocity field of one event: ``kernel`` with ``load`` (a force (3,) or an affine
    load (3, 3)) at ``center`` (3,), which moves by ``step`` (3,); within ``reach`` ε."""

    kernel: GreenKernel
    center: np.ndarray
    load: np.ndarray
    step: np.ndarray
    reach: float


@dataclass(frozen=True)
class Displacement:
    """What one event does: vertex ``rows`` (n,) int64 go to ``positions`` (n, 3) (may be
    the driver's buffer); ``written``: already written into the mesh; ``mask``: a mask
    painter's new mask values (n,) of ``rows`` instead (``positions`` None)."""

    rows: np.ndarray
    positions: np.ndarray | None
    written: bool = False
    mask: np.ndarray | None = None


class BrushType(ABC):
    """One row of the brush table: how a brush of kind :attr:`kind` acts.

    family : ``"vector"`` (events carry the cursor's motion ``delta``), ``"affine"`` (the brush
        stays at the press point, events carry an ``amount``) or ``"paint"`` (acts along the
        segment ``center`` → ``center + delta`` with ``amount`` ± the pen pressure).
    """

    family: ClassVar[str] = "vector"
    #: The amount an event without one acts with (None: an event must carry one).
    default_amount: ClassVar[float | None] = 0.0

    def __init__(self, kind: str) -> None:
        self.kind = kind

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.kind!r})"

    @property
    def is_affine(self) -> bool:
        return self.family == "affine"

    def with_amount(self, event: BrushEvent) -> BrushEvent:
        """``event`` with its amount, else :attr:`default_amount` (None: ParameterError)."""
        if event.amount is not None:
            return event
        if self.default_amount is None:
            raise ParameterError(
                "amount",
                f"an event of the {self.kind} brush needs an amount (the log strain or angle "
                "at the brush centre); none was given",
            )
        return replace(event, amount=self.default_amount)

    def check_event(self, brush: Brush, event: BrushEvent, reach: float) -> None:
        """Refuse an event whose magnitudes this brush cannot take (:class:`ParameterError`
        naming the field); ``reach``: the farthest motion allowed, model units."""
        return None

    def default_weights(self, l_max: int) -> np.ndarray:
        """The degree weights ω_l (l_max + 2,) this brush starts with: all ones."""
        return np.ones(l_max + 2)

    #: Whether the brush's field has per-degree weights an artist can edit.
    weighted: ClassVar[bool] = False
    #: The influence (ε) an automatic one means for a brush without a field of its own.
    auto_reach: ClassVar[float] = DEFAULT_INFLUENCE

    def reach(self, ctx: StrokeContext, brush: Brush) -> float:
        """Influence radius in ε (``inf``: every vertex): ``influence`` or :attr:`auto_reach`."""
        if brush.influence == AUTO_INFLUENCE:
            return self.auto_reach
        return float(brush.influence)

    def cutoff(self, ctx: StrokeContext, brush: Brush) -> tuple[float, float] | None:
        """(inner, outer) radii (model units) of the smooth cutoff; None for none."""
        return brush.cutoff(ctx.model_size, self.reach(ctx, brush))

    def kernel(self, ctx: StrokeContext, brush: Brush) -> GreenKernel | None:
        """The brush's Green's function kernel at its radius, or None."""
        return None

    @abstractmethod
    def displace(self, ctx: StrokeContext, brush: Brush, event: BrushEvent) -> Displacement:
        """The rows ``event`` moves and their new positions (ValueError: nothing moved)."""


class GreenBrush(BrushType):
    """A brush whose field is a regularized Green's function's: members give :meth:`load`
    (normalized and bounded, :mod:`~gogreen_core.sculpt.falloff_safety`)."""

    #: Names the brush's falloff variant: brushes with equal keys, family and weights share
    #: one sampled field bound per influence radius.
    radial_key: str = ""
    weighted = True

    def __init__(
        self,
        kind: str,
        multiscale: Callable[[RadialProfile], RadialProfile] | None = None,
        weights_of: str | None = None,
    ) -> None:
        """``multiscale`` makes the brush's falloff from the settings' one (e.g.
        :meth:`MultiscaleRadial.local`; None: that one). ``weights_of``: the brush whose
        degree weights it reads (None: its own)."""
        super().__init__(kind)
        self._multiscale = multiscale
        self.radial_key = "" if multiscale is None else kind
        self.weights_kind = kind if weights_of is None else weights_of

    def radial(self, falloff: RadialProfile) -> RadialProfile:
        """The brush's falloff from the settings' shape ``falloff`` at the brush's ε."""
        return falloff if self._multiscale is None else self._multiscale(falloff)

    def degree_weights(self, settings: EngineSettings) -> np.ndarray | None:
        """The kernel's degree weights (l_max + 1,) from the brush's ω_l, None when all ones;
        an affine load's ω_l scales ℛ_l of ∇G (the kernel's weight l − 1)."""
        omega = settings.weights_for(self.weights_kind)
        if np.all(omega == 1.0):
            return None
        return omega[1:] if self.is_affine else omega[:-1]

    def reach(self, ctx: StrokeContext, brush: Brush) -> float:
        """Influence radius in ε: ``influence``, or for ``"auto"``
        :func:`~gogreen_core.sculpt.falloff_safety.field_reach` (cached per settings)."""
        if brush.influence != AUTO_INFLUENCE:
            return float(brush.influence)
        kernels = ctx.kernels.unturned  # the same for every frame the material takes
        key = ("reach", type(self), *self._shape_key(ctx.settings))  # (reach_kernel per class)
        return kernels.derived(key, lambda: field_reach(self.reach_kernel(kernels), self.is_affine))

    def reach_kernel(self, kernels: KernelCache) -> GreenKernel:
        """The kernel at ε = 1 whose field's decay sets an automatic influence."""
        return self.unit_kernel(kernels)

    def _shape_key(self, settings: EngineSettings) -> tuple[Any, ...]:
        """What the brush's field at ε = 1 depends on besides the settings' kernels."""
        weights = self.degree_weights(settings)
        return self.family, self.radial_key, None if weights is None else weights.tobytes()

    def unit_kernel(self, kernels: KernelCache, eps: float = 1.0) -> GreenKernel:
        """The brush's kernel at ``eps`` (model units) for the settings of ``kernels``."""
        radial = self.radial(kernels.settings.falloff.with_eps(eps))
        return kernels.weighted(self.degree_weights(kernels.settings)).with_radial(radial)

    def kernel(self, ctx: StrokeContext, brush: Brush) -> GreenKernel:
        return self.unit_kernel(ctx.kernels, brush.eps(ctx.model_size))

    def field_bound(self, ctx: StrokeContext, brush: Brush, kernel: GreenKernel) -> FieldBound:
        """The sampled bound of this brush's field (cached per settings and influence)."""
        reach = self.reach(ctx, brush)
        key = ("field bound", *self._shape_key(ctx.settings), reach)
        return self.cached_bound(ctx, key, kernel, reach)

    def cached_bound(
        self, ctx: StrokeContext, key: tuple[Any, ...], kernel: GreenKernel, reach: float
    ) -> FieldBound:
        """The field bound of ``kernel`` with ``reach``, cached under ``key``; in a stroke's
        surface frame, the unturned :meth:`unit_kernel`'s turned."""
        affine = self.is_affine
        frame = ctx.kernels.frame
        if frame is None:
            return ctx.kernels.derived(key, lambda: FieldBound(kernel, reach, affine))
        base = ctx.kernels.unturned
        bound = base.derived(
            (*key, "unturned"), lambda: FieldBound(self.unit_kernel(base), reach, affine)
        )
        return TurnedFieldBound(bound, frame)

    @abstractmethod
    def load(
        self, ctx: StrokeContext, brush: Brush, kernel: GreenKernel, event: BrushEvent
    ) -> tuple[np.ndarray, np.ndarray]:
        """(load, centre step) of one event: a force (3,) or affine load (3, 3), and (3,)."""

    def field(self, ctx: StrokeContext, brush: Brush, event: BrushEvent) -> EventField:
        kernel = self.kernel(ctx, brush)
        load, step = self.load(ctx, brush, kernel, event)
        return EventField(kernel, event.center, load, step, self.reach(ctx, brush))

    def displace(self, ctx: StrokeContext, brush: Brush, event: BrushEvent) -> Displacement:
        return self.integrate(ctx, brush, self.field(ctx, brush, event))

    def integrate(self, ctx: StrokeContext, brush: Brush, field: EventField) -> Displacement:
        """Move the rows within reach of the load and its mirror images (paper Sec. 3.2)."""
        kernel, center, load, step = field.kernel, field.center, field.load, field.step
        cutoff = brush.cutoff(ctx.model_size, field.reach)
        signs = mirror_signs(brush.symmetry)
        mesh = ctx.mesh
        rows = mesh.rows_near(center, step, None if cutoff is None else cutoff[1], signs)
        out = ctx.rows(len(rows))
        if len(rows):
            try:
                # written through only if every end position is finite (the kernel checks)
                kernel.streamlines(
                    mesh.vertices,
                    center,
                    load,
                    center_step=step,
                    cutoff=cutoff,
                    mirror_signs=signs,
                    origin=mesh.origin,
                    substeps=max(brush.substeps, 1),
                    tolerance=None if brush.substeps else STREAMLINE_TOLERANCE,
                    indices=rows,
                    in_place=ctx.write_through,
                    rows_checked=True,  # the influence test's rows of a finite mesh
                    out=out,
                )
            except StreamlineOverflow:
                raise ValueError(self._overflow()) from None
            if not ctx.write_through and not np.isfinite(out).all():  # never NaN in the mesh
                raise ValueError(self._overflow())
        return Displacement(rows, None if ctx.write_through else out, written=ctx.write_through)

    def _overflow(self) -> str:
        return (
            f"the {self.kind} event would move vertices to infinity; "
            "lower the strength, amount or delta"
        )
