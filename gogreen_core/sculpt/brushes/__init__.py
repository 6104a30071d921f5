"""Brushes: their settings and events (:mod:`~gogreen_core.sculpt.brushes.brush`), the
interface (:mod:`~gogreen_core.sculpt.brushes.base`) and the table of what each kind does
(:mod:`~gogreen_core.sculpt.brushes.table`), one module per brush or family.

Every brush of Regularized Kelvinlets (de Goes & James 2017), extended to any material by the
regularized Green's function of ``kernel.py``, is a row of the table; so are the paint family's
(smooth, mask and the detail brushes), which act where the cursor passes without one.
"""

from gogreen_core.field.limits import MAX_AMOUNT, MAX_RADIUS, MAX_STRENGTH, MAX_SUBSTEPS, MIN_RADIUS
from gogreen_core.sculpt.brushes.base import (
    AUTO_INFLUENCE,
    CUTOFF_START,
    DEFAULT_INFLUENCE,
    Displacement,
    GreenBrush,
    StrokeContext,
    mirror_signs,
    smooth_cutoff,
)
from gogreen_core.sculpt.brushes.brush import Brush, BrushEvent
from gogreen_core.sculpt.brushes.table import (
    AFFINE_BRUSHES,
    BRUSH_KINDS,
    BRUSH_ROWS,
    BRUSH_TABLE,
    DEFAULT_BRUSH,
    DRAGS,
    GRAB_BRUSHES,
    PAINT_BRUSHES,
    REPLAY_KINDS,
    affine_load_shape,
    brush_for_key,
    brush_row,
    brush_type,
)
from gogreen_core.sculpt.brushes.wrinkle import FOLD_DEGREES, FOLD_DEPTH, fold_weights

__all__ = [
    "AFFINE_BRUSHES",
    "AUTO_INFLUENCE",
    "BRUSH_KINDS",
    "BRUSH_ROWS",
    "BRUSH_TABLE",
    "CUTOFF_START",
    "DEFAULT_BRUSH",
    "DEFAULT_INFLUENCE",
    "DRAGS",
    "FOLD_DEGREES",
    "FOLD_DEPTH",
    "GRAB_BRUSHES",
    "MAX_AMOUNT",
    "MAX_RADIUS",
    "MAX_STRENGTH",
    "MAX_SUBSTEPS",
    "MIN_RADIUS",
    "PAINT_BRUSHES",
    "REPLAY_KINDS",
    "Brush",
    "BrushEvent",
    "Displacement",
    "GreenBrush",
    "StrokeContext",
    "affine_load_shape",
    "brush_for_key",
    "brush_row",
    "brush_type",
    "fold_weights",
    "mirror_signs",
    "smooth_cutoff",
]
