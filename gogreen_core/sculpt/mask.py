"""The vertex mask (Blender's sculpt mask): how much each vertex is held, 0 (free) to 1.

Every brush and pin drag moves a vertex by (1 − mask) of what it would. The mask is painted
with the mask brush (:mod:`gogreen_core.sculpt.brushes.mask`), inverted or cleared here (each an
undo step and a log record).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from gogreen_core.mesh.mesh_state import MaskRows, MeshState
from gogreen_core.sculpt.history import History
from gogreen_core.sculpt.operations import MaskClear, MaskInvert
from gogreen_core.sculpt.session_log import SessionLog
from gogreen_core.validation import ParameterError

__all__ = ["Mask"]


class Mask:
    """The mask of the sculptor's mesh; ``refuse(what)`` raises while a stroke runs."""

    def __init__(
        self,
        mesh: MeshState,
        history: History,
        log: SessionLog,
        refuse: Callable[[str], None],
    ) -> None:
        self._mesh, self._history, self._log, self._refuse = mesh, history, log, refuse

    @property
    def values(self) -> np.ndarray:
        """(N,) float64 in [0, 1], one per vertex (a read-only view of the engine's array)."""
        view = self._mesh.mask.view()
        view.setflags(write=False)
        return view

    @property
    def version(self) -> int:
        """Changes with every edit of the mask (painting, invert, clear, undo, subdivision)."""
        return self._mesh.mask_version

    @property
    def any(self) -> bool:
        """Some vertex is masked (a value above 0)."""
        return self._mesh.masked

    def _change(self, label: str, rows: np.ndarray, values: np.ndarray) -> None:
        mesh = self._mesh
        before = mesh.mask_rows(rows)
        after = MaskRows(before.rows, values)
        mesh.set_mask_rows(after)
        self._history.record_state(label, (before, after))

    def adopt(self, values: np.ndarray) -> np.ndarray:
        """Take the mask a host application keeps: ``values`` (N,) in [0, 1] replace it, as
        :meth:`Sculptor.adopt_vertices` takes positions. Returns the indices (K,) of the changed
        values; ParameterError naming ``mask`` for a wrong shape or a value outside [0, 1]."""
        self._refuse("adopt a mask")
        mask = self._mesh.mask
        held = np.asarray(values, dtype=np.float64)
        if held.shape != mask.shape:
            raise ParameterError("mask", f"mask must have shape {mask.shape} (got {held.shape})")
        if not np.all((held >= 0.0) & (held <= 1.0)):  # NaN fails too
            raise ParameterError("mask", "mask values must lie in [0, 1]")
        rows = np.flatnonzero(held != mask)
        if len(rows):
            self._mesh.set_mask_rows(MaskRows(rows, held[rows]))
            self._history.clear()
        return rows

    def invert(self) -> None:
        """m → 1 − m for every vertex: one undo step."""
        self._refuse("invert the mask")
        mask = self._mesh.mask
        self._change("invert mask", np.arange(len(mask)), 1.0 - mask)
        self._log.record(MaskInvert())

    def clear(self) -> None:
        """Every vertex free (0): one undo step; nothing when nothing is masked."""
        self._refuse("clear the mask")
        rows = np.flatnonzero(self._mesh.mask)
        if not len(rows):
            return
        self._change("clear mask", rows, np.zeros(len(rows)))
        self._log.record(MaskClear())
