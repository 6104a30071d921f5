"""Interaction tools without a GUI: stroke, pin and brush-cursor controllers.

The viewport turns its toolkit's mouse or pen events into :class:`PointerEvent` s and feeds them
to :class:`SculptTools`, which turns them into engine calls and reports what changed in a
:class:`ToolUpdate` for the view to draw; all without a window (napari's mouse callbacks). Moves
are coalesced: :meth:`SculptTools.move` records the newest, :meth:`SculptTools.flush` applies
it, so no backlog builds while a brush step or a render runs.
"""

from gogreen_core.interaction.tools.cursor import (
    MOVING_FRACTION,
    CursorController,
    brush_profile,
    felt_profile,
    grab_motion,
)
from gogreen_core.interaction.tools.events import CursorState, PointerEvent, ToolUpdate
from gogreen_core.interaction.tools.sculpt import NUMBER_KEYS, SculptTools, brush_for_key
from gogreen_core.interaction.tools.stroke import PIXELS_PER_UNIT_AMOUNT, StrokeController

__all__ = [
    "MOVING_FRACTION",
    "NUMBER_KEYS",
    "PIXELS_PER_UNIT_AMOUNT",
    "CursorController",
    "CursorState",
    "PointerEvent",
    "SculptTools",
    "StrokeController",
    "ToolUpdate",
    "brush_for_key",
    "brush_profile",
    "felt_profile",
    "grab_motion",
]
