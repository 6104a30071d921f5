"""OBJ (Wavefront): reading and writing.

Positions stay as listed (trimesh's loader splits vertices at UV seams, changing the vertex
count and order that sessions rely on); texture coordinates are kept per face corner. Normals,
materials and groups are not kept. The reader classifies every statement at once and parses the
v, vt and f statements each as one array; a kind with a statement the arrays cannot take (a tab
after its tag, mixed corner forms, a bad number, a relative index...) is read statement by
statement, which accepts it as the specification does or names the first line at fault.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from typing import BinaryIO

import numpy as np

from gogreen_core.mesh.mesh_io.data import MAX_INDEX, MeshData, MeshFileError, first_non_finite
from gogreen_core.mesh.mesh_io.polygons import triangulate
from gogreen_core.mesh.mesh_io.text import BOM, parse_numbers, without_dos_eof, write_rows

__all__ = ["OBJ_STATEMENTS", "read_obj", "write_obj"]

_SPACE = 32  # bytes <= 32 separate tokens (space, tab, line ends, control characters)
_MAX_RUNS = 10_000  # more runs of same-kind lines than this: gather them with a byte mask
#: One statement read on its own: (its first line, its words, its text).
_Statement = tuple[int, list[str], str]


def read_obj(data: bytes, name: str) -> MeshData:
    text, firsts = _statements(data)
    arr = np.frombuffer(text, dtype=np.uint8)
    ends = np.flatnonzero(arr == ord("\n"))
    starts = np.concatenate([[0], ends[:-1] + 1])
    c0, c1, c2 = (arr[np.minimum(starts + k, len(arr) - 1)] for k in range(3))
    kinds = {
        b"v ": (c0 == ord("v")) & (c1 == _SPACE),
        b"vt ": (c0 == ord("v")) & (c1 == ord("t")) & (c2 == _SPACE),
        b"f ": (c0 == ord("f")) & (c1 == _SPACE),
    }
    lines = np.arange(1, len(starts) + 1) if firsts is None else firsts
    errors: list[tuple[int, str]] = []  # (line, message): the first of each kind of statement
    ignored = (starts == ends) | (c0 == ord("#"))  # blank, a comment line, a normal:
    ignored |= (c0 == ord("v")) & (c1 == ord("n")) & (c2 == _SPACE)
    for i in np.flatnonzero(~(kinds[b"v "] | kinds[b"vt "] | kinds[b"f "] | ignored)).tolist():
        words = text[starts[i] : ends[i]].decode(errors="replace").split()  # g, s, usemtl...
        tag = words[0] if words else ""
        if tag in ("v", "vt", "f", "fo"):
            kinds[tag[:2].replace("fo", "f").encode() + b" "][i] = True
        elif tag and tag not in OBJ_STATEMENTS:
            errors.append((int(lines[i]), f"unknown statement {tag[:20]!r} (not an OBJ file?)"))
            break

    def statements(tag: bytes) -> Iterator[_Statement]:
        for i in np.flatnonzero(kinds[tag]).tolist():
            content = text[starts[i] : ends[i]].decode(errors="replace")
            yield int(lines[i]), content.split(), content

    pieces = _pieces(text, starts, ends, kinds)
    counted = [np.cumsum(kinds[tag])[kinds[b"f "]] for tag in (b"v ", b"vt ")]
    v = _coordinates(pieces[b"v "], statements(b"v "), errors, 3)
    uv = _coordinates(pieces[b"vt "], statements(b"vt "), errors, 2)
    corners, textures, sizes = _faces(pieces[b"f "], statements(b"f "), counted, errors)
    if errors:
        line, message = min(errors)
        raise MeshFileError(f"{name}, line {line}: {message}")
    if not len(v):
        raise MeshFileError(f"{name}: no vertices (empty or not an OBJ file)")
    if not len(sizes):
        raise MeshFileError(f"{name}: no faces (the file has only points)")
    if (bad := first_non_finite(v)) is not None:
        raise MeshFileError(
            f"{name}, line {lines[kinds[b'v ']][bad]}: vertex {bad + 1} has a non-finite "
            f"coordinate {v[bad].tolist()}"
        )
    for indices, count, what in ((corners, len(v), "vertex"), (textures, len(uv), "texture")):
        outside = indices >= count
        if outside.any():
            bad = int(np.argmax(outside))
            polygon = int(np.searchsorted(np.cumsum(sizes), bad, side="right"))
            face, have = f"face {polygon + 1}", f"{count} vertices"
            if what == "texture":
                face, what, have = "face", "texture coordinate", f"{count} texture coordinates"
            raise MeshFileError(
                f"{name}, line {lines[kinds[b'f ']][polygon]}: {face} references {what} "
                f"{int(indices[bad]) + 1} but the file has {have}"
            )
    triangles = triangulate(v, corners, sizes)
    mesh = MeshData(v, corners[triangles])
    if (textures >= 0).any():
        mesh.uv, mesh.uv_faces = uv, textures[triangles]
    return mesh


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


def _statements(data: bytes) -> tuple[bytes, np.ndarray | None]:
    """The statements of an OBJ file (its text as :func:`text_lines` reads it) one a line, each
    ending in a line end: comments removed (whole comment lines may stay), and a line that ends
    in a backslash joined with the next (the specification's continuation; Rhino writes long
    faces so); and the first line of each statement (None: the statements are the lines)."""
    text = without_dos_eof(data).removeprefix(BOM.encode())
    if b"\r" in text:
        text = text.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
    if not text.endswith(b"\n"):
        text += b"\n"
    first, last = text.find(b"#"), text.find(b"\n", text.rfind(b"#"))  # (whole lines stay)
    if first >= 0 and (b"\\" in text or re.search(rb"[^\n]#", text[max(first - 1, 0) : last])):
        view = memoryview(text)  # a comment after a statement, or continuations: cut them
        comments = re.sub(rb"#[^\n]*", b"", text[first:last])
        text = b"".join([view[:first], comments, view[last:]])
    if b"\\" not in text:
        return text, None
    decoded = text.decode("utf-8", "replace")  # (any Unicode space may follow the backslash)
    continued = re.compile(r"\\[^\S\n]*\n")
    joined = [m.end() - 1 for m in continued.finditer(decoded)]
    newlines = np.flatnonzero(np.frombuffer(decoded.encode("utf-32-le"), np.uint32) == ord("\n"))
    firsts = np.concatenate([[1], np.flatnonzero(~np.isin(newlines, joined)) + 2])
    return continued.sub(" ", decoded).encode() + b"\n", firsts


def _pieces(
    text: bytes, starts: np.ndarray, ends: np.ndarray, kinds: dict[bytes, np.ndarray]
) -> dict[bytes, bytes | None]:
    """The statements of each kind as one text, without the first one's tag and the last line
    end (None without statements of that kind)."""
    pieces: dict[bytes, bytes | None] = {}
    for tag, keep in kinds.items():
        if not keep.any():
            pieces[tag] = None
            continue
        edges = np.diff(np.concatenate([[0], keep.view(np.int8), [0]]))
        first, last = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
        if len(first) <= _MAX_RUNS:  # runs of lines of this kind: copied whole, once
            begin, end, view = starts[first], ends[last] + 1, memoryview(text)
            begin[0], end[-1] = begin[0] + len(tag), end[-1] - 1
            pieces[tag] = b"".join([view[a:b] for a, b in np.column_stack([begin, end]).tolist()])
        else:
            mask = np.repeat(keep, ends - starts + 1)
            pieces[tag] = np.frombuffer(text, dtype=np.uint8)[mask].tobytes()[len(tag) : -1]
    return pieces


class _Refused(Exception):
    """A statement that is not OBJ; the message says why."""


def _coordinates(
    piece: bytes | None,
    statements: Iterator[_Statement],
    errors: list[tuple[int, str]],
    width: int,
) -> np.ndarray:
    """Positions (N, 3) of the v statements (``width`` 3) or texture coordinates (T, 2) of
    the vt ones (v = 0 when not given, none non-finite)."""
    tag, least = (b"v ", 3) if width == 3 else (b"vt ", 1)
    parsed = None if piece is None else _numbers_per_line(piece, tag, b"nan", np.float64)
    if parsed is not None and parsed[1].min() >= least:
        values, counts = parsed
        if counts.min() >= width:
            found = _first_columns(values, counts, width)
        elif counts.max() == 1:
            found = np.stack([values, np.zeros_like(values)], axis=1)
        if (counts.min() >= width or counts.max() == 1) and np.isfinite(found).all():
            return found
    rows: list[tuple[float, ...]] = []

    def read(words: list[str], content: str, *_: object) -> None:
        if len(words) <= least:
            raise _Refused(
                "a vertex needs 3 coordinates" if width == 3 else "empty texture coordinate"
            )
        try:
            values = tuple(map(float, words[1 : width + 1]))
        except ValueError:
            raise _Refused(f"bad number in {content.strip()!r}") from None
        if width == 2 and not np.isfinite(values).all():
            raise _Refused(
                f"texture coordinate {len(rows) + 1} has a non-finite value {list(values)}"
            )
        rows.append((*values, 0.0)[:width])

    _each(statements, read, errors)
    return np.array(rows, dtype=np.float64).reshape(-1, width)


def _faces(
    piece: bytes | None,
    statements: Iterator[_Statement],
    counted: list[np.ndarray],
    errors: list[tuple[int, str]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The f statements' vertex (C,) and texture indices (C,) of each corner (from 0; -1 for
    a face without), and the corners of each (P,); ``counted``: the v and vt statements before
    each (for relative indices)."""
    found = None if piece is None else _face_corners(piece)
    if found is not None and found[1].min() >= 3:
        numbers, sizes, doubled = found
        position = _resolved(numbers[:, 0], counted[0], sizes)
        plain = numbers.shape[1] < 2 or doubled  # no corner has a texture index
        texture = (
            np.full(len(numbers), -1) if plain else _resolved(numbers[:, 1], counted[1], sizes)
        )
        if position is not None and texture is not None:
            return position, texture, sizes
    corners: list[int] = []
    textures: list[int] = []
    polygons: list[int] = []

    def read(words: list[str], _: str, vertices: int, uvs: int) -> None:
        if len(words) < 4:
            raise _Refused("a face needs at least 3 corners")
        pos: list[int] = []
        tex: list[int] = []
        for corner in words[1:]:
            fields = corner.split("/")
            pos.append(_index(fields[0], vertices, "vertex"))
            if len(fields) > 1 and fields[1]:
                tex.append(_index(fields[1], uvs, "texture coordinate"))
        if tex and len(tex) != len(pos):
            raise _Refused("some corners of this face lack a texture index")
        corners.extend(pos)
        textures.extend(tex or [-1] * len(pos))
        polygons.append(len(pos))

    _each(statements, read, errors, *(c.tolist() for c in counted))
    return np.array(corners, np.int64), np.array(textures, np.int64), np.array(polygons, np.int64)


