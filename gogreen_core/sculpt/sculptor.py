"""The sculpting engine: a mesh, its settings, strokes, pins, undo and the session log. Everything
the app does with the mouse goes through :class:`Sculptor`, so a script can do it too."""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np

from gogreen_core.field.kernel import GreenKernel
from gogreen_core.field.limits import check_constraint_radius
from gogreen_core.mesh.mesh_state import MaskRows, MeshEdit, MeshSnapshot, MeshState
from gogreen_core.mesh.subdivision import PreparedSubdivision, prepare_subdivision
from gogreen_core.physics.material import Material
from gogreen_core.physics.radial import RadialProfile
from gogreen_core.sculpt.brushes import Brush, BrushEvent
from gogreen_core.sculpt.checkpoint import SculptState
from gogreen_core.sculpt.constraints import CONSTRAINT_INFLUENCE, ConstraintSet
from gogreen_core.sculpt.engine_settings import (
    SETTING_GROUPS,
    EngineSettings,
    resized_brush_weights,
)
from gogreen_core.sculpt.history import History
from gogreen_core.sculpt.kernel_cache import KernelCache
from gogreen_core.sculpt.mask import Mask
from gogreen_core.sculpt.operations import Operation, Redo, Subdivide, Undo, settings_record
from gogreen_core.sculpt.pins import Pins
from gogreen_core.sculpt.session import (
    SESSION_FORMAT,
    SESSION_VERSION,
    Session,
    mesh_fingerprint,
    parse_session,
    replay,
)
from gogreen_core.sculpt.session_log import LogListener, SessionLog
from gogreen_core.sculpt.stroke import Remesher, StrokeDriver
from gogreen_core.validation import (
    ParameterError,
    check_bool,
    check_type,
    check_vector,
    prefixed,
)

__all__ = [
    "Sculptor",
    "capture_state",
    "restore_state",
]

#: Undo label of each settings group (a continued change joins the last of these).
_LABELS = {group[0]: group[0].replace("_", " ") for group in SETTING_GROUPS}


