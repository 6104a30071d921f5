"""Text helpers shared by the formats: decoding a file's text, parsing whole arrays of numbers
the same way under numpy 1.26 and 2.x, showing a number the way the file wrote it, and writing
rows of numbers."""

from __future__ import annotations

import warnings
from typing import BinaryIO

import numpy as np

from gogreen_core.mesh.mesh_io.data import MAX_INDEX

__all__ = [
    "BOM",
    "DOS_EOF",
    "is_number",
    "parse_numbers",
    "show_number",
    "text_lines",
    "without_dos_eof",
    "write_rows",
]

BOM = "\ufeff"
DOS_EOF = b"\x1a"  # Ctrl-Z: old DOS programs end text files with it

# numpy >= 2 raises ValueError when np.fromstring meets a token it cannot read whole; numpy 1.x
# (Blender's Python ships 1.26) only warns and returns the numbers before it. The warning is
# turned into the same error, matched by its message so that no other warning changes.
_FROMSTRING_WARNS = np.lib.NumpyVersion(np.__version__) < "2.0.0"
_UNMATCHED = "string or file could not be read to its end"


def parse_numbers(text: bytes, dtype: type[np.generic]) -> np.ndarray:
    """All whitespace-separated numbers of ``text`` as a 1-D array of ``dtype`` (C parsing,
    correctly rounded like ``float()``); ValueError if a token is not a number of that type,
    under numpy 1.26 as under numpy 2."""
    if not _FROMSTRING_WARNS:
        return np.fromstring(text, dtype, sep=" ")
    with warnings.catch_warnings():
        warnings.filterwarnings("error", _UNMATCHED, DeprecationWarning)
        try:
            return np.fromstring(text, dtype, sep=" ")
        except DeprecationWarning as exc:
            raise ValueError(str(exc)) from None


def without_dos_eof(data: bytes) -> bytes:
    """``data`` without a DOS end-of-file byte (and what follows it, whitespace only) at its
    end."""
    end = len(data)
    while end and data[end - 1] in b" \t\r\n\0":  # (rstrip would copy a large file)
        end -= 1
    return data[: end - 1] if data[end - 1 : end] == DOS_EOF else data


def text_lines(data: bytes) -> str:
    """The file as text with '\\n' line ends: UTF-8 (undecodable bytes replaced), a leading
    byte-order mark and a final DOS end-of-file byte removed, CR LF and lone CR (old Mac files)
    read as line ends."""
    text = without_dos_eof(data).decode("utf-8", errors="replace")
    if text.startswith(BOM):
        text = text[1:]
    if "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    return text


def show_number(value: np.floating) -> str:
    """A value read from a file, shown as the file has it: whole numbers as integers, others
    in the shortest form of their own precision (float32 1e30 as '1e+30', not 1.00000002e30)."""
    if np.isfinite(value) and value == np.round(value) and abs(value) < MAX_INDEX:
        return str(int(value))
    return str(value)


def is_number(token: str | bytes) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


_CHUNK = 100_000  # rows formatted at a time: bounds the temporary memory of a large mesh


def write_rows(out: BinaryIO, fmt: str, table: np.ndarray) -> None:
    """Write each row of ``table`` formatted with ``fmt`` (which ends in a newline); ``%.17g``
    for floats reloads bit for bit. Much faster than np.savetxt, which formats row by row."""
    for start in range(0, len(table), _CHUNK):
        rows = table[start : start + _CHUNK]
        out.write(((fmt * len(rows)) % tuple(rows.ravel().tolist())).encode("ascii"))
