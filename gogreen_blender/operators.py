"""Operators: the modal GoGreen Sculpt stroke, ``gogreen.apply_stroke`` for scripts, presets,
homogenization and kernel compilation.

Errors in the user's settings or input (a :class:`gogreen_core.ParameterError`, a
``ValueError``) become Blender error reports naming the problem, before the mesh changes.
"""

from __future__ import annotations

import dataclasses
import json
import time
from pathlib import Path

import bpy
import numpy as np
from bpy.props import EnumProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper
from mathutils import Vector

from gogreen_core import (
    GaussianRadial,
    KelvinletRadial,
    ParameterError,
    Preset,
    builtin_presets,
    load_preset,
    save_preset,
)
from gogreen_core.sculpt.setting_table import rows

from . import compile_status, drawing, engine, mesh_access, properties, radial
from .jobs import ENGINE_LOCK, RUNNER
from .modal import CANCELLED, FINISHED, RUNNING, InputEvent, ModalStroke

__all__ = ["ObjectStroke", "RegionView", "apply_preset", "preset_from_scene"]

#: Seconds between the timer ticks that apply the newest mouse move of a stroke.
TICK_SECONDS = 1.0 / 60.0


def _report_error(operator, exc: Exception) -> set[str]:
    operator.report({"ERROR"}, f"GoGreen: {exc}")
    return {"CANCELLED"}


def _kind_items(_self, _context):
    return _KIND_ITEMS


_KIND_ITEMS = [("SCENE", "Scene's brush", "The brush chosen in the GoGreen panel")] + [
    (k, engine.brush_label(k), f"The {k} brush") for k in engine.ADDON_BRUSH_KINDS
]


class GOGREEN_OT_apply_stroke(bpy.types.Operator):
    """Apply one GoGreen stroke to the active mesh (events in object space), as the tool would"""

    bl_idname = "gogreen.apply_stroke"
    bl_label = "Apply GoGreen Stroke"
    bl_options = {"REGISTER", "UNDO"}

    kind: EnumProperty(name="Brush", items=_kind_items)
    events: StringProperty(
        name="Events",
        description="JSON list of events in object space, as in session files: "
        '[{"center": [x, y, z], "delta": [dx, dy, dz]}, ...]; scale, twist and pinch take '
        '"amount", "axis", "direction"; "radius_factor" scales the radius of one event',
        default="[]",
    )

    @classmethod
    def poll(cls, context):
        return _poll_sculptable(cls, context)

    def execute(self, context):
        obj = context.active_object
        try:
            mesh_access.check_sculptable(obj)
            kind = None if self.kind == "SCENE" else self.kind
            settings = properties.read_settings(context.scene, obj, kind)
            events = engine.events_from_json(self.events)
            if not events:
                raise ParameterError("events", "a stroke needs at least one event")
        except ValueError as exc:
            return _report_error(self, exc)
        RUNNER.wait()  # a background job (homogenization) ends first
        start = time.perf_counter()
        with ENGINE_LOCK:
            link = mesh_access.link_for(obj, settings)
            try:
                link.use(settings)
                link.moved(link.sculptor.apply_brush(settings.brush, events))
            except ValueError as exc:
                return _report_error(self, exc)
            finally:
                link.stroke_done()
        mesh_access.prepare_undo(obj)
        mesh_access.write_positions(obj, link.positions)
        mesh_access.stroke_done(obj)
        self.report(
            {"INFO"},
            f"GoGreen: {settings.brush.kind} stroke of {len(events)} events "
            f"({time.perf_counter() - start:.2f} s)",
        )
        return {"FINISHED"}


def _poll_sculptable(cls, context, need_view: bool = False) -> bool:
    """An operator's poll: a mesh in object or sculpt mode is active (and, with
    ``need_view``, the mouse is in a 3D view); else Blender shows why not."""
    if need_view and (context.area is None or context.area.type != "VIEW_3D"):
        cls.poll_message_set("GoGreen sculpts in a 3D view")
        return False
    obj = context.active_object
    if obj is None:
        cls.poll_message_set("GoGreen needs an active mesh object: select one")
        return False
    if obj.type != "MESH":
        cls.poll_message_set(f"GoGreen sculpts meshes; the active object {obj.name!r} is a "
                             f"{obj.type.lower()}")  # fmt: skip
        return False
    if obj.mode not in {"OBJECT", "SCULPT"}:
        cls.poll_message_set("GoGreen sculpts in object or sculpt mode")
        return False
    return True


