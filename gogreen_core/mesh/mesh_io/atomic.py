"""Atomic file writes: the data goes to a temporary file in the destination's folder, is flushed
and fsync'ed, then renamed over the destination with :func:`os.replace`. If anything fails the
temporary file is removed and an existing destination is left byte-identical. Meshes, sessions,
presets and screenshots are saved this way."""

from __future__ import annotations

import contextlib
import os
import secrets
import stat
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

from gogreen_core.mesh.mesh_io.data import MeshFileError

__all__ = ["atomic_write", "write_bytes_atomic", "write_text_atomic"]


def write_text_atomic(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically; ``MeshFileError`` on failure."""
    write_bytes_atomic(path, text.encode("utf-8"))


def write_bytes_atomic(path: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` to ``path`` atomically; ``MeshFileError`` on failure."""
    p = Path(path)
    try:
        atomic_write(p, lambda out: out.write(data))
    except OSError as exc:
        raise MeshFileError(f"{p.name}: cannot write ({exc.strerror or exc})") from None


def atomic_write(path: str | os.PathLike[str], write: Callable[[BinaryIO], object]) -> None:
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
