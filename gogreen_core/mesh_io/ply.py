"""PLY (Stanford polygon files), ASCII and binary, read and written here rather than by trimesh,
which silently drops the faces of a truncated binary file instead of reporting it. Vertex
properties besides ``x, y, z`` are read and ignored."""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import BinaryIO

import numpy as np

from gogreen_core.mesh_io.data import MeshData, MeshFileError
from gogreen_core.mesh_io.polygons import check_polygon_indices, fan, fan_ragged
from gogreen_core.mesh_io.text import BOM, is_number, show_number, write_int_rows, write_rows

__all__ = ["read_ply", "write_ply"]

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}  # fmt: skip


@dataclass
class _PlyProperty:
    name: str
    dtype: str  # numpy type code of the value (of each item for a list)
    count_dtype: str | None = None  # numpy type code of a list's length; None for a scalar


@dataclass
class _PlyElement:
    name: str
    count: int
    properties: list[_PlyProperty]


def _read_ply_header(data: bytes, name: str) -> tuple[str, list[_PlyElement], int]:
    """Format ('ascii', '<' or '>'), elements, and the offset of the first data byte."""
    if not data.startswith(b"ply"):
        raise MeshFileError(f"{name}: not a PLY file (it does not start with 'ply')")
    end = data.find(b"end_header")
    if end < 0:
        raise MeshFileError(f"{name}: truncated PLY header (no 'end_header')")
    newline = data.find(b"\n", end)
    body = len(data) if newline < 0 else newline + 1
    fmt = None
    elements: list[_PlyElement] = []
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
            elements.append(_PlyElement(words[1], count, []))
        elif words[0] == "property" and elements:
            if len(words) == 3 and words[1] in _PLY_TYPES:
                prop = _PlyProperty(words[2], _PLY_TYPES[words[1]])
            elif (
                len(words) == 5
                and words[1] == "list"
                and words[2] in _PLY_TYPES
                and words[3] in _PLY_TYPES
                and _PLY_TYPES[words[2]][0] in "iu"
            ):
                prop = _PlyProperty(words[4], _PLY_TYPES[words[3]], _PLY_TYPES[words[2]])
            else:
                raise bad
            elements[-1].properties.append(prop)
        else:
            raise bad
    if fmt is None:
        raise MeshFileError(f"{name}: the PLY header has no 'format' line")
    return fmt, elements, body


def _read_ply_binary(data: bytes, offset: int, element: _PlyElement, endian: str, name: str):
    """Read one element; returns ({property: values}, next offset). Scalars give (count,)
    arrays, lists give a (count, k) array when all have length k, else a list of arrays."""
    props, count = element.properties, element.count
    truncated = MeshFileError(
        f"{name}: truncated file: the data of element '{element.name}' ({count} announced) "
        "ends early"
    )
    # Guess the layout from the first record (lists of a fixed length), then verify it.
    pos = offset
    lengths = []
    for p in props:
        if p.count_dtype is None:
            pos += np.dtype(p.dtype).itemsize
            continue
        if count == 0:
            lengths.append(0)
            continue
        if pos + np.dtype(p.count_dtype).itemsize > len(data):
            raise truncated
        k = _list_length(np.frombuffer(data, endian + p.count_dtype, 1, pos)[0], element, name)
        lengths.append(k)
        pos += np.dtype(p.count_dtype).itemsize + k * np.dtype(p.dtype).itemsize
    fields, lists = [], iter(lengths)
    for i, p in enumerate(props):
        if p.count_dtype is None:
            fields.append((f"s{i}", endian + p.dtype))
        else:
            fields += [
                (f"n{i}", endian + p.count_dtype),
                (f"l{i}", endian + p.dtype, (next(lists),)),
            ]
    record = np.dtype(fields)
    if offset + count * record.itemsize <= len(data):
        table = np.frombuffer(data, record, count, offset)
        if all(
            np.all(table[f"n{i}"] == k)
            for i, k in zip([i for i, p in enumerate(props) if p.count_dtype], lengths, strict=True)
        ):
            columns = {
                p.name: table[f"s{i}" if p.count_dtype is None else f"l{i}"]
                for i, p in enumerate(props)
            }
            return columns, offset + count * record.itemsize
    # Lists of varying lengths: walk record by record.
    codes = {"i1": "b", "u1": "B", "i2": "h", "u2": "H", "i4": "i", "u4": "I", "f4": "f", "f8": "d"}
    values: dict[str, list] = {p.name: [] for p in props}
    pos = offset
    try:
        for _ in range(count):
            for p in props:
                if p.count_dtype is None:
                    values[p.name].append(struct.unpack_from(endian + codes[p.dtype], data, pos)[0])
                    pos += np.dtype(p.dtype).itemsize
                else:
                    (k,) = struct.unpack_from(endian + codes[p.count_dtype], data, pos)
                    k = _list_length(k, element, name)
                    pos += np.dtype(p.count_dtype).itemsize
                    items = struct.unpack_from(f"{endian}{k}{codes[p.dtype]}", data, pos)
                    values[p.name].append(np.array(items, dtype=p.dtype))
                    pos += k * np.dtype(p.dtype).itemsize
    except struct.error:
        raise truncated from None
    columns = {
        p.name: np.array(values[p.name], dtype=p.dtype) if p.count_dtype is None else values[p.name]
        for p in props
    }
    return columns, pos


