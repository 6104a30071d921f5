"""STL, binary and ASCII. Each triangle lists its own corners; they are welded at load
(:func:`~gogreen_core.mesh.mesh_io.weld.weld`), so a closed model loads closed. Saving writes
float32 corners (rounding positions). Normals and attribute words are ignored. A truncated file
is refused; an ASCII one names the line where it leaves the grammar.
"""

from __future__ import annotations

import re
from typing import BinaryIO, NoReturn

import numpy as np

from gogreen_core.mesh.mesh_io.data import MeshData, MeshFileError, first_non_finite
from gogreen_core.mesh.mesh_io.text import is_number, parse_numbers, without_dos_eof
from gogreen_core.mesh.mesh_io.weld import weld

__all__ = ["TRIANGLE", "read_stl", "write_stl"]

_HEADER = 80
#: A binary STL triangle record.
TRIANGLE = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])


def read_stl(data: bytes, name: str) -> MeshData:
    if len(data) >= _HEADER + 4:
        count = int(np.frombuffer(data, "<u4", 1, _HEADER)[0])
        if len(data) == _HEADER + 4 + count * TRIANGLE.itemsize:
            triangles = np.frombuffer(data, TRIANGLE, count, _HEADER + 4)
            corners = triangles["corners"].reshape(-1, 3)
            if (bad := first_non_finite(corners)) is not None:
                raise MeshFileError(
                    f"{name}: triangle {bad // 3} (from 0) has a non-finite corner "
                    f"{corners[bad].tolist()}"
                )
            return _welded(corners, name)
    else:
        count = None
    if data.lstrip()[:5].lower() == b"solid":
        return _welded(_ascii_corners(data, name), name)
    announced = "" if count is None else f": its header announces {count} triangles"
    raise MeshFileError(
        f"{name}: no triangles could be read (a binary STL of {len(data)} bytes{announced}, "
        "which do not fit: broken or truncated STL)"
    )


# An ASCII STL (lower-cased, any whitespace between words): solids, each ``solid [name]``,
# facets, ``endsolid [name]``. A solid's facets are matched by one regular expression run; only
# where it stops is the file walked piece by piece, to name the line at fault.
_NUMBER = rb"\s+\S+"
_CORNER = ("vertex x y z", rb"\s*vertex" + 3 * _NUMBER + rb"(?=\s|\Z)")
_FACET_PARTS = (
    ("facet normal nx ny nz", rb"\s*facet\s+normal" + 3 * _NUMBER + rb"(?=\s|\Z)"),
    ("outer loop", rb"\s*outer\s+loop\b"),
    *[_CORNER] * 3,
    ("endloop", rb"\s*endloop\b"),
    ("endfacet", rb"\s*endfacet\b"),
)
_PARTS = [(word, re.compile(pattern)) for word, pattern in _FACET_PARTS]
_SOLID = re.compile(rb"\s*solid\b[^\n]*")
_FACETS = re.compile(rb"(?:" + b"".join(pattern for _, pattern in _FACET_PARTS) + rb")*")
_ENDSOLID = re.compile(rb"\s*endsolid\b[^\n]*")
_VERTEX = re.compile(rb"\bvertex\s+(\S+)\s+(\S+)\s+(\S+)")


def _ascii_corners(data: bytes, name: str) -> np.ndarray:
    """(3·M, 3) corner positions of an ASCII STL (every solid of the file)."""
    text = without_dos_eof(data).lower().replace(b"\r\n", b"\n").replace(b"\r", b"\n")
    _check_ascii_structure(text, name)
    found = _VERTEX.findall(text)
    if not found:
        raise MeshFileError(f"{name}: no triangles could be read (an ASCII STL without facets)")
    flat = b" ".join(b" ".join(xyz) for xyz in found)
    try:
        corners = parse_numbers(flat, np.float64)
    except ValueError:  # numbers the C parser does not take ('1_0'), read as ASCII PLY's are
        words = (m for m in _VERTEX.finditer(text) if not all(map(is_number, m.groups())))
        bad = next(words, None)
        if bad is not None:
            shown = b" ".join(bad.groups()).decode("ascii", "replace")
            raise MeshFileError(
                f"{name}, line {_line_of(text, bad.start())}: bad number in the vertex {shown!r}"
            ) from None
        corners = np.array([float(t) for t in flat.split()])
    corners = corners.reshape(-1, 3)
    if (row := first_non_finite(corners)) is not None:
        bad = list(_VERTEX.finditer(text))[row]
        shown = b" ".join(bad.groups()).decode("ascii", "replace")
        raise MeshFileError(
            f"{name}, line {_line_of(text, bad.start())}: the vertex {shown!r} is not finite"
        )
    return corners


def _check_ascii_structure(text: bytes, name: str) -> None:
    """Raise MeshFileError at the first place ``text`` (lower case, '\\n' line ends) leaves
    the grammar of an ASCII STL."""
    position = 0
    while position == 0 or text[position:].strip():
        solid = _SOLID.match(text, position)
        if solid is None:
            _refuse(text, position, name, "'solid'", "")
        position = solid.end()
        while (end := _ENDSOLID.match(text, position)) is None:
            position = _FACETS.match(text, position).end()  # type: ignore[union-attr]
            if _ENDSOLID.match(text, position) is not None:
                continue
            at = _skip_space(text, position)
            if not text.startswith(b"facet", at):
                _refuse(text, position, name, "'facet' or 'endsolid'", "")
            where = f" in the facet begun on line {_line_of(text, at)}"
            for word, part in _PARTS:  # where the facet at ``position`` goes wrong
                piece = part.match(text, position)
                if piece is None:
                    _refuse(text, position, name, repr(word), where)
                position = piece.end()
        position = end.end()


def _refuse(text: bytes, position: int, name: str, expected: str, where: str) -> NoReturn:
    at = _skip_space(text, position)
    line = _line_of(text, at)
    if at == len(text):
        raise MeshFileError(
            f"{name}, line {line}: the file ends{where} where {expected} should follow "
            "(a truncated ASCII STL)"
        )
    found = text[at : text.find(b"\n", at) if b"\n" in text[at:] else len(text)]
    shown = found[:60].decode("ascii", "replace")
    raise MeshFileError(f"{name}, line {line}: expected {expected}{where}, found {shown!r}")


def _skip_space(text: bytes, position: int) -> int:
    return len(text) - len(text[position:].lstrip()) if position < len(text) else len(text)


def _line_of(text: bytes, position: int) -> int:
    return text.count(b"\n", 0, position) + 1


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
