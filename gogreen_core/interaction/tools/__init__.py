"""Interaction tools without a GUI: stroke, pin and brush-cursor controllers.

The viewport translates its toolkit's mouse or pen events into :class:`PointerEvent` (a screen
position, the world point under it, the surface normal, the camera axes, pressure and modifier
names) and feeds them to :class:`SculptTools`; the tools turn them into engine calls on a
:class:`gogreen_core.Sculptor` and report what changed in a :class:`ToolUpdate`, which the view
draws. Everything here runs, and is tested, without a window (napari's mouse-callback model).

Moves are coalesced: :meth:`SculptTools.move` only records the newest event and
:meth:`SculptTools.flush` applies the newest one, so however many mouse events arrive while a
brush step or a render runs, the next step starts from the latest cursor position and no
backlog builds. :meth:`SculptTools.release` always applies the last recorded position before it
ends the stroke. The counters :attr:`SculptTools.received` and :attr:`SculptTools.processed`
(per drag) make that measurable.
"""

from gogreen_core.interaction.tools.cursor import (
    MOVING_FRACTION,
    PIXELS_PER_STRENGTH,
    PROFILE_SAMPLES,
    CursorController,
    ValueDrag,
    brush_profile,
    felt_profile,
    grab_motion,
    moving_radius,
)
from gogreen_core.interaction.tools.events import CursorState, PointerEvent, ToolUpdate
from gogreen_core.interaction.tools.gauge import DeformationGauge
from gogreen_core.interaction.tools.pins import PIN_PICK_FRACTION, PinController
from gogreen_core.interaction.tools.sculpt import NUMBER_KEYS, SculptTools, brush_for_key
from gogreen_core.interaction.tools.stroke import (
    MIN_PRESSURE_RADIUS,
    PIXELS_PER_UNIT_AMOUNT,
    StrokeController,
    brush_drag,
    pressure_radius_factor,
)
from gogreen_core.sculpt.constraints import smooth_cutoff

__all__ = [
    "MIN_PRESSURE_RADIUS",
    "MOVING_FRACTION",
    "NUMBER_KEYS",
    "PIN_PICK_FRACTION",
    "PIXELS_PER_STRENGTH",
    "PIXELS_PER_UNIT_AMOUNT",
    "PROFILE_SAMPLES",
    "CursorController",
    "CursorState",
    "DeformationGauge",
    "PinController",
    "PointerEvent",
    "SculptTools",
    "StrokeController",
    "ToolUpdate",
    "ValueDrag",
    "brush_drag",
    "brush_for_key",
    "brush_profile",
    "felt_profile",
    "grab_motion",
    "moving_radius",
    "pressure_radius_factor",
    "smooth_cutoff",
]
