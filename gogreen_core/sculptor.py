"""The sculpting engine: a mesh, a material, a falloff, brushes, constraints, history, a log.

Everything the app does with the mouse goes through :class:`Sculptor`, so a script (or
``gogreen replay``) can do it too. Data flows one way: material → kernel → brush → integrator →
new vertex positions.

How a stroke accumulates: a stroke is :meth:`Sculptor.begin_stroke`, one
:meth:`Sculptor.stroke_event` per mouse event, :meth:`Sculptor.end_stroke`. Each event moves the
current (already deformed) vertices along the brush's displacement field taken as a velocity
over pseudo-time [0, 1] (adaptive RK4, or ``brush.substeps`` fixed steps; paper Sec. 3.2);
successive events compose, so a stroke is the composition of the flows of its events. For grab
brushes the load center travels with the cursor during each event, so the point under the cursor
follows the cursor path exactly. A stroke is one undo step, and one entry of the session log.

Safe falloffs: the load is normalized at the centre (the grabbed point follows the cursor) only
while no vertex can then move more than :data:`MAX_GRAB_RATIO` × the cursor motion in one event
(nor shear faces over); a falloff an artist edited so that its field is weak at the centre gets
its load scaled down to that bound (:meth:`Sculptor._load`), and a zero one is refused.

Constraints (paper Fig. 1) are applied as a direct displacement u(x) = Σ_j G(x − p_j) f_j on
every vertex (no pseudo-time), so the constrained points land exactly on their targets.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from gogreen_core._expansion import near_segment
from gogreen_core.brushes import (
    AFFINE_BRUSHES,
    MAX_AMOUNT,
    MAX_RADIUS,
    MIN_RADIUS,
    Brush,
    BrushEvent,
    affine_load_shape,
    legacy_wrinkle_weights,
    mirror_signs,
)
from gogreen_core.constraints import CONSTRAINT_INFLUENCE, ConstraintSet
from gogreen_core.falloff_safety import (
    AFFINE_FALLBACK,
    AFFINE_MARGIN,
    MAX_GRAB_RATIO,
    MAX_GRAB_STRAIN,
    FieldBound,
    mean_green_direction,
)
from gogreen_core.history import History
from gogreen_core.kernel import (
    EVALUATION,
    STREAMLINE_TOLERANCE,
    GreenKernel,
    StreamlineOverflow,
)
from gogreen_core.material import Material
from gogreen_core.operations import (
    ConstraintAdd,
    ConstraintDrag,
    ConstraintRadius,
    ConstraintRemove,
    ConstraintsClear,
    FalloffChange,
    MaterialChange,
    Operation,
    Redo,
    Stroke,
    Undo,
    operation_from_dict,
)
from gogreen_core.radial import GaussianRadial, MultiscaleRadial, RadialProfile, SplineRadial
from gogreen_core.schema import (
    EngineSettings,
    check_material,
    parse_degree_weights,
    parse_l_max,
)
from gogreen_core.session import (
    SESSION_FORMAT,
    SESSION_VERSION,
    Session,
    SessionLog,
    mesh_fingerprint,
    parse_session,
)
from gogreen_core.validation import (
    ParameterError,
    check_bool,
    check_integer,
    check_number,
    check_vector,
    prefixed,
    vector_norm,
)

__all__ = ["MAX_REACH", "SESSION_FORMAT", "Sculptor", "mesh_fingerprint"]

#: Step (in ε) of the central differences that measure the velocity gradient an affine load
#: makes at its centre (Sculptor._centre_jacobian), which sets what `amount` means.
_JACOBIAN_STEP = 1e-3
#: Farthest a brush centre, a grab displacement (times the strength), a pin or a pin drag may
#: reach, in model sizes from the model's centre: beyond it nothing is left to sculpt, and the
#: arithmetic stays far from overflow whatever the model's scale.
MAX_REACH = 1e3
#: Undo labels of settings changes (a continued change joins the last of these).
_SETTING_LABELS = ("material", "falloff", "constraint radius")
_NO_ROWS = np.zeros((0, 3))
#: A field smaller than this fraction of the material's G scale (‖A‖/ε) is zero everywhere.
_ZERO_FIELD = 1e-9


class _Pins(NamedTuple):
    """The pins (k, 3) before or after adding, removing or clearing them (an undo step)."""

    points: np.ndarray


class _Pin(NamedTuple):
    """A dragged pin's index and position: the caller state of a pin-drag undo step."""

    index: int
    point: np.ndarray


