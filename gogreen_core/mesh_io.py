"""Mesh files: OBJ, PLY (ASCII and binary), STL and OFF, loaded and saved without reordering.

Loading keeps the vertices exactly as the file lists them: same count, same order, no merging.
Polygons are fan-triangulated (corners ``0, k, k+1``), so a quad becomes two triangles in place.

* **OBJ** is parsed here: trimesh's OBJ loader splits vertices that carry several texture
  coordinates (UV seams), which changes the vertex count and order that a sculpting session and
  its replay rely on. Positions stay as listed; texture coordinates are kept per face corner
  (:attr:`MeshData.uv`, :attr:`MeshData.uv_faces`) so they survive a load/save round trip.
  Normals (``vn``), materials and groups are not kept: normals are recomputed after sculpting.
  A statement that is not in the OBJ specification is refused (a damaged line is reported, not
  dropped), as is an index too large for any file. A regular file is parsed with whole-array
  operations (about 2x faster than ``trimesh.load`` on a million vertices); anything unusual
  goes to a strict line-by-line reader that accepts the same files with the same result and
  names the line of any problem.
* **PLY** and **OFF** are parsed here as well, because trimesh silently drops the faces of a
  truncated binary PLY or OFF file instead of reporting it. Any vertex properties besides
  ``x, y, z`` are read and ignored.
* **STL** goes through trimesh with ``process=False``. An STL file has no shared vertices: each
  triangle lists its own three corners, so a loaded STL has 3·M vertices in file order (no
  welding, which would renumber them). STL stores float32, so saving to STL rounds positions.

Text is read as UTF-8; a leading byte-order mark is skipped and CR LF or lone CR line ends are
accepted, so no first vertex or line is lost to them.

Every problem raises :class:`MeshFileError` (a ``ValueError``) whose message starts with the
file name, e.g. ``"spot.obj, line 3012: face 12 references vertex 9001 but the file has 2930
vertices"``. Vertex and face numbers in messages are counted the way the format counts them:
from 1 in OBJ, from 0 in PLY and OFF.

Saving is atomic: the data is written to a temporary file in the destination's folder, flushed
and fsync'ed, then renamed over the destination with :func:`os.replace`. If anything fails the
temporary file is removed and an existing destination is left byte-identical. Coordinates are
written with ``%.17g`` in text formats and as float64 in binary PLY, so they reload bit for bit;
indices are formatted with whole-array operations.
"""

from __future__ import annotations

import contextlib
import io
import itertools
import os
import secrets
import stat
import struct
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

import numpy as np

__all__ = [
    "MESH_FORMATS",
    "MeshData",
    "MeshFileError",
    "load_mesh",
    "save_mesh",
    "write_atomic",
    "write_bytes_atomic",
    "write_text_atomic",
]

#: File extensions :func:`load_mesh` and :func:`save_mesh` understand (lower case).
MESH_FORMATS = (".obj", ".ply", ".stl", ".off")


class MeshFileError(ValueError):
    """A mesh file could not be read or written; the message names the file and the problem."""


@dataclass
class MeshData:
    """A triangle mesh as plain arrays.

    Attributes
    ----------
    vertices : (N, 3) float64
        Positions, in the file's units and order.
    faces : (M, 3) int64
        Vertex indices (from 0) of each triangle, counter-clockwise seen from outside when the
        file is consistently oriented.
    uv : (T, 2) float64 or None
        Texture coordinates (OBJ ``vt``), shared between corners like the file shares them.
    uv_faces : (M, 3) int64 or None
        Per face corner, the row of ``uv`` it uses; a row of -1 marks a face that has no
        texture coordinates (allowed in OBJ). Set together with ``uv``.
    source : str or None
        Path of the file the mesh was loaded from.
    """

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray | None = None
    uv_faces: np.ndarray | None = None
    source: str | None = None

    def __post_init__(self) -> None:
        self.vertices = np.asarray(self.vertices, dtype=np.float64)
        self.faces = np.asarray(self.faces, dtype=np.int64)
        if self.vertices.ndim != 2 or self.vertices.shape[1] != 3:
            raise ValueError(f"vertices must have shape (N, 3), got {self.vertices.shape}")
        if self.faces.ndim != 2 or self.faces.shape[1] != 3:
            raise ValueError(f"faces must have shape (M, 3), got {self.faces.shape}")
        if (self.uv is None) != (self.uv_faces is None):
            raise ValueError("uv and uv_faces must be given together")
        if self.uv is not None:
            self.uv = np.asarray(self.uv, dtype=np.float64)
            self.uv_faces = np.asarray(self.uv_faces, dtype=np.int64)

    def copy(self) -> MeshData:
        """A deep copy (arrays are copied, ``source`` is shared)."""
        return MeshData(
            vertices=self.vertices.copy(),
            faces=self.faces.copy(),
            uv=None if self.uv is None else self.uv.copy(),
            uv_faces=None if self.uv_faces is None else self.uv_faces.copy(),
            source=self.source,
        )


