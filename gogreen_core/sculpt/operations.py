"""Typed records of what a sculptor did: one immutable class per operation, whose ``to_dict``
(``{"op": name, ...}``) a session's ``operations`` list holds; :func:`operation_from_dict` reads
one back (ParameterError naming the field). ``continued`` (settings and pin drags) joins the
previous change of its kind, so a whole drag is one undo step.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields
from types import MappingProxyType
from typing import Any, ClassVar, cast

import numpy as np

from gogreen_core.field.limits import check_detail_size
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.engine_settings import SETTING_GROUPS, EngineSettings
from gogreen_core.sculpt.schema import member
from gogreen_core.sculpt.setting_table import Setting, rows
from gogreen_core.validation import (
    check_bool,
    check_choice,
    check_finite,
    check_integer,
    check_list,
    check_object,
    prefixed,
)
from gogreen_core.validation import field as field_path

__all__ = [
    "OPERATIONS",
    "SETTINGS_CHANGES",
    "ConstraintAdd",
    "ConstraintDrag",
    "ConstraintRemove",
    "ConstraintsClear",
    "MaskClear",
    "MaskInvert",
    "Operation",
    "Redo",
    "Remesh",
    "SettingsChange",
    "Stroke",
    "Subdivide",
    "Undo",
    "operation_from_dict",
    "settings_record",
]

#: Largest constraint index a file may name (far beyond any pin count an artist places).
MAX_INDEX = 1_000_000
#: Most events in one stroke record.
MAX_EVENTS = 10_000_000
#: Rounds of split, collapse, flip and relaxation of Mesh → Remesh, and the most a file may ask.
REMESH_ITERATIONS = 6
MAX_REMESH_ITERATIONS = 100


class Operation:
    """Base of the operation records (immutable dataclasses): a field is written to the file
    when it is required or not at its default; a record checks its fields when made."""

    #: The ``"op"`` value in a session file.
    name: ClassVar[str]
    #: Fields besides ``op`` that a file may (``optional``) or must (``required``) give.
    required: ClassVar[tuple[str, ...]] = ()
    optional: ClassVar[tuple[str, ...]] = ()

    @property
    def steps(self) -> int:
        """Units of progress this operation reports (mouse events of a stroke, else 1)."""
        return 1

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready ``{"op": name, ...}``."""
        data: dict[str, Any] = {"op": self.name}
        for f in fields(cast(Any, self)):
            value = getattr(self, f.name)
            if f.name in self.required or value != f.default:
                data[f.name] = value.tolist() if isinstance(value, np.ndarray) else value
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> Operation:
        """Read the fields of a checked ``data`` (``op`` and keys already checked)."""
        given = {k: data[k] for k in (*cls.required, *cls.optional) if k in data}
        with prefixed(path):
            return cast("Callable[..., Operation]", cls)(**given)


def _set(record: Operation, name: str, value: object) -> None:
    object.__setattr__(record, name, value)


