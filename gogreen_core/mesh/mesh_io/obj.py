"""OBJ (Wavefront): reading and writing.

Positions stay as listed (trimesh's loader splits vertices at UV seams, changing the vertex
count and order that sessions rely on); texture coordinates are kept per face corner. Normals,
materials and groups are not kept. Two readers: :func:`read_obj_fast` parses a regular file with
whole-array operations and returns None as soon as anything is unusual (a comment after data, a
tab after a tag, mixed corner forms, a bad number, an index out of range, ...); then
:func:`read_obj_strict` reads it line by line, accepting it the same way (same result) or naming
the line at fault.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import BinaryIO

import numpy as np

from gogreen_core.mesh.mesh_io.data import MAX_INDEX, MeshData, MeshFileError, first_non_finite
from gogreen_core.mesh.mesh_io.polygons import triangulate
from gogreen_core.mesh.mesh_io.text import parse_numbers, text_lines, without_dos_eof, write_rows

__all__ = ["OBJ_STATEMENTS", "read_obj", "read_obj_fast", "read_obj_strict", "write_obj"]


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


# -- the fast reader -------------------------------------------------------------------------------
_SPACE = 32  # bytes <= 32 separate tokens (space, tab, line ends, control characters)
_MAX_RUNS = 10_000  # more runs of same-kind lines than this: gather them with a byte mask


#: The v, vt and f pieces (None without such lines), and per face line the count of v and vt
#: lines before it (for relative indices).
Sections = tuple[dict[bytes, bytes | None], np.ndarray, np.ndarray]


def sections_by_lines(data: bytes) -> Sections | None:
    """The sections of an OBJ text ('\n' line ends), by classifying every line with
    whole-array operations; None unless every other line is a comment, blank, or a known
    statement other than v, vt and f."""
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
        words = data[starts[line] : ends[line]].decode("utf-8", "replace").split()
        if words and (words[0] not in OBJ_STATEMENTS or words[0] in ("v", "vt", "f", "fo")):
            return None
    pieces: dict[bytes, bytes | None] = {}
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
    return pieces, np.cumsum(kinds[b"v "])[face_lines], np.cumsum(kinds[b"vt "])[face_lines]


def _numbers_per_line(
    piece: bytes, tag: bytes, sentinel: bytes, dtype: type[np.generic]
) -> tuple[np.ndarray, np.ndarray] | None:
    """All numbers of a piece and how many each line has (a ``sentinel`` the data cannot hold
    marks each line break), or None for a token not a number or a line of another kind."""
    lines = piece.count(b"\n") + 1
    between = b" " + sentinel + b" " * max(1, len(tag) + 2 - len(sentinel))
    text = piece.replace(b"\n" + tag, between)
    if len(text) - len(piece) != (lines - 1) * (len(between) - len(tag) - 1):
        return None  # a line without the tag among them
    try:
        values = parse_numbers(text + b" " + sentinel, dtype)
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
        numbers = parse_numbers(text.replace(b"/", b" "), np.int64)
    except ValueError:
        return None
    if len(numbers) != fields * n_corners:
        return None  # an empty field such as "1/ 2/ 3/"
    return numbers.reshape(-1, fields), corners, bool(doubled)


def read_obj_fast(data: bytes) -> MeshData | None:
    """The mesh of a regular OBJ file, else None (the strict reader then reads it)."""
    data = without_dos_eof(data.removeprefix(b"\xef\xbb\xbf"))
    if b"\r" in data:
        data = data.replace(b"\r\n", b"\n")
        if b"\r" in data:
            return None
    if b"\\" in data:  # lines continued by a backslash
        continued = [m.start() for m in re.finditer(rb"\\[ \t]*\n", data)]
        if any(b"#" in data[data.rfind(b"\n", 0, at) + 1 : at] for at in continued):
            return None  # a comment never continues: the strict reader knows that
        data = re.sub(rb"\\[ \t]*\n", b" ", data)
    if not data.endswith(b"\n"):
        data += b"\n"
    sections = sections_by_lines(data)
    return None if sections is None else mesh_from_sections(*sections)


def mesh_from_sections(
    pieces: dict[bytes, bytes | None], v_before: np.ndarray, vt_before: np.ndarray
) -> MeshData | None:
    if pieces[b"v "] is None or pieces[b"f "] is None:
        return None

    parsed = _numbers_per_line(pieces[b"v "], b"v ", b"nan", np.float64)
    if parsed is None or parsed[1].min() < 3:
        return None
    vertices = _first_columns(*parsed, 3)
    if not np.isfinite(vertices).all():
        return None

    uv = np.zeros((0, 2))
    if pieces[b"vt "] is not None:
        parsed = _numbers_per_line(pieces[b"vt "], b"vt ", b"nan", np.float64)
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

    found = _face_corners(pieces[b"f "])
    if found is None:
        return None
    numbers, corners, doubled = found
    if corners.min() < 3:
        return None

    def indices(column: np.ndarray, counted: np.ndarray, total: int) -> np.ndarray | None:
        """0-based indices from 1-based or relative ones (``counted``: entries before each face
        line); None when one is 0, before the first entry, or past the last."""
        if (column == 0).any():
            return None
        relative = column < 0
        if relative.any():
            column = column.copy()
            column[relative] += counted[np.repeat(np.arange(len(corners)), corners)[relative]] + 1
            if (column[relative] < 1).any():
                return None
        if column.max() > total:  # also catches indices too large for int64 (saturated)
            return None
        return column - 1

    position = indices(numbers[:, 0], v_before, len(vertices))
    if position is None:
        return None
    triangles = triangulate(vertices, position, corners)
    mesh = MeshData(vertices, position[triangles])
    if numbers.shape[1] >= 2 and not doubled:
        texture = indices(numbers[:, 1], vt_before, len(uv))
        if texture is None:
            return None
        mesh.uv, mesh.uv_faces = uv, texture[triangles]
    return mesh