# -- validation --------------------------------------------------------------------------------
def _validate(mesh: MeshData, name: str) -> None:
    """Raise MeshFileError unless ``mesh`` is a usable triangle mesh."""
    v, f = mesh.vertices, mesh.faces
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
        raise MeshFileError(f"{name}: no vertices")
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise MeshFileError(f"{name}: no faces")
    finite = np.isfinite(v).all(axis=1)
    if not finite.all():
        bad = int(np.flatnonzero(~finite)[0])
        raise MeshFileError(f"{name}: vertex {bad} has a non-finite coordinate {v[bad].tolist()}")
    outside = (f < 0) | (f >= len(v))
    if outside.any():
        row, col = (int(i[0]) for i in np.nonzero(outside))
        raise MeshFileError(
            f"{name}: face {row} references vertex {int(f[row, col])} "
            f"but the mesh has {len(v)} vertices"
        )
    if mesh.uv is None:
        return
    uv, uvf = mesh.uv, mesh.uv_faces
    if uv.ndim != 2 or uv.shape[1] != 2 or not np.isfinite(uv).all():
        raise MeshFileError(f"{name}: texture coordinates must be finite (T, 2) values")
    if uvf.shape != f.shape:
        raise MeshFileError(f"{name}: uv_faces has shape {uvf.shape} but there are {len(f)} faces")
    partial = (uvf < 0).any(axis=1) & (uvf >= 0).any(axis=1)
    if partial.any() or (uvf < -1).any() or (uvf >= len(uv)).any():
        raise MeshFileError(
            f"{name}: uv_faces must hold rows of -1 or indices below {len(uv)} (texture "
            "coordinates)"
        )


def _fan(polygons: np.ndarray) -> np.ndarray:
    """Fan-triangulate polygons of equal size: (P, k) → (P·(k-2), 3), in polygon order."""
    k = polygons.shape[1]
    if k == 3:
        return polygons
    fans = [polygons[:, [0, i, i + 1]] for i in range(1, k - 1)]
    return np.stack(fans, axis=1).reshape(-1, 3)


