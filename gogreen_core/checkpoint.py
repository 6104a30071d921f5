"""A sculptor's state as a file: the checkpoints of the recovery journal.

:class:`SculptState` is everything a :class:`~gogreen_core.Sculptor`'s next operations compute
from besides the faces: the vertices, the settings, the pins with their solver state bit for
bit, and the model size and mirror origin (both fixed when the mesh was loaded, so a state
taken after sculpting must carry them). :func:`gogreen_core.sculptor.capture_state` takes one,
:func:`gogreen_core.sculptor.restore_state` continues from it exactly.

The file (``checkpoint-<record>.bin``)::

    b"GOGREEN-CHECKPOINT\\n"
    header length (8 bytes, little endian), header (JSON, UTF-8)
    vertices (N, 3) float64, then pin points (k, 3), matrix and inverse (3k, 3k), little endian
    CRC-32 of everything before (4 bytes, little endian)

A file cut short, or whose checksum or header does not match, is refused with
:class:`CheckpointError` naming the problem; :func:`write_checkpoint` writes through a temporary
file renamed over the target, so a crash in the middle leaves no half-written checkpoint.
"""

from __future__ import annotations

import json
import os
import struct
import zlib
from dataclasses import dataclass
from typing import BinaryIO

import numpy as np

from gogreen_core.engine_settings import EngineSettings
from gogreen_core.mesh_io.atomic import atomic_write

__all__ = ["CHECKPOINT_VERSION", "CheckpointError", "SculptState", "read_checkpoint"]

CHECKPOINT_MAGIC = b"GOGREEN-CHECKPOINT\n"
CHECKPOINT_VERSION = 1
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
    """

    vertices: np.ndarray
    settings: EngineSettings
    pins: tuple[np.ndarray, np.ndarray, np.ndarray] | None
    model_size: float
    origin: np.ndarray

    def arrays(self) -> list[np.ndarray]:
        """The arrays a checkpoint file stores, in order (contiguous float64)."""
        pins = list(self.pins) if self.pins is not None else []
        return [np.ascontiguousarray(a, dtype="<f8") for a in (self.vertices, *pins)]

    def header(self) -> dict:
        """The JSON-ready part (settings, sizes, model size, origin; floats exact)."""
        return {
            "vertices": len(self.vertices),
            "pins": None if self.pins is None else len(self.pins[0]),
            "settings": self.settings.to_dict(),
            "model_size": float(self.model_size),
            "origin": [float(x) for x in self.origin],
        }

    @classmethod
    def from_header(cls, header: dict, arrays: list[np.ndarray]) -> SculptState:
        """Inverse of :meth:`header` with the arrays read back (ValueError if malformed)."""
        settings = EngineSettings.from_dict(header["settings"], "settings")
        origin = np.array(header["origin"], dtype=np.float64)
        size = float(header["model_size"])
        if origin.shape != (3,) or not np.isfinite(origin).all() or not size > 0:
            raise ValueError("model size or origin malformed")
        pins = tuple(arrays[1:4]) if header["pins"] is not None else None
        return cls(arrays[0], settings, pins, size, origin)


def _shapes(header: dict) -> list[tuple[int, ...]]:
    n, k = header["vertices"], header["pins"]
    if not isinstance(n, int) or n < 1 or not (k is None or (isinstance(k, int) and k >= 0)):
        raise ValueError("vertex or pin count malformed")
    shapes: list[tuple[int, ...]] = [(n, 3)]
    if k is not None:
        shapes += [(k, 3), (3 * k, 3 * k), (3 * k, 3 * k)]
    return shapes


def write_checkpoint(path: str | os.PathLike, state: SculptState, extra: dict) -> None:
    """Write ``state`` (and ``extra`` header fields: the journal's record number...) to
    ``path`` atomically (fsynced, renamed). OSError as raised."""
    header = json.dumps({"version": CHECKPOINT_VERSION, **extra, **state.header()}).encode()

    def write(out: BinaryIO) -> None:
        crc = 0
        for piece in (CHECKPOINT_MAGIC, struct.pack("<Q", len(header)), header):
            out.write(piece)
            crc = zlib.crc32(piece, crc)
        for array in state.arrays():
            data = memoryview(array).cast("B")
            for start in range(0, len(data), _CHUNK):
                chunk = data[start : start + _CHUNK]
                out.write(chunk)
                crc = zlib.crc32(chunk, crc)
        out.write(struct.pack("<I", crc))

    atomic_write(path, write)


def read_checkpoint(path: str | os.PathLike) -> tuple[SculptState, dict]:
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
    size = offset + 8 * sum(int(np.prod(s)) for s in shapes) + 4
    if len(data) != size:
        state = "cut short" if len(data) < size else "too long"
        raise CheckpointError(f"{name}: {state} ({len(data)} bytes, {size} expected)")
    (crc,) = struct.unpack_from("<I", data, size - 4)
    if zlib.crc32(memoryview(data)[: size - 4]) != crc:
        raise CheckpointError(f"{name}: corrupt (checksum mismatch)")
    arrays = []
    for shape in shapes:
        count = int(np.prod(shape))
        arrays.append(np.frombuffer(data, "<f8", count, offset).astype(np.float64).reshape(shape))
        offset += 8 * count
    try:
        return SculptState.from_header(header, arrays), header
    except (ValueError, KeyError, TypeError) as exc:
        raise CheckpointError(f"{name}: corrupt header ({exc})") from None
