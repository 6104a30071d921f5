"""Input validation that names the offending parameter: every check raises
:class:`ParameterError`, a :class:`ValueError` carrying the parameter's name.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, TypeVar

import numpy as np

__all__ = [
    "ParameterError",
    "check_bool",
    "check_choice",
    "check_finite",
    "check_integer",
    "check_list",
    "check_number",
    "check_object",
    "check_string",
    "check_type",
    "check_vector",
    "field",
    "prefixed",
    "vector_norm",
]


class ParameterError(ValueError):
    """A bad value for one named ``parameter`` as the user sees it (``"radius"``,
    ``"operations[3].events[0].delta"``); ``message`` names it and the value received."""

    def __init__(self, parameter: str, message: str):
        super().__init__(message)
        self.parameter = parameter


def field(path: str, name: str | int) -> str:
    """The path of a member of ``path``: ``field("brush", "radius")`` → ``"brush.radius"``,
    ``field("events", 0)`` → ``"events[0]"``."""
    if isinstance(name, int):
        return f"{path}[{name}]"
    return f"{path}.{name}" if path else name


@contextmanager
def prefixed(prefix: str) -> Iterator[None]:
    """Re-raise any :class:`ParameterError` as seen from ``prefix`` (``delta`` within
    ``"operations[3]"`` is ``operations[3].delta``), and any other ``ValueError`` as a
    :class:`ParameterError` of ``prefix`` itself."""
    try:
        yield
    except ValueError as exc:
        if not prefix:
            raise
        name = exc.parameter if isinstance(exc, ParameterError) else ""
        path = field(prefix, name) if name else prefix
        message = str(exc)
        if name and message.startswith(name):
            message = path + message[len(name) :]
        elif not (isinstance(exc, ParameterError) and message.startswith(path)):
            message = f"{path}: {message}"
        raise ParameterError(path, message) from None


def check_number(
    name: str,
    value: object,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """``value`` as a finite float within the bounds (closed unless ``low_open`` /
    ``high_open``); ``bool`` is refused (``True`` is not a radius)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ParameterError(name, f"{name} must be a number (got {value!r})")
    try:
        v = float(value)
    except OverflowError:  # an int too large for a float
        raise ParameterError(name, f"{name} is too large (got {value!r})") from None
    if not math.isfinite(v):
        raise ParameterError(name, f"{name} must be finite (got {value!r})")
    if low is not None and (v < low or (low_open and v == low)):
        sign = ">" if low_open else "≥"
        raise ParameterError(name, f"{name} must be {sign} {low:g} (got {value!r})")
    if high is not None and (v > high or (high_open and v == high)):
        sign = "<" if high_open else "≤"
        raise ParameterError(name, f"{name} must be {sign} {high:g} (got {value!r})")
    return v


def check_finite(name: str, value: object, shape: tuple[int, ...] | None = None) -> np.ndarray:
    """``value`` as a float64 array of finite numbers (and of ``shape`` when given)."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(name, f"{name} must be an array of numbers (got {value!r})") from None
    if shape is not None and arr.shape != shape:
        raise ParameterError(name, f"{name} must have shape {shape} (got {arr.shape})")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(name, f"{name} must be finite (got NaN or infinite values)")
    return arr


def vector_norm(vector: np.ndarray) -> float:
    """Euclidean length without overflow of the squares (``norm([0, 1e200, 0])`` is inf)."""
    v = np.asarray(vector, dtype=np.float64)
    peak = float(np.abs(v).max()) if v.size else 0.0
    if peak == 0.0 or not math.isfinite(peak):
        return peak
    return peak * float(np.linalg.norm(v / peak))


def check_vector(name: str, value: object, *, max_norm: float | None = None) -> np.ndarray:
    """``value`` as a finite float64 3-vector, with ``|value| ≤ max_norm`` when given."""
    arr = check_finite(name, value, (3,))
    if max_norm is not None:
        norm = vector_norm(arr)
        if not norm <= max_norm:
            raise ParameterError(
                name, f"{name} is too large (|{name}| = {norm:.4g} must be ≤ {max_norm:.4g})"
            )
    return arr


def check_integer(
    name: str, value: object, *, low: int | None = None, high: int | None = None
) -> int:
    """``value`` as an int within [low, high]. An integral float (``4.0``, as JSON may write
    it) is accepted; ``bool``, ``0.5`` and ``1e300`` beyond ``high`` are refused."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ParameterError(name, f"{name} must be an integer (got {value!r})")
    if isinstance(value, (float, np.floating)) and not (
        math.isfinite(value) and float(value).is_integer()
    ):
        raise ParameterError(name, f"{name} must be an integer (got {value!r})")
    v = int(value)
    if low is not None and v < low:
        raise ParameterError(name, f"{name} must be ≥ {low} (got {value!r})")
    if high is not None and v > high:
        raise ParameterError(name, f"{name} must be ≤ {high} (got {value!r})")
    return v


def check_bool(name: str, value: object) -> bool:
    """``value`` if it is ``True`` or ``False`` (not 1, not "yes")."""
    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(name, f"{name} must be true or false (got {value!r})")
    return bool(value)


def check_string(name: str, value: object, *, max_length: int = 10_000) -> str:
    """``value`` if it is a string of at most ``max_length`` characters."""
    if not isinstance(value, str):
        raise ParameterError(name, f"{name} must be a string (got {type(value).__name__})")
    if len(value) > max_length:
        raise ParameterError(name, f"{name} is too long ({len(value)} > {max_length} characters)")
    return value


T = TypeVar("T")


def check_type(name: str, value: object, kind: type[T]) -> T:
    """``value`` if it is an instance of ``kind`` (a Brush, EngineSettings...)."""
    if not isinstance(value, kind):
        what = kind.__name__
        raise ParameterError(name, f"{name} must be {what} (got {type(value).__name__})")
    return value


def check_choice(name: str, value: object, choices: tuple[str, ...]) -> str:
    """``value`` if it is one of the strings ``choices``."""
    if not isinstance(value, str) or value not in choices:
        raise ParameterError(name, f"{name} must be one of {', '.join(choices)} (got {value!r})")
    return value


def check_list(name: str, value: object, *, max_length: int | None = None) -> list[Any]:
    """``value`` if it is a list (a JSON array), of at most ``max_length`` items."""
    if not isinstance(value, (list, tuple)):
        raise ParameterError(name, f"{name} must be a list (got {type(value).__name__})")
    if max_length is not None and len(value) > max_length:
        raise ParameterError(name, f"{name} has too many items ({len(value)} > {max_length})")
    return list(value)


def check_object(
    name: str,
    value: object,
    required: tuple[str, ...] = (),
    optional: tuple[str, ...] | None = None,
) -> dict[str, Any]:
    """``value`` if it is a dict (a JSON object) with every ``required`` key and, when either
    is given, no key outside ``required + optional``."""
    if not isinstance(value, dict):
        what = "null" if value is None else type(value).__name__
        raise ParameterError(name, f"{name or 'the file'} must be an object (got {what})")
    for key in required:
        if key not in value:
            path = field(name, key)
            raise ParameterError(path, f"{path} is missing")
    if not required and optional is None:
        return value
    allowed = set(required) | set(optional or ())
    for key in value:
        if key not in allowed:
            path = field(name, str(key))
            raise ParameterError(
                path, f"{path} is not a known field (expected {', '.join(sorted(allowed))})"
            )
    return value
