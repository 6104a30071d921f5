"""Input validation that names the offending parameter.

Every check raises :class:`ParameterError`, a :class:`ValueError` that carries the parameter's
name in :attr:`ParameterError.parameter`, so callers (the app's panels, the command line, session
and preset readers) can point at the field without parsing the message text.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "ParameterError",
    "check_finite",
    "check_number",
    "check_vector",
]


class ParameterError(ValueError):
    """A bad value for one named parameter.

    Parameters
    ----------
    parameter : str
        The parameter's name as the user sees it (``"radius"``, ``"brush.strength"``,
        ``"operations[3].events[0].delta"``).
    message : str
        The whole message; it should name the parameter and the value received.
    """

    def __init__(self, parameter: str, message: str):
        super().__init__(message)
        self.parameter = parameter


def check_number(
    name: str,
    value: object,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """``value`` as a finite float within the given bounds, else :class:`ParameterError`.

    ``bool`` is refused (``True`` is not a radius). Bounds are closed unless ``low_open`` /
    ``high_open``.
    """
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


def check_vector(name: str, value: object, *, max_norm: float | None = None) -> np.ndarray:
    """``value`` as a finite float64 3-vector, with ``|value| ≤ max_norm`` when given."""
    arr = check_finite(name, value, (3,))
    if max_norm is not None and not np.linalg.norm(arr) <= max_norm:
        raise ParameterError(name, f"{name} is too large (|{name}| must be ≤ {max_norm:g})")
    return arr
