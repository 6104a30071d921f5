"""Typed records of what a sculptor did: one immutable class per operation, with ``to_dict``
and ``from_dict``; data only (replaying them is :func:`gogreen_core.sculpt.session.replay`).

A session's ``operations`` list holds their ``to_dict`` (``{"op": name, ...}``);
:func:`operation_from_dict` is the schema that reads one back, checking every field's type and
range and raising :class:`~gogreen_core.validation.ParameterError` naming the field
(``operations[3].events[0].delta``).

``continued`` (settings and pin drags): the change continues the previous one of its kind, so a
whole slider drag, curve drag or pin drag is one undo step.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, ClassVar

import numpy as np

from gogreen_core.field.limits import MAX_RADIUS, MIN_RADIUS, check_detail_size
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import RadialProfile
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.brushes.weights import check_brush_weights
from gogreen_core.sculpt.engine_settings import MATERIAL_FRAMES, EngineSettings
from gogreen_core.sculpt.schema import (
    parse_falloff,
    parse_l_max,
    parse_material,
)
from gogreen_core.validation import (
    ParameterError,
    check_bool,
    check_choice,
    check_finite,
    check_integer,
    check_list,
    check_number,
    check_object,
    prefixed,
)
from gogreen_core.validation import (
    field as field_path,
)

__all__ = [
    "OPERATIONS",
    "ConstraintAdd",
    "ConstraintDrag",
    "ConstraintRadius",
    "ConstraintRemove",
    "ConstraintsClear",
    "DynamicTopology",
    "FalloffChange",
    "MaskClear",
    "MaskInvert",
    "MaterialChange",
    "Operation",
    "Redo",
    "Remesh",
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
    """Base of the operation records (immutable dataclasses)."""

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
        raise NotImplementedError

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> Operation:
        """Read the fields of a checked ``data`` (``op`` and keys already checked)."""
        raise NotImplementedError


def _continued(data: dict[str, Any], path: str) -> bool:
    return check_bool(field_path(path, "continued"), data.get("continued", False))


def _with_flag(data: dict[str, Any], continued: bool) -> dict[str, Any]:
    return {**data, "continued": True} if continued else data


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
class MaterialChange(Operation):
    """The material and its frame from now on (an undo step; ``continued`` joins the previous
    setting). ``material_frame`` is written when it is not "world" (older files: "world")."""

    name: ClassVar[str] = "material"
    required: ClassVar[tuple[str, ...]] = ("material",)
    optional: ClassVar[tuple[str, ...]] = ("continued", "material_frame")
    material: Material
    continued: bool = False
    material_frame: str = "world"

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {"op": self.name, "material": self.material.to_dict()}
        if self.material_frame != "world":
            data["material_frame"] = self.material_frame
        return _with_flag(data, self.continued)

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> MaterialChange:
        material = parse_material(data["material"], field_path(path, "material"))
        frame = check_choice(
            field_path(path, "material_frame"),
            data.get("material_frame", "world"),
            MATERIAL_FRAMES,
        )
        return cls(material, _continued(data, path), frame)


@dataclass(frozen=True, eq=False)
class FalloffChange(Operation):
    """Falloff shape, truncation degree and degree weights from now on (an undo step):
    ``brush_weights`` of every brush that has its own (absent: every brush at its defaults)."""

    name: ClassVar[str] = "falloff"
    required: ClassVar[tuple[str, ...]] = ("falloff", "l_max")
    optional: ClassVar[tuple[str, ...]] = ("brush_weights", "continued")
    falloff: RadialProfile
    l_max: int
    continued: bool = False
    brush_weights: Mapping[str, tuple[float, ...]] = field(
        default_factory=lambda: MappingProxyType({})
    )

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {
            "op": self.name,
            "falloff": self.falloff.to_dict(),
            "l_max": int(self.l_max),
        }
        if self.brush_weights:
            data["brush_weights"] = {k: list(v) for k, v in self.brush_weights.items()}
        return _with_flag(data, self.continued)

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> FalloffChange:
        falloff = parse_falloff(data["falloff"], field_path(path, "falloff"))
        l_max = parse_l_max(data["l_max"], field_path(path, "l_max"))
        brush_weights = check_brush_weights(
            data.get("brush_weights"), l_max, field_path(path, "brush_weights")
        )
        return cls(falloff, l_max, _continued(data, path), brush_weights)


@dataclass(frozen=True)
class ConstraintRadius(Operation):
    """ε of the pins as a fraction of the model size (an undo step)."""

    name: ClassVar[str] = "constraint_radius"
    required: ClassVar[tuple[str, ...]] = ("radius",)
    optional: ClassVar[tuple[str, ...]] = ("continued",)
    radius: float
    continued: bool = False

    def to_dict(self) -> dict[str, Any]:
        return _with_flag({"op": self.name, "radius": self.radius}, self.continued)

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> ConstraintRadius:
        name = field_path(path, "radius")
        radius = check_number(name, data["radius"], low=MIN_RADIUS, high=MAX_RADIUS)
        return cls(radius, _continued(data, path))


@dataclass(frozen=True, eq=False)
class ConstraintAdd(Operation):
    """A pin at ``point`` (3,), model units."""

    name: ClassVar[str] = "constraint_add"
    required: ClassVar[tuple[str, ...]] = ("point",)
    point: np.ndarray

    def to_dict(self) -> dict[str, Any]:
        return {"op": self.name, "point": np.asarray(self.point, float).tolist()}

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> ConstraintAdd:
        return cls(check_finite(field_path(path, "point"), data["point"], (3,)))


@dataclass(frozen=True)
class ConstraintRemove(Operation):
    """Remove pin ``index``."""

    name: ClassVar[str] = "constraint_remove"
    required: ClassVar[tuple[str, ...]] = ("index",)
    index: int

    def to_dict(self) -> dict[str, Any]:
        return {"op": self.name, "index": int(self.index)}

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> ConstraintRemove:
        name = field_path(path, "index")
        return cls(check_integer(name, data["index"], low=0, high=MAX_INDEX))


@dataclass(frozen=True)
class ConstraintsClear(Operation):
    """Remove every pin."""

    name: ClassVar[str] = "constraints_clear"

    def to_dict(self) -> dict[str, Any]:
        return {"op": self.name}

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> ConstraintsClear:
        return cls()


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

    def to_dict(self) -> dict[str, Any]:
        data = {"op": self.name, "index": int(self.index), "delta": self.delta.tolist()}
        return _with_flag(data, self.continued)

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> ConstraintDrag:
        index = check_integer(field_path(path, "index"), data["index"], low=0, high=MAX_INDEX)
        delta = check_finite(field_path(path, "delta"), data["delta"], (3,))
        return cls(index, delta, _continued(data, path))


@dataclass(frozen=True)
class MaskInvert(Operation):
    """Invert the vertex mask, m → 1 − m (an undo step; the vertices do not move)."""

    name: ClassVar[str] = "mask_invert"

    def to_dict(self) -> dict[str, Any]:
        return {"op": self.name}

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> MaskInvert:
        return cls()


@dataclass(frozen=True)
class MaskClear(Operation):
    """Clear the vertex mask (an undo step when anything was masked)."""

    name: ClassVar[str] = "mask_clear"

    def to_dict(self) -> dict[str, Any]:
        return {"op": self.name}

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> MaskClear:
        return cls()


@dataclass(frozen=True)
class Subdivide(Operation):
    """One step of Loop subdivision of the whole mesh, or of its faces that are not masked
    (``unmasked_only``); an undo step (:mod:`gogreen_core.mesh.subdivision`)."""

    name: ClassVar[str] = "subdivide"
    optional: ClassVar[tuple[str, ...]] = ("unmasked_only",)
    unmasked_only: bool = False

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {"op": self.name}
        if self.unmasked_only:
            data["unmasked_only"] = True
        return data

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> Subdivide:
        name = field_path(path, "unmasked_only")
        return cls(check_bool(name, data.get("unmasked_only", False)))


@dataclass(frozen=True)
class DynamicTopology(Operation):
    """Dynamic topology on or off and its detail size (a fraction of the model size, or None:
    the edge length the surface had) from now on (an undo step)."""

    name: ClassVar[str] = "dynamic_topology"
    required: ClassVar[tuple[str, ...]] = ("enabled",)
    optional: ClassVar[tuple[str, ...]] = ("detail_size", "continued")
    enabled: bool
    detail_size: float | None = None
    continued: bool = False

    def to_dict(self) -> dict[str, Any]:
        data = {"op": self.name, "enabled": self.enabled, "detail_size": self.detail_size}
        return _with_flag(data, self.continued)

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> DynamicTopology:
        enabled = check_bool(field_path(path, "enabled"), data["enabled"])
        size = check_detail_size(data.get("detail_size"), field_path(path, "detail_size"))
        return cls(enabled, size, _continued(data, path))


@dataclass(frozen=True)
class Remesh(Operation):
    """Isotropic remeshing of the whole mesh, or of its faces that are not masked
    (``unmasked_only``), to the edge length ``detail_size`` (a fraction of the model size) in
    ``iterations`` rounds; an undo step (:mod:`gogreen_core.mesh.remesh`)."""

    name: ClassVar[str] = "remesh"
    required: ClassVar[tuple[str, ...]] = ("detail_size",)
    optional: ClassVar[tuple[str, ...]] = ("unmasked_only", "iterations")
    detail_size: float
    unmasked_only: bool = False
    iterations: int = REMESH_ITERATIONS

    def to_dict(self) -> dict[str, Any]:
        data: dict[str, Any] = {"op": self.name, "detail_size": self.detail_size}
        if self.unmasked_only:
            data["unmasked_only"] = True
        if self.iterations != REMESH_ITERATIONS:
            data["iterations"] = self.iterations
        return data

    def __post_init__(self) -> None:
        size = check_detail_size(self.detail_size)
        if size is None:
            raise ParameterError("detail_size", "detail_size must be a number (got None)")
        object.__setattr__(self, "detail_size", size)
        object.__setattr__(self, "unmasked_only", check_bool("unmasked_only", self.unmasked_only))
        rounds = check_integer("iterations", self.iterations, low=1, high=MAX_REMESH_ITERATIONS)
        object.__setattr__(self, "iterations", rounds)

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> Remesh:
        with prefixed(path):
            return cls(
                data["detail_size"],
                data.get("unmasked_only", False),
                data.get("iterations", REMESH_ITERATIONS),
            )


@dataclass(frozen=True)
class Undo(Operation):
    """Undo the last step."""

    name: ClassVar[str] = "undo"

    def to_dict(self) -> dict[str, Any]:
        return {"op": self.name}

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> Undo:
        return cls()


@dataclass(frozen=True)
class Redo(Operation):
    """Redo the last undone step."""

    name: ClassVar[str] = "redo"

    def to_dict(self) -> dict[str, Any]:
        return {"op": self.name}

    @classmethod
    def from_dict(cls, data: dict[str, Any], path: str) -> Redo:
        return cls()


#: ``"op"`` name → record class.
OPERATIONS: dict[str, type[Operation]] = {
    cls.name: cls
    for cls in (
        Stroke,
        MaterialChange,
        FalloffChange,
        ConstraintRadius,
        ConstraintAdd,
        ConstraintRemove,
        ConstraintsClear,
        ConstraintDrag,
        MaskInvert,
        MaskClear,
        Subdivide,
        DynamicTopology,
        Remesh,
        Undo,
        Redo,
    )
}


def settings_record(settings: EngineSettings, group: str, continued: bool) -> Operation:
    """The log record of a change of the settings group named ``group`` (its first field, see
    :data:`~gogreen_core.sculpt.engine_settings.SETTING_GROUPS`) to ``settings``."""
    s = settings
    if group == "material":
        return MaterialChange(s.material, continued, s.material_frame)
    if group == "constraint_radius":
        return ConstraintRadius(s.constraint_radius, continued)
    if group == "dynamic_topology":
        return DynamicTopology(s.dynamic_topology, s.detail_size, continued)
    return FalloffChange(s.falloff, s.l_max, continued, s.brush_weights)


def operation_from_dict(data: object, path: str = "operation") -> Operation:
    """One session operation ``{"op": name, ...}`` → its typed record; ParameterError naming
    the field (``path.op``, ``path.events[0].delta``...) for anything missing, unknown,
    mistyped or out of range."""
    data = check_object(path, data)
    if "op" not in data:
        raise ParameterError(field_path(path, "op"), f"{field_path(path, 'op')} is missing")
    name = check_choice(field_path(path, "op"), data["op"], tuple(OPERATIONS))
    cls = OPERATIONS[name]
    check_object(path, data, required=("op", *cls.required), optional=cls.optional)
    return cls.from_dict(data, path)