def _check_mesh(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    v = np.array(vertices, dtype=np.float64)
    f = np.array(faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
        raise ValueError(f"vertices must be a non-empty (N, 3) array (got shape {v.shape})")
    if not np.all(np.isfinite(v)):
        raise ValueError("vertices contain NaN or infinite coordinates")
    if f.ndim != 2 or f.shape[1] != 3:
        raise ValueError(f"faces must be an (M, 3) array (got shape {f.shape})")
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        raise ValueError(f"faces reference vertices outside 0..{len(v) - 1}")
    return v, f


@dataclass
class _Stroke:
    brush: Brush
    before: np.ndarray
    touched: np.ndarray
    events: list = field(default_factory=list)


class Sculptor:
    """Sculpting state and operations (no GUI).

    Parameters
    ----------
    vertices : (N, 3) float64, faces : (M, 3) int64
        The mesh; vertices are copied and then edited in place (see :attr:`vertices`).
    material : Material, default isotropic E = 1, ν = 0.3
    l_max : int, default 8
    falloff : RadialProfile, default GaussianRadial
        The falloff shape; its ε is ignored (each brush sets ε = radius · model size).
    degree_weights : (l_max + 1,) floats, optional
        Per-degree weights of the wrinkle brush. None means :func:`legacy_wrinkle_weights`
        (what sessions recorded as null, so they replay exactly); the app and presets pass
        :func:`~gogreen_core.brushes.default_wrinkle_weights` explicitly.
    constraint_radius : float, default 0.1
        ε of the pins as a fraction of the model size.
    history_bytes : memory cap of the undo history.

    The parts: the mesh, the settings and strokes live here; undo steps in :attr:`history`
    (:class:`History`); the session log in a :class:`SessionLog` of typed operation records
    (:mod:`gogreen_core.operations`), exported by :meth:`session` and applied by :meth:`replay`.
    """

    def __init__(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        *,
        material: Material | None = None,
        l_max: int = 8,
        falloff: RadialProfile | None = None,
        degree_weights: np.ndarray | None = None,
        constraint_radius: float = 0.1,
        history_bytes: int = 512 * 2**20,
    ):
        self._vertices, self._faces = _check_mesh(vertices, faces)
        low, high = self._vertices.min(axis=0), self._vertices.max(axis=0)
        self.model_size = float(np.linalg.norm(high - low))
        if not self.model_size > 0:
            raise ValueError("the mesh has zero size (all vertices coincide)")
        if not np.isfinite(self.model_size):
            raise ValueError("the mesh is too large (its size overflows a float)")
        #: Point of the mirror planes: the center of the bounding box at load.
        self.origin = 0.5 * (low + high)
        self.history = History(history_bytes)
        self._event_rows = np.empty((0, 3))  # the integrator's result rows (grown as needed)
        self._kernels: dict[str, GreenKernel] = {}
        #: (base kernel, sampled field bound or affine limits): see _field_bound.
        self._bounds: dict[tuple, tuple] = {}
        self._stroke: _Stroke | None = None
        self._constraints: ConstraintSet | None = None
        self._log = SessionLog()
        #: False for a sculptor replaying a version-1 session: settings are no undo steps.
        self._settings_undoable = True
        #: The kernels' compiled arithmetic: 1 for a sculptor replaying a session of version 1
        #: or 2, which it reproduces bit for bit (see GreenKernel's ``evaluation``).
        self._evaluation = EVALUATION
        self._fingerprint = mesh_fingerprint(self._vertices)
        material = Material.isotropic(1.0, 0.3) if material is None else material
        self._settings = self._checked(
            material=material,
            falloff=falloff or GaussianRadial(1.0),
            l_max=l_max,
            degree_weights=degree_weights,
            constraint_radius=constraint_radius,
        )
        self._kernels = {"full": self._full_kernel(self._settings)}
        self._initial = self._settings

    # -- state -------------------------------------------------------------------------------
    @property
    def vertices(self) -> np.ndarray:
        """(N, 3) current positions (read-only view; the engine edits the array in place)."""
        view = self._vertices.view()
        view.setflags(write=False)
        return view

    @property
    def faces(self) -> np.ndarray:
        return self._faces

    @property
    def settings(self) -> EngineSettings:
        """Material, falloff, l_max, wrinkle weights and constraint radius (immutable)."""
        return self._settings

    @property
    def material(self) -> Material:
        return self._settings.material

    @property
    def falloff(self) -> RadialProfile:
        return self._settings.falloff

    @property
    def l_max(self) -> int:
        return self._settings.l_max

    @property
    def degree_weights(self) -> np.ndarray:
        """Weights of the wrinkle brush (l_max + 1,)."""
        weights = self._settings.degree_weights
        return legacy_wrinkle_weights(self.l_max) if weights is None else weights

    @property
    def in_stroke(self) -> bool:
        return self._stroke is not None

    # -- settings ----------------------------------------------------------------------------
    def _checked(self, **values) -> EngineSettings:
        """Settings from raw values, each checked (ParameterError naming it)."""
        material, falloff = values["material"], values["falloff"]
        if not isinstance(material, Material):
            raise ParameterError(
                "material", f"material must be a Material (got {type(material).__name__})"
            )
        check_material(material)
        if not isinstance(falloff, RadialProfile) or isinstance(falloff, MultiscaleRadial):
            raise ParameterError(
                "falloff", "falloff must be a single RadialProfile (Gaussian, Kelvinlet, spline)"
            )
        if isinstance(falloff, SplineRadial) and not any(
            np.any(falloff.curve(kind, l)[1]) for kind, l in falloff.curve_keys()
        ):
            raise ParameterError(
                "falloff",
                "the falloff is zero everywhere (every curve's control values are 0): "
                "no brush would move anything",
            )
        l_max = parse_l_max(values["l_max"])
        weights = values["degree_weights"]
        if weights is not None:
            weights = np.array(weights, dtype=np.float64)
            if weights.shape != (l_max + 1,) or not np.isfinite(weights).all():
                raise ParameterError(
                    "degree_weights",
                    f"degree_weights must be l_max + 1 = {l_max + 1} finite numbers",
                )
            weights = parse_degree_weights(weights.tolist(), l_max)
            weights.setflags(write=False)
        radius = check_number(
            "constraint_radius", values["constraint_radius"], low=MIN_RADIUS, high=MAX_RADIUS
        )
        # a copy of the shape: later edits of the caller's profile need another call
        return EngineSettings(material, falloff.with_eps(1.0), l_max, weights, radius)

    def _full_kernel(self, settings: EngineSettings) -> GreenKernel:
        current = self._kernels.get("full")
        if (
            current is not None
            and current.l_max == settings.l_max
            and self._settings.material == settings.material
        ):
            return current.with_radial(settings.falloff)  # same material: no new quadrature
        return GreenKernel(
            settings.material, settings.l_max, settings.falloff, evaluation=self._evaluation
        )

    def _commit(self, settings: EngineSettings) -> None:
        """Compute with ``settings`` from now on: kernels and pins are rebuilt first, so a
        failure (an inadmissible falloff, pins the new radius cannot separate) changes nothing."""
        full = self._full_kernel(settings)
        constraints = None
        if self._constraints is not None:
            constraints = self._constraint_set(full, settings, self._constraints.points)
        self._settings, self._kernels, self._constraints = settings, {"full": full}, constraints

    def change_settings(
        self, *, continued: bool = False, replaying: bool = False, **changes
    ) -> None:
        """Change some of :attr:`settings` (``material``, ``falloff``, ``l_max``,
        ``degree_weights``, ``constraint_radius``): one undo step and one log entry, or part of
        the last settings step when ``continued`` (every value of one slider or curve drag but
        the first). Undo puts the previous settings back exactly.

        A value equal to the current one is ignored unless ``continued`` (a drag may come back
        to where it started) or ``replaying`` (a logged change is always replayed, as the drag it
        stands for was a step).
        """
        keys = set(changes)
        if not keys or not (
            keys in ({"material"}, {"constraint_radius"})
            or keys <= {"falloff", "l_max", "degree_weights"}
        ):
            raise TypeError(
                "change_settings() takes material, constraint_radius, or falloff / l_max / "
                f"degree_weights, one group at a time (got {sorted(keys)})"
            )
        continued = check_bool("continued", continued)
        if "material" in keys:
            label = "material"

            def operation(s: EngineSettings) -> Operation:
                return MaterialChange(s.material, continued)
        elif "constraint_radius" in keys:
            label = "constraint radius"

            def operation(s: EngineSettings) -> Operation:
                return ConstraintRadius(s.constraint_radius, continued)
        else:
            label = "falloff"
            if "l_max" in keys:
                changes.setdefault("degree_weights", None)  # weights belong to one l_max

            def operation(s: EngineSettings) -> Operation:
                return FalloffChange(s.falloff, s.l_max, s.degree_weights, continued)

        before = self._settings
        after = self._checked(**{**before.__dict__, **changes})
        self._refuse_in_stroke(f"change the {label}")
        if after.same_as(before) and not (continued or replaying):
            return  # nothing to do, nothing to undo
        self._commit(after)
        if not self._settings_undoable:  # a version-1 session: settings were no undo steps
            self._log.record(operation(after), replace_last=True)
            return
        last = self.history.undo_labels[-1] if self.history.can_undo else None
        merge = continued and last in _SETTING_LABELS and not self.history.can_redo
        self.history.record_change(
            last if merge else label, _NO_ROWS, _NO_ROWS, merge=merge, state=(before, after)
        )
        # A collapsed drag is logged as its last value; the replay makes the same one step.
        self._log.record(operation(after), replace_last=merge)

    def set_material(self, material: Material, continued: bool = False) -> None:
        """Use ``material`` for the next operations (see :meth:`change_settings`)."""
        self.change_settings(material=material, continued=continued)

    def set_falloff(
        self,
        falloff: RadialProfile,
        l_max: int | None = None,
        degree_weights: np.ndarray | None = None,
        continued: bool = False,
    ) -> None:
        """Use this falloff shape (and truncation degree, wrinkle weights) from now on (see
        :meth:`change_settings`)."""
        self.change_settings(
            falloff=falloff,
            l_max=self.l_max if l_max is None else l_max,
            degree_weights=degree_weights,
            continued=continued,
        )

    def set_constraint_radius(self, radius: float, continued: bool = False) -> None:
        """ε of the constraints, relative to the model size (see :meth:`change_settings`)."""
        radius = check_number("radius", radius, low=MIN_RADIUS, high=MAX_RADIUS)
        self.change_settings(constraint_radius=radius, continued=continued)

    def _refuse_in_stroke(self, what: str) -> None:
        if self._stroke is not None:
            raise RuntimeError(f"cannot {what} during a stroke; end the stroke first")

    def _base_kernel(self, wrinkle: bool) -> GreenKernel:
        key = "wrinkle" if wrinkle else "full"
        if key not in self._kernels:
            s = self._settings
            self._kernels[key] = GreenKernel(
                s.material, s.l_max, s.falloff, self.degree_weights, evaluation=self._evaluation
            )
        return self._kernels[key]

    def kernel(self, brush: Brush) -> GreenKernel:
        """The kernel of ``brush`` on this model: its falloff, ε and degree weights."""
        radial = self.falloff.with_eps(brush.eps(self.model_size))
        if brush.kind == "grab_biscale":
            radial = MultiscaleRadial.biscale(radial)
        elif brush.kind == "grab_triscale":
            radial = MultiscaleRadial.triscale(radial)
        return self._base_kernel(brush.kind == "wrinkle").with_radial(radial)

    # -- strokes -----------------------------------------------------------------------------
    def begin_stroke(self, brush: Brush) -> None:
        """Start a stroke with ``brush``; events follow, then :meth:`end_stroke`."""
        self._refuse_in_stroke("begin a stroke")
        if not isinstance(brush, Brush):
            raise ParameterError("brush", f"brush must be a Brush (got {type(brush).__name__})")
        self._stroke = _Stroke(
            brush, self._vertices.copy(), np.zeros(len(self._vertices), dtype=bool)
        )

    def stroke_event(self, event: BrushEvent) -> np.ndarray:
        """Apply one mouse event of the current stroke; returns the indices of moved vertices.

        Refused (:class:`ParameterError` naming the event field, nothing moved): a centre
        farther than :data:`MAX_REACH` model sizes from the model's centre, a grab displacement
        |strength · delta| beyond that, an affine |strength · amount| above ``MAX_AMOUNT``.
        The event acts with the stroke's brush at radius × ``event.radius_factor``.
        """
        if self._stroke is None:
            raise RuntimeError("stroke_event outside a stroke: call begin_stroke first")
        if not isinstance(event, BrushEvent):
            raise ParameterError(
                "event", f"a stroke event must be a BrushEvent (got {type(event).__name__})"
            )
        # pen pressure → radius: this event's ε, influence ball and load normalization use the
        # scaled radius (the field bound is cached in units of ε, valid for every radius)
        brush = event.brush(self._stroke.brush)
        self._check_event(brush, event)
        moved = self._apply_event(brush, event)
        self._stroke.touched[moved] = True
        self._stroke.events.append(event)
        return moved

    def _check_event(self, brush: Brush, event: BrushEvent) -> None:
        reach = MAX_REACH * self.model_size
        self._check_point("center", event.center)
        if brush.is_affine:
            load = abs(brush.strength * event.amount)
            if not load <= MAX_AMOUNT:
                raise ParameterError(
                    "amount",
                    f"amount × brush strength must be ≤ {MAX_AMOUNT:g} in magnitude "
                    f"(got {event.amount:g} × {brush.strength:g})",
                )
            return
        check_vector("delta", event.delta, max_norm=reach)
        if not vector_norm(brush.strength * event.delta) <= reach:
            raise ParameterError(
                "delta",
                f"delta × brush strength must be ≤ {MAX_REACH:g} model sizes "
                f"({reach:.4g}) long (got |delta| = {vector_norm(event.delta):.4g}, "
                f"strength {brush.strength:g})",
            )

    def end_stroke(self) -> np.ndarray:
        """Finish the stroke: one undo step and one log entry. Returns the moved indices."""
        stroke, self._stroke = self._stroke, None
        if stroke is None:
            return np.zeros(0, dtype=np.int64)
        idx = np.flatnonzero(stroke.touched)
        changed = np.any(stroke.before[idx] != self._vertices[idx], axis=1)
        idx = idx[changed]
        if len(idx):
            self.history.record(
                f"{stroke.brush.kind} stroke", idx, stroke.before[idx], self._vertices[idx]
            )
        if stroke.events:
            self._log.record(Stroke(stroke.brush, tuple(stroke.events)))
        return idx

    def cancel_stroke(self) -> None:
        """Abandon the current stroke, restoring the vertices as they were before it."""
        if self._stroke is not None:
            self._vertices[:] = self._stroke.before
            self._stroke = None

    def apply_brush(self, brush: Brush, events: list[BrushEvent]) -> np.ndarray:
        """A whole stroke at once; returns the moved indices."""
        self.begin_stroke(brush)
        try:
            for number, event in enumerate(events):
                with prefixed(f"events[{number}]"):
                    self.stroke_event(event)
        except Exception:
            self.cancel_stroke()
            raise
        return self.end_stroke()

    def _field_bound(self, brush: Brush, kernel: GreenKernel) -> FieldBound:
        """The sampled field bound of ``brush``'s kernel shape (cached per base kernel, i.e.
        per material, l_max, weights and falloff, and per brush variant and influence; the
        brush radius does not matter)."""
        base = self._base_kernel(brush.kind == "wrinkle")
        variant = brush.kind if brush.kind in ("grab_biscale", "grab_triscale") else ""
        key = (id(base), variant, brush.influence, brush.is_affine)
        cached = self._bounds.get(key)
        if cached is None or cached[0] is not base:
            if len(self._bounds) >= 16:
                self._bounds.clear()
            cached = (base, FieldBound(kernel, brush.influence, brush.is_affine))
            self._bounds[key] = cached
        return cached[1]

    def _load(self, brush: Brush, kernel: GreenKernel, event: BrushEvent):
        """(load, center_step) of one event: a force (3,) or an affine load (3, 3).

        Safe falloffs: the load is normalized at the centre (grab: f = G(0)⁻¹ Δ, the grabbed
        point follows the cursor; affine: the velocity gradient there is strength · amount
        along the pattern) as long as no vertex can then move more than
        :data:`MAX_GRAB_RATIO` |Δ| nor be sheared by more than :data:`MAX_GRAB_STRAIN` |Δ|/ε
        (grab), or more than :data:`AFFINE_MARGIN` × what the Gaussian falloff does with
        this material (affine), in the event; closed-form falloffs always are (their fields
        peak at the centre). An edited falloff whose centre is weak (a dip, a zero or a
        negative R₀ near 0) gets the load scaled to those bounds, with the most moved point
        going along the cursor; a field that is zero everywhere is refused.
        """
        if brush.kind in AFFINE_BRUSHES:
            return self._affine_load(brush, kernel, event), np.zeros(3)
        delta = brush.strength * event.delta
        # The wrinkle brush's force comes from the full (unweighted) kernel at the same falloff.
        full = (
            self._base_kernel(False).with_radial(kernel.radial)
            if brush.kind == "wrinkle"
            else kernel
        )
        g0 = full.green(np.zeros((1, 3)))[0]
        with np.errstate(all="ignore"):
            try:
                force = np.linalg.solve(g0, delta)
            except np.linalg.LinAlgError:  # G(0) = 0: R₀(0) pulled to 0
                force = np.full(3, np.nan)
        size = vector_norm(delta)
        finite = bool(np.all(np.isfinite(force)))
        if size == 0:
            return (force if finite else np.zeros(3)), delta
        bound = self._field_bound(brush, kernel)
        eps = kernel.eps
        if (
            finite
            and bound.motion_sup(force, eps)[0] <= MAX_GRAB_RATIO * size
            and bound.strain_sup(force, eps) * eps <= MAX_GRAB_STRAIN * size
        ):
            return force, delta
        # A weak centre: G(0) = c R₀(0) A whatever the falloff, so A⁻¹ Δ is the direction of
        # G(0)⁻¹ Δ even where R₀(0) = 0; scale it to the bounds.
        direction = np.linalg.solve(mean_green_direction(self.material), delta)
        peak, _, moved = bound.motion_sup(direction, eps)
        if not peak * eps > _ZERO_FIELD * vector_norm(direction) * self._green_scale():
            raise ParameterError(
                "falloff",
                f"the {brush.kind} brush's falloff is zero everywhere within its influence "
                f"({brush.influence:g} ε): raise R0 somewhere in the falloff editor",
            )
        strain = bound.strain_sup(direction, eps) * eps
        scale = min(MAX_GRAB_RATIO / peak, MAX_GRAB_STRAIN / strain if strain else np.inf) * size
        sign = -1.0 if moved @ delta < 0 else 1.0  # the most moved point goes with the cursor
        return direction * (sign * scale), delta

    def _green_scale(self) -> float:
        """‖A‖ (see :func:`mean_green_direction`): G's size for this material at ε = 1 up to a
        falloff factor of order 1."""
        return float(np.linalg.norm(mean_green_direction(self.material), 2))

    def _affine_load(self, brush: Brush, kernel: GreenKernel, event: BrushEvent) -> np.ndarray:
        """Affine load H (3, 3) of one scale / twist / pinch event (see :meth:`_load`)."""
        shape = affine_load_shape(brush.kind, event.axis, event.direction)
        jacobian = self._centre_jacobian(kernel, event.center, shape)
        # Its component along the pattern B (the sign depends on the material: Kelvinlets'
        # scale load contracts for ν < 1/2) is divided out, so that the velocity gradient at
        # the centre has component strength · amount along B: `amount` is a log strain or
        # an angle at the centre whatever the material (brushes.py docstring).
        response = float(np.sum(jacobian * shape) / np.sum(shape * shape))
        amount = brush.strength * event.amount
        eps = kernel.eps
        # The largest displacement and velocity gradient of the load B anywhere: the centre's
        # response must be large enough that B · amount / response stays within the limits.
        bound = self._field_bound(brush, kernel)
        peak, at, moved = bound.motion_sup(shape, eps)
        if not peak * eps**2 > _ZERO_FIELD * self._green_scale():
            raise ParameterError(
                "falloff",
                f"the {brush.kind} brush's falloff has no gradient within its influence "
                f"({brush.influence:g} ε): its odd-degree curves (dR) are zero",
            )
        motion_limit, strain_limit = self._affine_limits(brush, shape)
        needed = max(peak / (motion_limit * eps), bound.strain_sup(shape, eps) / strain_limit)
        if np.linalg.norm(jacobian) >= needed:  # the centre moves: the usual rule
            if not abs(response) * np.linalg.norm(shape) > 1e-3 * np.linalg.norm(jacobian):
                raise ValueError(
                    f"the {brush.kind} brush has no effect with this material and falloff "
                    f"(response {response:.3g})"
                )
            if abs(response) >= needed:
                return shape * (amount / response)
        # A weak centre: scale B to the limits, with the sign of the centre's response, or
        # where that is lost in rounding, the sign that makes the most moved point follow the
        # pattern (outwards for scale).
        if abs(response) * eps > 1e-6 * peak:
            sign = np.sign(response)
        else:
            sign = -1.0 if moved @ (shape @ at) < 0 else 1.0
        return shape * (sign * amount / needed)

    def _affine_limits(self, brush: Brush, shape: np.ndarray) -> tuple[float, float]:
        """(motion in |amount| ε, velocity gradient in |amount|) an affine event of pattern
        ``shape`` may reach: AFFINE_MARGIN × what the Gaussian falloff reaches with the same
        material, l_max, influence and pattern (its field bound is cached per base kernel)."""
        base = self._base_kernel(False)
        key = ("gaussian", id(base), brush.influence)
        cached = self._bounds.get(key)
        if cached is None or cached[0] is not base:
            if len(self._bounds) >= 16:
                self._bounds.clear()
            gaussian = base.with_radial(GaussianRadial(1.0))
            cached = (base, (gaussian, FieldBound(gaussian, brush.influence, True)))
            self._bounds[key] = cached
        gaussian, bound = cached[1]
        jacobian = self._centre_jacobian(gaussian, np.zeros(3), shape)
        response = float(np.sum(jacobian * shape) / np.sum(shape * shape))
        if not abs(response) * np.linalg.norm(shape) > 1e-3 * np.linalg.norm(jacobian):
            return AFFINE_FALLBACK  # no effect with a Gaussian (an incompressible scale)
        load = shape / response
        motion, strain = bound.motion_sup(load, 1.0)[0], bound.strain_sup(load, 1.0)
        return AFFINE_MARGIN * motion, AFFINE_MARGIN * strain

    @staticmethod
    def _centre_jacobian(kernel: GreenKernel, center: np.ndarray, load: np.ndarray) -> np.ndarray:
        """∂u_i/∂x_p (3, 3) at the load's centre of the affine load ``load``: central
        differences at steps h = _JACOBIAN_STEP · ε and h/2, Richardson-extrapolated (error
        O(h⁴), ~1e-12 relative; the O(h²) differences alone were ~1e-6 off)."""
        h = _JACOBIAN_STEP * kernel.eps
        steps = np.array([h, h, h, 0.5 * h, 0.5 * h, 0.5 * h])[:, None]
        offsets = steps * np.vstack([np.eye(3), np.eye(3)])
        u = kernel.affine_displacement(
            center + np.vstack([offsets, -offsets]), center, load
        )  # (12, 3): +h, +h/2, −h, −h/2
        coarse = (u[0:3] - u[6:9]) / (2 * h)
        fine = (u[3:6] - u[9:12]) / h
        return ((4 * fine - coarse) / 3).T  # [i, p] = ∂u_i/∂x_p

    def _active(self, brush: Brush, center: np.ndarray, step: np.ndarray) -> np.ndarray:
        """Indices of vertices the brush can reach during the event (inside the influence
        ball around the segment the center travels, or its mirror images)."""
        cutoff = brush.cutoff(self.model_size)
        if cutoff is None:
            return np.arange(len(self._vertices))
        reach = np.empty(len(self._vertices), dtype=bool)
        signs = mirror_signs(brush.symmetry)
        near_segment(self._vertices, center, step, cutoff[1], signs, self.origin, reach)
        return np.flatnonzero(reach)

    def _apply_event(self, brush: Brush, event: BrushEvent) -> np.ndarray:
        kernel = self.kernel(brush)
        load, step = self._load(brush, kernel, event)
        active = self._active(brush, event.center, step)
        if len(active):
            # the integrator's result rows, kept between events (no per-event allocation)
            buffer = self._event_rows
            if len(buffer) < len(active):
                buffer = self._event_rows = np.empty((len(active), 3))
            try:
                # the mesh rows are read and written in place, the latter only if every end
                # position is finite (a last guard: never write NaN into the mesh)
                kernel._streamlines(
                    self._vertices,
                    event.center,
                    load,
                    center_step=step,
                    cutoff=brush.cutoff(self.model_size),
                    mirror_signs=mirror_signs(brush.symmetry),
                    origin=self.origin,
                    substeps=max(brush.substeps, 1),
                    tolerance=None if brush.substeps else STREAMLINE_TOLERANCE,
                    indices=active,
                    in_place=True,
                    out=buffer,
                )
            except StreamlineOverflow:
                raise ValueError(
                    f"the {brush.kind} event would move vertices to infinity; "
                    "lower the strength, amount or delta"
                ) from None
        return active

    # -- constraints -------------------------------------------------------------------------
    @property
    def constraint_points(self) -> np.ndarray:
        """(k, 3) positions of the constraints."""
        return np.zeros((0, 3)) if self._constraints is None else self._constraints.points

    @property
    def constraint_radius(self) -> float:
        """ε of the constraints as a fraction of the model size."""
        return self._settings.constraint_radius

    @property
    def constraint_reach(self) -> float:
        """Distance (model units) beyond which a pin moves nothing:
        :data:`gogreen_core.constraints.CONSTRAINT_INFLUENCE` constraint radii."""
        return CONSTRAINT_INFLUENCE * self._settings.constraint_radius * self.model_size

    def _constraint_set(
        self, full: GreenKernel, settings: EngineSettings, points: np.ndarray
    ) -> ConstraintSet:
        eps = settings.constraint_radius * self.model_size
        constraints = ConstraintSet(full.with_radial(settings.falloff.with_eps(eps)))
        for p in points:
            constraints.add(p)
        return constraints

    def _check_point(self, name: str, point: object) -> np.ndarray:
        """``point`` (3,) if finite and within :data:`MAX_REACH` model sizes of the centre."""
        p = check_vector(name, point)
        distance = vector_norm(p - self.origin)
        if not distance <= MAX_REACH * self.model_size:
            raise ParameterError(
                name,
                f"{name} is too far from the model: {distance:.4g} from its centre, more than "
                f"{MAX_REACH:g} model sizes ({MAX_REACH * self.model_size:.4g})",
            )
        return p

    def add_constraint(self, point: np.ndarray) -> int:
        """Pin a point (3,) (model units, within :data:`MAX_REACH` model sizes of the model's
        centre); returns its index. An undo step (the vertices do not move)."""
        self._refuse_in_stroke("add a constraint")
        p = self._check_point("point", point)
        if self._constraints is None:
            constraints = self._constraint_set(self._base_kernel(False), self._settings, [])
        else:
            constraints = self._constraints
        before = constraints.points
        index = constraints.add(p)
        self._constraints = constraints
        self._record_pins("add pin", before)
        self._log.record(ConstraintAdd(p))
        return index

    def _record_pins(self, label: str, before: np.ndarray) -> None:
        """One undo step for a change of the pins alone (positions before and now)."""
        state = (_Pins(before), _Pins(self.constraint_points))
        self.history.record(label, np.zeros(0, dtype=np.int64), _NO_ROWS, _NO_ROWS, state)

    def _set_pins(self, points: np.ndarray) -> None:
        """Rebuild the pins at ``points`` (k, 3) (undo/redo of an add, remove or clear)."""
        if not len(points):
            self._constraints = None
            return
        self._constraints = self._constraint_set(self._base_kernel(False), self._settings, points)

    def _check_index(self, index: object) -> int:
        count = 0 if self._constraints is None else len(self._constraints)
        if count == 0:
            raise ParameterError("index", f"index {index!r}: there are no constraints")
        return check_integer("index", index, low=0, high=count - 1)

    def remove_constraint(self, index: int) -> None:
        """Remove pin ``index`` (an undo step)."""
        self._refuse_in_stroke("remove a constraint")
        index = self._check_index(index)
        before = self._constraints.points
        self._constraints.remove(index)
        self._record_pins("remove pin", before)
        self._log.record(ConstraintRemove(index))

    def clear_constraints(self) -> None:
        """Remove every pin (an undo step when there were any)."""
        self._refuse_in_stroke("clear the constraints")
        before = self.constraint_points
        self._constraints = None
        if len(before):
            self._record_pins("clear pins", before)
        self._log.record(ConstraintsClear())

    def drag_constraint(self, index: int, delta: np.ndarray, continued: bool = False) -> np.ndarray:
        """Move constraint ``index`` by ``delta`` (3,) while the others stay: every vertex moves
        by u = Σ_j G(x − p_j) f_j with u(p_index) = delta and u(p_j) = 0. Returns (N, 3) u.

        ``continued``: this step continues the previous drag (one mouse drag = one undo step).
        """
        self._refuse_in_stroke("drag a constraint")
        index = self._check_index(index)
        continued = check_bool("continued", continued)
        d = check_vector("delta", delta, max_norm=MAX_REACH * self.model_size)
        start = self._constraints.points[index]
        self._check_point("delta", start + d)  # the pin stays within reach of the model
        targets = np.zeros((len(self._constraints), 3))
        targets[index] = d
        forces = self._constraints.solve(targets)
        # only the rows within the pins' reach move: no pass over the whole mesh
        rows, moved = self._constraints.displacement_rows(self._vertices, forces)
        if not np.all(np.isfinite(moved)):
            raise ParameterError("delta", "the pin drag would move vertices to infinity")
        self._constraints.move(index, start + d)
        before = self._vertices[rows]
        self._vertices[rows] += moved
        # the pin's own move is undone with the vertices: (index, position) before and after
        pin = (_Pin(index, start), _Pin(index, start + d))
        self.history.record_rows(
            "constraint drag", rows, before, self._vertices[rows], merge=continued, state=pin
        )
        self._log.record(ConstraintDrag(index, d, continued))
        u = np.zeros_like(self._vertices)
        u[rows] = moved
        return u

    # -- history -----------------------------------------------------------------------------
    def undo(self) -> str | None:
        """Undo the last step (bit for bit; a settings step puts the previous settings back
        exactly); returns its label or None."""
        self._refuse_in_stroke("undo")
        label = self.history.undo(self._vertices)
        if label is not None:
            self._restore_state()
            self._log.record(Undo())
        return label

    def redo(self) -> str | None:
        self._refuse_in_stroke("redo")
        label = self.history.redo(self._vertices)
        if label is not None:
            self._restore_state()
            self._log.record(Redo())
        return label

    def _restore_state(self) -> None:
        """Put back the settings, or a dragged pin, that the undone/redone step had."""
        state = self.history.restored_state
        if isinstance(state, EngineSettings):
            self._commit(state)
            return
        if isinstance(state, _Pins):
            self._set_pins(state.points)
            return
        if not isinstance(state, _Pin) or self._constraints is None:
            return
        if state.index < len(self._constraints):
            with contextlib.suppress(ValueError):  # another pin sits there now: leave it
                self._constraints.move(state.index, state.point)

    # -- session log -------------------------------------------------------------------------
    @property
    def operations(self) -> list[Operation]:
        """The typed operation records so far (see :mod:`gogreen_core.operations`)."""
        return list(self._log)

    def session(self) -> dict:
        """The session so far as a JSON-ready dict (see README, "Session files")."""
        return {
            "format": SESSION_FORMAT,
            "version": (
                1
                if not self._settings_undoable
                else (SESSION_VERSION if self._evaluation == EVALUATION else 2)
            ),
            "mesh": {
                "vertices": len(self._vertices),
                "faces": len(self._faces),
                "sha256": self._fingerprint,
            },
            "settings": self._initial.to_dict(),
            "operations": self._log.to_list(),
        }

    @classmethod
    def from_session(
        cls, session: dict | Session, vertices: np.ndarray, faces: np.ndarray
    ) -> Sculptor:
        """A sculptor on ``vertices``/``faces`` with the session's initial settings (no
        operations applied yet; see :meth:`replay`). The whole session is checked first
        (:func:`~gogreen_core.session.parse_session`)."""
        parsed = session if isinstance(session, Session) else parse_session(session)
        if parsed.vertices != len(vertices) or parsed.faces != len(faces):
            raise ValueError(
                f"the session was recorded on a mesh with {parsed.vertices} vertices and "
                f"{parsed.faces} faces; this one has {len(vertices)} and {len(faces)}"
            )
        sculptor = cls(vertices, faces, **parsed.settings)
        sculptor._settings_undoable = parsed.version >= 2
        if parsed.version < 3:  # recorded with evaluation 1: replayed with it, bit for bit
            sculptor._evaluation = 1
            sculptor._kernels = {}
            sculptor._kernels = {"full": sculptor._full_kernel(sculptor._settings)}
        return sculptor

    def replay(
        self,
        operations: list[dict] | list[Operation] | Session,
        progress: Callable[[int, int], None] | None = None,
    ) -> None:
        """Apply logged operations in order (the result is bit for bit the recorded one on the
        same machine). ``progress(done, total)`` is called after each mouse event and each
        other operation.

        All of them are checked before any is applied (ParameterError naming the field, e.g.
        ``operations[3].events[0].delta``), and a replay that fails part-way is rolled back:
        the mesh, settings, pins, history and log are as before the call.
        """
        if isinstance(operations, Session):
            ops = list(operations.operations)
        else:
            ops = [
                op if isinstance(op, Operation) else operation_from_dict(op, f"operations[{i}]")
                for i, op in enumerate(operations)
            ]
        total = sum(op.steps for op in ops)
        done = 0

        def step() -> None:
            nonlocal done
            done += 1
            if progress:
                progress(done, total)

        saved = self._checkpoint()
        number = 0
        try:
            for number, op in enumerate(ops):
                with prefixed(f"operations[{number}]"):
                    op.apply(self, step)
        except (ValueError, RuntimeError) as exc:
            self._rollback(saved)
            if isinstance(exc, ParameterError):
                raise
            raise ValueError(f"operations[{number}] ({ops[number].name}): {exc}") from None
        except BaseException:
            self._rollback(saved)
            raise

    def _checkpoint(self) -> tuple:
        points = None if self._constraints is None else self._constraints.points
        return (
            self._vertices.copy(),
            self._settings,
            dict(self._kernels),
            self._constraints,
            points,
            self.history.snapshot(),
            len(self._log),
        )

    def _rollback(self, saved: tuple) -> None:
        vertices, settings, kernels, constraints, points, history, log_length = saved
        self.cancel_stroke()
        self._vertices[:] = vertices
        self._settings, self._kernels = settings, kernels
        if constraints is not None:
            constraints = self._constraint_set(self._kernels["full"], settings, points)
        self._constraints = constraints
        self.history.restore(history)
        self._log.truncate(log_length)
