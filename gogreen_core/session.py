"""Session files: the log of a sculptor's operations, their schema, and replay.

A session (README, "Session files") is ``{"format": "gogreen-session", "version": 4, "mesh":
{vertices, faces, sha256}, "settings": {...}, "operations": [...]}``. :func:`parse_session`
checks all of it before anything is applied (every field's type and range; errors name the field,
e.g. ``operations[3].events[0].delta``), :func:`load_session` reads a file, and :func:`replay`
(:meth:`Sculptor.replay`) applies the typed operations through the sculptor's public methods,
which record them again in its own log, so replaying a session records the same session.

Older files still replay as recorded, bit for bit: every version replays with the kernels'
evaluation it was recorded with (:data:`VERSION_EVALUATIONS`: 3 for version 4, 2 for version 3,
1 before); in version 1 files (written before settings changes were undo steps) material,
falloff and constraint-radius changes are not undo steps; in version 1 and 2 files the
``wrinkle`` brush is the one of that time (``wrinkle_legacy`` now; its weights are the
settings' ``degree_weights``) and a stroke that gives no influence had 4 ε.
"""

from __future__ import annotations

import dataclasses
import hashlib
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from gogreen_core.engine_settings import EngineSettings
from gogreen_core.operations import (
    ConstraintAdd,
    ConstraintDrag,
    ConstraintRadius,
    ConstraintRemove,
    ConstraintsClear,
    DynamicTopology,
    FalloffChange,
    MaskClear,
    MaskInvert,
    MaterialChange,
    Operation,
    Redo,
    Remesh,
    Stroke,
    Subdivide,
    Undo,
    operation_from_dict,
)
from gogreen_core.schema import parse_file
from gogreen_core.session_log import SessionLog
from gogreen_core.validation import (
    ParameterError,
    check_choice,
    check_integer,
    check_list,
    check_object,
    check_string,
    field,
    prefixed,
)

if TYPE_CHECKING:
    from gogreen_core.sculptor import Sculptor

__all__ = [
    "RENAMED_BEFORE_3",
    "SESSION_FORMAT",
    "SESSION_VERSION",
    "VERSION_EVALUATIONS",
    "Session",
    "SessionLog",
    "load_session",
    "mesh_fingerprint",
    "parse_session",
    "replay",
    "version_of",
]

SESSION_FORMAT = "gogreen-session"
#: 4: computed with the kernels' evaluation 3 (``GreenKernel(evaluation=3)``: the strokes'
#: fields partly in single precision); 3: evaluation 2, ``wrinkle`` is the folding wrinkle brush,
#: brushes have their own degree weights (``brush_weights``) and an automatic influence;
#: 2: settings changes are undo steps (``continued`` joins one to the previous), evaluation 1;
#: 1: they were not. Every version replays with its evaluation, bit for bit.
SESSION_VERSION = 4
#: The kernels' evaluation the sessions of each version were recorded, and replay, with.
VERSION_EVALUATIONS = {1: 1, 2: 1, 3: 2, 4: 3}
#: The brush influence (in ε) of a session before version 3 that does not give one.
OLD_DEFAULT_INFLUENCE = 4.0
#: The brush kinds a session before version 3 names differently: what they are now.
RENAMED_BEFORE_3 = {"wrinkle": "wrinkle_legacy"}
#: Most operations one session file may hold.
MAX_OPERATIONS = 10_000_000


def version_of(evaluation: int, settings_undoable: bool = True) -> int:
    """The session version that records what a sculptor with the kernels' ``evaluation`` does
    (1 where settings changes are no undo steps, as in the version-1 file it replays)."""
    if not settings_undoable:
        return 1
    return max(v for v, e in VERSION_EVALUATIONS.items() if e == evaluation)


def mesh_fingerprint(vertices: np.ndarray) -> str:
    """SHA-256 of the float64 vertex array: tells whether a session replays on its own mesh."""
    return hashlib.sha256(np.ascontiguousarray(vertices, dtype=np.float64).tobytes()).hexdigest()


@dataclass(frozen=True)
class Session:
    """A checked session file: mesh sizes and fingerprint, initial settings, typed operations,
    format version."""

    vertices: int
    faces: int
    sha256: str | None
    settings: EngineSettings
    operations: tuple[Operation, ...]
    version: int = SESSION_VERSION

    @property
    def steps(self) -> int:
        """Progress units of a replay (mouse events, one per other operation)."""
        return sum(op.steps for op in self.operations)


def parse_session(data: object) -> Session:
    """The schema of a session file: every field checked before anything is applied;
    :class:`ParameterError` naming the first bad field."""
    data = check_object("", data, required=("format", "version", "mesh", "settings", "operations"))
    check_choice("format", data["format"], (SESSION_FORMAT,))
    version = check_integer("version", data["version"], low=1, high=SESSION_VERSION)
    mesh = check_object("mesh", data["mesh"], required=("vertices", "faces"), optional=("sha256",))
    vertices = check_integer("mesh.vertices", mesh["vertices"], low=1)
    faces = check_integer("mesh.faces", mesh["faces"], low=0)
    sha = mesh.get("sha256")
    if sha is not None:
        sha = check_string("mesh.sha256", sha, max_length=64)
    settings = EngineSettings.from_dict(data["settings"], "settings")
    operations = check_list("operations", data["operations"], max_length=MAX_OPERATIONS)
    if version < 3:  # the brush influence was 4 ε when a file did not say
        operations = [_old_influence(op) for op in operations]
    ops = tuple(operation_from_dict(op, field("operations", i)) for i, op in enumerate(operations))
    if version < 3:
        ops = tuple(_renamed(op) for op in ops)
    return Session(vertices, faces, sha, settings, ops, version)


