"""Brush settings and brush events: the immutable values a stroke is made of.

Sizes are relative to the model (the bounding-box diagonal at load), so the same settings act
alike on a 0.15-unit bunny and a 30-unit ogre: ε = radius · model_size, and only vertices within
``influence`` · ε of the load are moved, with a C² smooth cutoff starting at half that radius.
What each kind does is its row of the brush table (:mod:`gogreen_core.sculpt.brushes.table`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from gogreen_core.field.limits import MAX_AMOUNT, MAX_RADIUS, MAX_STRENGTH, MAX_SUBSTEPS, MIN_RADIUS
from gogreen_core.sculpt.brushes.base import AUTO_INFLUENCE, CUTOFF_START, BrushType
from gogreen_core.sculpt.brushes.table import brush_type
from gogreen_core.validation import (
    ParameterError,
    check_finite,
    check_integer,
    check_number,
    check_object,
    check_string,
    prefixed,
)

__all__ = ["Brush", "BrushEvent"]


@dataclass(frozen=True)
class Brush:
    """Settings of one brush (immutable; use :func:`dataclasses.replace` to change one).

    kind : one of :data:`BRUSH_KINDS`.
    radius : regularization radius ε as a fraction of the model size (bounding-box diagonal).
    strength : multiplies the cursor displacement (grab) or the amount (affine brushes).
    substeps : RK4 steps of each event over pseudo-time [0, 1]; 0 (the default): adaptive, within
        1e-4 of the cursor motion (:meth:`GreenKernel.streamlines`).
    influence : radius of the influence ball in ε (``inf``: every vertex), or ``"auto"`` (the
        default): where the brush's field has faded (:meth:`Sculptor.influence` gives it).
    symmetry : mirror planes, any of "x", "y", "z" (e.g. "xz"), through the model's origin.
    """

    kind: str = "grab"
    radius: float = 0.1
    strength: float = 1.0
    substeps: int = 0
    influence: float | str = AUTO_INFLUENCE
    symmetry: str = ""

    def __post_init__(self) -> None:
        with prefixed("kind"):
            brush_type(self.kind)  # an offered or a replay-only kind
        radius = check_number("radius", self.radius, low=MIN_RADIUS, high=MAX_RADIUS)
        strength = check_number("strength", self.strength, low=-MAX_STRENGTH, high=MAX_STRENGTH)
        substeps = check_integer("substeps", self.substeps, low=0, high=MAX_SUBSTEPS)
        influence = self.influence
        if isinstance(influence, str):
            if influence != AUTO_INFLUENCE:
                raise ParameterError(
                    "influence",
                    f"influence must be a number of ε, inf or {AUTO_INFLUENCE!r} "
                    f"(got {influence!r})",
                )
        elif not (isinstance(influence, float) and influence == math.inf):  # every vertex
            influence = float(check_number("influence", influence, low=0.0, low_open=True))
        symmetry = check_string("symmetry", self.symmetry, max_length=3).lower()
        axes = "".join(sorted(set(symmetry)))
        if any(a not in "xyz" for a in axes):
            raise ParameterError(
                "symmetry", f"brush symmetry must use the letters x, y, z (got {self.symmetry!r})"
            )
        checked = dict(radius=radius, strength=strength, substeps=substeps, influence=influence)
        for name, value in {**checked, "symmetry": axes}.items():
            object.__setattr__(self, name, value)

    @property
    def type(self) -> BrushType:
        """What this kind of brush does: its row of the brush table."""
        return brush_type(self.kind)

    @property
    def is_affine(self) -> bool:
        """The brush stays at the press point and its events carry an ``amount``."""
        return self.type.is_affine

    def eps(self, model_size: float) -> float:
        """ε in model units."""
        return self.radius * model_size

    def scaled(self, factor: float) -> Brush:
        """This brush with its radius times ``factor`` (at least :data:`MIN_RADIUS`); itself
        at 1 (pen pressure → radius)."""
        if factor == 1.0:
            return self
        return replace(self, radius=max(self.radius * factor, MIN_RADIUS))

    @property
    def auto_influence(self) -> bool:
        """The influence follows the brush's field (``influence == "auto"``)."""
        return self.influence == AUTO_INFLUENCE

    def cutoff(self, model_size: float, reach: float | None = None) -> tuple[float, float] | None:
        """(inner, outer) cutoff radii in model units (None: no cutoff) for an influence of
        ``reach`` ε (None: the brush's own number)."""
        if reach is None:
            if self.auto_influence:
                raise ValueError(
                    "an automatic influence depends on the brush's field: ask the engine "
                    "(Sculptor.influence(brush)) for its radius"
                )
            reach = float(self.influence)
        if math.isinf(reach):
            return None
        outer = reach * self.eps(model_size)
        return CUTOFF_START * outer, outer

    def to_dict(self) -> dict[str, Any]:
        data = asdict(self)
        if not self.auto_influence and math.isinf(float(self.influence)):
            data["influence"] = None
        return data

    @classmethod
    def from_dict(cls, data: object, path: str = "brush") -> Brush:
        """Inverse of :meth:`to_dict`: :class:`ParameterError` naming a bad field."""
        fields = ("kind", "radius", "strength", "substeps", "influence", "symmetry")
        values = dict(check_object(path, data, optional=fields))
        if "influence" in values and values["influence"] is None:
            values["influence"] = math.inf
        with prefixed(path):
            return cls(**values)


def _vector(name: str, value: object, nonzero: bool = False) -> np.ndarray:
    arr = check_finite(name, value, (3,))
    if nonzero and not np.any(arr):
        raise ParameterError(name, f"{name} must be nonzero (got {value!r})")
    return arr


@dataclass(frozen=True)
class BrushEvent:
    """One mouse event of a stroke (model units).

    center : (3,) the cursor on the surface at the start of the event.
    delta : (3,) cursor displacement during the event (grab brushes).
    amount : affine brushes (required): the log strain or angle (radians) at the brush centre
        per event, times the strength. Paint brushes: the pen pressure, negative to erase or
        invert (1.0 when not given).
    axis : (3,) view direction (twist axis, pinch normal), any nonzero length; +z when omitted.
    direction : (3,) stroke direction in the view plane (pinch); any vector ⟂ axis if omitted.
    radius_factor : in (0, 1], scales the brush's radius for this event (pen pressure).
    """

    center: np.ndarray
    delta: np.ndarray = field(default_factory=lambda: np.zeros(3))
    amount: float | None = None
    axis: np.ndarray | None = None
    direction: np.ndarray | None = None
    radius_factor: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "center", _vector("center", self.center))
        object.__setattr__(self, "delta", _vector("delta", self.delta))
        if self.amount is not None:
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

    @property
    def acting_amount(self) -> float:
        """:attr:`amount`, 0 when none was given (:meth:`BrushType.with_amount`)."""
        return 0.0 if self.amount is None else self.amount

    def brush(self, stroke_brush: Brush) -> Brush:
        """``stroke_brush`` with its radius scaled by :attr:`radius_factor`."""
        return stroke_brush.scaled(self.radius_factor)

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {"center": self.center.tolist()}
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
        """Inverse of :meth:`to_dict`: :class:`ParameterError` naming a bad field."""
        fields = ("center", "delta", "amount", "axis", "direction", "radius_factor")
        values = dict(check_object(path, data, required=("center",), optional=fields[1:]))
        values.setdefault("amount", 0.0)  # a file leaves out a zero amount (to_dict)
        with prefixed(path):
            return cls(**values)
