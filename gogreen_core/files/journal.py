"""The recovery journal: every completed operation of a sculptor, on disk before the next one.

:class:`Journal` listens to a sculptor's operation log (:meth:`Sculptor.subscribe`) and appends
each completed operation to its folder under :func:`recovery_root`, so that a crash loses
nothing that completed (:mod:`gogreen_core.files.recovery` rebuilds the mesh from it). The
folder's files and the line format: README, "Crash recovery", and
:mod:`gogreen_core.files.journal_format`. A record is written (one ``write``) before the
operation's call returns; ``fsync``, the base copy and the checkpoints follow on the journal's
worker thread. No error of the journal reaches the sculptor: it stops and says so once
(:meth:`Journal.take_problems`).
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
from functools import partial
from pathlib import Path
from typing import Any, cast

import numpy as np

from gogreen_core.files.journal_format import (
    JOURNAL_FILE,
    JOURNAL_FORMAT,
    JOURNAL_VERSION,
    THUMBNAIL_FILE,
    JournalLock,
    checkpoint_files,
    frame,
    new_folder,
    owner,
    recovery_root,
    replay_work,
    write_all,
)
from gogreen_core.mesh.mesh_io import MeshData, write_bytes_atomic
from gogreen_core.mesh.mesh_io.atomic import atomic_write
from gogreen_core.sculpt.brushes.brush import BrushEvent
from gogreen_core.sculpt.checkpoint import SculptState, write_checkpoint
from gogreen_core.sculpt.operations import Operation, Stroke
from gogreen_core.sculpt.sculptor import Sculptor, capture_state
from gogreen_core.sculpt.session import mesh_fingerprint

__all__ = ["CHECKPOINT_WORK", "JOURNAL_FILE", "THUMBNAIL_FILE", "Journal", "recovery_root"]

#: Replay work (see :func:`replay_work`) after which a checkpoint is due: about 0.5 s here.
CHECKPOINT_WORK = 1.5e7
#: Checkpoints kept per journal (recovery may start from an older one for a deeper undo).
KEEP_CHECKPOINTS = 3
_COMPACT = (",", ":")
#: A task of the journal's worker: (kind, the file of an fsync, the action; None to stop).
_Task = tuple[str, object, Callable[[], object] | None]
_TASK_PROBLEMS = {
    "checkpoint": "Crash-recovery checkpoints cannot be written",
    "base": "The crash-recovery copy of the mesh cannot be written",
    "fsync": "The crash-recovery journal cannot be flushed to disk",
}


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

    ``sculptor``'s operations are journaled from its current state on (its vertices, faces,
    UVs and mask are the base copy); ``mesh`` is the document's as loaded. ``document`` (its
    file, tried when the base copy is missing) and ``title`` are what recovery shows; ``root``
    the journals' folder (:func:`recovery_root`). ``auto_checkpoint``: take due checkpoints
    right after an operation (scripts; the app calls :meth:`checkpoint` when idle), due after
    ``checkpoint_work`` of replay work (:func:`replay_work`). ``replaces``: the lock of a
    journal this one continues (a recovered document's), removed once this base copy is on
    disk. ``wake``: called after each record (the app restarts its idle timer). Never raises
    for a disk problem: see :meth:`take_problems`.
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
        self._tasks: collections.deque[_Task] = collections.deque()
        self._busy = False
        self._cond = threading.Condition()
        self._thread = threading.Thread(target=self._run, name="gogreen-journal", daemon=True)
        self._thread.start()
        self._unsubscribe = sculptor.subscribe(self._on_log)
        self._retire = replaces
        self._base_written = False
        self._start()

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

    def _start(self) -> None:
        """Begin a journal (or a new generation of it) from the sculptor's current state."""
        self._pending.clear()
        try:
            if self.directory is None:
                self.directory, self._lock = new_folder(self.root)
            state = capture_state(self.sculptor)  # with its faces and UVs: the base copy's
            self._base_faces = self.sculptor.faces
            sha = mesh_fingerprint(state.vertices)
            base = f"base-{sha[:16]}.npz"
            self._token = secrets.token_hex(8)
            names = ("points", "matrix", "inverse")
            pins = state.pins and dict(zip(names, [a.tolist() for a in state.pins], strict=True))
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
                "start": {
                    **state.header(),
                    "pins": pins,
                    "done": self._done(),
                },
            }
            if self._retire is not None:
                header["continues"] = self._retire.directory.name
            tmp = self.directory / f".{JOURNAL_FILE}.tmp"
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | os.O_APPEND, 0o600)
            try:  # a new journal of the header alone, renamed over the old one
                write_all(fd, frame(json.dumps(header, separators=_COMPACT).encode()))
                os.replace(tmp, self.directory / JOURNAL_FILE)
            except BaseException:
                os.close(fd)
                raise
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
            self._submit("close", partial(os.close, old))
        self._submit("base", partial(self._write_base, state, base))
        self._submit("fsync", partial(self._fsync, fd, 0), fd)
        self._submit("prune", partial(self._prune, base))
        if self._retire is not None:
            self._submit("retire", partial(self._retire_journal, self._retire))
            self._retire = None

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
                self._start()
            else:
                self._append(kind, cast(Operation, item), length)
        except Exception as exc:  # nothing may stop the sculpting
            self._stopped = True
            self._pending.clear()
            self._problem(
                f"The crash-recovery journal stopped: {_reason(exc)}. Work from now on is not "
                "protected until you save."
            )
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
        fd = cast(int, self._fd)
        write_all(fd, frame(record.encode()))
        self.records = seq
        events = len(op.events) if isinstance(op, Stroke) else 0
        self._work += replay_work(op.name, events, len(self.sculptor.vertices))
        self._submit("fsync", partial(self._fsync, fd, seq), fd)
        if self.wake is not None:
            self.wake()
        if self.auto_checkpoint and self.checkpoint_due:
            self.checkpoint()

    def checkpoint(self) -> bool:
        """Copy the sculptor's state now (the vertices: ~8 ms for 1M) and write it on the
        worker thread; returns whether one was taken (not during a stroke)."""
        if not self.active or self.sculptor.in_stroke:
            return False
        state = capture_state(self.sculptor, self._base_faces)  # faces only if subdivided
        extra = {
            "token": self._token,
            "seq": self.records,
            "done": self._done(),
            "time": time.time(),
        }
        self._work = 0.0
        self._submit("checkpoint", partial(self._write_checkpoint, state, extra))
        return True

    def maybe_checkpoint(self) -> bool:
        """:meth:`checkpoint` if one is due."""
        return self.checkpoint() if self.checkpoint_due else False

    def write_file(self, name: str, data: bytes) -> None:
        """Write a small file (the thumbnail) into the folder, atomically, in the background."""
        if self.active:
            self._submit(
                "file", partial(write_bytes_atomic, cast(Path, self.directory) / name, data)
            )

    def restart(self, document: str | None = None, title: str | None = None) -> None:
        """Start a fresh journal from the sculptor's current state (after a save: the saved
        file, ``document`` called ``title`` from now on, holds what came before). The old
        records go once the new base copy is written."""
        if document is not None:
            self.document = os.path.abspath(document)
            self.title = title or Path(document).name
        self._start()

    def flush(self, timeout: float | None = 30.0) -> bool:
        """Wait until everything queued is written and on disk; False on timeout."""
        with self._cond:
            return self._cond.wait_for(lambda: not self._tasks and not self._busy, timeout)

    def close(self, remove: bool = True, timeout: float = 10.0) -> None:
        """Stop journaling. ``remove`` (a clean close: saved, or changes discarded): delete
        the folder. Without it the folder stays as a crash would leave it (what was written is
        flushed first). Waits at most ``timeout`` seconds for the disk."""
        self._unsubscribe()
        self._stopped = True
        self._submit("stop", None)
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

    def _submit(self, kind: str, action: Callable[[], object] | None, key: object = None) -> None:
        """Queue ``action`` (None: stop the worker); ``key``: the file of an fsync."""
        with self._cond:
            self._tasks.append((kind, key, action))
            self._cond.notify_all()

    def _next_task(self) -> _Task:
        """The next task: a run of fsyncs of one file as one, a checkpoint only if the newest."""
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
            kind, _, action = self._next_task()
            if action is None:
                return
            try:
                action()
            except Exception as exc:
                if kind != "file":  # a picture protects nothing: not worth a message
                    what = _TASK_PROBLEMS.get(kind, "The crash-recovery journal had a problem")
                    self._problem(f"{what} ({_reason(exc)})")

    def _fsync(self, fd: int, seq: int) -> None:
        os.fsync(fd)
        if fd == self._fd:
            self.durable = max(self.durable, seq)

    def _retire_journal(self, lock: JournalLock) -> None:
        if self._base_written:
            lock.remove()
        else:  # this journal has no base copy: the recovered one stays for next time
            lock.release()

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
        """Keep the newest :data:`KEEP_CHECKPOINTS` checkpoints (``keep_base``: a restart, none
        of them, nor other base copies)."""
        directory = cast(Path, self.directory)  # (tasks are queued once the folder was made)
        numbered = checkpoint_files(directory)
        drop = numbered if keep_base is not None else numbered[:-KEEP_CHECKPOINTS]
        for _, path in drop:
            path.unlink(missing_ok=True)
        if keep_base is not None:
            for path in directory.glob("base-*.npz"):
                if path.name != keep_base:
                    path.unlink(missing_ok=True)


def _index_type(indices: np.ndarray) -> type:
    return np.int32 if indices.size == 0 or int(indices.max()) < 2**31 - 1 else np.int64


def _reason(exc: BaseException) -> str:
    if isinstance(exc, OSError) and exc.strerror:
        return exc.strerror + (f": {exc.filename}" if exc.filename else "")
    return str(exc) or type(exc).__name__
