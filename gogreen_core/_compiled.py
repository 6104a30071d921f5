"""The compiled evaluation, brought into the process without making anyone wait for a compiler.

Compiled code comes in units: the drivers of the current evaluation (``_expansion``,
``_integrator``: one unit, :data:`DRIVERS`) and the generated angular kernel of each parity and
highest degree (``(l_first, l_last)``, see ``_unrolled``). Until a unit is ready the evaluation
runs in NumPy (``_numpy_eval``) or with the generic angular kernel, with the same results bit
for bit, so nothing waits for it: :func:`request` queues units and returns at once.

A worker thread then brings them in: units already in numba's disk cache are loaded
(milliseconds); the others are compiled by a child Python process (``_main``), which fills
the same disk cache, and loaded after it. A numba compilation holds the GIL most of the time
and numba's global compiler lock all of it: in a thread of this process it would slow the GUI
and the NumPy evaluation (a thread waiting for the GIL waits up to Python's switch interval,
5 ms, each time) and block every other compilation; in a child it runs on the other core.
Where no child can run (an application embedding Python), the worker compiles in this process.

The environment variable ``GOGREEN_COMPILE`` chooses: ``child`` (the default), ``thread``
(compile in a background thread of this process) or ``off`` (never in the background: the
NumPy evaluation serves everything not compiled by an explicit :func:`prepare`; for tests and
for machines where numba cannot compile).
"""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
import traceback
from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING, Any

import numpy as np

from gogreen_core import _expansion, _influence_compiled, _integrator, _stream, _unrolled

if TYPE_CHECKING:
    from numba.core.ccallback import CFunc

#: A unit of compilation: DRIVERS, GEOMETRY, BRUSHES, MESH_IO or (l_first, l_last) of an
#: angular kernel.
Unit = str | tuple[int, ...]
#: What :func:`when_ready` calls with the errors of the units that failed.
ReadyCallback = Callable[[list[Exception]], None]

__all__ = [
    "BRUSHES",
    "DRIVERS",
    "GEOMETRY",
    "MESH_IO",
    "angular",
    "brushes",
    "drivers",
    "ensure_drivers",
    "forced",
    "geometry",
    "prepare",
    "request",
    "units_for",
    "wait",
    "when_ready",
]

#: The unit of the drivers (the others: (l_first, l_last) of a generated angular kernel,
#: GEOMETRY and MESH_IO).
DRIVERS = "drivers"
#: The unit of ``geometry.py``'s compiled functions (the viewport's surface index).
GEOMETRY = "geometry"
#: The unit of the paint brushes' compiled loops (``brushes.paint_kernels``: smooth, mask).
BRUSHES = "brushes"
#: The unit of the mesh readers' compiled loops (``mesh_io.warm_up``): opening a file then
#: never compiles on the calling thread.
MESH_IO = "mesh_io"
#: How compilation runs (see the module docstring), and the value a compiling child gets.
_MODE_VARIABLE = "GOGREEN_COMPILE"
MODES = ("child", "thread", "off")
#: Longest a compiling child may take before the worker compiles in this process instead.
CHILD_TIMEOUT = 900.0

_ready: set[Unit] = set()
_pending: list[Unit] = []
_failed: dict[Unit, Exception] = {}
#: (units, callback) waiting for their units (see :func:`when_ready`).
_callbacks: list[tuple[tuple[Unit, ...], ReadyCallback]] = []
_condition = threading.Condition()
_worker: threading.Thread | None = None
_markers: dict[bool, CFunc[Any]] = {}


def generic_marker(single: bool = False) -> CFunc[Any]:
    """The C callback passed as ``angular`` (``single``: as ``angular32``, evaluation 3's
    single precision kernel) with ``unrolled=False`` (never called): the drivers then run the
    generic ``_expansion._angular``. Compiled with the drivers."""
    marker = _markers.get(single)
    if marker is None:
        from numba import cfunc

        signature = _expansion.ANGULAR_SINGLE_SIGNATURE if single else _expansion.ANGULAR_SIGNATURE
        marker = _markers[single] = cfunc(signature, cache=True)(_expansion.generic_marker)
    return marker


#: Tests and benchmarks only (:func:`forced`): None, or which code evaluates.
_forced: str | None = None


def drivers() -> bool:
    """Whether the compiled drivers are ready (else they are requested; use NumPy)."""
    return _in_use(DRIVERS)


def geometry() -> bool:
    """Whether ``geometry.py``'s compiled functions are ready (else they are requested)."""
    return _in_use(GEOMETRY)


def brushes() -> bool:
    """Whether the paint brushes' compiled loops are ready (else they are requested)."""
    return _in_use(BRUSHES)


def _in_use(unit: Unit) -> bool:
    if _forced is not None:
        if _forced == "numpy":
            return False
        prepare(unit)
    if unit in _ready:
        return True
    request(unit)
    return False


def angular(l_first: int, l_last: int, single: bool = False) -> CFunc[Any] | None:
    """The generated angular kernel (``single``: its single precision one) if it is ready,
    else None (its unit is requested)."""
    if _forced == "generic":
        return None
    if _forced == "unrolled":
        prepare((l_first, l_last))
    kernel = _unrolled._KERNELS.get((l_first, l_last, single))
    if kernel is None:
        request((l_first, l_last))
    return kernel


