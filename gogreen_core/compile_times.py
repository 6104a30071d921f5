"""How long each compile unit takes: the start-up status's "about 25 s left".

Each unit's expected time is what it took when last compiled on this machine (a JSON file beside
numba's disk cache), else its built-in weight times :data:`SECONDS_PER_WEIGHT`; the pace of the
units compiled so far (measured over expected seconds: a busy machine is slower) scales the rest.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Mapping, Sequence

from gogreen_core._compile_lock import cache_folder

__all__ = [
    "SECONDS_PER_WEIGHT",
    "record",
    "recorded",
    "seconds_left",
    "unit_name",
    "weight",
]

#: The named units: relative compile time, the drivers 1 (measured one unit at a time on an
#: empty cache on the project's 2-core machine, under load), and what the status bar calls it.
_UNITS = {
    "drivers": (1.0, "field drivers"),
    "geometry": (0.22, "surface index"),
    "mesh_io": (0.10, "mesh readers"),
    "brushes": (0.04, "paint brushes"),
}
#: An angular kernel (l_first, l_last): this weight per degree up to l_last.
ANGULAR_WEIGHT_PER_DEGREE = 0.0115
#: Seconds of weight 1 when nothing was measured: a first start on a quiet machine took 40 s
#: at l_max 8 (issue 32), of total weight 1.57.
SECONDS_PER_WEIGHT = 25.0
#: The file of measured seconds per unit, beside numba's disk cache (``cache_folder``).
FILE_NAME = "gogreen-compile-times.json"


def _key(unit: str | tuple[int, ...]) -> str:
    return unit if isinstance(unit, str) else "angular " + "-".join(str(v) for v in unit)


def unit_name(unit: str | tuple[int, ...]) -> str:
    """What ``unit`` is, for the status bar: "field drivers", "angular kernel, degrees 0–8"."""
    if isinstance(unit, str):
        return _UNITS[unit][1] if unit in _UNITS else unit.replace("_", " ")
    return f"angular kernel, degrees {unit[0]}–{unit[-1]}"


def weight(unit: str | tuple[int, ...]) -> float | None:
    """The built-in relative compile time of ``unit`` (None for a unit it does not know)."""
    if isinstance(unit, str):
        return _UNITS[unit][0] if unit in _UNITS else None
    return ANGULAR_WEIGHT_PER_DEGREE * (unit[-1] + 1)


def recorded() -> dict[str, float]:
    """Seconds each unit took when last compiled here ({} if none or unreadable)."""
    try:
        data = json.loads((cache_folder() / FILE_NAME).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    if not isinstance(data, dict):
        return {}
    return {
        str(k): float(v)
        for k, v in data.items()
        if isinstance(v, (int, float)) and 0 < v < float("inf")
    }


def record(seconds: Mapping[str | tuple[int, ...], float]) -> None:
    """Add the measured ``seconds`` per unit to the file (written whole, then renamed); nothing
    when its folder cannot be written."""
    path = cache_folder() / FILE_NAME
    data = recorded()
    known = {unit: s for unit, s in seconds.items() if weight(unit) is not None and s > 0}
    if not known:  # only the units of this table (not a test's, a plug-in's)
        return
    data.update({_key(unit): round(float(s), 3) for unit, s in known.items()})
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(
            "w", dir=path.parent, suffix=".tmp", delete=False, encoding="utf-8"
        ) as out:
            json.dump(data, out, indent=1, sort_keys=True)
        os.replace(out.name, path)
    except OSError:
        return


def seconds_left(
    done: Mapping[str | tuple[int, ...], float],
    left: Sequence[str | tuple[int, ...]],
    known: Mapping[str, float],
) -> float | None:
    """About how long the units ``left`` take, at the pace of the units ``done`` (unit →
    measured seconds) against their expected times (``known``: :func:`recorded`, else the
    built-in weights); None for a unit without one."""

    def expected(unit: str | tuple[int, ...]) -> float | None:
        if _key(unit) in known:
            return known[_key(unit)]
        w = weight(unit)
        return None if w is None else w * SECONDS_PER_WEIGHT

    rest = [expected(u) for u in left]
    if any(e is None for e in rest):
        return None
    before = [expected(u) for u in done]
    pace = 1.0
    if done and all(e is not None for e in before):
        planned = sum(e for e in before if e is not None)
        pace = sum(done.values()) / planned if planned > 0 else 1.0
    return float(sum(pace * (e or 0.0) for e in rest))
