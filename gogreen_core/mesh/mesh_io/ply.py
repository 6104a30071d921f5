"""PLY (Stanford polygon files), ASCII and binary, read and written here rather than by trimesh,
which silently drops the faces of a truncated binary file and writes float32 positions.

Reading: positions ``x, y, z``; texture coordinates (:data:`UV_PROPERTIES`); faces
(``vertex_indices`` or ``vertex_index`` lists) and triangle strips (element ``tristrips``).
Vertices that carry attributes besides their position are welded where their positions are
equal (exporters split them for their attributes, Blender along UV seams); ``MeshData.uv`` holds
the file's per-vertex texture coordinates and ``uv_faces`` the file's vertex of each corner.
Writing: float64 positions, int32 indices, ``s, t`` split at the seams.

Each element's records are walked in compiled code, which finds where each starts (lists vary
in length: triangles and quads mixed, as most Blender meshes are), then each property is
gathered. ASCII data is parsed into float64 numbers whose bytes are read the same way, as
float64 properties.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import BinaryIO, cast

import numba
import numpy as np

from gogreen_core.mesh.mesh_io.data import MeshData, MeshFileError, first_non_finite
from gogreen_core.mesh.mesh_io.polygons import triangulate
from gogreen_core.mesh.mesh_io.text import (
    BOM,
    DOS_EOF,
    is_number,
    parse_numbers,
    show_number,
    without_dos_eof,
    write_rows,
)
from gogreen_core.mesh.mesh_io.weld import split_at_seams, weld

__all__ = ["PLY_TYPES", "UV_PROPERTIES", "read_ply", "write_ply"]

#: Names of the texture coordinates of a vertex, in the order they are looked for.
UV_PROPERTIES = (("s", "t"), ("u", "v"), ("texture_u", "texture_v"), ("texture_s", "texture_t"))


def read_ply(data: bytes, name: str) -> MeshData:
    data = data.removeprefix(BOM.encode("utf-8"))
    fmt, elements, offset = read_header(data, name)
    tables: dict[str, Columns] = {}
    if fmt == "ascii":
        values = ascii_numbers(without_dos_eof(data[offset:]), name)
        cursor = 0
        try:
            for element in elements:
                tables[element.name], cursor = read_ascii_element(values, cursor, element, name)
            if cursor != len(values):
                raise MeshFileError(
                    f"{name}: {len(values) - cursor} values after the last element: the "
                    "header's counts do not match the data"
                )
        except MeshFileError as exc:  # a row with values the header does not declare?
            raise row_problem(data, offset, elements, name) or exc from None
    else:
        for element in elements:
            tables[element.name], offset = read_binary_element(data, offset, element, fmt, name)
        if data[offset:].strip(b" \t\r\n\0" + DOS_EOF):
            raise MeshFileError(
                f"{name}: {len(data) - offset} bytes after the last element: the header's "
                "counts do not match the data"
            )

    vertex = tables.get("vertex", {})
    scalars = {key: column for key, column in vertex.items() if isinstance(column, np.ndarray)}
    if not all(axis in scalars for axis in "xyz"):
        raise MeshFileError(f"{name}: no vertex positions (element 'vertex' with x, y, z)")
    points = np.stack([scalars[axis] for axis in "xyz"], axis=1).astype(np.float64)
    corners, sizes = _polygons(tables, len(points), name)
    file_faces = corners[triangulate(points, corners, sizes)]
    uv_names = next((pair for pair in UV_PROPERTIES if all(n in scalars for n in pair)), None)
    uv = None
    if uv_names is not None:
        uv = np.stack([scalars[n] for n in uv_names], axis=1).astype(np.float64)
        _check_finite(uv, name, "a non-finite texture coordinate")
    if set(vertex) == {"x", "y", "z"}:
        mesh = MeshData(points, file_faces)
    else:  # joined whether their attributes differ or not (UVs equal but for rounding...)
        _check_finite(points, name, "a non-finite coordinate")  # named as the file counts
        index, kept = weld(points)
        mesh = MeshData(points[kept], index[file_faces])
    if uv is not None:
        mesh.uv, mesh.uv_faces = uv, file_faces
    return mesh


def _check_finite(values: np.ndarray, name: str, what: str) -> None:
    if (bad := first_non_finite(values)) is not None:
        raise MeshFileError(f"{name}: vertex {bad} has {what} {values[bad].tolist()}")


def _polygons(tables: dict[str, Columns], n_vertices: int, name: str) -> tuple[np.ndarray, ...]:
    """Corners (C,) int64 and sizes (P,) of the faces, then of the triangles of the strips."""
    face = tables.get("face", {})
    lists = face.get("vertex_indices", face.get("vertex_index"))
    strips = tables.get("tristrips", {}).get("vertex_indices")
    if lists is None and strips is None:
        raise MeshFileError(f"{name}: no faces")
    if isinstance(lists, np.ndarray) or isinstance(strips, np.ndarray):
        raise MeshFileError(f"{name}: the face corners are not a list property")
    corners = np.zeros(0, dtype=np.int64)
    sizes = np.zeros(0, dtype=np.int64)
    if lists is not None:
        short = np.flatnonzero(lists.sizes < 3)
        if len(short):
            raise MeshFileError(f"{name}: face {int(short[0])} has fewer than 3 corners")
        corners = _whole_indices(lists, n_vertices, name, "face")
        sizes = lists.sizes.astype(np.int64)
    if strips is not None:
        triangles = _strip_triangles(strips, n_vertices, name)
        corners = np.concatenate([corners, triangles.ravel()])
        sizes = np.concatenate([sizes, np.full(len(triangles), 3)])
    if len(sizes) == 0:
        raise MeshFileError(f"{name}: no faces")
    return corners, sizes


def _whole_indices(lists: PlyList, n_vertices: int, name: str, what: str) -> np.ndarray:
    """The items of ``lists`` as int64; MeshFileError naming the record of one not a whole
    number (checked before the cast) or not in [0, n_vertices) (-1 allowed in strips)."""
    values = lists.values

    def refuse(wrong: np.ndarray, problem: str) -> None:
        if wrong.any():
            bad = int(np.argmax(wrong))
            record = int(np.searchsorted(np.cumsum(lists.sizes), bad, side="right"))
            shown = show_number(values[bad])
            raise MeshFileError(f"{name}: {what} {record} {problem.format(shown)}")

    whole = np.isfinite(values) & (values == np.round(values))
    refuse(~whole, "has vertex index {}, which is not a whole number")
    outside = (values < 0) | (values >= n_vertices)
    if what == "tristrip":
        outside &= values != -1
    refuse(outside, f"references vertex {{}} but the file has {n_vertices} vertices")
    return values.astype(np.int64)


def _strip_triangles(strips: PlyList, n_vertices: int, name: str) -> np.ndarray:
    """Triangles (T, 3) of triangle strips: each record is one or more strips separated by
    -1; every other triangle is flipped so that all turn the same way, and the degenerate
    ones (strips repeat a vertex to turn or to join) are dropped."""
    indices = _whole_indices(strips, n_vertices, name, "tristrip")
    # One -1 after each record, so that strips never run from one record into the next.
    ends = np.cumsum(strips.sizes)
    flat = np.insert(indices, ends, -1)
    stop = flat == -1
    after_stop = np.maximum.accumulate(np.where(stop, np.arange(len(flat)), -1)) + 1
    i = np.flatnonzero(~(stop[:-2] | stop[1:-1] | stop[2:]))
    a, b, c = flat[i], flat[i + 1], flat[i + 2]
    odd = (i - after_stop[i]) % 2 == 1
    triangles = np.stack([np.where(odd, b, a), np.where(odd, a, b), c], axis=1)
    return cast(np.ndarray, triangles[(a != b) & (b != c) & (a != c)])


def write_ply(mesh: MeshData, out: BinaryIO, ascii: bool) -> None:
    """PLY with float64 vertices, int32 triangle indices, and ``s, t`` (float64) when the mesh
    has texture coordinates: vertices are split where their corners' coordinates differ."""
    vertices, faces = mesh.vertices, mesh.faces
    columns = "xyz"
    if mesh.uv is not None and mesh.uv_faces is not None:
        source, vertex_uv, faces = split_at_seams(mesh.faces, mesh.uv, mesh.uv_faces, len(vertices))
        vertices = np.concatenate([vertices[source], vertex_uv], axis=1)
        columns = "xyzst"
    header = (
        "ply\n"
        f"format {'ascii' if ascii else 'binary_little_endian'} 1.0\n"
        "comment written by GoGreen Sculpt\n"
        f"element vertex {len(vertices)}\n"
        + "".join(f"property double {c}\n" for c in columns)
        + f"element face {len(faces)}\n"
        "property list uchar int vertex_indices\nend_header\n"
    )
    out.write(header.encode("ascii"))
    if ascii:
        write_rows(out, " ".join(["%.17g"] * len(columns)) + "\n", vertices)
        write_rows(out, "3 %d %d %d\n", faces)
        return
    out.write(np.ascontiguousarray(vertices, dtype="<f8").tobytes())
    record = np.dtype([("n", "u1"), ("i", "<i4", 3)])
    table = np.empty(len(faces), dtype=record)
    table["n"], table["i"] = 3, faces
    out.write(table.tobytes())