def _list_length(value: float, element: _PlyElement, name: str) -> int:
    """A list's item count read from the data: a whole number ≥ 0, else MeshFileError."""
    value = value.item() if isinstance(value, np.generic) else value
    if not (np.isfinite(value) and value >= 0 and value == int(value)):
        raise MeshFileError(f"{name}: bad list length {value!r} in element '{element.name}'")
    return int(value)


def _read_ply_ascii(values: np.ndarray, cursor: int, element: _PlyElement, name: str):
    """ASCII counterpart of :func:`_read_ply_binary` on the file's numbers (float64)."""
    props, count = element.properties, element.count
    truncated = MeshFileError(
        f"{name}: truncated file: the data of element '{element.name}' ({count} announced) "
        "ends early"
    )
    # Guess a fixed record width from the first record, then verify it.
    width, pos, starts = 0, cursor, []
    for p in props:
        starts.append(width)
        if p.count_dtype is None:
            width += 1
            pos += 1
            continue
        if count == 0:
            continue
        if pos >= len(values):
            raise truncated
        k = _list_length(values[pos], element, name)
        width += 1 + k
        pos += 1 + k
    if count and cursor + count * width <= len(values):
        table = values[cursor : cursor + count * width].reshape(count, width)
        ok = True
        columns = {}
        for p, start in zip(props, starts, strict=True):
            if p.count_dtype is None:
                columns[p.name] = table[:, start]
                continue
            k = int(table[0, start])
            ok &= bool(np.all(table[:, start] == k))
            columns[p.name] = table[:, start + 1 : start + 1 + k]
        if ok:
            return columns, cursor + count * width
    out: dict[str, list] = {p.name: [] for p in props}
    pos = cursor
    for _ in range(count):
        for p in props:
            if pos >= len(values):
                raise truncated
            if p.count_dtype is None:
                out[p.name].append(values[pos])
                pos += 1
                continue
            k = _list_length(values[pos], element, name)
            if pos + 1 + k > len(values):
                raise truncated
            out[p.name].append(values[pos + 1 : pos + 1 + k])
            pos += 1 + k
    columns = {
        p.name: np.array(out[p.name]) if p.count_dtype is None else out[p.name] for p in props
    }
    return columns, pos


