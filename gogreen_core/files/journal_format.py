"""The recovery journal's files (README, "Crash recovery": the folder and the line format):
where they live, their lock, their lines, and reading them back (:func:`read_journal`). Besides
``seq``, ``kind`` and ``op`` a record holds ``n`` (operations after it), ``t`` (unix time) and
``d`` (undo steps done: recovery checks a replay from a checkpoint against it).
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import secrets
import shutil
import socket
import tempfile
import time
import zlib
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from types import ModuleType
from typing import Any

from gogreen_core.sculpt.operations import Operation, operation_from_dict
from gogreen_core.sculpt.session import SESSION_VERSION, upgrade_session
from gogreen_core.validation import ParameterError

fcntl: ModuleType | None  # None where there is no fcntl
try:
    import fcntl
except ImportError:  # not POSIX (Windows): no journal, said as a problem
    fcntl = None

__all__ = [
    "JOURNAL_FILE",
    "JOURNAL_FORMAT",
    "JOURNAL_VERSION",
    "SETTINGS_WORK",
    "SUBDIVIDE_WORK",
    "JournalContents",
    "JournalError",
    "JournalLock",
    "Record",
    "checkpoint_files",
    "frame",
    "lock_owner",
    "new_folder",
    "owner",
    "read_journal",
    "recovery_root",
    "replay_work",
    "state_home",
    "write_all",
]

JOURNAL_FORMAT = "gogreen-journal"
JOURNAL_VERSION = 2
#: The session version of a version-1 journal's records by its start's kernel evaluation.
_V1_SESSION_VERSIONS = {1: 2, 2: 3, 3: 4}
JOURNAL_FILE = "journal.jsonl"
LOCK_FILE = "lock"
THUMBNAIL_FILE = "thumbnail.png"
#: Replay work of a material or falloff change (a new kernel: ~50 ms).
SETTINGS_WORK = 1.5e6
#: A subdivision's or remesh's replay work in vertex passes (about 20 strokes' events).
SUBDIVIDE_WORK = 20


def replay_work(name: str, events: int, vertices: int) -> float:
    """Estimated cost of replaying an operation (``"op"`` name, mouse events if a stroke) on
    a mesh of ``vertices``: events × vertices for a stroke (each event passes over the whole
    mesh), one event for other operations, a kernel's worth for a material or falloff."""
    if name == "stroke":
        return max(1, events) * vertices
    if name in ("material", "falloff"):
        return max(vertices, SETTINGS_WORK)
    if name in ("subdivide", "remesh"):
        return SUBDIVIDE_WORK * vertices
    return vertices


def state_home() -> Path:
    """``$XDG_STATE_HOME``, or ``~/.local/state`` when it is unset or not absolute."""
    value = os.environ.get("XDG_STATE_HOME", "")
    return Path(value) if os.path.isabs(value) else Path.home() / ".local" / "state"


def recovery_root() -> Path:
    """The folder of the recovery journals: ``<state home>/gogreen-sculpt/recovery``."""
    return state_home() / "gogreen-sculpt" / "recovery"


def frame(payload: bytes) -> bytes:
    """One journal line: the payload's CRC-32 (8 hex digits), a space, the payload, newline."""
    return b"%08x %s\n" % (zlib.crc32(payload), payload)


def write_all(fd: int, data: bytes) -> None:
    """``write`` until all of ``data`` is written (a short write is retried; a full disk
    raises ``OSError``, leaving the line cut short, which a reader detects)."""
    view = memoryview(data)
    while view:
        written = os.write(fd, view)
        if written <= 0:
            raise OSError(errno.EIO, "write wrote nothing")
        view = view[written:]


def checkpoint_files(directory: Path) -> list[tuple[int, Path]]:
    """(record, path) of the ``checkpoint-<record>.bin`` files in ``directory``, oldest first."""
    found = []
    for path in directory.glob("checkpoint-*.bin"):
        with contextlib.suppress(ValueError):
            found.append((int(path.stem.split("-", 1)[1]), path))
    return sorted(found)


