"""Brush settings and the loads they put on the Green's function kernel.

Every brush of Regularized Kelvinlets (de Goes & James 2017), extended to any material by the
regularized Green's function of ``kernel.py``:

* ``grab``: a vector load f at the cursor. The center moves with the cursor during an event,
  c(t) = c₀ + tΔ, and f solves G(0) f = Δ for the anisotropic G(0), so the point under the
  cursor has velocity exactly Δ along its whole streamline and lands on the cursor.
* ``grab_biscale``, ``grab_triscale``: the same with Kelvinlets' multi-scale falloff (weighted
  sums of the falloff at radii ε, 1.25ε, 1.25²ε; the ratio 1.25 is ours: Blender's Elastic
  Deform uses 2), which decays faster.
* ``scale``, ``twist``, ``pinch``: affine loads H = k B at a fixed center, with the pattern B of
  :func:`affine_load_shape`: I, [a]_× (rotation about the view axis a), d dᵀ − e eᵀ (stretch
  along the stroke direction d, squeeze across it, e = a × d). k is set so that the velocity
  gradient J at the centre has component (J : B)/(B : B) = ``strength · amount`` along B,
  whatever the material. An event is the flow of that field over pseudo-time [0, 1] with the
  centre fixed, so the centre's deformation gradient is exp(J): per unit ``amount``, scale is a
  logarithmic strain of 1 in every direction (lengths × e), pinch a log strain of +1 along d
  and −1 across, twist a rotation of 1 radian about a; for small amounts the displacement
  gradient at the centre is ``amount · B``. Log strains and angles add up, so an amount split
  over several events gives the same result. For an isotropic material J = amount · B exactly;
  an anisotropic one adds components that are not along B (its own coupling).
* ``wrinkle``: a grab whose field uses reweighted SH degrees (paper Fig. 10): the force is fixed
  by the full kernel (the grabbed point follows the cursor), the field by the
  ``degree_weights`` of the falloff, which bring out the angular ripples of high degrees
  (:func:`default_wrinkle_weights`). Only an anisotropic material has such degrees (an
  isotropic one has l ≤ 2, so wrinkle = grab); the ripples follow its layers or fibres and
  are strongest where they are tilted to the surface (a laminate whose layers lie in or
  across the surface makes none in the surface's normal direction, by symmetry).

Sizes are relative to the model (the bounding-box diagonal at load), so the same settings act
alike on a 0.15-unit bunny and a 30-unit ogre: ε = radius · model_size, and only vertices within
``influence`` · ε of the load are moved, with a C² smooth cutoff starting at half that radius.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from gogreen_core.radial import GaussianRadial
from gogreen_core.validation import (
    ParameterError,
    check_finite,
    check_integer,
    check_number,
    check_object,
    check_string,
    prefixed,
)

__all__ = [
    "AFFINE_BRUSHES",
    "BRUSH_KINDS",
    "GRAB_BRUSHES",
    "Brush",
    "BrushEvent",
    "affine_load_shape",
    "default_wrinkle_weights",
    "legacy_wrinkle_weights",
    "mirror_signs",
]

#: Vector-load brushes (the cursor point follows the cursor).
GRAB_BRUSHES = ("grab", "grab_biscale", "grab_triscale", "wrinkle")
#: Affine-load brushes.
AFFINE_BRUSHES = ("scale", "twist", "pinch")
BRUSH_KINDS = GRAB_BRUSHES + AFFINE_BRUSHES
#: Where the smooth cutoff starts, as a fraction of the influence radius.
CUTOFF_START = 0.5
#: Default radius of the moved region in multiples of ε (also the pins' reach, and the extent
#: the cursor draws for a brush of infinite influence).
DEFAULT_INFLUENCE = 4.0
#: Radius (in ε) at which :func:`default_wrinkle_weights` equalizes the degrees' radial terms.
WRINKLE_RING = 2.5
#: Highest degree :func:`default_wrinkle_weights` boosts.
WRINKLE_TOP_DEGREE = 8
#: Level the boosted degrees' Gaussian radial terms are brought to at :data:`WRINKLE_RING`, as
#: a fraction of R_0 there (see :func:`default_wrinkle_weights`).
WRINKLE_LEVEL = 0.6


#: Bounds of the brush settings (documented in the README, "Sculpting without the GUI"): a
#: radius is a fraction of the model size; beyond these the numbers overflow or mean nothing.
MIN_RADIUS, MAX_RADIUS = 1e-6, 100.0
MAX_STRENGTH = 1e3
MAX_SUBSTEPS = 1000
#: Largest |amount| (and |strength · amount|) of an affine brush event: a strain or an angle
#: in radians per event at the brush centre.
MAX_AMOUNT = 100.0


@dataclass(frozen=True)
class Brush:
    """Settings of one brush (immutable; use :func:`dataclasses.replace` to change one).

    kind : one of :data:`BRUSH_KINDS`.
    radius : regularization radius ε as a fraction of the model size (bounding-box diagonal).
    strength : multiplies the cursor displacement (grab) or the amount (affine brushes).
    substeps : how each event is integrated over pseudo-time [0, 1]. 0 (the default): adaptive
        RK4 with a per-vertex error estimate, within 1e-4 of the cursor motion of a 64-step
        reference (:meth:`GreenKernel.streamlines`); n ≥ 1: exactly n RK4 steps for every
        vertex (what sessions recorded before adaptive integration used, so they replay bit for
        bit).
    influence : radius of the influence ball in multiples of ε (``inf``: every vertex).
    symmetry : mirror planes, any of "x", "y", "z" (e.g. "xz"): the brush is applied mirrored
        across the planes through the model's center normal to those axes.
    """

    kind: str = "grab"
    radius: float = 0.1
    strength: float = 1.0
    substeps: int = 0
    influence: float = DEFAULT_INFLUENCE
    symmetry: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.kind, str) or self.kind not in BRUSH_KINDS:
            raise ParameterError(
                "kind", f"unknown brush {self.kind!r}; expected one of {', '.join(BRUSH_KINDS)}"
            )
        radius = check_number("radius", self.radius, low=MIN_RADIUS, high=MAX_RADIUS)
        strength = check_number("strength", self.strength, low=-MAX_STRENGTH, high=MAX_STRENGTH)
        substeps = check_integer("substeps", self.substeps, low=0, high=MAX_SUBSTEPS)
        influence = self.influence
        if not (isinstance(influence, float) and influence == math.inf):  # inf: every vertex
            influence = check_number("influence", influence, low=0.0, low_open=True)
        symmetry = check_string("symmetry", self.symmetry, max_length=3).lower()
        axes = "".join(sorted(set(symmetry)))
        if any(a not in "xyz" for a in axes):
            raise ParameterError(
                "symmetry", f"brush symmetry must use the letters x, y, z (got {self.symmetry!r})"
            )
        for name, value in [
            ("radius", radius),
            ("strength", strength),
            ("substeps", substeps),
            ("influence", float(influence)),
            ("symmetry", axes),
        ]:
            object.__setattr__(self, name, value)

    @property
    def is_affine(self) -> bool:
        return self.kind in AFFINE_BRUSHES

    def eps(self, model_size: float) -> float:
        """ε in model units."""
        return self.radius * model_size

    def scaled(self, factor: float) -> Brush:
        """This brush with its radius times ``factor`` (at least :data:`MIN_RADIUS`); itself
        at 1 (pen pressure → radius)."""
        if factor == 1.0:
            return self
        return replace(self, radius=max(self.radius * factor, MIN_RADIUS))

    def cutoff(self, model_size: float) -> tuple[float, float] | None:
        """(inner, outer) cutoff radii in model units, or None for no cutoff."""
        if math.isinf(self.influence):
            return None
        outer = self.influence * self.eps(model_size)
        return CUTOFF_START * outer, outer

    def to_dict(self) -> dict:
        data = asdict(self)
        data["influence"] = None if math.isinf(self.influence) else self.influence
        return data

    @classmethod
    def from_dict(cls, data: object, path: str = "brush") -> Brush:
        """Inverse of :meth:`to_dict`, the brush's schema: :class:`ParameterError` naming the
        field (``path.radius``...) for a missing, unknown, mistyped or out-of-range one."""
        fields = ("kind", "radius", "strength", "substeps", "influence", "symmetry")
        values = dict(check_object(path, data, optional=fields))
        if "influence" in values and values["influence"] is None:
            values["influence"] = math.inf
        with prefixed(path):
            return cls(**values)


def _vector(name: str, value, nonzero: bool = False) -> np.ndarray:
    arr = check_finite(name, value, (3,))
    if nonzero and not np.any(arr):
        raise ParameterError(name, f"{name} must be nonzero (got {value!r})")
    return arr


@dataclass(frozen=True)
class BrushEvent:
    """One mouse event of a stroke (model units).

    center : (3,) the cursor on the surface at the start of the event.
    delta : (3,) cursor displacement during the event (grab brushes).
    amount : affine brushes: the logarithmic strain (scale, pinch) or the angle in radians
        (twist) at the brush centre per event, times the brush strength (see module docstring).
    axis : (3,) view direction (twist axis, pinch normal), any nonzero length; +z when omitted.
    direction : (3,) stroke direction in the view plane (pinch); any vector ⟂ axis if omitted.
    radius_factor : in (0, 1], scales the stroke brush's radius ε for this event alone (pen
        pressure → radius along a stroke); its kernel ε, influence ball and safety bound use
        max(radius · radius_factor, MIN_RADIUS). 1 (the default) is not written by
        :meth:`to_dict`, so sessions without pressure read and write as before.
    """

    center: np.ndarray
    delta: np.ndarray = field(default_factory=lambda: np.zeros(3))
    amount: float = 0.0
    axis: np.ndarray | None = None
    direction: np.ndarray | None = None
    radius_factor: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _vector("center", self.center))
        object.__setattr__(self, "delta", _vector("delta", self.delta))
        amount = check_number("amount", self.amount, low=-MAX_AMOUNT, high=MAX_AMOUNT)
        object.__setattr__(self, "amount", amount)
        if self.axis is not None:
            # kept as given (normalized where used): a stored unit vector renormalized on
            # reading could differ in its last bit and a replay would drift
            object.__setattr__(self, "axis", _vector("axis", self.axis, nonzero=True))
        if self.direction is not None:
            object.__setattr__(self, "direction", _vector("direction", self.direction))
        factor = check_number("radius_factor", self.radius_factor, low=0.0, high=1.0, low_open=True)
        object.__setattr__(self, "radius_factor", factor)

    def brush(self, stroke_brush: Brush) -> Brush:
        """The brush this event acts with: ``stroke_brush`` with its radius scaled by
        :attr:`radius_factor` (:meth:`Brush.scaled`)."""
        return stroke_brush.scaled(self.radius_factor)

    def to_dict(self) -> dict:
        data: dict = {"center": self.center.tolist()}
        if np.any(self.delta):
            data["delta"] = self.delta.tolist()
        if self.amount:
            data["amount"] = self.amount
        if self.axis is not None:
            data["axis"] = self.axis.tolist()
        if self.direction is not None:
            data["direction"] = self.direction.tolist()
        if self.radius_factor != 1.0:
            data["radius_factor"] = self.radius_factor
        return data

    @classmethod
    def from_dict(cls, data: object, path: str = "event") -> BrushEvent:
        """Inverse of :meth:`to_dict`, the event's schema: :class:`ParameterError` naming the
        field (``path.delta``...)."""
        fields = ("center", "delta", "amount", "axis", "direction", "radius_factor")
        values = check_object(path, data, required=("center",), optional=fields[1:])
        with prefixed(path):
            return cls(**values)


def _tame(vector) -> np.ndarray:
    """``vector`` (3,), rescaled by its largest component when its length would overflow or
    underflow (a direction is all that is used)."""
    v = np.asarray(vector, dtype=np.float64)
    peak = np.abs(v).max()
    return v / peak if peak > 1e150 or 0 < peak < 1e-150 else v


def _unit(vector) -> np.ndarray:
    v = _tame(vector)
    return v / np.linalg.norm(v)


def affine_load_shape(
    kind: str, axis: np.ndarray | None, direction: np.ndarray | None
) -> np.ndarray:
    """Pattern B (3, 3) of an affine brush: the velocity gradient that ``amount`` 1 asks for at
    the brush centre. ``scale``: B = I (every direction stretches); ``twist``: B = [a]_×
    (B x = a × x, a rotation about the unit view axis a, one radian per unit); ``pinch``:
    B = d dᵀ − e eᵀ (stretch along the unit stroke direction d projected ⟂ a, squeeze along
    e = a × d)."""
    a = np.array([0.0, 0.0, 1.0]) if axis is None else _unit(axis)
    if kind == "scale":
        return np.eye(3)
    if kind == "twist":
        return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    if kind == "pinch":
        d = np.cross(a, [1.0, 0.0, 0.0]) if direction is None else _tame(direction)
        d = d - a * (d @ a)
        if np.linalg.norm(d) < 1e-12:
            d = np.cross(a, [0.0, 1.0, 0.0])
        d = d / np.linalg.norm(d)
        e = np.cross(a, d)
        return np.outer(d, d) - np.outer(e, e)
    raise ValueError(f"{kind!r} is not an affine brush ({', '.join(AFFINE_BRUSHES)})")


def default_wrinkle_weights(l_max: int) -> np.ndarray:
    """Per-degree weights of the wrinkle brush (l_max + 1,): what the app, the presets and
    "Use a wrinkle material" start with.

    Degree l's field is Y_l(x̂) R_l(r) P_l: its angular ripples (up to l around a ring) are
    there whenever the material is anisotropic, but R_l(r) grows like r^l, so within the brush
    (r ≲ 2.5ε; the cutoff fades the field from 2ε to 4ε) the Gaussian R_4, R_6, R_8 are 6, 18
    and 59 times smaller than R_0 at 2.5ε (10, 40, 195 at 2ε), and the old weights
    max(1, l/2) left them invisible (a stroke differed from grab by ~5 % of its largest
    displacement). Here each degree 2 < l ≤ :data:`WRINKLE_TOP_DEGREE` is weighted so its
    Gaussian radial term reaches :data:`WRINKLE_LEVEL` = 0.6 of R_0 at ρ = :data:`WRINKLE_RING`
    = 2.5: w_l = 0.6 R_0(2.5 ε) / R_l(2.5 ε), i.e. 3.79, 10.67, 35.54 for l = 4, 6, 8.
    Measured on the default model with the "Layered sheet wrinkles" material
    (``python tests/test_wrinkle.py``, strokes of 10 events, 1 ε in all): normal ripples
    around the brush 0.19 of the stroke's largest displacement (median; grab 0.056, the old
    weights 0.045 with the old 1:30 material), the grabbed point following the cursor exactly;
    and no face folded over in 120 strokes of 1.5 ε. With the layers tilted 20°, level 0.6
    gave ripples 0.16 and no fold, 0.75 gave 0.18 but folded faces in 3 strokes of those 120,
    1.0 gave 0.22 and 2 (the ripples are compressions: the events of a stroke repeat them
    until they fold), 0.5 gave 0.13. Degrees above 8 keep weight 1: their radial terms peak
    beyond the brush (R_10(2.5ε) = 0.004 R_0(2.5ε)), so boosting them only raises a wall at
    the rim, and the safe falloff bound then scales the whole stroke down (l_max 12, all
    boosted: the surface moved 0.3 × the cursor motion, with no stronger ripples). Degrees
    ≤ 2 keep 1: they make no ripples. Odd entries are unused by G (∇G's degree l uses weight
    l − 1). Rounded to 2 decimals (the Falloff panel shows 2: editing one weight there leaves
    the others).
    """
    l_max = check_integer("l_max", l_max, low=0)
    weights = np.ones(l_max + 1)
    degrees = np.arange(3, min(l_max, WRINKLE_TOP_DEGREE) + 1)
    if len(degrees):
        gaussian, ring = GaussianRadial(1.0), np.array([WRINKLE_RING])
        r0 = gaussian.radial(0, ring)[0]
        weights[degrees] = [WRINKLE_LEVEL * r0 / gaussian.radial(int(l), ring)[0] for l in degrees]
    return np.round(weights, 2)


def legacy_wrinkle_weights(l_max: int) -> np.ndarray:
    """The wrinkle weights max(1, l/2) (l_max + 1,) that ``degree_weights = None`` means in
    the engine: sessions and presets recorded ``null`` for them before
    :func:`default_wrinkle_weights` changed, so None keeps this meaning and they replay
    exactly; new code records the weights it uses explicitly."""
    l_max = check_integer("l_max", l_max, low=0)
    return np.maximum(1.0, np.arange(l_max + 1) / 2.0)


def mirror_signs(symmetry: str) -> np.ndarray:
    """Sign rows (2^k, 3) of the mirror group of ``symmetry`` ("", "x", "xz", ...); row 0 is the
    identity."""
    rows = [np.ones(3)]
    for axis in symmetry:
        flip = np.ones(3)
        flip["xyz".index(axis)] = -1.0
        rows += [r * flip for r in rows]
    return np.array(rows)
