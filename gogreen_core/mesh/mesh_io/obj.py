"""OBJ (Wavefront): reading (the fast reader, else the strict one) and writing.

Positions stay as listed (trimesh's loader splits vertices at UV seams, changing the vertex
count and order that sessions rely on); texture coordinates are kept per face corner. Normals,
materials and groups are not kept.
"""

from __future__ import annotations

from typing import BinaryIO

import numpy as np

from gogreen_core.mesh.mesh_io.data import MeshData
from gogreen_core.mesh.mesh_io.obj_fast import read_obj_fast
from gogreen_core.mesh.mesh_io.obj_strict import read_obj_strict
from gogreen_core.mesh.mesh_io.text import write_rows

__all__ = ["read_obj", "write_obj"]


def read_obj(data: bytes, name: str) -> MeshData:
    """OBJ: the fast whole-array reader when the file is regular, else the strict one."""
    mesh = read_obj_fast(data)
    return read_obj_strict(data, name) if mesh is None else mesh


def write_obj(mesh: MeshData, out: BinaryIO) -> None:
    out.write(b"# written by GoGreen Sculpt\n")
    write_rows(out, "v %.17g %.17g %.17g\n", mesh.vertices)
    if mesh.uv is None:
        write_rows(out, "f %d %d %d\n", mesh.faces + 1)
        return
    write_rows(out, "vt %.17g %.17g\n", mesh.uv)
    uv_faces = mesh.uv_faces
    assert uv_faces is not None  # set together with uv
    has_uv = uv_faces[:, 0] >= 0
    corners = np.stack([mesh.faces + 1, uv_faces + 1], axis=2).reshape(-1, 6)
    if has_uv.all():
        write_rows(out, "f %d/%d %d/%d %d/%d\n", corners)
        return
    lines = [  # some faces without texture coordinates: keep them so, in order
        "f {}/{} {}/{} {}/{}\n".format(*row) if textured else "f {} {} {}\n".format(*row[::2])
        for row, textured in zip(corners.tolist(), has_uv.tolist(), strict=True)
    ]
    out.write("".join(lines).encode("ascii"))
