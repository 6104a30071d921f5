"""OBJ, the fast reader: whole-array parsing of a regular file.

:func:`read_obj_fast` returns None as soon as anything is unusual (a comment after data, a tab
after a tag, mixed corner forms, a bad number, an index out of range, ...); the strict reader
(:mod:`~gogreen_core.mesh.mesh_io.obj_strict`) then accepts the file the same way or names the
line at fault. The lines of one kind (v, vt or f), found with whole-array operations, are parsed
as one "piece": their contents joined by ``b"\n" + tag``.
"""

from __future__ import annotations

import re

import numpy as np

from gogreen_core.mesh.mesh_io.data import MeshData
from gogreen_core.mesh.mesh_io.obj_strict import OBJ_STATEMENTS
from gogreen_core.mesh.mesh_io.polygons import triangulate
from gogreen_core.mesh.mesh_io.text import parse_numbers, without_dos_eof

__all__ = [
    "mesh_from_sections",
    "read_obj_fast",
    "sections_by_lines",
]

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
    """All numbers of a piece and how many each line has, or None if a token is not a number
    or a line of another kind is among them. A ``sentinel`` the data cannot hold (NaN, or 0
    among 1-based indices) replaces each line break to count them."""
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
