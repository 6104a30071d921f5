"""Side panels of the main window: material, homogenization and falloff editors.

Each panel is a thin Qt view over :mod:`gogreen_core` objects: it builds them with the core's
constructors, shows the core's ValueError messages, and reports changes through signals.
"""

from app.panels.curve_editor import CurveEditor
from app.panels.falloff_panel import FalloffPanel
from app.panels.glyph import YoungModulusGlyph
from app.panels.homogenization_panel import HomogenizationPanel
from app.panels.material_panel import MaterialPanel

__all__ = [
    "CurveEditor",
    "FalloffPanel",
    "HomogenizationPanel",
    "MaterialPanel",
    "YoungModulusGlyph",
]