class RegionView:
    """:class:`~.modal.View` of a 3D view region on an object (object-space picks)."""

    def __init__(self, context, region, rv3d, obj, link) -> None:
        from bpy_extras import view3d_utils

        self._utils = view3d_utils
        self.region, self.rv3d, self.obj, self.link = region, rv3d, obj, link
        self.matrix = obj.matrix_world.copy()
        self.inverse = self.matrix.inverted()

    def pick(self, x: float, y: float) -> np.ndarray | None:
        """The base mesh's surface under (x, y), through the link's surface index (Blender's
        ``ray_cast`` would rebuild its search tree after every stroke)."""
        origin = self._utils.region_2d_to_origin_3d(self.region, self.rv3d, (x, y))
        direction = self._utils.region_2d_to_vector_3d(self.region, self.rv3d, (x, y))
        local_origin = np.array(self.inverse @ origin, dtype=float)
        local_direction = np.array(self.inverse.to_3x3() @ direction, dtype=float)
        return self.link.pick(local_origin, local_direction)

    def units_per_pixel(self, point: np.ndarray) -> float:
        """Object-space length of one region pixel at the depth of ``point`` (3,)."""
        world = self.matrix @ Vector(point)
        at = self._utils.location_3d_to_region_2d(self.region, self.rv3d, world)
        if at is None:  # behind the view
            return 0.0
        beside = self._utils.region_2d_to_location_3d(
            self.region, self.rv3d, (at.x + 1.0, at.y), world
        )
        return float(np.linalg.norm(np.array(self.inverse @ beside) - np.asarray(point)))

    def drag_point(self, x: float, y: float, depth: np.ndarray) -> np.ndarray:
        world_depth = self.matrix @ Vector(depth)
        point = self._utils.region_2d_to_location_3d(self.region, self.rv3d, (x, y), world_depth)
        return np.array(self.inverse @ point, dtype=float)

    def _local_direction(self, world: Vector) -> np.ndarray:
        local = np.array(self.inverse.to_3x3() @ world, dtype=float)
        return local / np.linalg.norm(local)

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        rotation = self.rv3d.view_rotation
        return (
            self._local_direction(rotation @ Vector((0.0, 0.0, -1.0))),
            self._local_direction(rotation @ Vector((1.0, 0.0, 0.0))),
        )

    def cursor(self, center: np.ndarray, eps: float, reach: float) -> drawing.CursorState:
        """The brush circle at object-space ``center`` with object-space radii."""
        rotation = self.rv3d.view_rotation
        scale = float(np.mean(np.abs(self.matrix.to_scale())))
        return drawing.CursorState(
            center=np.array(self.matrix @ Vector(center), dtype=float),
            right=np.array(rotation @ Vector((1.0, 0.0, 0.0)), dtype=float),
            up=np.array(rotation @ Vector((0.0, 1.0, 0.0)), dtype=float),
            radius=eps * scale,
            reach=reach * scale,
        )


def _brush_radii(brush, sculptor) -> tuple[float, float]:
    """ε and the influence radius (model units) of ``brush`` on ``sculptor``'s mesh (an
    automatic influence resolved by the engine)."""
    eps = brush.eps(sculptor.model_size)
    return eps, sculptor.influence(brush) * eps


def input_event(event) -> InputEvent:
    """The parts of a ``bpy.types.Event`` (or any object with those attributes) a stroke
    reads."""
    return InputEvent(
        type=event.type,
        value=event.value,
        x=float(event.mouse_region_x),
        y=float(event.mouse_region_y),
        ctrl=bool(event.ctrl),
        pressure=float(getattr(event, "pressure", 1.0) or 1.0),
    )


