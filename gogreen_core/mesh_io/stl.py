"""STL, through trimesh with ``process=False``. An STL file has no shared vertices: each triangle
lists its own three corners, so a loaded STL has 3·M vertices in file order (no welding, which
would renumber them). STL stores float32, so saving to STL rounds positions."""

from __future__ import annotations

import io
from typing import BinaryIO

import numpy as np

from gogreen_core.mesh_io.data import MeshData, MeshFileError

__all__ = ["read_stl", "write_stl"]


def read_stl(data: bytes, name: str) -> MeshData:
    import trimesh

    try:
        loaded = trimesh.load(io.BytesIO(data), file_type="stl", process=False, force="mesh")
    except Exception as exc:  # trimesh raises many kinds of errors on broken files
        raise MeshFileError(f"{name}: broken STL file ({exc or type(exc).__name__})") from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshFileError(f"{name}: no triangles could be read (broken or truncated STL)")
    return MeshData(np.array(loaded.vertices, dtype=np.float64), np.array(loaded.faces))


def write_stl(mesh: MeshData, out: BinaryIO) -> None:
    import trimesh

    tm = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    out.write(trimesh.exchange.stl.export_stl(tm))
