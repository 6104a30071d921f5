"""Presets: a material, a falloff (with l_max and wrinkle weights) and a brush, saved as JSON.

The app's Presets menu lists :func:`builtin_presets` (JSON files shipped in ``resources/presets``)
and loads or saves any other file; a script does the same::

    preset = load_preset("my_clay.json")
    preset.apply(sculptor)                      # material and falloff
    sculptor.apply_brush(preset.brush, events)

File format (``"format": "gogreen-preset"``, ``"version": 1``): ``name``, ``description``,
``material`` (:meth:`Material.to_dict`), ``falloff`` (a radial profile's ``to_dict``),
``l_max``, ``degree_weights`` (l_max + 1 numbers or null for the default), ``brush``
(:meth:`Brush.to_dict`).
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field, replace
from importlib.resources import files
from pathlib import Path

import numpy as np

from gogreen_core.brushes import Brush
from gogreen_core.kernel import L_MAX_LIMIT
from gogreen_core.material import Material
from gogreen_core.mesh_io import write_text_atomic
from gogreen_core.radial import GaussianRadial, RadialProfile, radial_from_dict
from gogreen_core.sculptor import Sculptor

__all__ = ["PRESET_FORMAT", "Preset", "builtin_presets", "load_preset", "save_preset"]

PRESET_FORMAT = "gogreen-preset"
PRESET_VERSION = 1


@dataclass(frozen=True, eq=False)  # eq: the weights array has no single truth value
class Preset:
    """Everything an artist tunes before a stroke, as one named, shareable unit.

    ``degree_weights`` is None for the engine's default wrinkle weights, else (l_max + 1,).
    """

    name: str
    material: Material
    falloff: RadialProfile = field(default_factory=lambda: GaussianRadial(1.0))
    l_max: int = 8
    degree_weights: np.ndarray | None = None
    brush: Brush = field(default_factory=Brush)
    description: str = ""

    def apply(self, sculptor: Sculptor) -> None:
        """Give ``sculptor`` this material and falloff (the brush is the caller's to use)."""
        sculptor.set_material(self.material)
        sculptor.set_falloff(self.falloff, self.l_max, self.degree_weights)

    def to_dict(self) -> dict:
        weights = self.degree_weights
        return {
            "format": PRESET_FORMAT,
            "version": PRESET_VERSION,
            "name": self.name,
            "description": self.description,
            "material": self.material.to_dict(),
            "falloff": self.falloff.to_dict(),
            "l_max": int(self.l_max),
            "degree_weights": None if weights is None else [float(w) for w in weights],
            "brush": self.brush.to_dict(),
        }

    @classmethod
    def from_dict(cls, data: dict) -> Preset:
        """Inverse of :meth:`to_dict`; ``ValueError`` naming what is wrong."""
        if not isinstance(data, dict) or data.get("format") != PRESET_FORMAT:
            raise ValueError(f"not a GoGreen preset (expected format {PRESET_FORMAT!r})")
        if data.get("version", PRESET_VERSION) > PRESET_VERSION:
            raise ValueError(f"preset version {data['version']} is newer than this program's")
        try:
            material = Material.from_dict(data["material"])
            falloff = radial_from_dict(data["falloff"])
            brush = Brush.from_dict(data["brush"])
            l_max = data.get("l_max", 8)
            weights = data.get("degree_weights")
        except KeyError as exc:
            raise ValueError(f"preset has no {exc.args[0]!r} entry") from None
        except TypeError as exc:
            raise ValueError(f"malformed preset: {exc}") from None
        if isinstance(l_max, bool) or not isinstance(l_max, int) or not 0 <= l_max <= L_MAX_LIMIT:
            raise ValueError(
                f"preset l_max must be an integer in [0, {L_MAX_LIMIT}] (got {l_max!r})"
            )
        if weights is not None:
            weights = np.asarray(weights, dtype=np.float64)
            if weights.shape != (l_max + 1,) or not np.all(np.isfinite(weights)):
                raise ValueError(f"preset degree_weights must be l_max + 1 = {l_max + 1} numbers")
        return cls(
            name=str(data.get("name", "")),
            material=material,
            falloff=falloff,
            l_max=l_max,
            degree_weights=weights,
            brush=brush,
            description=str(data.get("description", "")),
        )


def load_preset(path: str | os.PathLike) -> Preset:
    """Read a preset file; ``ValueError`` naming the file and the problem."""
    p = Path(path)
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise ValueError(f"{p.name}: cannot read ({exc.strerror or exc})") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{p.name}: not valid JSON ({exc})") from None
    try:
        preset = Preset.from_dict(data)
    except ValueError as exc:
        raise ValueError(f"{p.name}: {exc}") from None
    return preset if preset.name else replace(preset, name=p.stem)


def save_preset(preset: Preset, path: str | os.PathLike) -> None:
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
