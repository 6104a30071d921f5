#!/usr/bin/env bash
# The Blender tests' environment: .venv-blender, a Python 3.11 virtual environment with Blender
# as a Python module (bpy from the package index, built for CPython 3.11 only; it pins numpy < 2,
# hence a venv of its own beside .venv), pytest, the engine's dependencies and this checkout
# (editable, without the GUI's dependencies). About 1.4 GB, half a minute to install.
# Safe to run again: skipped when already done. Exits 3, saying why, when it cannot be made
# (no Python 3.11, no package index), so that the caller can skip the Blender tests.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

bpy_version="5.0.1"  # Blender 5.0, the newest bpy for CPython 3.11

python=""
for candidate in "${PYTHON311:-}" python3.11 python3; do
    if [ -n "$candidate" ] && command -v "$candidate" >/dev/null 2>&1 \
        && "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
        python="$candidate"
        break
    fi
done

stamp=.venv-blender/.gogreen-installed
wanted="bpy==$bpy_version $(cat pyproject.toml scripts/setup_blender_env.sh | cksum)"
if [ -x .venv-blender/bin/python ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$wanted" ]; then
    exit 0
fi
if [ -z "$python" ]; then
    echo "[gogreen] no Python 3.11 found (bpy $bpy_version is built for CPython 3.11 only)"
    exit 3
fi
echo "[gogreen] installing Blender as a Python module (bpy $bpy_version) into .venv-blender"
rm -rf .venv-blender
"$python" -m venv .venv-blender
pip=(.venv-blender/bin/python -m pip install -q)
if ! "${pip[@]}" "bpy==$bpy_version" pytest "numba>=0.60" "scipy>=1.15" "trimesh>=4.0" \
    "mapbox-earcut>=1.0.3"; then
    rm -rf .venv-blender
    echo "[gogreen] could not install bpy $bpy_version from the package index"
    exit 3
fi
"${pip[@]}" --no-deps -e .
echo "$wanted" >"$stamp"
