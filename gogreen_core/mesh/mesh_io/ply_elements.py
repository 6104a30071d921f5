"""PLY elements: the header, and each element's records as arrays, binary or ASCII.

The records are walked in compiled code, which finds where each starts (lists vary in length:
triangles and quads mixed, as most Blender meshes are), then each property is gathered. ASCII
data is parsed into float64 numbers whose bytes are read the same way, as float64 properties.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numba
import numpy as np

from gogreen_core.mesh.mesh_io.data import MeshFileError
from gogreen_core.mesh.mesh_io.text import is_number, parse_numbers

__all__ = [
    "PLY_TYPES",
    "Columns",
    "PlyElement",
    "PlyList",
    "PlyProperty",
    "ascii_numbers",
    "read_ascii_element",
    "read_binary_element",
    "read_header",
    "row_problem",
]

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
    """Start of each record and the end of the last (count + 1,), and the length of each list
    (count, lists) of an element of binary records at ``buffer[offset:]``; status 0, or
    _TRUNCATED, or _BAD_LENGTH with the bad length. ``numbers``: the buffer as float64 when
    the list lengths are float64 (ASCII's numbers), else empty."""
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
            pos += size[j] + k * item[j]
            if pos > end:
                return starts, lengths, _TRUNCATED, 0.0
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
    row = 0
    for element in elements:
        for record in range(element.count):
            if row >= len(lines):
                return None
            number, words = lines[row]
            row += 1
            expected, pos, has_list = 0, 0, False
            for p in element.properties:
                if p.count_dtype is None:
                    expected += 1
                    pos += 1
                    continue
                has_list = True
                if pos >= len(words) or not re.fullmatch(r"\+?\d+(\.0*)?", words[pos]):
                    return None  # a bad length: reported as such
                k = int(float(words[pos]))
                expected += 1 + k
                pos += 1 + k
            if len(words) > expected or (len(words) < expected and not has_list):
                declared = ", ".join(p.name for p in element.properties)
                return MeshFileError(
                    f"{name}, line {number}: element '{element.name}' "
                    f"row {record} has {len(words)} values but the header declares "
                    f"{expected} ({declared}): the row has "
                    f"{'more' if len(words) > expected else 'fewer'} values than declared"
                )
    return None
