"""The open model: mesh data, its sculptor, its file path and unsaved-changes state (no Qt).

A pure model in the napari sense: the window shows it and calls it; tests drive it directly.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gogreen_core.mesh_io import MeshData, load_mesh, save_mesh
from gogreen_core.sculptor import Sculptor
from gogreen_core.shapes import default_model

__all__ = ["SAVE_FORMATS", "Document"]

#: Extensions the app saves to (the core also writes OFF).
SAVE_FORMATS = (".obj", ".ply", ".stl")


class Document:
    """A mesh being sculpted.

    ``mesh`` keeps what the file had; ``sculptor`` owns the vertex positions, faces and
    texture coordinates while editing (a subdivision changes all three); :meth:`save` writes
    them atomically.
    """

    def __init__(self, mesh: MeshData, path: str | None, sculptor_options: dict | None = None):
        self.mesh = mesh
        self.path = path
        self.sculptor = Sculptor(
            mesh.vertices,
            mesh.faces,
            uv=mesh.uv,
            uv_faces=mesh.uv_faces,
            **(sculptor_options or {}),
        )
        self._saved_vertices = self.sculptor.vertices.copy()
        self._saved_faces = self.sculptor.faces

    @classmethod
    def open(cls, path: str, sculptor_options: dict | None = None) -> Document:
        """Load a mesh file (raises ValueError naming the file and the problem)."""
        return cls(load_mesh(path), str(path), sculptor_options)

    @classmethod
    def default(cls, sculptor_options: dict | None = None) -> Document:
        """The embedded default model (generated, not loaded from the network)."""
        vertices, faces = default_model()
        return cls(MeshData(vertices=vertices, faces=faces), None, sculptor_options)

    @property
    def title(self) -> str:
        return Path(self.path).name if self.path else "untitled (default model)"

    @property
    def dirty(self) -> bool:
        """True when the vertices or faces differ from the last saved (or loaded) state."""
        faces = self.sculptor.faces
        same_faces = faces is self._saved_faces or np.array_equal(faces, self._saved_faces)
        return not (same_faces and np.array_equal(self.sculptor.vertices, self._saved_vertices))

    def save(self, path: str | None = None) -> str:
        """Write the current vertices (atomically) to ``path`` or the document's own path."""
        target = path or self.path
        if not target:
            raise ValueError("this model has no file yet: choose a file name (Save As)")
        if Path(target).suffix.lower() not in (*SAVE_FORMATS, ".off"):
            raise ValueError(
                f"{Path(target).name}: unsupported format (save as {', '.join(SAVE_FORMATS)})"
            )
        now = self.sculptor.mesh
        out = MeshData(now.vertices, now.faces, now.uv, now.uv_faces, self.mesh.source)
        save_mesh(out, target)
        self.path = str(target)
        self._saved_vertices = now.vertices
        self._saved_faces = self.sculptor.faces
        return self.path
