"""The engine's settings as one immutable value: material, falloff, l_max, weights, pins' radius.

:class:`EngineSettings` is what a :class:`~gogreen_core.Sculptor` computes with besides the mesh
and the brush. The evented model (:class:`gogreen_core.interaction.settings.Settings`) hands one to
the engine in one typed call (:meth:`Sculptor.apply_settings`), presets make one
(:meth:`Preset.engine_settings`), a session file stores one (its ``settings``) and undo steps hold
the one before and the one after. Its constructor checks every field
(:mod:`gogreen_core.field.limits`: :class:`ParameterError` naming it), so a value that exists is
valid; equality is by content.

Adding an engine setting: one field here (its default, its check in ``__post_init__``, its
``to_dict`` / ``from_dict`` entry), one field on the evented model, and the engine reads it from
:attr:`Sculptor.settings`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, fields, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from gogreen_core.field.limits import (
    check_constraint_radius,
    check_detail_size,
    check_falloff,
    check_l_max,
    check_material,
)
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import GaussianRadial, RadialProfile
from gogreen_core.sculpt.brushes.weights import (
    check_brush_weights,
    default_weights,
    resized_brush_weights,
)
from gogreen_core.sculpt.schema import parse_falloff, parse_material
from gogreen_core.validation import check_bool, check_choice, check_object
from gogreen_core.validation import field as field_path

__all__ = [
    "DEFAULT_CONSTRAINT_RADIUS",
    "MATERIAL_FRAMES",
    "SETTING_GROUPS",
    "EngineSettings",
    "resized_brush_weights",
]

#: ε of the pins (fraction of the model size) when a session file does not say.
DEFAULT_CONSTRAINT_RADIUS = 0.1
#: Where a material's axes are: "world" (fixed in the model's axes, its own rotation applied;
#: the default, as before this setting existed) or "surface" (each stroke turns them onto the
#: surface where it starts: :mod:`gogreen_core.sculpt.material_frame`).
MATERIAL_FRAMES = ("world", "surface")
#: Fields that change together, as one undo step and one session record each: the material
#: with its frame;
#: the falloff with l_max and the brushes' weights (which belong to one l_max); the pins' radius;
#: dynamic topology with its detail size.
SETTING_GROUPS: tuple[tuple[str, ...], ...] = (
    ("material", "material_frame"),
    ("falloff", "l_max", "brush_weights"),
    ("constraint_radius",),
    ("dynamic_topology", "detail_size"),
)


def _default_material() -> Material:
    return Material.isotropic(1.0, 0.3)


def _default_falloff() -> RadialProfile:
    return GaussianRadial(1.0)


@dataclass(frozen=True, eq=False)  # eq: by content, below (the weights are an array)
class EngineSettings:
    """What the engine computes with besides the mesh and the brush (immutable, checked).

    material : :class:`Material`, default isotropic E = 1, ν = 0.3.
    falloff : the falloff shape, a single :class:`RadialProfile` held as an immutable value at
        ε = 1 (each brush sets its ε = radius · model size).
    l_max : SH truncation degree, 0 … ``L_MAX_LIMIT``.
    constraint_radius : ε of the pins as a fraction of the model size.
    brush_weights : per-brush degree weights ω_l (paper Fig. 7 and 10), a read-only mapping
        from a brush kind to l_max + 2 numbers (degrees 0 … l_max + 1); a brush not in it uses
        its defaults (:meth:`weights_for`).
    dynamic_topology : remesh what each stroke moves (:mod:`gogreen_core.mesh.remesh`), default off.
    detail_size : its target edge length as a fraction of the model size, or None (the
        default): the median edge length the moved region had before the stroke.
    material_frame : one of :data:`MATERIAL_FRAMES`: "world" (the default) or "surface" (the
        material's axes follow the surface where each stroke starts).

    Change one with :meth:`replace` (checked again); compare with ``==`` (by content).
    """

    material: Material = field(default_factory=_default_material)
    falloff: RadialProfile = field(default_factory=_default_falloff)
    l_max: int = 8
    constraint_radius: float = DEFAULT_CONSTRAINT_RADIUS
    brush_weights: Mapping[str, tuple[float, ...]] = field(
        default_factory=lambda: MappingProxyType({})
    )
    dynamic_topology: bool = False
    detail_size: float | None = None
    material_frame: str = "world"

    def __post_init__(self) -> None:
        l_max = check_l_max(self.l_max)
        checked = {
            "material": check_material(self.material),
            "falloff": check_falloff(self.falloff),
            "l_max": l_max,
            "constraint_radius": check_constraint_radius(self.constraint_radius),
            "brush_weights": check_brush_weights(self.brush_weights, l_max),
            "dynamic_topology": check_bool("dynamic_topology", self.dynamic_topology),
            "detail_size": check_detail_size(self.detail_size),
            "material_frame": check_choice("material_frame", self.material_frame, MATERIAL_FRAMES),
        }
        for name, value in checked.items():
            object.__setattr__(self, name, value)

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

    def same_as(self, other: EngineSettings) -> bool:
        """True when both compute the same thing (``==``)."""
        return self == other

    def to_dict(self) -> dict[str, Any]:
        """The session's ``settings`` object (constraint radius included; brush weights when
        some brush has its own)."""
        data: dict[str, Any] = {
            "material": self.material.to_dict(),
            "falloff": self.falloff.to_dict(),
            "l_max": self.l_max,
            "constraint_radius": self.constraint_radius,
        }
        if self.brush_weights:
            data["brush_weights"] = {k: list(v) for k, v in self.brush_weights.items()}
        if self.dynamic_topology or self.detail_size is not None:  # older files stay as they were
            data["dynamic_topology"] = self.dynamic_topology
            data["detail_size"] = self.detail_size
        if self.material_frame != "world":  # older files (world) stay as they were
            data["material_frame"] = self.material_frame
        return data

    @classmethod
    def from_dict(cls, data: object, path: str = "settings") -> EngineSettings:
        """Inverse of :meth:`to_dict`, the schema of a session's ``settings``:
        :class:`ParameterError` naming the field (``settings.l_max``...)."""
        names = tuple(f.name for f in fields(cls))
        values = check_object(path, data, required=names[:3], optional=names[3:])
        l_max = check_l_max(values["l_max"], field_path(path, "l_max"))
        return cls(
            material=parse_material(values["material"], field_path(path, "material")),
            falloff=parse_falloff(values["falloff"], field_path(path, "falloff")),
            l_max=l_max,
            constraint_radius=check_constraint_radius(
                values.get("constraint_radius", DEFAULT_CONSTRAINT_RADIUS),
                field_path(path, "constraint_radius"),
            ),
            brush_weights=check_brush_weights(
                values.get("brush_weights"), l_max, field_path(path, "brush_weights")
            ),
            dynamic_topology=check_bool(
                field_path(path, "dynamic_topology"), values.get("dynamic_topology", False)
            ),
            detail_size=check_detail_size(
                values.get("detail_size"), field_path(path, "detail_size")
            ),
            material_frame=check_choice(
                field_path(path, "material_frame"),
                values.get("material_frame", "world"),
                MATERIAL_FRAMES,
            ),
        )
