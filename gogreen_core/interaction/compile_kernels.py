"""Compile the kernels the app's first stroke needs, once, with a line per unit: the install
step (``scripts/setup_env.sh``), so that the first window after it sculpts compiled.

    python -m gogreen_core.interaction.compile_kernels [--l-max N]

Units already in numba's disk cache are not compiled again (then this prints nothing); while
another process compiles into the same cache (its lock, see ``_compiled``) this waits for it
and compiles only what it left.
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time

from gogreen_core import _compiled
from gogreen_core.compile_times import unit_name

__all__ = ["UNIT_MODULES", "compile_for_app", "main", "units_for_app"]

#: The modules registering the app's compile units (importing them registers the units).
UNIT_MODULES = (
    "gogreen_core.field._drivers",
    "gogreen_core.mesh.geometry",
    "gogreen_core.sculpt.brushes.paint_kernels",
    "gogreen_core.mesh.mesh_io.formats",
)


def units_for_app(l_max: int) -> tuple[_compiled.Unit, ...]:
    """The units the app asks for at start, in the order its first stroke needs them: the
    field's drivers, the generated angular kernels of ``l_max`` (the generic one serves until
    then), the surface index, the paint brushes, the mesh readers."""
    from gogreen_core.field import _drivers

    drivers, *angular = _drivers.units_for(l_max)
    return (drivers, *angular, _compiled.GEOMETRY, _compiled.BRUSHES, _compiled.MESH_IO)


def compile_for_app(l_max: int, say: _compiled.ProgressCallback | None = None) -> list[str]:
    """Bring in :func:`units_for_app` (compiled in a child process when missing from the disk
    cache; ``say`` hears each unit compiled) and wait for them; returns the units compiled."""
    for module in UNIT_MODULES:
        importlib.import_module(module)
    units = units_for_app(l_max)
    if say is not None:
        _compiled.add_progress_listener(say)
    try:
        _compiled.prepare(*units)
    finally:
        if say is not None:
            _compiled.remove_progress_listener(say)
    return [unit_name(u) for u in units if _compiled.compiled_here([u])]


class _Lines:
    """Prints a line per unit compiled (the progress listener, on the compiling thread)."""

    def __init__(self) -> None:
        self.left: tuple[_compiled.Unit, ...] | None = None

    def __call__(self, progress: _compiled.Progress) -> None:
        if self.left is None or progress.done == 0:
            print(
                f"[gogreen] compiling the kernels once ({progress.total} "
                f"unit{'s' if progress.total > 1 else ''}; numba keeps them on disk)",
                flush=True,
            )
        else:
            done = [u for u in self.left if u not in progress.left]
            left = progress.seconds_left
            print(
                f"[gogreen]   {progress.done}/{progress.total} {', '.join(map(unit_name, done))}: "
                f"{progress.elapsed:.1f} s"
                + (f", about {left:.0f} s left" if left and progress.left else ""),
                flush=True,
            )
        self.left = progress.left


def main(argv: list[str] | None = None) -> int:
    from gogreen_core.interaction.settings import Settings

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--l-max", type=int, default=Settings().l_max, help="truncation degree")
    args = parser.parse_args(argv)
    holder = _compiled.compile_holder()
    if holder:
        print(f"[gogreen] waiting for another process compiling the kernels ({holder})")
    start = time.perf_counter()
    try:
        compiled = compile_for_app(args.l_max, _Lines())
    except Exception as exc:  # the app still runs: NumPy until compiled in the background
        print(f"[gogreen] compiling the kernels failed ({type(exc).__name__}: {exc}); the app "
              "evaluates in NumPy and tries again in the background", file=sys.stderr)  # fmt: skip
        return 1
    if compiled:
        print(f"[gogreen] kernels compiled in {time.perf_counter() - start:.1f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
