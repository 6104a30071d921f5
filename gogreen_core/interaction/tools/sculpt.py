"""The sculpt tools: pointer events routed to the stroke or pin controller and the cursor."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from gogreen_core.interaction.settings import BrushSettings, PenSettings
from gogreen_core.interaction.tools.cursor import (
    PIXELS_PER_STRENGTH,
    CursorController,
    ValueDrag,
    anchored_label,
    brush_profile,
    moving_radius,
)
from gogreen_core.interaction.tools.events import PointerEvent, ToolUpdate
from gogreen_core.interaction.tools.gauge import DeformationGauge
from gogreen_core.interaction.tools.material_axes import cursor_axes
from gogreen_core.interaction.tools.pins import PinController
from gogreen_core.interaction.tools.stroke import StrokeController
from gogreen_core.mesh.remesh import median_edge_length
from gogreen_core.sculpt.brushes import (
    DEFAULT_INFLUENCE,
    MAX_RADIUS,
    MAX_STRENGTH,
    MIN_RADIUS,
    Brush,
    GreenBrush,
    brush_for_key,
    brush_row,
)
from gogreen_core.threads import threads_at_most

if TYPE_CHECKING:
    from gogreen_core.sculpt.engine_settings import EngineSettings
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["DETAIL_SAMPLE_FACES", "NUMBER_KEYS", "SMOOTH", "SculptTools", "brush_for_key"]

#: The cursor's detail circle measures the surface's edge length on at most this many faces.
DETAIL_SAMPLE_FACES = 20_000
#: The brush a stroke begun with Shift held uses.
SMOOTH = "smooth"
#: The number keys brushes may have (each brush row's ``number``).
NUMBER_KEYS = "1234567890"


class SculptTools:
    """Routes pointer events to the stroke or the pin controller and the cursor.

    Parameters
    ----------
    sculptor : Sculptor, the engine the tools act on (replace with :meth:`set_sculptor`).
    brush : callable returning the :class:`Brush` a new stroke uses.
    first_pin_radius : callable run before the first pin is added, optional.
    ready : callable returning None when strokes may start, else the reason they may not.
    settings : the brush settings model that number keys and value drags change, optional.
    pen : callable returning the :class:`PenSettings` (defaults if None).

    ``mode`` is ``"brush"`` or ``"pin"``. :attr:`received` and :attr:`processed` count the
    current (or last) drag's move events received and applied (the rest were coalesced).
    """

    def __init__(
        self,
        sculptor: Sculptor | None,
        brush: Callable[[], Brush],
        first_pin_radius: Callable[[], None] | None = None,
        ready: Callable[[], str | None] | None = None,
        settings: BrushSettings | None = None,
        pen: Callable[[], PenSettings] | None = None,
    ) -> None:
        self.brush = brush
        defaults = PenSettings()
        self.pen = pen or (lambda: defaults)
        self.settings = settings
        self.value_drag: ValueDrag | None = None
        self.first_pin_radius = first_pin_radius
        self.ready = ready or (lambda: None)
        self.mode = "brush"
        self._pending: PointerEvent | None = None  # the newest move not yet applied
        self.received = self.processed = 0
        self._hover: PointerEvent | None = None
        self.cursor = CursorController(self)
        self._detail_of: tuple[np.ndarray | None, float] = (None, 0.0)
        self._profile_key: tuple[Any, ...] | None = None
        self._profile: np.ndarray | None = None
        self._moving_ratio = 1.0  # the cached ring's moving_radius in units of its ε
        self._moving_key: tuple[Any, ...] | None = None
        self._profile_settings: EngineSettings | None = None
        #: Compute the ring of new settings on a worker thread, showing the previous one
        #: meanwhile, and call :attr:`ring_ready` (there) when it is done.
        self.ring_in_background = False
        self.ring_ready: Callable[[], None] | None = None
        self._ring_thread: threading.Thread | None = None
        self._ring_wanted: tuple[tuple[Any, ...], Brush, float] | None = None
        self._ring_done: tuple[tuple[Any, ...], float] | None = None
        #: The material's axes last drawn: (what they were for, the point, the axes).
        self._axes_at: tuple[tuple[Any, ...], np.ndarray, np.ndarray | None] | None = None
        self._gauge: DeformationGauge | None = None  # during an anchored stroke
        self.set_sculptor(sculptor)

    def set_sculptor(self, sculptor: Sculptor | None) -> None:
        """Act on another engine (a newly opened mesh); drops any stroke in progress."""
        if getattr(self, "stroke", None) is not None:
            self.stroke.cancel()
        self._gauge = None
        self.sculptor = sculptor
        self.stroke: StrokeController = StrokeController(
            cast("Sculptor", sculptor), lambda: self.pen()
        )
        self.pin: PinController = PinController(cast("Sculptor", sculptor))

    def _cursor_radius(self) -> float:
        """ε of the cursor (model units): the stroke's (pressure-scaled), else the brush's."""
        if self.sculptor is None:
            return 0.0
        if self.stroke.radius is None:  # between strokes: the brush's
            return self.brush().eps(self.sculptor.model_size)
        return self.stroke.radius * self.sculptor.model_size

    def _cursor_influence(self, brush: Brush | None = None) -> float:
        """The influence in ε of ``brush`` (the current one when None), ``"auto"`` resolved
        (:data:`DEFAULT_INFLUENCE` while the kernels are not ready)."""
        brush = self.brush() if brush is None else brush
        if not brush.auto_influence:
            return float(brush.influence)
        if self.sculptor is None or self.ready():
            return DEFAULT_INFLUENCE
        try:
            return self.sculptor.influence(brush)
        except (ValueError, RuntimeError, np.linalg.LinAlgError):
            return DEFAULT_INFLUENCE

    def _cursor_full_radius(self) -> float | None:
        """The brush's own ε (model units) while pen pressure shrinks the stroke's, else None."""
        if self.sculptor is None or not self.stroke.active or self.stroke.radius_factor >= 1.0:
            return None
        return self.brush().eps(self.sculptor.model_size)

    def _cursor_profile(self) -> np.ndarray | None:
        """The current brush's falloff samples (:func:`brush_profile`), cached per engine
        settings and brush; with :attr:`ring_in_background` the ring of new settings (~30-75
        ms) is computed on a worker thread, the previous one shown meanwhile."""
        if self.sculptor is None:
            return None
        brush = self.brush()
        eps = brush.eps(self.sculptor.model_size)
        ready = not self.ready()
        settings = self.sculptor.settings
        key = (id(self.sculptor), brush.kind, brush.influence, eps, ready)
        # the moved region in units of ε is the same at any ε: an F drag does not recompute it
        moving_key = (key[:3], ready, settings)
        done = self._ring_done
        if done is not None and done[0] == moving_key:  # computed on the worker thread
            self._ring_done = None
            self._moving_ratio, self._moving_key = done[1], moving_key
            self._profile_key = None  # the profile with the new influence, below
        if key == self._profile_key and settings is self._profile_settings:
            return self._profile
        if moving_key != self._moving_key:
            # only new settings go to the worker (a new mesh, brush or readiness: here)
            same = self._moving_key is not None and self._moving_key[:2] == moving_key[:2]
            if self.ring_in_background and self._profile is not None and ready and same:
                self._ring_start(moving_key, brush, eps)
                return self._profile  # the previous ring meanwhile
            self._moving_ratio = self._ring_ratio(brush, eps, ready)
            self._moving_key = moving_key
        influence = self._cursor_influence()
        try:
            kernel = self.sculptor.kernel(brush) if ready else None
            self._profile = brush_profile(kernel, influence, eps)
        except (ValueError, RuntimeError, np.linalg.LinAlgError):
            self._profile = brush_profile(None, influence, eps)
        self._profile_key, self._profile_settings = key, settings
        return self._profile

    def _ring_ratio(self, brush: Brush, eps: float, ready: bool) -> float:
        """The moved region's radius in units of ε (:func:`moving_radius`) of ``brush``."""
        assert self.sculptor is not None
        influence = self._cursor_influence(brush)
        anchored = brush_row(brush.kind).drag == "anchored"
        try:
            kernel = self.sculptor.kernel(brush) if ready else None
            moving = moving_radius(kernel, influence, eps, anchored)
            return moving / eps if eps > 0 else 1.0
        except (ValueError, RuntimeError, np.linalg.LinAlgError):
            return moving_radius(None, influence, 1.0)

    def _ring_start(self, moving_key: tuple[Any, ...], brush: Brush, eps: float) -> None:
        """Compute the ring of ``moving_key`` on a worker thread (one at a time)."""
        self._ring_wanted = (moving_key, brush, eps)
        if self._ring_thread is not None and self._ring_thread.is_alive():
            return

        def work() -> None:
            while True:
                wanted = self._ring_wanted
                if wanted is None:
                    return
                key, wanted_brush, wanted_eps = wanted
                with threads_at_most(1):
                    ratio = self._ring_ratio(wanted_brush, wanted_eps, True)
                self._ring_done = (key, ratio)
                if self._ring_wanted is wanted:
                    self._ring_wanted = None
                if self.ring_ready is not None:
                    self.ring_ready()

        self._ring_thread = threading.Thread(target=work, name="cursor ring", daemon=True)
        self._ring_thread.start()

    def _cursor_axes(self, point: np.ndarray) -> np.ndarray | None:
        """:func:`cursor_axes` where the cursor rests (None for a brush without a Green's
        function field)."""
        if self.sculptor is None or not isinstance(self.brush().type, GreenBrush):
            return None
        radius = self._cursor_radius()
        key = (id(self.sculptor), self.sculptor.settings, self.stroke.active)
        last = self._axes_at
        # the frame changes little over a fifth of ε: no new surface sample on every hover
        if last is not None and last[0] == key and np.linalg.norm(point - last[1]) < 0.2 * radius:
            return last[2]
        try:
            axes = cursor_axes(self.sculptor, point, radius)
        except ValueError:  # no surface to follow under the cursor
            axes = None
        self._axes_at = (key, np.array(point, dtype=float), axes)
        return axes

    def _cursor_moving_radius(self) -> float | None:
        """:func:`moving_radius` (model units) at the cursor's ε."""
        if self.sculptor is None or self._cursor_profile() is None:
            return None
        return self._moving_ratio * self._cursor_radius()

    def _cursor_detail(self) -> float | None:
        """Dynamic topology's edge length (model units) while it is on: the detail size, else
        the surface's median edge length (measured once per face array); None when off."""
        sculptor = self.sculptor
        if sculptor is None or not sculptor.settings.dynamic_topology:
            return None
        size = sculptor.settings.detail_size
        if size is not None:
            return float(size * sculptor.model_size)
        faces = sculptor.faces
        if self._detail_of[0] is not faces:
            sample = faces[:: max(1, len(faces) // DETAIL_SAMPLE_FACES)]
            self._detail_of = (faces, median_edge_length(sculptor.vertices, sample))
        return self._detail_of[1]

    # -- state -------------------------------------------------------------------------------
    @property
    def dragging(self) -> bool:
        return self.stroke.active or self.pin.active

    @property
    def has_pending(self) -> bool:
        return self._pending is not None or self._hover is not None

    # -- keys --------------------------------------------------------------------------------
    def pick_brush(self, key: str) -> bool:
        """A number key picks the brush whose row has it; True if ``key`` did."""
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
        ``screen``, the cursor's screen centre and ring radius (pixels) if it is shown."""
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
    def stroke_brush(self, modifiers: frozenset[str] = frozenset()) -> Brush:
        """The brush a stroke begun with ``modifiers`` held uses: with Shift the smooth brush
        at the current one's radius, influence and symmetry (Blender's habit)."""
        brush = self.brush()
        if "shift" in modifiers and brush.kind != SMOOTH:
            return replace(brush, kind=SMOOTH, substeps=0)
        return brush

    def press(self, event: PointerEvent) -> ToolUpdate:
        """Start a stroke, or add/grab a pin, at the picked ``event.point``."""
        if self.sculptor is None or self.dragging:
            return ToolUpdate()
        reason = self.ready() if self.mode == "brush" else None
        if reason:
            return ToolUpdate(error=reason, refused=True)
        self._pending, self.received, self.processed = None, 0, 0
        self._hover = None
        try:
            if self.mode == "pin":
                added = self.pin.press(event, self.first_pin_radius)
                return ToolUpdate(pins_changed=added)
            brush = self.stroke_brush(event.modifiers)
            moved = self.stroke.press(event, brush)
        except (ValueError, RuntimeError) as exc:
            self.pin.end()
            return ToolUpdate(error=str(exc))
        cursor = self.cursor.place(event.point, event.normal)
        if self.stroke.anchored and cursor is not None:  # the gauge, and the label
            at = (cursor.center, cursor.normal, cursor.radius)
            self._gauge = DeformationGauge.at_press(self.sculptor.vertices, *at)
            label = anchored_label(brush.kind)
            cursor = self.cursor.place(event.point, None, label, self._gauge_now())
        return ToolUpdate(moved=moved, cursor=cursor)

    def _gauge_now(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The anchored stroke's gauge now: loop (K, 3) and spokes (S, P, 3); None without."""
        if self._gauge is None or self.sculptor is None:
            return None
        positions = self._gauge.positions(self.sculptor.vertices)
        if positions is None:  # remeshed: the marks have nothing left to follow
            self._gauge = None
            return None
        return DeformationGauge.loop(positions), DeformationGauge.spokes(positions)

    def move(self, event: PointerEvent) -> None:
        """Record a drag move (applied by the next :meth:`flush`; newer moves replace it)."""
        if self.dragging:
            self._pending = event
            self.received += 1

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
        event, self._pending = self._pending, None
        if event is None:
            return ToolUpdate()
        self.processed += 1
        start = time.perf_counter()
        try:
            if self.pin.active:
                stepped = self.pin.step(event)
                update = ToolUpdate(all_moved=stepped, pins_changed=stepped)
            else:
                moved = self.stroke.step(event)
                stepped = moved is not None
                # the cursor sits where the brush acts: affine brushes at their press point
                if self.stroke.anchored:
                    label = anchored_label(cast(Brush, self.stroke.brush).kind)
                    cursor = self.cursor.place(self.stroke.anchor, None, label, self._gauge_now())
                else:
                    cursor = self.cursor.place(event.point, None)
                update = ToolUpdate(moved=moved, cursor=cursor)
        except (ValueError, RuntimeError) as exc:
            self._gauge = None
            self.stroke.cancel()
            self.pin.end()
            return ToolUpdate(all_moved=True, error=str(exc))
        if stepped:
            update.step_seconds = time.perf_counter() - start
        return update

    def release(self) -> ToolUpdate:
        """Apply the last recorded move, then end the stroke (one undo step; ``note`` says
        when it changed nothing) or the pin drag."""
        update = self.flush() if self._pending is not None else ToolUpdate()
        brush = self.stroke.brush
        history = self.sculptor.history if self.sculptor is not None else None
        steps = history.done if history is not None else 0
        moved = self.stroke.end()
        self.pin.end()
        if self._gauge is not None:  # the gauge shows the stroke acting: gone with it
            self._gauge = None
            state = self.cursor.state
            if state is not None:
                update.cursor = self.cursor.place(state.center, state.normal, state.label)
        # recorded nothing: no vertex moved and no mask value painted (a mask stroke moves none)
        recorded = history is not None and history.done != steps
        if brush is not None and moved is not None and not recorded:
            hint = "drag away from where you press" if brush.is_affine else "drag farther"
            mask = " and changed no mask value" if brush.type.family == "paint" else ""
            update.note = (
                f"Nothing changed: the {brush_row(brush.kind).label} stroke moved no vertex"
                f"{mask}, so it is not recorded ({hint})"
            )
        return update

    def remove_pin(self, event: PointerEvent) -> ToolUpdate:
        """Remove the pin near ``event.point`` (a right click in pin mode), if any."""
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
        self._pending = None
        self._gauge = None
        self.stroke.cancel()
        self.pin.end()
