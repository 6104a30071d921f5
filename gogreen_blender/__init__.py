"""GoGreen Sculpt for Blender: elastic sculpting with any linear elastic material.

An extension (Blender 4.2+) around ``gogreen_core``, the engine of the GoGreen Sculpt desktop
app (Chen & Desbrun, "Go Green: General Regularized Green's Functions for Elasticity", 2022):
the GoGreen Sculpt tool in the 3D view's toolbar (object and sculpt mode), the GoGreen tab of
the sidebar for its settings (stored on the scene), and ``bpy.ops.gogreen.apply_stroke`` for
scripts. The modules that do not import ``bpy`` (:mod:`.engine`, :mod:`.modal`, :mod:`.jobs`)
run and are tested outside Blender too; the others load when the add-on registers.
"""

from __future__ import annotations

_REGISTERED: list = []


def register() -> None:
    import bpy

    from . import compile_status, drawing, mesh_access, operators, properties, ui

    properties.register()
    for cls in (*operators.CLASSES, *ui.PANELS):
        bpy.utils.register_class(cls)
    ui.register_tools()
    mesh_access.register()
    compile_status.register()
    handle = bpy.types.SpaceView3D.draw_handler_add(drawing.draw_cursor, (), "WINDOW", "POST_VIEW")
    _REGISTERED.append(handle)


def unregister() -> None:
    import bpy

    from . import compile_status, drawing, mesh_access, operators, properties, ui

    while _REGISTERED:
        bpy.types.SpaceView3D.draw_handler_remove(_REGISTERED.pop(), "WINDOW")
    drawing.set_cursor(None)
    compile_status.unregister()
    mesh_access.unregister()
    ui.unregister_tools()
    for cls in reversed((*operators.CLASSES, *ui.PANELS)):
        bpy.utils.unregister_class(cls)
    properties.unregister()
