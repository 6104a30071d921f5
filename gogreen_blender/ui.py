"""The GoGreen sidebar tab (3D view, N panel) and the GoGreen Sculpt tool in the toolbar."""

from __future__ import annotations

import bpy

from gogreen_core import PATTERNS

from . import compile_status, properties
from .drawing import TOOL_ID
from .jobs import RUNNER

__all__ = ["PANELS", "register_tools", "unregister_tools"]


class _GoGreenPanel:
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "GoGreen"


class VIEW3D_PT_gogreen(_GoGreenPanel, bpy.types.Panel):
    bl_label = "GoGreen Sculpt"

    def draw(self, context):
        layout = self.layout
        job = RUNNER.busy
        if job is not None:
            if job.progress is not None:
                layout.progress(factor=job.progress, type="BAR", text=job.status())
            else:
                layout.label(text=job.status(), icon="TIME")
        elif compile_status.status_line():  # the compilation, else the last outcome
            compiling = not compile_status.is_warm(context.scene.gogreen.l_max)
            icon = "TIME" if compiling else "INFO"
            layout.label(text=compile_status.status_line(), icon=icon)
        row = layout.row(align=True)
        row.operator("wm.tool_set_by_id", text="Sculpt Tool", icon="BRUSH_DATA").name = TOOL_ID
        row.operator("gogreen.compile_kernels", text="", icon="FILE_REFRESH")
        obj = context.active_object
        if obj is not None and obj.type == "MESH":
            mesh = obj.data
            row = layout.row(align=True)
            row.label(text="Mirror")
            for axis in "xyz":
                row.prop(mesh, f"use_mirror_{axis}", text=axis.upper(), toggle=True)


class VIEW3D_PT_gogreen_brush(_GoGreenPanel, bpy.types.Panel):
    bl_label = "Brush"
    bl_parent_id = "VIEW3D_PT_gogreen"

    def draw(self, context):
        s = context.scene.gogreen
        layout = self.layout
        layout.prop(s, "brush", text="")
        layout.row(align=True).prop(s, "radius_unit", expand=True)
        col = layout.column(align=True)
        col.prop(s, _radius_prop(s))
        col.prop(s, "strength")
        col.prop(s, "influence")
        layout.prop(s, "substeps")


def _draw_pattern(layout, s) -> None:
    """The homogenization inputs, the Compute button and the state of the result."""
    layout.prop(s, "pattern", text="")
    col = layout.column(align=True)
    for p in PATTERNS[s.pattern].parameters:
        col.prop(s, properties.pattern_prop(s.pattern, p.name))
    col = layout.column(align=True)
    col.prop(s, "phase_young")
    col.prop(s, "phase_poisson")
    col.prop(s, "contrast")
    col.prop(s, "resolution")
    row = layout.row()
    row.enabled = RUNNER.busy is None
    row.operator("gogreen.homogenize", text="Compute", icon="PLAY")
    if not s.homogenized_material:
        layout.label(text="Not computed yet", icon="ERROR")
    elif s.homogenized_inputs != properties.homogenization_inputs(s):
        layout.label(text="Inputs changed: compute again", icon="ERROR")


class VIEW3D_PT_gogreen_material(_GoGreenPanel, bpy.types.Panel):
    bl_label = "Material"
    bl_parent_id = "VIEW3D_PT_gogreen"

    def draw(self, context):
        s = context.scene.gogreen
        layout = self.layout
        row = layout.row(align=True)
        row.operator_menu_enum("gogreen.load_preset", "preset", text="Presets", icon="PRESET")
        row.operator("gogreen.load_preset_file", text="", icon="FILEBROWSER")
        row.operator("gogreen.save_preset", text="", icon="FILE_TICK")
        layout.prop(s, "material_mode", text="")
        col = layout.column(align=True)
        if s.material_mode == "ISOTROPIC":
            col.prop(s, "young")
            col.prop(s, "poisson")
        elif s.material_mode == "ORTHOTROPIC":
            col.prop(s, "ortho_young")
            col.prop(s, "ortho_shear")
            col.prop(s, "ortho_poisson")
        elif s.material_mode == "HOMOGENIZED":
            _draw_pattern(layout, s)
        else:
            col.label(text=s.custom_name or "No preset loaded", icon="MATERIAL")
        if s.material_mode != "ISOTROPIC":
            layout.prop(s, "material_frame")
            layout.prop(s, "rotation")


class VIEW3D_PT_gogreen_falloff(_GoGreenPanel, bpy.types.Panel):
    bl_label = "Falloff"
    bl_parent_id = "VIEW3D_PT_gogreen"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        s = context.scene.gogreen
        self.layout.prop(s, "falloff", text="")
        self.layout.prop(s, "l_max")


PANELS = (
    VIEW3D_PT_gogreen,
    VIEW3D_PT_gogreen_brush,
    VIEW3D_PT_gogreen_material,
    VIEW3D_PT_gogreen_falloff,
)


def _radius_prop(s) -> str:
    """The radius field of the scene's radius unit."""
    return "radius_pixels" if s.radius_unit == "VIEW" else "radius"


def _draw_tool_settings(context, layout, _tool):
    s = context.scene.gogreen
    layout.prop(s, "brush", text="")
    layout.prop(s, _radius_prop(s))
    layout.prop(s, "radius_unit", text="")
    layout.prop(s, "strength")


_KEYMAP = (
    ("gogreen.sculpt", {"type": "LEFTMOUSE", "value": "PRESS", "any": True}, None),
    ("gogreen.hover", {"type": "MOUSEMOVE", "value": "ANY", "any": True}, None),
    # as in Blender's sculpt mode: F the radius, Shift+F the strength
    (
        "gogreen.radial_control",
        {"type": "F", "value": "PRESS"},
        {"properties": [("target", "RADIUS")]},
    ),
    (
        "gogreen.radial_control",
        {"type": "F", "value": "PRESS", "shift": True},
        {"properties": [("target", "STRENGTH")]},
    ),
)


def _tool_class(mode: str) -> type:
    return type(
        f"VIEW3D_WT_gogreen_{mode.lower()}",
        (bpy.types.WorkSpaceTool,),
        {
            "bl_space_type": "VIEW_3D",
            "bl_context_mode": mode,
            "bl_idname": TOOL_ID,
            "bl_label": "GoGreen Sculpt",
            "bl_description": "Elastic sculpting with any material: drag on the mesh "
            "(Ctrl inverts, Esc or right click cancels the stroke); F sets the radius, Shift+F "
            "the strength",
            "bl_icon": "brush.uv_sculpt.grab",
            "bl_keymap": _KEYMAP,
            "draw_settings": staticmethod(_draw_tool_settings),
        },
    )


TOOLS = tuple(_tool_class(mode) for mode in ("OBJECT", "SCULPT"))


def register_tools() -> None:
    for tool in TOOLS:
        bpy.utils.register_tool(tool, separator=True)


def unregister_tools() -> None:
    for tool in TOOLS:
        bpy.utils.unregister_tool(tool)