class ObjectStroke:
    """A :class:`~.modal.ModalStroke` on a Blender object: what the modal operator runs.

    :meth:`begin` starts it at a press (None when the press misses the mesh); :meth:`handle`
    takes each later event, writes moved vertices to the mesh and returns the operator state.
    Errors in the settings raise :class:`ParameterError` before anything moves; an event the
    engine refuses cancels the stroke (the mesh as before it) and is re-raised.
    """

    def __init__(self, obj, stroke: ModalStroke, view, link) -> None:
        self.obj, self.stroke, self.view, self.link = obj, stroke, view, link

    @classmethod
    def begin(cls, context, obj, view, event: InputEvent) -> ObjectStroke | None:
        """``view``'s link is the object's (:func:`mesh_access.link_for`), synced."""
        mesh_access.check_sculptable(obj)
        settings = properties.read_settings(context.scene, obj)
        link = view.link
        brush = settings.brush
        with ENGINE_LOCK:
            link.use(settings)
            if context.scene.gogreen.radius_unit == "VIEW":
                point = view.pick(event.x, event.y)
                if point is None:
                    return None
                brush = dataclasses.replace(
                    brush, radius=properties.view_radius(context.scene, view, point, link)
                )
            stroke = ModalStroke(link.sculptor, brush, view)
            if not stroke.start(event):
                return None
        mesh_access.prepare_undo(obj)
        self = cls(obj, stroke, view, link)
        self._write()  # a paint brush's dab
        self.show_cursor()
        return self

    def show_cursor(self) -> None:
        if hasattr(self.view, "cursor") and self.stroke.center is not None:
            eps, reach = _brush_radii(self.stroke.brush, self.stroke.sculptor)
            drawing.set_cursor(self.view.cursor(self.stroke.center, eps, reach))

    def handle(self, event: InputEvent) -> str:
        try:
            with ENGINE_LOCK:
                state = self.stroke.handle(event)
        except ValueError:
            self.stroke.cancel()
            self._end()
            raise
        if state in (FINISHED, CANCELLED):
            self._end()
            if state == FINISHED:
                mesh_access.stroke_done(self.obj)
        elif self.stroke.take_changed():
            self._write()
            self.show_cursor()
        return state

    def _write(self) -> None:
        """The rows moved since the last write, to the mesh."""
        rows = self.stroke.take_rows()
        if len(rows):
            self.link.moved(rows)
            mesh_access.write_positions(self.obj, self.link.positions)

    def _end(self) -> None:
        """The stroke ended or was cancelled: the mesh as the sculptor has it (float32)."""
        self.link.moved(self.stroke.take_rows())
        self.link.stroke_done()
        mesh_access.write_positions(self.obj, self.link.positions)


def object_view(context, obj, settings, check_topology: bool = True) -> RegionView | None:
    """The :class:`RegionView` of the context's 3D view on ``obj``, whose link is in step with
    the mesh (None outside a 3D view)."""
    region, rv3d = _window_region(context)
    if region is None or rv3d is None:
        return None
    with ENGINE_LOCK:
        link = mesh_access.link_for(obj, settings, check_topology)
    return RegionView(context, region, rv3d, obj, link)


def _window_region(context):
    """The 3D view's main region and its view data, or (None, None)."""
    area = context.area
    if area is None or area.type != "VIEW_3D":
        return None, None
    region = context.region
    if region is None or region.type != "WINDOW":
        region = next((r for r in area.regions if r.type == "WINDOW"), None)
    return region, area.spaces.active.region_3d


class GOGREEN_OT_sculpt(bpy.types.Operator):
    """Sculpt the active mesh with the GoGreen brush: drag on the mesh (Ctrl inverts; Esc or
    right click cancels the stroke)"""

    bl_idname = "gogreen.sculpt"
    bl_label = "GoGreen Sculpt"
    bl_options = {"REGISTER", "UNDO", "BLOCKING"}

    @classmethod
    def poll(cls, context):
        return _poll_sculptable(cls, context, need_view=True)

    def invoke(self, context, event):
        ended = self.begin(context, event)
        if ended is not None:
            return ended
        wm = context.window_manager
        self._timer = wm.event_timer_add(TICK_SECONDS, window=context.window)
        wm.modal_handler_add(self)
        context.area.tag_redraw()
        return {"RUNNING_MODAL"}

    def begin(self, context, event) -> set[str] | None:
        """Start the stroke at the press ``event`` (``self._stroke``); None if it started,
        else the operator's result."""
        busy = RUNNER.busy
        if busy is not None:  # a homogenization (compilation never blocks a stroke)
            self.report({"WARNING"}, f"GoGreen: wait a moment, {busy.status()}")
            return {"CANCELLED"}
        # Before the kernels are compiled the engine runs the same arithmetic in NumPy (and
        # asks for them in the background): a stroke never waits for the compiler.
        compile_status.request_warm_up(context.scene)
        obj = context.active_object
        try:
            mesh_access.check_sculptable(obj)
            view = object_view(context, obj, properties.read_settings(context.scene, obj))
        except ValueError as exc:
            return _report_error(self, exc)
        if view is None:
            self.report({"ERROR"}, "GoGreen: sculpt in a 3D view")
            return {"CANCELLED"}
        try:
            self._stroke = ObjectStroke.begin(context, obj, view, input_event(event))
        except ValueError as exc:
            return _report_error(self, exc)
        if self._stroke is None:
            return {"PASS_THROUGH"}  # not on the mesh: let the click do what it would
        return None

    def modal(self, context, event):
        try:
            state = self._stroke.handle(input_event(event))
        except ValueError as exc:
            state = CANCELLED
            self.report({"ERROR"}, f"GoGreen: {exc}")
        if context.area is not None:
            context.area.tag_redraw()
        if state != RUNNING:
            context.window_manager.event_timer_remove(self._timer)
            drawing.set_cursor(None)
        return {state}


