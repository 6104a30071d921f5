"""The add-on's settings, stored on the scene (``scene.gogreen``) so they save with the file.

Brush kinds come from :data:`gogreen_core.BRUSH_KINDS` (but the mask brush:
:data:`engine.ADDON_BRUSH_KINDS`) and the homogenization patterns and their parameters from
:data:`gogreen_core.PATTERNS` when the add-on registers, so a kind or a
pattern added to the engine appears here by itself. Materials that Blender's single-precision
float properties would round (a preset's, a homogenized one) are kept as JSON text.
"""

from __future__ import annotations

import math

import bpy
from bpy.props import (
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

from gogreen_core import PATTERNS, Brush, Material, ParameterError
from gogreen_core.sculpt.brushes import AUTO_INFLUENCE

from . import engine

__all__ = ["GoGreenSettings", "pattern_prop", "read_settings", "register", "unregister"]

#: The engine's default brush, whose values the panel starts from.
_DEFAULT_BRUSH = Brush()
#: An influence at least this large means every vertex (math.inf in the engine).
INFINITE_INFLUENCE = 1e30
#: How the brush radius is measured: identifier, label, description.
RADIUS_UNITS = (
    ("MODEL", "Model", "A fraction of the mesh's bounding-box diagonal (as in the desktop app)"),
    ("VIEW", "View", "Pixels on screen (Blender's brushes' default)"),
)
#: Resolution of the homogenization cell (voxels per side).
DEFAULT_RESOLUTION = 16


def pattern_prop(pattern: str, parameter: str) -> str:
    """Name of the scene property of a pattern's parameter: ``layered__fraction``."""
    return f"{pattern}__{parameter}"


def _changed_l_max(settings, context) -> None:
    from . import compile_status  # the warm-up reacts to a new truncation degree

    compile_status.request_warm_up(context.scene)


def _pattern_annotations() -> dict:
    """One property per parameter of each pattern of :data:`gogreen_core.PATTERNS`."""
    props = {}
    for spec in PATTERNS.values():
        for p in spec.parameters:
            name = pattern_prop(spec.name, p.name)
            if p.kind == "choice":
                items = [(str(c), str(c), "") for c in p.choices]
                props[name] = EnumProperty(
                    name=p.name.title(), description=p.description, items=items, default=p.default
                )
            elif p.kind == "int":
                props[name] = IntProperty(
                    name=p.name.title(),
                    description=p.description,
                    default=int(p.default),
                    min=int(p.low),
                    max=int(p.high),
                )
            else:
                props[name] = FloatProperty(
                    name=p.name.title(),
                    description=p.description,
                    default=float(p.default),
                    min=float(p.low),
                    max=float(p.high),
                )
    return props


def _settings_class() -> type:
    """The scene settings PropertyGroup, built from the engine's brush kinds and patterns."""
    annotations = {
        # -- brush ---------------------------------------------------------------------
        "brush": EnumProperty(
            name="Brush",
            description="Brush of the GoGreen Sculpt tool",
            items=[(k, engine.brush_label(k), f"The {k} brush") for k in engine.ADDON_BRUSH_KINDS],
            default=_DEFAULT_BRUSH.kind,
        ),
        # The core checks the ranges and names the problem; the UI limits only guide.
        "radius": FloatProperty(
            name="Radius",
            description="Brush radius ε as a fraction of the mesh's bounding-box diagonal",
            default=0.08,
            min=0.0,
            soft_min=0.005,
            soft_max=0.5,
            precision=3,
            step=0.5,
        ),
        # -- the radius on screen (Blender artists size brushes in pixels) ------------------
        "radius_unit": EnumProperty(
            name="Radius Unit",
            description="How the brush radius is measured",
            items=RADIUS_UNITS,
            default="MODEL",
        ),
        "radius_pixels": IntProperty(
            name="Radius",
            description="Brush radius ε in pixels on screen, at the point where a stroke starts",
            default=50,
            min=1,
            soft_max=500,
            subtype="PIXEL",
        ),
        "strength": FloatProperty(
            name="Strength",
            description="Multiplies the cursor motion (grab) or the amount (scale, twist, pinch)",
            default=_DEFAULT_BRUSH.strength,
            soft_min=0.0,
            soft_max=2.0,
        ),
        "influence": FloatProperty(
            name="Influence",
            description=(
                "Radius of the moved region in multiples of ε; 0: automatic, where the brush's "
                "field has faded (the desktop app's default); inf: every vertex"
            ),
            default=0.0,
            min=0.0,
            soft_max=32.0,
        ),
        "substeps": IntProperty(
            name="Substeps",
            description="RK4 steps per mouse event (0: adaptive, within 1e-4 of the motion)",
            default=_DEFAULT_BRUSH.substeps,
            min=0,
            soft_max=64,
        ),
        # -- material ------------------------------------------------------------------
        "material_mode": EnumProperty(
            name="Material", items=engine.MATERIAL_MODES, default="ISOTROPIC"
        ),
        "young": FloatProperty(name="Young's modulus", default=1.0, soft_min=0.01, soft_max=100.0),
        "poisson": FloatProperty(name="Poisson ratio", default=0.3, soft_min=-0.99, soft_max=0.49),
        "ortho_young": FloatVectorProperty(
            name="Young's moduli", description="E1, E2, E3", size=3, default=(1.0, 1.0, 10.0)
        ),
        "ortho_shear": FloatVectorProperty(
            name="Shear moduli", description="G23, G13, G12", size=3, default=(0.5, 0.5, 0.4)
        ),
        "ortho_poisson": FloatVectorProperty(
            name="Poisson ratios", description="ν12, ν13, ν23", size=3, default=(0.3, 0.1, 0.1)
        ),
        "rotation": FloatVectorProperty(
            name="Material axes",
            description="Rotation of the material's axes (XYZ Euler, about the object's axes)",
            subtype="EULER",
            unit="ROTATION",
            size=3,
        ),
        "material_frame": EnumProperty(
            name="Material frame",
            description="Where the material's axes are",
            items=[
                (
                    "WORLD",
                    "World",
                    "The material's axes fixed to the object (turned by Material axes)",
                ),
                (
                    "SURFACE",
                    "Surface",
                    "Each stroke turns the material's axes onto the surface where it starts: "
                    "third axis along the normal, first along the stroke",
                ),
            ],
            default="WORLD",
        ),
        "custom_material": StringProperty(
            name="Stiffness", description="6x6 Voigt stiffness as JSON (set by presets)"
        ),
        "custom_name": StringProperty(name="Preset", description="Name of the loaded preset"),
        # -- homogenization ------------------------------------------------------------
        "pattern": EnumProperty(
            name="Pattern",
            items=[(name, name.title(), spec.description) for name, spec in PATTERNS.items()],
        ),
        "phase_young": FloatProperty(name="E of phase a", default=1.0, min=1e-6),
        "phase_poisson": FloatProperty(name="ν of phase a", default=0.3, min=-0.99, max=0.49),
        "contrast": FloatProperty(
            name="Contrast",
            description="Stiffness of phase b over phase a (1 to 10000)",
            default=100.0,
            min=1.0,
            max=1e4,
        ),
        "resolution": IntProperty(
            name="Resolution",
            description="Voxels per side of the periodic cell",
            default=DEFAULT_RESOLUTION,
            min=4,
            max=48,
        ),
        "homogenized_material": StringProperty(
            name="Homogenized stiffness", description="Result of the last homogenization (JSON)"
        ),
        "homogenized_inputs": StringProperty(
            name="Homogenized inputs", description="The inputs of that result"
        ),
        # -- falloff -------------------------------------------------------------------
        "falloff": EnumProperty(name="Falloff", items=engine.FALLOFF_KINDS, default="GAUSSIAN"),
        "custom_falloff": StringProperty(name="Falloff curves", description="JSON (presets)"),
        "l_max": IntProperty(
            name="l max",
            description="Truncation degree of the spherical-harmonic expansion (higher: finer "
            "anisotropic detail, slower)",
            default=8,
            min=0,
            max=60,
            soft_max=16,
            update=_changed_l_max,
        ),
        "brush_weights": StringProperty(
            name="Degree weights",
            description="Each brush kind's per-degree weights ω_0 … ω_(l_max+1) (JSON object; "
            "a kind not listed has its defaults)",
        ),
    }
    annotations.update(_pattern_annotations())
    return type("GoGreenSettings", (bpy.types.PropertyGroup,), {"__annotations__": annotations})


GoGreenSettings = _settings_class()


def pattern_params(settings) -> dict:
    """The current pattern's parameters from the scene."""
    spec = PATTERNS[settings.pattern]
    return {p.name: getattr(settings, pattern_prop(spec.name, p.name)) for p in spec.parameters}


def homogenization_inputs(settings) -> str:
    """A key of everything the homogenized material depends on (to tell a stale result)."""
    params = sorted(pattern_params(settings).items())
    values = (
        settings.pattern,
        settings.resolution,
        params,
        round(settings.phase_young, 9),
        round(settings.phase_poisson, 9),
        round(settings.contrast, 9),
    )
    return repr(values)


def read_material(settings):
    """The material the scene's settings describe (rotation applied)."""
    mode = settings.material_mode
    if mode == "ISOTROPIC":
        try:
            material = Material.isotropic(settings.young, settings.poisson)
        except ParameterError:
            raise
        except ValueError as exc:
            raise ParameterError("material", f"isotropic material: {exc}") from None
    elif mode == "ORTHOTROPIC":
        material = engine.orthotropic_material(
            tuple(settings.ortho_young), tuple(settings.ortho_shear), tuple(settings.ortho_poisson)
        )
    elif mode == "HOMOGENIZED":
        if not settings.homogenized_material:
            raise ParameterError(
                "material", "the pattern has not been homogenized yet: press Compute"
            )
        if settings.homogenized_inputs != homogenization_inputs(settings):
            raise ParameterError(
                "material",
                "the pattern changed since it was homogenized: press Compute again",
            )
        material = engine.material_from_json(settings.homogenized_material, "homogenized material")
    else:
        material = engine.material_from_json(settings.custom_material, "preset material")
    return engine.rotated_material(material, tuple(settings.rotation))


def read_settings(scene, obj=None, kind: str | None = None) -> engine.SculptSettings:
    """The scene's settings as plain values; the brush's symmetry from ``obj``'s mesh mirror
    toggles (Blender's sculpt symmetry). ParameterError names a bad value."""
    s = scene.gogreen
    symmetry = ""
    if obj is not None and obj.type == "MESH":
        mesh = obj.data
        symmetry = engine.mirror_axes(mesh.use_mirror_x, mesh.use_mirror_y, mesh.use_mirror_z)
    # Blender stores an automatic influence as 0, an infinite one (every vertex) as the
    # largest single float
    influence: float | str = s.influence
    if s.influence <= 0.0:
        influence = AUTO_INFLUENCE
    elif s.influence >= INFINITE_INFLUENCE:
        influence = math.inf
    try:
        brush = Brush(
            kind or s.brush,
            radius=s.radius,
            strength=s.strength,
            substeps=s.substeps,
            influence=influence,
            symmetry=symmetry,
        )
    except ParameterError as exc:
        raise ParameterError(f"brush.{exc.parameter}", f"brush {exc}") from None
    l_max = int(s.l_max)
    return engine.SculptSettings(
        brush=brush,
        material=read_material(s),
        falloff=engine.falloff_from(s.falloff, s.custom_falloff),
        l_max=l_max,
        brush_weights=engine.brush_weights_from(s.brush_weights, l_max),
        material_frame=s.material_frame.lower(),
    )


def eps_at(scene, view, point, link) -> float:
    """The brush radius ε (object units) for a stroke at ``point`` (3,) in ``view``: the
    scene's fraction of the model's size, or its pixels at that point's depth."""
    s = scene.gogreen
    if s.radius_unit == "VIEW":
        return s.radius_pixels * view.units_per_pixel(point)
    return s.radius * link.model_size


def view_radius(scene, view, point, link) -> float:
    """The brush radius as the fraction of the model's size (what the engine takes) that the
    scene's radius gives at ``point`` (3,) in ``view``; ParameterError when it is none (the
    point behind the view)."""
    radius = eps_at(scene, view, point, link) / link.model_size
    if not radius > 0.0:
        raise ParameterError("radius", "the brush radius in pixels has no size at this point")
    return radius


def register() -> None:
    bpy.utils.register_class(GoGreenSettings)
    bpy.types.Scene.gogreen = PointerProperty(type=GoGreenSettings)


def unregister() -> None:
    del bpy.types.Scene.gogreen
    bpy.utils.unregister_class(GoGreenSettings)
