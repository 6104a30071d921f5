"""The engine's settings, each declared once: :data:`SETTINGS`, one :class:`Setting` a row.

``EngineSettings``, the app's ``Settings``, presets, session files, the CLI's flags and the
Blender extension's properties are made from the rows that apply there (:data:`PLACES`).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from gogreen_core.field.kernel import L_MAX_LIMIT
from gogreen_core.field.limits import (
    MAX_DETAIL_SIZE,
    MAX_RADIUS,
    MIN_DETAIL_SIZE,
    MIN_RADIUS,
    check_falloff,
    check_material,
)
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import GaussianRadial
from gogreen_core.sculpt.brushes.weights import check_brush_weights
from gogreen_core.sculpt.schema import parse_falloff, parse_material
from gogreen_core.validation import check_bool, check_choice, check_integer, check_number

__all__ = ["DEFAULT_CONSTRAINT_RADIUS", "PLACES", "SETTINGS", "Setting", "rows"]

#: Where a setting may apply: the engine's value, the app's settings model, preset files,
#: session files (their ``settings`` and change records), the Blender extension, the CLI.
PLACES = ("engine", "app", "preset", "session", "blender", "cli")
#: ε of the pins (fraction of the model size) when a session file does not say.
DEFAULT_CONSTRAINT_RADIUS = 0.1


@dataclass(frozen=True)
class Setting:
    """One setting. ``type``: ``"int"``, ``"float"``, ``"bool"``, ``"choice"`` (one of
    ``choices``), ``"material"``, ``"falloff"`` or ``"weights"`` (per-brush degree weights of
    the row ``l_max``). ``low``/``high``: closed bounds of a number (``soft_high``: a slider's
    usual end); ``none``: None is a value too. ``group``: settings that change together (one
    undo step, one session record whose ``"op"`` is the group's name; ``key`` is the field's
    name in that record). ``since``: the session version it appeared in (later ones are written
    only when not at their default, so older files stay as they were). ``required``: the files
    (``"session"``, ``"preset"``) that must give it."""

    name: str
    type: str
    default: Any  # a value, or a function of no argument making one
    doc: str
    group: str = ""  # its own name when empty
    since: int = 1
    places: tuple[str, ...] = ("engine", "app", "session")
    low: float | None = None
    high: float | None = None
    soft_high: float | None = None
    choices: tuple[str, ...] = ()
    none: bool = False
    required: tuple[str, ...] = ()
    key: str = ""  # its own name when empty

    @property
    def group_name(self) -> str:
        return self.group or self.name

    @property
    def record_key(self) -> str:
        return self.key or self.name

    @property
    def flag(self) -> str:
        """Its command-line flag: ``--l-max``."""
        return "--" + self.name.replace("_", "-")

    @property
    def title(self) -> str:
        """Its label in a user interface: ``Detail size``."""
        return self.name.replace("_", " ").capitalize()

    def initial(self) -> Any:
        """A new default value."""
        return self.default() if callable(self.default) else self.default

    def check(self, value: object, path: str = "", earlier: Mapping[str, Any] | None = None) -> Any:
        """``value`` checked (normalized), else ParameterError naming ``path`` (default: the
        setting's name); ``earlier``: the checked values of the rows above (a ``weights`` row
        reads ``l_max``)."""
        path = path or self.name
        if value is None and self.none:
            return None
        if self.type == "material":
            return check_material(value, path)
        if self.type == "falloff":
            return check_falloff(value, path)
        if self.type == "weights":
            return check_brush_weights(value, (earlier or {})["l_max"], path)
        if self.type == "int":
            low, high = (None if b is None else int(b) for b in (self.low, self.high))
            return check_integer(path, value, low=low, high=high)
        if self.type == "float":
            return check_number(path, value, low=self.low, high=self.high)
        if self.type == "bool":
            return check_bool(path, value)
        return check_choice(path, value, self.choices)

    def to_json(self, value: Any) -> Any:
        """``value`` as JSON (a material's or falloff's ``to_dict``, weights as lists)."""
        if self.type in ("material", "falloff"):
            return value.to_dict()
        if self.type == "weights":
            return {kind: list(weights) for kind, weights in value.items()}
        return value

    def from_json(self, data: object, path: str, earlier: Mapping[str, Any]) -> Any:
        """Inverse of :meth:`to_json`, checked (ParameterError naming ``path``)."""
        if self.type == "material":
            return parse_material(data, path)
        if self.type == "falloff":
            return parse_falloff(data, path)
        return self.check(data, path, earlier)

    def written(self, value: Any) -> bool:
        """Whether a file holds ``value``: always for the first version's settings, else when
        it is not the default."""
        return self.since == 1 or value != self.initial()


def rows(place: str) -> tuple[Setting, ...]:
    """The rows of :data:`SETTINGS` that apply in ``place``."""
    return tuple(s for s in SETTINGS if place in s.places)


_ALL = PLACES
_NOT_BLENDER = ("engine", "app", "session", "cli")
#: Every setting of the engine, in the order files list them (a row's check may read the
#: rows above it).
SETTINGS: tuple[Setting, ...] = (
    Setting("material", "material", lambda: Material.isotropic(1.0, 0.3),
            "the elastic material (default isotropic, E 1, ν 0.3)",
            places=_ALL, required=("session", "preset")),
    Setting("falloff", "falloff", lambda: GaussianRadial(1.0),
            "the falloff shape at ε = 1 (each brush sets its ε)",
            places=_ALL, required=("session", "preset")),
    Setting("l_max", "int", 8,
            "truncation degree of the spherical-harmonic expansion (higher: finer, slower)",
            group="falloff", places=_ALL, low=0, high=L_MAX_LIMIT, soft_high=16,
            required=("session",)),
    Setting("constraint_radius", "float", DEFAULT_CONSTRAINT_RADIUS,
            "ε of the pins as a fraction of the model size",
            low=MIN_RADIUS, high=MAX_RADIUS, soft_high=0.5, key="radius"),
    Setting("brush_weights", "weights", lambda: MappingProxyType({}),
            "per-brush degree weights ω_0 … ω_(l_max+1) (a brush not listed has its defaults)",
            group="falloff", since=3, places=("engine", "app", "preset", "session", "blender")),
    Setting("dynamic_topology", "bool", False, "strokes remesh what they move",
            since=5, places=_NOT_BLENDER, key="enabled"),
    Setting("detail_size", "float", None,
            "dynamic topology's edge length as a fraction of the model size (none: the surface's)",
            group="dynamic_topology", since=5, places=_NOT_BLENDER,
            low=MIN_DETAIL_SIZE, high=MAX_DETAIL_SIZE, none=True),
    Setting("material_frame", "choice", "world",
            "where the material's axes are: fixed in the world, or turned onto the surface where "
            "each stroke starts (third axis along the normal, first along the stroke)",
            group="material", since=6, places=_ALL, choices=("world", "surface")),
)  # fmt: skip
