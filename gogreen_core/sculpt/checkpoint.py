"""A sculptor's state as a file: the checkpoints of the recovery journal.

:class:`SculptState` is everything a sculptor's next operations compute from
(:func:`~gogreen_core.sculpt.sculptor.capture_state` takes one,
:func:`~gogreen_core.sculpt.sculptor.restore_state` continues from it exactly).

The file (``checkpoint-<record>.bin``)::

    b"GOGREEN-CHECKPOINT\\n"
    header length (8 bytes, little endian), header (JSON, UTF-8)
    vertices (N, 3) float64, then pin points (k, 3), matrix and inverse (3k, 3k), then (version
    2, when the header says so) the mask (N,), the faces (M, 3), the UVs (T, 2) and their
    corners (M, 3) (indices as float64, exact), all little endian
    CRC-32 of everything before (4 bytes, little endian)

A file cut short, or whose checksum or header does not match, is refused with
:class:`CheckpointError` naming the problem; a write is atomic.
"""

from __future__ import annotations

import json
import os
import struct
import zlib
from dataclasses import dataclass
from typing import Any, BinaryIO, cast

import numpy as np

from gogreen_core.mesh.mesh_io.atomic import atomic_write
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.session import upgrade_session

__all__ = ["CHECKPOINT_VERSION", "CheckpointError", "SculptState", "read_checkpoint"]

CHECKPOINT_MAGIC = b"GOGREEN-CHECKPOINT\n"
#: 3: no ``evaluation``, settings as in session version 5; 2: the mask, faces and UVs may follow
#: the pins (version 1 files are read as before).
CHECKPOINT_VERSION = 3
#: Largest header a checkpoint may have (settings with a spline falloff are a few kB).
_MAX_HEADER = 1 << 20
_CHUNK = 1 << 22  # bytes per write and checksum step


class CheckpointError(ValueError):
    """A checkpoint file that cannot be used (cut short, corrupt, or from a newer version)."""


@dataclass(frozen=True, eq=False)
class SculptState:
    """What a sculptor's next operations compute from (a copy).

    vertices : (N, 3) float64
    settings : EngineSettings
    pins : ((k, 3) points, (3k, 3k) matrix, (3k, 3k) inverse) or None
        The pins' solver state, bit for bit (:meth:`ConstraintSet.restored`).
    model_size : float, origin : (3,) float64
        Size and bounding-box centre of the mesh as first loaded (brush radii and mirror planes).
    mask : (N,) float64 or None (nothing masked)
    faces : (M, 3) int64 or None (the faces of the journal's start); uv : (T, 2) and
        uv_faces : (M, 3) with them, or None.
    """

    vertices: np.ndarray
    settings: EngineSettings
    pins: tuple[np.ndarray, np.ndarray, np.ndarray] | None
    model_size: float
    origin: np.ndarray
    mask: np.ndarray | None = None
    faces: np.ndarray | None = None
    uv: np.ndarray | None = None
    uv_faces: np.ndarray | None = None

    def arrays(self) -> list[np.ndarray]:
        """The arrays a checkpoint file stores, in order (contiguous float64)."""
        pins = list(self.pins) if self.pins is not None else []
        extra = [a for a in (self.mask, self.faces, self.uv, self.uv_faces) if a is not None]
        return [np.ascontiguousarray(a, dtype="<f8") for a in (self.vertices, *pins, *extra)]

    def header(self) -> dict[str, Any]:
        """The JSON-ready part (settings, sizes, model size, origin; floats exact)."""
        return {
            "vertices": len(self.vertices),
            "pins": None if self.pins is None else len(self.pins[0]),
            "settings": self.settings.to_dict(),
            "model_size": float(self.model_size),
            "origin": [float(x) for x in self.origin],
            "mask": self.mask is not None,
            "faces": None if self.faces is None else len(self.faces),
            "uv": None if self.uv is None else len(self.uv),
        }

    @classmethod
    def from_header(cls, header: dict[str, Any], arrays: dict[str, np.ndarray]) -> SculptState:
        """Inverse of :meth:`header` with the arrays read back by name (ValueError if malformed)."""
        settings = EngineSettings.from_dict(_upgraded_settings(header), "settings")
        origin = np.array(header["origin"], dtype=np.float64)
        size = float(header["model_size"])
        if origin.shape != (3,) or not np.isfinite(origin).all() or not size > 0:
            raise ValueError("model size or origin malformed")
        pins = tuple(arrays[key] for key in _PINS) if "points" in arrays else None
        faces, uv_faces = (arrays[k].astype(np.int64) if k in arrays else None for k in _INDICES)
        mask, uv = arrays.get("mask"), arrays.get("uv")
        return cls(
            arrays["vertices"], settings, cast(Any, pins), size, origin, mask, faces, uv, uv_faces
        )


