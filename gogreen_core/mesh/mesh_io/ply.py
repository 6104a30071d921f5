"""PLY (Stanford polygon files), ASCII and binary, read and written here rather than by trimesh,
which silently drops the faces of a truncated binary file and writes float32 positions.

Reading: positions ``x, y, z``; texture coordinates (:data:`UV_PROPERTIES`); faces
(``vertex_indices`` or ``vertex_index`` lists) and triangle strips (element ``tristrips``).
Vertices that carry attributes besides their position are welded where their positions are
equal (exporters split them for their attributes, Blender along UV seams); ``MeshData.uv`` holds
the file's per-vertex texture coordinates and ``uv_faces`` the file's vertex of each corner.
Writing: float64 positions, int32 indices, ``s, t`` split at the seams.
"""

from __future__ import annotations

from typing import BinaryIO

import numpy as np

from gogreen_core.mesh.mesh_io.data import MeshData, MeshFileError, first_non_finite
from gogreen_core.mesh.mesh_io.ply_elements import (
    Columns,
    PlyList,
    ascii_numbers,
    read_ascii_element,
    read_binary_element,
    read_header,
    row_problem,
)
from gogreen_core.mesh.mesh_io.polygons import triangulate
from gogreen_core.mesh.mesh_io.text import (
    BOM,
    DOS_EOF,
    show_number,
    without_dos_eof,
    write_rows,
)
from gogreen_core.mesh.mesh_io.weld import split_at_seams, weld

__all__ = ["UV_PROPERTIES", "read_ply", "write_ply"]

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
    """The items of ``lists`` as int64; MeshFileError naming the record of one that is not a
    whole number (checked before the cast, which would make a meaningless int64 of 1e30 or
    NaN) or not in [0, n_vertices) (-1 allowed in strips, where it separates them)."""
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
    kept: np.ndarray = triangles[(a != b) & (b != c) & (a != c)]
    return kept


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
