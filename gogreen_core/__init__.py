"""GoGreen Sculpt numerics and sculpting engine (no GUI imports).

Regularized Green's functions of any linear elastic material by the spherical-harmonic expansion
of Chen & Desbrun, "Go Green: General Regularized Green's Functions for Elasticity" (2022), the
bimaterial homogenization that turns a voxel pattern into an anisotropic material, and the
sculpting engine built on them.
"""

from gogreen_core.brushes import BRUSH_KINDS, Brush, BrushEvent
from gogreen_core.constraints import ConstraintSet
from gogreen_core.engine_settings import EngineSettings
from gogreen_core.history import History
from gogreen_core.homogenization import (
    HomogenizationResult,
    bimaterial,
    check_phases,
    homogenize,
    homogenize_detailed,
    reuss_bound,
    voigt_bound,
)
from gogreen_core.kernel import GreenKernel, lebedev_points
from gogreen_core.material import Material
from gogreen_core.patterns import PATTERNS, PatternParameter, PatternSpec, make_pattern
from gogreen_core.presets import Preset, builtin_presets, load_preset, save_preset
from gogreen_core.radial import (
    GaussianRadial,
    KelvinletRadial,
    MultiscaleRadial,
    RadialProfile,
    SplineRadial,
    radial_from_dict,
)
from gogreen_core.sculptor import Sculptor
from gogreen_core.session import load_session
from gogreen_core.symmetry import SYMMETRY_CLASSES, SymmetryDescription, describe_symmetry
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
    "lebedev_points",
    "load_preset",
    "load_session",
    "make_pattern",
    "radial_from_dict",
    "reuss_bound",
    "save_preset",
    "voigt_bound",
]