#: Type names of the PLY header (both spellings) and their numpy type codes.
PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}  # fmt: skip


@dataclass
class PlyProperty:
    name: str
    dtype: str  # numpy type code of the value (of each item for a list)
    count_dtype: str | None = None  # numpy type code of a list's length; None for a scalar


@dataclass
class PlyElement:
    name: str
    count: int
    properties: list[PlyProperty]


@dataclass
class PlyList:
    """The values of a list property: every item (I,) in record order, and each record's
    item count (R,)."""

    values: np.ndarray
    sizes: np.ndarray


#: One element's data: per property, (R,) values of a scalar or a :class:`PlyList`.
Columns = dict[str, "np.ndarray | PlyList"]


def read_header(data: bytes, name: str) -> tuple[str, list[PlyElement], int]:
    """Format ('ascii', '<' or '>'), elements, and the offset of the first data byte."""
    if not data.startswith(b"ply"):
        raise MeshFileError(f"{name}: not a PLY file (it does not start with 'ply')")
    end = data.find(b"end_header")
    if end < 0:
        raise MeshFileError(f"{name}: truncated PLY header (no 'end_header')")
    newline = data.find(b"\n", end)
    body = len(data) if newline < 0 else newline + 1
    fmt = None
    elements: list[PlyElement] = []
    for number, line in enumerate(data[:end].decode("ascii", "replace").splitlines(), 1):
        words = line.split()
        if not words or words[0] in ("ply", "comment", "obj_info"):
            continue
        bad = MeshFileError(f"{name}, header line {number}: cannot understand {line.strip()!r}")
        if words[0] == "format" and len(words) >= 2:
            formats = {"ascii": "ascii", "binary_little_endian": "<", "binary_big_endian": ">"}
            if words[1] not in formats:
                raise bad
            fmt = formats[words[1]]
        elif words[0] == "element" and len(words) == 3:
            try:
                count = int(words[2])
            except ValueError:
                raise bad from None
            if count < 0:
                raise bad
            elements.append(PlyElement(words[1], count, []))
        elif words[0] == "property" and elements:
            if len(words) == 3 and words[1] in PLY_TYPES:
                prop = PlyProperty(words[2], PLY_TYPES[words[1]])
            elif (
                len(words) == 5
                and words[1] == "list"
                and words[2] in PLY_TYPES
                and words[3] in PLY_TYPES
                and PLY_TYPES[words[2]][0] in "iu"
            ):
                prop = PlyProperty(words[4], PLY_TYPES[words[3]], PLY_TYPES[words[2]])
            else:
                raise bad
            elements[-1].properties.append(prop)
        else:
            raise bad
    if fmt is None:
        raise MeshFileError(f"{name}: the PLY header has no 'format' line")
    return fmt, elements, body


