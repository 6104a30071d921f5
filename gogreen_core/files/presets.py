"""Presets: a material, a falloff (with l_max and the brushes' weights) and a brush, as JSON.

The app's Presets menu lists :func:`builtin_presets` (JSON files shipped in ``resources/presets``)
and loads or saves any other file; a script does the same::

    preset = load_preset("my_clay.json")
    preset.apply(sculptor)                      # material and falloff
    sculptor.apply_brush(preset.brush, events)

File format (``"format": "gogreen-preset"``, ``"version": 3``): ``name``, ``description``,
``material`` (:meth:`Material.to_dict`), ``falloff`` (a radial profile's ``to_dict``),
``l_max``, ``brush_weights`` (optional: per brush kind, l_max + 2 numbers), ``brush``
(:meth:`Brush.to_dict`), ``material_frame`` (optional: "world", the default, or "surface").
Files of versions 1-2 may hold ``degree_weights`` (of the wrinkle brush of sessions before
version 3, which no longer exists): ignored.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from importlib.resources import files
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from gogreen_core.mesh.mesh_io import write_text_atomic
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import GaussianRadial, RadialProfile
from gogreen_core.sculpt.brushes import Brush
from gogreen_core.sculpt.brushes.weights import check_brush_weights
from gogreen_core.sculpt.engine_settings import MATERIAL_FRAMES, EngineSettings
from gogreen_core.sculpt.schema import (
    parse_falloff,
    parse_file,
    parse_l_max,
    parse_material,
)
from gogreen_core.validation import (
    ParameterError,
    check_choice,
    check_integer,
    check_object,
    check_string,
)

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["PRESET_FORMAT", "Preset", "builtin_presets", "load_preset", "save_preset"]

PRESET_FORMAT = "gogreen-preset"
PRESET_VERSION = 3


@dataclass(frozen=True)
class Preset:
    """Everything an artist tunes before a stroke, as one named, shareable unit.

    The material, falloff, l_max and weights are checked as the engine's settings
    are (:class:`EngineSettings`, a :class:`ParameterError` naming the field); the falloff is
    held as an immutable value at ε = 1.
    """

    name: str
    material: Material
    falloff: RadialProfile = field(default_factory=lambda: GaussianRadial(1.0))
    l_max: int = 8
    brush: Brush = field(default_factory=Brush)
    description: str = ""
    brush_weights: Mapping[str, tuple[float, ...]] = field(
        default_factory=lambda: MappingProxyType({})
    )
    material_frame: str = "world"

    def __post_init__(self) -> None:
        checked = self.engine_settings()
        object.__setattr__(self, "material", checked.material)
        object.__setattr__(self, "falloff", checked.falloff)
        object.__setattr__(self, "l_max", checked.l_max)
        object.__setattr__(self, "brush_weights", checked.brush_weights)
        object.__setattr__(self, "material_frame", checked.material_frame)
        if not isinstance(self.brush, Brush):
            raise ParameterError(
                "brush", f"brush must be a Brush (got {type(self.brush).__name__})"
            )

    def engine_settings(self, base: EngineSettings | None = None) -> EngineSettings:
        """``base`` (default: the engine's defaults) with this preset's material and its frame,
        falloff, l_max and brushes' weights."""
        values: dict[str, Any] = {
            "material": self.material,
            "material_frame": self.material_frame,
            "falloff": self.falloff,
            "l_max": self.l_max,
            "brush_weights": self.brush_weights,
        }
        return EngineSettings(**values) if base is None else base.replace(**values)

    def apply(self, sculptor: Sculptor) -> None:
        """Give ``sculptor`` this material (and frame) and falloff, as one undo step (the brush
        is the caller's to use)."""
        before = sculptor.settings
        joined = not before.agrees(self.engine_settings(), ("material", "material_frame"))
        # ignored when unchanged; a new step the falloff joins
        sculptor.change_settings(material=self.material, material_frame=self.material_frame)
        sculptor.set_falloff(
            self.falloff,
            self.l_max,
            continued=joined,
            brush_weights=self.brush_weights,
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": PRESET_FORMAT,
            "version": PRESET_VERSION,
            "name": self.name,
            "description": self.description,
            "material": self.material.to_dict(),
            "falloff": self.falloff.to_dict(),
            "l_max": int(self.l_max),
            "brush": self.brush.to_dict(),
            **({"material_frame": self.material_frame} if self.material_frame != "world" else {}),
            **(
                {"brush_weights": {k: list(v) for k, v in self.brush_weights.items()}}
                if self.brush_weights
                else {}
            ),
        }

    @classmethod
    def from_dict(cls, data: object) -> Preset:
        """Inverse of :meth:`to_dict`, the preset schema: :class:`ParameterError` (a
        ``ValueError``) naming the missing, unknown, mistyped or out-of-range field."""
        if not isinstance(data, dict) or data.get("format") != PRESET_FORMAT:
            raise ParameterError(
                "format", f"not a GoGreen preset (expected format {PRESET_FORMAT!r})"
            )
        check_object(
            "",
            data,
            required=("format", "material", "falloff", "brush"),
            optional=(
                "version",
                "name",
                "description",
                "l_max",
                "degree_weights",
                "brush_weights",
                "material_frame",
            ),
        )
        version = data.get("version", PRESET_VERSION)
        if check_integer("version", version, low=1) > PRESET_VERSION:
            raise ParameterError(
                "version", f"preset version {version} is newer than this program's"
            )
        if version >= 3 and "degree_weights" in data:
            raise ParameterError("degree_weights", "degree_weights is not a preset field")
        l_max = parse_l_max(data.get("l_max", 8))
        return cls(
            name=check_string("name", data.get("name", ""), max_length=1000),
            material=parse_material(data["material"]),
            falloff=parse_falloff(data["falloff"]),
            l_max=l_max,
            brush=Brush.from_dict(data["brush"]),
            description=check_string("description", data.get("description", "")),
            brush_weights=check_brush_weights(data.get("brush_weights"), l_max),
            material_frame=check_choice(
                "material_frame", data.get("material_frame", "world"), MATERIAL_FRAMES
            ),
        )


def load_preset(path: str | os.PathLike[str]) -> Preset:
    """Read a preset file; ``ValueError`` (a :class:`ParameterError` for a bad field) whose
    message starts with the file's name."""
    preset = parse_file(path, Preset.from_dict, "preset file")
    return preset if preset.name else replace(preset, name=Path(path).stem)


def save_preset(preset: Preset, path: str | os.PathLike[str]) -> None:
    """Write ``preset`` as JSON atomically (a failed save leaves any old file intact)."""
    write_text_atomic(path, json.dumps(preset.to_dict(), indent=1) + "\n")


def builtin_presets() -> list[Preset]:
    """The presets shipped with the program (``resources/presets/*.json``), by file name."""
    folder = files("gogreen_resources").joinpath("presets")
    paths = sorted(
        (entry for entry in folder.iterdir() if entry.name.endswith(".json")),
        key=lambda e: e.name,
    )
    return [load_preset(str(entry)) for entry in paths]
