"""Operators: the modal GoGreen Sculpt stroke, ``gogreen.apply_stroke`` for scripts, presets,
homogenization and kernel compilation.

Errors in the user's settings or input (a :class:`gogreen_core.ParameterError`, a
``ValueError``) become Blender error reports naming the problem, before the mesh changes.
"""

from __future__ import annotations

import contextlib
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
    Preset,
    builtin_presets,
    load_preset,
    save_preset,
)

from . import compile_status, drawing, engine, mesh_access, properties
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


@contextlib.contextmanager
def _compile_progress(context, settings):
    """Around an engine call on the main thread that may compile kernels: with a window, the
    mouse cursor shows progress and the status bar says why Blender waits."""
    cold = not bpy.app.background and not compile_status.is_warm(settings.l_max)
    workspace = context.workspace
    if cold:
        context.window_manager.progress_begin(0, 1)
        if workspace is not None:
            workspace.status_text_set(
                "GoGreen: compiling the brush kernels (first use only, about 30 s)..."
            )
    try:
        yield
    finally:
        if cold:
            context.window_manager.progress_end()
            if workspace is not None:
                workspace.status_text_set(None)


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
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and obj.mode in {"OBJECT", "SCULPT"}

    def execute(self, context):
        obj = context.active_object
        try:
            mesh_access.check_sculptable(obj)
            kind = None if self.kind == "SCENE" else self.kind
            settings = properties.read_settings(context.scene, obj, kind)
            events = engine.events_from_json(self.events)
        except ValueError as exc:
            return _report_error(self, exc)
        RUNNER.wait()  # a background job (compilation, homogenization) ends first
        vertices, faces = mesh_access.read_mesh(obj.data)
        start = time.perf_counter()
        try:
            with ENGINE_LOCK, _compile_progress(context, settings):
                result = engine.stroke(vertices, faces, settings, events)
        except ValueError as exc:
            return _report_error(self, exc)
        mesh_access.prepare_undo(obj)
        mesh_access.write_vertices(obj, result)
        mesh_access.stroke_done(obj)
        self.report(
            {"INFO"},
            f"GoGreen: {settings.brush.kind} stroke of {len(events)} events "
            f"({time.perf_counter() - start:.2f} s)",
        )
        return {"FINISHED"}


class RegionView:
    """:class:`~.modal.View` of a 3D view region on an object (object-space picks)."""

    def __init__(self, context, region, rv3d, obj) -> None:
        from bpy_extras import view3d_utils

        self._utils = view3d_utils
        self.region, self.rv3d, self.obj = region, rv3d, obj
        self.depsgraph = context.evaluated_depsgraph_get()
        self.matrix = obj.matrix_world.copy()
        self.inverse = self.matrix.inverted()

    def pick(self, x: float, y: float) -> np.ndarray | None:
        origin = self._utils.region_2d_to_origin_3d(self.region, self.rv3d, (x, y))
        direction = self._utils.region_2d_to_vector_3d(self.region, self.rv3d, (x, y))
        local_origin = self.inverse @ origin
        local_direction = self.inverse.to_3x3() @ direction
        hit, location, _normal, _index = self.obj.ray_cast(
            local_origin, local_direction, depsgraph=self.depsgraph
        )
        return np.array(location, dtype=float) if hit else None

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

    def __init__(self, obj, stroke: ModalStroke, view) -> None:
        self.obj, self.stroke, self.view = obj, stroke, view

    @classmethod
    def begin(cls, context, obj, view, event: InputEvent) -> ObjectStroke | None:
        mesh_access.check_sculptable(obj)
        settings = properties.read_settings(context.scene, obj)
        vertices, faces = mesh_access.read_mesh(obj.data)
        sculptor = engine.make_sculptor(vertices, faces, settings)
        stroke = ModalStroke(sculptor, settings.brush, view)
        with ENGINE_LOCK:
            if not stroke.start(event):
                return None
        mesh_access.prepare_undo(obj)
        self = cls(obj, stroke, view)
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
            self._write()
            raise
        if self.stroke.take_changed():
            self._write()
            self.show_cursor()
        if state == FINISHED:
            mesh_access.stroke_done(self.obj)
        return state

    def _write(self) -> None:
        mesh_access.write_vertices(self.obj, self.stroke.sculptor.vertices)


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
        obj = context.active_object
        return (
            context.area is not None
            and context.area.type == "VIEW_3D"
            and obj is not None
            and obj.type == "MESH"
            and obj.mode in {"OBJECT", "SCULPT"}
        )

    def invoke(self, context, event):
        busy = RUNNER.busy
        if busy is not None:
            self.report({"WARNING"}, f"GoGreen: wait a moment, {busy.status()}")
            return {"CANCELLED"}
        scene = context.scene
        if not bpy.app.background and not compile_status.is_warm(scene.gogreen.l_max):
            compile_status.request_warm_up(scene)
            self.report(
                {"WARNING"},
                "GoGreen: compiling the brush kernels first (once per machine, about 30 s); "
                "the panel shows the progress",
            )
            return {"CANCELLED"}
        region, rv3d = _window_region(context)
        if region is None or rv3d is None:
            self.report({"ERROR"}, "GoGreen: sculpt in a 3D view")
            return {"CANCELLED"}
        obj = context.active_object
        view = RegionView(context, region, rv3d, obj)
        try:
            self._stroke = ObjectStroke.begin(context, obj, view, input_event(event))
        except ValueError as exc:
            return _report_error(self, exc)
        if self._stroke is None:
            return {"PASS_THROUGH"}  # not on the mesh: let the click do what it would
        wm = context.window_manager
        self._timer = wm.event_timer_add(TICK_SECONDS, window=context.window)
        wm.modal_handler_add(self)
        context.area.tag_redraw()
        return {"RUNNING_MODAL"}

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
        region, rv3d = _window_region(context)
        state = None
        if obj is not None and obj.type == "MESH" and region is not None and rv3d is not None:
            view = RegionView(context, region, rv3d, obj)
            point = view.pick(event.mouse_region_x, event.mouse_region_y)
            if point is not None:
                s = context.scene.gogreen
                corners = np.array(obj.bound_box, dtype=float)
                size = float(np.linalg.norm(corners.max(axis=0) - corners.min(axis=0)))
                eps = s.radius * size
                state = view.cursor(
                    point, eps, engine.influence_of(properties.read_settings(context.scene)) * eps
                )
        if state is not None or drawing.cursor() is not None:
            drawing.set_cursor(state)
            context.area.tag_redraw()
        return {"PASS_THROUGH"}


