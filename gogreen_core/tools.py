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

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from gogreen_core.brushes import (
    BRUSH_KINDS,
    CUTOFF_START,
    DEFAULT_INFLUENCE,
    MAX_RADIUS,
    MAX_STRENGTH,
    MIN_RADIUS,
    Brush,
    BrushEvent,
)
from gogreen_core.constraints import smooth_cutoff
from gogreen_core.settings import PenSettings
from gogreen_core.threads import threads_at_most

__all__ = [
    "PIN_PICK_FRACTION",
    "PIXELS_PER_UNIT_AMOUNT",
    "PROFILE_SAMPLES",
    "CursorController",
    "CursorState",
    "PinController",
    "PointerEvent",
    "SculptTools",
    "StrokeController",
    "ToolUpdate",
    "ValueDrag",
    "brush_for_key",
    "brush_profile",
    "grab_motion",
    "pressure_radius_factor",
    "smooth_cutoff",
]

#: Screen drag (pixels) that makes an affine brush's amount 1 (strain, or radians for twist).
PIXELS_PER_UNIT_AMOUNT = 250.0
#: A press closer to a pin than this fraction of the constraint radius drags that pin.
PIN_PICK_FRACTION = 0.5


#: Screen distance (pixels) from the cursor centre that means strength 1 when F-dragging the
#: strength with no cursor shown.
PIXELS_PER_STRENGTH = 100.0


def brush_for_key(key: str) -> str | None:
    """The brush a number key picks ("1" → the first of :data:`BRUSH_KINDS`), else None."""
    if len(key) == 1 and key.isdigit() and 1 <= int(key) <= len(BRUSH_KINDS):
        return BRUSH_KINDS[int(key) - 1]
    return None


@dataclass(frozen=True)
class PointerEvent:
    """One pointer sample in plain numbers.

    screen : (x, y) widget pixels, x right, y down.
    point : (3,) world point: the picked surface point (press, hover), or the cursor on the
        drag plane through the press point (moves during a drag); None when nothing is hit.
    normal : (3,) surface normal at ``point`` when it was picked, else None.
    view_dir : (3,) unit direction from the camera into the screen.
    screen_x : (3,) unit world direction of the screen's x axis.
    pressure : pen pressure in [0, 1] (1 for a mouse); scales the step of a stroke.
    modifiers : names of held modifier keys ("shift", "ctrl", "alt").
    """

    screen: tuple[float, float]
    point: np.ndarray | None = None
    normal: np.ndarray | None = None
    view_dir: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -1.0]))
    screen_x: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0]))
    pressure: float = 1.0
    modifiers: frozenset[str] = frozenset()


#: Samples of the falloff profile drawn in the brush cursor, over [0, influence · ε].
PROFILE_SAMPLES = 48


def brush_profile(kernel, brush: Brush, eps: float, samples: int = PROFILE_SAMPLES) -> np.ndarray:
    """Relative motion (samples,) in [0, 1] at distances ``linspace(0, influence · ε)`` from a
    grab of ``kernel`` (a :class:`GreenKernel` at ε = ``eps``): |G(r x̂) G(0)⁻¹ e| averaged over
    the three axes e, times the brush's smooth cutoff, divided by its largest value. With
    ``kernel`` None (kernels not ready) only the cutoff is drawn."""
    finite = np.isfinite(brush.influence)
    outer = (brush.influence if finite else DEFAULT_INFLUENCE) * eps
    r = np.linspace(0.0, outer, samples)
    cutoff = smooth_cutoff(r, CUTOFF_START * outer, outer) if finite else 1.0
    if kernel is None:
        return np.broadcast_to(cutoff, r.shape).astype(float)
    motion = grab_motion(kernel, r) * cutoff
    peak = motion.max()
    return motion / peak if peak > 0 and np.isfinite(peak) else np.zeros(samples)


