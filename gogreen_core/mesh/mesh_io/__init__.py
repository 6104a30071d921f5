"""Mesh files: OBJ, PLY (ASCII and binary), STL and OFF, loaded and saved without reordering.

Loading keeps the vertices as the file lists them: same order, and the same count except where
the format itself made copies of a vertex: STL's triangle corners and the vertices a PLY (as
Blender writes it) splits along UV seams are welded back into one, so the surface a brush
deforms is in one piece. Polygons are triangulated by their shape: a convex polygon by its fan
(corners ``0, k, k+1``) in place, as the file orders it; a quad that would fold by its other
diagonal (all quads at once); a concave n-gon without covering its notch
(:mod:`~gogreen_core.mesh.mesh_io.polygons`).

Text is read as UTF-8; a leading byte-order mark is skipped and CR LF or lone CR line ends are
accepted, so no first vertex or line is lost to them.

Every problem raises :class:`MeshFileError` (a ``ValueError``) whose message starts with the
file name, e.g. ``"spot.obj, line 3012: face 12 references vertex 9001 but the file has 2930
vertices"``. Vertex and face numbers in messages are counted the way the format counts them:
from 1 in OBJ, from 0 in PLY and OFF.

Saving is atomic (:mod:`~gogreen_core.mesh.mesh_io.atomic`). Coordinates are written with ``%.17g``
in text formats and as float64 in binary PLY, so they reload bit for bit; indices are formatted
with whole-array operations.

Modules: :mod:`~gogreen_core.mesh.mesh_io.formats` (``load_mesh``, ``save_mesh``: the reader or
writer by extension), one module per format (``obj`` with its two readers ``obj_fast`` and
``obj_strict``, ``ply`` with ``ply_elements`` for its records, ``stl``, ``off``), ``data``
(``MeshData``, ``MeshFileError``), ``polygons`` (polygons to triangles), ``weld`` (joining
and splitting vertices at seams), ``text`` (number parsing, the same under numpy 1.26 and 2,
and formatting) and ``atomic`` (``write_bytes_atomic``, ``write_text_atomic``, also used for
sessions, presets and screenshots). A few loops run as numba code (cached on disk like the
kernels'): the PLY record walk, the fan test and the weld.
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