class forced:
    """``with forced("numpy" | "generic" | "unrolled"):`` evaluations in the block use that
    code (compiled first if needed; ``geometry.py`` compiled for the last two): tests comparing
    them, benchmarks. Not thread safe."""

    def __init__(self, code: str) -> None:
        if code not in ("numpy", "generic", "unrolled"):
            raise ValueError(f"unknown evaluation code {code!r}")
        self.code = code

    def __enter__(self) -> forced:
        global _forced
        self._saved, _forced = _forced, self.code
        return self

    def __exit__(self, *exc: object) -> None:
        global _forced
        _forced = self._saved


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
    """Call ``callback(failures)`` once every unit of ``units`` is ready or failed (failures:
    the exceptions of those that failed), on the worker thread, or now if they already are.
    The units are requested."""
    units = tuple(units)
    request(*units)
    with _condition:
        if not _settled(units):
            _callbacks.append((units, callback))
            return
    callback([_failed[u] for u in units if u in _failed])


def _settled(units: Iterable[Unit]) -> bool:
    return all(u in _ready or u in _failed for u in units)


def wait(units: Iterable[Unit], timeout: float | None = None) -> bool:
    """Block until ``units`` are ready (or failed); False on time-out. The units are
    requested (with ``GOGREEN_COMPILE=off``, never ready: returns False at once)."""
    units = tuple(units)
    request(*units)
    if _mode() == "off" and not _settled(units):
        return False
    deadline = None if timeout is None else time.monotonic() + timeout
    with _condition:
        while any(u not in _ready and u not in _failed for u in units):
            left = None if deadline is None else deadline - time.monotonic()
            if left is not None and left <= 0:
                return False
            _condition.wait(left)
    return True


def prepare(*units: Unit) -> float:
    """Bring ``units`` in and wait for them (this thread waits; the compilation runs in a
    child process where it can). Returns the seconds it took; raises the error of a unit that
    could not be compiled."""
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


def _work() -> None:
    global _worker
    while True:
        with _condition:
            units = list(_pending)
            if not units:
                _worker = None
                return
        missing = [u for u in units if not _cached(u)]
        if missing and _can_spawn():
            _compile_in_child(missing)
        for unit in units:
            try:
                _load(unit)  # from the disk cache now; compiled here if the child could not
            except Exception as exc:  # the NumPy / generic evaluation keeps serving
                with _condition:
                    _failed[unit] = exc
            else:
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


def units_for(l_max: int) -> tuple[Unit, ...]:
    """The units vector and affine loads of truncation degree ``l_max`` evaluate with: the
    drivers and the generated angular kernel of each parity (when one is generated)."""
    parities = ((0, l_max - l_max % 2), (1, l_max + 1 - l_max % 2))
    return (DRIVERS, *(p for p in parities if p[1] <= _unrolled.UNROLLED_L_MAX))


def _compile_geometry() -> None:
    """Compile (or load from numba's disk cache) every compiled function of ``geometry.py``,
    on this thread: a small surface index built, updated, compared and picked with them."""
    from gogreen_core import geometry

    geometry._compiling.now = True
    try:
        vertices = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
        index = geometry.SurfaceIndex(vertices, faces)
        moved = vertices.copy()
        moved[3, 2] = 1.5
        index.update(moved, np.array([3]))
        index.changed_rows(vertices)
        index.pick(np.array([0.2, 0.2, 3.0]), np.array([0.0, 0.0, -1.0]))
    finally:
        geometry._compiling.now = False


def _compile_mesh_io() -> None:
    from gogreen_core import mesh_io

    mesh_io.warm_up()


def _compile_brushes() -> None:
    from gogreen_core.brushes import paint_kernels

    paint_kernels.compile_now()


#: Units named by a string (but DRIVERS), each with the function that compiles or loads it.
_NAMED = {GEOMETRY: _compile_geometry, MESH_IO: _compile_mesh_io, BRUSHES: _compile_brushes}


def _load(unit: Unit) -> None:
    if unit == DRIVERS:
        ensure_drivers()
    elif unit in _NAMED:
        _NAMED[unit]()
    else:
        for first, last, single in _angular_kernels(unit):
            _unrolled.unrolled_angular(first, last, single)


def _angular_kernels(unit: Unit) -> list[tuple[int, int, bool]]:
    """(l_first, l_last, single) of the kernels of an angular unit: double precision, and
    single where the parity has more than one degree (evaluation 3's degrees above the
    lowest)."""
    first, last = int(unit[0]), int(unit[1])
    return [(first, last, single) for single in ((False, True) if last > first else (False,))]