def grab_motion(kernel, distances: np.ndarray) -> np.ndarray:
    """Motion (n,) at ``distances`` (n,) along x̂ from a unit grab of ``kernel`` (a
    :class:`GreenKernel`): |G(r x̂) G(0)⁻¹ e| averaged over the three axes e, so 1 at the centre
    (G(0) singular, a falloff with R₀(0) = 0: G divided by its largest entry instead). What the
    brush cursor and the falloff panel's preview draw.

    Evaluated on the calling thread alone: for a few dozen samples (~0.2 ms) a second numba
    thread only adds its wake-up, measured at 3-7 ms median on this 2-core machine right after
    numpy's BLAS threads ran (0.24 ms with one thread)."""
    offsets = np.zeros((len(distances), 3))
    offsets[:, 0] = distances
    with threads_at_most(1):
        green = kernel.green(offsets)  # (n, 3, 3)
    try:
        normalized = green @ np.linalg.inv(green[0])
    except np.linalg.LinAlgError:
        normalized = green / (np.abs(green).max() or 1.0)
    return np.linalg.norm(normalized, axis=1).mean(axis=1)


@dataclass(frozen=True)
class CursorState:
    """Where the brush cursor is drawn: ``center`` (3,), unit ``normal`` (3,), ``radius`` ε
    (model units), ``influence`` (the moved region's radius in multiples of ε), ``profile``
    (samples over [0, influence · ε] of the relative motion, :func:`brush_profile`, or None),
    ``label`` (a live value shown while F / Shift+F drags it, else None) and ``full_radius``
    (during a pen stroke whose pressure shrinks the radius: the brush's own ε, model units,
    drawn faintly around the pressed one; else None)."""

    center: np.ndarray
    normal: np.ndarray
    radius: float
    influence: float = DEFAULT_INFLUENCE
    profile: np.ndarray | None = None
    label: str | None = None
    full_radius: float | None = None

    def ring_matrix(self) -> np.ndarray:
        """(4, 4) transform placing the unit circle of the xy plane on the surface (lifted by
        1e-3 radius along the normal so the surface does not hide it)."""
        n = np.asarray(self.normal, dtype=float)
        n = n / (np.linalg.norm(n) or 1.0)
        helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        t1 = np.cross(n, helper)
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        matrix = np.eye(4)
        matrix[:3, 0], matrix[:3, 1], matrix[:3, 2] = t1 * self.radius, t2 * self.radius, n
        matrix[:3, 2] *= self.radius
        matrix[:3, 3] = np.asarray(self.center, dtype=float) + 1e-3 * self.radius * n
        return matrix


@dataclass
class ToolUpdate:
    """What one call of the tools changed, for the view to draw.

    moved : indices of moved vertices (None: none moved; ``all_moved``: redraw every vertex).
    pins_changed : the constraint points changed.
    cursor : new brush-ring placement, or None to keep it (``hide_cursor`` hides it).
    step_seconds : wall time of the engine call, 0 if none ran.
    error : message of an engine error (the stroke was cancelled and the mesh restored).
    refused : the press was refused before reaching the engine (``error`` says why).
    """

    moved: np.ndarray | None = None
    all_moved: bool = False
    pins_changed: bool = False
    cursor: CursorState | None = None
    hide_cursor: bool = False
    step_seconds: float = 0.0
    error: str | None = None
    refused: bool = False

    @property
    def changed(self) -> bool:
        return bool(
            self.moved is not None
            or self.all_moved
            or self.pins_changed
            or self.cursor is not None
            or self.hide_cursor
            or self.error
        )


class _Coalescer:
    """Keeps only the newest pending event; counts received and processed ones."""

    def __init__(self) -> None:
        self.pending: PointerEvent | None = None
        self.received = 0
        self.processed = 0

    def reset(self) -> None:
        self.pending, self.received, self.processed = None, 0, 0

    def push(self, event: PointerEvent) -> None:
        self.pending = event
        self.received += 1

    def take(self) -> PointerEvent | None:
        event, self.pending = self.pending, None
        if event is not None:
            self.processed += 1
        return event