@dataclass(frozen=True, eq=False)
class Stroke(Operation):
    """A brush stroke: a brush and its mouse events (one undo step)."""

    name: ClassVar[str] = "stroke"
    required: ClassVar[tuple[str, ...]] = ("brush", "events")
    brush: Brush
    events: tuple[BrushEvent, ...] = field(default_factory=tuple)

    @property
    def steps(self) -> int:
        return max(1, len(self.events))

    def to_dict(self) -> dict[str, Any]:
        return {
            "op": self.name,
            "brush": self.brush.to_dict(),
            "events": [e.to_dict() for e in self.events],
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> Stroke:
        brush = Brush.from_dict(data["brush"], field_path(path, "brush"))
        name = field_path(path, "events")
        events = check_list(name, data["events"], max_length=MAX_EVENTS)
        return cls(
            brush, tuple(BrushEvent.from_dict(e, field_path(name, i)) for i, e in enumerate(events))
        )


@dataclass(frozen=True, eq=False)
class SettingsChange(Operation):
    """A settings group's values from now on (an undo step; ``continued`` joins the previous
    change of settings): one subclass per group of the setting table (:data:`SETTINGS_CHANGES`),
    whose ``"op"`` is the group's name and whose fields are the group's rows (by their record
    key: ``{"op": "constraint_radius", "radius": 0.1}``). The group's first row and the rows a
    session must give are required; a later row is written when not at its default."""

    values: Mapping[str, Any]  # the group's settings by name (checked values)
    continued: bool = False

    @classmethod
    def group_rows(cls) -> tuple[Setting, ...]:
        return tuple(s for s in rows("session") if s.group_name == cls.name)

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {"op": self.name}
        for s in self.group_rows():
            value = self.values[s.name]
            if s.record_key in self.required or s.written(value):
                data[s.record_key] = s.to_json(value)
        return {**data, "continued": True} if self.continued else data

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> SettingsChange:
        values: dict[str, Any] = {}
        for s in cls.group_rows():
            at, given = field_path(path, s.record_key), s.record_key in data
            values[s.name] = s.from_json(data[s.record_key], at, values) if given else s.initial()
        continued = check_bool(field_path(path, "continued"), data.get("continued", False))
        return cls(MappingProxyType(values), continued)


def _change_class(group: tuple[Setting, ...]) -> type[SettingsChange]:
    """The record class of a settings group (``MaterialChange``, ``FalloffChange``...)."""
    first = group[0]
    required = tuple(s.record_key for s in group if s is first or "session" in s.required)
    return type(
        first.name.title().replace("_", "") + "Change",
        (SettingsChange,),
        {
            "name": first.group_name,
            "required": required,
            "optional": (
                *(s.record_key for s in group if s.record_key not in required),
                "continued",
            ),
        },
    )


#: The change record of each settings group, by the group's name.
SETTINGS_CHANGES: dict[str, type[SettingsChange]] = {
    group[0]: _change_class(tuple(s for s in rows("session") if s.name in group))
    for group in SETTING_GROUPS
}


@dataclass(frozen=True, eq=False)
class ConstraintAdd(Operation):
    """A pin at ``point`` (3,), model units."""

    name: ClassVar[str] = "constraint_add"
    required: ClassVar[tuple[str, ...]] = ("point",)
    point: np.ndarray

    def __post_init__(self) -> None:
        _set(self, "point", check_finite("point", self.point, (3,)))


@dataclass(frozen=True)
class ConstraintRemove(Operation):
    """Remove pin ``index``."""

    name: ClassVar[str] = "constraint_remove"
    required: ClassVar[tuple[str, ...]] = ("index",)
    index: int

    def __post_init__(self) -> None:
        _set(self, "index", check_integer("index", self.index, low=0, high=MAX_INDEX))


@dataclass(frozen=True, eq=False)
class ConstraintDrag(Operation):
    """Move pin ``index`` by ``delta`` (3,) while the others stay (an undo step, joined to the
    previous drag when ``continued``)."""

    name: ClassVar[str] = "constraint_drag"
    required: ClassVar[tuple[str, ...]] = ("index", "delta")
    optional: ClassVar[tuple[str, ...]] = ("continued",)
    index: int
    delta: np.ndarray
    continued: bool = False

    def __post_init__(self) -> None:
        _set(self, "index", check_integer("index", self.index, low=0, high=MAX_INDEX))
        _set(self, "delta", check_finite("delta", self.delta, (3,)))
        _set(self, "continued", check_bool("continued", self.continued))


@dataclass(frozen=True)
class Subdivide(Operation):
    """One step of Loop subdivision of the whole mesh, or of its faces that are not masked
    (``unmasked_only``); an undo step (:mod:`gogreen_core.mesh.subdivision`)."""

    name: ClassVar[str] = "subdivide"
    optional: ClassVar[tuple[str, ...]] = ("unmasked_only",)
    unmasked_only: bool = False

    def __post_init__(self) -> None:
        _set(self, "unmasked_only", check_bool("unmasked_only", self.unmasked_only))


@dataclass(frozen=True)
class Remesh(Operation):
    """Isotropic remeshing of the whole mesh, or of its faces that are not masked
    (``unmasked_only``), to the edge length ``detail_size`` (a fraction of the model size; None:
    each vertex's own, the mean of its edges) in ``iterations`` rounds; an undo step
    (:mod:`gogreen_core.mesh.remesh`)."""

    name: ClassVar[str] = "remesh"
    required: ClassVar[tuple[str, ...]] = ("detail_size",)
    optional: ClassVar[tuple[str, ...]] = ("unmasked_only", "iterations")
    detail_size: float | None
    unmasked_only: bool = False
    iterations: int = REMESH_ITERATIONS

    def __post_init__(self) -> None:
        _set(self, "detail_size", check_detail_size(self.detail_size))
        _set(self, "unmasked_only", check_bool("unmasked_only", self.unmasked_only))
        rounds = check_integer("iterations", self.iterations, low=1, high=MAX_REMESH_ITERATIONS)
        _set(self, "iterations", rounds)


def _plain_record(name: str, doc: str) -> type[Operation]:
    """The record class of an operation without fields: ``{"op": name}``."""
    made = type(name.title().replace("_", ""), (Operation,), {"name": name, "__doc__": doc})
    return cast("type[Operation]", dataclass(frozen=True)(made))


ConstraintsClear = _plain_record("constraints_clear", "Remove every pin.")
MaskInvert = _plain_record("mask_invert", "Invert the vertex mask, m → 1 − m (an undo step).")
MaskClear = _plain_record("mask_clear", "Clear the vertex mask (an undo step if any was masked).")
Undo = _plain_record("undo", "Undo the last step.")
Redo = _plain_record("redo", "Redo the last undone step.")

_RECORDS: tuple[type[Operation], ...] = (
    Stroke,
    *SETTINGS_CHANGES.values(),
    ConstraintAdd,
    ConstraintRemove,
    ConstraintsClear,
    ConstraintDrag,
    MaskInvert,
    MaskClear,
    Subdivide,
    Remesh,
    Undo,
    Redo,
)
#: ``"op"`` name → record class.
OPERATIONS: dict[str, type[Operation]] = {cls.name: cls for cls in _RECORDS}


def settings_record(settings: EngineSettings, group: str, continued: bool) -> SettingsChange:
    """The log record of a change of the settings group named ``group`` (its first field, see
    :data:`~gogreen_core.sculpt.engine_settings.SETTING_GROUPS`) to ``settings``."""
    record = SETTINGS_CHANGES[group]
    return record({s.name: getattr(settings, s.name) for s in record.group_rows()}, continued)


def operation_from_dict(data: object, path: str = "operation") -> Operation:
    """One session operation ``{"op": name, ...}`` → its typed record; ParameterError naming
    the field (``path.events[0].delta``...)."""
    data = check_object(path, data)
    name = check_choice(field_path(path, "op"), member(data, path, "op"), tuple(OPERATIONS))
    cls = OPERATIONS[name]
    check_object(path, data, required=("op", *cls.required), optional=cls.optional)
    return cls.from_dict(data, path)