def _truncated(element: PlyElement, name: str) -> MeshFileError:
    return MeshFileError(
        f"{name}: truncated file: the data of element '{element.name}' ({element.count} "
        "announced) ends early"
    )


# -- binary ------------------------------------------------------------------------------------
def read_binary_element(
    data: bytes | np.ndarray, offset: int, element: PlyElement, endian: str, name: str
) -> tuple[Columns, int]:
    """One element's records from ``data[offset:]`` (``endian`` '<', '>' or '=' for ASCII's
    numbers): its columns and the offset after its last record."""
    props, count = element.properties, element.count
    if not props:
        return {}, offset
    size = [np.dtype(p.count_dtype or p.dtype).itemsize for p in props]
    if count * sum(size) > len(data) - offset:  # (also a count too large for any array)
        raise _truncated(element, name)
    if not any(p.count_dtype for p in props):  # records of one size: a view of the file
        record = np.dtype([(f"s{i}", endian + p.dtype) for i, p in enumerate(props)])
        table = np.frombuffer(data, record, count, offset)
        return {p.name: table[f"s{i}"] for i, p in enumerate(props)}, offset + sum(size) * count
    item = [np.dtype(p.dtype).itemsize if p.count_dtype else 0 for p in props]
    buffer = np.frombuffer(data, dtype=np.uint8)
    ascii = any(p.count_dtype == "f8" for p in props)  # (binary list lengths are integers)
    starts, lengths, status, bad = _walk_binary_records(
        buffer,
        buffer.view(np.float64) if ascii else np.empty(0),
        offset,
        element.count,
        np.array([p.count_dtype is not None for p in props]),
        np.array(size, dtype=np.int64),
        np.array(item, dtype=np.int64),
        np.array([(p.count_dtype or "u")[0] == "i" for p in props]),
        endian == ">",
    )
    if status == _TRUNCATED:
        raise _truncated(element, name)
    if status == _BAD_LENGTH:
        value = bad if ascii else int(bad)
        raise MeshFileError(f"{name}: bad list length {value!r} in element '{element.name}'")
    position = starts[:-1].copy()  # where the current property starts, per record
    columns: Columns = {}
    list_number = 0
    for p, nbytes, itemsize in zip(props, size, item, strict=True):
        if p.count_dtype is None:
            gathered = _copy_runs(buffer, position, np.full(len(position), nbytes))
            columns[p.name] = gathered.view(endian + p.dtype)
            position += nbytes
            continue
        counts = lengths[:, list_number]
        list_number += 1
        position += nbytes
        gathered = _copy_runs(buffer, position, counts * itemsize)
        columns[p.name] = PlyList(gathered.view(endian + p.dtype), counts)
        position += counts * itemsize
    return columns, int(starts[-1])


