"""Mesh files: OBJ, PLY (ASCII and binary), STL and OFF, loaded and saved without reordering.

:func:`load_mesh` and :func:`save_mesh` (:mod:`~gogreen_core.mesh.mesh_io.formats`) pick the
reader or writer by extension; each format has its module. Every problem raises
:class:`MeshFileError` (a ``ValueError``) whose message starts with the file name, e.g.
``"spot.obj, line 3012: face 12 references vertex 9001 but the file has 2930 vertices"``;
vertex and face numbers count the way the format does (from 1 in OBJ, from 0 in PLY and OFF).
Saving is atomic (:mod:`~gogreen_core.mesh.mesh_io.atomic`, also used for sessions, presets and
screenshots) and text formats write ``%.17g``, so coordinates reload bit for bit.
"""

from gogreen_core.mesh.mesh_io.atomic import write_bytes_atomic, write_text_atomic
from gogreen_core.mesh.mesh_io.data import MeshData, MeshFileError
from gogreen_core.mesh.mesh_io.formats import MESH_FORMATS, load_mesh, save_mesh, warm_up

__all__ = [
    "MESH_FORMATS",
    "MeshData",
    "MeshFileError",
    "load_mesh",
    "save_mesh",
    "warm_up",
    "write_bytes_atomic",
    "write_text_atomic",
]
