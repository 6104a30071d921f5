"""The compiled code, brought into the process without making anyone wait for a compiler.

Compiled code comes in units (:data:`DRIVERS`, :data:`GEOMETRY`, :data:`BRUSHES`,
:data:`MESH_IO`, and the generated angular kernel ``(l_first, l_last)`` of each parity and
highest degree). Each module registers its unit when imported (:func:`register`) and
asks here whether it is ready; until then its NumPy twin (or the generic angular kernel) serves
with the same results, and :func:`request` queues the unit without waiting.

A worker thread loads the units numba's disk cache holds (milliseconds) and has the others
compiled by a child Python (``_main``: in a thread here a compilation would hold the GIL and
numba's lock, slowing the GUI), then loads them; where no child can run (Python embedded in an
application) it compiles in this process. ``GOGREEN_COMPILE``: ``child`` (default), ``thread``
or ``off`` (only :func:`prepare` compiles). One compilation per cache at a time: see
``_compile_lock``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
import traceback
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from types import ModuleType
from typing import Any

from gogreen_core import compile_times
from gogreen_core._compile_lock import LOCK_HELD_VARIABLE, CacheLock, compile_holder, running

#: A unit: DRIVERS, GEOMETRY, BRUSHES, MESH_IO or (l_first, l_last) of an angular kernel.
Unit = str | tuple[int, ...]
#: What :func:`when_ready` calls with the errors of the units that failed.
ReadyCallback = Callable[[list[Exception]], None]

__all__ = [
    "ANGULAR",
    "BRUSHES",
    "DRIVERS",
    "GEOMETRY",
    "MESH_IO",
    "CompiledModule",
    "Progress",
    "add_progress_listener",
    "compile_holder",
    "dispatchers_cached",
    "drivers",
    "forced",
    "forced_code",
    "modules_cached",
    "prepare",
    "register",
    "remove_progress_listener",
    "request",
    "wait",
    "when_ready",
]

#: The field's drivers (``_drivers``).
DRIVERS = "drivers"
#: The unit of ``geometry.py``'s compiled functions (the viewport's surface index).
GEOMETRY = "geometry"
#: The unit of the paint brushes' compiled loops (``brushes.paint_kernels``: smooth, mask).
BRUSHES = "brushes"
#: The unit of the mesh readers' compiled loops (``mesh_io.warm_up``).
MESH_IO = "mesh_io"
#: What the (l_first, l_last) units of the generated angular kernels register as.
ANGULAR = "angular"
#: How compilation runs (see the module docstring), and the value a compiling child gets.
_MODE_VARIABLE = "GOGREEN_COMPILE"
MODES = ("child", "thread", "off")
#: Longest a compiling child may take before the worker compiles in this process instead.
CHILD_TIMEOUT = 900.0

_ready: set[Unit] = set()
_pending: list[Unit] = []
_failed: dict[Unit, Exception] = {}
#: Units this process had compiled (the others it only loaded from numba's disk cache).
_compiled_units: set[Unit] = set()
#: A progress listener (:func:`add_progress_listener`).
ProgressCallback = Callable[["Progress"], None]
_progress_listeners: list[ProgressCallback] = []
#: (units, callback) waiting for their units (see :func:`when_ready`).
_callbacks: list[tuple[tuple[Unit, ...], ReadyCallback]] = []
_condition = threading.Condition()
_worker: threading.Thread | None = None


@dataclass(frozen=True)
class Progress:
    """Where a compilation stands: ``done`` of ``total`` units compiled, ``elapsed`` seconds
    since it started, and the units still to compile (``left``)."""

    done: int
    total: int
    elapsed: float
    left: tuple[Unit, ...]
    #: Seconds left from the units' expected times (``compile_times``; None if one has none).
    estimate: float | None = None

    @property
    def seconds_left(self) -> float | None:
        """About how long the rest takes: :attr:`estimate`, else from the time per unit
        compiled so far (None before the first unit is in: nothing measured yet)."""
        if self.estimate is not None:
            return self.estimate
        if not self.done:
            return None
        return self.elapsed / self.done * (self.total - self.done)

    @property
    def compiling(self) -> str:
        """What is compiling now ("field drivers"; "" when nothing is left)."""
        return compile_times.unit_name(self.left[0]) if self.left else ""


def add_progress_listener(callback: ProgressCallback) -> None:
    """Call ``callback(progress)`` (on a compile thread, one call at a time) when a compilation
    starts and after each of its units."""
    with _condition:
        _progress_listeners.append(callback)


def remove_progress_listener(callback: ProgressCallback) -> None:
    with _condition:
        if callback in _progress_listeners:
            _progress_listeners.remove(callback)


def _tell_progress(progress: Progress) -> None:
    with _condition:
        listeners = list(_progress_listeners)
    for listener in listeners:
        try:
            listener(progress)
        except Exception:  # one listener's error must not stop the compilation
            traceback.print_exc()


@dataclass(frozen=True)
class _Part:
    """A registered unit: ``load(unit)`` compiles or loads it on the calling thread,
    ``cached(unit)`` tells whether the disk cache holds it; a compiling child imports
    ``module``."""

    module: str
    load: Callable[[Unit], object]
    cached: Callable[[Unit], bool]


#: The registered units (ANGULAR for every (l_first, l_last)).
_units: dict[str, _Part] = {}
#: unit → the unit that helps compile it (see :func:`register`).
_helpers: dict[Unit, str] = {}


def register(
    unit: str,
    module: str,
    load: Callable[[Unit], object],
    cached: Callable[[Unit], bool],
    helps: Unit | None = None,
) -> None:
    """Register ``unit`` of ``module`` (:class:`_Part`; again: replaced, and not ready until
    loaded again). ``helps``: a unit part of which ``unit`` compiles, in a second child while the
    first compiles that unit."""
    with _condition:
        if helps is not None:
            _helpers[helps] = unit
        _units[unit] = _Part(module, load, cached)
        _ready.difference_update([u for u in _ready if _kind(u) == unit])


class CompiledModule:
    """The compiled functions of module ``module`` once they are ready, else their NumPy twins
    (module ``twin``): registered as ``unit``, which ``exercise`` compiles or loads by calling
    each of them once, typed as the module calls them."""

    def __init__(
        self, unit: str, module: str, twin: ModuleType, exercise: Callable[[], object]
    ) -> None:
        self.unit, self.module, self.twin, self._exercise = unit, module, twin, exercise
        self._compiling = threading.local()  # ``now``: this thread runs ``exercise``
        register(unit, module, lambda _: self.compile_now(), lambda _: modules_cached(module))

    def kernels(self) -> ModuleType:
        """The module once its compiled functions are ready (else they are requested; on the
        thread compiling them, the module), else the twin."""
        if getattr(self._compiling, "now", False) or _in_use(self.unit):
            return sys.modules[self.module]
        return self.twin

    def compile_now(self) -> None:
        """Compile (or load from numba's disk cache) the module's functions, on this thread."""
        self._compiling.now = True
        try:
            self._exercise()
        finally:
            self._compiling.now = False


def dispatchers_cached(calls: Iterable[tuple[Any, tuple[Any, ...]]]) -> bool:
    """Whether numba's disk cache holds every (dispatcher, arguments) call of ``calls``,
    typed as they are (numba's ``_cache.load_overload``, not public API)."""
    from numba import typeof

    for dispatcher, args in calls:
        signature = tuple(typeof(a) for a in args)
        if dispatcher._cache.load_overload(signature, dispatcher.targetctx) is None:
            return False
    return True


def modules_cached(name: str) -> bool:
    """Whether numba's disk cache holds machine code for this machine of every compiled
    function of module ``name`` (of a package: of its modules too), from their cache index. A
    function without any entry is one only compiled code calls."""
    import importlib
    import pkgutil

    from numba.core.dispatcher import Dispatcher

    module = importlib.import_module(name)
    modules = [module]
    for info in pkgutil.iter_modules(getattr(module, "__path__", [])):
        modules.append(importlib.import_module(f"{module.__name__}.{info.name}"))
    found = False
    for dispatcher in (v for m in modules for v in vars(m).values()):
        if isinstance(dispatcher, Dispatcher) and dispatcher.__module__.startswith(module.__name__):
            internals: Any = dispatcher  # numba's cache and code generator carry no types
            magic = internals.targetctx.codegen().magic_tuple()
            index = internals._cache._cache_file._load_index()
            if not index:  # never compiled on its own: called only from compiled code (inlined)
                continue
            if not any(key[1] == magic for key in index):
                return False
            found = True
    return found


def _kind(unit: Unit) -> str:
    return unit if isinstance(unit, str) else ANGULAR


def _part(unit: Unit) -> _Part | None:
    with _condition:
        return _units.get(_kind(unit))


#: Tests and benchmarks only (:func:`forced`): None, or which code evaluates.
_forced: str | None = None


def drivers() -> bool:
    """Whether the compiled drivers are ready (else they are requested; use NumPy)."""
    return _in_use(DRIVERS)


def forced_code() -> str | None:
    """The code :func:`forced` chose ("numpy", "generic", "unrolled"), or None."""
    return _forced


def _in_use(unit: Unit) -> bool:
    if _forced is not None:
        if _forced == "numpy":
            return False
        prepare(unit)
    if unit in _ready:
        return True
    request(unit)
    return False


@contextmanager
def forced(code: str) -> Iterator[None]:
    """``with forced("numpy" | "generic" | "unrolled"):`` evaluations in the block use that
    code (compiled first if needed): tests comparing them, benchmarks. Not thread safe."""
    global _forced
    if code not in ("numpy", "generic", "unrolled"):
        raise ValueError(f"unknown evaluation code {code!r}")
    saved, _forced = _forced, code
    try:
        yield
    finally:
        _forced = saved


def _mode() -> str:
    mode = os.environ.get(_MODE_VARIABLE, "child").strip().lower()
    return mode if mode in MODES else "child"


def request(*units: Unit) -> None:
    """Queue ``units`` for the worker unless ready, queued or failed; never blocks."""
    global _worker
    if _mode() == "off":
        return
    with _condition:
        new = [u for u in units if u not in _ready and u not in _pending and u not in _failed]
        if not new:
            return
        _pending.extend(new)
        if _worker is None:
            # a daemon: a script that ends meanwhile does not wait; a child process compiling
            # then still finishes and leaves its work in numba's disk cache for the next run
            _worker = threading.Thread(target=_work, name="gogreen-compile", daemon=True)
            _worker.start()


def when_ready(units: Iterable[Unit], callback: ReadyCallback) -> None:
    """Request ``units`` and call ``callback(failures)`` (the exceptions of those that failed)
    once each is ready or failed: on a compile thread, or now if they already are."""
    units = tuple(units)
    request(*units)
    with _condition:
        if not _settled(units):
            _callbacks.append((units, callback))
            return
    callback([_failed[u] for u in units if u in _failed])


def compiled_here(units: Iterable[Unit]) -> bool:
    """Whether any of ``units`` was compiled (not only loaded) by this process or its child."""
    with _condition:
        return any(u in _compiled_units for u in units)


def _settled(units: Iterable[Unit]) -> bool:
    return all(u in _ready or u in _failed for u in units)


def wait(units: Iterable[Unit], timeout: float | None = None) -> bool:
    """Block until ``units`` are ready (or failed); False on time-out. The units are
    requested (with ``GOGREEN_COMPILE=off``, never ready: returns False at once)."""
    units = tuple(units)
    request(*units)
    if _mode() == "off" and not _settled(units):
        return False
    with _condition:
        return _condition.wait_for(lambda: _settled(units), timeout)


def prepare(*units: Unit) -> float:
    """Bring ``units`` in and wait for them; returns the seconds it took, raises the error of a
    unit that could not be compiled."""
    start = time.perf_counter()
    if _mode() == "off":
        for unit in units:
            _load(unit)
            with _condition:
                _ready.add(unit)
        return time.perf_counter() - start
    request(*units)
    wait(units)
    for unit in units:
        if unit in _failed:
            raise _failed[unit]
    return time.perf_counter() - start


class _UnitCount:
    """Counts one compilation's units as they are compiled, telling the progress listeners."""

    def __init__(self, missing: list[Unit], split: bool = False) -> None:
        self.missing, self.done, self.split = missing, list[Unit](), split
        self.start = time.perf_counter()
        self.last = {False: self.start, True: self.start}  # split: the first unit's own clock
        self.seconds: dict[Unit, float] = {}  # measured per unit, recorded when all are in
        self.known = compile_times.recorded() if missing else {}
        if missing:
            left = tuple(missing)
            estimate = compile_times.seconds_left({}, left, self.known)
            _tell_progress(Progress(0, len(missing), 0.0, left, estimate))

    def compiled(self, unit: Unit) -> None:
        if unit in self.done:
            return
        self.done.append(unit)
        now = time.perf_counter()
        lane = self.split and unit == self.missing[0]
        self.seconds[unit], self.last[lane] = now - self.last[lane], now
        left = tuple(u for u in self.missing if u not in self.done)
        estimate = compile_times.seconds_left(self.seconds, left, self.known)
        _tell_progress(
            Progress(len(self.done), len(self.missing), now - self.start, left, estimate)
        )
        if not left:
            compile_times.record(self.seconds)


def _work() -> None:
    global _worker
    while True:
        with _condition:
            units = list(_pending)
            if not units:
                _worker = None
                return
        missing = [u for u in units if not _cached(u)]
        # waits while another process compiles; what it compiled is loaded, not compiled again
        lock = CacheLock.take() if missing else None
        try:
            if lock is not None and lock.waited:
                missing = [u for u in missing if not _cached(u)]
            _bring_in(units, missing, lock)
        finally:
            if lock is not None:
                lock.release()


def _bring_in(units: list[Unit], missing: list[Unit], lock: CacheLock | None) -> None:
    """Compile ``missing`` (in children where they can run, each unit loaded here as soon as a
    child has it in the disk cache: the first ones serve while the rest compile), then load
    the other ``units``."""
    with _condition:
        _compiled_units.update(missing)
    split = _can_spawn() and _splits(missing)
    count = _UnitCount(missing, split)
    settled: set[Unit] = set()

    def compiled_by_child(unit: Unit) -> None:
        if unit in units and unit not in settled:
            settled.add(unit)
            _settle(unit, missing, count)

    if missing and _can_spawn():
        _compile_in_child(missing, compiled_by_child, lock, split)
    elif missing and lock is not None:  # compiled by this process (in _settle)
        lock.note_holder([os.getpid()], [str(u) for u in missing])
    for unit in units:
        if unit not in settled:
            _settle(unit, missing, count)


def _settle(unit: Unit, missing: list[Unit], count: _UnitCount) -> None:
    """Load ``unit`` (compiled here if no child did), mark it ready or failed, take it off the
    queue and call the callbacks now due."""
    if _part(unit) is None:  # its module is not imported yet: asked for again later
        with _condition:
            _pending.remove(unit)
            _condition.notify_all()
        return
    try:
        _load(unit)  # from the disk cache now; compiled here if the child could not
    except Exception as exc:  # the NumPy / generic evaluation keeps serving
        with _condition:
            _failed[unit] = exc
    else:
        if unit in missing:  # told before a waiter sees it ready; compiled here if
            count.compiled(unit)  # the child did not
        with _condition:
            _ready.add(unit)
    with _condition:
        _pending.remove(unit)
        _condition.notify_all()
        due = [entry for entry in _callbacks if _settled(entry[0])]
        for entry in due:
            _callbacks.remove(entry)
    for waited, callback in due:
        try:
            callback([_failed[u] for u in waited if u in _failed])
        except Exception:  # one listener's error must not starve the others
            traceback.print_exc()


def _load(unit: Unit) -> None:
    part = _part(unit)
    if part is None:
        raise LookupError(f"no compile unit {unit!r} is registered (its module is not imported)")
    part.load(unit)


def _cached(unit: Unit) -> bool:
    """Whether numba's disk cache holds ``unit`` (then loading it takes milliseconds); any
    doubt counts as not cached (a child then finds everything cached)."""
    try:
        part = _part(unit)
        return part is not None and part.cached(unit)
    except Exception:
        return False


def _can_spawn() -> bool:
    """A child Python can compile for us: asked for, and this process is a Python interpreter
    (not an application embedding one, e.g. Blender)."""
    name = os.path.basename(sys.executable or "").lower()
    return _mode() == "child" and name.startswith("python")


def _splits(units: list[Unit]) -> bool:
    """Whether ``units`` compile in two children (``_compile_in_child``): two cores or more."""
    several = len(units) > 1 or (bool(units) and units[0] in _helpers)
    return several and (os.cpu_count() or 1) > 1


def _compile_in_child(
    units: list[Unit],
    unit_compiled: Callable[[Unit], None] = lambda unit: None,
    lock: CacheLock | None = None,
    split: bool = False,
) -> bool:
    """Compile ``units`` into numba's disk cache in a child process; True if it succeeded.
    Its arguments are ``module=unit`` (the module registers the unit); it prints each
    once its unit is compiled, and ``unit_compiled(unit)`` is called then. It inherits ``lock``
    and holds it to its end. ``split`` (two cores or more): the first unit (what the first
    stroke needs) alone in one child, its helper (:func:`register`) and the rest in another."""
    env = dict(os.environ, **{_MODE_VARIABLE: "thread", LOCK_HELD_VARIABLE: "1"})
    # the child imports what this process does: an application embedding Python (Blender)
    # adds folders to sys.path at run time (its extensions' wheels) that no child would know
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    children: list[tuple[subprocess.Popen[str], dict[str, Unit]]] = []
    helper = [_helpers[units[0]]] if units[0] in _helpers else []
    for group in (units[:1], [*helper, *units[1:]]) if split else (units,):
        by_arg: dict[str, Unit] = {}
        for unit in group:
            part = _part(unit)
            name = unit if isinstance(unit, str) else f"{unit[0]}:{unit[1]}"
            by_arg[f"{part.module if part else ''}={name}"] = unit
        try:
            child = subprocess.Popen(
                [sys.executable, "-c", _CHILD_SCRIPT, *by_arg],
                env=env,
                stdin=subprocess.DEVNULL,
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                text=True,
                pass_fds=() if lock is None else (lock.fd,),
                start_new_session=True,  # runs on if this process ends (module docstring)
            )
        except (OSError, subprocess.SubprocessError):
            break
        running.add(child)
        children.append((child, by_arg))
    if lock is not None and children:
        lock.note_holder([c.pid for c, _ in children], [a for _, args in children for a in args])
    done: list[bool] = []
    one_at_a_time = threading.Lock()  # two followers: one unit's count and listeners at a time

    def follow(child: subprocess.Popen[str], by_arg: dict[str, Unit]) -> None:
        timer = threading.Timer(CHILD_TIMEOUT, child.kill)
        timer.daemon = True
        timer.start()
        try:
            assert child.stdout is not None
            for line in child.stdout:  # anything else the child prints is not a unit's name
                if line.strip() in by_arg:
                    with one_at_a_time:
                        unit_compiled(by_arg[line.strip()])
            done.append(child.wait() == 0)
        finally:
            timer.cancel()
            running.discard(child)

    others = [threading.Thread(target=follow, args=child) for child in children[1:]]
    for thread in others:
        thread.start()
    if children:
        follow(*children[0])
    for thread in others:
        thread.join()
    return len(done) == (2 if split else 1) and all(done)


_CHILD_SCRIPT = (
    "import sys; from gogreen_core._compiled import _main; sys.exit(_main(sys.argv[1:]))"
)


def _main(argv: list[str]) -> int:
    """The child: compile into numba's disk cache the units of its command line
    (``module=unit``). It outlives a parent that ends meanwhile, not CHILD_TIMEOUT."""
    import importlib

    quit_timer = threading.Timer(CHILD_TIMEOUT, os._exit, (3,))
    quit_timer.daemon = True
    quit_timer.start()
    for arg in argv:
        module, _, name = arg.rpartition("=")
        if module:
            importlib.import_module(module)
        _load(tuple(int(v) for v in name.split(":")) if ":" in name else name)
        try:
            print(arg, flush=True)  # the parent counts the units compiled
        except (BrokenPipeError, ValueError):  # the parent is gone: compile the rest anyway
            sys.stdout = open(os.devnull, "w")  # for the rest of this process
    return 0
