"""Undo/redo of vertex edits, storing only the vertices an operation moved.

Each entry keeps the indices (K,) and the positions before and after (K, 3) of the moved
vertices, so undo and redo copy exact float64 values back: positions are restored bit for bit.
A memory cap drops the oldest entries first.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["History"]


@dataclass(frozen=True)
class _Entry:
    label: str
    indices: np.ndarray  # (K,) int64
    before: np.ndarray  # (K, 3) float64
    after: np.ndarray  # (K, 3) float64

    @property
    def nbytes(self) -> int:
        return self.indices.nbytes + self.before.nbytes + self.after.nbytes


class History:
    """Undo and redo stacks of vertex edits with a memory cap (bytes)."""

    def __init__(self, max_bytes: int = 512 * 2**20):
        if not max_bytes > 0:
            raise ValueError(f"history memory cap must be > 0 bytes (got {max_bytes!r})")
        self.max_bytes = int(max_bytes)
        self._undo: list[_Entry] = []
        self._redo: list[_Entry] = []

    @property
    def can_undo(self) -> bool:
        return bool(self._undo)

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    @property
    def undo_labels(self) -> list[str]:
        """Labels of the undoable operations, oldest first."""
        return [e.label for e in self._undo]

    @property
    def redo_labels(self) -> list[str]:
        """Labels of the redoable operations, next first."""
        return [e.label for e in reversed(self._redo)]

    @property
    def memory_bytes(self) -> int:
        return sum(e.nbytes for e in self._undo + self._redo)

    def clear(self) -> None:
        self._undo.clear()
        self._redo.clear()

    def record(
        self, label: str, indices: np.ndarray, before: np.ndarray, after: np.ndarray
    ) -> None:
        """Record that vertices ``indices`` (K,) went from ``before`` to ``after`` (K, 3).
        Clears the redo stack; an empty change is not recorded."""
        idx = np.array(indices, dtype=np.int64).reshape(-1)
        b = np.array(before, dtype=np.float64).reshape(-1, 3)
        a = np.array(after, dtype=np.float64).reshape(-1, 3)
        if not len(idx) == len(b) == len(a):
            raise ValueError("history record needs as many before/after rows as indices")
        if len(idx) == 0:
            return
        self._redo.clear()
        self._undo.append(_Entry(label, idx, b, a))
        while len(self._undo) > 1 and self.memory_bytes > self.max_bytes:
            self._undo.pop(0)

    def record_change(self, label: str, before: np.ndarray, after: np.ndarray) -> None:
        """Record the rows that differ between two full (N, 3) vertex arrays."""
        changed = np.flatnonzero(np.any(before != after, axis=1))
        self.record(label, changed, before[changed], after[changed])

    def undo(self, vertices: np.ndarray) -> str | None:
        """Restore ``vertices`` (N, 3) in place to before the last entry; its label or None."""
        if not self._undo:
            return None
        entry = self._undo.pop()
        vertices[entry.indices] = entry.before
        self._redo.append(entry)
        return entry.label

    def redo(self, vertices: np.ndarray) -> str | None:
        """Re-apply the last undone entry to ``vertices`` in place; its label or None."""
        if not self._redo:
            return None
        entry = self._redo.pop()
        vertices[entry.indices] = entry.after
        self._undo.append(entry)
        return entry.label