#: Smallest radius factor pen pressure gives (a feather touch still sculpts).
MIN_PRESSURE_RADIUS = 0.1


def pressure_radius_factor(pressure: float) -> float:
    """The radius factor in [:data:`MIN_PRESSURE_RADIUS`, 1] of a pen ``pressure`` (clipped to
    [0, 1]; NaN counts as a full press)."""
    p = float(pressure)
    p = 1.0 if not np.isfinite(p) else min(max(p, 0.0), 1.0)
    return max(p, MIN_PRESSURE_RADIUS)


class StrokeController:
    """One brush stroke at a time: press begins it, moves step it, release ends it.

    Grab brushes move the surface by the cursor's world motion on the drag plane (the point
    under the cursor follows the cursor); affine brushes (scale, twist, pinch) stay at the press
    point and take their amount from the horizontal screen motion (:data:`PIXELS_PER_UNIT_AMOUNT`
    pixels = amount 1) and their direction from the screen motion.
    """

    def __init__(self, sculptor, pen: Callable[[], PenSettings] | None = None) -> None:
        self.sculptor = sculptor
        defaults = PenSettings()
        self.pen = pen or (lambda: defaults)
        self.brush: Brush | None = None
        self._anchor: np.ndarray | None = None
        self._last_point: np.ndarray | None = None
        self._last_screen: tuple[float, float] | None = None
        #: Stabilized pointer: screen (x, y) and world point where the brush is.
        self._lazy: tuple[tuple[float, float], np.ndarray | None] | None = None
        #: World point of the last applied event (spacing is measured from it).
        self._applied: np.ndarray | None = None
        #: Radius factor of the latest pen sample of the stroke (pressure → radius), 1 when
        #: off or between strokes: what the brush cursor draws.
        self.radius_factor = 1.0

    @property
    def active(self) -> bool:
        return self.brush is not None

    @property
    def anchor(self) -> np.ndarray | None:
        """(3,) the press point of the stroke (where affine brushes act), None between strokes."""
        return self._anchor

    def press(self, event: PointerEvent, brush: Brush) -> None:
        """Begin a stroke at the picked ``event.point`` (engine errors propagate, nothing
        starts)."""
        if event.point is None:
            raise ValueError("a stroke starts on the surface (no point under the cursor)")
        self.sculptor.begin_stroke(brush)
        self.brush = brush
        self._anchor = np.array(event.point, dtype=float)
        self._last_point = self._anchor.copy()
        self._last_screen = event.screen
        self._lazy = (event.screen, self._anchor.copy())
        self._applied = self._anchor.copy()
        self.radius_factor = self._radius_factor(event)

    def _radius_factor(self, event: PointerEvent) -> float:
        """The radius factor of ``event``'s pressure (1 unless pressure → radius is on)."""
        return pressure_radius_factor(event.pressure) if self.pen().pressure_radius else 1.0

    @property
    def radius(self) -> float | None:
        """The radius (fraction of the model size) the stroke's next event acts with: the
        brush's times the pen's :attr:`radius_factor`; None between strokes."""
        if self.brush is None:
            return None
        return self.brush.scaled(self.radius_factor).radius

    def brush_event(self, event: PointerEvent) -> BrushEvent | None:
        """The engine event of moving to ``event`` (None when the cursor did not move)."""
        assert self.brush is not None
        dx = event.screen[0] - self._last_screen[0]
        dy = self._last_screen[1] - event.screen[1]  # y up
        self._last_screen = event.screen
        pressure = float(np.clip(event.pressure, 0.0, 1.0)) if self.pen().pressure_strength else 1.0
        factor = self._radius_factor(event)
        if "ctrl" in event.modifiers:  # Ctrl held inverts the brush (Blender's habit)
            pressure = -pressure
        if self.brush.is_affine:
            if dx == 0 and dy == 0:
                return None
            view = np.asarray(event.view_dir, dtype=float)
            right = np.asarray(event.screen_x, dtype=float)
            up = np.cross(right, view)
            return BrushEvent(
                center=self._anchor,
                amount=pressure * dx / PIXELS_PER_UNIT_AMOUNT,
                axis=view,
                direction=dx * right + dy * up,
                radius_factor=factor,
            )
        point = np.asarray(event.point, dtype=float)
        delta = point - self._last_point
        if not np.any(delta):
            return None
        center, self._last_point = self._last_point, point
        return BrushEvent(center=center, delta=pressure * delta, radius_factor=factor)

    def stabilized(self, event: PointerEvent) -> PointerEvent | None:
        """``event`` after the stabilizer and spacing (:class:`PenSettings`): the brush point
        trails the pointer by ``lazy_radius`` pixels (the world point interpolated on the drag
        plane), and None while it has moved less than ``spacing`` · ε since the last applied
        event or not left the lazy radius (ε at the event's pressure when pressure → radius is
        on, as the spacing is relative to the brush size)."""
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
            eps = self.brush.eps(self.sculptor.model_size) * self._radius_factor(event)
            if np.linalg.norm(np.asarray(event.point) - self._applied) < spacing * eps:
                return None
        return event

    def step(self, event: PointerEvent) -> np.ndarray | None:
        """Apply one move (after :meth:`stabilized`); the indices of moved vertices, or None
        when nothing moved."""
        self.radius_factor = self._radius_factor(event)  # the cursor follows the pen at once
        event = self.stabilized(event)
        if event is None:
            return None
        if event.point is not None:
            self._applied = np.array(event.point, dtype=float)
        brush_event = self.brush_event(event)
        if brush_event is None:
            return None
        return self.sculptor.stroke_event(brush_event)

    def end(self) -> None:
        if self.brush is not None:
            self.sculptor.end_stroke()
        self.brush, self.radius_factor = None, 1.0

    def cancel(self) -> None:
        if self.brush is not None:
            self.sculptor.cancel_stroke()
        self.brush, self.radius_factor = None, 1.0


