"""The open model: mesh data, its sculptor, its file path, unsaved-changes state and crash-
recovery journal (no Qt).

A pure model in the napari sense: the window shows it and calls it; tests drive it directly.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from gogreen_core.files.journal import Journal
from gogreen_core.files.recovery import Recovery
from gogreen_core.mesh.mesh_io import MeshData, load_mesh, save_mesh
from gogreen_core.mesh.shapes import default_model
from gogreen_core.sculpt.sculptor import Sculptor

__all__ = ["SAVE_FORMATS", "Document"]

#: Extensions the app saves to (the core also writes OFF).
SAVE_FORMATS = (".obj", ".ply", ".stl")


class Document:
    """A mesh being sculpted.

    ``mesh`` keeps what the file had; ``sculptor`` owns the vertex positions, faces and
    texture coordinates while editing (a subdivision changes all three); :meth:`save` writes
    them atomically. While the window shows it, :attr:`journal` records every operation for
    crash recovery (:meth:`start_journal`; a save starts a fresh one; :meth:`close` removes it).
    """

    def __init__(
        self,
        mesh: MeshData,
        path: str | None,
        sculptor_options: dict | None = None,
        sculptor: Sculptor | None = None,
    ):
        self.mesh = mesh
        self.path = path
        self.sculptor = sculptor or Sculptor(
            mesh.vertices,
            mesh.faces,
            uv=mesh.uv,
            uv_faces=mesh.uv_faces,
            **(sculptor_options or {}),
        )
        self._saved_vertices = self.sculptor.vertices.copy()
        self._saved_faces = self.sculptor.faces
        #: The crash-recovery journal (None until :meth:`start_journal`).
        self.journal: Journal | None = None
        #: Rebuilt from a journal after a crash and not saved since.
        self.recovered = False
        self._recovery: Recovery | None = None

    @classmethod
    def open(cls, path: str, sculptor_options: dict | None = None) -> Document:
        """Load a mesh file (raises ValueError naming the file and the problem)."""
        return cls(load_mesh(path), str(path), sculptor_options)

    @classmethod
    def default(cls, sculptor_options: dict | None = None) -> Document:
        """The embedded default model (generated, not loaded from the network)."""
        vertices, faces = default_model()
        return cls(MeshData(vertices=vertices, faces=faces), None, sculptor_options)

    @classmethod
    def recovered_from(cls, recovery: Recovery) -> Document:
        """The document a crash-recovery journal rebuilt (its undo history holds the replayed
        records); unsaved until saved. Its journal continues the recovered one, which is
        removed once the new one holds the recovered state."""
        document = cls(recovery.mesh, recovery.contents.document, sculptor=recovery.sculptor)
        document.recovered = True
        document._recovery = recovery
        return document

    @property
    def name(self) -> str:
        """The file's name, or what stands for it."""
        return Path(self.path).name if self.path else "untitled (default model)"

    @property
    def title(self) -> str:
        return f"{self.name} (recovered)" if self.recovered else self.name

    @property
    def dirty(self) -> bool:
        """True when recovered and not saved since, or when the vertices or faces differ from
        the last saved (or loaded) state."""
        faces = self.sculptor.faces
        same_faces = faces is self._saved_faces or np.array_equal(faces, self._saved_faces)
        return self.recovered or not (
            same_faces and np.array_equal(self.sculptor.vertices, self._saved_vertices)
        )

    def start_journal(self, wake: Callable[[], None] | None = None) -> Journal:
        """Record every operation from now on in a crash-recovery journal (its checkpoints are
        taken by the caller when idle: :meth:`Journal.maybe_checkpoint`)."""
        if self.journal is None:
            recovery, self._recovery = self._recovery, None
            self.journal = Journal(
                self.sculptor,
                self.mesh,
                document=self.path,
                title=self.name,
                auto_checkpoint=False,
                replaces=None if recovery is None else recovery.lock,
                wake=wake,
            )
        return self.journal

    def close(self) -> None:
        """A clean close (saved, or the changes discarded): the journal is removed."""
        if self.journal is not None:
            self.journal.close(remove=True)
            self.journal = None
        if self._recovery is not None:  # recovered, never shown: its journal stays
            self._recovery.release()
            self._recovery = None

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
        self.recovered = False
        if self.journal is not None:  # the file holds what came before
            self.journal.restart(self.path, self.name)
        return self.path
