"""The brush table: every brush, declared once, with the :class:`BrushType` that does it and
everything the app shows of it (the app's keymap, brush bar and panels derive from
:data:`BRUSH_ROWS`). Adding a brush: a module with its :class:`BrushType` (or a pattern of the
affine family), one row here and an icon in ``resources/icons``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gogreen_core.physics.radial import MultiscaleRadial
from gogreen_core.sculpt.brushes.affine import (
    AffineBrush,
    local_affine,
    pinch_pattern,
    scale_pattern,
    stretch_pattern,
    twist_pattern,
)
from gogreen_core.sculpt.brushes.base import BrushType
from gogreen_core.sculpt.brushes.clay_strips import ClayStripsBrush
from gogreen_core.sculpt.brushes.crease import CreaseBrush
from gogreen_core.sculpt.brushes.draw import DrawBrush
from gogreen_core.sculpt.brushes.flatten import FlattenBrush
from gogreen_core.sculpt.brushes.grab import GrabBrush
from gogreen_core.sculpt.brushes.inflate import InflateBrush
from gogreen_core.sculpt.brushes.mask import MaskBrush
from gogreen_core.sculpt.brushes.smooth import SmoothBrush
from gogreen_core.sculpt.brushes.wrinkle import WrinkleBrush

__all__ = [
    "AFFINE_BRUSHES",
    "BRUSH_KINDS",
    "BRUSH_ROWS",
    "BRUSH_TABLE",
    "DEFAULT_BRUSH",
    "DRAGS",
    "GRAB_BRUSHES",
    "PAINT_BRUSHES",
    "REPLAY_KINDS",
    "BrushRow",
    "affine_load_shape",
    "brush_for_key",
    "brush_row",
    "brush_type",
    "weighted_kinds",
]

#: How a drag becomes a brush's events (:class:`gogreen_core.interaction.tools.StrokeController`):
#: ``"follow"``: the point under the cursor follows the cursor (each event the world motion on
#: the drag plane); ``"anchored"``: the brush stays at the press point and takes its amount from
#: the signed screen length of the drag, its direction from the drag's; ``"sweep"``: the brush
#: acts where the cursor passes (a dab at the press point, then each swept segment).
DRAGS = ("follow", "anchored", "sweep")

_ODD_HINT = (
    "ℛ_l of ∇G (odd degrees): 1 is the expansion as it is, 0 removes a degree, "
    "16 × ℛ₁ makes a pinch local (paper Fig. 7)"
)
_EVEN_HINT = "R_l of G (even degrees): 1 is the expansion as it is, 0 removes a degree"


@dataclass(frozen=True)
class BrushRow:
    """One brush, declared once.

    type : the :class:`BrushType` that does it (its ``kind`` names the brush everywhere).
    label : toolbar text ("Grab").
    title : one line for the keymap and the panels ("Wide grab (elastic, whole body)").
    letter : its letter key in Qt's portable text ("G", "Shift+S").
    number : its number key ("1" … "9", "0"), fixed per brush; "" for none.
    tooltip : what it does, for the toolbar button.
    drag : how a drag becomes its events, one of :data:`DRAGS`.
    weights_hint : the caption of its degree weights (what they are, what to try); "" for a
        brush without weights.
    acting : what an anchored brush does, for its cursor's label while it acts ("scaling").
    depth : an anchored brush's load centre lies this many ε below the press point, into the
        body (the scale brush then bulges the surface instead of spreading it along itself).
    """

    type: BrushType
    label: str
    title: str
    letter: str
    number: str
    tooltip: str
    drag: str
    weights_hint: str = ""
    acting: str = ""
    depth: float = 0.0

    @property
    def kind(self) -> str:
        return self.type.kind

    @property
    def icon(self) -> str:
        """Name of its icon in ``resources/icons`` (without ``.svg``): its kind."""
        return self.type.kind


BRUSH_ROWS: tuple[BrushRow, ...] = (
    BrushRow(
        GrabBrush("grab_local", MultiscaleRadial.local),
        "Grab",
        "Grab brush: moves what is inside its ring",
        "G",
        "1",
        "Grab: the point under the cursor follows it, the ring shows what moves (elastic, "
        "local; tri-scale at 0.4, 0.8 and 1.6 ε)",
        "follow",
        _EVEN_HINT,
    ),
    BrushRow(
        GrabBrush("grab"),
        "Wide grab",
        "Wide grab (elastic, whole body)",
        "Shift+G",
        "2",
        "Wide grab (elastic, whole body): the regularized Kelvinlet grab; the whole body "
        "follows softly",
        "follow",
        _EVEN_HINT,
    ),
    BrushRow(
        GrabBrush("grab_biscale", MultiscaleRadial.biscale),
        "Bi-scale",
        "Bi-scale grab brush (sharper falloff)",
        "B",
        "",
        "Bi-scale grab: sharper falloff (two radii)",
        "follow",
        _EVEN_HINT,
    ),
    BrushRow(
        GrabBrush("grab_triscale", MultiscaleRadial.triscale),
        "Tri-scale",
        "Tri-scale grab brush (sharpest falloff)",
        "T",
        "3",
        "Tri-scale grab: sharpest falloff (three radii)",
        "follow",
        _EVEN_HINT,
    ),
    BrushRow(
        WrinkleBrush("wrinkle"),
        "Wrinkle",
        "Wrinkle brush: a pull that folds the surface (needs an anisotropic material)",
        "R",
        "4",
        "Wrinkle: a pull that folds the surface around the cursor (folds: Falloff panel)",
        "follow",
        "R_l of G (even degrees): R0 and R2 are the pull, the degrees from 4 up are the folds "
        "(set them with the fold degree and depth below)",
    ),
    BrushRow(
        AffineBrush("scale", scale_pattern, local_affine),
        "Scale",
        "Scale brush: inflate / deflate",
        "S",
        "5",
        "Scale: inflate (drag right or up) or deflate (left or down)",
        "anchored",
        "ℛ_l of ∇G (odd degrees): 1 is the expansion as it is, 0 removes a degree",
        acting="scaling",
        depth=0.5,
    ),
    BrushRow(
        AffineBrush("twist", twist_pattern, local_affine),
        "Twist",
        "Twist brush",
        "W",
        "6",
        "Twist about the view axis: drag right or up, left or down",
        "anchored",
        "ℛ_l of ∇G (odd degrees): 1 is the expansion as it is, 0 removes a degree",
        acting="twisting",
    ),
    BrushRow(
        AffineBrush("pinch", pinch_pattern, local_affine),
        "Pinch",
        "Pinch brush",
        "P",
        "7",
        "Pinch: stretch along the drag (right or up), squeeze (left or down)",
        "anchored",
        _ODD_HINT,
        acting="pinching",
    ),
    BrushRow(
        AffineBrush("stretch", stretch_pattern, local_affine),
        "Stretch",
        "Stretch brush: pull along the drag; the material moves the sides (Poisson)",
        "E",
        "8",
        "Stretch along the drag: the material decides whether the sides narrow or widen",
        "anchored",
        _ODD_HINT,
        acting="stretching",
    ),
    BrushRow(
        SmoothBrush("smooth"),
        "Smooth",
        "Smooth brush",
        "Shift+S",
        "9",
        "Smooth: relaxes bumps and facets without shrinking (Shift+drag with any brush)",
        "sweep",
    ),
    BrushRow(
        MaskBrush("mask"),
        "Mask",
        "Mask brush (Ctrl erases)",
        "M",
        "0",
        "Mask: paint what no brush moves; Ctrl+drag erases, Ctrl+I inverts",
        "sweep",
    ),
    # the detail brushes: Blender's keys, but Clay Strips' C is our pin mode (L: Blender's
    # Layer, the nearest brush it has that we do not)
    BrushRow(
        DrawBrush("draw"),
        "Draw",
        "Draw brush: raise the surface where you stroke (Ctrl carves)",
        "X",
        "",
        "Draw: raises the surface along its mean normal where you stroke; Ctrl+drag carves",
        "sweep",
    ),
    BrushRow(
        ClayStripsBrush("clay_strips"),
        "Clay Strips",
        "Clay strips brush: lay flat strips of clay (Ctrl digs)",
        "L",
        "",
        "Clay Strips: lays flat-topped square strips of clay along the stroke that build up "
        "as they cross; Ctrl+drag digs",
        "sweep",
    ),
    BrushRow(
        CreaseBrush("crease"),
        "Crease",
        "Crease brush: cut a sharp crease (Ctrl: a sharp ridge)",
        "Shift+C",
        "",
        "Crease: cuts a sharp groove, pinching the surface towards the stroke; Ctrl+drag "
        "raises a sharp ridge",
        "sweep",
    ),
    BrushRow(
        FlattenBrush("flatten"),
        "Flatten",
        "Flatten brush: level towards the mean plane (Ctrl: contrast)",
        "Shift+T",
        "",
        "Flatten: levels bumps and dents towards the mean plane under the brush; Ctrl+drag "
        "pushes away from it",
        "sweep",
    ),
    BrushRow(
        InflateBrush("inflate"),
        "Inflate",
        "Inflate brush: swell along the normals (Ctrl deflates)",
        "I",
        "",
        "Inflate: swells the surface, each point along its own normal; Ctrl+drag deflates",
        "sweep",
    ),
)
#: The brush of key 1, what a new session starts with.
DEFAULT_BRUSH = "grab_local"
BRUSH_TABLE: tuple[BrushType, ...] = tuple(row.type for row in BRUSH_ROWS)
#: Not offered, no row: the affine brushes with the settings' falloff itself, which strokes of
#: sessions before version 6 are renamed to (:func:`~gogreen_core.sculpt.session.upgrade_session`).
_REPLAY_BRUSHES = {
    row.kind: row.type.wide() for row in BRUSH_ROWS if isinstance(row.type, AffineBrush)
}
#: The kind each replay-only brush has, by the offered kind it replays.
REPLAY_KINDS = {kind: brush.kind for kind, brush in _REPLAY_BRUSHES.items()}

_BY_KIND = {brush.kind: brush for brush in (*BRUSH_TABLE, *_REPLAY_BRUSHES.values())}
_ROWS = {row.kind: row for row in BRUSH_ROWS}
_ROWS.update({wide: _ROWS[kind] for kind, wide in REPLAY_KINDS.items()})
_BY_NUMBER = {row.number: row.kind for row in BRUSH_ROWS if row.number}
#: Every brush kind an artist is offered, in the table's order.
BRUSH_KINDS = tuple(brush.kind for brush in BRUSH_TABLE)
#: Vector-load brushes (the cursor point follows the cursor).
GRAB_BRUSHES = tuple(b.kind for b in BRUSH_TABLE if b.family == "vector")
#: Affine-load brushes.
AFFINE_BRUSHES = tuple(b.kind for b in BRUSH_TABLE if b.family == "affine")
#: Brushes acting where the cursor passes, without a Green's function (smooth, mask and the
#: detail brushes).
PAINT_BRUSHES = tuple(b.kind for b in BRUSH_TABLE if b.family == "paint")


def _known(kind: object) -> str:
    if not isinstance(kind, str) or kind not in _BY_KIND:
        raise ValueError(f"unknown brush {kind!r}; expected one of {', '.join(BRUSH_KINDS)}")
    return kind


def brush_row(kind: str) -> BrushRow:
    """The row of brush ``kind`` (a replay-only kind: its offered brush's); ValueError naming
    the kinds for another one."""
    return _ROWS[_known(kind)]


def brush_for_key(key: str) -> str | None:
    """The brush number key ``key`` picks (its row's fixed ``number``), else None."""
    return _BY_NUMBER.get(key) if isinstance(key, str) else None


def weighted_kinds() -> tuple[str, ...]:
    """The offered kinds whose field has per-degree weights ω_l an artist can edit."""
    return tuple(brush.kind for brush in BRUSH_TABLE if brush.weighted)


def brush_type(kind: str) -> BrushType:
    """The table row of ``kind``; ValueError naming the kinds for an unknown one."""
    return _BY_KIND[_known(kind)]


def affine_load_shape(
    kind: str, axis: np.ndarray | None, direction: np.ndarray | None
) -> np.ndarray:
    """Pattern B (3, 3) of the affine brush ``kind`` for a view ``axis`` and stroke
    ``direction`` (:mod:`gogreen_core.sculpt.brushes.affine`)."""
    brush = _BY_KIND.get(kind)
    if not isinstance(brush, AffineBrush):
        raise ValueError(f"{kind!r} is not an affine brush ({', '.join(AFFINE_BRUSHES)})")
    return brush.shape(axis, direction)
