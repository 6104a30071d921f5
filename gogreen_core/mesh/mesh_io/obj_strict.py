"""OBJ, the strict reader: line by line, naming the line of any problem. It accepts what the
fast reader accepts, with the same result, and reads every file that one hands over."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from gogreen_core.mesh.mesh_io.data import MAX_INDEX, MeshData, MeshFileError, first_non_finite
from gogreen_core.mesh.mesh_io.polygons import triangulate
from gogreen_core.mesh.mesh_io.text import text_lines

__all__ = ["OBJ_STATEMENTS", "read_obj_strict", "statements"]

#: Every statement of the OBJ specification; the reader keeps v, vt and f, ignores the others
#: (normals, groups, materials, smoothing, lines, points, free-form geometry) and refuses any
#: other word, so that a damaged line is reported instead of silently dropped.
OBJ_STATEMENTS = frozenset(
    "v vt vn vp f fo l p g o s mg usemtl mtllib usemap maplib cstype deg bmat step curv curv2 "
    "surf parm trim hole scrv sp end con bevel c_interp d_interp lod shadow_obj trace_obj ctech "
    "stech call csh".split()
)


def read_obj_strict(data: bytes, name: str) -> MeshData:
    vertices: list[tuple[float, ...]] = []
    vertex_lines: list[int] = []
    uvs: list[tuple[float, float]] = []
    corners: list[int] = []  # vertex index of each polygon corner, polygon after polygon
    corner_uvs: list[int] = []  # texture index of each corner, -1 when the face has none
    sizes: list[int] = []  # corners of each polygon
    face_lines: list[int] = []  # source line of each polygon
    textured = 0

    def index(token: str, count: int, kind: str, line: int) -> int:
        try:
            i = int(token)
        except ValueError:
            raise MeshFileError(f"{name}, line {line}: bad {kind} index {token!r}") from None
        if i > MAX_INDEX:  # no file holds that many; int64 arrays could not even store it
            raise MeshFileError(
                f"{name}, line {line}: {kind} index {i} is out of range (the file cannot hold "
                f"that many)"
            )
        if i > 0:
            return i - 1  # checked against the final count below (forward references are legal)
        if i < 0 and count + i >= 0:
            return count + i  # relative to the entries read so far
        if i == 0:
            raise MeshFileError(f"{name}, line {line}: OBJ indices start at 1 (got 0)")
        raise MeshFileError(
            f"{name}, line {line}: relative {kind} index {i} points before the first {kind} "
            f"(only {count} read so far)"
        )

    def numbers(tokens: list[str], line: int, raw: str) -> tuple[float, ...]:
        try:
            return tuple(map(float, tokens))
        except ValueError:
            raise MeshFileError(f"{name}, line {line}: bad number in {raw.strip()!r}") from None

    for number, raw in statements(text_lines(data)):
        parts = raw.split()
        if not parts:
            continue
        tag = parts[0]
        if tag not in OBJ_STATEMENTS:
            raise MeshFileError(
                f"{name}, line {number}: unknown statement {tag[:20]!r} (not an OBJ file?)"
            )
        if tag == "v":
            if len(parts) < 4:
                raise MeshFileError(f"{name}, line {number}: a vertex needs 3 coordinates")
            vertices.append(numbers(parts[1:4], number, raw))
            vertex_lines.append(number)
        elif tag == "vt":
            if len(parts) < 2:
                raise MeshFileError(f"{name}, line {number}: empty texture coordinate")
            u, *rest = numbers(parts[1:3], number, raw)
            if not np.isfinite([u, *rest]).all():
                raise MeshFileError(
                    f"{name}, line {number}: texture coordinate {len(uvs) + 1} has a non-finite "
                    f"value {[u, *rest]}"
                )
            uvs.append((u, rest[0] if rest else 0.0))
        elif tag in ("f", "fo"):  # 'fo' is the old spelling of 'f'
            if len(parts) < 4:
                raise MeshFileError(f"{name}, line {number}: a face needs at least 3 corners")
            pos: list[int] = []
            tex: list[int] = []
            for corner in parts[1:]:
                fields = corner.split("/")
                pos.append(index(fields[0], len(vertices), "vertex", number))
                if len(fields) > 1 and fields[1]:
                    tex.append(index(fields[1], len(uvs), "texture coordinate", number))
            if tex and len(tex) != len(pos):
                raise MeshFileError(
                    f"{name}, line {number}: some corners of this face lack a texture index"
                )
            textured += bool(tex)
            corners += pos
            corner_uvs += tex or [-1] * len(pos)
            sizes.append(len(pos))
            face_lines.append(number)

    if not vertices:
        raise MeshFileError(f"{name}: no vertices (empty or not an OBJ file)")
    if not sizes:
        raise MeshFileError(f"{name}: no faces (the file has only points)")
    v = np.array(vertices, dtype=np.float64)
    c = np.array(corners, dtype=np.int64)
    ends = np.cumsum(sizes)

    def polygon_of(corner: int) -> int:
        return int(np.searchsorted(ends, corner, side="right"))

    if (bad := first_non_finite(v)) is not None:
        raise MeshFileError(
            f"{name}, line {vertex_lines[bad]}: vertex {bad + 1} has a non-finite coordinate "
            f"{v[bad].tolist()}"
        )
    outside = c >= len(v)
    if outside.any():
        bad = int(np.argmax(outside))
        polygon = polygon_of(bad)
        raise MeshFileError(
            f"{name}, line {face_lines[polygon]}: face {polygon + 1} references vertex "
            f"{int(c[bad]) + 1} but the file has {len(v)} vertices"
        )
    triangles = triangulate(v, c, np.array(sizes))
    mesh = MeshData(v, c[triangles])
    if textured:
        t = np.array(corner_uvs, dtype=np.int64)
        outside = t >= len(uvs)
        if outside.any():
            bad = int(np.argmax(outside))
            raise MeshFileError(
                f"{name}, line {face_lines[polygon_of(bad)]}: face references texture "
                f"coordinate {int(t[bad]) + 1} but the file has {len(uvs)} texture coordinates"
            )
        mesh.uv = np.array(uvs, dtype=np.float64).reshape(-1, 2)
        mesh.uv_faces = t[triangles]
    return mesh


def statements(text: str) -> Iterator[tuple[int, str]]:
    """The number of its first line and the content of each statement of an OBJ text:
    comments removed, and a line that ends in a backslash joined with the next one (the
    specification's continuation; Rhino writes long faces so)."""
    pending, first = "", 0
    for number, raw in enumerate(text.split("\n"), start=1):
        if "#" in raw:
            raw = raw.split("#", 1)[0]
        content = raw.rstrip()
        if content.endswith("\\"):
            if not pending:
                first = number
            pending += content[:-1] + " "
        elif pending:
            yield first, pending + raw
            pending = ""
        else:
            yield number, raw
    if pending:
        yield first, pending
