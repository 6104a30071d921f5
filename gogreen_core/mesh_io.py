"""Mesh files: OBJ, PLY (ASCII and binary), STL and OFF, loaded and saved without reordering.

OBJ is read and written by our own small parser: trimesh's OBJ loader splits vertices that carry
several texture coordinates (UV seams), which would change the vertex count and order the
sculpting session and its replay rely on. Here positions stay exactly as listed in the file and
texture coordinates are kept per face corner (``uv`` and ``uv_faces``), so they survive a
load/save round trip. PLY, STL and OFF go through trimesh with ``process=False`` (no merging, no
reordering; an STL has no shared vertices by nature, so its vertices are the triangle corners).

Errors raise :class:`MeshFileError` (a ValueError) naming the file and the problem. Saving is
atomic: the data goes to a temporary file in the same folder, is flushed to disk, then renamed
over the destination; on any failure the destination is left untouched.
"""

from __future__ import annotations

import io
import os
import tempfile
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

__all__ = ["MESH_FORMATS", "MeshData", "MeshFileError", "load_mesh", "save_mesh"]

MESH_FORMATS = (".obj", ".ply", ".stl", ".off")


class MeshFileError(ValueError):
    """A mesh file could not be read or written; the message names the file and the problem."""


@dataclass
class MeshData:
    """A triangle mesh as plain arrays.

    vertices : (N, 3) float64; faces : (M, 3) int64 (triangles, polygons fan-triangulated).
    uv : (T, 2) float64 texture coordinates or None; uv_faces : (M, 3) int64 indices into
        ``uv`` per face corner (OBJ ``vt``), or None.
    source : the file it came from, if any.
    """

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray | None = None
    uv_faces: np.ndarray | None = None
    source: str | None = field(default=None)

    def copy(self) -> MeshData:
        def dup(a):
            return None if a is None else a.copy()

        return replace(
            self,
            vertices=self.vertices.copy(),
            faces=self.faces.copy(),
            uv=dup(self.uv),
            uv_faces=dup(self.uv_faces),
        )


def _check(mesh: MeshData, name: str) -> MeshData:
    v = np.asarray(mesh.vertices, dtype=np.float64)
    f = np.asarray(mesh.faces, dtype=np.int64)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) == 0:
        raise MeshFileError(f"{name}: no vertices")
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise MeshFileError(f"{name}: no triangles (faces) in the file")
    if not np.all(np.isfinite(v)):
        bad = int(np.flatnonzero(~np.isfinite(v).all(axis=1))[0])
        raise MeshFileError(f"{name}: vertex {bad} has a NaN or infinite coordinate")
    if f.min() < 0 or f.max() >= len(v):
        row = int(np.flatnonzero((f < 0).any(axis=1) | (f >= len(v)).any(axis=1))[0])
        raise MeshFileError(
            f"{name}: face {row} references vertex {int(f[row].max())} "
            f"but the file has {len(v)} vertices"
        )
    mesh.vertices, mesh.faces = v, f
    return mesh


# -- OBJ ---------------------------------------------------------------------------------------
def _obj_index(token: str, count: int, name: str, line: int) -> int:
    try:
        i = int(token)
    except ValueError:
        raise MeshFileError(f"{name}, line {line}: bad index {token!r}") from None
    if i == 0:
        raise MeshFileError(f"{name}, line {line}: OBJ indices start at 1 (got 0)")
    return i - 1 if i > 0 else count + i  # negative: relative to the end so far


def _read_obj(path: Path) -> MeshData:
    name = path.name
    vertices: list[list[float]] = []
    uvs: list[list[float]] = []
    faces: list[tuple[int, int, int]] = []
    uv_faces: list[tuple[int, int, int]] = []
    corners_without_uv = False
    with open(path, encoding="utf-8", errors="replace") as handle:
        for number, raw in enumerate(handle, start=1):
            parts = raw.split("#", 1)[0].split()
            if not parts:
                continue
            tag = parts[0]
            if tag == "v" and len(parts) < 4:
                raise MeshFileError(f"{name}, line {number}: vertex needs 3 coordinates")
            if tag == "vt" and len(parts) < 2:
                raise MeshFileError(f"{name}, line {number}: empty texture coordinate")
            try:
                if tag == "v":
                    vertices.append([float(x) for x in parts[1:4]])
                elif tag == "vt":
                    uvs.append([float(parts[1]), float(parts[2]) if len(parts) > 2 else 0.0])
            except ValueError:
                raise MeshFileError(
                    f"{name}, line {number}: bad number in {raw.strip()!r}"
                ) from None
            if tag != "f":
                continue
            if len(parts) < 4:
                raise MeshFileError(f"{name}, line {number}: a face needs at least 3 corners")
            pos, tex = [], []
            for corner in parts[1:]:
                fields = corner.split("/")
                pos.append(_obj_index(fields[0], len(vertices), name, number))
                if len(fields) > 1 and fields[1]:
                    tex.append(_obj_index(fields[1], len(uvs), name, number))
            if tex and len(tex) != len(pos):
                raise MeshFileError(
                    f"{name}, line {number}: some face corners lack a texture index"
                )
            corners_without_uv |= not tex
            for k in range(1, len(pos) - 1):  # fan triangulation
                faces.append((pos[0], pos[k], pos[k + 1]))
                if tex:
                    uv_faces.append((tex[0], tex[k], tex[k + 1]))
    if not vertices:
        raise MeshFileError(f"{name}: no vertices (empty or not an OBJ file)")
    mesh = MeshData(np.array(vertices), np.array(faces, dtype=np.int64).reshape(-1, 3))
    if uvs and uv_faces and not corners_without_uv:
        mesh.uv = np.array(uvs, dtype=np.float64)
        mesh.uv_faces = np.array(uv_faces, dtype=np.int64)
        if mesh.uv_faces.min() < 0 or mesh.uv_faces.max() >= len(mesh.uv):
            raise MeshFileError(f"{name}: a face references a missing texture coordinate")
    return mesh


