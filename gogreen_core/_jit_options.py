"""The type of the compile options modules pass to numba's ``njit`` as ``**options`` (for the
type checker: numba's own annotations then keep each compiled function's signature). Options
also passed one by one next to them (``parallel``) are no keys here: no keyword given twice."""

from __future__ import annotations

from typing import Literal, TypedDict


class NogilJitOptions(TypedDict, total=False):
    cache: bool
    boundscheck: bool
    error_model: Literal["python", "numpy"]
    fastmath: bool | set[str]
    nogil: bool