class PinController:
    """Constraint pins: a press near a pin grabs it, elsewhere adds one; a drag moves the
    grabbed pin (one undo step per drag, the engine's ``continued`` flag)."""

    def __init__(self, sculptor) -> None:
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
        eps = self.sculptor.constraint_radius * self.sculptor.model_size
        return nearest if dist[nearest] < PIN_PICK_FRACTION * eps else None

    def press(self, event: PointerEvent, first_pin_radius: Callable[[], None] | None) -> bool:
        """Grab the pin near ``event.point`` (False) or add a pin there (True: pins changed).

        ``first_pin_radius`` is called before the first pin is added (the app gives the
        constraints the brush radius then)."""
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
        """Move the grabbed pin to ``event.point`` (every vertex may move); False if it did
        not move."""
        point = np.asarray(event.point, dtype=float)
        delta = point - self._last_point
        if not np.any(delta):
            return False
        self._last_point = point
        self.sculptor.drag_constraint(self.index, delta, self._continued)
        self._continued = True
        return True

    def end(self) -> None:
        self.index = None


class ValueDrag:
    """An on-screen drag of the brush radius or strength (Blender's F / Shift+F).

    The value is proportional to the screen distance from the cursor centre ``center``
    (pixels): ``value = start · distance / start_distance``, so the ring's edge follows the
    pointer for the radius. ``start_distance`` is the distance that means the starting value
    (the ring's pixel radius for the radius; the pointer's distance when the drag starts for the
    strength). Values are clipped to ``[low, high]``.
    """

    def __init__(
        self,
        name: str,
        start: float,
        center: tuple[float, float],
        start_distance: float,
        low: float,
        high: float,
    ) -> None:
        if name not in ("radius", "strength"):
            raise ValueError(f"a value drag is of radius or strength (got {name!r})")
        self.name, self.start, self.center = name, float(start), center
        self.start_distance = max(float(start_distance), 1.0)
        self.low, self.high = low, high
        self.value = self.start

    def move(self, screen: tuple[float, float]) -> float:
        distance = float(np.hypot(screen[0] - self.center[0], screen[1] - self.center[1]))
        self.value = float(
            np.clip(self.start * distance / self.start_distance, self.low, self.high)
        )
        return self.value

    @property
    def label(self) -> str:
        return f"{self.name.capitalize()} {self.value:.3g}"


