"""The typed schema of the JSON the program reads (materials, falloffs, files).

Each ``parse_*`` function takes the decoded JSON value and the path of the field it sits at and
returns the engine object, or raises a ParameterError naming the field
(``falloff.eps must be a number (got '1')``); brushes, settings, sessions and operations have
theirs in their own ``from_dict``. Written by hand rather than with a schema library: the
checks that matter are numeric and done by the engine's own constructors, whose messages we keep.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, TypeVar, cast

from gogreen_core.field.kernel import L_MAX_LIMIT
from gogreen_core.field.limits import check_material
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import (
    INTERPOLATIONS,
    KINDS,
    GaussianRadial,
    KelvinletRadial,
    RadialProfile,
    SplineRadial,
)
from gogreen_core.validation import (
    ParameterError,
    check_choice,
    check_finite,
    check_integer,
    check_list,
    check_number,
    check_object,
    field,
    prefixed,
)

if TYPE_CHECKING:
    import numpy as np

__all__ = [
    "FALLOFF_TYPES",
    "MAX_CONTROL_POINTS",
    "parse_falloff",
    "parse_file",
    "parse_material",
    "read_json",
]

T = TypeVar("T")

#: Falloff shapes a sculptor, a preset or a session can use (multi-scale ones are made by the
#: grab_biscale / grab_triscale brushes, never stored).
FALLOFF_TYPES = ("gaussian", "kelvinlet", "spline")
#: Control points of one spline curve, and curves of one spline falloff, at most.
MAX_CONTROL_POINTS = 1000
MAX_CURVES = 2 * (L_MAX_LIMIT + 2)


def parse_material(data: object, path: str = "material") -> Material:
    """``{"voigt": 6×6 numbers}`` → :class:`Material` (symmetric positive definite)."""
    data = check_object(path, data, required=("voigt",))
    name = field(path, "voigt")
    voigt = check_finite(name, data["voigt"])
    if voigt.shape != (6, 6):
        raise ParameterError(name, f"{name} must be a 6×6 matrix (got shape {voigt.shape})")
    with prefixed(name):
        return check_material(Material(voigt), name)


def parse_falloff(data: object, path: str = "falloff") -> RadialProfile:
    """A falloff's ``to_dict`` → Gaussian, Kelvinlet or spline profile."""
    kind = check_choice(field(path, "type"), member(data, path, "type"), FALLOFF_TYPES)
    if kind == "spline":
        data = check_object(
            path, data, required=("type", "eps", "curves"), optional=("interpolation",)
        )
    else:
        data = check_object(path, data, required=("type", "eps"))
    eps = check_number(field(path, "eps"), data["eps"], low=0.0, low_open=True)
    if kind == "gaussian":
        return GaussianRadial(eps)
    if kind == "kelvinlet":
        return KelvinletRadial(eps)
    name = field(path, "curves")
    curves: dict[tuple[str, int], tuple[np.ndarray, np.ndarray]] = {}
    for i, curve in enumerate(check_list(name, data["curves"], max_length=MAX_CURVES)):
        at = field(name, i)
        curve = check_object(at, curve, required=("kind", "degree", "rho", "value"))
        kind_l = check_choice(field(at, "kind"), curve["kind"], KINDS)
        degree = check_integer(field(at, "degree"), curve["degree"], low=0, high=L_MAX_LIMIT + 1)
        points = []
        for key in ("rho", "value"):
            values = check_list(field(at, key), curve[key], max_length=MAX_CONTROL_POINTS)
            points.append(check_finite(field(at, key), values))
        if (kind_l, degree) in curves:
            raise ParameterError(at, f"{at}: a second curve {kind_l}{degree}")
        curves[(kind_l, degree)] = cast("tuple[np.ndarray, np.ndarray]", tuple(points))
    if not curves:
        raise ParameterError(name, f"{name} must hold at least one curve")
    # absent: the interpolating cubic that files written before PCHIP used (bit for bit)
    interpolation = check_choice(
        field(path, "interpolation"), data.get("interpolation", "cubic"), INTERPOLATIONS
    )
    with prefixed(name):
        return SplineRadial(eps, curves, interpolation)


def member(data: object, path: str, key: str) -> object:
    """``data[key]`` of the JSON object ``data`` at ``path``; ParameterError naming the
    missing field or the non-object."""
    if not isinstance(data, dict):
        data = check_object(path, data)  # raises, naming the path
    if key not in data:
        name = field(path, key)
        raise ParameterError(name, f"{name} is missing")
    return data[key]


def read_json(path: str | os.PathLike[str], kind: str = "JSON file") -> object:
    """The JSON value in file ``path``; ``ValueError`` starting with the file's name when it
    cannot be read, is not UTF-8 text (``kind`` says what was expected) or is not JSON."""
    p = Path(path)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise ValueError(f"{p.name}: cannot read ({exc.strerror or exc})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(
            f"{p.name}: not a {kind} (not UTF-8 text: byte {exc.start} is 0x{raw[exc.start]:02x})"
        ) from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{p.name}: not valid JSON ({exc.msg}, line {exc.lineno})") from None
    except RecursionError:
        raise ValueError(f"{p.name}: not valid JSON (nested too deeply)") from None


def parse_file(path: str | os.PathLike[str], parse: Callable[[object], T], kind: str) -> T:
    """``parse`` of the JSON in ``path`` (see :func:`read_json`); a :class:`ParameterError`
    keeps its field and gets the file's name in front of its message."""
    data = read_json(path, kind)
    try:
        return parse(data)
    except ParameterError as exc:
        raise ParameterError(exc.parameter, f"{Path(path).name}: {exc}") from None
