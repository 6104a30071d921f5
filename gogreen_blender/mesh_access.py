"""Reading and writing a Blender mesh's vertices, the add-on's link to each mesh, and the undo
step a stroke needs.

Blender stores positions in single precision: a stroke reads them as float64 (exactly), sculpts
in float64 and writes the result back rounded to float32. Positions, the sculpt mask, hidden
vertices and face corners are read and written as whole attribute arrays
(``mesh.attributes[name].data.foreach_get``/``foreach_set``: a copy of the array, 0.3 ms for
655k positions, where ``mesh.vertices.foreach_get("co")`` goes element by element, 50 ms).
Blender offers no write of a subset of rows but element by element (about 4 µs a vertex), so
a stroke writes the whole array: a fraction of a millisecond.

:func:`link_for` gives the :class:`~.mesh_link.MeshLink` of an object (made once per mesh and
topology, then kept in step with the mesh), through which strokes and picks go.

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

from . import engine
from .mesh_link import MeshLink, held_values

__all__ = [
    "check_sculptable",
    "forget_links",
    "link_for",
    "prepare_undo",
    "read_held",
    "read_mesh",
    "read_positions",
    "stroke_done",
    "write_positions",
]

#: Links kept (the most recently used meshes): each holds a few copies of its mesh.
MAX_LINKS = 2
_links: dict[tuple[int, int], MeshLink] = {}

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


def _attribute(mesh, name: str, dtype, width: int = 1) -> np.ndarray | None:
    """The whole point attribute ``name`` as an array (None when the mesh has none)."""
    attribute = mesh.attributes.get(name)
    if attribute is None:
        return None
    out = np.empty(len(mesh.vertices) * width if attribute.domain == "POINT" else 0, dtype)
    if not len(out):
        return None
    attribute.data.foreach_get("vector" if width == 3 else "value", out)
    return out


def read_positions(mesh) -> np.ndarray:
    """(N, 3) float32 positions in object space, as Blender holds them."""
    positions = _attribute(mesh, "position", np.float32, 3)
    assert positions is not None  # every mesh has positions
    return positions.reshape(-1, 3)


def read_held(mesh) -> np.ndarray:
    """(N,) float64: how much each vertex is held by Blender's sculpt mask and hiding (see
    :func:`.mesh_link.held_values`)."""
    return held_values(
        len(mesh.vertices),
        _attribute(mesh, ".sculpt_mask", np.float32),
        _attribute(mesh, ".hide_vert", np.bool_),
    )


def read_topology(mesh) -> np.ndarray:
    """(L,) int32 the vertex of each face corner: what tells a changed topology."""
    out = np.empty(len(mesh.loops), np.int32)
    if len(out):
        mesh.attributes[".corner_vert"].data.foreach_get("value", out)
    return out


def read_mesh(mesh) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) float64 positions and (M, 3) int64 triangles of ``mesh``."""
    mesh.calc_loop_triangles()
    tris = np.empty(len(mesh.loop_triangles) * 3, dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return read_positions(mesh).astype(np.float64), tris.reshape(-1, 3).astype(np.int64)


def write_positions(obj, positions: np.ndarray) -> None:
    """Store ``positions`` (N, 3) (float32 as Blender keeps them) as ``obj``'s and tell
    Blender they changed."""
    mesh = obj.data
    data = np.ascontiguousarray(positions, dtype=np.float32).ravel()
    mesh.attributes["position"].data.foreach_set("vector", data)
    mesh.update()


def link_for(obj, settings: engine.SculptSettings, check_topology: bool = True) -> MeshLink:
    """The :class:`MeshLink` of ``obj``'s mesh, in step with it (its positions, sculpt mask and
    hidden vertices); made anew when there is none or the topology changed (with
    ``check_topology`` False only the counts are compared: the hover's cheaper check)."""
    mesh = obj.data
    key = (obj.session_uid, mesh.session_uid)
    link = _links.pop(key, None)
    if link is not None:
        if check_topology:
            fits = link.fits(len(mesh.vertices), read_topology(mesh))
        else:
            fits = len(link.positions) == len(mesh.vertices) and len(link.topology) == len(
                mesh.loops
            )
        if not fits:
            link = None
    positions = read_positions(mesh)
    if link is None:
        _, faces = read_mesh(mesh)
        link = MeshLink(positions, faces, read_topology(mesh), settings)
    while len(_links) >= MAX_LINKS:
        _links.pop(next(iter(_links)))
    _links[key] = link  # the most recent last
    link.sync(positions, read_held(mesh))
    return link


def forget_links() -> None:
    """Drop every link (a new file: its meshes are others)."""
    _links.clear()


def _fingerprint(mesh) -> bytes:
    return hashlib.blake2b(read_positions(mesh).tobytes(), digest_size=16).digest()


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
    forget_links()
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
    forget_links()