class JournalLock:
    """An exclusive ``flock`` on a journal folder's ``lock`` file: held by the app writing the
    journal, and by whoever recovers or discards it. The kernel drops it when its process dies
    (a crash, ``kill -9``), which is what makes a journal recoverable."""

    def __init__(self, directory: Path, fd: int) -> None:
        self.directory = Path(directory)
        self._fd: int | None = fd

    @classmethod
    def acquire(cls, directory: str | os.PathLike[str], create: bool = False) -> JournalLock | None:
        """The lock of ``directory``, or None while another process (or another journal of
        this one) holds it. ``create``: write this process's id and host into the file.
        OSError when the folder cannot be opened."""
        directory = Path(directory)
        if fcntl is None:
            raise OSError(errno.ENOSYS, "file locks (flock) are not available on this system")
        fd = os.open(directory / LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o600)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            return None
        except BaseException:
            os.close(fd)
            raise
        if create:
            with contextlib.suppress(OSError):
                os.ftruncate(fd, 0)
                write_all(fd, json.dumps(owner()).encode())
        return cls(directory, fd)

    def release(self) -> None:
        """Let go (the folder stays)."""
        if self._fd is not None:
            os.close(self._fd)  # closing the last descriptor drops the flock
            self._fd = None

    def remove(self) -> None:
        """Delete the folder and everything in it, then let go."""
        with contextlib.suppress(OSError):
            for child in self.directory.iterdir():
                if child.name != LOCK_FILE:
                    if child.is_dir() and not child.is_symlink():
                        shutil.rmtree(child, ignore_errors=True)
                    else:
                        child.unlink(missing_ok=True)
            (self.directory / LOCK_FILE).unlink(missing_ok=True)
            self.directory.rmdir()
        self.release()


def owner() -> dict[str, Any]:
    """Who writes a journal: this process's id, host and start time."""
    return {"pid": os.getpid(), "host": socket.gethostname(), "since": time.time()}


