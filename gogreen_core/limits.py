"""The bounds of every value the engine accepts, and the checks that apply them.

One set of range checks and messages (README, "Sculpting without the GUI"): the engine's
settings value (:class:`gogreen_core.engine_settings.EngineSettings`), the evented settings
model, brushes, presets and session files all call these. Each check takes the parameter's name
(or field path) and raises :class:`~gogreen_core.validation.ParameterError` naming it.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

import numpy as np

from gogreen_core.kernel import L_MAX_LIMIT
from gogreen_core.material import Material
from gogreen_core.radial import MultiscaleRadial, RadialProfile, SplineRadial
from gogreen_core.validation import (
    ParameterError,
    check_finite,
    check_integer,
    check_list,
    check_number,
)

__all__ = [
    "L_MAX_LIMIT",
    "MAX_AMOUNT",
    "MAX_DEGREE_WEIGHT",
    "MAX_RADIUS",
    "MAX_REACH",
    "MAX_STIFFNESS",
    "MAX_STRENGTH",
    "MAX_SUBSTEPS",
    "MIN_RADIUS",
    "MIN_STIFFNESS",
    "check_brush_weights",
    "check_constraint_radius",
    "check_falloff",
    "check_l_max",
    "check_material",
]

#: A brush radius or the pins' radius, as a fraction of the model size: beyond these the
#: numbers overflow or mean nothing.
MIN_RADIUS, MAX_RADIUS = 1e-6, 100.0
MAX_STRENGTH = 1e3
MAX_SUBSTEPS = 1000
#: Largest |amount| (and |strength · amount|) of an affine brush event: a strain or an angle
#: in radians per event at the brush centre.
MAX_AMOUNT = 100.0
#: Farthest a brush centre, a grab displacement (times the strength), a pin or a pin drag may
#: reach, in model sizes from the model's centre: beyond it nothing is left to sculpt, and the
#: arithmetic stays far from overflow whatever the model's scale.
MAX_REACH = 1e3
#: Bounds of the largest stiffness coefficient |C_ab| (units are free: brushes are normalized by
#: the material's own response, so only the ratios matter; beyond these the kernel over- or
#: underflows).
MIN_STIFFNESS, MAX_STIFFNESS = 1e-100, 1e100
#: Largest |weight| of a degree.
MAX_DEGREE_WEIGHT = 1e6


def check_material(material: object, path: str = "material") -> Material:
    """``material`` if it is a :class:`Material` whose largest stiffness coefficient is within
    [MIN_STIFFNESS, MAX_STIFFNESS]."""
    if not isinstance(material, Material):
        raise ParameterError(path, f"{path} must be a Material (got {type(material).__name__})")
    scale = float(np.abs(material.voigt).max())
    if not MIN_STIFFNESS <= scale <= MAX_STIFFNESS:
        raise ParameterError(
            path,
            f"{path}: the largest stiffness coefficient must be within [{MIN_STIFFNESS:g}, "
            f"{MAX_STIFFNESS:g}] (got {scale:.3g}); only ratios matter, rescale it",
        )
    return material


def check_falloff(falloff: object, path: str = "falloff") -> RadialProfile:
    """The falloff shape ``falloff`` as an immutable value at ε = 1
    (:meth:`RadialProfile.as_value`): a single profile (Gaussian, Kelvinlet, spline; multi-scale
    ones are made by brushes) that is not zero everywhere."""
    if not isinstance(falloff, RadialProfile) or isinstance(falloff, MultiscaleRadial):
        raise ParameterError(
            path,
            f"{path} must be a single RadialProfile (Gaussian, Kelvinlet, spline), "
            f"got {type(falloff).__name__}",
        )
    if isinstance(falloff, SplineRadial) and not any(
        np.any(falloff.curve(kind, l)[1]) for kind, l in falloff.curve_keys()
    ):
        raise ParameterError(
            path,
            f"the {path} is zero everywhere (every curve's control values are 0): "
            "no brush would move anything",
        )
    return falloff.as_value()


def check_l_max(value: object, path: str = "l_max") -> int:
    """Truncation degree: an integer in [0, :data:`L_MAX_LIMIT`]."""
    return check_integer(path, value, low=0, high=L_MAX_LIMIT)


def check_constraint_radius(value: object, path: str = "constraint_radius") -> float:
    """ε of the pins as a fraction of the model size, in [MIN_RADIUS, MAX_RADIUS]."""
    return check_number(path, value, low=MIN_RADIUS, high=MAX_RADIUS)


def check_brush_weights(
    value: object, l_max: int, path: str = "brush_weights"
) -> Mapping[str, tuple[float, ...]]:
    """Per-brush degree weights ω_l: a mapping from a Green's-function brush kind to l_max + 2
    finite numbers within ±:data:`MAX_DEGREE_WEIGHT` (ω_0 … ω_{l_max+1}: vector brushes read
    the even degrees of G, affine brushes the odd degrees of ∇G), as a read-only mapping of
    tuples; None or {} leaves every brush at its defaults."""
    from gogreen_core.brushes.table import weighted_kinds  # the table imports this module

    if value is None:
        return MappingProxyType({})
    if not isinstance(value, Mapping):
        raise ParameterError(
            path, f"{path} must map brush kinds to weights (got {type(value).__name__})"
        )
    kinds = weighted_kinds()
    out: dict[str, tuple[float, ...]] = {}
    for kind in sorted(value):
        at = f"{path}.{kind}"
        if kind not in kinds:
            raise ParameterError(
                at, f"{at}: no brush {kind!r} with degree weights (expected {', '.join(kinds)})"
            )
        weights = value[kind]
        if isinstance(weights, (list, tuple)):
            weights = check_list(at, weights, max_length=L_MAX_LIMIT + 2)
        array = np.asarray(check_finite(at, weights), dtype=np.float64)
        if array.shape != (l_max + 2,):
            raise ParameterError(
                at,
                f"{at} must hold l_max + 2 = {l_max + 2} numbers, one per degree 0 … "
                f"{l_max + 1} (got shape {array.shape})",
            )
        if not np.abs(array).max() <= MAX_DEGREE_WEIGHT:
            raise ParameterError(at, f"{at} must be within ±{MAX_DEGREE_WEIGHT:g}")
        out[kind] = tuple(float(x) for x in array)
    return MappingProxyType(out)
