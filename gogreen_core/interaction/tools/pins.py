"""The pin controller: a press pins a point or grabs a pin, a drag moves the grabbed pin."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, cast

import numpy as np

from gogreen_core.interaction.tools.events import PointerEvent

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["PIN_PICK_FRACTION", "PinController"]

#: A press closer to a pin than this fraction of the constraint radius drags that pin.
PIN_PICK_FRACTION = 0.5


class PinController:
    """Constraint pins: a press near a pin grabs it, elsewhere adds one; a drag moves the
    grabbed pin (one undo step per drag, the engine's ``continued`` flag)."""

    def __init__(self, sculptor: Sculptor) -> None:
        self.sculptor = sculptor
        self.index: int | None = None
        self._last_point: np.ndarray | None = None
        self._continued = False

    @property
    def active(self) -> bool:
        return self.index is not None

    def nearest_pin(self, point: np.ndarray) -> int | None:
        """Index of the pin within :data:`PIN_PICK_FRACTION` constraint radii, else None."""
        points = self.sculptor.constraint_points
        if not len(points):
            return None
        dist = np.linalg.norm(points - np.asarray(point), axis=1)
        nearest = int(np.argmin(dist))
        eps = self.sculptor.settings.constraint_radius * self.sculptor.model_size
        return nearest if dist[nearest] < PIN_PICK_FRACTION * eps else None

    def press(self, event: PointerEvent, first_pin_radius: Callable[[], None] | None) -> bool:
        """Grab the pin near ``event.point`` (False) or add a pin there (True: pins changed),
        calling ``first_pin_radius`` before the first pin is added."""
        if event.point is None:
            raise ValueError("a pin goes on the surface (no point under the cursor)")
        point = np.array(event.point, dtype=float)
        grabbed = self.nearest_pin(point)
        added = grabbed is None
        if added:
            if not len(self.sculptor.constraint_points) and first_pin_radius is not None:
                first_pin_radius()
            grabbed = self.sculptor.add_constraint(point)
        self.index, self._last_point, self._continued = grabbed, point, False
        return added

    def step(self, event: PointerEvent) -> bool:
        """Move the grabbed pin to ``event.point``; False if it did not move."""
        point = np.asarray(event.point, dtype=float)
        delta = point - self._last_point
        if not np.any(delta):
            return False
        self._last_point = point
        self.sculptor.drag_constraint(cast(int, self.index), delta, self._continued)
        self._continued = True
        return True

    def end(self) -> None:
        self.index = None