def _driver_calls() -> list[tuple[Any, tuple[Any, ...]]]:
    """(dispatcher, arguments) of every driver, typed as the real calls are (float64
    C-contiguous writable arrays, int64 rows and bases, bool flags, the C callback type of
    ``angular``), with empty ranges: calling them compiles and returns."""
    f3, f33 = np.zeros(3), np.zeros((1, 3))
    rows, base = np.zeros(1, dtype=np.int64), np.zeros(2, dtype=np.int64)
    tables = np.zeros((1, 2, _expansion.SEGMENT_DEGREE + 1))
    beta, blocks, flags = np.zeros((2, 2)), np.zeros(1), np.zeros(1, dtype=np.bool_)
    marker = generic_marker()
    single = (f33.astype(np.float32), beta.astype(np.float32), np.zeros((2, 0, 3), np.float32))
    coeffs32, beta32, tables32 = single
    field = _stream.StreamField(
        center0=f3, center_step=f3, eps=1.0, power=1, l_first=0, l_last=0, base=base,
        coeffs=f33, beta=beta, tables=tables, angular=marker, unrolled=False,
        cutoff_inner=0.0, inv_width=0.0, mirrors=f33, origin=f3, single=False,
        coeffs32=coeffs32, beta32=beta32, tables32=tables32, cscale=0.0,
        angular32=generic_marker(single=True), unrolled32=False,
    )  # fmt: skip
    return [
        (_expansion.expand_blocks,
         (f33, f3, 1.0, 1, 0, 0, base, f33, beta, tables, marker, False, f33, 0, 0)),
        (_integrator._probe_pass,
         (f33, rows, True, 1.0, field, rows, blocks, blocks, blocks, 0, 0)),
        (_integrator._first_pass,
         (f33, rows, True, 1.0, 1, True, True, 0.0, field, f33, rows, blocks, blocks, blocks,
          rows, flags, 0, 0)),
        (_integrator._refine_pass, (f33, rows, True, field, 1.0, rows, f33, rows, flags, 0, 0)),
        (_integrator._write_back, (f33, rows, True, f33, 0, 0)),
        *_influence_compiled.compile_calls(),
    ]  # fmt: skip


def ensure_drivers() -> None:
    """Compile (or load from numba's disk cache) every driver in this thread, now."""
    for dispatcher, args in _driver_calls():
        dispatcher(*args)
    with _condition:
        _ready.add(DRIVERS)
        _condition.notify_all()


def _cached(unit: Unit) -> bool:
    """Whether numba's disk cache holds ``unit`` (then loading it takes milliseconds). Asks
    the caches directly (numba's ``_cache.load_overload``, not public API; the drivers' C
    callback marker is compiled or loaded on the way, a fraction of a second): any doubt counts
    as not cached, which only costs a child process that finds everything cached."""
    try:
        if unit in _NAMED:
            return _modules_cached(unit)
        if unit != DRIVERS:
            return all(_unrolled.angular_cached(*kernel) for kernel in _angular_kernels(unit))
        from numba import typeof

        for dispatcher, args in _driver_calls():
            signature = tuple(typeof(a) for a in args)
            if dispatcher._cache.load_overload(signature, dispatcher.targetctx) is None:
                return False
        return True
    except Exception:
        return False


def _modules_cached(unit: str) -> bool:
    """Whether numba's disk cache holds machine code for this machine of every compiled
    function of the modules of ``unit`` (their cache index is read, not the code: numba's
    ``_cache._cache_file``, not public API)."""
    import importlib
    import pkgutil

    from numba.core.dispatcher import Dispatcher

    module = importlib.import_module(f"gogreen_core.{unit}")
    modules = [module]
    for info in pkgutil.iter_modules(getattr(module, "__path__", [])):
        modules.append(importlib.import_module(f"{module.__name__}.{info.name}"))
    for dispatcher in (v for m in modules for v in vars(m).values()):
        if isinstance(dispatcher, Dispatcher) and dispatcher.__module__.startswith(module.__name__):
            internals: Any = dispatcher  # numba's cache and code generator carry no types
            magic = internals.targetctx.codegen().magic_tuple()
            index = internals._cache._cache_file._load_index()
            if not any(key[1] == magic for key in index):
                return False
    return True


def _can_spawn() -> bool:
    """A child Python can compile for us: asked for (a child itself runs in mode ``thread``),
    and this process is a Python interpreter (not an application embedding one, e.g. Blender)."""
    name = os.path.basename(sys.executable or "").lower()
    return _mode() == "child" and name.startswith("python")


def _compile_in_child(units: Iterable[Unit]) -> bool:
    """Compile ``units`` into numba's disk cache in a child process; True if it succeeded."""
    args = [u if isinstance(u, str) else f"{u[0]}:{u[1]}" for u in units]
    env = dict(os.environ, **{_MODE_VARIABLE: "thread"})
    try:
        result = subprocess.run(
            [sys.executable, "-c", _CHILD_SCRIPT, *args],
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            timeout=CHILD_TIMEOUT,
            check=False,
        )
    except (OSError, subprocess.SubprocessError):
        return False
    return result.returncode == 0


_CHILD_SCRIPT = (
    "import sys; from gogreen_core._compiled import _main; sys.exit(_main(sys.argv[1:]))"
)


def _main(argv: list[str]) -> int:
    """The child: compile (into numba's disk cache) the units named on its command line."""
    for arg in argv:
        _load(arg if arg == DRIVERS or arg in _NAMED else tuple(int(v) for v in arg.split(":")))
    return 0