def _each(
    statements: Iterator[_Statement],
    read: Callable[..., None],
    errors: list[tuple[int, str]],
    *per_statement: list[int],
) -> None:
    """``read(words, text, *values)`` of each statement until one is refused (appended to
    ``errors`` with its line)."""
    for (line, words, content), *values in zip(statements, *per_statement, strict=False):
        try:
            read(words, content, *values)
        except _Refused as exc:
            errors.append((line, str(exc)))
            return


def _resolved(column: np.ndarray, counted: np.ndarray, sizes: np.ndarray) -> np.ndarray | None:
    """0-based indices from 1-based or relative ones (``counted``: entries before each face);
    None when one is 0, before the first entry or beyond :data:`MAX_INDEX`."""
    if (column == 0).any() or column.max() > MAX_INDEX:
        return None
    relative = column < 0
    if relative.any():
        column = column.copy()
        column[relative] += np.repeat(counted, sizes)[relative] + 1
        if (column[relative] < 1).any():
            return None
    return column - 1


def _index(token: str, count: int, kind: str) -> int:
    """The 0-based index of an OBJ index ``token`` (1-based, or relative to the ``count``
    entries read so far)."""
    try:
        i = int(token)
    except ValueError:
        raise _Refused(f"bad {kind} index {token!r}") from None
    if i > MAX_INDEX:  # no file holds that many; int64 arrays could not even store it
        raise _Refused(f"{kind} index {i} is out of range (the file cannot hold that many)")
    if i > 0:
        return i - 1  # checked against the final count (forward references are legal)
    if i < 0 and count + i >= 0:
        return count + i
    if i == 0:
        raise _Refused("OBJ indices start at 1 (got 0)")
    raise _Refused(
        f"relative {kind} index {i} points before the first {kind} (only {count} read so far)"
    )


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
        values = parse_numbers(b" ".join([text, sentinel]), dtype)
    except ValueError:
        return None
    marks = np.flatnonzero(np.isnan(values) if sentinel == b"nan" else values == 0)
    if len(marks) != lines:
        return None  # a NaN or 0 in the data itself: read statement by statement
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
    ``a//c`` (no texture), from the f piece; None unless every corner has the same form (or
    for a sign before a space, which numpy's integers skip)."""
    if b"-" in piece or b"+" in piece:
        buffer = np.frombuffer(piece + b" ", dtype=np.uint8)
        signs = np.flatnonzero((buffer == ord("-")) | (buffer == ord("+")))
        if (buffer[signs + 1] <= _SPACE).any():
            return None
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