def _write_obj(mesh: MeshData, out: io.TextIOBase) -> None:
    out.write("# written by GoGreen Sculpt\n")
    np.savetxt(out, mesh.vertices, fmt="v %.17g %.17g %.17g")
    if mesh.uv is not None and mesh.uv_faces is not None:
        np.savetxt(out, mesh.uv, fmt="vt %.17g %.17g")
        corners = np.stack([mesh.faces + 1, mesh.uv_faces + 1], axis=2).reshape(-1, 6)
        np.savetxt(out, corners, fmt="f %d/%d %d/%d %d/%d")
    else:
        np.savetxt(out, mesh.faces + 1, fmt="f %d %d %d")


# -- PLY, STL, OFF through trimesh --------------------------------------------------------------
def _read_with_trimesh(path: Path) -> MeshData:
    import trimesh

    try:
        loaded = trimesh.load(path, process=False, force="mesh")
    except Exception as exc:  # trimesh raises many kinds on broken files
        detail = str(exc) or type(exc).__name__
        raise MeshFileError(f"{path.name}: broken or truncated file ({detail})") from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.vertices) == 0:
        raise MeshFileError(f"{path.name}: no triangle mesh in the file")
    return MeshData(np.array(loaded.vertices, dtype=np.float64), np.array(loaded.faces))


def _write_with_trimesh(mesh: MeshData, out: io.BufferedIOBase, suffix: str, ascii: bool) -> None:
    import trimesh

    if suffix == ".ply":
        _write_ply(mesh, out, ascii)
    elif suffix == ".stl":
        tm = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
        out.write(trimesh.exchange.stl.export_stl(tm))
    else:  # OFF, exact floats
        text = io.StringIO()
        text.write(f"OFF\n{len(mesh.vertices)} {len(mesh.faces)} 0\n")
        np.savetxt(text, mesh.vertices, fmt="%.17g %.17g %.17g")
        np.savetxt(text, mesh.faces, fmt="3 %d %d %d")
        out.write(text.getvalue().encode())


def _write_ply(mesh: MeshData, out: io.BufferedIOBase, ascii: bool) -> None:
    """PLY with double-precision vertices (trimesh writes float32, which would lose the
    sculpted positions' last bits)."""
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
        text = io.StringIO()
        np.savetxt(text, mesh.vertices, fmt="%.17g %.17g %.17g")
        np.savetxt(text, mesh.faces, fmt="3 %d %d %d")
        out.write(text.getvalue().encode("ascii"))
        return
    out.write(np.ascontiguousarray(mesh.vertices, dtype="<f8").tobytes())
    record = np.dtype([("n", "u1"), ("i", "<i4", 3)])
    faces = np.empty(len(mesh.faces), dtype=record)
    faces["n"], faces["i"] = 3, mesh.faces
    out.write(faces.tobytes())


# -- public API --------------------------------------------------------------------------------
def load_mesh(path: str | os.PathLike) -> MeshData:
    """Read a mesh file (.obj, .ply, .stl, .off) keeping vertex order and count."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in MESH_FORMATS:
        raise MeshFileError(
            f"{p.name}: unknown format {suffix or '(none)'!r}; use {', '.join(MESH_FORMATS)}"
        )
    if not p.is_file():
        raise MeshFileError(f"{p}: no such file")
    if p.stat().st_size == 0:
        raise MeshFileError(f"{p.name}: the file is empty")
    try:
        mesh = _read_obj(p) if suffix == ".obj" else _read_with_trimesh(p)
    except OSError as exc:
        raise MeshFileError(f"{p.name}: cannot read ({exc.strerror})") from None
    mesh.source = str(p)
    return _check(mesh, p.name)


def save_mesh(mesh: MeshData, path: str | os.PathLike, ascii: bool = False) -> None:
    """Write ``mesh`` atomically to ``path``; the format follows the extension. PLY is binary
    unless ``ascii``. An existing file is replaced only once the new one is complete."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix not in MESH_FORMATS:
        raise MeshFileError(
            f"{p.name}: cannot save as {suffix or '(none)'!r}; use {', '.join(MESH_FORMATS)}"
        )
    _check(MeshData(mesh.vertices, mesh.faces), p.name)
    if not p.parent.is_dir():
        raise MeshFileError(f"{p}: the folder {p.parent} does not exist")
    fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=p.parent or ".")
    try:
        with os.fdopen(fd, "wb") as raw:
            if suffix == ".obj":
                text = io.TextIOWrapper(raw, encoding="utf-8", newline="\n")
                _write_obj(mesh, text)
                text.flush()
                text.detach()
            else:
                _write_with_trimesh(mesh, raw, suffix, ascii)
            raw.flush()
            os.fsync(raw.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes it private; give it a normal file's mode
        os.replace(tmp, p)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
