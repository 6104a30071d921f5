"""Crash recovery: list the journals :mod:`gogreen_core.files.journal` leaves behind after an
unclean exit, and rebuild a document from one, bit for bit the state after its last complete
record (README, "Crash recovery")::

    journals = list_journals()                 # newest first; in_use: a running app writes it
    recovery = recover(journals[0].directory)  # locks it, replays it
    recovery.mesh, recovery.sculptor           # the mesh as it was, a sculptor to go on with

Recovery starts from the oldest checkpoint (or the journal's start) whose replay fits
:data:`RECOVERY_WORK`, so the recovered undo history is as deep as that allows; a checkpoint
whose later records undo past it is skipped for an older one. Damage is never fatal: every
complete record before it is kept and the notes say what was dropped.
"""

from __future__ import annotations

import collections
import contextlib
import os
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, cast

import numpy as np

from gogreen_core.files.journal_format import (
    JOURNAL_FILE,
    THUMBNAIL_FILE,
    JournalContents,
    JournalError,
    JournalLock,
    Record,
    checkpoint_files,
    lock_owner,
    read_journal,
    recovery_root,
    replay_work,
)
from gogreen_core.mesh.mesh_io import MeshData, load_mesh
from gogreen_core.sculpt.checkpoint import CheckpointError, SculptState, read_checkpoint
from gogreen_core.sculpt.operations import SETTINGS_CHANGES, Operation
from gogreen_core.sculpt.sculptor import Sculptor, restore_state
from gogreen_core.sculpt.session import SESSION_FORMAT, SESSION_VERSION, mesh_fingerprint, replay

__all__ = [
    "RECOVERY_WORK",
    "JournalContents",
    "JournalError",
    "JournalInfo",
    "Recovery",
    "discard",
    "find_journal",
    "journal_session",
    "list_journals",
    "read_journal",
    "recover",
]

#: Most replay work (:func:`~gogreen_core.files.journal.replay_work`) recovery replays when it can
#: choose: about 1 s here.
RECOVERY_WORK = 3e7
#: Names of the operations in summaries (singular, plural).
_KINDS = {
    "stroke": ("stroke", "strokes"),
    "constraint_add": ("pin edit", "pin edits"),
    "constraint_remove": ("pin edit", "pin edits"),
    "constraints_clear": ("pin edit", "pin edits"),
    "constraint_drag": ("pin drag", "pin drags"),
    **dict.fromkeys(SETTINGS_CHANGES, ("settings change", "settings changes")),
    "undo": ("undo", "undos"),
    "redo": ("redo", "redos"),
}


@dataclass
class JournalInfo:
    """A journal as the recovery dialog and ``gogreen recover --list`` show it."""

    directory: Path
    title: str
    document: str | None
    modified: float
    operations: int
    kinds: dict[str, int]
    vertices: int
    in_use: bool
    owner: dict[str, Any]
    notes: list[str]
    thumbnail: Path | None
    readable: bool = True

    @property
    def id(self) -> str:
        return self.directory.name

    def summary(self) -> str:
        """``"20 strokes, 2 pin edits, 1 undo"`` (or ``"no operations"``)."""
        counts: dict[str, int] = collections.Counter()
        names: dict[str, str] = {}
        for op, count in self.kinds.items():
            one, many = _KINDS.get(op, (op, op + "s"))
            counts[one] += count
            names[one] = many
        parts = [f"{c} {one if c == 1 else names[one]}" for one, c in counts.items()]
        return ", ".join(parts) or "no operations"

    def status(self) -> str:
        """Who holds it or what is wrong with it ("" when nothing)."""
        if self.in_use:
            who = self.owner
            process = f"process {who['pid']}" if "pid" in who else "another process"
            host = f" on {who['host']}" if who.get("host") else ""
            return f"in use by a running GoGreen Sculpt ({process}{host})"
        return "; ".join(self.notes)