# -- presets --------------------------------------------------------------------------------
def apply_preset(scene, preset: Preset) -> None:
    """Set the scene's material, falloff, l_max, wrinkle weights and brush from ``preset``."""
    s = scene.gogreen
    s.material_mode = "CUSTOM"
    s.custom_material = engine.material_to_json(preset.material)
    s.custom_name = preset.name
    s.rotation = (0.0, 0.0, 0.0)
    falloff = preset.falloff
    if type(falloff) is GaussianRadial:
        s.falloff = "GAUSSIAN"
    elif type(falloff) is KelvinletRadial:
        s.falloff = "KELVINLET"
    else:
        s.falloff = "CUSTOM"
        s.custom_falloff = json.dumps(falloff.to_dict())
    s.l_max = preset.l_max
    s.brush_weights = json.dumps({k: list(w) for k, w in preset.brush_weights.items()})
    brush = preset.brush
    s.brush, s.radius, s.strength = brush.kind, brush.radius, brush.strength
    s.substeps = brush.substeps
    # an automatic influence is stored as 0, an infinite one as the largest float
    s.influence = 0.0 if brush.auto_influence else brush.influence


def preset_from_scene(scene, name: str) -> Preset:
    """The scene's settings as a :class:`gogreen_core.Preset` (ParameterError if invalid)."""
    settings = properties.read_settings(scene)
    return Preset(
        name=name,
        material=settings.material,
        falloff=settings.falloff,
        l_max=settings.l_max,
        brush_weights=settings.brush_weights,
        brush=settings.brush,
        description="Saved from Blender",
    )


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
        apply_preset(context.scene, chosen)
        compile_status.request_warm_up(context.scene)
        return {"FINISHED"}


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
        apply_preset(context.scene, preset)
        compile_status.request_warm_up(context.scene)
        self.report({"INFO"}, f"GoGreen: loaded preset {preset.name!r}")
        return {"FINISHED"}


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
        if bpy.app.background:
            try:
                settings = properties.read_settings(context.scene)
            except ValueError as exc:
                return _report_error(self, exc)
            with ENGINE_LOCK:
                engine.warm_up(settings)
            compile_status.mark_warm(settings.l_max)
            return {"FINISHED"}
        if not compile_status.request_warm_up(context.scene):
            self.report({"INFO"}, f"GoGreen: {compile_status.status_line() or 'kernels ready'}")
        return {"FINISHED"}


CLASSES = (
    GOGREEN_OT_apply_stroke,
    GOGREEN_OT_sculpt,
    GOGREEN_OT_hover,
    GOGREEN_OT_load_preset,
    GOGREEN_OT_load_preset_file,
    GOGREEN_OT_save_preset,
    GOGREEN_OT_homogenize,
    GOGREEN_OT_compile_kernels,
)
