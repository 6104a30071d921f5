"""Loading and saving by file extension: :func:`load_mesh` and :func:`save_mesh` pick the reader
or writer, check the mesh, and report every problem as a :class:`MeshFileError` naming the file."""

from __future__ import annotations

import os
import struct
import time
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

import numpy as np

from gogreen_core import _compiled
from gogreen_core.mesh.mesh_io import obj, off, ply, stl
from gogreen_core.mesh.mesh_io.atomic import atomic_write
from gogreen_core.mesh.mesh_io.data import MeshData, MeshFileError, validate_mesh

__all__ = ["MESH_FORMATS", "load_mesh", "save_mesh", "warm_up"]

#: File extensions :func:`load_mesh` and :func:`save_mesh` understand (lower case).
MESH_FORMATS = (".obj", ".ply", ".stl", ".off")

_READERS: dict[str, Callable[[bytes, str], MeshData]] = {
    ".obj": obj.read_obj,
    ".ply": ply.read_ply,
    ".stl": stl.read_stl,
    ".off": off.read_off,
}


def load_mesh(path: str | os.PathLike[str]) -> MeshData:
    """Read a triangle mesh, keeping its vertices' count and order as in the file, except those
    the format made copies of (STL's triangle corners, a PLY's vertices split along UV seams),
    joined back so that a closed model loads closed. Polygons are triangulated by their shape
    (:mod:`~gogreen_core.mesh.mesh_io.polygons`). Text is UTF-8 (a byte-order mark skipped,
    CR LF or lone CR line ends accepted).

    ``path``: a ``.obj``, ``.ply`` (ASCII or binary), ``.stl`` (binary or ASCII) or ``.off``
    file. Returns its :class:`MeshData` (``source`` = ``str(path)``). Raises
    :class:`MeshFileError` naming the file for an unknown extension, a missing or unreadable
    file, empty, broken or truncated content, no faces, non-finite coordinates or an index out
    of range.
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
    validate_mesh(mesh, p.name)  # a safety net: the readers already report problems precisely
    mesh.source = str(p)
    return mesh


def save_mesh(mesh: MeshData, path: str | os.PathLike[str], *, ascii: bool = False) -> None:
    """Write ``mesh`` to ``path`` (``.obj``, ``.ply``, ``.stl`` or ``.off``) atomically; a
    symbolic link is written through, an existing file keeps its permission bits. Texture
    coordinates go to OBJ (per corner) and PLY (``s, t`` per vertex, a vertex written once per
    texture coordinate of its corners, joined back at load). ``ascii``: ASCII PLY instead of
    binary little-endian. Raises :class:`MeshFileError` for an unknown extension, a mesh that
    cannot be saved (checked before anything is written), a missing folder or an OS error
    while writing; the destination is then untouched.
    """
    p = Path(path)
    suffix = p.suffix.lower()
    writers: dict[str, Callable[[BinaryIO], None]] = {
        ".obj": lambda out: obj.write_obj(mesh, out),
        ".ply": lambda out: ply.write_ply(mesh, out, ascii),
        ".stl": lambda out: stl.write_stl(mesh, out),
        ".off": lambda out: off.write_off(mesh, out),
    }
    if suffix not in writers:
        raise MeshFileError(
            f"{p.name}: cannot save as {suffix or '(no extension)'!r}; "
            f"use {', '.join(MESH_FORMATS)}"
        )
    validate_mesh(mesh, p.name)
    if suffix == ".ply" and len(mesh.vertices) > np.iinfo(np.int32).max:
        raise MeshFileError(f"{p.name}: too many vertices for 32-bit PLY indices")
    if suffix == ".stl" and np.abs(mesh.vertices).max() > np.finfo(np.float32).max:
        raise MeshFileError(f"{p.name}: coordinates too large for STL (float32)")
    try:
        atomic_write(p, writers[suffix])
    except MeshFileError as exc:
        if str(exc).startswith(p.name):
            raise
        raise MeshFileError(f"{p.name}: {exc}") from None
    except OSError as exc:
        raise MeshFileError(f"{p.name}: cannot write ({exc.strerror or exc})") from exc


def warm_up() -> float:
    """Compile (or load from numba's disk cache) the readers' compiled loops by reading a few
    tiny files made here; seconds (about 3) from an empty cache, milliseconds from it. The app
    calls it off the GUI thread at start, so that opening a file never waits on a compiler."""
    start = time.perf_counter()
    header = (
        "ply\nformat {} 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
        "property float z\nproperty float s\nproperty float t\nelement face 2\n"
        "property list uchar int vertex_indices\nend_header\n"
    )
    square = np.array([[0, 0, 0, 0, 0], [1, 0, 0, 1, 0], [1, 1, 0, 1, 1], [0, 1, 0, 0, 1],
                       [0, 0, 0, 1, 1]], dtype="<f4")  # fmt: skip
    faces = struct.pack("<B5iB3i", 5, 0, 1, 2, 3, 4, 3, 0, 2, 4)  # a pentagon and a triangle
    ply.read_ply(header.format("binary_little_endian").encode() + square.tobytes() + faces, "")
    rows = "".join(" ".join(map(str, row)) + "\n" for row in square.tolist())
    ply.read_ply((header.format("ascii") + rows + "5 0 1 2 3 4\n3 0 2 4\n").encode(), "")
    triangle = np.zeros(1, dtype=stl.TRIANGLE)
    triangle["corners"] = square[:3, :3]
    stl.read_stl(bytes(80) + struct.pack("<I", 1) + triangle.tobytes(), "")
    return time.perf_counter() - start


# The readers' loops are a compile unit of their own (the whole package's compiled functions).
_compiled.register(
    _compiled.MESH_IO,
    __name__,
    lambda unit: warm_up(),
    lambda unit: _compiled.modules_cached(__name__.rpartition(".")[0]),
)
