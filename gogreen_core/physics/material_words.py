"""What a material does, in an artist's words: stiff along, soft across, how the sides move.

:func:`describe_material` reads the directional Young's modulus E(d) over the sphere and the
Poisson ratios of its stiffest direction, and says in two short sentences what a brush will
show for the kind it finds: isotropic, fibres (one stiff axis), layers (one soft axis) or
general. Directions are named by the nearest model axis within 10°, else by the axis pair
they lie between ("tilted 45° from +Z toward −Y").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from gogreen_core.physics.material import VOIGT_INDEX, Material, uniaxial_stress
from gogreen_core.physics.quadrature import lebedev_points

__all__ = [
    "MaterialTraits",
    "describe_material",
    "direction_words",
    "material_name",
    "material_traits",
    "young_extremes",
]

#: E_max / E_min below this: isotropic to the eye.
_ISOTROPIC_RATIO = 1.05
#: How much closer two principal moments of E(d) must be than the third to call the material
#: fibrous (one stiff axis) or layered (one soft axis).
_PAIRED = 0.25
_AXES = np.eye(3)
_AXIS_NAMES = ("X", "Y", "Z")


@dataclass(frozen=True)
class MaterialTraits:
    """What :func:`describe_material` puts in words: ``kind`` ("isotropic", "fibres",
    "layers", "general"), unit directions (3,) ``stiff`` and ``soft`` of the largest and smallest
    E(d), their ``ratio``, ``poisson_stiff`` (2,) of a stretch along ``stiff`` on the two
    directions across it (the softest first), and ``axis`` (fibre axis, layers' normal, else
    ``stiff``)."""

    kind: str
    stiff: np.ndarray
    soft: np.ndarray
    ratio: float
    poisson_stiff: np.ndarray
    axis: np.ndarray


def _poisson(material: Material, along: np.ndarray, across: np.ndarray) -> float:
    """ν = −ε_across / ε_along under a uniaxial stress along ``along`` (unit vectors)."""
    e = material.compliance @ uniaxial_stress(along)  # engineering shear: halved off the diagonal
    strain = e[VOIGT_INDEX] * np.where(np.eye(3) > 0, 1.0, 0.5)
    return float(-(across @ strain @ across) / (along @ strain @ along))


def _unit(angles: np.ndarray) -> np.ndarray:
    theta, phi = angles
    return np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])


def young_extremes(material: Material) -> tuple[float, float, np.ndarray, np.ndarray]:
    """(E_min, E_max, softest, stiffest): the extremes of the directional Young's modulus and
    their unit directions (3,), the anisotropy E_max / E_min the glyph's legend and the words
    share: 4,000 directions, each extreme refined by a local search."""
    k = np.arange(4000) + 0.5  # a Fibonacci sphere of near-uniform directions
    z = 1.0 - 2.0 * k / 4000
    phi = np.pi * (1.0 + np.sqrt(5.0)) * k
    r = np.sqrt(1.0 - z * z)
    directions = np.column_stack([r * np.cos(phi), r * np.sin(phi), z])
    young = material.directional_young(directions)
    found = []
    for sign, index in ((1.0, int(np.argmin(young))), (-1.0, int(np.argmax(young)))):
        d = directions[index]
        start = np.array([np.arccos(np.clip(d[2], -1.0, 1.0)), np.arctan2(d[1], d[0])])
        result = minimize(
            lambda a, s=sign: s * float(material.directional_young(_unit(a)[None])[0]),
            start,
            method="Nelder-Mead",
            options={"xatol": 1e-7, "fatol": 1e-12 * float(young.max())},
        )
        best = _unit(result.x) if result.fun < sign * young[index] else d
        found.append((float(material.directional_young(best[None])[0]), best))
    (e_min, soft), (e_max, stiff) = found
    return e_min, e_max, soft, stiff


def material_traits(material: Material) -> MaterialTraits:
    """Measure the traits of ``material`` (see :class:`MaterialTraits`)."""
    directions, weights = lebedev_points()
    young = material.directional_young(directions)
    e_min, e_max, soft, stiff = young_extremes(material)
    ratio = e_max / e_min
    # principal moments of E(d) d dᵀ: a pair of near-equal large ones and a small one is a
    # plane of stiff directions (layers); one large and a near-equal small pair, a stiff axis
    moment = np.einsum("q,q,qi,qj->ij", weights, young, directions, directions)
    values, vectors = np.linalg.eigh(moment)  # ascending
    spread = values[2] - values[0]
    kind, axis = "general", stiff
    if ratio < _ISOTROPIC_RATIO:
        kind = "isotropic"
    elif spread > 0 and values[2] - values[1] < _PAIRED * spread:
        kind, axis = "layers", vectors[:, 0]
    elif spread > 0 and values[1] - values[0] < _PAIRED * spread:
        kind, axis = "fibres", vectors[:, 2]
    across = soft - (soft @ stiff) * stiff
    if not np.linalg.norm(across) > 1e-9:  # soft along stiff: any direction across it
        across = np.cross(stiff, _AXES[np.argmin(np.abs(stiff))])
    across = across / np.linalg.norm(across)
    third = np.cross(stiff, across)
    poisson = np.array([_poisson(material, stiff, across), _poisson(material, stiff, third)])
    return MaterialTraits(kind, stiff, soft, ratio, poisson, axis)


def direction_words(direction: np.ndarray) -> str:
    """An axis (not an arrow) in words: "Z" (within 10° of an axis), else "Z tilted 45° toward
    −Y" (the nearest axis and the one or two it leans to)."""
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    if d[np.argmax(np.abs(d))] < 0:
        d = -d  # name the axis's positive end
    first, second, third = np.argsort(-np.abs(d))

    def name(i: int) -> str:
        return ("−" if d[i] < 0 else "") + _AXIS_NAMES[i]

    angle = float(np.degrees(np.arccos(min(1.0, abs(d[first])))))
    if angle <= 10.0:
        return name(first)
    toward = name(second)
    if abs(d[third]) > 0.9 * abs(d[second]):
        toward += f" and {name(third)}"
    return f"{name(first)} tilted {angle:.0f}° toward {toward}"