_TRUNCATED, _BAD_LENGTH = 1, 2


@numba.njit(cache=True, nogil=True)
def _walk_binary_records(
    buffer: np.ndarray,
    numbers: np.ndarray,
    offset: int,
    count: int,
    is_list: np.ndarray,
    size: np.ndarray,
    item: np.ndarray,
    signed: np.ndarray,
    big_endian: bool,
) -> tuple[np.ndarray, np.ndarray, int, float]:
    """Each record's start and the last's end (count + 1,), each list's length (count, lists),
    status (0, _TRUNCATED, _BAD_LENGTH) and the bad length; ``numbers``: float64 view or empty."""
    n_lists = np.count_nonzero(is_list)
    starts = np.empty(count + 1, dtype=np.int64)
    lengths = np.zeros((count, n_lists), dtype=np.int64)
    pos = offset
    end = len(buffer)
    for r in range(count):
        starts[r] = pos
        column = 0
        for j in range(len(is_list)):
            if not is_list[j]:
                pos += size[j]
                continue
            if pos + size[j] > end:
                return starts, lengths, _TRUNCATED, 0.0
            if len(numbers):
                value = numbers[pos >> 3]
                if not (np.isfinite(value) and value >= 0 and value == np.floor(value)):
                    return starts, lengths, _BAD_LENGTH, value
                if value * item[j] > end - pos - size[j]:
                    return starts, lengths, _TRUNCATED, 0.0
                k = int(value)
            else:
                k = 0
                for b in range(size[j]):
                    byte = buffer[pos + (b if big_endian else size[j] - 1 - b)]
                    k = k * 256 + byte
                if signed[j] and k >= 1 << (8 * size[j] - 1):
                    k -= 1 << (8 * size[j])
                if k < 0:
                    return starts, lengths, _BAD_LENGTH, float(k)
            lengths[r, column] = k
            column += 1
            pos += size[j] + k * item[j]  # past the end: refused below, or at the next length
        if pos > end:
            return starts, lengths, _TRUNCATED, 0.0
    starts[count] = pos
    return starts, lengths, 0, 0.0