def journal_info(directory: str | os.PathLike[str]) -> JournalInfo:
    """What :func:`list_journals` shows of one journal folder (never raises)."""
    directory = Path(directory)
    lock = None
    with contextlib.suppress(OSError):
        lock = JournalLock.acquire(directory)
    if lock is not None:
        lock.release()
    thumbnail = directory / THUMBNAIL_FILE
    picture = thumbnail if thumbnail.is_file() else None
    try:
        contents = read_journal(directory, validate=False)
    except JournalError as exc:
        mtime = directory.stat().st_mtime if directory.exists() else 0.0
        return JournalInfo(
            directory, directory.name, None, mtime, 0, {}, 0, lock is None,
            lock_owner(directory), [str(exc)], picture, readable=False,
        )  # fmt: skip
    ops = contents.operations
    return JournalInfo(
        directory,
        contents.title,
        contents.document,
        contents.modified,
        len(ops),
        dict(collections.Counter(op.get("op", "?") for op in ops)),
        contents.header["mesh"]["vertices"],
        lock is None,
        lock_owner(directory),
        contents.notes,
        picture,
    )


def list_journals(root: str | os.PathLike[str] | None = None) -> list[JournalInfo]:
    """The journals under ``root`` (:func:`~gogreen_core.files.journal.recovery_root`), last changed
    first, the ones running apps write included (``in_use``). Folders a crash left half-made
    are deleted."""
    root = Path(root) if root is not None else recovery_root()
    if not root.is_dir():
        return []
    infos = []
    for folder in root.iterdir():
        if not folder.is_dir():
            continue
        if folder.name.startswith(".new-"):  # a crash while a journal was being created
            with contextlib.suppress(OSError):
                lock = JournalLock.acquire(folder)
                if lock is not None and time.time() - folder.stat().st_mtime > 60:
                    lock.remove()
                elif lock is not None:
                    lock.release()
            continue
        if not folder.name.startswith("."):
            infos.append(journal_info(folder))
    return sorted(infos, key=lambda info: info.modified, reverse=True)


def find_journal(name: str, root: str | os.PathLike[str] | None = None) -> Path:
    """The journal folder called ``name`` (or the only one starting with it, or a path to
    one); :class:`JournalError` naming the candidates otherwise."""
    root = Path(root) if root is not None else recovery_root()
    if os.sep in name and (Path(name) / JOURNAL_FILE).is_file():
        return Path(name)
    if (root / name / JOURNAL_FILE).is_file():
        return root / name
    matches = sorted(p for p in root.glob(f"{name}*") if (p / JOURNAL_FILE).is_file())
    if len(matches) == 1:
        return matches[0]
    if not matches:
        raise JournalError(f"no journal {name!r} in {root} (`gogreen recover --list`)")
    raise JournalError(f"{name!r} names several journals: {', '.join(p.name for p in matches)}")


def discard(directory: str | os.PathLike[str]) -> None:
    """Delete a journal (not one a running app writes: :class:`JournalError`)."""
    _lock(Path(directory)).remove()


def _lock(directory: Path) -> JournalLock:
    try:
        lock = JournalLock.acquire(directory)
    except OSError as exc:
        raise JournalError(f"{directory.name}: cannot open ({exc.strerror})") from None
    if lock is None:
        raise JournalError(f"{directory.name}: {journal_info(directory).status()}")
    return lock


@dataclass
class Recovery:
    """A recovered journal (``contents``: its title, document, operations...): the document's
    ``mesh``, a ``sculptor`` that continues bit for bit (its undo history holds the ``replayed``
    records), ``start`` (0, or the checkpoint's record), ``notes`` on what was dropped, and the
    ``lock`` (held until :meth:`release`)."""

    contents: JournalContents
    mesh: MeshData
    sculptor: Sculptor
    records: int
    replayed: int
    start: int
    notes: list[str]
    lock: JournalLock | None
    seconds: float = 0.0

    def release(self) -> None:
        if self.lock is not None:
            self.lock.release()
            self.lock = None


def journal_session(contents: JournalContents) -> dict[str, Any]:
    """The journal's complete records as a session file (README, "Session files") starting
    from the journal's start mesh; pins the journal started with come first as
    ``constraint_add`` operations."""
    header = contents.header
    start = header["start"]
    pins = start.get("pins")
    adds = [{"op": "constraint_add", "point": p} for p in (pins or {}).get("points", [])]
    mesh = header["mesh"]
    return {
        "format": SESSION_FORMAT,
        "version": SESSION_VERSION,  # (an older journal's records upgraded as read)
        "mesh": {"vertices": mesh["vertices"], "faces": mesh["faces"], "sha256": mesh["sha256"]},
        "settings": start["settings"],
        "operations": adds + contents.operations,
    }


