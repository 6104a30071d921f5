"""The lock beside numba's disk cache: one compilation per cache at a time, across processes.

``_compiled``'s worker takes an exclusive ``flock`` on :data:`LOCK_NAME` in :func:`cache_folder`
before compiling, and its compiling children inherit it to their end (the kernel frees a dead
holder's). Another process finding it held evaluates in NumPy meanwhile, then loads what the
holder compiled. The lock file names the holder, :data:`LOG_NAME` logs each compilation.
Children still compiling when their process exits run on detached (their own session) and
finish the cache for the next run; stderr says so.
"""

from __future__ import annotations

import atexit
import os
import subprocess
import sys
import time
from pathlib import Path

__all__ = ["LOCK_NAME", "LOG_NAME", "CacheLock", "cache_folder", "compile_holder", "running"]

#: The compiling children of this process still running (said on stderr at exit).
running: set[subprocess.Popen[str]] = set()
#: Set in a compiling child's environment: its parent's lock is its own (it takes none).
LOCK_HELD_VARIABLE = "GOGREEN_COMPILE_LOCK_HELD"
LOCK_NAME = "gogreen-compile.lock"
LOG_NAME = "gogreen-compile.log"


def cache_folder() -> Path:
    """The folder of numba's disk cache of gogreen_core (the lock's): ``NUMBA_CACHE_DIR``, else
    the package's ``__pycache__`` when writable, else one in the temporary directory."""
    configured = os.environ.get("NUMBA_CACHE_DIR", "").strip()
    if configured:
        return Path(configured)
    beside = Path(__file__).resolve().parent / "__pycache__"
    if os.access(beside if beside.is_dir() else beside.parent, os.W_OK):
        return beside
    import tempfile

    return Path(tempfile.gettempdir()) / f"gogreen-numba-{os.getuid()}"


class CacheLock:
    """The exclusive ``flock`` on ``cache_folder() / LOCK_NAME``. ``waited``: another process
    held it when asked (it may have compiled what was missing)."""

    def __init__(self, fd: int, waited: bool) -> None:
        self.fd, self.waited = fd, waited

    @classmethod
    def take(cls) -> CacheLock | None:
        """Take the lock, waiting (polling every quarter second) while another process holds
        it; None where none can be taken (no fcntl, a read-only folder, a compiling child)."""
        if os.environ.get(LOCK_HELD_VARIABLE):
            return None
        try:
            import fcntl

            folder = cache_folder()
            folder.mkdir(parents=True, exist_ok=True)
            fd = os.open(folder / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o666)
        except (ImportError, OSError):
            return None
        waited = False
        while True:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                return cls(fd, waited)
            except BlockingIOError:
                waited = True
                time.sleep(0.25)
            except OSError:  # a file system without locks: compile as if alone
                os.close(fd)
                return None

    def note_holder(self, pids: list[int], units: list[str]) -> None:
        """Write who holds the lock into the lock file, and a line into the log beside it."""
        holders = " ".join(map(str, pids))
        line = f"{time.strftime('%Y-%m-%dT%H:%M:%S')} pid {holders} (parent {os.getpid()}) "
        line += f"compiling {' '.join(units)}\n"
        try:
            os.ftruncate(self.fd, 0)
            os.pwrite(self.fd, line.encode(), 0)
            with open(cache_folder() / LOG_NAME, "a", encoding="utf-8") as log:
                log.write(line)
        except OSError:  # the note is for people; the lock holds without it
            pass

    def release(self) -> None:
        os.close(self.fd)  # a child holding the inherited lock keeps it until it ends


def compile_holder() -> str | None:
    """Who compiles into the disk cache now (the lock file's line), or None if nobody does."""
    try:
        import fcntl

        fd = os.open(cache_folder() / LOCK_NAME, os.O_RDONLY)
    except (ImportError, OSError):
        return None
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except OSError:
        with open(fd, encoding="utf-8", closefd=False) as file:
            return file.read().strip() or "another process"
    finally:
        os.close(fd)
    return None


@atexit.register
def _say_what_runs_on() -> None:
    """At exit, name the compiling children left running (they finish on their own)."""
    for child in list(running):
        if child.poll() is None:
            print(
                f"gogreen: compiling process {child.pid} runs on to finish numba's disk cache "
                f"in {cache_folder()} (the next run loads its kernels from there)",
                file=sys.stderr,
            )