@numba.njit(cache=True, nogil=True)
def _copy_runs(buffer: np.ndarray, starts: np.ndarray, nbytes: np.ndarray) -> np.ndarray:
    """The bytes ``buffer[starts[i] : starts[i] + nbytes[i]]``, concatenated."""
    out = np.empty(nbytes.sum(), dtype=np.uint8)
    at = 0
    for i in range(len(starts)):
        start = starts[i]
        for b in range(nbytes[i]):  # a few bytes each: a loop beats a slice copy
            out[at + b] = buffer[start + b]
        at += nbytes[i]
    return out


# -- ASCII -------------------------------------------------------------------------------------
def ascii_numbers(body: bytes, name: str) -> np.ndarray:
    """Every number of an ASCII PLY's data (float64), in order; MeshFileError naming the first
    token that is not a number."""
    try:  # whole-array parsing
        return parse_numbers(body, np.float64)
    except ValueError:
        tokens = body.decode("ascii", "replace").split()
        bad = next((t for t in tokens if not is_number(t)), None)
        if bad is not None:
            raise MeshFileError(f"{name}: bad number {bad!r} in the PLY data") from None
        return np.array(tokens, dtype=np.float64)  # e.g. Unicode spaces between them


def read_ascii_element(
    values: np.ndarray, cursor: int, element: PlyElement, name: str
) -> tuple[Columns, int]:
    """ASCII counterpart of :func:`read_binary_element` on the file's numbers (float64) from
    ``values[cursor]``: their bytes read as an element of float64 properties."""
    as_numbers = PlyElement(
        element.name,
        element.count,
        [PlyProperty(p.name, "f8", p.count_dtype and "f8") for p in element.properties],
    )
    columns, end = read_binary_element(values.view(np.uint8), 8 * cursor, as_numbers, "=", name)
    return columns, end // 8


def row_problem(
    data: bytes, offset: int, elements: list[PlyElement], name: str
) -> MeshFileError | None:
    """The error naming the first data line of an ASCII PLY with more values than the header
    declares (or fewer, without lists), rather than the misread value further on; None unless
    the file has one record per line, as many as the header's counts."""
    lines = [
        (number, line.split())
        for number, line in enumerate(
            data[offset:].decode("ascii", "replace").split("\n"),
            start=data.count(b"\n", 0, offset) + 1,
        )
        if line.strip()
    ]
    if len(lines) != sum(element.count for element in elements):
        return None  # not one record per line, or the counts are wrong: said as it is
    rows = iter(lines)
    for element in elements:
        for record in range(element.count):
            number, words = next(rows)
            expected, has_list = 0, False  # (the values before each property's)
            for p in element.properties:
                if p.count_dtype is None:
                    expected += 1
                    continue
                has_list = True
                if expected >= len(words) or not re.fullmatch(r"\+?\d+(\.0*)?", words[expected]):
                    return None  # a bad length: reported as such
                expected += 1 + int(float(words[expected]))
            if len(words) > expected or (len(words) < expected and not has_list):
                declared = ", ".join(p.name for p in element.properties)
                return MeshFileError(
                    f"{name}, line {number}: element '{element.name}' "
                    f"row {record} has {len(words)} values but the header declares "
                    f"{expected} ({declared}): the row has "
                    f"{'more' if len(words) > expected else 'fewer'} values than declared"
                )
    return None
