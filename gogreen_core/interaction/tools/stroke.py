"""The stroke controller: pointer samples of one drag → brush events of one stroke."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING, cast

import numpy as np

from gogreen_core.interaction.settings import PenSettings
from gogreen_core.interaction.tools.events import PointerEvent
from gogreen_core.sculpt.brushes import Brush, BrushEvent, brush_row

if TYPE_CHECKING:
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = [
    "AFFINE_SIGN_PIXELS",
    "MIN_PRESSURE_RADIUS",
    "PIXELS_PER_UNIT_AMOUNT",
    "StrokeController",
]

#: Screen drag (pixels) that makes an affine brush's amount 1 (strain, or radians for twist).
PIXELS_PER_UNIT_AMOUNT = 100.0
#: An affine stroke's sign is set once its drag is this long (pixels).
AFFINE_SIGN_PIXELS = 3.0
#: Smallest radius factor pen pressure gives (a feather touch still sculpts).
MIN_PRESSURE_RADIUS = 0.1


class StrokeController:
    """One brush stroke at a time: press begins it, moves step it, release ends it.

    Grab brushes move the surface by the cursor's world motion on the drag plane. Affine
    brushes stay at the press point and, as Blender's Elastic Deform, take their amount from
    the signed length of the drag (:data:`PIXELS_PER_UNIT_AMOUNT` pixels = 1) and their
    direction from the drag: + when it sets off right or up, − left or down, set once the drag
    is :data:`AFFINE_SIGN_PIXELS` long and again whenever it comes back that close, so the
    amount never jumps. Paint brushes act where the cursor passes, a dab at the press first:
    each event is the segment the cursor moved and the pen pressure (negative with Ctrl).
    """

    def __init__(self, sculptor: Sculptor, pen: Callable[[], PenSettings] | None = None) -> None:
        self.sculptor = sculptor
        defaults = PenSettings()
        self.pen = pen or (lambda: defaults)
        self.brush: Brush | None = None
        self.anchor: np.ndarray | None = None  # (3,) the press point (affine brushes' ring)
        self._load_centre = np.zeros(3)  # where an anchored brush's load acts
        self._last_point: np.ndarray | None = None
        #: Affine strokes: the press point on screen, the sign of the drag (0 undecided) and
        #: the signed drag length (pixels) already applied.
        self._press_screen: tuple[float, float] = (0.0, 0.0)
        self._sign = 0
        self._applied_drag = 0.0
        #: Stabilized pointer: screen (x, y) and world point where the brush is.
        self._lazy: tuple[tuple[float, float], np.ndarray | None] | None = None
        self._applied: np.ndarray | None = None  # the last applied event's point (spacing)
        #: The latest pen sample's radius factor (1 when off or between strokes).
        self.radius_factor = 1.0
        self._drag = ""  # how the stroke's drag becomes events (its brush row's ``drag``)

    @property
    def anchored(self) -> bool:
        """True during a stroke whose brush stays at the press point (affine brushes)."""
        return self.brush is not None and self._drag == "anchored"

    @property
    def sweeping(self) -> bool:
        """True during a stroke whose brush acts where the cursor passes (paint brushes): its
        moves belong on the surface under the cursor, not on the drag plane."""
        return self.brush is not None and self._drag == "sweep"

    @property
    def active(self) -> bool:
        return self.brush is not None

    def press(self, event: PointerEvent, brush: Brush) -> np.ndarray | None:
        """Begin a stroke at the picked ``event.point`` (engine errors propagate); the rows a
        paint brush's dab there changed (None for other brushes)."""
        if event.point is None:
            raise ValueError("a stroke starts on the surface (no point under the cursor)")
        self.sculptor.begin_stroke(brush)
        self.brush = brush
        self.anchor = np.array(event.point, dtype=float)
        self._load_centre = self.anchor - self._depth(event, brush)
        self._last_point = self.anchor.copy()
        self._press_screen, self._sign, self._applied_drag = event.screen, 0, 0.0
        self._lazy = (event.screen, self.anchor.copy())
        self._applied = self.anchor.copy()
        self.radius_factor = self._radius_factor(event)
        self._drag = brush_row(brush.kind).drag
        if self._drag != "sweep":
            return None
        dab = BrushEvent(
            center=self.anchor, amount=self._pressure(event), radius_factor=self.radius_factor
        )
        try:
            return self.sculptor.stroke_event(dab)
        except (ValueError, RuntimeError):
            self.cancel()
            raise

    def _pressure(self, event: PointerEvent) -> float:
        """The pen pressure the step takes (1 unless pressure → strength is on), negative
        with Ctrl held."""
        pressure = float(np.clip(event.pressure, 0.0, 1.0)) if self.pen().pressure_strength else 1.0
        return -pressure if "ctrl" in event.modifiers else pressure

    def _radius_factor(self, event: PointerEvent) -> float:
        """The radius factor in [:data:`MIN_PRESSURE_RADIUS`, 1] of ``event``'s pressure (1
        unless pressure → radius is on; NaN: 1)."""
        p = float(event.pressure)
        if not self.pen().pressure_radius or not np.isfinite(p):
            return 1.0
        return min(max(p, MIN_PRESSURE_RADIUS), 1.0)

    @property
    def radius(self) -> float | None:
        """The radius (fraction of the model size) of the stroke's next event, or None."""
        if self.brush is None:
            return None
        return self.brush.scaled(self.radius_factor).radius

    def brush_event(self, event: PointerEvent) -> BrushEvent | None:
        """The engine event of moving to ``event`` (None when the cursor did not move)."""
        assert self.brush is not None
        pressure = self._pressure(event)
        factor = self._radius_factor(event)
        if self._drag == "anchored":
            return self._affine_event(event, pressure, factor)
        point = np.asarray(event.point, dtype=float)
        delta = point - self._last_point
        if not np.any(delta):
            return None
        center, self._last_point = cast(np.ndarray, self._last_point), point
        if self._drag == "sweep":  # the swept segment, the pressure apart
            return BrushEvent(center=center, delta=delta, amount=pressure, radius_factor=factor)
        return BrushEvent(center=center, delta=pressure * delta, radius_factor=factor)

    def _depth(self, event: PointerEvent, brush: Brush) -> np.ndarray:
        """How far (3,) below the press point an anchored brush's load centre lies: its row's
        ``depth`` ε along the normal turned away from the viewer."""
        row = brush_row(brush.kind)
        depth = row.depth if row.drag == "anchored" else 0.0
        if not depth or event.normal is None:
            return np.zeros(3)
        normal = np.asarray(event.normal, dtype=float)
        size = float(np.linalg.norm(normal))
        if not size > 0 or not np.isfinite(size):
            return np.zeros(3)
        normal = normal / size
        if event.view_dir is not None and normal @ np.asarray(event.view_dir, dtype=float) > 0:
            normal = -normal  # the side facing the viewer is outside
        eps = brush.eps(self.sculptor.model_size) * self._radius_factor(event)
        return depth * eps * normal

    def _affine_event(
        self, event: PointerEvent, pressure: float, factor: float
    ) -> BrushEvent | None:
        """The affine event of the drag reaching ``event`` (see the class docstring)."""
        assert self.anchor is not None
        dx = event.screen[0] - self._press_screen[0]
        dy = self._press_screen[1] - event.screen[1]  # y up
        length = float(np.hypot(dx, dy))
        if length < AFFINE_SIGN_PIXELS:
            self._sign = 0  # back at the press point: the next drag sets the sign again
        elif self._sign == 0:
            self._sign = 1 if dx + dy > 0 or (dx + dy == 0 and dx > 0) else -1
        signed = self._sign * length
        change, self._applied_drag = signed - self._applied_drag, signed
        if change == 0:
            return None
        view = np.asarray(event.view_dir, dtype=float)
        right = np.asarray(event.screen_x, dtype=float)
        up = np.cross(right, view)
        return BrushEvent(
            center=self._load_centre,
            amount=pressure * change / PIXELS_PER_UNIT_AMOUNT,
            axis=view,
            direction=dx * right + dy * up if length > 0 else None,
            radius_factor=factor,
        )

    def stabilized(self, event: PointerEvent) -> PointerEvent | None:
        """``event`` after the stabilizer and spacing (:class:`PenSettings`): the brush point
        trails the pointer by ``lazy_radius`` pixels; None while it has moved less than
        ``spacing`` · ε since the last applied event or not left the lazy radius."""
        pen = self.pen()
        lazy = float(pen.lazy_radius)
        if lazy > 0 and self._lazy is not None:
            (lx, ly), lpoint = self._lazy
            dx, dy = event.screen[0] - lx, event.screen[1] - ly
            distance = float(np.hypot(dx, dy))
            if distance <= lazy:
                return None
            t = (distance - lazy) / distance
            screen = (lx + t * dx, ly + t * dy)
            point = None
            if event.point is not None and lpoint is not None:
                point = lpoint + t * (np.asarray(event.point, dtype=float) - lpoint)
            self._lazy = (screen, point)
            event = replace(event, screen=screen, point=point)
        spacing = float(pen.spacing)
        if spacing > 0 and event.point is not None and self._applied is not None:
            eps = cast(Brush, self.brush).eps(self.sculptor.model_size) * self._radius_factor(event)
            if np.linalg.norm(np.asarray(event.point) - self._applied) < spacing * eps:
                return None
        return event

    def step(self, event: PointerEvent) -> np.ndarray | None:
        """Apply one move (after :meth:`stabilized`); the indices of moved vertices, or None."""
        self.radius_factor = self._radius_factor(event)  # the cursor follows the pen at once
        stable = self.stabilized(event)
        if stable is None:
            return None
        if stable.point is not None:
            self._applied = np.array(stable.point, dtype=float)
        brush_event = self.brush_event(stable)
        return None if brush_event is None else self.sculptor.stroke_event(brush_event)

    def end(self) -> np.ndarray | None:
        """End the stroke (one undo step if it changed anything); the indices of the vertices
        it moved, None without a stroke."""
        moved = self.sculptor.end_stroke() if self.brush is not None else None
        self.brush, self.radius_factor = None, 1.0
        return moved

    def cancel(self) -> None:
        if self.brush is not None:
            self.sculptor.cancel_stroke()
        self.brush, self.radius_factor = None, 1.0
