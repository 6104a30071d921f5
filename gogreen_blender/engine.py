"""From the add-on's plain setting values to ``gogreen_core`` objects, and strokes (no bpy).

Everything here takes and returns plain Python and NumPy values, so it runs (and is tested)
outside Blender too; :mod:`.properties` reads the scene's values into a :class:`SculptSettings`
and the operators call :func:`stroke` or build a :class:`gogreen_core.Sculptor` with
:func:`make_sculptor`. The engine is ``gogreen_core`` itself: nothing of its numerics is
repeated here.

Conventions: vertices and events are in object space; a brush radius is ε as a fraction of the
mesh's bounding-box diagonal (as in the desktop app, so presets carry over); mirror symmetry is
about the object's own axes through its origin (Blender's sculpt symmetry), not the centre of the
bounding box the desktop app mirrors about.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from gogreen_core import (
    BRUSH_KINDS,
    PATTERNS,
    Brush,
    BrushEvent,
    GaussianRadial,
    KelvinletRadial,
    Material,
    ParameterError,
    RadialProfile,
    Sculptor,
    bimaterial,
    homogenize,
    make_pattern,
    radial_from_dict,
)
from gogreen_core.mesh.shapes import icosphere
from gogreen_core.sculpt.brushes.weights import check_brush_weights
from gogreen_core.sculpt.engine_settings import EngineSettings, resized_brush_weights
from gogreen_core.sculpt.schema import parse_material

__all__ = [
    "ADDON_BRUSH_KINDS",
    "FALLOFF_KINDS",
    "MATERIAL_MODES",
    "SculptSettings",
    "brush_label",
    "brush_weights_from",
    "default_settings",
    "euler_matrix",
    "events_from_json",
    "falloff_from",
    "homogenized_material",
    "influence_of",
    "make_sculptor",
    "material_from_json",
    "material_to_json",
    "mirror_axes",
    "orthotropic_material",
    "rotated_material",
    "stroke",
]

#: The engine's brushes the add-on offers: all but the mask brush, whose mask would live for one
#: stroke only here (Blender keeps its own sculpt mask, with its own tools).
ADDON_BRUSH_KINDS = tuple(kind for kind in BRUSH_KINDS if kind != "mask")

#: Material sources of the panel: identifier, label, description.
MATERIAL_MODES = (
    ("ISOTROPIC", "Isotropic", "Young's modulus and Poisson ratio"),
    ("ORTHOTROPIC", "Orthotropic", "Three Young's moduli, shear moduli and Poisson ratios"),
    ("HOMOGENIZED", "Homogenized", "The effective material of a periodic two-phase pattern"),
    ("CUSTOM", "Preset / custom", "A 6x6 stiffness from a preset file or a script"),
)
#: Falloff shapes: identifier, label, description.
FALLOFF_KINDS = (
    ("GAUSSIAN", "Gaussian", "Gaussian falloff (the default)"),
    ("KELVINLET", "Kelvinlet", "Regularized Kelvinlet falloff (Blender's Elastic Deform)"),
    ("CUSTOM", "Preset curve", "The falloff curves of the loaded preset"),
)


def brush_label(kind: str) -> str:
    """'grab_biscale' → 'Grab Biscale' (what the panel shows for a brush kind)."""
    return kind.replace("_", " ").title()


@dataclass(frozen=True)
class SculptSettings:
    """What a stroke needs besides the mesh and the events: the brush and the engine settings.

    brush : the :class:`gogreen_core.Brush` (kind, radius as a fraction of the model size,
        strength, substeps, influence in ε, symmetry letters).
    engine_settings : the engine's settings (material, falloff, l_max, the brushes' degree
        weights... the rows of :data:`gogreen_core.sculpt.setting_table.SETTINGS`; its
        falloff's ε is ignored: each brush sets it).
    """

    brush: Brush
    engine_settings: EngineSettings


def euler_matrix(angles: Sequence[float]) -> np.ndarray:
    """(3, 3) rotation Rz(γ) Ry(β) Rx(α) of Euler angles (α, β, γ) in radians: extrinsic
    rotations about the fixed x, then y, then z axes (Blender's XYZ Euler order)."""
    a, b, c = (float(v) for v in angles)
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


def rotated_material(material: Material, angles: Sequence[float]) -> Material:
    """``material`` with its axes turned by XYZ Euler ``angles`` (radians)."""
    if not any(angles):
        return material
    return material.rotated(euler_matrix(angles))


def orthotropic_material(
    young: Sequence[float], shear: Sequence[float], poisson: Sequence[float]
) -> Material:
    """:meth:`Material.orthotropic` whose errors name the panel's fields."""
    try:
        return Material.orthotropic(young, shear, poisson)
    except ParameterError:
        raise
    except ValueError as exc:
        raise ParameterError("material", f"orthotropic material: {exc}") from None


def material_to_json(material: Material) -> str:
    """A material as JSON text (double precision, unlike Blender's float properties)."""
    return json.dumps(material.to_dict())


def material_from_json(text: str, what: str = "material") -> Material:
    """Inverse of :func:`material_to_json`; :class:`ParameterError` naming ``what``."""
    if not text:
        raise ParameterError(what, f"no {what} has been set (load a preset or compute one)")
    try:
        return parse_material(json.loads(text), what)
    except (ValueError, TypeError) as exc:
        raise ParameterError(what, f"{what} is not a valid stiffness: {exc}") from None


def falloff_from(kind: str, custom_json: str = "") -> RadialProfile:
    """The falloff shape of the panel's choice (ε 1: the brush sets its own)."""
    if kind == "GAUSSIAN":
        return GaussianRadial(1.0)
    if kind == "KELVINLET":
        return KelvinletRadial(1.0)
    if kind == "CUSTOM":
        if not custom_json:
            raise ParameterError("falloff", "no falloff curve has been loaded (load a preset)")
        try:
            return radial_from_dict(json.loads(custom_json))
        except (ValueError, TypeError, KeyError) as exc:
            raise ParameterError("falloff", f"the stored falloff is not valid: {exc}") from None
    raise ParameterError("falloff", f"unknown falloff {kind!r}")


def brush_weights_from(text: str, l_max: int) -> Mapping[str, tuple[float, ...]]:
    """The per-brush degree weights stored as a JSON object (a preset's, the panel's), fitted
    to ``l_max`` (degrees both have are kept, new ones get each brush's defaults); none
    stored: every brush at its defaults."""
    if not text:
        return {}
    try:
        stored = json.loads(text)
    except (ValueError, TypeError) as exc:
        raise ParameterError("brush_weights", f"stored weights are not JSON: {exc}") from None
    if not isinstance(stored, dict) or not all(isinstance(w, list) for w in stored.values()):
        raise ParameterError("brush_weights", "stored weights must map brush kinds to lists")
    sized = {kind: tuple(weights) for kind, weights in stored.items()}
    if {len(weights) for weights in sized.values()} - {l_max + 2}:  # stored for another l_max
        try:
            sized = dict(resized_brush_weights(sized, l_max))
        except (TypeError, ValueError) as exc:
            message = f"stored weights are not numbers: {exc}"
            raise ParameterError("brush_weights", message) from None
    return check_brush_weights(sized, l_max)


#: Resolved automatic influences (ε) of recent settings (the cursor asks at every hover).
_influences: dict[str, float] = {}


def influence_of(settings: SculptSettings) -> float:
    """The brush's influence radius in ε for these settings: its own number, or the one an
    automatic influence resolves to (where the field has faded; mesh independent, so found on
    a small sphere and remembered)."""
    brush = settings.brush
    if not brush.auto_influence:
        return float(brush.influence)
    key = json.dumps(
        [brush.kind, brush.substeps, settings.engine_settings.to_dict()],
        sort_keys=True,
        default=float,
    )
    if key not in _influences:
        vertices, faces = icosphere(1)
        if len(_influences) > 64:
            _influences.clear()
        _influences[key] = make_sculptor(vertices, faces, settings).influence(brush)
    return _influences[key]


def pattern_phases(pattern: str, resolution: int, params: Mapping[str, object]) -> np.ndarray:
    """The (n, n, n) 0/1 voxel cell of a pattern of :data:`gogreen_core.PATTERNS`."""
    if pattern not in PATTERNS:
        raise ParameterError("pattern", f"unknown pattern {pattern!r}")
    return make_pattern(pattern, n=int(resolution), **dict(params))


def homogenized_material(
    pattern: str,
    resolution: int,
    params: Mapping[str, object],
    young: float,
    poisson: float,
    contrast: float,
    progress: Callable[[float], None] | None = None,
) -> Material:
    """The effective material of a two-phase pattern: phase a isotropic (``young``,
    ``poisson``), phase b ``contrast`` times stiffer (:func:`gogreen_core.bimaterial`),
    homogenized by :func:`gogreen_core.homogenize` (seconds; ``progress(fraction)`` reports)."""
    phases = pattern_phases(pattern, resolution, params)
    return homogenize(phases, bimaterial(young, poisson, contrast), progress)


def mirror_axes(x: bool, y: bool, z: bool) -> str:
    """The brush symmetry letters of the mesh's X/Y/Z mirror toggles."""
    return "".join(axis for axis, on in zip("xyz", (x, y, z), strict=True) if on)


def make_sculptor(
    vertices: np.ndarray, faces: np.ndarray, settings: SculptSettings, **options: int
) -> Sculptor:
    """A :class:`gogreen_core.Sculptor` on the mesh (object space, float64) with the settings;
    mirror planes through the object's origin. ``options``: the sculptor's (``history_bytes``).
    Its errors (:class:`ParameterError`, a ``ValueError``) name the bad setting."""
    sculptor = Sculptor(vertices, faces, settings=settings.engine_settings, **options)
    # Blender mirrors sculpting about the object's local axes through its origin
    sculptor.origin = np.zeros(3)
    return sculptor


def events_from_json(text: str) -> list[BrushEvent]:
    """Brush events from JSON text: a list of objects with ``center`` and optionally
    ``delta``, ``amount``, ``axis``, ``direction``, ``radius_factor`` (object space), the
    event format of the desktop app's session files (:meth:`BrushEvent.from_dict`).
    ParameterError names the field, e.g. ``events[2].delta``."""
    try:
        items = json.loads(text)
    except (TypeError, ValueError) as exc:
        raise ParameterError("events", f"events are not valid JSON: {exc}") from None
    if not isinstance(items, list):
        raise ParameterError("events", "events must be a JSON list of event objects")
    return [BrushEvent.from_dict(item, f"events[{i}]") for i, item in enumerate(items)]


def stroke(
    vertices: np.ndarray, faces: np.ndarray, settings: SculptSettings, events: list[BrushEvent]
) -> np.ndarray:
    """The vertices (N, 3) float64 after one stroke of ``settings.brush`` with ``events``
    on a fresh sculptor (exactly :meth:`Sculptor.apply_brush`). Raises before anything moves
    on a bad setting or event."""
    if not events:
        raise ParameterError("events", "a stroke needs at least one event")
    sculptor = make_sculptor(vertices, faces, settings)
    sculptor.apply_brush(settings.brush, events)
    return np.array(sculptor.vertices)


def default_settings(l_max: int = 8) -> SculptSettings:
    """The engine's defaults (a grab brush, an isotropic material E 1, ν 0.3, a Gaussian
    falloff) with truncation degree ``l_max``."""
    return SculptSettings(Brush(), EngineSettings(l_max=l_max))


def _with_brush(settings: SculptSettings, brush: Brush) -> SculptSettings:
    return dataclasses.replace(settings, brush=brush)
