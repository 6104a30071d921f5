"""Session files (README, "Session files"): their schema, upgrades and replay.

:func:`parse_session` checks all of a session before anything is applied (errors name the
field, e.g. ``operations[3].events[0].delta``); :func:`replay` applies the typed operations
through the sculptor's public methods, which log them again. A file of an older version is
upgraded as it is read (:func:`upgrade_session`, one function a version step) and replayed with
today's arithmetic (within 1e-4 of its motion), or refused naming the operation that cannot be.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from gogreen_core.sculpt.brushes.table import REPLAY_KINDS
from gogreen_core.sculpt.engine_settings import EngineSettings
from gogreen_core.sculpt.operations import (
    SETTINGS_CHANGES,
    ConstraintAdd,
    ConstraintDrag,
    ConstraintRemove,
    ConstraintsClear,
    MaskClear,
    MaskInvert,
    Operation,
    Redo,
    Remesh,
    Stroke,
    Subdivide,
    Undo,
    operation_from_dict,
)
from gogreen_core.sculpt.schema import parse_file
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
    from gogreen_core.sculpt.sculptor import Sculptor

__all__ = [
    "SESSION_FORMAT",
    "SESSION_VERSION",
    "Session",
    "load_session",
    "mesh_fingerprint",
    "parse_session",
    "replay",
    "upgrade_session",
]

SESSION_FORMAT = "gogreen-session"
#: What each version changed: see its upgrade function below.
SESSION_VERSION = 7
#: The brush influence (in ε) of a session before version 3 that does not give one.
OLD_DEFAULT_INFLUENCE = 4.0
#: Most operations one session file may hold.
MAX_OPERATIONS = 10_000_000


def mesh_fingerprint(vertices: np.ndarray) -> str:
    """SHA-256 of the float64 vertex array: tells whether a session replays on its own mesh."""
    array = np.ascontiguousarray(vertices, dtype=np.float64)
    return hashlib.sha256(memoryview(cast(Any, array)).cast("B")).hexdigest()


@dataclass(frozen=True)
class Session:
    """A checked session file."""

    vertices: int
    faces: int
    sha256: str | None
    settings: EngineSettings
    operations: tuple[Operation, ...]
    version: int = SESSION_VERSION


def parse_session(data: object) -> Session:
    """The checked :class:`Session` of a decoded session file (an older version's upgraded
    first); :class:`ParameterError` naming the first bad field."""
    data = check_object("", data, required=("format", "version", "mesh", "settings", "operations"))
    check_choice("format", data["format"], (SESSION_FORMAT,))
    version = check_integer("version", data["version"], low=1, high=SESSION_VERSION)
    data = upgrade_session(data)
    mesh = check_object("mesh", data["mesh"], required=("vertices", "faces"), optional=("sha256",))
    vertices = check_integer("mesh.vertices", mesh["vertices"], low=1)
    faces = check_integer("mesh.faces", mesh["faces"], low=0)
    sha = mesh.get("sha256")
    if sha is not None:
        sha = check_string("mesh.sha256", sha, max_length=64)
    settings = EngineSettings.from_dict(data["settings"], "settings")
    operations = check_list("operations", data["operations"], max_length=MAX_OPERATIONS)
    ops = tuple(operation_from_dict(op, field("operations", i)) for i, op in enumerate(operations))
    return Session(vertices, faces, sha, settings, ops, version)


# -- upgrades: each takes a session (a checked object whose version is the step's first) and
# returns it in the next version, leaving whatever it does not recognize for the schema to name.
def _operations(data: dict[str, Any]) -> list[Any]:
    operations = data.get("operations")
    return operations if isinstance(operations, list) else []


#: The operations each version 1 file's undo steps were (settings changes were none).
_STEPS_V1 = frozenset({"stroke", "constraint_drag"})
#: Settings changes, undo steps from version 2 on.
_SETTINGS_OPS = frozenset({"material", "falloff", "constraint_radius"})
#: Pins: undo steps from version 2 on.
_PIN_OPS = frozenset({"constraint_add", "constraint_remove", "constraints_clear"})


#: What version-1 operations meant then and do not now: an affine brush's ``amount`` (the
#: velocity gradient then, the log strain or angle now), a pin drag (it moved every vertex).
_CHANGED_V1 = {
    "scale": "the scale brush's amount measured another strain",
    "twist": "the twist brush's amount measured another angle",
    "pinch": "the pinch brush's amount measured another strain",
    "constraint_drag": "a pin drag moved every vertex (pins hold only nearby ones now)",
}


def _upgrade_v1_to_v2(data: dict[str, Any]) -> dict[str, Any]:
    """Settings changes and pin edits became undo steps: an undo or redo that would now take
    another step is refused, as is what meant something else then (:data:`_CHANGED_V1`)."""
    done: list[bool] = []  # per undo step of today: was it one in version 1
    undone: list[bool] = []
    for number, op in enumerate(_operations(data)):
        kind = op.get("op") if isinstance(op, dict) else None
        brush = op.get("brush") if isinstance(op, dict) else None
        changed = brush.get("kind") if kind == "stroke" and isinstance(brush, dict) else kind
        if isinstance(changed, str) and changed in _CHANGED_V1:
            raise ParameterError(
                field("operations", number),
                f"operations[{number}] ({changed}) of this version-1 session cannot be "
                f"replayed: {_CHANGED_V1[changed]} when it was recorded",
            )
        if kind in ("undo", "redo"):
            source, target = (done, undone) if kind == "undo" else (undone, done)
            if source and not source[-1]:
                raise ParameterError(
                    field("operations", number),
                    f"operations[{number}] ({kind}) of this version-1 session would {kind} a "
                    "settings change or a pin edit today (they are undo steps since version 2), "
                    "not what it did when it was recorded: it cannot be replayed",
                )
            if source:
                target.append(source.pop())
            continue
        if kind == "constraint_drag" and op.get("continued") and done and done[-1]:
            continue  # the same step
        if kind in _STEPS_V1 or kind in _SETTINGS_OPS or kind in _PIN_OPS:
            done.append(kind in _STEPS_V1)
            undone.clear()
    return {**data, "version": 2}


def _upgrade_v2_to_v3(data: dict[str, Any]) -> dict[str, Any]:
    """Brush weights, an automatic influence (it was 4 ε), and another ``wrinkle`` brush (a
    stroke of the old one is refused)."""
    operations = []
    for number, op in enumerate(_operations(data)):
        brush = op.get("brush") if isinstance(op, dict) else None
        if isinstance(brush, dict):
            if brush.get("kind") == "wrinkle":
                raise ParameterError(
                    field("operations", number),
                    f"operations[{number}] is a stroke of the wrinkle brush of version-"
                    f"{data['version']} sessions, which no longer exists (today's wrinkle "
                    "brush folds the surface instead): this session cannot be replayed",
                )
            if "influence" not in brush:
                op = {**op, "brush": {**brush, "influence": OLD_DEFAULT_INFLUENCE}}
        operations.append(op)
    return {**data, "version": 3, "operations": operations}


def _upgrade_v4_to_v5(data: dict[str, Any]) -> dict[str, Any]:
    """``degree_weights`` (of the wrinkle brush of versions 1-2 only) went."""

    def without(value: object) -> object:
        if isinstance(value, dict):
            return {k: v for k, v in value.items() if k != "degree_weights"}
        return value

    operations = [
        without(op) if isinstance(op, dict) and op.get("op") == "falloff" else op
        for op in _operations(data)
    ]
    return {
        **data,
        "version": 5,
        "settings": without(data.get("settings")),
        "operations": operations,
    }


def _upgrade_v5_to_v6(data: dict[str, Any]) -> dict[str, Any]:
    """The affine brushes became local: their older strokes are renamed to the replay-only
    brushes that do what they did (:data:`REPLAY_KINDS`)."""
    operations = []
    for op in _operations(data):
        brush = op.get("brush") if isinstance(op, dict) else None
        if isinstance(brush, dict) and brush.get("kind") in REPLAY_KINDS:
            op = {**op, "brush": {**brush, "kind": REPLAY_KINDS[brush["kind"]]}}
        operations.append(op)
    return {**data, "version": 6, "operations": operations}


def _renumbered(data: dict[str, Any]) -> dict[str, Any]:
    """A version step that changed nothing an older file holds."""
    return {**data, "version": data["version"] + 1}


#: The upgrade from each version to the next.
_UPGRADES: dict[int, Callable[[dict[str, Any]], dict[str, Any]]] = {
    1: _upgrade_v1_to_v2,
    2: _upgrade_v2_to_v3,
    3: _renumbered,  # the strokes' fields partly in single precision (within 1e-4 of the motion)
    4: _upgrade_v4_to_v5,
    5: _upgrade_v5_to_v6,
    6: _renumbered,  # a remesh may give "detail_size": null (each vertex's own edge length)
}


def upgrade_session(data: dict[str, Any]) -> dict[str, Any]:
    """A session object of version 1 … :data:`SESSION_VERSION` as one of today's (reading only
    its ``settings`` and ``operations``); :class:`ParameterError` naming an operation that cannot
    be replayed today."""
    version = data["version"]
    while version < SESSION_VERSION:
        data = _UPGRADES[version](data)
        version = data["version"]
    return data


def load_session(path: str | os.PathLike[str]) -> Session:
    """Read and check a session file (:func:`~gogreen_core.sculpt.schema.parse_file`)."""
    return parse_file(path, parse_session, "session file")


# -- replay ------------------------------------------------------------------------------------
#: How each record is done: through the sculptor's public methods (a logged settings change is
#: always replayed, as the drag it stands for was a step).
_ACTIONS: dict[type[Operation], Callable[[Sculptor, Any], object]] = {
    **dict.fromkeys(
        SETTINGS_CHANGES.values(),
        lambda s, op: s.change_settings(continued=op.continued, replaying=True, **op.values),
    ),
    ConstraintAdd: lambda s, op: s.add_constraint(op.point),
    ConstraintRemove: lambda s, op: s.remove_constraint(op.index),
    ConstraintsClear: lambda s, op: s.clear_constraints(),
    ConstraintDrag: lambda s, op: s.drag_constraint(op.index, op.delta, op.continued),
    MaskInvert: lambda s, op: s.mask.invert(),
    MaskClear: lambda s, op: s.mask.clear(),
    Subdivide: lambda s, op: s.subdivide(op.unmasked_only),
    Remesh: lambda s, op: s.remesher.remesh(op.detail_size, op.unmasked_only, op.iterations),
    Undo: lambda s, op: s.undo(),
    Redo: lambda s, op: s.redo(),
}


def replay(
    sculptor: Sculptor,
    operations: Sequence[dict[str, Any]] | Sequence[Operation] | Session,
    progress: Callable[[int, int], None] | None = None,
) -> None:
    """Apply logged operations to ``sculptor`` in order, bit for bit as recorded on the same
    machine; all checked first, and rolled back as a whole if one fails
    (:meth:`Sculptor.all_or_nothing`). ``progress(done, total)`` is called after each mouse
    event and each other operation."""
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
                        sculptor.apply_brush(op.brush, op.events, step)
                    else:
                        _ACTIONS[type(op)](sculptor, op)
                        step()
    except ParameterError:
        raise
    except (ValueError, RuntimeError) as exc:
        raise ValueError(f"operations[{number}] ({ops[number].name}): {exc}") from None
