"""Per-brush degree weights ω_l: their check and their defaults, read from the brush table
(here, below the settings, since the brushes' table says which kinds have weights).
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

import numpy as np

from gogreen_core.field.kernel import L_MAX_LIMIT
from gogreen_core.field.limits import MAX_DEGREE_WEIGHT
from gogreen_core.sculpt.brushes.table import brush_type, weighted_kinds
from gogreen_core.validation import ParameterError, check_finite, check_list

__all__ = ["check_brush_weights", "default_weights", "resized_brush_weights"]


def check_brush_weights(
    value: object, l_max: int, path: str = "brush_weights"
) -> Mapping[str, tuple[float, ...]]:
    """Per-brush degree weights: a mapping from a weighted brush kind to l_max + 2 finite numbers
    within ±:data:`MAX_DEGREE_WEIGHT`, as a read-only mapping of tuples (None: {})."""
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


def default_weights(kind: str, l_max: int) -> np.ndarray:
    """The degree weights (l_max + 2,) brush ``kind`` starts with (its table row's)."""
    return brush_type(kind).default_weights(l_max)


def resized_brush_weights(
    weights: Mapping[str, tuple[float, ...]], l_max: int
) -> Mapping[str, tuple[float, ...]]:
    """``weights`` for another ``l_max``: each brush keeps the degrees both have, and new
    degrees get the brush's defaults."""
    out = {}
    for kind, values in weights.items():
        padded = default_weights(kind, l_max)
        keep = min(len(values), l_max + 2)
        padded[:keep] = values[:keep]
        out[kind] = tuple(float(x) for x in padded)
    return MappingProxyType(out)