class CursorController:
    """The brush cursor: on the surface under the hovering cursor, where the brush acts while
    dragging, hidden off the model. Callables give the current brush's ε in model units
    (``radius``), influence factor, falloff samples (``profile``, or None) and, during a pen
    stroke whose pressure shrinks ε, the full ε (``full_radius``, else None)."""

    def __init__(
        self,
        radius: Callable[[], float],
        influence: Callable[[], float],
        profile: Callable[[], np.ndarray | None],
        full_radius: Callable[[], float | None],
    ) -> None:
        self.radius = radius
        self.influence = influence
        self.profile = profile
        self.full_radius = full_radius
        self.state: CursorState | None = None
        self._normal: np.ndarray | None = None

    def place(
        self, point: np.ndarray | None, normal: np.ndarray | None, label: str | None = None
    ) -> CursorState | None:
        if point is None:
            self.state = None
            return None
        if normal is not None:
            self._normal = np.asarray(normal, dtype=float)
        n = self._normal if self._normal is not None else np.array([0.0, 0.0, 1.0])
        self.state = CursorState(
            np.array(point, dtype=float),
            n,
            float(self.radius()),
            float(self.influence()),
            self.profile(),
            label,
            self.full_radius(),
        )
        return self.state

    def refresh(self) -> CursorState | None:
        """The same place with the current radius, influence and profile (None if hidden)."""
        if self.state is None:
            return None
        return self.place(self.state.center, self.state.normal, self.state.label)

    def hide(self) -> None:
        """Hidden until the pointer moves again (after undo, or a newly opened file)."""
        self.state = None


