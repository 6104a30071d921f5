"""Side panels of the main window: material, homogenization and falloff editors.

Each panel is a thin Qt view over :mod:`gogreen_core` objects: it builds them with the core's
constructors, shows the core's ValueError messages, and reports changes through signals.
"""

from app.panels._compat import apply_none_refcount_workaround

# PySide6 6.12.0 on CPython 3.11 drops a reference to None on every void Qt call (see
# _compat.py); without this the app aborts after some thousands of paint calls.
apply_none_refcount_workaround()

from app.panels.curve_editor import CurveEditor  # noqa: E402
from app.panels.falloff_panel import FalloffPanel  # noqa: E402
from app.panels.glyph import YoungModulusGlyph  # noqa: E402
from app.panels.homogenization_panel import HomogenizationPanel  # noqa: E402
from app.panels.material_panel import MaterialPanel  # noqa: E402

__all__ = [
    "CurveEditor",
    "FalloffPanel",
    "HomogenizationPanel",
    "MaterialPanel",
    "YoungModulusGlyph",
]
