"""STL, binary and ASCII, read and written here (numpy views of the file, no copies beyond the
float64 positions).

An STL file has no shared vertices: each triangle lists its own three corners (float32). They
are welded at load (:func:`~gogreen_core.mesh_io.weld.weld`: corners at exactly the same
position are one vertex, in order of first appearance), so a closed model loads closed, as it
was in the program that wrote it; saving writes each triangle's corners again. STL stores
float32, so saving to STL rounds positions. Normals in the file are ignored (the corners' order
gives the orientation); the attribute word of each binary triangle too.
"""

from __future__ import annotations

import re
from typing import BinaryIO

import numpy as np

from gogreen_core.mesh_io.data import MeshData, MeshFileError
from gogreen_core.mesh_io.text import parse_numbers, without_dos_eof
from gogreen_core.mesh_io.weld import weld

__all__ = ["TRIANGLE", "read_stl", "write_stl"]

_HEADER = 80
#: A binary STL triangle record.
TRIANGLE = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])


def read_stl(data: bytes, name: str) -> MeshData:
    if len(data) >= _HEADER + 4:
        count = int(np.frombuffer(data, "<u4", 1, _HEADER)[0])
        if len(data) == _HEADER + 4 + count * TRIANGLE.itemsize:
            triangles = np.frombuffer(data, TRIANGLE, count, _HEADER + 4)
            return _welded(triangles["corners"].reshape(-1, 3), name)
    else:
        count = None
    if data.lstrip()[:5].lower() == b"solid":
        return _welded(_ascii_corners(data, name), name)
    announced = "" if count is None else f": its header announces {count} triangles"
    raise MeshFileError(
        f"{name}: no triangles could be read (a binary STL of {len(data)} bytes{announced}, "
        "which do not fit: broken or truncated STL)"
    )


def _ascii_corners(data: bytes, name: str) -> np.ndarray:
    """(3·M, 3) corner positions of an ASCII STL (every solid of the file)."""
    text = without_dos_eof(data).lower()
    facets = len(re.findall(rb"\bendfacet\b", text))
    found = re.findall(rb"\bvertex\s+(\S+)\s+(\S+)\s+(\S+)", text)
    if facets == 0 or len(found) != 3 * facets:
        raise MeshFileError(
            f"{name}: no triangles could be read (an ASCII STL with {facets} complete facets "
            f"and {len(found)} vertices: broken or truncated STL)"
        )
    try:
        return parse_numbers(b" ".join(b" ".join(xyz) for xyz in found), np.float64).reshape(-1, 3)
    except ValueError:
        bad = next(b" ".join(xyz) for xyz in found if not _all_numbers(xyz))
        raise MeshFileError(
            f"{name}: bad number in the vertex {bad.decode('ascii', 'replace')!r}"
        ) from None


def _all_numbers(tokens: tuple[bytes, ...]) -> bool:
    try:
        [float(t) for t in tokens]
    except ValueError:
        return False
    return True


def _welded(corners: np.ndarray, name: str) -> MeshData:
    if len(corners) == 0:
        raise MeshFileError(f"{name}: no triangles could be read (an STL without triangles)")
    try:
        index, kept = weld(corners)  # float32 keys for binary STL
    except ValueError as exc:
        raise MeshFileError(f"{name}: {exc}") from None
    return MeshData(corners[kept].astype(np.float64), index.reshape(-1, 3))


def write_stl(mesh: MeshData, out: BinaryIO) -> None:
    """Binary STL: each triangle's unit normal (0 for a degenerate one) and its corners, in
    float32."""
    corners = mesh.vertices[mesh.faces]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    table = np.zeros(len(mesh.faces), dtype=TRIANGLE)
    table["normal"] = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    table["corners"] = corners
    header = b"binary STL written by GoGreen Sculpt".ljust(_HEADER, b" ")
    out.write(header + np.array(len(table), dtype="<u4").tobytes() + table.tobytes())