class GOGREEN_OT_hover(bpy.types.Operator):
    """Show the GoGreen brush circle under the mouse"""

    bl_idname = "gogreen.hover"
    bl_label = "GoGreen Brush Circle"
    bl_options = {"INTERNAL"}

    def invoke(self, context, event):
        obj = context.active_object
        state = None
        if obj is not None and obj.type == "MESH" and obj.mode in {"OBJECT", "SCULPT"}:
            try:
                settings = properties.read_settings(context.scene, obj)
            except ValueError:  # said at the press; the circle shows the defaults' reach
                settings = engine.default_settings(context.scene.gogreen.l_max)
            view = object_view(context, obj, settings, check_topology=False)
            point = None if view is None else view.pick(event.mouse_region_x, event.mouse_region_y)
            if point is not None:
                eps = properties.eps_at(context.scene, view, point, view.link)
                state = view.cursor(point, eps, engine.influence_of(settings) * eps)
        if state is not None or drawing.cursor() is not None:
            drawing.set_cursor(state)
            context.area.tag_redraw()
        return {"PASS_THROUGH"}


class GOGREEN_OT_radial_control(bpy.types.Operator):
    """Drag the GoGreen brush's radius (F) or strength (Shift+F) on screen: click or Enter
    keeps it, Esc or right click puts it back"""

    bl_idname = "gogreen.radial_control"
    bl_label = "GoGreen Radius / Strength"
    bl_options = {"REGISTER", "UNDO", "BLOCKING"}

    target: EnumProperty(
        name="Set",
        items=[("RADIUS", "Radius", "The brush radius"), ("STRENGTH", "Strength", "")],
    )

    @classmethod
    def poll(cls, context):
        return _poll_sculptable(cls, context, need_view=True)

    def invoke(self, context, event):
        try:
            self.start(context, event)
        except ValueError as exc:
            return _report_error(self, exc)
        if not bpy.app.background:
            self._draw = bpy.types.SpaceView3D.draw_handler_add(
                drawing.draw_radial, (self._control,), "WINDOW", "POST_PIXEL"
            )
        context.window_manager.modal_handler_add(self)
        context.area.tag_redraw()
        return {"RUNNING_MODAL"}

    def start(self, context, event) -> None:
        """The :class:`~.radial.RadialControl` of the target (``self._control``)."""
        s = context.scene.gogreen
        x, y = float(event.mouse_region_x), float(event.mouse_region_y)
        if self.target == "STRENGTH":
            self._prop, low, high, scale = "strength", 0.0, 10.0, radial.STRENGTH_PIXELS
        elif s.radius_unit == "VIEW":
            self._prop, low, high, scale = "radius_pixels", 1.0, 5000.0, 1.0
        else:  # the model fraction's pixels at the surface under the mouse (or the origin)
            obj = context.active_object
            view = object_view(context, obj, properties.read_settings(context.scene, obj))
            if view is None:
                raise ParameterError("radius", "set the radius in a 3D view")
            point = view.pick(x, y)
            if point is None:
                point = np.zeros(3)
            per_pixel = view.units_per_pixel(point)
            if not per_pixel > 0.0:
                raise ParameterError("radius", "the object is behind the view")
            self._prop, low, high = "radius", 0.001, 1.0
            scale = view.link.model_size / per_pixel
        self._control = radial.RadialControl(getattr(s, self._prop), low, high, scale, x, y)

    def modal(self, context, event):
        control = self._control
        state = control.handle(input_event(event))
        value = round(control.value) if self._prop == "radius_pixels" else control.value
        setattr(context.scene.gogreen, self._prop, value)
        if context.area is not None:
            context.area.tag_redraw()
        if state != RUNNING and getattr(self, "_draw", None) is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self._draw, "WINDOW")
            self._draw = None
        return {state}


