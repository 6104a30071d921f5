"""OFF (Object File Format), read here rather than by trimesh (which silently drops the faces of
a truncated file) and written. Colours after a vertex's or a face's numbers are ignored."""

from __future__ import annotations

import contextlib
import re
from typing import BinaryIO

import numpy as np

from gogreen_core.mesh.mesh_io.data import MeshData, MeshFileError, first_non_finite
from gogreen_core.mesh.mesh_io.polygons import check_corner_indices, triangulate
from gogreen_core.mesh.mesh_io.text import is_number, text_lines, write_rows

__all__ = ["read_off", "write_off"]


def read_off(data: bytes, name: str) -> MeshData:
    rows = [  # (line number, content without comment), non-empty only
        (number, line)
        for number, raw in enumerate(text_lines(data).split("\n"), start=1)
        if (line := raw.split("#", 1)[0].strip())
    ]
    if not rows:
        raise MeshFileError(f"{name}: no data (only comments or blank lines)")
    head = rows[0][1].split()
    # [ST][C][N][4][n]OFF, the vertex count possibly glued to it ("OFF8 6 12", ModelNet40).
    match = re.fullmatch(r"([STCN4n]*OFF)(\d*)", head[0])
    if match is None:
        raise MeshFileError(f"{name}: not an OFF file (it starts with {head[0]!r})")
    keyword = match[1]
    head = [keyword, match[2], *head[1:]] if match[2] else head
    if "4" in keyword or "n" in keyword:
        raise MeshFileError(f"{name}: {keyword} files (not 3-D) are not supported")
    counts, first = head[1:], 1
    if not counts:
        if len(rows) < 2:
            raise MeshFileError(f"{name}: truncated file (no vertex and face counts)")
        counts, first = rows[1][1].split(), 2
    try:
        n_vertices, n_faces = int(counts[0]), int(counts[1])
    except (ValueError, IndexError):
        raise MeshFileError(f"{name}: bad vertex and face counts {' '.join(counts)!r}") from None
    if n_faces < 0 or n_vertices < 0:
        raise MeshFileError(f"{name}: negative vertex or face count ({n_vertices} {n_faces})")
    if n_vertices == 0:
        raise MeshFileError(f"{name}: no vertices (counts {n_vertices} {n_faces})")
    vertex_rows = rows[first : first + n_vertices]
    face_rows = rows[first + n_vertices : first + n_vertices + n_faces]
    if len(vertex_rows) < n_vertices or len(face_rows) < n_faces:
        raise MeshFileError(
            f"{name}: truncated file: the header announces {n_vertices} vertices and {n_faces} "
            f"faces, the file holds {len(rows) - first} lines of them"
        )
    if len(rows) > first + n_vertices + n_faces:
        raise MeshFileError(
            f"{name}, line {rows[first + n_vertices + n_faces][0]}: data after the last face "
            "(the header's counts do not match the file)"
        )
    v = _off_vertices(vertex_rows, name)
    if (bad := first_non_finite(v)) is not None:
        raise MeshFileError(
            f"{name}, line {vertex_rows[bad][0]}: vertex {bad} has a non-finite coordinate"
        )
    if n_faces == 0:
        raise MeshFileError(f"{name}: no faces")
    table = _off_polygons_fast(face_rows)
    if table is not None:
        corners, sizes = table.ravel(), np.full(len(table), table.shape[1])
    else:
        corners, sizes = _off_polygons(face_rows, n_vertices, name)
    check_corner_indices(corners, sizes, n_vertices, lambda p: f"{name}, line {face_rows[p][0]}")
    return MeshData(v, corners[triangulate(v, corners, sizes)])


def _off_vertices(vertex_rows: list[tuple[int, str]], name: str) -> np.ndarray:
    """(N, 3) positions from OFF vertex lines (extra values such as colours ignored)."""
    tokens = " ".join(line for _, line in vertex_rows).split()
    if len(tokens) == 3 * len(vertex_rows):  # the common case: exactly x y z on every line
        with contextlib.suppress(ValueError):
            return np.array(tokens, dtype=np.float64).reshape(-1, 3)
    coordinates = []
    for number, line in vertex_rows:
        words = line.split()
        if len(words) < 3:
            raise MeshFileError(f"{name}, line {number}: a vertex needs 3 coordinates")
        if not all(map(is_number, words[:3])):
            raise MeshFileError(f"{name}, line {number}: bad number in a vertex")
        coordinates.append(words[:3])
    return np.array(coordinates, dtype=np.float64)


def _off_polygons_fast(face_rows: list[tuple[int, str]]) -> np.ndarray | None:
    """(F, k) indices when every face line is exactly ``k a b c ...`` with the same k ≥ 3
    (all triangles, all quads), else None."""
    tokens = " ".join(line for _, line in face_rows).split()
    width = len(tokens) // len(face_rows)
    if width < 4 or len(tokens) != width * len(face_rows):
        return None
    try:
        table = np.array(tokens, dtype=np.int64).reshape(-1, width)
    except (ValueError, OverflowError):  # the line-by-line reader names the line
        return None
    return table[:, 1:] if np.all(table[:, 0] == width - 1) else None


def _off_polygons(
    face_rows: list[tuple[int, str]], n_vertices: int, name: str
) -> tuple[np.ndarray, np.ndarray]:
    """Corners (C,) and sizes (F,) of the faces of OFF face lines of any sizes; values after a
    face's indices (a colour) are ignored."""
    polygons: list[list[int]] = []
    for face, (number, line) in enumerate(face_rows):
        words = line.split()
        try:
            k = int(words[0])
            corners = [int(w) for w in words[1 : 1 + k]]  # Python ints: no overflow
        except ValueError:
            raise MeshFileError(f"{name}, line {number}: bad face {line!r}") from None
        if k < 3:
            raise MeshFileError(f"{name}, line {number}: a face needs at least 3 corners")
        if len(corners) < k:
            raise MeshFileError(
                f"{name}, line {number}: the face announces {k} corners but lists {len(corners)}"
            )
        outside = [c for c in corners if not 0 <= c < n_vertices]
        if outside:
            raise MeshFileError(
                f"{name}, line {number}: face {face} references vertex {outside[0]} but the file "
                f"has {n_vertices} vertices"
            )
        polygons.append(corners)
    sizes = np.array([len(p) for p in polygons], dtype=np.int64)
    return np.array([c for p in polygons for c in p], dtype=np.int64), sizes


def write_off(mesh: MeshData, out: BinaryIO) -> None:
    header = f"OFF\n# written by GoGreen Sculpt\n{len(mesh.vertices)} {len(mesh.faces)} 0\n"
    out.write(header.encode("ascii"))
    write_rows(out, "%.17g %.17g %.17g\n", mesh.vertices)
    write_rows(out, "3 %d %d %d\n", mesh.faces)