def _start_state(header: dict[str, Any], base: MeshData, mask: np.ndarray | None) -> SculptState:
    """The start state: the header's settings and pins, the base copy's arrays."""
    start = header["start"]
    arrays = {"vertices": base.vertices.copy()}  # (the faces: the base copy's, not a second)
    for key, value in (start.get("pins") or {}).items():
        arrays[key] = np.array(value, dtype=np.float64)
    if start.get("mask"):
        if mask is None or mask.shape != (len(base.vertices),):
            raise CheckpointError("the start's mask is missing from the copy of the start mesh")
        arrays["mask"] = np.array(mask, dtype=np.float64)
    return SculptState.from_header(start, arrays)


def _load_base(
    contents: JournalContents, notes: list[str]
) -> tuple[MeshData | None, bool, np.ndarray | None]:
    """The start mesh, whether its vertices are the start's (False: only the document's faces,
    for a checkpoint), and the start's mask (None if unmasked or lost)."""
    header = contents.header
    mesh = header["mesh"]
    name = mesh["base"]
    document = contents.document
    try:
        with np.load(contents.directory / name, allow_pickle=False) as arrays:
            data = {key: arrays[key] for key in arrays.files}
        base = MeshData(
            vertices=data["vertices"],
            faces=data["faces"].astype(np.int64),
            uv=data.get("uv"),
            uv_faces=None if "uv_faces" not in data else data["uv_faces"].astype(np.int64),
            source=document,
        )
        problem = _base_mismatch(base, mesh)
    except FileNotFoundError:
        problem = "is missing"
    except Exception as exc:  # a zip cut short, a bad CRC, missing arrays
        problem = f"is unreadable ({exc})"
    if problem is None:
        return base, True, data.get("mask")
    note = f"the copy of the start mesh ({name}) {problem}"
    if document:
        try:
            mesh_file = load_mesh(document)
        except (ValueError, OSError) as exc:
            notes.append(f"{note}, and the document's file cannot be read ({exc})")
            return None, False, None
        if _base_mismatch(mesh_file, mesh) is None:
            notes.append(f"{note}: the document's file {document} has the same mesh and was used")
            return mesh_file, True, None
        if len(mesh_file.vertices) == mesh["vertices"] and len(mesh_file.faces) == mesh["faces"]:
            notes.append(
                f"{note}, and {document} changed since: only a checkpoint can be recovered, on "
                "the file's faces"
            )
            return mesh_file, False, None
        notes.append(f"{note}, and {document} is another mesh now")
        return None, False, None
    notes.append(note)
    return None, False, None


def _base_mismatch(base: MeshData, mesh: dict[str, Any]) -> str | None:
    if len(base.vertices) != mesh["vertices"] or len(base.faces) != mesh["faces"]:
        return (
            f"has {len(base.vertices)} vertices and {len(base.faces)} faces, not "
            f"{mesh['vertices']} and {mesh['faces']}"
        )
    if mesh_fingerprint(base.vertices) != mesh["sha256"]:
        return "has other vertices (hash mismatch)"
    return None


class _Diverged(Exception):
    """A replay from a checkpoint undid something from before it."""


def _replay(
    sculptor: Sculptor,
    records: list[Record],
    done: int,
    progress: Callable[[int, int], None] | None,
) -> tuple[int, str | None]:
    """Apply ``records`` to ``sculptor`` (whose ``history.done`` stands for ``done``): how many
    were applied and the error that stopped it, or :class:`_Diverged`."""
    offset = done - sculptor.history.done
    total = sum(r.steps for r in records)
    plan: list[Record] = []  # of a run of ``replace`` records (one operation) only the last
    for record in records:
        if record.kind == "replace" and plan and plan[-1].kind == "replace":
            plan[-1] = record
        else:
            plan.append(record)
    steps = applied = 0
    for record in plan:
        op = cast(Operation, record.op)  # (the records were read with validation)
        if record.kind == "replace" and hasattr(op, "continued"):
            op = replace(cast(Any, op), continued=True)  # merges into the last step, as it did
        try:
            replay(sculptor, [op])  # one record at a time: a failure undoes that record alone
        except (ValueError, RuntimeError) as exc:
            return applied, f"record {record.seq} ({record.data.get('op')}) failed: {exc}"
        if sculptor.history.done + offset != record.d:
            raise _Diverged(record.seq)
        applied = record.seq - records[0].seq + 1
        steps += record.steps
        if progress:
            progress(steps, total)
    return applied, None


