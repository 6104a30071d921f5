"""The recovery journal: every completed operation of a sculptor, on disk before the next one.

While a document is open, :class:`Journal` listens to its sculptor's operation log
(:meth:`Sculptor.subscribe`) and appends each completed operation (a stroke, a pin edit, a
settings change, an undo, a redo) to a file, so that a crash loses nothing that completed:
``gogreen_core.files.recovery`` rebuilds the mesh bit for bit from it.

Where: one folder per open document under :func:`recovery_root`
(``$XDG_STATE_HOME/gogreen-sculpt/recovery``, ``~/.local/state/gogreen-sculpt/recovery`` when
the variable is unset), private to the user (mode 0700)::

    <id>/lock                 an flock held by the running app that writes the journal
    <id>/journal.jsonl        a header, then one record per operation
    <id>/base-<sha256>.npz    the mesh the journal starts from (vertices, faces, uv): a copy,
                              named by the SHA-256 of its vertices, since any file can change
    <id>/checkpoint-<k>.bin   the state after record k (:mod:`gogreen_core.sculpt.checkpoint`)
    <id>/thumbnail.png        a small picture of the model (written by the app)

Records: each line is ``<CRC-32 of the JSON, 8 hex digits> <JSON>\\n``, so a line cut short by
a crash (or a full disk) is detected and dropped, with everything before it kept. The header
(line 1) holds the format and version, the document's file and title, the mesh's sizes and
hash, and the start state (settings, pins, model size and mirror origin). Each record is
``{"seq": k, "kind": "append" | "replace", "n": operations, "t": unix time, "d": undo steps
done, "op": {...}}``: ``op`` is the operation's session form (README, "Session files");
``replace`` stands for a continued slider or curve drag that the session log merges into its
last operation; ``d`` (:attr:`History.done`) lets recovery check that a replay from a checkpoint
undoes exactly what the session undid.

When: the record is written (one ``write``) before the operation's call returns, so a killed
process loses nothing that completed; the mouse events of a stroke are serialized as they come,
so ending a stroke only joins them. ``fsync`` (against a power cut) follows at once on the
journal's worker thread, which also writes the base copy and the checkpoints: the full vertex
array, taken when enough brush work has piled up since the last one (:attr:`checkpoint_due`) so
that recovery replays little. The app takes them when it is idle (the copy of the vertices is
the one cost on its thread); scripts let the journal take them after each operation.

Never in the way: no error of the journal reaches the sculptor. A journal that cannot be
written (a full disk, a read-only folder) stops, keeps what it wrote, and says so once through
:meth:`take_problems`; a failed checkpoint only makes recovery replay longer.
"""

from __future__ import annotations

import collections
import contextlib
import json
import os
import secrets
import threading
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any, cast

import numpy as np

from gogreen_core.files.journal_format import (
    JOURNAL_FILE,
    JOURNAL_FORMAT,
    JOURNAL_VERSION,
    SETTINGS_WORK,
    THUMBNAIL_FILE,
    JournalLock,
    frame,
    new_folder,
    owner,
    recovery_root,
    replay_work,
    state_home,
    vertex_hash,
    write_all,
)
from gogreen_core.mesh.mesh_io import MeshData, write_bytes_atomic
from gogreen_core.mesh.mesh_io.atomic import atomic_write
from gogreen_core.sculpt.brushes.brush import BrushEvent
from gogreen_core.sculpt.checkpoint import SculptState, write_checkpoint
from gogreen_core.sculpt.operations import Operation, Stroke
from gogreen_core.sculpt.sculptor import Sculptor, capture_state

__all__ = [
    "CHECKPOINT_WORK",
    "JOURNAL_FILE",
    "JOURNAL_FORMAT",
    "JOURNAL_VERSION",
    "SETTINGS_WORK",
    "THUMBNAIL_FILE",
    "Journal",
    "JournalLock",
    "frame",
    "recovery_root",
    "replay_work",
    "state_home",
    "write_all",
]

