"""Pins (paper Fig. 1): points of the surface held in place, one of which can be dragged.

A drag moves the vertices by a direct displacement u(x) = Σ_j G(x − p_j) f_j (no pseudo-time)
with u(p_dragged) = delta and u = 0 at the other pins
(:class:`~gogreen_core.sculpt.constraints.ConstraintSet`), times (1 − mask). Each edit is an
undo step and a log entry; a drag's mouse events join one step (``continued``).
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from gogreen_core.mesh.mesh_state import MeshState
from gogreen_core.sculpt.constraints import ConstraintSet
from gogreen_core.sculpt.history import History
from gogreen_core.sculpt.kernel_cache import KernelCache
from gogreen_core.sculpt.material_frame import FramedKernels, frame_at
from gogreen_core.sculpt.operations import (
    ConstraintAdd,
    ConstraintDrag,
    ConstraintRemove,
    ConstraintsClear,
)
from gogreen_core.sculpt.session_log import SessionLog
from gogreen_core.validation import ParameterError, check_bool, check_integer, check_vector

__all__ = ["Pins"]

#: A pin's influence test: the ball about its point (no step, no mirror image).
_NO_STEP = np.zeros(3)
_ONE_IMAGE = np.ones((1, 3))


class _Points(NamedTuple):
    """The pins (k, 3) before or after adding, removing or clearing them (an undo step)."""

    points: np.ndarray


class _Pin(NamedTuple):
    """A dragged pin's index and position: the caller state of a pin-drag undo step."""

    pin_index: int  # (not ``index``: a tuple's method)
    point: np.ndarray


class Pins:
    """The pins of ``mesh``; ``kernels()`` gives the kernels of the current settings (their
    full kernel at the settings' falloff and ``constraint_radius`` · model size)."""

    def __init__(
        self,
        mesh: MeshState,
        history: History,
        log: SessionLog,
        kernels: Callable[[], KernelCache],
    ) -> None:
        self.mesh, self.history, self.log, self._kernels = mesh, history, log, kernels
        self.constraints: ConstraintSet | None = None
        #: With the "surface" material frame: the pins solved with the material turned onto
        #: the surface where the current drag started (kept while the drag continues).
        self._framed: ConstraintSet | None = None

    @property
    def points(self) -> np.ndarray:
        """(k, 3) positions of the pins."""
        return np.zeros((0, 3)) if self.constraints is None else self.constraints.points

    def __len__(self) -> int:
        return 0 if self.constraints is None else len(self.constraints)

    def built(self, kernels: KernelCache, points: np.ndarray | None = None) -> ConstraintSet:
        """A constraint set for ``kernels`` with ``points`` (k, 3) (default: the pins now);
        ValueError when the settings cannot separate them."""
        settings = kernels.settings
        eps = settings.constraint_radius * self.mesh.model_size
        constraints = ConstraintSet(kernels.full.with_radial(settings.falloff.with_eps(eps)))
        for p in self.points if points is None else points:
            constraints.add(p)
        return constraints

    def follow(self, kernels: KernelCache) -> KernelCache:
        """Rebuild the pins for new settings' ``kernels`` and keep them; returns ``kernels``.
        A failure (pins the new radius cannot separate) raises before anything changed."""
        self.constraints = None if self.constraints is None else self.built(kernels)
        return kernels

    # -- edits -------------------------------------------------------------------------------
    def add(self, point: object) -> int:
        """Pin ``point`` (3,) (within reach of the model); its index. An undo step."""
        p = self.mesh.check_point("point", point)
        constraints = self.constraints
        if constraints is None:
            constraints = self.built(self._kernels(), np.zeros((0, 3)))
        before = constraints.points
        index = constraints.add(p)
        self.constraints = constraints
        self._record("add pin", before)
        self.log.record(ConstraintAdd(p))
        return index

    def _record(self, label: str, before: np.ndarray) -> None:
        state = (_Points(before), _Points(self.points))
        self.history.record_state(label, state)

    def _check_index(self, index: object) -> int:
        if not len(self):
            raise ParameterError("index", f"index {index!r}: there are no constraints")
        return check_integer("index", index, low=0, high=len(self) - 1)

    def remove(self, index: object) -> None:
        """Remove pin ``index`` (an undo step)."""
        i = self._check_index(index)
        assert self.constraints is not None
        before = self.constraints.points
        self.constraints.remove(i)
        self._record("remove pin", before)
        self.log.record(ConstraintRemove(i))

    def clear(self) -> None:
        """Remove every pin (an undo step when there were any)."""
        before = self.points
        self.constraints = None
        if len(before):
            self._record("clear pins", before)
        self.log.record(ConstraintsClear())

    def drag(self, index: object, delta: object, continued: object = False) -> np.ndarray:
        """Move pin ``index`` by ``delta`` (3,) while the others stay; (N, 3) u. An undo step,
        joined to the previous drag when ``continued``."""
        i = self._check_index(index)
        continued = check_bool("continued", continued)
        d = check_vector("delta", delta, max_norm=self.mesh.reach)
        constraints = self.constraints
        assert constraints is not None
        start = constraints.points[i]
        self.mesh.check_point("delta", start + d)  # the pin stays within reach of the model
        targets = np.zeros((len(constraints), 3))
        targets[i] = d
        solver = self._solver(constraints, start, d, continued)
        forces = solver.solve(targets)
        # only the rows within the pins' reach move: no pass over the whole mesh
        vertices = self.mesh.vertices
        rows, moved = solver.displacement_rows(
            vertices, forces, lambda p, r: self.mesh.rows_near(p, _NO_STEP, r, _ONE_IMAGE)
        )
        if not np.all(np.isfinite(moved)):
            raise ParameterError("delta", "the pin drag would move vertices to infinity")
        if self.mesh.masked:  # masked vertices move (1 − mask) of the way: held ones not at all
            moved *= (1.0 - self.mesh.mask[rows])[:, None]
        constraints.move(i, start + d)
        if solver is not constraints:
            solver.move(i, start + d)
        before = vertices[rows]
        self.mesh.write_rows(rows, before + moved)
        # the pin's own move is undone with the vertices: (index, position) before and after
        pin = (_Pin(i, start), _Pin(i, start + d))
        self.history.record_rows(
            "constraint drag", rows, before, vertices[rows], merge=continued, state=pin
        )
        self.log.record(ConstraintDrag(i, d, continued))
        u = np.zeros_like(vertices)
        u[rows] = moved
        return u

    def _solver(
        self, constraints: ConstraintSet, start: np.ndarray, delta: np.ndarray, continued: bool
    ) -> ConstraintSet:
        """``constraints``, or with the "surface" material frame the pins with the material turned
        onto the surface at ``start`` (the dragged pin's), kept while the drag continues."""
        kernels = self._kernels()
        if kernels.settings.material_frame != "surface":
            self._framed = None
            return constraints
        framed = self._framed
        if not continued or framed is None or not np.array_equal(framed.points, constraints.points):
            radius = kernels.settings.constraint_radius * self.mesh.model_size
            frame = frame_at(self.mesh, start, radius, delta)
            framed = self._framed = self.built(FramedKernels(kernels, frame))
        return framed

    def restore(self, state: object) -> None:
        """Put back the pins an undone or redone step had (its ``restored_state``)."""
        if isinstance(state, _Points):
            points = state.points
            self.constraints = self.built(self._kernels(), points) if len(points) else None
            return
        if not isinstance(state, _Pin) or self.constraints is None:
            return
        if state.pin_index < len(self.constraints):
            with contextlib.suppress(ValueError):  # another pin sits there now: leave it
                self.constraints.move(state.pin_index, state.point)
