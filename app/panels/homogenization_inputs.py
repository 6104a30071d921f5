"""The Homogenize panel's inputs as an evented model (no Qt): :class:`HomogenizationInputs`."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gogreen_core import PATTERNS, bimaterial, make_pattern
from gogreen_core.interaction.settings import EventedModel, Field
from gogreen_core.validation import ParameterError

__all__ = ["CELL_SIZE", "HomogenizationInputs"]

#: Voxels per axis of the periodic cell.
CELL_SIZE = 16


def _pattern(_inputs: EventedModel, name: str, value: Any) -> str:
    if value not in PATTERNS:
        raise ParameterError(name, f"unknown pattern {value!r}; choose one of {list(PATTERNS)}")
    return str(value)


def _real(_inputs: EventedModel, name: str, value: Any) -> float:
    number = float(value)
    if not math.isfinite(number):
        raise ParameterError(name, f"{name} must be a finite number (got {value!r})")
    return number


def _angles(_inputs: EventedModel, name: str, value: Any) -> tuple[float, ...]:
    return tuple(_real(_inputs, name, a) for a in value)


def _defaults(pattern: str) -> dict[str, Any]:
    return {p.name: p.default for p in PATTERNS[pattern].parameters}


class HomogenizationInputs(EventedModel):
    """The Homogenize panel's inputs: the ``pattern`` and its ``parameters``, phase a's
    ``young`` and ``poisson``, the stiffness ``contrast`` E_b / E_a, the Euler ``angles`` of
    the result, ``auto`` (recompute after each change) and the ``slice`` shown. Always valid:
    the pattern is made (:func:`gogreen_core.make_pattern`) and the phases
    (:func:`gogreen_core.bimaterial`) built before a change is taken; a new pattern starts
    from its parameters' defaults."""

    pattern = Field(next(iter(PATTERNS)), _pattern)
    parameters = Field(lambda: _defaults(next(iter(PATTERNS))))
    young = Field(1.0, _real)
    poisson = Field(0.3, _real)
    contrast = Field(100.0, _real)
    angles = Field((0.0, 0.0, 0.0), _angles)
    auto = Field(True, lambda _m, _n, value: bool(value))
    slice = Field(CELL_SIZE // 2, lambda _m, _n, value: int(value))

    def _normalize(self, values: dict[str, Any]) -> dict[str, Any]:
        out = super()._normalize(values)
        merged = {**self._values, **out}
        if "pattern" in out and out["pattern"] != self._values["pattern"]:
            out["parameters"] = {**_defaults(out["pattern"]), **values.get("parameters", {})}
            merged["parameters"] = out["parameters"]
        if {"pattern", "parameters"} & set(out):
            unknown = set(merged["parameters"]) - set(_defaults(merged["pattern"]))
            if unknown:
                raise ParameterError(
                    "parameters",
                    f"unknown parameter(s) {sorted(unknown)} for pattern {merged['pattern']!r}",
                )
            try:
                make_pattern(merged["pattern"], CELL_SIZE, **merged["parameters"])
            except ValueError as exc:
                named = [str(p) for p in merged["parameters"] if str(p) in str(exc)]
                parameter = getattr(exc, "parameter", None) or next(iter(named), "parameters")
                raise ParameterError(str(parameter), str(exc)) from None
        if {"young", "poisson", "contrast"} & set(out):
            try:
                bimaterial(merged["young"], merged["poisson"], merged["contrast"])
            except ValueError as exc:
                named = [k for k in ("contrast", "young", "poisson") if k in str(exc)]
                raise ParameterError((named or list(out))[0], str(exc)) from None
        return out

    @property
    def phases(self) -> np.ndarray:
        """The (16, 16, 16) 0/1 cell of the pattern."""
        return make_pattern(self.pattern, CELL_SIZE, **self.parameters)