class SculptTools:
    """Routes pointer events to the stroke or the pin controller and the cursor.

    Parameters
    ----------
    sculptor : Sculptor, the engine the tools act on (replace with :meth:`set_sculptor`).
    brush : callable returning the :class:`Brush` a new stroke uses (the settings model's).
    first_pin_radius : callable run before the first pin is added, optional.
    ready : callable returning None when strokes may start, else the reason they may not
        (e.g. kernels still compiling): a refused press reports it as ``error``.

    ``mode`` is ``"brush"`` (presses sculpt) or ``"pin"`` (presses pin and drag pins).
    """

    def __init__(
        self,
        sculptor,
        brush: Callable[[], Brush],
        first_pin_radius: Callable[[], None] | None = None,
        ready: Callable[[], str | None] | None = None,
        settings=None,
        pen: Callable[[], PenSettings] | None = None,
    ) -> None:
        self.brush = brush
        #: Pressure, stabilizer and spacing options (:class:`PenSettings`; defaults if None).
        defaults = PenSettings()
        self.pen = pen or (lambda: defaults)
        #: The brush settings model (``kind``, ``radius``, ``strength``) that keys and value
        #: drags change (a :class:`gogreen_core.settings.BrushSettings`), optional.
        self.settings = settings
        self.value_drag: ValueDrag | None = None
        self.first_pin_radius = first_pin_radius
        self.ready = ready or (lambda: None)
        self.mode = "brush"
        self._moves = _Coalescer()
        self._hover: PointerEvent | None = None
        self.cursor = CursorController(
            self._cursor_radius,
            lambda: self.brush().influence,
            self._cursor_profile,
            self._cursor_full_radius,
        )
        self._profile_key: tuple | None = None
        self._profile: np.ndarray | None = None
        self._profile_settings = None
        self.set_sculptor(sculptor)

    def set_sculptor(self, sculptor) -> None:
        """Act on another engine (a newly opened mesh); drops any stroke in progress."""
        if getattr(self, "stroke", None) is not None:
            self.stroke.cancel()
        self.sculptor = sculptor
        self.stroke = StrokeController(sculptor, lambda: self.pen())
        self.pin = PinController(sculptor)

    def _cursor_radius(self) -> float:
        """ε of the cursor (model units): during a stroke the radius its events act with (the
        pen's pressure-scaled one), else the current brush's."""
        if self.sculptor is None:
            return 0.0
        radius = self.stroke.radius if self.stroke.active else None
        if radius is None:
            return self.brush().eps(self.sculptor.model_size)
        return radius * self.sculptor.model_size

    def _cursor_full_radius(self) -> float | None:
        """The brush's own ε (model units) while pen pressure shrinks the stroke's, else None."""
        if self.sculptor is None or not self.stroke.active or self.stroke.radius_factor >= 1.0:
            return None
        return self.brush().eps(self.sculptor.model_size)

    def _cursor_profile(self) -> np.ndarray | None:
        """The current brush's falloff samples (:func:`brush_profile`), cached per engine
        settings (material, falloff, l_max) and brush shape."""
        if self.sculptor is None:
            return None
        brush = self.brush()
        eps = brush.eps(self.sculptor.model_size)
        ready = not self.ready()
        settings = self.sculptor.settings
        key = (id(self.sculptor), brush.kind, brush.influence, eps, ready)
        if key != self._profile_key or settings is not self._profile_settings:
            try:
                kernel = self.sculptor.kernel(brush) if ready else None
                self._profile = brush_profile(kernel, brush, eps)
            except (ValueError, RuntimeError, np.linalg.LinAlgError):
                self._profile = brush_profile(None, brush, eps)
            self._profile_key, self._profile_settings = key, settings
        return self._profile

    # -- state -------------------------------------------------------------------------------
    @property
    def dragging(self) -> bool:
        return self.stroke.active or self.pin.active

    @property
    def received(self) -> int:
        """Move events received during the current (or last) drag."""
        return self._moves.received

    @property
    def processed(self) -> int:
        """Move events applied during the current (or last) drag (the rest were coalesced)."""
        return self._moves.processed

    @property
    def has_pending(self) -> bool:
        return self._moves.pending is not None or self._hover is not None

    # -- keys --------------------------------------------------------------------------------
    def pick_brush(self, key: str) -> bool:
        """Number keys pick brushes in :data:`BRUSH_KINDS` order; True if ``key`` did."""
        kind = brush_for_key(key)
        if kind is None or self.settings is None or self.dragging:
            return False
        self.settings.kind = kind
        return True

    def start_value_drag(
        self,
        name: str,
        screen: tuple[float, float],
        cursor_center: tuple[float, float] | None,
        ring_pixels: float | None,
    ) -> ToolUpdate:
        """Begin an F (``"radius"``) or Shift+F (``"strength"``) drag with the pointer at
        ``screen``; the cursor's screen centre and ε ring radius (pixels) if it is shown."""
        if self.settings is None or self.dragging or self.value_drag is not None:
            return ToolUpdate()
        start = float(getattr(self.settings, name))
        if name == "radius":
            low, high = MIN_RADIUS, MAX_RADIUS
            if cursor_center is None or not ring_pixels:
                ring_pixels = 100.0
                cursor_center = (screen[0] - ring_pixels, screen[1])
            distance = ring_pixels
        else:
            low, high = 0.0, MAX_STRENGTH
            if cursor_center is None:
                cursor_center = (screen[0] - PIXELS_PER_STRENGTH * start, screen[1])
            distance = float(np.hypot(screen[0] - cursor_center[0], screen[1] - cursor_center[1]))
            distance = distance if distance >= 1.0 else PIXELS_PER_STRENGTH
        self.value_drag = ValueDrag(name, start, cursor_center, distance, low, high)
        return self._value_update()

    def _value_update(self) -> ToolUpdate:
        state = self.cursor.state
        if state is None:
            return ToolUpdate()
        label = self.value_drag.label if self.value_drag is not None else None
        return ToolUpdate(cursor=self.cursor.place(state.center, state.normal, label))

    def move_value_drag(self, screen: tuple[float, float]) -> ToolUpdate:
        """The pointer moved during a value drag: the setting follows at once."""
        if self.value_drag is None:
            return ToolUpdate()
        value = self.value_drag.move(screen)
        setattr(self.settings, self.value_drag.name, value)
        return self._value_update()

    def finish_value_drag(self, confirm: bool) -> ToolUpdate:
        """Click or Enter (``confirm``) keeps the value; Escape or right click restores it."""
        drag, self.value_drag = self.value_drag, None
        if drag is None:
            return ToolUpdate()
        if not confirm:
            setattr(self.settings, drag.name, drag.start)
        return self._value_update()

    # -- events ------------------------------------------------------------------------------
    def press(self, event: PointerEvent) -> ToolUpdate:
        """Start a stroke, or add/grab a pin, at the picked ``event.point``."""
        if self.sculptor is None or self.dragging:
            return ToolUpdate()
        reason = self.ready() if self.mode == "brush" else None
        if reason:
            return ToolUpdate(error=reason, refused=True)
        self._moves.reset()
        self._hover = None
        try:
            if self.mode == "pin":
                added = self.pin.press(event, self.first_pin_radius)
                return ToolUpdate(pins_changed=added)
            self.stroke.press(event, self.brush())
        except (ValueError, RuntimeError) as exc:
            self.pin.end()
            return ToolUpdate(error=str(exc))
        return ToolUpdate(cursor=self.cursor.place(event.point, event.normal))

    def move(self, event: PointerEvent) -> None:
        """Record a drag move (applied by the next :meth:`flush`; newer moves replace it)."""
        if self.dragging:
            self._moves.push(event)

    def hover(self, event: PointerEvent) -> None:
        """Record a hover sample (no button): the ring follows at the next :meth:`flush`."""
        if not self.dragging:
            self._hover = event

    def flush(self) -> ToolUpdate:
        """Apply the newest recorded move (or hover): one engine step at most."""
        if self._hover is not None and not self.dragging:
            hover, self._hover = self._hover, None
            state = self.cursor.place(hover.point, hover.normal)
            return ToolUpdate(cursor=state, hide_cursor=state is None)
        event = self._moves.take()
        if event is None:
            return ToolUpdate()
        start = time.perf_counter()
        try:
            if self.pin.active:
                stepped = self.pin.step(event)
                update = ToolUpdate(all_moved=stepped, pins_changed=stepped)
            else:
                moved = self.stroke.step(event)
                stepped = moved is not None
                # the cursor sits where the brush acts: affine brushes at their press point
                acts = self.stroke.anchor if self.stroke.brush.is_affine else event.point
                update = ToolUpdate(moved=moved, cursor=self.cursor.place(acts, None))
        except (ValueError, RuntimeError) as exc:
            self.stroke.cancel()
            self.pin.end()
            return ToolUpdate(all_moved=True, error=str(exc))
        if stepped:
            update.step_seconds = time.perf_counter() - start
        return update

    def release(self) -> ToolUpdate:
        """Apply the last recorded move (if not yet applied), then end the stroke (one undo
        step) or the pin drag."""
        update = self.flush() if self._moves.pending is not None else ToolUpdate()
        self.stroke.end()
        self.pin.end()
        return update

    def remove_pin(self, event: PointerEvent) -> ToolUpdate:
        """Remove the pin near ``event.point`` (a right click in pin mode; an undo step);
        nothing when no pin is near."""
        if self.sculptor is None or self.dragging or event.point is None:
            return ToolUpdate()
        index = self.pin.nearest_pin(np.asarray(event.point, dtype=float))
        if index is None:
            return ToolUpdate()
        try:
            self.sculptor.remove_constraint(index)
        except (ValueError, RuntimeError) as exc:
            return ToolUpdate(error=str(exc))
        return ToolUpdate(pins_changed=True)

    def cancel(self) -> None:
        """Abandon a stroke in progress (restoring the mesh) or a pin drag."""
        self._moves.pending = None
        self.stroke.cancel()
        self.pin.end()