def recover(
    directory: str | os.PathLike[str],
    *,
    budget: float = RECOVERY_WORK,
    progress: Callable[[int, int], None] | None = None,
) -> Recovery:
    """Rebuild the document a journal was recording, locked by the returned :class:`Recovery`.

    ``budget``: most replay work (:func:`~gogreen_core.files.journal.replay_work`) when a
    checkpoint allows less (0: the newest usable checkpoint, ``inf``: the start).
    ``progress(done, total)`` in mouse events. :class:`JournalError` when nothing can be
    recovered or a running app holds it.
    """
    began = time.perf_counter()
    directory = Path(directory)
    held = _lock(directory)
    try:
        contents = read_journal(directory)
        notes = list(contents.notes)
        base, exact, mask = _load_base(contents, notes)
        if base is None:
            raise JournalError(
                f"{directory.name}: nothing to rebuild the mesh from ({notes[-1]}); "
                "`gogreen recover ID --session OUT.json` still writes its operations"
            )
        records = contents.records
        vertices = contents.header["mesh"]["vertices"]
        cost = np.cumsum(
            [0] + [replay_work(str(r.data.get("op")), r.steps, vertices) for r in reversed(records)]
        )[::-1]
        starts: list[tuple[int, Path | None]] = [(0, None)] if exact else []
        starts += [c for c in checkpoint_files(directory)[::-1] if 0 < c[0] <= len(records)]
        fits = sorted(s for s in starts if cost[s[0]] <= budget)
        order = fits + sorted((s for s in starts if cost[s[0]] > budget), reverse=True)
        best = None
        for seq, path in order:
            try:
                state, done = _state_at(contents, base, mask, seq, path)
            except CheckpointError as exc:
                notes.append(f"checkpoint after record {seq} not used: {exc}")
                continue
            sculptor = restore_state(state, base.faces, base.uv, base.uv_faces)
            try:
                applied, error = _replay(sculptor, records[seq:], done, progress)
            except _Diverged:
                continue  # undoes past this checkpoint: an older start replays it right
            result = (seq + applied, seq, sculptor, applied, error)
            if best is None or result[0] > best[0]:
                best = result
            if error is None:
                break
        if best is None:
            raise JournalError(f"{directory.name}: no usable start ({'; '.join(notes)})")
        kept, seq, sculptor, replayed, error = best
        if error is not None:
            rest = len(records) - kept - 1
            what = f"it and the {rest} after it were" if rest else "it was"
            notes.append(f"{error}: {what} dropped")
            contents.records = records[:kept]
        now = sculptor.mesh  # a subdivision replayed: its faces and UVs
        mesh = MeshData(now.vertices, now.faces, now.uv, now.uv_faces, source=contents.document)
        return Recovery(
            contents, mesh, sculptor, kept, replayed, seq, notes, held,
            time.perf_counter() - began,
        )  # fmt: skip
    except BaseException:
        held.release()
        raise


def _state_at(
    contents: JournalContents,
    base: MeshData,
    mask: np.ndarray | None,
    seq: int,
    path: Path | None,
) -> tuple[SculptState, int]:
    """The state to replay from (the start or a checkpoint) and its undo steps done."""
    header = contents.header
    if path is None:
        return _start_state(header, base, mask), int(header["start"].get("done", 0))
    state, meta = read_checkpoint(path)
    if meta.get("token") != header.get("token") or meta.get("seq") != seq:
        raise CheckpointError(f"{path.name}: belongs to an older journal in this folder")
    if state.faces is None and len(state.vertices) != header["mesh"]["vertices"]:
        raise CheckpointError(f"{path.name}: has {len(state.vertices)} vertices")
    if state.faces is not None and state.faces.size and state.faces.max() >= len(state.vertices):
        raise CheckpointError(f"{path.name}: its faces name vertices it does not have")
    return state, int(meta.get("done", 0))