class Sculptor:
    """Sculpting state and operations (no GUI).

    Parameters
    ----------
    vertices : (N, 3) float64, faces : (M, 3) int64
        The mesh; vertices are copied and then edited in place (see :attr:`vertices`).
    uv : (T, 2) float64 and uv_faces : (M, 3) int64, optional
        Texture coordinates per face corner (rows of -1: untextured faces), carried through a
        subdivision (see :attr:`mesh`).
    settings : EngineSettings, optional
        Material, falloff, l_max, brushes' weights, pins' radius... in one value; or some of
        its fields as keywords (``material=``, ``l_max=``...; an unknown one is refused).
    history_bytes : memory cap of the undo history (:attr:`history`).
    """

    def __init__(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        *,
        uv: np.ndarray | None = None,
        uv_faces: np.ndarray | None = None,
        settings: EngineSettings | None = None,
        history_bytes: int = 512 * 2**20,
        **values: Any,
    ) -> None:
        self._mesh = MeshState(vertices, faces, uv, uv_faces)
        self.model_size = self._mesh.model_size
        self._loaded = (len(self._mesh.vertices), len(self._mesh.faces))  # the session's mesh
        self.history = History(history_bytes)
        self._log = SessionLog()
        self._fingerprint = mesh_fingerprint(self._mesh.vertices)
        if settings is None:
            settings = EngineSettings(**values)
        elif values:
            raise TypeError("Sculptor() takes settings or their fields one by one, not both")
        self._kernels = KernelCache(check_type("settings", settings, EngineSettings))
        self._initial = settings
        self._strokes = StrokeDriver(self._mesh, self.history, self._log)
        self._pins = Pins(self._mesh, self.history, self._log, lambda: self._kernels)
        self._strokes.pin_points = lambda: self._pins.points  # dynamic topology keeps them
        #: Mesh → Remesh (:meth:`Remesher.remesh`).
        self.remesher: Remesher = Remesher(self._mesh, self.history, self._log, self._strokes)
        #: The vertex mask: what holds vertices still under every brush and pin drag.
        self.mask: Mask = Mask(self._mesh, self.history, self._log, self._strokes.refuse)

    # -- state -------------------------------------------------------------------------------
    @property
    def vertices(self) -> np.ndarray:
        """(N, 3) current positions (read-only view; the engine edits the array in place)."""
        view = self._mesh.vertices.view()
        view.setflags(write=False)
        return view

    @property
    def faces(self) -> np.ndarray:
        """(M, 3) int64 faces (a subdivision, and its undo, give the sculptor new ones)."""
        return self._mesh.faces

    @property
    def mesh(self) -> MeshSnapshot:
        """Copies of the mesh's arrays: vertices, faces, mask, UVs and their corners."""
        return self._mesh.snapshot()

    @property
    def origin(self) -> np.ndarray:
        """(3,) point of the mirror planes: the bounding box's centre at load, unless set."""
        return self._mesh.origin

    @origin.setter
    def origin(self, point: np.ndarray) -> None:
        self._mesh.origin = check_vector("origin", point)

    @property
    def settings(self) -> EngineSettings:
        """Material, falloff, l_max, wrinkle weights and constraint radius (immutable)."""
        return self._kernels.settings

    @property
    def material(self) -> Material:
        return self.settings.material

    @property
    def falloff(self) -> RadialProfile:
        return self.settings.falloff

    @property
    def l_max(self) -> int:
        return self.settings.l_max

    @property
    def in_stroke(self) -> bool:
        return self._strokes.active

    def adopt_vertices(self, vertices: np.ndarray) -> np.ndarray:
        """Take positions (N, 3) a host application (Blender) changed outside the engine: the
        rows that differ are written, no undo step or record (undo is cleared). Returns their
        indices (K,); ParameterError for a wrong shape or a coordinate that is not finite."""
        self._strokes.refuse("adopt vertices")
        mesh = self._mesh
        new = np.asarray(vertices, dtype=np.float64)
        if new.shape != mesh.vertices.shape:
            raise ParameterError(
                "vertices", f"vertices must have shape {mesh.vertices.shape} (got {new.shape})"
            )
        rows = np.flatnonzero((new != mesh.vertices).any(axis=1))
        if not np.all(np.isfinite(new[rows])):
            raise ParameterError("vertices", "vertices must be finite")
        if len(rows):
            mesh.write_rows(rows, new[rows])
            self.history.clear()
        return rows

    # -- settings ----------------------------------------------------------------------------
    def apply_settings(
        self, settings: EngineSettings, *, continued: bool = False, one_step: bool = False
    ) -> None:
        """Compute with ``settings`` from now on: each group of fields that differs changes
        (:meth:`change_settings`, one undo step per group, or all in one with ``one_step``)."""
        settings = check_type("settings", settings, EngineSettings)
        for group in SETTING_GROUPS:
            if not self.settings.agrees(settings, group):
                values = {name: getattr(settings, name) for name in group}
                self.change_settings(continued=continued, **values)
                continued = continued or one_step

    def change_settings(
        self, *, continued: bool = False, replaying: bool = False, **changes: Any
    ) -> None:
        """Change one group of :attr:`settings` (``material``, ``falloff``...): one undo step
        and log entry, or part of the last settings step when ``continued`` (a drag's later
        values). An unchanged value is ignored unless ``continued`` or ``replaying``."""
        keys = set(changes)
        group = next((g for g in SETTING_GROUPS if keys and keys <= set(g)), None)
        if group is None:
            groups = ", ".join(" / ".join(group) for group in SETTING_GROUPS)
            raise TypeError(
                f"change_settings() takes one group of {groups} at a time (got {sorted(keys)})"
            )
        continued = check_bool("continued", continued)
        before = self.settings
        if "l_max" in keys and "brush_weights" not in keys:  # weights belong to one l_max
            changes["brush_weights"] = resized_brush_weights(before.brush_weights, changes["l_max"])
        after = before.replace(**changes)
        label = _LABELS[group[0]]
        self._strokes.refuse(f"change the {label}")
        if after == before and not (continued or replaying):
            return  # nothing to do, nothing to undo
        self._kernels = self._pins.follow(KernelCache(after, self._kernels))
        last = self.history.undo_labels[-1] if self.history.can_undo else None
        merge = continued and last in _LABELS.values() and not self.history.can_redo
        self.history.record_state(last if merge and last else label, (before, after), merge)
        # A collapsed drag is logged as its last value; the replay makes the same one step.
        self._log.record(settings_record(after, group[0], continued), replace_last=merge)

    def set_material(self, material: Material, continued: bool = False) -> None:
        """Use ``material`` for the next operations (see :meth:`change_settings`)."""
        self.change_settings(material=material, continued=continued)

    def set_falloff(
        self, falloff: RadialProfile, l_max: int | None = None, *, continued: bool = False
    ) -> None:
        """Use this falloff shape (and l_max; None: kept) from now on, the brushes' weights
        resized to it (see :meth:`change_settings`)."""
        l_max = self.l_max if l_max is None else l_max
        self.change_settings(falloff=falloff, l_max=l_max, continued=continued)

    def set_constraint_radius(self, radius: float, continued: bool = False) -> None:
        """ε of the constraints, relative to the model size (see :meth:`change_settings`)."""
        radius = check_constraint_radius(radius, "radius")
        self.change_settings(constraint_radius=radius, continued=continued)

    # -- strokes -----------------------------------------------------------------------------
    def kernel(self, brush: Brush) -> GreenKernel | None:
        """The kernel of ``brush`` on this model: its falloff, ε and degree weights (None for
        a brush without a Green's function)."""
        return brush.type.kernel(self._strokes.context(self._kernels), brush)

    def influence(self, brush: Brush) -> float:
        """``brush``'s influence radius in ε (``inf``: every vertex): its own number, or what
        ``"auto"`` gives with the current settings (the cursor's influence ring)."""
        context = self._strokes.context(self._kernels)
        return check_type("brush", brush, Brush).type.reach(context, brush)

    def begin_stroke(self, brush: Brush) -> None:
        """Start a stroke with ``brush``; events follow, then :meth:`end_stroke`."""
        self._strokes.refuse("begin a stroke")
        self._strokes.begin(brush)

    def stroke_event(self, event: BrushEvent) -> np.ndarray:
        """Apply one mouse event of the current stroke; returns the indices of moved vertices.
        ParameterError naming the event field (nothing moved) beyond the limits of
        :mod:`gogreen_core.field.limits` (``MAX_REACH``, ``MAX_AMOUNT``)."""
        return self._strokes.event(self._kernels, event)

    def end_stroke(self) -> np.ndarray:
        """Finish the stroke: one undo step and one log entry. Returns the moved indices."""
        return self._strokes.end()

    def cancel_stroke(self) -> None:
        """Abandon the current stroke, restoring the vertices as they were before it."""
        self._strokes.cancel()

    def apply_brush(
        self,
        brush: Brush,
        events: Sequence[BrushEvent],
        progress: Callable[[], None] | None = None,
    ) -> np.ndarray:
        """A whole stroke at once; returns the moved indices (no events: ParameterError).
        ``progress()`` is called after each event."""
        if len(events) == 0:
            raise ParameterError("events", "a stroke needs at least one event (none given)")
        self.begin_stroke(brush)
        try:
            for number, event in enumerate(events):
                with prefixed(f"events[{number}]"):
                    self.stroke_event(event)
                if progress is not None:
                    progress()
        except Exception:
            self.cancel_stroke()
            raise
        return self.end_stroke()

    # -- pins --------------------------------------------------------------------------------
    @property
    def constraint_points(self) -> np.ndarray:
        """(k, 3) positions of the constraints."""
        return self._pins.points

    @property
    def constraint_reach(self) -> float:
        """Distance (model units) beyond which a pin moves nothing (``CONSTRAINT_INFLUENCE``
        constraint radii)."""
        return CONSTRAINT_INFLUENCE * self.settings.constraint_radius * self._mesh.model_size

    def add_constraint(self, point: np.ndarray) -> int:
        """Pin a point (3,) (model units, within ``MAX_REACH`` model sizes of the model's
        centre); returns its index. An undo step (the vertices do not move)."""
        self._strokes.refuse("add a constraint")
        return self._pins.add(point)

    def remove_constraint(self, index: int) -> None:
        """Remove pin ``index`` (an undo step)."""
        self._strokes.refuse("remove a constraint")
        self._pins.remove(index)

    def clear_constraints(self) -> None:
        """Remove every pin (an undo step when there were any)."""
        self._strokes.refuse("clear the constraints")
        self._pins.clear()

    def drag_constraint(self, index: int, delta: np.ndarray, continued: bool = False) -> np.ndarray:
        """Move pin ``index`` by ``delta`` (3,) while the others stay (:meth:`Pins.drag`);
        ``continued`` joins the previous drag's undo step. Returns (N, 3) u."""
        self._strokes.refuse("drag a constraint")
        return self._pins.drag(index, delta, continued)

    # -- topology ----------------------------------------------------------------------------
    def subdivide(
        self,
        unmasked_only: bool = False,
        *,
        progress: Callable[[float], None] | None = None,
        prepared: PreparedSubdivision | None = None,
    ) -> None:
        """One step of Loop subdivision of the whole mesh or its unmasked faces; one undo step
        and log entry. ``prepared``: the same computed ahead from :attr:`mesh` (ValueError if
        the mesh changed since); ``progress(fraction)`` while computing here."""
        self._strokes.refuse("subdivide")
        unmasked_only = check_bool("unmasked_only", unmasked_only)
        mesh = self._mesh
        before = mesh.snapshot()
        if prepared is None:
            prepared = prepare_subdivision(before, unmasked_only, progress, mesh.edges)
        elif prepared.unmasked_only != unmasked_only or not prepared.made_from(before):
            raise ValueError(
                "the prepared subdivision was made from another mesh (it changed since, or "
                "another part was asked for): subdivide again"
            )
        mesh.adopt(prepared.result)  # copies: the read-only result is the step's after-side
        state = (before, prepared.result)
        self.history.record_state("subdivide", state)
        self._log.record(Subdivide(unmasked_only))

    # -- history -----------------------------------------------------------------------------
    def undo(self) -> str | None:
        """Undo the last step (bit for bit); returns its label or None."""
        self._strokes.refuse("undo")
        return self._history_step(self.history.undo, Undo())

    def redo(self) -> str | None:
        self._strokes.refuse("redo")
        return self._history_step(self.history.redo, Redo())

    def _history_step(
        self, step: Callable[[np.ndarray], str | None], record: Operation
    ) -> str | None:
        label = step(self._mesh.vertices)
        if label is not None:
            self._mesh.moved(self.history.restored_indices)  # written in place
            state = self.history.restored_state
            if isinstance(state, EngineSettings):
                self._kernels = self._pins.follow(KernelCache(state, self._kernels))
            elif isinstance(state, MaskRows):
                self._mesh.set_mask_rows(state)
            elif isinstance(state, (MeshSnapshot, MeshEdit)):
                self._mesh.adopt(state)
            else:
                self._pins.restore(state)
            self._log.record(record)
        return label

    @contextlib.contextmanager
    def all_or_nothing(self) -> Iterator[None]:
        """A block whose failure puts back the mesh, settings, pins, history and log."""
        mesh = self._mesh.snapshot()
        kernels, points = self._kernels, None if not len(self._pins) else self._pins.points
        history, log_length = self.history.snapshot(), len(self._log)
        try:
            yield
        except BaseException:
            self.cancel_stroke()
            self._mesh.adopt(mesh)
            self._kernels = kernels
            self._pins.constraints = None if points is None else self._pins.built(kernels, points)
            self.history.restore(history)
            self._log.truncate(log_length)
            raise

    # -- session log -------------------------------------------------------------------------
    def subscribe(self, listener: LogListener) -> Callable[[], None]:
        """:meth:`SessionLog.subscribe`: returns the function that unsubscribes ``listener``."""
        return self._log.subscribe(listener)

    @property
    def operations(self) -> list[Operation]:
        """The typed operation records so far (see :mod:`gogreen_core.sculpt.operations`)."""
        return list(self._log)

    def session(self) -> dict[str, Any]:
        """The session so far as a JSON-ready dict (see README, "Session files")."""
        return {
            "format": SESSION_FORMAT,
            "version": SESSION_VERSION,
            "mesh": {  # the mesh it started from (a subdivision changes the sculptor's)
                "vertices": self._loaded[0],
                "faces": self._loaded[1],
                "sha256": self._fingerprint,
            },
            "settings": self._initial.to_dict(),
            "operations": [op.to_dict() for op in self._log],
        }

    @classmethod
    def from_session(
        cls,
        session: dict[str, Any] | Session,
        vertices: np.ndarray,
        faces: np.ndarray,
        uv: np.ndarray | None = None,
        uv_faces: np.ndarray | None = None,
    ) -> Sculptor:
        """A sculptor on this mesh with the session's initial settings (see :meth:`replay`)."""
        parsed = session if isinstance(session, Session) else parse_session(session)
        if parsed.vertices != len(vertices) or parsed.faces != len(faces):
            raise ValueError(
                f"the session was recorded on a mesh with {parsed.vertices} vertices and "
                f"{parsed.faces} faces; this one has {len(vertices)} and {len(faces)}"
            )
        return cls(vertices, faces, uv=uv, uv_faces=uv_faces, settings=parsed.settings)

    def replay(
        self,
        operations: Sequence[dict[str, Any]] | Sequence[Operation] | Session,
        progress: Callable[[int, int], None] | None = None,
    ) -> None:
        """Apply logged operations in order (:func:`gogreen_core.sculpt.session.replay`)."""
        replay(self, operations, progress)