# -- presets --------------------------------------------------------------------------------
def preset_rows() -> tuple:
    """The scene properties of the setting table that a preset sets."""
    return tuple(r for r in properties.table_rows() if "preset" in r.places)


def preset_values(preset: Preset, current_kind: str) -> tuple[dict[str, object], str]:
    """The scene settings ``preset`` sets, by name, and a note of what it could not (empty
    when none): a preset of the mask brush keeps ``current_kind`` (Blender paints its own
    sculpt mask, which GoGreen's strokes respect)."""
    falloff = preset.falloff
    values: dict[str, object] = {
        "material_mode": "CUSTOM",
        "custom_material": engine.material_to_json(preset.material),
        "custom_name": preset.name,
        "rotation": (0.0, 0.0, 0.0),
        "material_frame": preset.material_frame,
    }
    if type(falloff) is GaussianRadial:
        values["falloff"] = "GAUSSIAN"
    elif type(falloff) is KelvinletRadial:
        values["falloff"] = "KELVINLET"
    else:
        values["falloff"] = "CUSTOM"
        values["custom_falloff"] = json.dumps(falloff.to_dict())
    values.update({r.name: getattr(preset.settings, r.name) for r in preset_rows()})
    values["brush_weights"] = json.dumps({k: list(w) for k, w in preset.brush_weights.items()})
    brush = preset.brush
    if brush.kind not in engine.ADDON_BRUSH_KINDS:
        label = engine.brush_label(brush.kind)
        note = (
            f"the preset's brush is the {label} brush, which GoGreen leaves to Blender (paint "
            f"with Blender's own Mask brush: GoGreen's strokes respect its mask); the "
            f"{engine.brush_label(current_kind)} brush stays"
        )
        return values, note
    values.update(brush=brush.kind, radius=brush.radius, strength=brush.strength)
    values["substeps"] = brush.substeps
    # an automatic influence is stored as 0, an infinite one as the largest float
    values["influence"] = 0.0 if brush.auto_influence else brush.influence
    return values, ""


def apply_preset(scene, preset: Preset) -> str:
    """Set the scene's material, falloff, l_max, weights and brush from ``preset``, all or
    nothing: a value Blender refuses, or settings that do not make a valid engine setting,
    leave the scene as it was (ParameterError naming the preset). Returns the note of what it
    could not set (see :func:`preset_values`), empty when none."""
    s = scene.gogreen
    values, note = preset_values(preset, s.brush)
    saved = {name: _plain(getattr(s, name)) for name in values}
    try:
        for name, value in values.items():
            setattr(s, name, value)
        properties.read_settings(scene)
    except (TypeError, ValueError) as exc:
        for name, value in saved.items():
            setattr(s, name, value)
        message = f"preset {preset.name!r} was not applied: {exc}"
        raise ParameterError("preset", message) from None
    return note


def _plain(value):
    """A property's value as a plain Python value (vectors as tuples)."""
    return tuple(value) if hasattr(value, "__len__") and not isinstance(value, str) else value


def _applied(operator, context, preset: Preset) -> set[str]:
    """Apply ``preset`` for ``operator`` and report what it could not set."""
    try:
        note = apply_preset(context.scene, preset)
    except ValueError as exc:
        return _report_error(operator, exc)
    compile_status.request_warm_up(context.scene)
    if note:
        operator.report({"WARNING"}, f"GoGreen: loaded preset {preset.name!r}; {note}")
    else:
        operator.report({"INFO"}, f"GoGreen: loaded preset {preset.name!r}")
    return {"FINISHED"}


