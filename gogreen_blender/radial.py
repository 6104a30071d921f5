"""F / Shift+F: the brush radius or strength dragged on screen, as in Blender's sculpt mode
(``wm.radial_control``), as plain Python (no bpy): driven by Blender's events in the add-on
and by synthetic ones in the tests.

A circle about a centre left of the mouse, whose radius shows the value: the mouse starts on
its rim, moving it sets the value from its distance to the centre; a click or Enter keeps the
value, Esc or a right click puts the first one back.
"""

from __future__ import annotations

import math

from .modal import CANCELLED, FINISHED, RUNNING, InputEvent

__all__ = ["CONFIRM_EVENTS", "RadialControl"]

#: Event types that keep the value (on press).
CONFIRM_EVENTS = frozenset({"LEFTMOUSE", "RET", "NUMPAD_ENTER"})
#: Event types that put the first value back (on press).
CANCEL_EVENTS = frozenset({"ESC", "RIGHTMOUSE"})
#: Pixels of the circle of a strength of 1 (Blender's radial control shows a factor so).
STRENGTH_PIXELS = 200.0


class RadialControl:
    """One F / Shift+F drag of a value.

    value : the value at the start; low, high : the range it is kept in; pixels_per_unit :
    the circle's radius in region pixels per unit of the value (> 0); x, y : the mouse (region
    pixels) at the start, on the circle's rim.
    """

    def __init__(
        self, value: float, low: float, high: float, pixels_per_unit: float, x: float, y: float
    ) -> None:
        if not pixels_per_unit > 0.0 or not math.isfinite(pixels_per_unit):
            raise ValueError(f"pixels_per_unit must be positive (got {pixels_per_unit})")
        self.initial = self.value = float(value)
        self.low, self.high, self.scale = float(low), float(high), float(pixels_per_unit)
        self.center = (float(x) - self.value * self.scale, float(y))

    @property
    def pixels(self) -> float:
        """The circle's radius in region pixels."""
        return self.value * self.scale

    def handle(self, event: InputEvent) -> str:
        """React to one event; RUNNING, FINISHED (value kept) or CANCELLED (value back)."""
        if event.type in {"MOUSEMOVE", "INBETWEEN_MOUSEMOVE"}:
            distance = math.hypot(event.x - self.center[0], event.y - self.center[1])
            self.value = min(max(distance / self.scale, self.low), self.high)
            return RUNNING
        if event.value == "PRESS" and event.type in CONFIRM_EVENTS:
            return FINISHED
        if event.value == "PRESS" and event.type in CANCEL_EVENTS:
            self.value = self.initial
            return CANCELLED
        return RUNNING
