#!/usr/bin/env bash
# Quick start, command 2: install what is needed, then run the lint and type checks and the test
# suite.
# Extra arguments go to pytest (and then only the main suite runs; GOGREEN_BLENDER_TESTS=1 runs
# the Blender tests too).
#
# The Blender extension's tests run in a second pytest, inside .venv-blender (Python 3.11 with
# Blender as a Python module, made by scripts/setup_blender_env.sh); when that cannot be made
# (no Python 3.11, no package index) they are skipped with the reason. The mesh file tests run
# there again: under numpy 1.26, the numpy of Blender's Python, where gogreen_core runs too.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$root/scripts/setup_env.sh"
cd "$root"
.venv/bin/ruff check .
.venv/bin/mypy  # the app, default mode ([tool.mypy] in pyproject.toml)
.venv/bin/mypy --strict -p gogreen_core  # the core, strict mode (same config's overrides)

run_pytest() {
    # GUI tests run on a real X server (a virtual one when there is no display) so that the VTK
    # viewport renders and picks as on a desktop.
    if [ -z "${DISPLAY:-}" ]; then
        xvfb-run -a -s "-screen 0 1600x1000x24" "$@"
    else
        "$@"
    fi
}

status=0
run_pytest .venv/bin/python -m pytest -q "$@" || status=$?

if [ $# -eq 0 ] || [ "${GOGREEN_BLENDER_TESTS:-0}" = "1" ]; then
    blender_status=0
    bash scripts/setup_blender_env.sh || blender_status=$?
    if [ "$blender_status" -eq 0 ]; then
        echo "[gogreen] Blender extension and mesh file tests (bpy, numpy 1.26 in .venv-blender)"
        # numba's cache of the kernels compiled with .venv-blender's numba, apart from .venv's
        NUMBA_CACHE_DIR="$root/.venv-blender/numba-cache" .venv-blender/bin/python -m pytest -q \
            tests/blender tests/core/mesh/test_mesh_io*.py || status=$?
    elif [ "$blender_status" -eq 3 ]; then
        echo "[gogreen] Blender extension tests SKIPPED: bpy could not be installed (see above)"
    else
        status=$blender_status
    fi
fi
exit "$status"