def preset_from_scene(scene, name: str) -> Preset:
    """The scene's settings as a :class:`gogreen_core.Preset` (ParameterError if invalid)."""
    settings = properties.read_settings(scene)
    values = {r.name: getattr(settings.engine_settings, r.name) for r in rows("preset")}
    return Preset(name, brush=settings.brush, description="Saved from Blender", **values)


_builtin: list[Preset] | None = None


def builtin() -> list[Preset]:
    global _builtin
    if _builtin is None:
        _builtin = builtin_presets()
    return _builtin


def _preset_items(_self, _context):
    global _PRESET_ITEMS
    _PRESET_ITEMS = [(p.name, p.name, p.description) for p in builtin()]
    return _PRESET_ITEMS


_PRESET_ITEMS: list = []  # Blender needs the enum item strings kept alive


class GOGREEN_OT_load_preset(bpy.types.Operator):
    """Use a built-in GoGreen preset (material, falloff and brush), as in the desktop app"""

    bl_idname = "gogreen.load_preset"
    bl_label = "Load GoGreen Preset"
    bl_options = {"REGISTER", "UNDO"}

    preset: EnumProperty(name="Preset", items=_preset_items)

    def execute(self, context):
        chosen = next((p for p in builtin() if p.name == self.preset), None)
        if chosen is None:
            self.report({"ERROR"}, f"GoGreen: no preset named {self.preset!r}")
            return {"CANCELLED"}
        return _applied(self, context, chosen)


class GOGREEN_OT_load_preset_file(bpy.types.Operator, ImportHelper):
    """Load a GoGreen preset file (.json, shared with the desktop app)"""

    bl_idname = "gogreen.load_preset_file"
    bl_label = "Load GoGreen Preset File"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})

    def execute(self, context):
        try:
            preset = load_preset(self.filepath)
        except (OSError, ValueError) as exc:
            return _report_error(self, exc)
        return _applied(self, context, preset)


class GOGREEN_OT_save_preset(bpy.types.Operator, ExportHelper):
    """Save the GoGreen settings as a preset file the desktop app can load"""

    bl_idname = "gogreen.save_preset"
    bl_label = "Save GoGreen Preset"

    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})

    def execute(self, context):
        try:
            preset = preset_from_scene(context.scene, Path(self.filepath).stem)
            save_preset(preset, self.filepath)
        except (OSError, ValueError) as exc:
            return _report_error(self, exc)
        self.report({"INFO"}, f"GoGreen: saved {self.filepath}")
        return {"FINISHED"}


class GOGREEN_OT_homogenize(bpy.types.Operator):
    """Compute the effective material of the pattern (in the background when there is a
    window)"""

    bl_idname = "gogreen.homogenize"
    bl_label = "Homogenize Pattern"

    def execute(self, context):
        try:
            problem = compile_status.start_homogenization(context.scene)
        except ValueError as exc:
            return _report_error(self, exc)
        if problem is not None:
            self.report({"WARNING"}, problem)
            return {"CANCELLED"}
        message = compile_status.last_message()
        if bpy.app.background and message.startswith("Homogenization failed"):
            self.report({"ERROR"}, f"GoGreen: {message}")
            return {"CANCELLED"}
        return {"FINISHED"}


class GOGREEN_OT_compile_kernels(bpy.types.Operator):
    """Compile the GoGreen brush kernels for the current l_max now (once per machine)"""

    bl_idname = "gogreen.compile_kernels"
    bl_label = "Compile GoGreen Kernels"

    def execute(self, context):
        l_max = context.scene.gogreen.l_max
        if bpy.app.background:  # scripts: wait for them
            with ENGINE_LOCK:
                compile_status.compile_now(l_max)
            return {"FINISHED"}
        compile_status.request_warm_up(context.scene)
        self.report({"INFO"}, f"GoGreen: {compile_status.status_line() or 'kernels ready'}")
        return {"FINISHED"}


CLASSES = (
    GOGREEN_OT_apply_stroke,
    GOGREEN_OT_sculpt,
    GOGREEN_OT_hover,
    GOGREEN_OT_radial_control,
    GOGREEN_OT_load_preset,
    GOGREEN_OT_load_preset_file,
    GOGREEN_OT_save_preset,
    GOGREEN_OT_homogenize,
    GOGREEN_OT_compile_kernels,
)
