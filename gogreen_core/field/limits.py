"""The bounds of every value the engine accepts, and the checks that apply them: one set of
range checks for the engine's settings, the settings model, brushes, presets and session files,
each raising :class:`~gogreen_core.validation.ParameterError` naming the parameter.
"""

from __future__ import annotations

import numpy as np

from gogreen_core.field.kernel import L_MAX_LIMIT
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import MultiscaleRadial, RadialProfile, SplineRadial
from gogreen_core.validation import ParameterError, check_integer, check_number

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
    "check_constraint_radius",
    "check_detail_size",
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
#: Farthest a brush centre, a grab (times the strength), a pin or a pin drag may reach, in model
#: sizes from the model's centre: nothing is left to sculpt beyond, and no overflow.
MAX_REACH = 1e3
#: Bounds of the largest stiffness coefficient |C_ab| (only ratios matter: brushes are
#: normalized by the material's response; beyond these the kernel over- or underflows).
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


#: Dynamic topology's detail size (target edge length) as a fraction of the model size.
MIN_DETAIL_SIZE, MAX_DETAIL_SIZE = 1e-4, 0.25


def check_detail_size(value: object, path: str = "detail_size") -> float | None:
    """Dynamic topology's target edge length as a fraction of the model size, in
    [MIN_DETAIL_SIZE, MAX_DETAIL_SIZE], or None (the edge length the surface had)."""
    if value is None:
        return None
    return check_number(path, value, low=MIN_DETAIL_SIZE, high=MAX_DETAIL_SIZE)
