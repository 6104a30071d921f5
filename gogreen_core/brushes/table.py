"""The brush table: every brush kind and the :class:`BrushType` that does it.

Adding a brush: a module with its :class:`BrushType` (or a member of an existing family: a
pattern for the affine family) and one row here. The row's position is the brush's number key
in the app (1 = the first row); :data:`BRUSH_KINDS` follows this order.
"""

from __future__ import annotations

import numpy as np

from gogreen_core.brushes.affine import (
    AffineBrush,
    pinch_pattern,
    scale_pattern,
    stretch_pattern,
    twist_pattern,
)
from gogreen_core.brushes.base import BrushType
from gogreen_core.brushes.grab import GrabBrush
from gogreen_core.brushes.mask import MaskBrush
from gogreen_core.brushes.smooth import SmoothBrush
from gogreen_core.brushes.wrinkle import WrinkleBrush
from gogreen_core.radial import MultiscaleRadial

__all__ = [
    "AFFINE_BRUSHES",
    "BRUSH_KINDS",
    "BRUSH_TABLE",
    "GRAB_BRUSHES",
    "PAINT_BRUSHES",
    "affine_load_shape",
    "brush_type",
    "weighted_kinds",
]

BRUSH_TABLE: tuple[BrushType, ...] = (
    GrabBrush("grab"),
    GrabBrush("grab_biscale", MultiscaleRadial.biscale),
    GrabBrush("grab_triscale", MultiscaleRadial.triscale),
    WrinkleBrush("wrinkle"),
    AffineBrush("scale", scale_pattern),
    AffineBrush("twist", twist_pattern),
    AffineBrush("pinch", pinch_pattern),
    AffineBrush("stretch", stretch_pattern),
    SmoothBrush("smooth"),
    MaskBrush("mask"),
)

_BY_KIND = {brush.kind: brush for brush in BRUSH_TABLE}
#: Every brush kind an artist is offered, in the table's order.
BRUSH_KINDS = tuple(brush.kind for brush in BRUSH_TABLE)
#: Vector-load brushes (the cursor point follows the cursor).
GRAB_BRUSHES = tuple(b.kind for b in BRUSH_TABLE if b.family == "vector")
#: Affine-load brushes.
AFFINE_BRUSHES = tuple(b.kind for b in BRUSH_TABLE if b.family == "affine")
#: Brushes acting where the cursor passes, without a Green's function (smooth, mask).
PAINT_BRUSHES = tuple(b.kind for b in BRUSH_TABLE if b.family == "paint")


def weighted_kinds() -> tuple[str, ...]:
    """The offered kinds whose field has per-degree weights ω_l an artist can edit."""
    return tuple(brush.kind for brush in BRUSH_TABLE if brush.weighted)


def brush_type(kind: str) -> BrushType:
    """The table row of ``kind``; ValueError naming the kinds for an unknown one."""
    try:
        return _BY_KIND[kind]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown brush {kind!r}; expected one of {', '.join(BRUSH_KINDS)}"
        ) from None


def affine_load_shape(
    kind: str, axis: np.ndarray | None, direction: np.ndarray | None
) -> np.ndarray:
    """Pattern B (3, 3) of the affine brush ``kind``: the velocity gradient that ``amount`` 1
    asks for at the brush centre (:mod:`gogreen_core.brushes.affine`) for a view ``axis`` and
    stroke ``direction``."""
    brush = _BY_KIND.get(kind)
    if not isinstance(brush, AffineBrush):
        raise ValueError(f"{kind!r} is not an affine brush ({', '.join(AFFINE_BRUSHES)})")
    return brush.shape(axis, direction)
