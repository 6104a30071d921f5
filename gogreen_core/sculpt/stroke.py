"""The stroke driver: begin a stroke, one event per mouse event, end it (one undo step and one
session log entry); and Mesh → Remesh.

Each event moves the current vertices with the stroke's brush (:mod:`gogreen_core.sculpt.brushes`);
a Green's function brush takes its field as a velocity over pseudo-time [0, 1] (paper Sec. 3.2),
so a stroke is the composition of its events' flows. With dynamic topology the strained faces
are remeshed after each event (:meth:`StrokeDriver._remesh`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from gogreen_core.mesh.mesh_state import MaskRows, MeshSnapshot, MeshState, topology_edit
from gogreen_core.mesh.remesh import (
    grow_region,
    local_edge_lengths,
    remesh,
    strained_corners,
)
from gogreen_core.mesh.subdivision import MASK_THRESHOLD
from gogreen_core.sculpt.brushes import Brush, BrushEvent, Displacement, GreenBrush, StrokeContext
from gogreen_core.sculpt.brushes.table import brush_row
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.history import History
from gogreen_core.sculpt.kernel_cache import KernelCache
from gogreen_core.sculpt.material_frame import FramedKernels, frame_at
from gogreen_core.sculpt.operations import REMESH_ITERATIONS, Remesh, Stroke
from gogreen_core.sculpt.session_log import SessionLog
from gogreen_core.validation import check_type

__all__ = [
    "CORE_MOTION",
    "DYNAMIC_ITERATIONS",
    "STRAIN_TOLERANCE",
    "PreparedRemesh",
    "Remesher",
    "StrokeDriver",
    "blend_by_mask",
]

#: Dynamic topology remeshes where a side of a face changed (as a vector) by more than this
#: fraction of its length since its vertices were last remeshed: a rigid shift strains nothing.
STRAIN_TOLERANCE = 0.1
#: ... and where a vertex moved at least this fraction of the most any did in the stroke.
CORE_MOTION = 0.25
#: Rounds of split, collapse, flip and relaxation after each event.
DYNAMIC_ITERATIONS = 1
_NO_INDEX = np.zeros(0, dtype=np.int64)


def blend_by_mask(old: np.ndarray, new: np.ndarray, held: np.ndarray) -> np.ndarray:
    """Rows (n, 3) moved (1 − ``held``) of the way from ``old`` to ``new`` (both (n, 3));
    exactly ``old`` where ``held`` (n,) is 1 and exactly ``new`` where it is 0."""
    held = held[:, None]
    blended = old + (1.0 - held) * (new - old)
    return np.where(held >= 1.0, old, np.where(held <= 0.0, new, blended))


@dataclass
class _Stroke:
    brush: Brush
    before: np.ndarray  # (N, 3) the vertices when the stroke began
    events: list[BrushEvent] = field(default_factory=list)
    memo: dict[str, Any] = field(default_factory=dict)  # the brush's state between events
    mask_before: np.ndarray | None = None  # (N,) the mask, copied at the first mask edit
    # dynamic topology: the mesh at the start (once remeshed), each vertex's, face's and texture
    # row's row in it (-1: new), position when last remeshed and event after which it was; the
    # target edge length (model units): one, or each vertex's (N,)
    start: MeshSnapshot | None = None
    origin: np.ndarray = field(default_factory=lambda: _NO_INDEX)
    face_origin: np.ndarray = field(default_factory=lambda: _NO_INDEX)
    uv_origin: np.ndarray | None = None
    reference: np.ndarray | None = None
    settled_at: np.ndarray | None = None
    detail: float | np.ndarray | None = None
    kernels: KernelCache | None = None  # the surface frame's, fixed at the first event
    # the rows (ascending) moved since they were last remeshed: only their faces can be strained
    unsettled: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    fastest: float = 0.0  # the core's largest squared motion an event so far


class StrokeDriver:
    """Strokes on ``mesh``: each ends as one undo step in ``history`` and one :class:`Stroke`
    record in ``log``."""

    def __init__(self, mesh: MeshState, history: History, log: SessionLog) -> None:
        self.mesh, self.history, self.log = mesh, history, log
        self._stroke: _Stroke | None = None
        self._rows = np.empty((0, 3))  # the brushes' result rows, grown as needed
        #: The pins' points (k, 3): dynamic topology never moves nor removes their vertices.
        self.pin_points: Callable[[], np.ndarray] = lambda: np.zeros((0, 3))

    @property
    def active(self) -> bool:
        return self._stroke is not None

    @property
    def current_kernels(self) -> KernelCache | None:
        """The kernels the current stroke has fixed (its surface frame's), else None."""
        return None if self._stroke is None else self._stroke.kernels

    def refuse(self, what: str) -> None:
        """RuntimeError naming ``what`` while a stroke runs (what may not happen then)."""
        if self._stroke is not None:
            raise RuntimeError(f"cannot {what} during a stroke; end the stroke first")

    def context(self, kernels: KernelCache) -> StrokeContext:
        """What a brush sees of the engine (the mesh, ``kernels``, the result buffer, its state
        in the current stroke)."""
        memo = None if self._stroke is None else self._stroke.memo
        return StrokeContext(
            self.mesh, kernels, self._buffer, write_through=not self.mesh.masked, stroke=memo
        )

    def begin(self, brush: Brush) -> None:
        self._stroke = _Stroke(check_type("brush", brush, Brush), self.mesh.vertices.copy())

    def event(self, kernels: KernelCache, event: BrushEvent) -> np.ndarray:
        """Apply one event of the current stroke; the indices (n,) of the rows it moved (or
        whose mask it painted)."""
        stroke = self._stroke
        if stroke is None:
            raise RuntimeError("stroke_event outside a stroke: call begin_stroke first")
        check_type("event", event, BrushEvent)
        # pen pressure → radius (the field bound is cached in units of ε: valid for any)
        brush = event.brush(stroke.brush)
        self.mesh.check_point("center", event.center)
        behaviour = brush.type
        event = behaviour.with_amount(event)  # recorded as it acts: a replay acts the same
        behaviour.check_event(brush, event, self.mesh.reach)
        kernels = self._stroke_kernels(stroke, kernels, brush, event)
        moved = behaviour.displace(self.context(kernels), brush, event)
        self._write(stroke, moved)
        stroke.events.append(event)
        rows = moved.rows
        if kernels.settings.dynamic_topology and moved.mask is None and len(rows):
            if self._remesh(stroke, kernels.settings, rows):
                rows = np.arange(len(self.mesh.vertices))
        self.log.event(event)  # the recovery journal serializes it now
        return rows

    def _stroke_kernels(
        self, stroke: _Stroke, kernels: KernelCache, brush: Brush, event: BrushEvent
    ) -> KernelCache:
        """The kernels the stroke computes with: ``kernels``, or with the "surface" material
        frame those turned onto the surface at the stroke's first event (then kept)."""
        if kernels.settings.material_frame != "surface" or not isinstance(brush.type, GreenBrush):
            return kernels
        if stroke.kernels is None:
            stroke.kernels = FramedKernels(kernels, surface_frame_of(self.mesh, brush, event))
        return stroke.kernels

    def pinned_vertices(self) -> np.ndarray:
        """(N,) bool: the vertex nearest each pin."""
        vertices = self.mesh.vertices
        pinned = np.zeros(len(vertices), dtype=bool)
        for point in self.pin_points():
            gap = vertices - point
            pinned[np.argmin(np.einsum("ij,ij->i", gap, gap))] = True
        return pinned

    def _remesh(self, stroke: _Stroke, settings: EngineSettings, rows: np.ndarray) -> bool:
        """Dynamic topology after an event that moved ``rows``: remesh the faces (grown by a
        ring) around vertices strained (:data:`STRAIN_TOLERANCE`) or moving most
        (:data:`CORE_MOTION`) since they were last remeshed. True when the mesh changed."""
        mesh = self.mesh
        if stroke.reference is None:
            stroke.reference, stroke.settled_at = stroke.before, np.zeros(len(stroke.before), int)
        if stroke.detail is None:
            if settings.detail_size is not None:
                stroke.detail = settings.detail_size * mesh.model_size
            else:  # each vertex's edges before the stroke: coarse parts stay coarse
                stroke.detail = local_edge_lengths(stroke.before, mesh.faces)
        detail = stroke.detail
        if not np.all(detail > 0):  # a model of size 0: nothing to measure by
            return False
        # a face this event did not move strains as after the last one: not enough
        around = np.zeros(len(mesh.vertices), dtype=bool)
        around[stroke.unsettled] = True  # a mark, not np.union1d: no sort of ~N rows
        around[rows] = True
        unsettled = stroke.unsettled = np.flatnonzero(around)
        around[:] = False
        around[rows] = True
        strained = strained_corners(
            stroke.reference, mesh.vertices, mesh.faces, around, STRAIN_TOLERANCE**2
        )
        # and the brush's core, per event (against the total motion the bar would creep out), as
        # against the fastest yet: after a pause the whole path would be the core, remeshed at once
        assert stroke.settled_at is not None
        shift = mesh.vertices[unsettled] - stroke.reference[unsettled]
        elapsed = len(stroke.events) - stroke.settled_at[unsettled]
        moved2 = np.einsum("ij,ij->i", shift, shift) / (elapsed * elapsed)
        stroke.fastest = max(stroke.fastest, float(moved2.max()))
        strained[unsettled] |= (moved2 > 0) & (moved2 >= CORE_MOTION**2 * stroke.fastest)
        if not strained.any():
            return False
        if stroke.start is None:  # the topology is still the stroke's start's
            start = (stroke.before, mesh.faces, mesh.mask.copy(), mesh.uv, mesh.uv_faces)
            stroke.start = MeshSnapshot(*start)
            stroke.origin = np.arange(len(mesh.vertices))
            stroke.face_origin = np.arange(len(mesh.faces))
            stroke.uv_origin = None if mesh.uv is None else np.arange(len(mesh.uv))
        done = remesh(
            mesh.vertices,
            mesh.faces,
            grow_region(mesh.faces, strained),
            detail,
            mask=mesh.mask,
            uv=mesh.uv,
            uv_faces=mesh.uv_faces,
            locked=self.pinned_vertices(),
            iterations=DYNAMIC_ITERATIONS,
        )
        # the remeshed vertices settle where they are now; the unsettled others keep theirs
        reference = done.vertices.copy()
        now = done.kept[unsettled]
        still = now >= 0
        still[still] = ~done.changed[now[still]]
        reference[now[still]] = stroke.reference[unsettled[still]]
        stroke.reference, stroke.unsettled = reference, now[still]
        settled_at = np.full(len(done.vertices), len(stroke.events), dtype=np.int64)
        settled_at[now[still]] = stroke.settled_at[unsettled[still]]
        stroke.settled_at = settled_at
        if done.sizes is not None:
            stroke.detail = done.sizes
        for name, kept, new in (
            ("origin", done.kept >= 0, done.vertices),
            ("face_origin", done.kept_faces, done.faces),
            ("uv_origin", None if done.uv_kept is None else done.uv_kept >= 0, done.uv),
        ):  # the kept rows come first, in order
            if kept is not None and new is not None:
                carried = np.compress(kept, getattr(stroke, name))
                n = len(new) - len(carried)
                setattr(stroke, name, np.concatenate([carried, np.full(n, -1)]))
        assert done.mask is not None
        new_mesh = MeshSnapshot(done.vertices, done.faces, done.mask, done.uv, done.uv_faces)
        mesh.adopt(new_mesh, owned=True)
        mesh.renumbering = (stroke.start.faces, stroke.origin, stroke.face_origin)
        return True

    def _write(self, stroke: _Stroke, moved: Displacement) -> None:
        """The one place brush results reach the mesh (unless the brush wrote them through)."""
        mesh = self.mesh
        if moved.mask is not None:
            if stroke.mask_before is None:
                stroke.mask_before = mesh.mask.copy()
            mesh.set_mask_rows(MaskRows(moved.rows, moved.mask))
            return
        if moved.written:
            mesh.moved(moved.rows)  # the brush wrote them in place
            return
        if moved.positions is None:
            return
        positions = moved.positions
        if mesh.masked:
            positions = blend_by_mask(mesh.vertices[moved.rows], positions, mesh.mask[moved.rows])
        mesh.write_rows(moved.rows, positions)

    def _buffer(self, n: int) -> np.ndarray:
        """A C-contiguous (n, 3) float64 buffer, kept between events."""
        if len(self._rows) < n:
            self._rows = np.empty((n, 3))
        return self._rows[:n]

    def end(self) -> np.ndarray:
        """Finish the stroke: one undo step and one log entry, unless it changed nothing.
        Returns the moved indices."""
        stroke, self._stroke = self._stroke, None
        if stroke is None:
            return np.zeros(0, dtype=np.int64)
        # the changed rows found once here, not marked every event (1M vertices: 6 ms once)
        mesh, label = self.mesh, f"{brush_row(stroke.brush.kind).label} stroke"
        if stroke.start is not None:  # new faces: what changed
            origins = (stroke.origin, stroke.face_origin, stroke.uv_origin)
            self.history.record_state(label, topology_edit(stroke.start, mesh, *origins))
            self.log.record(Stroke(stroke.brush, tuple(stroke.events)))
            return np.arange(len(mesh.vertices))
        vertices, before = self.mesh.vertices, stroke.before
        changed = before[:, 0] != vertices[:, 0]
        for k in (1, 2):
            changed |= before[:, k] != vertices[:, k]
        idx = np.flatnonzero(changed)
        state = None
        if stroke.mask_before is not None:
            painted = np.flatnonzero(stroke.mask_before != self.mesh.mask)
            if len(painted):
                state = (
                    MaskRows(painted, stroke.mask_before[painted]),
                    self.mesh.mask_rows(painted),
                )
        # a stroke that changed nothing (no vertex, no mask value) is no undo step, no log entry
        if len(idx) or state is not None:
            self.history.record(label, idx, stroke.before[idx], vertices[idx], state)
            self.log.record(Stroke(stroke.brush, tuple(stroke.events)))
        return idx

    def cancel(self) -> None:
        """Abandon the current stroke, restoring the vertices (and mask) as they were before."""
        stroke, self._stroke = self._stroke, None
        if stroke is not None and stroke.start is not None:
            self.mesh.adopt(stroke.start)
        elif stroke is not None:
            self.mesh.write_rows(None, stroke.before)
            if stroke.mask_before is not None:
                self.mesh.set_mask_rows(MaskRows(np.arange(len(stroke.before)), stroke.mask_before))


@dataclass(frozen=True)
class PreparedRemesh:
    """A Mesh → Remesh computed ahead (:meth:`Remesher.prepare`, :meth:`compute` on any thread),
    adopted by :meth:`Remesher.remesh` if the mesh is still ``before``."""

    op: Remesh
    before: MeshSnapshot
    length: float | None  # the target edge length, model units (None: each vertex's own)
    locked: np.ndarray  # (N,) bool: the pins' vertices
    result: list[MeshSnapshot] = field(default_factory=list)  # the after-side, once computed

    def compute(self, progress: Callable[[float], None] | None = None) -> PreparedRemesh:
        """Remesh ``before`` (``progress(fraction)`` may raise to cancel); returns itself."""
        op, before = self.op, self.before
        # without a detail size each vertex's own: about as many vertices, fine parts fine
        length = self.length or local_edge_lengths(before.vertices, before.faces)
        masked = (before.mask >= MASK_THRESHOLD) & op.unmasked_only
        done = remesh(
            before.vertices,
            before.faces,
            ~masked,
            length,
            mask=before.mask,
            uv=before.uv,
            uv_faces=before.uv_faces,
            locked=self.locked,
            iterations=op.iterations,
            progress=progress,
        )
        assert done.mask is not None
        after = MeshSnapshot(done.vertices, done.faces, done.mask, done.uv, done.uv_faces)
        self.result[:] = [after.frozen()]  # read-only, compact: the undo's after
        return self

    def made_from(self, mesh: MeshSnapshot | MeshState) -> bool:
        """``mesh`` has the arrays this remesh was computed from."""
        b = self.before
        return bool(
            np.array_equal(b.vertices, mesh.vertices)
            and np.array_equal(b.faces, mesh.faces)
            and np.array_equal(b.mask, mesh.mask)
        )


class Remesher:
    """Mesh → Remesh on the mesh of ``strokes`` (whose pins it keeps): one undo step in
    ``history`` and one :class:`Remesh` record in ``log`` each."""

    def __init__(
        self, mesh: MeshState, history: History, log: SessionLog, strokes: StrokeDriver
    ) -> None:
        self.mesh, self.history, self.log, self.strokes = mesh, history, log, strokes

    def prepare(
        self,
        detail_size: float | None,
        unmasked_only: bool = False,
        iterations: int = REMESH_ITERATIONS,
    ) -> PreparedRemesh:
        """What :meth:`remesh` with these arguments computes, to compute on another thread
        (:meth:`PreparedRemesh.compute`, on a copy of the mesh) and adopt with ``prepared``."""
        self.strokes.refuse("remesh")
        op = Remesh(detail_size, unmasked_only, iterations)  # checked
        mesh = self.mesh
        length = None if op.detail_size is None else op.detail_size * mesh.model_size
        return PreparedRemesh(op, mesh.snapshot(), length, self.strokes.pinned_vertices())

    def remesh(
        self,
        detail_size: float | None,
        unmasked_only: bool = False,
        iterations: int = REMESH_ITERATIONS,
        *,
        prepared: PreparedRemesh | None = None,
    ) -> None:
        """Remesh the whole mesh, or its faces not masked, to edges of about ``detail_size``
        model sizes (None: each vertex's own; :mod:`gogreen_core.mesh.remesh`), the pins'
        vertices kept: one undo step and log entry. ``prepared``: the same computed ahead
        (:meth:`prepare`); ValueError, nothing changed, if the mesh changed since."""
        self.strokes.refuse("remesh")
        if prepared is None:
            prepared = self.prepare(detail_size, unmasked_only, iterations).compute()
        op, before = prepared.op, prepared.before
        if op != Remesh(detail_size, unmasked_only, iterations) or not prepared.result:
            raise ValueError("the prepared remesh is another one, or not computed: remesh again")
        if not prepared.made_from(self.mesh):
            raise ValueError("the mesh changed since the remesh was prepared: remesh again")
        after = prepared.result[0]
        self.mesh.adopt(after)
        self.history.record_state("remesh", (before, after))
        self.log.record(op)


def surface_frame_of(mesh: MeshState, brush: Brush, event: BrushEvent) -> np.ndarray:
    """The surface frame (3, 3) of a stroke of ``brush`` whose first event is ``event``: the
    area normal within the brush's ε of its centre, the first axis along its motion (an affine
    brush's stroke direction, another's cursor motion; :func:`frame_at`)."""
    motion = event.direction if brush.type.is_affine else event.delta
    return frame_at(mesh, event.center, brush.eps(mesh.model_size), motion)