def lock_owner(directory: str | os.PathLike[str]) -> dict[str, Any]:
    """What the ``lock`` file says about the process that wrote the journal ({} if nothing)."""
    try:
        data = json.loads((Path(directory) / LOCK_FILE).read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def new_folder(root: Path) -> tuple[Path, JournalLock]:
    """A new journal folder, locked before it gets its final name (never seen unlocked)."""
    for folder in (root.parent, root):  # ``gogreen-sculpt`` and its ``recovery``: private
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        if folder.stat().st_mode & 0o077:
            folder.chmod(0o700)
    staging = Path(tempfile.mkdtemp(prefix=".new-", dir=root))  # mode 0700
    lock = JournalLock.acquire(staging, create=True)
    if lock is None:  # nobody else knows this folder
        raise OSError(errno.EBUSY, f"{staging} is locked")
    while True:
        name = f"{datetime.now():%Y%m%d-%H%M%S}-{secrets.token_hex(3)}"
        try:
            os.rename(staging, root / name)  # fails if the name exists (a non-empty folder)
            break
        except OSError as exc:
            if exc.errno not in (errno.EEXIST, errno.ENOTEMPTY):
                lock.remove()
                raise
    lock.directory = root / name
    return lock.directory, lock


class JournalError(ValueError):
    """A journal that cannot be recovered at all (its header unreadable, no mesh left), or is
    in use by a running app; the message says which and why."""


@dataclass(frozen=True)
class Record:
    """One complete journal record (see the module docstring): the operation's session form
    ``data`` and its typed ``op`` (None when read without validation)."""

    seq: int
    kind: str
    n: int
    t: float
    d: int
    data: dict[str, Any]
    op: Operation | None

    @property
    def steps(self) -> int:
        """Progress units of its replay: a stroke's mouse events, else 1."""
        events = self.data.get("events")
        return max(1, len(events)) if isinstance(events, list) else 1


@dataclass
class JournalContents:
    """What a journal holds up to its first damage: header, complete records, and ``notes``
    saying what was dropped and why."""

    directory: Path
    header: dict[str, Any]
    records: list[Record]
    notes: list[str] = field(default_factory=list)

    @property
    def operations(self) -> list[dict[str, Any]]:
        """The session operations the records make (a ``replace`` replaces the last)."""
        ops: list[dict[str, Any]] = []
        for record in self.records:
            if record.kind == "replace" and ops:
                ops[-1] = record.data
            else:
                ops.append(record.data)
        return ops

    @property
    def document(self) -> str | None:
        """The document's file, when it had one."""
        return (self.header.get("document") or {}).get("path")

    @property
    def title(self) -> str:
        return str((self.header.get("document") or {}).get("title") or self.directory.name)

    @property
    def modified(self) -> float:
        """Time of the last complete record (of the header when there is none)."""
        return self.records[-1].t if self.records else float(self.header.get("created", 0))


def _frame_payload(line: bytes) -> bytes | None:
    """The payload of a journal line, or None if its checksum does not match."""
    if len(line) < 10 or line[8:9] != b" ":
        return None
    try:
        crc = int(line[:8], 16)
    except ValueError:
        return None
    payload = line[9:]
    return payload if zlib.crc32(payload) == crc else None


def read_journal(directory: str | os.PathLike[str], validate: bool = True) -> JournalContents:
    """Read a journal folder's ``journal.jsonl`` up to its first damage. ``validate``: also
    check every operation (as session files are); listing skips that. :class:`JournalError`
    when even the header cannot be read."""
    directory = Path(directory)
    path = directory / JOURNAL_FILE
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise JournalError(f"{directory.name}: cannot read the journal ({exc.strerror})") from None
    lines = data.split(b"\n")
    try:  # (a bad checksum: no payload, no JSON)
        header = json.loads(_frame_payload(lines[0]) or b"") if len(lines) > 1 else None
    except ValueError:
        header = None
    if header is None:
        raise JournalError(f"{directory.name}: the journal's header is cut off or corrupt")
    if not isinstance(header, dict) or header.get("format") != JOURNAL_FORMAT:
        raise JournalError(f"{directory.name}: not a GoGreen Sculpt journal")
    try:
        mesh = header["mesh"]
        values = (header["version"], mesh["vertices"], mesh["faces"], mesh["sha256"], mesh["base"])
        ok = isinstance(header["start"], dict) and all(
            isinstance(v, t) for v, t in zip(values, (int, int, int, str, str), strict=True)
        )
    except (KeyError, TypeError):
        ok = False
    if not ok:
        raise JournalError(f"{directory.name}: the journal's header is malformed")
    contents = JournalContents(directory, header, [])
    version = SESSION_VERSION
    if header["version"] < 2:  # records of an older session version: upgraded as read
        start = header["start"]
        version = _V1_SESSION_VERSIONS.get(start.get("evaluation", 2), 4)
        with contextlib.suppress(ParameterError):  # (left for the start's reader to name)
            settings = upgrade_session({"version": version, "settings": start.get("settings")})
            header["start"] = {**start, "settings": settings["settings"]}
    if header["version"] > JOURNAL_VERSION:
        contents.notes.append(
            f"written by a newer GoGreen Sculpt (journal version {header['version']}; this one "
            f"reads {JOURNAL_VERSION}): read as far as this version understands it"
        )
    body = lines[1:]  # the last piece follows the last newline: empty unless cut off
    for index, line in enumerate(body):
        last = index == len(body) - 1
        if last and not line:
            break
        seq = index + 1
        record, problem = (
            _parse_record(line, seq, validate, version)
            if not last
            else (None, "was cut off (its write did not finish)")
        )
        if record is None:
            dropped = len(body) - index - (0 if body[-1] else 1)
            size = sum(len(x) + 1 for x in body[index:]) - 1
            what = f"it and the {dropped - 1} after it were" if dropped > 1 else "it was"
            contents.notes.append(
                f"record {seq} {problem}: {what} dropped ({size:,} bytes); the {seq - 1} "
                "records before it are kept"
            )
            break
        contents.records.append(record)
    return contents


def _parse_record(
    line: bytes, seq: int, validate: bool, version: int = SESSION_VERSION
) -> tuple[Record | None, str | None]:
    """One record; ``version``: the session version its operation is written in (upgraded to
    the current one: :func:`~gogreen_core.sculpt.session.upgrade_session`)."""
    payload = _frame_payload(line)
    if payload is None:
        return None, "is corrupt (checksum mismatch)"
    try:
        data = json.loads(payload)
        values = (data["seq"], data["kind"], data["n"], data["t"], data["d"], data["op"])
    except (ValueError, KeyError, TypeError):
        return None, "is malformed"
    number, kind, n, t, d, op = values
    if number != seq:
        return None, f"is out of order (numbered {number})"
    if kind not in ("append", "replace"):
        return None, f"is of a kind this version does not know ({kind!r})"
    if not (isinstance(n, int) and isinstance(d, int) and isinstance(t, (int, float))):
        return None, "is malformed"
    if not isinstance(op, dict):
        return None, "is malformed"
    typed = None
    if validate:
        try:
            if version < SESSION_VERSION:
                op = upgrade_session({"version": version, "operations": [op]})["operations"][0]
            typed = operation_from_dict(op, "op")
        except ParameterError as exc:
            return None, f"holds an operation this version cannot read ({exc})"
    elif not isinstance(op.get("op"), str):
        return None, "is malformed"
    return Record(seq, kind, n, float(t), d, op, typed), None
