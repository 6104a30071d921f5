"""Blender's side of the background jobs: kernel warm-up and homogenization, with a status.

numba compiles the brush kernels the first time they run on a machine (tens of seconds; then
they load from its disk cache in well under a second). With a window, the add-on compiles them
on a worker thread as soon as it is enabled and whenever l_max changes, and shows the progress
in the GoGreen panel; the modal tool refuses to start a stroke until they are ready (a message
says so) instead of freezing the window. In background mode (scripts, tests, render farms)
nothing runs on its own: a stroke compiles what it needs when it runs, and a homogenization
runs to its end before the operator returns.
"""

from __future__ import annotations

import bpy

from gogreen_core import ParameterError

from . import engine, properties
from .jobs import RUNNER, Job

__all__ = [
    "is_warm",
    "last_message",
    "request_warm_up",
    "start_homogenization",
    "status_line",
]

#: Truncation degrees whose kernels are compiled in this session.
_warm: set[int] = set()
#: The last job's outcome for the panel ("Kernels ready (2.1 s)", or an error).
_message = ""
_POLL_SECONDS = 0.2


def is_warm(l_max: int) -> bool:
    return int(l_max) in _warm


def mark_warm(l_max: int) -> None:
    """Strokes of ``l_max`` ran (so its kernels are compiled)."""
    _warm.add(int(l_max))


def last_message() -> str:
    return _message


def status_line() -> str:
    """What the panel shows: the running job's progress, else the last outcome."""
    job = RUNNER.busy
    return job.status() if job is not None else _message


def _redraw() -> None:
    wm = bpy.context.window_manager
    for window in wm.windows if wm is not None else ():
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def _poll() -> float | None:
    """Timer on the main thread: redraw the progress, deliver a finished job."""
    _redraw()
    RUNNER.poll()
    return _POLL_SECONDS if RUNNER.current is not None else None


def _submit(job: Job) -> bool:
    threaded = not bpy.app.background
    if not RUNNER.submit(job, threaded=threaded):
        return False
    if threaded:
        if not bpy.app.timers.is_registered(_poll):
            bpy.app.timers.register(_poll, first_interval=_POLL_SECONDS)
    else:
        RUNNER.poll()
    return True


def request_warm_up(scene) -> bool:
    """Compile the kernels of the scene's settings on a worker thread (with a window only;
    True if a warm-up started)."""
    global _message
    if bpy.app.background or scene is None:
        return False
    l_max = int(scene.gogreen.l_max)
    if is_warm(l_max) or RUNNER.busy is not None:
        return False
    try:
        settings = properties.read_settings(scene)
    except ParameterError:
        # a bad material or falloff: compile with the engine's defaults (the code is the same)
        settings = engine.default_settings(l_max)

    def done(job: Job) -> None:
        global _message
        if job.error is None:
            mark_warm(l_max)
            _message = f"Brush kernels ready (l_max {l_max}, {job.elapsed:.1f} s)"
        else:
            _message = f"Compiling the brush kernels failed: {job.error}"
        _redraw()

    _message = ""
    return _submit(
        Job(f"Compiling brush kernels for l_max {l_max} (first use only)", _warm_up(settings), done)
    )


def _warm_up(settings):
    def work(_progress) -> None:
        engine.warm_up(settings)

    return work


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


def _start_warm_up() -> None:
    request_warm_up(bpy.context.scene)


def unregister() -> None:
    for timer in (_poll, _start_warm_up):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
