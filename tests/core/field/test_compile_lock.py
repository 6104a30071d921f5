"""One compilation per numba cache at a time, across processes (issue 36, item 2): a lock beside
the cache, held by the compiling child; later processes evaluate in NumPy meanwhile and compile
nothing the holder compiles."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from gogreen_core import Brush, BrushEvent, Material, Sculptor, _compile_lock, _compiled
from gogreen_core.mesh.shapes import default_model

ONE_EVENT = """
import sys
import time
import numpy as np
from gogreen_core import Brush, BrushEvent, Material, Sculptor, _compile_lock, _compiled
from gogreen_core.mesh.shapes import default_model

vertices, faces = default_model(4)
sculptor = Sculptor(vertices, faces, material=Material.cubic(3.0, 1.5, 0.4), l_max=6)
top = vertices[int(np.argmax(vertices[:, 2]))]
sculptor.apply_brush(Brush("grab", radius=0.2), [BrushEvent(top, [0.02, 0.05, 0.0])])
np.save(sys.argv[1], sculptor.vertices)
# the script goes on a while (as one doing more than a brush event would): long enough for its
# compile worker to start a child if it were to
deadline = time.monotonic() + 120
while _compiled.compile_holder() is None and time.monotonic() < deadline:
    time.sleep(0.1)
time.sleep(3)
"""


def compiling_children(cache: Path) -> list[int]:
    """Pids of the compiling children (``_compiled._main``) working for the cache ``cache``."""
    pids = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            command = (entry / "cmdline").read_bytes()
            environment = (entry / "environ").read_bytes().split(b"\0")
        except OSError:  # gone meanwhile, or not ours
            continue
        if b"_compiled import _main" in command and f"NUMBA_CACHE_DIR={cache}".encode() in (
            environment
        ):
            pids.append(int(entry.name))
    return pids


@pytest.mark.skipif(not Path("/proc/self/environ").exists(), reason="needs Linux's /proc")
def test_three_scripts_in_a_row_on_an_empty_cache_run_one_compilation(tmp_path):
    cache = tmp_path / "cache"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), GOGREEN_COMPILE="child")
    results, errors = [], []
    try:
        for i in range(3):
            out = tmp_path / f"run{i}.npy"
            run = subprocess.run(
                [sys.executable, "-c", ONE_EVENT, str(out)],
                env=env,
                capture_output=True,
                text=True,
                timeout=300,
            )
            assert run.returncode == 0, run.stderr
            results.append(np.load(out))
            errors.append(run.stderr)
        children = compiling_children(cache)
        log = (cache / _compile_lock.LOG_NAME).read_text().splitlines()
    finally:
        for pid in compiling_children(cache):  # not left compiling after the test
            os.kill(pid, signal.SIGKILL)
    assert len(log) == 1, log  # one compilation started, by the first script's children
    # none of another script (none left if they already finished)
    assert all(f" {pid} " in log[0] for pid in children)
    if children:  # the first script left them running and said so
        assert "runs on" in errors[0]
    for other in results[1:]:
        np.testing.assert_array_equal(other, results[0])  # the NumPy evaluation: bit for bit
    # and the event as this process evaluates it (compiled or not: within 1e-12 of the motion)
    vertices, faces = default_model(4)
    sculptor = Sculptor(vertices, faces, material=Material.cubic(3.0, 1.5, 0.4), l_max=6)
    top = vertices[int(np.argmax(vertices[:, 2]))]
    with _compiled.forced("numpy"):  # (no compilation in this process: not the test's aim)
        sculptor.apply_brush(Brush("grab", radius=0.2), [BrushEvent(top, [0.02, 0.05, 0.0])])
    motion = np.abs(sculptor.vertices - vertices).max()
    assert motion > 1e-3
    assert np.abs(results[0] - sculptor.vertices).max() <= 1e-12 * motion


HOLD_THE_LOCK = """
import fcntl, os, sys, time
fd = os.open(sys.argv[1], os.O_RDWR | os.O_CREAT, 0o666)
fcntl.flock(fd, fcntl.LOCK_EX)
os.write(fd, b"pid %d (parent 1) compiling test units" % os.getpid())
print("held", flush=True)
time.sleep(600)
"""


@pytest.fixture
def lock_holder(tmp_path, monkeypatch):
    """A process holding the compile lock of a temporary cache, as a compiling child does."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("GOGREEN_COMPILE_LOCK_HELD", raising=False)
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLD_THE_LOCK, str(tmp_path / _compile_lock.LOCK_NAME)],
        stdout=subprocess.PIPE,
        text=True,
    )
    assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
    yield holder
    holder.kill()
    holder.wait()


def test_a_process_waits_for_the_holder_and_loads_what_it_compiled(lock_holder, monkeypatch):
    """Units missing from the cache while another process holds the lock: evaluations go on
    without them; once the holder ends, what it put in the cache is loaded, not compiled, and
    only what it left missing is compiled here."""
    monkeypatch.setenv("GOGREEN_COMPILE", "thread")
    in_cache = {"lock_test_a": False, "lock_test_b": False}
    seen: list[_compiled.Progress] = []
    for name in in_cache:
        _compiled.register(name, __name__, lambda unit: None, lambda unit: in_cache[unit])
    _compiled.add_progress_listener(seen.append)
    try:
        assert (
            _compiled.compile_holder() == f"pid {lock_holder.pid} (parent 1) compiling test units"
        )
        assert not _compiled.wait(list(in_cache), timeout=1.0)  # waits for the holder
        in_cache["lock_test_a"] = True  # what the holder compiled
        lock_holder.kill()  # a holder that dies: its lock is taken over at once
        assert _compiled.wait(list(in_cache), timeout=30)
        deadline = time.monotonic() + 10  # the worker lets go of the lock just after
        while _compiled.compile_holder() is not None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert _compiled.compile_holder() is None
        assert not _compiled.compiled_here(["lock_test_a"])
        assert _compiled.compiled_here(["lock_test_b"])
    finally:
        _compiled.remove_progress_listener(seen.append)
        with _compiled._condition:
            for name in in_cache:
                _compiled._units.pop(name, None)
                _compiled._ready.discard(name)
                _compiled._compiled_units.discard(name)
    ours = [p for p in seen if set(p.left) <= set(in_cache)]
    assert [(p.done, p.total) for p in ours] == [(0, 1), (1, 1)]  # only b was compiled here


def test_the_lock_is_free_when_nobody_compiles(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert _compiled.compile_holder() is None
    lock = _compile_lock.CacheLock.take()
    assert lock is not None and not lock.waited
    try:
        taken = threading.Event()

        def other() -> None:  # a second lock in this process is refused like another's
            second = _compile_lock.CacheLock.take()
            taken.set()
            assert second is not None
            second.release()

        thread = threading.Thread(target=other, daemon=True)
        thread.start()
        time.sleep(0.6)
        assert not taken.is_set()
    finally:
        lock.release()
    thread.join(5)
    assert taken.is_set()