#: Replay work (see :func:`replay_work`) after which a checkpoint is due: about 0.5 s of
#: replay on this project's 2-core test machine (a 1M-vertex event: 25 to 80 ms).
CHECKPOINT_WORK = 1.5e7
#: Checkpoints kept per journal (recovery may start from an older one for a deeper undo).
KEEP_CHECKPOINTS = 3
_COMPACT = (",", ":")


def operation_json(op: Operation, events: list[tuple[object, str]] | None = None) -> str:
    """The operation's session form as compact JSON; a stroke's events are taken from
    ``events`` ((event, JSON) pairs serialized while the stroke ran) when they are its own."""
    if isinstance(op, Stroke) and events is not None and op.events:
        mine = events[-len(op.events) :]
        if len(mine) == len(op.events) and all(
            a is b for a, (b, _) in zip(op.events, mine, strict=True)
        ):
            head = json.dumps(replace(op, events=()).to_dict(), separators=_COMPACT)
            joined = ",".join(text for _, text in mine)
            if head.endswith('"events":[]}'):
                return f"{head[: -len('[]}')]}[{joined}]}}"
    return json.dumps(op.to_dict(), separators=_COMPACT)


class Journal:
    """The recovery journal of one open document (see the module docstring).

    Parameters
    ----------
    sculptor : Sculptor
        Whose operations are journaled, from its current state on.
    mesh : MeshData
        The document's mesh as loaded (not used for the base copy: the journal starts from
        ``sculptor``'s vertices, faces, texture coordinates and mask, which a subdivision
        changes).
    document : str, optional
        The document's file (shown by recovery, tried when the base copy is missing).
    title : str, optional
        What recovery calls the document (the file's name by default).
    root : path, optional
        The folder of the journals (:func:`recovery_root` by default).
    auto_checkpoint : bool
        Take due checkpoints right after an operation (scripts); the app passes False and
        calls :meth:`checkpoint` when idle.
    checkpoint_work : float
        Replay work (:func:`replay_work`) after which a checkpoint is due.
    replaces : JournalLock, optional
        The lock of a journal this one continues (a recovered document's): that folder is
        removed once this journal's base copy is on disk.
    wake : callable, optional
        Called (on the sculptor's thread) after each record: the app restarts its idle timer.

    Never raises for a disk problem: see :meth:`take_problems`.
    """

    def __init__(
        self,
        sculptor: Sculptor,
        mesh: MeshData,
        *,
        document: str | None = None,
        title: str | None = None,
        root: str | os.PathLike[str] | None = None,
        auto_checkpoint: bool = True,
        checkpoint_work: float = CHECKPOINT_WORK,
        replaces: JournalLock | None = None,
        wake: Callable[[], None] | None = None,
    ) -> None:
        self.sculptor = sculptor
        self.mesh = mesh
        #: The face array of the journal's start: checkpoints hold faces only when another.
        self._base_faces: np.ndarray | None = None
        self.document = None if document is None else os.path.abspath(document)
        self.title = title or (Path(document).name if document else "untitled")
        self.root = Path(root) if root is not None else recovery_root()
        self.auto_checkpoint = auto_checkpoint
        self.checkpoint_work = float(checkpoint_work)
        self.wake = wake
        #: The journal's folder (None when it could not be made).
        self.directory: Path | None = None
        #: Records written, and of those the ones known to be on disk (fsynced).
        self.records = 0
        self.durable = 0
        self._lock: JournalLock | None = None
        self._fd: int | None = None
        self._token = ""
        self._stopped = True  # no records are written (not started, failed, or closed)
        self._pending: list[tuple[object, str]] = []  # events of the stroke in progress
        self._work = 0.0
        self._problems: list[str] = []
        self._reported = 0
        self._lock_problems = threading.Lock()
        self._tasks: collections.deque[tuple[Any, ...]] = collections.deque()
        self._busy = False
        self._cond = threading.Condition()
        self._thread = threading.Thread(target=self._run, name="gogreen-journal", daemon=True)
        self._thread.start()
        self._unsubscribe = sculptor.subscribe(self._on_log)
        self._retire = replaces
        self._base_written = False
        self._start()

    # -- state -------------------------------------------------------------------------------
    @property
    def id(self) -> str | None:
        """The journal's name (its folder's), or None."""
        return None if self.directory is None else self.directory.name

    @property
    def active(self) -> bool:
        """True while records are being written."""
        return not self._stopped

    @property
    def checkpoint_due(self) -> bool:
        """Enough brush work since the last checkpoint, and no stroke in progress."""
        return self.active and self._work >= self.checkpoint_work and not self.sculptor.in_stroke

    def take_problems(self) -> list[str]:
        """The problems not yet reported (each once): a journal that stopped, a checkpoint or
        base copy that could not be written. Thread-safe."""
        with self._lock_problems:
            new = self._problems[self._reported :]
            self._reported = len(self._problems)
        return new

    def _problem(self, text: str) -> None:
        with self._lock_problems:
            if text not in self._problems:
                self._problems.append(text)

    # -- writing -----------------------------------------------------------------------------
    def _start(self) -> None:
        """Begin a journal of the sculptor's current state (a new folder, or a new generation
        in the same folder): header now, base copy on the worker thread."""
        try:
            if self.directory is None:
                self.directory, self._lock = new_folder(self.root)
            state = capture_state(self.sculptor)  # with its faces and UVs: the base copy's
            self._base_faces = self.sculptor.faces
            sha = vertex_hash(state.vertices)
            base = f"base-{sha[:16]}.npz"
            self._token = secrets.token_hex(8)
            header = {
                "format": JOURNAL_FORMAT,
                "version": JOURNAL_VERSION,
                "token": self._token,
                "created": time.time(),
                **owner(),
                "document": {"path": self.document, "title": self.title},
                "mesh": {
                    "vertices": len(state.vertices),
                    "faces": len(self.sculptor.faces),
                    "sha256": sha,
                    "base": base,
                },
                "start": {**state.header(), "pins": _pins_json(state), "done": self._done()},
            }
            if self._retire is not None:
                header["continues"] = self._retire.directory.name
            fd = self._write_header(json.dumps(header, separators=_COMPACT).encode())
        except Exception as exc:
            self._stopped = True
            where = self.directory or self.root
            self._problem(
                f"Crash recovery is off: cannot write the journal in {where} ({_reason(exc)}). "
                "Save often: unsaved work is not protected."
            )
            return
        old, self._fd = self._fd, fd
        self.records = self.durable = 0
        self._work = 0.0
        self._stopped = False
        if old is not None:
            self._submit(("close", old))
        self._submit(("base", state, base))
        self._submit(("fsync", fd, 0))
        self._submit(("prune", base))
        if self._retire is not None:
            self._submit(("retire", self._retire))
            self._retire = None

    def _write_header(self, header: bytes) -> int:
        """Write a new ``journal.jsonl`` holding the header alone (renamed over the old one, so
        there is always a whole journal); returns its descriptor, open for appending."""
        directory = cast(Path, self.directory)  # (started: the folder was made)
        tmp = directory / f".{JOURNAL_FILE}.tmp"
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_APPEND, 0o600)
        try:
            write_all(fd, frame(header))
            os.replace(tmp, directory / JOURNAL_FILE)
        except BaseException:
            os.close(fd)
            raise
        return fd

    def _done(self) -> int:
        return int(self.sculptor.history.done)

    def _on_log(self, kind: str, item: object, length: int) -> None:
        """The sculptor's log changed (see :data:`gogreen_core.sculpt.session_log.LogListener`)."""
        if self._stopped:
            return
        try:
            if kind == "event":
                text = json.dumps(cast(BrushEvent, item).to_dict(), separators=_COMPACT)
                self._pending.append((item, text))
            elif kind == "truncate":  # a rolled-back replay: start again from what is now
                self._pending.clear()
                self._start()
            else:
                self._append(kind, cast(Operation, item), length)
        except Exception as exc:  # nothing may stop the sculpting
            self._stop(exc)
            if self.wake is not None:
                self.wake()  # the app says so

    def _append(self, kind: str, op: Operation, length: int) -> None:
        text = operation_json(op, self._pending)
        self._pending.clear()
        seq = self.records + 1
        record = (
            f'{{"seq":{seq},"kind":"{kind}","n":{length},"t":{time.time():.3f},'
            f'"d":{self._done()},"op":{text}}}'
        )
        write_all(cast(int, self._fd), frame(record.encode()))
        self.records = seq
        events = len(op.events) if isinstance(op, Stroke) else 0
        self._work += replay_work(op.name, events, len(self.sculptor.vertices))
        self._submit(("fsync", self._fd, seq))
        if self.wake is not None:
            self.wake()
        if self.auto_checkpoint and self.checkpoint_due:
            self.checkpoint()

    def _stop(self, exc: Exception) -> None:
        self._stopped = True
        self._pending.clear()
        self._problem(
            f"The crash-recovery journal stopped: {_reason(exc)}. Work from now on is not "
            "protected until you save."
        )

    def checkpoint(self) -> bool:
        """Copy the sculptor's state now (the vertices: ~8 ms for 1M) and write it on the
        worker thread; returns whether one was taken (not during a stroke)."""
        if not self.active or self.sculptor.in_stroke:
            return False
        state = capture_state(self.sculptor, self._base_faces)  # faces only if subdivided
        extra = {"token": self._token, "seq": self.records, "done": self._done()}
        self._work = 0.0
        self._submit(("checkpoint", state, {**extra, "time": time.time()}))
        return True

    def maybe_checkpoint(self) -> bool:
        """:meth:`checkpoint` if one is due."""
        return self.checkpoint() if self.checkpoint_due else False

    def write_file(self, name: str, data: bytes) -> None:
        """Write a small file into the journal's folder on the worker thread (the app's
        thumbnail), atomically."""
        if self.active:
            self._submit(("file", name, data))

    def restart(self, document: str | None = None, title: str | None = None) -> None:
        """Start a fresh journal from the sculptor's current state (after a save: the saved
        file, ``document`` called ``title`` from now on, holds what came before). The old
        records go once the new base copy is written."""
        if document is not None:
            self.document = os.path.abspath(document)
            self.title = title or Path(document).name
        self._pending.clear()
        self._start()

    def flush(self, timeout: float | None = 30.0) -> bool:
        """Wait until everything queued is written and on disk; False on timeout."""
        deadline = None if timeout is None else time.monotonic() + timeout
        with self._cond:
            while self._tasks or self._busy:
                left = None if deadline is None else deadline - time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._cond.wait(left)
        return True

    def close(self, remove: bool = True, timeout: float = 10.0) -> None:
        """Stop journaling. ``remove`` (a clean close: saved, or changes discarded): delete
        the folder. Without it the folder stays as a crash would leave it (what was written is
        flushed first). Waits at most ``timeout`` seconds for the disk."""
        self._unsubscribe()
        self._stopped = True
        self._submit(("stop",))
        self._thread.join(timeout)
        if self._fd is not None:
            with contextlib.suppress(OSError):
                os.close(self._fd)
            self._fd = None
        if self._lock is not None:
            if remove and not self._thread.is_alive():
                self._lock.remove()
            else:
                self._lock.release()
            self._lock = None
        if self._retire is not None:  # never started: the recovered journal stays
            self._retire.release()
            self._retire = None

    # -- worker thread -----------------------------------------------------------------------
    def _submit(self, task: tuple[Any, ...]) -> None:
        with self._cond:
            self._tasks.append(task)
            self._cond.notify_all()

    def _next_task(self) -> tuple[Any, ...]:
        """The next task; runs of fsyncs of one file collapse into the last, and a checkpoint
        with a newer one queued is skipped."""
        with self._cond:
            while not self._tasks:
                self._busy = False
                self._cond.notify_all()
                self._cond.wait()
            self._busy = True
            while True:
                task = self._tasks.popleft()
                if task[0] == "checkpoint" and any(t[0] == "checkpoint" for t in self._tasks):
                    continue  # a newer one is queued
                while task[0] == "fsync" and self._tasks and self._tasks[0][:2] == task[:2]:
                    task = self._tasks.popleft()
                return task

    def _run(self) -> None:
        while True:
            task = self._next_task()
            kind = task[0]
            try:
                if kind == "stop":
                    return
                self._do(task)
            except Exception as exc:
                if kind != "file":  # a picture protects nothing: not worth a message
                    self._problem(_task_problem(kind, exc))

    def _do(self, task: tuple[Any, ...]) -> None:
        kind = task[0]
        if kind == "fsync":
            os.fsync(task[1])
            self.durable = max(self.durable, task[2]) if task[1] == self._fd else self.durable
        elif kind == "close":
            os.close(task[1])
        elif kind == "base":
            self._write_base(task[1], task[2])
        elif kind == "checkpoint":
            self._write_checkpoint(task[1], task[2])
        elif kind == "prune":
            self._prune(keep_base=task[1])
        elif kind == "file":
            write_bytes_atomic(cast(Path, self.directory) / task[1], task[2])
        elif kind == "retire":
            if self._base_written:
                task[1].remove()
            else:  # this journal has no base copy: the recovered one stays for next time
                task[1].release()

    def _write_base(self, state: SculptState, name: str) -> None:
        faces = state.faces
        assert faces is not None  # the start's state holds its faces
        arrays: dict[str, Any] = {
            "vertices": state.vertices,
            "faces": faces.astype(_index_type(faces)),
        }
        if state.uv is not None and state.uv_faces is not None:
            arrays["uv"] = state.uv
            arrays["uv_faces"] = state.uv_faces.astype(_index_type(state.uv_faces))
        if state.mask is not None:
            arrays["mask"] = state.mask
        self._base_written = False
        atomic_write(cast(Path, self.directory) / name, lambda out: np.savez(out, **arrays))
        self._base_written = True

    def _write_checkpoint(self, state: SculptState, extra: dict[str, Any]) -> None:
        if extra["token"] != self._token:
            return  # the journal restarted since it was taken
        write_checkpoint(
            cast(Path, self.directory) / f"checkpoint-{extra['seq']}.bin", state, extra
        )
        self._prune()

    def _prune(self, keep_base: str | None = None) -> None:
        """Delete all but the newest :data:`KEEP_CHECKPOINTS` checkpoints, the checkpoints of
        an older generation (``keep_base`` given: a restart) and other base copies."""
        directory = cast(Path, self.directory)  # (tasks are queued once the folder was made)
        numbered = []
        for path in directory.glob("checkpoint-*.bin"):
            with contextlib.suppress(ValueError):
                numbered.append((int(path.stem.split("-", 1)[1]), path))
        numbered.sort()
        drop = numbered if keep_base is not None else numbered[:-KEEP_CHECKPOINTS]
        for _, path in drop:
            path.unlink(missing_ok=True)
        if keep_base is not None:
            for path in directory.glob("base-*.npz"):
                if path.name != keep_base:
                    path.unlink(missing_ok=True)


def _pins_json(state: SculptState) -> dict[str, Any] | None:
    if state.pins is None:
        return None
    points, matrix, inverse = state.pins
    return {"points": points.tolist(), "matrix": matrix.tolist(), "inverse": inverse.tolist()}


def _index_type(indices: np.ndarray) -> type:
    return np.int32 if indices.size == 0 or int(indices.max()) < 2**31 - 1 else np.int64


def _reason(exc: BaseException) -> str:
    if isinstance(exc, OSError) and exc.strerror:
        return exc.strerror + (f": {exc.filename}" if exc.filename else "")
    return str(exc) or type(exc).__name__


def _task_problem(kind: str, exc: Exception) -> str:
    what = {
        "checkpoint": "Crash-recovery checkpoints cannot be written",
        "base": "The crash-recovery copy of the mesh cannot be written",
        "fsync": "The crash-recovery journal cannot be flushed to disk",
    }.get(kind, "The crash-recovery journal had a problem")
    return f"{what} ({_reason(exc)})"