def read_ply(data: bytes, name: str) -> MeshData:
    if data.startswith(BOM.encode("utf-8")):
        data = data[3:]
    fmt, elements, offset = _read_ply_header(data, name)
    tables: dict[str, dict] = {}
    if fmt == "ascii":
        try:  # whole-array parsing; numpy >= 2 raises on any token it cannot read whole
            values = np.fromstring(data[offset:], dtype=np.float64, sep=" ")
        except ValueError:
            tokens = data[offset:].decode("ascii", "replace").split()
            bad = next((t for t in tokens if not is_number(t)), None)
            if bad is not None:
                raise MeshFileError(f"{name}: bad number {bad!r} in the PLY data") from None
            values = np.array(tokens, dtype=np.float64)  # e.g. Unicode spaces between them
        cursor = 0
        for element in elements:
            tables[element.name], cursor = _read_ply_ascii(values, cursor, element, name)
        if cursor != len(values):
            raise MeshFileError(
                f"{name}: {len(values) - cursor} values after the last element: the header's "
                "counts do not match the data"
            )
    else:
        for element in elements:
            tables[element.name], offset = _read_ply_binary(data, offset, element, fmt, name)
        if data[offset:].strip(b" \t\r\n\0"):
            raise MeshFileError(
                f"{name}: {len(data) - offset} bytes after the last element: the header's "
                "counts do not match the data"
            )

    vertex = tables.get("vertex", {})
    if not all(
        axis in vertex and isinstance(vertex[axis], np.ndarray) and vertex[axis].ndim == 1
        for axis in "xyz"
    ):
        raise MeshFileError(f"{name}: no vertex positions (element 'vertex' with x, y, z)")
    v = np.stack([vertex[axis] for axis in "xyz"], axis=1).astype(np.float64)
    face = tables.get("face", {})
    corners = face.get("vertex_indices", face.get("vertex_index"))
    if corners is None or len(corners) == 0:
        raise MeshFileError(f"{name}: no faces")
    if isinstance(corners, np.ndarray) and corners.ndim != 2:
        raise MeshFileError(f"{name}: the face corners are not a list property")
    if isinstance(corners, np.ndarray):
        if corners.shape[1] < 3:
            raise MeshFileError(f"{name}: face 0 has fewer than 3 corners")
        triangles = fan(corners)
        owner = np.repeat(np.arange(len(corners)), corners.shape[1] - 2)
    else:
        short = [i for i, c in enumerate(corners) if len(c) < 3]
        if short:
            raise MeshFileError(f"{name}: face {short[0]} has fewer than 3 corners")
        triangles, owner = fan_ragged(corners)
    if triangles.dtype.kind == "f":  # ASCII data, or float-typed binary indices
        # Check before casting: 1e30 or NaN would become a meaningless int64.
        whole = np.isfinite(triangles) & (triangles == np.round(triangles))
        if not whole.all():
            row, col = (int(i[0]) for i in np.nonzero(~whole))
            raise MeshFileError(
                f"{name}: face {int(owner[row])} has vertex index "
                f"{show_number(triangles[row, col])}, which is not a whole number"
            )
        outside = (triangles < 0) | (triangles >= len(v))
        if outside.any():
            row, col = (int(i[0]) for i in np.nonzero(outside))
            raise MeshFileError(
                f"{name}: face {int(owner[row])} references vertex "
                f"{show_number(triangles[row, col])} but the file has "
                f"{len(v)} vertices"
            )
    triangles = triangles.astype(np.int64)
    check_polygon_indices(triangles, owner, len(v), lambda _p: name)
    return MeshData(v, triangles)


def write_ply(mesh: MeshData, out: BinaryIO, ascii: bool) -> None:
    """PLY with float64 vertices (trimesh writes float32, which would round sculpted
    positions) and int32 triangle indices."""
    header = (
        "ply\n"
        f"format {'ascii' if ascii else 'binary_little_endian'} 1.0\n"
        "comment written by GoGreen Sculpt\n"
        f"element vertex {len(mesh.vertices)}\n"
        "property double x\nproperty double y\nproperty double z\n"
        f"element face {len(mesh.faces)}\n"
        "property list uchar int vertex_indices\nend_header\n"
    )
    out.write(header.encode("ascii"))
    if ascii:
        write_rows(out, "%.17g %.17g %.17g\n", mesh.vertices)
        write_int_rows(out, b"3 ", mesh.faces, b"  \n")
        return
    out.write(np.ascontiguousarray(mesh.vertices, dtype="<f8").tobytes())
    record = np.dtype([("n", "u1"), ("i", "<i4", 3)])
    faces = np.empty(len(mesh.faces), dtype=record)
    faces["n"], faces["i"] = 3, mesh.faces
    out.write(faces.tobytes())
