"""Brushes: their settings, their events, and a table of what each kind does.

Every brush of Regularized Kelvinlets (de Goes & James 2017), extended to any material by the
regularized Green's function of ``kernel.py``, is a row of the brush table
(:mod:`gogreen_core.sculpt.brushes.table`), one module per family:

* :mod:`~gogreen_core.sculpt.brushes.grab`: ``grab``, ``grab_biscale``, ``grab_triscale``, a vector
  load the grabbed point follows exactly (multi-scale falloffs decay faster);
* :mod:`~gogreen_core.sculpt.brushes.wrinkle`: ``wrinkle``, a pull that folds the surface around the
  cursor with the material's high SH degrees (paper Fig. 10);
* :mod:`~gogreen_core.sculpt.brushes.affine`: ``scale``, ``twist``, ``pinch``, ``stretch``, an
  affine load at the press point whose ``amount`` is a log strain or an angle at the centre,
  whatever the material;
* the paint family (:mod:`~gogreen_core.sculpt.brushes.paint`), acting where the cursor passes
  without a Green's function: ``smooth`` (:mod:`~gogreen_core.sculpt.brushes.smooth`, Taubin
  relaxation), ``mask`` (:mod:`~gogreen_core.sculpt.brushes.mask`, paints the vertex mask that
  holds vertices) and the detail brushes, Blender's, in dabs along the stroke
  (:mod:`~gogreen_core.sculpt.brushes.dabs`): ``draw``, ``clay_strips``, ``crease``,
  ``flatten``, ``inflate`` (one module each).

The interface (:mod:`~gogreen_core.sculpt.brushes.base`): a :class:`BrushType` turns one event into
the rows it moves and their new positions; the stroke driver (:mod:`gogreen_core.sculpt.stroke`)
writes them. :class:`Brush` and :class:`BrushEvent` (:mod:`~gogreen_core.sculpt.brushes.brush`) are
the immutable settings and events that strokes, sessions and presets carry.

Adding a brush: one module (a :class:`BrushType`, usually a :class:`GreenBrush`) and one row in
:data:`BRUSH_TABLE`.
"""

from gogreen_core.field.limits import MAX_AMOUNT, MAX_RADIUS, MAX_STRENGTH, MAX_SUBSTEPS, MIN_RADIUS
from gogreen_core.sculpt.brushes.base import (
    AUTO_INFLUENCE,
    CUTOFF_START,
    DEFAULT_INFLUENCE,
    BrushType,
    Displacement,
    EventField,
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
    BrushRow,
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
    "BrushRow",
    "BrushType",
    "Displacement",
    "EventField",
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
