"""Sculpt through the Blender extension and render the result with Workbench (no window).

Run with the Blender tests' environment (``bash scripts/setup_blender_env.sh`` makes it)::

    .venv-blender/bin/python scripts/blender_demo.py gogreen_blender.png

Three sheets get the same pull through ``bpy.ops.gogreen.apply_stroke``: "Soft clay"
(isotropic: a round bump), "Wood grain" (orthotropic, the grain tilted 30°: a lopsided bump) and
"Layered sheet wrinkles" (a homogenized laminate whose layers are tilted 45°, wrinkle brush: the
surface ripples along the layers). Prints the seconds each stroke took.
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import bpy

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import gogreen_blender  # noqa: E402  (the add-on, registered from this checkout)

#: A pull up out of the middle of a 2 x 2 sheet, 1.5 ε (ε = 0.05 of the sheet's diagonal) in
#: all, in 15 mouse events.
EPS = 0.05 * 2 * math.sqrt(2)
PULL = [{"center": [0.0, 0.0, EPS * i / 10], "delta": [0.0, 0.0, EPS / 10]} for i in range(15)]
#: Presets of the three sheets, left to right, and their brush.
SHEETS = (
    ("Soft clay", "grab"),
    ("Wood grain", "grab"),
    ("Layered sheet wrinkles", "wrinkle"),
)


def sheet(name: str, x: float):
    bpy.ops.mesh.primitive_grid_add(
        x_subdivisions=160, y_subdivisions=160, size=2.0, location=(x, 0.0, 0.0)
    )
    obj = bpy.context.active_object
    obj.name = name
    bpy.ops.object.shade_smooth()
    return obj


def stroke(obj, preset: str, kind: str, events: list[dict]) -> None:
    for other in bpy.context.view_layer.objects:
        other.select_set(other is obj)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.gogreen.load_preset(preset=preset)
    bpy.context.scene.gogreen.radius = 0.05
    start = time.perf_counter()
    bpy.ops.gogreen.apply_stroke(kind=kind, events=json.dumps(events))
    print(f"{obj.name}: {preset}, {kind}: {time.perf_counter() - start:.2f} s")


def main(path: str) -> None:
    bpy.ops.wm.read_homefile(use_empty=True)
    gogreen_blender.register()
    for number, (preset, kind) in enumerate(SHEETS):
        stroke(sheet(preset, 2.3 * (number - 1)), preset, kind, PULL)

    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    shading = scene.display.shading
    shading.light, shading.color_type = "STUDIO", "SINGLE"
    shading.single_color = (0.8, 0.62, 0.45)
    shading.show_cavity, shading.cavity_type = True, "BOTH"
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.location = (0.0, -5.6, 4.6)
    camera.rotation_euler = (math.radians(52), 0.0, 0.0)
    camera.data.lens = 32
    scene.render.resolution_x, scene.render.resolution_y = 1500, 460
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    gogreen_blender.unregister()
    print(f"wrote {path}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "gogreen_blender.png")