def _fan_ragged(polygons: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Fan-triangulate polygons of any sizes ≥ 3: triangles (T, 3) and their polygon (T,)."""
    triangles: list[np.ndarray] = []
    owner: list[np.ndarray] = []
    for p, corners in enumerate(polygons):
        tri = _fan(corners[None, :])
        triangles.append(tri)
        owner.append(np.full(len(tri), p, dtype=np.int64))
    if not triangles:
        return np.zeros((0, 3), dtype=np.int64), np.zeros(0, dtype=np.int64)
    return np.concatenate(triangles), np.concatenate(owner)


def _check_polygon_indices(
    triangles: np.ndarray, owner: np.ndarray, n_vertices: int, where: Callable[[int], str]
) -> None:
    """Raise MeshFileError for the first triangle whose index is not in [0, n_vertices)."""
    outside = (triangles < 0) | (triangles >= n_vertices)
    if outside.any():
        row, col = (int(i[0]) for i in np.nonzero(outside))
        polygon = int(owner[row])
        raise MeshFileError(
            f"{where(polygon)}: face {polygon} references vertex {int(triangles[row, col])} "
            f"but the file has {n_vertices} vertices"
        )


_CHUNK = 100_000  # rows formatted at a time: bounds the temporary memory of a large mesh


def _write_rows(out: BinaryIO, fmt: str, table: np.ndarray) -> None:
    """Write each row of ``table`` formatted with ``fmt`` (which ends in a newline); ``%.17g``
    for floats reloads bit for bit. Much faster than np.savetxt, which formats row by row."""
    for start in range(0, len(table), _CHUNK):
        rows = table[start : start + _CHUNK]
        out.write(((fmt * len(rows)) % tuple(rows.ravel().tolist())).encode("ascii"))


def _write_int_rows(out: BinaryIO, prefix: bytes, table: np.ndarray, separators: bytes) -> None:
    """Write rows ``prefix`` + the row's integers (>= 0), each followed by its separator
    (``separators[j]`` after column j: b" ", b"/" or b"\n"), in decimal, with whole-array
    operations: a fixed-width digit grid whose leading zeros are dropped."""
    n, columns = table.shape
    if n == 0:
        return
    width = len(str(int(table.max())))
    kind = np.uint32 if table.max() < 2**32 else np.uint64  # 32-bit division is faster
    row_width = len(prefix) + columns * (width + 1)
    for start in range(0, n, _CHUNK):
        rows = table[start : start + _CHUNK].astype(kind)
        m = len(rows)
        grid = np.empty((m, row_width), dtype=np.uint8)
        grid[:, : len(prefix)] = np.frombuffer(prefix, dtype=np.uint8)
        cells = grid[:, len(prefix) :].reshape(m, columns, width + 1)
        cells[:, :, width] = np.frombuffer(separators, dtype=np.uint8)
        mask = np.ones((m, row_width), dtype=bool)
        keep = mask[:, len(prefix) :].reshape(m, columns, width + 1)
        rest = rows.copy()
        for digit in range(width - 1, -1, -1):  # last digit first
            rest, cells[:, :, digit] = np.divmod(rest, kind(10))
            keep[:, :, digit] = rows >= 10 ** (width - 1 - digit)
        keep[:, :, width - 1] = True  # 0 keeps its one digit
        cells[:, :, :width] += ord("0")
        out.write(grid[mask].tobytes())


# -- OBJ ---------------------------------------------------------------------------------------
#: Larger 1-based indices cannot be real (and would overflow int64 arrays).
_MAX_INDEX = 2**53

#: Every statement of the OBJ specification; the reader keeps v, vt and f, ignores the others
#: (normals, groups, materials, smoothing, lines, points, free-form geometry) and refuses any
#: other word, so that a damaged line is reported instead of silently dropped.
_OBJ_STATEMENTS = frozenset(
    "v vt vn vp f fo l p g o s mg usemtl mtllib usemap maplib cstype deg bmat step curv curv2 "
    "surf parm trim hole scrv sp end con bevel c_interp d_interp lod shadow_obj trace_obj ctech "
    "stech call csh".split()
)
_BOM = "\ufeff"


def _text_lines(data: bytes) -> str:
    """The file as text with '\\n' line ends: UTF-8 (undecodable bytes replaced), a leading
    byte-order mark removed, CR LF and lone CR (old Mac files) read as line ends."""
    text = data.decode("utf-8", errors="replace")
    if text.startswith(_BOM):
        text = text[1:]
    if "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    return text


def _read_obj(data: bytes, name: str) -> MeshData:
    """OBJ: the fast whole-array reader when the file is regular, else the strict one."""
    mesh = _read_obj_fast(data)
    return _read_obj_strict(data, name) if mesh is None else mesh


def _read_obj_strict(data: bytes, name: str) -> MeshData:
    """Line by line: accepts what the fast reader accepts, the same way, and names the line of
    any problem."""
    vertices: list[tuple[float, float, float]] = []
    uvs: list[tuple[float, float]] = []
    faces: list[tuple[int, int, int]] = []
    uv_faces: list[tuple[int, int, int]] = []
    face_lines: list[int] = []  # source line of each polygon
    face_first: list[int] = []  # first triangle of each polygon
    textured = 0

    def index(token: str, count: int, kind: str, line: int) -> int:
        try:
            i = int(token)
        except ValueError:
            raise MeshFileError(f"{name}, line {line}: bad {kind} index {token!r}") from None
        if i > _MAX_INDEX:  # no file holds that many; int64 arrays could not even store it
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

    text = _text_lines(data)
    for number, raw in enumerate(text.split("\n"), start=1):
        if "#" in raw:
            raw = raw.split("#", 1)[0]
        parts = raw.split()
        if not parts:
            continue
        tag = parts[0]
        if tag not in _OBJ_STATEMENTS:
            raise MeshFileError(
                f"{name}, line {number}: unknown statement {tag[:20]!r} (not an OBJ file?)"
            )
        if tag == "v":
            if len(parts) < 4:
                raise MeshFileError(f"{name}, line {number}: a vertex needs 3 coordinates")
            vertices.append(numbers(parts[1:4], number, raw))
        elif tag == "vt":
            if len(parts) < 2:
                raise MeshFileError(f"{name}, line {number}: empty texture coordinate")
            u, *v = numbers(parts[1:3], number, raw)
            if not np.isfinite([u, *v]).all():
                raise MeshFileError(
                    f"{name}, line {number}: texture coordinate {len(uvs) + 1} has a non-finite "
                    f"value {[u, *v]}"
                )
            uvs.append((u, v[0] if v else 0.0))
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
            if tex:
                textured += 1
            else:
                tex = [-1] * len(pos)
            face_lines.append(number)
            face_first.append(len(faces))
            for k in range(1, len(pos) - 1):  # fan triangulation
                faces.append((pos[0], pos[k], pos[k + 1]))
                uv_faces.append((tex[0], tex[k], tex[k + 1]))

    if not vertices:
        raise MeshFileError(f"{name}: no vertices (empty or not an OBJ file)")
    if not faces:
        raise MeshFileError(f"{name}: no faces (the file has only points)")
    v = np.array(vertices, dtype=np.float64)
    f = np.array(faces, dtype=np.int64)

    def line_of_triangle(row: int) -> int:
        return face_lines[int(np.searchsorted(face_first, row, side="right")) - 1]

    finite = np.isfinite(v).all(axis=1)
    if not finite.all():
        bad = int(np.flatnonzero(~finite)[0])
        lines = (n for n, raw in enumerate(text.split("\n"), 1) if raw.split()[:1] == ["v"])
        raise MeshFileError(
            f"{name}, line {next(itertools.islice(lines, bad, None))}: vertex {bad + 1} has a "
            f"non-finite coordinate {v[bad].tolist()}"
        )
    outside = f >= len(v)
    if outside.any():
        row, col = (int(i[0]) for i in np.nonzero(outside))
        polygon = int(np.searchsorted(face_first, row, side="right"))
        raise MeshFileError(
            f"{name}, line {line_of_triangle(row)}: face {polygon} references vertex "
            f"{int(f[row, col]) + 1} but the file has {len(v)} vertices"
        )
    mesh = MeshData(v, f)
    if textured:
        t = np.array(uv_faces, dtype=np.int64)
        outside = t >= len(uvs)
        if outside.any():
            row, col = (int(i[0]) for i in np.nonzero(outside))
            raise MeshFileError(
                f"{name}, line {line_of_triangle(row)}: face references texture coordinate "
                f"{int(t[row, col]) + 1} but the file has {len(uvs)} texture coordinates"
            )
        mesh.uv = np.array(uvs, dtype=np.float64).reshape(-1, 2)
        mesh.uv_faces = t
    return mesh


# Fast path: whole-array parsing of a regular OBJ file. It returns None as soon as anything is
# unusual (a comment after data, a tab after a tag, mixed corner forms, a bad number, an index
# out of range, ...); _read_obj then runs the strict line-by-line reader, which either accepts
# the file the same way or names the line at fault. np.fromstring (numpy >= 2) raises on any
# token it cannot read whole, and rounds decimals correctly like float().
#
# The lines of one kind (v, vt or f) are handled as a "piece": their contents joined by
# b"\n" + tag, i.e. the file's bytes from after the first line's tag to the end of the last
# line, when they form one block.
_SPACE = 32  # bytes <= 32 separate tokens (space, tab, line ends, control characters)
_MAX_RUNS = 10_000  # more runs of same-kind lines than this: gather them with a byte mask
_MAX_OTHER = 1 << 20  # bytes of other lines checked one by one in Python


@dataclass
class _ObjSections:
    """The v, vt and f lines of an OBJ file as pieces (see above; None when there are no such
    lines), and per face line the count of v and vt lines before it (an int when the same for
    all, None when unknown: relative indices then go to the strict reader)."""

    v: bytes | None
    vt: bytes | None
    f: bytes | None
    v_before: np.ndarray | int | None
    vt_before: np.ndarray | int | None


def _other_lines_are_fine(text: bytes) -> bool:
    """Whether lines other than v, vt and f are comments, blank, or known OBJ statements."""
    for line in text.decode("utf-8", "replace").split("\n"):
        words = line.split()
        if not words or line.startswith("#"):
            continue
        if "#" in line or words[0] not in _OBJ_STATEMENTS or words[0] in ("v", "vt", "f", "fo"):
            return False
    return True


def _block(data: bytes, tag: bytes, lo: int, hi: int) -> tuple[int, int] | None:
    """[start, end) from the first line starting with ``tag`` in data[lo:hi] (``lo`` a line
    start) to the '\\n' of the last one; None when there is none."""
    if data.startswith(tag, lo):
        start = lo
    else:
        found = data.find(b"\n" + tag, lo, hi)
        if found < 0:
            return None
        start = found + 1
    last = data.rfind(b"\n" + tag, start, hi)
    return start, data.find(b"\n", start if last < 0 else last + 1, hi)


def _obj_sections_by_blocks(data: bytes) -> _ObjSections | None:
    """Sections of the usual layout: one block of each of v, vt, vn and f lines and a few
    other lines (comments, g, s, usemtl...) around them; None otherwise. Found with bytes
    find/count alone, without an array over every byte."""
    blocks = {}
    for tag in (b"v ", b"f "):
        blocks[tag] = _block(data, tag, 0, len(data))
        if blocks[tag] is None:
            return None
    spans = sorted(blocks.values())
    if spans[0][1] >= spans[1][0]:
        return None  # interleaved (a v line after a face, ...)
    gaps = [(0, spans[0][0]), (spans[0][1] + 1, spans[1][0]), (spans[1][1] + 1, len(data))]
    for tag in (b"vt ", b"vn "):  # each within one gap
        for k, (lo, hi) in enumerate(gaps):
            found = _block(data, tag, lo, hi)
            if found is not None:
                blocks[tag] = found
                gaps[k : k + 1] = [(lo, found[0]), (found[1] + 1, hi)]
                break
    if b"vn " in blocks:
        start, end = blocks.pop(b"vn ")
        if data.count(b"\n", start, end) != data.count(b"\nvn ", start, end):
            return None
    if sum(hi - lo for lo, hi in gaps) > _MAX_OTHER:
        return None
    if not all(_other_lines_are_fine(data[lo:hi]) for lo, hi in gaps):
        return None
    pieces = {tag: data[start + len(tag) : end] for tag, (start, end) in blocks.items()}
    faces_start = blocks[b"f "][0]

    def before(tag: bytes) -> int | None:
        if tag not in blocks:
            return 0
        return pieces[tag].count(b"\n") + 1 if blocks[tag][1] < faces_start else None

    return _ObjSections(
        pieces[b"v "], pieces.get(b"vt "), pieces[b"f "], before(b"v "), before(b"vt ")
    )


def _obj_sections_by_lines(data: bytes) -> _ObjSections | None:
    """Sections of any layout, by classifying every line with whole-array operations."""
    arr = np.frombuffer(data + b"   ", dtype=np.uint8)
    ends = np.flatnonzero(arr == ord("\n"))
    starts = np.concatenate([[0], ends[:-1] + 1])
    c0, c1, c2 = arr[starts], arr[starts + 1], arr[starts + 2]
    kinds = {
        b"v ": (c0 == ord("v")) & (c1 == ord(" ")),
        b"vt ": (c0 == ord("v")) & (c1 == ord("t")) & (c2 == ord(" ")),
        b"f ": (c0 == ord("f")) & (c1 == ord(" ")),
    }
    if b"#" in data:  # a comment is fine only on a line of its own
        hashes = np.flatnonzero(arr == ord("#"))
        if (c0[np.searchsorted(starts, hashes, side="right") - 1] != ord("#")).any():
            return None
    ignored = (c0 == ord("#")) | (starts == ends)
    ignored |= (c0 == ord("v")) & (c1 == ord("n")) & (c2 == ord(" "))  # normals: not kept
    others = np.flatnonzero(~(kinds[b"v "] | kinds[b"vt "] | kinds[b"f "] | ignored))
    for line in others.tolist():  # g, s, usemtl...
        if not _other_lines_are_fine(data[starts[line] : ends[line]]):
            return None
    pieces = {}
    for tag, keep in kinds.items():
        if not keep.any():
            pieces[tag] = None
            continue
        edges = np.diff(np.concatenate([[0], keep.view(np.int8), [0]]))
        first, last = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
        if len(first) <= _MAX_RUNS:  # runs of lines of this kind: copy them whole
            bounds = zip(starts[first].tolist(), (ends[last] + 1).tolist(), strict=True)
            text = b"".join([data[a:b] for a, b in bounds])
        else:
            mask = np.repeat(keep, ends - starts + 1)
            text = arr[: len(mask)][mask].tobytes()
        pieces[tag] = text[len(tag) : -1]
    face_lines = np.flatnonzero(kinds[b"f "])
    return _ObjSections(
        pieces[b"v "],
        pieces[b"vt "],
        pieces[b"f "],
        np.cumsum(kinds[b"v "])[face_lines],
        np.cumsum(kinds[b"vt "])[face_lines],
    )


def _numbers_per_line(
    piece: bytes, tag: bytes, sentinel: bytes, dtype
) -> tuple[np.ndarray, np.ndarray] | None:
    """All numbers of a piece and how many each line has, or None if a token is not a number
    or a line of another kind is among them. A ``sentinel`` that the data cannot hold (NaN
    among finite floats, 0 among 1-based indices) replaces each line break to count them."""
    lines = piece.count(b"\n") + 1
    between = b" " + sentinel + b" " * max(1, len(tag) + 2 - len(sentinel))
    text = piece.replace(b"\n" + tag, between)
    if len(text) - len(piece) != (lines - 1) * (len(between) - len(tag) - 1):
        return None  # a line without the tag among them
    try:
        values = np.fromstring(text + b" " + sentinel, dtype, sep=" ")
    except ValueError:
        return None
    marks = np.flatnonzero(np.isnan(values) if sentinel == b"nan" else values == 0)
    if len(marks) != lines:
        return None  # a NaN or 0 in the data itself: the strict reader reports it
    counts = np.diff(marks, prepend=-1) - 1
    return np.delete(values, marks), counts


def _first_columns(values: np.ndarray, counts: np.ndarray, columns: int) -> np.ndarray:
    """The first ``columns`` values of each line, from line-major ``values`` (counts per line
    all >= columns), as a contiguous (lines, columns) array."""
    if counts.min() == counts.max():
        return np.ascontiguousarray(values.reshape(len(counts), -1)[:, :columns])
    firsts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    return values[firsts[:, None] + np.arange(columns)]


def _face_corners(piece: bytes) -> tuple[np.ndarray, np.ndarray, bool] | None:
    """Corner numbers (C, fields), corners per face line, and whether the corners are
    ``a//c`` (no texture), from the f piece; None unless every corner has the same form."""
    n_slashes = piece.count(b"/")
    if n_slashes == 0:
        parsed = _numbers_per_line(piece, b"f ", b"0", np.int64)
        return None if parsed is None else (parsed[0][:, None], parsed[1], False)
    text = piece.replace(b"\nf ", b"\n  ")
    if len(text) != len(piece) or text.count(b"\n") != piece.count(b"\nf "):
        return None
    buffer = np.frombuffer(text, dtype=np.uint8)
    word = buffer > _SPACE
    first = word.copy()
    first[1:] &= ~word[:-1]
    corner_starts = np.flatnonzero(first)
    line_starts = np.concatenate([[0], np.flatnonzero(buffer == ord("\n")) + 1, [len(text)]])
    corners = np.diff(np.searchsorted(corner_starts, line_starts))
    n_corners = len(corner_starts)
    per_corner = n_slashes // n_corners  # 1: "a/b"; 2: "a/b/c" or "a//c"
    doubled = text.count(b"//")
    if n_slashes % n_corners or per_corner > 2 or doubled not in (0, n_corners):
        return None
    if doubled and per_corner != 2:
        return None
    # Every corner must have the same number of slashes as the others.
    before = np.searchsorted(np.flatnonzero(buffer == ord("/")), corner_starts)
    if (np.diff(np.append(before, n_slashes)) != per_corner).any():
        return None
    fields = 2 if per_corner == 1 or doubled else 3
    try:
        numbers = np.fromstring(text.replace(b"/", b" "), np.int64, sep=" ")
    except ValueError:
        return None
    if len(numbers) != fields * n_corners:
        return None  # an empty field such as "1/ 2/ 3/"
    return numbers.reshape(-1, fields), corners, bool(doubled)


def _read_obj_fast(data: bytes) -> MeshData | None:
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    if b"\r" in data:
        data = data.replace(b"\r\n", b"\n")
        if b"\r" in data:
            return None
    if not data.endswith(b"\n"):
        data += b"\n"
    sections = _obj_sections_by_blocks(data)
    mesh = None if sections is None else _obj_from_sections(sections)
    if mesh is None:  # not the usual layout (faces grouped by material, ...), or a bad file
        sections = _obj_sections_by_lines(data)
        mesh = None if sections is None else _obj_from_sections(sections)
    return mesh


def _obj_from_sections(sections: _ObjSections) -> MeshData | None:
    if sections.v is None or sections.f is None:
        return None

    parsed = _numbers_per_line(sections.v, b"v ", b"nan", np.float64)
    if parsed is None or parsed[1].min() < 3:
        return None
    vertices = _first_columns(*parsed, 3)
    if not np.isfinite(vertices).all():
        return None

    uv = np.zeros((0, 2))
    if sections.vt is not None:
        parsed = _numbers_per_line(sections.vt, b"vt ", b"nan", np.float64)
        if parsed is None or parsed[1].min() < 1:
            return None
        values, counts = parsed
        if counts.max() == 1:
            uv = np.stack([values, np.zeros_like(values)], axis=1)
        elif counts.min() >= 2:
            uv = _first_columns(values, counts, 2)
        else:
            return None  # a mix of 1- and 2-value lines: left to the strict reader
        if not np.isfinite(uv).all():
            return None

    found = _face_corners(sections.f)
    if found is None:
        return None
    numbers, corners, doubled = found
    if corners.min() < 3:
        return None

    def indices(column: np.ndarray, counted, total: int) -> np.ndarray | None:
        """0-based indices from 1-based or relative ones (``counted``: entries read before each
        face line, see _ObjSections); None when one is 0, before the first entry, or past the
        last."""
        if (column == 0).any():
            return None
        relative = column < 0
        if relative.any():
            if counted is None:
                return None
            if not isinstance(counted, int):
                counted = counted[np.repeat(np.arange(len(corners)), corners)[relative]]
            column = column.copy()
            column[relative] += counted + 1
            if (column[relative] < 1).any():
                return None
        if column.max() > total:  # also catches indices too large for int64 (saturated)
            return None
        return column - 1

    position = indices(numbers[:, 0], sections.v_before, len(vertices))
    if position is None:
        return None
    mesh = MeshData(vertices, _fan_corners(position, corners))
    if numbers.shape[1] >= 2 and not doubled:
        texture = indices(numbers[:, 1], sections.vt_before, len(uv))
        if texture is None:
            return None
        mesh.uv, mesh.uv_faces = uv, _fan_corners(texture, corners)
    return mesh


def _fan_corners(corners: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """Fan triangles (T, 3) of polygons given as consecutive corners (C,) with sizes (P,):
    corners 0, k, k+1 of each polygon, in polygon order."""
    if sizes.min() == sizes.max():
        return _fan(corners.reshape(len(sizes), -1))
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    per_polygon = sizes - 2
    owner_first = np.repeat(first, per_polygon)
    k = np.arange(int(per_polygon.sum())) - np.repeat(
        np.concatenate([[0], np.cumsum(per_polygon)[:-1]]), per_polygon
    )
    return np.stack(
        [corners[owner_first], corners[owner_first + k + 1], corners[owner_first + k + 2]], axis=1
    )


def _write_obj(mesh: MeshData, out: BinaryIO) -> None:
    out.write(b"# written by GoGreen Sculpt\n")
    _write_rows(out, "v %.17g %.17g %.17g\n", mesh.vertices)
    if mesh.uv is None:
        _write_int_rows(out, b"f ", mesh.faces + 1, b"  \n")
        return
    _write_rows(out, "vt %.17g %.17g\n", mesh.uv)
    has_uv = mesh.uv_faces[:, 0] >= 0
    if has_uv.all():
        corners = np.stack([mesh.faces + 1, mesh.uv_faces + 1], axis=2).reshape(-1, 6)
        _write_int_rows(out, b"f ", corners, b"/ / /\n")
        return
    text = io.StringIO()  # some faces without texture coordinates: keep them so, in order
    for face, tex, textured in zip(
        (mesh.faces + 1).tolist(), (mesh.uv_faces + 1).tolist(), has_uv, strict=True
    ):
        if textured:
            text.write("f " + " ".join(f"{a}/{b}" for a, b in zip(face, tex, strict=True)))
        else:
            text.write("f {} {} {}".format(*face))
        text.write("\n")
    out.write(text.getvalue().encode("ascii"))


# -- PLY ---------------------------------------------------------------------------------------
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


def _read_ply(data: bytes, name: str) -> MeshData:
    if data.startswith(_BOM.encode("utf-8")):
        data = data[3:]
    fmt, elements, offset = _read_ply_header(data, name)
    tables: dict[str, dict] = {}
    if fmt == "ascii":
        try:  # whole-array parsing; numpy >= 2 raises on any token it cannot read whole
            values = np.fromstring(data[offset:], dtype=np.float64, sep=" ")
        except ValueError:
            tokens = data[offset:].decode("ascii", "replace").split()
            bad = next((t for t in tokens if not _is_number(t)), None)
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
        triangles = _fan(corners)
        owner = np.repeat(np.arange(len(corners)), corners.shape[1] - 2)
    else:
        short = [i for i, c in enumerate(corners) if len(c) < 3]
        if short:
            raise MeshFileError(f"{name}: face {short[0]} has fewer than 3 corners")
        triangles, owner = _fan_ragged(corners)
    if triangles.dtype.kind == "f":  # ASCII data, or float-typed binary indices
        # Check before casting: 1e30 or NaN would become a meaningless int64.
        whole = np.isfinite(triangles) & (triangles == np.round(triangles))
        if not whole.all():
            row, col = (int(i[0]) for i in np.nonzero(~whole))
            raise MeshFileError(
                f"{name}: face {int(owner[row])} has vertex index "
                f"{_show_number(triangles[row, col])}, which is not a whole number"
            )
        outside = (triangles < 0) | (triangles >= len(v))
        if outside.any():
            row, col = (int(i[0]) for i in np.nonzero(outside))
            raise MeshFileError(
                f"{name}: face {int(owner[row])} references vertex "
                f"{_show_number(triangles[row, col])} but the file has "
                f"{len(v)} vertices"
            )
    triangles = triangles.astype(np.int64)
    _check_polygon_indices(triangles, owner, len(v), lambda _p: name)
    return MeshData(v, triangles)


def _show_number(value: np.floating) -> str:
    """A value read from a file, shown as the file has it: whole numbers as integers, others
    in the shortest form of their own precision (float32 1e30 as '1e+30', not 1.00000002e30)."""
    if np.isfinite(value) and value == np.round(value) and abs(value) < _MAX_INDEX:
        return str(int(value))
    return str(value)


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def _write_ply(mesh: MeshData, out: BinaryIO, ascii: bool) -> None:
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
        _write_rows(out, "%.17g %.17g %.17g\n", mesh.vertices)
        _write_int_rows(out, b"3 ", mesh.faces, b"  \n")
        return
    out.write(np.ascontiguousarray(mesh.vertices, dtype="<f8").tobytes())
    record = np.dtype([("n", "u1"), ("i", "<i4", 3)])
    faces = np.empty(len(mesh.faces), dtype=record)
    faces["n"], faces["i"] = 3, mesh.faces
    out.write(faces.tobytes())


# -- OFF ---------------------------------------------------------------------------------------
def _read_off(data: bytes, name: str) -> MeshData:
    rows: list[tuple[int, str]] = []  # (line number, content without comment), non-empty only
    for number, raw in enumerate(_text_lines(data).split("\n"), start=1):
        if "#" in raw:
            raw = raw.split("#", 1)[0]
        line = raw.strip()
        if line:
            rows.append((number, line))
    if not rows:
        raise MeshFileError(f"{name}: no data (only comments or blank lines)")
    head = rows[0][1].split()
    keyword = head[0]
    if not keyword.endswith("OFF") or keyword.strip("STCN4n") != "OFF":
        raise MeshFileError(f"{name}: not an OFF file (it starts with {keyword!r})")
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
    finite = np.isfinite(v).all(axis=1)
    if not finite.all():
        bad = int(np.flatnonzero(~finite)[0])
        raise MeshFileError(
            f"{name}, line {vertex_rows[bad][0]}: vertex {bad} has a non-finite coordinate"
        )
    if n_faces == 0:
        raise MeshFileError(f"{name}: no faces")
    triangles = _off_triangles_fast(face_rows)
    if triangles is not None:
        owner = np.arange(len(triangles))
    else:
        triangles, owner = _off_polygons(face_rows, n_vertices, name)
    _check_polygon_indices(
        triangles, owner, n_vertices, lambda p: f"{name}, line {face_rows[p][0]}"
    )
    return MeshData(v, triangles)


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
        if not all(map(_is_number, words[:3])):
            raise MeshFileError(f"{name}, line {number}: bad number in a vertex")
        coordinates.append(words[:3])
    return np.array(coordinates, dtype=np.float64)


def _off_triangles_fast(face_rows: list[tuple[int, str]]) -> np.ndarray | None:
    """(F, 3) indices when every face line is exactly ``3 a b c``, else None."""
    tokens = " ".join(line for _, line in face_rows).split()
    if len(tokens) != 4 * len(face_rows):
        return None
    try:
        table = np.array(tokens, dtype=np.int64).reshape(-1, 4)
    except (ValueError, OverflowError):  # the strict reader names the line
        return None
    return table[:, 1:] if np.all(table[:, 0] == 3) else None


def _off_polygons(
    face_rows: list[tuple[int, str]], n_vertices: int, name: str
) -> tuple[np.ndarray, np.ndarray]:
    """Triangles (T, 3) and their face (T,) from OFF face lines of any sizes; values after a
    face's indices (a colour) are ignored."""
    polygons: list[np.ndarray] = []
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
        polygons.append(np.array(corners, dtype=np.int64))
    return _fan_ragged(polygons)


def _write_off(mesh: MeshData, out: BinaryIO) -> None:
    header = f"OFF\n# written by GoGreen Sculpt\n{len(mesh.vertices)} {len(mesh.faces)} 0\n"
    out.write(header.encode("ascii"))
    _write_rows(out, "%.17g %.17g %.17g\n", mesh.vertices)
    _write_int_rows(out, b"3 ", mesh.faces, b"  \n")


# -- STL (trimesh) -----------------------------------------------------------------------------
def _read_stl(data: bytes, name: str) -> MeshData:
    import trimesh

    try:
        loaded = trimesh.load(io.BytesIO(data), file_type="stl", process=False, force="mesh")
    except Exception as exc:  # trimesh raises many kinds of errors on broken files
        raise MeshFileError(f"{name}: broken STL file ({exc or type(exc).__name__})") from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise MeshFileError(f"{name}: no triangles could be read (broken or truncated STL)")
    return MeshData(np.array(loaded.vertices, dtype=np.float64), np.array(loaded.faces))


def _write_stl(mesh: MeshData, out: BinaryIO) -> None:
    import trimesh

    tm = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    out.write(trimesh.exchange.stl.export_stl(tm))


# -- public API --------------------------------------------------------------------------------
_READERS = {".obj": _read_obj, ".ply": _read_ply, ".stl": _read_stl, ".off": _read_off}


def load_mesh(path: str | os.PathLike) -> MeshData:
    """Read a triangle mesh, keeping its vertices' count and order exactly as in the file.

    Parameters
    ----------
    path : str or PathLike
        A ``.obj``, ``.ply`` (ASCII or binary), ``.stl`` or ``.off`` file (case-insensitive).

    Returns
    -------
    MeshData
        vertices (N, 3) float64 in file units, faces (M, 3) int64 (polygons fan-triangulated),
        ``uv``/``uv_faces`` for an OBJ with texture coordinates, ``source`` = ``str(path)``.

    Raises
    ------
    MeshFileError
        Unknown extension, missing or unreadable file, empty, broken or truncated content, no
        faces, non-finite coordinates, or an index out of range; the message names the file.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in _READERS:
        raise MeshFileError(
            f"{p.name}: unknown mesh format {suffix or '(no extension)'!r}; "
            f"use {', '.join(MESH_FORMATS)}"
        )
    if not p.exists():
        raise MeshFileError(f"{p.name}: no such file ({p})")
    if not p.is_file():
        raise MeshFileError(f"{p.name}: not a file ({p})")
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise MeshFileError(f"{p.name}: cannot read ({exc.strerror or exc})") from None
    if not data or data.isspace():
        raise MeshFileError(f"{p.name}: the file is empty")
    mesh = _READERS[suffix](data, p.name)
    _validate(mesh, p.name)  # a safety net: the readers already report problems precisely
    mesh.source = str(p)
    return mesh


def save_mesh(mesh: MeshData, path: str | os.PathLike, *, ascii: bool = False) -> None:
    """Write ``mesh`` to ``path`` atomically; the extension chooses the format.

    Parameters
    ----------
    mesh : MeshData
        vertices (N, 3) float64 (must be finite), faces (M, 3) int64; ``uv``/``uv_faces`` are
        written to OBJ only.
    path : str or PathLike
        ``.obj``, ``.ply``, ``.stl`` or ``.off``. A symbolic link is written through (the
        link stays); an existing file keeps its permission bits.
    ascii : bool
        PLY only: ASCII instead of binary little-endian.

    Raises
    ------
    MeshFileError
        Unknown extension, a mesh that cannot be saved (checked before anything is written),
        a missing folder, or an OS error while writing. The destination is then untouched.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    writers: dict[str, Callable[[BinaryIO], None]] = {
        ".obj": lambda out: _write_obj(mesh, out),
        ".ply": lambda out: _write_ply(mesh, out, ascii),
        ".stl": lambda out: _write_stl(mesh, out),
        ".off": lambda out: _write_off(mesh, out),
    }
    if suffix not in writers:
        raise MeshFileError(
            f"{p.name}: cannot save as {suffix or '(no extension)'!r}; "
            f"use {', '.join(MESH_FORMATS)}"
        )
    _validate(mesh, p.name)
    if suffix == ".ply" and len(mesh.vertices) > np.iinfo(np.int32).max:
        raise MeshFileError(f"{p.name}: too many vertices for 32-bit PLY indices")
    if suffix == ".stl" and np.abs(mesh.vertices).max() > np.finfo(np.float32).max:
        raise MeshFileError(f"{p.name}: coordinates too large for STL (float32)")
    try:
        _atomic_write(p, writers[suffix])
    except MeshFileError as exc:
        if str(exc).startswith(p.name):
            raise
        raise MeshFileError(f"{p.name}: {exc}") from None
    except OSError as exc:
        raise MeshFileError(f"{p.name}: cannot write ({exc.strerror or exc})") from exc


def write_text_atomic(path: str | os.PathLike, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` through a temporary file renamed over it, so a failed
    write never leaves a half-written file (sessions, presets). ``MeshFileError`` on failure."""
    write_bytes_atomic(path, text.encode("utf-8"))


def write_bytes_atomic(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file renamed over it, so a failed write
    never leaves a half-written file (screenshots). ``MeshFileError`` on failure."""
    p = Path(path)
    try:
        _atomic_write(p, lambda out: out.write(data))
    except OSError as exc:
        raise MeshFileError(f"{p.name}: cannot write ({exc.strerror or exc})") from None


def write_atomic(path: str | os.PathLike, write: Callable[[BinaryIO], None]) -> None:
    """Stream a file through ``write(handle)`` into a temporary file next to ``path``, fsynced
    and renamed over it (the rename made durable too), so there is never a half-written file
    (the recovery journal's checkpoints). ``OSError`` as raised; ``MeshFileError`` when the
    folder does not exist."""
    _atomic_write(Path(path), write)


def _atomic_write(path: Path, write: Callable[[BinaryIO], None]) -> None:
    """Write through ``write`` into a temporary file next to ``path``, then rename it over."""
    target = Path(os.path.realpath(path))
    folder = target.parent
    if not folder.is_dir():
        raise MeshFileError(f"the folder {folder} does not exist")
    try:
        mode = stat.S_IMODE(target.stat().st_mode)
    except FileNotFoundError:
        mode = None  # new file: 0o666 minus the umask, as os.open applies it
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    while True:
        tmp = folder / f".{target.name}.{secrets.token_hex(4)}.tmp"
        try:
            fd = os.open(tmp, flags, 0o666)
            break
        except FileExistsError:
            continue
    try:
        with os.fdopen(fd, "wb") as handle:
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
        if mode is not None:
            os.chmod(tmp, mode)
        os.replace(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    with contextlib.suppress(OSError):  # make the rename itself durable (POSIX)
        folder_fd = os.open(folder, os.O_RDONLY)
        try:
            os.fsync(folder_fd)
        finally:
            os.close(folder_fd)
