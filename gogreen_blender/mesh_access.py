"""Reading and writing a Blender mesh's vertices, and the undo step a stroke needs.

Blender stores positions in single precision: a stroke reads them as float64 (exactly), sculpts
in float64 and writes the result back rounded to float32.

Undo: a stroke is one operator call with the UNDO flag, so Blender records one global-undo step
after it. In sculpt mode the step before is usually a sculpt-mode step, whose decoding does not
bring back positions changed outside Blender's brushes (undoing the first GoGreen stroke after
entering sculpt mode, or after a Blender brush stroke, would do nothing). So the first stroke
after such a step pushes a global step of the state before it (:func:`prepare_undo`); strokes
that follow one another do not.
"""

from __future__ import annotations

import hashlib

import bpy
import numpy as np

from gogreen_core import ParameterError

__all__ = ["check_sculptable", "prepare_undo", "read_mesh", "stroke_done", "write_vertices"]

#: (object session id, fingerprint of its positions) after the last GoGreen stroke in sculpt
#: mode, while no other undo step can have come after it; None otherwise.
_last_stroke: tuple[int, bytes] | None = None
_MSGBUS_OWNER = object()


def check_sculptable(obj) -> None:
    """ParameterError naming why ``obj`` cannot be sculpted (None if it can)."""
    if obj is None or obj.type != "MESH":
        raise ParameterError("object", "the active object must be a mesh")
    if obj.mode not in {"OBJECT", "SCULPT"}:
        raise ParameterError("object", "GoGreen sculpts in object or sculpt mode")
    if obj.mode == "SCULPT" and obj.use_dynamic_topology_sculpting:
        raise ParameterError("object", "GoGreen cannot sculpt with dynamic topology (Dyntopo) on")
    if obj.data.shape_keys is not None:
        raise ParameterError("object", "GoGreen does not sculpt meshes with shape keys yet")
    if len(obj.data.vertices) == 0:
        raise ParameterError("object", "the mesh has no vertices")


def read_vertices(mesh) -> np.ndarray:
    """(N, 3) float64 positions in object space."""
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def read_mesh(mesh) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) float64 positions and (M, 3) int64 triangles of ``mesh``."""
    mesh.calc_loop_triangles()
    tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return read_vertices(mesh), tris.reshape(-1, 3).astype(np.int64)


def write_vertices(obj, vertices: np.ndarray) -> None:
    """Store ``vertices`` (N, 3) as ``obj``'s positions and tell Blender they changed."""
    mesh = obj.data
    mesh.vertices.foreach_set("co", np.ascontiguousarray(vertices, dtype=np.float32).ravel())
    mesh.update()


def _fingerprint(mesh) -> bytes:
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    return hashlib.blake2b(co.tobytes(), digest_size=16).digest()


def prepare_undo(obj) -> None:
    """Before a stroke changes ``obj``: in sculpt mode, unless the last undo step is a GoGreen
    stroke on it, push a global undo step of the state before the stroke."""
    if obj.mode != "SCULPT":
        return
    if _last_stroke == (obj.session_uid, _fingerprint(obj.data)):
        return
    bpy.ops.ed.undo_push(message="GoGreen: before stroke")


def stroke_done(obj) -> None:
    """After a stroke was written: remember it, so the next one needs no extra undo step."""
    global _last_stroke
    _last_stroke = (obj.session_uid, _fingerprint(obj.data)) if obj.mode == "SCULPT" else None


@bpy.app.handlers.persistent
def forget_stroke(*_args) -> None:
    """Undo, redo, a file load or a mode change: the last step may be anything now."""
    global _last_stroke
    _last_stroke = None


def _watch_modes() -> None:
    bpy.msgbus.clear_by_owner(_MSGBUS_OWNER)
    bpy.msgbus.subscribe_rna(
        key=(bpy.types.Object, "mode"), owner=_MSGBUS_OWNER, args=(), notify=forget_stroke
    )


@bpy.app.handlers.persistent
def _loaded(*_args) -> None:
    forget_stroke()
    _watch_modes()  # a file load drops the message bus subscriptions


_HANDLERS = (("undo_post", forget_stroke), ("redo_post", forget_stroke), ("load_post", _loaded))


def register() -> None:
    for name, handler in _HANDLERS:
        getattr(bpy.app.handlers, name).append(handler)
    _watch_modes()


def unregister() -> None:
    bpy.msgbus.clear_by_owner(_MSGBUS_OWNER)
    for name, handler in _HANDLERS:
        handlers = getattr(bpy.app.handlers, name)
        if handler in handlers:
            handlers.remove(handler)
    forget_stroke()
