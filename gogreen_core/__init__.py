"""GoGreen Sculpt numerics and sculpting engine (no GUI imports).

Regularized Green's functions of any linear elastic material by the spherical-harmonic expansion
of Chen & Desbrun, "Go Green: General Regularized Green's Functions for Elasticity" (2022), the
bimaterial homogenization that turns a voxel pattern into an anisotropic material, and the
sculpting engine built on them.
"""

from gogreen_core.field import kernel
from gogreen_core.field.kernel import GreenKernel, lebedev_points
from gogreen_core.files import presets
from gogreen_core.files.presets import Preset, builtin_presets, load_preset, save_preset
from gogreen_core.interaction import settings, tools
from gogreen_core.mesh import mesh_io, shapes
from gogreen_core.physics.homogenization import (
    HomogenizationResult,
    bimaterial,
    check_phases,
    homogenize,
    homogenize_detailed,
    reuss_bound,
    voigt_bound,
)
from gogreen_core.physics.material import Material
from gogreen_core.physics.patterns import PATTERNS, PatternParameter, PatternSpec, make_pattern
from gogreen_core.physics.radial import (
    GaussianRadial,
    KelvinletRadial,
    MultiscaleRadial,
    RadialProfile,
    SplineRadial,
    radial_from_dict,
)
from gogreen_core.physics.symmetry import SYMMETRY_CLASSES, SymmetryDescription, describe_symmetry
from gogreen_core.sculpt import session
from gogreen_core.sculpt.brushes import BRUSH_KINDS, Brush, BrushEvent
from gogreen_core.sculpt.constraints import ConstraintSet
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.history import History
from gogreen_core.sculpt.sculptor import Sculptor
from gogreen_core.sculpt.session import load_session
from gogreen_core.validation import ParameterError

__all__ = [
    "BRUSH_KINDS",
    "PATTERNS",
    "SYMMETRY_CLASSES",
    "Brush",
    "BrushEvent",
    "ConstraintSet",
    "EngineSettings",
    "GaussianRadial",
    "GreenKernel",
    "History",
    "HomogenizationResult",
    "KelvinletRadial",
    "Material",
    "MultiscaleRadial",
    "ParameterError",
    "PatternParameter",
    "PatternSpec",
    "Preset",
    "RadialProfile",
    "Sculptor",
    "SplineRadial",
    "SymmetryDescription",
    "bimaterial",
    "builtin_presets",
    "check_phases",
    "describe_symmetry",
    "homogenize",
    "homogenize_detailed",
    "kernel",
    "lebedev_points",
    "load_preset",
    "load_session",
    "make_pattern",
    "mesh_io",
    "presets",
    "radial_from_dict",
    "reuss_bound",
    "save_preset",
    "session",
    "settings",
    "shapes",
    "tools",
    "voigt_bound",
]