def _most_auxetic(material: Material, traits: MaterialTraits) -> tuple[float, str, str]:
    """(ν, along, across) of the most negative Poisson ratio among the axes, stiff and soft."""
    candidates = [*_AXES, traits.stiff, traits.soft]
    best = (np.inf, "", "")
    for i, along in enumerate(candidates):
        for across in candidates[i + 1 :] + candidates[:i]:
            across = across - (across @ along) * along
            if np.linalg.norm(across) < 0.5:
                continue
            across = across / np.linalg.norm(across)
            nu = _poisson(material, along, across)
            if nu < best[0]:
                best = (nu, direction_words(along), direction_words(across))
    return best


def material_name(material: Material) -> str:
    """A short name of ``material`` for the screen ("isotropic, E 1, ν 0.30", "fibres along
    +Z, 20.7× stiffer"): the kind and the one anisotropy figure of :func:`young_extremes`."""
    traits = material_traits(material)
    if traits.kind == "isotropic":
        e_min, e_max, _, _ = young_extremes(material)
        nu = float(np.mean(traits.poisson_stiff))
        return f"isotropic, E {0.5 * (e_min + e_max):.3g}, ν {nu:.2f}"
    if traits.kind == "fibres":
        return f"fibres along {direction_words(traits.axis)}, {traits.ratio:.3g}× stiffer"
    if traits.kind == "layers":
        return f"layers across {direction_words(traits.axis)}, {traits.ratio:.3g}× softer"
    return f"anisotropic, stiffest along {direction_words(traits.stiff)}, {traits.ratio:.3g}×"


def describe_material(material: Material) -> str:
    """Two short sentences on what ``material`` does under a brush (see the module docstring)."""
    traits = material_traits(material)
    ratio, (nu_soft, nu_third) = traits.ratio, traits.poisson_stiff
    if traits.kind == "isotropic":
        nu = (nu_soft + nu_third) / 2
        if nu < -0.05:
            sides = f"a pull widens the sides (ν = {nu:.2f}, auxetic)"
        elif nu > 0.45:
            sides = f"a pull thins the sides and keeps the volume (ν = {nu:.2f})"
        else:
            sides = f"a pull thins the sides a little (ν = {nu:.2f})"
        return f"The same in every direction: {sides}."
    if traits.kind == "fibres":
        text = (
            f"Fibres along {direction_words(traits.axis)}, {ratio:.3g}× stiffer along them than "
            "across. Grabs slide across the fibres; pinch and twist crease along them."
        )
    elif traits.kind == "layers":
        text = (
            f"Layers stacked along {direction_words(traits.axis)}, {ratio:.3g}× softer across the "
            "layers than within them. Strokes ripple along the layers (try the wrinkle brush)."
        )
    else:
        text = (
            f"Stiffest along {direction_words(traits.stiff)}, softest along "
            f"{direction_words(traits.soft)} ({ratio:.3g}× softer)."
        )
    nu, along, across = _most_auxetic(material, traits)
    if nu < -0.05:
        text += f" A stretch along {along} widens it along {across} (ν = {nu:.2f})."
    return text
