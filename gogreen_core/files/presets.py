"""Presets: a material, a falloff (with l_max and the brushes' weights) and a brush, as JSON::

    preset = load_preset("my_clay.json")
    preset.apply(sculptor)                      # material and falloff
    sculptor.apply_brush(preset.brush, events)

File format (``"format": "gogreen-preset"``, ``"version": 3``): ``name``, ``description``,
the ``"preset"`` settings of the setting table, ``brush`` (:meth:`Brush.to_dict`). The
``degree_weights`` of versions 1-2 (a wrinkle brush that no longer exists) are ignored.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path
from typing import TYPE_CHECKING, Any

from gogreen_core.mesh.mesh_io import write_text_atomic
from gogreen_core.sculpt.brushes import Brush
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.schema import parse_file
from gogreen_core.sculpt.setting_table import rows
from gogreen_core.validation import (
    ParameterError,
    check_integer,
    check_object,
    check_string,
    check_type,
)

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["PRESET_FORMAT", "Preset", "builtin_presets", "load_preset", "save_preset"]

PRESET_FORMAT = "gogreen-preset"
PRESET_VERSION = 3


@dataclass(frozen=True, init=False)
class Preset:
    """Everything an artist tunes before a stroke, as one named, shareable unit:
    ``Preset(name, material, falloff, l_max, brush_weights=..., brush=..., description=...)``.
    Its settings are the ``"preset"`` rows of the setting table, given by keyword, in the
    table's order or from ``settings``, read as attributes and held (checked) in
    :attr:`settings` (an :class:`EngineSettings`, the other rows at their defaults).
    """

    name: str
    settings: EngineSettings
    brush: Brush
    description: str

    def __init__(
        self,
        name: str,
        *ordered: Any,
        brush: Brush | None = None,
        description: str = "",
        settings: EngineSettings | None = None,
        **values: Any,
    ) -> None:
        names = [s.name for s in rows("preset")]
        given = {n: getattr(settings, n) for n in names} if settings is not None else {}
        given.update({**dict(zip(names, ordered, strict=False)), **values})
        if len(ordered) > len(names) or set(given) - set(names):
            raise TypeError(f"Preset() takes the settings {', '.join(names)} (got {sorted(given)})")
        brush = Brush() if brush is None else check_type("brush", brush, Brush)
        for attribute, value in (("name", name), ("brush", brush), ("description", description)):
            object.__setattr__(self, attribute, value)
        object.__setattr__(self, "settings", EngineSettings(**given))

    def __getattr__(self, name: str) -> Any:
        if name in _NAMES:  # a setting of the preset
            return getattr(self.settings, name)
        raise AttributeError(f"Preset has no attribute {name!r}")

    def engine_settings(self, base: EngineSettings | None = None) -> EngineSettings:
        """``base`` (default: the engine's defaults) with this preset's settings."""
        values = {name: getattr(self.settings, name) for name in _NAMES}
        return EngineSettings(**values) if base is None else base.replace(**values)

    def apply(self, sculptor: Sculptor) -> None:
        """Give ``sculptor`` this preset's settings (not the brush), as one undo step."""
        sculptor.apply_settings(self.engine_settings(sculptor.settings), one_step=True)

    def to_dict(self) -> dict[str, Any]:
        return {
            "format": PRESET_FORMAT,
            "version": PRESET_VERSION,
            "name": self.name,
            "description": self.description,
            **self.settings.to_dict("preset"),
            "brush": self.brush.to_dict(),
        }

    @classmethod
    def from_dict(cls, data: object, name: str = "") -> Preset:
        """Inverse of :meth:`to_dict`, the preset schema: :class:`ParameterError` (a
        ``ValueError``) naming the missing, unknown, mistyped or out-of-range field. ``name``:
        the preset's when the file gives none."""
        if not isinstance(data, dict) or data.get("format") != PRESET_FORMAT:
            raise ParameterError(
                "format", f"not a GoGreen preset (expected format {PRESET_FORMAT!r})"
            )
        check_object(
            "",
            data,
            required=(
                "format",
                *(s.name for s in rows("preset") if "preset" in s.required),
                "brush",
            ),
            optional=("version", "name", "description", "degree_weights", *_NAMES),
        )
        version = data.get("version", PRESET_VERSION)
        if check_integer("version", version, low=1) > PRESET_VERSION:
            raise ParameterError(
                "version", f"preset version {version} is newer than this program's"
            )
        if version >= 3 and "degree_weights" in data:
            raise ParameterError("degree_weights", "degree_weights is not a preset field")
        settings = EngineSettings.from_dict(data, "", "preset")
        return cls(
            check_string("name", data.get("name", ""), max_length=1000) or name,
            brush=Brush.from_dict(data["brush"]),
            description=check_string("description", data.get("description", "")),
            **{s: getattr(settings, s) for s in _NAMES},
        )


#: The settings a preset holds.
_NAMES = frozenset(s.name for s in rows("preset"))


def load_preset(path: str | os.PathLike[str]) -> Preset:
    """Read a preset file; ``ValueError`` (a :class:`ParameterError` for a bad field) whose
    message starts with the file's name."""
    return parse_file(path, lambda data: Preset.from_dict(data, Path(path).stem), "preset file")


def save_preset(preset: Preset, path: str | os.PathLike[str]) -> None:
    """Write ``preset`` as JSON atomically (a failed save leaves any old file intact)."""
    write_text_atomic(path, json.dumps(preset.to_dict(), indent=1) + "\n")


def builtin_presets() -> list[Preset]:
    """The presets shipped with the program (``resources/presets/*.json``), by file name."""
    folder = files("gogreen_resources").joinpath("presets")
    paths = sorted(e.name for e in folder.iterdir() if e.name.endswith(".json"))
    return [load_preset(str(folder.joinpath(name))) for name in paths]
