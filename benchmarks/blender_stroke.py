"""The Blender extension's cost per event and of a second stroke's first press (issue 37).

    NUMBA_CACHE_DIR=$PWD/.venv-blender/numba-cache \\
        .venv-blender/bin/python benchmarks/blender_stroke.py [--segments 1000] [--events 20]

Runs in ``.venv-blender`` (bpy 5.0.1, headless) on a UV sphere made by bpy (``--segments`` ×
``--segments / 2`` rings: 499,002 vertices by default), with the compiled kernels (prepared
first). Prints, figures only (medians and ranges):

* the tool's stroke through the 3D view of Blender's startup screen (the add-on's
  ``ObjectStroke`` with the window events a drag sends): the first press (the mesh's link
  made: triangles, sculptor, surface index), each event (the engine and writing the positions
  to Blender), the release, then the first hover and the second stroke's first press (the link
  kept in step with the mesh: no rebuild);
* the same steps as the add-on did them before (Blender's ``Object.ray_cast`` through a new
  depsgraph after each change of the mesh, positions read and written element by element
  with ``mesh.vertices.foreach_get/set("co")``, a new sculptor for each stroke): the pick after
  a stroke, the read and the write;
* ``gogreen.apply_stroke`` with one grab event (scripts), its first and second call;
* the raw array costs: ``mesh.attributes["position"].data.foreach_get/set`` against
  ``mesh.vertices.foreach_get/set("co")``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import bpy  # noqa: E402
from bpy_extras import view3d_utils  # noqa: E402
from mathutils import Vector  # noqa: E402

import gogreen_blender  # noqa: E402
from gogreen_blender import compile_status, mesh_access, mesh_link, operators, properties  # noqa: E402
from gogreen_core import Sculptor  # noqa: E402


class Event:
    """What the operator reads of a window event."""

    def __init__(self, type, value="NOTHING", x=0.0, y=0.0):
        self.type, self.value, self.ctrl, self.pressure = type, value, False, 1.0
        self.mouse_region_x, self.mouse_region_y = round(x), round(y)


def timed(fn):
    start = time.perf_counter()
    result = fn()
    return time.perf_counter() - start, result


def ms(seconds: float) -> str:
    return f"{1e3 * seconds:.1f} ms"


def summary(values: list[float]) -> str:
    return (
        f"median {ms(statistics.median(values))} (min {ms(min(values))}, max {ms(max(values))}, "
        f"{len(values)} runs)"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--segments", type=int, default=1000)
    parser.add_argument("--events", type=int, default=20)
    args = parser.parse_args()

    bpy.ops.wm.read_homefile()
    gogreen_blender.register()
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_uv_sphere_add(
        segments=args.segments, ring_count=args.segments // 2, radius=1.0
    )
    obj = bpy.context.active_object
    mesh = obj.data
    print(f"mesh: UV sphere, {len(mesh.vertices):,} vertices, {len(mesh.polygons):,} faces")
    scene = bpy.context.scene
    scene.gogreen.radius = 0.05
    seconds = compile_status.compile_now(scene.gogreen.l_max)
    print(f"compiled kernels ready: {seconds:.1f} s")

    n = len(mesh.vertices)
    buffer = np.empty(3 * n, np.float32)
    position = mesh.attributes["position"].data
    for label, fn in (
        ("attributes['position'] foreach_get", lambda: position.foreach_get("vector", buffer)),
        ("attributes['position'] foreach_set", lambda: position.foreach_set("vector", buffer)),
        ("vertices.foreach_get('co')", lambda: mesh.vertices.foreach_get("co", buffer)),
        ("vertices.foreach_set('co')", lambda: mesh.vertices.foreach_set("co", buffer)),
    ):
        print(f"{label}: {summary([timed(fn)[0] for _ in range(5)])}")

    area = next(a for a in bpy.context.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    rv3d = area.spaces.active.region_3d
    top = view3d_utils.location_3d_to_region_2d(region, rv3d, obj.matrix_world @ Vector((0, 0, 1)))
    x, y = top.x - 20.0, top.y - 30.0
    context = bpy.context

    def view():
        settings = properties.read_settings(scene, obj)
        link = mesh_access.link_for(obj, settings)
        region_view = operators.RegionView(context, region, rv3d, obj, link)
        return region_view

    def stroke(label: str) -> None:
        builds = mesh_link.MeshLink.builds
        press_time, tool = timed(
            lambda: operators.ObjectStroke.begin(
                context, obj, view(), operators.input_event(Event("LEFTMOUSE", "PRESS", x, y))
            )
        )
        assert tool is not None, "the press missed the mesh"
        events = []
        for k in range(1, args.events + 1):
            tool.handle(operators.input_event(Event("MOUSEMOVE", x=x + 2 * k, y=y + k)))
            events.append(timed(lambda: tool.handle(operators.input_event(Event("TIMER"))))[0])
        end = x + 2 * args.events, y + args.events
        release = timed(
            lambda: tool.handle(operators.input_event(Event("LEFTMOUSE", "RELEASE", *end)))
        )[0]
        rebuilt = mesh_link.MeshLink.builds - builds
        print(
            f"{label}: press {ms(press_time)} (links built: {rebuilt}); event {summary(events)}; "
            f"release {ms(release)}"
        )

    stroke("first stroke (the link made at the press)")
    hover = timed(lambda: view().pick(x + 5, y + 5))[0]
    print(f"first hover after it (sync and pick through our index): {ms(hover)}")
    stroke("second stroke (the link kept)")

    # before: Blender's ray_cast after a change of the mesh, element-wise reads and writes
    origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, (x, y))
    direction = view3d_utils.region_2d_to_vector_3d(region, rv3d, (x, y))
    picks = []
    for _ in range(3):
        mesh.vertices.foreach_set("co", buffer)
        mesh.update()
        depsgraph = context.evaluated_depsgraph_get()
        picks.append(timed(lambda d=depsgraph: obj.ray_cast(origin, direction, depsgraph=d))[0])
    print(f"before: Object.ray_cast after a stroke (Blender's tree rebuilt): {summary(picks)}")
    read_old = timed(lambda: mesh_access.read_mesh(mesh))[0]
    print(f"before: reading the mesh for each stroke (triangles and positions): {ms(read_old)}")
    vertices, faces = mesh_access.read_mesh(mesh)
    settings = properties.read_settings(scene, obj)
    fresh = timed(lambda: Sculptor(vertices, faces, settings=settings.engine_settings))[0]
    print(f"before: a new sculptor for each stroke: {ms(fresh)}")

    events = json.dumps([{"center": [0.0, 0.0, 1.0], "delta": [0.0, 0.0, 0.01]}])
    for call in ("first", "second"):
        seconds = timed(lambda: bpy.ops.gogreen.apply_stroke(kind="grab", events=events))[0]
        print(f"gogreen.apply_stroke, a 1-event grab, {call} call: {ms(seconds)}")


if __name__ == "__main__":
    main()
