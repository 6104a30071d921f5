"""The types of the compile options modules pass to numba's ``njit`` as ``**options`` (for the
type checker: numba's own annotations then keep each compiled function's signature). Options a
module also passes one by one next to them (``parallel``, ``nogil``) are no keys
here, so that the type checker sees that no keyword is given twice."""

from __future__ import annotations

from typing import Literal, TypedDict


class JitOptions(TypedDict, total=False):
    cache: bool
    boundscheck: bool
    error_model: Literal["python", "numpy"]
    fastmath: bool | set[str]


class NogilJitOptions(JitOptions, total=False):
    nogil: bool