def _upgraded_settings(header: dict[str, Any]) -> object:
    """The settings of a checkpoint header or a journal's start, an older version's (with an
    ``evaluation`` or ``degree_weights``) upgraded like a session's."""
    settings = header["settings"]
    if "evaluation" in header or (isinstance(settings, dict) and "degree_weights" in settings):
        return upgrade_session({"version": 4, "settings": settings})["settings"]
    return settings


_PINS = ("points", "matrix", "inverse")  # the names of the pins' arrays
_INDICES = ("faces", "uv_faces")  # and of the index arrays (stored as float64)


def _shapes(header: dict[str, Any]) -> dict[str, tuple[int, ...]]:
    n, k = header["vertices"], header["pins"]
    if not isinstance(n, int) or n < 1 or not (k is None or (isinstance(k, int) and k >= 0)):
        raise ValueError("vertex or pin count malformed")
    shapes: dict[str, tuple[int, ...]] = {"vertices": (n, 3)}
    if k is not None:
        shapes.update(zip(_PINS, [(k, 3), (3 * k, 3 * k), (3 * k, 3 * k)], strict=True))
    m, t = header.get("faces"), header.get("uv")
    if header.get("mask"):
        shapes["mask"] = (n,)
    if m is not None:
        if not isinstance(m, int) or m < 0 or not (t is None or (isinstance(t, int) and t >= 0)):
            raise ValueError("face or texture coordinate count malformed")
        shapes["faces"] = (m, 3)
        if t is not None:
            shapes.update(uv=(t, 2), uv_faces=(m, 3))
    return shapes


def write_checkpoint(
    path: str | os.PathLike[str], state: SculptState, extra: dict[str, Any]
) -> None:
    """Write ``state`` (and ``extra`` header fields: the journal's record number...) to
    ``path`` atomically (fsynced, renamed). OSError as raised."""
    header = json.dumps({"version": CHECKPOINT_VERSION, **extra, **state.header()}).encode()

    def write(out: BinaryIO) -> None:
        crc = 0
        for piece in (CHECKPOINT_MAGIC, struct.pack("<Q", len(header)), header):
            out.write(piece)
            crc = zlib.crc32(piece, crc)
        for array in state.arrays():
            # (numpy declares its buffer protocol to type checkers from Python 3.12 on)
            data = memoryview(cast(Any, array)).cast("B")
            for start in range(0, len(data), _CHUNK):
                chunk = data[start : start + _CHUNK]
                out.write(chunk)
                crc = zlib.crc32(chunk, crc)
        out.write(struct.pack("<I", crc))

    atomic_write(path, write)


def read_checkpoint(path: str | os.PathLike[str]) -> tuple[SculptState, dict[str, Any]]:
    """The state in a checkpoint file and its header; :class:`CheckpointError` saying what is
    wrong (missing, cut short, checksum, newer version, malformed)."""
    name = os.path.basename(path)
    try:
        with open(path, "rb") as handle:
            data = handle.read()
    except OSError as exc:
        raise CheckpointError(f"{name}: cannot read ({exc.strerror or exc})") from None
    magic = len(CHECKPOINT_MAGIC)
    if data[:magic] != CHECKPOINT_MAGIC:
        raise CheckpointError(f"{name}: not a checkpoint (or cut short at its start)")
    if len(data) < magic + 12:
        raise CheckpointError(f"{name}: cut short ({len(data)} bytes)")
    (length,) = struct.unpack_from("<Q", data, magic)
    if length > _MAX_HEADER or magic + 8 + length + 4 > len(data):
        raise CheckpointError(f"{name}: cut short or corrupt (header of {length} bytes)")
    try:
        header = json.loads(data[magic + 8 : magic + 8 + length])
        version = header["version"]
        shapes = _shapes(header)
    except (ValueError, KeyError, TypeError) as exc:
        raise CheckpointError(f"{name}: corrupt header ({exc})") from None
    if not isinstance(version, int) or version > CHECKPOINT_VERSION:
        raise CheckpointError(
            f"{name}: written by a newer GoGreen Sculpt (checkpoint version {version}; this "
            f"one reads {CHECKPOINT_VERSION})"
        )
    offset = magic + 8 + length
    size = offset + 8 * sum(int(np.prod(s)) for s in shapes.values()) + 4
    if len(data) != size:
        state = "cut short" if len(data) < size else "too long"
        raise CheckpointError(f"{name}: {state} ({len(data)} bytes, {size} expected)")
    (crc,) = struct.unpack_from("<I", data, size - 4)
    if zlib.crc32(memoryview(data)[: size - 4]) != crc:
        raise CheckpointError(f"{name}: corrupt (checksum mismatch)")
    arrays = {}
    for key, shape in shapes.items():
        count = int(np.prod(shape))
        arrays[key] = np.frombuffer(data, "<f8", count, offset).astype(np.float64).reshape(shape)
        offset += 8 * count
    try:
        return SculptState.from_header(header, arrays), header
    except (ValueError, KeyError, TypeError) as exc:
        raise CheckpointError(f"{name}: corrupt header ({exc})") from None
