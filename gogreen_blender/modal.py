"""The modal stroke's event handling as plain Python (no bpy): driven by Blender's events in the
add-on and by synthetic ones in the tests.

:class:`ModalStroke` turns window events into one stroke of a :class:`gogreen_core.Sculptor`
through :class:`gogreen_core.interaction.tools.StrokeController` (the desktop app's stroke logic:
grab brushes follow the cursor on the drag plane through the press point, paint brushes act on
the surface under it, affine brushes take their amount from the signed length of the drag in any
direction, Ctrl inverts, pen pressure scales the step). What
it needs from the viewport is a :class:`View` (object-space ray picks and projections), which
the operator implements with ``bpy_extras.view3d_utils`` and the tests with a fake.

Moves are coalesced: a mouse move only records the newest position and a timer tick applies
it, so a stroke slower than the mouse never builds a backlog; a release applies the last
recorded position before it ends the stroke.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from gogreen_core import Brush, Sculptor
from gogreen_core.interaction.tools import PointerEvent, StrokeController

__all__ = ["CANCELLED", "FINISHED", "RUNNING", "InputEvent", "ModalStroke", "View"]

RUNNING, FINISHED, CANCELLED = "RUNNING_MODAL", "FINISHED", "CANCELLED"
#: Blender event types that move the pointer.
MOVE_EVENTS = frozenset({"MOUSEMOVE", "INBETWEEN_MOUSEMOVE"})
#: Event types that cancel the stroke in progress (on press).
CANCEL_EVENTS = frozenset({"ESC", "RIGHTMOUSE"})
#: Event type of the timer that applies the newest recorded move.
TIMER_EVENT = "TIMER"


@dataclass(frozen=True)
class InputEvent:
    """The parts of a ``bpy.types.Event`` the stroke reads.

    type, value : Blender's event type ('LEFTMOUSE', 'MOUSEMOVE', 'ESC', 'TIMER', ...) and
        value ('PRESS', 'RELEASE', 'NOTHING').
    x, y : region pixels (Blender's ``mouse_region_x``/``_y``: y up).
    ctrl : Ctrl held (inverts the brush).
    pressure : pen pressure in [0, 1] (1 for a mouse).
    """

    type: str
    value: str = "NOTHING"
    x: float = 0.0
    y: float = 0.0
    ctrl: bool = False
    pressure: float = 1.0


class View(Protocol):
    """What the stroke needs from the 3D view, in the object's space."""

    def pick(self, x: float, y: float) -> np.ndarray | None:
        """(3,) the point of the object's surface under region pixel (x, y), or None."""

    def drag_point(self, x: float, y: float, depth: np.ndarray) -> np.ndarray:
        """(3,) the point under (x, y) on the view plane through ``depth``."""

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        """Unit view direction (into the screen) and unit screen-x direction, (3,) each."""


class ModalStroke:
    """One stroke of the GoGreen tool, from a press on the mesh to release or cancel.

    sculptor : the engine on the mesh (object space); ``sculptor.vertices`` is what to show.
    brush : the stroke's brush.
    view : the :class:`View` of the region the stroke happens in.

    :meth:`start` takes the press; :meth:`handle` each later event and returns the operator's
    state: RUNNING (``'RUNNING_MODAL'``), FINISHED (released: one undo step) or CANCELLED
    (Esc or right click: the vertices are back as they were). :attr:`changed` tells whether
    the vertices moved since the caller last read them (:meth:`take_changed`).
    """

    def __init__(self, sculptor: Sculptor, brush: Brush, view: View) -> None:
        self.sculptor = sculptor
        self.brush = brush
        self.view = view
        self.controller = StrokeController(sculptor)
        self._pending: InputEvent | None = None
        #: (3,) object-space point of the brush (the press point, then the grabbed point).
        self.center: np.ndarray | None = None
        self.changed = False
        self.events_applied = 0
        self._rows: list[np.ndarray] = []  # rows moved since the caller last took them

    def _pointer(self, event: InputEvent, point: np.ndarray | None) -> PointerEvent:
        view_dir, screen_x = self.view.axes()
        return PointerEvent(
            screen=(float(event.x), -float(event.y)),  # PointerEvent's y points down
            point=point,
            view_dir=view_dir,
            screen_x=screen_x,
            pressure=float(event.pressure),
            modifiers=frozenset({"ctrl"}) if event.ctrl else frozenset(),
        )

    def start(self, event: InputEvent) -> bool:
        """Begin at the press ``event``; False (nothing started) when it misses the mesh."""
        point = self.view.pick(event.x, event.y)
        if point is None:
            return False
        rows = self.controller.press(
            self._pointer(event, np.asarray(point, dtype=float)), self.brush
        )
        if rows is not None:  # a paint brush's dab
            self._rows.append(rows)
            self.changed = True
        self.center = np.array(point, dtype=float)
        return True

    def _apply(self, event: InputEvent) -> None:
        # a paint brush acts on the surface under the cursor (Blender casts each dab onto it),
        # the others on the drag plane facing the view through the press point (as in the app)
        hit = self.view.pick(event.x, event.y) if self.controller.sweeping else None
        if hit is None:
            hit = self.view.drag_point(event.x, event.y, self.controller.anchor)
        point = np.asarray(hit, dtype=float)
        moved = self.controller.step(self._pointer(event, point))
        if moved is not None:
            self.events_applied += 1
            self.changed = True
            self._rows.append(moved)
            if not self.brush.is_affine:
                self.center = point  # grab brushes: the grabbed point follows the cursor

    def flush(self) -> None:
        """Apply the newest recorded move, if any."""
        event, self._pending = self._pending, None
        if event is not None:
            self._apply(event)

    def handle(self, event: InputEvent) -> str:
        """React to one event during the stroke; returns RUNNING, FINISHED or CANCELLED."""
        if event.type in MOVE_EVENTS:
            self._pending = event
            return RUNNING
        if event.type == TIMER_EVENT:
            self.flush()
            return RUNNING
        if event.type in CANCEL_EVENTS and event.value == "PRESS":
            self.cancel()
            return CANCELLED
        if event.type == "LEFTMOUSE" and event.value == "RELEASE":
            self.flush()
            self.controller.end()
            return FINISHED
        return RUNNING  # everything else waits until the stroke ends (as Blender's brushes)

    def cancel(self) -> None:
        """Abandon the stroke: the vertices go back to where they were at the press."""
        self._pending = None
        self.controller.cancel()
        self.changed = True

    def take_changed(self) -> bool:
        """Whether the vertices moved since the last call (and forget it)."""
        changed, self.changed = self.changed, False
        return changed

    def take_rows(self) -> np.ndarray:
        """(K,) int64 the rows events moved since the last call (not those a cancel put back)."""
        rows, self._rows = self._rows, []
        return np.concatenate(rows) if rows else np.zeros(0, dtype=np.int64)
