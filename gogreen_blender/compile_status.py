"""Blender's side of the background work: the compiled kernels and homogenization, with a
status.

Strokes never wait for a compiler: until numba's compiled code of an l_max is in, the engine
runs the same arithmetic in NumPy (``gogreen_core._compiled``: same results bit for bit) and
asks for the code in the background itself, as in the desktop app. The add-on asks for the
current l_max's kernels (with the surface index's and the paint brushes' loops) as soon as it
is enabled and whenever l_max changes, and says "ready" in the GoGreen panel when they are
compiled or loaded from numba's disk cache (not when a first stroke ran: that one may run in
NumPy). On a new machine a child process compiles them (tens of seconds, once per machine).

A homogenization (seconds) runs on a worker thread while a timer on the main thread shows its
progress; in background mode (scripts, tests, render farms) it runs to its end before the
operator returns.
"""

from __future__ import annotations

import time

import bpy

from gogreen_core import _compiled
from gogreen_core.field import _drivers

from . import engine, properties
from .jobs import RUNNER, Job

__all__ = [
    "is_warm",
    "last_message",
    "request_warm_up",
    "start_homogenization",
    "status_line",
]

#: l_max -> when its kernels were asked for (monotonic seconds).
_requested: dict[int, float] = {}
#: (l_max, seconds, error) of requests settled on the compiling thread, for the main thread.
_settled: list[tuple[int, float, str]] = []
#: The last outcome for the panel ("Brush kernels ready (2.1 s)", or an error).
_message = ""
_POLL_SECONDS = 0.2


def kernel_units(l_max: int) -> tuple:
    """The compiled units strokes of ``l_max`` use: the drivers, the angular kernels of its
    degree, the surface index (picks) and the paint brushes' loops."""
    return (*_drivers.units_for(int(l_max)), _compiled.GEOMETRY, _compiled.BRUSHES)


def is_warm(l_max: int) -> bool:
    """The compiled kernels of ``l_max`` are in use (strokes run at full speed)."""
    return int(l_max) in _requested and int(l_max) not in _waiting()


def _waiting() -> set[int]:
    """l_max values asked for whose kernels are not settled yet."""
    _deliver()
    return {l_max for l_max in _requested if l_max not in _done}


_done: set[int] = set()


def _deliver() -> None:
    """On the main thread: take the settled requests (the panel's message)."""
    global _message
    while _settled:
        l_max, seconds, error = _settled.pop(0)
        _done.add(l_max)
        if error:
            _message = f"Compiling the brush kernels failed (strokes run in NumPy): {error}"
        else:
            _message = f"Brush kernels ready (l_max {l_max}, {seconds:.1f} s)"


def last_message() -> str:
    _deliver()
    return _message


def status_line() -> str:
    """What the panel shows: the running job's progress, the compilation, else the last
    outcome."""
    job = RUNNER.busy
    if job is not None:
        return job.status()
    waiting = _waiting()
    if waiting:
        l_max = max(waiting, key=lambda k: _requested[k])
        seconds = time.monotonic() - _requested[l_max]
        return (
            f"Compiling brush kernels for l_max {l_max} (first use only; strokes run "
            f"meanwhile): {seconds:.0f} s"
        )
    return _message


def _redraw() -> None:
    wm = bpy.context.window_manager
    for window in wm.windows if wm is not None else ():
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def _poll() -> float | None:
    """Timer on the main thread: redraw the progress, deliver a finished job or
    compilation."""
    _redraw()
    RUNNER.poll()
    busy = RUNNER.current is not None or bool(_waiting())
    return _POLL_SECONDS if busy else None


def _watch() -> None:
    if not bpy.app.background and not bpy.app.timers.is_registered(_poll):
        bpy.app.timers.register(_poll, first_interval=_POLL_SECONDS)


def _submit(job: Job) -> bool:
    threaded = not bpy.app.background
    if not RUNNER.submit(job, threaded=threaded):
        return False
    if threaded:
        _watch()
    else:
        RUNNER.poll()
    return True


def request_warm_up(scene) -> bool:
    """Ask for the compiled kernels of the scene's l_max (True if asked now; returns at once:
    the compilation runs in the background, strokes run in NumPy meanwhile)."""
    if scene is None:
        return False
    l_max = int(scene.gogreen.l_max)
    if l_max in _requested:
        return False
    _requested[l_max] = start = time.monotonic()
    units = kernel_units(l_max)

    def settled(failures: list) -> None:  # on the compiling thread
        error = "; ".join(f"{type(e).__name__}: {e}" for e in failures)
        _settled.append((l_max, time.monotonic() - start, error))

    _compiled.when_ready(units, settled)
    _watch()
    return True


def compile_now(l_max: int) -> float:
    """Compile (or load) the kernels of ``l_max`` and wait for them; the seconds it took."""
    seconds = _compiled.prepare(*kernel_units(l_max))
    _requested.setdefault(int(l_max), time.monotonic() - seconds)
    _done.add(int(l_max))
    return seconds


def start_homogenization(scene) -> str | None:
    """Homogenize the scene's pattern (worker thread with a window, here without); the result
    goes to ``scene.gogreen.homogenized_material``. None if it started, else why not."""
    s = scene.gogreen
    busy = RUNNER.busy
    if busy is not None:
        return f"GoGreen is busy: {busy.status()}"
    pattern, resolution = s.pattern, s.resolution
    params = properties.pattern_params(s)
    young, poisson, contrast = s.phase_young, s.phase_poisson, s.contrast
    inputs = properties.homogenization_inputs(s)
    scene_name = scene.name

    def work(progress):
        return engine.homogenized_material(
            pattern, resolution, params, young, poisson, contrast, progress
        )

    def done(job: Job) -> None:
        global _message
        target = bpy.data.scenes.get(scene_name)
        if job.error is not None:
            _message = f"Homogenization failed: {job.error}"
        elif target is not None:
            target.gogreen.homogenized_material = engine.material_to_json(job.result)
            target.gogreen.homogenized_inputs = inputs
            _message = f"Homogenized {pattern} in {job.elapsed:.1f} s"
        _redraw()

    _submit(Job(f"Homogenizing the {pattern} pattern", work, done))
    return None


def register() -> None:
    if not bpy.app.background:
        # after the add-on (and the startup file) finished loading
        bpy.app.timers.register(_start_warm_up, first_interval=1.0)


def forget() -> None:
    """Forget the requests (tests: a fresh start)."""
    _requested.clear()
    _settled.clear()
    _done.clear()


def _start_warm_up() -> None:
    request_warm_up(bpy.context.scene)


def unregister() -> None:
    for timer in (_poll, _start_warm_up):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
