"""The engine's settings as one immutable value: material, falloff, l_max, weights, pins' radius.

Its fields, checks, defaults and file form are the rows of
:data:`~gogreen_core.sculpt.setting_table.SETTINGS` (a value that exists is valid). Adding an
engine setting: one row there and its typed line here (checked against the table at import).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import RadialProfile
from gogreen_core.sculpt.brushes.weights import default_weights, resized_brush_weights
from gogreen_core.sculpt.setting_table import SETTINGS, Setting, rows
from gogreen_core.validation import check_object
from gogreen_core.validation import field as field_path

__all__ = [
    "SETTING_GROUPS",
    "EngineSettings",
    "resized_brush_weights",
]

#: Fields that change together, as one undo step and one session record each (the table's
#: groups, in its order): the material; the falloff with l_max and the brushes' weights (which
#: belong to one l_max); the pins' radius; dynamic topology with its detail size.
SETTING_GROUPS: tuple[tuple[str, ...], ...] = tuple(
    tuple(s.name for s in rows("engine") if s.group_name == group)
    for group in dict.fromkeys(s.group_name for s in rows("engine"))
)


_Weights = Mapping[str, tuple[float, ...]]


def _initial(name: str) -> Callable[[], Any]:
    """What makes the default of setting ``name`` (a new value each time)."""
    return next(s for s in SETTINGS if s.name == name).initial


@dataclass(frozen=True, eq=False)  # eq: by content, below (the weights are an array)
class EngineSettings:
    """What the engine computes with besides the mesh and the brush: one field per ``"engine"``
    row of the setting table, in its order. Change one with :meth:`replace` (checked again)."""

    material: Material = field(default_factory=_initial("material"))
    falloff: RadialProfile = field(default_factory=_initial("falloff"))
    l_max: int = field(default_factory=_initial("l_max"))
    constraint_radius: float = field(default_factory=_initial("constraint_radius"))
    brush_weights: _Weights = field(default_factory=_initial("brush_weights"))
    dynamic_topology: bool = field(default_factory=_initial("dynamic_topology"))
    detail_size: float | None = field(default_factory=_initial("detail_size"))
    material_frame: str = field(default_factory=_initial("material_frame"))

    def __post_init__(self) -> None:
        checked: dict[str, Any] = {}
        for s in rows("engine"):
            checked[s.name] = s.check(getattr(self, s.name), s.name, checked)
            object.__setattr__(self, s.name, checked[s.name])

    def replace(self, **changes: Any) -> EngineSettings:
        """This value with some fields changed (checked like a new one)."""
        return replace(self, **changes)

    def weights_for(self, kind: str) -> np.ndarray:
        """The degree weights ω_l (l_max + 2,) of brush ``kind``: its own in
        :attr:`brush_weights`, else its defaults (a new array)."""
        stored = self.brush_weights.get(kind)
        if stored is None:
            return default_weights(kind, self.l_max)
        return np.array(stored)

    def with_brush_weights(self, kind: str, weights: Iterable[float] | None) -> EngineSettings:
        """This value with brush ``kind``'s degree weights ω_l set (l_max + 2 numbers, degrees 0
        … l_max + 1), or back to its defaults for None; e.g.
        ``sculptor.apply_settings(sculptor.settings.with_brush_weights("pinch", w))``."""
        table = dict(self.brush_weights)
        if weights is None:
            table.pop(kind, None)
        else:
            table[kind] = tuple(float(w) for w in weights)
        return self.replace(brush_weights=table)

    def agrees(self, other: EngineSettings, names: Iterable[str]) -> bool:
        """True when the fields ``names`` are equal in both (by content)."""
        return all(getattr(self, name) == getattr(other, name) for name in names)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, EngineSettings):
            return NotImplemented
        return self.agrees(other, (f.name for f in fields(self)))

    __hash__ = None  # type: ignore[assignment]  # equal by content, holds an array

    def to_dict(self, place: str = "session") -> dict[str, Any]:
        """The JSON form of the settings of ``place`` (a session's, a preset's)."""
        return {
            s.name: s.to_json(getattr(self, s.name))
            for s in rows(place)
            if s.written(getattr(self, s.name))
        }

    @classmethod
    def from_dict(
        cls, data: object, path: str = "settings", place: str = "session"
    ) -> EngineSettings:
        """Inverse of :meth:`to_dict` (ParameterError naming the field; rows not given take
        their defaults). With a ``path``, ``data`` must hold nothing else."""
        table = rows(place)
        if path != "":
            required = tuple(s.name for s in table if place in s.required)
            check_object(path, data, required, tuple(s.name for s in table))
        values = dict(data) if isinstance(data, dict) else {}
        checked: dict[str, Any] = {}
        for s in table:
            if s.name in values:
                checked[s.name] = s.from_json(values[s.name], field_path(path, s.name), checked)
        return cls(**checked)


def _check_fields(table: Iterable[Setting]) -> None:
    """Raise at import when :class:`EngineSettings`' fields are not the table's, in order."""
    declared = [s.name for s in table if "engine" in s.places]
    present = [f.name for f in fields(EngineSettings)]
    if declared != present:
        raise TypeError(
            f"EngineSettings declares {present}, the setting table {declared}: add the "
            "missing typed line to EngineSettings (in the table's order)"
        )


_check_fields(SETTINGS)