def _old_influence(op: object) -> object:
    """A stroke record of a session before version 3 with its brush's influence made explicit:
    4 ε (:data:`OLD_DEFAULT_INFLUENCE`), the default then (now "auto")."""
    if not (isinstance(op, dict) and isinstance(op.get("brush"), dict)):
        return op
    if "influence" in op["brush"]:
        return op
    return {**op, "brush": {**op["brush"], "influence": OLD_DEFAULT_INFLUENCE}}


def _renamed(op: Operation) -> Operation:
    """``op`` with the brush kind its name meant before version 3 (:data:`RENAMED_BEFORE_3`)."""
    if isinstance(op, Stroke) and op.brush.kind in RENAMED_BEFORE_3:
        return dataclasses.replace(
            op, brush=dataclasses.replace(op.brush, kind=RENAMED_BEFORE_3[op.brush.kind])
        )
    return op


def load_session(path: str | os.PathLike[str]) -> Session:
    """Read and check a session file; ``ValueError`` (a :class:`ParameterError` for a bad
    field) whose message starts with the file's name."""
    return parse_file(path, parse_session, "session file")


# -- replay ------------------------------------------------------------------------------------
Step = Callable[[], None]


def _stroke(sculptor: Sculptor, op: Stroke, step: Step) -> None:
    sculptor.begin_stroke(op.brush)
    try:
        for number, event in enumerate(op.events):
            with prefixed(f"events[{number}]"):
                sculptor.stroke_event(event)
            step()
    except Exception:
        sculptor.cancel_stroke()
        raise
    sculptor.end_stroke()
    if not op.events:
        step()


def _falloff(sculptor: Sculptor, op: FalloffChange) -> None:
    sculptor.change_settings(
        falloff=op.falloff,
        l_max=op.l_max,
        degree_weights=op.degree_weights,
        brush_weights=op.brush_weights,
        continued=op.continued,
        replaying=True,
    )


#: How each record is done: through the sculptor's public methods (a logged settings change is
#: always replayed, as the drag it stands for was a step).
_ACTIONS: dict[type[Operation], Callable[[Sculptor, Any], object]] = {
    MaterialChange: lambda s, op: s.change_settings(
        material=op.material, continued=op.continued, replaying=True
    ),
    FalloffChange: _falloff,
    ConstraintRadius: lambda s, op: s.change_settings(
        constraint_radius=op.radius, continued=op.continued, replaying=True
    ),
    ConstraintAdd: lambda s, op: s.add_constraint(op.point),
    ConstraintRemove: lambda s, op: s.remove_constraint(op.index),
    ConstraintsClear: lambda s, op: s.clear_constraints(),
    ConstraintDrag: lambda s, op: s.drag_constraint(op.index, op.delta, op.continued),
    MaskInvert: lambda s, op: s.mask.invert(),
    MaskClear: lambda s, op: s.mask.clear(),
    Subdivide: lambda s, op: s.subdivide(op.unmasked_only),
    DynamicTopology: lambda s, op: s.change_settings(
        dynamic_topology=op.enabled,
        detail_size=op.detail_size,
        continued=op.continued,
        replaying=True,
    ),
    Remesh: lambda s, op: s.remesher.remesh(op.detail_size, op.unmasked_only, op.iterations),
    Undo: lambda s, op: s.undo(),
    Redo: lambda s, op: s.redo(),
}


def replay(
    sculptor: Sculptor,
    operations: Sequence[dict[str, Any]] | Sequence[Operation] | Session,
    progress: Callable[[int, int], None] | None = None,
) -> None:
    """Apply logged operations to ``sculptor`` in order (the result is bit for bit the recorded
    one on the same machine). ``progress(done, total)`` is called after each mouse event and
    each other operation.

    All of them are checked before any is applied (ParameterError naming the field, e.g.
    ``operations[3].events[0].delta``), and a replay that fails part-way is rolled back
    (:meth:`Sculptor.all_or_nothing`): the mesh, settings, pins, history and log are as before.
    """
    if isinstance(operations, Session):
        ops = list(operations.operations)
    else:
        ops = [
            op if isinstance(op, Operation) else operation_from_dict(op, f"operations[{i}]")
            for i, op in enumerate(operations)
        ]
    total = sum(op.steps for op in ops)
    done = 0

    def step() -> None:
        nonlocal done
        done += 1
        if progress:
            progress(done, total)

    number = 0
    try:
        with sculptor.all_or_nothing():
            for number, op in enumerate(ops):
                with prefixed(f"operations[{number}]"):
                    if isinstance(op, Stroke):
                        _stroke(sculptor, op, step)
                    else:
                        _ACTIONS[type(op)](sculptor, op)
                        step()
    except ParameterError:
        raise
    except (ValueError, RuntimeError) as exc:
        raise ValueError(f"operations[{number}] ({ops[number].name}): {exc}") from None
