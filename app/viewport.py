"""The 3D viewport: a pyvistaqt QtInteractor where the left mouse button sculpts.

Mouse map (Blender's, :mod:`app.navigation`): left drag sculpts (one that starts off the model
sculpts once it reaches it; preference: it orbits), middle drag orbits, Shift+middle pans,
Ctrl+middle and the wheel zoom (the "classic" scheme: right drag orbits, middle pans);
Ctrl+wheel changes the brush radius and Shift+wheel the strength. Keys are the window's
(app.keymap) and the tools' (F, number keys): none reaches VTK's interactor, whose default keys
(and pyvista's) would act behind the app's back.

The stroke loop: the viewport translates Qt mouse events into plain
:class:`gogreen_core.interaction.tools.PointerEvent` (the world point under the cursor, picked on
press and hover, on the drag plane through the press point while dragging, or on the surface
under the cursor while a paint brush sweeps over it), hands them to its
Qt-free :class:`gogreen_core.interaction.tools.SculptTools` (:meth:`SculptViewport.set_tools`) and
draws the :class:`~gogreen_core.interaction.tools.ToolUpdate` each call gives back
(:meth:`SculptViewport.draw`); what the window must know (a message, an error, a step's time, a
stroke's end) leaves as signals. Drag moves are coalesced: the tools keep the newest and one
zero-timer per event-loop turn applies it (:meth:`SculptViewport.flush_tools`), so a burst of moves
costs one brush step. Slow steps run on a worker thread (:mod:`app.stroke_worker`).

It renders on demand only: :meth:`SculptViewport.request_render` coalesces every request made
before control returns to the event loop into one render (pyvistaqt's periodic
``auto_update`` render is off), and hover picking is coalesced the same way, so an idle window
uses no CPU and a burst of mouse moves costs one pick and one render. Camera input too: wheel
notches add up until the event loop is idle and then zoom once (about the point under the
cursor, :meth:`CameraViews.zoom_at`), and an orbit, pan or zoom drag hands VTK's trackball
style only the newest move per event-loop turn, its own render held back for the one requested
render: a burst of notches or moves that arrives while a slow frame draws costs one more frame.
Where full frames are slow, camera and stroke frames draw a lighter copy of a big mesh, the
full mesh again once they settle (:mod:`app.level_of_detail`).

The brush cursor shows where the brush acts: on the surface under a hovering pointer (again as
soon as a stroke ends, without waiting for a move), at the press point while an affine brush
acts (labelled so); in pin mode the pointer is a pin and no brush ring is drawn.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from PySide6.QtCore import QEvent, QPointF, Qt, QTimer, Signal
from PySide6.QtGui import QCursor, QKeyEvent, QMouseEvent, QTabletEvent, QWheelEvent
from PySide6.QtWidgets import QWidget
from pyvistaqt import QtInteractor

from app.icons import icon_pixmap
from app.mesh_display import BACKGROUND_INDEX_FACES, HOME_VIEW_DIRECTION, PIN_COLOR, MeshDisplay
from app.navigation import ZOOM_STEP, CameraViews, camera_gesture, vtk_button
from app.stroke_worker import StrokeWorker
from gogreen_core.interaction.tools import PointerEvent, SculptTools, ToolUpdate

__all__ = ["BACKGROUND_INDEX_FACES", "HOME_VIEW_DIRECTION", "SculptViewport"]

_MODIFIER_NAMES = (
    ("shift", Qt.KeyboardModifier.ShiftModifier),
    ("ctrl", Qt.KeyboardModifier.ControlModifier),
    ("alt", Qt.KeyboardModifier.AltModifier),
)


def _mute_vtk_keys(iren: Any) -> None:
    """No VTK or pyvista key binding may act (app.keymap is the app's only keymap): keys are
    not passed to the interactor (:meth:`SculptViewport.keyPressEvent`), and should one arrive
    by another path, pyvista's key callbacks (q, b, v, Shift+C, Up, Down, plus, minus) are gone
    and the style's default key actions (p outline, s / w, r, e / q, f, 3, j / t / c / a) are
    replaced by observers that do nothing."""
    iren.clear_key_event_callbacks()
    style = iren.interactor.GetInteractorStyle()
    for event in ("CharEvent", "KeyPressEvent", "KeyReleaseEvent"):
        style.AddObserver(event, lambda *_args: None)


# pyvistaqt's QtInteractor itself joins QWidget.update and BasePlotter.update
class SculptViewport(CameraViews, MeshDisplay, QtInteractor):  # type: ignore[misc]
    """Viewport with the stroke loop, a brush cursor ring, in-place mesh updates and
    on-demand rendering.

    Signals
    -------
    pointer_pressed(PointerEvent) : a left press on the model handed to the tools.
    hovered() : a hover was handed to the tools (the cursor moved, or left the model).
    tool_message(str) : what the tools refused and why (e.g. kernels still compiling).
    tool_error(str, str) : (title, message) of an engine error; the stroke was cancelled.
    step_timed(float) : milliseconds of the engine step just drawn.
    stroke_ended() : a stroke or pin drag ended (the document may have changed).
    radius_wheel(int), strength_wheel(int) : +1 / -1 per wheel notch with Ctrl / Shift.
    frame_rendered(float) : milliseconds of a render just done.
    surface_progress(float) : fraction done of a background :class:`SurfaceIndex` build.
    surface_ready() : that build ended; picking and smooth shading work from now on.
    surface_failed(str) : that build failed (the error).
    surface_pending() : a left press while that build runs (no stroke started).
    """

    pointer_pressed = Signal(object)
    hovered = Signal()
    #: The tools' worker has the ring of new settings (emitted on its thread).
    _ring_computed = Signal()
    tool_message = Signal(str)
    tool_error = Signal(str, str)
    step_timed = Signal(float)
    #: A tool step gave the mesh new faces (dynamic topology): show the new mesh.
    faces_replaced = Signal()
    stroke_ended = Signal()
    radius_wheel = Signal(int)
    strength_wheel = Signal(int)
    frame_rendered = Signal(float)
    surface_progress = Signal(float)
    surface_ready = Signal()
    surface_failed = Signal(str)
    surface_pending = Signal()

    def __init__(self, parent: QWidget | None = None) -> None:
        # auto_update=False: no periodic render (pyvistaqt's default re-renders 5 times a
        # second, which alone kept a core busy with software OpenGL)
        # multisampling once the renderer is known not to be software (app.level_of_detail)
        super().__init__(parent, auto_update=False, multi_samples=0)
        plotter: Any = self  # pyvista's argument-checking decorator hides these signatures
        plotter.set_background("#2b2f36", top="#4a5260")
        plotter.enable_trackball_style()
        _mute_vtk_keys(self.iren)
        self._init_display()
        #: The Qt-free tools pointer events go to (:meth:`set_tools`); None: nothing sculpts.
        self.tools: SculptTools | None = None
        #: Navigation scheme (a key of app.navigation.NAVIGATIONS) and what a left drag that
        #: starts off the model does ("sculpt" once it reaches the model, or "orbit").
        self.navigation = "blender"
        self.left_on_background = "sculpt"
        #: Depth (display z) of the drag plane while the left button drags on the model.
        self._drag_depth: float | None = None
        #: The stroke gave the mesh new faces (dynamic topology), drawn without a full rebuild.
        self._faces_in_stroke = False
        #: The camera drag going on: (the Qt button held, VTK's button doing the gesture).
        self._camera: tuple[Qt.MouseButton, Qt.MouseButton] | None = None
        #: A left drag that started off the model, waiting to reach it (Blender's habit).
        self._reaching = False
        self._hover_pos: QPointF | None = None
        #: Pen pressure of the latest tablet event (1 for a mouse), given to the tools.
        self._pressure = 1.0
        self._hover_timer = self._zero_timer(self._hover_now)
        self._ring_computed.connect(self.refresh_cursor)
        self._flush_timer = self._zero_timer(self.flush_tools)
        #: Runs slow brush steps off the GUI thread (moves, the release and undo wait there).
        self.stroke_worker = StrokeWorker(self)
        #: Wheel notches not yet applied (a sum: a touchpad gives fractions) and where the
        #: pointer was at the newest; the newest camera drag move not yet handed to VTK.
        self._wheel_notches = 0.0
        self._wheel_pos = QPointF()
        self._wheel_timer = self._zero_timer(self.apply_wheel)
        self._camera_move: QMouseEvent | None = None
        self._camera_timer = self._zero_timer(self.apply_camera_move)
        #: The wheel zooms about the point under the cursor (else about the view's centre).
        self.zoom_to_mouse = True
        #: Renders done and the duration of the last one (ms), measured by VTK's own events.
        self.frames = 0
        self.last_frame_ms = 0.0
        self._render_pending = False
        self._frame_start = 0.0
        window = self.ren_win
        assert window is not None
        window.AddObserver("StartEvent", self._frame_started)
        window.AddObserver("EndEvent", self._frame_ended)
        self.setMouseTracking(True)
        # takes the keyboard focus when clicked, and back from fields (app.keyboard)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)

    def close(self) -> None:  # type: ignore[override]  # pyvistaqt.QtInteractor.close
        """Close the plotter; a matcap's texture first gives back what it holds in the render
        window (else VTK reports the window deleted first), and pyvistaqt's GL-surface wrapper."""
        self.lod.settle_timer.stop()
        self.stroke_worker.stop()
        actor, window = self.mesh_actor, self.ren_win
        if actor is not None and window is not None and actor.GetTexture() is not None:
            actor.GetTexture().ReleaseGraphicsResources(window)
        super().close()
        getattr(self, "_forget_context", lambda: None)()  # else its QSurface wrapper goes stale

    def _zero_timer(self, slot: Callable[[], None]) -> QTimer:
        timer = QTimer(self)
        timer.setSingleShot(True)
        timer.setInterval(0)
        timer.timeout.connect(slot)
        return timer

    # -- rendering ---------------------------------------------------------------------------
    def request_render(self) -> None:
        """Render once when control returns to the event loop.

        A Qt ``update()``: requests made before the next paint merge into one paint, and the
        widget's paint is where pyvistaqt renders. (``render()`` renders at once and then
        schedules that paint, which renders again: two renders per frame.)"""
        self._render_pending = True
        self.update()

    def render_now(self) -> None:
        """Render at once (tests, screenshots); a paint (one more render) follows."""
        self.render()

    def _frame_started(self, *_args) -> None:
        self._frame_start = time.perf_counter()

    def _frame_ended(self, *_args) -> None:
        self.last_frame_ms = 1e3 * (time.perf_counter() - self._frame_start)
        self.lod.frame_ended(self.last_frame_ms)
        self.frames += 1
        self._render_pending = False
        self.frame_rendered.emit(self.last_frame_ms)

    @property
    def render_pending(self) -> bool:
        """A requested render has not happened yet."""
        return self._render_pending

    # -- the stroke loop ---------------------------------------------------------------------
    def set_tools(self, tools: SculptTools | None) -> None:
        """Hand pointer events (and the F / Shift+F drags, number keys) to ``tools``."""
        self.tools = tools
        if tools is not None:  # new settings' ring on a worker: the pointer never waits for it
            tools.ring_in_background = True
            tools.ring_ready = self._ring_computed.emit  # queued to the GUI thread

    def flush_tools(self) -> None:
        """Apply the newest recorded move or hover (older ones were coalesced) and draw it (a
        slow step: once it ended on the worker)."""
        self._flush_timer.stop()
        self.stroke_worker.flush()

    def _schedule_flush(self) -> None:
        if not self._flush_timer.isActive():
            self._flush_timer.start()

    def draw(self, update: ToolUpdate, error_title: str = "Brush stopped") -> None:
        """Draw what the tools changed (one render is requested for all of it) and tell the
        window about refusals, errors and step times."""
        sculptor = self.tools.sculptor if self.tools is not None else None
        if sculptor is not None and self._faces is not None and sculptor.faces is not self._faces:
            if self.in_stroke:  # dynamic topology: drawn at once, indexed when the stroke ends
                change = sculptor.remesher.mesh.renumbering  # how its faces came
                self.set_mesh(
                    sculptor.vertices, sculptor.faces, False, in_stroke=True, renumbering=change
                )
                self.show_mask_of(sculptor)
                self._faces_in_stroke = True
            else:
                self.faces_replaced.emit()  # the window shows the new mesh (vertices and faces)
        elif sculptor is not None and update.all_moved:
            self.update_vertices(sculptor.vertices)
        elif sculptor is not None and update.moved is not None:
            self.update_vertices(sculptor.vertices, update.moved)
        if sculptor is not None and update.changed:
            self.show_mask_of(sculptor, update.moved)  # a mask stroke's rows
        if update.refused:  # not an error: e.g. kernels still compiling
            self.tool_message.emit(f"{error_title}: {update.error}")
        elif update.error:
            self.tool_error.emit(error_title, update.error)
        if update.note:
            self.tool_message.emit(update.note)
        if sculptor is None or not update.changed:
            return
        if update.step_seconds:
            self.step_timed.emit(1e3 * update.step_seconds)
        if update.pins_changed:
            self.show_pins(sculptor.constraint_points, sculptor.constraint_reach)
        drag = self.tools.value_drag if self.tools is not None else None
        self.cursor_overlay.profile_now = drag is not None and drag.name == "radius"
        if update.cursor is not None:
            # pin mode: the pointer is a pin (set_pin_mode), no brush ring or profile
            self.show_cursor(None if self.pin_mode and drag is None else update.cursor)
        elif update.hide_cursor:
            self.show_cursor(None)
        self.request_render()

    @property
    def pin_mode(self) -> bool:
        """Presses pin (the tools' mode is "pin")."""
        return self.tools is not None and self.tools.mode == "pin"

    def set_pin_mode(self, on: bool) -> None:
        """The pointer as a pin over the view (presses pin), the brush ring hidden; or back."""
        if on:
            self.setCursor(QCursor(icon_pixmap("pin", 32, PIN_COLOR), 16, 28))  # the pin's tip
            self.show_cursor(None)
        else:
            self.unsetCursor()
            self.rehover()

    def show_sculptor(self, indices=None) -> None:
        """Draw the tools' sculptor as it is (after undo, redo, a script): the vertices that
        differ (or ``indices``) and the pins; the cursor hides until the pointer moves."""
        if self.tools is None or self.tools.sculptor is None:
            return
        sculptor = self.tools.sculptor
        self.tools.cursor.hide()
        self.show_cursor(None)
        self.update_vertices(sculptor.vertices, indices)
        self.show_mask_of(sculptor)
        self.show_pins(sculptor.constraint_points, sculptor.constraint_reach)

    def refresh_cursor(self) -> None:
        """The brush changed: the ring shows its new radius at once (after a running step)."""
        if self.stroke_worker.running:
            self.stroke_worker.after_step(self.refresh_cursor)
        elif self.tools is not None and self.tools.cursor.state is not None:
            if self.tools.sculptor is not None:
                self.show_cursor(self.tools.cursor.refresh())

    def pointer_event(
        self,
        pos: QPointF,
        point=None,
        normal=None,
        modifiers: Qt.KeyboardModifier = Qt.KeyboardModifier.NoModifier,
        pressure: float | None = None,
    ) -> PointerEvent:
        """A plain :class:`PointerEvent` for widget position ``pos`` (pressure: the pen's)."""
        pressure = self._pressure if pressure is None else pressure
        view, right = self._view_axes()
        names = frozenset(name for name, flag in _MODIFIER_NAMES if modifiers & flag)
        return PointerEvent((pos.x(), pos.y()), point, normal, view, right, float(pressure), names)

    def tabletEvent(self, ev: QTabletEvent) -> None:
        """Keep the pen's pressure; Qt then sends the mouse event made from this one."""
        touching = ev.type() != QTabletEvent.Type.TabletRelease and bool(ev.buttons())
        self._pressure = float(ev.pressure()) if touching else 1.0  # hover: a mouse's 1
        ev.ignore()

    # -- keys and value drags (F / Shift+F) ---------------------------------------------------
    @property
    def value_dragging(self) -> bool:
        return self.tools is not None and self.tools.value_drag is not None

    def start_value_drag(self, name: str, pos: QPointF | None = None) -> None:
        """Begin dragging the brush ``"radius"`` (F) or ``"strength"`` (Shift+F) with the
        pointer at ``pos`` (default: where it is now): moving sets it live, a click or Enter
        confirms, Escape or a right click restores it."""
        if self.tools is None or self.in_stroke:
            return
        if pos is None:
            pos = QPointF(self.mapFromGlobal(self.cursor().pos()))
        center, ring = None, None
        if self.cursor_overlay.screen is not None and self.cursor_overlay.ring_pixels:
            (x, y), _, _ = self.cursor_overlay.screen
            ring = self.cursor_overlay.ring_pixels  # the drawn ring's edge follows the pointer
            ratio = self.devicePixelRatioF() or 1.0
            center, ring = (x / ratio, self.height() - 1 - y / ratio), ring / ratio
        self._hover_timer.stop()
        self.draw(self.tools.start_value_drag(name, (pos.x(), pos.y()), center, ring))

    def finish_value_drag(self, confirm: bool) -> None:
        if self.tools is not None and self.value_dragging:
            self.draw(self.tools.finish_value_drag(confirm))

    def keyPressEvent(self, ev: QKeyEvent) -> None:
        key, mods = ev.key(), ev.modifiers()
        if self.value_dragging:
            if key in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
                self.finish_value_drag(True)
            elif key == Qt.Key.Key_Escape:
                self.finish_value_drag(False)
            ev.accept()  # nothing else while dragging a value
            return
        plain = not mods & ~Qt.KeyboardModifier.ShiftModifier & ~Qt.KeyboardModifier.KeypadModifier
        if key == Qt.Key.Key_F and plain and self.tools is not None:
            shift = bool(mods & Qt.KeyboardModifier.ShiftModifier)
            self.start_value_drag("strength" if shift else "radius")
            ev.accept()
            return
        if plain and self.tools is not None and self.tools.pick_brush(ev.text()):
            ev.accept()
            return
        # not to VTK (its and pyvista's default keys would act): Qt gives it to the parent
        ev.ignore()

    def keyReleaseEvent(self, ev: QKeyEvent) -> None:
        ev.ignore()  # not to VTK either

    # -- mouse -----------------------------------------------------------------------------
    @staticmethod
    def _as_button(ev: QMouseEvent, button: Qt.MouseButton) -> QMouseEvent:
        """``ev`` as VTK's trackball style should see it: ``button`` (held while dragging),
        no modifiers (the gesture was chosen already)."""
        pressed = ev.type() != QEvent.Type.MouseMove
        held = button if ev.type() != QEvent.Type.MouseButtonRelease else Qt.MouseButton.NoButton
        return QMouseEvent(
            ev.type(),
            ev.position(),
            ev.globalPosition(),
            button if pressed else Qt.MouseButton.NoButton,
            held,
            Qt.KeyboardModifier.NoModifier,
        )

    def _start_camera(self, ev: QMouseEvent, gesture: str) -> None:
        self._camera = (ev.button(), vtk_button(gesture))
        self._hover_timer.stop()
        self.lod.interaction_frames()
        super().mousePressEvent(self._as_button(ev, self._camera[1]))

    def mousePressEvent(self, ev: QMouseEvent) -> None:
        self.setFocus(Qt.FocusReason.MouseFocusReason)
        if self.value_dragging:
            self.finish_value_drag(ev.button() != Qt.MouseButton.RightButton)
            return
        if self._camera is not None or self._drag_depth is not None or self._reaching:
            return  # one drag at a time
        button = ev.button()
        if button == Qt.MouseButton.LeftButton and self.surface_building:
            self.surface_pending.emit()  # nothing to pick on yet: no stroke, no orbit
            return
        if button == Qt.MouseButton.LeftButton:
            if self._press_on_surface(ev):
                return
            if self.left_on_background == "orbit":
                self._start_camera(ev, "orbit")
            else:
                self._reaching = True  # sculpts once the drag reaches the model
            return
        if button == Qt.MouseButton.RightButton and self._remove_pin(ev.position()):
            return
        gesture = camera_gesture(self.navigation, button, ev.modifiers())
        if gesture is not None:
            self._start_camera(ev, gesture)

    def _press_on_surface(self, ev: QMouseEvent) -> bool:
        """A left press on the model: the tools start a stroke (or a pin) there (True);
        False off the model."""
        hit = self.pick(ev.position())
        if hit is None:
            return False
        self._reaching = False
        if self.stroke_worker.refuse_press():  # the last stroke's release waits for its step
            return True
        point, normal = hit
        self._drag_depth = self._depth(point)
        self._hover_timer.stop()
        self.lod.interaction_frames()
        event = self.pointer_event(ev.position(), point, normal, ev.modifiers())
        if self.tools is not None:
            self.stroke_worker.press(event)
        self.pointer_pressed.emit(event)
        return True

    def _remove_pin(self, pos: QPointF) -> bool:
        """In pin mode, a right click on a pin removes it (True); elsewhere it orbits."""
        if self.tools is None or self.tools.mode != "pin" or self.in_stroke:
            return False
        hit = self.pick(pos)
        if hit is None:
            return False
        update = self.tools.remove_pin(self.pointer_event(pos, hit[0], hit[1]))
        if not update.changed:
            return False
        self.draw(update, "Pin")
        self.stroke_ended.emit()
        return True

    def mouseMoveEvent(self, ev: QMouseEvent) -> None:
        if self.value_dragging and self.tools is not None:
            pos = ev.position()
            self.draw(self.tools.move_value_drag((pos.x(), pos.y())))
            return
        if self._drag_depth is not None:
            point = self._unproject(ev.position(), self._drag_depth)
            if self.tools is not None and self.tools.stroke.sweeping:
                hit = self.pick(ev.position())  # a paint stroke follows the surface
                point = point if hit is None else hit[0]
            event = self.pointer_event(ev.position(), point, None, ev.modifiers())
            if self.tools is not None and not self.stroke_worker.move(event):
                self.tools.move(event)
                self._schedule_flush()
            return
        if self._reaching:
            self._press_on_surface(ev)  # the drag reached the model: the stroke starts there
            return
        if self._camera is not None:  # the newest move, handed to VTK when the loop is idle
            self._camera_move = self._as_button(ev, self._camera[1])
            if not self._camera_timer.isActive():
                self._camera_timer.start()
            return
        super().mouseMoveEvent(ev)
        if not ev.buttons():  # hover: pick once for the newest position
            self._hover_pos = ev.position()
            if not self._hover_timer.isActive():
                self._hover_timer.start()

    def rehover(self) -> None:
        """The camera moved under a still pointer: pick what is under it now (the brush
        cursor follows), as a hover would."""
        if self.in_stroke or self.value_dragging or not self.underMouse():
            return
        self._hover_pos = QPointF(self.mapFromGlobal(self.cursor().pos()))
        if not self._hover_timer.isActive():
            self._hover_timer.start()

    def _hover_now(self) -> None:
        """The newest hover position, picked and handed to the tools (the ring follows)."""
        if self._hover_pos is None or self._drag_depth is not None or self.tools is None:
            return
        pos, self._hover_pos = self._hover_pos, None
        hit = self.pick(pos)
        point, normal = hit if hit is not None else (None, None)
        self.tools.hover(self.pointer_event(pos, point, normal))
        self.flush_tools()
        self.hovered.emit()

    def leaveEvent(self, ev: QEvent) -> None:
        super().leaveEvent(ev)
        self._pointer_gone()

    def event(self, ev: QEvent) -> bool:
        if ev.type() == QEvent.Type.WindowDeactivate:  # a dialog or another window has the input
            self._pointer_gone()
        return super().event(ev)

    def _pointer_gone(self) -> None:
        """The pointer left the view (in any jump) or the window lost the input: hide the brush
        cursor until the next hover over the model. A miss is handed to the tools as the newest
        hover, so they forget the cursor too and a hover still queued cannot bring it back. Not
        during a stroke or an F / Shift+F drag, which keep their cursor."""
        if self.in_stroke or self.value_dragging:
            return
        self._hover_timer.stop()
        self._hover_pos = None
        if not self.cursor_visible and (self.tools is None or self.tools.cursor.state is None):
            return  # nothing shown: no event, no render
        self.show_cursor(None)
        if self.tools is not None:
            pos = QPointF(self.mapFromGlobal(self.cursor().pos()))
            self.tools.hover(self.pointer_event(pos, None))
            self.flush_tools()
            self.hovered.emit()

    def mouseReleaseEvent(self, ev: QMouseEvent) -> None:
        if self._drag_depth is not None and ev.button() == Qt.MouseButton.LeftButton:
            self._drag_depth = None
            self._flush_timer.stop()
            self.stroke_worker.release(ev.position())  # (after a running step)
            return
        if self._reaching and ev.button() == Qt.MouseButton.LeftButton:
            self._reaching = False  # the drag never reached the model
            return
        if self._camera is not None and ev.button() == self._camera[0]:
            self.apply_camera_move()  # the drag's last move first
            button, self._camera = self._camera[1], None
            interactor = self.iren.interactor
            interactor.EnableRenderOff()  # VTK renders as a gesture ends: one request instead
            try:
                super().mouseReleaseEvent(self._as_button(ev, button))
            finally:
                interactor.EnableRenderOn()
            if not self.in_stroke:  # the copy's catch-up reads the mesh: after the steps
                self.lod.show_full()
            self.request_render()
            self.rehover()

    def apply_camera_move(self) -> None:
        """Hand VTK's trackball style the newest camera drag move (older ones were
        coalesced: it turns, pans or zooms by the motion since the last move it saw); its own
        render is held back for one requested render."""
        self._camera_timer.stop()
        move, self._camera_move = self._camera_move, None
        if move is None or self._camera is None:
            return
        interactor = self.iren.interactor
        interactor.EnableRenderOff()
        try:
            super().mouseMoveEvent(move)
        finally:
            interactor.EnableRenderOn()
        self.request_render()

    def wheelEvent(self, ev: QWheelEvent) -> None:
        notches = 1 if ev.angleDelta().y() > 0 else -1
        if ev.modifiers() & Qt.KeyboardModifier.ControlModifier:
            self.radius_wheel.emit(notches)
        elif ev.modifiers() & Qt.KeyboardModifier.ShiftModifier:
            self.strength_wheel.emit(notches)
        else:  # zoom: the notches add up until the event loop is idle (apply_wheel)
            self._wheel_notches += ev.angleDelta().y() / 120.0
            self._wheel_pos = ev.position()
            if not self._wheel_timer.isActive():
                self._wheel_timer.start()
        ev.accept()

    def apply_wheel(self) -> None:
        """Zoom by the wheel notches received since the last call, in one step: about the
        point under the pointer (:attr:`zoom_to_mouse`) or the view's centre; one render."""
        self._wheel_timer.stop()
        notches, self._wheel_notches = self._wheel_notches, 0.0
        if notches:
            self.lod.interaction_frames()
            self.zoom_at(self._wheel_pos if self.zoom_to_mouse else None, ZOOM_STEP**notches)
            if self.lod.shown and not self.in_stroke and self._camera is None:
                self.lod.settle_timer.start()  # a drag's release shows the full mesh itself

    @property
    def in_stroke(self) -> bool:
        """The left button is dragging on the model (or was released while a step ran)."""
        return self._drag_depth is not None or self.stroke_worker.release_pos is not None