# -- crash recovery ----------------------------------------------------------------------------
def capture_state(sculptor: Sculptor, faces: np.ndarray | None = None) -> SculptState:
    """A copy of what ``sculptor``'s next operations compute from (:class:`SculptState`); its
    faces and UVs (held: never edited in place) unless they are the array ``faces``."""
    pins = sculptor._pins.constraints
    mesh = sculptor._mesh
    topology = mesh.faces is not faces
    return SculptState(
        mesh.vertices.copy(),
        sculptor.settings,
        None if pins is None else (pins.points, pins.matrix.copy(), pins.inverse.copy()),
        mesh.model_size,
        mesh.origin.copy(),
        mesh.mask.copy() if mesh.masked else None,
        mesh.faces if topology else None,
        mesh.uv if topology else None,
        mesh.uv_faces if topology else None,
    )


def restore_state(
    state: SculptState,
    faces: np.ndarray,
    uv: np.ndarray | None = None,
    uv_faces: np.ndarray | None = None,
) -> Sculptor:
    """A sculptor that continues bit for bit from ``state`` (:func:`capture_state`), empty
    history and log. ``faces``, ``uv``, ``uv_faces``: for a state without its own."""
    if state.faces is not None:
        faces, uv, uv_faces = state.faces, state.uv, state.uv_faces
    sculptor = Sculptor(state.vertices, faces, uv=uv, uv_faces=uv_faces, settings=state.settings)
    if state.mask is not None:
        sculptor._mesh.set_mask_rows(MaskRows(np.arange(len(state.mask)), state.mask))
    sculptor.model_size = sculptor._mesh.model_size = float(state.model_size)
    sculptor._mesh.origin = state.origin.copy()
    if state.pins is not None:
        kernel = sculptor._pins.built(sculptor._kernels, np.zeros((0, 3))).kernel
        sculptor._pins.constraints = ConstraintSet.restored(kernel, *state.pins)
    return sculptor
